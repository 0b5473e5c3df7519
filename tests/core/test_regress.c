/* test_regress.c -- inputs that once broke an algorithm, each named for
 * what broke. Every one must give VOR_OK, pass vor_check and be identical
 * from all three algorithms. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "../../core/vor.h"

static void agree(const double *xy, size_t n) {
    vor_sites *s = NULL;
    assert_int_equal(vor_sites_new(xy, n, &s, NULL), VOR_OK);
    vor_diagram *d[VOR_ALGORITHM_COUNT] = {0};
    char msg[256];
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        assert_int_equal(vor_compute(s, (vor_algorithm)a, &d[a]), VOR_OK);
        if (vor_check(d[a], s, msg, sizeof msg) != 0)
            fail_msg("%s: %s", vor_algorithm_name((vor_algorithm)a), msg);
        if (a > 0 && !vor_diagram_equal(d[0], d[a]))
            fail_msg("%s differs from %s", vor_algorithm_name((vor_algorithm)a),
                     vor_algorithm_name((vor_algorithm)0));
    }
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) vor_diagram_free(d[a]);
    vor_sites_free(s);
}

/* Found by fuzz_body: subnormal x coordinates on y = 0 plus one site at
 * 6e-154 above the origin. An exactness test in Fortune's event ordering
 * was fooled by underflow and merged vertices that are distinct. */
static void test_subnormal_row_fortune_merge(void **state) {
    (void)state;
    static const double xy[] = {
        4.510976999673251e-308, 0.0, 0.0, 0.0, 0.0, 5.966672584960166e-154,
        2.8728e-319, 0.0, 2.91412e-318, 0.0, 1.2350678627e-314, 0.0,
    };
    agree(xy, sizeof xy / sizeof xy[0] / 2);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_subnormal_row_fortune_merge),
    };
    return cmocka_run_group_tests_name("core/regress", tests, NULL, NULL);
}
