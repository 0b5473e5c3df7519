/* test_diagram.c -- the canonical diagram builder, the mesh conversion, the
 * degenerate diagrams, the dual triangles, equality and the dispatcher.
 *
 * Expected diagrams come from hand calculation (square, triangles, a site
 * inside a triangle) and from the brute-force oracle in oracle_voronoi.h,
 * whose raw output is fed to the builder in many shuffled forms: the
 * canonical result must not depend on the order it was given in. Random
 * sets use fixed seeds, printed.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
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

static vor_diagram *build_bf(const vor_sites *s, const bf_voronoi *b,
                             uint64_t seed) {
    uint32_t *edges;
    int32_t *ends;
    vor_diagram *d = NULL;
    assert_int_equal(bf_raw(b, seed, &edges, &ends), 0);
    assert_int_equal(vor__diagram_build(s, b->nv, edges, ends, b->ne, &d),
                     VOR_OK);
    assert_non_null(d);
    return d;
}

/* The other site of edge e. */
static uint32_t other(const vor_diagram *d, uint32_t e, uint32_t i) {
    return d->edge_sites[2 * e] == i ? d->edge_sites[2 * e + 1]
                                     : d->edge_sites[2 * e];
}

/* Checks written independently of the builder: canonical order of vertices
 * and edges, vertex coordinates, rays, and counter-clockwise cells whose
 * consecutive edges share a vertex. */
static void assert_canonical(const vor_diagram *d, const vor_sites *s) {
    const double *xy = s->xy;
    assert_int_equal(d->n_sites, s->n);
    for (size_t v = 0; v < d->n_vertices; v++) {
        const uint32_t *t = d->vertex_sites + 3 * v;
        assert_true(t[0] < t[1] && t[1] < t[2] && t[2] < s->n);
        if (v > 0)
            assert_true(t[-3] < t[0] ||
                        (t[-3] == t[0] &&
                         (t[-2] < t[1] || (t[-2] == t[1] && t[-1] < t[2]))));
        double c[2];
        vor_circumcenter(xy + 2 * t[0], xy + 2 * t[1], xy + 2 * t[2], c);
        assert_memory_equal(c, d->vertex_xy + 2 * v, sizeof c);
    }
    size_t nr = 0;
    for (size_t e = 0; e < d->n_edges; e++) {
        const uint32_t *ab = d->edge_sites + 2 * e;
        const int32_t *en = d->edge_ends + 2 * e;
        assert_true(ab[0] < ab[1]);
        if (e > 0)
            assert_true(ab[-2] < ab[0] || (ab[-2] == ab[0] && ab[-1] < ab[1]));
        if (en[0] >= 0 && en[1] >= 0) assert_true(en[0] < en[1]);
        if (en[0] < 0) assert_int_equal(en[1], VOR_NONE);
        if (en[1] < 0) {
            assert_true(nr < d->n_rays);
            assert_int_equal(d->ray_edge[nr], e);
            double dir[2];
            const double *pa = xy + 2 * ab[0], *pb = xy + 2 * ab[1];
            if (en[0] < 0) {
                vor_bisector_dir(pa, pb, dir);
            } else {
                /* away from the vertex's other sites: the ray is on the side
                 * of ab where none of them is */
                const uint32_t *t = d->vertex_sites + 3 * en[0];
                uint32_t k = t[0] != ab[0] && t[0] != ab[1] ? t[0]
                           : t[1] != ab[0] && t[1] != ab[1] ? t[1] : t[2];
                int o = vor_orient2d(pa, pb, xy + 2 * k);
                assert_int_not_equal(o, 0);
                vor_bisector_dir(o > 0 ? pb : pa, o > 0 ? pa : pb, dir);
                double side = (pb[0] - pa[0]) * dir[1] - (pb[1] - pa[1]) * dir[0];
                assert_true(o > 0 ? side < 0 : side > 0);
            }
            assert_memory_equal(dir, d->ray_dir + 2 * nr, sizeof dir);
            nr++;
        }
    }
    assert_int_equal(nr, d->n_rays);
    assert_int_equal(d->cell_start[0], 0);
    assert_int_equal(d->cell_start[s->n], 2 * d->n_edges);
    for (uint32_t i = 0; i < s->n; i++) {
        const uint32_t *L = d->cell_edges + d->cell_start[i];
        size_t k = d->cell_start[i + 1] - d->cell_start[i];
        int bounded = 1;
        for (size_t t = 0; t < k; t++) {
            assert_true(L[t] < d->n_edges);
            assert_true(d->edge_sites[2 * L[t]] == i ||
                        d->edge_sites[2 * L[t] + 1] == i);
            if (d->edge_ends[2 * L[t] + 1] < 0) bounded = 0;
        }
        if (k == 0) bounded = 0;
        assert_int_equal(d->cell_bounded[i], bounded);
        if (d->n_vertices == 0) continue; /* parallel lines */
        size_t turns = bounded ? k : k - 1;
        for (size_t t = 0; t < turns; t++) {
            uint32_t e = L[t], f = L[(t + 1) % k];
            assert_int_equal(vor_orient2d(xy + 2 * i, xy + 2 * other(d, e, i),
                                          xy + 2 * other(d, f, i)), 1);
            const int32_t *p = d->edge_ends + 2 * e, *q = d->edge_ends + 2 * f;
            int shared = (p[0] >= 0 && (p[0] == q[0] || p[0] == q[1])) ||
                         (p[1] >= 0 && (p[1] == q[0] || p[1] == q[1]));
            assert_true(shared);
        }
        if (bounded) {
            for (size_t t = 1; t < k; t++) assert_true(L[0] < L[t]);
        } else {
            /* first edge comes in from infinity: its vertex is shared with
             * the next edge (or it is the only edge) */
            assert_true(d->edge_ends[2 * L[0] + 1] < 0);
            assert_true(d->edge_ends[2 * L[k - 1] + 1] < 0);
        }
    }
}

/* ---- hand-made diagrams -------------------------------------------------- */

static void test_square_by_hand(void **state) {
    (void)state;
    static const double pts[] = {0, 0, 1, 0, 1, 1, 0, 1};
    vor_sites *s = sites_of(pts, 4);
    /* one vertex (id 0) with four rays, given in a scrambled order */
    uint32_t *edges = malloc(8 * sizeof *edges);
    int32_t *ends = malloc(8 * sizeof *ends);
    static const uint32_t E[] = {2, 3, 1, 0, 3, 0, 2, 1};
    static const int32_t N[] = {VOR_NONE, 0, 0, VOR_NONE, 0, VOR_NONE, VOR_NONE, 0};
    memcpy(edges, E, sizeof E);
    memcpy(ends, N, sizeof N);
    vor_diagram *d = NULL;
    assert_int_equal(vor__diagram_build(s, 1, edges, ends, 4, &d), VOR_OK);

    assert_int_equal(d->n_vertices, 1);
    static const uint32_t VS[] = {0, 1, 2};
    assert_memory_equal(d->vertex_sites, VS, sizeof VS);
    assert_true(d->vertex_xy[0] == 0.5 && d->vertex_xy[1] == 0.5);
    assert_int_equal(d->n_edges, 4);
    static const uint32_t ES[] = {0, 1, 0, 3, 1, 2, 2, 3};
    assert_memory_equal(d->edge_sites, ES, sizeof ES);
    for (int e = 0; e < 4; e++) {
        assert_int_equal(d->edge_ends[2 * e], 0);
        assert_int_equal(d->edge_ends[2 * e + 1], VOR_NONE);
    }
    assert_int_equal(d->n_rays, 4);
    static const double DIR[] = {0, -1, -1, 0, 1, 0, 0, 1};
    for (int r = 0; r < 4; r++) {
        assert_int_equal(d->ray_edge[r], r);
        assert_true(d->ray_dir[2 * r] == DIR[2 * r]);
        assert_true(d->ray_dir[2 * r + 1] == DIR[2 * r + 1]);
    }
    /* cell of (0,0): in from below along x = 0.5, out to the left */
    static const uint32_t CS[] = {0, 2, 4, 6, 8};
    static const uint32_t CE[] = {0, 1, 2, 0, 3, 2, 1, 3};
    assert_memory_equal(d->cell_start, CS, sizeof CS);
    assert_memory_equal(d->cell_edges, CE, sizeof CE);
    for (int i = 0; i < 4; i++) assert_int_equal(d->cell_bounded[i], 0);
    assert_canonical(d, s);

    uint32_t *tri;
    size_t nt;
    assert_int_equal(vor_diagram_triangles(d, s, &tri, &nt), VOR_OK);
    assert_int_equal(nt, 2);
    static const uint32_t T[] = {0, 1, 2, 0, 2, 3};
    assert_memory_equal(tri, T, sizeof T);
    free(tri);
    vor_diagram_free(d);
    sites_done(s);
}

/* An obtuse triangle: the vertex lies outside the hull, below the long
 * edge, and that edge's ray still points away from the third site. */
static void test_obtuse_triangle(void **state) {
    (void)state;
    static const double pts[] = {0, 0, 4, 0, 2, 1};
    vor_sites *s = sites_of(pts, 3);
    uint32_t *edges = malloc(6 * sizeof *edges);
    int32_t *ends = malloc(6 * sizeof *ends);
    static const uint32_t E[] = {1, 0, 2, 1, 0, 2};
    static const int32_t N[] = {0, VOR_NONE, VOR_NONE, 0, 0, VOR_NONE};
    memcpy(edges, E, sizeof E);
    memcpy(ends, N, sizeof N);
    vor_diagram *d = NULL;
    assert_int_equal(vor__diagram_build(s, 1, edges, ends, 3, &d), VOR_OK);
    assert_true(d->vertex_xy[0] == 2.0 && d->vertex_xy[1] == -1.5);
    static const uint32_t ES[] = {0, 1, 0, 2, 1, 2};
    assert_memory_equal(d->edge_sites, ES, sizeof ES);
    assert_true(d->ray_dir[0] == 0.0 && d->ray_dir[1] == -1.0);
    /* (0,2): away from (4,0), i.e. up and to the left */
    assert_true(d->ray_dir[2] < 0 && d->ray_dir[3] > 0);
    assert_true(d->ray_dir[4] > 0 && d->ray_dir[5] > 0);
    assert_canonical(d, s);
    vor_diagram_free(d);
    sites_done(s);
}

/* A site inside a triangle has a bounded cell of three segments. */
static void test_bounded_cell(void **state) {
    (void)state;
    static const double pts[] = {0, 10, -9, -5, 9, -5, 0, 0};
    vor_sites *s = sites_of(pts, 4);
    bf_voronoi b;
    assert_int_equal(bf_voronoi_make(s, &b), 0);
    assert_int_equal(b.nv, 3);
    assert_int_equal(b.ne, 6);
    vor_diagram *d = build_bf(s, &b, 7);
    assert_canonical(d, s);
    assert_int_equal(d->cell_bounded[3], 1);
    assert_int_equal(d->cell_start[4] - d->cell_start[3], 3);
    /* edges (0,3) (1,3) (2,3) are 2, 4, 5; the cell starts at the smallest */
    static const uint32_t ES[] = {0, 1, 0, 2, 0, 3, 1, 2, 1, 3, 2, 3};
    assert_memory_equal(d->edge_sites, ES, sizeof ES);
    assert_int_equal(d->cell_edges[d->cell_start[3]], 2);
    assert_int_equal(d->n_rays, 3);
    bf_free(&b);
    vor_diagram_free(d);
    sites_done(s);
}

/* ---- brute force, shuffled ----------------------------------------------- */

/* Small sets with and without cocircular sites. */
static double *small_set(int kind, uint64_t seed, size_t *n) {
    vt_rng r = {seed};
    switch (kind) {
    case 0: /* uniform */
        *n = 3 + (size_t)(vt_next(&r) % 28);
        return vt_uniform(*n, seed);
    case 1: { /* small integer lattice: many cocircular quadruples */
        *n = 4 + (size_t)(vt_next(&r) % 20);
        double *xy = malloc(2 * *n * sizeof *xy);
        for (size_t i = 0; i < *n; i++) {
            xy[2 * i] = (double)(vt_next(&r) % 6);
            xy[2 * i + 1] = (double)(vt_next(&r) % 6);
        }
        return xy;
    }
    case 2: /* integer circle of radius 5 with its centre */
        return vt_int_circle(5, (int)(seed & 1), n);
    default: /* 4x4 grid */
        *n = 16;
        return vt_grid(4, 4);
    }
}

static void test_brute_force_shuffled(void **state) {
    (void)state;
    const uint64_t seed0 = 20240601;
    printf("brute-force shuffles: seeds %llu..%llu\n",
           (unsigned long long)seed0, (unsigned long long)seed0 + 199);
    for (uint64_t seed = seed0; seed < seed0 + 200; seed++) {
        size_t n0;
        double *xy = small_set((int)(seed % 4), seed, &n0);
        vor_sites *s = sites_of(xy, n0);
        free(xy);
        if (vor__all_collinear(s)) {
            sites_done(s);
            continue;
        }
        bf_voronoi b;
        assert_int_equal(bf_voronoi_make(s, &b), 0);
        vor_diagram *d0 = build_bf(s, &b, 0);
        assert_canonical(d0, s);
        assert_int_equal(d0->n_vertices, b.nv);
        assert_int_equal(d0->n_edges, b.ne);
        /* Euler with one vertex at infinity */
        assert_int_equal(d0->n_vertices + 1 + s->n, d0->n_edges + 2);
        for (uint64_t k = 1; k <= 4; k++) {
            vor_diagram *d1 = build_bf(s, &b, seed * 31 + k);
            if (!vor_diagram_equal(d0, d1))
                fail_msg("seed %llu shuffle %llu: builder depends on input order",
                         (unsigned long long)seed, (unsigned long long)k);
            vor_diagram_free(d1);
        }
        /* the dual triangles are the oracle's fans from the smallest site */
        uint32_t *tri;
        size_t nt, expect = 0;
        assert_int_equal(vor_diagram_triangles(d0, s, &tri, &nt), VOR_OK);
        for (size_t v = 0; v < b.nv; v++) {
            size_t lo = b.vstart[v], m = b.vstart[v + 1] - lo;
            for (size_t q = 1; q + 1 < m; q++) {
                uint32_t t3[3] = {b.vsite[lo], b.vsite[lo + q], b.vsite[lo + q + 1]};
                int found = 0;
                for (size_t t = 0; t < nt && !found; t++)
                    found = memcmp(tri + 3 * t, t3, sizeof t3) == 0;
                if (!found) fail_msg("seed %llu: fan triangle missing",
                                     (unsigned long long)seed);
                expect++;
            }
        }
        assert_int_equal(nt, expect);
        free(tri);
        vor_diagram_free(d0);
        bf_free(&b);
        sites_done(s);
    }
}

/* Any Delaunay triangulation (here: cocircular polygons fanned from random
 * corners, triangles in random order) converts to the same diagram. */
static void test_mesh_to_diagram(void **state) {
    (void)state;
    const uint64_t seed0 = 777;
    printf("mesh conversion: seeds %llu..%llu\n", (unsigned long long)seed0,
           (unsigned long long)seed0 + 99);
    for (uint64_t seed = seed0; seed < seed0 + 100; seed++) {
        size_t n0;
        double *xy = small_set((int)(seed % 4), seed, &n0);
        vor_sites *s = sites_of(xy, n0);
        free(xy);
        if (vor__all_collinear(s)) {
            sites_done(s);
            continue;
        }
        bf_voronoi b;
        assert_int_equal(bf_voronoi_make(s, &b), 0);
        vor_diagram *d0 = build_bf(s, &b, 0);
        for (uint64_t k = 0; k < 3; k++) {
            vor__mesh m;
            assert_int_equal(bf_mesh(&b, k ? seed * 7 + k : 0, &m), 0);
            vor_diagram *d1 = NULL;
            assert_int_equal(vor__mesh_to_diagram(s, &m, &d1), VOR_OK);
            assert_null(m.tri);
            assert_null(m.adj);
            if (!vor_diagram_equal(d0, d1))
                fail_msg("seed %llu fan %llu: mesh conversion differs",
                         (unsigned long long)seed, (unsigned long long)k);
            vor_diagram_free(d1);
        }
        vor_diagram_free(d0);
        bf_free(&b);
        sites_done(s);
    }
}

/* Site 0 at the centre of 60 sites on a circle: it is the smallest site of
 * all 60 vertices and of 60 edges, so the sorts take their path for large
 * buckets. Both builders must still agree and be canonical. */
static void test_large_buckets(void **state) {
    (void)state;
    double *ring = vt_unit_circle(60);
    double xy[2 * 61];
    xy[0] = 0.0;
    xy[1] = 0.0;
    memcpy(xy + 2, ring, sizeof(double) * 120);
    free(ring);
    vor_sites *s = sites_of(xy, 61);
    bf_voronoi b;
    assert_int_equal(bf_voronoi_make(s, &b), 0);
    assert_int_equal(b.nv, 60);
    vor_diagram *d0 = build_bf(s, &b, 0);
    assert_canonical(d0, s);
    char msg[256];
    if (vor_check(d0, s, msg, sizeof msg) != 0) fail_msg("%s", msg);
    for (uint64_t k = 1; k <= 3; k++) {
        vor_diagram *d1 = build_bf(s, &b, k);
        assert_true(vor_diagram_equal(d0, d1));
        vor_diagram_free(d1);
        vor__mesh m;
        assert_int_equal(bf_mesh(&b, k, &m), 0);
        assert_int_equal(vor__mesh_to_diagram(s, &m, &d1), VOR_OK);
        assert_true(vor_diagram_equal(d0, d1));
        vor_diagram_free(d1);
    }
    vor_diagram_free(d0);
    bf_free(&b);
    sites_done(s);
}

/* ---- degenerate ---------------------------------------------------------- */

static void test_degenerate(void **state) {
    (void)state;
    vor_diagram *d = NULL;
    vor_sites *s = sites_of(NULL, 0);
    assert_true(vor__all_collinear(s));
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        assert_int_equal(vor_compute(s, (vor_algorithm)a, &d), VOR_OK);
        assert_int_equal(d->n_sites, 0);
        assert_int_equal(d->n_edges + d->n_vertices + d->n_rays, 0);
        assert_int_equal(d->cell_start[0], 0);
        vor_diagram_free(d);
    }
    sites_done(s);

    static const double one[] = {3, 4};
    s = sites_of(one, 1);
    assert_int_equal(vor__diagram_degenerate(s, &d), VOR_OK);
    assert_int_equal(d->n_edges, 0);
    assert_int_equal(d->cell_start[1], 0);
    assert_int_equal(d->cell_bounded[0], 0);
    vor_diagram_free(d);
    sites_done(s);

    /* two sites: one line, site 0 on its left */
    static const double two[] = {1, 1, 0, 0};
    s = sites_of(two, 2);
    assert_int_equal(vor_compute(s, VOR_FLIP, &d), VOR_OK);
    assert_int_equal(d->n_edges, 1);
    assert_int_equal(d->edge_ends[0], VOR_NONE);
    assert_int_equal(d->edge_ends[1], VOR_NONE);
    assert_int_equal(d->n_rays, 1);
    assert_true(d->ray_dir[0] > 0 && d->ray_dir[1] < 0);
    assert_true(fabs(d->ray_dir[0] - sqrt(0.5)) < 1e-15);
    vor_diagram_free(d);
    sites_done(s);

    /* collinear, shuffled, slanted: lines between neighbours along the line;
     * a middle cell lists its two lines in edge order */
    static const double col[] = {2, 1, -4, -2, 0, 0, 6, 3, 4, 2};
    s = sites_of(col, 5);
    assert_true(vor__all_collinear(s));
    assert_int_equal(vor_compute(s, VOR_BOWYER_WATSON, &d), VOR_OK);
    assert_int_equal(d->n_vertices, 0);
    /* order along the line: 1 (-4), 2 (0), 0 (2), 4 (4), 3 (6) */
    static const uint32_t ES[] = {0, 2, 0, 4, 1, 2, 3, 4};
    assert_int_equal(d->n_edges, 4);
    assert_memory_equal(d->edge_sites, ES, sizeof ES);
    static const uint32_t CS[] = {0, 2, 3, 5, 6, 8};
    static const uint32_t CE[] = {0, 1, 2, 0, 2, 3, 1, 3};
    assert_memory_equal(d->cell_start, CS, sizeof CS);
    assert_memory_equal(d->cell_edges, CE, sizeof CE);
    for (int r = 0; r < 4; r++) {
        assert_int_equal(d->ray_edge[r], r);
        double dir[2];
        vor_bisector_dir(col + 2 * ES[2 * r], col + 2 * ES[2 * r + 1], dir);
        assert_memory_equal(dir, d->ray_dir + 2 * r, sizeof dir);
    }
    assert_canonical(d, s);
    uint32_t *tri;
    size_t nt = 99;
    assert_int_equal(vor_diagram_triangles(d, s, &tri, &nt), VOR_OK);
    assert_int_equal(nt, 0);
    free(tri);
    vor_diagram_free(d);
    sites_done(s);

    /* vertical line: order by y */
    static const double vert[] = {1, 5, 1, -1, 1, 2};
    s = sites_of(vert, 3);
    assert_int_equal(vor__diagram_degenerate(s, &d), VOR_OK);
    static const uint32_t VES[] = {0, 2, 1, 2};
    assert_memory_equal(d->edge_sites, VES, sizeof VES);
    vor_diagram_free(d);
    sites_done(s);

    static const double tri3[] = {0, 0, 1, 0, 0, 1};
    s = sites_of(tri3, 3);
    assert_false(vor__all_collinear(s));
    sites_done(s);
}

/* ---- contract violations ------------------------------------------------- */

/* Waits for child pid, which ran a builder on broken input: it must have
 * exited 0 (the builder refused it) or stopped on an assert (SIGABRT). */
static void expect_refusal(pid_t pid, const char *failure, const char *what) {
    int ws = 0;
    assert_int_equal(waitpid(pid, &ws, 0), pid);
    int ok = (WIFEXITED(ws) && WEXITSTATUS(ws) == 0) ||
             (WIFSIGNALED(ws) && WTERMSIG(ws) == SIGABRT);
    if (!ok) fail_msg("%s: %s (status %d)", failure, what, ws);
}

/* Runs the builder on broken input in a child process: a debug build must
 * stop on its assert, a release build must return VOR_EINVAL. */
static void expect_rejected(const char *what, const double *pts, size_t n,
                            size_t nv, const uint32_t *E, const int32_t *N,
                            size_t ne) {
    fflush(stdout);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        close(2); /* the assert message is expected */
        vor_sites *s = sites_of(pts, n);
        uint32_t *edges = malloc(2 * ne * sizeof *edges);
        int32_t *ends = malloc(2 * ne * sizeof *ends);
        memcpy(edges, E, 2 * ne * sizeof *edges);
        memcpy(ends, N, 2 * ne * sizeof *ends);
        vor_diagram *d = NULL;
        vor_status st = vor__diagram_build(s, nv, edges, ends, ne, &d);
        sites_done(s);
        _exit(st == VOR_EINVAL && d == NULL ? 0 : 1);
    }
    expect_refusal(pid, "broken input accepted", what);
}

static void test_rejects_broken_input(void **state) {
    (void)state;
    static const double sq[] = {0, 0, 1, 0, 1, 1, 0, 1};
    const int32_t X = VOR_NONE;
    {
        const uint32_t E[] = {0, 1, 1, 2, 2, 3, 0, 3};
        const int32_t N[] = {0, X, 0, X, 0, X, 0, X};
        expect_rejected("site out of range", sq, 3, 1, E, N, 4);
    }
    {
        const uint32_t E[] = {0, 1, 1, 1, 2, 3, 0, 3};
        const int32_t N[] = {0, X, 0, X, 0, X, 0, X};
        expect_rejected("edge between a site and itself", sq, 4, 1, E, N, 4);
    }
    {
        const uint32_t E[] = {0, 1, 1, 2, 2, 3, 0, 3};
        const int32_t N[] = {0, X, 0, X, 0, X, 0, 0};
        expect_rejected("zero-length segment", sq, 4, 1, E, N, 4);
    }
    {
        const uint32_t E[] = {0, 1, 1, 2, 2, 3, 0, 3, 1, 0};
        const int32_t N[] = {0, X, 0, X, 0, X, 0, X, X, 0};
        expect_rejected("duplicate edge", sq, 4, 1, E, N, 5);
    }
    {
        const uint32_t E[] = {0, 1, 1, 2, 2, 3, 0, 3};
        const int32_t N[] = {0, X, 0, X, 0, X, 0, X};
        expect_rejected("vertex without edges", sq, 4, 2, E, N, 4);
    }
    {
        const uint32_t E[] = {0, 1, 1, 2, 2, 3, 0, 3};
        const int32_t N[] = {0, X, 0, X, 1, X, 1, X};
        expect_rejected("two vertices on one circle", sq, 4, 2, E, N, 4);
    }
    {
        const uint32_t E[] = {0, 1, 1, 2, 2, 3, 0, 3};
        const int32_t N[] = {0, X, 0, X, 0, 3, 0, X};
        expect_rejected("vertex id out of range", sq, 4, 1, E, N, 4);
    }
    {
        /* cell of site 0 misses an edge: the chain does not close */
        const uint32_t E[] = {0, 1, 1, 2, 2, 3};
        const int32_t N[] = {0, X, 0, X, 0, X};
        expect_rejected("open cell chain", sq, 4, 1, E, N, 3);
    }
    {
        /* square with its centre, one spoke missing */
        static const double sc[] = {0, 0, 2, 0, 2, 2, 0, 2, 1, 1};
        const uint32_t E[] = {0, 1, 1, 2, 2, 3, 0, 3, 0, 4, 1, 4, 2, 4};
        const int32_t N[] = {0, X, 1, X, 2, X, 3, X, 3, 0, 0, 1, 1, 2};
        expect_rejected("bounded cell not closed", sc, 5, 4, E, N, 7);
    }
}

/* The same for the mesh conversion: a mesh that is not Delaunay, or whose
 * twins do not match, is refused. */
static void expect_mesh_rejected(const char *what, const double *pts, size_t n,
                                 const uint32_t *T, const int32_t *A, size_t nt) {
    fflush(stdout);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        close(2);
        vor_sites *s = sites_of(pts, n);
        vor__mesh m = {nt, nt, malloc(3 * nt * sizeof(uint32_t)),
                       malloc(3 * nt * sizeof(int32_t))};
        memcpy(m.tri, T, 3 * nt * sizeof *T);
        memcpy(m.adj, A, 3 * nt * sizeof *A);
        vor_diagram *d = NULL;
        vor_status st = vor__mesh_to_diagram(s, &m, &d);
        int cleared = m.tri == NULL && m.adj == NULL;
        sites_done(s);
        _exit(st == VOR_EINVAL && d == NULL && cleared ? 0 : 1);
    }
    expect_refusal(pid, "broken mesh accepted", what);
}

static void test_rejects_broken_mesh(void **state) {
    (void)state;
    /* kite: AC is the Delaunay diagonal (D lies outside the circle of ABC) */
    static const double kite[] = {0, 0, 1, -1, 2, 0, 1, 1.5};
    /* triangles ABD, BCD: half-edge 1 (B->D) twins 5 (D->B) */
    const uint32_t T[] = {0, 1, 3, 1, 2, 3};
    const int32_t A[] = {-1, 5, -1, -1, -1, 1};
    expect_mesh_rejected("mesh not Delaunay", kite, 4, T, A, 2);
    const uint32_t T2[] = {0, 1, 2, 0, 2, 3}; /* the Delaunay one */
    const int32_t A2[] = {-1, -1, 3, 2, -1, -1};
    const int32_t A3[] = {-1, -1, 4, 2, -1, -1};
    expect_mesh_rejected("twins do not match", kite, 4, T2, A3, 2);
    const uint32_t T4[] = {0, 1, 2, 0, 2, 7};
    expect_mesh_rejected("site out of range", kite, 4, T4, A2, 2);
    /* and the good one is accepted */
    vor_sites *s = sites_of(kite, 4);
    vor__mesh m = {2, 2, malloc(6 * sizeof(uint32_t)), malloc(6 * sizeof(int32_t))};
    memcpy(m.tri, T2, sizeof T2);
    memcpy(m.adj, A2, sizeof A2);
    vor_diagram *d = NULL;
    assert_int_equal(vor__mesh_to_diagram(s, &m, &d), VOR_OK);
    assert_int_equal(d->n_vertices, 2);
    assert_int_equal(d->n_edges, 5);
    vor_diagram_free(d);
    sites_done(s);
}

/* ---- allocation failures ------------------------------------------------- */

/* Every allocation of the builder, the mesh conversion, the degenerate
 * builder and the dual triangles is made to fail in turn: each must return
 * VOR_ENOMEM with nothing allocated (LeakSanitizer checks at exit), until
 * enough succeed. */
static void test_allocation_failures(void **state) {
    (void)state;
    static const double pts[] = {0, 10, -9, -5, 9, -5, 0, 0, 3, 1, 1, 1, -1, -1, 2, 3};
    vor_sites *s = sites_of(pts, 8);
    bf_voronoi b;
    assert_int_equal(bf_voronoi_make(s, &b), 0);
    long k, total[6] = {0};

    for (k = 0;; k++) { /* vor__diagram_build */
        uint32_t *edges;
        int32_t *ends;
        assert_int_equal(bf_raw(&b, 5, &edges, &ends), 0);
        vor_diagram *d = (vor_diagram *)1;
        fault_arm(k);
        vor_status st = vor__diagram_build(s, b.nv, edges, ends, b.ne, &d);
        fault_disarm();
        if (st == VOR_OK) {
            vor_diagram_free(d);
            break;
        }
        assert_int_equal(st, VOR_ENOMEM);
        assert_null(d);
    }
    total[0] = k;
    vor_diagram *good = NULL;
    for (k = 0;; k++) { /* vor__mesh_to_diagram */
        vor__mesh m;
        assert_int_equal(bf_mesh(&b, 3, &m), 0);
        vor_diagram *d = (vor_diagram *)1;
        fault_arm(k);
        vor_status st = vor__mesh_to_diagram(s, &m, &d);
        fault_disarm();
        assert_null(m.tri);
        if (st == VOR_OK) {
            good = d;
            break;
        }
        assert_int_equal(st, VOR_ENOMEM);
        assert_null(d);
    }
    total[1] = k;
    /* vor_diagram_triangles (its vertices have three sites each), the
     * cells' walk, and vor_diagram_triangles on a grid of nine points
     * (vertices of four sites) */
    static const double g9[] = {0, 0, 1, 0, 2, 0, 0, 1, 1, 1,
                                2, 1, 0, 2, 1, 2, 2, 2};
    vor_sites *sg = sites_of(g9, 9);
    vor_diagram *dg = NULL;
    assert_int_equal(vor_compute(sg, VOR_FLIP, &dg), VOR_OK);
    for (int way = 0; way < 3; way++) {
        for (k = 0;; k++) {
            uint32_t *tri = (uint32_t *)1;
            size_t nt = 9;
            fault_arm(k);
            vor_status st =
                way == 1 ? vor__diagram_triangles_cells(good, s, &tri, &nt)
                : way == 0 ? vor_diagram_triangles(good, s, &tri, &nt)
                           : vor_diagram_triangles(dg, sg, &tri, &nt);
            fault_disarm();
            if (st == VOR_OK) {
                if (way == 2) assert_int_equal(nt, 8);
                free(tri);
                break;
            }
            assert_int_equal(st, VOR_ENOMEM);
            assert_null(tri);
            assert_int_equal(nt, 0);
        }
        total[way == 0 ? 2 : way == 1 ? 4 : 5] = k;
    }
    vor_diagram_free(dg);
    sites_done(sg);
    vor_diagram_free(good);
    bf_free(&b);
    sites_done(s);

    static const double col[] = {2, 1, -4, -2, 0, 0, 6, 3, 4, 2};
    s = sites_of(col, 5);
    for (k = 0;; k++) { /* vor__diagram_degenerate */
        vor_diagram *d = (vor_diagram *)1;
        fault_arm(k);
        vor_status st = vor__diagram_degenerate(s, &d);
        fault_disarm();
        if (st == VOR_OK) {
            vor_diagram_free(d);
            break;
        }
        assert_int_equal(st, VOR_ENOMEM);
        assert_null(d);
    }
    total[3] = k;
    sites_done(s);
    printf("allocations failed in turn: build %ld, mesh conversion %ld, "
           "triangles %ld (from the cells %ld, of a grid %ld), degenerate "
           "%ld\n", total[0], total[1], total[2], total[4], total[5],
           total[3]);
    assert_true(total[0] >= 8 && total[1] >= 10 && total[2] >= 1 &&
                total[4] >= 4 && total[5] >= 5 && total[3] >= 8);
}

/* ---- equality and the dispatcher ----------------------------------------- */

static void test_equal(void **state) {
    (void)state;
    static const double pts[] = {0, 10, -9, -5, 9, -5, 0, 0, 3, 1};
    vor_sites *s = sites_of(pts, 5);
    bf_voronoi b;
    assert_int_equal(bf_voronoi_make(s, &b), 0);
    vor_diagram *p = build_bf(s, &b, 1), *q = build_bf(s, &b, 2);
    assert_true(vor_diagram_equal(p, q));
    assert_true(vor_diagram_equal(p, p));
    assert_false(vor_diagram_equal(p, NULL));
    assert_true(vor_diagram_equal(NULL, NULL));
    uint64_t bits;
    memcpy(&bits, q->vertex_xy + 1, sizeof bits);
    bits ^= 1;
    memcpy(q->vertex_xy + 1, &bits, sizeof bits);
    assert_false(vor_diagram_equal(p, q));
    bits ^= 1;
    memcpy(q->vertex_xy + 1, &bits, sizeof bits);
    q->cell_edges[3] ^= 1;
    assert_false(vor_diagram_equal(p, q));
    q->cell_edges[3] ^= 1;
    q->cell_bounded[0] ^= 1;
    assert_false(vor_diagram_equal(p, q));
    q->cell_bounded[0] ^= 1;
    assert_true(vor_diagram_equal(p, q));
    vor_diagram_free(p);
    vor_diagram_free(q);
    vor_diagram_free(NULL);
    bf_free(&b);
    sites_done(s);
}

static void test_compute_arguments(void **state) {
    (void)state;
    static const double pts[] = {0, 0, 1, 0, 0, 1};
    vor_sites *s = sites_of(pts, 3);
    vor_diagram *d = (vor_diagram *)1;
    assert_int_equal(vor_compute(NULL, VOR_FLIP, &d), VOR_EINVAL);
    assert_null(d);
    assert_int_equal(vor_compute(s, VOR_FLIP, NULL), VOR_EINVAL);
    d = (vor_diagram *)1;
    assert_int_equal(vor_compute(s, (vor_algorithm)3, &d), VOR_EALGORITHM);
    assert_null(d);
    assert_int_equal(vor_compute(s, (vor_algorithm)-1, &d), VOR_EALGORITHM);
    uint32_t *tri = (uint32_t *)1;
    size_t nt = 5;
    assert_int_equal(vor_diagram_triangles(NULL, s, &tri, &nt), VOR_EINVAL);
    assert_null(tri);
    assert_int_equal(nt, 0);
    sites_done(s);
}

/* vor_diagram_triangles reads vertex_sites where a vertex has three
 * sites and fans a vertex of more from its edges: on every standard set
 * and every distribution of the service, by each algorithm, it must give
 * the cells' triangles exactly (vor__diagram_triangles_cells: the
 * definition). The sets without four cocircular sites must take the
 * first way alone (each vertex three edge ends), and some have vertices
 * of more. */
static void test_triangles_from_vertices(void **state) {
    (void)state;
    static const char *const dists[] = {"uniform", "gaussian", "clustered",
                                        "lognormal", "outlier", "decades",
                                        "pixels", "grid", "circle"};
    const size_t nd = sizeof dists / sizeof dists[0];
    int generic = 0, cocircular = 0;
    size_t kmax = 0;
    for (size_t i = 0; i < vt_count() + nd + 1; i++) {
        vt_set set = {0};
        if (i < vt_count()) {
            assert_int_equal(vt_make(i, &set), 0);
        } else if (i == vt_count() + nd) {
            /* the 180 integer points on x^2 + y^2 = 5525^2: one vertex */
            set.name = "integer circle";
            set.xy = vt_int_circle(5525, 0, &set.n);
            assert_non_null(set.xy);
        } else {
            set.name = dists[i - vt_count()];
            set.n = 3000;
            set.xy = vt_distribution(set.name, set.n, 7);
            assert_non_null(set.xy);
        }
        vor_sites *s = NULL;
        if (vor_sites_new(set.xy, set.n, &s, NULL) != VOR_OK || s->n < 3) {
            vor_sites_free(s);
            vt_set_free(&set);
            continue;
        }
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            vor_diagram *d = NULL;
            assert_int_equal(vor_compute(s, (vor_algorithm)a, &d), VOR_OK);
            uint32_t *t1 = NULL, *t2 = NULL;
            size_t n1 = 0, n2 = 0, ends = 0;
            assert_int_equal(vor_diagram_triangles(d, s, &t1, &n1), VOR_OK);
            assert_int_equal(vor__diagram_triangles_cells(d, s, &t2, &n2),
                             VOR_OK);
            if (n1 != n2 || (n1 && memcmp(t1, t2, 12 * n1) != 0))
                fail_msg("%s by %s: the triangles differ from the cells'",
                         set.name, vor_algorithm_name((vor_algorithm)a));
            /* the vertices' degrees: edge ends at each */
            uint32_t *deg = calloc(d->n_vertices + 1, sizeof *deg);
            assert_non_null(deg);
            for (size_t k = 0; k < 2 * d->n_edges; k++) {
                if (d->edge_ends[k] < 0) continue;
                ends++;
                if (++deg[d->edge_ends[k]] > kmax) kmax = deg[d->edge_ends[k]];
            }
            free(deg);
            if (d->n_vertices) {
                generic += ends == 3 * d->n_vertices;
                cocircular += ends != 3 * d->n_vertices;
            }
            free(t1);
            free(t2);
            vor_diagram_free(d);
        }
        vor_sites_free(s);
        vt_set_free(&set);
    }
    print_message("triangles_from_vertices: %d diagrams of three sites a "
                  "vertex, %d with more; the largest vertex %zu sites\n",
                  generic, cocircular, kmax);
    assert_true(generic >= 15 && cocircular >= 9 && kmax >= 100);
}

int main(void) {
    /* VOR_TEST_FILTER / VOR_TEST_SKIP: run a subset (glob on test names) */
    if (getenv("VOR_TEST_FILTER")) cmocka_set_test_filter(getenv("VOR_TEST_FILTER"));
    if (getenv("VOR_TEST_SKIP")) cmocka_set_skip_filter(getenv("VOR_TEST_SKIP"));
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_square_by_hand),
        cmocka_unit_test(test_obtuse_triangle),
        cmocka_unit_test(test_bounded_cell),
        cmocka_unit_test(test_brute_force_shuffled),
        cmocka_unit_test(test_triangles_from_vertices),
        cmocka_unit_test(test_mesh_to_diagram),
        cmocka_unit_test(test_large_buckets),
        cmocka_unit_test(test_degenerate),
        cmocka_unit_test(test_rejects_broken_input),
        cmocka_unit_test(test_rejects_broken_mesh),
        cmocka_unit_test(test_allocation_failures),
        cmocka_unit_test(test_equal),
        cmocka_unit_test(test_compute_arguments),
    };
    return cmocka_run_group_tests_name("core/diagram", tests, NULL, NULL);
}
