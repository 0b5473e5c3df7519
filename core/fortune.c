/* fortune.c -- Fortune's sweep line: the Voronoi diagram built directly,
 * without a triangulation.
 *
 * The sweep line moves towards +y over the sites, sorted by (y, x). Behind
 * it, the beach line -- the lower envelope, seen from the line, of the
 * parabolas of points as far from a site as from the line -- is a sequence
 * of arcs; consecutive arcs meet at breakpoints, which trace Voronoi edges.
 * A site event splits the arc above the new site (or, when the site lies
 * exactly below a breakpoint, puts a new arc there and starts a vertex at
 * once); a circle event removes an arc squeezed to a point by its
 * neighbours, which is a Voronoi vertex.
 *
 * Representation.
 *   - Sites: a private copy of the coordinates sorted by (y, x) (a
 *     distribution sort by an estimate of each y's rank that adapts to the
 *     data's scale, see "Sweep rank of a y"), moved to an origin within
 *     the data when that is exact, rescaled by a power of two and, when
 *     the sites are more than four times wider than tall, turned a
 *     quarter so that the sweep runs along x (see choose_frame), so
 *     that the filters of fortune_predicates.h apply without range tests
 *     and bound their errors by the data's extent, not its distance from
 *     zero; orig[] maps back to site indices.
 *   - Beach line: arcs in a flat pool (index 0 is the nil sentinel, freed
 *     arcs are reused), linked as a red-black tree in beach-line order and as
 *     a doubly linked list. A breakpoint is not stored: an arc's site and its
 *     left neighbour's define it, and the arc holds both sites' indices (a
 *     32-byte record, two to a cache line); their coordinates are read from
 *     the sorted copy. The edge record of the breakpoint to an arc's right
 *     is in an array beside the pool, which only events read.
 *   - Circle events: live events only, at most one per arc, each an
 *     interval for the event's y and a record index; the record holds the
 *     event, the triple of sites, the queue position and which parts of
 *     what ties taught are known (those parts themselves are in a side
 *     slot, taken by the few records that meet ties). An event is replaced in
 *     the queue as soon as its triple changes, so no stale event is ever
 *     popped. (Lazy deletion was measured: the queue grows eightfold with
 *     cancelled far-future events.) The queue is a set of buckets by the
 *     estimated rank of an event's y among the sites' while sites remain,
 *     O(1) per operation whatever the sites' distribution in y, and a
 *     binary heap when buckets crowd (unless the crowd is large: then
 *     buckets fitted to it), after the last site (unless many events are
 *     left: buckets fitted to them) and for small inputs (see "Event
 *     queue"). Sites are not in the queue: the next
 *     site in sorted order is compared with the earliest event.
 *   - Output: the Delaunay triangulation the sweep discovers, in the
 *     ghost-closed form of mesh.h, handed to vor__mesh_dual() (mesh_dual.c),
 *     which reads the canonical diagram off it as it does for Bowyer-Watson
 *     and flipping. Each vertex event (a circle event, or a site exactly
 *     below a breakpoint) is a triangle; each breakpoint traces a Delaunay
 *     edge, whose record holds the half-edge of its first end until the
 *     second end links the two triangles as twins; the breakpoints left at
 *     the end, and the edges of the first row, are the convex hull, closed
 *     by ghost triangles. Vertex ids are ranks in sweep order, which keeps
 *     the conversion's fan walks local. Only the topology is decided here.
 *
 * Exactness. Every topological decision is exact:
 *   - a circle event exists for arcs of sites a, b, c (left to right) iff
 *     orient2d(a, b, c) > 0 (the breakpoints converge);
 *   - a site is placed by the exact breakpoint predicate; equality means
 *     the site is exactly below a breakpoint: a vertex at once;
 *   - events are ordered exactly, sites by (y, x) and circle events by the
 *     top of their circle (y, then x); at the same point a circle event
 *     comes before a site. Each event carries a floating-point interval
 *     proven to contain its y; only when intervals overlap is the order
 *     decided otherwise: by cheap proofs of equal tops (circles computed
 *     exactly in doubles, horizontal translates), by double-double bounds
 *     (computed once per event; outside the filters' range, bounds from
 *     the exact circle, tight_top), by 64- and 128-bit integers on small
 *     lattices (pixels, grids: equal radii or centres at equal height
 *     there make equal tops common), and finally by exact integer
 *     arithmetic on limb arrays (a site against a square root, or two sums
 *     of a rational and a square root). The queue is
 *     ordered by this exact comparison (the buckets only narrow down where
 *     to look), so its earliest event is always the next one;
 *   - cocircular sites produce several triangles with one circumcircle
 *     (zero-length Voronoi edges between them); the conversion finds them
 *     with the exact incircle and makes the centre of 4+ cocircular sites
 *     one vertex, as for the other algorithms. When no two consecutive
 *     vertex events had overlapping intervals, no two triangles share a
 *     circle (vertex_at) and the conversion tests nothing;
 *   - the first sites of equal lowest y start the beach line as a row of
 *     arcs separated by vertical bisectors, unbounded below.
 *
 * Cost: O(n log n) time: sorting O(n), each site one search of the tree
 * (O(log n) breakpoint predicates; two or four when sites follow a curve
 * and fall in the arcs of the sites just before, see locate_near), each
 * event O(log n) tree work and O(1) (buckets) or O(log n) (heap) queue
 * work; about 1 us of CPU per uniform
 * site at 10^6 sites, the conversion a third of it, the circle-top filter
 * a seventh. Exact arithmetic runs only near degeneracies. Memory: the
 * sorted copy (20 bytes per site), the mesh (2n - 2 triangles with ghosts,
 * 48 bytes per site, in which the sort runs before the sweep), edge
 * records (at most 3n, 4 bytes each, few of them ever touched), the
 * buckets (4 bytes per site, while sites remain), the rank map (at most
 * 2^12 bins and as many again for crowded ones, about 40 KiB), the beach
 * line and queue (O(sqrt n) arcs for typical input, at most 2n). The edge
 * records, the map, the beach line and the queue are freed before the
 * conversion, which owns the rest.
 *
 * Counts and trace (vor_counts, vor_step). The sweep counts its events,
 * its predicates by name and how many of them needed exact arithmetic in
 * w->cnt, a field of its own state, at the points where it decides; the
 * run gets them at the end. With a trace hook, each event reports a step
 * in site indices, with the beach line after it (walked from the leftmost
 * arc: O(beach) per event, only when tracing); without one, each report
 * is a branch not taken.
 */
#include <assert.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fortune_predicates.h"
#include "mesh.h"
#include "predicates.h"

#define NIL 0u              /* no arc (the sentinel) */
#define NO_EVENT UINT32_MAX /* arc without a circle event */
#define NO_EDGE UINT32_MAX  /* rightmost arc: no breakpoint to its right */
#define NO_END (-1)         /* edge record: no end yet */
#define FREED_SITE UINT32_MAX /* the site of a freed arc */
/* Arcs of the last sites split in, tried before a search (locate_near). */
#define FINGERS 4

/* Bytes of an arc, and the alignment of the arc pool (arcs_resize). An arc
 * holds indices only. With its site's and its left neighbour's coordinates
 * copied in (64 bytes), a search read one line a level and no site, but
 * sites in convex position keep two arcs a site on the beach line, and
 * those 128 bytes a site were the largest part of the sweep's memory:
 * peak bytes a site 282 -> 225 for 10^6 sites on a circle, 299 -> 257
 * for 10^5 and 354 -> 289 for 10^4; a cold run on 10^5 of them took 5%
 * less time, one on 10^6 as long. The coordinates come from the sorted
 * copy, where the sites of neighbouring arcs are mostly close (sorted by
 * y), and the search fetches them a level ahead (locate). */
#define ARC_ALIGN 32

typedef struct arc {
    uint32_t site;            /* sorted site index */
    uint32_t lsite;           /* the left neighbour's, if prev != NIL */
    uint32_t left, right, up; /* red-black tree links, NIL if none */
    uint32_t prev, next;      /* beach-line neighbours, NIL if none */
    uint32_t ev; /* event record of this arc's triple, or NO_EVENT */
} arc;

/* A queue entry: lo <= y of the circle's top <= hi, its record and the
 * arc the event removes: the earliest event's arc is read, and
 * prefetched for the next, without the record. */
typedef struct event {
    double lo, hi;
    uint32_t rec, arc;
} event;

/* An event record: alive while its event is in the queue. Its fields sit
 * together, and records are taken from the first on, so that the pages
 * they touch are one prefix of their block: kept in six arrays, each
 * array's prefix was mapped 2 MiB at a time under the block's advice
 * for huge pages, and 10^5 sites on a star peaked 78 bytes a site
 * higher (see recs_resize). The arc it removes is its key's; the circle
 * event itself reads the triple off the beach line. A freed record's
 * hpos links the free list. */
typedef struct evrec {
    event key;        /* its event (buckets and late[]) */
    uint32_t s[3];    /* its triple, left to right (sorted site indices) */
    uint32_t link[2]; /* previous and next in its bucket */
    uint32_t hpos;    /* heap position, or bucket, or LATE and its place
                       * in late[] */
    uint32_t slot;    /* its side slot, if known has HAS_SLOT */
    uint16_t known;   /* which parts of its slot are filled (side_of) */
} evrec;

/* Estimated sweep rank of a y (see "Sweep rank of a y"): a table of
 * bins of equal key width, each bin's first rank; a crowded bin has a
 * table of its own. */
typedef struct ymap_table {
    uint64_t base;   /* smallest key in the table's range */
    uint64_t span;   /* largest key minus base */
    int shift;       /* bin of key k: (k - base) >> shift */
    uint32_t nbins;
    uint32_t *start; /* nbins + 1: rank of each bin's first site */
} ymap_table;

typedef struct ymap {
    ymap_table top;
    uint32_t *sub;     /* top.nbins: index into inner[], or UINT32_MAX */
    ymap_table *inner; /* tables of the crowded bins */
    uint32_t n_inner;
    void *block;       /* the one allocation behind all of it */
    /* when the sites are spread evenly in y, the plain linear map serves
     * as well and costs less: rank ~ (y - y0) * scale */
    int linear;
    double y0, scale;
    uint32_t n;
    /* when they are spread smoothly over a bounded range (gaussian,
     * clusters), a grid of equal y steps with the rank at each step
     * serves instead of the tables: rank at t = (y - y0) * gscale is
     * grid[c] and a share of grid[c + 1] - grid[c], c = floor(t) */
    uint32_t *grid; /* YMAP_GRID + 1 ranks, or NULL */
    double gscale;
} ymap;

typedef struct sweep {
    size_t n;
    double *xy;     /* 2n, sorted by (y, x), in the frame (choose_frame) */
    uint32_t *orig; /* n: site index of each sorted site */
    int safe;       /* coordinates in the filters' range */
    int lattice;    /* few bits per coordinate: equal tops are common */
    int small;      /* at most 16 of them (vor__fortune_circle_exact_small) */
    uint64_t equal_tops; /* ties of two events' tops found equal */
    /* vertex events (circle events, sites exactly below a breakpoint)
     * whose y interval overlapped the one before's (see vertex_at):
     * none proves that no four sites of the mesh are cocircular */
    uint64_t vertex_overlaps;
    double vertex_hi; /* the last vertex event's interval's hi */
    int vertex_seen;
    int vertex_circle;     /* it was a circle event, of triple vertex_t */
    uint32_t vertex_t[3];
    uint32_t vertex_exact; /* overlaps decided exactly so far */

    arc *arcs;       /* ARC_ALIGN-aligned, inside arcs_block */
    void *arcs_block;
    uint8_t *red;    /* colour of each arc */
    uint32_t *aedge; /* each arc's edge record of its breakpoint with next */
    uint32_t n_arcs; /* pool slots used, the sentinel included */
    uint32_t cap_arcs;
    uint32_t free_arcs; /* list of freed arcs through .next */
    uint32_t root;
    /* the arcs of the last FINGERS sites split in, the latest first, and
     * how often lately the next site fell in one of them (see
     * locate_near) */
    uint32_t finger[FINGERS];
    uint32_t finger_score;
    /* the arc of the last site split in within each of XDIR slices of
     * x, cut at quantiles of the sites' x (xcut, XDIR - 1 of them), and
     * how often lately the next site fell in its slice's arc (see
     * locate_from); NULL until the beach line first holds more than
     * LOCATE_AHEAD arcs */
    uint32_t *xdir;
    double *xcut;
    uint32_t xdir_score;
    int list_only; /* no site left: arcs leave the list, not the tree */
    int loose;     /* few sites left: the tree is no longer rebalanced */

    /* The event queue (see "Event queue"): n_heap live events in the
     * heap, n_bucketed in the buckets (while bhead is set), n_late in
     * late[]. */
    event *heap; /* cap_recs entries: one per live record */
    uint32_t n_heap;
    uint32_t *bhead;   /* n_buckets: first record of each bucket's list */
    uint32_t n_buckets;
    uint32_t cur;      /* the buckets below cur are poured into the heap */
    uint32_t n_bucketed;
    ymap ymap;         /* bucket of lo: its rank estimate (see ymap) */
    /* near buckets (see spill): n_near of them, fitted to events that
     * crowded the heap, NULL when none; near_cur and n_nearq as cur and
     * n_bucketed; the heap spills when it holds more than spill_at */
    uint32_t *nhead;
    uint32_t n_near, near_cur, n_nearq, spill_at;
    ymap nmap;
    evrec *rr; /* cap_recs records */
    uint32_t *late; /* the events after the last site, unordered (key) */
    uint32_t n_late;
    int late_ok;    /* sites remain: a new event may wait in late[] */
    double ylast;   /* the last site's y */
    /* what the tie-breaking stages know about a record's event lives in
     * a side slot of SIDE_DOUBLES (see side_of), taken on first use */
    double *side; /* cap_recs slots, filled in order; the block of heap
                   * and late[] too (recs_resize) */
    uint32_t n_slots;   /* slots handed out so far */
    uint32_t free_slot; /* list of freed slots, NO_EVENT if none */
    uint32_t n_recs, cap_recs;
    uint32_t free_recs; /* list of freed records through hpos */

    /* Edge records: the half-edge of an edge's first end, or NO_END. A
     * record is freed when its second end is linked (the free list runs
     * through ehe), so the live ones stay few and in the cache. Edges
     * 0 .. row - 2 are those of the first row (sites 0 .. row - 1, of the
     * lowest y), unbounded below: hull edges, never freed. */
    int32_t *ehe;
    size_t n_edges, cap_edges;
    uint32_t free_edges; /* NO_EDGE if none */
    uint32_t row;

    /* The mesh: finite triangles in the order of their events, then the
     * ghosts. */
    uint32_t *tri;
    int32_t *adj;
    size_t n_tri, cap_tri;

    vor__fortune_ws *ws; /* scratch of the exact event comparison */

    /* What the sweep reports besides the mesh (vor_counts, vor_step):
     * the counts of this run, the arcs on the beach line now, and with a
     * trace, the input (for drawing coordinates), the leftmost arc and a
     * scratch array of cap_beach sites. */
    vor_counts cnt;
    uint32_t n_beach;
    int tracing; /* run->trace is set */
    vor__run *run;
    const vor_sites *s;
    uint32_t leftmost;
    uint32_t *beach;
    size_t cap_beach;
    /* how often lately a tie was two events of one shape, and the ties
     * since the last try (see shape_try) */
    uint32_t shape_score, shape_skips;
} sweep;

static inline const double *site_xy(const sweep *w, uint32_t s) {
    return w->xy + 2 * (size_t)s;
}

/* ---- Sorting the sites --------------------------------------------------- */

/* A site in the sort: y as an order-preserving key, x, its index. */
typedef struct keyed {
    uint64_t k;
    double x;
    uint32_t i;
} keyed;

/* Order-preserving map of a double (not nan, no -0.0) to an unsigned key,
 * and back. */
static inline uint64_t dkey(double d) {
    uint64_t u;
    memcpy(&u, &d, sizeof u);
    return (u >> 63) ? ~u : (u | 0x8000000000000000ull);
}

static inline double kdouble(uint64_t k) {
    uint64_t u = (k >> 63) ? (k & ~0x8000000000000000ull) : ~k;
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

/* By (y, x). */
static inline int cmp_keyed(const keyed *a, const keyed *b) {
    if (a->k != b->k) return a->k < b->k ? -1 : 1;
    return (a->x > b->x) - (a->x < b->x);
}

#define SMALL_SORT 256 /* below this, sort the whole array at once */
/* Fewer sites than this use neither the map of y nor event buckets (see
 * "Event queue"). */
#define BUCKET_MIN_SITES 64
#define TINY_SORT 16   /* at most this, insertion sort */

/* Insertion sort of r[j..k-1] by (y, x). */
static void insertion_sort(keyed *r, size_t j, size_t k) {
    for (size_t t = j + 1; t < k; t++) {
        keyed v = r[t];
        size_t u = t;
        while (u > j && cmp_keyed(&v, &r[u - 1]) < 0) {
            r[u] = r[u - 1];
            u--;
        }
        r[u] = v;
    }
}

/* Heapsort of r[0..n-1] by (y, x): O(n log n), in place, no allocation
 * (the C library's qsort may allocate, and may fall back silently when it
 * cannot, which hides allocation failures from the tests). */
static void heap_sort(keyed *r, size_t n) {
    for (size_t end = n, i = n / 2; end > 1;) {
        keyed v;
        size_t j;
        if (i > 0) { /* building: sift r[--i] down */
            j = --i;
            v = r[j];
        } else { /* extracting: the largest goes to the end */
            v = r[--end];
            r[end] = r[0];
            j = 0;
        }
        for (;;) {
            size_t c = 2 * j + 1;
            if (c >= end) break;
            if (c + 1 < end && cmp_keyed(&r[c], &r[c + 1]) < 0) c++;
            if (cmp_keyed(&v, &r[c]) >= 0) break;
            r[j] = r[c];
            j = c;
        }
        r[j] = v;
    }
}

static inline void swap_keyed(keyed *a, keyed *b) {
    keyed t = *a;
    *a = *b;
    *b = t;
}

/* Sorts r[j..k-1] by (y, x): insertion for short ranges; otherwise
 * quicksort (median of three, the smaller part first so that the stack
 * stays logarithmic), falling back to heapsort for a part when the
 * partitions keep coming out lopsided (introsort): O(m log m) at worst.
 * A bucket of a row of sites at one y (integer input) can hold thousands;
 * heapsort alone strides through memory there. */
static void sort_range(keyed *r, size_t j, size_t k) {
    size_t depth = 0;
    for (size_t m = k - j; m > 1; m >>= 1) depth += 2;
    while (k - j > TINY_SORT) {
        if (depth-- == 0) {
            heap_sort(r + j, k - j);
            return;
        }
        size_t mid = j + (k - j) / 2;
        if (cmp_keyed(&r[mid], &r[j]) < 0) swap_keyed(&r[mid], &r[j]);
        if (cmp_keyed(&r[k - 1], &r[mid]) < 0) {
            swap_keyed(&r[k - 1], &r[mid]);
            if (cmp_keyed(&r[mid], &r[j]) < 0) swap_keyed(&r[mid], &r[j]);
        }
        keyed piv = r[mid];
        size_t lo = j, hi = k - 1; /* r[j] <= piv <= r[k - 1] */
        for (;;) {
            do lo++; while (cmp_keyed(&r[lo], &piv) < 0);
            do hi--; while (cmp_keyed(&piv, &r[hi]) < 0);
            if (lo >= hi) break;
            swap_keyed(&r[lo], &r[hi]);
        }
        /* r[j..hi] <= piv <= r[hi+1..k-1] */
        if (hi + 1 - j < k - hi - 1) {
            sort_range(r, j, hi + 1);
            j = hi + 1;
        } else {
            sort_range(r, hi + 1, k);
            k = hi + 1;
        }
    }
    insertion_sort(r, j, k);
}

/* ---- Sweep rank of a y --------------------------------------------------
 *
 * The site sort and the event queue both bucket by y, and both want
 * buckets of about equal population whatever the distribution: log-normal
 * or Cauchy coordinates, a dense city with one stray point, values over
 * many decades. Equal widths over the y range put nearly all of such a set
 * into a few buckets. So y is mapped to an estimate of its rank among the
 * sites' y: the sites' order-preserving keys (dkey) are counted into
 * 2^YMAP_BITS bins of equal key width -- equal steps of the mantissa
 * within each power of two, so the bins follow the data's scale -- and a
 * y's rank is its bin's first rank plus its place within the bin,
 * interpolated linearly. The map is monotone (a larger key never maps
 * lower), which is all that sorting and the queue need for exactness;
 * evenness only makes them fast. A cluster narrower than a bin still lands
 * in one bucket; the queue then falls back to its heap. */
#define YMAP_GRID 4096 /* cells of the grid of equal y steps */
#define YMAP_BITS 12
#define YMAP_FRAC 24 /* bits of the place within a bin */
#define YMAP_PER_BIN 16 /* sites per bin aimed at */

/* Rank estimate of key k within table t, clamped to its range. */
static inline uint32_t table_rank(const ymap_table *t, uint64_t k,
                                  uint32_t *bin) {
    uint64_t off = k > t->base ? k - t->base : 0;
    if (off > t->span) off = t->span;
    uint32_t b = (uint32_t)(off >> t->shift);
    uint64_t low = off & ((UINT64_C(1) << t->shift) - 1);
    uint64_t frac = t->shift > YMAP_FRAC ? low >> (t->shift - YMAP_FRAC)
                                         : low << (YMAP_FRAC - t->shift);
    uint32_t first = t->start[b], cnt = t->start[b + 1] - first;
    *bin = b;
    return first + (uint32_t)((frac * cnt) >> YMAP_FRAC);
}

/* Rank estimate in [0, n - 1] of y (n >= 1 sites); values beyond the
 * sites' range are clamped to it. Monotone in y. */
static inline __attribute__((always_inline)) uint32_t
ymap_rank(const ymap *m, double y) {
    if (m->linear) {
        double t = (y - m->y0) * m->scale; /* nan (y = -inf): 0 */
        return t >= 0 ? t < (double)m->n ? (uint32_t)t : m->n - 1 : 0;
    }
    if (m->grid) {
        double t = (y - m->y0) * m->gscale;
        if (!(t > 0)) return 0; /* also nan */
        if (t >= YMAP_GRID) return m->n - 1;
        uint32_t c = (uint32_t)t, lo = m->grid[c], hi = m->grid[c + 1];
        /* hi - lo sites in the cell: the place within it, below hi (the
         * product may round up to hi - lo itself) */
        uint32_t off = (uint32_t)((t - (double)c) * (double)(hi - lo));
        return lo + (off < hi - lo ? off : hi - lo - (hi > lo));
    }
    uint64_t k = dkey(y + 0.0); /* + 0.0: -0.0 and 0.0 differ as keys */
    uint32_t b, r = table_rank(&m->top, k, &b);
    uint32_t i = m->sub[b];
    return i == UINT32_MAX ? r : table_rank(&m->inner[i], k, &b);
}
/* Sets up t for keys in [kmin, kmax] with about `want` bins (a power of
 * two at most 2^YMAP_BITS); start is left to the caller. */
static uint32_t table_shape(ymap_table *t, uint64_t kmin, uint64_t kmax,
                            size_t want) {
    int bits = 0;
    while (bits < YMAP_BITS && ((size_t)1 << bits) < want) bits++;
    t->base = kmin;
    t->span = kmax - kmin;
    t->shift = 0;
    while ((t->span >> t->shift) >= ((uint64_t)1 << bits)) t->shift++;
    t->nbins = (uint32_t)(t->span >> t->shift) + 1;
    return t->nbins;
}

/* A quick look before the tables: YSAMPLE of the n >= 4096 sites' y,
 * every (n / YSAMPLE)-th, sorted. */
enum { YSAMPLE = 1024 };

static void y_sample(const keyed *a, size_t n, double *smp) {
    keyed k[YSAMPLE]; /* 24 KiB */
    for (size_t j = 0; j < YSAMPLE; j++) k[j] = a[j * (n / YSAMPLE)];
    sort_range(k, 0, YSAMPLE);
    for (size_t j = 0; j < YSAMPLE; j++) smp[j] = kdouble(k[j].k);
}

/* 1 when each sampled y lies within n / 16 of the rank the linear map of
 * [y0, y1] gives it (a sample's quantiles stray by a few per cent at most
 * for evenly spread y; gaussian y strays by a quarter). Samples beyond
 * the range count as at its ends. */
static int linear_enough(const double *smp, double y0, double y1) {
    const double scale = (double)YSAMPLE / (y1 - y0);
    for (size_t j = 0; j < YSAMPLE; j++) {
        double t = (smp[j] - y0) * scale;
        t = t < 0 ? 0 : t > YSAMPLE ? YSAMPLE : t;
        if (fabs(t - (double)j) > YSAMPLE / 16.0) return 0;
    }
    return 1;
}

/* Narrows [*y0, *y1] to the bulk of the sites when a few stray far from
 * it (a city and one geocode at (0, 0)): the range of the sample less its
 * extremes, widened by 8 / YSAMPLE of itself, then the sites' own
 * extremes within that, provided at most n / 1024 sites lie outside (a
 * heavy tail is no few strays: the tables serve it). The maps built on
 * the bulk's range clamp the strays to their ends, which keeps them
 * monotone; with the whole range, the bulk would share a few cells. One
 * pass over the keys, only when the range is four times the sample's. */
static void bulk_range(const keyed *a, size_t n, const double *smp,
                       double *y0, double *y1) {
    double s0 = smp[1], s1 = smp[YSAMPLE - 2], wd = s1 - s0;
    if (!(wd > 0) || !(*y1 - *y0 > 4 * wd)) return;
    double lo = s0 - wd * (8.0 / YSAMPLE), hi = s1 + wd * (8.0 / YSAMPLE);
    double b0 = INFINITY, b1 = -INFINITY;
    size_t out = 0;
    for (size_t j = 0; j < n; j++) {
        double y = kdouble(a[j].k);
        if (y < lo || y > hi) {
            if (++out > n / 1024) return; /* a tail: stop here */
            continue;
        }
        b0 = y < b0 ? y : b0;
        b1 = y > b1 ? y : b1;
    }
    if (!(b1 > b0)) return;
    *y0 = b0;
    *y1 = b1;
}

/* The grid of equal y steps over [y0, y1] (see ymap), kept in m->grid
 * when no cell holds more than 16 times its share of the n sites (no
 * heavy tail, no far outlier); else m->grid stays NULL. One pass. */
static vor_status grid_build(ymap *m, const keyed *a, size_t n, double y0,
                             double y1) {
    double gs = (double)YMAP_GRID / (y1 - y0);
    if (!(gs > 0 && gs <= DBL_MAX) || n < 4 * (size_t)YMAP_GRID) return VOR_OK;
    uint32_t *g = calloc(YMAP_GRID + 2, sizeof *g);
    if (!g) return VOR_ENOMEM;
    for (size_t j = 0; j < n; j++) {
        double t = (kdouble(a[j].k) - y0) * gs; /* < 0: a stray below */
        uint32_t c = t >= YMAP_GRID ? YMAP_GRID - 1 : t > 0 ? (uint32_t)t : 0;
        g[c + 1]++;
    }
    uint32_t most = 0;
    for (uint32_t c = 1; c <= YMAP_GRID; c++) {
        most = g[c] > most ? g[c] : most;
        g[c] += g[c - 1];
    }
    g[YMAP_GRID + 1] = g[YMAP_GRID]; /* t == YMAP_GRID exactly: clamped */
    if ((size_t)most > 16 * (n / YMAP_GRID)) {
        free(g);
        return VOR_OK;
    }
    m->grid = g;
    m->gscale = gs;
    return VOR_OK;
}

/* Builds m over the keys of a[0..n-1] (n >= 1), whose smallest and
 * largest are kmin and kmax: the top table, then a table for each bin
 * that holds more than four times its share and more than 64 sites,
 * over the keys that bin actually holds (one stray point far from a
 * dense city puts the whole city into one top bin). Three passes over
 * the keys. When the plain linear map of y agrees with the tables
 * (evenly spread y), the linear map is used instead: its
 * buckets are as good, and it costs a multiplication instead of two
 * table look-ups per event. A sample decides that, for n >= 4096
 * (smaller inputs keep the tables: their events are few).
 * Otherwise a grid of equal y steps (grid_build) serves when no cell of
 * it is crowded, which leaves the tables for heavy tails and outliers.
 * VOR_ENOMEM on failure (m->block NULL). */
static vor_status ymap_build(ymap *m, const keyed *a, size_t n,
                             uint64_t kmin, uint64_t kmax) {
    memset(m, 0, sizeof *m);
    double y0 = kdouble(kmin), y1 = kdouble(kmax);
    m->n = (uint32_t)n;
    if (n >= 4096) {
        double smp[YSAMPLE];
        y_sample(a, n, smp);
        bulk_range(a, n, smp, &y0, &y1);
        m->y0 = y0;
        m->scale = (double)n / (y1 - y0);
        if (m->scale > 0 && m->scale <= DBL_MAX &&
            linear_enough(smp, y0, y1)) {
            m->linear = 1; /* no tables: the sample says they would agree */
            return VOR_OK;
        }
    }
    if (grid_build(m, a, n, y0, y1) != VOR_OK) return VOR_ENOMEM;
    if (m->grid) return VOR_OK;
    ymap_table *t = &m->top;
    uint32_t nb = table_shape(t, kmin, kmax, n / YMAP_PER_BIN);
    /* top counts and, per bin, its smallest and largest key */
    uint32_t *cnt = calloc(nb + 1, sizeof *cnt);
    uint64_t *bmin = malloc(2 * (size_t)nb * sizeof *bmin);
    if (!cnt || !bmin) {
        free(cnt);
        free(bmin);
        return VOR_ENOMEM;
    }
    for (uint32_t b = 0; b < nb; b++) {
        bmin[2 * b] = UINT64_MAX;
        bmin[2 * b + 1] = 0;
    }
    for (size_t j = 0; j < n; j++) {
        uint64_t k = a[j].k;
        uint32_t b = (uint32_t)((k - kmin) >> t->shift);
        cnt[b + 1]++;
        if (k < bmin[2 * b]) bmin[2 * b] = k;
        if (k > bmin[2 * b + 1]) bmin[2 * b + 1] = k;
    }
    size_t crowd = 4 * (n / nb + 1), n_inner = 0, inner_bins = 0;
    ymap_table tmp;
    for (uint32_t b = 0; b < nb; b++)
        if (cnt[b + 1] > crowd && cnt[b + 1] > 64) {
            n_inner++;
            inner_bins += table_shape(&tmp, bmin[2 * b], bmin[2 * b + 1],
                                      cnt[b + 1] / YMAP_PER_BIN) + 1;
        }
    /* one block: top starts, sub, inner tables, inner starts */
    size_t words = (size_t)nb + 1 + nb + inner_bins;
    m->block = malloc(n_inner * sizeof(ymap_table) + words * sizeof(uint32_t));
    if (!m->block) {
        free(cnt);
        free(bmin);
        return VOR_ENOMEM;
    }
    m->inner = m->block;
    t->start = (uint32_t *)(void *)(m->inner + n_inner);
    m->sub = t->start + nb + 1;
    uint32_t *istart = m->sub + nb;
    t->start[0] = 0;
    for (uint32_t b = 0; b < nb; b++) t->start[b + 1] = t->start[b] + cnt[b + 1];
    for (uint32_t b = 0; b < nb; b++) {
        m->sub[b] = UINT32_MAX;
        if (!(cnt[b + 1] > crowd && cnt[b + 1] > 64)) continue;
        ymap_table *in = &m->inner[m->n_inner];
        uint32_t k = table_shape(in, bmin[2 * b], bmin[2 * b + 1],
                                 cnt[b + 1] / YMAP_PER_BIN);
        in->start = istart;
        memset(istart, 0, ((size_t)k + 1) * sizeof *istart);
        istart += k + 1;
        m->sub[b] = m->n_inner++;
    }
    /* inner counts, prefix-summed from their bin's first rank */
    if (m->n_inner) {
        for (size_t j = 0; j < n; j++) {
            uint64_t k = a[j].k;
            uint32_t i = m->sub[(k - kmin) >> t->shift];
            if (i == UINT32_MAX) continue;
            ymap_table *in = &m->inner[i];
            in->start[((k - in->base) >> in->shift) + 1]++;
        }
        for (uint32_t b = 0; b < nb; b++) {
            uint32_t i = m->sub[b];
            if (i == UINT32_MAX) continue;
            ymap_table *in = &m->inner[i];
            in->start[0] = t->start[b];
            for (uint32_t c = 1; c <= in->nbins; c++)
                in->start[c] += in->start[c - 1];
        }
    }
    free(cnt);
    free(bmin);
    return VOR_OK;
}

/* A bucket of more than ROW_SORT sites is most often a row: sites of one
 * y, which the map of y gives one rank (a lattice's rows: 166 sites each
 * at 10^5 integer pixels, 316 on a grid). row_sort sorts such a row
 * r[0..m-1] by x as the buckets sort by y: a linear map of x onto about
 * m / 2 sub-buckets (monotone: a subtraction and a product, each rounded
 * monotonically), one scatter into scratch (m entries) and back, and each
 * sub-bucket sorted by sort_range. Anything else, sites of several y or
 * an x range beyond the doubles, is sorted by sort_range as it was.
 * Sorting the rows of 10^5 pixels by comparisons took 3.4% of Fortune's
 * run. */
#define ROW_SORT 64

static void row_sort(keyed *r, size_t m, keyed *scratch) {
    double lo = r[0].x, hi = r[0].x;
    for (size_t j = 1; j < m; j++) {
        if (r[j].k != r[0].k) {
            sort_range(r, 0, m);
            return;
        }
        lo = r[j].x < lo ? r[j].x : lo;
        hi = r[j].x > hi ? r[j].x : hi;
    }
    const size_t nb = m / 2;
    double scale = (double)nb / (hi - lo);
    if (!(scale > 0 && scale < INFINITY)) { /* one x (cannot be: the sites
                                             * are distinct) or overflow */
        sort_range(r, 0, m);
        return;
    }
    /* the counts: here, or for a row longer than 8192 sites (rows of 10^4
     * sorted by comparisons took 5% of Fortune's run), on the heap */
    uint32_t cs[ROW_SORT * 64 + 1], *c = cs;
    if (nb > ROW_SORT * 64 && !(c = malloc((nb + 1) * sizeof *c))) {
        sort_range(r, 0, m);
        return;
    }
    memset(c, 0, (nb + 1) * sizeof *c);
    for (size_t j = 0; j < m; j++) {
        size_t b = (size_t)((r[j].x - lo) * scale);
        c[(b < nb ? b : nb - 1) + 1]++;
    }
    for (size_t b = 1; b <= nb; b++) c[b] += c[b - 1];
    for (size_t j = 0; j < m; j++) {
        size_t b = (size_t)((r[j].x - lo) * scale);
        scratch[c[b < nb ? b : nb - 1]++] = r[j];
    }
    memcpy(r, scratch, m * sizeof *r);
    for (size_t b = 0, start = 0; b < nb; start = c[b++])
        sort_range(r, start, c[b]);
    if (c != cs) free(c);
}

/* Distribution sort of a[0..n-1] by (y, x) into tmp: buckets of two
 * ranks' width under the map (about n / 2 of them), one counting pass,
 * one scatter, then each bucket sorted (sort_range). The map is monotone,
 * so the result is exactly sorted whatever the distribution. Against a
 * radix sort it saves two scatters of the array, which at 10^6 sites miss
 * the cache on nearly every write. Returns tmp, or NULL if out of
 * memory. */
static keyed *bucket_sort(const ymap *m, keyed *a, keyed *tmp, size_t n) {
    const size_t nb = (n + 1) / 2;
    uint32_t *c = calloc(nb + 1, sizeof *c);
    if (!c) return NULL;
    for (size_t j = 0; j < n; j++)
        c[(ymap_rank(m, kdouble(a[j].k)) >> 1) + 1]++;
    for (size_t b = 1; b <= nb; b++) c[b] += c[b - 1]; /* starts */
    for (size_t j = 0; j < n; j++)
        tmp[c[ymap_rank(m, kdouble(a[j].k)) >> 1]++] = a[j];
    /* now c[b] is the end of bucket b; a is free */
    for (size_t b = 0, start = 0; b < nb; start = c[b++]) {
        if (c[b] - start > ROW_SORT)
            row_sort(tmp + start, c[b] - start, a + start);
        else
            sort_range(tmp, start, c[b]);
    }
    free(c);
    return tmp;
}

/* Where the sweep puts the origin: an offset per axis, subtracted from
 * every coordinate, then a power-of-two scale. Both are exact, so every
 * predicate keeps its sign (each is invariant under translation and
 * scaling) and the diagram, computed from the input's coordinates, keeps
 * its bits; only the filters gain. */
typedef struct frame {
    double off[2]; /* subtracted from x and y */
    double scale, scale2; /* then multiplied by both (2^1023 and more for
                           * sites of subnormal magnitude) */
    /* the quarter turns (exact, orientation-preserving) that take the
     * sites into the sweep's frame: 0, (x, y) as they are; 1, the sweep
     * runs along x, (-y, x); 2, it runs down y, (-x, -y) */
    int turn;
} frame;

/* Fills w->xy and w->orig: the sites moved, scaled and turned by frame f
 * (choose_frame: exact), sorted by (y, x) in it, and w->ymap over
 * their y. Fewer than SMALL_SORT sites: sort_range on the whole; otherwise
 * bucket_sort. The sort's two arrays of n keyed sites are the mesh arrays
 * w->tri and w->adj, not yet used (each holds at least n keyed sites, see
 * vor__fortune), so that their pages are touched once: fresh pages cost a
 * fault and zeroing each. */
static vor_status sort_sites(sweep *w, const vor_sites *s, frame f) {
    size_t n = s->n;
    keyed *a = (keyed *)(void *)w->tri, *tmp = (keyed *)(void *)w->adj;
    w->xy = vor__alloc_large(2 * n, sizeof *w->xy);
    w->orig = vor__alloc_large(n, sizeof *w->orig);
    vor_status st = VOR_ENOMEM;
    if (!w->xy || !w->orig) goto done;
    uint64_t kmin = UINT64_MAX, kmax = 0;
    const int along = f.turn == 1 ? 0 : 1;
    const double ksign = f.turn == 2 ? -1.0 : 1.0;
    const double sign = f.turn ? -1.0 : 1.0;
    for (size_t j = 0; j < n; j++) {
        /* + 0.0: a turned 0 is +0.0, as the sites' coordinates are */
        uint64_t k = dkey(ksign * ((s->xy[2 * j + along] - f.off[along]) *
                                   f.scale * f.scale2) + 0.0);
        a[j].k = k;
        a[j].x = sign * ((s->xy[2 * j + 1 - along] - f.off[1 - along]) *
                         f.scale * f.scale2) + 0.0;
        a[j].i = (uint32_t)j;
        kmin = k < kmin ? k : kmin;
        kmax = k > kmax ? k : kmax;
    }
    /* The map serves the bucket sort and the event buckets, neither of
     * which a small input uses (a 10-point request must not pay for it).
     * On a lattice too the linear map serves where it fits: the rank
     * map gives every site of a row one rank and the gap above the row
     * the next, so a row's events went to the heap together (78 on
     * average at each removal for 10^5 integer pixels, 16 with the linear
     * map's buckets spread over the gap). */
    if (n >= BUCKET_MIN_SITES &&
        (st = ymap_build(&w->ymap, a, n, kmin, kmax)) != VOR_OK)
        goto done;
    st = VOR_ENOMEM;
    keyed *r;
    if (n < SMALL_SORT) {
        /* Zeroing and scanning the count tables costs more than sorting a
         * few hundred keys outright (about 6 us of the 30 us a 10-point
         * request costs the service) */
        sort_range(a, 0, n);
        r = a;
    } else if (!(r = bucket_sort(&w->ymap, a, tmp, n))) {
        goto done;
    }
    /* sorted by (y, x), a repeated site lies next to its twin: vor_sites_new
     * never makes one, a vor_sites filled by hand can, and the sweep would
     * split an arc at its own site (VOR_EINVAL) */
    int repeat = 0;
    for (size_t j = 0; j < n; j++) {
        w->xy[2 * j] = r[j].x;
        w->xy[2 * j + 1] = kdouble(r[j].k);
        w->orig[j] = r[j].i;
        repeat |= j > 0 && r[j].k == r[j - 1].k && r[j].x == r[j - 1].x;
    }
    st = repeat ? VOR_EINVAL : VOR_OK;
done:
    return st;
}

/* The offset of one axis whose values lie in [lo, hi]: the value nearest
 * zero when all lie within a factor of two of it on one side of zero, so
 * that every difference with it is exact (Sterbenz); else 0. Data far from
 * the origin for its extent (projected coordinates in metres, a grid at
 * 10^15) then sits at the origin, where the filters' error bounds, which
 * grow with the coordinates' magnitude, are as tight as the data's extent
 * allows, and where its few significant bits can make a small lattice. */
static double axis_offset(double lo, double hi) {
    if (lo > 0 && hi <= 2 * lo) return lo;
    if (hi < 0 && lo >= 2 * hi) return hi;
    return 0;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int cmp_pair(const void *a, const void *b) {
    const double *p = a, *q = b;
    int c = (p[0] > q[0]) - (p[0] < q[0]);
    return c ? c : (p[1] > q[1]) - (p[1] < q[1]);
}

/* How many distinct values axis a (0: x, 1: y) takes among at most
 * TURN_SAMPLE sites spread evenly over the input. */
#define TURN_SAMPLE 1024
static size_t distinct_in_sample(const vor_sites *s, int a) {
    double v[TURN_SAMPLE];
    size_t m = s->n < TURN_SAMPLE ? s->n : TURN_SAMPLE, k = 0;
    for (size_t i = 0; i < m; i++)
        v[i] = s->xy[2 * (size_t)((uint64_t)i * s->n / m) + (size_t)a];
    qsort(v, m, sizeof *v, cmp_double);
    for (size_t i = 0; i < m; i++) k += i == 0 || v[i] != v[i - 1];
    return k;
}

/* The scale for a set whose coordinates are not all in the filters' range
 * once the largest is in [1, 2): one that brings the bulk there instead
 * (nine in ten of a sample of TURN_SAMPLE coordinates below 2), so that
 * the predicates among the bulk's sites pass their per-call range check
 * (vor__fortune_in_range4) and take the fast filters; the others rescale
 * per call as before. Uniform sites and one stray point at 10^300 (their
 * coordinates scaled by the outlier's 2^-996, every call rescaled): 10^5
 * sites 201 -> 95 ms (CGAL 66). Exactness needs only that no coordinate
 * overflow or become subnormal (emax: the largest's exponent, mn the
 * smallest nonzero magnitude); else the scale stays fallback. */
static double bulk_scale(const vor_sites *s, frame f, int emax, double mn,
                         double fallback) {
    double v[TURN_SAMPLE];
    size_t m = s->n < TURN_SAMPLE / 2 ? s->n : TURN_SAMPLE / 2, k = 0;
    for (size_t i = 0; i < m; i++) {
        const double *p = s->xy + 2 * (size_t)((uint64_t)i * s->n / m);
        v[k++] = fabs(p[0] - f.off[0]);
        v[k++] = fabs(p[1] - f.off[1]);
    }
    qsort(v, k, sizeof *v, cmp_double);
    double q = v[k - 1 - k / 10];
    if (q == 0) return fallback;
    int eq;
    (void)frexp(q, &eq);
    int shift = 1 - eq; /* q 2^shift in [1, 2) */
    if (shift > 1023 || shift < -1022 || emax + shift > 1023 ||
        ldexp(mn, shift) < DBL_MIN)
        return fallback;
    return ldexp(1.0, shift);
}

/* Chooses the frame: the direction of the sweep, the offsets
 * (axis_offset), then the power-of-two scale that brings the largest
 * coordinate into [1, 2) if that is exact (no scaled value becomes
 * subnormal). Tells whether the coordinates so moved satisfy the filters'
 * range condition (every coordinate 0 or in [2^-250, 2), hence every
 * nonzero difference in [2^-302, 4]) and form a small lattice.
 *
 * The sweep runs along the longer side of the bounding box when it is
 * more than four times the shorter: the frame is then turned a quarter
 * (x, y) -> (-y, x), exact and orientation-preserving. Swept across the
 * short side, such sites lie nearly along the sweep line: the beach line
 * holds more arcs, and circles through three sites far apart along the
 * line have tops known only to the line's scale, not the short side's,
 * so their intervals overlap and the exact comparison decides (2 10^4
 * sites log-uniform in x over 2^-60 .. 2^60, uniform in y in [0, 1]:
 * 268 k exact comparisons, 434 ms; turned, 11 k, 36 ms). A 1000 x 1
 * box or ellipse gains a tenth to a fifth, 30 rows of equal y 1000 long
 * a tenth. Columns of equal x in such a box (samples at equal steps of
 * time, say) are the harder case. Swept along them, every site stays on
 * the beach line until the sweep is half a column's gap past it: with
 * columns shorter than half their gap, all of them at once (10^6 sites
 * in 1000 columns in [0, 1]: a beach line of 10^6 arcs, 1.7-2.3 s).
 * Swept across, each column is a row of equal sweep coordinate whose
 * events crowd the gap to the next (see spill): cheaper, unless the rows
 * are very long (the same sites: 1.07-1.23 s; 100 columns of 10^4 sites,
 * 1.2-1.3 s along and 1.4-1.8 s across; 10^5 sites in 10 columns, 95-122
 * ms along, 108-164 across, in 30 columns 99-130 along and 84-97
 * across). So the sweep keeps y only when a sample of the sites has
 * fewer distinct x than distinct y and the columns hold more than
 * LONG_ROW sites each on average (n over the sample's distinct x, which
 * is at least that average). Short of four, lattices decide, not the
 * box: a hexagonal lattice of horizontal rows is swept twice as fast
 * across its rows as along them (cocircular rectangles appear), while
 * other grids gain a little.
 *
 * Swept along y, the sites on a curve that bends down from the sweep
 * (y = -x^2: the upper chain of their hull) keep their arcs until the
 * sweep has passed them all, and their events then come in no order
 * along the beach line. Swept down instead, (x, y) -> (-x, -y), such a
 * curve bends up, and its events mostly follow its sites (10^5 sites,
 * ms, CGAL about 44: y = -x^2 84 -> 62, y = -x^2 / 2 86 -> 64, an
 * upper half circle 122 -> 102, an arc of 60 degrees 92 -> 86; the
 * steeper y = -3x^2 and y = -10x^2 lose 4 and 6%, 70 -> 73 and 58 ->
 * 62). So a sweep along y runs down when the upper chain of a sample's
 * hull holds an eighth of it or more and four times the lower chain.
 * (Swept along x, a curve in a box four times wider than tall is steep
 * in the sweep's frame, where running the other way did not pay.) */
#define LONG_ROW 4096

/* Of a sample of FLIP_SAMPLE sites spread evenly over the input, those on
 * the upper chain of its convex hull (far: facing the end of a sweep up
 * y) and on the lower chain (near). Strictly convex vertices only, in
 * plain doubles: a heuristic, not a topology decision. */
#define FLIP_SAMPLE 256
#define FLIP_MIN 8192 /* fewer sites: no flip (the sample's sort costs) */
static void hull_chains(const vor_sites *s, size_t *far, size_t *near) {
    double v[FLIP_SAMPLE][2], h[FLIP_SAMPLE][2];
    size_t m = s->n < FLIP_SAMPLE ? s->n : FLIP_SAMPLE;
    for (size_t i = 0; i < m; i++)
        memcpy(v[i], s->xy + 2 * (size_t)((uint64_t)i * s->n / m),
               sizeof v[i]);
    qsort(v, m, sizeof v[0], cmp_pair); /* by x, then y */
    for (int side = 0; side < 2; side++) {
        /* left to right: the upper chain turns right (cr < 0), the
         * lower one left */
        double sg = side ? -1.0 : 1.0;
        size_t k = 0;
        for (size_t i = 0; i < m; i++) {
            while (k >= 2) {
                double cr =
                    (h[k - 1][0] - h[k - 2][0]) * (v[i][1] - h[k - 2][1]) -
                    (h[k - 1][1] - h[k - 2][1]) * (v[i][0] - h[k - 2][0]);
                if (sg * cr < 0) break;
                k--;
            }
            memcpy(h[k++], v[i], sizeof h[0]);
        }
        *(side ? near : far) = k;
    }
}

static frame choose_frame(const vor_sites *s, int *safe, int *lattice,
                          int *small) {
    frame f = {{0, 0}, 1.0, 1.0, 0};
    double box[4];
    vor__bbox(s->xy, s->n, box);
    double hx = box[2] * 0.5 - box[0] * 0.5, hy = box[3] * 0.5 - box[1] * 0.5;
    if (hy > 0 && hx > 4 * hy) {
        size_t dx = distinct_in_sample(s, 0);
        f.turn = dx >= distinct_in_sample(s, 1) || s->n <= LONG_ROW * dx;
    }
    if (!f.turn && s->n >= FLIP_MIN) {
        size_t far = 0, near = 0;
        hull_chains(s, &far, &near);
        if (far >= FLIP_SAMPLE / 8 && 4 * near <= far) f.turn = 2;
    }
    f.off[0] = axis_offset(box[0], box[2]);
    f.off[1] = axis_offset(box[1], box[3]);
    double mx = 0, mn = INFINITY;
    int lowest = INT32_MAX;
    for (size_t j = 0; j < 2 * s->n; j++) {
        double v = fabs(s->xy[j] - f.off[j & 1]);
        if (v > mx) mx = v;
        if (v != 0 && v < mn) mn = v;
        uint64_t u;
        memcpy(&u, &v, sizeof u);
        if (v != 0) { /* the exponent of v's lowest set bit */
            int ex = (int)(u >> 52);
            uint64_t m = (u & 0xfffffffffffffull) | (ex ? 0x10000000000000ull : 0);
            int lb = (ex ? ex : 1) - 1075 + __builtin_ctzll(m);
            lowest = lb < lowest ? lb : lowest;
        }
    }
    *safe = 0;
    *lattice = 0;
    *small = 0;
    if (mx == 0) return f;
    int e;
    (void)frexp(mx, &e); /* mx = f 2^e, f in [0.5, 1) */
    /* a small lattice: every coordinate a multiple of 2^lowest below 2^e,
     * e - lowest <= 26 bits (pixels, grids, small integers) */
    *lattice = e - lowest <= 26;
    /* and 16 bits or fewer: in the frame below (coordinates under 2), the
     * multiples of 2^(lowest + 1 - e) >= 2^-15 that
     * vor__fortune_circle_exact_small takes */
    *small = e - lowest <= 16;
    /* scaled by 2^(1 - e), in two factors past 2^1023 (sites of
     * subnormal magnitude: scaling up is exact), unless the smallest
     * difference would turn subnormal */
    int sh = 1 - e;
    if (ldexp(mn, sh) < DBL_MIN) sh = 0;
    f.scale = ldexp(1.0, sh > 1023 ? 1023 : sh);
    f.scale2 = ldexp(1.0, sh > 1023 ? sh - 1023 : 0);
    double smx = ldexp(mx, sh), smn = ldexp(mn, sh);
    *safe = smx < 2.0 && smn >= 0x1p-250;
    if (!*safe) {
        double b = bulk_scale(s, f, e, mn, 0.0);
        if (b != 0.0) {
            f.scale = b;
            f.scale2 = 1.0;
        }
    }
    return f;
}

/* ---- Mesh output ---------------------------------------------------------
 *
 * A vertex event makes triangle t = (a, b, c), counter-clockwise; its
 * half-edges 3t, 3t + 1, 3t + 2 go a->b, b->c, c->a. The breakpoint of two
 * arcs traces their Delaunay edge; each end of the edge is a half-edge of
 * the triangle made there, and the two ends are twins.
 */

/* A new edge record, no end yet. (At most 3n records are ever made, the
 * capacity; with reuse far fewer.) */
static uint32_t edge_new(sweep *w) {
    uint32_t e = w->free_edges;
    if (e != NO_EDGE) {
        w->free_edges = (uint32_t)w->ehe[e];
    } else {
        assert(w->n_edges < w->cap_edges);
        e = (uint32_t)w->n_edges++;
    }
    w->ehe[e] = NO_END;
    return e;
}

/* Edge e ends at half-edge h: the first end is remembered, the second is
 * linked to it, and the record freed. */
static void edge_end(sweep *w, uint32_t e, uint32_t h) {
    int32_t f = w->ehe[e];
    if (f == NO_END) {
        w->ehe[e] = (int32_t)h;
        return;
    }
    w->adj[h] = f;
    w->adj[f] = (int32_t)h;
    w->ehe[e] = (int32_t)w->free_edges;
    w->free_edges = e;
}

/* Appends triangle (a, b, c); returns its first half-edge (a->b). */
static uint32_t tri_put(sweep *w, uint32_t a, uint32_t b, uint32_t c) {
    size_t t = w->n_tri++;
    assert(t < w->cap_tri);
    uint32_t *v = w->tri + 3 * t;
    v[0] = a;
    v[1] = b;
    v[2] = c;
    return 3 * (uint32_t)t;
}

/* Triangle (a, b, c) of sorted site ids, counter-clockwise. */
static uint32_t tri_new(sweep *w, uint32_t a, uint32_t b, uint32_t c) {
    assert(vor_orient2d(site_xy(w, a), site_xy(w, b), site_xy(w, c)) > 0);
    return tri_put(w, a, b, c);
}

/* Ghost triangle (p, q, GHOST) beyond hull half-edge q->p; returns its
 * half-edge p->q. */
static uint32_t tri_ghost(sweep *w, uint32_t p, uint32_t q) {
    return tri_put(w, p, q, VOR__GHOST);
}

/* ---- Arc pool ------------------------------------------------------------ */

_Static_assert(sizeof(arc) == ARC_ALIGN, "an arc is half a cache line");

/* Makes the arc pool a block of cap arcs, aligned so that none lies across
 * two cache lines, with the n_arcs in use copied over: 0, or -1 if out of
 * memory (nothing changed). malloc's blocks start 16 bytes into a line (a
 * large one 16 bytes into its first page), which put every other arc
 * across two. The caller grows red[] and aedge[] alike. */
static int arcs_resize(sweep *w, size_t cap) {
    if (cap > (SIZE_MAX - ARC_ALIGN) / sizeof(arc)) return -1;
    unsigned char *block = vor__alloc_large(cap * sizeof(arc) + ARC_ALIGN, 1);
    if (!block) return -1;
    arc *a = (arc *)(block + (ARC_ALIGN - (uintptr_t)block % ARC_ALIGN) % ARC_ALIGN);
    assert((uintptr_t)a % ARC_ALIGN == 0 &&
           (unsigned char *)(a + cap) <= block + cap * sizeof(arc) + ARC_ALIGN);
    if (w->arcs) memcpy(a, w->arcs, (size_t)w->n_arcs * sizeof *a);
    free(w->arcs_block);
    w->arcs_block = block;
    w->arcs = a;
    return 0;
}

/* A new arc of site s (red, unlinked), or NIL if out of memory. */
static uint32_t arc_new(sweep *w, uint32_t s) {
    uint32_t a;
    if (w->free_arcs != NIL) {
        a = w->free_arcs;
        w->free_arcs = w->arcs[a].next;
    } else {
        if (w->n_arcs == w->cap_arcs) {
            if (w->cap_arcs > UINT32_MAX / 4) return NIL;
            uint32_t cap = 2 * w->cap_arcs;
            if (arcs_resize(w, cap)) return NIL;
            uint8_t *nr = realloc(w->red, cap);
            if (!nr) return NIL;
            w->red = nr;
            uint32_t *ne = realloc(w->aedge, (size_t)cap * sizeof *ne);
            if (!ne) return NIL;
            w->aedge = ne;
            w->cap_arcs = cap;
        }
        a = w->n_arcs++;
    }
    arc *x = &w->arcs[a];
    x->site = s;
    x->lsite = 0; /* none while prev is NIL, but a site all the same: the
                   * search prefetches the sites of the arcs it passes */
    x->left = x->right = x->up = x->prev = x->next = NIL;
    x->ev = NO_EVENT;
    w->aedge[a] = NO_EDGE;
    w->red[a] = 1;
    return a;
}

static void arc_free(sweep *w, uint32_t a) {
    w->arcs[a].site = FREED_SITE; /* no finger (locate_near) */
    w->arcs[a].next = w->free_arcs;
    w->free_arcs = a;
}

/* ---- Red-black tree of arcs in beach-line order -----------------------------
 *
 * The classic algorithm with a sentinel (arc 0: black, its links scratch);
 * colours in a separate byte array. Insertion and removal also keep the
 * list links and each arc's copy of its left neighbour's site index.
 *
 *        x                y
 *       / \   left      /  \
 *      a   y  ----->   x    c
 *         / \  <----- / \
 *        b   c  right a  b
 */
#define ARC(i) (w->arcs[i])
#define RED(i) (w->red[i])

static void rotate_left(sweep *w, uint32_t x) {
    uint32_t y = ARC(x).right;
    ARC(x).right = ARC(y).left;
    if (ARC(y).left != NIL) ARC(ARC(y).left).up = x;
    ARC(y).up = ARC(x).up;
    if (ARC(x).up == NIL)
        w->root = y;
    else if (x == ARC(ARC(x).up).left)
        ARC(ARC(x).up).left = y;
    else
        ARC(ARC(x).up).right = y;
    ARC(y).left = x;
    ARC(x).up = y;
}

static void rotate_right(sweep *w, uint32_t x) {
    uint32_t y = ARC(x).left;
    ARC(x).left = ARC(y).right;
    if (ARC(y).right != NIL) ARC(ARC(y).right).up = x;
    ARC(y).up = ARC(x).up;
    if (ARC(x).up == NIL)
        w->root = y;
    else if (x == ARC(ARC(x).up).right)
        ARC(ARC(x).up).right = y;
    else
        ARC(ARC(x).up).left = y;
    ARC(y).right = x;
    ARC(x).up = y;
}

/* Inserts arc z right after arc x, in the tree and in the list. */
static void insert_after(sweep *w, uint32_t x, uint32_t z) {
    uint32_t nx = ARC(x).next;
    ARC(z).prev = x;
    ARC(z).next = nx;
    ARC(z).lsite = ARC(x).site;
    if (nx != NIL) {
        ARC(nx).prev = z;
        ARC(nx).lsite = ARC(z).site;
    }
    ARC(x).next = z;
    ARC(z).left = ARC(z).right = NIL;
    RED(z) = 1;
    if (ARC(x).right == NIL) {
        ARC(x).right = z;
        ARC(z).up = x;
    } else { /* the successor nx is the leftmost of x's right subtree */
        ARC(nx).left = z;
        ARC(z).up = nx;
    }
    if (w->loose) return; /* see LOOSE_SITES */
    while (RED(ARC(z).up)) {
        uint32_t p = ARC(z).up, g = ARC(p).up;
        if (p == ARC(g).left) {
            uint32_t u = ARC(g).right;
            if (RED(u)) {
                RED(p) = 0;
                RED(u) = 0;
                RED(g) = 1;
                z = g;
            } else {
                if (z == ARC(p).right) {
                    z = p;
                    rotate_left(w, z);
                    p = ARC(z).up;
                }
                RED(p) = 0;
                RED(g) = 1;
                rotate_right(w, g);
            }
        } else {
            uint32_t u = ARC(g).left;
            if (RED(u)) {
                RED(p) = 0;
                RED(u) = 0;
                RED(g) = 1;
                z = g;
            } else {
                if (z == ARC(p).left) {
                    z = p;
                    rotate_right(w, z);
                    p = ARC(z).up;
                }
                RED(p) = 0;
                RED(g) = 1;
                rotate_left(w, g);
            }
        }
    }
    RED(w->root) = 0;
}

static void transplant(sweep *w, uint32_t u, uint32_t v) {
    uint32_t p = ARC(u).up;
    if (p == NIL)
        w->root = v;
    else if (u == ARC(p).left)
        ARC(p).left = v;
    else
        ARC(p).right = v;
    ARC(v).up = p; /* also for the sentinel: the fix-up starts there */
}

/* Removes arc z from the tree and the list (it is not freed). */
static void remove_arc(sweep *w, uint32_t z) {
    uint32_t pz = ARC(z).prev, nz = ARC(z).next;
    if (pz != NIL) ARC(pz).next = nz;
    if (nz != NIL) {
        ARC(nz).prev = pz;
        ARC(nz).lsite = ARC(z).lsite;
    }
    /* With no site left, nothing searches the tree again: the events
     * left (all of them for sites in convex position below their
     * circles' tops, a parabola's say) take the arc off the list alone,
     * without the rebalancing's reads of its parent and sibling (6% of
     * the sweep on 10^5 sites on a parabola). */
    if (w->list_only) return;

    uint32_t y = z, x;
    int y_red = RED(y);
    if (ARC(z).left == NIL) {
        x = ARC(z).right;
        transplant(w, z, x);
    } else if (ARC(z).right == NIL) {
        x = ARC(z).left;
        transplant(w, z, x);
    } else {
        y = nz; /* successor: leftmost of the right subtree */
        y_red = RED(y);
        x = ARC(y).right;
        if (ARC(y).up == z) {
            ARC(x).up = y;
        } else {
            transplant(w, y, x);
            ARC(y).right = ARC(z).right;
            ARC(ARC(y).right).up = y;
        }
        transplant(w, z, y);
        ARC(y).left = ARC(z).left;
        ARC(ARC(y).left).up = y;
        RED(y) = RED(z);
    }
    if (w->loose) return; /* see LOOSE_SITES */
    if (y_red) {
        RED(NIL) = 0;
        return;
    }
    while (x != w->root && !RED(x)) {
        uint32_t p = ARC(x).up;
        if (x == ARC(p).left) {
            uint32_t s = ARC(p).right;
            if (RED(s)) {
                RED(s) = 0;
                RED(p) = 1;
                rotate_left(w, p);
                s = ARC(p).right;
            }
            if (!RED(ARC(s).left) && !RED(ARC(s).right)) {
                RED(s) = 1;
                x = p;
            } else {
                if (!RED(ARC(s).right)) {
                    RED(ARC(s).left) = 0;
                    RED(s) = 1;
                    rotate_right(w, s);
                    s = ARC(p).right;
                }
                RED(s) = RED(p);
                RED(p) = 0;
                RED(ARC(s).right) = 0;
                rotate_left(w, p);
                x = w->root;
            }
        } else {
            uint32_t s = ARC(p).left;
            if (RED(s)) {
                RED(s) = 0;
                RED(p) = 1;
                rotate_right(w, p);
                s = ARC(p).left;
            }
            if (!RED(ARC(s).right) && !RED(ARC(s).left)) {
                RED(s) = 1;
                x = p;
            } else {
                if (!RED(ARC(s).left)) {
                    RED(ARC(s).right) = 0;
                    RED(s) = 1;
                    rotate_left(w, s);
                    s = ARC(p).left;
                }
                RED(s) = RED(p);
                RED(p) = 0;
                RED(ARC(s).left) = 0;
                rotate_right(w, p);
                x = w->root;
            }
        }
    }
    RED(x) = 0;
    RED(NIL) = 0;
}

/* Side of p (on the sweep line) against arc x's left breakpoint: > 0 if
 * the breakpoint is left of p (or x is the leftmost arc), < 0 if right of
 * it, 0 if exactly above p. */
static inline int bp_side(const sweep *w, uint32_t x, const double *p,
                          uint64_t *leftmost, uint64_t *slow) {
    const arc *ax = &w->arcs[x];
    if (ax->prev == NIL) {
        ++*leftmost; /* no breakpoint tested */
        return 1;
    }
    return vor__fortune_bp_side_n(site_xy(w, ax->lsite), site_xy(w, ax->site),
                                  p, w->safe, slow);
}

/* The arc above site p (sweep line at p.y): the last arc whose left
 * breakpoint is not right of p. *on is set when p is exactly below that
 * breakpoint. O(log n) breakpoint tests. On a long beach line (more
 * than LOCATE_AHEAD arcs) each arc's test is preceded by prefetches of
 * the sites its children hold (their arcs were fetched a level above)
 * and of its four grandchildren's arcs: where it holds a good share of
 * the sites (coordinates spread over decades: 3 * 10^5 arcs for 10^6
 * sites), each level below the cached top is a miss, for its arc and
 * for its sites' coordinates, and the test's arithmetic then overlaps
 * the next ones. A short one stays in the cache, and the prefetches
 * would only add instructions (1.5% of uniform sites' at 10^5). */
#define LOCATE_AHEAD 4096u
static uint32_t locate(sweep *w, const double *p, int *on) {
    const arc *arcs = w->arcs;
    uint32_t x = w->root, found = NIL;
    /* arcs visited, the leftmost among them, the slow tests */
    uint64_t visited = 0, leftmost = 0, slow = 0;
    const int ahead = w->n_beach > LOCATE_AHEAD;
    *on = 0;
    while (x != NIL) {
        visited++;
        if (ahead) {
            /* the children's sites (their arcs were fetched a level
             * above) and the grandchildren's arcs */
            const arc *l = &arcs[arcs[x].left], *r = &arcs[arcs[x].right];
            __builtin_prefetch(site_xy(w, l->site));
            __builtin_prefetch(site_xy(w, l->lsite));
            __builtin_prefetch(site_xy(w, r->site));
            __builtin_prefetch(site_xy(w, r->lsite));
            __builtin_prefetch(&arcs[l->left]);
            __builtin_prefetch(&arcs[l->right]);
            __builtin_prefetch(&arcs[r->left]);
            __builtin_prefetch(&arcs[r->right]);
        }
        int side = bp_side(w, x, p, &leftmost, &slow);
        if (side > 0) {
            found = x;
            x = arcs[x].right;
        } else if (side < 0) {
            x = arcs[x].left;
        } else {
            *on = 1;
            found = x;
            break;
        }
    }
    w->cnt.breakpoint_tests += visited - leftmost;
    w->cnt.breakpoint_exact += slow;
    assert(found != NIL);
    return found;
}

/* Sites along a curve (on a circle or a parabola, near a line, in
 * convex position) fall mostly in the arc of the site split in just
 * before, or the one before that, on the same side; sorted by y, the
 * sites of a closed curve's two sides come in no order between them: the
 * last FINGERS arcs split in (both sides' last two) are worth two
 * breakpoint tests each before a search of a beach line that holds up to
 * 2n arcs there (35 tests a site for 10^6 sites on a circle). With the
 * last two only, a site followed two of the other side's a quarter of
 * the time and was searched: 11 tests a site on that circle, 3.5 with
 * four. Elsewhere they are not, so they are tried only while most
 * sites lately fell in one of them: finger_score follows that share
 * (FINGER_ONE is all of them), and costs a few comparisons a site to
 * keep. */
#define FINGER_ONE 256u
#define FINGER_ON (FINGER_ONE / 2)

/* The arc above site p if it is arc h, or one of the `steps` arcs on
 * either side of h, and p lies strictly between its breakpoints, else
 * NIL (then locate decides, and also whether p lies exactly below a
 * breakpoint). A freed arc (its site FREED_SITE) or NIL is none; one
 * freed and taken again is tried like any other. Inlined with steps a
 * constant: 0 for the fingers, HINT_STEPS for a slice's arc. */
static inline uint32_t locate_from(sweep *w, const double *p, uint32_t h,
                                   int steps) {
    if (h == NIL || ARC(h).site == FREED_SITE) return NIL;
    uint64_t leftmost = 0, slow = 0, tests = 1;
    uint32_t found = NIL;
    int side = bp_side(w, h, p, &leftmost, &slow);
    if (side < 0) { /* p is left of h: the first arc left of it that
                     * holds p is the one (its right breakpoint was h's) */
        for (int k = 0; k < steps && side < 0; k++) {
            h = ARC(h).prev; /* h's breakpoint is right of p: h has one */
            tests++;
            side = bp_side(w, h, p, &leftmost, &slow);
        }
        if (side > 0) found = h;
    } else if (side > 0) {
        for (int k = 0;; k++) {
            uint32_t y = ARC(h).next;
            int next = 0;
            if (y != NIL) {
                tests++;
                next = bp_side(w, y, p, &leftmost, &slow);
            }
            if (y == NIL || next < 0) {
                found = h;
                break;
            }
            if (next == 0 || k == steps) break;
            h = y;
        }
    }
    w->cnt.breakpoint_tests += tests - leftmost;
    w->cnt.breakpoint_exact += slow;
    return found;
}

/* The arc above site p if it is one of the fingers and p lies strictly
 * between its breakpoints, else NIL. */
static uint32_t locate_near(sweep *w, const double *p) {
    uint32_t found = NIL;
    for (int f = 0; f < FINGERS && found == NIL; f++)
        found = locate_from(w, p, w->finger[f], 0);
    return found;
}

/* Slices of x. Sites on several curves at once (concentric rings, rays
 * from a point, spirals) keep one front on the beach line for each side
 * of each curve, more than FINGERS can follow, and each site fell in a
 * search of a beach line as long as a quarter to a third of the sites:
 * 20 to 24 breakpoint tests a site for 10^6 sites, each test below the
 * cached top of the tree a miss. But each front is the arc of the last
 * site split in near that x: with the arc of the last site of each of
 * 64 to 1024 slices of x (cut at the quantiles of a sample of the sites'
 * x), 99% of 10^6 sites on ten rings and 86% on sixteen rays fell in
 * their slice's arc, 96% of those on rays within two arcs of it. Elsewhere
 * the slice's arc is seldom the one (9% for coordinates spread over
 * decades, whose sites come in no order along x), so, like the fingers,
 * it is tried only while it has lately been right (xdir_score). A
 * short beach line stays in the cache and needs no slices. */
#define XDIR 256u
#define XDIR_SAMPLE 4096u
#define XDIR_ON (FINGER_ONE * 3 / 4)
/* Arcs a slice's arc may be walked past, each way (locate_from). */
#define HINT_STEPS 2

/* Makes the slices (once): 1 if they are there, 0 if out of memory
 * (then the search goes on without them). */
static int xdir_make(sweep *w) {
    if (w->xdir) return 1;
    size_t m = w->n < XDIR_SAMPLE ? w->n : XDIR_SAMPLE;
    void *block = malloc(XDIR * sizeof *w->xdir +
                         (XDIR - 1 + m) * sizeof *w->xcut);
    if (!block) return 0;
    uint32_t *dir = block;
    double *cut = (double *)(dir + XDIR), *smp = cut + (XDIR - 1);
    for (size_t k = 0; k < m; k++) smp[k] = w->xy[2 * (k * w->n / m)];
    qsort(smp, m, sizeof *smp, cmp_double);
    for (uint32_t j = 0; j + 1 < XDIR; j++)
        cut[j] = smp[(size_t)(j + 1) * m / XDIR];
    for (uint32_t j = 0; j < XDIR; j++) dir[j] = NIL;
    w->xdir = dir;
    w->xcut = cut;
    return 1;
}

/* The slice of x: how many cuts are not above it. */
static inline uint32_t xslice(const sweep *w, double x) {
    uint32_t k = 0;
    for (uint32_t step = XDIR / 2; step; step >>= 1)
        k += x >= w->xcut[k + step - 1] ? step : 0;
    return k;
}

/* ---- Trace -----------------------------------------------------------------
 * With a trace (run->trace, w->tracing), each event reports a step (vor.h)
 * in site indices: orig[] maps the sorted ids. Coordinates for drawing
 * come from the input, not the rescaled copy. Only called when tracing,
 * and kept out of line (VOR__COLD) so that the events' code stays as it
 * is without a trace. */

/* The counts so far into c; exact is the sum of the sweep's three. */
static const vor_counts *counts_now(const sweep *w, vor_counts *c) {
    *c = w->run->counts;
    vor__counts_add(c, &w->cnt);
    c->exact += w->cnt.breakpoint_exact + w->cnt.circle_top_exact +
                w->cnt.event_exact;
    return c;
}

/* Reports a SCHEDULE or CANCEL step for the sorted triple t. */
VOR__COLD static void trace_event(sweep *w, vor_step_kind kind,
                                  const uint32_t *t) {
    vor_step st;
    vor_counts c;
    vor__step_init(&st, kind);
    st.counts = counts_now(w, &c);
    for (int k = 0; k < 3; k++) st.tri[k] = w->orig[t[k]];
    vor__trace_circle(w->s, st.tri[0], st.tri[1], st.tri[2], st.vertex, &st.y);
    w->run->trace(w->run->trace_ctx, &st);
}

/* Fills st->beach with the beach line's sites, left to right, and returns
 * the position of arc x in it (UINT32_MAX if x is not on it). VOR_ENOMEM
 * through *status if the scratch cannot grow. */
static uint32_t trace_beach(sweep *w, vor_step *st, uint32_t x,
                            vor_status *status) {
    *status = VOR_OK;
    if (w->cap_beach < w->n_beach) {
        size_t cap = 2 * (size_t)w->n_beach + 64;
        uint32_t *v = realloc(w->beach, cap * sizeof *v);
        if (!v) {
            *status = VOR_ENOMEM;
            return UINT32_MAX;
        }
        w->beach = v;
        w->cap_beach = cap;
    }
    uint32_t at = UINT32_MAX, k = 0;
    for (uint32_t a = w->leftmost; a != NIL; a = ARC(a).next) {
        assert(k < w->n_beach);
        if (a == x) at = k;
        w->beach[k++] = w->orig[ARC(a).site];
    }
    assert(k == w->n_beach);
    st->beach = w->beach;
    st->n_beach = k;
    return at;
}

/* Reports the SITE step of site i, whose new arc s is on the beach line:
 * it split the arc of sorted site arc_site (split), or it lies below the
 * breakpoint of the arcs of l and r. */
VOR__COLD static vor_status trace_site(sweep *w, uint32_t i, uint32_t s,
                                       int split, uint32_t arc_site,
                                       uint32_t l, uint32_t r) {
    vor_step t;
    vor_counts c;
    vor_status st;
    vor__step_init(&t, VOR_STEP_SITE);
    t.counts = counts_now(w, &c);
    t.site = w->orig[i];
    t.y = w->s->xy[2 * (size_t)t.site + 1];
    if (split) {
        t.arc = w->orig[arc_site];
    } else {
        t.breakpoint[0] = t.tri[0] = w->orig[l];
        t.breakpoint[1] = t.tri[1] = w->orig[r];
        t.tri[2] = t.site;
        double top;
        vor__trace_circle(w->s, t.tri[0], t.tri[1], t.tri[2], t.vertex, &top);
    }
    t.at = trace_beach(w, &t, s, &st);
    if (st != VOR_OK) return st;
    w->run->trace(w->run->trace_ctx, &t);
    return VOR_OK;
}

/* Reports the CIRCLE step of the arcs of sorted sites a, b, c; b's arc,
 * just removed, was right of arc left (of site a); the beach line is the
 * one after. */
VOR__COLD static vor_status trace_circle(sweep *w, uint32_t left, uint32_t a,
                                         uint32_t b, uint32_t c) {
    vor_step t;
    vor_counts now;
    vor_status st;
    vor__step_init(&t, VOR_STEP_CIRCLE);
    t.counts = counts_now(w, &now);
    t.tri[0] = w->orig[a];
    t.tri[1] = w->orig[b];
    t.tri[2] = w->orig[c];
    vor__trace_circle(w->s, t.tri[0], t.tri[1], t.tri[2], t.vertex, &t.y);
    t.at = trace_beach(w, &t, left, &st) + 1; /* where b was */
    if (st != VOR_OK) return st;
    w->run->trace(w->run->trace_ctx, &t);
    return VOR_OK;
}

/* ---- Event records and the heap ------------------------------------------ */

/* What the tie-breaking stages know about record r's event, computed on
 * first use and kept in its side slot (side_of), its known saying which
 * parts are filled:
 * c[0..2] the double-double bounds (hi, lo, err; err < 0 if unavailable;
 * outside the safe range, tight_top's) (KNOWN_DD),
 * c[3..5] the circle exactly in doubles (x, y, r^2; r^2 < 0 if not
 * exact) (KNOWN_EXACT),
 * c[6..9] its box (event_box),
 * c[10..12] its offs: the y of the triple's left site, the top's height
 * above it and that height's error bound (event_off),
 * c[13..24] its shape (event_shape). */
enum {
    KNOWN_DD = 1,
    KNOWN_EXACT = 2,
    KNOWN_BOX = 4,
    IS_BOX = 8,
    KNOWN_OFFSET = 16,
    KNOWN_TOP = 32, /* c[0..1] hold the top exactly, c[2] = 0 */
    KNOWN_SHAPE = 64, /* its shape filled, if HAS_SHAPE (event_shape) */
    HAS_SHAPE = 128,
    KNOWN_OFF = 256, /* its offs filled (event_off) */
    HAS_SLOT = 512   /* rr[r].slot is its side slot */
};

#define SIDE_BOX 6
#define SIDE_OFF 10
#define SIDE_SHAPE 13
#define SIDE_DOUBLES (SIDE_SHAPE + VOR__FORTUNE_SHAPE)

/* Side slots. Few events meet a tie at any one time, and their records
 * are spread over all the sweep has: on 10^6 sites on a circle, at most
 * 1,247 at once among 10^6 records. Kept in arrays indexed by record,
 * what ties taught wrote a few doubles here and there over 400 MB and
 * faulted in a page for nearly every write (23 k of the run's 40 k page
 * faults were the shapes' and the bounds'; 16.6 k faults in all with
 * slots, and 383 -> 292 bytes a site at the peak). A slot is taken in
 * order from a block of one per record (recs_resize; pages never
 * written cost nothing), freed with its record and kept when the
 * record is reused for a new triple (rec_fill), so that the slots in
 * use stay as many as the records that meet ties now, packed at the
 * block's start. There are never more slots than records: a record has
 * at most one. */
static inline double *slot_at(const sweep *w, uint32_t k) {
    return w->side + SIDE_DOUBLES * (size_t)k;
}

static void slot_free(sweep *w, uint32_t k) {
    memcpy(slot_at(w, k), &w->free_slot, sizeof w->free_slot);
    w->free_slot = k;
}

/* Record r's side slot, taken if it has none. */
static inline double *side_of(sweep *w, uint32_t r) {
    if (!(w->rr[r].known & HAS_SLOT)) {
        uint32_t k = w->free_slot;
        if (k != NO_EVENT)
            memcpy(&w->free_slot, slot_at(w, k), sizeof w->free_slot);
        else
            k = w->n_slots++;
        w->rr[r].slot = k;
        w->rr[r].known |= HAS_SLOT;
    }
    return slot_at(w, w->rr[r].slot);
}

/* Gives the records room for cap of them, keeping the n_recs there are,
 * in two allocations: one of the records, one of what varies in use
 * (the side slots, see side_of; the heap, which the buckets keep short;
 * late[], which holds the events past the last site: up to one a site on
 * a parabola, a few on most inputs). -1 if out of memory, with nothing
 * changed. The first block's advice for huge pages (vor__alloc_large)
 * maps 2 MiB at a time, however little of an array is used, so that
 * only what is used from its start on is in it. Peak bytes a site at
 * 10^5 sites, medians of 3 runs, with a record's fields in six arrays
 * (each array's used prefix rounded up to 2 MiB) and with one array of
 * records: a circle 345 -> 304, a polygon 349 -> 304, a star 254 -> 176,
 * a geometric line 307 -> 282; with the heap and late[] in that block
 * too, the circle had peaked at 361. */
static int recs_resize(sweep *w, uint32_t cap) {
    size_t c = cap, k = w->n_recs;
    evrec *rr = vor__alloc_large(c, sizeof *rr);
    char *q = malloc(c * (SIDE_DOUBLES * sizeof(double) + sizeof(event) +
                          sizeof(uint32_t)));
    if (!rr || !q) {
        free(rr);
        free(q);
        return -1;
    }
    double *side = (double *)(void *)q;
    event *heap = (event *)(void *)(side + SIDE_DOUBLES * c);
    uint32_t *late = (uint32_t *)(void *)(heap + c);
    if (k) {
        memcpy(rr, w->rr, k * sizeof *rr);
        memcpy(heap, w->heap, w->n_heap * sizeof *heap);
        memcpy(late, w->late, w->n_late * sizeof *late);
        memcpy(side, w->side, w->n_slots * SIDE_DOUBLES * sizeof *side);
    }
    free(w->rr);
    free(w->side);
    w->rr = rr;
    w->side = side;
    w->heap = heap;
    w->late = late;
    w->cap_recs = cap;
    return 0;
}

/* A free event record, or NO_EVENT if out of memory. The heap grows with
 * the records, one entry per record. */
static uint32_t rec_new(sweep *w) {
    uint32_t r;
    if (w->free_recs != NO_EVENT) {
        r = w->free_recs;
        w->free_recs = w->rr[r].hpos;
        return r;
    }
    if (w->n_recs == w->cap_recs) {
        if (w->cap_recs > UINT32_MAX / 4) return NO_EVENT;
        if (recs_resize(w, 2 * w->cap_recs)) return NO_EVENT;
    }
    w->rr[w->n_recs].known = 0;
    return w->n_recs++;
}

static void rec_free(sweep *w, uint32_t r) {
    if (w->rr[r].known & HAS_SLOT) slot_free(w, w->rr[r].slot);
    w->rr[r].known = 0;
    w->rr[r].hpos = w->free_recs;
    w->free_recs = r;
}

/* Outside the filters' safe range (sites over more than 2^250 binary
 * orders of magnitude) there are no double-double bounds, and the float
 * interval of a circle whose sites' differences span hundreds of orders
 * is wide or unbounded: two such events met the exact comparison
 * whenever they met (x log-uniform over 2^-500 .. 2^500, y in [0, 1],
 * 10^5 sites: 3 M exact comparisons, 17 s). There the interval computed
 * from the circle's exact integers (vor__fortune_circle_top_tight, about
 * 2^-44 wide) takes the bounds' place, as a midpoint and a half-width
 * that covers the midpoint's rounding. */
#define BEYOND (-2.0) /* out[2] of tight_top: a top past the doubles */
static void tight_top(const double *a, const double *b, const double *c,
                      double *out) {
    double lo, hi;
    int k = vor__fortune_circle_top_tight(a, b, c, &lo, &hi, out);
    if (k == 2) { /* out[0..1] hold its key */
        out[2] = BEYOND;
        return;
    }
    out[0] = lo + (hi - lo) / 2;
    out[1] = 0;
    /* hi - out[0] and out[0] - lo are at most (hi - lo) (1/2 + u/2) +
     * |out[0]| u (1 + u), u = 2^-53; the factors below cover that and the
     * three roundings of this line */
    out[2] = (hi - lo) * (0.5 + 0x1p-50) + fabs(out[0]) * 0x1p-51;
    if (k == 0 || !isfinite(out[2])) out[2] = -1;
}

static int event_dd(sweep *w, uint32_t r, const double **v) {
    const evrec *e = &w->rr[r];
    double *c = side_of(w, r);
    if (!(w->rr[r].known & KNOWN_DD)) {
        w->rr[r].known |= KNOWN_DD;
        const double *a = site_xy(w, e->s[0]), *b = site_xy(w, e->s[1]),
                     *d = site_xy(w, e->s[2]);
        if (!w->safe)
            tight_top(a, b, d, c); /* c[2] < 0 if it has no bounds */
        else if (!vor__fortune_circle_top_dd(a, b, d, &c[0], &c[1], &c[2]))
            c[2] = -1;
    }
    *v = c;
    return c[2] >= 0;
}

/* Record r's bounds (event_dd) narrowed, where they can be, by the
 * bounds relative to the triple's highest site (vor__fortune_circle_offset,
 * exact integers: computed once, and only for events whose bounds failed
 * to order them): 1 if they changed. */
static int event_offset(sweep *w, uint32_t r) {
    if (w->rr[r].known & KNOWN_OFFSET) return 0;
    w->rr[r].known |= KNOWN_OFFSET;
    const double *d;
    int had = event_dd(w, r, &d);
    const uint32_t *t = w->rr[r].s;
    double v[3];
    if (!vor__fortune_circle_offset(site_xy(w, t[0]), site_xy(w, t[1]),
                                    site_xy(w, t[2]), &v[0], &v[1], &v[2]) ||
        (had && v[2] >= d[2]))
        return 0;
    memcpy(side_of(w, r), v, sizeof v);
    return 1;
}

/* Record r's circle exactly in doubles (c[3..5]), if it is; and where
 * its radius is exact too, its top exactly in place of the bounds
 * (KNOWN_TOP: c[0] + c[1] with no error). A lattice's circles of
 * Pythagorean radius have tops on the lattice's rows and equal to one
 * another's: the sites of a row met them in integers (80 k of the
 * 105 k exact comparisons of 10^5 integer pixels), and so did their
 * ties. */
static int event_exact(sweep *w, uint32_t r, const double **v) {
    const evrec *e = &w->rr[r];
    double *c = side_of(w, r);
    if (!(w->rr[r].known & KNOWN_EXACT)) {
        w->rr[r].known |= KNOWN_EXACT;
        const double *a = site_xy(w, e->s[0]), *b = site_xy(w, e->s[1]),
                     *d = site_xy(w, e->s[2]);
        if (!(w->small ? vor__fortune_circle_exact_small(a, b, d, c + 3)
                       : vor__fortune_circle_exact_double(a, b, d, c + 3)))
            c[5] = -1;
        else if (w->safe && vor__fortune_exact_top(c + 3, &c[0], &c[1])) {
            c[2] = 0;
            w->rr[r].known |= KNOWN_DD | KNOWN_TOP;
        }
    }
    *v = c + 3;
    return c[5] >= 0;
}

/* Order of the events of records r1, r2 whose tops are both known
 * exactly (KNOWN_TOP): by top, then by the centres' x, then (one point)
 * by record index. */
static int top_before(sweep *w, uint32_t r1, uint32_t r2) {
    const double *c1 = side_of(w, r1), *c2 = side_of(w, r2);
    if (c1[0] != c2[0]) return c1[0] < c2[0];
    if (c1[1] != c2[1]) return c1[1] < c2[1];
    if (c1[3] != c2[3]) return c1[3] < c2[3];
    w->equal_tops++;
    return r1 < r2;
}

/* Record r's box (vor__fortune_box_of), or NULL if its triple is none;
 * found on first use, like the other tie-breaking knowledge: a grid's
 * events meet each other's ties again and again (a decimal grid with
 * holes: 2.7 M comparisons of 200 k events at 10^5 sites), and reading
 * the triple's three points for each was a sixth of the run. */
static const double *event_box(sweep *w, uint32_t r) {
    if (!(w->rr[r].known & KNOWN_BOX)) {
        const uint32_t *t = w->rr[r].s;
        w->rr[r].known |= KNOWN_BOX;
        if (vor__fortune_box_of(site_xy(w, t[0]), site_xy(w, t[1]),
                                site_xy(w, t[2]), side_of(w, r) + SIDE_BOX))
            w->rr[r].known |= IS_BOX;
    }
    return w->rr[r].known & IS_BOX ? side_of(w, r) + SIDE_BOX : NULL;
}

/* Record r's shape (vor__fortune_shape_of), or NULL if its triple has
 * none: found on first use, like the other knowledge of ties, and kept
 * with it, apart from the arrays every event writes (recs_resize). Two
 * records of one shape, or of one shape and its mirror image, compare
 * without reading a site (shape_try). */
static const double *event_shape(sweep *w, uint32_t r) {
    double *v = side_of(w, r) + SIDE_SHAPE;
    if (!(w->rr[r].known & KNOWN_SHAPE)) {
        w->rr[r].known |= KNOWN_SHAPE;
        const uint32_t *t = w->rr[r].s;
        if (vor__fortune_shape_of(site_xy(w, t[0]), site_xy(w, t[1]),
                                  site_xy(w, t[2]), v))
            w->rr[r].known |= HAS_SHAPE;
    }
    return w->rr[r].known & HAS_SHAPE ? v : NULL;
}

/* The shapes' comparison of events r1, r2 (vor__fortune_shapes_cmp). */
static int shape_cmp(sweep *w, uint32_t r1, uint32_t r2, int *c) {
    const double *u = event_shape(w, r1), *v;
    return u && (v = event_shape(w, r2)) && vor__fortune_shapes_cmp(u, v, c);
}

/* shape_cmp where it has lately decided ties: off a lattice, ahead of
 * the bounds. The cells of a lattice in doubles (a hexagonal grid of
 * spacing 0.1, say) meet each other's ties in the heap again and again:
 * 921 k ties among 150 k events at 10^5 sites, 525 k of them between
 * translates, each of which went through the bounds of both and the
 * proofs of ev_tie. Where translates are rare (the same grid with its x
 * moved by 10^-12, sites on a circle) the shapes would cost more than
 * they decide, so they are tried while they decided at least one tie in
 * 16 lately, and on one tie in 64 otherwise, to notice when they would
 * again. */
#define SHAPE_ONE 1024u
#define SHAPE_ON (SHAPE_ONE / 16)
static int shape_try(sweep *w, uint32_t r1, uint32_t r2, int *c) {
    if (w->shape_score < SHAPE_ON && (++w->shape_skips & 63)) return 0;
    int ok = shape_cmp(w, r1, r2, c);
    if (ok)
        w->shape_score += (SHAPE_ONE - w->shape_score) >> 4;
    else
        w->shape_score -= w->shape_score >> 4;
    return ok;
}

/* The box comparison of events r1, r2 (vor__fortune_boxes_cmp). */
static int box_cmp(sweep *w, uint32_t r1, uint32_t r2, int *c) {
    const double *p = event_box(w, r1), *q;
    return p && (q = event_box(w, r2)) && vor__fortune_boxes_cmp(p, q, c);
}

/* 1 if triples t1 and t2 (counter-clockwise) share two sites and lie on
 * one circle: the two triangles of four cocircular sites, whose events
 * have one top and one centre. One incircle test proves it where the
 * comparison of the two circles' tops would take integers of degree 20:
 * a grid turned by an angle and rounded keeps a third of its cells
 * exactly cocircular, and their pairs met that comparison 410 k times
 * at 10^6 sites. */
static int one_circle(const sweep *w, const uint32_t *t1, const uint32_t *t2) {
    int shared = 0;
    uint32_t other = 0;
    for (int k = 0; k < 3; k++) {
        uint32_t s = t2[k];
        if (s == t1[0] || s == t1[1] || s == t1[2])
            shared++;
        else
            other = s;
    }
    return shared == 2 &&
           vor_incircle(site_xy(w, t1[0]), site_xy(w, t1[1]),
                        site_xy(w, t1[2]), site_xy(w, other)) == 0;
}

/* 1 if the circles e1, e2 of records r1, r2, known exactly in doubles
 * (event_exact), have one centre y and one radius, hence one top; then
 * *before says whether r1's event comes first: by the centres' x, and at
 * one point by record index. */
static inline int same_top(sweep *w, const double *e1, const double *e2,
                           uint32_t r1, uint32_t r2, int *before) {
    if (e1[1] != e2[1] || e1[2] != e2[2]) return 0;
    if (e1[0] != e2[0]) {
        *before = e1[0] < e2[0];
    } else {
        w->equal_tops++;
        *before = r1 < r2;
    }
    return 1;
}

/* Off a lattice, where equal tops are rare: 1 with *before if the
 * events of records r1, r2 separate by their tops' heights above their
 * left sites (vor__fortune_off_cmp). Their intervals' widths are set
 * by the sites' y: the events over a row of 10^4 random x at y = 50 lie
 * within about 10^-9 of one another, closer than the rounding of y
 * allows their intervals to tell, and each needed its double-double
 * bounds; the heights decided 1.59 M of the 2.02 M such comparisons of
 * 100 such rows. (A grid jittered by 10^-12 has tops closer still,
 * often within an ulp of their y: the heights decide 92% of its
 * 1.46 M ties, the bounds the rest.) */
/* 1 if event e's interval is within four times the rounding of its
 * site's y plus the height (about 2^-50 of the top), where the heights
 * can separate what the interval cannot; wider, the height's own error
 * is wider too (the refined tops of sites on a circle, about 2^-47),
 * and computing the heights would only cost time and a record's 24
 * bytes. */
static inline int at_rounding(const event *e) {
    return e->hi - e->lo <= 0x1p-48 * fabs(e->lo);
}

/* Record r's offs (see off_before), computed on first use: the ties
 * are few where they do not crowd, and storing them with every event cost
 * uniform sites 2% more instructions. */
static const double *event_off(sweep *w, uint32_t r) {
    double *o = side_of(w, r) + SIDE_OFF;
    if (!(w->rr[r].known & KNOWN_OFF)) {
        w->rr[r].known |= KNOWN_OFF;
        const uint32_t *t = w->rr[r].s;
        const double *a = site_xy(w, t[0]);
        double lo, hi;
        o[0] = a[1];
        if (vor__fortune_circle_top_off(a, site_xy(w, t[1]), site_xy(w, t[2]),
                                        w->safe, &lo, &hi, o + 1) != 1)
            o[2] = -1;
    }
    return o;
}

static inline int off_before(sweep *w, uint32_t r1, uint32_t r2,
                             int *before) {
    const double *o1 = event_off(w, r1), *o2 = event_off(w, r2);
    int c;
    if (!vor__fortune_off_cmp(o1[0], o1 + 1, o2[0], o2 + 1, &c)) return 0;
    *before = c < 0;
    return 1;
}

/* Order of the events of records r1, r2 whose float intervals overlap (see
 * ev_before): cheapest first. Two cells of a grid compare in sums, two
 * circles known exactly in doubles prove equal tops, translates (and
 * their images) compare by their vector, level triangles of equal width
 * by their apexes, the double-double bounds separate nearly equal tops,
 * and the integer comparison of the two tops decides the rest. Events at
 * the same point are ordered by record index (any fixed order would do). */
static int ev_tie(sweep *w, uint32_t r1, uint32_t r2) {
    const double *e1, *e2, *d1, *d2;
    const uint32_t *t1 = w->rr[r1].s, *t2 = w->rr[r2].s;
    const double *a1 = site_xy(w, t1[0]), *b1 = site_xy(w, t1[1]),
                 *c1 = site_xy(w, t1[2]);
    const double *a2 = site_xy(w, t2[0]), *b2 = site_xy(w, t2[1]),
                 *c2 = site_xy(w, t2[2]);
    int c, box = 0; /* 1: both are cells of a grid, compared; -1: not */
    /* Off a lattice, equal tops are rare and nearly equal ones the rule
     * (sites on a circle): the double-double bounds first, unless both
     * events are cells of a grid of any spacing (0.37 by 0.11, say),
     * whose circles compare in sums and whose equal tops no bounds
     * separate. On a lattice, event_exact holds most circles exactly. */
    if (!w->lattice) {
        box = box_cmp(w, r1, r2, &c) ? 1 : -1;
        if (box > 0 || shape_try(w, r1, r2, &c)) goto decided;
        if (w->safe ? event_dd(w, r1, &d1) && event_dd(w, r2, &d2)
                    : event_dd(w, r1, &d1) + event_dd(w, r2, &d2) == 2) {
            c = vor__fortune_dd_cmp(d1[0], d1[1], d1[2], d2[0], d2[1], d2[2]);
            if (c != 0) return c < 0;
        } else if (!w->safe && d1[2] == BEYOND && d2[2] == BEYOND) {
            /* both tops past the doubles: their keys */
            if ((c = vor__fortune_key_cmp(d1, d2)) != 0) return c < 0;
        }
    }
    if (event_exact(w, r1, &e1) && event_exact(w, r2, &e2) &&
        same_top(w, e1, e2, r1, r2, &c))
        return c;
    if (w->rr[r1].known & w->rr[r2].known & KNOWN_TOP)
        return top_before(w, r1, r2);
    if (box == 0 && box_cmp(w, r1, r2, &c))
        goto decided;
    if (vor__fortune_translate_cmp(a1, b1, c1, a2, b2, c2, w->safe,
                                   w->small, &c) ||
        vor__fortune_level_cmp(a1, b1, c1, a2, b2, c2, &c))
        goto decided;
    /* the bounds separate nearly equal tops of a lattice; on a small one
     * the integers below are cheaper than two records' bounds, and the
     * ties that come this far are equal tops, which no bounds separate
     * (16 k of 10^5 integer pixels, none decided here) */
    if (w->lattice && !w->small && event_dd(w, r1, &d1) &&
        event_dd(w, r2, &d2)) {
        c = vor__fortune_dd_cmp(d1[0], d1[1], d1[2], d2[0], d2[1], d2[2]);
        if (c != 0) return c < 0;
    }
    if (one_circle(w, t1, t2)) {
        c = 0;
        goto decided;
    }
    /* bounds relative to the highest sites, computed once per event and
     * only here, past the cheap proofs of equal tops (which they could
     * not separate) */
    if (!w->lattice && event_offset(w, r1) + event_offset(w, r2) &&
        event_dd(w, r1, &d1) && event_dd(w, r2, &d2)) {
        c = vor__fortune_dd_cmp(d1[0], d1[1], d1[2], d2[0], d2[1], d2[2]);
        if (c != 0) return c < 0;
    }
    w->cnt.event_exact++;
    if (!vor__fortune_circle_cmp_small(a1, b1, c1, a2, b2, c2, &c))
        c = vor__fortune_circle_cmp_exact(a1, b1, c1, a2, b2, c2, w->ws);
decided:
    if (c != 0) return c < 0;
    w->equal_tops++;
    return r1 < r2;
}

/* 1 if event x comes strictly before event y in sweep order. Exact: the
 * float intervals decide when they are disjoint, ev_tie() otherwise. */
static inline int ev_before(sweep *w, const event *x, const event *y) {
    w->cnt.event_compares++;
    if (x->hi < y->lo) return 1;
    if (y->hi < x->lo) return 0;
    uint16_t k = w->rr[x->rec].known & w->rr[y->rec].known;
    int c;
    if (w->lattice && (k & KNOWN_EXACT)) {
        /* both circles known exactly: equal ones decide here, without
         * the calls of ev_tie and its reads of six sites (a grid's
         * cells of one row meet again and again in the heap: 10^5 sites
         * on a grid took a tenth longer) */
        const double *e1 = side_of(w, x->rec) + 3,
                     *e2 = side_of(w, y->rec) + 3;
        if (e1[2] >= 0 && same_top(w, e1, e2, x->rec, y->rec, &c)) return c;
        if (k & KNOWN_TOP) return top_before(w, x->rec, y->rec);
    } else if (!w->lattice && (k & KNOWN_DD)) {
        /* both bounds known: decide here, without the calls of ev_tie
         * (sites on a circle make nearly every comparison come here) */
        const double *d1 = side_of(w, x->rec), *d2 = side_of(w, y->rec);
        if (d1[2] >= 0 && d2[2] >= 0) {
            c = vor__fortune_dd_cmp(d1[0], d1[1], d1[2], d2[0], d2[1], d2[2]);
            if (c != 0) return c < 0;
        }
    } else if (!w->lattice && at_rounding(x) && at_rounding(y) &&
               off_before(w, x->rec, y->rec, &c)) {
        /* the bounds are tighter: tried only where they are missing */
        return c;
    }
    return ev_tie(w, x->rec, y->rec);
}

/* Index of the earlier of children c and c + 1 (c + 1 < n_heap): the
 * interval test picks without branching in the usual case that it
 * decides. */
static inline uint32_t earlier_child(sweep *w, uint32_t c) {
    const event *x = &w->heap[c + 1], *y = &w->heap[c];
    int lt = x->hi < y->lo, gt = y->hi < x->lo;
    if (lt | gt) {
        w->cnt.event_compares++; /* ev_before counts the others */
        return c + (uint32_t)lt;
    }
    return c + (uint32_t)ev_before(w, x, y);
}

static inline void heap_put(sweep *w, uint32_t pos, event e) {
    w->heap[pos] = e;
    w->rr[e.rec].hpos = pos;
}

static void sift_up(sweep *w, uint32_t pos, event e) {
    while (pos > 0) {
        uint32_t par = (pos - 1) / 2;
        if (!ev_before(w, &e, &w->heap[par])) break;
        heap_put(w, pos, w->heap[par]);
        pos = par;
    }
    heap_put(w, pos, e);
}

/* Places e at pos, moving it down past earlier children. */
static void sift_down(sweep *w, uint32_t pos, event e) {
    uint32_t n = w->n_heap;
    for (;;) {
        uint32_t c = 2 * pos + 1;
        if (c >= n) break;
        if (c + 1 < n) c = earlier_child(w, c);
        if (!ev_before(w, &w->heap[c], &e)) break;
        heap_put(w, pos, w->heap[c]);
        pos = c;
    }
    heap_put(w, pos, e);
}

/* Removes the entry at pos: the hole sinks to a leaf along the earlier
 * child (one comparison per level), the last entry fills it and rises to
 * its place. */
static void heap_remove(sweep *w, uint32_t pos) {
    uint32_t n = --w->n_heap;
    if (pos == n) return;
    event last = w->heap[n];
    for (;;) {
        uint32_t c = 2 * pos + 1;
        if (c >= n) break;
        if (c + 1 < n) c = earlier_child(w, c);
        heap_put(w, pos, w->heap[c]);
        pos = c;
    }
    sift_up(w, pos, last);
}

/* ---- Event queue ---------------------------------------------------------
 *
 * While sites remain, most events wait in buckets by the low end of their
 * interval: bucket k holds the events whose lo has the estimated sweep
 * rank k (ymap_rank, clamped to the sites' range), a monotone map; one
 * bucket per site, so that a bucket holds one or two events however the
 * sites are spread in y. Inserting and removing are O(1): each bucket is
 * a doubly linked list of records. A binary heap of every event had to
 * walk a dozen levels for every event removed, the largest single cost of
 * the sweep (a sixth of Fortune's time at 10^6 uniform sites).
 *
 * The events near the sweep line are in a small heap in front of the
 * buckets: the buckets below cur have been poured into it, and an event
 * whose bucket is below cur goes into it at once. It holds the earliest
 * event as long as its top's hi maps below cur, because then every event
 * in a bucket from cur on has its lo past that hi (the map is monotone);
 * q_top pours the next buckets until that holds, and while sites remain,
 * event_first pours only those up to the next site's. So a bucket
 * crowded with events of nearly or exactly equal tops (the cells of a row
 * of a grid, jittered or not; a lattice's unit squares) costs a heap
 * operation on a heap of that bucket's size per event, where a scan of
 * the bucket for each event cost its square. Where the map fails outright (a cluster
 * narrower than a bin, an event whose interval has no upper bound) the
 * buckets pour into the heap, which then serves whatever the input.
 *
 * A crowd of thousands (the events above a long row of sites of one y)
 * spills from the heap into near buckets fitted to it (see spill).
 *
 * After the last site the sites' map sends every event to the last
 * bucket; when many events remain (sites on a parabola or near a line
 * leave half of them), the map is fitted to them instead (refit), and the
 * buckets go on. Events that crowd the fitted buckets (equal tops) go
 * through the heap as before, which alone serves small inputs.
 *
 * Whatever holds the others, an event whose interval lies wholly after
 * the last site's y cannot come before any site: while sites remain, it
 * waits unordered in late[] (O(1) in and out) and joins the others
 * after the last site: in the buckets fitted to them all, or in the
 * buckets (the last of them) or the heap as they are. Sites in convex
 * position below their circles' tops (on an arc of a circle, say) put
 * nearly every event there, each of which would otherwise cost a heap
 * operation as it comes and another as the next site cancels it.
 */
/* Fitting the map to the events after the last site (refit) is worth
 * its pass for this many events; else they stay where they are. */
#define REFIT_MIN 4096
#define LATE 0x80000000u /* hpos: the event waits in late[] */
/* The heap spills into near buckets when it holds more than this. */
#define SPILL_MIN 2048

static inline uint32_t ev_bucket(const sweep *w, double lo) {
    return ymap_rank(&w->ymap, lo);
}

/* 1 if record r's event is in the heap (else in a bucket, or late: hpos
 * holds its bucket or LATE and its place in late[], never a heap
 * position that holds r). */
static inline int in_heap(const sweep *w, uint32_t r) {
    uint32_t p = w->rr[r].hpos;
    return p < w->n_heap && w->heap[p].rec == r;
}

/* Links record r, whose event is set, at *head, in bucket k (hpos). */
static inline void list_link(sweep *w, uint32_t r, uint32_t *head,
                             uint32_t k) {
    uint32_t h = *head;
    w->rr[r].hpos = k;
    w->rr[r].link[0] = NO_EVENT;
    w->rr[r].link[1] = h;
    if (h != NO_EVENT) w->rr[h].link[0] = r;
    *head = r;
}

/* Links record r, whose event is set, into bucket k (k >= cur). */
static void bucket_link(sweep *w, uint32_t r, uint32_t k) {
    list_link(w, r, &w->bhead[k], k);
    w->n_bucketed++;
}

/* Links record r, whose event is set, into near bucket k (>= near_cur);
 * hpos holds n_buckets + k. */
static void near_link(sweep *w, uint32_t r, uint32_t k) {
    list_link(w, r, &w->nhead[k], w->n_buckets + k);
    w->n_nearq++;
}

static void bucket_unlink(sweep *w, uint32_t r) {
    uint32_t p = w->rr[r].link[0], q = w->rr[r].link[1], k = w->rr[r].hpos;
    if (p != NO_EVENT)
        w->rr[p].link[1] = q;
    else if (k < w->n_buckets)
        w->bhead[k] = q;
    else
        w->nhead[k - w->n_buckets] = q;
    if (q != NO_EVENT) w->rr[q].link[0] = p;
    if (k < w->n_buckets)
        w->n_bucketed--;
    else
        w->n_nearq--;
}

/* Pours a bucket's list, from record r, into the heap (count: the
 * events left in its kind of bucket): its events are put in one by one
 * when they are fewer than the heap's, else the heap is built anew
 * (Floyd). */
static inline __attribute__((always_inline)) void
pour_list(sweep *w, uint32_t r, uint32_t *count) {
    uint32_t n0 = w->n_heap;
    for (; r != NO_EVENT; r = w->rr[r].link[1])
        heap_put(w, w->n_heap++, w->rr[r].key);
    *count -= w->n_heap - n0;
    if (w->n_heap - n0 > n0) {
        for (uint32_t i = w->n_heap / 2; i-- > 0;) sift_down(w, i, w->heap[i]);
        return;
    }
    for (uint32_t j = n0; j < w->n_heap; j++) sift_up(w, j, w->heap[j]);
}

/* Pours bucket cur, and moves cur past it; likewise near bucket
 * near_cur. */
static inline __attribute__((always_inline)) void pour(sweep *w) {
    uint32_t r = w->bhead[w->cur];
    w->bhead[w->cur++] = NO_EVENT;
    pour_list(w, r, &w->n_bucketed);
}

static void pour_near(sweep *w) {
    uint32_t r = w->nhead[w->near_cur];
    w->nhead[w->near_cur++] = NO_EVENT;
    pour_list(w, r, &w->n_nearq);
}

static void near_free(sweep *w) {
    free(w->nhead);
    free(w->nmap.block);
    free(w->nmap.grid);
    w->nhead = NULL;
    memset(&w->nmap, 0, sizeof w->nmap);
    w->n_near = w->near_cur = w->n_nearq = 0;
}

/* Near buckets. Sites of one y (a row: time series sampled at equal
 * steps, or columns once turned) make a crowd: each site of the row adds
 * events whose tops lie just above the row, all in the row's bucket,
 * which the sweep has reached, so they go into the heap, whose size the
 * row's length then sets (10^4 sites to a row: 16 k events, every
 * operation some 14 levels of comparisons of nearly equal tops). Once
 * the heap holds more than spill_at events, a map fitted to their lo
 * (ymap_build, as refit does) spreads them over near buckets, one per
 * event, and events that would go into the heap later go there too if
 * their near bucket is not yet poured; front pours them like the
 * others. Where the fitted map cannot spread them (equal tops, which no
 * map separates) the heap keeps them and tries again only at twice the
 * size. When the near buckets are empty they are freed. */
static void spill(sweep *w) {
    uint32_t m = w->n_heap;
    w->spill_at = m < UINT32_MAX / 2 ? 2 * m : UINT32_MAX;
    if (m == 0 || (uint64_t)w->n_buckets + m >= LATE) return;
    keyed *a = malloc((size_t)m * sizeof *a);
    uint32_t *head = malloc((size_t)m * sizeof *head);
    ymap nm;
    memset(&nm, 0, sizeof nm);
    if (!a || !head) goto out;
    uint64_t kmin = UINT64_MAX, kmax = 0;
    for (uint32_t j = 0; j < m; j++) {
        uint64_t key = dkey(w->heap[j].lo + 0.0);
        a[j] = (keyed){key, 0.0, j};
        kmin = key < kmin ? key : kmin;
        kmax = key > kmax ? key : kmax;
    }
    if (ymap_build(&nm, a, m, kmin, kmax) != VOR_OK) goto out;
    /* spread enough? */
    memset(head, 0, (size_t)m * sizeof *head);
    uint32_t most = 0;
    for (uint32_t j = 0; j < m; j++) {
        uint32_t c = ++head[ymap_rank(&nm, w->heap[j].lo)];
        most = c > most ? c : most;
    }
    if (most > m / 16) goto out;
    memset(head, 0xff, (size_t)m * sizeof *head);
    w->nhead = head;
    w->nmap = nm;
    w->n_near = m;
    w->near_cur = 0;
    w->n_nearq = 0;
    for (uint32_t j = 0; j < m; j++) {
        event e = w->heap[j];
        w->rr[e.rec].key = e;
        near_link(w, e.rec, ymap_rank(&nm, e.lo));
    }
    w->n_heap = 0;
    free(a);
    return;
out:
    free(nm.block);
    free(nm.grid);
    free(a);
    free(head);
}

/* front without near buckets: the sites' buckets up to last */
static inline __attribute__((always_inline)) void front_sites(sweep *w,
                                                            uint32_t last) {
    while (w->n_bucketed && w->cur <= last &&
           (!w->n_heap || ev_bucket(w, w->heap[0].hi) >= w->cur))
        pour(w);
}

/* front with the near buckets, or a heap to spill */
static void front_near(sweep *w, uint32_t last, double y) {
    if (w->n_heap > w->spill_at && w->bhead && !w->nhead) spill(w);
    if (!w->nhead) {
        front_sites(w, last);
        return;
    }
    uint32_t last2 = ymap_rank(&w->nmap, y);
    for (;;) {
        if (w->n_nearq && w->near_cur <= last2 &&
            (!w->n_heap || ymap_rank(&w->nmap, w->heap[0].hi) >= w->near_cur)) {
            pour_near(w);
            continue;
        }
        if (w->n_bucketed && w->cur <= last &&
            (!w->n_heap || ev_bucket(w, w->heap[0].hi) >= w->cur)) {
            pour(w);
            continue;
        }
        break;
    }
    if (!w->n_nearq) {
        near_free(w);
        w->spill_at = SPILL_MIN;
    }
}

/* Pours buckets into the heap until its top is the earliest event (see
 * above: its hi maps below cur, and below near_cur under the near
 * buckets' map), or until the buckets of y are poured (last: the sites'
 * bucket of y): past them, an event starts after y. Spills the heap
 * first if it has grown past spill_at, and frees the near buckets once
 * they are empty. */
static inline void front(sweep *w, uint32_t last, double y) {
    if (w->n_heap > w->spill_at || w->nhead)
        front_near(w, last, y);
    else
        front_sites(w, last);
}

/* The map of y to buckets need not be the sites': any monotone map keeps
 * the buckets exact. After the last site, where the sites' map sends
 * every event to the last bucket, the map is fitted again to the live
 * events' lo, the waiting ones of late[] and those in the heap included,
 * and they spread over the buckets, with cur back at the first: sites on
 * a parabola or near a line leave nearly half their events to then,
 * which the heap took one O(log n) operation at a time. The same holds
 * a little before the last site when the heap has grown past REFIT_MIN
 * events and 16 per site left: the events of sites on a circle, whose
 * tops differ from the circle's top only by the sites' rounding, lie
 * above all but its last few dozen sites; they crowd the buckets of
 * those sites and from there the heap (22 k events on average at each
 * removal, 10^5 sites), and fitted to the events then, the buckets take
 * them (see sweep_run). Fitting earlier, while events still bunch among
 * the sites, measured slower than the heap. VOR_ENOMEM if out of memory. */
static vor_status refit(sweep *w) {
    while (w->n_nearq) pour_near(w); /* the heap's events are taken too */
    if (w->nhead) near_free(w);
    size_t m = (size_t)w->n_heap + w->n_bucketed + w->n_late, k = 0;
    keyed *a = vor__alloc_large(m, sizeof *a);
    if (!a) return VOR_ENOMEM;
    if (m > w->n_buckets) {
        uint32_t *h = vor__scratch_new(m, sizeof *h);
        if (!h) {
            free(a);
            return VOR_ENOMEM;
        }
        memset(h, 0xff, m * sizeof *h);
        for (uint32_t b = w->cur; b < w->n_buckets; b++) h[b] = w->bhead[b];
        vor__scratch_free(w->bhead);
        w->bhead = h;
        w->n_buckets = (uint32_t)m;
    }
    for (uint32_t b = w->cur; w->n_bucketed; b++) {
        for (uint32_t r = w->bhead[b]; r != NO_EVENT; r = w->rr[r].link[1]) {
            a[k++].i = r;
            w->n_bucketed--;
        }
        w->bhead[b] = NO_EVENT;
    }
    for (uint32_t j = 0; j < w->n_heap; j++) {
        w->rr[w->heap[j].rec].key = w->heap[j];
        a[k++].i = w->heap[j].rec;
    }
    for (uint32_t j = 0; j < w->n_late; j++) a[k++].i = w->late[j];
    w->n_heap = 0;
    w->n_late = 0;
    w->late_ok = 0;
    uint64_t kmin = UINT64_MAX, kmax = 0;
    for (size_t j = 0; j < m; j++) {
        uint64_t key = dkey(w->rr[a[j].i].key.lo + 0.0);
        a[j].k = key;
        kmin = key < kmin ? key : kmin;
        kmax = key > kmax ? key : kmax;
    }
    ymap fitted;
    vor_status st = ymap_build(&fitted, a, m, kmin, kmax);
    if (st == VOR_OK) {
        free(w->ymap.block);
        free(w->ymap.grid);
        w->ymap = fitted;
    }
    /* with the old map, should the new one be out of memory: a monotone
     * map either way */
    w->cur = 0;
    for (size_t j = 0; j < m; j++)
        bucket_link(w, a[j].i, ev_bucket(w, w->rr[a[j].i].key.lo));
    free(a);
    return st;
}

static inline int late_event(const sweep *w, const event *e) {
    return w->late_ok && e->lo > w->ylast;
}

static void late_put(sweep *w, event e) {
    w->rr[e.rec].key = e;
    w->rr[e.rec].hpos = LATE | w->n_late;
    w->late[w->n_late++] = e.rec;
}

static void late_remove(sweep *w, uint32_t r) {
    uint32_t k = w->rr[r].hpos & ~LATE, m = w->late[--w->n_late];
    w->late[k] = m;
    w->rr[m].hpos = LATE | k;
}

/* Adds event e, whose record holds nothing in the queue, to the heap or
 * its bucket. */
static void q_put(sweep *w, event e) {
    if (w->bhead) {
        uint32_t k = ev_bucket(w, e.lo);
        if (k >= w->cur) {
            w->rr[e.rec].key = e;
            bucket_link(w, e.rec, k);
            return;
        }
        if (w->nhead && (k = ymap_rank(&w->nmap, e.lo)) >= w->near_cur) {
            w->rr[e.rec].key = e;
            near_link(w, e.rec, k);
            return;
        }
    }
    w->n_heap++;
    sift_up(w, w->n_heap - 1, e);
}

/* After the last site: the waiting events join the others, in their
 * buckets (the last, under the sites' map) or the heap. */
static void late_flush(sweep *w) {
    w->late_ok = 0;
    for (uint32_t j = 0; j < w->n_late; j++) q_put(w, w->rr[w->late[j]].key);
    w->n_late = 0;
}

/* The number of events in the queue, late[] aside. */
static inline uint32_t q_size(const sweep *w) {
    return w->n_heap + w->n_bucketed + w->n_nearq;
}

/* The earliest event (the queue is not empty). */
static inline const event *q_top(sweep *w) {
    front(w, UINT32_MAX, INFINITY);
    return &w->heap[0];
}

/* Adds event e, whose record holds nothing in the queue. */
static void q_insert(sweep *w, event e) {
    if (late_event(w, &e))
        late_put(w, e);
    else
        q_put(w, e);
}

/* Removes record r's event. */
static void q_remove(sweep *w, uint32_t r) {
    if (w->rr[r].hpos & LATE)
        late_remove(w, r);
    else if (!w->bhead || in_heap(w, r))
        heap_remove(w, w->rr[r].hpos);
    else
        bucket_unlink(w, r);
}

/* Record e.rec's event becomes e: in the heap it moves up or down from
 * its place (cheaper than a removal and an insertion), wherever its new
 * interval would put it. */
static void q_update(sweep *w, event e) {
    if ((w->rr[e.rec].hpos & LATE) || late_event(w, &e) ||
        (w->bhead && !in_heap(w, e.rec))) {
        q_remove(w, e.rec);
        q_insert(w, e);
        return;
    }
    uint32_t pos = w->rr[e.rec].hpos;
    if (pos > 0 && ev_before(w, &e, &w->heap[(pos - 1) / 2]))
        sift_up(w, pos, e);
    else
        sift_down(w, pos, e);
}

/* Deletes arc b's circle event, if it has one. */
static void drop_event(sweep *w, uint32_t b) {
    uint32_t r = ARC(b).ev;
    if (r == NO_EVENT) return;
    ARC(b).ev = NO_EVENT;
    q_remove(w, r);
    rec_free(w, r);
}

/* The circle event of arc b's current triple: 1 with its interval if the
 * breakpoints around b converge (exact orient2d > 0), else 0. */
static inline int event_of(sweep *w, uint32_t b, double *lo, double *hi) {
    const arc *x = &w->arcs[b];
    if (x->prev == NIL || x->next == NIL) return 0;
    const arc *z = &w->arcs[x->next];
    if (x->lsite == z->site) return 0;
    w->cnt.circle_tops++;
    int o = vor__fortune_circle_top(site_xy(w, x->lsite), site_xy(w, x->site),
                                    site_xy(w, z->site), w->safe, lo, hi);
    /* collinear: only exact arithmetic says so (the callers count the
     * converging triples whose top has no bound, as they read lo) */
    if (o == 0) w->cnt.circle_top_exact++;
    return o > 0;
}

/* Fills record r for arc b's current triple. */
static inline void rec_fill(sweep *w, uint32_t r, uint32_t b) {
    evrec *rec = &w->rr[r];
    rec->s[0] = ARC(b).lsite;
    rec->s[1] = ARC(b).site;
    rec->s[2] = ARC(ARC(b).next).site;
    w->rr[r].known &= HAS_SLOT; /* nothing known about ties yet */
}

/* Narrows record r's interval [*lo, *hi] by its double-double bounds when
 * it is wide. Nearly collinear triples have huge circles whose tops the
 * double filter bounds loosely where their differences are not exact (see
 * vor__fortune_circle_top); their intervals overlap, and every comparison
 * of two such events would read both records' bounds. Computed here once,
 * the bounds shrink the interval to a few ulps, and the queue's plain
 * interval test separates the tops from then on. Only for intervals wider
 * than 2^-30 of the top: the filter's own refinement of nearly collinear
 * triples keeps those of sites on a circle near 2^-47, and the thin
 * triangles of sites in columns or on a parabola come out between 2^-40
 * and 2^-28, which separates their tops almost always; bounds for each of
 * those cost a sixth of the run, and the few comparisons that do overlap
 * compute them when they need them (ev_tie). The margin 2m covers the
 * rounding of t and of t -+ 2m: |t - (d0 + d1)| <= |t| 2^-53. An
 * unbounded interval is narrowed too. Outside the safe range the bounds
 * are tight_top's, and narrowing them as wide as the rule says, not
 * wider, keeps consecutive vertex events apart (vertex_at): with twice
 * their width, 738 pairs of 10^5 sites over 2^+-500 overlapped, and the
 * conversion tested every edge exactly (+60%). */
static inline void narrow(sweep *w, uint32_t r, double *lo, double *hi) {
    if (w->lattice || (*lo > -INFINITY && *hi < INFINITY &&
                       *hi - *lo <= (fabs(*lo) + fabs(*hi)) * 0x1p-30))
        return;
    const double *d;
    if (!event_dd(w, r, &d)) {
        if (d[2] == BEYOND) *lo = DBL_MAX; /* and *hi stays */
        return;
    }
    double t = d[0] + d[1];
    /* outside the safe range d is tight_top's midpoint and half-width,
     * d[1] = 0: t is d[0], and m need cover only its own two roundings
     * and those of t -+ m (fl(t - m) <= t - d[2] needs m (1 - u) >=
     * d[2] + u |t| after m's rounding, u = 2^-53) */
    double m = w->safe ? 2 * (d[2] + fabs(t) * 0x1p-51 + 0x1p-1000)
                       : d[2] * (1 + 0x1p-50) + fabs(t) * 0x1p-52;
    double l = t - m, h = t + m;
    if (l > *lo) *lo = l;
    if (h < *hi) *hi = h;
}

/* Gives arc b the circle event of its triple, if the breakpoints around it
 * converge. b must have no event. VOR_ENOMEM if the heap cannot grow. */
static vor_status add_event(sweep *w, uint32_t b) {
    assert(ARC(b).ev == NO_EVENT);
    double lo, hi;
    if (!event_of(w, b, &lo, &hi)) return VOR_OK;
    if (lo == -INFINITY) w->cnt.circle_top_exact++; /* rare: a branch */
    uint32_t r = rec_new(w);
    if (r == NO_EVENT) return VOR_ENOMEM;
    rec_fill(w, r, b);
    narrow(w, r, &lo, &hi);
    q_insert(w, (event){lo, hi, r, b});
    ARC(b).ev = r;
    if (w->tracing) trace_event(w, VOR_STEP_SCHEDULE, w->rr[r].s);
    return VOR_OK;
}

/* Arc b's triple has changed: its event, if it keeps one, takes the place
 * of the old one in the heap and moves up or down from there (cheaper than
 * a removal and an insertion). */
static vor_status renew_event(sweep *w, uint32_t b) {
    uint32_t r = ARC(b).ev;
    if (r == NO_EVENT) return add_event(w, b);
    w->cnt.false_alarms++; /* the old triple's event will not happen */
    if (w->tracing) trace_event(w, VOR_STEP_CANCEL, w->rr[r].s);
    double lo, hi;
    if (!event_of(w, b, &lo, &hi)) {
        drop_event(w, b);
        return VOR_OK;
    }
    if (lo == -INFINITY) w->cnt.circle_top_exact++; /* rare: a branch */
    rec_fill(w, r, b);
    narrow(w, r, &lo, &hi);
    q_update(w, (event){lo, hi, r, b});
    if (w->tracing) trace_event(w, VOR_STEP_SCHEDULE, w->rr[r].s);
    return VOR_OK;
}

/* ---- Events -------------------------------------------------------------- */

/* A vertex event whose top's y lies in [lo, hi] is being processed: a
 * circle event of triple t, or (t NULL) a site exactly below a
 * breakpoint, whose top is the site. Events come in the order of their
 * tops, so two triangles of one circle (four or more cocircular sites,
 * whose vertex events share the top) are made by vertex events with no
 * other between them but events of that same top: two consecutive vertex
 * events at one point, whose intervals overlap. If no two ever do, no two
 * triangles of the mesh share a circle, and the conversion need not test
 * its edges (vor__mesh_dual's hint -1). Where two intervals overlap, two
 * sites are two points, and two circle events are compared exactly, up
 * to VERTEX_EXACT times a run (a few chance overlaps among 10^6 sites of
 * a dense cluster far from the origin, say); past that, or for a site
 * and a circle event, the overlap counts as a sign. */
#define VERTEX_EXACT 64

/* 1 if the vertex event now (triple t, or NULL) is proven to lie at
 * another point than the one before, whose interval overlapped. */
static int another_point(sweep *w, const uint32_t *t) {
    if (!t && !w->vertex_circle) return 1;
    if (!t || !w->vertex_circle || w->vertex_overlaps ||
        w->vertex_exact == VERTEX_EXACT)
        return 0;
    w->vertex_exact++;
    const uint32_t *u = w->vertex_t;
    const double *a1 = site_xy(w, u[0]), *b1 = site_xy(w, u[1]),
                 *c1 = site_xy(w, u[2]), *a2 = site_xy(w, t[0]),
                 *b2 = site_xy(w, t[1]), *c2 = site_xy(w, t[2]);
    int c;
    if (!vor__fortune_circle_cmp_small(a1, b1, c1, a2, b2, c2, &c))
        c = vor__fortune_circle_cmp_exact(a1, b1, c1, a2, b2, c2, w->ws);
    return c != 0;
}

static inline void vertex_at(sweep *w, double lo, double hi,
                             const uint32_t *t) {
    if (w->vertex_seen && lo <= w->vertex_hi && !another_point(w, t))
        w->vertex_overlaps++;
    w->vertex_hi = hi;
    w->vertex_seen = 1;
    w->vertex_circle = t != NULL;
    if (t) memcpy(w->vertex_t, t, sizeof w->vertex_t);
}

/* Site i: split the arc above it, or open a vertex at once if it lies
 * exactly below a breakpoint.
 *
 *   inside arc b:            below the breakpoint of l and r:
 *     ... b ...                ... l | r ...
 *     ... b | i | b2 ...       ... l | i | r ...   vertex (l, i, r) at once
 *   edge (b, i) traced by      edge (l, r) ends there; (l, i) and (i, r)
 *   both new breakpoints       start there
 */
static vor_status site_event(sweep *w, uint32_t i) {
    const double *p = site_xy(w, i);
    int on = 0;
    uint32_t b = w->finger_score >= FINGER_ON ? locate_near(w, p) : NIL;
    /* the slice's arc, where the beach line has been long */
    uint32_t *slot = NULL, hint = NIL, hinted = NIL;
    if (w->xdir || (w->n_beach > LOCATE_AHEAD && xdir_make(w))) {
        slot = &w->xdir[xslice(w, p[0])];
        hint = *slot;
        if (b == NIL && w->xdir_score >= XDIR_ON)
            b = hinted = locate_from(w, p, hint, HINT_STEPS);
    }
    if (b == NIL) b = locate(w, p, &on);
    int fell = 0;
    for (int f = 0; f < FINGERS; f++) fell |= b == w->finger[f];
    if (fell)
        w->finger_score += (FINGER_ONE - w->finger_score) >> 3;
    else
        w->finger_score -= w->finger_score >> 3;
    if (slot) {
        if (b == hint || b == hinted)
            w->xdir_score += (FINGER_ONE - w->xdir_score) >> 3;
        else
            w->xdir_score -= w->xdir_score >> 3;
    }
    vor_status st;
    w->cnt.site_events++;
    if (!on) {
        uint32_t s = arc_new(w, i);
        if (s == NIL) return VOR_ENOMEM;
        uint32_t b2 = arc_new(w, ARC(b).site);
        if (b2 == NIL) return VOR_ENOMEM;
        uint32_t e = edge_new(w);
        w->aedge[b2] = w->aedge[b];
        w->aedge[b] = e;
        w->aedge[s] = e;
        insert_after(w, b, s);
        insert_after(w, s, b2);
        memmove(w->finger + 1, w->finger, (FINGERS - 1) * sizeof *w->finger);
        w->finger[0] = s;
        if (slot) *slot = s;
        w->n_beach += 2;
        if (w->n_beach > w->cnt.beach_max) w->cnt.beach_max = w->n_beach;
        if (w->tracing &&
            (st = trace_site(w, i, s, 1, ARC(b).site, 0, 0)) != VOR_OK)
            return st;
        if ((st = renew_event(w, b)) != VOR_OK) return st;
        return add_event(w, b2);
    }
    uint32_t r = b, l = ARC(b).prev;
    uint32_t s = arc_new(w, i);
    if (s == NIL) return VOR_ENOMEM;
    if (slot) *slot = s;
    vertex_at(w, p[1], p[1], NULL);
    /* triangle (l, r, i): i, on the sweep line, is the top of the circle
     * and l the left arc, so the three are counter-clockwise */
    uint32_t h = tri_new(w, ARC(l).site, ARC(r).site, i);
    edge_end(w, w->aedge[l], h);
    w->aedge[l] = edge_new(w);
    edge_end(w, w->aedge[l], h + 2);
    w->aedge[s] = edge_new(w);
    edge_end(w, w->aedge[s], h + 1);
    insert_after(w, l, s);
    w->cnt.breakpoint_hits++;
    if (++w->n_beach > w->cnt.beach_max) w->cnt.beach_max = w->n_beach;
    if (w->tracing &&
        (st = trace_site(w, i, s, 0, 0, ARC(l).site, ARC(r).site)) != VOR_OK)
        return st;
    if ((st = renew_event(w, l)) != VOR_OK) return st;
    return renew_event(w, r);
}

/* Circle event of arc b between a and c: vertex (a, b, c); the edges of
 * (a, b) and (b, c) end there, the edge of (a, c) starts there.
 *
 *     ... a | b | c ...   -->   ... a | c ...
 */
static vor_status circle_event(sweep *w, uint32_t b, double lo, double hi) {
    uint32_t a = ARC(b).prev, c = ARC(b).next;
    const uint32_t t[3] = {ARC(a).site, ARC(b).site, ARC(c).site};
    vertex_at(w, lo, hi, t);
    /* what the renewals read besides a and c: the arc after c, and the
     * site left of a (a names it) */
    __builtin_prefetch(site_xy(w, ARC(a).lsite));
    __builtin_prefetch(&w->arcs[ARC(c).next]);
    /* the breakpoints converge: orient2d(a, b, c) > 0 */
    uint32_t h = tri_new(w, ARC(a).site, ARC(b).site, ARC(c).site);
    edge_end(w, w->aedge[a], h);
    edge_end(w, w->aedge[b], h + 1);
    w->aedge[a] = edge_new(w);
    edge_end(w, w->aedge[a], h + 2);
    vor_status st;
    w->cnt.circle_events++;
    remove_arc(w, b);
    w->n_beach--;
    if (w->tracing &&
        (st = trace_circle(w, a, ARC(a).site, ARC(b).site, ARC(c).site)) !=
            VOR_OK)
        return st;
    arc_free(w, b);
    st = renew_event(w, a);
    if (st != VOR_OK) return st;
    return renew_event(w, c);
}

/* ---- Driver -------------------------------------------------------------- */

/* 1 if site p comes strictly before the circle event of triple t, by
 * exact arithmetic (integers for small lattices). */
static int site_before(sweep *w, const double *p, const uint32_t *t) {
    const double *a = site_xy(w, t[0]), *b = site_xy(w, t[1]),
                 *c = site_xy(w, t[2]);
    w->cnt.event_exact++;
    int f = vor__fortune_site_first_small(p, a, b, c);
    return f < 0 ? vor__fortune_site_first_exact(p, a, b, c) : f;
}

/* 1 if the earliest event in the queue comes before site p; then it is
 * the heap's top. Buckets are poured as q_top pours them, but none past
 * p's: an event in a later one starts after p (the map is monotone), and
 * the heap's top, if before p, before it too. Pouring as far as the top's
 * hi would put every event created until the sweep gets there into the
 * heap whenever the nearest event lies far ahead (across the hole of a
 * ring, say); pouring every bucket up to p's, those of events that come
 * after the top. Where the float interval cannot tell, the
 * event's double-double bounds (computed once per event: the same event
 * often meets every site of a row), then integers for small lattices,
 * then the exact comparison. */
static int event_first(sweep *w, const double *p) {
    if (w->bhead && (w->n_bucketed || w->n_nearq || w->n_heap > w->spill_at))
        front(w, ev_bucket(w, p[1]), p[1]);
    if (!w->n_heap) return 0;
    const event *e = &w->heap[0];
    w->cnt.event_compares++;
    if (e->lo > p[1]) return 0;
    if (e->hi < p[1]) return 1;
    const double *d, *x;
    uint32_t r = e->rec;
    int f = -1;
    if (event_dd(w, r, &d)) {
        int c = vor__fortune_dd_cmp(p[1], 0, 0, d[0], d[1], d[2]);
        if (c == 0 && (w->lattice ? !(w->rr[r].known & KNOWN_EXACT) &&
                                        event_exact(w, r, &x) &&
                                        (w->rr[r].known & KNOWN_TOP)
                                  : event_offset(w, r)))
            c = vor__fortune_dd_cmp(p[1], 0, 0, d[0], d[1], d[2]);
        if (c != 0) return c > 0;
        /* a top exactly at p's y: the site first iff left of the centre */
        if (w->rr[r].known & KNOWN_TOP) f = p[0] < d[3];
    }
    if (f < 0) f = site_before(w, p, w->rr[r].s);
    if (f && w->late_ok && p[1] == w->ylast) {
        /* p is on the last row of sites, yet the event's interval reaches
         * below it: unless moved, the event stays the earliest, and every
         * site left on that row (the upper of two lines of sites, say)
         * pays for the same exact comparison. If it comes after the last
         * site too, it waits in late[] (O(1)) with those after the last
         * site. */
        const double *q = site_xy(w, (uint32_t)w->n - 1);
        if (q == p || site_before(w, q, w->rr[r].s)) {
            event moved = *e;
            q_remove(w, r);
            late_put(w, moved);
        }
    }
    return !f;
}

/* With this many sites left, or fewer than the square root of the events
 * waiting, the beach line's tree is no longer rebalanced: an arc leaves
 * it by the plain splice and a new one joins as a leaf. A splice never
 * deepens a binary search tree, and each site left adds at most two
 * levels, so that with k sites left the remaining searches stay within
 * the red-black height plus 2k steps: at most 2k^2 in all, no more than
 * twice the events waiting. Sites in convex position below their
 * circles' tops leave nearly every circle event to the last few sites
 * (on 10^5 sites on a circle, to the last 15, whose y lie above most of
 * the tops; on 10^6, to the last few hundred), and each of those
 * removals rebalanced the tree at random places: a miss on a sibling at
 * each level it walked up. 10^6 sites on a circle go loose with 981
 * sites left and 963 k events waiting, where 64 sites left had let the
 * rebalancing take 5% of the run; the searches of those 981 tested 457
 * breakpoints more in all. */
#define LOOSE_SITES 64

/* Runs the sweep over all sites; *first receives the leftmost arc (site
 * 0's first arc, which stays leftmost: splits keep the left part and circle
 * events never remove an arc without a left neighbour). */
static vor_status sweep_run(sweep *w, uint32_t *first) {
    size_t n = w->n;
    /* the first row: sites of the lowest y, left to right */
    uint32_t last = arc_new(w, 0);
    if (last == NIL) return VOR_ENOMEM;
    *first = last;
    RED(last) = 0;
    w->root = last;
    size_t i = 1;
    while (i < n && w->xy[2 * i + 1] == w->xy[1]) {
        uint32_t s = arc_new(w, (uint32_t)i);
        if (s == NIL) return VOR_ENOMEM;
        w->aedge[last] = edge_new(w);
        insert_after(w, last, s);
        last = s;
        i++;
    }
    w->row = (uint32_t)i;
    w->n_beach = (uint32_t)i;
    w->cnt.beach_max = i;
    w->cnt.site_events = i;
    if (w->tracing) {
        vor_step t;
        vor_status st;
        vor_counts c;
        w->leftmost = *first;
        vor__step_init(&t, VOR_STEP_ORDER);
        t.counts = counts_now(w, &c);
        t.order = w->orig;
        t.n_order = n;
        w->run->trace(w->run->trace_ctx, &t);
        vor__step_init(&t, VOR_STEP_BEGIN);
        t.counts = &c;
        t.y = w->s->xy[2 * (size_t)w->orig[0] + 1];
        (void)trace_beach(w, &t, NIL, &st);
        if (st != VOR_OK) return st;
        w->run->trace(w->run->trace_ctx, &t);
    }
    for (uint64_t step = 0;; step++) {
        vor_status st;
        if (vor__stop_now(w->run, step)) return VOR_ESTOPPED;
        /* after the last site, or when the heap holds most events and
         * few sites are left (see refit) */
        if (w->late_ok &&
            (i == n || (w->bhead && w->n_heap >= REFIT_MIN &&
                        w->n_heap > 16 * (n - i)))) {
            if (w->bhead && q_size(w) + w->n_late >= REFIT_MIN) {
                if ((st = refit(w)) != VOR_OK) return st;
            } else {
                late_flush(w);
            }
        }
        w->list_only = i == n;
        if (!w->loose && (n - i <= LOOSE_SITES ||
                          (uint64_t)(n - i) * (n - i) <=
                              (uint64_t)q_size(w) + w->n_late))
            w->loose = 1;
        if (q_size(w) > 0 &&
            (i == n || event_first(w, site_xy(w, (uint32_t)i)))) {
            const event *e = i == n ? q_top(w) : &w->heap[0];
            uint32_t b = e->arc;
            double lo = e->lo, hi = e->hi;
            assert(w->rr[e->rec].s[1] == ARC(b).site &&
                   w->rr[e->rec].s[0] == ARC(ARC(b).prev).site &&
                   w->rr[e->rec].s[2] == ARC(ARC(b).next).site);
            if (w->n_heap > 2) {
                /* the next event is most often one of the top's
                 * children: its arc and neighbours will be read */
                __builtin_prefetch(&w->arcs[w->heap[1].arc]);
                __builtin_prefetch(&w->arcs[w->heap[2].arc]);
            }
            /* the event's neighbours and edge record, read after the
             * queue's removal: their misses overlap its work */
            const arc *ab = &w->arcs[b];
            __builtin_prefetch(&w->arcs[ab->prev]);
            __builtin_prefetch(&w->arcs[ab->next]);
            __builtin_prefetch(&w->ehe[w->aedge[b]]);
            drop_event(w, b);
            st = circle_event(w, b, lo, hi);
        } else if (i < n) {
            st = site_event(w, (uint32_t)i++);
        } else {
            return VOR_OK;
        }
        if (st != VOR_OK) return st;
    }
}

static void sweep_free(sweep *w) {
    free(w->xy);
    free(w->orig);
    free(w->arcs_block);
    free(w->red);
    free(w->aedge);
    free(w->rr);
    free(w->side);
    vor__scratch_free(w->bhead);
    free(w->nhead);
    free(w->nmap.block);
    free(w->nmap.grid);
    free(w->ymap.block);
    free(w->ymap.grid);
    free(w->ehe);
    free(w->tri);
    free(w->adj);
    free(w->beach);
    free(w->xdir);
    vor__fortune_ws_free(w->ws);
}

/* Closes the mesh with a ghost triangle on every hull edge, once the sweep
 * is done. The breakpoints left on the beach line, left to right, and then
 * the edges of the first row, right to left, are the hull edges in
 * clockwise order (the leftmost arc is always site 0's first arc, the
 * rightmost the last site of the first row):
 *
 *        q ----- p           arcs p | q left to right: finite half-edge
 *         \  t  /            q->p in triangle t (interior on its left),
 *          \   /             ghost (p, q, GHOST) on the other side;
 *            .               its half-edge q->GHOST is the twin of
 *                            GHOST->q in the next ghost, (q, r, GHOST).
 *
 * Every such edge has exactly one end (an edge with none would be a whole
 * line: collinear sites, excluded by the caller). */
static void close_hull(sweep *w, uint32_t first) {
    const size_t g0 = w->n_tri;
    for (uint32_t x = first; ARC(x).next != NIL; x = ARC(x).next) {
        uint32_t h = tri_ghost(w, ARC(x).site, ARC(ARC(x).next).site);
        edge_end(w, w->aedge[x], h);
    }
    for (uint32_t j = w->row - 1; j > 0; j--) {
        uint32_t h = tri_ghost(w, j, j - 1);
        edge_end(w, j - 1, h);
    }
    const size_t g1 = w->n_tri;
    for (size_t g = g0; g < g1; g++) {
        uint32_t a = 3 * (uint32_t)g + 1;
        uint32_t b = 3 * (uint32_t)(g + 1 < g1 ? g + 1 : g0) + 2;
        w->adj[a] = (int32_t)b;
        w->adj[b] = (int32_t)a;
    }
    assert(w->n_tri == 2 * w->n - 2); /* Euler */
}

vor_status vor__fortune(const vor_sites *s, vor_diagram **out) {
    vor__run run;
    memset(&run, 0, sizeof run);
    return vor__fortune_run(s, &run, out);
}

/* The counts of the sweep added to the run's. */
static void count(const sweep *w, vor__run *run) {
    vor__counts_add(&run->counts, &w->cnt);
    run->counts.exact += w->cnt.breakpoint_exact + w->cnt.circle_top_exact +
                         w->cnt.event_exact;
    run->cocircular_signs +=
        w->cnt.event_exact + w->equal_tops + (uint64_t)w->lattice;
}

vor_status vor__fortune_run(const vor_sites *s, vor__run *run,
                            vor_diagram **out) {
    if (!out) return VOR_EINVAL;
    *out = NULL;
    if (!s || s->n < 3 || !s->xy) return VOR_EINVAL;
    if (s->n > VOR_MAX_POINTS) return VOR_ETOOMANY;

    sweep w;
    memset(&w, 0, sizeof w);
    w.n = s->n;
    w.run = run;
    w.tracing = run->trace != NULL;
    w.s = s;
    vor_status st;
    frame f = choose_frame(s, &w.safe, &w.lattice, &w.small);
    /* a trace draws the sweep line across the sites' y */
    if (w.tracing) f.turn = 0;
    /* 2n triangles' room, of which the mesh uses 2n - 2 (Euler, ghosts
     * included): 24n bytes each for tri and adj, the room of n keyed
     * sites, which the sort borrows first */
    _Static_assert(sizeof(keyed) <= 3 * 2 * sizeof(uint32_t),
                   "the sort fits in the mesh arrays");
    st = VOR_ENOMEM;
    w.cap_tri = 2 * w.n;
    w.tri = vor__alloc_large(3 * w.cap_tri, sizeof *w.tri);
    w.adj = vor__alloc_large(3 * w.cap_tri, sizeof *w.adj);
    if (!w.tri || !w.adj) goto fail;
    if ((st = sort_sites(&w, s, f)) != VOR_OK) goto fail;

    st = VOR_ENOMEM;
    /* Room for every arc and event record the sweep can hold (a site adds
     * at most two arcs; an arc has at most one event), taken at once: the
     * pages past the longest beach line are never touched, and nothing is
     * copied as the beach line grows. Sites in convex position keep an
     * arc for each site: doubling copied as many records again as the
     * sweep ended with, and faulted each new block in (a sixth of the
     * time on 10^5 sites on a circle). Where the address space is short,
     * the arrays start small and double. */
    w.cap_arcs = (uint32_t)(2 * w.n + 2);
    while (arcs_resize(&w, w.cap_arcs) || !(w.red = malloc(w.cap_arcs)) ||
           !(w.aedge = vor__alloc_large(w.cap_arcs, sizeof *w.aedge)) ||
           recs_resize(&w, w.cap_arcs)) {
        free(w.arcs_block);
        free(w.red);
        free(w.aedge);
        w.arcs_block = NULL;
        w.arcs = NULL;
        w.red = NULL;
        w.aedge = NULL;
        if (w.cap_arcs <= 64) goto fail;
        w.cap_arcs = 64;
    }
    w.cap_edges = 3 * w.n;
    w.ehe = malloc(w.cap_edges * sizeof *w.ehe); /* mostly never touched */
    w.free_edges = NO_EDGE;
    w.ws = vor__fortune_ws_new();
    if (!w.arcs || !w.red || !w.aedge || !w.ehe || !w.ws)
        goto fail;
    w.late_ok = 1;
    w.ylast = w.xy[2 * w.n - 1];
    if (w.n >= BUCKET_MIN_SITES && w.n <= UINT32_MAX &&
        w.xy[2 * w.n - 1] > w.xy[1]) {
        /* one bucket per site, if the sites' y range has a width */
        w.n_buckets = (uint32_t)w.n;
        w.bhead = vor__scratch_new(w.n_buckets, sizeof *w.bhead);
        if (!w.bhead) goto fail;
        memset(w.bhead, 0xff, w.n_buckets * sizeof *w.bhead); /* empty */
    }
    memset(&w.arcs[NIL], 0, sizeof w.arcs[NIL]); /* the sentinel: black */
    w.aedge[NIL] = NO_EDGE;
    w.red[NIL] = 0;
    w.n_arcs = 1;
    w.free_arcs = NIL;
    w.free_recs = NO_EVENT;
    w.free_slot = NO_EVENT;
    w.spill_at = SPILL_MIN;

    uint32_t first;
    st = sweep_run(&w, &first);
    count(&w, run);
    if (st != VOR_OK) goto fail;
    vor__trace_end(run);
    if (w.n_tri == 0) { /* no vertex: the sites were collinear after all */
        sweep_free(&w);
        return vor__diagram_degenerate(s, out);
    }
    close_hull(&w, first);

    vor__mesh m = {.n_tri = w.n_tri, .cap_tri = w.cap_tri,
                   .tri = w.tri, .adj = w.adj};
    double *lxy = w.xy;
    uint32_t *order = w.orig;
    w.tri = NULL;
    w.adj = NULL;
    w.xy = NULL;
    w.orig = NULL;
    sweep_free(&w); /* the beach line, the heap and the edge records */
    /* vertex ids are sweep ranks: the site of rank v is order[v], at
     * lxy[2v] (moved, rescaled and turned exactly, which leaves every
     * predicate's sign unchanged) */
    int hint = !run->cocircular_first && w.vertex_overlaps == 0
                   ? -1
                   : vor__cocircular_first(run, s->n);
    return vor__mesh_dual(s, &m, lxy, order, hint, out);

fail:
    sweep_free(&w);
    return st;
}
