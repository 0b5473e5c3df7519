/* test_testsets.c -- the shared test point sets are what they claim to be:
 * the integer circle is exactly cocircular with the right count, the
 * collinear set is exactly collinear, generators are deterministic. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../support/testsets.h"

static void test_every_set_builds(void **state) {
    (void)state;
    assert_true(vt_count() >= 25);
    for (size_t i = 0; i < vt_count(); i++) {
        vt_set s;
        assert_int_equal(vt_make(i, &s), 0);
        assert_string_equal(s.name, vt_set_name(i));
        assert_true(s.n == 0 || s.xy != NULL);
        vt_set_free(&s);
    }
    vt_set s;
    assert_int_equal(vt_make_named("no-such-set", &s), -1);
}

static void test_int_circle_is_exact(void **state) {
    (void)state;
    size_t n = 0;
    double *xy = vt_int_circle(1105, 1, &n);
    assert_non_null(xy);
    /* 1105 = 5 * 13 * 17, all primes 1 mod 4: r2(1105^2) = 4 * 3^3 = 108. */
    assert_int_equal(n, 109);
    for (size_t i = 0; i + 1 < n; i++) {
        double x = xy[2 * i], y = xy[2 * i + 1];
        assert_true(x * x + y * y == 1105.0 * 1105.0);
    }
    assert_true(xy[2 * (n - 1)] == 0.0 && xy[2 * (n - 1) + 1] == 0.0);
    free(xy);
}

static void test_collinear_is_exact(void **state) {
    (void)state;
    vt_set s;
    assert_int_equal(vt_make_named("collinear-500", &s), 0);
    for (size_t i = 0; i < s.n; i++) {
        /* y = 2x - 13 exactly for x = 3 + k/4, y = -7 + k/2. */
        assert_true(s.xy[2 * i + 1] == 2.0 * s.xy[2 * i] - 13.0);
    }
    vt_set_free(&s);
}

static void test_generators_deterministic(void **state) {
    (void)state;
    double *a = vt_uniform(1000, 42), *b = vt_uniform(1000, 42);
    double *c = vt_uniform(1000, 43);
    assert_memory_equal(a, b, 2000 * sizeof(double));
    assert_memory_not_equal(a, c, 2000 * sizeof(double));
    for (size_t i = 0; i < 2000; i++) assert_true(a[i] >= 0.0 && a[i] < 1.0);
    free(a);
    free(b);
    free(c);
    double *p = vt_pixels(5000, 1);
    size_t dups = 0;
    for (size_t i = 1; i < 5000; i++) {
        for (size_t j = 0; j < i; j++) {
            if (p[2 * i] == p[2 * j] && p[2 * i + 1] == p[2 * j + 1]) {
                dups++;
                break;
            }
        }
    }
    assert_true(dups > 0); /* 5000 draws from 480000 pixels collide */
    free(p);
}

/* The service's distributions through the test support: the alias gives
 * the same points, an unknown name gives NULL, the outlier set has its one
 * stray point. (tests/api/test_generate.c checks each distribution's
 * shape.) */
static void test_distributions(void **state) {
    (void)state;
    double *a = vt_distribution("random", 4000, 3);
    double *b = vt_distribution("pixels", 4000, 3);
    assert_non_null(a);
    assert_non_null(b);
    assert_memory_equal(a, b, 8000 * sizeof(double));
    free(a);
    free(b);
    assert_null(vt_distribution("poisson", 10, 1));
    assert_null(vt_distribution(NULL, 10, 1));
    double *o = vt_distribution("outlier", 300, 1);
    size_t strays = 0;
    for (size_t i = 0; i < 300; i++) strays += o[2 * i] == 0 && o[2 * i + 1] == 0;
    assert_int_equal(strays, 1);
    free(o);
    vt_set s;
    assert_int_equal(vt_make_named("decades-2000", &s), 0);
    assert_int_equal(s.n, 2000);
    vt_set_free(&s);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_set_builds),
        cmocka_unit_test(test_int_circle_is_exact),
        cmocka_unit_test(test_collinear_is_exact),
        cmocka_unit_test(test_generators_deterministic),
        cmocka_unit_test(test_distributions),
    };
    return cmocka_run_group_tests_name("tests/support/testsets", tests, NULL,
                                       NULL);
}
