/* distribution.h -- the named point distributions: what "generate" requests,
 * `voronoi --generate`, the test point sets and the benchmark generate.
 *
 * One implementation for all of them, so that a test, a bench row and a
 * request to the service with the same (distribution, n, seed) see the very
 * same doubles. It depends on libc and libm only: the core tests link it
 * (through tests/support/) without the rest of the codec.
 *
 * The random numbers are xoshiro256** seeded through splitmix64: the same
 * sequence on every platform for a seed (rand() is not). The distributions
 * that call libm (gaussian, circle, clustered, lognormal, decades) may differ
 * in the last bits between C libraries; the others are exact everywhere.
 *
 *   uniform    the unit square [0,1)^2
 *   gaussian   standard normal x and y (mean 0, deviation 1)
 *   pixels     integer pixels of an 800x600 window, x in 0..799, y in 0..599
 *              (duplicates likely); "random", the course report's name for
 *              it, is accepted as an alias
 *   grid       the first n points of the k x k integer grid, k = ceil(sqrt n),
 *              row by row (the seed is not used)
 *   circle     n points evenly spaced on the unit circle, in floating point
 *              (the seed is not used)
 *   clustered  c = clamp(round(sqrt(n)/10), 1, 1000) gaussian clusters,
 *              centres uniform in the unit square, deviation 0.1/sqrt(c)
 *   lognormal  exp(2 N(0,1)) in x and in y: heavy-tailed, most points near
 *              (1, 1), a few as far as 1e7
 *   outlier    n-1 points uniform in the 0.1 x 0.1 square centred on
 *              (8.5, 47.3), plus one point at (0, 0) at a position of the
 *              input chosen by the seed (a city with a failed geocode)
 *   decades    |x| and |y| log-uniform in [1e-6, 1e6), each sign random:
 *              twelve decades at once (multi-scale)
 *
 * Cost: O(n) time, no allocation. */
#ifndef VOR_API_DISTRIBUTION_H
#define VOR_API_DISTRIBUTION_H

#include <stddef.h>
#include <stdint.h>

/* name, whether the seed is used, description (for help texts). */
#define API_DIST_TABLE(X)                                                    \
    X(API_DIST_UNIFORM, "uniform", 1, "the unit square")                     \
    X(API_DIST_GAUSSIAN, "gaussian", 1, "standard normal x and y")           \
    X(API_DIST_PIXELS, "pixels", 1,                                          \
      "integer pixels of an 800x600 window, with duplicates")                \
    X(API_DIST_GRID, "grid", 0, "the k x k integer grid, k = ceil(sqrt n)")  \
    X(API_DIST_CIRCLE, "circle", 0, "n points on the unit circle")           \
    X(API_DIST_CLUSTERED, "clustered", 1, "gaussian clusters")               \
    X(API_DIST_LOGNORMAL, "lognormal", 1, "exp(2 N(0,1)) in x and in y")     \
    X(API_DIST_OUTLIER, "outlier", 1,                                        \
      "n-1 points in a 0.1 x 0.1 square around (8.5, 47.3), one at (0, 0)")  \
    X(API_DIST_DECADES, "decades", 1,                                        \
      "|x|, |y| log-uniform in [1e-6, 1e6], random signs")

typedef enum api_dist {
#define API__DIST_ENUM(id, name, seeded, text) id,
    API_DIST_TABLE(API__DIST_ENUM)
#undef API__DIST_ENUM
        API_DIST_COUNT
} api_dist;

/* The distribution called name (a canonical name or an alias such as
 * "random"); -1 if there is none or name is NULL. */
int api_dist_find(const char *name);

/* The canonical name of d ("pixels" for "random"); NULL if d is out of
 * range. A borrowed constant. */
const char *api_dist_name(api_dist d);

/* One line describing d, as in the table above; NULL if out of range. */
const char *api_dist_text(api_dist d);

/* 1 if d's points depend on the seed, 0 if not (grid, circle). */
int api_dist_seeded(api_dist d);

/* "uniform, gaussian, pixels (alias random), ...": every name, for error
 * messages and help texts. A borrowed constant. */
const char *api_dist_list(void);

/* Writes n points of d for seed into xy[0 .. 2n) as x, y pairs. Cannot
 * fail; d must be valid (asserted). */
void api_dist_fill(api_dist d, uint64_t seed, double *xy, size_t n);

#endif /* VOR_API_DISTRIBUTION_H */
