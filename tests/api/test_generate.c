/* test_generate.c -- generated point sets: counts, ranges, determinism,
 * the shape each distribution promises, the alias random = pixels, and the
 * refusals. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../api/api.h"
#include "../../api/distribution.h"

static const char *const names[] = {"uniform",   "gaussian",  "pixels",
                                    "grid",      "circle",    "clustered",
                                    "lognormal", "outlier",   "decades"};
#define N_NAMES (sizeof names / sizeof names[0])

/* Seed 1: the first uniform point, the first pixel, and where the outlier's
 * stray point lands among 1000 (values of the current generators). */
#define PIN_UNIFORM_X0 0x1.67e55eda1f8e2p-1
#define PIN_UNIFORM_Y0 0x1.0a76ab2c8e6c9p-1
#define PIN_PIXELS_X0 357.0
#define PIN_PIXELS_Y0 322.0
#define PIN_OUTLIER_STRAY 557

static double *gen(const char *name, size_t n, uint64_t seed) {
    double *xy = NULL;
    api_problem p;
    api_code c = api_generate(name, n, seed, &xy, &p);
    if (c != API_OK) fail_msg("%s n=%zu: %s", name, n, p.detail);
    return xy;
}

static void test_deterministic(void **state) {
    (void)state;
    for (size_t d = 0; d < N_NAMES; d++) {
        size_t n = 5000;
        double *a = gen(names[d], n, 42), *b = gen(names[d], n, 42);
        double *c = gen(names[d], n, 43);
        assert_memory_equal(a, b, 2 * n * sizeof(double));
        int seed_used = strcmp(names[d], "grid") && strcmp(names[d], "circle");
        if (seed_used && memcmp(a, c, 2 * n * sizeof(double)) == 0) {
            fail_msg("%s: seeds 42 and 43 give the same points", names[d]);
        }
        for (size_t i = 0; i < 2 * n; i++) assert_true(isfinite(a[i]));
        free(a);
        free(b);
        free(c);
        /* A prefix property does not hold in general, but n = 0 is empty. */
        double *z = (double *)1;
        api_problem p;
        assert_int_equal(api_generate(names[d], 0, 1, &z, &p), API_OK);
        assert_null(z);
    }
}

static void test_uniform_and_pixels(void **state) {
    (void)state;
    size_t n = 100000;
    double *u = gen("uniform", n, 7);
    double sx = 0;
    for (size_t i = 0; i < 2 * n; i++) {
        assert_true(u[i] >= 0 && u[i] < 1);
        sx += u[i];
    }
    assert_true(fabs(sx / (2.0 * n) - 0.5) < 0.01); /* mean of U(0,1) */
    free(u);

    double *r = gen("pixels", n, 7);
    int seen_x799 = 0, seen_y599 = 0;
    for (size_t i = 0; i < n; i++) {
        double x = r[2 * i], y = r[2 * i + 1];
        assert_true(x >= 0 && x < 800 && x == floor(x));
        assert_true(y >= 0 && y < 600 && y == floor(y));
        seen_x799 |= x == 799;
        seen_y599 |= y == 599;
    }
    assert_true(seen_x799 && seen_y599);
    /* 10^5 draws from 480000 pixels: duplicates are all but certain
     * (expected about 10^4), which is what this distribution is for. */
    char *hit = calloc(800 * 600, 1);
    size_t dups = 0;
    for (size_t i = 0; i < n; i++) {
        size_t k = (size_t)r[2 * i + 1] * 800 + (size_t)r[2 * i];
        dups += hit[k];
        hit[k] = 1;
    }
    assert_true(dups > 5000 && dups < 15000);
    free(hit);
    free(r);
}

static void test_gaussian_and_clustered(void **state) {
    (void)state;
    size_t n = 100000;
    double *g = gen("gaussian", n, 11);
    double m = 0, v = 0;
    for (size_t i = 0; i < 2 * n; i++) m += g[i];
    m /= 2.0 * n;
    for (size_t i = 0; i < 2 * n; i++) v += (g[i] - m) * (g[i] - m);
    v /= 2.0 * n;
    assert_true(fabs(m) < 0.01 && fabs(v - 1) < 0.02);
    free(g);

    /* 10^4 points: 10 clusters with deviation 0.1/sqrt(10): nearly every
     * point lies within 5 deviations of the unit square. */
    n = 10000;
    double *c = gen("clustered", n, 11);
    double sd = 0.1 / sqrt(10.0);
    for (size_t i = 0; i < 2 * n; i++) {
        assert_true(c[i] > -6 * sd && c[i] < 1 + 6 * sd);
    }
    free(c);
}

static void test_grid_and_circle(void **state) {
    (void)state;
    static const size_t sizes[] = {1, 2, 4, 5, 9, 10, 99, 100, 101};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        size_t n = sizes[s], k = 1;
        while (k * k < n) k++;
        double *g = gen("grid", n, 0);
        for (size_t i = 0; i < n; i++) {
            assert_true(g[2 * i] == (double)(i % k));
            assert_true(g[2 * i + 1] == (double)(i / k));
        }
        free(g);
    }
    size_t n = 1000;
    double *c = gen("circle", n, 0);
    for (size_t i = 0; i < n; i++) {
        double x = c[2 * i], y = c[2 * i + 1];
        assert_true(fabs(x * x + y * y - 1) < 1e-15);
        double t = atan2(y, x);
        if (t < 0) t += 2 * M_PI;
        assert_true(fabs(t - 2 * M_PI * (double)i / (double)n) < 1e-12);
    }
    free(c);
}

/* "random" is the course report's name for pixels: the same points, and
 * the canonical name is pixels. */
static void test_random_is_pixels(void **state) {
    (void)state;
    size_t n = 3000;
    double *a = gen("random", n, 5), *b = gen("pixels", n, 5);
    assert_memory_equal(a, b, 2 * n * sizeof(double));
    free(a);
    free(b);
    assert_string_equal(api_distribution_name("random"), "pixels");
    assert_string_equal(api_distribution_name("pixels"), "pixels");
    assert_int_equal(api_dist_find("random"), API_DIST_PIXELS);
    for (size_t d = 0; d < N_NAMES; d++) {
        assert_string_equal(api_distribution_name(names[d]), names[d]);
        assert_int_equal(api_dist_find(names[d]), (int)d);
        assert_string_equal(api_dist_name((api_dist)d), names[d]);
        assert_non_null(api_dist_text((api_dist)d));
        assert_non_null(strstr(api_dist_list(), names[d]));
    }
    assert_int_equal(API_DIST_COUNT, N_NAMES);
    assert_null(api_dist_name(API_DIST_COUNT));
    assert_null(api_dist_text(API_DIST_COUNT));
}

/* Every size gives exactly n finite points (ASan catches a write past
 * 2n doubles), and the seed flag says whether the seed matters. */
static void test_counts(void **state) {
    (void)state;
    static const size_t sizes[] = {1, 2, 3, 7, 64, 1001};
    for (size_t d = 0; d < N_NAMES; d++) {
        for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
            size_t n = sizes[s];
            double *a = gen(names[d], n, 9), *b = gen(names[d], n, 10);
            for (size_t i = 0; i < 2 * n; i++) assert_true(isfinite(a[i]));
            int same = memcmp(a, b, 2 * n * sizeof(double)) == 0;
            if (n >= 64 && same == api_dist_seeded((api_dist)d)) {
                fail_msg("%s n=%zu: seeds 9 and 10 give %s points", names[d],
                         n, same ? "the same" : "different");
            }
            free(a);
            free(b);
        }
    }
}

/* The sequences are part of the contract ("deterministic for a seed"),
 * also across versions: a bench row or a bug report names (distribution,
 * n, seed). Pinned here for the distributions that use no libm. */
static void test_pinned_values(void **state) {
    (void)state;
    double *u = gen("uniform", 2, 1);
    assert_true(u[0] == PIN_UNIFORM_X0 && u[1] == PIN_UNIFORM_Y0);
    free(u);
    double *p = gen("pixels", 2, 1);
    assert_true(p[0] == PIN_PIXELS_X0 && p[1] == PIN_PIXELS_Y0);
    free(p);
    double *o = gen("outlier", 1000, 1);
    size_t stray = 1000;
    for (size_t i = 0; i < 1000; i++)
        if (o[2 * i] == 0 && o[2 * i + 1] == 0) stray = i;
    assert_int_equal(stray, PIN_OUTLIER_STRAY);
    free(o);
}

/* exp(2 N(0,1)): positive, log(v)/2 standard normal, within the range
 * Box-Muller can reach (|N| < 8.6). */
static void test_lognormal(void **state) {
    (void)state;
    size_t n = 100000;
    double *g = gen("lognormal", n, 3);
    double m = 0, v = 0, lo = INFINITY, hi = 0;
    for (size_t i = 0; i < 2 * n; i++) {
        assert_true(g[i] > 0);
        double z = log(g[i]) / 2;
        m += z;
        v += z * z;
        if (g[i] < lo) lo = g[i];
        if (g[i] > hi) hi = g[i];
    }
    m /= 2.0 * n;
    v = v / (2.0 * n) - m * m;
    assert_true(fabs(m) < 0.01 && fabs(v - 1) < 0.02);
    assert_true(lo > exp(-17.2) && hi < exp(17.2));
    /* heavy tails: 2e5 draws reach beyond 4 deviations on both sides */
    assert_true(lo < exp(-8) && hi > exp(8));
    free(g);
}

/* n-1 points in [8.45, 8.55) x [47.25, 47.35), exactly one at (0, 0), at a
 * position that depends on the seed. */
static void test_outlier(void **state) {
    (void)state;
    size_t n = 5000, first_stray = n;
    int moved = 0;
    for (uint64_t seed = 1; seed <= 8; seed++) {
        double *o = gen("outlier", n, seed);
        size_t strays = 0, stray = n;
        double sx = 0, sy = 0;
        for (size_t i = 0; i < n; i++) {
            double x = o[2 * i], y = o[2 * i + 1];
            if (x == 0 && y == 0) {
                strays++;
                stray = i;
                continue;
            }
            assert_true(x >= 8.45 && x < 8.55 + 1e-12);
            assert_true(y >= 47.25 && y < 47.35 + 1e-12);
            sx += x;
            sy += y;
        }
        assert_int_equal(strays, 1);
        assert_true(fabs(sx / (double)(n - 1) - 8.5) < 0.005);
        assert_true(fabs(sy / (double)(n - 1) - 47.3) < 0.005);
        if (seed == 1) first_stray = stray;
        moved |= stray != first_stray;
        free(o);
    }
    assert_true(moved);
    double *one = gen("outlier", 1, 4);
    assert_true(one[0] == 0 && one[1] == 0);
    free(one);
}

/* |x|, |y| log-uniform over twelve decades: every decade [10^k, 10^(k+1)),
 * k = -6..5, holds about a twelfth of the coordinates; half are negative,
 * and x's sign says nothing about y's. */
static void test_decades(void **state) {
    (void)state;
    size_t n = 60000, decade[12] = {0}, neg = 0, same_sign = 0;
    double *d = gen("decades", n, 21);
    for (size_t i = 0; i < 2 * n; i++) {
        double a = fabs(d[i]);
        assert_true(a >= 1e-6 * (1 - 1e-15) && a < 1e6 * (1 + 1e-15));
        int k = (int)floor(log10(a)) + 6;
        if (k < 0) k = 0;
        if (k > 11) k = 11;
        decade[k]++;
        neg += d[i] < 0;
    }
    for (size_t i = 0; i < n; i++) same_sign += (d[2 * i] < 0) == (d[2 * i + 1] < 0);
    for (int k = 0; k < 12; k++) {
        double share = (double)decade[k] / (2.0 * n);
        if (fabs(share - 1.0 / 12) > 0.006) {
            fail_msg("decade 1e%d holds %.4f of the coordinates", k - 6, share);
        }
    }
    assert_true(fabs((double)neg / (2.0 * n) - 0.5) < 0.01);
    assert_true(fabs((double)same_sign / (double)n - 0.5) < 0.01);
    free(d);
}

static void test_refusals(void **state) {
    (void)state;
    double *xy = (double *)1;
    api_problem p;
    assert_int_equal(api_generate("poisson", 10, 1, &xy, &p), API_INVALID);
    assert_null(xy);
    assert_int_equal(api_code_http(p.code), 422);
    assert_string_equal(p.detail, "unknown distribution \"poisson\"; valid: "
                                  "uniform, gaussian, pixels (alias random), "
                                  "grid, circle, clustered, lognormal, "
                                  "outlier, decades");
    /* Names are matched exactly: no case folding, no prefixes. */
    assert_int_equal(api_generate("Pixels", 10, 1, &xy, &p), API_INVALID);
    assert_int_equal(api_generate("pix", 10, 1, &xy, &p), API_INVALID);
    assert_int_equal(api_generate("", 10, 1, &xy, &p), API_INVALID);
    assert_null(api_distribution_name("poisson"));
    assert_null(api_distribution_name(NULL));
    assert_int_equal(api_generate(NULL, 10, 1, &xy, &p), API_INVALID);
    assert_int_equal(api_generate("uniform", VOR_MAX_POINTS + 1, 1, &xy, &p),
                     API_TOO_LARGE);
    assert_int_equal(api_code_http(p.code), 413);
    assert_null(xy);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_deterministic),
        cmocka_unit_test(test_uniform_and_pixels),
        cmocka_unit_test(test_gaussian_and_clustered),
        cmocka_unit_test(test_grid_and_circle),
        cmocka_unit_test(test_random_is_pixels),
        cmocka_unit_test(test_counts),
        cmocka_unit_test(test_pinned_values),
        cmocka_unit_test(test_lognormal),
        cmocka_unit_test(test_outlier),
        cmocka_unit_test(test_decades),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests_name("api/generate", tests, NULL, NULL);
}
