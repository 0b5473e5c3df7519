/* hilbert.c -- the order in which the incremental algorithms insert sites:
 * biased randomised insertion order (BRIO, Amenta, Choi and Rote 2003)
 * with a Hilbert curve order inside each round.
 *
 * Why: inserting in random order bounds the expected amount of
 * restructuring; inserting along a space-filling curve makes each point
 * land next to the previous one, so that point location walks a step or
 * two and the touched triangles are still in cache. BRIO keeps both: the
 * sites are split into rounds whose sizes grow geometrically (each about
 * seven times as large as all earlier rounds together, the first a few
 * dozen sites), a site's round chosen at random; rounds are inserted one
 * after the other, each in Hilbert order. The factor is free (the analysis
 * needs only a constant); each round's walk along the curve meets, at
 * every place, the triangles of every earlier round, which lie elsewhere
 * in memory, so fewer rounds miss the cache less: with a factor of 8
 * instead of 2 (6 rounds instead of 15 at 10^6 sites) the simulated
 * last-level misses of a whole Bowyer-Watson run drop by a sixth.
 *
 * Representation: for every site one 64-bit word: its round, the top 22
 * bits of its Hilbert key (11 per axis of the 2^16 x 2^16 grid over the
 * bounding square: plenty to separate the sites of a round, and 22 bits
 * sort in fewer passes than 32) and its index, in that order of
 * significance. One least significant digit radix sort (three 9-bit
 * digits, passes whose digit is constant skipped) puts the rounds in order
 * and each round along the curve, equal keys in index order.
 *
 * Adapting to the data: a grid over the bounding box serves uniform
 * points, but skewed, heavy-tailed or multi-scale sets (log-normal
 * coordinates, a city plus one stray point at (0, 0), values spread over
 * many decades) put most sites of a round into a few cells, where they
 * would stay in input order and point location would walk across the
 * whole cluster for every site. So every run of more than LEAF sites that
 * share a cell is keyed again on a grid over its own bounding square,
 * with the curve continuing in the cell's orientation, and sorted; runs
 * that still share a cell are refined in turn. Each refinement resolves a
 * factor of 2^11 in scale, so a cluster is ordered along a curve of its
 * own at whatever scale it lives, and the work stays linear for sets that
 * span a few dozen binary orders of magnitude per level of nesting.
 * Sites on rows of equal y (or columns of equal x), far apart against
 * the spacing of the sites in a row, are keyed with that axis scaled down
 * until the two spacings match (see "Rows and columns"), so that the
 * curve fills neighbouring rows together.
 *
 * The Hilbert key comes from a 4-state automaton (the state is the
 * rotation/reflection of the current sub-square). Its 64-entry table for
 * two bits of x and of y is derived, per call, from the one-bit rule, and
 * a 1024-entry table for four bits at a time from that, so there is no
 * hand-written table to get wrong.
 *
 * Determinism: the round of site i is drawn from a splitmix64 sequence
 * seeded from n, so the same input gives the same order on every run and
 * machine. Coordinates are quantised with halves (x/2 - xmin/2), so that
 * spans up to 2 DBL_MAX do not overflow; a span of 0 (all x equal) puts
 * every site at x = 0.
 *
 * Cost: O(n) for uniform points: one pass for the bounding box, one for
 * keys and rounds, four for the sort (a histogram and three scatters) and
 * one to find crowded cells, and a sample of at most 65536 sites read
 * twice for rows and columns; 10^6 sites take about 45 ms (a third of it
 * the keys, a third the sort, the rest the kernel's zeroing of fresh
 * pages). A refinement costs a pass over its run, so a site pays once per
 * level of nesting it sits in (two or three for the skewed sets above; at
 * most MAX_DEPTH on contrived input). Memory: 16 bytes per site, freed
 * before returning. vor__insertion_order_counted adds the rounds, the
 * refinements and the keys computed to a vor_counts, once per call and
 * per refinement.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

/* ---- Hilbert keys ------------------------------------------------------- */

/* One level of the curve, in the frame of the current sub-square: the
 * point's bits (x, y) select a quadrant, visited in the order (0,0),
 * (0,1), (1,1), (1,0); returns that digit (0..3) and updates the frame
 * state (bit 0: x and y swapped, bit 1: both complemented). The lower-left
 * quadrant's sub-curve is the transpose, the lower-right's the
 * anti-transpose; the upper two keep the frame. */
static unsigned hilbert_step(unsigned *state, unsigned bx, unsigned by) {
    unsigned swap = *state & 1, flip = *state >> 1;
    unsigned x = (swap ? by : bx) ^ flip, y = (swap ? bx : by) ^ flip;
    unsigned digit = (x << 1) | (x ^ y);
    if (y == 0) {
        *state ^= 1;
        if (x == 1)
            *state ^= 2;
    }
    return digit;
}

/* table[state << 4 | x2 << 2 | y2] = next state << 4 | four key bits, for
 * two bits x2 of x and y2 of y (most significant first). */
static void hilbert_table(uint8_t table[64]) {
    for (unsigned st = 0; st < 4; st++) {
        for (unsigned xy = 0; xy < 16; xy++) {
            unsigned s = st, x2 = xy >> 2, y2 = xy & 3;
            unsigned hi = hilbert_step(&s, x2 >> 1, y2 >> 1);
            unsigned lo = hilbert_step(&s, x2 & 1, y2 & 1);
            table[st << 4 | xy] = (uint8_t)(s << 4 | hi << 2 | lo);
        }
    }
}

/* big[state << 8 | x4 << 4 | y4] = next state << 8 | eight key bits, for
 * four bits of x and of y at a time, composed from two steps of table. */
static void hilbert_table4(const uint8_t table[64], uint16_t big[1024]) {
    for (unsigned st = 0; st < 4; st++) {
        for (unsigned xy = 0; xy < 256; xy++) {
            unsigned x4 = xy >> 4, y4 = xy & 15;
            unsigned e1 = table[st << 4 | (x4 >> 2) << 2 | (y4 >> 2)];
            unsigned e2 = table[(e1 >> 4) << 4 | (x4 & 3) << 2 | (y4 & 3)];
            big[st << 8 | xy] =
                (uint16_t)((e2 >> 4) << 8 | (e1 & 15) << 4 | (e2 & 15));
        }
    }
}

/* The top 24 bits of the key of the cell (x, y) of the 2^16 x 2^16 grid
 * (its position along the curve), for a curve that starts in frame state
 * (0 for the whole square): the curve's first 12 levels, which read only
 * the top 12 bits of x and y. The sort uses KEY_BITS <= 24 of them, so the
 * last levels are not computed. */
static inline uint32_t hilbert_key(const uint16_t big[1024], unsigned state,
                                   uint32_t x, uint32_t y) {
    uint32_t key = 0;
    for (int shift = 12; shift >= 4; shift -= 4) {
        unsigned e = big[state << 8 | ((x >> shift) & 15) << 4 |
                         ((y >> shift) & 15)];
        key = key << 8 | (e & 255);
        state = e >> 8;
    }
    return key;
}

/* ---- Quantisation -------------------------------------------------------- */

typedef struct quantiser {
    double lo2;   /* min / 2 */
    double inv;   /* 65535.99 / (span / 2) when finite */
    double half;  /* span / 2 */
} quantiser;

/* Cell 0..65535 of v along one axis. NaN (not expected: sites are
 * validated) lands in cell 0 rather than in undefined behaviour. */
static inline uint32_t quantise(const quantiser *q, double v) {
    double t = v * 0.5 - q->lo2; /* in [0, half] */
    double c = q->inv != 0 ? t * q->inv : t / q->half * 65535.99;
    if (c >= 65535)
        return 65535;
    return c >= 0 ? (uint32_t)c : 0;
}

/* Quantiser for values in [lo, lo + 2 half], over a square of side
 * 2 half (the larger of the two spans). */
static void quantiser_init(quantiser *q, double lo, double half) {
    q->lo2 = lo * 0.5;
    q->half = half;
    q->inv = 0;
    if (half > 0) {
        double inv = 65535.99 / half;
        if (inv <= 0x1p1000) /* finite with room: the usual case */
            q->inv = inv;
    }
}

/* ---- Sorting ------------------------------------------------------------ */

/* Layout of a sort word: site index in the low 30 bits, the top KEY_BITS
 * of its Hilbert key above, its round above that. Sorting the words by
 * bits 30..63 orders by round, then by key, then (stably) by index. */
#define INDEX_BITS 30
#define KEY_BITS 22
#define SORT_BITS 27 /* KEY_BITS + 5 bits of round */
_Static_assert(KEY_BITS <= 24, "hilbert_key computes 24 bits");

/* Sorts w[0..n-1] by bits INDEX_BITS .. INDEX_BITS + SORT_BITS - 1, stably,
 * with tmp (n words): least significant digit first, three 9-bit digits,
 * a pass skipped when all words share its digit. The result is in w. */
static void sort_words(uint64_t *w, uint64_t *tmp, size_t n) {
    enum { BITS = 9, BUCKETS = 1 << BITS, PASSES = SORT_BITS / BITS };
    uint32_t count[PASSES][BUCKETS]; /* n <= 2^30 */
    memset(count, 0, sizeof count);
    for (size_t i = 0; i < n; i++)
        for (int p = 0; p < PASSES; p++)
            count[p][(w[i] >> (INDEX_BITS + BITS * p)) & (BUCKETS - 1)]++;
    uint64_t *src = w, *dst = tmp;
    for (int p = 0; p < PASSES; p++) {
        int shift = INDEX_BITS + BITS * p;
        uint32_t *c = count[p];
        if (c[(src[0] >> shift) & (BUCKETS - 1)] == n)
            continue; /* every word has this digit: nothing to do */
        uint32_t sum = 0;
        for (int b = 0; b < BUCKETS; b++) {
            uint32_t k = c[b];
            c[b] = sum;
            sum += k;
        }
        for (size_t i = 0; i < n; i++)
            dst[c[(src[i] >> shift) & (BUCKETS - 1)]++] = src[i];
        uint64_t *t = src;
        src = dst;
        dst = t;
    }
    if (src != w)
        memcpy(w, src, n * sizeof *w);
}

static inline uint64_t splitmix64(uint64_t *s) {
    uint64_t z = (*s += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

/* ---- Adapting to the data ------------------------------------------------ */

/* The frame state in which the curve runs through the cell whose key's
 * top KEY_BITS bits are in key (a curve started in state): every level's
 * digit changes the state by a constant, independent of the state
 * (hilbert_step: digit 0 swaps x and y, digit 3 swaps and complements,
 * digits 1 and 2 keep the frame), so the state is the start state with
 * the changes of all digits xored in. */
static unsigned key_state(unsigned state, uint32_t key) {
    for (int shift = KEY_BITS - 2; shift >= 0; shift -= 2) {
        unsigned d = (key >> shift) & 3;
        state ^= d == 0 ? 1u : d == 3 ? 3u : 0u;
    }
    return state;
}

/* Runs of at most this many sites that share a grid cell stay in index
 * order; longer ones are refined. */
#define LEAF 16

/* Rows and columns. Sites on a few levels of y (scan lines, tracks, a
 * table of readings: 300 rows of 333 sites in a 1 x 300 box, say) have a
 * triangulation of long thin triangles between neighbouring rows, and a
 * square cell of the grid holds a piece of one row. The curve then goes
 * through the box a row at a time, and every round fills each row while
 * the row above still holds only the earlier rounds' sites; a site of
 * that row then falls into a fan of the row below and opens a cavity of
 * half a dozen triangles (8.5 triangles made a site against 6.2 for
 * uniform sites). With y scaled so that the rows lie as far apart as the
 * sites in a row, the cells hold pieces of several rows and the curve
 * fills neighbouring rows together. Scaling each axis to its span would
 * do it for these sets but costs those that are long because of their
 * shape (a 1 x 300 box of uniform sites, sites near a line), whose
 * triangles are not long: so the scale comes from the levels themselves.
 * Among a sample of m sites, on a grid of m cells over the axis's span,
 * the levels are the runs of occupied cells; an axis is on levels when
 * they are fewer than m / 4, evenly spread and evenly filled (no gap
 * wider than four times the mean, no level with more than four times or
 * less than a quarter of the mean share of the sample): heavy tails and
 * far outliers also leave few occupied cells, but unevenly (a city and
 * one stray point at (0, 0) fill two levels of each axis, one with a
 * single site). L rows over a height 2 hy and a width 2 hx hold n / L
 * sites each, 2 hx L / n apart, with the rows 2 hy / L apart: y is
 * scaled by hx L^2 / (n hy) when that is below 1 (rows farther apart than
 * their sites), and x likewise for columns. Sites spread evenly in y
 * occupy about 0.63 m cells and keep the scale 1. A level must also be
 * thin: its sites' y may differ by at most four times the spacing of
 * sites along it. Two dense clusters far apart in x fill two levels of x,
 * evenly, but each is a cloud as tall as it is wide; scaling x would
 * flatten every cluster into a line of sites ordered by y alone, and
 * point location would walk across the cluster for every site (two
 * clusters of 5 10^4 sites 10^6 apart: 107 steps a site, not 2). */
#define LEVEL_SAMPLE 65536

/* The cell of axis value v on the grid of m cells over [lo, lo + 2 half]. */
static inline size_t level_cell(double v, size_t m, double lo, double half) {
    double cells = (double)m, c = (v * 0.5 - lo * 0.5) / half * cells;
    return c >= cells ? m - 1 : c > 0 ? (size_t)c : 0;
}

/* The levels of axis a (0: x, 1: y) among m of the n sites, spread
 * evenly over the input (input order may follow rows); 0 if the axis is
 * not on levels (see above). *thick receives the largest half-extent
 * along axis a of the sampled sites of one level. work has room for m
 * doubles: m counters, then the extents of at most m / 4 levels. */
static size_t axis_levels(const double *xy, size_t n, size_t m, int a,
                          double lo, double half, double *work,
                          double *thick) {
    uint32_t *count = (uint32_t *)work;
    memset(count, 0, m * sizeof *count);
    for (size_t i = 0; i < m; i++)
        count[level_cell(xy[2 * (size_t)((uint64_t)i * n / m) + a], m, lo,
                         half)]++;
    /* runs of occupied cells: how many, the widest gap between the starts
     * of two, the most and the fewest sites in one */
    size_t levels = 0, start = 0, widest = 0, most = 0, fewest = m, sites = 0;
    for (size_t j = 0; j <= m; j++) {
        if (j < m && count[j]) {
            if (sites == 0) {
                if (levels > 0 && j - start > widest)
                    widest = j - start;
                start = j;
                levels++;
            }
            sites += count[j];
            continue;
        }
        if (sites) {
            most = sites > most ? sites : most;
            fewest = sites < fewest ? sites : fewest;
        }
        sites = 0;
    }
    if (levels < 2 || levels > m / 4 || widest * (levels - 1) > 4 * (m - 1) ||
        most * levels > 4 * m || 4 * fewest * levels < m)
        return 0;
    /* each cell names its level; each level's extent among the sample */
    double *ext = work + (m + 1) / 2;
    for (size_t j = 0, l = 0; j < m; j++) {
        if (!count[j])
            continue;
        if (j == 0 || !count[j - 1]) {
            ext[2 * l] = INFINITY;
            ext[2 * l + 1] = -INFINITY;
            l++;
        }
        count[j] = (uint32_t)l; /* level l - 1, kept nonzero */
    }
    for (size_t i = 0; i < m; i++) {
        double v = xy[2 * (size_t)((uint64_t)i * n / m) + a];
        double *e = ext + 2 * (count[level_cell(v, m, lo, half)] - 1);
        e[0] = v < e[0] ? v : e[0];
        e[1] = v > e[1] ? v : e[1];
    }
    *thick = 0;
    for (size_t l = 0; l < levels; l++) {
        double t = ext[2 * l + 1] * 0.5 - ext[2 * l] * 0.5;
        *thick = t > *thick ? t : *thick;
    }
    return levels;
}

/* Scale of each axis for the keys (see above): scale[a] <= 1, 1 unless
 * the sites lie on rows (a = 1) or columns (a = 0). work has room for
 * min(n, LEVEL_SAMPLE) doubles. */
static void axis_scales(const double *xy, size_t n, const double box[4],
                        double *work, double scale[2]) {
    scale[0] = scale[1] = 1;
    double h[2] = {box[2] * 0.5 - box[0] * 0.5, box[3] * 0.5 - box[1] * 0.5};
    if (n < 4 * LEAF || !(h[0] > 0) || !(h[1] > 0))
        return;
    size_t m = n < LEVEL_SAMPLE ? n : LEVEL_SAMPLE;
    for (int a = 0; a < 2; a++) {
        double thick;
        double levels =
            (double)axis_levels(xy, n, m, a, box[a], h[a], work, &thick);
        /* half the spacing of sites along a level: h[1 - a] L / n */
        double along = h[1 - a] * levels / (double)n;
        double s = along / h[a] * levels;
        if (levels > 0 && s < 1 && thick <= 4 * along)
            scale[a] = s > 0x1p-30 ? s : 0x1p-30;
    }
}

/* Far strays. A dense set with a few sites far from it (a city and one
 * failed geocode at (0, 0)) puts the whole set into a few cells of the grid
 * over its bounding box, and every site is keyed a second time, on the
 * grid over its cell's sites (refine): a pass in key order that reads
 * the coordinates at random, 4% of Bowyer-Watson's time at 10^6
 * sites. So the grid goes over the bulk of the sites instead when at
 * most n / 1024 lie outside it, and quantise() puts the strays into the
 * edge cells. The bulk, per axis: the range of a sample of BULK_SAMPLE
 * sites less its two extremes, widened by 8 / BULK_SAMPLE of itself on
 * each side, then the sites' own extremes within that; tried only when
 * the axis's span is four times the sample's (the sweep's y map finds
 * the bulk of y the same way: fortune.c, bulk_range). One pass over the
 * sites when tried. */
#define BULK_SAMPLE 1024

static void bulk_box(const double *xy, size_t n, double box[4]) {
    if (n < 16 * BULK_SAMPLE) return;
    double lo[2], hi[2];
    int tried = 0;
    for (int a = 0; a < 2; a++) {
        /* the sample's second smallest and second largest */
        double m[2] = {INFINITY, INFINITY}, M[2] = {-INFINITY, -INFINITY};
        for (size_t j = 0; j < BULK_SAMPLE; j++) {
            double v = xy[2 * (j * (n / BULK_SAMPLE)) + (size_t)a];
            if (v < m[1]) {
                m[1] = v < m[0] ? m[0] : v;
                m[0] = v < m[0] ? v : m[0];
            }
            if (v > M[1]) {
                M[1] = v > M[0] ? M[0] : v;
                M[0] = v > M[0] ? v : M[0];
            }
        }
        double s0 = m[1], s1 = M[1], wd = s1 - s0;
        lo[a] = box[a];
        hi[a] = box[a + 2];
        if (wd > 0 && box[a + 2] * 0.5 - box[a] * 0.5 > 2 * wd) {
            lo[a] = s0 - wd * (8.0 / BULK_SAMPLE);
            hi[a] = s1 + wd * (8.0 / BULK_SAMPLE);
            tried = 1;
        }
    }
    if (!tried) return;
    double b[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY};
    size_t out = 0;
    for (size_t i = 0; i < n; i++) {
        double x = xy[2 * i], y = xy[2 * i + 1];
        if (x < lo[0] || x > hi[0] || y < lo[1] || y > hi[1]) {
            if (++out > n / 1024) return; /* a tail, not a few strays */
            continue;
        }
        b[0] = x < b[0] ? x : b[0];
        b[1] = y < b[1] ? y : b[1];
        b[2] = x > b[2] ? x : b[2];
        b[3] = y > b[3] ? y : b[3];
    }
    if (b[0] <= b[2] && b[1] <= b[3]) memcpy(box, b, sizeof b);
}

/* Refinements nest at most this deep: each resolves at least a factor of
 * 2^11 in scale, and doubles span 2098 binary orders of magnitude
 * (2^-1074 to 2^1024), so 192 levels separate any sites the grid can.
 * A cap of 64 (704 orders) left sites spread evenly over a thousand
 * orders (x = 2^(i/100) for 10^5 sites on a line, shuffled) in input
 * order below the 64th level: a quarter of them, and point location
 * walked 900 triangles a site. The work stays O(n) a level. */
#define MAX_DEPTH 192

/* Sorts w[0..m-1] by bits INDEX_BITS.. as sort_words does, by insertion
 * when m is small (a radix sort's fixed cost dominates there). */
static void sort_run(uint64_t *w, uint64_t *tmp, size_t m) {
    if (m > 96) {
        sort_words(w, tmp, m);
        return;
    }
    for (size_t i = 1; i < m; i++) {
        uint64_t v = w[i];
        size_t j = i;
        for (; j > 0 && w[j - 1] > v; j--)
            w[j] = w[j - 1];
        w[j] = v;
    }
}

/* Re-orders the m > LEAF sites w[0..m-1] (sort words whose index field
 * names the sites) that fell into one cell of the grid, in frame state
 * state: each gets a new Hilbert key over the bounding square of these
 * sites alone, so the grid adapts to where they are, and the words are
 * sorted by it (round field cleared: a run lies in one round). Runs that
 * again share a cell are refined in turn, so a cluster of any size or
 * scale is ordered along a curve of its own. Stops when a refinement no
 * longer separates the sites (coordinates that differ only below what
 * halving keeps), or at MAX_DEPTH. tmp has room for m words. */
static void refine(const double *xy, const double scale[2],
                   const uint16_t big[1024], uint64_t *w, uint64_t *tmp,
                   size_t m, unsigned state, int depth, vor_counts *counts) {
    const uint64_t imask = ((uint64_t)1 << INDEX_BITS) - 1;
    double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY,
           ymax = -INFINITY;
    for (size_t i = 0; i < m; i++) {
        const double *p = xy + 2 * (w[i] & imask);
        xmin = p[0] < xmin ? p[0] : xmin;
        xmax = p[0] > xmax ? p[0] : xmax;
        ymin = p[1] < ymin ? p[1] : ymin;
        ymax = p[1] > ymax ? p[1] : ymax;
    }
    double hx = (xmax * 0.5 - xmin * 0.5) * scale[0],
           hy = (ymax * 0.5 - ymin * 0.5) * scale[1];
    double half = hx > hy ? hx : hy;
    if (!(half > 0))
        return;
    if (counts) {
        counts->order_refinements++;
        counts->order_keys += m;
    }
    quantiser qx, qy;
    quantiser_init(&qx, xmin, half / scale[0]);
    quantiser_init(&qy, ymin, half / scale[1]);
    for (size_t i = 0; i < m; i++) {
        uint64_t idx = w[i] & imask;
        uint32_t key = hilbert_key(big, state, quantise(&qx, xy[2 * idx]),
                                   quantise(&qy, xy[2 * idx + 1]));
        w[i] = (uint64_t)(key >> (24 - KEY_BITS)) << INDEX_BITS | idx;
    }
    sort_run(w, tmp, m);
    if ((w[0] >> INDEX_BITS) == (w[m - 1] >> INDEX_BITS) ||
        depth + 1 >= MAX_DEPTH)
        return;
    for (size_t i = 0; i < m;) {
        size_t j = i + 1;
        while (j < m && (w[j] >> INDEX_BITS) == (w[i] >> INDEX_BITS))
            j++;
        if (j - i > LEAF)
            refine(xy, scale, big, w + i, tmp, j - i,
                   key_state(state, (uint32_t)(w[i] >> INDEX_BITS)),
                   depth + 1, counts);
        i = j;
    }
}

/* ---- The order ----------------------------------------------------------- */

/* Expected size of the first round. */
#define FIRST_ROUND 64
/* Each round is expected to be 2^ROUND_BITS = 8 times the size of the one
 * before. */
#define ROUND_BITS 3
/* Rounds are numbered 0..MAX_ROUNDS-1 at most (5 bits in a sort word;
 * 2^32 sites need 10). */
#define MAX_ROUNDS 32

vor_status vor__insertion_order(const double *xy, size_t n, uint32_t *order) {
    return vor__insertion_order_counted(xy, n, order, NULL);
}

vor_status vor__insertion_order_counted(const double *xy, size_t n,
                                        uint32_t *order, vor_counts *counts) {
    return vor__insertion_order_in(xy, n, order, counts, NULL);
}

vor_status vor__insertion_order_in(const double *xy, size_t n,
                                   uint32_t *order, vor_counts *counts,
                                   uint64_t *scratch) {
    if (n == 0)
        return VOR_OK;
    if (n == 1) {
        order[0] = 0;
        return VOR_OK;
    }

    uint64_t *w = scratch, *tmp = scratch ? scratch + n : NULL;
    if (!scratch) {
        w = vor__alloc_large(n, sizeof *w);
        tmp = vor__alloc_large(n, sizeof *tmp);
    }
    if (!w || !tmp) {
        free(w);
        free(tmp);
        return VOR_ENOMEM;
    }

    /* bounding box, each axis scaled for rows or columns, and a square
     * around the scaled box */
    double box[4], scale[2];
    vor__bbox(xy, n, box);
    bulk_box(xy, n, box);
    const double xmin = box[0], ymin = box[1], xmax = box[2], ymax = box[3];
    double hx = xmax * 0.5 - xmin * 0.5, hy = ymax * 0.5 - ymin * 0.5;
    axis_scales(xy, n, box, (double *)tmp, scale);
    double half = hx * scale[0] > hy * scale[1] ? hx * scale[0] : hy * scale[1];
    quantiser qx, qy;
    quantiser_init(&qx, xmin, half / scale[0]);
    quantiser_init(&qy, ymin, half / scale[1]);

    /* rounds: k rounds, the last taking each site with probability 7/8,
     * the one before 7/64, ..., the first the remaining ~FIRST_ROUND / n
     * (the shift bound only keeps the shift inside size_t) */
    int k = 1;
    while (k < MAX_ROUNDS && ROUND_BITS * (k - 1) < 40 &&
           ((size_t)FIRST_ROUND << (ROUND_BITS * (k - 1))) < n)
        k++;

    if (counts) {
        counts->order_rounds += (uint64_t)k;
        counts->order_keys += n;
    }

    uint8_t table[64];
    uint16_t big[1024];
    hilbert_table(table);
    hilbert_table4(table, big);
    uint64_t seed = 0x5eed0f0b1a5edu ^ (uint64_t)n, bits = 0;
    int nbits = 0;
    const uint64_t last = (uint64_t)1 << (ROUND_BITS * (k - 1));
    for (size_t i = 0; i < n; i++) {
        uint32_t key = hilbert_key(big, 0, quantise(&qx, xy[2 * i]),
                                   quantise(&qy, xy[2 * i + 1]));
        /* z trailing zeros of a random word, capped at ROUND_BITS * (k-1);
         * t = z / ROUND_BITS is t with probability (7/8) 8^-t below k-1,
         * and k-1 with the rest; round = k-1-t */
        if (nbits <= ROUND_BITS * (k - 1)) {
            bits = splitmix64(&seed);
            nbits = 64;
        }
        uint64_t r = bits | last;
        int z = 0;
        while (!(r & 1)) {
            r >>= 1;
            z++;
        }
        bits >>= z + 1;
        nbits -= z + 1;
        int t = z / ROUND_BITS;
        uint64_t round = (uint64_t)(k - 1 - t);
        w[i] = (round << KEY_BITS | key >> (24 - KEY_BITS)) << INDEX_BITS |
               (uint64_t)i;
    }
    sort_words(w, tmp, n);
    /* cells the fixed grid over the whole set could not split: clusters,
     * heavy tails, a far outlier */
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && (w[j] >> INDEX_BITS) == (w[i] >> INDEX_BITS))
            j++;
        if (j - i > LEAF) {
            uint32_t key = (uint32_t)(w[i] >> INDEX_BITS) &
                           (((uint32_t)1 << KEY_BITS) - 1);
            refine(xy, scale, big, w + i, tmp, j - i, key_state(0, key), 1,
                   counts);
        }
        i = j;
    }
    for (size_t i = 0; i < n; i++)
        order[i] = (uint32_t)(w[i] & (((uint64_t)1 << INDEX_BITS) - 1));
    if (!scratch) {
        free(w);
        free(tmp);
    }
    return VOR_OK;
}
