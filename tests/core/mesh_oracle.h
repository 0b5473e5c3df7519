/* mesh_oracle.h -- what the Delaunay mesh tests share: site sets built
 * without core/sites.c, a brute-force Delaunay oracle, a canonical form for
 * comparing two triangulations, and the test bodies that test_bowyer_watson.c
 * and test_flip.c run on their own algorithm.
 *
 * The oracle is independent of core/mesh.c's checker: every triangle must
 * be counter-clockwise and have no site strictly inside its circumcircle
 * (exact vor_incircle against all n sites, O(n T)), every site must be a
 * vertex, and the triangle count must be 2n - 2 - h with h the number of
 * sites on the convex hull boundary, found by a monotone chain that keeps
 * collinear boundary sites. Header-only: static functions, one copy per
 * test binary.
 */
#ifndef VOR_TESTS_MESH_ORACLE_H
#define VOR_TESTS_MESH_ORACLE_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../core/mesh.h"
#include "../support/testsets.h"

/* An algorithm under test: the mesh with its own insertion order, and with
 * a given one. */
typedef struct mo_algorithm {
    const char *name;
    vor_status (*mesh)(const vor_sites *s, vor__mesh *m);
    vor_status (*ordered)(const vor_sites *s, uint32_t *order, vor__mesh *m);
    vor_status (*diagram)(const vor_sites *s, vor_diagram **out);
} mo_algorithm;

/* ---- Sites ---------------------------------------------------------------
 * The distinct points of xy in order of first occurrence, like
 * vor_sites_new but written here so that these tests depend on nothing but
 * the mesh code and the predicates. */
static const double *mo_sort_xy;

static inline int mo_cmp(const void *pa, const void *pb) {
    uint32_t a = *(const uint32_t *)pa, b = *(const uint32_t *)pb;
    const double *p = mo_sort_xy + 2 * (size_t)a, *q = mo_sort_xy + 2 * (size_t)b;
    if (p[0] != q[0])
        return p[0] < q[0] ? -1 : 1;
    if (p[1] != q[1])
        return p[1] < q[1] ? -1 : 1;
    return (a > b) - (a < b);
}

/* Fills *s (free with mo_sites_free); returns 0, or -1 on allocation
 * failure. */
static inline int mo_sites(const double *xy, size_t n, vor_sites *s) {
    memset(s, 0, sizeof *s);
    s->n_input = n;
    uint32_t *idx = malloc((n ? n : 1) * sizeof *idx);
    uint8_t *keep = calloc(n ? n : 1, 1);
    s->xy = malloc(2 * (n ? n : 1) * sizeof *s->xy);
    if (!idx || !keep || !s->xy) {
        free(idx);
        free(keep);
        free(s->xy);
        return -1;
    }
    for (size_t i = 0; i < n; i++)
        idx[i] = (uint32_t)i;
    mo_sort_xy = xy;
    qsort(idx, n, sizeof *idx, mo_cmp);
    for (size_t i = 0; i < n; i++) {
        const double *p = xy + 2 * (size_t)idx[i];
        const double *q = i ? xy + 2 * (size_t)idx[i - 1] : NULL;
        keep[idx[i]] = !q || p[0] != q[0] || p[1] != q[1];
    }
    for (size_t i = 0; i < n; i++) {
        if (!keep[i])
            continue;
        s->xy[2 * s->n] = xy[2 * i] == 0 ? 0.0 : xy[2 * i];
        s->xy[2 * s->n + 1] = xy[2 * i + 1] == 0 ? 0.0 : xy[2 * i + 1];
        s->n++;
    }
    free(idx);
    free(keep);
    return 0;
}

static inline void mo_sites_free(vor_sites *s) {
    free(s->xy);
    memset(s, 0, sizeof *s);
}

/* Non-zero if the sites are fewer than 3 or all on one line. */
static inline int mo_collinear(const vor_sites *s) {
    for (size_t i = 2; i < s->n; i++)
        if (vor_orient2d(s->xy, s->xy + 2, s->xy + 2 * i) != 0)
            return 0;
    return 1;
}

/* ---- Brute-force oracle --------------------------------------------------- */

/* Number of sites on the boundary of the convex hull, collinear ones
 * included (Andrew's monotone chain popping only on strict right turns).
 * The sites must not all be collinear. -1 on allocation failure. */
static inline long mo_hull_sites(const vor_sites *s) {
    size_t n = s->n;
    uint32_t *idx = malloc(n * sizeof *idx);
    uint32_t *h = malloc(2 * n * sizeof *h);
    if (!idx || !h) {
        free(idx);
        free(h);
        return -1;
    }
    for (size_t i = 0; i < n; i++)
        idx[i] = (uint32_t)i;
    mo_sort_xy = s->xy;
    qsort(idx, n, sizeof *idx, mo_cmp);
    const double *xy = s->xy;
#define MO_P(i) (xy + 2 * (size_t)(i))
    size_t k = 0;
    for (size_t i = 0; i < n; i++) { /* lower chain */
        while (k >= 2 &&
               vor_orient2d(MO_P(h[k - 2]), MO_P(h[k - 1]), MO_P(idx[i])) < 0)
            k--;
        h[k++] = idx[i];
    }
    size_t lower = k;
    for (size_t i = n - 1; i-- > 0;) { /* upper chain */
        while (k >= lower + 1 &&
               vor_orient2d(MO_P(h[k - 2]), MO_P(h[k - 1]), MO_P(idx[i])) < 0)
            k--;
        h[k++] = idx[i];
    }
#undef MO_P
    free(idx);
    free(h);
    return (long)k - 1; /* the first site closes the chain */
}

/* 0 if m is a Delaunay triangulation of s by brute force; otherwise
 * non-zero with a reason in msg. */
static inline int mo_brute(const vor__mesh *m, const vor_sites *s, char *msg,
                    size_t size) {
    const double *xy = s->xy;
    uint8_t *used = calloc(s->n, 1);
    if (!used) {
        snprintf(msg, size, "out of memory");
        return 1;
    }
    int bad = 0;
    for (size_t t = 0; t < m->n_tri && !bad; t++) {
        const uint32_t *v = m->tri + 3 * t;
        if (v[0] >= s->n || v[1] >= s->n || v[2] >= s->n) {
            snprintf(msg, size, "triangle %zu: vertex out of range", t);
            bad = 1;
            break;
        }
        const double *a = xy + 2 * (size_t)v[0], *b = xy + 2 * (size_t)v[1],
                     *c = xy + 2 * (size_t)v[2];
        if (vor_orient2d(a, b, c) <= 0) {
            snprintf(msg, size, "triangle %zu (%u %u %u) not ccw", t, v[0],
                     v[1], v[2]);
            bad = 1;
            break;
        }
        used[v[0]] = used[v[1]] = used[v[2]] = 1;
        for (size_t i = 0; i < s->n; i++) {
            if (vor_incircle(a, b, c, xy + 2 * i) > 0) {
                snprintf(msg, size,
                         "site %zu inside the circle of triangle %zu "
                         "(%u %u %u)",
                         i, t, v[0], v[1], v[2]);
                bad = 1;
                break;
            }
        }
    }
    for (size_t i = 0; i < s->n && !bad; i++) {
        if (!used[i]) {
            snprintf(msg, size, "site %zu is not a vertex", i);
            bad = 1;
        }
    }
    free(used);
    if (bad)
        return 1;
    long h = mo_hull_sites(s);
    if (h < 0 || m->n_tri != 2 * s->n - 2 - (size_t)h) {
        snprintf(msg, size, "%zu triangles, expected 2n - 2 - h = %ld",
                 m->n_tri, (long)(2 * s->n) - 2 - h);
        return 1;
    }
    return 0;
}

/* ---- Canonical form ------------------------------------------------------
 * Each triangle rotated so its smallest vertex comes first, then the list
 * sorted: two meshes of the same triangulation compare equal. */
static inline int mo_cmp_tri(const void *pa, const void *pb) {
    const uint32_t *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

static inline uint32_t *mo_canonical(const vor__mesh *m) {
    uint32_t *c = malloc(3 * m->n_tri * sizeof *c);
    if (!c)
        return NULL;
    for (size_t t = 0; t < m->n_tri; t++) {
        const uint32_t *v = m->tri + 3 * t;
        int k = v[0] < v[1] ? (v[0] < v[2] ? 0 : 2) : (v[1] < v[2] ? 1 : 2);
        for (int j = 0; j < 3; j++)
            c[3 * t + j] = v[(k + j) % 3];
    }
    qsort(c, m->n_tri, 3 * sizeof *c, mo_cmp_tri);
    return c;
}

/* ---- Running one case ------------------------------------------------------ */

/* Checks a fresh mesh of s with the library checker and, for small sets,
 * the brute-force oracle; the label names the case in failure messages. */
static inline void mo_verify(const vor__mesh *m, const vor_sites *s,
                      const char *label) {
    char msg[256] = "";
    if (vor__mesh_check(m, s, msg, sizeof msg)) {
        print_error("%s: vor__mesh_check: %s\n", label, msg);
        fail();
    }
    if (s->n <= 2000 && mo_brute(m, s, msg, sizeof msg)) {
        print_error("%s: brute force: %s\n", label, msg);
        fail();
    }
}

/* Builds the mesh of the n points xy with algorithm a in the given order
 * (NULL: the algorithm's own order) and verifies it. The points must be
 * distinct and not all collinear; order indexes the points. */
static inline void mo_run(const mo_algorithm *a, const double *xy, size_t n,
                   const uint32_t *order, const char *label) {
    vor_sites s;
    assert_int_equal(mo_sites(xy, n, &s), 0);
    assert_int_equal(s.n, n);
    vor__mesh m = {0};
    vor_status r;
    if (order) {
        uint32_t *o = malloc(n * sizeof *o);
        assert_non_null(o);
        memcpy(o, order, n * sizeof *o);
        r = a->ordered(&s, o, &m);
        free(o);
    } else {
        r = a->mesh(&s, &m);
    }
    if (r != VOR_OK) {
        print_error("%s: %s\n", label, vor_status_name(r));
        fail();
    }
    mo_verify(&m, &s, label);
    vor__mesh_clear(&m);
    mo_sites_free(&s);
}

/* A random permutation of 0..n-1 from a fixed seed. */
static inline uint32_t *mo_shuffled(size_t n, uint64_t seed) {
    uint32_t *o = malloc((n ? n : 1) * sizeof *o);
    if (!o)
        return NULL;
    vt_rng r = {seed};
    for (size_t i = 0; i < n; i++)
        o[i] = (uint32_t)i;
    for (size_t i = n; i > 1; i--) {
        size_t j = (size_t)(vt_next(&r) % i);
        uint32_t t = o[i - 1];
        o[i - 1] = o[j];
        o[j] = t;
    }
    return o;
}

/* ---- The test bodies --------------------------------------------------------- */

/* Every standard set: the mesh passes the checker (and the oracle when
 * small); sets with fewer than 3 distinct sites or all collinear are
 * refused with VOR_EINVAL and leave the mesh empty. */
static inline void mo_test_standard_sets(const mo_algorithm *a) {
    for (size_t i = 0; i < vt_count(); i++) {
        vt_set set;
        assert_int_equal(vt_make(i, &set), 0);
        vor_sites s;
        assert_int_equal(mo_sites(set.xy, set.n, &s), 0);
        vor__mesh m = {0};
        vor_status r = a->mesh(&s, &m);
        if (s.n < 3 || mo_collinear(&s)) {
            if (r != VOR_EINVAL || m.tri || m.adj || m.n_tri) {
                print_error("%s: %s on a degenerate set\n", set.name,
                            vor_status_name(r));
                fail();
            }
        } else {
            if (r != VOR_OK) {
                print_error("%s: %s\n", set.name, vor_status_name(r));
                fail();
            }
            mo_verify(&m, &s, set.name);
            print_message("  %-22s n=%-6zu triangles=%zu\n", set.name, s.n,
                          m.n_tri);
        }
        vor__mesh_clear(&m);
        mo_sites_free(&s);
        vt_set_free(&set);
    }
}

/* The first k sites in insertion order lie on one line (sorted, reversed or
 * shuffled along it), then one site off the line, then random sites. */
static inline void mo_test_collinear_start(const mo_algorithm *a) {
    const size_t k = 1000, extra = 300;
    const uint64_t seed = 20240611;
    print_message("  seed %llu\n", (unsigned long long)seed);
    size_t n = k + 1 + extra;
    double *xy = malloc(2 * n * sizeof *xy);
    uint32_t *order = malloc(n * sizeof *order);
    assert_non_null(xy);
    assert_non_null(order);
    vt_rng r = {seed};
    for (int variant = 0; variant < 3; variant++) {
        uint32_t *perm = mo_shuffled(k, seed + (uint64_t)variant);
        assert_non_null(perm);
        for (size_t i = 0; i < k; i++) { /* y = 3x + 1, exactly */
            size_t j = variant == 0 ? i : variant == 1 ? k - 1 - i : perm[i];
            xy[2 * i] = (double)j * 0.25 - 40.0;
            xy[2 * i + 1] = 3.0 * xy[2 * i] + 1.0;
        }
        free(perm);
        xy[2 * k] = 7.5; /* off the line */
        xy[2 * k + 1] = -3.0;
        for (size_t i = k + 1; i < n; i++) {
            xy[2 * i] = vt_unit(&r) * 400.0 - 200.0;
            xy[2 * i + 1] = vt_unit(&r) * 400.0 - 200.0;
        }
        for (size_t i = 0; i < n; i++)
            order[i] = (uint32_t)i;
        char label[64];
        /* Only the line and the apex: a fan of k - 1 triangles. */
        snprintf(label, sizeof label, "collinear start %d, fan", variant);
        mo_run(a, xy, k + 1, order, label);
        snprintf(label, sizeof label, "collinear start %d", variant);
        mo_run(a, xy, n, order, label);
        /* The apex first, then the line. */
        order[0] = (uint32_t)k;
        for (size_t i = 0; i < k; i++)
            order[i + 1] = (uint32_t)i;
        snprintf(label, sizeof label, "apex then line %d", variant);
        mo_run(a, xy, n, order, label);
    }
    free(xy);
    free(order);
}

/* Sites exactly on hull edges, and on the lines through hull edges beyond
 * their ends (they must become collinear hull vertices, not flat
 * triangles), inserted in several orders. */
static inline void mo_test_hull_edges(const mo_algorithm *a) {
    double xy[2 * 64];
    size_t n = 0;
#define MO_ADD(x, y) (xy[2 * n] = (x), xy[2 * n + 1] = (y), n++)
    MO_ADD(0, 0); /* a triangle first */
    MO_ADD(8, 0);
    MO_ADD(0, 8);
    MO_ADD(4, 0); /* on its edges */
    MO_ADD(0, 4);
    MO_ADD(4, 4);
    MO_ADD(2, 6);
    MO_ADD(12, 0); /* beyond the ends of hull edges, on their lines */
    MO_ADD(-4, 0);
    MO_ADD(0, 12);
    MO_ADD(0, -4);
    MO_ADD(-2, 10);
    MO_ADD(10, -2);
    MO_ADD(16, 0);
    MO_ADD(6, 0); /* on the edges again, now longer */
    MO_ADD(0, 6);
    MO_ADD(1, 1); /* inside */
    MO_ADD(3, 2);
    MO_ADD(-8, 0); /* a long collinear bottom row */
    MO_ADD(20, 0);
    MO_ADD(24, 0);
    MO_ADD(2, 0);
    MO_ADD(10, 0);
#undef MO_ADD
    uint32_t order[64];
    for (size_t i = 0; i < n; i++)
        order[i] = (uint32_t)i;
    mo_run(a, xy, n, order, "hull edges, given order");
    for (uint64_t seed = 1; seed <= 200; seed++) {
        uint32_t *o = mo_shuffled(n, seed);
        assert_non_null(o);
        char label[64];
        snprintf(label, sizeof label, "hull edges, shuffle seed %llu",
                 (unsigned long long)seed);
        mo_run(a, xy, n, o, label);
        free(o);
    }
    mo_run(a, xy, n, NULL, "hull edges, own order");
}

/* Sites exactly on interior edges: a square split by a diagonal, then
 * points on that diagonal and on the edges the splits create. */
static inline void mo_test_interior_edges(const mo_algorithm *a) {
    double xy[2 * 32];
    size_t n = 0;
#define MO_ADD(x, y) (xy[2 * n] = (x), xy[2 * n + 1] = (y), n++)
    MO_ADD(0, 0);
    MO_ADD(16, 0);
    MO_ADD(16, 16);
    MO_ADD(0, 16);
    MO_ADD(8, 8); /* on the diagonal */
    MO_ADD(4, 4);
    MO_ADD(12, 12);
    MO_ADD(4, 12); /* on the other diagonal */
    MO_ADD(12, 4);
    MO_ADD(8, 4); /* on edges created by the splits */
    MO_ADD(8, 12);
    MO_ADD(2, 2);
    MO_ADD(6, 10);
    MO_ADD(10, 6);
    MO_ADD(8, 0);
    MO_ADD(16, 8);
#undef MO_ADD
    uint32_t order[32];
    for (size_t i = 0; i < n; i++)
        order[i] = (uint32_t)i;
    mo_run(a, xy, n, order, "interior edges, given order");
    for (uint64_t seed = 1; seed <= 200; seed++) {
        uint32_t *o = mo_shuffled(n, seed);
        assert_non_null(o);
        char label[64];
        snprintf(label, sizeof label, "interior edges, shuffle seed %llu",
                 (unsigned long long)seed);
        mo_run(a, xy, n, o, label);
        free(o);
    }
}

/* Degenerate sets in many random insertion orders, so that cocircular,
 * collinear and on-edge insertions happen in every combination: small
 * standard sets, and smaller versions of the big degenerate ones (the
 * oracle needs the exact stages of the predicates on nearly every test
 * there, which costs seconds at 2000 sites; the full sizes run once, in
 * the standard sets). */
static inline void mo_test_shuffled_degenerate(const mo_algorithm *a) {
    static const char *const names[] = {
        "square-centre", "grid-7x7", "int-circle-1105", "equal-y-first",
        "hex-12x12", "unit-circle-200", "rows-10x30",
    };
    const uint64_t seed = 777;
    print_message("  seed %llu\n", (unsigned long long)seed);
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        double *xy = NULL;
        size_t n = 0;
        vt_set set = {0};
        if (!strcmp(names[i], "hex-12x12")) {
            n = 144;
            xy = vt_hex(12, 12);
        } else if (!strcmp(names[i], "unit-circle-200")) {
            n = 200;
            xy = vt_unit_circle(n);
        } else if (!strcmp(names[i], "rows-10x30")) {
            /* 10 rows of 30 random x at equal y. */
            n = 300;
            xy = malloc(2 * n * sizeof *xy);
            vt_rng r = {seed};
            for (size_t k = 0; xy && k < n; k++) {
                xy[2 * k] = vt_unit(&r) * 100.0;
                xy[2 * k + 1] = (double)(k % 10) * 3.0;
            }
        } else {
            assert_int_equal(vt_make_named(names[i], &set), 0);
        }
        vor_sites s;
        assert_int_equal(set.xy ? mo_sites(set.xy, set.n, &s)
                                : (xy ? mo_sites(xy, n, &s) : -1),
                         0);
        for (int k = 0; k < 20; k++) {
            uint32_t *o = mo_shuffled(s.n, seed + (uint64_t)k);
            assert_non_null(o);
            char label[96];
            snprintf(label, sizeof label, "%s, shuffle %d", names[i], k);
            mo_run(a, s.xy, s.n, o, label);
            free(o);
        }
        mo_sites_free(&s);
        vt_set_free(&set);
        free(xy);
    }
}

/* The full path: the mesh, then the diagram built from it, passes
 * vor_check. */
static inline void mo_test_diagram(const mo_algorithm *a) {
    static const char *const names[] = {
        "uniform-1000", "grid-100x100", "int-circle-1105",
        "unit-circle-2000", "duplicates-3000", "scale-1e15",
    };
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        vt_set set;
        assert_int_equal(vt_make_named(names[i], &set), 0);
        vor_sites s;
        assert_int_equal(mo_sites(set.xy, set.n, &s), 0);
        vor_diagram *d = NULL;
        vor_status r = a->diagram(&s, &d);
        if (r != VOR_OK) {
            print_error("%s: %s\n", names[i], vor_status_name(r));
            fail();
        }
        char msg[256] = "";
        if (vor_check(d, &s, msg, sizeof msg)) {
            print_error("%s: vor_check: %s\n", names[i], msg);
            fail();
        }
        vor_diagram_free(d);
        mo_sites_free(&s);
        vt_set_free(&set);
    }
}

/* ---- the test program of one algorithm ---------------------------------
 * Each case receives the algorithm as cmocka's prestate, so the test files
 * of Bowyer-Watson and flipping only name their algorithm. */
#define MO__CASE(name, body)                                                 \
    static inline void name(void **state) { body((const mo_algorithm *)*state); }
MO__CASE(mo_case_standard_sets, mo_test_standard_sets)
MO__CASE(mo_case_collinear_start, mo_test_collinear_start)
MO__CASE(mo_case_sites_on_hull_edges, mo_test_hull_edges)
MO__CASE(mo_case_sites_on_interior_edges, mo_test_interior_edges)
MO__CASE(mo_case_degenerate_sets_shuffled, mo_test_shuffled_degenerate)
MO__CASE(mo_case_diagram_from_mesh, mo_test_diagram)
#undef MO__CASE

static inline int mo_main(const mo_algorithm *a, const char *group) {
    void *st = (void *)(uintptr_t)a;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_prestate(mo_case_standard_sets, st),
        cmocka_unit_test_prestate(mo_case_collinear_start, st),
        cmocka_unit_test_prestate(mo_case_sites_on_hull_edges, st),
        cmocka_unit_test_prestate(mo_case_sites_on_interior_edges, st),
        cmocka_unit_test_prestate(mo_case_degenerate_sets_shuffled, st),
        cmocka_unit_test_prestate(mo_case_diagram_from_mesh, st),
    };
    return _cmocka_run_group_tests(group, tests, sizeof tests / sizeof tests[0],
                                   NULL, NULL);
}

#endif /* VOR_TESTS_MESH_ORACLE_H */
