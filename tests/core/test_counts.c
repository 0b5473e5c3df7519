/* test_counts.c -- operation counts (vor_counts, vor_compute_ex): the
 * table, determinism, and what theory says about them.
 *
 *   - the table: every count has a name, a description and the algorithms
 *     it applies to; counts outside an algorithm stay 0;
 *   - determinism: a grid, points on a circle and a random set give the
 *     same counts on every run, with or without the counts asked for;
 *   - identities: Bowyer-Watson makes 2n - 2 more triangles than it
 *     removes (the sphere triangulation's Euler count, ghosts included);
 *     Fortune has one site event per distinct site, and its circle events
 *     and breakpoint hits are the 2n - 2 - h triangles of the Delaunay
 *     triangulation (h sites with unbounded cells); every orientation and
 *     in-circle test the incremental algorithms make is counted once, so
 *     the exact ones are at most their sum;
 *   - theory: for uniform points in random-ish (BRIO) order, Bowyer-
 *     Watson's created triangles and in-circle tests per site and flip's
 *     flips per site stay bounded as n grows tenfold twice (expected O(1)
 *     per site), and Fortune's beach line stays within a constant of
 *     sqrt(n) (its expected size);
 *   - exactness: on an integer grid, where four sites are cocircular
 *     everywhere and rows are collinear, the filters cannot decide and
 *     exact arithmetic is counted; the insertion order refines the
 *     crowded cell of a dense cluster with one far outlier;
 *   - input no algorithm sees counts nothing. */
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

static vor_sites *sites_of(const double *xy, size_t n) {
    vor_sites *s = NULL;
    assert_int_equal(vor_sites_new(xy, n, &s, NULL), VOR_OK);
    return s;
}

static vor_counts counts_of(const vor_sites *s, vor_algorithm a) {
    vor_counts c;
    memset(&c, 0xab, sizeof c); /* must be overwritten */
    vor_options o = {.counts = &c};
    vor_diagram *d = NULL;
    assert_int_equal(vor_compute_ex(s, a, &o, &d), VOR_OK);
    vor_diagram_free(d);
    return c;
}

static void test_table(void **state) {
    (void)state;
    assert_true(VOR_COUNT_FIELDS >= 15);
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++) {
        assert_non_null(vor_count_name(i));
        assert_true(strlen(vor_count_what(i)) > 10);
        assert_true(vor_count_algorithms(i) != 0);
        assert_true((vor_count_algorithms(i) & ~VOR_IN_ALL) == 0);
        for (size_t j = 0; j < i; j++)
            assert_string_not_equal(vor_count_name(i), vor_count_name(j));
    }
    assert_null(vor_count_name(VOR_COUNT_FIELDS));
    assert_int_equal(vor_count_algorithms(VOR_COUNT_FIELDS), 0);
    vor_counts c;
    memset(&c, 0, sizeof c);
    c.flips = 42;
    int found = 0;
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++) {
        if (strcmp(vor_count_name(i), "flips") == 0) {
            assert_int_equal(vor_count_value(&c, i), 42);
            assert_int_equal(vor_count_algorithms(i), VOR_IN_FLIP);
            found = 1;
        } else {
            assert_int_equal(vor_count_value(&c, i), 0);
        }
    }
    assert_true(found);
    assert_int_equal(vor_count_value(NULL, 0), 0);
    assert_int_equal(vor_count_value(&c, VOR_COUNT_FIELDS), 0);
}

/* Counts of a's inapplicable fields are 0, of the basic ones not. */
static void check_applies(const vor_counts *c, vor_algorithm a) {
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++) {
        if (!(vor_count_algorithms(i) & (1u << a)))
            assert_int_equal(vor_count_value(c, i), 0);
    }
    if (a == VOR_FORTUNE) {
        assert_true(c->site_events > 0 && c->circle_events > 0);
        assert_true(c->breakpoint_tests > 0 && c->circle_tops > 0);
    } else {
        assert_true(c->orient2d > 0 && c->incircle > 0 && c->walk_steps > 0);
        assert_true(c->order_rounds > 0 && c->order_keys > 0);
    }
}

static void test_deterministic(void **state) {
    (void)state;
    const char *sets[] = {"grid-100x100", "unit-circle-2000", "uniform-1000",
                          "duplicates-3000"};
    for (size_t k = 0; k < sizeof sets / sizeof sets[0]; k++) {
        vt_set set;
        assert_int_equal(vt_make_named(sets[k], &set), 0);
        vor_sites *s = sites_of(set.xy, set.n);
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            vor_counts c1 = counts_of(s, (vor_algorithm)a);
            vor_counts c2 = counts_of(s, (vor_algorithm)a);
            assert_memory_equal(&c1, &c2, sizeof c1);
            check_applies(&c1, (vor_algorithm)a);
            /* the same diagram as vor_compute's */
            vor_diagram *d1 = NULL, *d2 = NULL;
            vor_options o = {.counts = &c2};
            assert_int_equal(vor_compute(s, (vor_algorithm)a, &d1), VOR_OK);
            assert_int_equal(vor_compute_ex(s, (vor_algorithm)a, &o, &d2), VOR_OK);
            assert_true(vor_diagram_equal(d1, d2));
            vor_diagram_free(d1);
            vor_diagram_free(d2);
        }
        print_message("%s: deterministic\n", sets[k]);
        vor_sites_free(s);
        vt_set_free(&set);
    }
}

static void test_identities(void **state) {
    (void)state;
    for (size_t i = 0; i < vt_count(); i++) {
        vt_set set;
        assert_int_equal(vt_make(i, &set), 0);
        vor_sites *s = sites_of(set.xy, set.n);
        if (vor__all_collinear(s)) {
            for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
                vor_counts c = counts_of(s, (vor_algorithm)a), zero;
                memset(&zero, 0, sizeof zero);
                assert_memory_equal(&c, &zero, sizeof c);
            }
            vor_sites_free(s);
            vt_set_free(&set);
            continue;
        }
        vor_diagram *d = NULL;
        assert_int_equal(vor_compute(s, VOR_FORTUNE, &d), VOR_OK);
        uint64_t n = s->n, h = 0;
        for (size_t j = 0; j < s->n; j++) h += !d->cell_bounded[j];
        vor_diagram_free(d);

        vor_counts f = counts_of(s, VOR_FORTUNE);
        assert_int_equal(f.site_events, n);
        assert_int_equal(f.circle_events + f.breakpoint_hits, 2 * n - 2 - h);
        assert_int_equal(f.exact, f.breakpoint_exact + f.circle_top_exact +
                                      f.event_exact);
        assert_true(f.beach_max >= 2 && f.beach_max <= 2 * n - 1);
        assert_true(f.breakpoint_exact <= f.breakpoint_tests);
        assert_true(f.circle_top_exact <= f.circle_tops);
        assert_true(f.event_exact <= f.event_compares);

        vor_counts b = counts_of(s, VOR_BOWYER_WATSON);
        assert_int_equal(b.triangles_created - b.cavity_triangles, 2 * n - 2);
        assert_true(b.exact <= b.orient2d + b.incircle);
        assert_true(b.order_keys >= n);

        vor_counts l = counts_of(s, VOR_FLIP);
        /* each insertion nets two triangles; each flip makes two */
        assert_true(l.triangles_created >= 2 * n - 2 + 2 * l.flips);
        assert_true(l.exact <= l.orient2d + l.incircle);
        /* the same insertion order */
        assert_int_equal(l.order_keys, b.order_keys);
        assert_int_equal(l.order_rounds, b.order_rounds);
        assert_int_equal(l.order_refinements, b.order_refinements);
        vor_sites_free(s);
        vt_set_free(&set);
    }
}

static void test_bounded_per_site(void **state) {
    (void)state;
    const uint64_t seed = 77;
    print_message("uniform sets: seed %llu\n", (unsigned long long)seed);
    double created[3], incircle[3], flips[3];
    const size_t ns[3] = {1000, 10000, 100000};
    for (int k = 0; k < 3; k++) {
        double *xy = vt_uniform(ns[k], seed);
        assert_non_null(xy);
        vor_sites *s = sites_of(xy, ns[k]);
        double n = (double)s->n;
        vor_counts b = counts_of(s, VOR_BOWYER_WATSON);
        vor_counts l = counts_of(s, VOR_FLIP);
        vor_counts f = counts_of(s, VOR_FORTUNE);
        created[k] = (double)b.triangles_created / n;
        incircle[k] = (double)b.incircle / n;
        flips[k] = (double)l.flips / n;
        print_message("n %zu: created %.3f, incircle %.3f, walk %.3f per site "
                      "(bowyer-watson); flips %.3f per site; beach %llu "
                      "(%.2f sqrt n)\n",
                      s->n, created[k], incircle[k],
                      (double)b.walk_steps / n, flips[k],
                      (unsigned long long)f.beach_max,
                      (double)f.beach_max / sqrt(n));
        /* a triangulation's average degree is below 6: the stars of
         * expected O(1) insertions, a few ghosts */
        assert_true(created[k] < 8);
        assert_true(flips[k] < 5);
        assert_true((double)b.walk_steps / n < 6);
        assert_true((double)f.beach_max < 4 * sqrt(n));
        vor_sites_free(s);
        free(xy);
    }
    /* bounded: not growing with n (a 10% drift over a hundredfold) */
    assert_true(created[2] < 1.1 * created[0]);
    assert_true(incircle[2] < 1.1 * incircle[0]);
    assert_true(flips[2] < 1.1 * flips[0]);
}

/* Point location must not walk far on any input: a fixed grid over the
 * bounding box once left the sites of a crowded cell in input order, and
 * on log-normal or outlier sets the walk grew with sqrt(n). On every
 * distribution the service offers, at two sizes, Bowyer-Watson's and
 * flip's walks stay a few steps per site and do not grow tenfold. */
static void test_walk_every_distribution(void **state) {
    (void)state;
    static const char *const dists[] = {"uniform", "gaussian", "pixels",
                                        "grid", "circle", "clustered",
                                        "lognormal", "outlier", "decades"};
    const uint64_t seed = 11;
    print_message("walk steps per site, seed %llu\n", (unsigned long long)seed);
    for (size_t k = 0; k < sizeof dists / sizeof dists[0]; k++) {
        double walk[2][2];
        const size_t ns[2] = {2000, 20000};
        for (int j = 0; j < 2; j++) {
            double *xy = vt_distribution(dists[k], ns[j], seed);
            assert_non_null(xy);
            vor_sites *s = sites_of(xy, ns[j]);
            vor_counts b = counts_of(s, VOR_BOWYER_WATSON);
            vor_counts l = counts_of(s, VOR_FLIP);
            walk[j][0] = (double)b.walk_steps / (double)s->n;
            walk[j][1] = (double)l.walk_steps / (double)s->n;
            vor_sites_free(s);
            free(xy);
        }
        print_message("  %-10s %.2f -> %.2f (bowyer-watson), %.2f -> %.2f "
                      "(flip)\n", dists[k], walk[0][0], walk[1][0],
                      walk[0][1], walk[1][1]);
        for (int a = 0; a < 2; a++) {
            assert_true(walk[1][a] < 8);
            assert_true(walk[1][a] < 1.5 * walk[0][a] + 1);
        }
    }
}

/* Sites in convex position (a parabola, an ellipse): every site lies
 * just outside the hull of those before it, and the walk goes along the
 * hull from the site before, not through the long thin triangles of the
 * interior (16.6 orientation tests a site on the parabola that way at
 * 10^5 sites, 9.5 along the hull). Both diagrams must match Fortune's. */
static void test_walk_convex(void **state) {
    (void)state;
    enum { N = 20000 };
    static double xy[2 * N];
    vt_rng r = {29};
    print_message("convex position: seed 29\n");
    for (int set = 0; set < 2; set++) {
        for (size_t i = 0; i < N; i++) {
            double u = vt_unit(&r);
            if (set == 0) {
                xy[2 * i] = 2 * u - 1;
                xy[2 * i + 1] = xy[2 * i] * xy[2 * i];
            } else {
                xy[2 * i] = 3 * cos(6.283185307179586 * u);
                xy[2 * i + 1] = sin(6.283185307179586 * u);
            }
        }
        vor_sites *s = sites_of(xy, N);
        vor_diagram *f = NULL;
        assert_int_equal(vor_compute(s, VOR_FORTUNE, &f), VOR_OK);
        for (vor_algorithm a = VOR_BOWYER_WATSON; a <= VOR_FLIP; a++) {
            vor_counts c = counts_of(s, a);
            double per = (double)c.orient2d / (double)s->n;
            print_message("  %s, %s: %.2f orientation tests a site\n",
                          set ? "ellipse" : "parabola", vor_algorithm_name(a),
                          per);
            assert_true(per < 12);
            vor_diagram *d = NULL;
            assert_int_equal(vor_compute(s, a, &d), VOR_OK);
            assert_true(vor_diagram_equal(d, f));
            vor_diagram_free(d);
        }
        vor_diagram_free(f);
        vor_sites_free(s);
    }
}

static void test_exact_and_refined(void **state) {
    (void)state;
    vt_set set;
    assert_int_equal(vt_make_named("grid-100x100", &set), 0);
    vor_sites *s = sites_of(set.xy, set.n);
    vor_counts b = counts_of(s, VOR_BOWYER_WATSON);
    vor_counts l = counts_of(s, VOR_FLIP);
    vor_counts f = counts_of(s, VOR_FORTUNE);
    assert_true(b.exact > 0);
    assert_true(l.exact > 0);
    assert_true(f.circle_top_exact > 0); /* collinear triples in a row */
    assert_true(f.exact > 0);
    vor_sites_free(s);
    vt_set_free(&set);

    /* a city of 3000 points in a 0.1 x 0.1 square and one stray at (0, 0):
     * the insertion order's grid over the whole set puts the city into
     * one cell, which is ordered again on a grid of its own */
    double *xy = vt_uniform(3001, 5);
    assert_non_null(xy);
    for (size_t i = 0; i < 3000; i++) {
        xy[2 * i] = 8.5 + 0.1 * xy[2 * i];
        xy[2 * i + 1] = 47.3 + 0.1 * xy[2 * i + 1];
    }
    xy[6000] = xy[6001] = 0;
    s = sites_of(xy, 3001);
    b = counts_of(s, VOR_BOWYER_WATSON);
    assert_true(b.order_refinements > 0);
    assert_true(b.order_keys > s->n);
    vor_counts u = counts_of(s, VOR_FLIP);
    assert_int_equal(u.order_refinements, b.order_refinements);
    vor_sites_free(s);
    free(xy);
}

/* The same 3000 uniform sites scaled by 2^700, 2^-700 and 2^-1060 (all
 * subnormal): Bowyer-Watson's and flipping's copy of the coordinates and
 * Fortune's frame are scaled back into the filters' range (exactly, by a
 * power of two), so that exact arithmetic stays rare where every
 * predicate went to it, and the three diagrams are the same. */
static void test_scaled_sets(void **state) {
    (void)state;
    enum { N = 3000 };
    double *xy = vt_uniform(N, 9), *p = malloc(2 * N * sizeof *p);
    assert_true(xy != NULL && p != NULL);
    static const int shifts[] = {700, -700, -1060};
    for (int k = 0; k < 3; k++) {
        for (size_t i = 0; i < 2 * N; i++) p[i] = ldexp(xy[i], shifts[k]);
        vor_sites *s = sites_of(p, N);
        vor_diagram *d[3] = {NULL, NULL, NULL};
        for (int a = 0; a < 3; a++) {
            vor_algorithm alg = a == 0   ? VOR_BOWYER_WATSON
                                : a == 1 ? VOR_FLIP
                                         : VOR_FORTUNE;
            vor_counts c;
            vor_options o = {.counts = &c};
            assert_int_equal(vor_compute_ex(s, alg, &o, &d[a]), VOR_OK);
            uint64_t tests = a < 2 ? c.orient2d + c.incircle
                                   : c.breakpoint_tests + c.event_compares;
            print_message("  2^%d: %s: %llu exact of %llu\n", shifts[k],
                          vor_algorithm_name(alg),
                          (unsigned long long)c.exact,
                          (unsigned long long)tests);
            assert_true(c.exact * 100 < tests);
        }
        assert_true(vor_diagram_equal(d[0], d[1]));
        assert_true(vor_diagram_equal(d[0], d[2]));
        for (int a = 0; a < 3; a++) vor_diagram_free(d[a]);
        vor_sites_free(s);
    }
    free(p);
    free(xy);
}

static void test_degenerate_and_errors(void **state) {
    (void)state;
    const double line[] = {0, 0, 1, 1, 2, 2, 3, 3};
    vor_sites *s = sites_of(line, 4);
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        vor_counts c = counts_of(s, (vor_algorithm)a), zero;
        memset(&zero, 0, sizeof zero);
        assert_memory_equal(&c, &zero, sizeof c);
    }
    /* errors leave the counts zeroed */
    vor_counts c;
    memset(&c, 0xab, sizeof c);
    vor_options o = {.counts = &c};
    vor_diagram *d = NULL;
    assert_int_equal(vor_compute_ex(s, VOR_ALGORITHM_COUNT, &o, &d), VOR_EALGORITHM);
    assert_null(d);
    assert_int_equal(c.orient2d, 0);
    assert_int_equal(vor_compute_ex(NULL, VOR_FLIP, &o, &d), VOR_EINVAL);
    assert_int_equal(vor_compute_ex(s, VOR_FLIP, &o, NULL), VOR_EINVAL);
    assert_int_equal(vor_compute_ex(s, VOR_FLIP, NULL, &d), VOR_OK);
    vor_diagram_free(d);
    vor_sites_free(s);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table),
        cmocka_unit_test(test_deterministic),
        cmocka_unit_test(test_identities),
        cmocka_unit_test(test_bounded_per_site),
        cmocka_unit_test(test_walk_every_distribution),
        cmocka_unit_test(test_walk_convex),
        cmocka_unit_test(test_exact_and_refined),
        cmocka_unit_test(test_scaled_sets),
        cmocka_unit_test(test_degenerate_and_errors),
    };
    return cmocka_run_group_tests_name("core/counts", tests, NULL, NULL);
}
