/* bowyer_watson.c -- Delaunay triangulation by Bowyer-Watson insertion.
 *
 * Sites are inserted in spatial order (vor__insertion_order: Hilbert curve,
 * biased randomised rounds) into a triangulation closed by ghost triangles
 * (mesh.h). For each site p: a walk from the previous insertion finds one
 * triangle whose circumcircle contains p; a depth-first search over
 * neighbours collects the cavity, all triangles whose circumcircle strictly
 * contains p (exact vor_incircle; for ghosts the half-plane rule of mesh.h);
 * the cavity is replaced by the star of p over its boundary.
 *
 * The cavity is a disk, star-shaped from p, with all its vertices on its
 * boundary, so its dual graph is a tree: the search needs no visited marks,
 * and visiting each triangle's edges in counter-clockwise order emits the
 * boundary edges in counter-clockwise order around the cavity, so the new
 * triangles link to their neighbours in the star by position alone. A
 * cavity of k triangles has k + 2 boundary edges; the new triangles take
 * the k freed slots plus two at the end, so the mesh stays compact and the
 * arrays never grow.
 *
 * Cost: expected O(1) walk steps and cavity size per site in spatial order,
 * O(n log n) with the sort; memory: the mesh (48 bytes per site), the order
 * (4 bytes per site) and three small stacks.
 */
#include <assert.h>
#include <stdlib.h>

#include "mesh.h"

#define XY(v) (xy + 2 * (size_t)(v))

/* A growable stack of 32-bit values. */
typedef struct stack {
    uint32_t *v;
    size_t n, cap;
} stack;

static int stack_grow(stack *s) {
    size_t cap = s->cap ? 2 * s->cap : 64;
    uint32_t *v = realloc(s->v, cap * sizeof *v);
    if (!v)
        return -1;
    s->v = v;
    s->cap = cap;
    return 0;
}

static inline int push(stack *s, uint32_t x) {
    if (s->n == s->cap && stack_grow(s))
        return -1;
    s->v[s->n++] = x;
    return 0;
}

typedef struct bw {
    vor__mesh *m;
    const double *xy;
    vor__walk w;
    stack todo;   /* half-edges of cavity triangles still to look across */
    stack cavity; /* cavity triangles, in the order found */
    stack bound;  /* twins of the boundary edges, counter-clockwise */
} bw;

/* Non-zero if p is strictly inside the circumcircle of the triangle of
 * half-edge f (ghost rule of mesh.h for a ghost). */
static inline int conflict(const uint32_t *tri, const double *xy, uint32_t f,
                           const double *p) {
    uint32_t a = tri[f], b = tri[vor__next(f)], c = tri[vor__prev(f)];
    if (c == VOR__GHOST)
        return vor__ghost_conflict(XY(a), XY(b), p);
    if (a == VOR__GHOST)
        return vor__ghost_conflict(XY(b), XY(c), p);
    if (b == VOR__GHOST)
        return vor__ghost_conflict(XY(c), XY(a), p);
    return vor__incircle_fast(XY(a), XY(b), XY(c), p) > 0;
}

/* Inserts site p. VOR_ENOMEM if a stack cannot grow (the mesh is then
 * unchanged). */
static vor_status insert(bw *st, uint32_t p) {
    vor__mesh *m = st->m;
    uint32_t *tri = m->tri;
    int32_t *adj = m->adj;
    const double *xy = st->xy;
    const double *pp = XY(p);
    int32_t on_edge;
    uint32_t t0 = vor__mesh_locate(m, xy, p, &st->w, &on_edge);
    (void)on_edge; /* a triangle with p on an edge is in conflict too */

    /* Cavity search. Popping e means: look across e from inside the
     * cavity. A conflicting neighbour joins the cavity and its other two
     * edges are pushed so that next(f) is looked across before prev(f);
     * that keeps the boundary in counter-clockwise order. */
    st->todo.n = st->cavity.n = st->bound.n = 0;
    if (push(&st->cavity, t0) || push(&st->todo, 3 * t0 + 2) ||
        push(&st->todo, 3 * t0 + 1) || push(&st->todo, 3 * t0))
        return VOR_ENOMEM;
    while (st->todo.n) {
        uint32_t e = st->todo.v[--st->todo.n];
        uint32_t f = (uint32_t)adj[e];
        if (conflict(tri, xy, f, pp)) {
            if (push(&st->cavity, f / 3) || push(&st->todo, vor__prev(f)) ||
                push(&st->todo, vor__next(f)))
                return VOR_ENOMEM;
        } else if (push(&st->bound, f)) {
            return VOR_ENOMEM;
        }
    }

    /* The star. Boundary edge i, seen from outside as f = b->a, gives the
     * new triangle (a, b, p) in slot t_i:
     *
     *              p
     *            / | \            t_i:     a -> b -> p
     *      t_i  /  |  \  t_i+1    3t_i+1 (b->p) is the twin of
     *          /   |   \          3t_i+1 + 2 (p->b) in t_i+1
     *         a----b----c
     *          (outside)
     */
    size_t nb = st->bound.n;
    assert(nb == st->cavity.n + 2);
    assert(m->n_tri + 2 <= m->cap_tri);
    if (push(&st->cavity, (uint32_t)m->n_tri) ||
        push(&st->cavity, (uint32_t)m->n_tri + 1))
        return VOR_ENOMEM; /* nothing has been changed yet */
    m->n_tri += 2;
    const uint32_t *slot = st->cavity.v;
    const uint32_t *bound = st->bound.v;
    uint32_t ghost = UINT32_MAX;
    for (size_t i = 0; i < nb; i++) {
        uint32_t t = slot[i], f = bound[i];
        uint32_t a = tri[vor__next(f)], b = tri[f];
        uint32_t u = slot[i + 1 == nb ? 0 : i + 1];
        assert(tri[vor__next(bound[i + 1 == nb ? 0 : i + 1])] == b);
        tri[3 * t] = a;
        tri[3 * t + 1] = b;
        tri[3 * t + 2] = p;
        adj[3 * t] = (int32_t)f;
        adj[f] = (int32_t)(3 * t);
        adj[3 * t + 1] = (int32_t)(3 * u + 2);
        adj[3 * u + 2] = (int32_t)(3 * t + 1);
        if (a == VOR__GHOST || b == VOR__GHOST)
            ghost = t;
    }
    if (ghost != UINT32_MAX)
        st->w.ghost = ghost;
    st->w.tri = slot[0];
    return VOR_OK;
}

vor_status vor__bowyer_watson_mesh_ordered(const vor_sites *s,
                                           uint32_t *order, vor__mesh *m) {
    double *xy;
    bw st = {.m = m};
    vor_status r = vor__mesh_begin(m, s->xy, s->n, order, &xy, &st.w);
    if (r != VOR_OK)
        return r;
    st.xy = xy;
    for (uint32_t v = 3; v < s->n && r == VOR_OK; v++)
        r = insert(&st, v);
    free(st.todo.v);
    free(st.cavity.v);
    free(st.bound.v);
    free(xy);
    if (r != VOR_OK) {
        vor__mesh_clear(m);
        return r;
    }
    vor__mesh_finish(m, &st.w, order);
    return VOR_OK;
}

vor_status vor__bowyer_watson_mesh(const vor_sites *s, vor__mesh *m) {
    if (s->n < 3)
        return VOR_EINVAL;
    uint32_t *order = malloc(s->n * sizeof *order);
    if (!order)
        return VOR_ENOMEM;
    vor_status r = vor__insertion_order(s->xy, s->n, order);
    if (r == VOR_OK)
        r = vor__bowyer_watson_mesh_ordered(s, order, m);
    free(order);
    return r;
}

vor_status vor__bowyer_watson(const vor_sites *s, vor_diagram **out) {
    vor__mesh m = {0};
    *out = NULL;
    vor_status r = vor__bowyer_watson_mesh(s, &m);
    if (r != VOR_OK)
        return r;
    return vor__mesh_to_diagram(s, &m, out);
}
