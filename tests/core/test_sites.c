/* test_sites.c -- vor_sites_new: validation and exact de-duplication.
 *
 * Oracles: a brute-force O(n^2) first-occurrence scan for small random sets
 * with many duplicates, and an independent sort-based one (qsort by
 * coordinates, ties by input index) for the standard test sets and large
 * random ones. Random sets use a fixed seed, printed; VOR_TEST_SEED
 * replays another.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../core/vor.h"
#include "../support/testsets.h"

static uint64_t seed;

static int setup_seed(void **state) {
    (void)state;
    const char *s = getenv("VOR_TEST_SEED");
    seed = s ? strtoull(s, NULL, 0) : 20240612u;
    printf("# test_sites seed %llu (set VOR_TEST_SEED to change)\n",
           (unsigned long long)seed);
    return 0;
}

/* Checks the structural invariants that hold for any valid result. */
static void check_invariants(const double *xy, size_t n, const vor_sites *s) {
    assert_non_null(s);
    assert_int_equal(s->n_input, n);
    assert_true(s->n <= n);
    assert_true(n == 0 || s->n > 0);
    for (size_t k = 0; k < s->n; k++) {
        assert_true(k == 0 || s->input_of[k] > s->input_of[k - 1]);
        assert_true(s->input_of[k] < n);
        assert_int_equal(s->site_of[s->input_of[k]], k);
        /* stored exactly, with -0.0 as +0.0 */
        for (int j = 0; j < 2; j++) {
            double v = s->xy[2 * k + j];
            assert_true(v == xy[2 * s->input_of[k] + j]);
            assert_false(v == 0 && signbit(v));
        }
    }
    for (size_t i = 0; i < n; i++) {
        uint32_t k = s->site_of[i];
        assert_true(k < s->n);
        assert_true(s->xy[2 * k] == xy[2 * i]);
        assert_true(s->xy[2 * k + 1] == xy[2 * i + 1]);
        assert_true(s->input_of[k] <= i);
    }
}

/* Brute force: a point is a new site iff no earlier point equals it. */
static void check_brute(const double *xy, size_t n, const vor_sites *s) {
    check_invariants(xy, n, s);
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        size_t first = i;
        for (size_t j = 0; j < i; j++)
            if (xy[2 * j] == xy[2 * i] && xy[2 * j + 1] == xy[2 * i + 1]) {
                first = j;
                break;
            }
        if (first == i) {
            assert_true(m < s->n);
            assert_int_equal(s->input_of[m], i);
            m++;
        }
        assert_int_equal(s->input_of[s->site_of[i]], first);
    }
    assert_int_equal(m, s->n);
}

/* Sort-based oracle: order the input indices by (x, y, index); the first of
 * each run of equal points is a site, and all of the run map to it. */
static const double *sort_xy;

static int cmp_point(const void *pa, const void *pb) {
    size_t a = *(const size_t *)pa, b = *(const size_t *)pb;
    for (int j = 0; j < 2; j++) {
        double u = sort_xy[2 * a + j], v = sort_xy[2 * b + j];
        if (u < v)
            return -1;
        if (u > v)
            return 1;
    }
    return (a > b) - (a < b);
}

static void check_sorted(const double *xy, size_t n, const vor_sites *s) {
    check_invariants(xy, n, s);
    if (n == 0)
        return;
    size_t *idx = malloc(n * sizeof *idx);
    assert_non_null(idx);
    for (size_t i = 0; i < n; i++)
        idx[i] = i;
    sort_xy = xy;
    qsort(idx, n, sizeof *idx, cmp_point);
    size_t distinct = 0, run_first = 0;
    for (size_t r = 0; r < n; r++) {
        size_t i = idx[r];
        if (r == 0 || xy[2 * i] != xy[2 * idx[r - 1]] ||
            xy[2 * i + 1] != xy[2 * idx[r - 1] + 1]) {
            run_first = i; /* smallest index of the run: ties by index */
            distinct++;
        }
        assert_int_equal(s->input_of[s->site_of[i]], run_first);
    }
    assert_int_equal(distinct, s->n);
    free(idx);
}

static vor_sites *make(const double *xy, size_t n) {
    vor_sites *s = NULL;
    size_t bad = 12345;
    assert_int_equal(vor_sites_new(xy, n, &s, &bad), VOR_OK);
    assert_int_equal(bad, 12345); /* untouched on success */
    return s;
}

static void test_trivial_sizes(void **state) {
    (void)state;
    vor_sites *s = make(NULL, 0);
    assert_int_equal(s->n, 0);
    assert_int_equal(s->n_input, 0);
    vor_sites_free(s);

    const double one[2] = {3.5, -2};
    s = make(one, 1);
    check_brute(one, 1, s);
    assert_int_equal(s->n, 1);
    vor_sites_free(s);

    const double two[4] = {1, 2, 1, 2};
    s = make(two, 2);
    check_brute(two, 2, s);
    assert_int_equal(s->n, 1);
    vor_sites_free(s);

    const double two_distinct[4] = {1, 2, 2, 1};
    s = make(two_distinct, 2);
    check_brute(two_distinct, 2, s);
    assert_int_equal(s->n, 2);
    vor_sites_free(s);
    vor_sites_free(NULL); /* no-op */
}

static void test_signed_zero(void **state) {
    (void)state;
    const double xy[] = {-0.0, 0.0, 0.0, -0.0, -0.0, -0.0, 0.0, 0.0,
                         1, -0.0, 1, 0.0, -0.0, 1};
    vor_sites *s = make(xy, 7);
    check_brute(xy, 7, s);
    assert_int_equal(s->n, 3); /* (0,0), (1,0), (0,1) */
    for (int i = 0; i < 4; i++)
        assert_int_equal(s->site_of[i], 0);
    assert_int_equal(s->site_of[4], 1);
    assert_int_equal(s->site_of[5], 1);
    assert_int_equal(s->site_of[6], 2);
    assert_false(signbit(s->xy[0]) || signbit(s->xy[1]));
    assert_false(signbit(s->xy[3]) || signbit(s->xy[4]));
    vor_sites_free(s);
}

static void test_all_equal(void **state) {
    (void)state;
    size_t n = 10000;
    double *xy = malloc(2 * n * sizeof *xy);
    assert_non_null(xy);
    for (size_t i = 0; i < n; i++) {
        xy[2 * i] = 0.1;
        xy[2 * i + 1] = i % 2 ? -0.0 : 0.0;
    }
    vor_sites *s = make(xy, n);
    check_invariants(xy, n, s);
    assert_int_equal(s->n, 1);
    assert_int_equal(s->input_of[0], 0);
    vor_sites_free(s);
    free(xy);
}

static void test_nonfinite(void **state) {
    (void)state;
    const double bad_values[] = {NAN, -NAN, INFINITY, -INFINITY};
    const size_t n = 50;
    double xy[100];
    for (size_t v = 0; v < 4; v++) {
        for (size_t at = 0; at < 2 * n; at += 7) {
            for (size_t i = 0; i < 2 * n; i++)
                xy[i] = (double)(i % 10); /* with duplicates */
            xy[at] = bad_values[v];
            if (at + 20 < 2 * n) /* a later bad value must not win */
                xy[at + 20] = NAN;
            vor_sites *s = (vor_sites *)&s;
            size_t bad = 999;
            assert_int_equal(vor_sites_new(xy, n, &s, &bad), VOR_ENONFINITE);
            assert_null(s);
            assert_int_equal(bad, at / 2);
            /* bad_index may be NULL */
            s = (vor_sites *)&s;
            assert_int_equal(vor_sites_new(xy, n, &s, NULL), VOR_ENONFINITE);
            assert_null(s);
        }
    }
    /* the very first and the very last coordinate */
    for (size_t i = 0; i < 2 * n; i++)
        xy[i] = (double)i;
    xy[2 * n - 1] = INFINITY;
    vor_sites *s;
    size_t bad = 0;
    assert_int_equal(vor_sites_new(xy, n, &s, &bad), VOR_ENONFINITE);
    assert_int_equal(bad, n - 1);
    xy[0] = NAN;
    assert_int_equal(vor_sites_new(xy, n, &s, &bad), VOR_ENONFINITE);
    assert_int_equal(bad, 0);
}

static void test_bad_arguments(void **state) {
    (void)state;
    const double xy[2] = {0, 0};
    vor_sites *s = (vor_sites *)&s;
    /* never read: the count is refused first */
    assert_int_equal(vor_sites_new(xy, VOR_MAX_POINTS + 1, &s, NULL),
                     VOR_ETOOMANY);
    assert_null(s);
    s = (vor_sites *)&s;
    assert_int_equal(vor_sites_new(NULL, 1, &s, NULL), VOR_EINVAL);
    assert_null(s);
    assert_int_equal(vor_sites_new(xy, 1, NULL, NULL), VOR_EINVAL);
}

/* Small random sets with many duplicates against the brute force. */
static void test_random_brute(void **state) {
    (void)state;
    vt_rng r = {seed};
    double xy[2 * 600];
    for (int round = 0; round < 300; round++) {
        size_t n = 1 + vt_next(&r) % 600;
        int range = 1 + (int)(vt_next(&r) % 30);
        for (size_t i = 0; i < 2 * n; i++) {
            double v = (double)(int)(vt_next(&r) % (uint64_t)range) - range / 2;
            if (v == 0 && vt_next(&r) % 2)
                v = -0.0;
            xy[i] = v;
        }
        vor_sites *s = make(xy, n);
        check_brute(xy, n, s);
        vor_sites_free(s);
    }
}

/* vor_compute with a vor_sites filled by hand that repeats a site: every
 * algorithm answers VOR_EINVAL with no diagram, where the sweep had
 * corrupted its heap and flip's walk cycled; one with an infinity or a
 * NaN, VOR_ENONFINITE, where all three had answered VOR_OK. Sets of small integer
 * coordinates (many repeats), sets with one repeat of a hull vertex, of
 * an inner site and of the first site, on a line, and signed zeros; sets
 * that happen to repeat nothing must compute. */
static void compute_by_hand(const double *xy, size_t n, int repeats) {
    uint32_t *ident = malloc(n * sizeof *ident);
    assert_non_null(ident);
    for (size_t i = 0; i < n; i++) ident[i] = (uint32_t)i;
    vor_sites s = {n, n, (double *)xy, ident, ident};
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        vor_diagram *d = (vor_diagram *)&d;
        vor_status st = vor_compute(&s, (vor_algorithm)a, &d);
        if (repeats) {
            if (st != VOR_EINVAL)
                fail_msg("%s on %zu sites with a repeat: %s",
                         vor_algorithm_name((vor_algorithm)a), n,
                         vor_status_name(st));
            assert_null(d);
        } else {
            assert_int_equal(st, VOR_OK);
            vor_diagram_free(d);
        }
    }
    free(ident);
}

/* 1 if two of the n points are equal, by vor_sites_new's count */
static int has_repeat(const double *xy, size_t n) {
    vor_sites *s = make(xy, n);
    int r = s->n < n;
    vor_sites_free(s);
    return r;
}

static void test_by_hand(void **state) {
    (void)state;
    vt_rng r = {seed};
    static const size_t sizes[] = {3, 4, 5, 20, 100, 1000, 5000};
    static const int ranges[] = {2, 3, 5, 10, 30, 100, 1000};
    double *xy = malloc(2 * 5001 * sizeof *xy);
    assert_non_null(xy);
    int repeated = 0, distinct = 0;
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++)
        for (size_t j = 0; j < sizeof ranges / sizeof *ranges; j++) {
            size_t n = sizes[i];
            for (size_t k = 0; k < 2 * n; k++)
                xy[k] = (double)(vt_next(&r) % (uint64_t)ranges[j]);
            int rep = has_repeat(xy, n);
            repeated += rep;
            distinct += !rep;
            compute_by_hand(xy, n, rep);
        }
    assert_true(repeated >= 20 && distinct >= 5); /* both kinds ran */

    /* one repeat among distinct random sites: of the first site, of a
     * site inside, of the hull's lowest vertex, placed first or last */
    size_t n = 2000;
    for (size_t k = 0; k < 2 * n; k++) xy[k] = vt_unit(&r);
    size_t low = 0;
    for (size_t k = 1; k < n; k++)
        if (xy[2 * k + 1] < xy[2 * low + 1]) low = k;
    assert_false(has_repeat(xy, n));
    const size_t copied[] = {0, n / 2, low};
    for (size_t c = 0; c < 3; c++) {
        xy[2 * n] = xy[2 * copied[c]];
        xy[2 * n + 1] = xy[2 * copied[c] + 1];
        compute_by_hand(xy, n + 1, 1);
        /* the copy first instead: swap it with site 1 */
        double t0 = xy[2], t1 = xy[3];
        xy[2] = xy[2 * n];
        xy[3] = xy[2 * n + 1];
        xy[2 * n] = t0;
        xy[2 * n + 1] = t1;
        compute_by_hand(xy, n + 1, 1);
        xy[2 * n] = xy[2];
        xy[2 * n + 1] = xy[3];
        xy[2] = t0;
        xy[3] = t1;
    }

    /* an infinity or a NaN, in x or in y, first, inside or last, among
     * distinct sites or on a line: VOR_ENONFINITE, not a diagram */
    const double odd[] = {INFINITY, -INFINITY, NAN};
    for (size_t o = 0; o < 3; o++)
        for (size_t at = 0; at < 2 * 5; at += 3) {
            double few[10] = {0, 0, 1, 0, 0, 1, 1, 1, 2, 3};
            double line[10] = {0, 0, 1, 1, 2, 2, 3, 3, 4, 4};
            few[at] = line[at] = odd[o];
            vor_sites fs = {5, 5, few, NULL, NULL}, ls = {5, 5, line, NULL, NULL};
            for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
                vor_diagram *d = (vor_diagram *)&d;
                assert_int_equal(vor_compute(&fs, (vor_algorithm)a, &d),
                                 VOR_ENONFINITE);
                assert_null(d);
                assert_int_equal(vor_compute(&ls, (vor_algorithm)a, &d),
                                 VOR_ENONFINITE);
                assert_null(d);
            }
        }
    xy[2 * 1000 + 1] = NAN;
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        vor_sites big = {n, n, xy, NULL, NULL};
        vor_diagram *d = (vor_diagram *)&d;
        assert_int_equal(vor_compute(&big, (vor_algorithm)a, &d),
                         VOR_ENONFINITE);
        assert_null(d);
    }

    /* on a line (the degenerate diagram), and a signed zero's twin */
    const double line[] = {0, 0, 1, 1, 2, 2, 1, 1, 3, 3};
    compute_by_hand(line, 5, 1);
    const double zeros[] = {0.0, 0.0, 1, 0, 0, 1, -0.0, -0.0};
    compute_by_hand(zeros, 4, 1);
    compute_by_hand(zeros, 3, 0);
    free(xy);
}

/* Every standard set, against the sort-based oracle. */
static void test_standard_sets(void **state) {
    (void)state;
    for (size_t i = 0; i < vt_count(); i++) {
        vt_set set;
        assert_int_equal(vt_make(i, &set), 0);
        vor_sites *s = make(set.xy, set.n);
        check_sorted(set.xy, set.n, s);
        printf("# %-20s %7zu points, %7zu sites\n", set.name, set.n, s->n);
        vor_sites_free(s);
        vt_set_free(&set);
    }
}

/* Large sets: uniform (almost no duplicates), pixels (many), a grid given
 * twice, coordinates differing in the last bit only. */
static void test_large(void **state) {
    (void)state;
    size_t n = 200000;
    double *u = vt_uniform(n, seed);
    double *p = vt_pixels(n, seed + 1);
    double *g = malloc(4 * n * sizeof *g);
    assert_non_null(u);
    assert_non_null(p);
    assert_non_null(g);
    const double *sets[3] = {u, p, g};
    for (size_t i = 0; i < n; i++) {
        g[2 * i] = (double)(i % 400);
        g[2 * i + 1] = (double)(i / 400);
        g[2 * (n + i)] = (double)((n - 1 - i) % 400); /* again, reversed */
        g[2 * (n + i) + 1] = (double)((n - 1 - i) / 400);
    }
    for (int k = 0; k < 3; k++) {
        size_t m = k == 2 ? 2 * n : n;
        vor_sites *s = make(sets[k], m);
        check_sorted(sets[k], m, s);
        if (k == 2)
            assert_int_equal(s->n, n);
        vor_sites_free(s);
    }
    /* neighbours in the last bit: all distinct */
    for (size_t i = 0; i < n; i++) {
        g[2 * i] = i % 2 ? nextafter(1.0, 2.0) : 1.0;
        g[2 * i + 1] = 1.0 + (double)(i / 2) * 0x1p-52;
    }
    vor_sites *s = make(g, n);
    check_sorted(g, n, s);
    assert_int_equal(s->n, n);
    vor_sites_free(s);
    free(u);
    free(p);
    free(g);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_trivial_sizes),
        cmocka_unit_test(test_signed_zero),
        cmocka_unit_test(test_all_equal),
        cmocka_unit_test(test_nonfinite),
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_random_brute),
        cmocka_unit_test(test_by_hand),
        cmocka_unit_test(test_standard_sets),
        cmocka_unit_test(test_large),
    };
    return cmocka_run_group_tests_name("core/sites", tests, setup_seed, NULL);
}
