/* oracle_voronoi.h -- a brute-force Voronoi diagram for small site sets,
 * independent of every algorithm in core/, for the diagram and checker
 * tests.
 *
 * Every triple of sites whose circle holds no site strictly inside (exact
 * vor_incircle against all sites) is a Voronoi vertex; all sites exactly on
 * that circle belong to it, and the vertex is recorded once, by its three
 * smallest sites. Its sites are put in counter-clockwise order along the
 * circle exactly: seen from one site of a circle, the others are in angular
 * order, so vor_orient2d compares them. Consecutive sites of a vertex are
 * joined by a Voronoi edge; a pair found at two vertices is a segment, at one
 * a ray (a hull edge). O(n^4): for n up to about 40.
 *
 * The raw output can be shuffled (vertex numbering, edge order, the order of
 * each edge's sites and ends) to exercise the builder's canonicalisation, and
 * can be turned into a Delaunay mesh by fanning every vertex's polygon from
 * a chosen corner, so that cocircular groups are triangulated in different
 * ways. Header-only; the functions are static inline so that a test may use
 * any subset.
 */
#ifndef VOR_TESTS_ORACLE_VORONOI_H
#define VOR_TESTS_ORACLE_VORONOI_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../../core/internal.h"
#include "../support/testsets.h"

typedef struct bf_voronoi {
    size_t nv;         /* vertices */
    uint32_t *vstart;  /* nv + 1: sites of vertex v are vsite[vstart[v]..] */
    uint32_t *vsite;   /* counter-clockwise, starting at the smallest site */
    size_t ne;         /* edges */
    uint32_t *edges;   /* 2 * ne: sites a < b */
    int32_t *ends;     /* 2 * ne: vertex ids (segment) or vertex, VOR_NONE */
} bf_voronoi;

static inline void bf_free(bf_voronoi *b) {
    free(b->vstart);
    free(b->vsite);
    free(b->edges);
    free(b->ends);
    memset(b, 0, sizeof *b);
}

/* Sorts sites c[0..m-1] of one circle counter-clockwise starting at c[0]
 * (insertion sort with the exact comparator described above). */
static inline void bf_sort_on_circle(const double *xy, uint32_t *c, size_t m) {
    const double *p0 = xy + 2 * (size_t)c[0];
    for (size_t i = 2; i < m; i++) {
        uint32_t x = c[i];
        size_t j = i;
        while (j > 1 &&
               vor_orient2d(p0, xy + 2 * (size_t)x, xy + 2 * (size_t)c[j - 1]) > 0) {
            c[j] = c[j - 1];
            j--;
        }
        c[j] = x;
    }
}

typedef struct bf_rec {
    uint32_t a, b;
    int32_t v;
} bf_rec;

static inline int bf_rec_cmp(const void *p, const void *q) {
    const bf_rec *x = p, *y = q;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    if (x->b != y->b) return x->b < y->b ? -1 : 1;
    return (x->v > y->v) - (x->v < y->v);
}

/* Brute-force diagram of s (n >= 3, not all collinear). 0 on success, -1 on
 * allocation failure or an inconsistency (a pair at three vertices). */
static inline int bf_voronoi_make(const vor_sites *s, bf_voronoi *out) {
    const size_t n = s->n;
    const double *xy = s->xy;
    memset(out, 0, sizeof *out);
    size_t cap_v = 16, cap_s = 64, nv = 0, ns = 0;
    uint32_t *vstart = malloc((cap_v + 1) * sizeof *vstart);
    uint32_t *vsite = malloc(cap_s * sizeof *vsite);
    uint32_t *on = malloc((n ? n : 1) * sizeof *on);
    if (!vstart || !vsite || !on) goto fail;
    vstart[0] = 0;
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t j = i + 1; j < n; j++)
            for (uint32_t k = j + 1; k < n; k++) {
                const double *a = xy + 2 * (size_t)i, *b = xy + 2 * (size_t)j,
                             *c = xy + 2 * (size_t)k;
                int o = vor_orient2d(a, b, c);
                if (o == 0) continue;
                if (o < 0) {
                    const double *t = b;
                    b = c;
                    c = t;
                }
                size_t m = 0;
                int empty = 1;
                on[m++] = i;
                on[m++] = j;
                on[m++] = k;
                for (uint32_t q = 0; q < n && empty; q++) {
                    if (q == i || q == j || q == k) continue;
                    int ic = vor_incircle(a, b, c, xy + 2 * (size_t)q);
                    if (ic > 0) empty = 0;
                    else if (ic == 0) {
                        if (q < k) empty = 0; /* recorded by a smaller triple */
                        else on[m++] = q;
                    }
                }
                if (!empty) continue;
                bf_sort_on_circle(xy, on, m);
                if (nv + 1 > cap_v) {
                    cap_v *= 2;
                    uint32_t *t = realloc(vstart, (cap_v + 1) * sizeof *t);
                    if (!t) goto fail;
                    vstart = t;
                }
                while (ns + m > cap_s) {
                    cap_s *= 2;
                    uint32_t *t = realloc(vsite, cap_s * sizeof *t);
                    if (!t) goto fail;
                    vsite = t;
                }
                memcpy(vsite + ns, on, m * sizeof *on);
                ns += m;
                vstart[++nv] = (uint32_t)ns;
            }
    /* q < k on the circle but not in {i, j}: if q < j or q < i the triple
     * (smallest three) is another one; the rule above keeps exactly the
     * triple of the three smallest sites, since any on-circle q < k that is
     * not i or j rejects this triple. */
    bf_rec *rec = malloc((ns ? ns : 1) * sizeof *rec);
    if (!rec) goto fail;
    size_t nrec = 0;
    for (size_t v = 0; v < nv; v++) {
        size_t lo = vstart[v], m = vstart[v + 1] - lo;
        for (size_t t = 0; t < m; t++) {
            uint32_t p = vsite[lo + t], q = vsite[lo + (t + 1) % m];
            rec[nrec].a = p < q ? p : q;
            rec[nrec].b = p < q ? q : p;
            rec[nrec].v = (int32_t)v;
            nrec++;
        }
    }
    qsort(rec, nrec, sizeof *rec, bf_rec_cmp);
    out->edges = malloc((nrec ? nrec : 1) * 2 * sizeof *out->edges);
    out->ends = malloc((nrec ? nrec : 1) * 2 * sizeof *out->ends);
    if (!out->edges || !out->ends) {
        free(rec);
        goto fail;
    }
    size_t ne = 0;
    for (size_t r = 0; r < nrec;) {
        size_t q = r + 1;
        while (q < nrec && rec[q].a == rec[r].a && rec[q].b == rec[r].b) q++;
        if (q - r > 2) {
            free(rec);
            goto fail;
        }
        out->edges[2 * ne] = rec[r].a;
        out->edges[2 * ne + 1] = rec[r].b;
        out->ends[2 * ne] = rec[r].v;
        out->ends[2 * ne + 1] = q - r == 2 ? rec[r + 1].v : VOR_NONE;
        ne++;
        r = q;
    }
    free(rec);
    free(on);
    out->nv = nv;
    out->vstart = vstart;
    out->vsite = vsite;
    out->ne = ne;
    return 0;
fail:
    free(vstart);
    free(vsite);
    free(on);
    bf_free(out);
    return -1;
}

/* Copies of the raw edges for vor__diagram_build (which takes ownership),
 * shuffled by seed (seed 0: as made). 0 on success, -1 on allocation
 * failure. */
static inline int bf_raw(const bf_voronoi *b, uint64_t seed, uint32_t **edges,
                         int32_t **ends) {
    size_t ne = b->ne, nv = b->nv;
    *edges = malloc((ne ? ne : 1) * 2 * sizeof **edges);
    *ends = malloc((ne ? ne : 1) * 2 * sizeof **ends);
    uint32_t *perm = malloc((nv ? nv : 1) * sizeof *perm);
    if (!*edges || !*ends || !perm) {
        free(*edges);
        free(*ends);
        free(perm);
        return -1;
    }
    memcpy(*edges, b->edges, ne * 2 * sizeof **edges);
    memcpy(*ends, b->ends, ne * 2 * sizeof **ends);
    for (size_t v = 0; v < nv; v++) perm[v] = (uint32_t)v;
    if (seed) {
        vt_rng r = {seed};
        for (size_t v = nv; v > 1; v--) {
            size_t j = (size_t)(vt_next(&r) % v);
            uint32_t t = perm[v - 1];
            perm[v - 1] = perm[j];
            perm[j] = t;
        }
        for (size_t k = 0; k < 2 * ne; k++)
            if ((*ends)[k] >= 0) (*ends)[k] = (int32_t)perm[(*ends)[k]];
        for (size_t e = ne; e > 1; e--) {
            size_t j = (size_t)(vt_next(&r) % e);
            for (int h = 0; h < 2; h++) {
                uint32_t t = (*edges)[2 * (e - 1) + h];
                (*edges)[2 * (e - 1) + h] = (*edges)[2 * j + h];
                (*edges)[2 * j + h] = t;
                int32_t u = (*ends)[2 * (e - 1) + h];
                (*ends)[2 * (e - 1) + h] = (*ends)[2 * j + h];
                (*ends)[2 * j + h] = u;
            }
        }
        for (size_t e = 0; e < ne; e++) {
            uint64_t x = vt_next(&r);
            if (x & 1) {
                uint32_t t = (*edges)[2 * e];
                (*edges)[2 * e] = (*edges)[2 * e + 1];
                (*edges)[2 * e + 1] = t;
            }
            if (x & 2) {
                int32_t u = (*ends)[2 * e];
                (*ends)[2 * e] = (*ends)[2 * e + 1];
                (*ends)[2 * e + 1] = u;
            }
        }
    }
    free(perm);
    return 0;
}

/* A Delaunay mesh dual to b: every vertex's polygon fanned from a corner
 * chosen by seed (seed 0: the first), twins matched by brute force. The
 * triangle order is shuffled too. 0 on success, -1 on allocation failure. */
static inline int bf_mesh(const bf_voronoi *b, uint64_t seed, vor__mesh *m) {
    size_t nt = 0;
    for (size_t v = 0; v < b->nv; v++) nt += b->vstart[v + 1] - b->vstart[v] - 2;
    memset(m, 0, sizeof *m);
    m->tri = malloc((nt ? nt : 1) * 3 * sizeof *m->tri);
    m->adj = malloc((nt ? nt : 1) * 3 * sizeof *m->adj);
    if (!m->tri || !m->adj) {
        vor__mesh_clear(m);
        return -1;
    }
    vt_rng r = {seed};
    size_t t = 0;
    for (size_t v = 0; v < b->nv; v++) {
        size_t lo = b->vstart[v], k = b->vstart[v + 1] - lo;
        size_t apex = seed ? (size_t)(vt_next(&r) % k) : 0;
        for (size_t q = 1; q + 1 < k; q++) {
            m->tri[3 * t] = b->vsite[lo + apex];
            m->tri[3 * t + 1] = b->vsite[lo + (apex + q) % k];
            m->tri[3 * t + 2] = b->vsite[lo + (apex + q + 1) % k];
            t++;
        }
    }
    if (seed) {
        for (size_t i = nt; i > 1; i--) {
            size_t j = (size_t)(vt_next(&r) % i);
            for (int h = 0; h < 3; h++) {
                uint32_t x = m->tri[3 * (i - 1) + h];
                m->tri[3 * (i - 1) + h] = m->tri[3 * j + h];
                m->tri[3 * j + h] = x;
            }
        }
    }
    for (size_t e = 0; e < 3 * nt; e++) {
        m->adj[e] = -1;
        uint32_t p = m->tri[e], q = m->tri[vor__next((uint32_t)e)];
        for (size_t f = 0; f < 3 * nt; f++)
            if (m->tri[f] == q && m->tri[vor__next((uint32_t)f)] == p)
                m->adj[e] = (int32_t)f;
    }
    m->n_tri = m->cap_tri = nt;
    return 0;
}

#endif /* VOR_TESTS_ORACLE_VORONOI_H */
