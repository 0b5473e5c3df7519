/* diagram.c -- the canonical Voronoi diagram: the one builder every
 * algorithm ends in, the Delaunay-mesh conversion, the degenerate diagrams
 * (fewer than three sites, or all collinear), the dual triangles, equality
 * and freeing.
 *
 * Representation: struct vor_diagram in vor.h, flat arrays with fixed
 * strides. vor__diagram_build() alone decides the canonical form, so that
 * Fortune's sweep and the two triangulation algorithms return bit-identical
 * diagrams:
 *   - vertices ordered by their three smallest sites (s0, s1, s2), coordinates
 *     from vor_circumcenter(s0, s1, s2);
 *   - edges (a, b) with a < b, ordered by (a, b); a segment's ends increase;
 *     a ray lists its vertex first;
 *   - rays in edge order, directions from vor_bisector_dir();
 *   - cells counter-clockwise; a bounded cell starts at its smallest edge
 *     index, an unbounded one with the edge that comes in from infinity.
 *     The cell of a site between two parallel lines (all sites collinear)
 *     has no such edge: it lists its two lines in edge order (smaller edge
 *     index first), each of which is traversed with the site on its left.
 *
 * Every decision that depends on geometry (which end of an edge comes first
 * around a site, which way a ray points, which triangles share a circle) is
 * taken with the exact predicates vor_orient2d / vor_incircle, or read off
 * the counter-clockwise triangles of a Delaunay mesh, which were themselves
 * built with them; everything else is combinatorial. Vertices and edges are
 * sorted by a counting pass on their smallest site that moves whole records
 * into place, then a sort of each bucket where it lies (2 or 3 records on
 * average), so the build is O(n) for any input whose sites each are the
 * smallest of a bounded number of circles and O(n log n) at worst. Cost at
 * 10^6 uniform sites in random order (2 cores, Debian 12): about 1.1 s CPU
 * for a mesh conversion, dominated by cache misses on the sites. That is
 * why Bowyer-Watson and flipping do not come through here but through
 * mesh_dual.c, which reads the same canonical diagram off their mesh in
 * its own (spatial) order; vor__mesh_to_diagram stays for finished meshes
 * and is that path's oracle in the tests.
 * Peak memory: the result (about 133 bytes per site for uniform input) is
 * never held twice; the largest moment is the chaining of the cells,
 * about 141 bytes per site.
 *
 * Input that breaks a builder's contract can only come from a bug in one of
 * our algorithms: a debug build stops on an assert naming the broken rule, a
 * release build returns VOR_EINVAL (nothing leaks, *out is NULL).
 */
#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "predicates.h"

/* Indices handled here (vertex and edge ids, which are int32_t in the
 * diagram) stay below 2^31. */
#define MAX_INDEX 0x7fffffffu
#define EMPTY UINT32_MAX

#define CONTRACT(cond)                                                     \
    do {                                                                   \
        if (!(cond)) {                                                     \
            assert(!"diagram contract broken: " #cond);                     \
            st = VOR_EINVAL;                                               \
            goto fail;                                                     \
        }                                                                  \
    } while (0)

void vor_diagram_free(vor_diagram *d) {
    if (!d) return;
    free(d->vertex_xy);
    free(d->vertex_sites);
    free(d->edge_sites);
    free(d->edge_ends);
    free(d->ray_edge);
    free(d->ray_dir);
    free(d->cell_start);
    free(d->cell_edges);
    free(d->cell_bounded);
    free(d);
}

/* ---- sorting helpers ----------------------------------------------------- */

/* Bit 31 of an edge's second site carries, while the builder sorts, whether
 * its first end is the vertex on the left of a->b (see `oriented`). Site
 * indices stay below 2^31. */
#define LEFT_BIT 0x80000000u

/* A record of four words, used to sort large buckets: w[1], w[2] are the
 * key (w[1] without LEFT_BIT first), the rest travels along. */
typedef struct rec4 {
    uint32_t w[4];
} rec4;

static int rec4_less(const rec4 *x, const rec4 *y) {
    uint32_t a = x->w[1] & ~LEFT_BIT, b = y->w[1] & ~LEFT_BIT;
    return a < b || (a == b && x->w[2] < y->w[2]);
}

/* Sorts r[0..k-1] by rec4_less: insertion sort when small, else a
 * bottom-up merge sort through tmp (k entries). Stable. */
static void sort_rec4(rec4 *r, rec4 *tmp, size_t k) {
    if (k <= 16) {
        for (size_t i = 1; i < k; i++) {
            rec4 x = r[i];
            size_t j = i;
            while (j > 0 && rec4_less(&x, &r[j - 1])) {
                r[j] = r[j - 1];
                j--;
            }
            r[j] = x;
        }
        return;
    }
    for (size_t w = 1; w < k; w *= 2) {
        for (size_t lo = 0; lo < k; lo += 2 * w) {
            size_t mid = lo + w < k ? lo + w : k, hi = lo + 2 * w < k ? lo + 2 * w : k;
            size_t i = lo, j = mid, o = lo;
            while (i < mid && j < hi) tmp[o++] = rec4_less(&r[j], &r[i]) ? r[j++] : r[i++];
            while (i < mid) tmp[o++] = r[i++];
            while (j < hi) tmp[o++] = r[j++];
        }
        memcpy(r, tmp, k * sizeof *r);
    }
}

/* Largest bucket of the counts in cnt[0..n-1] (cnt[i] = size of bucket i). */
static size_t largest(const uint32_t *cnt, size_t n) {
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (cnt[i] > m) m = cnt[i];
    return m;
}

/* Vertices in (s0, s1, s2) order. One counting pass on s0 scatters whole
 * triples into a new array (so that nothing is gathered through a
 * permutation later), then each bucket of equal s0 is sorted where it lies
 * by (s1, s2). newid[old] receives each vertex's new index. count has
 * n + 1 entries. O(nv + n) for buckets of at most 16 vertices (uniform
 * input: 2 on average); a bucket of k > 16 costs O(k log k), so at worst
 * O(nv log nv), for one site on every circle. NULL on allocation failure. */
static uint32_t *sort_vertices(const uint32_t *vs, size_t nv, size_t n,
                               uint32_t *count, uint32_t *newid) {
    uint32_t *sorted = vor__alloc_large(3 * nv, sizeof *sorted);
    uint32_t *ids = vor__alloc_large(nv, sizeof *ids);
    rec4 *r = NULL, *tmp = NULL;
    if (!sorted || !ids) goto fail;
    memset(count, 0, (n + 1) * sizeof *count);
    for (size_t v = 0; v < nv; v++) count[vs[3 * v]]++;
    size_t big = largest(count, n);
    if (big > 16) {
        r = vor__alloc_large(big, sizeof *r);
        tmp = vor__alloc_large(big, sizeof *tmp);
        if (!r || !tmp) goto fail;
    }
    for (size_t i = 0, sum = 0; i <= n; i++) { /* count[i]: start of bucket i */
        size_t c = i < n ? count[i] : 0;
        count[i] = (uint32_t)sum;
        sum += c;
    }
    for (size_t v = 0; v < nv; v++) {
        size_t p = count[vs[3 * v]]++;
        memcpy(sorted + 3 * p, vs + 3 * v, 3 * sizeof *vs);
        ids[p] = (uint32_t)v;
    }
    /* now count[i] is the end of bucket i */
    for (size_t i = 0, lo = 0; i < n; lo = count[i], i++) {
        size_t hi = count[i], k = hi - lo;
        if (k < 2) continue;
        uint32_t *t = sorted + 3 * lo, *id = ids + lo;
        if (k <= 16) {
            for (size_t a = 1; a < k; a++) {
                uint32_t x1 = t[3 * a + 1], x2 = t[3 * a + 2], xi = id[a];
                size_t j = a;
                while (j > 0 && (x1 < t[3 * j - 2] ||
                                 (x1 == t[3 * j - 2] && x2 < t[3 * j - 1]))) {
                    t[3 * j + 1] = t[3 * j - 2];
                    t[3 * j + 2] = t[3 * j - 1];
                    id[j] = id[j - 1];
                    j--;
                }
                t[3 * j + 1] = x1;
                t[3 * j + 2] = x2;
                id[j] = xi;
            }
        } else {
            for (size_t a = 0; a < k; a++)
                r[a] = (rec4){{t[3 * a], t[3 * a + 1], t[3 * a + 2], id[a]}};
            sort_rec4(r, tmp, k);
            for (size_t a = 0; a < k; a++) {
                t[3 * a + 1] = r[a].w[1];
                t[3 * a + 2] = r[a].w[2];
                id[a] = r[a].w[3];
            }
        }
    }
    for (size_t p = 0; p < nv; p++) newid[ids[p]] = (uint32_t)p;
    free(ids);
    free(r);
    free(tmp);
    return sorted;
fail:
    free(sorted);
    free(ids);
    free(r);
    free(tmp);
    return NULL;
}

/* Edges in (a, b) order, the same way: a counting pass on a scatters the
 * site pairs and ends into new arrays, then each bucket of equal a is
 * sorted by b. Same cost as sort_vertices. Returns 0, or -1 on allocation
 * failure (the old arrays are then kept). */
static int sort_edges(vor_diagram *d, size_t n, uint32_t *count) {
    const size_t ne = d->n_edges;
    const uint32_t *es = d->edge_sites;
    const int32_t *en = d->edge_ends;
    uint32_t *ns = vor__alloc_large(2 * ne, sizeof *ns);
    int32_t *nn = vor__alloc_large(2 * ne, sizeof *nn);
    rec4 *r = NULL, *tmp = NULL;
    if (!ns || !nn) goto fail;
    memset(count, 0, (n + 1) * sizeof *count);
    for (size_t e = 0; e < ne; e++) count[es[2 * e]]++;
    size_t big = largest(count, n);
    if (big > 16) {
        r = vor__alloc_large(big, sizeof *r);
        tmp = vor__alloc_large(big, sizeof *tmp);
        if (!r || !tmp) goto fail;
    }
    for (size_t i = 0, sum = 0; i <= n; i++) {
        size_t c = i < n ? count[i] : 0;
        count[i] = (uint32_t)sum;
        sum += c;
    }
    for (size_t e = 0; e < ne; e++) {
        size_t p = count[es[2 * e]]++;
        ns[2 * p] = es[2 * e];
        ns[2 * p + 1] = es[2 * e + 1];
        nn[2 * p] = en[2 * e];
        nn[2 * p + 1] = en[2 * e + 1];
    }
    for (size_t i = 0, lo = 0; i < n; lo = count[i], i++) {
        size_t hi = count[i], k = hi - lo;
        if (k < 2) continue;
        uint32_t *t = ns + 2 * lo;
        int32_t *u = nn + 2 * lo;
        if (k <= 16) {
            for (size_t a = 1; a < k; a++) {
                uint32_t xb = t[2 * a + 1];
                int32_t x0 = u[2 * a], x1 = u[2 * a + 1];
                size_t j = a;
                while (j > 0 && (xb & ~LEFT_BIT) < (t[2 * j - 1] & ~LEFT_BIT)) {
                    t[2 * j + 1] = t[2 * j - 1];
                    u[2 * j] = u[2 * j - 2];
                    u[2 * j + 1] = u[2 * j - 1];
                    j--;
                }
                t[2 * j + 1] = xb;
                u[2 * j] = x0;
                u[2 * j + 1] = x1;
            }
        } else {
            for (size_t a = 0; a < k; a++)
                r[a] = (rec4){{t[2 * a], t[2 * a + 1], 0, (uint32_t)a}};
            sort_rec4(r, tmp, k);
            /* apply the order to the ends through tmp as scratch */
            for (size_t a = 0; a < k; a++) {
                tmp[a].w[0] = (uint32_t)u[2 * r[a].w[3]];
                tmp[a].w[1] = (uint32_t)u[2 * r[a].w[3] + 1];
            }
            for (size_t a = 0; a < k; a++) {
                t[2 * a + 1] = r[a].w[1];
                u[2 * a] = (int32_t)tmp[a].w[0];
                u[2 * a + 1] = (int32_t)tmp[a].w[1];
            }
        }
    }
    free(d->edge_sites);
    free(d->edge_ends);
    d->edge_sites = ns;
    d->edge_ends = nn;
    free(r);
    free(tmp);
    return 0;
fail:
    free(ns);
    free(nn);
    free(r);
    free(tmp);
    return -1;
}


/* A site of the triple t other than a and b (one exists: t is three
 * distinct sites). */
static uint32_t third_site(const uint32_t *t, uint32_t a, uint32_t b) {
    for (int k = 0; k < 3; k++)
        if (t[k] != a && t[k] != b) return t[k];
    return t[0];
}

/* While the cells are chained, each entry of cell_edges carries in FWD_BIT
 * whether the counter-clockwise walk around that cell's site runs along the
 * edge from end0 to end1; in VISITED_BIT of the scratch copy, whether the
 * walk has used it. Edge indices stay below 2^30. */
#define FWD_BIT 0x80000000u
#define VISITED_BIT 0x40000000u
#define INDEX_MASK 0x3fffffffu

static int32_t entry_start(const vor_diagram *d, uint32_t x) {
    return d->edge_ends[2 * (size_t)(x & INDEX_MASK) + ((x & FWD_BIT) ? 0 : 1)];
}
static int32_t entry_end(const vor_diagram *d, uint32_t x) {
    return d->edge_ends[2 * (size_t)(x & INDEX_MASK) + ((x & FWD_BIT) ? 1 : 0)];
}

/* Orders the cell of site i counter-clockwise in place (see the file
 * comment for where it starts), sets cell_bounded[i] and leaves plain edge
 * indices in its entries. slot (n_vertices entries, contents irrelevant)
 * maps a vertex to the entry that starts there; tmp holds a copy of the
 * cell's entries. Only edge_ends is read per entry, once or twice, which
 * keeps the random memory accesses to a minimum. Returns 0, or -1 if the
 * edges of the cell do not form one chain. O(cell size). */
static int order_cell(vor_diagram *d, uint32_t *slot, uint32_t *tmp, uint32_t i) {
    uint32_t *L = d->cell_edges + d->cell_start[i];
    const size_t k = d->cell_start[i + 1] - d->cell_start[i];
    size_t n_lines = 0, n_in = 0, n_out = 0, first_in = 0;

    d->cell_bounded[i] = 0;
    if (k == 0) return d->n_sites == 1 ? 0 : -1;
    for (size_t t = 0; t < k; t++) {
        uint32_t x = tmp[t] = L[t];
        int32_t s0 = entry_start(d, x), s1 = entry_end(d, x);
        if (s0 < 0 && s1 < 0) {
            n_lines++;
            continue;
        }
        if (s0 < 0) {
            n_in++;
            first_in = t;
        } else {
            slot[s0] = (uint32_t)t;
        }
        if (s1 < 0) n_out++;
    }
    if (n_lines) { /* all sites collinear: lines only, kept in edge order */
        for (size_t t = 0; t < k; t++) L[t] &= INDEX_MASK;
        return n_lines == k && k <= 2 ? 0 : -1;
    }
    if (n_in != n_out || n_in > 1) return -1;

    size_t cur = n_in ? first_in : 0; /* entries are in edge order */
    const int32_t closing = entry_start(d, tmp[cur]);
    for (size_t t = 0;; t++) {
        uint32_t x = tmp[cur];
        if (x & VISITED_BIT) return -1;
        tmp[cur] = x | VISITED_BIT;
        L[t] = x & INDEX_MASK;
        int32_t v = entry_end(d, x);
        if (t + 1 == k) {
            if (v != closing) return -1;
            break;
        }
        if (v < 0) return -1;
        uint32_t nx = slot[v];
        if (nx >= k || entry_start(d, tmp[nx]) != v) return -1;
        cur = nx;
    }
    d->cell_bounded[i] = n_in == 0;
    return 0;
}

/* The builder. With `oriented` set, every raw edge must list first the
 * vertex on the left of edges[2e] -> edges[2e+1] (the side where that
 * vertex's other sites lie; VOR_NONE for a ray's end at infinity is on the
 * right): the mesh conversion knows this from its counter-clockwise
 * triangles, which saves every orientation test (checked by assert in a
 * debug build). Otherwise orientations come from vor_orient2d. */
static vor_status build(const vor_sites *s, size_t n_vertices, uint32_t *edges,
                        int32_t *ends, size_t n_edges, int oriented,
                        vor_diagram **out) {
    vor_status st = VOR_ENOMEM;
    vor_diagram *d = NULL;
    uint32_t *count = NULL, *newid = NULL, *slot = NULL, *tmp = NULL;
    uint8_t *fwd = NULL;
    const size_t nv = n_vertices, ne = n_edges;

    if (!out) {
        free(edges);
        free(ends);
        assert(!"vor__diagram_build: out is NULL");
        return VOR_EINVAL;
    }
    *out = NULL;
    CONTRACT(s != NULL && (s->n == 0 || s->xy != NULL));
    CONTRACT(ne == 0 || (edges != NULL && ends != NULL));
    if (nv > MAX_INDEX || ne > INDEX_MASK || s->n > MAX_INDEX) {
        st = VOR_ETOOMANY;
        goto fail;
    }
    const size_t n = s->n;
    const double *xy = s->xy;

    d = calloc(1, sizeof *d);
    if (!d) goto fail;
    d->n_sites = n;
    d->n_vertices = nv;
    d->n_edges = ne;
    d->edge_sites = edges;
    d->edge_ends = ends;
    edges = NULL;
    ends = NULL;

    /* 1. Each vertex's three smallest sites: the union of its edges' sites. */
    d->vertex_sites = vor__alloc_large(3 * nv, sizeof(uint32_t));
    count = vor__alloc_large(n + 1, sizeof(uint32_t));
    if (!d->vertex_sites || !count) goto fail;
    uint32_t *vs = d->vertex_sites;
    for (size_t k = 0; k < 3 * nv; k++) vs[k] = EMPTY;
    for (size_t e = 0; e < ne; e++) {
        uint32_t *ab = d->edge_sites + 2 * e;
        int32_t *en = d->edge_ends + 2 * e;
        CONTRACT(ab[0] < n && ab[1] < n && ab[0] != ab[1]);
        uint32_t left = oriented ? LEFT_BIT : 0; /* end0 left of a->b */
        if (ab[0] > ab[1]) {
            uint32_t t = ab[0];
            ab[0] = ab[1];
            ab[1] = t;
            left ^= oriented ? LEFT_BIT : 0;
        }
        for (int k = 0; k < 2; k++) {
            CONTRACT(en[k] == VOR_NONE || (en[k] >= 0 && (size_t)en[k] < nv));
            if (en[k] >= 0) {
                vor__min3_add(vs + 3 * (size_t)en[k], ab[0]);
                vor__min3_add(vs + 3 * (size_t)en[k], ab[1]);
            }
        }
        CONTRACT(en[0] < 0 || en[0] != en[1]); /* no zero-length segment */
        CONTRACT(!oriented || en[0] >= 0);      /* a mesh has no lines */
        ab[1] |= left;
    }
    for (size_t v = 0; v < nv; v++) CONTRACT(vs[3 * v + 2] != EMPTY);

    /* 2. Vertices in (s0, s1, s2) order, then the edges' ends renumbered. */
    if (nv > 0) {
        newid = vor__alloc_large(nv, sizeof *newid);
        if (!newid) goto fail;
        uint32_t *sorted = sort_vertices(vs, nv, n, count, newid);
        if (!sorted) goto fail;
        free(vs);
        d->vertex_sites = vs = sorted;
        for (size_t v = 1; v < nv; v++) /* one circle, one vertex */
            CONTRACT(memcmp(vs + 3 * (v - 1), vs + 3 * v, 3 * sizeof *vs) != 0);
        for (size_t k = 0; k < 2 * ne; k++)
            if (d->edge_ends[k] >= 0)
                d->edge_ends[k] = (int32_t)newid[d->edge_ends[k]];
        free(newid);
        newid = NULL;
    }
    /* 3. Canonical ends: a segment's increase, a ray's vertex comes first. */
    for (size_t e = 0; e < ne; e++) {
        int32_t *en = d->edge_ends + 2 * e;
        if ((en[0] < 0 && en[1] >= 0) || (en[1] >= 0 && en[0] > en[1])) {
            int32_t t = en[0];
            en[0] = en[1];
            en[1] = t;
            if (oriented) d->edge_sites[2 * e + 1] ^= LEFT_BIT;
        }
    }

    /* 4. Edges in (a, b) order. */
    if (ne > 0 && sort_edges(d, n, count) != 0) goto fail;
    for (size_t e = 1; e < ne; e++) { /* a pair of sites has one edge */
        const uint32_t *p = d->edge_sites + 2 * (e - 1);
        CONTRACT(p[0] < p[2] || (p[0] == p[2] && (p[1] & ~LEFT_BIT) < (p[3] & ~LEFT_BIT)));
    }

    free(count); /* sorting is done */
    count = NULL;

    /* Coordinates, allocated only now to keep the peak low while sorting. */
    d->vertex_xy = vor__alloc_large(2 * nv, sizeof(double));
    if (!d->vertex_xy) goto fail;
    for (size_t v = 0; v < nv; v++) {
        const double *a = xy + 2 * (size_t)vs[3 * v], *b = xy + 2 * (size_t)vs[3 * v + 1],
                     *c = xy + 2 * (size_t)vs[3 * v + 2];
        if (!vor__circumcenter_fast(a, b, c, d->vertex_xy + 2 * v))
            vor_circumcenter(a, b, c, d->vertex_xy + 2 * v);
    }

    /* 5. Orientation of each edge around its sites, decided exactly: around
     * site a the walk runs towards the vertex whose other sites lie to the
     * left of a->b. Rays point away from those sites. */
    fwd = vor__alloc_large(ne, 1);
    if (!fwd) goto fail;
    size_t nr = 0;
    for (size_t e = 0; e < ne; e++) {
        const uint32_t left = d->edge_sites[2 * e + 1] & LEFT_BIT;
        d->edge_sites[2 * e + 1] &= ~LEFT_BIT;
        const uint32_t a = d->edge_sites[2 * e], b = d->edge_sites[2 * e + 1];
        const int32_t u = d->edge_ends[2 * e], w = d->edge_ends[2 * e + 1];
        fwd[e] = 1;
        if (w < 0) nr++;
        if (u < 0) continue; /* line */
        if (oriented) { /* end0 on the left: the walk around a ends there */
            fwd[e] = !left;
            assert(vor__orient2d_fast(xy + 2 * (size_t)a, xy + 2 * (size_t)b,
                                xy + 2 * (size_t)third_site(vs + 3 * (size_t)u, a, b)) ==
                   (left ? 1 : -1));
            continue;
        }
        uint32_t k = third_site(vs + 3 * (size_t)u, a, b);
        int o = vor__orient2d_fast(xy + 2 * (size_t)a, xy + 2 * (size_t)b, xy + 2 * (size_t)k);
        CONTRACT(o != 0);
        if (w >= 0) {
            uint32_t k2 = third_site(vs + 3 * (size_t)w, a, b);
            int o2 = vor__orient2d_fast(xy + 2 * (size_t)a, xy + 2 * (size_t)b,
                                  xy + 2 * (size_t)k2);
            CONTRACT(o2 == -o); /* the segment joins the two sides of ab */
        }
        fwd[e] = o < 0;
    }
    d->n_rays = nr;
    d->ray_edge = vor__alloc_large(nr, sizeof(uint32_t));
    d->ray_dir = vor__alloc_large(2 * nr, sizeof(double));
    if (!d->ray_edge || !d->ray_dir) goto fail;
    nr = 0;
    for (size_t e = 0; e < ne; e++) {
        if (d->edge_ends[2 * e + 1] >= 0) continue;
        const double *pa_ = xy + 2 * (size_t)d->edge_sites[2 * e];
        const double *pb_ = xy + 2 * (size_t)d->edge_sites[2 * e + 1];
        d->ray_edge[nr] = (uint32_t)e;
        /* A line has a on its left; a ray leaves its vertex in the walking
         * direction around a when fwd (vertex first), else around b. */
        if (fwd[e])
            vor_bisector_dir(pa_, pb_, d->ray_dir + 2 * nr);
        else
            vor_bisector_dir(pb_, pa_, d->ray_dir + 2 * nr);
        nr++;
    }

    /* 6. Cells: bucket the edges by site (in edge order, each entry
     * tagged with its walking direction), then chain each cell through its
     * vertices. */
    d->cell_start = vor__alloc_large(n + 1, sizeof(uint32_t));
    d->cell_edges = vor__alloc_large(2 * ne, sizeof(uint32_t));
    d->cell_bounded = vor__alloc_large(n, 1);
    if (!d->cell_start || !d->cell_edges || !d->cell_bounded) goto fail;
    uint32_t *cs = d->cell_start;
    memset(cs, 0, (n + 1) * sizeof *cs);
    for (size_t k = 0; k < 2 * ne; k++) cs[d->edge_sites[k] + 1]++;
    size_t max_k = 0;
    for (size_t i = 0; i < n; i++) {
        if (cs[i + 1] > max_k) max_k = cs[i + 1];
        cs[i + 1] += cs[i];
    }
    for (size_t e = 0; e < ne; e++) {
        uint32_t f = fwd[e] ? FWD_BIT : 0; /* around a; reversed around b */
        d->cell_edges[cs[d->edge_sites[2 * e]]++] = (uint32_t)e | f;
        d->cell_edges[cs[d->edge_sites[2 * e + 1]]++] = (uint32_t)e | (f ^ FWD_BIT);
    }
    for (size_t i = n; i > 0; i--) cs[i] = cs[i - 1];
    cs[0] = 0;
    free(fwd);
    fwd = NULL;
    slot = vor__alloc_large(nv, sizeof(uint32_t));
    tmp = vor__alloc_large(max_k, sizeof(uint32_t));
    if (!slot || !tmp) goto fail;
    for (size_t i = 0; i < n; i++)
        CONTRACT(order_cell(d, slot, tmp, (uint32_t)i) == 0);

    free(slot);
    free(tmp);
    *out = d;
    return VOR_OK;

fail:
    free(edges);
    free(ends);
    free(count);
    free(newid);
    free(slot);
    free(tmp);
    free(fwd);
    vor_diagram_free(d);
    return st;
}

vor_status vor__diagram_build(const vor_sites *s, size_t n_vertices,
                              uint32_t *edges, int32_t *ends, size_t n_edges,
                              vor_diagram **out) {
    return build(s, n_vertices, edges, ends, n_edges, 0, out);
}

/* ---- from a Delaunay mesh ------------------------------------------------ */

static uint32_t uf_find(uint32_t *uf, uint32_t x) {
    while (uf[x] != x) {
        uf[x] = uf[uf[x]]; /* path halving */
        x = uf[x];
    }
    return x;
}

/* Triangles t and u are adjacent across half-edges e (in t) and f (in u).
 * They belong to the same Voronoi vertex when the apex of u, tri[prev(f)],
 * lies exactly on the circumcircle of t. Union-find links the larger root
 * under the smaller, so each group's root is its smallest triangle. */
vor_status vor__mesh_to_diagram(const vor_sites *s, vor__mesh *m,
                                vor_diagram **out) {
    vor_status st = VOR_ENOMEM;
    uint32_t *uf = NULL, *edges = NULL;
    int32_t *ends = NULL;

    if (!out) {
        vor__mesh_clear(m);
        return VOR_EINVAL;
    }
    *out = NULL;
    CONTRACT(s != NULL && m != NULL);
    const size_t T = m->n_tri, n = s->n;
    const double *xy = s->xy;
    const uint32_t *tri = m->tri;
    const int32_t *adj = m->adj;
    if (T > MAX_INDEX / 3) {
        st = VOR_ETOOMANY;
        goto fail;
    }
    CONTRACT(T == 0 || (tri != NULL && adj != NULL));

    uf = vor__alloc_large(T, sizeof *uf);
    if (!uf) goto fail;
    for (size_t t = 0; t < T; t++) uf[t] = (uint32_t)t;
    size_t hull = 0;
    for (size_t e = 0; e < 3 * T; e++) CONTRACT(tri[e] < n);
    for (size_t e = 0; e < 3 * T; e++) {
        int32_t f = adj[e];
        if (f < 0) {
            CONTRACT(f == -1);
            hull++;
            continue;
        }
        CONTRACT((size_t)f < 3 * T && adj[f] == (int32_t)e);
        if ((size_t)f < e) continue;
        size_t t = e / 3, u = (size_t)f / 3;
        const double *apex = xy + 2 * (size_t)tri[vor__prev((uint32_t)f)];
        int ic = vor__incircle_fast(xy + 2 * (size_t)tri[3 * t],
                              xy + 2 * (size_t)tri[3 * t + 1],
                              xy + 2 * (size_t)tri[3 * t + 2], apex);
        CONTRACT(ic <= 0); /* the mesh is Delaunay */
        if (ic == 0) {
            uint32_t rt = uf_find(uf, (uint32_t)t), ru = uf_find(uf, (uint32_t)u);
            if (rt < ru) uf[ru] = rt;
            else if (ru < rt) uf[rt] = ru;
        }
    }
    /* Number the groups in order of their smallest triangle. */
    for (size_t t = 0; t < T; t++) uf[t] = uf_find(uf, (uint32_t)t);
    size_t nv = 0;
    for (size_t t = 0; t < T; t++)
        uf[t] = uf[t] == t ? (uint32_t)nv++ : uf[uf[t]];

    /* Delaunay edges: (3T + hull) / 2; those inside a group vanish. */
    size_t cap = (3 * T + hull) / 2, ne = 0;
    edges = vor__alloc_large(2 * cap, sizeof *edges);
    ends = vor__alloc_large(2 * cap, sizeof *ends);
    if (!edges || !ends) goto fail;
    for (size_t e = 0; e < 3 * T; e++) {
        int32_t f = adj[e];
        int32_t vt = (int32_t)uf[e / 3], vu = VOR_NONE;
        if (f >= 0) {
            if ((size_t)f < e) continue;
            vu = (int32_t)uf[f / 3];
            if (vu == vt) continue; /* inside one cocircular group */
        }
        CONTRACT(ne < cap);
        edges[2 * ne] = tri[e];
        edges[2 * ne + 1] = tri[vor__next((uint32_t)e)];
        ends[2 * ne] = vt;
        ends[2 * ne + 1] = vu;
        ne++;
    }
    vor__mesh_clear(m);
    free(uf);
    uf = NULL;
    if (ne < cap) { /* shrinking; keep the larger block if realloc fails */
        uint32_t *e2 = realloc(edges, 2 * (ne ? ne : 1) * sizeof *edges);
        if (e2) edges = e2;
        int32_t *n2 = realloc(ends, 2 * (ne ? ne : 1) * sizeof *ends);
        if (n2) ends = n2;
    }
    /* each edge lists first the vertex of the triangle it was taken from,
     * which lies to the left of tri[e] -> tri[next(e)] */
    return build(s, nv, edges, ends, ne, 1, out);

fail:
    vor__mesh_clear(m);
    free(uf);
    free(edges);
    free(ends);
    return st;
}

/* ---- degenerate input ---------------------------------------------------- */

int vor__all_collinear(const vor_sites *s) {
    if (!s || s->n < 3) return 1;
    const double *xy = s->xy;
    for (size_t k = 2; k < s->n; k++)
        if (vor__orient2d_fast(xy, xy + 2, xy + 2 * k) != 0) return 0;
    return 1;
}

/* Lexicographic (x, y) order of sites i and j; for collinear points it is
 * their order along the line, decided exactly. */
static int xy_less(const double *xy, uint32_t i, uint32_t j) {
    const double *p = xy + 2 * (size_t)i, *q = xy + 2 * (size_t)j;
    return p[0] < q[0] || (p[0] == q[0] && p[1] < q[1]);
}

/* Bottom-up merge sort of a[0..n-1] by xy_less, tmp as scratch.
 * O(n log n), no recursion. */
static void sort_along(const double *xy, uint32_t *a, uint32_t *tmp,
                       size_t n) {
    for (size_t w = 1; w < n; w *= 2) {
        for (size_t lo = 0; lo < n; lo += 2 * w) {
            size_t mid = lo + w < n ? lo + w : n;
            size_t hi = lo + 2 * w < n ? lo + 2 * w : n;
            size_t i = lo, j = mid, k = lo;
            while (i < mid && j < hi)
                tmp[k++] = xy_less(xy, a[j], a[i]) ? a[j++] : a[i++];
            while (i < mid) tmp[k++] = a[i++];
            while (j < hi) tmp[k++] = a[j++];
        }
        memcpy(a, tmp, n * sizeof *a);
    }
}

/* n == 0: empty; n == 1: one unbounded cell, no edge; otherwise the lines
 * between consecutive sites along their common line. */
vor_status vor__diagram_degenerate(const vor_sites *s, vor_diagram **out) {
    vor_status st = VOR_ENOMEM;
    uint32_t *ord = NULL, *tmp = NULL, *edges = NULL;
    int32_t *ends = NULL;

    if (!out) return VOR_EINVAL;
    *out = NULL;
    CONTRACT(s != NULL && vor__all_collinear(s));
    const size_t n = s->n, ne = n > 1 ? n - 1 : 0;
    if (n > MAX_INDEX) {
        st = VOR_ETOOMANY;
        goto fail;
    }
    edges = vor__alloc_large(2 * ne, sizeof *edges);
    ends = vor__alloc_large(2 * ne, sizeof *ends);
    ord = vor__alloc_large(n, sizeof *ord);
    tmp = vor__alloc_large(n, sizeof *tmp);
    if (!edges || !ends || !ord || !tmp) goto fail;
    for (size_t i = 0; i < n; i++) ord[i] = (uint32_t)i;
    sort_along(s->xy, ord, tmp, n);
    for (size_t k = 0; k < ne; k++) {
        const double *p = s->xy + 2 * (size_t)ord[k],
                     *q = s->xy + 2 * (size_t)ord[k + 1];
        if (p[0] == q[0] && p[1] == q[1]) { /* a repeated site (by hand) */
            st = VOR_EINVAL;
            goto fail;
        }
        edges[2 * k] = ord[k];
        edges[2 * k + 1] = ord[k + 1];
        ends[2 * k] = ends[2 * k + 1] = VOR_NONE;
    }
    free(ord);
    free(tmp);
    return vor__diagram_build(s, 0, edges, ends, ne, out);

fail:
    free(ord);
    free(tmp);
    free(edges);
    free(ends);
    return st;
}

/* ---- the dual triangles -------------------------------------------------- */

/* Walking the cell of site i counter-clockwise, the edge that arrives at
 * vertex v separates i from the site that follows i counter-clockwise on
 * v's circle. Collecting that successor for every (vertex, site) pair gives
 * each vertex's sites in counter-clockwise order, which are fanned from the
 * smallest site. Triangles are emitted in vertex order. O(n) time; scratch
 * of about 4 words per (vertex, site) pair, every one of them visited at
 * random (a vertex's pairs come from three cells far apart in site
 * order): at 10^6 uniform sites this took 435 to 600 ms, more than two
 * thirds of the diagram's own computation. */
vor_status vor__diagram_triangles_cells(const vor_diagram *d,
                                        const vor_sites *sites,
                                        uint32_t **out, size_t *n_tri) {
    vor_status st = VOR_ENOMEM;
    uint32_t *off = NULL, *cur = NULL, *pairs = NULL, *nxt = NULL;
    uint32_t *stamp = NULL, *tri = NULL;

    if (!out || !n_tri) return VOR_EINVAL;
    *out = NULL;
    *n_tri = 0;
    if (!d || !sites || d->n_sites != sites->n) return VOR_EINVAL;
    const size_t nv = d->n_vertices, ne = d->n_edges, n = d->n_sites;

    /* Degree of each vertex = number of edge ends there = number of sites
     * on its circle; off[] holds the CSR offsets of the (site, successor)
     * pairs, cur[] the fill cursors. */
    off = calloc(nv + 1, sizeof *off);
    cur = vor__alloc_large(nv, sizeof *cur);
    if (!off || !cur) goto fail;
    for (size_t k = 0; k < 2 * ne; k++) {
        int32_t v = d->edge_ends[k];
        if (v >= 0) {
            if ((size_t)v >= nv) goto invalid;
            off[v + 1]++;
        }
    }
    size_t ntri = 0;
    for (size_t v = 0; v < nv; v++) {
        if (off[v + 1] < 3) goto invalid;
        ntri += off[v + 1] - 2;
        off[v + 1] += off[v];
        cur[v] = off[v];
    }
    size_t n_pairs = off[nv], filled = 0;
    pairs = vor__alloc_large(2 * n_pairs, sizeof *pairs);
    nxt = vor__alloc_large(n, sizeof *nxt);
    stamp = vor__alloc_large(n, sizeof *stamp);
    tri = vor__alloc_large(3 * ntri, sizeof *tri);
    if (!pairs || !nxt || !stamp || !tri) goto fail;
    for (size_t i = 0; i < n && nv > 0; i++) {
        size_t a = d->cell_start[i], b = d->cell_start[i + 1];
        if (b < a || b > 2 * ne) goto invalid;
        size_t k = b - a, steps = d->cell_bounded[i] ? k : (k ? k - 1 : 0);
        for (size_t t = 0; t < steps; t++) {
            uint32_t ep = d->cell_edges[a + t], en = d->cell_edges[a + (t + 1) % k];
            if (ep >= ne || en >= ne) goto invalid;
            const int32_t *p = d->edge_ends + 2 * (size_t)ep;
            const int32_t *q = d->edge_ends + 2 * (size_t)en;
            int32_t v = p[0] >= 0 && (p[0] == q[0] || p[0] == q[1]) ? p[0]
                      : p[1] >= 0 && (p[1] == q[0] || p[1] == q[1]) ? p[1]
                      : -1;
            const uint32_t *ab = d->edge_sites + 2 * (size_t)ep;
            if (v < 0 || (ab[0] != i && ab[1] != i)) goto invalid;
            if (cur[v] >= off[v + 1]) goto invalid;
            pairs[2 * (size_t)cur[v]] = (uint32_t)i;
            pairs[2 * (size_t)cur[v] + 1] = ab[0] == i ? ab[1] : ab[0];
            cur[v]++;
            filled++;
        }
    }
    if (filled != n_pairs) goto invalid;
    for (size_t i = 0; i < n; i++) stamp[i] = EMPTY;
    size_t nt = 0;
    for (size_t v = 0; v < nv; v++) {
        size_t lo = off[v], hi = off[v + 1], m = hi - lo;
        for (size_t k = lo; k < hi; k++) {
            uint32_t x = pairs[2 * k], y = pairs[2 * k + 1];
            if (x >= n || y >= n) goto invalid;
            nxt[x] = y;
            stamp[x] = (uint32_t)v;
        }
        uint32_t c0 = d->vertex_sites[3 * v];
        if (c0 >= n || stamp[c0] != v) goto invalid;
        uint32_t c = nxt[c0];
        for (size_t t = 1; t + 1 < m; t++) {
            if (stamp[c] != v || nxt[c] == c0) goto invalid;
            tri[3 * nt] = c0;
            tri[3 * nt + 1] = c;
            tri[3 * nt + 2] = nxt[c];
            nt++;
            c = nxt[c];
        }
        if (stamp[c] != v || nxt[c] != c0) goto invalid;
        for (size_t k = lo; k < hi; k++) stamp[pairs[2 * k]] = EMPTY;
    }
    free(off);
    free(cur);
    free(pairs);
    free(nxt);
    free(stamp);
    *out = tri;
    *n_tri = nt;
    return VOR_OK;

invalid:
    st = VOR_EINVAL;
fail:
    free(off);
    free(cur);
    free(pairs);
    free(nxt);
    free(stamp);
    free(tri);
    return st;
}

/* Orders (site, neighbour) pairs by site, then neighbour. */
static int cmp_pair(const void *p, const void *q) {
    const uint32_t *a = p, *b = q;
    if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

/* A vertex of at most this many sites finds a site's neighbours by a
 * scan of its edges' pairs; a larger one sorts them. */
#define FAN_SCAN 16

/* The two neighbours *u, *w of site x on a vertex's circle, from its k
 * edges' site pairs at pr: k pairs as they are (k <= FAN_SCAN), or 2k
 * (site, neighbour) pairs sorted by cmp_pair. 1 if x has exactly two,
 * else 0. */
static int fan_nbrs(const uint32_t *pr, size_t k, uint32_t x, uint32_t *u,
                    uint32_t *w) {
    if (k <= FAN_SCAN) {
        uint32_t got[2];
        int c = 0;
        for (size_t j = 0; j < k; j++) {
            uint32_t a = pr[2 * j], b = pr[2 * j + 1], y;
            if (a == x)
                y = b;
            else if (b == x)
                y = a;
            else
                continue;
            if (c == 2) return 0;
            got[c++] = y;
        }
        if (c != 2) return 0;
        *u = got[0];
        *w = got[1];
        return 1;
    }
    size_t m = 2 * k, lo = 0, hi = m;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (pr[2 * mid] < x)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo + 1 >= m || pr[2 * lo] != x || pr[2 * lo + 2] != x ||
        (lo + 2 < m && pr[2 * lo + 4] == x))
        return 0;
    *u = pr[2 * lo + 1];
    *w = pr[2 * lo + 3];
    return 1;
}

/* The fan of a vertex of k > 3 sites, from the k edges at it (ids at
 * ed): each joins two sites next to each other on the vertex's circle,
 * so the edges' site pairs give each site its two neighbours (fan_nbrs;
 * scratch pr, 4k words); the smallest site s0 goes first and its
 * successor counter-clockwise is the neighbour q with exact orient2d(p,
 * s0, q) > 0 (the sites are in convex position). k - 2 triangles into
 * out. 0 on success, -1 if the edges name a site out of range or do not
 * make one cycle through s0. */
static int fan_of(const vor_diagram *d, const double *xy, const uint32_t *ed,
                  size_t k, uint32_t s0, uint32_t *pr, uint32_t *out) {
    for (size_t j = 0; j < k; j++) {
        const uint32_t *ab = d->edge_sites + 2 * (size_t)ed[j];
        if (ab[0] >= d->n_sites || ab[1] >= d->n_sites) return -1;
        if (k <= FAN_SCAN) {
            pr[2 * j] = ab[0];
            pr[2 * j + 1] = ab[1];
            continue;
        }
        pr[4 * j] = ab[0];
        pr[4 * j + 1] = ab[1];
        pr[4 * j + 2] = ab[1];
        pr[4 * j + 3] = ab[0];
    }
    if (k > FAN_SCAN) qsort(pr, 2 * k, 2 * sizeof *pr, cmp_pair);
    uint32_t u, w;
    if (!fan_nbrs(pr, k, s0, &u, &w) || u == w) return -1;
    int o = vor__orient2d_fast(xy + 2 * (size_t)u, xy + 2 * (size_t)s0,
                               xy + 2 * (size_t)w);
    if (o == 0) return -1;
    uint32_t prev = s0, cur = o > 0 ? w : u;
    for (size_t t = 0; t + 2 < k; t++) {
        if (!fan_nbrs(pr, k, cur, &u, &w)) return -1;
        uint32_t next = u == prev ? w : u;
        if ((u != prev && w != prev) || next == s0) return -1;
        out[3 * t] = s0;
        out[3 * t + 1] = cur;
        out[3 * t + 2] = next;
        prev = cur;
        cur = next;
    }
    /* the cycle closes at s0 after k sites */
    if (!fan_nbrs(pr, k, cur, &u, &w) || (u != s0 && w != s0)) return -1;
    return 0;
}

/* How many vertices ahead the triangles of degree-3 vertices prefetch
 * their second and third sites. */
#define TRI_AHEAD 32

/* A vertex of three sites is one triangle: its vertex_sites put
 * counter-clockwise, the smallest first, as the fan from the cells
 * starts, then the other two in the order the exact orient2d gives; a
 * vertex of more is fanned from its edges (fan_of). Every vertex has at
 * least three edge ends, so when they total 3 n_vertices (no four sites
 * cocircular: the usual case) none has more, and one pass in vertex
 * order does it, the second and third sites' points prefetched (the
 * first is nondecreasing). Otherwise the degrees are counted and the
 * edges of the vertices of more than three collected first. The result
 * is that of the cells' walk (vor__diagram_triangles_cells), which
 * defines it and which the checker uses. */
vor_status vor_diagram_triangles(const vor_diagram *d, const vor_sites *sites,
                                 uint32_t **out, size_t *n_tri) {
    if (!out || !n_tri) return VOR_EINVAL;
    *out = NULL;
    *n_tri = 0;
    if (!d || !sites || d->n_sites != sites->n) return VOR_EINVAL;
    const size_t nv = d->n_vertices, ne = d->n_edges, n = d->n_sites;
    if (nv == 0) return vor__diagram_triangles_cells(d, sites, out, n_tri);
    vor_status st = VOR_ENOMEM;
    uint32_t *deg = NULL, *hoff = NULL, *hedge = NULL, *pr = NULL, *tri = NULL;
    size_t ends = 0;
    for (size_t k = 0; k < 2 * ne; k++) ends += d->edge_ends[k] >= 0;
    size_t ntri = nv, kmax = 3;
    if (ends != 3 * nv) {
        /* degrees; then, for the vertices of more than three, their
         * edges (CSR: hoff[v] their first, filled from the end) */
        deg = calloc(nv, sizeof *deg);
        hoff = vor__alloc_large(nv + 1, sizeof *hoff);
        if (!deg || !hoff) goto done;
        for (size_t k = 0; k < 2 * ne; k++) {
            int32_t v = d->edge_ends[k];
            if (v < 0) continue;
            if ((size_t)v >= nv) goto invalid;
            deg[v]++;
        }
        size_t h = 0;
        ntri = 0;
        for (size_t v = 0; v < nv; v++) {
            if (deg[v] < 3) goto invalid;
            ntri += deg[v] - 2;
            if (deg[v] > 3) h += deg[v];
            if (deg[v] > kmax) kmax = deg[v];
            hoff[v] = (uint32_t)h;
        }
        hedge = vor__alloc_large(h ? h : 1, sizeof *hedge);
        pr = vor__alloc_large(4 * kmax, sizeof *pr);
        if (!hedge || !pr) goto done;
        for (size_t k = 0; k < 2 * ne; k++) {
            int32_t v = d->edge_ends[k];
            if (v >= 0 && deg[v] > 3) hedge[--hoff[v]] = (uint32_t)(k / 2);
        }
    }
    tri = vor__alloc_large(3 * ntri, sizeof *tri);
    if (!tri) goto done;
    const uint32_t *vs = d->vertex_sites;
    const double *xy = sites->xy;
    size_t nt = 0;
    for (size_t v = 0; v < nv; v++) {
        if (v + TRI_AHEAD < nv) {
            const uint32_t *a = vs + 3 * (v + TRI_AHEAD);
            if (a[1] < n && a[2] < n) {
                __builtin_prefetch(xy + 2 * (size_t)a[1]);
                __builtin_prefetch(xy + 2 * (size_t)a[2]);
            }
        }
        uint32_t a = vs[3 * v], b = vs[3 * v + 1], c = vs[3 * v + 2];
        if (a >= n || b >= n || c >= n) goto invalid;
        if (deg && deg[v] > 3) {
            if (fan_of(d, xy, hedge + hoff[v], deg[v], a, pr, tri + 3 * nt))
                goto invalid;
            nt += deg[v] - 2;
            continue;
        }
        int o = vor__orient2d_fast(xy + 2 * (size_t)a, xy + 2 * (size_t)b,
                                   xy + 2 * (size_t)c);
        if (o == 0) goto invalid;
        tri[3 * nt] = a;
        tri[3 * nt + 1] = o > 0 ? b : c;
        tri[3 * nt + 2] = o > 0 ? c : b;
        nt++;
    }
    *out = tri;
    *n_tri = nt;
    tri = NULL;
    st = VOR_OK;
    goto done; /* to free the scratch */

invalid:
    st = VOR_EINVAL;
done:
    free(deg);
    free(hoff);
    free(hedge);
    free(pr);
    free(tri);
    return st;
}

/* ---- comparing ----------------------------------------------------------- */

static int same(const void *p, const void *q, size_t bytes) {
    if (bytes == 0) return 1;
    if (!p || !q) return p == q;
    return memcmp(p, q, bytes) == 0;
}

int vor_diagram_equal(const vor_diagram *p, const vor_diagram *q) {
    if (p == q) return 1;
    if (!p || !q) return 0;
    if (p->n_sites != q->n_sites || p->n_vertices != q->n_vertices ||
        p->n_edges != q->n_edges || p->n_rays != q->n_rays)
        return 0;
    size_t n = p->n_sites, nv = p->n_vertices, ne = p->n_edges, nr = p->n_rays;
    if (!same(p->cell_start, q->cell_start, (n + 1) * sizeof(uint32_t)))
        return 0;
    size_t nc = p->cell_start ? p->cell_start[n] : 0;
    return same(p->vertex_xy, q->vertex_xy, 2 * nv * sizeof(double)) &&
           same(p->vertex_sites, q->vertex_sites, 3 * nv * sizeof(uint32_t)) &&
           same(p->edge_sites, q->edge_sites, 2 * ne * sizeof(uint32_t)) &&
           same(p->edge_ends, q->edge_ends, 2 * ne * sizeof(int32_t)) &&
           same(p->ray_edge, q->ray_edge, nr * sizeof(uint32_t)) &&
           same(p->ray_dir, q->ray_dir, 2 * nr * sizeof(double)) &&
           same(p->cell_edges, q->cell_edges, nc * sizeof(uint32_t)) &&
           same(p->cell_bounded, q->cell_bounded, n);
}
