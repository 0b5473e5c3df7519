/* test_check.c -- vor_check accepts valid diagrams and detects each kind of
 * corruption.
 *
 * Valid diagrams come from the brute-force oracle (oracle_voronoi.h) through
 * vor__diagram_build, and from vor_compute for every algorithm that is
 * available. Each corruption is applied to a deep copy and must be
 * reported; where the kind of failure is clear, the message is checked too.
 * Random sets use fixed seeds, printed.
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

#include "../../core/internal.h"
#include "../support/testsets.h"
#include "oracle_voronoi.h"
#include "fault_alloc.h"

static vor_sites *sites_of(const double *xy, size_t n) {
    vor_sites *s = NULL;
    assert_int_equal(vor_sites_new(xy, n, &s, NULL), VOR_OK);
    assert_non_null(s);
    return s;
}

static void sites_done(vor_sites *s) { vor_sites_free(s); }

static void *dup_array(const void *p, size_t bytes) {
    void *q = malloc(bytes ? bytes : 1);
    assert_non_null(q);
    if (bytes) memcpy(q, p, bytes);
    return q;
}

static vor_diagram *copy_diagram(const vor_diagram *d) {
    vor_diagram *c = calloc(1, sizeof *c);
    assert_non_null(c);
    *c = *d;
    size_t n = d->n_sites, nv = d->n_vertices, ne = d->n_edges, nr = d->n_rays;
    c->vertex_xy = dup_array(d->vertex_xy, 2 * nv * sizeof(double));
    c->vertex_sites = dup_array(d->vertex_sites, 3 * nv * sizeof(uint32_t));
    c->edge_sites = dup_array(d->edge_sites, 2 * ne * sizeof(uint32_t));
    c->edge_ends = dup_array(d->edge_ends, 2 * ne * sizeof(int32_t));
    c->ray_edge = dup_array(d->ray_edge, nr * sizeof(uint32_t));
    c->ray_dir = dup_array(d->ray_dir, 2 * nr * sizeof(double));
    c->cell_start = dup_array(d->cell_start, (n + 1) * sizeof(uint32_t));
    c->cell_edges = dup_array(d->cell_edges, 2 * ne * sizeof(uint32_t));
    c->cell_bounded = dup_array(d->cell_bounded, n);
    return c;
}

static vor_diagram *build_bf(const vor_sites *s, uint64_t seed) {
    bf_voronoi b;
    assert_int_equal(bf_voronoi_make(s, &b), 0);
    uint32_t *edges;
    int32_t *ends;
    assert_int_equal(bf_raw(&b, seed, &edges, &ends), 0);
    vor_diagram *d = NULL;
    assert_int_equal(vor__diagram_build(s, b.nv, edges, ends, b.ne, &d), VOR_OK);
    bf_free(&b);
    return d;
}

static void expect_valid(const vor_diagram *d, const vor_sites *s,
                         const char *what) {
    char msg[256];
    if (vor_check(d, s, msg, sizeof msg) != 0)
        fail_msg("%s: valid diagram rejected: %s", what, msg);
}

/* The corrupted copy must be rejected; if want is not NULL the reason must
 * contain it. */
static void expect_invalid(vor_diagram *bad, const vor_sites *s,
                           const char *what, const char *want) {
    char msg[256];
    int r = vor_check(bad, s, msg, sizeof msg);
    if (r == 0) fail_msg("%s: corruption not detected", what);
    printf("  %-34s -> %s\n", what, msg);
    if (want && !strstr(msg, want))
        fail_msg("%s: reason \"%s\" does not mention \"%s\"", what, msg, want);
    vor_diagram_free(bad);
}

static double *lattice_set(uint64_t seed, size_t *n) {
    vt_rng r = {seed};
    *n = 6 + (size_t)(vt_next(&r) % 20);
    double *xy = malloc(2 * *n * sizeof *xy);
    for (size_t i = 0; i < *n; i++) {
        xy[2 * i] = (double)(vt_next(&r) % 7);
        xy[2 * i + 1] = (double)(vt_next(&r) % 7);
    }
    return xy;
}

/* ---- valid diagrams pass -------------------------------------------------- */

static void test_valid_brute_force(void **state) {
    (void)state;
    const uint64_t seed0 = 4242;
    printf("valid diagrams: seeds %llu..%llu\n", (unsigned long long)seed0,
           (unsigned long long)seed0 + 149);
    for (uint64_t seed = seed0; seed < seed0 + 150; seed++) {
        size_t n;
        double *xy;
        if (seed % 3 == 0) {
            n = 3 + (size_t)(seed % 30);
            xy = vt_uniform(n, seed);
        } else if (seed % 3 == 1) {
            xy = lattice_set(seed, &n);
        } else {
            xy = vt_int_circle(5 + (long)(seed % 3) * 20, (int)(seed & 1), &n);
        }
        vor_sites *s = sites_of(xy, n);
        free(xy);
        if (!vor__all_collinear(s)) {
            vor_diagram *d = build_bf(s, seed);
            char what[64];
            snprintf(what, sizeof what, "seed %llu", (unsigned long long)seed);
            expect_valid(d, s, what);
            vor_diagram_free(d);
        }
        sites_done(s);
    }
}

static void test_valid_degenerate(void **state) {
    (void)state;
    static const double col[] = {2, 1, -4, -2, 0, 0, 6, 3, 4, 2};
    for (size_t n = 0; n <= 5; n++) {
        vor_sites *s = sites_of(col, n);
        vor_diagram *d = NULL;
        assert_int_equal(vor__diagram_degenerate(s, &d), VOR_OK);
        expect_valid(d, s, "collinear");
        if (n >= 3) {
            vor_diagram *b = copy_diagram(d);
            b->ray_dir[0] = -b->ray_dir[0];
            b->ray_dir[1] = -b->ray_dir[1];
            expect_invalid(b, s, "line direction reversed", "vor_bisector_dir");
            b = copy_diagram(d);
            b->edge_sites[0] = 1; /* (0,2) becomes (1,2): not neighbours */
            b->edge_sites[1] = 3;
            expect_invalid(b, s, "line between non-neighbours", NULL);
            b = copy_diagram(d);
            b->cell_bounded[0] = 1;
            expect_invalid(b, s, "collinear cell marked bounded", "cell_bounded");
        }
        vor_diagram_free(d);
        sites_done(s);
    }
    /* a diagram without vertices for sites that are not collinear */
    static const double tri[] = {0, 0, 1, 0, 0, 1};
    vor_sites *s = sites_of(tri, 3);
    vor_sites *s2 = sites_of(col, 3);
    vor_diagram *d = NULL;
    assert_int_equal(vor__diagram_degenerate(s2, &d), VOR_OK);
    char msg[200];
    assert_int_not_equal(vor_check(d, s, msg, sizeof msg), 0);
    printf("  %-34s -> %s\n", "lines for a triangle", msg);
    vor_diagram_free(d);
    sites_done(s);
    sites_done(s2);
}

/* Every available algorithm's output passes. */
static void test_valid_algorithms(void **state) {
    (void)state;
    double *xy = vt_uniform(300, 99);
    vor_sites *s = sites_of(xy, 300);
    free(xy);
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        vor_diagram *d = NULL;
        vor_status st = vor_compute(s, (vor_algorithm)a, &d);
        if (st == VOR_EUNAVAILABLE) {
            printf("  %s: not available yet\n", vor_algorithm_name((vor_algorithm)a));
            continue;
        }
        assert_int_equal(st, VOR_OK);
        expect_valid(d, s, vor_algorithm_name((vor_algorithm)a));
        vor_diagram_free(d);
    }
    sites_done(s);
}

/* ---- corruptions --------------------------------------------------------- */

static vor_sites *corruption_sites(void) {
    /* uniform points plus a lattice square (cocircular) */
    double *xy = vt_uniform(40, 5);
    xy = realloc(xy, 44 * 2 * sizeof *xy);
    static const double sq[] = {0.25, 0.25, 0.75, 0.25, 0.75, 0.75, 0.25, 0.75};
    memcpy(xy + 80, sq, sizeof sq);
    vor_sites *s = sites_of(xy, 44);
    free(xy);
    return s;
}

static size_t a_bounded_cell(const vor_diagram *d, size_t min_k) {
    for (size_t i = 0; i < d->n_sites; i++)
        if (d->cell_bounded[i] && d->cell_start[i + 1] - d->cell_start[i] >= min_k)
            return i;
    fail_msg("no bounded cell with %zu edges", min_k);
    return 0;
}

static size_t a_segment(const vor_diagram *d) {
    for (size_t e = 0; e < d->n_edges; e++)
        if (d->edge_ends[2 * e + 1] >= 0) return e;
    fail_msg("no segment");
    return 0;
}

static void test_corruptions(void **state) {
    (void)state;
    vor_sites *s = corruption_sites();
    vor_diagram *d = build_bf(s, 3);
    expect_valid(d, s, "base");
    vor_diagram *b;
    size_t e = a_segment(d), i = a_bounded_cell(d, 4);

    b = copy_diagram(d); /* swap two edges' order (data and all) */
    for (int h = 0; h < 2; h++) {
        uint32_t t = b->edge_sites[2 * e + h];
        b->edge_sites[2 * e + h] = b->edge_sites[2 * e + 2 + h];
        b->edge_sites[2 * e + 2 + h] = t;
        int32_t u = b->edge_ends[2 * e + h];
        b->edge_ends[2 * e + h] = b->edge_ends[2 * e + 2 + h];
        b->edge_ends[2 * e + 2 + h] = u;
    }
    expect_invalid(b, s, "two edges swapped", "not after edge");

    b = copy_diagram(d); /* duplicate an edge */
    b->edge_sites[2 * e + 2] = b->edge_sites[2 * e];
    b->edge_sites[2 * e + 3] = b->edge_sites[2 * e + 1];
    expect_invalid(b, s, "edge duplicated", NULL);

    b = copy_diagram(d); /* move a vertex */
    b->vertex_xy[0] = nextafter(b->vertex_xy[0], 1e300);
    expect_invalid(b, s, "vertex moved by one ulp", "vor_circumcenter");

    b = copy_diagram(d); /* another site set, coordinates made consistent */
    {
        uint32_t *t = b->vertex_sites + 3 * (b->n_vertices - 1);
        uint32_t x = t[0] == 0 ? 1 : 0; /* a smaller first site */
        if (x < t[0]) t[0] = x;
        vor_circumcenter(s->xy + 2 * t[0], s->xy + 2 * t[1], s->xy + 2 * t[2],
                         b->vertex_xy + 2 * (b->n_vertices - 1));
    }
    expect_invalid(b, s, "vertex given other sites", NULL);

    b = copy_diagram(d); /* swap two vertices' site sets and coordinates */
    {
        size_t v = b->n_vertices / 2;
        for (int h = 0; h < 3; h++) {
            uint32_t t = b->vertex_sites[3 * v + h];
            b->vertex_sites[3 * v + h] = b->vertex_sites[3 * v + 3 + h];
            b->vertex_sites[3 * v + 3 + h] = t;
        }
        for (int h = 0; h < 2; h++) {
            double t = b->vertex_xy[2 * v + h];
            b->vertex_xy[2 * v + h] = b->vertex_xy[2 * v + 2 + h];
            b->vertex_xy[2 * v + 2 + h] = t;
        }
    }
    expect_invalid(b, s, "two vertices swapped", "order");

    b = copy_diagram(d); /* flip a ray */
    b->ray_dir[0] = -b->ray_dir[0];
    b->ray_dir[1] = -b->ray_dir[1];
    expect_invalid(b, s, "ray reversed", "points into the hull");

    b = copy_diagram(d); /* ray direction off by one ulp */
    b->ray_dir[2] = nextafter(b->ray_dir[2], 2.0);
    expect_invalid(b, s, "ray direction off by one ulp", "vor_bisector_dir");

    b = copy_diagram(d); /* break a cell chain: swap two consecutive edges */
    {
        uint32_t *L = b->cell_edges + b->cell_start[i];
        uint32_t t = L[1];
        L[1] = L[2];
        L[2] = t;
    }
    expect_invalid(b, s, "cell chain broken", "cell");

    b = copy_diagram(d); /* bounded cell reversed (clockwise) */
    {
        uint32_t *L = b->cell_edges + b->cell_start[i];
        size_t k = b->cell_start[i + 1] - b->cell_start[i];
        for (size_t t = 1; t < k - t; t++) {
            uint32_t x = L[t];
            L[t] = L[k - t];
            L[k - t] = x;
        }
    }
    expect_invalid(b, s, "cell clockwise", "counter-clockwise");

    b = copy_diagram(d); /* bounded cell rotated: does not start at min */
    {
        uint32_t *L = b->cell_edges + b->cell_start[i];
        size_t k = b->cell_start[i + 1] - b->cell_start[i];
        uint32_t x = L[0];
        memmove(L, L + 1, (k - 1) * sizeof *L);
        L[k - 1] = x;
    }
    expect_invalid(b, s, "cell rotated", "smallest edge");

    b = copy_diagram(d);
    b->cell_bounded[i] = 0;
    expect_invalid(b, s, "bounded flag cleared", "cell_bounded");

    b = copy_diagram(d); /* an edge's end moved to another vertex */
    b->edge_ends[2 * e + 1] = (b->edge_ends[2 * e + 1] + 1) % (int32_t)b->n_vertices;
    if (b->edge_ends[2 * e + 1] <= b->edge_ends[2 * e]) b->edge_ends[2 * e + 1] = (int32_t)b->n_vertices - 1;
    expect_invalid(b, s, "segment end moved", NULL);

    b = copy_diagram(d); /* vertex index out of range */
    b->edge_ends[2 * e + 1] = (int32_t)b->n_vertices;
    expect_invalid(b, s, "vertex index out of range", "ends");

    b = copy_diagram(d); /* zero-length segment */
    b->edge_ends[2 * e + 1] = b->edge_ends[2 * e];
    expect_invalid(b, s, "zero-length segment", NULL);

    b = copy_diagram(d); /* a segment turned into a ray */
    b->edge_ends[2 * e + 1] = VOR_NONE;
    expect_invalid(b, s, "segment made a ray", "ray");

    b = copy_diagram(d);
    b->ray_edge[1] = b->ray_edge[0];
    expect_invalid(b, s, "ray list wrong", "ray");

    b = copy_diagram(d);
    b->cell_start[1]++;
    expect_invalid(b, s, "cell boundaries moved", NULL);

    b = copy_diagram(d);
    b->n_sites--;
    expect_invalid(b, s, "site count", "sites");

    vor_diagram_free(d);
    sites_done(s);
}

/* Raw input for the builder from a triangulation given as triples (ccw or
 * not): each triangle is a vertex, shared sides are segments, the others
 * rays. The builder does not test the empty-circle property; the checker
 * must. */
static vor_diagram *from_triangles(const vor_sites *s, const uint32_t *t,
                                   size_t nt) {
    uint32_t *edges = malloc(3 * nt * 2 * sizeof *edges);
    int32_t *ends = malloc(3 * nt * 2 * sizeof *ends);
    size_t ne = 0;
    for (size_t a = 0; a < nt; a++)
        for (int h = 0; h < 3; h++) {
            uint32_t p = t[3 * a + h], q = t[3 * a + (h + 1) % 3];
            size_t f = 0;
            while (f < ne && !((edges[2 * f] == p && edges[2 * f + 1] == q) ||
                               (edges[2 * f] == q && edges[2 * f + 1] == p)))
                f++;
            if (f < ne) {
                ends[2 * f + 1] = (int32_t)a;
                continue;
            }
            edges[2 * ne] = p;
            edges[2 * ne + 1] = q;
            ends[2 * ne] = (int32_t)a;
            ends[2 * ne + 1] = VOR_NONE;
            ne++;
        }
    vor_diagram *d = NULL;
    assert_int_equal(vor__diagram_build(s, nt, edges, ends, ne, &d), VOR_OK);
    return d;
}

static void test_non_delaunay(void **state) {
    (void)state;
    /* kite: the circle through A, B, C (centre (1,0), radius 1) leaves D
     * outside, so AC is the Delaunay diagonal; BD is not */
    static const double kite[] = {0, 0, 1, -1, 2, 0, 1, 1.5};
    vor_sites *s = sites_of(kite, 4);
    static const uint32_t good[] = {0, 1, 2, 0, 2, 3};
    static const uint32_t bad[] = {0, 1, 3, 1, 2, 3};
    vor_diagram *d = from_triangles(s, good, 2);
    expect_valid(d, s, "kite, Delaunay diagonal");
    vor_diagram_free(d);
    d = from_triangles(s, bad, 2);
    expect_invalid(d, s, "kite, wrong diagonal", "not locally Delaunay");

    /* a square split in two: the two circles are one and must be merged */
    static const double sq[] = {0, 0, 1, 0, 1, 1, 0, 1};
    sites_done(s);
    s = sites_of(sq, 4);
    static const uint32_t halves[] = {0, 1, 2, 0, 2, 3};
    d = from_triangles(s, halves, 2);
    expect_invalid(d, s, "cocircular vertices not merged", "not merged");
    sites_done(s);

    /* a site left out: the diagram of three of four sites, with an empty
     * fourth cell */
    static const double four[] = {0, 0, 4, 0, 0, 4, 5, 5};
    s = sites_of(four, 3);
    vor_sites *s4 = sites_of(four, 4);
    vor_diagram *d3 = build_bf(s, 0);
    d = copy_diagram(d3);
    d->n_sites = 4;
    d->cell_start = realloc(d->cell_start, 5 * sizeof *d->cell_start);
    d->cell_start[4] = d->cell_start[3];
    d->cell_bounded = realloc(d->cell_bounded, 4);
    d->cell_bounded[3] = 0;
    expect_invalid(d, s4, "site left out", "cell 3");
    vor_diagram_free(d3);
    sites_done(s);
    sites_done(s4);

    /* random sets: flip one interior Delaunay edge of the oracle's
     * triangulation (general position: the flipped edge is illegal) */
    const uint64_t seed0 = 31337;
    printf("edge flips: seeds %llu..%llu\n", (unsigned long long)seed0,
           (unsigned long long)seed0 + 29);
    for (uint64_t seed = seed0; seed < seed0 + 30; seed++) {
        size_t n = 8 + (size_t)(seed % 20);
        double *xy = vt_uniform(n, seed);
        s = sites_of(xy, n);
        free(xy);
        bf_voronoi bv;
        assert_int_equal(bf_voronoi_make(s, &bv), 0);
        vor__mesh m;
        assert_int_equal(bf_mesh(&bv, 0, &m), 0);
        /* find an interior edge whose quadrilateral is convex and flip it */
        int flipped = 0;
        for (size_t h = 0; h < 3 * m.n_tri && !flipped; h++) {
            int32_t g = m.adj[h];
            if (g < 0) continue;
            uint32_t p = m.tri[h], q = m.tri[vor__next((uint32_t)h)];
            uint32_t r = m.tri[vor__prev((uint32_t)h)];
            uint32_t o = m.tri[vor__prev((uint32_t)g)];
            const double *X = s->xy;
            if (vor_orient2d(X + 2 * r, X + 2 * o, X + 2 * q) <= 0 ||
                vor_orient2d(X + 2 * o, X + 2 * r, X + 2 * p) <= 0)
                continue;
            size_t t1 = h / 3, t2 = (size_t)g / 3;
            uint32_t T1[3] = {r, o, q}, T2[3] = {o, r, p};
            memcpy(m.tri + 3 * t1, T1, sizeof T1);
            memcpy(m.tri + 3 * t2, T2, sizeof T2);
            flipped = 1;
        }
        assert_true(flipped);
        d = from_triangles(s, m.tri, m.n_tri);
        char what[64];
        snprintf(what, sizeof what, "seed %llu: one edge flipped",
                 (unsigned long long)seed);
        expect_invalid(d, s, what, "not locally Delaunay");
        vor__mesh_clear(&m);
        bf_free(&bv);
        sites_done(s);
    }
}

/* Each allocation of vor_check fails in turn: it reports "out of memory"
 * (a failure, never a false pass) and leaks nothing. */
static void test_allocation_failures(void **state) {
    (void)state;
    vor_sites *s = corruption_sites();
    vor_diagram *d = build_bf(s, 1);
    char msg[128];
    long k;
    for (k = 0;; k++) {
        fault_arm(k);
        int r = vor_check(d, s, msg, sizeof msg);
        fault_disarm();
        if (r == 0) break;
        assert_string_equal(msg, "out of memory");
    }
    printf("  %ld allocations failed in turn\n", k);
    assert_true(k >= 10);
    vor_diagram_free(d);
    sites_done(s);
}

static void test_arguments(void **state) {
    (void)state;
    static const double tri[] = {0, 0, 1, 0, 0, 1};
    vor_sites *s = sites_of(tri, 3);
    vor_diagram *d = build_bf(s, 0);
    char msg[8];
    assert_int_not_equal(vor_check(NULL, s, msg, sizeof msg), 0);
    assert_true(strlen(msg) < sizeof msg); /* truncated, terminated */
    assert_int_not_equal(vor_check(d, NULL, NULL, 0), 0);
    assert_int_equal(vor_check(d, s, NULL, 0), 0);
    vor_diagram_free(d);
    sites_done(s);
}

int main(void) {
    /* VOR_TEST_FILTER / VOR_TEST_SKIP: run a subset (glob on test names) */
    if (getenv("VOR_TEST_FILTER")) cmocka_set_test_filter(getenv("VOR_TEST_FILTER"));
    if (getenv("VOR_TEST_SKIP")) cmocka_set_skip_filter(getenv("VOR_TEST_SKIP"));
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_valid_brute_force),
        cmocka_unit_test(test_valid_degenerate),
        cmocka_unit_test(test_valid_algorithms),
        cmocka_unit_test(test_corruptions),
        cmocka_unit_test(test_non_delaunay),
        cmocka_unit_test(test_allocation_failures),
        cmocka_unit_test(test_arguments),
    };
    return cmocka_run_group_tests_name("core/check", tests, NULL, NULL);
}
