/* test_generate.c -- generated point sets: counts, ranges, determinism,
 * the shape each distribution promises, and the refusals. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../api/api.h"

static const char *const names[] = {"uniform", "gaussian", "random",
                                    "grid",    "circle",   "clustered"};

static double *gen(const char *name, size_t n, uint64_t seed) {
    double *xy = NULL;
    api_problem p;
    api_code c = api_generate(name, n, seed, &xy, &p);
    if (c != API_OK) fail_msg("%s n=%zu: %s", name, n, p.detail);
    return xy;
}

static void test_deterministic(void **state) {
    (void)state;
    for (size_t d = 0; d < 6; d++) {
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

static void test_uniform_and_random(void **state) {
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

    double *r = gen("random", n, 7);
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

static void test_refusals(void **state) {
    (void)state;
    double *xy = (double *)1;
    api_problem p;
    assert_int_equal(api_generate("poisson", 10, 1, &xy, &p), API_INVALID);
    assert_null(xy);
    assert_int_equal(api_code_http(p.code), 422);
    assert_string_equal(p.detail, "unknown distribution \"poisson\"; valid: "
                                  "uniform, gaussian, random, grid, circle, "
                                  "clustered");
    assert_int_equal(api_generate(NULL, 10, 1, &xy, &p), API_INVALID);
    assert_int_equal(api_generate("uniform", VOR_MAX_POINTS + 1, 1, &xy, &p),
                     API_TOO_LARGE);
    assert_int_equal(api_code_http(p.code), 413);
    assert_null(xy);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_deterministic),
        cmocka_unit_test(test_uniform_and_random),
        cmocka_unit_test(test_gaussian_and_clustered),
        cmocka_unit_test(test_grid_and_circle),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests_name("api/generate", tests, NULL, NULL);
}
