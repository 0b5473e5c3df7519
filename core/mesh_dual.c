/* mesh_dual.c -- the canonical Voronoi diagram read straight off the
 * ghost-closed Delaunay mesh that Bowyer-Watson and flipping leave behind,
 * and that Fortune's sweep writes (fortune.c): the same diagram, bit for
 * bit, that vor__diagram_build (diagram.c) defines, without its sorting.
 *
 * Why a separate path. The mesh numbers vertices and triangles in
 * insertion order (Hilbert order for the incremental algorithms, sweep
 * order for Fortune), which is spatial (mesh.h); the canonical diagram is
 * ordered by site index, which is random in space. Every structure that
 * is visited in one order and written in the other costs a cache miss per
 * element, and a dependent chain of misses (a walk around a vertex at a
 * random place) costs a full memory latency per step. So the conversion
 * walks the mesh only in its own order, writes one compact record per
 * site, and does the rest in site order with sequential reads and writes:
 *
 *   count    one pass over the triangles: each site's number of finite
 *            neighbours (its cell size), prefix-summed into cell_start; a
 *            half-edge out of every vertex (outl).
 *   records  the fans in insertion order, a block of BLOCK vertices walked
 *            in lockstep so that their misses overlap. Each site's record
 *            goes to cell_start[site]: its finite neighbours counter-
 *            clockwise, starting after the ghost (hull site) or at its
 *            smallest neighbour (interior site) -- exactly the order of its
 *            cell, because the smallest neighbour's edge has the smallest
 *            edge id -- each slot with the neighbour's site and the
 *            triangle on the slot's left (rwt), and the record position of
 *            the twin slot (rx, which becomes cell_edges). Every interior
 *            edge is tested here, once, with the exact vor_incircle against
 *            the apexes of its two triangles (fan neighbours, already in
 *            the cache); a cocircular one is noted (a diagonal, see
 *            below), and past PATCH_MAX of them the pass stops. Where
 *            the construction proved that there are none
 *            (vor__mesh_hint), nothing is tested.
 *   sweep    sites in index order, records read in order. Site i owns the
 *            vertices whose other two sites exceed i (ids in (s1, s2)
 *            order: the canonical vertex order is by smallest site) and
 *            the edges to larger sites (ids in site order); an edge's ends
 *            are the ids of its two triangles, whose owners are at most i
 *            and so already numbered (vid, by triangle). Each new edge id
 *            is written into its slot; a slot of an edge to a smaller
 *            site reads the id from its twin slot, written when that
 *            site's turn came. So every record becomes its cell. Only vid
 *            and the twin slots are visited at random, prefetched
 *            SWEEP_AHEAD sites early; the twins are only read, so their
 *            lines stay clean (no write-back), which saved a few per cent of
 *            the sweep at 10^6 sites over writing the id into them.
 *   xy       vertex coordinates with vor_circumcenter from the three sites
 *            in increasing index order, ray directions with
 *            vor_bisector_dir, outward read off the ghost side: the same
 *            calls vor__diagram_build makes, hence the same bits.
 *
 * Twins meet through adj. The first of two neighbours to be visited
 * stashes its slot position in the adj of the twin half-edge (the one
 * pointing into itself: once a vertex's fan has been walked, the adj of a
 * half-edge into it is never read again, since walks read the adj of the
 * half-edges into their own vertex); the second reads it from the adj of
 * its own half-edge. Only the larger site of the two needs its twin's
 * position (to read the edge id there), so only that slot is linked; the
 * other slot holds garbage until its site's turn in the sweep.
 *
 * Cocircular sites. A vertex of four or more sites is one circle, which
 * the per-triangle records cannot express. The records pass notes the
 * diagonals of such polygons as it meets them and writes them as edges;
 * when it is done, the records of the few polygons' sites are patched in
 * place (see "few diagonals" below). Past PATCH_MAX diagonals the pass
 * stops instead: the adj entries stashed so far are restored (each pair
 * of twins has one half-edge from the earlier to the later visited
 * vertex, whose adj was never touched), every diagonal of a cocircular
 * polygon is marked and the polygon's triangles joined (see "cocircular
 * sites" below), and the passes run again with the diagonals left out
 * and each polygon standing for one vertex. Grids and integer pixels
 * thus take this path at the cost of one more pass over the edges; the
 * generic builder of diagram.c (vor__mesh_to_diagram), which it replaced
 * for such input, stays the definition the tests compare against.
 *
 * Cost: O(n) passes for sites of bounded degree, O(k log k) for a site of
 * degree k. Measured on uniform sites: about 47% of Bowyer-Watson's
 * instructions at 2 * 10^5 (cachegrind) and 28% of Fortune's CPU time at
 * 10^6 (perf), the records pass the larger part; vor__mesh_to_diagram took
 * longer than building the mesh. Memory: the mesh (48
 * bytes per site) with its coordinates (16), order (4), outl (4),
 * cell_start (4) and the records (12 per slot, 72); then, the mesh, its
 * coordinates and order freed, the records, vid (8) and the result
 * without its coordinates (about 101), which come last when everything
 * else is freed: 157 bytes per site at the peak, plus what the allocator
 * keeps. The mesh's adjacency array becomes the vertex sites, its
 * triangle array the edge sites, the coordinates in insertion order vid,
 * and the records' block the coordinates: at 10^6 sites each such array
 * is a fresh mapping that the kernel faults in and zeroes on first touch
 * (a tenth of a cold run; on a virtual machine whose host takes back
 * freed memory, a first touch can cost 2.5 ns a byte, half a cold run),
 * and reusing pages already touched spares 80 of the 281 bytes per site
 * so faulted in. Small diagrams (up to about 120
 * sites) keep outl, vid and the degree counts, and every diagram the
 * scratch of its first fans, in vor__mesh_dual's frame (6 KiB): for a
 * 10-site request the allocator's calls were a fifth of this file's
 * instructions.
 */
#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "mesh.h"

#define XY(v) (lxy + 2 * (size_t)(v))

/* Low word of a record slot whose left triangle is a ghost (the last slot
 * of a hull site's record); otherwise it is a triangle id. */
#define GHOST_T UINT32_MAX
/* A record slot freed when a few diagonals were patched out (patch()). */
#define HOLE UINT64_MAX
/* Lists of up to this many keys are ranked by counting or sorted by
 * insertion. */
#define SMALL_SORT 24
/* How far ahead (in vertices) the records and coordinates prefetch. */
#define AHEAD 48
/* Vertices walked together in the records pass, and the longest fan
 * walked that way (a longer one is walked again, alone). */
#define BLOCK 32
#define BLOCK_FAN 24
/* How many half-edges ahead the search for cocircular polygons
 * prefetches the twins' apexes (and half as many, their points). */
#define MERGE_AHEAD 32
/* How many sites ahead the sweep prefetches vid and the twin slots. */
#define SWEEP_AHEAD 8
/* Fan scratch slots that live in vor__mesh_dual's frame (about 4 KiB);
 * only a vertex of higher degree makes the scratch move to the heap. */
#define FAN0 64
_Static_assert(BLOCK_FAN < FAN0, "a block walk's fan fits the first scratch");
/* Words of vor__mesh_dual's frame that hold outl, the degree counts and
 * vid when together they fit (n + n + T words: up to about 120 sites),
 * so that a small diagram allocates only what it returns. */
#define SMALL_WORDS 512

/* Results of the passes besides a vor_status. PASS_BROKEN: the mesh breaks
 * its contract (a bug of ours: asserted in a debug build). */
enum { PASS_OK = 0, PASS_COCIRCULAR = 1, PASS_NOMEM = -1, PASS_BROKEN = -2 };

typedef struct key_slot {
    uint64_t key;
    uint32_t slot;
} key_slot;

typedef struct dual {
    const vor_sites *s;
    size_t n, T, h; /* sites; triangles, ghosts included; ghosts */
    uint32_t *tri;
    int32_t *adj;
    const double *lxy;
    const uint32_t *order;
    uint32_t *outl; /* n: a half-edge out of each local vertex */
    uint64_t *rwt;  /* per record slot: neighbour site << 32 | left triangle */
    uint32_t *vid;  /* T: vertex id of each (finite) triangle */
    /* scratch for one fan, cap slots: first in the caller's frame, then
     * in one heap block (heap, NULL until then) */
    uint32_t *he, *wl, *ws;
    key_slot *ks, *kt, *km;
    size_t cap;
    void *heap;
    /* outl, vid and count's degrees are in the caller's frame (small):
     * never freed */
    uint32_t *small;
    /* cocircular sites (see "cocircular sites"), all NULL without them:
     * a bit per half-edge set on the diagonals of cocircular polygons;
     * per triangle with a diagonal (in_polygon), its polygon's
     * representative triangle; per representative, the polygon's three
     * smallest sites. The other triangles are polygons of their own and
     * leave root and min3 unwritten (and their pages untouched) */
    uint8_t *cc;
    uint32_t *root;
    uint32_t *min3;
    int merge; /* the second pass: diagonals marked, polygons joined */
    int none;  /* the construction proved that no four sites are
                * cocircular: the first pass tests no edge */
    uint32_t tested; /* the first pass tested every edge at vertices below */
    /* the diagonals the first pass met (pairs of twin half-edges), to be
     * patched in (see "few diagonals"); the first met at vertex first_cc */
    uint32_t *diag;
    size_t n_diag, cap_diag;
    uint32_t first_cc;
    /* after a patch: the patched sites in increasing order, with the
     * length of each one's record; holes: slots freed in them */
    uint32_t *patched, *plen;
    size_t n_patched, holes;
    size_t n_poly; /* finite polygons (vertices of the diagram) */
    /* the result being written, and how far */
    vor_diagram *d;
    size_t nv, ne, nr;
} dual;

static inline int is_cc(const uint8_t *cc, uint32_t e) {
    return (cc[e >> 3] >> (e & 7)) & 1;
}

/* 1 if triangle t has a diagonal among its edges: it is part of a polygon
 * of more than one triangle (every such polygon's triangles have one). */
static inline int in_polygon(const uint8_t *cc, uint32_t t) {
    return is_cc(cc, 3 * t) | is_cc(cc, 3 * t + 1) | is_cc(cc, 3 * t + 2);
}

/* The fan scratch in s's FAN0 slots (vor__mesh_dual's frame). */
typedef struct fan_scratch {
    key_slot ks[FAN0], kt[FAN0], km[FAN0];
    uint32_t he[FAN0], wl[FAN0], ws[FAN0];
} fan_scratch;

static void scratch_init(dual *D, fan_scratch *s) {
    D->ks = s->ks;
    D->kt = s->kt;
    D->km = s->km;
    D->he = s->he;
    D->wl = s->wl;
    D->ws = s->ws;
    D->cap = FAN0;
}

/* Grows the fan scratch to at least k slots (doubling) in one new heap
 * block. The first cap entries of he, wl and ws are kept (a fan being
 * walked); ks, kt and km are filled only after a reserve. -1 when out of
 * memory, and nothing is changed. */
static int reserve(dual *D, size_t k) {
    if (k <= D->cap) return 0;
    const size_t slot = 3 * sizeof(key_slot) + 3 * sizeof(uint32_t);
    size_t cap = D->cap;
    while (cap < k) cap *= 2;
    if (cap > SIZE_MAX / slot) return -1;
    key_slot *ks = malloc(cap * slot);
    if (!ks) return -1;
    uint32_t *he = (uint32_t *)(ks + 3 * cap);
    memcpy(he, D->he, D->cap * sizeof *he);
    memcpy(he + cap, D->wl, D->cap * sizeof *he);
    memcpy(he + 2 * cap, D->ws, D->cap * sizeof *he);
    free(D->heap);
    D->heap = ks;
    D->ks = ks;
    D->kt = ks + cap;
    D->km = ks + 2 * cap;
    D->he = he;
    D->wl = he + cap;
    D->ws = he + 2 * cap;
    D->cap = cap;
    return 0;
}

/* Sorts a[0..k-1] by key (keys are distinct): insertion for short
 * lists, else a bottom-up merge through tmp. */
static void sort_ks(key_slot *a, key_slot *tmp, size_t k) {
    if (k <= SMALL_SORT) {
        for (size_t i = 1; i < k; i++) {
            key_slot x = a[i];
            size_t j = i;
            while (j > 0 && x.key < a[j - 1].key) {
                a[j] = a[j - 1];
                j--;
            }
            a[j] = x;
        }
        return;
    }
    for (size_t w = 1; w < k; w *= 2) {
        for (size_t lo = 0; lo < k; lo += 2 * w) {
            size_t mid = lo + w < k ? lo + w : k;
            size_t hi = lo + 2 * w < k ? lo + 2 * w : k;
            size_t i = lo, j = mid, o = lo;
            while (i < mid && j < hi)
                tmp[o++] = a[j].key < a[i].key ? a[j++] : a[i++];
            while (i < mid) tmp[o++] = a[i++];
            while (j < hi) tmp[o++] = a[j++];
        }
        memcpy(a, tmp, k * sizeof *a);
    }
}

/* Records the fan of the vertex that half-edge e0 leaves, counter-
 * clockwise: he[k] the half-edges, wl[k] the neighbours' local ids, ws[k]
 * their sites (VOR__GHOST for the ghost). *deg receives the count.
 * PASS_OK, PASS_NOMEM, or PASS_BROKEN if the walk does not close. */
static int walk_fan(dual *D, uint32_t e0, size_t *deg) {
    const uint32_t *tri = D->tri, *order = D->order;
    const int32_t *adj = D->adj;
    size_t k = 0;
    uint32_t e = e0;
    do {
        if (k == D->cap) {
            if (k > D->n) return PASS_BROKEN;
            if (reserve(D, k + 1)) return PASS_NOMEM;
        }
        uint32_t w = tri[vor__next(e)];
        D->he[k] = e;
        D->wl[k] = w;
        D->ws[k] = w == VOR__GHOST ? VOR__GHOST : order[w];
        k++;
        e = (uint32_t)adj[vor__prev(e)];
    } while (e != e0);
    *deg = k;
    return PASS_OK;
}

/* The most diagonals of cocircular polygons that the first records pass
 * notes and goes on for (patched in afterwards, see "few diagonals"), for
 * n sites; one more, and it stops there for the second pass. */
#define PATCH_MAX(n) ((n) / 256 + 16)

/* Notes diagonal e (out of vertex v, to a vertex visited later, so that
 * its adj and its twin's are still the mesh's). PASS_OK, PASS_COCIRCULAR
 * when the pass should stop for the second instead (too many), or
 * PASS_NOMEM. */
static int collect(dual *D, uint32_t e, uint32_t v) {
    if (D->n_diag == PATCH_MAX(D->n)) return PASS_COCIRCULAR;
    if (D->n_diag == D->cap_diag) {
        size_t cap = D->cap_diag ? 2 * D->cap_diag : 8;
        uint32_t *p = realloc(D->diag, 2 * cap * sizeof *p);
        if (!p) return PASS_NOMEM;
        D->diag = p;
        D->cap_diag = cap;
    }
    if (!D->n_diag) D->first_cc = v;
    D->diag[2 * D->n_diag] = e;
    D->diag[2 * D->n_diag + 1] = (uint32_t)D->adj[e];
    D->n_diag++;
    return PASS_OK;
}

/* ---- fast path: the records ----------------------------------------------
 * See the file comment. Cocircular edges are noted (collect);
 * PASS_COCIRCULAR at the one past PATCH_MAX, before anything of its vertex
 * is written (D->tested says up to where none was met). In the second
 * pass (D->merge) the diagonals, marked, are left out instead. */
static inline __attribute__((always_inline)) int
build_records_as(dual *D, const int merge, const int test) {
    const size_t n = D->n;
    const uint32_t *tri = D->tri;
    int32_t *adj = D->adj;
    const double *lxy = D->lxy;
    const uint32_t *order = D->order, *outl = D->outl, *cs = D->d->cell_start;
    uint64_t *rwt = D->rwt;
    uint32_t *rx = D->d->cell_edges;
    /* per vertex of the block: its fan's half-edges and neighbours so far,
     * where its walk is, and the vertices still walking */
    uint32_t fan[BLOCK][BLOCK_FAN], fanw[BLOCK][BLOCK_FAN], cur[BLOCK];
    uint8_t fdeg[BLOCK], act[BLOCK];
    const uint8_t *cc = merge ? D->cc : NULL;
    const uint32_t *root = merge ? D->root : NULL;

    for (size_t v = 0; v < n; v++) {
        const size_t j = v % BLOCK;
        if (j == 0) {
            /* walk the block's fans together: their misses overlap. A
             * vertex leaves the active list when its fan closes, or when
             * it is too long (fdeg 0: walked again, alone) */
            const size_t nb = n - v < BLOCK ? n - v : BLOCK;
            size_t na = nb;
            for (size_t b = 0; b < nb; b++) {
                cur[b] = outl[v + b];
                fdeg[b] = 0;
                act[b] = (uint8_t)b;
            }
            while (na) {
                for (size_t i = 0; i < na;) {
                    const size_t b = act[i];
                    uint32_t e = cur[b];
                    if (fdeg[b] == BLOCK_FAN) {
                        fdeg[b] = 0;
                        act[i] = act[--na];
                        continue;
                    }
                    uint32_t w = tri[vor__next(e)];
                    fan[b][fdeg[b]] = e;
                    fanw[b][fdeg[b]++] = w;
                    if (w != VOR__GHOST) {
                        __builtin_prefetch(order + w);
                        if (test) __builtin_prefetch(lxy + 2 * (size_t)w);
                    }
                    e = (uint32_t)adj[vor__prev(e)];
                    if (e == fan[b][0]) {
                        act[i] = act[--na];
                        continue;
                    }
                    __builtin_prefetch(adj + e);
                    __builtin_prefetch(tri + e);
                    cur[b] = e;
                    i++;
                }
            }
        }
        /* where the records of vertices AHEAD/2 on go, and, before that,
         * where to find it */
        if (v + AHEAD < n) __builtin_prefetch(cs + order[v + AHEAD]);
        if (v + AHEAD / 2 < n) {
            uint32_t q = cs[order[v + AHEAD / 2]];
            __builtin_prefetch(rwt + q, 1);
            __builtin_prefetch(rx + q, 1);
        }
        size_t deg = fdeg[j];
        const uint32_t *he, *wl, *ws = D->ws;
        if (deg) { /* fits the scratch: cap >= FAN0 > BLOCK_FAN */
            he = fan[j];
            wl = fanw[j];
            for (size_t k = 0; k < deg; k++) {
                uint32_t w = wl[k];
                D->ws[k] = w == VOR__GHOST ? VOR__GHOST : order[w];
            }
        } else {
            int r = walk_fan(D, outl[v], &deg);
            if (r != PASS_OK) return r;
            he = D->he;
            wl = D->wl;
            ws = D->ws; /* walk_fan may have grown the scratch */
        }
        const double *pv = XY(v);

        /* interior edges to vertices visited later: not cocircular?
         * (once they are marked, the diagonals are left out instead) */
        size_t ghost = deg, start = 0;
        uint32_t least = UINT32_MAX;
        for (size_t k = 0; k < deg; k++) {
            if (wl[k] == VOR__GHOST) {
                ghost = k;
                continue;
            }
            if (cc) {
                if (!is_cc(cc, he[k]) && ws[k] < least) {
                    least = ws[k];
                    start = k;
                }
                continue;
            }
            if (ws[k] < least) {
                least = ws[k];
                start = k;
            }
#ifdef NDEBUG
            if (!test) continue; /* a debug build checks the proof */
#endif
            if (wl[k] < v) continue;
            size_t kp = k ? k - 1 : deg - 1, kn = k + 1 < deg ? k + 1 : 0;
            if (wl[kp] == VOR__GHOST || wl[kn] == VOR__GHOST) continue;
            int ic = vor__incircle_local(pv, XY(wl[k]), XY(wl[kn]), XY(wl[kp]));
            if (ic > 0) return PASS_BROKEN;
            assert(test || ic != 0);
            if (ic == 0 && (ic = collect(D, he[k], (uint32_t)v)) != PASS_OK) {
                /* edges at vertices below the first diagonal's were all
                 * tested, and are none */
                D->tested = D->n_diag ? D->first_cc : (uint32_t)v;
                return ic;
            }
        }
        if (ghost < deg) start = ghost + 1 == deg ? 0 : ghost + 1;

        /* the record, in cell order. Twins meet through adj: x is either
         * the position of the neighbour's slot (visited earlier), or the
         * twin half-edge, whose adj then gets ours. A slot keeps its
         * twin's position only where the sweep will use it, at the
         * larger site (which reads the edge's id there, written by the
         * smaller one, its owner): so the neighbour's slot gets ours only
         * if the neighbour is the larger site. */
        const uint32_t si = order[v];
        uint32_t p = cs[si];
        for (size_t c = 0, k = start; c < deg; c++, k = k + 1 == deg ? 0 : k + 1) {
            if (k == ghost || (cc && is_cc(cc, he[k]))) continue;
            const uint32_t x = (uint32_t)adj[he[k]], t = he[k] / 3;
            rwt[p] = (uint64_t)ws[k] << 32 |
                     (root && in_polygon(cc, t) ? root[t] : t);
            rx[p] = x;
            if (wl[k] > v)
                adj[x] = (int32_t)p;
            else if (ws[k] > si)
                rx[x] = p;
            p++;
        }
        if (ghost < deg) /* the last slot's left triangle is a ghost */
            rwt[p - 1] |= GHOST_T;
    }
    return PASS_OK;
}

/* The pass compiled twice (always inlined, with merge a constant), so
 * that the usual one carries none of the merged pass's tests. */
static int build_records(dual *D) {
    return D->merge  ? build_records_as(D, 1, 0)
           : D->none ? build_records_as(D, 0, 0)
                     : build_records_as(D, 0, 1);
}

/* Until ray_directions: the two sites whose bisector's direction a ray
 * takes, in the order vor_bisector_dir takes them, in the bytes of its
 * direction. */
static inline void ray_put(double *dir, uint32_t a, uint32_t b) {
    uint32_t ab[2] = {a, b};
    memcpy(dir, ab, sizeof ab);
}

/* ---- fast path: the sweep in site order ------------------------------------
 * See the file comment. A hull site's record has the ghost right of its
 * first slot and left of its last; an interior site's record is a cycle. */
static int sweep_records(dual *D) {
    const size_t n = D->n;
    const uint64_t *rwt = D->rwt;
    uint32_t *vid = D->vid;
    vor_diagram *d = D->d;
    const uint32_t *cs = d->cell_start;
    uint32_t *rx = d->cell_edges, *vsites = d->vertex_sites, *esites = d->edge_sites;
    int32_t *eends = d->edge_ends;
    const uint32_t *min3 = D->min3;
    const uint8_t *cc = D->cc;
    size_t nv = 0, ne = 0, nr = 0;
#define RW(p) ((uint32_t)(rwt[p] >> 32))
#define RT(p) ((uint32_t)rwt[p])
    for (size_t i = 0; i < n; i++) {
        const uint32_t si = (uint32_t)i, lo = cs[i];
        uint32_t hi = cs[i + 1];
        if (D->holes) /* a patched record ends at its first hole */
            while (hi > lo && rwt[hi - 1] == HOLE) hi--;
        if (hi - lo < 2) return PASS_BROKEN;
        if (hi - lo > D->cap && reserve(D, hi - lo)) return PASS_NOMEM;
        key_slot *ko = D->ks, *ku = D->kt;
        if (i + SWEEP_AHEAD < n) { /* vid and the twins, a few sites on */
            const uint32_t ia = (uint32_t)(i + SWEEP_AHEAD);
            for (uint32_t p = cs[ia]; p < cs[ia + 1]; p++) {
                uint32_t t = RT(p);
                if (t != GHOST_T) {
                    __builtin_prefetch(vid + t, 1);
                    /* a polygon's smallest site (merged pass only) */
                    if (min3) __builtin_prefetch(min3 + 3 * (size_t)t);
                }
                if (RW(p) < ia) __builtin_prefetch(rx + rx[p]);
            }
        }
        const int hull = RT(hi - 1) == GHOST_T;

        /* the vertices i owns and the edges to larger sites */
        size_t no = 0, nu = 0;
        uint32_t b = RW(lo);
        for (uint32_t p = hi; p-- > lo;) {
            const uint32_t a = RW(p), t = RT(p);
            if (a < si) /* the owner a has written the edge's id */
                rx[p] = rx[rx[p]];
            else {
                ku[nu].key = a;
                ku[nu++].slot = p - lo;
                if (t == GHOST_T) {
                    /* no vertex */
                } else if (!min3 || !in_polygon(cc, t)) {
                    if (b > si) { /* a triangle whose smallest site is i */
                        ko[no].key = a < b ? (uint64_t)a << 32 | b
                                           : (uint64_t)b << 32 | a;
                        ko[no++].slot = p - lo;
                    }
                } else if (min3[3 * (size_t)t] == si) {
                    /* a polygon's owner is its smallest site */
                    ko[no].key = (uint64_t)min3[3 * (size_t)t + 1] << 32 |
                                 min3[3 * (size_t)t + 2];
                    ko[no++].slot = p - lo;
                }
            }
            b = a;
        }
        /* ids by rank: counted for the usual few, sorted for many */
        if (no > SMALL_SORT) sort_ks(ko, D->km, no);
        for (size_t j = 0; j < no; j++) {
            uint32_t r = (uint32_t)j;
            if (no <= SMALL_SORT) {
                r = 0;
                for (size_t k = 0; k < no; k++) r += ko[k].key < ko[j].key;
            }
            uint32_t id = (uint32_t)nv + r, *vs = vsites + 3 * (size_t)id;
            vs[0] = si;
            vs[1] = (uint32_t)(ko[j].key >> 32);
            vs[2] = (uint32_t)ko[j].key;
            vid[RT(lo + ko[j].slot)] = id;
        }
        nv += no;
        if (nu > SMALL_SORT) sort_ks(ku, D->km, nu);
        uint32_t ray_e[2], ray_p[2], nri = 0;
        for (size_t j = 0; j < nu; j++) {
            const uint32_t p = lo + ku[j].slot, w = (uint32_t)ku[j].key;
            uint32_t r = (uint32_t)j;
            if (nu <= SMALL_SORT) {
                r = 0;
                for (size_t k = 0; k < nu; k++) r += ku[k].key < w;
            }
            const uint32_t e = (uint32_t)ne + r;
            const uint32_t tl = RT(p), tr = p > lo ? RT(p - 1) : hull ? GHOST_T : RT(hi - 1);
            const int32_t vl = tl == GHOST_T ? VOR_NONE : (int32_t)vid[tl];
            const int32_t vr = tr == GHOST_T ? VOR_NONE : (int32_t)vid[tr];
            esites[2 * (size_t)e] = si;
            esites[2 * (size_t)e + 1] = w;
            if (vl >= 0 && vr >= 0) {
                eends[2 * (size_t)e] = vl < vr ? vl : vr;
                eends[2 * (size_t)e + 1] = vl < vr ? vr : vl;
            } else { /* a hull edge */
                eends[2 * (size_t)e] = vl >= 0 ? vl : vr;
                eends[2 * (size_t)e + 1] = VOR_NONE;
                if (nri == 2) return PASS_BROKEN;
                ray_e[nri] = e;
                ray_p[nri++] = p;
            }
            rx[p] = e;
        }
        ne += nu;
        /* rays, in edge order: each leaves the finite side, away from the
         * ghost */
        if (nri == 2 && ray_e[1] < ray_e[0]) {
            uint32_t x = ray_e[0];
            ray_e[0] = ray_e[1];
            ray_e[1] = x;
            x = ray_p[0];
            ray_p[0] = ray_p[1];
            ray_p[1] = x;
        }
        for (uint32_t j = 0; j < nri; j++) {
            const uint32_t p = ray_p[j];
            d->ray_edge[nr] = ray_e[j];
            /* the ghost is on the right of i -> w when p == lo: the
             * direction's sites, in order, until ray_directions */
            ray_put(d->ray_dir + 2 * nr, p == lo ? RW(p) : si, p == lo ? si : RW(p));
            nr++;
        }
        d->cell_bounded[i] = !hull;
    }
#undef RW
#undef RT
    D->nv = nv;
    D->ne = ne;
    D->nr = nr;
    return PASS_OK;
}

/* Ray directions with vor_bisector_dir, as vor__diagram_build computes
 * them, from the sites that sweep_records put in their place (ray_put),
 * the sites prefetched AHEAD rays early: in a pass of their own, the
 * square roots and divisions of many rays overlap, where in the sweep
 * each waited behind its misses (sites in convex position have a ray
 * each: 5% of Bowyer-Watson's time on 10^6 sites on a circle). */
static void ray_directions(const vor_sites *s, vor_diagram *d) {
    const double *sxy = s->xy;
    double *dir = d->ray_dir;
    const size_t nr = d->n_rays;
    for (size_t r = 0; r < nr; r++) {
        uint32_t ab[2];
        if (r + AHEAD < nr) {
            memcpy(ab, dir + 2 * (r + AHEAD), sizeof ab);
            __builtin_prefetch(sxy + 2 * (size_t)ab[0]);
            __builtin_prefetch(sxy + 2 * (size_t)ab[1]);
        }
        memcpy(ab, dir + 2 * r, sizeof ab);
        vor_bisector_dir(sxy + 2 * (size_t)ab[0], sxy + 2 * (size_t)ab[1], dir + 2 * r);
    }
}

/* Vertex coordinates from their three sites in increasing index order,
 * as vor__diagram_build computes them: the first site's coordinates are
 * read in order, the other two prefetched AHEAD vertices early. */
static void vertex_coordinates(const vor_sites *s, vor_diagram *d) {
    const double *sxy = s->xy;
    const uint32_t *vs = d->vertex_sites;
    const size_t nv = d->n_vertices;
    for (size_t v = 0; v < nv; v++) {
        if (v + AHEAD < nv) {
            __builtin_prefetch(sxy + 2 * (size_t)vs[3 * (v + AHEAD) + 1]);
            __builtin_prefetch(sxy + 2 * (size_t)vs[3 * (v + AHEAD) + 2]);
        }
        const double *a = sxy + 2 * (size_t)vs[3 * v], *b = sxy + 2 * (size_t)vs[3 * v + 1],
                     *c = sxy + 2 * (size_t)vs[3 * v + 2];
        if (!vor__circumcenter_fast(a, b, c, d->vertex_xy + 2 * v))
            vor_circumcenter(a, b, c, d->vertex_xy + 2 * v);
    }
}

/* ---- cocircular sites ------------------------------------------------------
 * Four or more cocircular sites make one vertex, which the per-triangle
 * records cannot express. When build_records stops (one diagonal past
 * PATCH_MAX, or a patch of too much work), the mesh is put back as the
 * construction left it (restore_adj), and merge_prepare marks every
 * diagonal of a cocircular polygon (an interior edge whose two triangles
 * share a circumcircle, exactly; the edges build_records has tested up to
 * its first diagonal are known not to be), joins the triangles of each
 * polygon under one representative (union-find, the smallest triangle id)
 * and notes each polygon's three smallest sites. Then the passes run again
 * with the diagonals left out of the degrees, the fans and the records,
 * with each slot's triangle replaced by its polygon's representative, and
 * with a polygon owned by its smallest site and keyed by the next two: a
 * diagonal is no Voronoi edge (its length is zero), and the polygon is one
 * vertex, whose defining sites are its three smallest. When the
 * construction met many signs of cocircular sites (vor__mesh_dual's
 * degenerate hint), polygons are likely many, and merge_prepare runs
 * first instead, over every edge, and its count is the only one: the
 * first pass would otherwise stop wherever it met the diagonal past
 * PATCH_MAX (early, on a grid) and start again. */

static int count(dual *D);

static uint32_t uf_find(uint32_t *root, uint32_t t) {
    while (root[t] != t) {
        root[t] = root[root[t]]; /* path halving */
        t = root[t];
    }
    return t;
}

/* Marks twin half-edges e and f a diagonal and joins the polygons of
 * their triangles under the smaller representative. */
static void join(uint8_t *cc, uint32_t *root, uint32_t e, uint32_t f) {
    uint32_t x = e / 3, y = f / 3;
    if (!in_polygon(cc, x)) root[x] = x; /* joins its first polygon */
    if (!in_polygon(cc, y)) root[y] = y;
    cc[e >> 3] |= (uint8_t)(1u << (e & 7));
    cc[f >> 3] |= (uint8_t)(1u << (f & 7));
    x = uf_find(root, x);
    y = uf_find(root, y);
    if (x < y)
        root[y] = x;
    else if (y < x)
        root[x] = y;
}


/* Triangle t, of a polygon of several, is pointed at its representative
 * (the smallest triangle of the polygon, met first in increasing order),
 * and its sites join the representative's three smallest. 1 if t is the
 * representative. */
static int add_to_polygon(dual *D, uint32_t t) {
    const uint32_t *v = D->tri + 3 * (size_t)t;
    const uint32_t r = D->root[t] = uf_find(D->root, t);
    uint32_t *m = D->min3 + 3 * (size_t)r;
    if (r == t) m[0] = m[1] = m[2] = UINT32_MAX;
    vor__min3_add(m, D->order[v[0]]);
    vor__min3_add(m, D->order[v[1]]);
    vor__min3_add(m, D->order[v[2]]);
    return r == t;
}

/* See above. Recounts the cells (count) without the diagonals. PASS_OK,
 * PASS_NOMEM, or PASS_BROKEN if an edge is not locally Delaunay. */
static int merge_prepare(dual *D) {
    const size_t T = D->T;
    const uint32_t *tri = D->tri;
    const int32_t *adj = D->adj;
    const double *lxy = D->lxy;
    D->cc = calloc((3 * T + 7) / 8, 1);
    D->root = vor__alloc_large(T, sizeof *D->root);
    if (!D->cc || !D->root) return PASS_NOMEM;
    uint8_t *cc = D->cc;
    uint32_t *root = D->root; /* set for triangles in polygons only */
    for (uint32_t e = 0; e < 3 * T; e++) {
        /* the twin's apex and the four points, read at random where the
         * mesh's neighbours are far apart in its order (points in convex
         * position): fetched MERGE_AHEAD and MERGE_AHEAD / 2 edges early */
        if (e + MERGE_AHEAD < 3 * T) {
            const uint32_t g = (uint32_t)adj[e + MERGE_AHEAD];
            __builtin_prefetch(tri + vor__prev(g));
            __builtin_prefetch(XY(tri[e + MERGE_AHEAD] & 0x3fffffffu));
        }
        if (e + MERGE_AHEAD / 2 < 3 * T) {
            const uint32_t g = (uint32_t)adj[e + MERGE_AHEAD / 2];
            __builtin_prefetch(XY(tri[vor__prev(g)] & 0x3fffffffu));
        }
        const uint32_t f = (uint32_t)adj[e];
        if (f < e) continue; /* each edge once */
        const uint32_t a = tri[e], b = tri[vor__next(e)], c = tri[vor__prev(e)],
                       d = tri[vor__prev(f)];
        if (((a | b | c | d) >> 30) != 0) continue; /* a ghost: hull edge */
        /* build_records tested each edge at its earlier vertex, up to
         * the vertex where it stopped: all of those but that vertex's
         * are no diagonals */
        if ((a < b ? a : b) < D->tested) continue;
        int ic = vor__incircle_local(XY(a), XY(b), XY(c), XY(d));
        if (ic > 0) return PASS_BROKEN;
        if (ic < 0) continue;
        join(cc, root, e, f);
    }
    /* flatten, count the finite polygons, note the smallest sites of
     * those of several triangles (a lone triangle's are its own, which
     * sweep_records reads off its records): min3 is written only at
     * their representatives, so that on input with few cocircular sites
     * (points on a circle: one polygon in 10^6 sites) its pages are
     * never touched */
    D->min3 = vor__alloc_large(3 * T, sizeof *D->min3);
    if (!D->min3) return PASS_NOMEM;
    size_t np = 0;
    for (size_t t = 0; t < T; t++) {
        const uint32_t *v = tri + 3 * t;
        if (((v[0] | v[1] | v[2]) >> 30) != 0) continue; /* ghost */
        if (!in_polygon(cc, (uint32_t)t)) { /* a polygon of its own */
            np++;
            continue;
        }
        np += add_to_polygon(D, (uint32_t)t);
    }
    D->n_poly = np;
    D->merge = 1;
    return count(D);
}

/* Puts back the adj entries build_records overwrote: each pair of twins
 * has one half-edge from the earlier to the later visited vertex, whose
 * adj was never touched. */
static void restore_adj(dual *D) {
    const uint32_t *tri = D->tri;
    int32_t *adj = D->adj;
    for (size_t e = 0; e < 3 * D->T; e++) {
        uint32_t a = tri[e], b = tri[vor__next((uint32_t)e)];
        if (a == VOR__GHOST || b == VOR__GHOST) continue;
        if (a < b) adj[adj[e]] = (int32_t)e;
    }
}

/* ---- few diagonals ----------------------------------------------------------
 * Points on a circle in floating point are nearly all cocircular within
 * rounding and exactly so only here and there (one polygon in 10^6 such
 * sites), and a uniform set may hold one square of pixels: a second pass
 * over every edge and every record for a handful of polygons cost a third
 * of the conversion. So the first records pass notes up to PATCH_MAX
 * diagonals and goes on, writing each as an edge, and patch() then
 * rewrites only the records of the polygons' sites, in place: the
 * diagonals left out, each triangle replaced by its polygon's
 * representative, interior cells rotated to start at their smallest
 * neighbour again, the slots freed at the end of each record marked
 * HOLE. Their twins are linked anew, by a search of the neighbour's
 * record. The sweep stops at a record's first hole, and squeeze() closes
 * them up in the cells' edges afterwards. The cc bits, representatives
 * and smallest sites are those merge_prepare would find; the work is
 * bounded by the patched records and their neighbours' (PATCH_WORK), and
 * beyond that the second pass runs instead. That bound is a pass's
 * slots: random sites on a lattice of 4096 x 4096 (10^5 of them) or 2^14
 * x 2^14 (10^6) leave a few hundred or thousand polygons, whose patch
 * reads 0.52 n and 0.27 n slots, where the second pass for them (at a
 * bound of n / 4) made flip's run 76 ms instead of 55 at 10^5 and 821-840
 * instead of 576-580 at 10^6 (CGAL: 57, 635). */
#define PATCH_WORK(n) ((n) + 4096)

static int cmp_u32(const void *a, const void *b) {
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* Sorts a[0..k-1] and drops repeats; returns the new length. */
static size_t sort_unique(uint32_t *a, size_t k) {
    qsort(a, k, sizeof *a, cmp_u32);
    size_t m = 0;
    for (size_t j = 0; j < k; j++)
        if (!m || a[j] != a[m - 1]) a[m++] = a[j];
    return m;
}

/* The position of site w's slot for site si (a live one: before any
 * hole), or UINT32_MAX. */
static uint32_t slot_of(const dual *D, uint32_t w, uint32_t si) {
    const uint32_t *cs = D->d->cell_start;
    for (uint32_t q = cs[w]; q < cs[w + 1] && D->rwt[q] != HOLE; q++)
        if ((uint32_t)(D->rwt[q] >> 32) == si) return q;
    return UINT32_MAX;
}

/* Patches the n_diag diagonals in (see above). PASS_OK, PASS_NOMEM,
 * PASS_BROKEN, or PASS_COCIRCULAR when the work would be too much (then
 * nothing is changed but D->tested; the second pass follows). */
static int patch(dual *D) {
    const size_t T = D->T;
    const uint32_t *tri = D->tri, *order = D->order, *cs = D->d->cell_start;
    const size_t nd = D->n_diag;
    uint32_t *pt = malloc(2 * nd * sizeof *pt), *pv = malloc(6 * nd * sizeof *pv);
    int r = PASS_NOMEM;
    if (!pt || !pv) goto out;
    /* the polygons' triangles and their sites, and the work of relinking
     * their records */
    for (size_t j = 0; j < 2 * nd; j++) pt[j] = D->diag[j] / 3;
    const size_t npt = sort_unique(pt, 2 * nd);
    for (size_t j = 0; j < npt; j++)
        for (int c = 0; c < 3; c++) pv[3 * j + c] = order[tri[3 * pt[j] + c]];
    const size_t npv = sort_unique(pv, 3 * npt);
    size_t work = 0;
    for (size_t j = 0; j < npv; j++)
        for (uint32_t p = cs[pv[j]]; p < cs[pv[j] + 1]; p++) {
            uint32_t w = (uint32_t)(D->rwt[p] >> 32);
            work += cs[w + 1] - cs[w];
        }
    if (work > PATCH_WORK(D->n)) {
        D->tested = D->first_cc;
        r = PASS_COCIRCULAR;
        goto out;
    }
    /* mark and join, as merge_prepare does */
    D->cc = calloc((3 * T + 7) / 8, 1);
    D->root = vor__alloc_large(T, sizeof *D->root);
    D->min3 = vor__alloc_large(3 * T, sizeof *D->min3);
    D->patched = malloc(2 * npv * sizeof *D->patched);
    if (!D->cc || !D->root || !D->min3 || !D->patched) goto out;
    D->plen = D->patched + npv;
    uint8_t *cc = D->cc;
    uint32_t *root = D->root;
    for (size_t j = 0; j < nd; j++) {
        join(cc, root, D->diag[2 * j], D->diag[2 * j + 1]);
    }
    size_t roots = 0;
    for (size_t j = 0; j < npt; j++) /* increasing: a root before its own */
        roots += add_to_polygon(D, pt[j]);
    D->n_poly = T - D->h - npt + roots;
    /* each polygon site's record without its diagonals, in cell order */
    for (size_t j = 0; j < npv; j++) {
        const uint32_t si = pv[j], lo = cs[si], hi = cs[si + 1];
        if (reserve(D, hi - lo)) goto out;
        key_slot *ks = D->ks;
        size_t k = 0, start = 0;
        for (uint32_t p = lo; p < hi; p++) {
            uint64_t x = D->rwt[p];
            uint32_t t = (uint32_t)x;
            if (t != GHOST_T) {
                const uint32_t *v = tri + 3 * (size_t)t;
                uint32_t c = order[v[0]] == si ? 0 : order[v[1]] == si ? 1 : 2;
                if (is_cc(cc, 3 * t + c)) continue;
                if (in_polygon(cc, t)) x = (x >> 32) << 32 | root[t];
            }
            if (!k || (x >> 32) < (ks[start].key >> 32)) start = k;
            ks[k++].key = x;
        }
        if (k < 2) {
            r = PASS_BROKEN;
            goto out;
        }
        if ((uint32_t)ks[k - 1].key == GHOST_T) start = 0; /* a hull site */
        for (size_t c = 0; c < k; c++)
            D->rwt[lo + c] = ks[(start + c) % k].key;
        for (uint32_t p = lo + (uint32_t)k; p < hi; p++) D->rwt[p] = HOLE;
        D->patched[j] = si;
        D->plen[j] = (uint32_t)k;
        D->holes += hi - lo - k;
    }
    D->n_patched = npv;
    /* their twins: the larger site's slot holds the smaller's position */
    uint32_t *rx = D->d->cell_edges;
    for (size_t j = 0; j < npv; j++) {
        const uint32_t si = pv[j];
        for (uint32_t p = cs[si]; p < cs[si] + D->plen[j]; p++) {
            const uint32_t w = (uint32_t)(D->rwt[p] >> 32), q = slot_of(D, w, si);
            if (q == UINT32_MAX) {
                r = PASS_BROKEN;
                goto out;
            }
            if (w < si)
                rx[p] = q;
            else
                rx[q] = p;
        }
    }
    r = PASS_OK;
out:
    free(pt);
    free(pv);
    free(D->root);
    D->root = NULL;
    return r;
}

/* Closes up the holes that patch() left in the cells' edges and moves
 * cell_start with them. */
static void squeeze(dual *D) {
    uint32_t *cs = D->d->cell_start, *rx = D->d->cell_edges;
    const size_t n = D->n;
    size_t src = 0, dst = 0;
    for (size_t j = 0; j < D->n_patched; j++) {
        const uint32_t si = D->patched[j], end = cs[si] + D->plen[j];
        memmove(rx + dst, rx + src, (end - src) * sizeof *rx);
        dst += end - src;
        src = cs[si + 1];
    }
    memmove(rx + dst, rx + src, (cs[n] - src) * sizeof *rx);
    uint32_t shift = 0;
    for (size_t i = 0, j = 0; i <= n; i++) {
        const uint32_t lo = cs[i];
        cs[i] = lo - shift;
        if (j < D->n_patched && D->patched[j] == i)
            shift += cs[i + 1] - lo - D->plen[j++];
    }
}

/* ---- driver -------------------------------------------------------------- */

/* Counts, per site, its finite neighbours (into cell_start, then made
 * offsets), finds a half-edge out of every vertex and counts the ghosts.
 * One pass over the triangles, one over the sites. */
static int count(dual *D) {
    const size_t n = D->n, T = D->T;
    const uint32_t *tri = D->tri, *order = D->order;
    const uint8_t *cc = D->cc;
    uint32_t *cs = D->d->cell_start, *outl = D->outl;
    uint32_t *deg; /* per local vertex */
    if (D->small) {
        deg = D->small + n;
        memset(deg, 0, n * sizeof *deg);
    } else if (!(deg = vor__scratch_new(n, sizeof *deg))) {
        return PASS_NOMEM;
    }
    size_t h = 0;
    for (size_t t = 0; t < T; t++) {
        const uint32_t *v = tri + 3 * t;
        if (((v[0] | v[1] | v[2]) >> 30) == 0) { /* finite: site ids < 2^30 */
            outl[v[0]] = 3 * (uint32_t)t;
            outl[v[1]] = 3 * (uint32_t)t + 1;
            outl[v[2]] = 3 * (uint32_t)t + 2;
            if (cc) { /* the diagonals of cocircular polygons are no edges */
                deg[v[0]] += !is_cc(cc, 3 * (uint32_t)t);
                deg[v[1]] += !is_cc(cc, 3 * (uint32_t)t + 1);
                deg[v[2]] += !is_cc(cc, 3 * (uint32_t)t + 2);
                continue;
            }
            deg[v[0]]++;
            deg[v[1]]++;
            deg[v[2]]++;
            continue;
        }
        h++;
        for (uint32_t k = 0; k < 3; k++) {
            uint32_t a = v[k], b = v[k == 2 ? 0 : k + 1];
            if (a == VOR__GHOST) continue;
            outl[a] = 3 * (uint32_t)t + k;
            deg[a] += b != VOR__GHOST;
        }
    }
    D->h = h;
    for (size_t v = 0; v < n; v++) cs[order[v]] = deg[v];
    if (!D->small) vor__scratch_free(deg);
    size_t nc = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t k = cs[i];
        cs[i] = (uint32_t)nc;
        nc += k;
    }
    cs[n] = (uint32_t)nc;
    return PASS_OK;
}

static vor_status status_of(int r) {
    assert(r != PASS_BROKEN && "vor__mesh_dual: the mesh is broken");
    return r == PASS_NOMEM ? VOR_ENOMEM : VOR_EINVAL;
}

/* Makes block p, whose contents are no longer needed, an array of count
 * elements of size bytes: realloc shrinks (or grows) it in place where it
 * can, so that pages already touched serve again instead of fresh ones
 * that the kernel must fault in and zero (at 10^6 sites that is a tenth
 * of a cold run). NULL on failure, and p is then still the caller's. */
static void *reuse(void *p, size_t count, size_t size) {
    if (count == 0) count = 1;
    if (count > SIZE_MAX / size) return NULL;
    return realloc(p, count * size);
}

/* The records and the cells' edge slots, sized by the counts in
 * cell_start. */
static int alloc_records(dual *D) {
    const size_t slots = D->d->cell_start[D->n];
    D->d->cell_edges = vor__alloc_scattered(slots, sizeof *D->d->cell_edges);
    D->rwt = vor__alloc_scattered(slots, sizeof *D->rwt);
    return D->d->cell_edges && D->rwt ? PASS_OK : PASS_NOMEM;
}

/* The output arrays sized for ne edges and nr rays (cell_start,
 * cell_edges and vertex_sites are allocated by the caller); the edge
 * sites are made of the mesh's triangle block *tri (as many words less
 * two per hull edge), which is then the result's. */
static int alloc_result(dual *D, uint32_t **tri, size_t ne, size_t nr) {
    vor_diagram *d = D->d;
    if ((d->edge_sites = reuse(*tri, 2 * ne, sizeof *d->edge_sites)))
        *tri = NULL;
    d->edge_ends = vor__alloc_large(2 * ne, sizeof *d->edge_ends);
    d->ray_edge = vor__alloc_large(nr, sizeof *d->ray_edge);
    d->ray_dir = vor__alloc_large(2 * nr, sizeof *d->ray_dir);
    d->cell_bounded = vor__alloc_large(D->n, 1);
    return d->edge_sites && d->edge_ends && d->ray_edge &&
                   d->ray_dir && d->cell_bounded
               ? PASS_OK
               : PASS_NOMEM;
}

vor_status vor__mesh_dual(const vor_sites *s, vor__mesh *m, double *lxy,
                          uint32_t *order, int degenerate, vor_diagram **out) {
    dual D;
    fan_scratch fan;
    uint32_t small[SMALL_WORDS];
    memset(&D, 0, sizeof D);
    vor_status st = VOR_ENOMEM;
    int r;
    *out = NULL;
    const size_t n = s->n, T = m->n_tri;
    D.s = s;
    D.n = n;
    D.T = T;
    D.tri = m->tri;
    D.adj = m->adj;
    D.lxy = lxy;
    D.order = order;
    scratch_init(&D, &fan);
    if (T <= SMALL_WORDS && 2 * n <= SMALL_WORDS - T) /* outl, deg; vid */
        D.small = small;

    vor_diagram *d = D.d = calloc(1, sizeof *d);
    D.outl = D.small ? D.small : vor__alloc_large(n, sizeof *D.outl);
    if (!d || !D.outl) goto done;
    d->n_sites = n;
    d->cell_start = vor__alloc_scattered(n + 1, sizeof *d->cell_start);
    if (!d->cell_start) goto done;
    /* where the construction met signs of cocircular sites, the polygons
     * are looked for at once (and the cells counted once, without the
     * diagonals): a first pass would run up to the first cocircular edge
     * only to start again (halfway through, for 10^5 sites on a circle) */
    D.none = degenerate < 0;
    r = degenerate > 0 ? PASS_COCIRCULAR : count(&D);
    if (r == PASS_OK) r = alloc_records(&D);
    if (r == PASS_OK) r = build_records(&D);
    if (r == PASS_OK && D.n_diag) r = patch(&D); /* a few diagonals */
    free(D.diag);
    D.diag = NULL;
    if (r == PASS_COCIRCULAR) { /* again, with the polygons merged */
        if (degenerate <= 0) restore_adj(&D);
        r = merge_prepare(&D);
        if (r == PASS_OK && !D.rwt) r = alloc_records(&D);
        if (r == PASS_OK) r = build_records(&D);
        free(D.root); /* cc stays for sweep_records (in_polygon) */
        D.root = NULL;
    }
    /* a vertex per finite polygon (triangle, without cocircular sites), an
     * edge per pair of finite twins, a ray per hull edge */
    const size_t nvmax = D.min3 ? D.n_poly : T - D.h,
                 nemax = (d->cell_start[n] - D.holes) / 2, nrmax = D.h;
    if (r == PASS_OK) {
        /* the mesh is no longer needed: its arrays become the vertex
         * sites and (in alloc_result) the edge sites */
        D.tri = NULL;
        D.adj = NULL;
        D.lxy = NULL;
        if (!D.small) free(D.outl);
        D.outl = NULL;
        free(order);
        order = NULL;
        D.order = NULL;
        if (!(d->vertex_sites = reuse(m->adj, 3 * nvmax, sizeof *d->vertex_sites)))
            goto done;
        m->adj = NULL;
        /* vid is made of lxy's block (16 bytes a site, vid needs about
         * 8), whose pages are touched already: not of tri's, which would
         * stay resident beside it, nor a fresh block, whose pages the
         * allocator may or may not take from those just freed (at 10^6
         * sites that lottery moved the peak between 172 and 180 bytes a
         * site with the input's layout) */
        if (D.small) {
            D.vid = D.small + 2 * n;
            free(lxy);
        } else if (!(D.vid = reuse(lxy, T, sizeof *D.vid))) {
            goto done;
        }
        lxy = NULL;
        if (alloc_result(&D, &m->tri, nemax, nrmax) != PASS_OK) goto done;
        r = sweep_records(&D);
        assert(r != PASS_OK || (D.nv == nvmax && D.ne == nemax && D.nr == nrmax));
        if (r == PASS_OK && D.holes) squeeze(&D);
    }
    if (r != PASS_OK) {
        st = status_of(r);
        goto done;
    }
    if (!D.small) free(D.vid);
    D.vid = NULL;
    free(D.min3);
    D.min3 = NULL;
    free(D.cc);
    D.cc = NULL;
    vor__mesh_clear(m);
    free(lxy);
    lxy = NULL;
    d->n_vertices = D.nv;
    d->n_edges = D.ne;
    d->n_rays = D.nr;
    /* the records become the coordinates */
    if (!(d->vertex_xy = reuse(D.rwt, 2 * D.nv, sizeof *d->vertex_xy))) goto done;
    D.rwt = NULL;
    vertex_coordinates(s, d);
    ray_directions(s, d);
    *out = d;
    D.d = NULL;
    st = VOR_OK;

done:
    vor_diagram_free(D.d);
    free(D.diag);
    free(D.patched);
    if (!D.small) {
        free(D.outl);
        free(D.vid);
    }
    free(D.rwt);
    free(D.heap);
    free(D.cc);
    free(D.root);
    free(D.min3);
    vor__mesh_clear(m);
    free(lxy);
    free(order);
    return st;
}

vor_status vor__mesh_voronoi(const vor_sites *s, vor__mesh_build_fn build,
                             vor__run *run, vor_diagram **out) {
    vor__mesh m = {0};
    double *lxy = NULL;
    uint32_t *order;
    *out = NULL;
    /* the order's scratch becomes the build's coordinates */
    vor_status r = vor__mesh_order_new(s, &order, &lxy, &run->counts);
    if (r == VOR_OK)
        r = build(s, order, &m, &lxy, run);
    if (r != VOR_OK) {
        free(order);
        return r;
    }
    return vor__mesh_dual(s, &m, lxy, order, vor__mesh_hint(run, s->n), out);
}
