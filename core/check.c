/* check.c -- vor_check: verifies a Voronoi diagram against its sites,
 * independently of how it was built.
 *
 * What is checked, in this order (the first failure is reported, naming the
 * offending vertex, edge, cell or site):
 *   1. shapes: counts, arrays present, cell_start a partition of 2 * n_edges;
 *   2. vertices: three increasing sites, strictly increasing (s0, s1, s2)
 *      order, coordinates bit-identical to vor_circumcenter(s0, s1, s2);
 *   3. edges: a < b, strictly increasing (a, b) order, ends of the three
 *      allowed forms (segment with end0 < end1, ray vertex-first, line);
 *      rays: ray_edge lists exactly the unbounded edges in order;
 *   4. cells: each edge appears once in the cell of each of its two sites;
 *      consecutive edges share exactly one vertex and chain (closed for a
 *      bounded cell, from infinity to infinity for an unbounded one); the
 *      neighbour sites turn left exactly (vor_orient2d > 0); a bounded cell
 *      starts at its smallest edge; cell_bounded agrees;
 *   5. each vertex: its sites (from its edges, put in order by the dual
 *      triangles) are exactly cocircular (vor_incircle == 0) and form a
 *      strictly convex counter-clockwise polygon whose sides are exactly the
 *      vertex's edges, and its three smallest sites are vertex_sites;
 *   6. the dual triangulation (from the cells, as vor_diagram_triangles
 *      derives it where a vertex has more than three sites): counter-clockwise
 *      triangles, every interior edge shared by exactly two of them in
 *      opposite directions, every site used, Euler's relation, boundary one
 *      closed convex counter-clockwise cycle winding once (the convex hull),
 *      every interior edge locally Delaunay (exact vor_incircle <= 0, and
 *      < 0 between different vertices, else they should have been merged).
 *      A triangulation that is locally Delaunay everywhere is Delaunay, so
 *      every vertex's circle is empty: no O(n^2) test against all sites;
 *   7. duality: every interior edge between two vertices is the segment
 *      joining them, every hull edge the ray from its triangle's vertex,
 *      pointing outwards (bit-identical to vor_bisector_dir(q, p) for the
 *      counter-clockwise hull edge p->q, and a float dot product with the
 *      outward normal as a second opinion), and there are no other edges;
 *      a cell is bounded exactly when its site is not on the hull; Euler's
 *      relation for the diagram with one vertex at infinity.
 * Diagrams without vertices (n < 3 or collinear sites) are checked against
 * the order of the sites along their line.
 *
 * Cost: O(n) for sites that are each on a bounded number of edges (O(log n)
 * per lookup at worst); scratch about 90 bytes per site. Never prints; allocation failure is reported as a
 * failure ("out of memory").
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "predicates.h"

#define NONE32 UINT32_MAX

typedef struct ctx {
    const vor_diagram *d;
    const double *xy;
    size_t n, nv, ne, nr;
    char *msg;
    size_t msg_size;
} ctx;

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static int fail(ctx *c, const char *fmt, ...) {
    if (c->msg && c->msg_size) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(c->msg, c->msg_size, fmt, ap);
        va_end(ap);
    }
    return 1;
}

static const double *P(const ctx *c, uint32_t i) { return c->xy + 2 * (size_t)i; }

static void *alloc(size_t count, size_t size) {
    return malloc((count ? count : 1) * size);
}

/* The other site of edge e, seen from site i. */
static uint32_t other_site(const vor_diagram *d, uint32_t e, uint32_t i) {
    return d->edge_sites[2 * (size_t)e] == i ? d->edge_sites[2 * (size_t)e + 1]
                                             : d->edge_sites[2 * (size_t)e];
}

/* Index of edge (a, b), a < b; -1 if absent. by_a[a] .. by_a[a + 1] is the
 * range of edges whose first site is a (edges are in (a, b) order, checked
 * before this is used): searched linearly when short, else by bisection. */
static long find_edge(const vor_diagram *d, const uint32_t *by_a, uint32_t a,
                      uint32_t b) {
    size_t lo = by_a[a], hi = by_a[a + 1];
    if (hi - lo <= 8) {
        for (size_t e = lo; e < hi; e++)
            if (d->edge_sites[2 * e + 1] == b) return (long)e;
        return -1;
    }
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (d->edge_sites[2 * mid + 1] < b) lo = mid + 1;
        else hi = mid;
    }
    return lo < by_a[a + 1] && d->edge_sites[2 * lo + 1] == b ? (long)lo : -1;
}

/* (x, y) lexicographic order: along a line, the order of the points. */
static int lex_less(const double *p, const double *q) {
    return p[0] < q[0] || (p[0] == q[0] && p[1] < q[1]);
}

/* ---- 1-3: shapes, vertices, edges, rays ---------------------------------- */

static int check_shapes(ctx *c) {
    const vor_diagram *d = c->d;
    if (c->nv > 0x7fffffffu || c->ne > 0x3fffffffu || c->nr > c->ne)
        return fail(c, "counts out of range (%zu vertices, %zu edges, %zu rays)",
                    c->nv, c->ne, c->nr);
    if (!d->cell_start) return fail(c, "cell_start is NULL");
    if ((c->n && !d->cell_bounded) ||
        (c->nv && (!d->vertex_xy || !d->vertex_sites)) ||
        (c->ne && (!d->edge_sites || !d->edge_ends || !d->cell_edges)) ||
        (c->nr && (!d->ray_edge || !d->ray_dir)))
        return fail(c, "an array with entries is NULL");
    if (d->cell_start[0] != 0) return fail(c, "cell 0 does not start at 0");
    for (size_t i = 0; i < c->n; i++)
        if (d->cell_start[i + 1] < d->cell_start[i])
            return fail(c, "cell %zu: cell_start decreases", i);
    if (d->cell_start[c->n] != 2 * c->ne)
        return fail(c, "cells hold %u edge entries, expected 2 * %zu",
                    (unsigned)d->cell_start[c->n], c->ne);
    return 0;
}

static int check_vertices(ctx *c) {
    const vor_diagram *d = c->d;
    for (size_t v = 0; v < c->nv; v++) {
        const uint32_t *t = d->vertex_sites + 3 * v;
        if (!(t[0] < t[1] && t[1] < t[2] && t[2] < c->n))
            return fail(c, "vertex %zu: sites %u %u %u not increasing or out of range",
                        v, (unsigned)t[0], (unsigned)t[1], (unsigned)t[2]);
        if (v > 0) {
            const uint32_t *p = t - 3;
            if (!(p[0] < t[0] ||
                  (p[0] == t[0] && (p[1] < t[1] || (p[1] == t[1] && p[2] < t[2])))))
                return fail(c, "vertex %zu: not after vertex %zu in (s0, s1, s2) order",
                            v, v - 1);
        }
        if (vor__orient2d_fast(P(c, t[0]), P(c, t[1]), P(c, t[2])) == 0)
            return fail(c, "vertex %zu: sites %u %u %u are collinear", v,
                        (unsigned)t[0], (unsigned)t[1], (unsigned)t[2]);
        double cc[2];
        vor_circumcenter(P(c, t[0]), P(c, t[1]), P(c, t[2]), cc);
        if (memcmp(cc, d->vertex_xy + 2 * v, sizeof cc) != 0)
            return fail(c, "vertex %zu: coordinates (%.17g, %.17g) are not "
                        "vor_circumcenter of its sites (%.17g, %.17g)", v,
                        d->vertex_xy[2 * v], d->vertex_xy[2 * v + 1], cc[0], cc[1]);
    }
    return 0;
}

static int check_edges(ctx *c) {
    const vor_diagram *d = c->d;
    size_t r = 0;
    for (size_t e = 0; e < c->ne; e++) {
        const uint32_t *ab = d->edge_sites + 2 * e;
        const int32_t *en = d->edge_ends + 2 * e;
        if (!(ab[0] < ab[1] && ab[1] < c->n))
            return fail(c, "edge %zu: sites %u %u not increasing or out of range",
                        e, (unsigned)ab[0], (unsigned)ab[1]);
        if (e > 0 && !(ab[-2] < ab[0] || (ab[-2] == ab[0] && ab[-1] < ab[1])))
            return fail(c, "edge %zu (%u,%u): not after edge %zu (%u,%u)", e,
                        (unsigned)ab[0], (unsigned)ab[1], e - 1,
                        (unsigned)ab[-2], (unsigned)ab[-1]);
        int seg = en[0] >= 0 && en[1] >= 0 && en[0] < en[1] && (size_t)en[1] < c->nv;
        int ray = en[0] >= 0 && (size_t)en[0] < c->nv && en[1] == VOR_NONE;
        int line = en[0] == VOR_NONE && en[1] == VOR_NONE;
        if (!seg && !ray && !line)
            return fail(c, "edge %zu (%u,%u): ends %d %d are not a segment "
                        "(end0 < end1), a ray (vertex first) or a line", e,
                        (unsigned)ab[0], (unsigned)ab[1], (int)en[0], (int)en[1]);
        if (line && c->nv > 0)
            return fail(c, "edge %zu (%u,%u): a line in a diagram with vertices",
                        e, (unsigned)ab[0], (unsigned)ab[1]);
        if (en[1] == VOR_NONE) {
            if (r >= c->nr || d->ray_edge[r] != e)
                return fail(c, "edge %zu (%u,%u): unbounded but not ray %zu", e,
                            (unsigned)ab[0], (unsigned)ab[1], r);
            double dir = d->ray_dir[2 * r] * d->ray_dir[2 * r] +
                         d->ray_dir[2 * r + 1] * d->ray_dir[2 * r + 1];
            if (!(fabs(dir - 1.0) < 1e-12))
                return fail(c, "ray %zu (edge %zu): direction is not a unit vector",
                            r, e);
            if (line) {
                double want[2];
                vor_bisector_dir(P(c, ab[0]), P(c, ab[1]), want);
                if (memcmp(want, d->ray_dir + 2 * r, sizeof want) != 0)
                    return fail(c, "ray %zu (line %zu): direction is not "
                                "vor_bisector_dir(a, b)", r, e);
            }
            r++;
        }
    }
    if (r != c->nr)
        return fail(c, "%zu rays listed, %zu unbounded edges", c->nr, r);
    return 0;
}

/* ---- 4: cells ------------------------------------------------------------ */

/* The vertex edges e and f share; -1 if none, -2 if they share both ends. */
static int32_t shared_vertex(const vor_diagram *d, uint32_t e, uint32_t f) {
    const int32_t *p = d->edge_ends + 2 * (size_t)e, *q = d->edge_ends + 2 * (size_t)f;
    int32_t s = -1;
    int k = 0;
    for (int i = 0; i < 2; i++)
        if (p[i] >= 0 && (p[i] == q[0] || p[i] == q[1])) {
            s = p[i];
            k++;
        }
    return k > 1 ? -2 : s;
}

static int check_cells(ctx *c, uint8_t *seen) {
    const vor_diagram *d = c->d;
    memset(seen, 0, c->ne ? c->ne : 1);
    for (uint32_t i = 0; i < c->n; i++) {
        const uint32_t *L = d->cell_edges + d->cell_start[i];
        size_t k = d->cell_start[i + 1] - d->cell_start[i], rays = 0;
        for (size_t t = 0; t < k; t++) {
            uint32_t e = L[t];
            if (e >= c->ne) return fail(c, "cell %u: entry %zu is edge %u, out of range",
                                        (unsigned)i, t, (unsigned)e);
            uint8_t side = d->edge_sites[2 * (size_t)e] == i ? 1
                         : d->edge_sites[2 * (size_t)e + 1] == i ? 2 : 0;
            if (!side)
                return fail(c, "cell %u: edge %u (%u,%u) does not bound it",
                            (unsigned)i, (unsigned)e,
                            (unsigned)d->edge_sites[2 * (size_t)e],
                            (unsigned)d->edge_sites[2 * (size_t)e + 1]);
            if (seen[e] & side)
                return fail(c, "cell %u: edge %u listed twice", (unsigned)i, (unsigned)e);
            seen[e] |= side;
            if (d->edge_ends[2 * (size_t)e + 1] < 0) rays++;
        }
        int bounded = rays == 0 && k > 0;
        if (d->cell_bounded[i] != bounded)
            return fail(c, "cell %u: cell_bounded is %d, its edges say %d",
                        (unsigned)i, d->cell_bounded[i], bounded);
        if (c->nv == 0) { /* lines: checked with the line order */
            for (size_t t = 1; t < k; t++)
                if (L[t - 1] >= L[t])
                    return fail(c, "cell %u: parallel lines not in edge order",
                                (unsigned)i);
            continue;
        }
        if (k < 2)
            return fail(c, "cell %u: %zu edge(s), a cell has at least two", (unsigned)i, k);
        if (bounded) {
            if (k < 3) return fail(c, "cell %u: bounded with %zu edges", (unsigned)i, k);
            for (size_t t = 1; t < k; t++)
                if (L[t] < L[0])
                    return fail(c, "cell %u: bounded but does not start at its "
                                "smallest edge %u", (unsigned)i, (unsigned)L[t]);
        } else if (rays != 2 || d->edge_ends[2 * (size_t)L[0] + 1] >= 0 ||
                   d->edge_ends[2 * (size_t)L[k - 1] + 1] >= 0) {
            return fail(c, "cell %u: unbounded, but its first and last edges are "
                        "not its two rays", (unsigned)i);
        }
        /* chain: c_t is the vertex between L[t] and L[t+1]; each segment
         * L[t] must run from c_{t-1} to c_t */
        size_t steps = bounded ? k : k - 1;
        int32_t first = -1, prev = -1;
        for (size_t t = 0; t < steps; t++) {
            uint32_t e = L[t], f = L[(t + 1) % k];
            int32_t v = shared_vertex(d, e, f);
            if (v < 0)
                return fail(c, "cell %u: edges %u and %u %s", (unsigned)i,
                            (unsigned)e, (unsigned)f,
                            v == -1 ? "share no vertex" : "share both ends");
            if (t == 0) first = v;
            else {
                const int32_t *en = d->edge_ends + 2 * (size_t)e;
                if (!((en[0] == prev && en[1] == v) || (en[0] == v && en[1] == prev)))
                    return fail(c, "cell %u: edge %u does not join vertices %d and %d",
                                (unsigned)i, (unsigned)e, (int)prev, (int)v);
            }
            prev = v;
            int o = vor__orient2d_fast(P(c, i), P(c, other_site(d, e, i)),
                                 P(c, other_site(d, f, i)));
            if (o <= 0)
                return fail(c, "cell %u: neighbours %u, %u do not turn left "
                            "(not counter-clockwise)", (unsigned)i,
                            (unsigned)other_site(d, e, i), (unsigned)other_site(d, f, i));
        }
        if (bounded) {
            const int32_t *en = d->edge_ends + 2 * (size_t)L[0];
            if (!((en[0] == prev && en[1] == first) || (en[0] == first && en[1] == prev)))
                return fail(c, "cell %u: chain does not close at edge %u",
                            (unsigned)i, (unsigned)L[0]);
        }
    }
    for (size_t e = 0; e < c->ne; e++)
        if (seen[e] != 3)
            return fail(c, "edge %zu (%u,%u): missing from the cell of site %u", e,
                        (unsigned)d->edge_sites[2 * e], (unsigned)d->edge_sites[2 * e + 1],
                        (unsigned)d->edge_sites[2 * e + (seen[e] & 1 ? 1 : 0)]);
    return 0;
}

/* ---- degenerate diagrams ------------------------------------------------- */

static void merge_sort_lex(const double *xy, uint32_t *a, uint32_t *tmp, size_t n) {
    for (size_t w = 1; w < n; w *= 2) {
        for (size_t lo = 0; lo < n; lo += 2 * w) {
            size_t mid = lo + w < n ? lo + w : n, hi = lo + 2 * w < n ? lo + 2 * w : n;
            size_t i = lo, j = mid, k = lo;
            while (i < mid && j < hi)
                tmp[k++] = lex_less(xy + 2 * (size_t)a[j], xy + 2 * (size_t)a[i]) ? a[j++]
                                                                               : a[i++];
            while (i < mid) tmp[k++] = a[i++];
            while (j < hi) tmp[k++] = a[j++];
        }
        memcpy(a, tmp, n * sizeof *a);
    }
}

/* No vertices: n < 3 or all sites collinear, n - 1 lines between sites
 * consecutive along the line. */
static int check_lines(ctx *c) {
    const vor_diagram *d = c->d;
    if (c->n >= 3)
        for (size_t k = 2; k < c->n; k++)
            if (vor__orient2d_fast(P(c, 0), P(c, 1), P(c, (uint32_t)k)) != 0)
                return fail(c, "no vertices, but sites 0, 1, %zu are not collinear", k);
    size_t want = c->n > 1 ? c->n - 1 : 0;
    if (c->ne != want)
        return fail(c, "%zu collinear sites need %zu lines, found %zu edges", c->n,
                    want, c->ne);
    if (c->n < 2) {
        if (c->n == 1 && d->cell_bounded[0])
            return fail(c, "cell 0: the only site's cell is bounded");
        return 0;
    }
    uint32_t *ord = alloc(c->n, sizeof *ord), *tmp = alloc(c->n, sizeof *tmp);
    if (!ord || !tmp) {
        free(ord);
        free(tmp);
        return fail(c, "out of memory");
    }
    for (size_t i = 0; i < c->n; i++) ord[i] = (uint32_t)i;
    merge_sort_lex(c->xy, ord, tmp, c->n);
    for (size_t k = 0; k < c->n; k++) tmp[ord[k]] = (uint32_t)k; /* rank */
    int bad = 0;
    for (size_t e = 0; e < c->ne && !bad; e++) {
        uint32_t a = d->edge_sites[2 * e], b = d->edge_sites[2 * e + 1];
        uint32_t ra = tmp[a], rb = tmp[b];
        if (ra + 1 != rb && rb + 1 != ra)
            bad = fail(c, "edge %zu (%u,%u): sites are not neighbours along the line",
                       e, (unsigned)a, (unsigned)b);
    }
    free(ord);
    free(tmp);
    return bad;
}

/* ---- 5-7: vertices, dual triangulation, duality -------------------------- */

typedef struct dual {
    uint32_t *tri;     /* 3 * nt */
    size_t nt;
    uint32_t *tvert;   /* nt: the vertex each triangle comes from */
    uint32_t *voff;    /* nv + 1: edges at each vertex (CSR) */
    uint32_t *vedge;
    uint32_t *pos;     /* n: position of a site in the current vertex */
    uint32_t *stamp;   /* n */
    uint32_t *he;      /* 3 * nt half-edges, sorted by (min, max) site */
    uint32_t *he_tmp;
    uint32_t *count;   /* n + 1 */
    uint32_t *hull_next; /* n: boundary successor of a hull site */
    uint32_t *by_a;    /* n + 1: first edge whose first site is a */
} dual;

static void dual_free(dual *D) {
    free(D->tri);
    free(D->tvert);
    free(D->voff);
    free(D->vedge);
    free(D->pos);
    free(D->stamp);
    free(D->he);
    free(D->he_tmp);
    free(D->count);
    free(D->hull_next);
    free(D->by_a);
}

static uint32_t he_from(const dual *D, uint32_t h) { return D->tri[h]; }
static uint32_t he_to(const dual *D, uint32_t h) {
    return D->tri[h % 3 == 2 ? h - 2 : h + 1];
}
static uint32_t he_apex(const dual *D, uint32_t h) {
    return D->tri[h % 3 == 0 ? h + 2 : h - 1];
}
static uint32_t he_min(const dual *D, uint32_t h) {
    uint32_t a = he_from(D, h), b = he_to(D, h);
    return a < b ? a : b;
}
static uint32_t he_max(const dual *D, uint32_t h) {
    uint32_t a = he_from(D, h), b = he_to(D, h);
    return a < b ? b : a;
}

/* 5: each vertex's sites, in the order the fan gives them. */
static int check_vertex_sites(ctx *c, dual *D) {
    const vor_diagram *d = c->d;
    size_t t = 0;
    for (uint32_t i = 0; i < c->n; i++) D->stamp[i] = NONE32;
    for (uint32_t v = 0; v < c->nv; v++) {
        size_t m = D->voff[v + 1] - D->voff[v];
        if (m < 3) return fail(c, "vertex %u: %zu edges, at least 3 needed",
                               (unsigned)v, m);
        if (t + m - 2 > D->nt)
            return fail(c, "vertex %u: dual triangles missing", (unsigned)v);
        /* sites c_0 .. c_{m-1}: tri[3t], tri[3t+1], then each fan apex */
        uint32_t c0 = D->tri[3 * t], c1 = D->tri[3 * t + 1];
        uint32_t t3[3] = {NONE32, NONE32, NONE32};
        for (size_t q = 0; q < m; q++) {
            uint32_t s = q == 0 ? c0 : q == 1 ? c1 : D->tri[3 * (t + q - 2) + 2];
            if (q >= 2 && (D->tri[3 * (t + q - 2)] != c0 ||
                           (q >= 3 && D->tri[3 * (t + q - 2) + 1] !=
                                          D->tri[3 * (t + q - 3) + 2])))
                return fail(c, "vertex %u: dual triangles are not a fan", (unsigned)v);
            if (D->stamp[s] == v)
                return fail(c, "vertex %u: site %u appears twice", (unsigned)v,
                            (unsigned)s);
            D->stamp[s] = v;
            D->pos[s] = (uint32_t)q;
            if (s < t3[0]) { t3[2] = t3[1]; t3[1] = t3[0]; t3[0] = s; }
            else if (s < t3[1]) { t3[2] = t3[1]; t3[1] = s; }
            else if (s < t3[2]) t3[2] = s;
            if (q >= 2) D->tvert[t + q - 2] = v;
        }
        if (memcmp(t3, d->vertex_sites + 3 * (size_t)v, sizeof t3) != 0)
            return fail(c, "vertex %u: its three smallest sites are %u %u %u, "
                        "vertex_sites says %u %u %u", (unsigned)v, (unsigned)t3[0],
                        (unsigned)t3[1], (unsigned)t3[2],
                        (unsigned)d->vertex_sites[3 * v],
                        (unsigned)d->vertex_sites[3 * v + 1],
                        (unsigned)d->vertex_sites[3 * v + 2]);
        /* every edge at v joins two sites adjacent on the polygon; m edges
         * and m sides, pairs unique: the sides are exactly the edges */
        for (size_t k = D->voff[v]; k < D->voff[v + 1]; k++) {
            uint32_t e = D->vedge[k];
            uint32_t a = d->edge_sites[2 * (size_t)e], b = d->edge_sites[2 * (size_t)e + 1];
            if (D->stamp[a] != v || D->stamp[b] != v)
                return fail(c, "vertex %u: edge %u (%u,%u) ends there but its "
                            "sites are not the vertex's", (unsigned)v, (unsigned)e,
                            (unsigned)a, (unsigned)b);
            uint32_t pa = D->pos[a], pb = D->pos[b];
            if (!((pa + 1) % m == pb || (pb + 1) % m == pa))
                return fail(c, "vertex %u: edge %u (%u,%u) is a diagonal of its "
                            "polygon", (unsigned)v, (unsigned)e, (unsigned)a,
                            (unsigned)b);
        }
        /* exactly cocircular, strictly convex, counter-clockwise */
        const double *p0 = P(c, c0), *p1 = P(c, c1), *p2 = P(c, D->tri[3 * t + 2]);
        for (size_t q = 3; q < m; q++) {
            uint32_t s = D->tri[3 * (t + q - 2) + 2];
            if (vor__incircle_fast(p0, p1, p2, P(c, s)) != 0)
                return fail(c, "vertex %u: site %u is not exactly on the circle "
                            "of %u %u %u", (unsigned)v, (unsigned)s, (unsigned)c0,
                            (unsigned)c1, (unsigned)D->tri[3 * t + 2]);
        }
        for (size_t q = 0; q < m; q++) {
            uint32_t s[3];
            for (int h = 0; h < 3; h++) {
                size_t r = (q + (size_t)h) % m;
                s[h] = r == 0 ? c0 : r == 1 ? c1 : D->tri[3 * (t + r - 2) + 2];
            }
            if (vor__orient2d_fast(P(c, s[0]), P(c, s[1]), P(c, s[2])) <= 0)
                return fail(c, "vertex %u: sites %u %u %u do not turn left "
                            "(polygon not convex counter-clockwise)", (unsigned)v,
                            (unsigned)s[0], (unsigned)s[1], (unsigned)s[2]);
        }
        for (size_t q = 0; q < m; q++) { /* clear the stamps */
            uint32_t s = q == 0 ? c0 : q == 1 ? c1 : D->tri[3 * (t + q - 2) + 2];
            D->stamp[s] = NONE32;
        }
        t += m - 2;
    }
    if (t != D->nt)
        return fail(c, "%zu dual triangles, the vertices account for %zu", D->nt, t);
    return 0;
}

/* Stable counting sort of the half-edges by key (min or max site). */
static void sort_he(dual *D, size_t n, int by_max) {
    size_t m = 3 * D->nt;
    memset(D->count, 0, (n + 1) * sizeof *D->count);
    for (size_t k = 0; k < m; k++) {
        uint32_t h = D->he[k];
        D->count[(by_max ? he_max(D, h) : he_min(D, h)) + 1]++;
    }
    for (size_t i = 0; i < n; i++) D->count[i + 1] += D->count[i];
    for (size_t k = 0; k < m; k++) {
        uint32_t h = D->he[k];
        D->he_tmp[D->count[by_max ? he_max(D, h) : he_min(D, h)]++] = h;
    }
    uint32_t *x = D->he;
    D->he = D->he_tmp;
    D->he_tmp = x;
}

/* Direction (q - p) in the upper half-plane (angle in [0, pi))? Exact. */
static int upper(const double *p, const double *q) {
    return q[1] > p[1] || (q[1] == p[1] && q[0] > p[0]);
}

static int check_dual(ctx *c, dual *D) {
    const vor_diagram *d = c->d;
    const size_t n = c->n, m = 3 * D->nt;
    for (size_t t = 0; t < D->nt; t++)
        if (vor__orient2d_fast(P(c, D->tri[3 * t]), P(c, D->tri[3 * t + 1]),
                         P(c, D->tri[3 * t + 2])) <= 0)
            return fail(c, "dual triangle %zu (%u %u %u) is not counter-clockwise",
                        t, (unsigned)D->tri[3 * t], (unsigned)D->tri[3 * t + 1],
                        (unsigned)D->tri[3 * t + 2]);
    for (size_t k = 0; k < m; k++) D->he[k] = (uint32_t)k;
    sort_he(D, n, 1);
    sort_he(D, n, 0);

    /* every site in some triangle */
    for (size_t i = 0; i < n; i++) D->stamp[i] = 0;
    for (size_t k = 0; k < m; k++) D->stamp[D->tri[k]] = 1;
    for (size_t i = 0; i < n; i++)
        if (!D->stamp[i]) return fail(c, "site %zu: in no dual triangle (its cell "
                                      "has no vertex)", i);

    size_t n_dual_edges = 0, n_voronoi = 0, n_hull = 0;
    for (size_t i = 0; i < n; i++) D->hull_next[i] = NONE32;
    for (size_t k = 0; k < m;) {
        size_t q = k + 1;
        uint32_t lo = he_min(D, D->he[k]), hi = he_max(D, D->he[k]);
        while (q < m && he_min(D, D->he[q]) == lo && he_max(D, D->he[q]) == hi) q++;
        n_dual_edges++;
        long e = find_edge(d, D->by_a, lo, hi);
        if (q - k > 2)
            return fail(c, "dual edge (%u,%u) is in %zu triangles", (unsigned)lo,
                        (unsigned)hi, q - k);
        if (q - k == 2) {
            uint32_t h1 = D->he[k], h2 = D->he[k + 1];
            if (he_from(D, h1) == he_from(D, h2))
                return fail(c, "dual edge (%u,%u): both triangles on the same side "
                            "(overlapping triangles)", (unsigned)lo, (unsigned)hi);
            uint32_t t1 = h1 / 3, t2 = h2 / 3;
            int ic = vor__incircle_fast(P(c, D->tri[3 * t1]), P(c, D->tri[3 * t1 + 1]),
                                  P(c, D->tri[3 * t1 + 2]), P(c, he_apex(D, h2)));
            uint32_t v1 = D->tvert[t1], v2 = D->tvert[t2];
            if (ic > 0)
                return fail(c, "dual edge (%u,%u) is not locally Delaunay: site %u "
                            "lies inside the circle of vertex %u (empty circle "
                            "violated)", (unsigned)lo, (unsigned)hi,
                            (unsigned)he_apex(D, h2), (unsigned)v1);
            if (v1 == v2) {
                if (e >= 0)
                    return fail(c, "edge %ld (%u,%u) joins non-adjacent sites of "
                                "vertex %u", e, (unsigned)lo, (unsigned)hi, (unsigned)v1);
            } else {
                if (ic == 0)
                    return fail(c, "vertices %u and %u lie on one circle but were "
                                "not merged", (unsigned)v1, (unsigned)v2);
                if (e < 0)
                    return fail(c, "no edge (%u,%u) between vertices %u and %u",
                                (unsigned)lo, (unsigned)hi, (unsigned)v1, (unsigned)v2);
                const int32_t *en = d->edge_ends + 2 * (size_t)e;
                uint32_t a = v1 < v2 ? v1 : v2, b = v1 < v2 ? v2 : v1;
                if (!(en[0] == (int32_t)a && en[1] == (int32_t)b))
                    return fail(c, "edge %ld (%u,%u): ends %d %d, its dual says "
                                "vertices %u %u", e, (unsigned)lo, (unsigned)hi,
                                (int)en[0], (int)en[1], (unsigned)a, (unsigned)b);
                n_voronoi++;
            }
        } else { /* hull edge p -> q, interior on its left */
            uint32_t h = D->he[k], p = he_from(D, h), qq = he_to(D, h);
            uint32_t v = D->tvert[h / 3];
            if (D->hull_next[p] != NONE32)
                return fail(c, "site %u: two hull edges leave it (hull not simple)",
                            (unsigned)p);
            D->hull_next[p] = qq;
            n_hull++;
            if (e < 0)
                return fail(c, "hull edge (%u,%u) has no ray", (unsigned)p, (unsigned)qq);
            const int32_t *en = d->edge_ends + 2 * (size_t)e;
            if (!(en[0] == (int32_t)v && en[1] == VOR_NONE))
                return fail(c, "edge %ld (%u,%u): on the hull, should be a ray from "
                            "vertex %u", e, (unsigned)lo, (unsigned)hi, (unsigned)v);
            size_t lo_r = 0, hi_r = c->nr; /* its ray index */
            while (lo_r < hi_r) {
                size_t mid = lo_r + (hi_r - lo_r) / 2;
                if (d->ray_edge[mid] < (uint32_t)e) lo_r = mid + 1;
                else hi_r = mid;
            }
            const double *dir = d->ray_dir + 2 * lo_r;
            const double *pp = P(c, p), *pq = P(c, qq);
            double out_n[2] = {pq[1] - pp[1], -(pq[0] - pp[0])};
            if (!(dir[0] * out_n[0] + dir[1] * out_n[1] > 0))
                return fail(c, "ray %zu (edge %ld): points into the hull", lo_r, e);
            double want[2];
            vor_bisector_dir(pq, pp, want);
            if (memcmp(want, dir, sizeof want) != 0)
                return fail(c, "ray %zu (edge %ld): direction is not "
                            "vor_bisector_dir(%u, %u)", lo_r, e, (unsigned)qq,
                            (unsigned)p);
            n_voronoi++;
        }
        k = q;
    }
    if (n_voronoi != c->ne)
        return fail(c, "%zu edges, but the dual triangulation has %zu Voronoi edges",
                    c->ne, n_voronoi);
    if (n + D->nt != n_dual_edges + 1)
        return fail(c, "dual triangulation breaks Euler: %zu sites - %zu edges + "
                    "%zu triangles != 1", n, n_dual_edges, D->nt);
    if (c->nv + 1 + n != c->ne + 2)
        return fail(c, "diagram breaks Euler: %zu vertices + 1 - %zu edges + %zu "
                    "cells != 2", c->nv, c->ne, n);

    /* the boundary: one cycle, convex, winding once counter-clockwise */
    uint32_t start = NONE32;
    for (uint32_t i = 0; i < n && start == NONE32; i++)
        if (D->hull_next[i] != NONE32) start = i;
    if (start == NONE32) return fail(c, "dual triangulation has no boundary");
    size_t len = 0, wraps = 0;
    uint32_t a = start, b = D->hull_next[start];
    do {
        if (b == NONE32 || len > n_hull)
            return fail(c, "hull: boundary does not close from site %u", (unsigned)start);
        uint32_t cc = D->hull_next[b];
        if (cc == NONE32) return fail(c, "hull: boundary breaks at site %u", (unsigned)b);
        int o = vor__orient2d_fast(P(c, a), P(c, b), P(c, cc));
        if (o < 0)
            return fail(c, "hull: turns right at site %u (not convex)", (unsigned)b);
        if (o == 0 && !(lex_less(P(c, a), P(c, b)) == lex_less(P(c, b), P(c, cc))))
            return fail(c, "hull: reverses at site %u", (unsigned)b);
        if (!upper(P(c, a), P(c, b)) && upper(P(c, b), P(c, cc))) wraps++;
        if (c->d->cell_bounded[b])
            return fail(c, "cell %u: bounded, but its site is on the hull", (unsigned)b);
        len++;
        a = b;
        b = cc;
    } while (a != start);
    if (len != n_hull)
        return fail(c, "hull: %zu boundary edges, the cycle has %zu", n_hull, len);
    if (wraps != 1)
        return fail(c, "hull: boundary winds %zu times", wraps);
    for (uint32_t i = 0; i < n; i++)
        if (D->hull_next[i] == NONE32 && !d->cell_bounded[i])
            return fail(c, "cell %u: unbounded, but its site is inside the hull",
                        (unsigned)i);
    return 0;
}

int vor_check(const vor_diagram *d, const vor_sites *sites, char *msg,
              size_t msg_size) {
    ctx c = {d, NULL, 0, 0, 0, 0, msg, msg_size};
    if (msg && msg_size) msg[0] = '\0';
    if (!d || !sites) return fail(&c, "diagram or sites is NULL");
    if (d->n_sites != sites->n)
        return fail(&c, "diagram has %zu sites, the sites %zu", d->n_sites, sites->n);
    if (sites->n && !sites->xy) return fail(&c, "sites have no coordinates");
    c.xy = sites->xy;
    c.n = sites->n;
    c.nv = d->n_vertices;
    c.ne = d->n_edges;
    c.nr = d->n_rays;
    if (check_shapes(&c) || check_vertices(&c) || check_edges(&c)) return 1;
    uint8_t *seen = alloc(c.ne, 1);
    if (!seen) return fail(&c, "out of memory");
    int bad = check_cells(&c, seen);
    free(seen);
    if (bad) return 1;
    if (c.nv == 0) return check_lines(&c);

    dual D;
    memset(&D, 0, sizeof D);
    vor_status st = vor__diagram_triangles_cells(d, sites, &D.tri, &D.nt);
    if (st != VOR_OK) {
        return fail(&c, st == VOR_ENOMEM ? "out of memory"
                                          : "cells do not chain around the "
                                            "vertices (no dual triangles)");
    }
    D.tvert = alloc(D.nt, sizeof *D.tvert);
    D.voff = calloc(c.nv + 1, sizeof *D.voff);
    D.vedge = alloc(2 * c.ne, sizeof *D.vedge);
    D.pos = alloc(c.n, sizeof *D.pos);
    D.stamp = alloc(c.n, sizeof *D.stamp);
    D.he = alloc(3 * D.nt, sizeof *D.he);
    D.he_tmp = alloc(3 * D.nt, sizeof *D.he_tmp);
    D.count = alloc(c.n + 1, sizeof *D.count);
    D.hull_next = alloc(c.n, sizeof *D.hull_next);
    D.by_a = calloc(c.n + 1, sizeof *D.by_a);
    if (!D.tvert || !D.voff || !D.vedge || !D.pos || !D.stamp || !D.he ||
        !D.he_tmp || !D.count || !D.hull_next || !D.by_a) {
        dual_free(&D);
        return fail(&c, "out of memory");
    }
    for (size_t e = 0; e < c.ne; e++) D.by_a[d->edge_sites[2 * e] + 1]++;
    for (size_t i = 0; i < c.n; i++) D.by_a[i + 1] += D.by_a[i];
    /* edges at each vertex (CSR) */
    for (size_t k = 0; k < 2 * c.ne; k++)
        if (d->edge_ends[k] >= 0) D.voff[d->edge_ends[k] + 1]++;
    for (size_t v = 0; v < c.nv; v++) D.voff[v + 1] += D.voff[v];
    uint32_t *cur = alloc(c.nv, sizeof *cur);
    if (!cur) {
        dual_free(&D);
        return fail(&c, "out of memory");
    }
    memcpy(cur, D.voff, c.nv * sizeof *cur);
    for (size_t k = 0; k < 2 * c.ne; k++)
        if (d->edge_ends[k] >= 0) D.vedge[cur[d->edge_ends[k]]++] = (uint32_t)(k / 2);
    free(cur);
    bad = check_vertex_sites(&c, &D) || check_dual(&c, &D);
    dual_free(&D);
    return bad;
}
