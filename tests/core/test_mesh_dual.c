/* test_mesh_dual.c -- the diagram read straight off the construction's mesh
 * (core/mesh_dual.c), the path vor__bowyer_watson and vor__flip take.
 *
 * Oracle: the generic builder. The same algorithm's finished mesh
 * (vor__bowyer_watson_mesh / vor__flip_mesh) converted by
 * vor__mesh_to_diagram, which goes through vor__diagram_build, must give a
 * bit-identical diagram, and vor_check must accept it. Sets: every standard
 * set, random uniform, gaussian and clustered sets of many sizes, sets with
 * a cocircular square that the records pass meets late or early (the
 * second pass that restores the mesh and merges cocircular triangles into
 * polygons), fans of more
 * sites than the walks and small sorts handle inline, and every allocation
 * failing in turn on both paths. Every set also runs with the
 * conversion's hint forced both ways (look for cocircular sites first, or
 * meet them in the records pass), Fortune's sweep included, and must give
 * the same diagram. Seeds are fixed and printed.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>

#include "../../core/mesh.h"
#include "../support/testsets.h"
#include "fault_alloc.h"

typedef struct algo {
    const char *name;
    vor_status (*diagram)(const vor_sites *s, vor_diagram **out);
    vor_status (*mesh)(const vor_sites *s, vor__mesh *m);
    vor__algorithm_run_fn run;
} algo;

static const algo algos[] = {
    {"bowyer-watson", vor__bowyer_watson, vor__bowyer_watson_mesh,
     vor__bowyer_watson_run},
    {"flip", vor__flip, vor__flip_mesh, vor__flip_run},
    {"fortune", vor__fortune, NULL, vor__fortune_run},
};

/* The conversion with its hint forced both ways (vor__run's
 * cocircular_first: look for cocircular sites first, or meet them in the
 * records pass and start again) gives the same diagram as ref. */
static void expect_hint_free(const vor_sites *s, const char *what,
                             const algo *a, const vor_diagram *ref) {
    for (int h = -1; h <= 1; h += 2) {
        vor__run run;
        memset(&run, 0, sizeof run);
        run.cocircular_first = h;
        vor_diagram *d = NULL;
        assert_int_equal(a->run(s, &run, &d), VOR_OK);
        if (!vor_diagram_equal(d, ref)) {
            print_error("%s, %s: the conversion %s cocircular sites first "
                        "differs\n", what, a->name, h > 0 ? "looking for" :
                        "not looking for");
            fail();
        }
        vor_diagram_free(d);
    }
}

static vor_sites *sites_of(const double *xy, size_t n) {
    vor_sites *s = NULL;
    assert_int_equal(vor_sites_new(xy, n, &s, NULL), VOR_OK);
    assert_non_null(s);
    return s;
}

/* The largest cell. */
static size_t max_degree(const vor_diagram *d) {
    size_t m = 0;
    for (size_t i = 0; i < d->n_sites; i++) {
        size_t k = d->cell_start[i + 1] - d->cell_start[i];
        if (k > m) m = k;
    }
    return m;
}

/* Both algorithms: the fast path equals the generic builder's diagram of
 * the same mesh, bit for bit, and passes vor_check (up to check_max
 * sites). Returns the diagram of the last algorithm (free it) when keep. */
static vor_diagram *expect_same(const vor_sites *s, const char *what,
                                size_t check_max, int keep) {
    vor_diagram *last = NULL;
    for (size_t a = 0; algos[a].mesh; a++) {
        vor_diagram *fast = NULL, *ref = NULL;
        vor__mesh m = {0};
        vor_status st = algos[a].diagram(s, &fast);
        if (st != VOR_OK) {
            print_error("%s, %s: %s\n", what, algos[a].name, vor_status_name(st));
            fail();
        }
        assert_int_equal(algos[a].mesh(s, &m), VOR_OK);
        assert_int_equal(vor__mesh_to_diagram(s, &m, &ref), VOR_OK);
        if (!vor_diagram_equal(fast, ref)) {
            print_error("%s, %s: differs from the generic builder "
                        "(%zu/%zu vertices, %zu/%zu edges)\n",
                        what, algos[a].name, fast->n_vertices, ref->n_vertices,
                        fast->n_edges, ref->n_edges);
            fail();
        }
        char msg[256] = "";
        if (s->n <= check_max && vor_check(fast, s, msg, sizeof msg)) {
            print_error("%s, %s: vor_check: %s\n", what, algos[a].name, msg);
            fail();
        }
        expect_hint_free(s, what, &algos[a], ref);
        vor_diagram_free(ref);
        vor_diagram_free(last);
        last = fast;
    }
    /* Fortune's sweep, through the same conversion: its own diagram must
     * be the others' (test_crosscheck), either way */
    expect_hint_free(s, what, &algos[2], last);
    if (!keep) {
        vor_diagram_free(last);
        last = NULL;
    }
    return last;
}

static void test_standard_sets(void **state) {
    (void)state;
    size_t ran = 0;
    for (size_t i = 0; i < vt_count(); i++) {
        vt_set set;
        assert_int_equal(vt_make(i, &set), 0);
        vor_sites *s = sites_of(set.xy, set.n);
        if (!vor__all_collinear(s)) {
            expect_same(s, set.name, 5000, 0);
            ran++;
        }
        vor_sites_free(s);
        vt_set_free(&set);
    }
    printf("  %zu standard sets (the collinear ones never reach a mesh)\n", ran);
    assert_true(ran >= 10);
}

static void test_random_sets(void **state) {
    (void)state;
    static const size_t sizes[] = {3, 4, 5, 7, 10, 31, 64, 100, 333, 1000, 4096, 20000};
    const uint64_t seed0 = 4242;
    printf("  seeds %llu..%llu\n", (unsigned long long)seed0,
           (unsigned long long)seed0 + 3 * (sizeof sizes / sizeof *sizes) - 1);
    uint64_t seed = seed0;
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
        for (int dist = 0; dist < 3; dist++, seed++) {
            size_t n = sizes[k];
            double *xy = dist == 0 ? vt_uniform(n, seed)
                         : dist == 1 ? vt_gaussian(n, seed)
                                     : vt_clusters(n, 1 + n / 50, seed);
            assert_non_null(xy);
            vor_sites *s = sites_of(xy, n);
            free(xy);
            char what[64];
            snprintf(what, sizeof what, "%s n=%zu seed=%llu",
                     dist == 0 ? "uniform" : dist == 1 ? "gaussian" : "clusters", n,
                     (unsigned long long)seed);
            if (!vor__all_collinear(s)) expect_same(s, what, 5000, 0);
            vor_sites_free(s);
        }
    }
}

/* A unit square far from the uniform points is one Voronoi vertex of four
 * sites, so the records pass must start again with the polygons merged;
 * where it meets the square (late or early) depends on the insertion
 * order, so many seeds and both ends of the site order are tried. Integer
 * pixels (many cocircular quadruples, duplicates) and a grid complete the
 * merged pass's sets. */
static void test_cocircular(void **state) {
    (void)state;
    const uint64_t seed0 = 777;
    printf("  seeds %llu..%llu\n", (unsigned long long)seed0,
           (unsigned long long)seed0 + 11);
    static const double sq[] = {10, 10, 11, 10, 11, 11, 10, 11};
    for (uint64_t seed = seed0; seed < seed0 + 12; seed++) {
        size_t n = 500 + 300 * (size_t)(seed - seed0);
        double *u = vt_uniform(n, seed);
        double *xy = malloc((n + 4) * 2 * sizeof *xy);
        assert_non_null(u);
        assert_non_null(xy);
        int first = seed % 2;
        memcpy(xy + (first ? 8 : 0), u, 2 * n * sizeof *xy);
        memcpy(xy + (first ? 0 : 2 * n), sq, sizeof sq);
        free(u);
        vor_sites *s = sites_of(xy, n + 4);
        free(xy);
        char what[64];
        snprintf(what, sizeof what, "uniform n=%zu seed=%llu + square %s", n,
                 (unsigned long long)seed, first ? "first" : "last");
        vor_diagram *d = expect_same(s, what, 5000, 1);
        /* the square's centre is one vertex, its four sites' first three */
        uint32_t a = first ? 0 : (uint32_t)n;
        size_t found = 0;
        for (size_t v = 0; v < d->n_vertices; v++)
            found += d->vertex_sites[3 * v] == a && d->vertex_sites[3 * v + 1] == a + 1 &&
                     d->vertex_sites[3 * v + 2] == a + 2;
        assert_int_equal(found, 1);
        vor_diagram_free(d);
        vor_sites_free(s);
    }
    /* few polygons, patched into the first records pass: four squares
     * that share sites, a 12-gon of exactly cocircular sites (a^2 + b^2
     * = 25, in 64ths) whose circle holds no other site, each inside a
     * uniform set; points on a circle in angle order (few exact
     * polygons among nearly cocircular sites) */
    {
        const size_t n = 3000;
        double *xy = vt_uniform(n + 12, 91);
        assert_non_null(xy);
        size_t m = 0;
        for (size_t i = 0; i < n; i++) {
            double dx = xy[2 * i] - 0.5, dy = xy[2 * i + 1] - 0.5;
            if (dx * dx + dy * dy < 0.01) continue; /* (6.4/64)^2 */
            xy[2 * m] = xy[2 * i];
            xy[2 * m + 1] = xy[2 * i + 1];
            m++;
        }
        static const int ab[12][2] = {{5, 0}, {4, 3}, {3, 4}, {0, 5},
                                      {-3, 4}, {-4, 3}, {-5, 0}, {-4, -3},
                                      {-3, -4}, {0, -5}, {3, -4}, {4, -3}};
        for (size_t k = 0; k < 12; k++, m++) {
            xy[2 * m] = 0.5 + ab[k][0] / 64.0;
            xy[2 * m + 1] = 0.5 + ab[k][1] / 64.0;
        }
        vor_sites *s = sites_of(xy, m);
        vor_diagram *d = expect_same(s, "uniform and a 12-gon", 5000, 1);
        /* the 12-gon's centre is one vertex of twelve edges' ends */
        size_t ends = 0;
        for (size_t v = 0; v < d->n_vertices; v++)
            if (d->vertex_xy[2 * v] == 0.5 && d->vertex_xy[2 * v + 1] == 0.5)
                for (size_t e = 0; e < 2 * d->n_edges; e++)
                    ends += d->edge_ends[e] == (int32_t)v;
        assert_int_equal(ends, 12);
        vor_diagram_free(d);
        vor_sites_free(s);
        free(xy);
        xy = vt_uniform(n, 92);
        assert_non_null(xy);
        for (size_t i = 0; i < 9; i++) {
            xy[2 * (n - 9 + i)] = 0.25 + (double)(i % 3) / 4096;
            xy[2 * (n - 9 + i) + 1] = 0.75 + (double)(i / 3) / 4096;
        }
        s = sites_of(xy, n);
        expect_same(s, "uniform and four squares sharing sites", 5000, 0);
        vor_sites_free(s);
        free(xy);
    }
    double *uc = vt_unit_circle(4000);
    vor_sites *s = sites_of(uc, 4000);
    free(uc);
    expect_same(s, "4000 points on a circle", 5000, 0);
    vor_sites_free(s);
    double *px = vt_pixels(20000, 5);
    s = sites_of(px, 20000);
    free(px);
    expect_same(s, "pixels n=20000 seed=5", 0, 0);
    vor_sites_free(s);
    double *g = vt_grid(60, 50);
    s = sites_of(g, 3000);
    free(g);
    expect_same(s, "grid 60x50", 3000, 0);
    vor_sites_free(s);
}

/* A site with more neighbours than the block walk and the small sorts
 * take: the centre of n points on a circle whose radii are perturbed (by
 * at most 1e-6, far below the (2 pi / n)^2 / 2 that would unseat the fan),
 * so that nothing is cocircular and the fast path runs. */
static void test_high_degree(void **state) {
    (void)state;
    static const size_t ns[] = {30, 100, 1000};
    for (size_t k = 0; k < sizeof ns / sizeof *ns; k++) {
        size_t n = ns[k];
        double *xy = malloc((n + 1) * 2 * sizeof *xy);
        assert_non_null(xy);
        vt_rng r = {99 + n};
        xy[0] = 0;
        xy[1] = 0;
        for (size_t i = 0; i < n; i++) {
            double t = 2 * 3.14159265358979323846 * (double)i / (double)n;
            double rad = 1 + 1e-6 * vt_unit(&r);
            xy[2 * i + 2] = rad * cos(t);
            xy[2 * i + 3] = rad * sin(t);
        }
        vor_sites *s = sites_of(xy, n + 1);
        free(xy);
        char what[64];
        snprintf(what, sizeof what, "fan of %zu, seed %zu", n, 99 + n);
        vor_diagram *d = expect_same(s, what, 5000, 1);
        assert_int_equal(max_degree(d), n);
        assert_int_equal(d->cell_start[1] - d->cell_start[0], n); /* the centre */
        vor_diagram_free(d);
        vor_sites_free(s);
    }
    /* more polygons, whose patch reads more slots than a quarter of the
     * sites' (82 diagonals, 12,055 slots for the 19,946 distinct sites):
     * random integer sites in an 1800 x 1800 window */
    {
        enum { N = 20000 };
        static double xy[2 * N];
        vt_rng r = {1};
        for (size_t i = 0; i < 2 * N; i++) xy[i] = (double)(vt_next(&r) % 1800);
        vor_sites *s = sites_of(xy, N);
        expect_same(s, "20000 integer sites in 1800 x 1800", 0, 0);
        vor_sites_free(s);
    }
}

/* Every allocation of vor__bowyer_watson and vor__flip fails in turn, on
 * the fast path (300 sites; 40 sites, whose scratch lives in
 * vor__mesh_dual's frame), on the merged pass for cocircular sites and on
 * the patch of a few diagonals (a square among uniform sites):
 * VOR_ENOMEM, *out NULL, nothing leaks (LeakSanitizer at exit); then the
 * call succeeds. */
static void test_allocation_failures(void **state) {
    (void)state;
    double *u = vt_uniform(300, 3);
    double *g = vt_grid(12, 9);
    double *v = vt_uniform(40, 4);
    double *q = vt_uniform(304, 5);
    static const double sq[] = {10, 10, 11, 10, 11, 11, 10, 11};
    memcpy(q + 600, sq, sizeof sq);
    vor_sites *sets[4] = {sites_of(u, 300), sites_of(g, 108), sites_of(v, 40),
                          sites_of(q, 304)};
    static const char *const set_names[4] = {
        "uniform", "grid (merged pass)", "small uniform",
        "uniform and a square (patched)"};
    free(u);
    free(g);
    free(v);
    free(q);
    /* hint 0 as always; -1: the records pass meets the grid's
     * cocircular squares and starts again (vor__run's cocircular_first) */
    for (size_t a = 0; algos[a].mesh; a++) {
        for (int k = 0; k < 5; k++) {
            const int set = k == 3 ? 1 : k == 4 ? 3 : k, hint = k == 3 ? -1 : 0;
            long i;
            for (i = 0;; i++) {
                vor_diagram *d = (vor_diagram *)1;
                vor__run run;
                memset(&run, 0, sizeof run);
                run.cocircular_first = hint;
                fault_arm(i);
                vor_status st = algos[a].run(sets[set], &run, &d);
                fault_disarm();
                if (st == VOR_OK) {
                    char msg[128] = "";
                    assert_int_equal(vor_check(d, sets[set], msg, sizeof msg),
                                     0);
                    vor_diagram_free(d);
                    break;
                }
                assert_int_equal(st, VOR_ENOMEM);
                assert_null(d);
            }
            printf("  %s, %s%s: %ld allocations failed in turn\n",
                   algos[a].name, set_names[set],
                   hint ? ", met in the records" : "", i);
            assert_true(i >= 12);
        }
    }
    for (int k = 0; k < 4; k++) vor_sites_free(sets[k]);
}

/* The hint's source: cocircular sites leave signs in every algorithm's
 * run (a grid of squares, integer points of a circle), sites in rows
 * (equal y, random x: much exact arithmetic, no four cocircular) and
 * uniform ones none. */
static void test_cocircular_signs(void **state) {
    (void)state;
    size_t n_circle = 0;
    double *circle = vt_int_circle(65, 0, &n_circle); /* 5 * 13: many */
    double *grid = vt_grid(30, 30), *uni = vt_uniform(3000, 5);
    double *rows = vt_uniform(3000, 6);
    assert_non_null(circle);
    assert_non_null(grid);
    assert_non_null(uni);
    assert_non_null(rows);
    for (size_t i = 0; i < 3000; i++) rows[2 * i + 1] = (double)(i % 12);
    const struct {
        const double *xy;
        size_t n;
        int signs;
    } sets[] = {{grid, 900, 1}, {circle, n_circle, 1}, {rows, 3000, 0},
                {uni, 3000, 0}};
    for (size_t k = 0; k < sizeof sets / sizeof sets[0]; k++) {
        vor_sites *s = sites_of(sets[k].xy, sets[k].n);
        for (size_t a = 0; a < sizeof algos / sizeof algos[0]; a++) {
            vor__run run;
            memset(&run, 0, sizeof run);
            vor_diagram *d = NULL;
            assert_int_equal(algos[a].run(s, &run, &d), VOR_OK);
            if ((run.cocircular_signs > 0) != sets[k].signs) {
                print_error("set %zu, %s: %llu signs of cocircular sites\n",
                            k, algos[a].name,
                            (unsigned long long)run.cocircular_signs);
                fail();
            }
            vor_diagram_free(d);
        }
        vor_sites_free(s);
    }
    free(circle);
    free(grid);
    free(uni);
    free(rows);
}

/* Scratch arrays: zeroed and writable on both sides of the size at which
 * they become mappings of their own; an allocation failure shows as NULL
 * for the small kind (the C library's), and an impossible size as NULL
 * for both. */
static void test_scratch(void **state) {
    (void)state;
    const size_t counts[] = {0, 1, 1000, (1u << 18) - 4, 1u << 18, 3u << 20};
    for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++) {
        size_t k = counts[c] ? counts[c] : 1;
        uint32_t *a = vor__scratch_new(counts[c], sizeof *a);
        assert_non_null(a);
        assert_int_equal((uintptr_t)a % 16, 0);
        for (size_t i = 0; i < k; i++) {
            assert_int_equal(a[i], 0);
            a[i] = (uint32_t)i;
        }
        for (size_t i = 0; i < k; i += 4099) assert_int_equal(a[i], i);
        vor__scratch_free(a);
    }
    vor__scratch_free(NULL);
    assert_null(vor__scratch_new(SIZE_MAX / 8, 16));
    fault_arm(0);
    void *p = vor__scratch_new(10, 4);
    fault_disarm();
    assert_null(p);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_standard_sets),
        cmocka_unit_test(test_random_sets),
        cmocka_unit_test(test_cocircular),
        cmocka_unit_test(test_high_degree),
        cmocka_unit_test(test_allocation_failures),
        cmocka_unit_test(test_scratch),
        cmocka_unit_test(test_cocircular_signs),
    };
    return cmocka_run_group_tests_name("core/mesh_dual", tests, NULL, NULL);
}
