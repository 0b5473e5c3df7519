/* test_crosscheck.c -- the central oracle: the three algorithms against
 * each other, against vor_check and against brute force.
 *
 * For every standard set of tests/support/testsets.h, for many small
 * random sets (fixed seeds, printed), for every distribution the service
 * generates and every shape of make bench's section 11 (small sizes,
 * fixed seeds), Fortune, Bowyer-Watson
 * and flipping must each return VOR_OK, pass vor_check and return
 * bit-identical diagrams. Every set is run to the end and reported on one line (which
 * algorithm fails or differs, and the first difference); the test fails
 * at the end if any set did.
 *
 * Brute-force oracles, independent of all three algorithms:
 *   - n <= 2000: every vertex's circle has no site strictly inside (exact
 *     vor_incircle against ALL sites) and the sites exactly on it are the
 *     vertex's sites; the vertices' polygons account for exactly the
 *     2n - 2 - h triangles Euler predicts for a triangulation of n sites with
 *     h of them on the hull boundary (h from a separate hull computation),
 *     so no vertex is missing; and the edges number n_vertices + n - 1;
 *   - n <= 30: the whole diagram equals the one vor__diagram_build makes
 *     from the O(n^4) oracle of oracle_voronoi.h.
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
#include "../../api/distribution.h"
#include "../../bench/bench_shapes.h"
#include "../support/testsets.h"
#include "oracle_voronoi.h"

static vor_sites *sites_of(const double *xy, size_t n) {
    vor_sites *s = NULL;
    assert_int_equal(vor_sites_new(xy, n, &s, NULL), VOR_OK);
    assert_non_null(s);
    return s;
}

static void sites_done(vor_sites *s) { vor_sites_free(s); }

/* ---- the first difference between two diagrams ------------------------- */

#define APPEND(...)                                                          \
    do {                                                                     \
        size_t used_ = strlen(buf);                                          \
        if (used_ < size) snprintf(buf + used_, size - used_, __VA_ARGS__);  \
    } while (0)

/* Describes where p and q first differ, array by array in the order of
 * the struct; "" if they are equal. */
static void describe_diff(const vor_diagram *p, const vor_diagram *q, char *buf,
                          size_t size) {
    buf[0] = '\0';
    if (p->n_sites != q->n_sites) {
        APPEND("n_sites %zu vs %zu", p->n_sites, q->n_sites);
        return;
    }
    if (p->n_vertices != q->n_vertices)
        APPEND("n_vertices %zu vs %zu; ", p->n_vertices, q->n_vertices);
    size_t nv = p->n_vertices < q->n_vertices ? p->n_vertices : q->n_vertices;
    for (size_t v = 0; v < nv; v++) {
        const uint32_t *a = p->vertex_sites + 3 * v, *b = q->vertex_sites + 3 * v;
        if (memcmp(a, b, 3 * sizeof *a)) {
            APPEND("vertex %zu: sites (%u,%u,%u) vs (%u,%u,%u)", v, a[0], a[1], a[2],
                   b[0], b[1], b[2]);
            return;
        }
        if (memcmp(p->vertex_xy + 2 * v, q->vertex_xy + 2 * v, 2 * sizeof(double))) {
            APPEND("vertex %zu (%u,%u,%u): xy (%a, %a) vs (%a, %a)", v, a[0], a[1],
                   a[2], p->vertex_xy[2 * v], p->vertex_xy[2 * v + 1],
                   q->vertex_xy[2 * v], q->vertex_xy[2 * v + 1]);
            return;
        }
    }
    if (p->n_vertices != q->n_vertices) {
        const vor_diagram *r = p->n_vertices > q->n_vertices ? p : q;
        APPEND("extra vertex %zu (%u,%u,%u) in the %s", nv, r->vertex_sites[3 * nv],
               r->vertex_sites[3 * nv + 1], r->vertex_sites[3 * nv + 2],
               r == p ? "first" : "second");
        return;
    }
    if (p->n_edges != q->n_edges)
        APPEND("n_edges %zu vs %zu; ", p->n_edges, q->n_edges);
    size_t ne = p->n_edges < q->n_edges ? p->n_edges : q->n_edges;
    for (size_t e = 0; e < ne; e++) {
        const uint32_t *a = p->edge_sites + 2 * e, *b = q->edge_sites + 2 * e;
        const int32_t *x = p->edge_ends + 2 * e, *y = q->edge_ends + 2 * e;
        if (a[0] != b[0] || a[1] != b[1] || x[0] != y[0] || x[1] != y[1]) {
            APPEND("edge %zu: (%u,%u) ends %d %d vs (%u,%u) ends %d %d", e, a[0],
                   a[1], x[0], x[1], b[0], b[1], y[0], y[1]);
            return;
        }
    }
    if (p->n_edges != q->n_edges) {
        const vor_diagram *r = p->n_edges > q->n_edges ? p : q;
        APPEND("extra edge %zu (%u,%u) in the %s", ne, r->edge_sites[2 * ne],
               r->edge_sites[2 * ne + 1], r == p ? "first" : "second");
        return;
    }
    if (p->n_rays != q->n_rays) {
        APPEND("n_rays %zu vs %zu", p->n_rays, q->n_rays);
        return;
    }
    for (size_t r = 0; r < p->n_rays; r++) {
        if (p->ray_edge[r] != q->ray_edge[r]) {
            APPEND("ray %zu: edge %u vs %u", r, p->ray_edge[r], q->ray_edge[r]);
            return;
        }
        if (memcmp(p->ray_dir + 2 * r, q->ray_dir + 2 * r, 2 * sizeof(double))) {
            APPEND("ray %zu (edge %u): dir (%a, %a) vs (%a, %a)", r, p->ray_edge[r],
                   p->ray_dir[2 * r], p->ray_dir[2 * r + 1], q->ray_dir[2 * r],
                   q->ray_dir[2 * r + 1]);
            return;
        }
    }
    for (size_t i = 0; i < p->n_sites; i++) {
        if (p->cell_start[i + 1] != q->cell_start[i + 1]) {
            APPEND("cell %zu: size %u vs %u", i,
                   p->cell_start[i + 1] - p->cell_start[i],
                   q->cell_start[i + 1] - q->cell_start[i]);
            return;
        }
        for (uint32_t t = p->cell_start[i]; t < p->cell_start[i + 1]; t++)
            if (p->cell_edges[t] != q->cell_edges[t]) {
                APPEND("cell %zu: entry %u is edge %u vs %u", i,
                       t - p->cell_start[i], p->cell_edges[t], q->cell_edges[t]);
                return;
            }
        if (p->cell_bounded[i] != q->cell_bounded[i]) {
            APPEND("cell %zu: bounded %d vs %d", i, p->cell_bounded[i],
                   q->cell_bounded[i]);
            return;
        }
    }
}

/* ---- brute-force oracle -------------------------------------------------- */

/* Sites on the boundary of the convex hull (corners and sites on its
 * edges), by Andrew's monotone chain for the corners and a scan of every
 * site against every hull edge. O(n h). */
static size_t hull_boundary_count(const vor_sites *s) {
    const size_t n = s->n;
    const double *xy = s->xy;
    uint32_t *ord = malloc(n * sizeof *ord), *h = malloc(2 * (n + 1) * sizeof *h);
    assert_true(ord && h);
    for (size_t i = 0; i < n; i++) ord[i] = (uint32_t)i;
    /* sort by (x, y): Shell sort, plenty for n <= 2000 */
    for (size_t gap = n / 2; gap > 0; gap /= 2)
        for (size_t i = gap; i < n; i++) {
            uint32_t x = ord[i];
            size_t j = i;
            while (j >= gap) {
                const double *a = xy + 2 * ord[j - gap], *b = xy + 2 * x;
                if (!(a[0] > b[0] || (a[0] == b[0] && a[1] > b[1]))) break;
                ord[j] = ord[j - gap];
                j -= gap;
            }
            ord[j] = x;
        }
    size_t k = 0;
    for (size_t i = 0; i < n; i++) { /* lower hull, strict corners */
        while (k >= 2 && vor_orient2d(xy + 2 * h[k - 2], xy + 2 * h[k - 1],
                                      xy + 2 * ord[i]) <= 0)
            k--;
        h[k++] = ord[i];
    }
    for (size_t i = n - 1, t = k + 1; i-- > 0;) { /* upper hull */
        while (k >= t && vor_orient2d(xy + 2 * h[k - 2], xy + 2 * h[k - 1],
                                      xy + 2 * ord[i]) <= 0)
            k--;
        h[k++] = ord[i];
    }
    size_t corners = k - 1, count = 0;
    for (size_t i = 0; i < n; i++) {
        const double *p = xy + 2 * i;
        int on = 0;
        for (size_t c = 0; c < corners && !on; c++) {
            const double *a = xy + 2 * h[c], *b = xy + 2 * h[c + 1];
            if (vor_orient2d(a, b, p) != 0) continue;
            double lo_x = a[0] < b[0] ? a[0] : b[0], hi_x = a[0] < b[0] ? b[0] : a[0];
            double lo_y = a[1] < b[1] ? a[1] : b[1], hi_y = a[1] < b[1] ? b[1] : a[1];
            on = p[0] >= lo_x && p[0] <= hi_x && p[1] >= lo_y && p[1] <= hi_y;
        }
        count += (size_t)on;
    }
    free(ord);
    free(h);
    return count;
}

/* Empty circles with exactly the right sites, and Euler's counts. Returns
 * 0, or 1 with a reason in msg. */
static int brute_force_check(const vor_diagram *d, const vor_sites *s, char *msg,
                             size_t size) {
    const size_t n = s->n, nv = d->n_vertices;
    const double *xy = s->xy;
    msg[0] = '\0';
    if (nv == 0) return 0; /* collinear: vor_check compares with the line */
    uint32_t *stamp = malloc(n * sizeof *stamp);
    uint32_t *deg = calloc(nv, sizeof *deg);
    assert_true(stamp && deg);
    for (size_t i = 0; i < n; i++) stamp[i] = UINT32_MAX;
    for (size_t k = 0; k < 2 * d->n_edges; k++)
        if (d->edge_ends[k] >= 0) deg[d->edge_ends[k]]++;
    /* edges at each vertex: scan the edges once per vertex would be
     * O(nv ne); instead mark sites through the cells' edges */
    uint32_t *voff = calloc(nv + 1, sizeof *voff), *vsites;
    assert_non_null(voff);
    for (size_t v = 0; v < nv; v++) voff[v + 1] = voff[v] + 2 * deg[v];
    vsites = malloc((voff[nv] ? voff[nv] : 1) * sizeof *vsites);
    assert_non_null(vsites);
    memset(deg, 0, nv * sizeof *deg);
    for (size_t e = 0; e < d->n_edges; e++)
        for (int h = 0; h < 2; h++) {
            int32_t v = d->edge_ends[2 * e + h];
            if (v < 0) continue;
            vsites[voff[v] + deg[v]++] = d->edge_sites[2 * e];
            vsites[voff[v] + deg[v]++] = d->edge_sites[2 * e + 1];
        }
    size_t tri = 0;
    int bad = 0;
    for (size_t v = 0; v < nv && !bad; v++) {
        size_t m = 0;
        for (uint32_t k = voff[v]; k < voff[v + 1]; k++)
            if (stamp[vsites[k]] != v) {
                stamp[vsites[k]] = (uint32_t)v;
                m++;
            }
        const uint32_t *t = d->vertex_sites + 3 * v;
        const double *a = xy + 2 * t[0], *b = xy + 2 * t[1], *c = xy + 2 * t[2];
        if (vor_orient2d(a, b, c) < 0) {
            const double *x = b;
            b = c;
            c = x;
        }
        size_t on = 0;
        for (size_t q = 0; q < n && !bad; q++) {
            int ic = vor_incircle(a, b, c, xy + 2 * q);
            if (ic > 0) {
                snprintf(msg, size, "site %zu lies inside the circle of vertex %zu", q, v);
                bad = 1;
            } else if (ic == 0) {
                on++;
                if (stamp[q] != v) {
                    snprintf(msg, size, "site %zu lies on the circle of vertex %zu "
                             "but is not one of its sites", q, v);
                    bad = 1;
                }
            }
        }
        if (!bad && on != m) {
            snprintf(msg, size, "vertex %zu has %zu sites, %zu on its circle", v, m, on);
            bad = 1;
        }
        tri += m - 2;
    }
    if (!bad) {
        size_t h = hull_boundary_count(s);
        if (tri != 2 * n - 2 - h) {
            snprintf(msg, size, "vertices account for %zu triangles, Euler says "
                     "2n - 2 - h = %zu (h = %zu)", tri, 2 * n - 2 - h, h);
            bad = 1;
        } else if (d->n_edges != nv + n - 1) {
            snprintf(msg, size, "%zu edges, Euler says %zu", d->n_edges, nv + n - 1);
            bad = 1;
        }
    }
    free(stamp);
    free(deg);
    free(voff);
    free(vsites);
    return bad;
}

/* ---- one set through everything ------------------------------------------ */

/* Runs the three algorithms and every oracle on s; prints one line; returns
 * the number of failures. */
static int crosscheck(const char *name, const vor_sites *s, int quiet) {
    vor_diagram *d[VOR_ALGORITHM_COUNT] = {NULL};
    char line[1024] = "", msg[512];
    int failures = 0;
    size_t len;
#define LINE(...)                                                              \
    do {                                                                       \
        len = strlen(line);                                                    \
        if (len < sizeof line) snprintf(line + len, sizeof line - len, __VA_ARGS__); \
    } while (0)
    LINE("%-22s n=%-6zu", name, s->n);
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        vor_status st = vor_compute(s, (vor_algorithm)a, &d[a]);
        const char *an = vor_algorithm_name((vor_algorithm)a);
        if (st != VOR_OK) {
            LINE(" | %s: %s", an, vor_status_name(st));
            failures++;
            continue;
        }
        if (vor_check(d[a], s, msg, sizeof msg) != 0) {
            LINE(" | %s: check: %s", an, msg);
            failures++;
            vor_diagram_free(d[a]);
            d[a] = NULL;
            continue;
        }
    }
    /* brute force on each distinct valid diagram (once when all agree) */
    for (int a = 0; a < VOR_ALGORITHM_COUNT && s->n <= 2000; a++) {
        int seen = 0;
        for (int b = 0; b < a && !seen; b++)
            seen = d[b] && d[a] && vor_diagram_equal(d[a], d[b]);
        if (!d[a] || seen) continue;
        if (brute_force_check(d[a], s, msg, sizeof msg) != 0) {
            LINE(" | %s: brute force: %s", vor_algorithm_name((vor_algorithm)a), msg);
            failures++;
        }
    }
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++)
        for (int b = a + 1; b < VOR_ALGORITHM_COUNT; b++) {
            if (!d[a] || !d[b] || vor_diagram_equal(d[a], d[b])) continue;
            describe_diff(d[a], d[b], msg, sizeof msg);
            LINE(" | %s != %s: %s", vor_algorithm_name((vor_algorithm)a),
                 vor_algorithm_name((vor_algorithm)b), msg);
            failures++;
        }
    /* small: the whole diagram against the O(n^4) oracle */
    if (s->n >= 3 && s->n <= 30 && !vor__all_collinear(s)) {
        bf_voronoi b;
        assert_int_equal(bf_voronoi_make(s, &b), 0);
        uint32_t *edges;
        int32_t *ends;
        assert_int_equal(bf_raw(&b, 0, &edges, &ends), 0);
        vor_diagram *o = NULL;
        assert_int_equal(vor__diagram_build(s, b.nv, edges, ends, b.ne, &o), VOR_OK);
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            if (!d[a] || vor_diagram_equal(d[a], o)) continue;
            describe_diff(d[a], o, msg, sizeof msg);
            LINE(" | %s != oracle: %s", vor_algorithm_name((vor_algorithm)a), msg);
            failures++;
        }
        vor_diagram_free(o);
        bf_free(&b);
    }
    if (failures || !quiet) printf("%s%s\n", line, failures ? "" : " | ok");
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) vor_diagram_free(d[a]);
    return failures;
#undef LINE
}

/* ---- tests --------------------------------------------------------------- */

static void test_standard_sets(void **state) {
    (void)state;
    int failed_sets = 0;
    for (size_t i = 0; i < vt_count(); i++) {
        vt_set set;
        assert_int_equal(vt_make(i, &set), 0);
        vor_sites *s = sites_of(set.xy, set.n);
        if (crosscheck(set.name, s, 0)) failed_sets++;
        sites_done(s);
        vt_set_free(&set);
    }
    if (failed_sets) fail_msg("%d of %zu standard sets failed", failed_sets, vt_count());
}

/* Small random sets of several kinds: uniform, small integer lattices (many
 * cocircular and collinear subsets), rows of equal y, integer circles, a
 * circle with its centre, duplicates, tiny and huge scales, x over a
 * thousand binary orders of magnitude, a turned grid, a hexagonal lattice
 * in doubles. */
static double *random_set(uint64_t seed, size_t *n, const char **kind) {
    vt_rng r = {seed};
    *n = 3 + (size_t)(vt_next(&r) % 48);
    double *xy = malloc(2 * *n * sizeof *xy);
    assert_non_null(xy);
    switch (seed % 10) {
    case 0:
        *kind = "uniform";
        for (size_t i = 0; i < 2 * *n; i++) xy[i] = vt_unit(&r);
        break;
    case 1:
        *kind = "lattice";
        for (size_t i = 0; i < 2 * *n; i++) xy[i] = (double)(vt_next(&r) % 6);
        break;
    case 2:
        *kind = "rows";
        for (size_t i = 0; i < *n; i++) {
            xy[2 * i] = vt_unit(&r);
            xy[2 * i + 1] = (double)(vt_next(&r) % 3);
        }
        break;
    case 3: { /* points of the integer circle of radius 25, some of them */
        *kind = "int-circle";
        size_t m;
        double *c = vt_int_circle(25, 1, &m);
        for (size_t i = 0; i < *n; i++) {
            size_t k = (size_t)(vt_next(&r) % m);
            xy[2 * i] = c[2 * k];
            xy[2 * i + 1] = c[2 * k + 1];
        }
        free(c);
        break;
    }
    case 4:
        *kind = "duplicates";
        for (size_t i = 0; i < *n; i++) {
            size_t k = (size_t)(vt_next(&r) % 5);
            xy[2 * i] = (double)(k * 37 % 11);
            xy[2 * i + 1] = (double)(k * k % 7) + (double)(vt_next(&r) % 2) * 0.5;
        }
        break;
    case 5:
        *kind = "tiny";
        for (size_t i = 0; i < 2 * *n; i++) xy[i] = (double)(vt_next(&r) % 16) * 1e-300;
        break;
    case 7: /* x at many scales, 2^-500 to 2^500, beside y in [0, 1):
             * calls over more bits than the expansions hold */
        *kind = "many-scales";
        for (size_t i = 0; i < *n; i++) {
            xy[2 * i] = ldexp(vt_unit(&r), (int)(vt_next(&r) % 1000) - 500);
            xy[2 * i + 1] = vt_unit(&r);
        }
        break;
    case 8: { /* a grid turned by an angle, in doubles: squares exactly
               * cocircular or off by the rounding */
        *kind = "turned-grid";
        double th = 0.1 + vt_unit(&r), co = cos(th), si = sin(th);
        for (size_t i = 0; i < *n; i++) {
            double u = (double)(vt_next(&r) % 6), v = (double)(vt_next(&r) % 6);
            xy[2 * i] = 40 + u * co - v * si;
            xy[2 * i + 1] = 40 + u * si + v * co;
        }
        break;
    }
    case 9: { /* a hexagonal lattice of a random spacing in doubles, with
               * holes: its cells are translates and mirror images of one
               * another, rounded alike or not (Fortune's event shapes) */
        *kind = "hex-doubles";
        double h = 0.05 + vt_unit(&r) / 4, x0 = vt_unit(&r) * 7;
        size_t w = 9 + (size_t)(vt_next(&r) % 6), k = 0;
        free(xy);
        xy = malloc(2 * w * w * sizeof *xy);
        assert_non_null(xy);
        for (size_t j = 0; j < w; j++)
            for (size_t i = 0; i < w; i++) {
                if (vt_next(&r) % 8 == 0) continue;
                xy[2 * k] = x0 + h * ((double)i + 0.5 * (double)(j % 2));
                xy[2 * k + 1] = h * (double)j * 0.8660254037844386;
                k++;
            }
        *n = k;
        break;
    }
    default:
        *kind = "huge-offset";
        for (size_t i = 0; i < *n; i++) {
            xy[2 * i] = 1e15 + (double)(vt_next(&r) % 8);
            xy[2 * i + 1] = -3e15 + (double)(vt_next(&r) % 8) * 0.5;
        }
        break;
    }
    return xy;
}

static void test_random_small(void **state) {
    (void)state;
    const uint64_t seed0 = 1000, count = 1000;
    printf("random small sets: seeds %llu..%llu (only failures are listed)\n",
           (unsigned long long)seed0, (unsigned long long)(seed0 + count - 1));
    int failed = 0;
    for (uint64_t seed = seed0; seed < seed0 + count; seed++) {
        size_t n;
        const char *kind;
        double *xy = random_set(seed, &n, &kind);
        vor_sites *s = sites_of(xy, n);
        free(xy);
        char name[64];
        snprintf(name, sizeof name, "%s/%llu", kind, (unsigned long long)seed);
        if (crosscheck(name, s, 1)) failed++;
        sites_done(s);
    }
    if (failed) fail_msg("%d of %llu random sets failed", failed, (unsigned long long)count);
}

/* Every distribution of the service (api/distribution.h, the generators
 * behind "generate" and voronoi --generate) at small sizes and two seeds:
 * heavy tails, a far outlier, twelve decades, pixels with duplicates. */
static void test_distributions(void **state) {
    (void)state;
    static const size_t sizes[] = {10, 100, 1000};
    int failed = 0, runs = 0;
    for (int d = 0; d < API_DIST_COUNT; d++) {
        const char *dist = api_dist_name((api_dist)d);
        for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
            for (uint64_t seed = 1; seed <= 2; seed++) {
                if (seed > 1 && !api_dist_seeded((api_dist)d)) continue;
                double *xy = vt_distribution(dist, sizes[k], seed);
                assert_non_null(xy);
                vor_sites *s = sites_of(xy, sizes[k]);
                free(xy);
                char name[64];
                snprintf(name, sizeof name, "%s:%zu:%llu", dist, sizes[k],
                         (unsigned long long)seed);
                if (crosscheck(name, s, 0)) failed++;
                runs++;
                sites_done(s);
            }
        }
    }
    if (failed) fail_msg("%d of %d distribution sets failed", failed, runs);
}

/* Every shape that make bench times against CGAL (bench/bench_shapes.h:
 * rows and columns, lattices rounded or turned, curves, a star, ulp-fine
 * steps, exponents over 2^+-500, a near-line, a line at geometric steps,
 * a line with one site off it, repeated points) at small
 * sizes, each through the brute-force oracle: the bench checks the
 * triangulations at 10^5 sites, here the diagrams must agree bit for bit. */
static void test_shapes(void **state) {
    (void)state;
    static const struct {
        size_t n;
        uint64_t seed;
    } runs[] = {{40, 1}, {400, 1}, {400, 2}, {1500, 1}};
    const size_t count = sizeof bs_shapes / sizeof bs_shapes[0];
    int failed = 0, sets = 0;
    for (size_t i = 0; i < count; i++) {
        for (size_t k = 0; k < sizeof runs / sizeof runs[0]; k++) {
            /* the oracle's exact in-circle tests over a thousand binary
             * orders cost seconds a set past a few hundred sites */
            if (runs[k].n > 400 && !strcmp(bs_shapes[i].name, "mixed-exponents"))
                continue;
            double *xy = bs_shape(bs_shapes[i].name, runs[k].n, runs[k].seed);
            assert_non_null(xy);
            vor_sites *s = sites_of(xy, runs[k].n);
            free(xy);
            char name[64];
            snprintf(name, sizeof name, "%s:%zu:%llu", bs_shapes[i].name,
                     runs[k].n, (unsigned long long)runs[k].seed);
            if (crosscheck(name, s, 0)) failed++;
            sets++;
            sites_done(s);
        }
    }
    if (failed) fail_msg("%d of %d shape sets failed", failed, sets);
}

/* The helper itself: it must find and name a planted difference. */
static void test_describe_diff(void **state) {
    (void)state;
    static const double pts[] = {0, 10, -9, -5, 9, -5, 0, 0, 3, 1};
    vor_sites *s = sites_of(pts, 5);
    bf_voronoi b;
    assert_int_equal(bf_voronoi_make(s, &b), 0);
    uint32_t *edges;
    int32_t *ends;
    vor_diagram *p = NULL, *q = NULL;
    assert_int_equal(bf_raw(&b, 1, &edges, &ends), 0);
    assert_int_equal(vor__diagram_build(s, b.nv, edges, ends, b.ne, &p), VOR_OK);
    assert_int_equal(bf_raw(&b, 2, &edges, &ends), 0);
    assert_int_equal(vor__diagram_build(s, b.nv, edges, ends, b.ne, &q), VOR_OK);
    char msg[256];
    describe_diff(p, q, msg, sizeof msg);
    assert_string_equal(msg, "");
    q->ray_dir[3] = -q->ray_dir[3];
    describe_diff(p, q, msg, sizeof msg);
    assert_non_null(strstr(msg, "ray 1"));
    q->ray_dir[3] = -q->ray_dir[3];
    q->cell_edges[q->cell_start[2]] ^= 1;
    describe_diff(p, q, msg, sizeof msg);
    assert_non_null(strstr(msg, "cell 2: entry 0"));
    q->cell_edges[q->cell_start[2]] ^= 1;
    q->vertex_sites[3] = 99;
    describe_diff(p, q, msg, sizeof msg);
    assert_non_null(strstr(msg, "vertex 1: sites"));
    vor_diagram_free(p);
    vor_diagram_free(q);
    bf_free(&b);
    sites_done(s);
}

int main(void) {
    if (getenv("VOR_TEST_FILTER")) cmocka_set_test_filter(getenv("VOR_TEST_FILTER"));
    if (getenv("VOR_TEST_SKIP")) cmocka_set_skip_filter(getenv("VOR_TEST_SKIP"));
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_describe_diff),
        cmocka_unit_test(test_standard_sets),
        cmocka_unit_test(test_random_small),
        cmocka_unit_test(test_distributions),
        cmocka_unit_test(test_shapes),
    };
    return cmocka_run_group_tests_name("core/crosscheck", tests, NULL, NULL);
}
