/* testsets.c -- generators and the table of standard test point sets.
 * See testsets.h. Each set is small enough for ASan runs and for the
 * brute-force oracles where the name says so (n <= 2000). */
#include "testsets.h"

#include "../../api/distribution.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

uint64_t vt_next(vt_rng *r) {
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double vt_unit(vt_rng *r) { return (double)(vt_next(r) >> 11) * 0x1.0p-53; }

double vt_gauss(vt_rng *r) {
    double u = vt_unit(r), v = vt_unit(r);
    if (u < 0x1.0p-60) u = 0x1.0p-60;
    return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

static double *alloc_xy(size_t n) {
    return malloc((n ? n : 1) * 2 * sizeof(double));
}

double *vt_uniform(size_t n, uint64_t seed) {
    vt_rng r = {seed};
    double *xy = alloc_xy(n);
    if (!xy) return NULL;
    for (size_t i = 0; i < 2 * n; i++) xy[i] = vt_unit(&r);
    return xy;
}

double *vt_gaussian(size_t n, uint64_t seed) {
    vt_rng r = {seed};
    double *xy = alloc_xy(n);
    if (!xy) return NULL;
    for (size_t i = 0; i < 2 * n; i++) xy[i] = vt_gauss(&r);
    return xy;
}

double *vt_pixels(size_t n, uint64_t seed) {
    vt_rng r = {seed};
    double *xy = alloc_xy(n);
    if (!xy) return NULL;
    for (size_t i = 0; i < n; i++) {
        xy[2 * i] = (double)(vt_next(&r) % 800);
        xy[2 * i + 1] = (double)(vt_next(&r) % 600);
    }
    return xy;
}

double *vt_grid(size_t w, size_t h) {
    double *xy = alloc_xy(w * h);
    if (!xy) return NULL;
    size_t k = 0;
    for (size_t j = 0; j < h; j++) {
        for (size_t i = 0; i < w; i++) {
            xy[k++] = (double)i;
            xy[k++] = (double)j;
        }
    }
    return xy;
}

double *vt_unit_circle(size_t n) {
    double *xy = alloc_xy(n);
    if (!xy) return NULL;
    for (size_t i = 0; i < n; i++) {
        double t = 6.283185307179586 * (double)i / (double)n;
        xy[2 * i] = cos(t);
        xy[2 * i + 1] = sin(t);
    }
    return xy;
}

double *vt_clusters(size_t n, size_t k, uint64_t seed) {
    vt_rng r = {seed};
    double *xy = alloc_xy(n);
    if (!xy || k == 0) return xy;
    double *centre = alloc_xy(k);
    if (!centre) {
        free(xy);
        return NULL;
    }
    for (size_t c = 0; c < 2 * k; c++) centre[c] = vt_unit(&r) * 100.0;
    for (size_t i = 0; i < n; i++) {
        size_t c = (size_t)(vt_next(&r) % k);
        xy[2 * i] = centre[2 * c] + vt_gauss(&r);
        xy[2 * i + 1] = centre[2 * c + 1] + vt_gauss(&r);
    }
    free(centre);
    return xy;
}

double *vt_hex(size_t w, size_t h) {
    double *xy = alloc_xy(w * h);
    if (!xy) return NULL;
    size_t k = 0;
    for (size_t j = 0; j < h; j++) {
        for (size_t i = 0; i < w; i++) {
            xy[k++] = (double)i + (j % 2 ? 0.5 : 0.0);
            xy[k++] = (double)j * 0.8660254037844386;
        }
    }
    return xy;
}

double *vt_int_circle(long r, int with_centre, size_t *n) {
    size_t count = with_centre ? 1 : 0;
    for (long x = -r; x <= r; x++) {
        long y2 = r * r - x * x;
        long y = (long)llround(sqrt((double)y2));
        if (y * y == y2) count += y == 0 ? 1 : 2;
    }
    double *xy = alloc_xy(count);
    if (!xy) return NULL;
    size_t k = 0;
    for (long x = -r; x <= r; x++) {
        long y2 = r * r - x * x;
        long y = (long)llround(sqrt((double)y2));
        if (y * y != y2) continue;
        xy[k++] = (double)x;
        xy[k++] = (double)y;
        if (y != 0) {
            xy[k++] = (double)x;
            xy[k++] = (double)-y;
        }
    }
    if (with_centre) {
        xy[k++] = 0.0;
        xy[k++] = 0.0;
    }
    *n = count;
    return xy;
}

double *vt_distribution(const char *name, size_t n, uint64_t seed) {
    int d = api_dist_find(name);
    if (d < 0) return NULL;
    double *xy = alloc_xy(n);
    if (xy) api_dist_fill((api_dist)d, seed, xy, n);
    return xy;
}

/* ---- the standard sets -------------------------------------------------- */

typedef double *(*make_fn)(size_t *n);

#define FIXED(name, count, expr)                                             \
    static double *name(size_t *n) {                                         \
        *n = (count);                                                        \
        return (expr);                                                       \
    }

FIXED(mk_uniform_1000, 1000, vt_uniform(1000, 1))
FIXED(mk_uniform_20000, 20000, vt_uniform(20000, 2))
FIXED(mk_gaussian_2000, 2000, vt_gaussian(2000, 3))
FIXED(mk_pixels_2000, 2000, vt_pixels(2000, 4))
FIXED(mk_pixels_20000, 20000, vt_pixels(20000, 5))
FIXED(mk_grid_100, 10000, vt_grid(100, 100))
FIXED(mk_grid_7, 49, vt_grid(7, 7))
FIXED(mk_unit_circle_2000, 2000, vt_unit_circle(2000))
FIXED(mk_clusters_3000, 3000, vt_clusters(3000, 10, 6))
FIXED(mk_hex_40, 1600, vt_hex(40, 40))
/* The service's skewed distributions (api/distribution.h). */
FIXED(mk_lognormal_2000, 2000, vt_distribution("lognormal", 2000, 16))
FIXED(mk_outlier_2000, 2000, vt_distribution("outlier", 2000, 17))
FIXED(mk_decades_2000, 2000, vt_distribution("decades", 2000, 18))

static double *mk_int_circle(size_t *n) { return vt_int_circle(1105, 1, n); }

/* Exactly collinear: k * (0.25, 0.5) + (3, -7), shuffled. */
static double *mk_collinear(size_t *n) {
    *n = 500;
    double *xy = alloc_xy(*n);
    if (!xy) return NULL;
    vt_rng r = {7};
    for (size_t i = 0; i < *n; i++) {
        long k = (long)(vt_next(&r) % 100000) - 50000;
        xy[2 * i] = 3.0 + 0.25 * (double)k;
        xy[2 * i + 1] = -7.0 + 0.5 * (double)k;
    }
    return xy;
}

/* One row: equal y, random x. */
static double *mk_single_row(size_t *n) {
    *n = 300;
    double *xy = alloc_xy(*n);
    if (!xy) return NULL;
    vt_rng r = {8};
    for (size_t i = 0; i < *n; i++) {
        xy[2 * i] = vt_unit(&r);
        xy[2 * i + 1] = 0.5;
    }
    return xy;
}

/* 30 rows of 40 points, each row of equal y, x random. */
static double *mk_rows(size_t *n) {
    *n = 1200;
    double *xy = alloc_xy(*n);
    if (!xy) return NULL;
    vt_rng r = {9};
    for (size_t i = 0; i < *n; i++) {
        xy[2 * i] = vt_unit(&r) * 100.0;
        xy[2 * i + 1] = (double)(i % 30) * 3.0;
    }
    return xy;
}

/* 3000 draws from 40 distinct positions. */
static double *mk_duplicates(size_t *n) {
    *n = 3000;
    double *xy = alloc_xy(*n);
    if (!xy) return NULL;
    vt_rng r = {10};
    double pos[80];
    for (size_t i = 0; i < 80; i++) pos[i] = vt_unit(&r);
    for (size_t i = 0; i < *n; i++) {
        size_t p = (size_t)(vt_next(&r) % 40);
        xy[2 * i] = pos[2 * p];
        xy[2 * i + 1] = pos[2 * p + 1];
    }
    return xy;
}

/* 2000 sites on the parabola y = x^2, x random in [-1, 1]: convex
 * position, every site outside the hull of those inserted before it. */
static double *mk_parabola(size_t *n) {
    *n = 2000;
    double *xy = alloc_xy(*n);
    if (!xy) return NULL;
    vt_rng r = {16};
    for (size_t i = 0; i < *n; i++) {
        double x = 2 * vt_unit(&r) - 1;
        xy[2 * i] = x;
        xy[2 * i + 1] = x * x;
    }
    return xy;
}

/* A time series: 2000 readings at x = 0, 1, 2, ..., y a Gaussian random
 * walk. */
static double *mk_random_walk(size_t *n) {
    *n = 2000;
    double *xy = alloc_xy(*n);
    if (!xy) return NULL;
    vt_rng r = {17};
    double y = 0;
    for (size_t i = 0; i < *n; i++) {
        y += vt_gauss(&r);
        xy[2 * i] = (double)i;
        xy[2 * i + 1] = y;
    }
    return xy;
}

/* Six tracks of 500 positions each, as a GPS logs them: steps of 5 units
 * with a slowly turning heading, and noise of 0.5 on each position. */
static double *mk_tracks(size_t *n) {
    *n = 3000;
    double *xy = alloc_xy(*n);
    if (!xy) return NULL;
    vt_rng r = {18};
    for (size_t t = 0; t < 6; t++) {
        double x = 1000 * vt_unit(&r), y = 1000 * vt_unit(&r),
               h = 6.283185307179586 * vt_unit(&r);
        for (size_t k = 0; k < 500; k++) {
            h += 0.1 * vt_gauss(&r);
            x += 5 * cos(h);
            y += 5 * sin(h);
            size_t i = 500 * t + k;
            xy[2 * i] = x + 0.5 * vt_gauss(&r);
            xy[2 * i + 1] = y + 0.5 * vt_gauss(&r);
        }
    }
    return xy;
}

/* A 40x40 integer grid, each coordinate moved by about 10^-12: every cell
 * nearly cocircular, the circles' tops of a row within 10^-16 or so of one
 * another. */
static double *mk_jittered_grid(size_t *n) {
    double *xy = vt_grid(40, 40);
    *n = 1600;
    if (!xy) return NULL;
    vt_rng r = {19};
    for (size_t i = 0; i < 2 * *n; i++) xy[i] += 1e-12 * vt_gauss(&r);
    return xy;
}

/* A 40x40 grid turned by 45 degrees, each coordinate (i -+ j) sqrt(1/2)
 * rounded: every cell a diamond whose four sites are nearly cocircular,
 * the circles' tops of a row and the sites above them apart by less than
 * 2^-300, never equal, so that most ties go to the exact comparisons. */
static double *mk_turned_grid(size_t *n) {
    const size_t k = 40;
    double *xy = alloc_xy(k * k);
    *n = k * k;
    if (!xy) return NULL;
    const double c = 0.70710678118654757; /* sqrt(1/2), rounded */
    for (size_t i = 0; i < k; i++) {
        for (size_t j = 0; j < k; j++) {
            xy[2 * (i * k + j)] = ((double)i - (double)j) * c;
            xy[2 * (i * k + j) + 1] = ((double)i + (double)j) * c;
        }
    }
    return xy;
}

/* 1000 uniform points in a square 10^-10 wide at 0 and one stray 10^10
 * away on the diagonal: the vertices next to the stray's cell are the
 * centres of slivers (two sites 10^-10 apart, the third 10^10 away); and
 * pairs of sites 10^-7 apart on a sine curve, whose triangles with a
 * third site are needles. */
static double *mk_stray_and_needles(size_t *n) {
    *n = 1001 + 600;
    double *xy = alloc_xy(*n);
    if (!xy) return NULL;
    vt_rng r = {23};
    for (size_t i = 0; i < 1000; i++) {
        xy[2 * i] = 1e-10 * vt_unit(&r);
        xy[2 * i + 1] = 1e-10 * vt_unit(&r);
    }
    xy[2000] = 1e10;
    xy[2001] = 1e10;
    /* a sine curve sampled in pairs 10^-7 apart, away from the cluster */
    for (size_t i = 0; i < 300; i++) {
        double x = 1e3 + 100 * vt_unit(&r);
        for (int k = 0; k < 2; k++) {
            xy[2 * (1001 + 2 * i + k)] = x + 1e-7 * k;
            xy[2 * (1001 + 2 * i + k) + 1] = 1e3 + sin(x + 1e-7 * k);
        }
    }
    return xy;
}

static double *scaled_uniform(size_t n, uint64_t seed, double scale,
                              double offset) {
    double *xy = vt_uniform(n, seed);
    if (!xy) return NULL;
    for (size_t i = 0; i < 2 * n; i++) xy[i] = offset + xy[i] * scale;
    return xy;
}

FIXED(mk_offset_1e9, 2000, scaled_uniform(2000, 11, 1.0, 1e9))
FIXED(mk_scale_1e_9, 2000, scaled_uniform(2000, 12, 1e-9, 0.0))
FIXED(mk_scale_1e15, 2000, scaled_uniform(2000, 13, 1e15, 0.0))
FIXED(mk_scale_1e300, 500, scaled_uniform(500, 14, 1e300, 0.0))
FIXED(mk_scale_1e_300, 500, scaled_uniform(500, 15, 1e-300, 0.0))

/* A 30x30 grid of spacing 1/8 offset by 1e9 in x: 1e9 + k/8 is exact, so
 * the squares stay exactly cocircular far from the origin, where naive
 * circumcircle tests cannot tell. */
static double *mk_grid_offset(size_t *n) {
    double *xy = vt_grid(30, 30);
    *n = 900;
    if (!xy) return NULL;
    for (size_t i = 0; i < *n; i++) xy[2 * i] = 1e9 + xy[2 * i] * 0.125;
    return xy;
}

static double *mk_empty(size_t *n) {
    *n = 0;
    return NULL;
}

static double *small_set(size_t *n, const double *pts, size_t count) {
    double *xy = alloc_xy(count);
    if (!xy) return NULL;
    memcpy(xy, pts, count * 2 * sizeof(double));
    *n = count;
    return xy;
}

static double *mk_one(size_t *n) {
    static const double p[] = {0.5, 0.25};
    return small_set(n, p, 1);
}
static double *mk_two(size_t *n) {
    static const double p[] = {0.0, 0.0, 1.0, 2.0};
    return small_set(n, p, 2);
}
static double *mk_two_dup(size_t *n) {
    static const double p[] = {1.0, 1.0, 1.0, 1.0, -0.0, 3.0, 0.0, 3.0};
    return small_set(n, p, 4);
}
static double *mk_three_collinear(size_t *n) {
    static const double p[] = {0.0, 0.0, 2.0, 2.0, 1.0, 1.0};
    return small_set(n, p, 3);
}
static double *mk_triangle(size_t *n) {
    static const double p[] = {0.0, 0.0, 1.0, 0.0, 0.0, 1.0};
    return small_set(n, p, 3);
}
static double *mk_square(size_t *n) {
    static const double p[] = {0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0};
    return small_set(n, p, 4);
}
static double *mk_square_centre(size_t *n) {
    static const double p[] = {0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.5, 0.5};
    return small_set(n, p, 5);
}
/* Two sites of equal y first in sweep order, then sites above. */
static double *mk_equal_y_first(size_t *n) {
    static const double p[] = {0.0, 0.0, 2.0, 0.0, 4.0, 0.0, 1.0, 3.0,
                                3.0, 1.0, 2.0, 5.0};
    return small_set(n, p, 6);
}

static const struct {
    const char *name;
    make_fn make;
} sets[] = {
    {"empty", mk_empty},
    {"one", mk_one},
    {"two", mk_two},
    {"two-with-duplicates", mk_two_dup},
    {"three-collinear", mk_three_collinear},
    {"triangle", mk_triangle},
    {"square", mk_square},
    {"square-centre", mk_square_centre},
    {"equal-y-first", mk_equal_y_first},
    {"uniform-1000", mk_uniform_1000},
    {"uniform-20000", mk_uniform_20000},
    {"gaussian-2000", mk_gaussian_2000},
    {"pixels-2000", mk_pixels_2000},
    {"pixels-20000", mk_pixels_20000},
    {"grid-7x7", mk_grid_7},
    {"grid-100x100", mk_grid_100},
    {"int-circle-1105", mk_int_circle},
    {"unit-circle-2000", mk_unit_circle_2000},
    {"collinear-500", mk_collinear},
    {"single-row-300", mk_single_row},
    {"rows-30x40", mk_rows},
    {"duplicates-3000", mk_duplicates},
    {"offset-1e9", mk_offset_1e9},
    {"grid-offset-1e9", mk_grid_offset},
    {"scale-1e-9", mk_scale_1e_9},
    {"scale-1e15", mk_scale_1e15},
    {"scale-1e300", mk_scale_1e300},
    {"scale-1e-300", mk_scale_1e_300},
    {"clusters-3000", mk_clusters_3000},
    {"hex-40x40", mk_hex_40},
    {"lognormal-2000", mk_lognormal_2000},
    {"outlier-2000", mk_outlier_2000},
    {"decades-2000", mk_decades_2000},
    {"parabola-2000", mk_parabola},
    {"random-walk-2000", mk_random_walk},
    {"tracks-3000", mk_tracks},
    {"jittered-grid-40x40", mk_jittered_grid},
    {"turned-grid-40x40", mk_turned_grid},
    {"stray-and-needles", mk_stray_and_needles},
};

size_t vt_count(void) { return sizeof sets / sizeof sets[0]; }

const char *vt_set_name(size_t i) { return i < vt_count() ? sets[i].name : NULL; }

int vt_make(size_t i, vt_set *out) {
    memset(out, 0, sizeof *out);
    if (i >= vt_count()) return -1;
    size_t n = 0;
    double *xy = sets[i].make(&n);
    if (!xy && n > 0) return -1;
    out->name = sets[i].name;
    out->xy = xy;
    out->n = n;
    return 0;
}

int vt_make_named(const char *name, vt_set *out) {
    for (size_t i = 0; i < vt_count(); i++) {
        if (strcmp(sets[i].name, name) == 0) return vt_make(i, out);
    }
    memset(out, 0, sizeof *out);
    return -1;
}

void vt_set_free(vt_set *s) {
    if (!s) return;
    free(s->xy);
    memset(s, 0, sizeof *s);
}
