/* bowyer_watson.c -- Delaunay triangulation by Bowyer-Watson insertion.
 *
 * Sites are inserted in spatial order (vor__insertion_order: Hilbert curve,
 * biased randomised rounds) into a triangulation closed by ghost triangles
 * (mesh.h). For each site p: a walk from the previous insertion finds one
 * triangle whose circumcircle contains p; a search over neighbours collects
 * the cavity, all triangles whose circumcircle strictly contains p (exact
 * vor_incircle; for ghosts the half-plane rule of mesh.h); the cavity is
 * replaced by the star of p over its boundary.
 *
 * The cavity is a disk, star-shaped from p, with all its vertices on its
 * boundary, so its dual graph is a tree. The search is a tour around that
 * tree, which meets the boundary edges in counter-clockwise order around
 * the cavity, so the new triangles link to their neighbours in the star by
 * position alone; the only cavity triangle seen again is the one the tour
 * came from, so a mark per cavity triangle replaces a stack. A cavity of k
 * triangles has k + 2 boundary edges; the new triangles take the k freed
 * slots plus two at the end, so the mesh stays compact and the arrays never
 * grow.
 *
 * Cost: expected O(1) walk steps and cavity size per site in spatial order,
 * O(n log n) with the sort; memory: the mesh (48 bytes per site), the
 * sites copied in insertion order (16), the order (4) and two small arrays
 * for the cavity and its boundary.
 *
 * Counts (vor_counts): predicate calls in locals, added to the walk's per
 * site, triangles made and removed in the state; with a trace hook each
 * insertion reports its cavity (each triangle written down as the search
 * marks it) and its star, in site indices (mesh.h, vor__run).
 *
 * vor__bowyer_watson hands the mesh as it stands (ghosts, local ids) to
 * vor__mesh_dual (mesh_dual.c), which reads the diagram off it in
 * insertion order; vor__bowyer_watson_mesh finishes it for the checker and
 * the tests instead.
 */
#include <assert.h>
#include <stdlib.h>

#include "mesh.h"

#define XY(v) (xy + 2 * (size_t)(v))

/* Construction state. The scratch arrays share one capacity, which
 * starts at 256 and doubles when a cavity needs more; so does the trace's
 * scratch, when there is a trace. */
typedef struct bw {
    vor__mesh *m;
    const double *xy;
    vor__walk w;
    uint32_t *cav; /* cavity triangles in the order found: the free slots */
    uint32_t *bnd; /* twins of the boundary edges, counter-clockwise */
    uint32_t *lost; /* the vertex each cavity triangle's mark replaced */
    size_t cap;
    uint64_t created, removed; /* triangles, ghosts included (vor_counts) */
    vor__run *run;
    const uint32_t *order; /* site index of each local vertex */
    uint32_t *steps;       /* with a trace: 6 cap site numbers, the cavity's
                              triangles then the star's */
} bw;

/* Marks a cavity triangle during the search, in its first vertex slot
 * (the vertices of cavity triangles are not needed once they are known to
 * conflict: the new triangles take theirs from the boundary). */
#define MARK (VOR__GHOST - 1)

/* Doubles the scratch capacity. -1 if out of memory (an array that did
 * grow is kept; cap is unchanged). */
static int grow(bw *st) {
    size_t cap = st->cap ? 2 * st->cap : 256;
    uint32_t *v;
    if (!(v = realloc(st->cav, cap * sizeof *v)))
        return -1;
    st->cav = v;
    if (!(v = realloc(st->bnd, cap * sizeof *v)))
        return -1;
    st->bnd = v;
    if (!(v = realloc(st->lost, cap * sizeof *v)))
        return -1;
    st->lost = v;
    if (st->run->trace) {
        if (!(v = realloc(st->steps, 6 * cap * sizeof *v)))
            return -1;
        st->steps = v;
    }
    st->cap = cap;
    return 0;
}

/* Site index of local vertex v, VOR_INFINITE for the ghost. */
static inline uint32_t site_of(const bw *st, uint32_t v) {
    return v == VOR__GHOST ? VOR_INFINITE : st->order[v];
}

/* Writes triangle a, b, c (local ids) as site numbers to out[0..2]. */
VOR__COLD static void put_sites(const bw *st, uint32_t *out, uint32_t a, uint32_t b,
                      uint32_t c) {
    out[0] = site_of(st, a);
    out[1] = site_of(st, b);
    out[2] = site_of(st, c);
}

/* The counts so far: the insertion order's (in run) and this build's. */
static void counts_now(const bw *st, vor_counts *c) {
    *c = st->run->counts;
    c->walk_steps += st->w.steps;
    c->orient2d += st->w.orient2d;
    c->incircle += st->w.incircle;
    c->exact += st->w.exact;
    c->triangles_created += st->created;
    c->cavity_triangles += st->removed;
}

/* Writes the cavity's ncav triangles, cav[0..ncav-1], to st->steps as
 * they were before the search marked them (their first vertex is in
 * st->lost), before the star overwrites them. */
VOR__COLD static void trace_cavity(bw *st, const uint32_t *cav, size_t ncav) {
    const uint32_t *tri = st->m->tri;
    for (size_t i = 0; i < ncav; i++) {
        const uint32_t *v = tri + 3 * (size_t)cav[i];
        put_sites(st, st->steps + 3 * i, st->lost[i], v[1], v[2]);
    }
}

/* The INSERT step of vertex p: the cavity's ncav triangles are in
 * st->steps (trace_cavity), the star is in the slots cav[0..nb-1] now. */
VOR__COLD static void trace_insert(bw *st, uint32_t p, const uint32_t *cav,
                                   size_t ncav, size_t nb) {
    const uint32_t *tri = st->m->tri;
    uint32_t *star = st->steps + 3 * st->cap;
    for (size_t i = 0; i < nb; i++) {
        const uint32_t *v = tri + 3 * (size_t)cav[i];
        put_sites(st, star + 3 * i, v[0], v[1], v[2]);
    }
    vor_counts c;
    counts_now(st, &c);
    vor_step step;
    vor__step_init(&step, VOR_STEP_INSERT);
    step.counts = &c;
    step.site = st->order[p];
    for (int k = 0; k < 3; k++) step.tri[k] = st->steps[k];
    step.cavity = st->steps;
    step.n_cavity = ncav;
    step.star = star;
    step.n_star = nb;
    st->run->trace(st->run->trace_ctx, &step);
}

/* Inserts vertex p. VOR_ENOMEM if the scratch arrays cannot grow; the
 * mesh is then inconsistent and only good for vor__mesh_clear. VOR_EINVAL
 * if p repeats a vertex (the mesh untouched). */
static vor_status insert(bw *st, uint32_t p) {
    vor__mesh *m = st->m;
    uint32_t *tri = m->tri;
    int32_t *adj = m->adj;
    const double *xy = st->xy;
    const double *pp = XY(p);
    int32_t on_edge;
    uint32_t t0 = vor__mesh_locate(m, xy, p, &st->w, &on_edge);
    /* a triangle with p on an edge is in conflict too; p at a vertex is
     * a repeated site */
    if (on_edge >= 0 && vor__mesh_at_vertex(m, xy, p, (uint32_t)on_edge))
        return VOR_EINVAL;
    const int tracing = st->run->trace != NULL;
    uint64_t ghosts = 0; /* ghost tests, orientation only */

    /* Cavity search: a walk around the boundary of the cavity, which is a
     * tree of triangles (a depth-first tour without a stack). Being at
     * half-edge e of a cavity triangle means: look across e. Across it is
     *   - a marked triangle: the one we came from; go back into it and
     *     on to the edge after the one we left it by: e = next(adj[e]);
     *   - a triangle whose circumcircle strictly contains p (ghost rule of
     *     mesh.h for ghosts): mark it, record it, go in and on to the edge
     *     after the one we entered by: e = next(adj[e]);
     *   - otherwise a boundary edge: record its twin, e = next(e).
     * The tour visits the boundary counter-clockwise and ends when it is
     * back at the first edge of the first triangle.
     *
     *          ____________             e0 = 3 t0; the tour goes round
     *         /\    u    /\            each triangle counter-clockwise,
     *        /  \   ^   /  \           dives into u through its twin
     *       /    \  | e/    \          edge and comes back out of u by
     *      /______\ | /______\         the same edge
     *             t0
     */
    uint32_t *cav = st->cav, *bnd = st->bnd;
    /* room: each step adds at most one entry to cav or bnd, and the star
     * below adds two to cav; one test covers both arrays */
    size_t room = st->cap - 3, ncav = 1, nb = 0;
    cav[0] = t0;
    uint32_t *lost = st->lost; /* for the trace, whose branch stays out of
                                  the loop: a store is cheaper */
    lost[0] = tri[3 * t0];
    tri[3 * t0] = MARK;
    uint32_t e0 = 3 * t0, e = e0;
    do {
        if (ncav + nb > room) {
            if (grow(st))
                return VOR_ENOMEM;
            cav = st->cav;
            bnd = st->bnd;
            lost = st->lost;
            room = st->cap - 3;
        }
        uint32_t f = (uint32_t)adj[e];
        uint32_t base = f / 3 * 3, k = f - base;
        uint32_t nf = k == 2 ? base : f + 1;
        if (tri[base] == MARK) { /* back into the triangle we came from */
            e = nf;
            continue;
        }
        uint32_t a = tri[f], b = tri[nf], c = tri[base + (k == 0 ? 2 : k - 1)];
        int in;
        if (((a | b | c) >> 30) == 0) {
            /* no vertex is the ghost: site ids are < 2^30 (mesh.h) */
            in = vor__incircle_local_n(XY(a), XY(b), XY(c), pp, &st->w.exact,
                                       &st->w.cocircular) > 0;
        } else {
            if (c == VOR__GHOST) {
                in = vor__ghost_conflict_n(XY(a), XY(b), pp, &st->w.exact);
            } else if (a == VOR__GHOST) {
                in = vor__ghost_conflict_n(XY(b), XY(c), pp, &st->w.exact);
            } else {
                in = vor__ghost_conflict_n(XY(c), XY(a), pp, &st->w.exact);
            }
            ghosts++;
        }
        if (in) {
            lost[ncav] = tri[base];
            tri[base] = MARK;
            cav[ncav++] = base / 3;
            e = nf;
        } else {
            bnd[nb++] = f;
            e = vor__next(e);
        }
    } while (e != e0);

    /* The star. Boundary edge i, seen from outside as f = b->a, gives the
     * new triangle (a, b, p) in slot t_i:
     *
     *              p
     *            / | \            t_i:     a -> b -> p
     *      t_i  /  |  \  t_i+1    3t_i+1 (b->p) is the twin of
     *          /   |   \          3t_i+1 + 2 (p->b) in t_i+1
     *         a----b----c
     *          (outside)
     *
     * The cavity's slots are reused and two come from the end of the
     * arrays: a disk of k triangles has k + 2 boundary edges. */
    assert(nb == ncav + 2);
    assert(m->n_tri + 2 <= m->cap_tri);
    if (tracing)
        trace_cavity(st, cav, ncav);
    cav[ncav++] = (uint32_t)m->n_tri;
    cav[ncav++] = (uint32_t)m->n_tri + 1;
    m->n_tri += 2;
    uint32_t t = cav[0], start = cav[0];
    for (size_t i = 0; i < nb; i++) {
        uint32_t f = bnd[i];
        uint32_t a = tri[vor__next(f)], b = tri[f];
        uint32_t u = cav[i + 1 == nb ? 0 : i + 1];
        assert(tri[vor__next(bnd[i + 1 == nb ? 0 : i + 1])] == b);
        tri[3 * t] = a;
        tri[3 * t + 1] = b;
        tri[3 * t + 2] = p;
        adj[3 * t] = (int32_t)f;
        adj[f] = (int32_t)(3 * t);
        adj[3 * t + 1] = (int32_t)(3 * u + 2);
        adj[3 * u + 2] = (int32_t)(3 * t + 1);
        if (a == VOR__GHOST || b == VOR__GHOST) start = t; /* p is on the hull */
        t = u;
    }
    /* the next walk starts beside p, at one of its ghosts if p is on the
     * hull: the next site of a curve is outside the hull there */
    st->w.tri = start;
    /* every triangle met but t0 and the marked ones was tested: the
     * cavity's ncav - 3 found ones and the nb boundary ones */
    st->w.incircle += ncav - 3 + nb - ghosts;
    st->w.orient2d += ghosts;
    st->removed += ncav - 2;
    st->created += nb;
    if (tracing)
        trace_insert(st, p, cav, ncav - 2, nb);
    return VOR_OK;
}

/* The ghost-closed mesh in local ids (mesh.h), *pxy the coordinates in
 * insertion order; on error nothing is left allocated. */
static vor_status build(const vor_sites *s, uint32_t *order, vor__mesh *m,
                        double **pxy, vor__run *run) {
    double *xy = *pxy; /* a block for the coordinates, if any */
    bw st = {.m = m, .run = run, .order = order};
    *pxy = NULL;
    if (grow(&st)) {
        free(xy);
        free(st.cav);
        free(st.bnd);
        free(st.lost);
        free(st.steps);
        return VOR_ENOMEM;
    }
    vor_status r = vor__mesh_begin(m, s->xy, s->n, order, &xy, &st.w);
    if (r != VOR_OK) {
        free(st.cav);
        free(st.bnd);
        free(st.lost);
        free(st.steps);
        return r;
    }
    st.xy = xy;
    st.created = 4; /* the first triangle and its ghosts */
    if (run->trace) {
        vor_counts c;
        counts_now(&st, &c);
        vor__mesh_trace_begin(m, order, s->n, run, &c);
    }
    for (uint32_t v = 3; v < s->n && r == VOR_OK; v++)
        r = vor__stop_now(run, v - 3) ? VOR_ESTOPPED : insert(&st, v);
    vor__walk_count(&st.w, run);
    run->counts.triangles_created += st.created;
    run->counts.cavity_triangles += st.removed;
    if (r == VOR_OK)
        vor__trace_end(run);
    free(st.cav);
    free(st.bnd);
    free(st.lost);
    free(st.steps);
    if (r != VOR_OK) {
        free(xy);
        vor__mesh_clear(m);
        return r;
    }
    *pxy = xy;
    return VOR_OK;
}

vor_status vor__bowyer_watson_mesh_ordered(const vor_sites *s,
                                           uint32_t *order, vor__mesh *m) {
    return vor__mesh_build_ordered(s, build, order, m);
}

vor_status vor__bowyer_watson_mesh(const vor_sites *s, vor__mesh *m) {
    return vor__mesh_build(s, build, m);
}

vor_status vor__bowyer_watson_run(const vor_sites *s, vor__run *run,
                                  vor_diagram **out) {
    return vor__mesh_voronoi(s, build, run, out);
}

vor_status vor__bowyer_watson(const vor_sites *s, vor_diagram **out) {
    vor__run run = {0};
    return vor__mesh_voronoi(s, build, &run, out);
}
