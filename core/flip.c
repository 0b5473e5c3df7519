/* flip.c -- Delaunay triangulation by Lawson flipping.
 *
 * Sites are inserted in spatial order (vor__insertion_order) into a
 * triangulation closed by ghost triangles (mesh.h). For each site p the walk
 * of vor__mesh_locate finds where it goes, then:
 *   - strictly inside a triangle: split it in three (1 -> 3);
 *   - on an edge (orient2d == 0): split the two triangles of that edge in
 *     four (2 -> 4); on a hull edge one of the two is a ghost, which splits
 *     into two ghosts the same way;
 *   - outside the hull: every hull edge p sees strictly becomes a triangle
 *     with p (its ghost is reused, the ghost vertex replaced by p), and two
 *     new ghosts close the hull from its ends to p. A hull edge that p sees
 *     only edge-on stays, so a site collinear with a hull edge becomes a
 *     collinear hull vertex instead of the apex of a flat triangle.
 * Then the edges opposite p are made Delaunay with an explicit stack: an
 * edge a->b of triangle (a, b, p) is flipped when the vertex d across it is
 * strictly inside the circle through a, b, p (exact vor_incircle); the two
 * new edges opposite p are pushed. Hull edges and ghosts are never flipped:
 * p is inside the hull by then, outside every ghost's half-plane.
 *
 * Invariant of the stack: each entry is the half-edge opposite p in a
 * distinct triangle around p, with p at prev(entry). A flip rewrites only
 * the triangle of the popped entry and one triangle without p, and leaves
 * the two new edges opposite p at the same two half-edge ids, so stacked
 * ids stay valid.
 *
 * Cost: expected O(1) walk steps and flips per site in spatial order,
 * O(n log n) with the sort; memory: the mesh (48 bytes per site), the
 * sites copied in insertion order (16), the order (4) and one small stack.
 *
 * Counts (vor_counts): predicate calls and flips in locals, added to the
 * state once per site; with a trace hook each insertion reports the
 * triangles it replaces and makes, and each flip its edges (in site
 * indices), before the mesh is rewritten.
 *
 * vor__flip hands the mesh as it stands (ghosts, local ids) to
 * vor__mesh_dual (mesh_dual.c), which reads the diagram off it in
 * insertion order; vor__flip_mesh finishes it for the checker and the
 * tests instead.
 */
#include <assert.h>
#include <stdlib.h>

#include "mesh.h"

#define XY(v) (xy + 2 * (size_t)(v))

typedef struct flipper {
    vor__mesh *m;
    const double *xy;
    vor__walk w;
    uint32_t *stack; /* edges to legalise */
    size_t n, cap;
    uint64_t created, flips; /* (vor_counts) */
    vor__run *run;
    const uint32_t *order; /* site index of each local vertex */
    uint32_t *steps;       /* with a trace: its scratch, tcap words */
    size_t tcap;
    uint32_t located[3];   /* with a trace: where location ended (sites) */
    int tracing;           /* run->trace is set */
} flipper;

/* Reserves room for k more stack entries. */
static int reserve(flipper *st, size_t k) {
    if (st->n + k <= st->cap)
        return 0;
    size_t cap = st->cap ? st->cap : 64;
    while (cap < st->n + k)
        cap *= 2;
    uint32_t *v = realloc(st->stack, cap * sizeof *v);
    if (!v)
        return -1;
    st->stack = v;
    st->cap = cap;
    return 0;
}

static inline void link(int32_t *adj, uint32_t e, uint32_t f) {
    adj[e] = (int32_t)f;
    adj[f] = (int32_t)e;
}

/* ---- Trace ----------------------------------------------------------------
 * With a trace, each insertion reports the triangles it replaces (written
 * to st->steps before the split or the hull fan rewrites them) and those
 * it makes, then each flip. */

static inline uint32_t site_of(const flipper *st, uint32_t v) {
    return v == VOR__GHOST ? VOR_INFINITE : st->order[v];
}

/* Room for k triangles in the trace's scratch: the lower half holds the
 * cavity's site numbers (3 k) and then the star's slots (k), the upper
 * half the star's site numbers. -1 if out of memory. */
static int trace_reserve(flipper *st, size_t k) {
    if (8 * k <= st->tcap)
        return 0;
    size_t cap = 8 * k + 64;
    uint32_t *v = realloc(st->steps, cap * sizeof *v);
    if (!v)
        return -1;
    st->steps = v;
    st->tcap = cap;
    return 0;
}

/* Writes triangle t as site numbers to out[0..2]. */
static void put_triangle(const flipper *st, uint32_t *out, uint32_t t) {
    const uint32_t *v = st->m->tri + 3 * (size_t)t;
    for (int k = 0; k < 3; k++) out[k] = site_of(st, v[k]);
}

/* The counts so far: the insertion order's (in run) and this build's,
 * with the legalisation's tests and flips not yet added to st. */
static void counts_now(const flipper *st, uint64_t tests, uint64_t flips,
                       vor_counts *c) {
    *c = st->run->counts;
    c->walk_steps += st->w.steps;
    c->orient2d += st->w.orient2d;
    c->incircle += st->w.incircle + tests;
    c->exact += st->w.exact;
    c->flips += st->flips + flips;
    c->triangles_created += st->created + 2 * (st->flips + flips);
}

/* Notes where location ended (triangle t, p on its half-edge on_edge or
 * -1) and the triangles a split would replace, before it rewrites them.
 * -1 if out of memory. */
VOR__COLD static int trace_located(flipper *st, uint32_t t, int32_t on_edge) {
    if (trace_reserve(st, 4))
        return -1;
    put_triangle(st, st->located, t);
    put_triangle(st, st->steps, t);
    if (on_edge >= 0)
        put_triangle(st, st->steps + 3, (uint32_t)st->m->adj[on_edge] / 3);
    return 0;
}

/* Reports the INSERT step of p: the cavity of ncav triangles already in
 * st->steps, the star the triangles star[0..nstar-1]. */
VOR__COLD static void trace_insert(flipper *st, uint32_t p, vor_split split,
                                   const uint32_t *edge, size_t ncav,
                                   const uint32_t *star, size_t nstar) {
    uint32_t *out = st->steps + st->tcap / 2;
    for (size_t i = 0; i < nstar; i++) put_triangle(st, out + 3 * i, star[i]);
    vor_counts c;
    counts_now(st, 0, 0, &c);
    vor_step step;
    vor__step_init(&step, VOR_STEP_INSERT);
    step.counts = &c;
    step.site = st->order[p];
    for (int k = 0; k < 3; k++) step.tri[k] = st->located[k];
    step.split = split;
    if (edge) {
        step.edge[0] = site_of(st, edge[0]);
        step.edge[1] = site_of(st, edge[1]);
    }
    step.cavity = st->steps;
    step.n_cavity = ncav;
    step.star = out;
    step.n_star = nstar;
    st->run->trace(st->run->trace_ctx, &step);
}

/* 1 -> 3: p strictly inside triangle t = (a, b, c).
 *
 *              c                 t  = (a, b, p)  keeps edge a->b
 *            / | \               n1 = (b, c, p)  takes edge b->c
 *           / n2  \              n2 = (c, a, p)  takes edge c->a
 *          /  _p_  \
 *         / _/   \_ \  n1        inner twins: b->p / p->b (t, n1),
 *        /_/   t   \_\           c->p / p->c (n1, n2), a->p / p->a (n2, t)
 *       a ----------- b
 */
static void split3(flipper *st, uint32_t t, uint32_t p) {
    vor__mesh *m = st->m;
    uint32_t *tri = m->tri;
    int32_t *adj = m->adj;
    uint32_t n1 = (uint32_t)m->n_tri, n2 = n1 + 1;
    m->n_tri += 2;
    uint32_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
    int32_t bc = adj[3 * t + 1], ca = adj[3 * t + 2];
    tri[3 * t + 2] = p;
    tri[3 * n1] = b;
    tri[3 * n1 + 1] = c;
    tri[3 * n1 + 2] = p;
    tri[3 * n2] = c;
    tri[3 * n2 + 1] = a;
    tri[3 * n2 + 2] = p;
    link(adj, 3 * n1, (uint32_t)bc);
    link(adj, 3 * n2, (uint32_t)ca);
    link(adj, 3 * t + 1, 3 * n1 + 2);
    link(adj, 3 * n1 + 1, 3 * n2 + 2);
    link(adj, 3 * n2 + 1, 3 * t + 2);
    st->stack[st->n++] = 3 * t;
    st->stack[st->n++] = 3 * n1;
    st->stack[st->n++] = 3 * n2;
    st->w.tri = t;
    st->created += 3;
    if (st->tracing) {
        const uint32_t star[3] = {t, n1, n2};
        trace_insert(st, p, VOR_SPLIT_TRIANGLE, NULL, 1, star, 3);
    }
}

/* 2 -> 4: p on edge e = a->b of triangle t = (a, b, c); across it is
 * f = b->a of triangle u = (b, a, d), d possibly the ghost vertex.
 *
 *              c                      t  = (p, b, c)  at e, next e, prev e
 *            / | \                    t2 = (a, p, c)  new
 *           / t2|t \                  u  = (p, a, d)  at f, next f, prev f
 *          a----p----b                u2 = (b, p, d)  new
 *           \ u | u2/
 *            \  |  /                  edges opposite p: b->c (next e),
 *              d                      c->a (3t2+2), a->d (next f), d->b
 *                                     (3u2+2); the last two are not
 *                                     pushed when d is the ghost vertex.
 */
static void split4(flipper *st, uint32_t e, uint32_t p) {
    vor__mesh *m = st->m;
    uint32_t *tri = m->tri;
    int32_t *adj = m->adj;
    uint32_t f = (uint32_t)adj[e];
    uint32_t t2 = (uint32_t)m->n_tri, u2 = t2 + 1;
    m->n_tri += 2;
    uint32_t ne = vor__next(e), pe = vor__prev(e);
    uint32_t nf = vor__next(f), pf = vor__prev(f);
    uint32_t a = tri[e], b = tri[ne], c = tri[pe], d = tri[pf];
    int32_t ca = adj[pe], db = adj[pf];
    tri[e] = p;
    tri[f] = p;
    tri[3 * t2] = a;
    tri[3 * t2 + 1] = p;
    tri[3 * t2 + 2] = c;
    tri[3 * u2] = b;
    tri[3 * u2 + 1] = p;
    tri[3 * u2 + 2] = d;
    link(adj, 3 * t2 + 2, (uint32_t)ca);
    link(adj, 3 * u2 + 2, (uint32_t)db);
    link(adj, e, 3 * u2);
    link(adj, pe, 3 * t2 + 1);
    link(adj, f, 3 * t2);
    link(adj, pf, 3 * u2 + 1);
    (void)b;
    st->stack[st->n++] = ne;
    st->stack[st->n++] = 3 * t2 + 2;
    if (d != VOR__GHOST) {
        st->stack[st->n++] = nf;
        st->stack[st->n++] = 3 * u2 + 2;
    }
    st->w.tri = e / 3;
    st->created += 4;
    if (st->tracing) {
        const uint32_t star[4] = {e / 3, t2, f / 3, u2}, edge[2] = {a, b};
        trace_insert(st, p, VOR_SPLIT_EDGE, edge, 2, star, 4);
    }
}

/* p strictly outside the hull edge of ghost g.
 *
 *        p                 the hull edges v0->v1 ... v(k-1)->vk that p
 *      / | \               sees strictly: their ghosts become (vi, vi+1, p)
 *     /  |  \              (the ghost vertex replaced by p, all twins
 *   v0---v1--v2            unchanged); new ghosts G0 = (v0, p, GHOST) and
 *  (interior below)        G1 = (p, vk, GHOST) sit between the fan and the
 *                          ghosts of the edges ending at v0 and leaving vk.
 *
 * Around the ghost vertex the ghosts form a ring: for the hull edge e of a
 * ghost (ghost vertex at prev(e)), the previous ghost's hull edge is
 * prev(adj[prev(e)]) and the next one's next(adj[next(e)]).
 */
static vor_status hull_insert(flipper *st, uint32_t g, uint32_t p) {
    vor__mesh *m = st->m;
    uint32_t *tri = m->tri;
    int32_t *adj = m->adj;
    const double *xy = st->xy;
    const double *pp = XY(p);
    uint32_t e = 3 * g;
    while (tri[e] == VOR__GHOST || tri[vor__next(e)] == VOR__GHOST)
        e++;
    uint32_t first = e, last = e;
    size_t k = 1;
    for (;;) {
        uint32_t pe = vor__prev((uint32_t)adj[vor__prev(first)]);
        st->w.orient2d++;
        if (vor__orient2d_fast_n(XY(tri[pe]), XY(tri[vor__next(pe)]), pp,
                                 &st->w.exact) <= 0)
            break;
        first = pe;
        k++;
    }
    for (;;) {
        uint32_t ne = vor__next((uint32_t)adj[vor__next(last)]);
        st->w.orient2d++;
        if (vor__orient2d_fast_n(XY(tri[ne]), XY(tri[vor__next(ne)]), pp,
                                 &st->w.exact) <= 0)
            break;
        last = ne;
        k++;
    }
    if (reserve(st, k))
        return VOR_ENOMEM;
    const int tracing = st->tracing;
    if (tracing) {
        if (trace_reserve(st, k + 2))
            return VOR_ENOMEM;
        size_t i = 0;
        for (e = first;; e = vor__next((uint32_t)adj[vor__next(e)])) {
            put_triangle(st, st->steps + 3 * i++, e / 3);
            if (e == last)
                break;
        }
    }
    uint32_t v0 = tri[first], vk = tri[vor__next(last)];
    uint32_t in0 = vor__prev(first), outk = vor__next(last);
    int32_t x0 = adj[in0], xk = adj[outk];
    for (e = first;; e = vor__next((uint32_t)adj[vor__next(e)])) {
        tri[vor__prev(e)] = p;
        st->stack[st->n++] = e;
        if (e == last)
            break;
    }
    uint32_t g0 = (uint32_t)m->n_tri, g1 = g0 + 1;
    m->n_tri += 2;
    tri[3 * g0] = v0;
    tri[3 * g0 + 1] = p;
    tri[3 * g0 + 2] = VOR__GHOST;
    tri[3 * g1] = p;
    tri[3 * g1 + 1] = vk;
    tri[3 * g1 + 2] = VOR__GHOST;
    link(adj, 3 * g0, in0);
    link(adj, 3 * g0 + 1, 3 * g1 + 2);
    link(adj, 3 * g0 + 2, (uint32_t)x0);
    link(adj, 3 * g1, outk);
    link(adj, 3 * g1 + 1, (uint32_t)xk);
    /* the next walk starts at p's ghost: the next site of a curve is
     * outside the hull there (vor__mesh_locate) */
    st->w.tri = g0;
    st->created += k + 2;
    if (tracing) {
        /* the fan's triangles (their slots are the ghosts'), then g0, g1 */
        uint32_t *star = st->steps + 3 * (k + 2);
        size_t i = 0;
        for (e = first;; e = vor__next((uint32_t)adj[vor__next(e)])) {
            star[i++] = e / 3;
            if (e == last)
                break;
        }
        star[i++] = g0;
        star[i++] = g1;
        trace_insert(st, p, VOR_SPLIT_HULL, NULL, k, star, k + 2);
    }
    return VOR_OK;
}

/* Flips edge e = a->b of T = (a, b, p) (p at prev(e)) with f = b->a of
 * U = (b, a, d):
 *
 *          p                     p          T' = (a, d, p) at e, next e,
 *        / | \                 / | \             prev e (p->a unchanged)
 *       /  T  \               / T'|U'\      U' = (d, b, p) at f, next f,
 *      a ----- b     =>      a    |   b          prev f
 *       \  U  /               \   |  /      edges opposite p stay at e
 *        \   /                 \  | /       (a->d) and f (d->b)
 *          d                     d
 */
static void flip(int32_t *adj, uint32_t *tri, uint32_t e, uint32_t f,
                 uint32_t p) {
    uint32_t ne = vor__next(e);
    uint32_t nf = vor__next(f), pf = vor__prev(f);
    uint32_t b = tri[ne], d = tri[pf];
    int32_t x1 = adj[nf]; /* across a->d */
    int32_t x2 = adj[pf]; /* across d->b */
    int32_t y1 = adj[ne]; /* across b->p */
    tri[ne] = d;
    tri[f] = d;
    tri[nf] = b;
    tri[pf] = p;
    link(adj, e, (uint32_t)x1);
    link(adj, f, (uint32_t)x2);
    link(adj, nf, (uint32_t)y1);
    link(adj, ne, pf);
}

/* Reports the flip of edge a-b of (a, b, p) to p-d; tests and flips are
 * legalise's so far. */
VOR__COLD static void trace_flip(flipper *st, uint32_t a, uint32_t b,
                                 uint32_t p, uint32_t d, uint64_t tests,
                                 uint64_t flips) {
    vor_counts c;
    counts_now(st, tests, flips, &c);
    vor_step step;
    vor__step_init(&step, VOR_STEP_FLIP);
    step.counts = &c;
    step.tri[0] = step.edge[0] = st->order[a];
    step.tri[1] = step.edge[1] = st->order[b];
    step.tri[2] = step.added[0] = st->order[p];
    step.added[1] = st->order[d];
    st->run->trace(st->run->trace_ctx, &step);
}

/* Pops edges until the stack is empty; each flip pushes two. Stacked
 * edges have finite ends (split4 leaves out those of the ghost vertex);
 * an edge whose far triangle is a ghost is a hull edge and stays. */
static vor_status legalise(flipper *st, uint32_t p) {
    uint32_t *tri = st->m->tri;
    int32_t *adj = st->m->adj;
    const double *xy = st->xy;
    const double *pp = XY(p);
    uint32_t *stack = st->stack;
    size_t n = st->n;
    uint64_t tests = 0, flips = 0;
    while (n) {
        uint32_t e = stack[--n];
        uint32_t f = (uint32_t)adj[e];
        uint32_t d = tri[vor__prev(f)];
        assert(tri[vor__prev(e)] == p);
        if (d == VOR__GHOST)
            continue;
        uint32_t a = tri[e], b = tri[vor__next(e)];
        assert(a != VOR__GHOST && b != VOR__GHOST);
        tests++;
        if (vor__incircle_local_n(XY(a), XY(b), pp, XY(d), &st->w.exact,
                                  &st->w.cocircular) <= 0)
            continue;
        if (n + 2 > st->cap) {
            st->n = n;
            if (reserve(st, 2)) {
                st->w.incircle += tests;
                st->flips += flips;
                return VOR_ENOMEM;
            }
            stack = st->stack;
        }
        flip(adj, tri, e, f, p);
        flips++;
        if (st->tracing)
            trace_flip(st, a, b, p, d, tests, flips);
        stack[n++] = e;
        stack[n++] = f;
    }
    st->n = 0;
    st->w.incircle += tests;
    st->flips += flips;
    return VOR_OK;
}

static vor_status insert(flipper *st, uint32_t p) {
    vor__mesh *m = st->m;
    int32_t on_edge;
    assert(m->n_tri + 2 <= m->cap_tri);
    uint32_t t = vor__mesh_locate(m, st->xy, p, &st->w, &on_edge);
    if (on_edge >= 0 && vor__mesh_at_vertex(m, st->xy, p, (uint32_t)on_edge))
        return VOR_EINVAL; /* a repeated site */
    if (st->tracing && trace_located(st, t, on_edge))
        return VOR_ENOMEM;
    if (vor__mesh_is_ghost(m->tri, t)) {
        if (hull_insert(st, t, p))
            return VOR_ENOMEM;
    } else {
        if (reserve(st, 4))
            return VOR_ENOMEM;
        if (on_edge < 0)
            split3(st, t, p);
        else
            split4(st, (uint32_t)on_edge, p);
    }
    return legalise(st, p);
}

/* The ghost-closed mesh in local ids (mesh.h), *pxy the coordinates in
 * insertion order; on error nothing is left allocated. */
static vor_status build(const vor_sites *s, uint32_t *order, vor__mesh *m,
                        double **pxy, vor__run *run) {
    double *xy = *pxy; /* a block for the coordinates, if any */
    flipper st = {.m = m, .run = run, .order = order,
                  .tracing = run->trace != NULL};
    *pxy = NULL;
    vor_status r = vor__mesh_begin(m, s->xy, s->n, order, &xy, &st.w);
    if (r != VOR_OK)
        return r;
    st.xy = xy;
    st.created = 4; /* the first triangle and its ghosts */
    if (run->trace) {
        vor_counts c;
        counts_now(&st, 0, 0, &c);
        vor__mesh_trace_begin(m, order, s->n, run, &c);
    }
    for (uint32_t v = 3; v < s->n && r == VOR_OK; v++)
        r = vor__stop_now(run, v - 3) ? VOR_ESTOPPED : insert(&st, v);
    vor__walk_count(&st.w, run);
    run->counts.triangles_created += st.created + 2 * st.flips;
    run->counts.flips += st.flips;
    if (r == VOR_OK)
        vor__trace_end(run);
    free(st.stack);
    free(st.steps);
    if (r != VOR_OK) {
        free(xy);
        vor__mesh_clear(m);
        return r;
    }
    *pxy = xy;
    return VOR_OK;
}

vor_status vor__flip_mesh_ordered(const vor_sites *s, uint32_t *order,
                                  vor__mesh *m) {
    return vor__mesh_build_ordered(s, build, order, m);
}

vor_status vor__flip_mesh(const vor_sites *s, vor__mesh *m) {
    return vor__mesh_build(s, build, m);
}

vor_status vor__flip_run(const vor_sites *s, vor__run *run,
                         vor_diagram **out) {
    return vor__mesh_voronoi(s, build, run, out);
}

vor_status vor__flip(const vor_sites *s, vor_diagram **out) {
    vor__run run = {0};
    return vor__mesh_voronoi(s, build, &run, out);
}
