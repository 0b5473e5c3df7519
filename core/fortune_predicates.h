/* fortune_predicates.h -- the exact decisions of Fortune's sweep, beyond
 * orient2d and incircle.
 *
 * The sweep line moves towards +y; sites are processed in (y, x) order. Two
 * questions need more than vor_orient2d / vor_incircle:
 *
 *   1. Where does a new site p hit the beach line? The breakpoint between
 *      the arcs of sites a (left) and b (right) lies where the circles
 *      through a and through b that touch the sweep line at p are equal.
 *      The circle through a touching the line y = py at p has radius
 *      |p-a|^2 / (2 (py - ay)), so p is left of the breakpoint when
 *          F = |p-a|^2 (py - by) - |p-b|^2 (py - ay) < 0,
 *      with two exceptions: the arcs of a and b meet twice, and F changes
 *      sign at both meeting points. The breakpoint (a, b) is the left one
 *      when b is the higher (newer) site and the right one otherwise; the
 *      newer site's x lies strictly between the two, which tells on which
 *      side of the pair p is before F is consulted. See
 *      vor__fortune_bp_side().
 *
 *   2. When does a circle event happen? At the top of its circle: y = cy + r,
 *      a square root of a rational function of the sites. The sweep keeps a
 *      floating-point interval [lo, hi] proven to contain it
 *      (vor__fortune_circle_top()) and decides exactly, when intervals
 *      cannot, the order of a site and an event
 *      (vor__fortune_site_first_exact(), one square root) and of two events
 *      (vor__fortune_circle_cmp_exact(), a sum of two square roots).
 *
 * Filters and their bounds. eps = 2^-53. Differences of inputs are rounded
 * (relative error eps), sums and products too; no operation may underflow or
 * overflow, which the callers guarantee by a range condition ("safe": every
 * nonzero difference in [2^-302, 4], true after fortune.c has rescaled the
 * input by a power of two so that every coordinate is 0 or in
 * [2^-250, 2)); otherwise the condition is checked per call
 * (vor__fortune_in_range4), and where it fails the out-of-line versions
 * rescale per call and, if even that cannot help, fall back to exact
 * integer arithmetic.
 *
 *   F: each of t1 = (ux^2 + uy^2) vy and t2 = (vx^2 + vy^2) uy (ux = px - ax,
 *   ...) carries 6 roundings (a difference and a square: 3, the sum: 1, a
 *   difference and the product: 2), so |t1 - t2 - F| <= gamma_6 (|t1| + |t2|)
 *   to first order, and the final subtraction does not change the sign. The
 *   bound 8 eps (|t1| + |t2|) covers gamma_6 = 6 eps + O(eps^2) with the
 *   roundings of the bound itself.
 *
 *   circle top: derived in fortune_predicates.c next to the code.
 *
 * Cost: the F filter is 12 flops; the circle top about 40 flops, a square
 * root and two divisions; exact fallbacks a few microseconds.
 */
#ifndef VOR_FORTUNE_PREDICATES_H
#define VOR_FORTUNE_PREDICATES_H

#include <float.h>
#include <math.h>
#include <stdint.h>

#include "internal.h"

/* 8 eps: the bound factor of the F filter (see above). */
#define VOR__BP_BOUND 0x1p-50

/* Sign of F exactly, for any finite input (rescaled filter, then integers).
 * Never fails. */
int vor__fortune_bp_poly_slow(const double *a, const double *b,
                              const double *p);

/* 1 if each of four differences is 0 or within [2^-302, 4] in magnitude:
 * the range condition, checked for one call (a set with a far outlier is
 * not in range as a whole, while nearly every call among its other sites
 * is). */
static inline int vor__fortune_in_range4(double a, double b, double c,
                                         double d) {
    const double lo = 0x1p-302;
    a = fabs(a);
    b = fabs(b);
    c = fabs(c);
    d = fabs(d);
    return (a == 0 || (a >= lo && a <= 4)) && (b == 0 || (b >= lo && b <= 4)) &&
           (c == 0 || (c >= lo && c <= 4)) && (d == 0 || (d >= lo && d <= 4));
}

/* Sign of F (see above), exact. safe: the caller guarantees the range
 * condition, which lets the inline filter decide (else the condition is
 * checked for this call). Adds 1 to *slow when the inline filter cannot
 * (the call goes to vor__fortune_bp_poly_slow: a rescaled filter, then
 * exact integers). */
static inline int vor__fortune_bp_poly_n(const double *a, const double *b,
                                         const double *p, int safe,
                                         uint64_t *slow) {
    double ux = p[0] - a[0], uy = p[1] - a[1];
    double vx = p[0] - b[0], vy = p[1] - b[1];
    if (safe || vor__fortune_in_range4(ux, uy, vx, vy)) {
        double t1 = (ux * ux + uy * uy) * vy;
        double t2 = (vx * vx + vy * vy) * uy;
        double f = t1 - t2, bound = VOR__BP_BOUND * (fabs(t1) + fabs(t2));
        if (f > bound) return 1;
        if (-f > bound) return -1;
    }
    ++*slow;
    return vor__fortune_bp_poly_slow(a, b, p);
}

static inline int vor__fortune_bp_poly(const double *a, const double *b,
                                       const double *p, int safe) {
    uint64_t unread = 0;
    return vor__fortune_bp_poly_n(a, b, p, safe, &unread);
}

/* Side of p relative to the breakpoint between adjacent arcs of sites a
 * (left) and b (right) when the sweep line is at y = p.y: -1 left, 0 exactly
 * below it (p, a and b then lie on a circle touching the sweep line at p),
 * +1 right. Requires a.y <= p.y, b.y <= p.y, (a.y, a.x) < (p.y, p.x) and the
 * same for b (both processed before p), a != b, and not both a.y and b.y
 * equal to p.y. Exact. */
static inline int vor__fortune_bp_side_n(const double *a, const double *b,
                                         const double *p, int safe,
                                         uint64_t *slow) {
    if (a[1] < b[1]) {
        /* b is the narrower arc; (a, b) is its left end, b.x inside it */
        if (p[0] >= b[0]) return 1;
    } else if (a[1] > b[1]) {
        /* a is the narrower arc; (a, b) is its right end, a.x inside it */
        if (p[0] <= a[0]) return -1;
    } else {
        /* equal y: the breakpoint is the vertical bisector. F is then
         * (py - ay) (bx - ax) (2 px - ax - bx) with py > ay, of the sign
         * of (bx - ax) (ux + vx); F's own filter fails where p lies far
         * above a and b against their distance (ux^2 - vx^2 is lost in
         * uy^2). ux, vx and their sum carry a relative rounding each
         * (a difference or sum that underflows is exact), so
         * |fl(ux + vx) - (ux + vx)| <= 2 eps (|ux| + |vx|) to first
         * order, and 4 eps of the rounded magnitudes bounds it with room
         * for their roundings; an overflow gives inf or nan, and both
         * comparisons fail. */
        double ux = p[0] - a[0], vx = p[0] - b[0], g = ux + vx,
               bound = 0x1p-51 * (fabs(ux) + fabs(vx));
        int dir = a[0] < b[0] ? 1 : -1;
        if (g > bound) return dir;
        if (-g > bound) return -dir;
    }
    return vor__fortune_bp_poly_n(a, b, p, safe, slow);
}

/* The same, without counting (*slow as for vor__fortune_bp_poly_n). */
static inline int vor__fortune_bp_side(const double *a, const double *b,
                                       const double *p, int safe) {
    uint64_t unread = 0;
    return vor__fortune_bp_side_n(a, b, p, safe, &unread);
}

/* The circle event of arcs of sites a, b, c (left to right): returns
 * orient2d(a, b, c), exactly (the event exists iff it is +1), and when it is
 * +1 an interval [*lo, *hi] that provably contains the y of the top of the
 * circle through a, b, c. When no useful bound can be proven (nearly
 * collinear sites, results outside the double range) the interval is
 * [-inf, +inf]. The orientation comes from the same determinant as the
 * circle, so the common case costs one evaluation. safe: as above, lets the
 * filter skip its per-call rescaling. Never fails. */
int vor__fortune_circle_top(const double *a, const double *b, const double *c,
                            int safe, double *lo, double *hi);

/* The same, with the top's height above a (y = a.y + g): off[0] = g and
 * off[1] a bound on its error, or off[1] = -1 where the interval is
 * unbounded. Two tops close together far from zero (a row of sites at
 * y = 300, say) overlap in their intervals, whose width the rounding of
 * a.y + g sets, but their heights above their sites' y differ by much
 * more than the heights' errors (see vor__fortune_off_cmp). */
int vor__fortune_circle_top_off(const double *a, const double *b,
                                const double *c, int safe, double *lo,
                                double *hi, double *off);

/* The order of two tops a1.y + g1 and a2.y + g2 (off1, off2 as from
 * vor__fortune_circle_top_off, y1 = a1.y, y2 = a2.y): 1 with *c the sign
 * of their difference if the errors allow, else 0. Exact: the
 * difference of the y is exact with its two_diff error term, and every
 * other rounding is bounded. */
static inline int vor__fortune_off_cmp(double y1, const double *off1,
                                       double y2, const double *off2,
                                       int *c) {
    if (!(off1[1] >= 0 && off2[1] >= 0)) return 0;
    double dy = y1 - y2, bv = y1 - dy, av = dy + bv;
    double edy = (y1 - av) + (bv - y2); /* y1 - y2 = dy + edy exactly */
    double dg = off1[0] - off2[0], s = dy + dg;
    /* |dg - (g1 - g2)| <= u |dg|, |s - (dy + dg)| <= u |s|, u = 2^-53;
     * the factor covers the roundings of the bound itself */
    double bound = (off1[1] + off2[1] + fabs(edy) +
                    0x1p-52 * (fabs(dg) + fabs(s))) * (1 + 0x1p-40) +
                   0x1p-1000;
    if (s > bound) {
        *c = 1;
        return 1;
    }
    if (-s > bound) {
        *c = -1;
        return 1;
    }
    return 0;
}


/* 1 if site s comes strictly before the circle event of a, b, c
 * (orient2d(a, b, c) > 0) in sweep order, 0 if the event comes first.
 * Sweep order: by y, then by x; the event's position is the top of its
 * circle; at the same position the circle event comes first. Exact for all
 * finite input; never fails. */
int vor__fortune_site_first_exact(const double *s, const double *a,
                                  const double *b, const double *c);

/* Second filter, in double-double arithmetic: on success (1), the y of the
 * top of the circle through a, b, c (orient2d > 0) lies within *err of
 * *top_hi + *top_lo. 0 when no bound can be proven (the caller then goes
 * to the exact comparison). Requires the safe range (see above). */
int vor__fortune_circle_top_dd(const double *a, const double *b,
                               const double *c, double *top_hi, double *top_lo,
                               double *err);

/* Compares two tops given by vor__fortune_circle_top_dd: -1 if the first is
 * provably lower, +1 if provably higher, 0 if the bounds cannot tell. */
static inline int vor__fortune_dd_cmp(double hi1, double lo1, double err1,
                                      double hi2, double lo2, double err2) {
    /* delta = top2 - top1 by the accurate double-double sum (relative
     * error at most 3 u^2): two-sums of the high and the low parts, then
     * two renormalisations; only delta's high part is needed */
    double a = -hi1, s = hi2 + a, sb = s - hi2;
    double se = (hi2 - (s - sb)) + (a - sb);
    double c = -lo1, t = lo2 + c, tb = t - lo2;
    double te = (lo2 - (t - tb)) + (c - tb);
    double v = s + (se + t);
    double ve = (se + t) - (v - s);
    double delta = v + (te + ve);
    double m = (err1 + err2) * (1 + 0x1p-40);
    if (delta > m) return -1;
    if (-delta > m) return 1;
    return 0;
}

/* An interval of relative width about 2^-44 around the y of the top of
 * the circle through a, b, c (orient2d > 0), for any finite input, from
 * the circle's exact integers (a few microseconds): 1 with [*lo, *hi];
 * 2 when the top lies past the doubles, with [*lo, *hi] = [DBL_MAX, inf]
 * and the top as key[0] 2^key[1] (key[0] in [0.5, 1), key[1] an integer)
 * within 2^-45 of itself; 0 if nothing is known (a top within 2^-47 of
 * DBL_MAX). */
int vor__fortune_circle_top_tight(const double *a, const double *b,
                                  const double *c, double *lo, double *hi,
                                  double key[2]);

/* The top of the circle through a, b, c (orient2d > 0) as the y of its
 * highest site, *base, plus an offset *off >= 0 known within *err (2^-46
 * of itself, and 2^-1060), from the circle's exact integers: bounds in
 * the form of vor__fortune_circle_top_dd's whose width follows the
 * offset, not the top. Where the top lies just above the highest site
 * (sites on two lines far apart, whose circles through two close sites
 * of one line touch it), the double-double bounds are as wide as
 * 2^-100 of the top and cannot order such tops; these can. 0 if the
 * offset is past 2^1000. */
int vor__fortune_circle_offset(const double *a, const double *b,
                               const double *c, double *base, double *off,
                               double *err);

/* Compares two tops past the doubles by their keys (within 2^-45 each):
 * -1 if the first is provably lower, +1 if higher, 0 if they cannot
 * tell. */
static inline int vor__fortune_key_cmp(const double k1[2],
                                       const double k2[2]) {
    double d = k1[1] - k2[1];
    if (d >= 2) return 1;
    if (d <= -2) return -1;
    double r = ldexp(k1[0] / k2[0], (int)d);
    if (r > 1 + 0x1p-43) return 1;
    if (r < 1 - 0x1p-43) return -1;
    return 0;
}

/* Exact ties cheaply. 1 if the centre and squared radius of the circle
 * through a, b, c (orient2d > 0) are exactly representable and were
 * computed exactly: out = {x, y, r^2}. Two such circles of equal y and
 * r^2 have equal tops; so may others (see vor__fortune_exact_top). 0
 * otherwise (nothing is known then). */
int vor__fortune_circle_exact_double(const double *a, const double *b,
                                     const double *c, double *out);

/* The same for sites of a small lattice: every coordinate a multiple of
 * one 2^k, k >= -300, and below 2^(k + 16) in magnitude (integer pixels,
 * grids and small integers, as the sweep's frame puts them). The
 * differences then have at most 17 significant bits, their products 34,
 * and the numerators of the centre at most 53, so they are computed
 * exactly without being checked: the same result as
 * vor__fortune_circle_exact_double, for half its operations. */
int vor__fortune_circle_exact_small(const double *a, const double *b,
                                    const double *c, double *out);

/* The top of a circle known exactly (circle = {x, y, r^2} from
 * vor__fortune_circle_exact_double) when its radius is exact in doubles
 * too, as the Pythagorean radii of a lattice's circles are: 1 with
 * y + r = *hi + *lo exactly (*hi the sum rounded), else 0. Two such
 * tops are equal iff both parts are, and ordered by *hi, then *lo. */
int vor__fortune_exact_top(const double *circle, double *hi, double *lo);

/* Exact ties of translates. When the triangle a2, b2, c2 is exactly a
 * translate of a1, b1, c1 by some vector (the same shape, in any
 * rotation of the vertices), their circles' tops differ by its y and
 * their centres by its x; a translate of its mirror image (x negated)
 * moves the top the same way, and where the tops are level the centres'
 * x compare in sums (triangles with two level sites), exactly in doubles
 * with small (all six sites on one small lattice, as
 * vor__fortune_circle_exact_small takes them), or, with safe (the range
 * of vor__fortune_circle_top_dd), in double-double bounds. Images turned
 * upside down or by half a turn are taken where the triangles have two
 * sites of equal x, which gives their centres' y exactly. 1 with *res
 * what vor__fortune_circle_cmp_exact would return; else 0 (nothing is
 * known then). Grids of any spacing repeat every shape along their rows,
 * and its images. */
int vor__fortune_translate_cmp(const double *a1, const double *b1,
                               const double *c1, const double *a2,
                               const double *b2, const double *c2, int safe,
                               int small, int *res);

/* vor__fortune_translate_cmp's first two cases in two steps, for callers
 * that keep each event's shape (the comparison inline: a lattice's ties
 * call it hundreds of thousands of times). 1 if the differences of the
 * triple's other two sites (in its cyclic order) from its first in sweep
 * order (least y, then least x) are exact in doubles, with v = {that
 * site's x and y, the four differences, those of the mirror image (x
 * negated, the cyclic order reversed, from its first site) or a NaN v[6]
 * where they are not exact, the two-sum of the x of two sites of one y
 * or a NaN v[10] where there are none}; else 0. Then the comparison of
 * two such shapes u and v: 1 with *res what vor__fortune_circle_cmp_exact
 * would return when one triangle is the other moved, or mirrored and
 * moved with its top moved or with two level sites; else 0 (nothing is
 * known then). */
#define VOR__FORTUNE_SHAPE 12
int vor__fortune_shape_of(const double *a, const double *b, const double *c,
                          double v[VOR__FORTUNE_SHAPE]);
static inline int vor__fortune_shapes_cmp(const double u[VOR__FORTUNE_SHAPE],
                                          const double v[VOR__FORTUNE_SHAPE],
                                          int *res) {
    int dy = (u[1] > v[1]) - (u[1] < v[1]);
    if (u[2] == v[2] && u[3] == v[3] && u[4] == v[4] && u[5] == v[5]) {
        /* moved: translate_cmp's first case */
        *res = dy ? dy : (u[0] > v[0]) - (u[0] < v[0]);
        return 1;
    }
    if (!(u[2] == v[6] && u[3] == v[7] && u[4] == v[8] && u[5] == v[9]))
        return 0;
    /* mirrored and moved: its second case, where two level sites give
     * the centres' x (a NaN sum: no level pair) */
    if (dy) {
        *res = dy;
        return 1;
    }
    if (u[10] != u[10] || v[10] != v[10]) return 0;
    *res = u[10] != v[10] ? (u[10] > v[10]) - (u[10] < v[10])
                          : (u[11] > v[11]) - (u[11] < v[11]);
    return 1;
}

/* Exact ties of level triangles. When each triple has two sites on one
 * row and the third on another, the same two rows for both, the level
 * pairs of equal width, and the third sites' offsets from the pairs'
 * bisectors exact in doubles (a triangular grid of any spacing, or a
 * square one with holes, rounded out of symmetry by ulps), their tops
 * are ordered by those offsets: 1 with *res what
 * vor__fortune_circle_cmp_exact would return; else 0 (nothing is known
 * then). */
int vor__fortune_level_cmp(const double *a1, const double *b1,
                           const double *c1, const double *a2,
                           const double *b2, const double *c2, int *res);

/* Exact ties of boxes. When each triple is three corners of a box with
 * sides parallel to the axes (a grid of any spacing in x and in y makes
 * every circle event so), their circles' tops compare in sums and
 * differences of coordinates: 1 with *res what
 * vor__fortune_circle_cmp_exact would return, when the boxes lie between
 * the same two rows or have the same width and height; else 0 (nothing
 * is known then). */
int vor__fortune_box_cmp(const double *a1, const double *b1, const double *c1,
                         const double *a2, const double *b2, const double *c2,
                         int *res);
/* The same in two steps, for callers that keep each event's box: 1 if a,
 * b, c are three corners of a box with sides parallel to the axes, with
 * the box in v = {x0, x1, y0, y1} (x0 < x1, y0 < y1); else 0. Then the
 * comparison of two such boxes p and q, as above. */
int vor__fortune_box_of(const double *a, const double *b, const double *c,
                        double v[4]);
int vor__fortune_boxes_cmp(const double p[4], const double q[4], int *res);

/* Scratch memory for vor__fortune_circle_cmp_exact (about 100 KiB), so that
 * the comparison cannot fail; NULL if out of memory. Free with
 * vor__fortune_ws_free (NULL is a no-op). */
typedef struct vor__fortune_ws vor__fortune_ws;
vor__fortune_ws *vor__fortune_ws_new(void);
void vor__fortune_ws_free(vor__fortune_ws *ws);

/* Sweep order of two circle events, of a1, b1, c1 and of a2, b2, c2 (each
 * with orient2d > 0): -1 if the first comes first, +1 if the second does,
 * 0 if both are at the same point. By the y of the circles' tops, then by
 * the x of their centres. Exact for all finite input; never fails. */
int vor__fortune_circle_cmp_exact(const double *a1, const double *b1,
                                  const double *c1, const double *a2,
                                  const double *b2, const double *c2,
                                  vor__fortune_ws *ws);

/* The same decisions for small lattices, in 64- and 128-bit integers:
 * the differences among the points must be exact in doubles and, in
 * units of their lowest set bit, below 2^11 within a triple (and 2^30
 * from a to the site, 2^40 between the two triples' first points).
 * vor__fortune_site_first_small returns what vor__fortune_site_first_exact
 * would, or -1 when the input is not such a lattice. For two circle
 * events, 1 with *res what vor__fortune_circle_cmp_exact would return,
 * or 0 when the input is not such a lattice or the two tops would need
 * square roots to compare (their centres' y and their radii ordered
 * oppositely). */
int vor__fortune_site_first_small(const double *s, const double *a,
                                  const double *b, const double *c);
int vor__fortune_circle_cmp_small(const double *a1, const double *b1,
                                  const double *c1, const double *a2,
                                  const double *b2, const double *c2,
                                  int *res);

#endif /* VOR_FORTUNE_PREDICATES_H */
