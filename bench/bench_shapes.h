/* bench_shapes.h -- point sets that no distribution of the service names,
 * for section 11 of bench/run: the shapes real data takes and the ones
 * that break sweeps and incremental insertion alike. Each is n points
 * from a seed; the same name, n and seed give the same doubles on one
 * machine (a few use libm's sin, cos and tan).
 *
 *   rows            300 rows of equal y (integers), x uniform in [0, 1)
 *   columns         300 columns of equal x, y uniform in [0, 1)
 *   two-lines       y = 0 or 1, x uniform
 *   jittered-grid   the integer grid of side ceil(sqrt n), each coordinate
 *                   moved by up to 10^-12 (nearly cocircular everywhere)
 *   hex-lattice     rows 0.866 apart, every other one shifted by a half
 *   rotated-grid    the integer grid turned by 0.3 radians, rounded
 *   diamond-grid    the integer grid turned by 45 degrees, rounded
 *   disk-lattice    the integer points of a disk, in random order
 *   ulp-lattice     random points of a 4096 x 4096 lattice of step 2^-52
 *                   at (1, 1)
 *   parabola        y = x^2, x uniform in [-1, 1)
 *   parabola-down   y = -x^2
 *   half-circle     the upper half of the unit circle, random angles
 *   circle-centre   the unit circle at random angles, and its centre
 *   polygon         the corners of a regular n-gon
 *   rings           ten concentric circles, random angles
 *   int-circle      integer points nearest a circle of radius 10^7
 *   spiral          r = t, t uniform in [0, 300)
 *   star            16 rays from the origin, radius uniform in [0, 1)
 *   annulus         random angles, radius in [1, 1 + 10^-3)
 *   cauchy          tan(pi (u - 1/2)) on each axis
 *   soneira         Soneira-Peebles clusters: 4 per level, 8 levels,
 *                   each an eighth of its parent's size
 *   duplicates      1000 distinct uniform points, each repeated
 *   near-line       (u, 10^-9 v)
 *   geometric-line  x = e^(10 i / n), y = 2x + 10^-9 u: a line sampled at
 *                   geometric steps (every triangle flat, four decades)
 *   line-and-apex   n - 1 sites exactly on y = x / 2 (x a half-integer
 *                   step, shuffled) and one off it
 *   mixed-exponents u 2^k on each axis, k uniform in [-500, 500)
 *   time-series     (i, random walk)
 *
 * Static, so that the driver stays one translation unit (as bench_util.h).
 */
#ifndef VOR_BENCH_SHAPES_H
#define VOR_BENCH_SHAPES_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../tests/support/testsets.h"

#define BS_PI 3.14159265358979323846

static void bs_rows(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        xy[2 * i] = vt_unit(r);
        xy[2 * i + 1] = (double)(vt_next(r) % 300);
    }
}

static void bs_columns(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        xy[2 * i] = (double)(vt_next(r) % 300);
        xy[2 * i + 1] = vt_unit(r);
    }
}

static void bs_two_lines(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        xy[2 * i] = vt_unit(r);
        xy[2 * i + 1] = (double)(vt_next(r) % 2);
    }
}

static size_t bs_side(size_t n) {
    size_t k = (size_t)sqrt((double)n);
    while (k * k < n) k++;
    return k;
}

static void bs_jittered_grid(vt_rng *r, double *xy, size_t n) {
    size_t k = bs_side(n);
    for (size_t i = 0; i < n; i++) {
        xy[2 * i] = (double)(i % k) + 1e-12 * vt_unit(r);
        xy[2 * i + 1] = (double)(i / k) + 1e-12 * vt_unit(r);
    }
}

static void bs_hex_lattice(vt_rng *r, double *xy, size_t n) {
    (void)r;
    size_t k = bs_side(n);
    for (size_t i = 0; i < n; i++) {
        size_t row = i / k;
        xy[2 * i] = (double)(i % k) + (row % 2 ? 0.5 : 0.0);
        xy[2 * i + 1] = (double)row * 0.8660254037844386;
    }
}

static void bs_rotated_grid(vt_rng *r, double *xy, size_t n) {
    (void)r;
    size_t k = bs_side(n);
    double c = cos(0.3), s = sin(0.3);
    for (size_t i = 0; i < n; i++) {
        double a = (double)(i % k), b = (double)(i / k);
        xy[2 * i] = a * c - b * s;
        xy[2 * i + 1] = a * s + b * c;
    }
}

/* The grid turned by 45 degrees, each coordinate (a -+ b) sqrt(1/2)
 * rounded: diamonds whose circles' tops and the sites above them agree to
 * better than 2^-300 without being equal. */
static void bs_diamond_grid(vt_rng *r, double *xy, size_t n) {
    (void)r;
    size_t k = bs_side(n);
    const double c = 0.70710678118654757; /* sqrt(1/2), rounded */
    for (size_t i = 0; i < n; i++) {
        double a = (double)(i % k), b = (double)(i / k);
        xy[2 * i] = (a - b) * c;
        xy[2 * i + 1] = (a + b) * c;
    }
}

/* The integer points of the smallest disk around 0 that holds n, the
 * first n of them after a shuffle. */
static void bs_disk_lattice(vt_rng *r, double *xy, size_t n) {
    long R = (long)sqrt((double)n / BS_PI) + 2;
    size_t k = 0;
    while (k < n) {
        k = 0;
        for (long x = -R; x <= R; x++)
            for (long y = -R; y <= R; y++) k += x * x + y * y <= R * R;
        if (k < n) R++;
    }
    double *all = malloc(2 * k * sizeof *all);
    if (!all) { /* the whole disk did not fit: its first n points */
        size_t j = 0;
        for (long x = -R; x <= R && j < n; x++)
            for (long y = -R; y <= R && j < n; y++)
                if (x * x + y * y <= R * R) {
                    xy[2 * j] = (double)x;
                    xy[2 * j++ + 1] = (double)y;
                }
        return;
    }
    size_t j = 0;
    for (long x = -R; x <= R; x++)
        for (long y = -R; y <= R; y++)
            if (x * x + y * y <= R * R) {
                all[2 * j] = (double)x;
                all[2 * j++ + 1] = (double)y;
            }
    for (size_t i = k; i-- > 1;) { /* Fisher-Yates */
        size_t m = (size_t)(vt_next(r) % (i + 1));
        double t0 = all[2 * i], t1 = all[2 * i + 1];
        all[2 * i] = all[2 * m];
        all[2 * i + 1] = all[2 * m + 1];
        all[2 * m] = t0;
        all[2 * m + 1] = t1;
    }
    memcpy(xy, all, 2 * n * sizeof *xy);
    free(all);
}

static void bs_ulp_lattice(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < 2 * n; i++)
        xy[i] = 1.0 + (double)(vt_next(r) % 4096) * 0x1p-52;
}

static void bs_parabola(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        double x = 2 * vt_unit(r) - 1;
        xy[2 * i] = x;
        xy[2 * i + 1] = x * x;
    }
}

static void bs_parabola_down(vt_rng *r, double *xy, size_t n) {
    bs_parabola(r, xy, n);
    for (size_t i = 0; i < n; i++) xy[2 * i + 1] = -xy[2 * i + 1];
}

static void bs_half_circle(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        double t = BS_PI * vt_unit(r);
        xy[2 * i] = cos(t);
        xy[2 * i + 1] = sin(t);
    }
}

/* The corners of a regular n-gon on the unit circle, in order. */
static void bs_polygon(vt_rng *r, double *xy, size_t n) {
    (void)r;
    for (size_t i = 0; i < n; i++) {
        double t = 2 * BS_PI * (double)i / (double)n;
        xy[2 * i] = cos(t);
        xy[2 * i + 1] = sin(t);
    }
}

/* Ten circles of radius 1 to 10 around 0, random angles. */
static void bs_rings(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        double rad = (double)(1 + vt_next(r) % 10), t = 2 * BS_PI * vt_unit(r);
        xy[2 * i] = rad * cos(t);
        xy[2 * i + 1] = rad * sin(t);
    }
}

static void bs_circle_centre(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i + 1 < n; i++) {
        double t = 2 * BS_PI * vt_unit(r);
        xy[2 * i] = cos(t);
        xy[2 * i + 1] = sin(t);
    }
    xy[2 * n - 2] = 0;
    xy[2 * n - 1] = 0;
}

static void bs_int_circle(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        double t = 2 * BS_PI * vt_unit(r);
        xy[2 * i] = nearbyint(1e7 * cos(t));
        xy[2 * i + 1] = nearbyint(1e7 * sin(t));
    }
}

static void bs_spiral(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        double t = 300 * vt_unit(r);
        xy[2 * i] = t * cos(t);
        xy[2 * i + 1] = t * sin(t);
    }
}

static void bs_star(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        double a = 2 * BS_PI * (double)(vt_next(r) % 16) / 16, d = vt_unit(r);
        xy[2 * i] = d * cos(a);
        xy[2 * i + 1] = d * sin(a);
    }
}

static void bs_annulus(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        double t = 2 * BS_PI * vt_unit(r), d = 1 + 1e-3 * vt_unit(r);
        xy[2 * i] = d * cos(t);
        xy[2 * i + 1] = d * sin(t);
    }
}

static void bs_cauchy(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < 2 * n; i++) xy[i] = tan(BS_PI * (vt_unit(r) - 0.5));
}

static void bs_soneira_in(vt_rng *r, double *xy, size_t *k, size_t m,
                          double cx, double cy, double s, int level) {
    if (level == 0 || m <= 1) {
        for (size_t i = 0; i < m; i++) {
            xy[2 * *k] = cx + s * (2 * vt_unit(r) - 1);
            xy[2 * *k + 1] = cy + s * (2 * vt_unit(r) - 1);
            ++*k;
        }
        return;
    }
    for (size_t j = 0; j < 4; j++) {
        double x = cx + s * (2 * vt_unit(r) - 1);
        double y = cy + s * (2 * vt_unit(r) - 1);
        bs_soneira_in(r, xy, k, m / 4 + (j < m % 4), x, y, s / 8, level - 1);
    }
}

static void bs_soneira(vt_rng *r, double *xy, size_t n) {
    size_t k = 0;
    bs_soneira_in(r, xy, &k, n, 0, 0, 1, 8);
}

static void bs_duplicates(vt_rng *r, double *xy, size_t n) {
    double base[2000];
    for (size_t i = 0; i < 2000; i++) base[i] = vt_unit(r);
    for (size_t i = 0; i < n; i++) {
        size_t j = (size_t)(vt_next(r) % 1000);
        xy[2 * i] = base[2 * j];
        xy[2 * i + 1] = base[2 * j + 1];
    }
}

static void bs_near_line(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        xy[2 * i] = vt_unit(r);
        xy[2 * i + 1] = 1e-9 * vt_unit(r);
    }
}

static void bs_geometric_line(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < n; i++) {
        double x = exp(10.0 * (double)i / (double)n);
        xy[2 * i] = x;
        xy[2 * i + 1] = 2 * x + 1e-9 * vt_unit(r);
    }
}

static void bs_line_and_apex(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i + 1 < n; i++) {
        xy[2 * i] = 0.5 * (double)i;
        xy[2 * i + 1] = 0.25 * (double)i;
    }
    for (size_t i = n - 1; i > 1; i--) { /* shuffle the line's sites */
        size_t j = (size_t)(vt_next(r) % i);
        double x = xy[2 * (i - 1)], y = xy[2 * (i - 1) + 1];
        xy[2 * (i - 1)] = xy[2 * j];
        xy[2 * (i - 1) + 1] = xy[2 * j + 1];
        xy[2 * j] = x;
        xy[2 * j + 1] = y;
    }
    xy[2 * n - 2] = 10;
    xy[2 * n - 1] = -3;
}

static void bs_mixed_exponents(vt_rng *r, double *xy, size_t n) {
    for (size_t i = 0; i < 2 * n; i++) {
        int e = (int)(vt_next(r) % 1000) - 500;
        xy[i] = ldexp(2 * vt_unit(r) - 1, e);
    }
}

static void bs_time_series(vt_rng *r, double *xy, size_t n) {
    double y = 0;
    for (size_t i = 0; i < n; i++) {
        y += vt_gauss(r);
        xy[2 * i] = (double)i;
        xy[2 * i + 1] = y;
    }
}

static const struct {
    const char *name;
    void (*fill)(vt_rng *r, double *xy, size_t n);
} bs_shapes[] = {
    {"rows", bs_rows},
    {"columns", bs_columns},
    {"two-lines", bs_two_lines},
    {"jittered-grid", bs_jittered_grid},
    {"hex-lattice", bs_hex_lattice},
    {"rotated-grid", bs_rotated_grid},
    {"diamond-grid", bs_diamond_grid},
    {"disk-lattice", bs_disk_lattice},
    {"ulp-lattice", bs_ulp_lattice},
    {"parabola", bs_parabola},
    {"parabola-down", bs_parabola_down},
    {"half-circle", bs_half_circle},
    {"circle-centre", bs_circle_centre},
    {"polygon", bs_polygon},
    {"rings", bs_rings},
    {"int-circle", bs_int_circle},
    {"spiral", bs_spiral},
    {"star", bs_star},
    {"annulus", bs_annulus},
    {"cauchy", bs_cauchy},
    {"soneira", bs_soneira},
    {"duplicates", bs_duplicates},
    {"near-line", bs_near_line},
    {"geometric-line", bs_geometric_line},
    {"line-and-apex", bs_line_and_apex},
    {"mixed-exponents", bs_mixed_exponents},
    {"time-series", bs_time_series},
};

/* New array of 2n doubles of shape name (n >= 1), NULL if the name is
 * unknown or out of memory. */
static double *bs_shape(const char *name, size_t n, uint64_t seed) {
    for (size_t i = 0; i < sizeof bs_shapes / sizeof bs_shapes[0]; i++) {
        if (strcmp(name, bs_shapes[i].name) != 0) continue;
        if (n == 0 || n > SIZE_MAX / 16) return NULL;
        double *xy = malloc(2 * n * sizeof *xy);
        if (!xy) return NULL;
        vt_rng r = {seed * 0x9e3779b97f4a7c15ull + i};
        bs_shapes[i].fill(&r, xy, n);
        return xy;
    }
    return NULL;
}

#endif /* VOR_BENCH_SHAPES_H */
