/* test_mesh.c -- the shared mesh code: the checker accepts real Delaunay
 * meshes and catches each kind of corruption (a clockwise triangle, a
 * broken twin, a non-Delaunay edge made by flipping a legal one, a
 * non-convex hull, a site left out, a hole); the ghost
 * conflict rule on and around a hull edge; the start refuses degenerate
 * input; Bowyer-Watson and flipping build the identical triangulation of
 * points in general position. */
#include "mesh_oracle.h"

/* A mesh of a standard set by Bowyer-Watson; *s must be freed with
 * mo_sites_free and *m with vor__mesh_clear. */
static void build(const char *name, vor_sites *s, vor__mesh *m) {
    vt_set set;
    assert_int_equal(vt_make_named(name, &set), 0);
    assert_int_equal(mo_sites(set.xy, set.n, s), 0);
    vt_set_free(&set);
    memset(m, 0, sizeof *m);
    assert_int_equal(vor__bowyer_watson_mesh(s, m), VOR_OK);
}

/* The checker must fail, and its message must contain want. */
static void expect_failure(const vor__mesh *m, const vor_sites *s,
                           const char *want) {
    char msg[256] = "";
    assert_int_not_equal(vor__mesh_check(m, s, msg, sizeof msg), 0);
    print_message("  caught: %s\n", msg);
    if (!strstr(msg, want)) {
        print_error("message \"%s\" lacks \"%s\"\n", msg, want);
        fail();
    }
}

static void test_checker_accepts_delaunay_meshes(void **state) {
    (void)state;
    static const char *const names[] = {"square-centre", "uniform-1000",
                                        "grid-7x7", "int-circle-1105"};
    for (size_t i = 0; i < 4; i++) {
        vor_sites s;
        vor__mesh m;
        build(names[i], &s, &m);
        char msg[256] = "";
        if (vor__mesh_check(&m, &s, msg, sizeof msg)) {
            print_error("%s: %s\n", names[i], msg);
            fail();
        }
        vor__mesh_clear(&m);
        mo_sites_free(&s);
    }
}

static void test_checker_catches_clockwise_triangle(void **state) {
    (void)state;
    vor_sites s;
    vor__mesh m;
    build("uniform-1000", &s, &m);
    uint32_t t = 17, v = m.tri[3 * t + 1];
    m.tri[3 * t + 1] = m.tri[3 * t + 2];
    m.tri[3 * t + 2] = v;
    expect_failure(&m, &s, "triangle 17 ");
    expect_failure(&m, &s, "not counter-clockwise");
    vor__mesh_clear(&m);
    mo_sites_free(&s);
}

static void test_checker_catches_broken_twin(void **state) {
    (void)state;
    vor_sites s;
    vor__mesh m;
    build("uniform-1000", &s, &m);
    /* An interior edge loses its twin. */
    size_t e = 0;
    while (m.adj[e] < 0)
        e++;
    int32_t f = m.adj[e];
    m.adj[e] = -1;
    expect_failure(&m, &s, "twin");
    /* Two interior half-edges exchange twins. */
    m.adj[e] = f;
    size_t g = e + 1;
    while (m.adj[g] < 0 || (size_t)m.adj[g] == e)
        g++;
    int32_t h = m.adj[g];
    m.adj[e] = h;
    m.adj[g] = f;
    expect_failure(&m, &s, "twin");
    vor__mesh_clear(&m);
    mo_sites_free(&s);
}

/* Flips the edge e = a->b of T = (a, b, c) with f = b->a of U = (b, a, d)
 * into T = (a, d, c), U = (d, b, c), if the quadrilateral is strictly
 * convex; returns 0 if it is not (nothing changed).
 *
 *          c                  c
 *        /   \              / | \
 *       a --- b     =>     a  |  b
 *        \   /              \ | /
 *          d                  d
 */
static int flip_edge(vor__mesh *m, const vor_sites *s, uint32_t e) {
    uint32_t *tri = m->tri;
    int32_t *adj = m->adj;
    uint32_t f = (uint32_t)adj[e];
    uint32_t ne = vor__next(e), pe = vor__prev(e);
    uint32_t nf = vor__next(f), pf = vor__prev(f);
    uint32_t a = tri[e], b = tri[ne], c = tri[pe], d = tri[pf];
    const double *xy = s->xy;
    if (vor_orient2d(xy + 2 * a, xy + 2 * d, xy + 2 * c) <= 0 ||
        vor_orient2d(xy + 2 * d, xy + 2 * b, xy + 2 * c) <= 0)
        return 0;
    int32_t ad = adj[nf], db = adj[pf], bc = adj[ne];
    /* T: e = a->d, ne = d->c, pe = c->a (unchanged).
     * U: f = d->b, nf = b->c, pf = c->d. */
    tri[ne] = d;
    tri[f] = d;
    tri[nf] = b;
    tri[pf] = c;
    adj[e] = ad;
    if (ad >= 0)
        adj[ad] = (int32_t)e;
    adj[f] = db;
    if (db >= 0)
        adj[db] = (int32_t)f;
    adj[nf] = bc;
    if (bc >= 0)
        adj[bc] = (int32_t)nf;
    adj[ne] = (int32_t)pf;
    adj[pf] = (int32_t)ne;
    return 1;
}

static void test_checker_catches_non_delaunay_edge(void **state) {
    (void)state;
    vor_sites s;
    vor__mesh m;
    build("uniform-1000", &s, &m);
    size_t e = 0;
    while (m.adj[e] < 0 || !flip_edge(&m, &s, (uint32_t)e))
        e++;
    /* Still a valid triangulation, only not Delaunay. */
    expect_failure(&m, &s, "not locally Delaunay");
    /* Flipping the new diagonal, d->c at next(e), repairs it. */
    assert_true(flip_edge(&m, &s, vor__next((uint32_t)e)));
    char msg[256] = "";
    assert_int_equal(vor__mesh_check(&m, &s, msg, sizeof msg), 0);
    vor__mesh_clear(&m);
    mo_sites_free(&s);
}

/* Removes triangle t: its neighbours see a hull edge, the last triangle
 * moves into its slot. */
static void remove_triangle(vor__mesh *m, uint32_t t) {
    for (uint32_t k = 0; k < 3; k++)
        if (m->adj[3 * t + k] >= 0)
            m->adj[m->adj[3 * t + k]] = -1;
    uint32_t last = (uint32_t)m->n_tri - 1;
    if (t != last) {
        for (uint32_t k = 0; k < 3; k++) {
            m->tri[3 * t + k] = m->tri[3 * last + k];
            m->adj[3 * t + k] = m->adj[3 * last + k];
            if (m->adj[3 * t + k] >= 0)
                m->adj[m->adj[3 * t + k]] = (int32_t)(3 * t + k);
        }
    }
    m->n_tri--;
}

static void test_checker_catches_non_convex_hull(void **state) {
    (void)state;
    /* A square and a site just above the middle of its bottom edge: the
     * triangle below that site leaves a notch. */
    static const double xy[] = {0, 0, 4, 0, 4, 4, 0, 4, 2, 1};
    vor_sites s;
    assert_int_equal(mo_sites(xy, 5, &s), 0);
    vor__mesh m = {0};
    assert_int_equal(vor__flip_mesh(&s, &m), VOR_OK);
    assert_int_equal(m.n_tri, 4);
    uint32_t t = 0;
    while (!((m.tri[3 * t] == 0 || m.tri[3 * t + 1] == 0 ||
              m.tri[3 * t + 2] == 0) &&
             (m.tri[3 * t] == 1 || m.tri[3 * t + 1] == 1 ||
              m.tri[3 * t + 2] == 1)))
        t++;
    remove_triangle(&m, t);
    expect_failure(&m, &s, "hull is not convex at vertex 4");
    vor__mesh_clear(&m);
    mo_sites_free(&s);
}

static void test_checker_catches_missing_site(void **state) {
    (void)state;
    vt_set set;
    assert_int_equal(vt_make_named("uniform-1000", &set), 0);
    vor_sites s;
    assert_int_equal(mo_sites(set.xy, set.n, &s), 0);
    vt_set_free(&set);
    /* The mesh of all sites but the last, checked against all sites. */
    s.n--;
    vor__mesh m = {0};
    assert_int_equal(vor__bowyer_watson_mesh(&s, &m), VOR_OK);
    s.n++;
    expect_failure(&m, &s, "site 999 is not a vertex");
    vor__mesh_clear(&m);
    mo_sites_free(&s);
}

static void test_checker_catches_hole(void **state) {
    (void)state;
    /* A triangle removed from the middle of a grid: the surface gets a
     * hole, whose boundary is a second, clockwise, cycle of hull edges. */
    vor_sites s;
    vor__mesh m;
    build("grid-7x7", &s, &m);
    uint32_t t = 0;
    for (;; t++) { /* a triangle with no vertex on the hull */
        int inner = 1;
        for (int k = 0; k < 3; k++) {
            const double *p = s.xy + 2 * (size_t)m.tri[3 * t + k];
            inner &= p[0] > 0 && p[0] < 6 && p[1] > 0 && p[1] < 6;
        }
        if (inner)
            break;
    }
    remove_triangle(&m, t);
    expect_failure(&m, &s, "hull");
    vor__mesh_clear(&m);
    mo_sites_free(&s);
}

static void test_ghost_conflict_rule(void **state) {
    (void)state;
    /* Ghost of the hull edge a->b: outside is to the left of a->b. */
    static const double a[2] = {0, 0}, b[2] = {4, 0};
    static const double left[2] = {1, 1}, right[2] = {1, -1};
    static const double mid[2] = {2, 0}, beyond[2] = {6, 0};
    static const double before[2] = {-1, 0};
    assert_int_equal(vor__ghost_conflict(a, b, left), 1);
    assert_int_equal(vor__ghost_conflict(a, b, right), 0);
    assert_int_equal(vor__ghost_conflict(a, b, mid), 1);
    assert_int_equal(vor__ghost_conflict(b, a, mid), 1);
    assert_int_equal(vor__ghost_conflict(a, b, beyond), 0);
    assert_int_equal(vor__ghost_conflict(a, b, before), 0);
    assert_int_equal(vor__ghost_conflict(a, b, a), 0);
    assert_int_equal(vor__ghost_conflict(a, b, b), 0);
    /* Vertical edge: the comparison falls to y. */
    static const double c[2] = {3, 5}, d[2] = {3, -5};
    static const double on[2] = {3, 0}, off[2] = {3, 7}, east[2] = {4, 0};
    assert_int_equal(vor__ghost_conflict(c, d, on), 1);
    assert_int_equal(vor__ghost_conflict(c, d, off), 0);
    assert_int_equal(vor__ghost_conflict(c, d, east), 1);
    assert_int_equal(vor__ghost_conflict(d, c, east), 0);
}

static void test_start_refuses_degenerate_input(void **state) {
    (void)state;
    static const double line[] = {0, 0, 1, 1, 2, 2, 3, 3, -5, -5};
    vor_sites s;
    assert_int_equal(mo_sites(line, 5, &s), 0);
    vor__mesh m = {0};
    assert_int_equal(vor__bowyer_watson_mesh(&s, &m), VOR_EINVAL);
    assert_null(m.tri);
    assert_int_equal(vor__flip_mesh(&s, &m), VOR_EINVAL);
    assert_null(m.tri);
    s.n = 2;
    assert_int_equal(vor__bowyer_watson_mesh(&s, &m), VOR_EINVAL);
    assert_int_equal(vor__flip_mesh(&s, &m), VOR_EINVAL);
    assert_int_equal(m.n_tri, 0);
    mo_sites_free(&s);
    vor__mesh_clear(NULL); /* a no-op */
}

/* Points in general position have one Delaunay triangulation: both
 * algorithms must produce it, triangle for triangle. */
static void test_algorithms_agree(void **state) {
    (void)state;
    static const char *const names[] = {"uniform-20000", "gaussian-2000",
                                        "clusters-3000", "scale-1e-300"};
    for (size_t i = 0; i < 4; i++) {
        vor_sites s;
        vor__mesh m;
        build(names[i], &s, &m);
        vor__mesh m2 = {0};
        assert_int_equal(vor__flip_mesh(&s, &m2), VOR_OK);
        assert_int_equal(m.n_tri, m2.n_tri);
        uint32_t *c1 = mo_canonical(&m), *c2 = mo_canonical(&m2);
        assert_non_null(c1);
        assert_non_null(c2);
        assert_memory_equal(c1, c2, 3 * m.n_tri * sizeof *c1);
        free(c1);
        free(c2);
        vor__mesh_clear(&m);
        vor__mesh_clear(&m2);
        mo_sites_free(&s);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_checker_accepts_delaunay_meshes),
        cmocka_unit_test(test_checker_catches_clockwise_triangle),
        cmocka_unit_test(test_checker_catches_broken_twin),
        cmocka_unit_test(test_checker_catches_non_delaunay_edge),
        cmocka_unit_test(test_checker_catches_non_convex_hull),
        cmocka_unit_test(test_checker_catches_missing_site),
        cmocka_unit_test(test_checker_catches_hole),
        cmocka_unit_test(test_ghost_conflict_rule),
        cmocka_unit_test(test_start_refuses_degenerate_input),
        cmocka_unit_test(test_algorithms_agree),
    };
    return cmocka_run_group_tests_name("core/mesh", tests, NULL, NULL);
}
