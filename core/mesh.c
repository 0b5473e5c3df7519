/* mesh.c -- the Delaunay mesh shared by Bowyer-Watson and Lawson flipping:
 * the start of a construction, point location, removal of the ghost
 * triangles at the end, and the exact checker.
 *
 * Representation (internal.h): delaunator's two flat arrays, tri[3t+k]
 * vertex ids counter-clockwise and adj[3t+k] the twin half-edge. During
 * construction the hull is closed by ghost triangles around the symbolic
 * vertex VOR__GHOST (mesh.h), so the mesh is a sphere triangulation with
 * exactly 2k - 2 triangles for k inserted sites and both algorithms only
 * ever add two triangles per site: the arrays are allocated once for
 * 2n - 2 triangles (48 bytes per site) and never grow. The sites are
 * copied in insertion order (16 bytes per site, freed at the end) and the
 * mesh numbers them by rank, so that spatially close vertices are close in
 * memory too.
 *
 * Cost: vor__mesh_begin O(n) (allocation, local copy of the coordinates),
 * vor__mesh_locate O(length of the walk), short in spatial insertion order;
 * vor__mesh_finish O(n) (renumbering);
 * vor__mesh_check O(n) time and about 6 bytes per site of scratch memory.
 * All geometric decisions are the exact predicates of internal.h. The
 * walk counts its steps and tests in locals and adds them to the walk
 * state (vor__walk) when it stops.
 */
#include <assert.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "mesh.h"

#define XY(v) (xy + 2 * (size_t)(v))

void vor__mesh_clear(vor__mesh *m) {
    if (!m)
        return;
    free(m->tri);
    free(m->adj);
    m->tri = NULL;
    m->adj = NULL;
    m->n_tri = 0;
    m->cap_tri = 0;
}

/* Gives advice (a madvise() advice, -1 for none where the system lacks
 * it) for the whole units of unit bytes inside a block of bytes at p, if
 * the block is at least min bytes long. Errors are ignored: a hint. */
static void advise(void *p, size_t bytes, uintptr_t unit, size_t min,
                   int advice) {
    if (advice < 0 || !p || bytes < min)
        return;
    uintptr_t lo = ((uintptr_t)p + unit - 1) & ~(unit - 1);
    uintptr_t hi = ((uintptr_t)p + bytes) & ~(unit - 1);
    if (hi > lo)
        (void)madvise((void *)lo, hi - lo, advice);
}

#if defined(MADV_HUGEPAGE)
#define ADVICE_HUGE MADV_HUGEPAGE
#else
#define ADVICE_HUGE (-1)
#endif
#if defined(MADV_POPULATE_WRITE)
#define ADVICE_POPULATE MADV_POPULATE_WRITE
#else
#define ADVICE_POPULATE (-1)
#endif

/* Advises the whole 2 MiB pages inside a block of 4 MiB or more. */
static void advise_huge(void *p, size_t bytes) {
    advise(p, bytes, (uintptr_t)1 << 21, (size_t)1 << 22, ADVICE_HUGE);
}

/* Maps the whole 4 KiB pages inside a block of 1 MiB or more, writable,
 * now. */
static void populate(void *p, size_t bytes) {
    advise(p, bytes, 4096, (size_t)1 << 20, ADVICE_POPULATE);
}

void *vor__alloc_large(size_t count, size_t size) {
    if (count == 0)
        count = 1;
    if (count > SIZE_MAX / size)
        return NULL;
    void *p = malloc(count * size);
    advise_huge(p, count * size);
    return p;
}

void *vor__alloc_scattered(size_t count, size_t size) {
    void *p = vor__alloc_large(count, size);
    populate(p, count * size);
    return p;
}

void *vor__calloc_large(size_t count, size_t size) {
    if (count == 0)
        count = 1;
    void *p = calloc(count, size); /* checks the product */
    advise_huge(p, count * size);
    populate(p, count * size);
    return p;
}

/* A scratch block starts with this header, which says how it was made;
 * the caller's array follows at SCRATCH_HEAD bytes (16: malloc's
 * alignment). */
#define SCRATCH_HEAD 16
#define SCRATCH_MAP ((size_t)1 << 20)

void *vor__scratch_new(size_t count, size_t size) {
    if (count == 0)
        count = 1;
    if (count > (SIZE_MAX - SCRATCH_HEAD) / size)
        return NULL;
    size_t bytes = SCRATCH_HEAD + count * size;
    unsigned char *p = NULL;
#if defined(MAP_ANONYMOUS)
    if (bytes >= SCRATCH_MAP) {
        void *m = mmap(NULL, bytes, PROT_READ | PROT_WRITE,
                       MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (m == MAP_FAILED)
            return NULL;
        p = m; /* zeroed by the kernel */
        advise_huge(m, bytes);
    }
#endif
    if (!p) {
        if (!(p = calloc(1, bytes)))
            return NULL;
        bytes = 0; /* the C library's */
    }
    memcpy(p, &bytes, sizeof bytes);
    return p + SCRATCH_HEAD;
}

void vor__scratch_free(void *q) {
    if (!q)
        return;
    unsigned char *p = (unsigned char *)q - SCRATCH_HEAD;
    size_t bytes;
    memcpy(&bytes, p, sizeof bytes);
#if defined(MAP_ANONYMOUS)
    if (bytes) {
        (void)munmap(p, bytes);
        return;
    }
#endif
    free(p);
}

/* ---- Start ---------------------------------------------------------------
 *
 * The first triangle a, b, c (counter-clockwise) in slot 0 and one ghost per
 * edge in slots 1..3; every ghost's third vertex is GHOST:
 *
 *              c
 *             / \           slot 0: (a, b, c)
 *       3    /   \    2     slot 1: (b, a, GHOST), across edge 0 = a->b
 *           /  0  \         slot 2: (c, b, GHOST), across edge 1 = b->c
 *          a ----- b        slot 3: (a, c, GHOST), across edge 2 = c->a
 *              1
 *
 * Ghost g = 1 + k is (y, x, GHOST) for edge k = x->y of slot 0; its edge
 * x->GHOST (3g+1) is the twin of GHOST->x in the ghost of the edge that ends
 * at x, which is edge prev(k): 3(1 + prev(k)) + 2.
 */
/* The local copy's scale. Every predicate's sign is the same for the
 * sites scaled by a power of two, exactly, and the filters decide only
 * within their range: sites of magnitude 10^200 or 10^-200 made every
 * orient2d and incircle of Bowyer-Watson and flipping rescale per call
 * (186 ms at 10^5 uniform sites, 62 ms in [0, 1]), subnormal ones go to
 * the expansions (1.0 s). So the copy (local ids, box its bounding box)
 * is scaled so that its largest magnitude lies in [1/2, 1) when that is
 * beyond 2^+-32: scaled up always (exact below DBL_MAX), down only if
 * its smallest nonzero magnitude stays a normal double (exact then). The
 * conversion reads the copy for incircle tests only, and the diagram's
 * geometry comes from the sites themselves. Returns the span of the copy
 * as scaled. */
static double scale_local(double *local, size_t n, const double box[4]) {
    double big = 0;
    for (int k = 0; k < 4; k++)
        big = fabs(box[k]) > big ? fabs(box[k]) : big;
    int e;
    (void)frexp(big, &e); /* big in [2^(e-1), 2^e) */
    if (big > 0 && (e < -32 || e > 32)) {
        int ok = e < 0;
        if (!ok) { /* down: the smallest nonzero magnitude stays normal */
            double small = big;
            for (size_t i = 0; i < 2 * n; i++) {
                double v = fabs(local[i]);
                if (v > 0 && v < small) small = v;
            }
            int f;
            (void)frexp(small, &f);
            ok = f - e >= -1020;
        }
        if (ok) {
            for (size_t i = 0; i < 2 * n; i++) local[i] = ldexp(local[i], -e);
            double sx = ldexp(box[2], -e) - ldexp(box[0], -e),
                   sy = ldexp(box[3], -e) - ldexp(box[1], -e);
            return sx > sy ? sx : sy;
        }
    }
    double sx = box[2] - box[0], sy = box[3] - box[1];
    return sx > sy ? sx : sy;
}

vor_status vor__mesh_begin(vor__mesh *m, const double *xy, size_t n,
                           uint32_t *order, double **pxy, vor__walk *w) {
    double *local = *pxy; /* the caller's block, if any: ours now */
    *pxy = NULL;
    if (n < 3 || n > ((size_t)INT32_MAX / 3 + 2) / 2) {
        /* 2n - 2 triangles, 3 half-edges each, ids must fit in int32_t */
        free(local);
        return n < 3 ? VOR_EINVAL : VOR_ETOOMANY;
    }
    size_t cap = 2 * n - 2;
    const double *a = XY(order[0]), *b = XY(order[1]);
    size_t k = 2;
    uint64_t exact = 0;
    while (k < n && vor__orient2d_fast_n(a, b, XY(order[k]), &exact) == 0)
        k++;
    w->orient2d = k; /* the k - 1 tests above, and the one below */
    w->steps = w->incircle = 0;
    if (k == n) {
        free(local);
        return VOR_EINVAL;
    }
    uint32_t c = order[k];
    order[k] = order[2];
    order[2] = c;
    if (!local)
        local = vor__alloc_large(2 * n, sizeof *local);
    m->tri = vor__alloc_large(3 * cap, sizeof *m->tri);
    m->adj = vor__alloc_large(3 * cap, sizeof *m->adj);
    if (!local || !m->tri || !m->adj) {
        free(local);
        vor__mesh_clear(m);
        return VOR_ENOMEM;
    }
    for (size_t i = 0; i < n; i++) {
        local[2 * i] = xy[2 * (size_t)order[i]];
        local[2 * i + 1] = xy[2 * (size_t)order[i] + 1];
    }
    m->cap_tri = cap;
    m->n_tri = 4;
    uint32_t *tri = m->tri;
    int32_t *adj = m->adj;
    int ccw = vor__orient2d_fast_n(local, local + 2, local + 4, &exact) > 0;
    w->exact = exact;
    tri[0] = ccw ? 0 : 1;
    tri[1] = ccw ? 1 : 0;
    tri[2] = 2;
    for (uint32_t e = 0; e < 3; e++) {
        uint32_t g = 1 + e;
        tri[3 * g] = tri[vor__next(e)];
        tri[3 * g + 1] = tri[e];
        tri[3 * g + 2] = VOR__GHOST;
        adj[e] = (int32_t)(3 * g);
        adj[3 * g] = (int32_t)e;
        adj[3 * g + 1] = (int32_t)(3 * (1 + vor__prev(e)) + 2);
        adj[3 * (1 + vor__prev(e)) + 2] = (int32_t)(3 * g + 1);
    }
    w->tri = 0;
    w->rng = 0x9e3779b9u;
    double box[4];
    vor__bbox(local, n, box);
    double span = scale_local(local, n, box);
    w->occ = vor__orient2d_static_bound(span);
    *pxy = local;
    return VOR_OK;
}

/* ---- Point location ------------------------------------------------------ */

/* The walk. In the first triangle all three edges are tested; after that
 * the walk has entered triangle t through half-edge f = a->b, knows p is
 * strictly on the inner side of it, and tests the other two edges b->c and
 * c->a, in an order chosen by one random bit (the top bit of a linear
 * congruential generator): p strictly beyond an edge crosses it. The
 * random choice keeps a walk from going round in circles in degenerate
 * configurations; in a Delaunay triangulation a visibility walk cannot
 * cycle anyway.
 *
 *              c
 *            /   \          test b->c and c->a in random order;
 *           /  t  \         o < 0: cross; both >= 0: p is in t
 *          a ----- b
 *             f (entered through)
 */
static inline double dist2(const double *a, const double *b) {
    double dx = a[0] - b[0], dy = a[1] - b[1];
    return dx * dx + dy * dy;
}

uint32_t vor__mesh_locate(const vor__mesh *m, const double *xy, uint32_t p,
                          vor__walk *w, int32_t *on_edge) {
    const uint32_t *tri = m->tri;
    const int32_t *adj = m->adj;
    const double *pp = XY(p);
    const double occ = w->occ;
    uint32_t rng = w->rng;
    uint32_t t = w->tri;
    uint64_t steps = 0, tests = 0;
    if (vor__mesh_is_ghost(tri, t)) {
        /* A ghost whose hull edge p is strictly outside of is an answer.
         * Sites in convex position (on a curve) make that the common case:
         * each lies just outside the hull, near the site before, at whose
         * ghost the walk starts (Bowyer-Watson) -- but not always within
         * an edge or two of it: a round's Hilbert order leaves a piece of
         * the curve for another and comes back, and a walk through the
         * interior from there crosses the long thin triangles of a convex
         * set one by one (10^5 sites on a parabola: a fifth of the sites
         * walked 36 steps on average, three times the steps of uniform
         * sites in all). So the walk goes along the hull first, towards
         * the hull vertex nearer p, as long as the vertices come nearer
         * (by the rounded distance: the direction is only a guess; the
         * answer is an exact test); failing that, it goes on from the
         * finite triangle across the last hull edge tested, which lies
         * as near p as the hull gets there. Hull edge e = x->y of a
         * ghost: the next one, from y, is next(adj[next(e)]); the one
         * before, to x, prev(adj[prev(e)]). */
        uint32_t e = 3 * t;
        while (tri[e] == VOR__GHOST || tri[vor__next(e)] == VOR__GHOST)
            e++;
        /* squared distances of p from the edge's two ends */
        double dfrom = dist2(XY(tri[e]), pp),
               dto = dist2(XY(tri[vor__next(e)]), pp);
        const int forward = dto < dfrom;
        double best = forward ? dto : dfrom;
        for (int last = 0;; steps++) {
            tests++;
            if (vor__orient2d_static_n(XY(tri[e]), XY(tri[vor__next(e)]), pp,
                                       occ, &w->exact) > 0) {
                w->tri = e / 3;
                w->orient2d += tests;
                w->steps += steps;
                *on_edge = -1;
                return e / 3;
            }
            if (last) break;
            /* the edge out of the nearest vertex is tested too */
            e = forward ? vor__next((uint32_t)adj[vor__next(e)])
                        : vor__prev((uint32_t)adj[vor__prev(e)]);
            double d = dist2(XY(tri[forward ? vor__next(e) : e]), pp);
            if (d < best)
                best = d;
            else
                last = 1;
        }
        t = (uint32_t)adj[e] / 3;
    }
    /* In the first triangle: an edge p is strictly beyond, or stop. */
    int32_t zero = -1;
    uint32_t k;
    for (k = 0; k < 3; k++) {
        uint32_t e = 3 * t + k;
        int o = vor__orient2d_static_n(XY(tri[e]), XY(tri[vor__next(e)]), pp,
                                       occ, &w->exact);
        if (o < 0)
            break;
        if (o == 0)
            zero = (int32_t)e;
    }
    if (k == 3) {
        w->tri = t;
        w->orient2d += tests + 3;
        *on_edge = zero;
        return t;
    }
    tests += k + 1;
    uint32_t f = (uint32_t)adj[3 * t + k];
    for (;;) {
        uint32_t nf = vor__next(f), pf = vor__prev(f);
        uint32_t c = tri[pf];
        steps++;
        if (c == VOR__GHOST) {
            /* p is strictly outside the hull edge we just crossed. */
            t = f / 3;
            w->tri = t;
            w->rng = rng;
            w->steps += steps;
            w->orient2d += tests;
            *on_edge = -1;
            return t;
        }
        const double *pa = XY(tri[f]), *pb = XY(tri[nf]), *pc = XY(c);
        rng = rng * 1103515245u + 12345u;
        /* Edge e1 is q0->q1, edge e2 is q2->q3: b->c and c->a in either
         * order. */
        uint32_t e1 = nf, e2 = pf;
        const double *q0 = pb, *q1 = pc, *q2 = pc, *q3 = pa;
        if (rng & 0x80000000u) {
            e1 = pf;
            e2 = nf;
            q0 = pc;
            q1 = pa;
            q2 = pb;
            q3 = pc;
        }
        int o1 = vor__orient2d_static_n(q0, q1, pp, occ, &w->exact);
        tests++;
        if (o1 < 0) {
            f = (uint32_t)adj[e1];
            continue;
        }
        int o2 = vor__orient2d_static_n(q2, q3, pp, occ, &w->exact);
        tests++;
        if (o2 < 0) {
            f = (uint32_t)adj[e2];
            continue;
        }
        t = f / 3;
        w->tri = t;
        w->rng = rng;
        w->steps += steps;
        w->orient2d += tests;
        *on_edge = o1 == 0 ? (int32_t)e1 : o2 == 0 ? (int32_t)e2 : -1;
        return t;
    }
}

vor_status vor__mesh_order_new(const vor_sites *s, uint32_t **order,
                               double **coords, vor_counts *counts) {
    *order = NULL;
    if (coords)
        *coords = NULL;
    if (s->n < 3)
        return VOR_EINVAL;
    uint32_t *o = vor__alloc_large(s->n, sizeof *o);
    double *c = coords ? vor__alloc_large(2 * s->n, sizeof *c) : NULL;
    vor_status r = VOR_ENOMEM;
    if (o && (c || !coords))
        r = vor__insertion_order_in(s->xy, s->n, o, counts, (uint64_t *)c);
    if (r != VOR_OK) {
        free(o);
        free(c);
        return r;
    }
    *order = o;
    if (coords)
        *coords = c;
    return VOR_OK;
}

vor_status vor__mesh_build_ordered(const vor_sites *s,
                                   vor__mesh_build_fn build, uint32_t *order,
                                   vor__mesh *m) {
    double *xy = NULL;
    vor__run run;
    memset(&run, 0, sizeof run);
    vor_status r = build(s, order, m, &xy, &run);
    if (r != VOR_OK)
        return r;
    free(xy);
    vor__mesh_finish(m, order);
    return VOR_OK;
}

vor_status vor__mesh_build(const vor_sites *s, vor__mesh_build_fn build,
                           vor__mesh *m) {
    uint32_t *order;
    vor_status r = vor__mesh_order_new(s, &order, NULL, NULL);
    if (r == VOR_OK)
        r = vor__mesh_build_ordered(s, build, order, m);
    free(order);
    return r;
}

double vor__span(const double *xy, size_t n) {
    double box[4];
    vor__bbox(xy, n, box);
    double sx = box[2] - box[0], sy = box[3] - box[1];
    return sx > sy ? sx : sy;
}

int vor__ghost_conflict(const double *a, const double *b, const double *p) {
    uint64_t unread = 0;
    return vor__ghost_conflict_n(a, b, p, &unread);
}

int vor__ghost_conflict_n(const double *a, const double *b, const double *p,
                          uint64_t *exact) {
    int o = vor__orient2d_fast_n(a, b, p, exact);
    if (o != 0)
        return o > 0;
    /* On the line through a and b: inside the open segment? Exact, since
     * only comparisons are involved. */
    if (a[0] != b[0])
        return a[0] < b[0] ? (a[0] < p[0] && p[0] < b[0])
                           : (b[0] < p[0] && p[0] < a[0]);
    return a[1] < b[1] ? (a[1] < p[1] && p[1] < b[1])
                       : (b[1] < p[1] && p[1] < a[1]);
}

void vor__mesh_trace_begin(const vor__mesh *m, const uint32_t *order,
                           size_t n, vor__run *run, const vor_counts *so_far) {
    if (!run->trace)
        return;
    vor_step st;
    vor__step_init(&st, VOR_STEP_ORDER);
    st.order = order;
    st.n_order = n;
    st.counts = so_far;
    run->trace(run->trace_ctx, &st);
    vor__step_init(&st, VOR_STEP_BEGIN);
    st.counts = so_far;
    for (int k = 0; k < 3; k++)
        st.tri[k] = order[m->tri[k]];
    run->trace(run->trace_ctx, &st);
}

/* ---- Removing the ghosts -------------------------------------------------
 *
 * The ghosts form a ring around GHOST: if e is the hull edge a->b of a
 * ghost (GHOST at prev(e)), then next(e) = b->GHOST is the twin of GHOST->b
 * in the next ghost, whose hull edge starts at b: next(adj[next(e)]).
 *
 *     pass 1: walk the ring, give the finite twin of every hull edge adj -1
 *             and count the ghosts h; the public mesh has F = n_tri - h.
 *     pass 2: walk the ring again; each ghost in a slot < F is overwritten
 *             by a finite triangle taken from the slots >= F (scanning down
 *             from the end), whose neighbours are told its new place.
 *     pass 3: local vertex ids become site indices.
 * The ring is only read ahead of the slot being overwritten, so it stays
 * valid for the rest of pass 2.
 */
static uint32_t ghost_hull_edge(const uint32_t *tri, uint32_t g) {
    uint32_t e = 3 * g;
    while (tri[e] == VOR__GHOST || tri[vor__next(e)] == VOR__GHOST)
        e++;
    return e;
}

static void move_triangle(uint32_t *tri, int32_t *adj, uint32_t from,
                          uint32_t to) {
    for (uint32_t k = 0; k < 3; k++) {
        int32_t a = adj[3 * from + k];
        tri[3 * to + k] = tri[3 * from + k];
        adj[3 * to + k] = a;
        if (a >= 0)
            adj[a] = (int32_t)(3 * to + k);
    }
}

void vor__mesh_finish(vor__mesh *m, const uint32_t *order) {
    uint32_t *tri = m->tri;
    int32_t *adj = m->adj;
    uint32_t g0 = 0;
    while (!vor__mesh_is_ghost(tri, g0)) /* there are at least three */
        g0++;
    uint32_t e0 = ghost_hull_edge(tri, g0);
    size_t h = 0;
    uint32_t e = e0;
    do {
        adj[adj[e]] = -1;
        h++;
        e = vor__next((uint32_t)adj[vor__next(e)]);
    } while (e != e0);
    size_t f = m->n_tri - h;
    size_t j = m->n_tri; /* finite triangles >= f are taken from below j */
    e = e0;
    for (size_t i = 0; i < h; i++) {
        uint32_t g = e / 3;
        e = vor__next((uint32_t)adj[vor__next(e)]);
        if (g >= f)
            continue;
        do
            j--;
        while (vor__mesh_is_ghost(tri, (uint32_t)j));
        assert(j >= f);
        move_triangle(tri, adj, (uint32_t)j, g);
    }
    m->n_tri = f;
    for (size_t i = 0; i < 3 * f; i++)
        tri[i] = order[tri[i]];
}

/* ---- The checker --------------------------------------------------------- */

/* Writes the reason into msg (if any) and returns 1. */
#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static int fail(char *msg, size_t msg_size, const char *fmt, ...) {
    if (msg && msg_size) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg, msg_size, fmt, ap);
        va_end(ap);
    }
    return 1;
}

/* Quadrant of the direction a->b, exactly (comparisons only):
 * 0: dx > 0, dy >= 0; 1: dx <= 0, dy > 0; 2: dx < 0, dy <= 0;
 * 3: dx >= 0, dy < 0. a != b. */
static int quadrant(const double *a, const double *b) {
    int sx = (b[0] > a[0]) - (b[0] < a[0]);
    int sy = (b[1] > a[1]) - (b[1] < a[1]);
    if (sx > 0 && sy >= 0)
        return 0;
    if (sx <= 0 && sy > 0)
        return 1;
    if (sx < 0 && sy <= 0)
        return 2;
    return 3;
}

/* Non-zero if b lies strictly between a and c on the line through them
 * (the three are known to be collinear). */
static int strictly_between(const double *a, const double *b,
                            const double *c) {
    if (a[0] != c[0])
        return a[0] < c[0] ? (a[0] < b[0] && b[0] < c[0])
                           : (c[0] < b[0] && b[0] < a[0]);
    return a[1] < c[1] ? (a[1] < b[1] && b[1] < c[1])
                       : (c[1] < b[1] && b[1] < a[1]);
}

/* Structure: ids in range, distinct vertices, twins symmetric and with
 * swapped ends, every triangle counter-clockwise. */
static int check_structure(const vor__mesh *m, const vor_sites *s, char *msg,
                           size_t msg_size) {
    const uint32_t *tri = m->tri;
    const int32_t *adj = m->adj;
    const double *xy = s->xy;
    size_t ne = 3 * m->n_tri;
    for (size_t t = 0; t < m->n_tri; t++) {
        uint32_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
        if (a >= s->n || b >= s->n || c >= s->n)
            return fail(msg, msg_size,
                        "triangle %zu (%u, %u, %u): vertex id out of range",
                        t, a, b, c);
        if (a == b || b == c || c == a)
            return fail(msg, msg_size,
                        "triangle %zu (%u, %u, %u): repeated vertex", t, a,
                        b, c);
        if (vor__orient2d_fast(XY(a), XY(b), XY(c)) <= 0)
            return fail(msg, msg_size,
                        "triangle %zu (%u, %u, %u) is not counter-clockwise",
                        t, a, b, c);
    }
    for (size_t e = 0; e < ne; e++) {
        int32_t f = adj[e];
        if (f == -1)
            continue;
        if (f < 0 || (size_t)f >= ne)
            return fail(msg, msg_size, "half-edge %zu: twin %d out of range",
                        e, (int)f);
        if ((size_t)adj[f] != e)
            return fail(msg, msg_size,
                        "half-edge %zu: twin %d points back to %d", e,
                        (int)f, (int)adj[f]);
        uint32_t fe = (uint32_t)f;
        if (tri[fe] != tri[vor__next((uint32_t)e)] ||
            tri[vor__next(fe)] != tri[e])
            return fail(msg, msg_size,
                        "half-edge %zu (%u->%u): twin %d is %u->%u", e,
                        tri[e], tri[vor__next((uint32_t)e)], (int)f,
                        tri[fe], tri[vor__next(fe)]);
    }
    return 0;
}

/* Every site is a vertex, and the triangles around every vertex form one
 * fan (a disk for an interior vertex, a path for a hull vertex): the mesh
 * is a surface. seen is 3 * n_tri bytes of scratch, fans n bytes. */
static int check_fans(const vor__mesh *m, const vor_sites *s, uint8_t *seen,
                      uint8_t *fans, char *msg, size_t msg_size) {
    const uint32_t *tri = m->tri;
    const int32_t *adj = m->adj;
    size_t ne = 3 * m->n_tri;
    memset(seen, 0, ne);
    memset(fans, 0, s->n);
    for (size_t e0 = 0; e0 < ne; e0++) {
        if (seen[e0])
            continue;
        uint32_t v = tri[e0];
        if (fans[v]++)
            return fail(msg, msg_size,
                        "vertex %u: its triangles form more than one fan "
                        "(met again at half-edge %zu)",
                        v, e0);
        /* Counter-clockwise from e0 (out of v) through prev, twin. */
        uint32_t e = (uint32_t)e0;
        int closed = 0;
        for (;;) {
            seen[e] = 1;
            int32_t f = adj[vor__prev(e)];
            if (f < 0)
                break;
            e = (uint32_t)f;
            if (e == e0) {
                closed = 1;
                break;
            }
            if (seen[e])
                return fail(msg, msg_size,
                            "vertex %u: fan runs into half-edge %u twice", v,
                            e);
        }
        if (closed)
            continue;
        /* Clockwise from e0 through twin, next. */
        e = (uint32_t)e0;
        for (;;) {
            int32_t f = adj[e];
            if (f < 0)
                break;
            e = vor__next((uint32_t)f);
            if (seen[e])
                return fail(msg, msg_size,
                            "vertex %u: fan runs into half-edge %u twice", v,
                            e);
            seen[e] = 1;
        }
    }
    for (size_t v = 0; v < s->n; v++)
        if (!fans[v])
            return fail(msg, msg_size, "site %zu is not a vertex of the mesh",
                        v);
    return 0;
}

/* The hull edges (adj -1) form one closed cycle, counter-clockwise, that
 * turns left or goes straight on at every vertex and winds exactly once:
 * a convex polygon, collinear hull sites included. out is n uint32 of
 * scratch. On success *h is the number of hull edges. */
static int check_hull(const vor__mesh *m, const vor_sites *s, uint32_t *out,
                      size_t *h, char *msg, size_t msg_size) {
    const uint32_t *tri = m->tri;
    const int32_t *adj = m->adj;
    const double *xy = s->xy;
    size_t ne = 3 * m->n_tri;
    size_t count = 0;
    uint32_t start = UINT32_MAX;
    for (size_t v = 0; v < s->n; v++)
        out[v] = UINT32_MAX;
    for (size_t e = 0; e < ne; e++) {
        if (adj[e] != -1)
            continue;
        uint32_t v = tri[e];
        if (out[v] != UINT32_MAX)
            return fail(msg, msg_size,
                        "vertex %u has two hull edges (half-edges %u, %zu)",
                        v, out[v], e);
        out[v] = (uint32_t)e;
        start = (uint32_t)e;
        count++;
    }
    if (count < 3)
        return fail(msg, msg_size, "hull has %zu edges", count);
    size_t steps = 0;
    long turn = 0;
    uint32_t e = start;
    do {
        uint32_t a = tri[e], b = tri[vor__next(e)];
        uint32_t f = out[b];
        if (f == UINT32_MAX)
            return fail(msg, msg_size,
                        "hull edge %u->%u (half-edge %u) has no successor",
                        a, b, e);
        uint32_t c = tri[vor__next(f)];
        int o = vor__orient2d_fast(XY(a), XY(b), XY(c));
        if (o < 0 || (o == 0 && !strictly_between(XY(a), XY(b), XY(c))))
            return fail(msg, msg_size,
                        "hull is not convex at vertex %u (%u->%u->%u)", b, a,
                        b, c);
        turn += (quadrant(XY(b), XY(c)) - quadrant(XY(a), XY(b)) + 4) % 4;
        e = f;
        steps++;
    } while (e != start && steps <= count);
    if (steps != count)
        return fail(msg, msg_size,
                    "hull edges form more than one cycle (%zu of %zu)",
                    steps, count);
    if (turn != 4)
        return fail(msg, msg_size, "hull winds %ld quarter turns, not 4",
                    turn);
    *h = count;
    return 0;
}

int vor__mesh_check(const vor__mesh *m, const vor_sites *s, char *msg,
                    size_t msg_size) {
    if (!m || !s || !s->xy || s->n < 3)
        return fail(msg, msg_size, "no mesh or fewer than 3 sites");
    if (m->n_tri == 0 || !m->tri || !m->adj)
        return fail(msg, msg_size, "empty mesh");
    if (m->n_tri > m->cap_tri)
        return fail(msg, msg_size, "n_tri %zu exceeds cap_tri %zu", m->n_tri,
                    m->cap_tri);
    if (check_structure(m, s, msg, msg_size))
        return 1;
    size_t ne = 3 * m->n_tri;
    uint8_t *bytes = malloc(ne + s->n);
    uint32_t *out = malloc(s->n * sizeof *out);
    if (!bytes || !out) {
        free(bytes);
        free(out);
        return fail(msg, msg_size, "out of memory while checking");
    }
    size_t h = 0;
    int bad = check_fans(m, s, bytes, bytes + ne, msg, msg_size) ||
              check_hull(m, s, out, &h, msg, msg_size);
    free(bytes);
    free(out);
    if (bad)
        return 1;
    if (m->n_tri != 2 * s->n - 2 - h)
        return fail(msg, msg_size,
                    "%zu triangles, Euler says %zu for %zu sites and %zu "
                    "hull vertices",
                    m->n_tri, 2 * s->n - 2 - h, s->n, h);
    const uint32_t *tri = m->tri;
    const int32_t *adj = m->adj;
    const double *xy = s->xy;
    for (size_t e = 0; e < ne; e++) {
        int32_t f = adj[e];
        if (f < 0 || (size_t)f < e)
            continue;
        uint32_t a = tri[e], b = tri[vor__next((uint32_t)e)];
        uint32_t c = tri[vor__prev((uint32_t)e)];
        uint32_t d = tri[vor__prev((uint32_t)f)];
        if (vor__incircle_fast(XY(a), XY(b), XY(c), XY(d)) > 0)
            return fail(msg, msg_size,
                        "edge %u-%u (triangles %zu, %d) is not locally "
                        "Delaunay: %u is inside the circle of %u, %u, %u",
                        a, b, e / 3, (int)f / 3, d, a, b, c);
    }
    return 0;
}
