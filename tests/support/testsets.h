/* testsets.h -- the point sets every algorithm test runs on.
 *
 * One table of named sets, each generated from a fixed seed, covering the
 * inputs where Voronoi implementations break: duplicates, collinear points,
 * exactly cocircular points (integer circle, grids), nearly cocircular ones
 * (float circle, hexagonal lattice), rows of equal y, huge offsets and tiny or
 * huge scales, heavy tails, one far outlier, twelve decades at once,
 * sites in convex position (a parabola), data as it is logged (a time
 * series, GPS-like tracks), a grid jittered by 10^-12, a grid turned by
 * 45 degrees with its coordinates rounded, a cluster 10^-10 wide beside a
 * stray 10^10 away (and pairs of sites 10^-7 apart on a curve), and the
 * trivial sizes 0, 1, 2, 3. Plus the generators, so a test can make its own sizes
 * and seeds, among them the service's own distributions. Deterministic:
 * the same name gives the same doubles on every machine (no libm calls
 * whose rounding may vary except sin/cos for the float circle, the tracks
 * and the gaussian sets).
 */
#ifndef VOR_TESTSETS_H
#define VOR_TESTSETS_H

#include <stddef.h>
#include <stdint.h>

/* splitmix64: small, fast, good enough for test data. */
typedef struct vt_rng {
    uint64_t s;
} vt_rng;

uint64_t vt_next(vt_rng *r);
double vt_unit(vt_rng *r);     /* uniform in [0, 1) */
double vt_gauss(vt_rng *r);    /* standard normal (Box-Muller) */

/* Generators: each returns a new array of 2*n doubles (free with free()),
 * or NULL if allocation failed. */
double *vt_uniform(size_t n, uint64_t seed);           /* unit square */
double *vt_gaussian(size_t n, uint64_t seed);          /* N(0,1) each axis */
double *vt_pixels(size_t n, uint64_t seed);            /* integers in 800x600 */
double *vt_grid(size_t w, size_t h);                   /* integers 0..w-1, 0..h-1 */
double *vt_unit_circle(size_t n);                      /* cos, sin of 2 pi k/n */
double *vt_clusters(size_t n, size_t k, uint64_t seed);
double *vt_hex(size_t w, size_t h);                    /* hexagonal lattice */
/* All integer points on x^2 + y^2 = r^2, plus the centre if with_centre.
 * *n receives the count. */
double *vt_int_circle(long r, int with_centre, size_t *n);

/* n points of a distribution of the service (uniform, gaussian, pixels or
 * its alias random, grid, circle, clustered, lognormal, outlier, decades:
 * api/distribution.h), the very doubles `"generate": {"distribution": name,
 * "n": n, "seed": seed}` gives. NULL if the name is unknown or allocation
 * failed. */
double *vt_distribution(const char *name, size_t n, uint64_t seed);

/* The standard sets. */
typedef struct vt_set {
    const char *name;
    double *xy; /* 2*n, owned; NULL when n == 0 */
    size_t n;
} vt_set;

/* Number of standard sets; vt_set_name(i) for i < vt_count(). */
size_t vt_count(void);
const char *vt_set_name(size_t i);

/* Makes standard set i (or by name). 0 on success, -1 on allocation failure
 * or unknown name. Free with vt_set_free. */
int vt_make(size_t i, vt_set *out);
int vt_make_named(const char *name, vt_set *out);
void vt_set_free(vt_set *s);

#endif /* VOR_TESTSETS_H */
