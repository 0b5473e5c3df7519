/* test_flip.c -- the Lawson flipping Delaunay mesh: every standard point set,
 * degenerate starts (a long collinear prefix in insertion order), sites on
 * hull edges and on the lines through them, sites on interior edges, the
 * degenerate sets in many insertion orders, and the diagram built from the
 * mesh. Each mesh passes vor__mesh_check and, up to 2000 sites, a
 * brute-force empty-circle oracle (tests/core/mesh_oracle.h). */
#include "mesh_oracle.h"

static const mo_algorithm algorithm = {
    "flip",
    vor__flip_mesh,
    vor__flip_mesh_ordered,
    vor__flip,
};

static void test_standard_sets(void **state) {
    (void)state;
    mo_test_standard_sets(&algorithm);
}

static void test_collinear_start(void **state) {
    (void)state;
    mo_test_collinear_start(&algorithm);
}

static void test_sites_on_hull_edges(void **state) {
    (void)state;
    mo_test_hull_edges(&algorithm);
}

static void test_sites_on_interior_edges(void **state) {
    (void)state;
    mo_test_interior_edges(&algorithm);
}

static void test_degenerate_sets_shuffled(void **state) {
    (void)state;
    mo_test_shuffled_degenerate(&algorithm);
}

static void test_diagram_from_mesh(void **state) {
    (void)state;
    mo_test_diagram(&algorithm);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_standard_sets),
        cmocka_unit_test(test_collinear_start),
        cmocka_unit_test(test_sites_on_hull_edges),
        cmocka_unit_test(test_sites_on_interior_edges),
        cmocka_unit_test(test_degenerate_sets_shuffled),
        cmocka_unit_test(test_diagram_from_mesh),
    };
    return cmocka_run_group_tests_name("core/flip", tests, NULL, NULL);
}
