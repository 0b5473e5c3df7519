/* replay.h -- a replayer of traces (vor.h, vor_step), independent of the
 * algorithms' code, for the tests.
 *
 * It follows the steps as the trace hook delivers them and keeps its own
 * state: the set of triangles (ghosts included for the incremental
 * algorithms), Fortune's beach line and its pending circle events, and
 * tallies of what the steps did. Every step is checked against that state
 * (the triangles a step removes exist, a flip's far vertex is inside the
 * circle, an insertion's cavity is exactly what it claims, the beach line
 * after an event is the one the event's position implies, a circle event
 * fires only if scheduled ...); the first violation is kept as a message
 * and the rest of the trace is ignored, so the algorithm always runs to
 * its end and frees what it holds. rp_finish then builds the Delaunay
 * mesh from the final triangles (finite ones, adjacency found by sorting
 * the half-edges) and converts it with vor__mesh_to_diagram: the same
 * conversion, so the result must equal the algorithm's diagram bit for
 * bit.
 *
 * Header-only; static functions, for one test file each. Memory: a hash
 * set of 4 slots per triangle, the beach line, the order. */
#ifndef VOR_TESTS_REPLAY_H
#define VOR_TESTS_REPLAY_H

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../core/internal.h"

/* ---- A hash set of triples ------------------------------------------------ */

#define RP_EMPTY 0u
#define RP_GONE 1u

typedef struct rp_set {
    uint32_t *key; /* 3 per slot; state[] says if the slot holds one */
    uint8_t *state; /* RP_EMPTY, RP_GONE (deleted) or 2 (full) */
    size_t cap, n;
} rp_set;

static int rp_set_init(rp_set *h, size_t want) {
    size_t cap = 64;
    while (cap < 4 * want) cap *= 2;
    h->key = malloc(3 * cap * sizeof *h->key);
    h->state = calloc(cap, 1);
    h->cap = cap;
    h->n = 0;
    return h->key && h->state ? 0 : -1;
}

static void rp_set_free(rp_set *h) {
    free(h->key);
    free(h->state);
    memset(h, 0, sizeof *h);
}

static size_t rp_hash(const uint32_t *t, size_t cap) {
    uint64_t x = t[0] * 0x9e3779b97f4a7c15ull ^ t[1] * 0xc2b2ae3d27d4eb4full ^
                 t[2] * 0x165667b19e3779f9ull;
    x ^= x >> 29;
    return (size_t)(x * 0xbf58476d1ce4e5b9ull >> 7) & (cap - 1);
}

/* Slot of t, or of the first free slot on its probe path (for adding)
 * when absent; *found says which. */
static size_t rp_find(const rp_set *h, const uint32_t *t, int *found) {
    size_t i = rp_hash(t, h->cap), free_slot = (size_t)-1;
    for (;;) {
        if (h->state[i] == RP_EMPTY) {
            *found = 0;
            return free_slot != (size_t)-1 ? free_slot : i;
        }
        if (h->state[i] == RP_GONE) {
            if (free_slot == (size_t)-1) free_slot = i;
        } else if (memcmp(h->key + 3 * i, t, 3 * sizeof *t) == 0) {
            *found = 1;
            return i;
        }
        i = (i + 1) & (h->cap - 1);
    }
}

static int rp_set_add(rp_set *h, const uint32_t *t) {
    int found;
    size_t i = rp_find(h, t, &found);
    if (found || h->n + 1 >= h->cap / 2) return -1; /* sized to never fill */
    memcpy(h->key + 3 * i, t, 3 * sizeof *t);
    h->state[i] = 2;
    h->n++;
    return 0;
}

static int rp_set_remove(rp_set *h, const uint32_t *t) {
    int found;
    size_t i = rp_find(h, t, &found);
    if (!found) return -1;
    h->state[i] = RP_GONE;
    h->n--;
    return 0;
}

/* ---- The replayer ----------------------------------------------------------- */

typedef struct replay {
    const vor_sites *s;
    vor_algorithm algorithm;
    char err[320]; /* the first violation, "" if none */
    rp_set tris;   /* triangles, each rotated to start at its smallest */
    rp_set events; /* Fortune: pending circle events, triples as given */
    uint32_t *order, *beach, *tmp;
    size_t n_order, next, n_beach;
    int ended;
    /* tallies, compared with the counts */
    uint64_t steps[VOR_STEP_KIND_COUNT];
    uint64_t created, removed, beach_max, row, hits, flips;
    vor_counts last; /* the counts of the last step */
} replay;

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static void rp_fail(replay *r, const char *fmt, ...);
/* Records the violation and leaves the step. */
#define RP_FAIL(r, ...)                                                      \
    do {                                                                     \
        rp_fail(r, __VA_ARGS__);                                             \
        return;                                                              \
    } while (0)

static void rp_fail(replay *r, const char *fmt, ...) {
    if (r->err[0]) return;
    size_t k = (size_t)snprintf(r->err, sizeof r->err, "step %llu: ",
                                (unsigned long long)(r->steps[0] + r->steps[1] +
                                                     r->steps[2] + r->steps[3] +
                                                     r->steps[4] + r->steps[5] +
                                                     r->steps[6] + r->steps[7]));
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->err + k, sizeof r->err - k, fmt, ap);
    va_end(ap);
}

static int rp_init(replay *r, const vor_sites *s, vor_algorithm a) {
    memset(r, 0, sizeof *r);
    r->s = s;
    r->algorithm = a;
    size_t n = s->n;
    r->order = malloc((n + 1) * sizeof *r->order);
    r->beach = malloc((2 * n + 2) * sizeof *r->beach);
    r->tmp = malloc((2 * n + 2) * sizeof *r->tmp);
    if (!r->order || !r->beach || !r->tmp) return -1;
    if (rp_set_init(&r->tris, 6 * n + 16) || rp_set_init(&r->events, 2 * n + 16))
        return -1;
    return 0;
}

static void rp_free(replay *r) {
    free(r->order);
    free(r->beach);
    free(r->tmp);
    rp_set_free(&r->tris);
    rp_set_free(&r->events);
}

static const double *rp_xy(const replay *r, uint32_t v) {
    return r->s->xy + 2 * (size_t)v;
}

/* t rotated to start at its smallest number, into out. */
static void rp_rotate(const uint32_t *t, uint32_t *out) {
    int k = t[0] <= t[1] && t[0] <= t[2] ? 0 : t[1] <= t[2] ? 1 : 2;
    for (int j = 0; j < 3; j++) out[j] = t[(k + j) % 3];
}

static int rp_valid(const replay *r, uint32_t v) {
    return v == VOR_INFINITE || v < r->s->n;
}

static void rp_add(replay *r, const uint32_t *t) {
    uint32_t k[3];
    if (!rp_valid(r, t[0]) || !rp_valid(r, t[1]) || !rp_valid(r, t[2]) ||
        t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
        rp_fail(r, "bad triangle (%u, %u, %u)", t[0], t[1], t[2]);
        return;
    }
    int ghost = t[0] == VOR_INFINITE || t[1] == VOR_INFINITE || t[2] == VOR_INFINITE;
    if (!ghost && vor_orient2d(rp_xy(r, t[0]), rp_xy(r, t[1]), rp_xy(r, t[2])) <= 0) {
        rp_fail(r, "triangle (%u, %u, %u) is not counter-clockwise", t[0], t[1], t[2]);
        return;
    }
    rp_rotate(t, k);
    if (rp_set_add(&r->tris, k)) rp_fail(r, "triangle (%u, %u, %u) added twice", t[0], t[1], t[2]);
    r->created++;
}

static void rp_remove(replay *r, const uint32_t *t) {
    uint32_t k[3];
    rp_rotate(t, k);
    if (rp_set_remove(&r->tris, k))
        rp_fail(r, "triangle (%u, %u, %u) removed but not there", t[0], t[1], t[2]);
    r->removed++;
}

/* Exact "conflict" of site p with triangle t, by the rule of the
 * incremental algorithms: a finite triangle's circumcircle contains p
 * strictly; a ghost (a, b, INF), the outside of hull edge b->a, conflicts
 * when p is strictly left of a->b or strictly inside segment ab. */
static int rp_conflict(const replay *r, const uint32_t *t, uint32_t p) {
    const double *pp = rp_xy(r, p);
    for (int k = 0; k < 3; k++) {
        if (t[k] != VOR_INFINITE) continue;
        const double *a = rp_xy(r, t[(k + 1) % 3]), *b = rp_xy(r, t[(k + 2) % 3]);
        int o = vor_orient2d(a, b, pp);
        if (o != 0) return o > 0;
        for (int c = 0; c < 2; c++)
            if (a[c] != b[c])
                return a[c] < b[c] ? a[c] < pp[c] && pp[c] < b[c]
                                   : b[c] < pp[c] && pp[c] < a[c];
        return 0;
    }
    return vor_incircle(rp_xy(r, t[0]), rp_xy(r, t[1]), rp_xy(r, t[2]), pp) > 0;
}

static void rp_counts_step(replay *r, const vor_step *st) {
    if (!st->counts) {
        rp_fail(r, "%s step without counts", vor_step_kind_name(st->kind));
        return;
    }
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++) {
        if (vor_count_value(st->counts, i) < vor_count_value(&r->last, i))
            rp_fail(r, "count %s went down", vor_count_name(i));
    }
    r->last = *st->counts;
}

/* The beach line the step carries equals ours. */
static void rp_same_beach(replay *r, const vor_step *st) {
    if (st->n_beach != r->n_beach ||
        memcmp(st->beach, r->beach, r->n_beach * sizeof *r->beach) != 0)
        rp_fail(r, "%s step: beach line of %zu arcs, replay has %zu",
                vor_step_kind_name(st->kind), st->n_beach, r->n_beach);
    if (r->n_beach > r->beach_max) r->beach_max = r->n_beach;
}

/* Inserts k sites at position at of the beach line. */
static void rp_beach_insert(replay *r, size_t at, const uint32_t *v, size_t k) {
    memmove(r->beach + at + k, r->beach + at, (r->n_beach - at) * sizeof *r->beach);
    memcpy(r->beach + at, v, k * sizeof *v);
    r->n_beach += k;
}

static void rp_step_incremental(replay *r, const vor_step *st) {
    switch (st->kind) {
    case VOR_STEP_BEGIN: {
        if (r->n_order < 3) RP_FAIL(r, "begin before the order");
        uint32_t a = r->order[0], b = r->order[1], c = r->order[2];
        const uint32_t *t = st->tri;
        int same = (t[0] == a || t[0] == b || t[0] == c) &&
                   (t[1] == a || t[1] == b || t[1] == c) &&
                   (t[2] == a || t[2] == b || t[2] == c);
        if (!same) RP_FAIL(r, "the first triangle is not order[0..2]");
        rp_add(r, t);
        for (int k = 0; k < 3; k++) {
            uint32_t g[3] = {t[(k + 1) % 3], t[k], VOR_INFINITE};
            rp_add(r, g);
        }
        r->next = 3;
        return;
    }
    case VOR_STEP_INSERT: {
        uint32_t p = st->site;
        if (r->next >= r->n_order || p != r->order[r->next])
            RP_FAIL(r, "site %u inserted out of order", p);
        r->next++;
        if (st->n_cavity == 0 || st->n_star != st->n_cavity + 2)
            RP_FAIL(r, "site %u: cavity of %zu, star of %zu triangles", p,
                           st->n_cavity, st->n_star);
        if (memcmp(st->tri, st->cavity, sizeof st->tri) != 0 &&
            st->split != VOR_SPLIT_HULL)
            RP_FAIL(r, "site %u: located triangle not in the cavity", p);
        for (size_t i = 0; i < st->n_cavity; i++) {
            const uint32_t *t = st->cavity + 3 * i;
            if (r->algorithm == VOR_BOWYER_WATSON && !rp_conflict(r, t, p))
                RP_FAIL(r, "site %u: cavity triangle (%u, %u, %u) does "
                                  "not conflict", p, t[0], t[1], t[2]);
            rp_remove(r, t);
        }
        for (size_t i = 0; i < st->n_star; i++) {
            const uint32_t *t = st->star + 3 * i;
            if (t[0] != p && t[1] != p && t[2] != p)
                RP_FAIL(r, "site %u: star triangle without it", p);
            rp_add(r, t);
        }
        /* Bowyer-Watson: no triangle left in the mesh conflicts with p
         * across the cavity's boundary (checked on the star's outer
         * neighbours by the final Delaunay conversion instead: every
         * interior edge is tested there). */
        return;
    }
    case VOR_STEP_FLIP: {
        if (r->algorithm != VOR_FLIP) RP_FAIL(r, "flip step");
        const uint32_t *t = st->tri;
        uint32_t a = t[0], b = t[1], p = t[2], d = st->added[1];
        if (st->edge[0] != a || st->edge[1] != b || st->added[0] != p)
            RP_FAIL(r, "flip: fields disagree");
        if (!rp_valid(r, d) || d == VOR_INFINITE ||
            vor_incircle(rp_xy(r, a), rp_xy(r, b), rp_xy(r, p), rp_xy(r, d)) <= 0)
            RP_FAIL(r, "flip of %u-%u: %u not inside the circle of "
                              "(%u, %u, %u)", a, b, d, a, b, p);
        const uint32_t t1[3] = {a, b, p}, t2[3] = {b, a, d};
        const uint32_t n1[3] = {a, d, p}, n2[3] = {d, b, p};
        rp_remove(r, t1);
        rp_remove(r, t2);
        rp_add(r, n1);
        rp_add(r, n2);
        r->flips++;
        return;
    }
    default:
        RP_FAIL(r, "%s step in an incremental trace",
                       vor_step_kind_name(st->kind));
    }
}

static void rp_step_fortune(replay *r, const vor_step *st) {
    switch (st->kind) {
    case VOR_STEP_BEGIN: {
        if (r->n_order == 0 || st->n_beach == 0) RP_FAIL(r, "empty first row");
        for (size_t i = 0; i < st->n_beach; i++)
            if (st->beach[i] != r->order[i]) RP_FAIL(r, "first row out of order");
        double y = rp_xy(r, r->order[0])[1];
        if (st->y != y) RP_FAIL(r, "first row at the wrong y");
        for (size_t i = 0; i < r->n_order; i++) {
            int in_row = i < st->n_beach;
            if ((rp_xy(r, r->order[i])[1] == y) != in_row)
                RP_FAIL(r, "the first row is not the sites of the lowest y");
        }
        memcpy(r->beach, st->beach, st->n_beach * sizeof *r->beach);
        r->n_beach = st->n_beach;
        r->row = st->n_beach;
        r->next = st->n_beach;
        rp_same_beach(r, st);
        return;
    }
    case VOR_STEP_SITE: {
        uint32_t p = st->site;
        if (r->next >= r->n_order || p != r->order[r->next])
            RP_FAIL(r, "site %u out of sweep order", p);
        r->next++;
        if (st->y != rp_xy(r, p)[1]) RP_FAIL(r, "site %u: wrong y", p);
        size_t at = st->at;
        if (at == 0 || at > r->n_beach) RP_FAIL(r, "site %u: position %zu", p, at);
        if (st->arc != VOR_INFINITE) {
            if (r->beach[at - 1] != st->arc)
                RP_FAIL(r, "site %u: arc %zu is not of site %u", p, at - 1, st->arc);
            const uint32_t v[2] = {p, st->arc};
            rp_beach_insert(r, at, v, 2);
        } else {
            uint32_t l = st->breakpoint[0], rr = st->breakpoint[1];
            if (at >= r->n_beach || r->beach[at - 1] != l || r->beach[at] != rr)
                RP_FAIL(r, "site %u: no breakpoint (%u, %u) at %zu", p, l, rr, at);
            if (st->tri[0] != l || st->tri[1] != rr || st->tri[2] != p)
                RP_FAIL(r, "site %u: wrong triangle", p);
            rp_add(r, st->tri);
            r->hits++;
            rp_beach_insert(r, at, &p, 1);
        }
        rp_same_beach(r, st);
        return;
    }
    case VOR_STEP_CIRCLE: {
        size_t at = st->at;
        if (at == 0 || at + 1 >= r->n_beach) RP_FAIL(r, "circle at %zu", at);
        if (r->beach[at - 1] != st->tri[0] || r->beach[at] != st->tri[1] ||
            r->beach[at + 1] != st->tri[2])
            RP_FAIL(r, "circle (%u, %u, %u): not the arcs at %zu", st->tri[0],
                           st->tri[1], st->tri[2], at);
        if (rp_set_remove(&r->events, st->tri))
            RP_FAIL(r, "circle (%u, %u, %u) was not scheduled", st->tri[0],
                           st->tri[1], st->tri[2]);
        memmove(r->beach + at, r->beach + at + 1, (r->n_beach - at - 1) * sizeof *r->beach);
        r->n_beach--;
        rp_add(r, st->tri);
        rp_same_beach(r, st);
        return;
    }
    case VOR_STEP_SCHEDULE: {
        const uint32_t *t = st->tri;
        if (!rp_valid(r, t[0]) || !rp_valid(r, t[1]) || !rp_valid(r, t[2]) ||
            t[0] == VOR_INFINITE || t[1] == VOR_INFINITE || t[2] == VOR_INFINITE)
            RP_FAIL(r, "schedule: bad triple");
        if (vor_orient2d(rp_xy(r, t[0]), rp_xy(r, t[1]), rp_xy(r, t[2])) <= 0)
            RP_FAIL(r, "schedule (%u, %u, %u): breakpoints do not converge",
                           t[0], t[1], t[2]);
        /* the triple is three consecutive arcs */
        int adjacent = 0;
        for (size_t i = 1; i + 1 < r->n_beach && !adjacent; i++)
            adjacent = r->beach[i - 1] == t[0] && r->beach[i] == t[1] &&
                       r->beach[i + 1] == t[2];
        if (!adjacent) RP_FAIL(r, "schedule (%u, %u, %u): not on the beach line",
                                      t[0], t[1], t[2]);
        if (rp_set_add(&r->events, t)) RP_FAIL(r, "schedule: triple already pending");
        return;
    }
    case VOR_STEP_CANCEL:
        if (rp_set_remove(&r->events, st->tri))
            RP_FAIL(r, "cancel (%u, %u, %u): not pending", st->tri[0],
                           st->tri[1], st->tri[2]);
        return;
    default:
        RP_FAIL(r, "%s step in Fortune's trace", vor_step_kind_name(st->kind));
    }
}

/* The trace hook: ctx is a replay. */
static void rp_hook(void *ctx, const vor_step *st) {
    replay *r = ctx;
    if (r->err[0]) return;
    if ((unsigned)st->kind >= VOR_STEP_KIND_COUNT) RP_FAIL(r, "unknown kind");
    if (r->ended) RP_FAIL(r, "step after the end");
    rp_counts_step(r, st);
    int first = r->steps[VOR_STEP_ORDER] == 0;
    r->steps[st->kind]++;
    if (first != (st->kind == VOR_STEP_ORDER)) RP_FAIL(r, "order is not the first step");
    if (st->kind == VOR_STEP_ORDER) {
        size_t n = r->s->n;
        if (st->n_order != n) RP_FAIL(r, "order of %zu sites, not %zu", st->n_order, n);
        memset(r->tmp, 0, n * sizeof *r->tmp);
        for (size_t i = 0; i < n; i++) {
            if (st->order[i] >= n || r->tmp[st->order[i]]++)
                RP_FAIL(r, "order is not a permutation");
        }
        memcpy(r->order, st->order, n * sizeof *r->order);
        r->n_order = n;
        return;
    }
    if (st->kind == VOR_STEP_END) {
        r->ended = 1;
        if (r->next != r->n_order) RP_FAIL(r, "end before every site was taken");
        if (r->events.n != 0) RP_FAIL(r, "%zu circle events pending at the end", r->events.n);
        return;
    }
    if (r->algorithm == VOR_FORTUNE)
        rp_step_fortune(r, st);
    else
        rp_step_incremental(r, st);
}

/* Builds the finite triangles into a public-form mesh and converts it:
 * *out the diagram. Returns -1 with r->err set on failure. */
static int rp_finish(replay *r, vor_diagram **out) {
    *out = NULL;
    if (r->err[0]) return -1;
    if (!r->ended) {
        rp_fail(r, "no end step");
        return -1;
    }
    size_t nt = 0;
    for (size_t i = 0; i < r->tris.cap; i++) {
        const uint32_t *t = r->tris.key + 3 * i;
        if (r->tris.state[i] == 2 && t[0] != VOR_INFINITE && t[1] != VOR_INFINITE &&
            t[2] != VOR_INFINITE)
            nt++;
    }
    vor__mesh m = {0};
    m.tri = malloc((3 * nt + 1) * sizeof *m.tri);
    m.adj = malloc((3 * nt + 1) * sizeof *m.adj);
    uint64_t *he = malloc((3 * nt + 1) * sizeof *he); /* a << 32 | b, then e */
    uint32_t *ord = malloc((3 * nt + 1) * sizeof *ord);
    if (!m.tri || !m.adj || !he || !ord) {
        free(m.tri);
        free(m.adj);
        free(he);
        free(ord);
        rp_fail(r, "out of memory");
        return -1;
    }
    m.n_tri = m.cap_tri = nt;
    size_t t = 0;
    for (size_t i = 0; i < r->tris.cap; i++) {
        const uint32_t *k = r->tris.key + 3 * i;
        if (r->tris.state[i] != 2 || k[0] == VOR_INFINITE || k[1] == VOR_INFINITE ||
            k[2] == VOR_INFINITE)
            continue;
        memcpy(m.tri + 3 * t++, k, 3 * sizeof *k);
    }
    /* twins: sort the half-edges by (from, to), look up (to, from) */
    for (size_t e = 0; e < 3 * nt; e++) {
        uint32_t a = m.tri[e], b = m.tri[vor__next((uint32_t)e)];
        he[e] = (uint64_t)a << 32 | b;
        ord[e] = (uint32_t)e;
        m.adj[e] = -1;
    }
    /* simple heap sort of ord by he */
    size_t n = 3 * nt;
    for (size_t end = n, i = n / 2; end > 1;) {
        uint32_t v;
        size_t j;
        if (i > 0) {
            j = --i;
            v = ord[j];
        } else {
            v = ord[--end];
            ord[end] = ord[0];
            j = 0;
        }
        for (;;) {
            size_t c = 2 * j + 1;
            if (c >= end) break;
            if (c + 1 < end && he[ord[c]] < he[ord[c + 1]]) c++;
            if (he[v] >= he[ord[c]]) break;
            ord[j] = ord[c];
            j = c;
        }
        ord[j] = v;
    }
    for (size_t e = 0; e < n && !r->err[0]; e++) {
        uint64_t want = he[e] >> 32 | he[e] << 32;
        size_t lo = 0, hi = n;
        while (lo < hi) {
            size_t mid = (lo + hi) / 2;
            if (he[ord[mid]] < want) lo = mid + 1; else hi = mid;
        }
        if (lo < n && he[ord[lo]] == want) m.adj[e] = (int32_t)ord[lo];
        if (e > 0 && he[ord[e]] == he[ord[e - 1]]) rp_fail(r, "a half-edge twice");
    }
    free(he);
    free(ord);
    if (r->err[0]) {
        vor__mesh_clear(&m);
        return -1;
    }
    char msg[256];
    if (vor__mesh_check(&m, r->s, msg, sizeof msg)) {
        rp_fail(r, "final triangulation: %s", msg);
        vor__mesh_clear(&m);
        return -1;
    }
    vor_status st = vor__mesh_to_diagram(r->s, &m, out);
    vor__mesh_clear(&m);
    if (st != VOR_OK) {
        rp_fail(r, "conversion: %s", vor_status_message(st));
        return -1;
    }
    return 0;
}

#endif /* VOR_TESTS_REPLAY_H */
