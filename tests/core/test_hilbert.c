/* test_hilbert.c -- vor__insertion_order: a deterministic permutation with
 * spatial locality inside rounds and a random first round (BRIO).
 *
 * Locality is measured as the mean distance between consecutive sites of
 * the order, against the mean for a random order of the same sites (about
 * 0.52 times the side for uniform points in a square). Random sets use a
 * fixed seed, printed; VOR_TEST_SEED replays another.
 */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../core/internal.h"
#include "../support/testsets.h"

static uint64_t seed;

static int setup_seed(void **state) {
    (void)state;
    const char *s = getenv("VOR_TEST_SEED");
    seed = s ? strtoull(s, NULL, 0) : 20240614u;
    printf("# test_hilbert seed %llu (set VOR_TEST_SEED to change)\n",
           (unsigned long long)seed);
    return 0;
}

/* Runs the order, checks it is a permutation of 0..n-1 and that a second
 * run (on a copy at another address) gives the same; returns it. */
static uint32_t *order_of(const double *xy, size_t n) {
    uint32_t *o = malloc((n ? n : 1) * sizeof *o);
    uint32_t *o2 = malloc((n ? n : 1) * sizeof *o2);
    double *copy = malloc((n ? 2 * n : 1) * sizeof *copy);
    uint8_t *seen = calloc(n ? n : 1, 1);
    assert_true(o && o2 && copy && seen);
    if (n)
        memcpy(copy, xy, 2 * n * sizeof *copy);
    assert_int_equal(vor__insertion_order(xy, n, o), VOR_OK);
    assert_int_equal(vor__insertion_order(copy, n, o2), VOR_OK);
    for (size_t i = 0; i < n; i++) {
        assert_true(o[i] < n);
        assert_false(seen[o[i]]);
        seen[o[i]] = 1;
    }
    assert_memory_equal(o, o2, n * sizeof *o);
    free(o2);
    free(copy);
    free(seen);
    return o;
}

/* Distance between sites i and j, in long double: a difference of two
 * doubles may overflow a double. */
static long double dist(const double *xy, uint32_t i, uint32_t j) {
    return hypotl((long double)xy[2 * i] - xy[2 * j],
                  (long double)xy[2 * i + 1] - xy[2 * j + 1]);
}

/* Mean distance between consecutive sites of the order, divided by the
 * same mean over a random order (Fisher-Yates with the test seed). */
static double locality_ratio(const double *xy, size_t n, const uint32_t *o) {
    long double along = 0, random = 0;
    uint32_t *p = malloc(n * sizeof *p);
    assert_non_null(p);
    vt_rng r = {seed};
    for (size_t i = 0; i < n; i++)
        p[i] = (uint32_t)i;
    for (size_t i = n - 1; i > 0; i--) {
        size_t j = vt_next(&r) % (i + 1);
        uint32_t t = p[i];
        p[i] = p[j];
        p[j] = t;
    }
    for (size_t i = 1; i < n; i++) {
        along += dist(xy, o[i], o[i - 1]);
        random += dist(xy, p[i], p[i - 1]);
    }
    free(p);
    return (double)(along / random);
}

static void test_permutation_sizes(void **state) {
    (void)state;
    const size_t sizes[] = {0, 1, 2, 3, 5, 63, 64, 65, 1000, 4097, 100000};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        size_t n = sizes[k];
        double *xy = vt_uniform(n ? n : 1, seed + k);
        assert_non_null(xy);
        free(order_of(xy, n));
        free(xy);
    }
}

static void test_locality_uniform(void **state) {
    (void)state;
    size_t n = 10000;
    double *xy = vt_uniform(n, seed);
    assert_non_null(xy);
    uint32_t *o = order_of(xy, n);
    double ratio = locality_ratio(xy, n, o);
    printf("# 10^4 uniform: consecutive distance %.4f of a random order's\n",
           ratio);
    assert_true(ratio < 0.1);

    /* BRIO, not a plain curve order: the first 100 sites are a random
     * sample spread over the square, not one corner of the curve */
    double x0 = 1, x1 = 0, y0 = 1, y1 = 0;
    for (size_t i = 0; i < 100; i++) {
        double x = xy[2 * o[i]], y = xy[2 * o[i] + 1];
        x0 = fmin(x0, x);
        x1 = fmax(x1, x);
        y0 = fmin(y0, y);
        y1 = fmax(y1, y);
    }
    printf("# first 100 sites span %.2f x %.2f\n", x1 - x0, y1 - y0);
    assert_true(x1 - x0 > 0.5 && y1 - y0 > 0.5);
    free(o);
    free(xy);
}

/* Scaling by a power of two changes no key: the order must be identical. */
static void test_power_of_two_scales(void **state) {
    (void)state;
    size_t n = 5000;
    double *xy = vt_uniform(n, seed + 1);
    double *s = malloc(2 * n * sizeof *s);
    assert_true(xy && s);
    uint32_t *o = order_of(xy, n);
    const int exps[] = {1000, -900, 500, -500, 1};
    for (size_t k = 0; k < sizeof exps / sizeof exps[0]; k++) {
        for (size_t i = 0; i < 2 * n; i++)
            s[i] = ldexp(2 * xy[i] - 1, exps[k]); /* centred: negatives */
        uint32_t *os = order_of(s, n);
        double *c = malloc(2 * n * sizeof *c);
        assert_non_null(c);
        for (size_t i = 0; i < 2 * n; i++)
            c[i] = 2 * xy[i] - 1;
        uint32_t *oc = order_of(c, n);
        assert_memory_equal(os, oc, n * sizeof *os);
        free(os);
        free(oc);
        free(c);
    }
    free(o);
    free(s);
    free(xy);
}

/* Extreme ranges: spans that overflow, tiny and subnormal spans, mixed
 * magnitudes, all x equal, all points equal. */
static void test_extreme_ranges(void **state) {
    (void)state;
    size_t n = 4000;
    double *u = vt_uniform(n, seed + 2);
    double *xy = malloc(2 * n * sizeof *xy);
    assert_true(u && xy);
    struct {
        const char *name;
        double scale, offset;
    } cases[] = {
        {"span 2 DBL_MAX", DBL_MAX, 0}, {"1e300", 1e300, 0},
        {"1e-300", 1e-300, 0},          {"subnormal", 1e-310, 0},
        {"1 at 1e9", 1, 1e9},           {"1e15", 1e15, -1e15},
        {"1e-9 at 1e-3", 1e-9, 1e-3},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        for (size_t i = 0; i < 2 * n; i++)
            xy[i] = (2 * u[i] - 1) * cases[k].scale + cases[k].offset;
        uint32_t *o = order_of(xy, n);
        double ratio = locality_ratio(xy, n, o);
        printf("# %-14s locality %.4f\n", cases[k].name, ratio);
        assert_true(ratio < 0.15);
        free(o);
    }
    /* mixed: most points tiny, a few huge */
    for (size_t i = 0; i < 2 * n; i++)
        xy[i] = i % 97 == 0 ? (2 * u[i] - 1) * 1e300 : u[i] * 1e-300;
    free(order_of(xy, n));
    /* all x equal: ordered along y */
    for (size_t i = 0; i < n; i++) {
        xy[2 * i] = 42;
        xy[2 * i + 1] = u[i];
    }
    uint32_t *o = order_of(xy, n);
    double ratio = locality_ratio(xy, n, o);
    printf("# all x equal    locality %.4f\n", ratio);
    assert_true(ratio < 0.1);
    free(o);
    /* all points equal */
    for (size_t i = 0; i < 2 * n; i++)
        xy[i] = -3.25;
    free(order_of(xy, n));
    free(xy);
    free(u);
}

/* Position of cell (x, y) along the Hilbert curve over a 2^bits grid,
 * the textbook way: quadrant by quadrant, rotating the remaining
 * coordinates into the sub-square's frame. Quadrants in the order (0,0),
 * (0,1), (1,1), (1,0). */
static uint32_t textbook_hilbert(uint32_t x, uint32_t y, int bits) {
    uint32_t d = 0;
    for (uint32_t s = (uint32_t)1 << (bits - 1); s > 0; s >>= 1) {
        uint32_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
        d += s * s * ((3 * rx) ^ ry);
        if (ry == 0) {
            if (rx == 1) {
                x = s - 1 - (x & (s - 1));
                y = s - 1 - (y & (s - 1));
            }
            uint32_t t = x;
            x = y;
            y = t;
        }
        x &= s - 1;
        y &= s - 1;
    }
    return d;
}

static int cmp_size(const void *a, const void *b) {
    size_t x = *(const size_t *)a, y = *(const size_t *)b;
    return (x > y) - (x < y);
}

/* Median, over consecutive sites p, q of the order, of the number of sites
 * closer to p than q is: a measure of locality that does not depend on
 * scale (random order: about n / 4; a good spatial order: a few). The
 * median, because the small early rounds of BRIO jump far by design.
 * O(n^2). */
static size_t neighbour_rank(const double *xy, size_t n, const uint32_t *o) {
    size_t *closer = calloc(n, sizeof *closer);
    assert_non_null(closer);
    for (size_t i = 1; i < n; i++) {
        long double d = dist(xy, o[i - 1], o[i]);
        for (size_t j = 0; j < n; j++)
            closer[i - 1] += dist(xy, o[i - 1], (uint32_t)j) < d;
    }
    qsort(closer, n - 1, sizeof *closer, cmp_size);
    size_t median = closer[(n - 1) / 2];
    free(closer);
    return median;
}

/* Skewed, heavy-tailed and multi-scale sets, where a grid over the
 * bounding box puts nearly every site into one cell: the order must still
 * be local at every scale. A fixed grid over the bounding box alone leaves
 * the sites of a crowded cell in input order (a median rank of 12 on the
 * lognormal set, growing with n); refinements capped at 64 levels left
 * the smallest three fifths of the last set in input order (rank 83). */
static void test_locality_skewed(void **state) {
    (void)state;
    const size_t n = 2000;
    const char *names[] = {"lognormal", "outlier", "decades", "nested",
                           "1800 binary orders on a line"};
    double *xy = malloc(2 * n * sizeof *xy);
    assert_non_null(xy);
    for (int k = 0; k < 5; k++) {
        vt_rng r = {seed + (uint64_t)k};
        for (size_t i = 0; i < n; i++) {
            double *p = xy + 2 * i;
            switch (k) {
            case 0: /* exp(2 N(0,1)) per axis */
                p[0] = exp(2 * vt_gauss(&r));
                p[1] = exp(2 * vt_gauss(&r));
                break;
            case 1: /* a city, and one failed geocode at (0, 0) */
                p[0] = i == n / 2 ? 0 : 8.45 + 0.1 * vt_unit(&r);
                p[1] = i == n / 2 ? 0 : 47.25 + 0.1 * vt_unit(&r);
                break;
            case 2: /* |x|, |y| log-uniform over twelve decades, signs */
                p[0] = pow(10, 12 * vt_unit(&r) - 6) *
                       (vt_next(&r) & 1 ? 1 : -1);
                p[1] = pow(10, 12 * vt_unit(&r) - 6) *
                       (vt_next(&r) & 1 ? 1 : -1);
                break;
            case 3: { /* clusters of sizes from 1e-9 to 1e-1 */
                double c = (double)(vt_next(&r) % 10);
                double size = pow(10, -1 - (double)(vt_next(&r) % 9));
                p[0] = c + size * vt_gauss(&r);
                p[1] = c * 0.5 + size * vt_gauss(&r);
                break;
            }
            default: /* x log-uniform over 2^-900 .. 2^900, y near x:
                      * about 164 levels of refinement deep */
                p[0] = pow(2, 1800 * vt_unit(&r) - 900);
                p[1] = p[0] * (1 + 1e-3 * vt_unit(&r));
            }
        }
        uint32_t *o = order_of(xy, n);
        size_t rank = neighbour_rank(xy, n, o);
        printf("# %s: median neighbour rank of consecutive sites %zu\n",
               names[k], rank);
        assert_true(rank <= 8);
        free(o);
    }
    free(xy);
}

/* Mean distance between consecutive sites of order o that both lie in
 * the box [x0, x0 + 1] x [y0, y0 + 1]. */
static double mean_step_in(const double *xy, size_t n, const uint32_t *o,
                           double x0, double y0) {
    long double sum = 0;
    size_t k = 0;
    for (size_t i = 1; i < n; i++) {
        const double *p = xy + 2 * (size_t)o[i - 1], *q = xy + 2 * (size_t)o[i];
        if (p[0] < x0 || p[0] > x0 + 1 || p[1] < y0 || p[1] > y0 + 1 ||
            q[0] < x0 || q[0] > x0 + 1 || q[1] < y0 || q[1] > y0 + 1)
            continue;
        sum += dist(xy, o[i - 1], o[i]);
        k++;
    }
    return k ? (double)(sum / (long double)k) : 0;
}

/* A dense city and a few far strays: the grid goes over the city, the
 * strays go to its edge cells, and no site is keyed twice (the grid over
 * the whole box put the city into a few cells, refined one by one); the
 * city's sites come as close together as without the strays. More
 * strays than n / 1024 are a tail, and the box keeps them. */
static void test_far_strays(void **state) {
    (void)state;
    const size_t n = 20000;
    double *xy = malloc(2 * n * sizeof *xy);
    assert_non_null(xy);
    for (int strays = 3; strays <= 40; strays += 37) {
        vt_rng r = {seed + 7};
        for (size_t i = 0; i < n; i++) {
            xy[2 * i] = 8.45 + 0.1 * vt_unit(&r);
            xy[2 * i + 1] = 47.25 + 0.1 * vt_unit(&r);
        }
        uint32_t *oc = order_of(xy, n);
        double alone = mean_step_in(xy, n, oc, 8, 47);
        free(oc);
        for (int k = 0; k < strays; k++) { /* spread over the input */
            size_t i = (size_t)k * (n / (size_t)strays) + 11;
            xy[2 * i] = k % 2 ? 0 : -120 + 7 * k;
            xy[2 * i + 1] = k % 3 ? 0 : 60 - 5 * k;
        }
        vor_counts c;
        memset(&c, 0, sizeof c);
        uint32_t *o = order_of(xy, n);
        assert_int_equal(vor__insertion_order_counted(xy, n, o, &c), VOR_OK);
        double step = mean_step_in(xy, n, o, 8, 47);
        printf("# %d far strays: %llu refinements, the city's step %.3g "
               "(alone %.3g)\n", strays,
               (unsigned long long)c.order_refinements, step, alone);
        if (strays == 3)
            assert_int_equal(c.order_refinements, 0);
        else
            assert_true(c.order_refinements > 0);
        assert_true(step < 1.25 * alone);
        free(o);
    }
    free(xy);
}

/* On the 256 x 256 integer grid every site has its own cell of the
 * 2^8 grid, so inside a round the sites must come in strictly increasing
 * textbook curve position; a decrease marks the start of a round. The
 * rounds: about log8(n / 64) + 1 of them, the last holding about 7/8 of
 * the sites. */
static void test_curve_and_rounds(void **state) {
    (void)state;
    size_t w = 256, n = w * w;
    double *xy = vt_grid(w, w);
    assert_non_null(xy);
    uint32_t *o = order_of(xy, n);
    size_t runs = 1, last_start = 0;
    for (size_t i = 1; i < n; i++) {
        uint32_t a = textbook_hilbert((uint32_t)xy[2 * o[i - 1]],
                                      (uint32_t)xy[2 * o[i - 1] + 1], 8);
        uint32_t b = textbook_hilbert((uint32_t)xy[2 * o[i]],
                                      (uint32_t)xy[2 * o[i] + 1], 8);
        assert_true(a != b);
        if (b < a) {
            runs++;
            last_start = i;
        }
    }
    double last = (double)(n - last_start) / (double)n;
    printf("# 256 x 256 grid: %zu increasing runs, the last %.3f of the "
           "sites\n", runs, last);
    assert_true(runs >= 4 && runs <= 5); /* 5 rounds for 2^16 sites */
    assert_true(last > 0.85 && last < 0.90);
    free(o);
    free(xy);
}

/* The median of v[0..m-1] (m > 0), which it sorts (by insertion: m is
 * small). */
static double median(double *v, size_t m) {
    for (size_t i = 1; i < m; i++)
        for (size_t j = i; j > 0 && v[j - 1] > v[j]; j--) {
            double t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
    return v[m / 2];
}

/* Windows of 64 consecutive sites of the last round (from n / 4 on): the
 * median of their extents in x and in y. */
static void window_extents(const double *xy, size_t n, const uint32_t *o,
                           double *ex, double *ey) {
    enum { WIN = 64 };
    size_t m = 0, cap = n / WIN + 1;
    double *wx = malloc(cap * sizeof *wx), *wy = malloc(cap * sizeof *wy);
    assert_true(wx && wy);
    for (size_t i = n / 4; i + WIN <= n; i += WIN) {
        double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
        for (size_t j = i; j < i + WIN; j++) {
            const double *p = xy + 2 * o[j];
            x0 = fmin(x0, p[0]);
            x1 = fmax(x1, p[0]);
            y0 = fmin(y0, p[1]);
            y1 = fmax(y1, p[1]);
        }
        wx[m] = x1 - x0;
        wy[m++] = y1 - y0;
    }
    *ex = median(wx, m);
    *ey = median(wy, m);
    free(wx);
    free(wy);
}

/* Rows: 100 rows of equal y, 1 apart, of 400 sites each in x in [0, 1]
 * (0.0025 apart), with and without a jitter of 10^-7 in y, and the same
 * as columns. Their triangles are long and thin, between neighbouring
 * rows: the curve must fill neighbouring rows together (64 consecutive
 * sites over several rows and a short piece of each), not a row at a
 * time (a square cell of the bounding square holds 16 sites of one
 * row, and 64 consecutive sites lie on one or two rows over a fifth of
 * its length). A box as long (1 x 100) of uniform sites has triangles
 * of every direction: its windows must stay about as wide as high. A
 * city and one stray point at (0, 0) sit on two levels of each axis,
 * unevenly filled: no rows there, the windows stay square. Two dense
 * clusters 10^6 apart in x fill two levels of x evenly, but each is as
 * tall as it is wide: not columns, and the windows in each stay square
 * (flattened into columns, 64 consecutive sites spanned a whole
 * cluster's width and a sliver of its height). */
static void test_rows_and_columns(void **state) {
    (void)state;
    const size_t rows = 100, per = 400, n = rows * per;
    double *xy = malloc(2 * n * sizeof *xy);
    assert_non_null(xy);
    for (int k = 0; k < 7; k++) {
        vt_rng r = {seed + (uint64_t)k};
        for (size_t i = 0; i < n; i++) {
            double along = vt_unit(&r), level = (double)(i % rows);
            if (k == 1 || k == 3)
                level += 1e-7 * vt_unit(&r);
            if (k == 4)
                level = 100 * vt_unit(&r);
            int columns = k == 2 || k == 3;
            xy[2 * i] = columns ? level : along;
            xy[2 * i + 1] = columns ? along : level;
            if (k == 5) { /* the city: degrees; the stray point */
                xy[2 * i] = i == n / 3 ? 0 : 8.45 + 0.1 * vt_unit(&r);
                xy[2 * i + 1] = i == n / 3 ? 0 : 47.25 + 0.1 * vt_unit(&r);
            }
            if (k == 6) { /* two clusters, 0.01 wide */
                xy[2 * i] = 1e6 * (double)(i % 2) + 0.01 * vt_unit(&r);
                xy[2 * i + 1] = 0.01 * vt_unit(&r);
            }
        }
        uint32_t *o = order_of(xy, n);
        double ex, ey;
        window_extents(xy, n, o, &ex, &ey);
        static const char *names[] = {"rows",          "jittered rows",
                                      "columns",       "jittered columns",
                                      "1 x 100 box",   "city and stray",
                                      "two clusters"};
        printf("# %s: 64 consecutive sites span %.4g x %.4g (median)\n",
               names[k], ex, ey);
        double along = k == 2 || k == 3 ? ey : ex,
               across = k == 2 || k == 3 ? ex : ey;
        if (k < 4) {
            assert_true(across >= 3);   /* several rows */
            assert_true(along < 0.05);  /* a short piece of each */
        } else {
            assert_true(ex < 4 * ey && ey < 4 * ex); /* square windows */
        }
        free(o);
    }
    free(xy);
}

/* Every standard set gives a permutation, deterministically. */
static void test_standard_sets(void **state) {
    (void)state;
    for (size_t i = 0; i < vt_count(); i++) {
        vt_set set;
        assert_int_equal(vt_make(i, &set), 0);
        free(order_of(set.xy, set.n));
        vt_set_free(&set);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_permutation_sizes),
        cmocka_unit_test(test_locality_uniform),
        cmocka_unit_test(test_power_of_two_scales),
        cmocka_unit_test(test_extreme_ranges),
        cmocka_unit_test(test_curve_and_rounds),
        cmocka_unit_test(test_locality_skewed),
        cmocka_unit_test(test_rows_and_columns),
        cmocka_unit_test(test_far_strays),
        cmocka_unit_test(test_standard_sets),
    };
    return cmocka_run_group_tests_name("core/hilbert", tests, setup_seed,
                                       NULL);
}
