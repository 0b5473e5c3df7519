/* test_status.c -- the status and algorithm-name tables. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "../../core/vor.h"

static void test_status_table(void **state) {
    (void)state;
    assert_string_equal(vor_status_name(VOR_ENONFINITE), "VOR_ENONFINITE");
    assert_int_equal(vor_status_http(VOR_ENONFINITE), 422);
    assert_int_equal(vor_status_http(VOR_ETOOMANY), 413);
    assert_string_equal(vor_status_message(VOR_OK), "ok");
    assert_string_equal(vor_status_name((vor_status)999), "VOR_EUNKNOWN");
}

static void test_algorithm_names_round_trip(void **state) {
    (void)state;
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        vor_algorithm got;
        assert_int_equal(vor_algorithm_parse(vor_algorithm_name(a), &got), VOR_OK);
        assert_int_equal(got, a);
    }
    vor_algorithm got = VOR_FLIP;
    assert_int_equal(vor_algorithm_parse("delaunay", &got), VOR_EALGORITHM);
    assert_int_equal(vor_algorithm_parse(NULL, &got), VOR_EALGORITHM);
    assert_int_equal(got, VOR_FLIP);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_status_table),
        cmocka_unit_test(test_algorithm_names_round_trip),
    };
    return cmocka_run_group_tests_name("core/status", tests, NULL, NULL);
}
