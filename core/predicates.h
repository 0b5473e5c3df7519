/* predicates.h -- inline fast paths of the exact predicates.
 *
 * vor_orient2d() and vor_incircle() (declared in internal.h, defined in
 * predicates.c) are exact for every finite double input. Most calls are
 * decided by a floating-point evaluation whose rounding error is bounded a
 * priori; only when the computed determinant is smaller than that bound, or
 * when the operands are outside the range where the bound is proven, the
 * out-of-line exact routines run. Hot loops (point location, cavity search,
 * legalisation) include this header to get the filter inlined:
 *
 *     vor__orient2d_fast(a, b, c)     same result as vor_orient2d(a, b, c)
 *     vor__incircle_fast(a, b, c, d)  same result as vor_incircle(a, b, c, d)
 *
 * Cost of a filtered call: orient2d 9 flops and 3 comparisons, incircle 43
 * flops and 3 comparisons, no branch on the sign (about 2.4 ns and 7 ns on
 * the development machine, against 1.6 ns and 3.8 ns for the naive,
 * wrong-near-degeneracy evaluations). Requires the translation
 * unit to be built with -ffp-contract=off (the Makefile does so for all C):
 * a fused multiply-add would change the rounding the bounds are derived for.
 *
 * Error bounds. eps = 2^-53 is the unit roundoff of binary64 with rounding to
 * nearest; every +, -, * returns the exact result times (1 + d), |d| <= eps,
 * as long as nothing overflows and no product falls below 2^-1022 (sums and
 * differences that fall below it are exact).
 *
 *   orient2d: l = (ax-cx)(by-cy), r = (ay-cy)(bx-cx), det = l - r. Each of
 *   l, r carries two rounded differences and one rounded product, so
 *   |l - L| <= (3 eps + 3 eps^2 + eps^3) |l| against the true product L
 *   (error measured against the computed |l|, which is what we know). The
 *   sign of det is right when |l - r| exceeds the sum of those errors; the
 *   last subtraction rounds det by a relative eps, which cannot change its
 *   sign, and costs a factor 1/(1 - eps) in the comparison. Computing
 *   |l| + |r| and the bound itself adds two more roundings. Collecting the
 *   terms, |det| > (3 eps + 12 eps^2 + O(eps^3)) (|l| + |r|) suffices, and
 *   (3 + 16 eps) eps (Shewchuk's ccwerrboundA) covers it with about
 *   4 eps^2 (|l| + |r|) to spare.
 *   Underflow: a product below 2^-1022 has an absolute error of at most
 *   2^-1075 instead. We require |l| + |r| >= 2^-960; then the spare
 *   4 eps^2 (|l| + |r|) >= 2^-1064 exceeds the two possible absolute errors
 *   2 * 2^-1075 by a factor of a thousand, so the bound stays valid.
 *   Overflow: any inf or nan in the products makes |l| + |r|, hence the
 *   bound, inf or nan, and no comparison with it can succeed; det cannot
 *   overflow without |l| + |r| overflowing too.
 *
 *   incircle: det = alift (bdx cdy - cdx bdy) + blift (cdx ady - adx cdy)
 *   + clift (adx bdy - bdx ady), evaluated left to right, with
 *   alift = adx^2 + ady^2 and adx = ax - dx etc. Relative error of one
 *   summand against its absolute value alift (|bdx cdy| + |cdx bdy|):
 *   alift 4 eps (one difference squared: 3, the sum: 1), the parenthesis
 *   4 eps (2 differences, 1 product, 1 subtraction), their product 1 eps:
 *   9 eps; the first addition adds 1 eps of the permanent; the second
 *   addition, like orient2d's subtraction, does not change the sign. So
 *   10 eps times the permanent to first order; Shewchuk's iccerrboundA =
 *   (10 + 96 eps) eps covers the second-order terms and the roundings of
 *   the permanent and of the bound. We add 2^-62 for underflow, below.
 *   Underflow: a product below 2^-1022 has an absolute error of at most
 *   2^-1075 (and then no relative one). Such an error is carried on,
 *   multiplied by the other factor of a later product: an error in a
 *   square by that row's cross term (pa = |bdx cdy| + |cdx bdy| bounds it),
 *   an error in a cross product by that row's lift. All of them together
 *   stay below 2^-1073 U with U = alift + blift + clift + pa + pb + pc + 4
 *   (the 4 for the products that are not multiplied further, with room
 *   for the (1 + eps)^k factors). A small permanent alone does not bound
 *   this (a = (2^500, 0), b = (1/2, 0), c = (0, 2^-1074), d = 0 has
 *   permanent 2^-576 yet a lost term of 2^-75, and the test suite checks
 *   it), so the filter decides only when U <= 2^1006 perm; then the
 *   underflow errors are at most 2^-67 perm, well inside the 2^-62 perm
 *   added to the bound. The check multiplies perm by a power of two
 *   instead of multiplying U by 2^-1073: results in the subnormal range
 *   are slow on x86 (tens of cycles) and would make every call pay.
 *   Overflow: an inf anywhere makes det, perm or U inf or nan; then either
 *   a comparison with nan fails, det = inf cannot exceed bound = inf, or
 *   U = inf fails the guard (perm * 2^1006 may be inf, but then so is the
 *   bound and no comparison succeeds).
 *
 * Outside these ranges the exact routines first rescale the call's points
 * by a power of two (exact) and try the same filter again, so very large or
 * very small but otherwise ordinary coordinates stay cheap.
 */
#ifndef VOR_PREDICATES_H
#define VOR_PREDICATES_H

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "internal.h"

/* (3 + 16 eps) eps and (10 + 96 eps) eps + 2^-62 with eps = 2^-53; both
 * are exactly representable (their bits span fewer than 53 binary places). */
#define VOR__CCW_BOUND (3.0 * 0x1p-53 + 16.0 * 0x1p-106)
#define VOR__ICC_BOUND (10.0 * 0x1p-53 + 96.0 * 0x1p-106 + 0x1p-62)
/* |l| + |r| below this may hide underflowed products (see above). */
#define VOR__CCW_MIN 0x1p-960
/* The incircle filter decides only if U <= perm * VOR__ICC_UNDER. */
#define VOR__ICC_UNDER 0x1p1006

/* The exact evaluations behind the filters (predicates.c). They accept any
 * finite input and return the same as vor_orient2d / vor_incircle; they
 * begin with the rescaled filter, so calling them directly is correct but
 * slower than the _fast versions. */
int vor__orient2d_exact(const double *a, const double *b, const double *c);
int vor__incircle_exact(const double *a, const double *b, const double *c,
                        const double *d);

/* The value of the orient2d determinant, (a.x-c.x)(b.y-c.y) -
 * (a.y-c.y)(b.x-c.x), computed exactly and rounded to long double
 * (relative error below 2^-62; long double holds every such value).
 * Zero exactly when the points are collinear. For constructions that
 * need the determinant of a very flat triangle (vor_circumcenter); too
 * slow for decisions, which need only the sign. */
long double vor__orient2d_value(const double *a, const double *b,
                                const double *c);

/* The filter of orient2d with an absolute term added to its bound: it
 * decides only where |det| exceeds the bound by slack as well. slack = 0
 * is the filter itself (the term is then compiled away); the exact
 * routines pass a slack for points moved by a rounding (predicates.c,
 * "wide calls"). */
static inline int vor__orient2d_filter_slack(const double *a,
                                             const double *b,
                                             const double *c, double slack) {
    double acx = a[0] - c[0], bcx = b[0] - c[0];
    double acy = a[1] - c[1], bcy = b[1] - c[1];
    double l = acx * bcy, r = acy * bcx;
    double det = l - r;
    double sum = fabs(l) + fabs(r);
    double bound = VOR__CCW_BOUND * sum;
    if (slack != 0)
        bound += slack;
    /* Without branches on the sign, which is unpredictable: inf and nan
     * make both comparisons false (bound is inf or nan). */
    int s = (det > bound) - (det < -bound);
    return sum >= VOR__CCW_MIN ? s : 0;
}

/* Sign of orient2d from the filter alone: +1 or -1 when proven, 0 when the
 * filter cannot decide (0 says nothing about collinearity). */
static inline int vor__orient2d_filter(const double *a, const double *b,
                                       const double *c) {
    return vor__orient2d_filter_slack(a, b, c, 0);
}

/* The filter of incircle with an absolute term added to its bound, as
 * vor__orient2d_filter_slack. */
static inline int vor__incircle_filter_slack(const double *a,
                                             const double *b,
                                             const double *c,
                                             const double *d, double slack) {
    double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
    double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
    double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    double cdxady = cdx * ady, adxcdy = adx * cdy;
    double adxbdy = adx * bdy, bdxady = bdx * ady;
    double alift = adx * adx + ady * ady;
    double blift = bdx * bdx + bdy * bdy;
    double clift = cdx * cdx + cdy * cdy;
    double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) +
                 clift * (adxbdy - bdxady);
    double pa = fabs(bdxcdy) + fabs(cdxbdy);
    double pb = fabs(cdxady) + fabs(adxcdy);
    double pc = fabs(adxbdy) + fabs(bdxady);
    double perm = pa * alift + pb * blift + pc * clift;
    double bound = VOR__ICC_BOUND * perm;
    if (slack != 0)
        bound += slack;
    /* underflow guard; inf and nan fail it or the comparisons */
    double under = (alift + blift + clift) + (pa + pb + pc) + 4.0;
    int s = (det > bound) - (det < -bound);
    return under <= perm * VOR__ICC_UNDER ? s : 0;
}

/* Sign of incircle from the filter alone: +1 or -1 when proven, 0 when the
 * filter cannot decide. */
static inline int vor__incircle_filter(const double *a, const double *b,
                                       const double *c, const double *d) {
    return vor__incircle_filter_slack(a, b, c, d, 0);
}

/* Exact orient2d with the filter inlined; see vor_orient2d. */
static inline int vor__orient2d_fast(const double *a, const double *b,
                                     const double *c) {
    int s = vor__orient2d_filter(a, b, c);
    return s ? s : vor__orient2d_exact(a, b, c);
}

/* Exact incircle with the filter inlined; see vor_incircle. */
static inline int vor__incircle_fast(const double *a, const double *b,
                                     const double *c, const double *d) {
    int s = vor__incircle_filter(a, b, c, d);
    return s ? s : vor__incircle_exact(a, b, c, d);
}

/* ---- Counting forms -----------------------------------------------------------
 * name_n is name with one more argument: it adds 1 to *exact when the call
 * is handed to the out-of-line exact routines (the inline filters could not
 * decide), so that the algorithms count their exact calls
 * (vor_counts.exact). The inline part is the same filters, whose shared
 * differences the compiler computes once; the counter is passed only to
 * the out-of-line call behind them (vor__orient2d_counted,
 * vor__incircle_counted: the count, then the exact routine, in
 * predicates.c), so the common path does not carry it. */
int vor__orient2d_counted(const double *a, const double *b, const double *c,
                          uint64_t *exact);
int vor__incircle_counted(const double *a, const double *b, const double *c,
                          const double *d, uint64_t *exact);

static inline int vor__orient2d_fast_n(const double *a, const double *b,
                                       const double *c, uint64_t *exact) {
    int s = vor__orient2d_filter(a, b, c);
    if (s) return s;
    ++*exact;
    return vor__orient2d_exact(a, b, c);
}

static inline int vor__incircle_fast_n(const double *a, const double *b,
                                       const double *c, const double *d,
                                       uint64_t *exact) {
    int s = vor__incircle_filter(a, b, c, d);
    if (s) return s;
    ++*exact;
    return vor__incircle_exact(a, b, c, d);
}

/* ---- Incircle with a local bound -------------------------------------------
 * The filter above needs the permanent of the determinant (about a third
 * of its flops) for a bound that holds whatever the points. A cheaper one
 * follows from the lifts it computes anyway: with L the largest of alift,
 * blift and clift, each lift is at most L, and |bdx cdy| + |cdx bdy| <=
 * (bdx^2 + cdy^2 + cdx^2 + bdy^2) / 2 = (blift + clift) / 2 <= L (and so
 * for the other two), so the permanent is at most 3 L^2, computed with at
 * most a few ulps more, and
 *
 *     S = VOR__ICC_BOUND * 4 L^2 + 2^-900
 *
 * exceeds the dynamic bound of the call by a quarter of itself at least;
 * the absolute term dwarfs the at most 2^-1069 that underflowed products
 * can lose. Overflow: |det| and each of its terms are at most about
 * 3 L^2, so where 4 L^2 overflows S is infinite and decides nothing, and
 * where it does not, det is finite (a nan det decides nothing either). A
 * computed |det| > S proves the sign as the dynamic filter would. L
 * scales with the four points' own extent, where a bound from the span of
 * all the sites (16 M^4, M the span) held for configurations of that size
 * only: at 10^6 gaussian sites, whose centre is 40 times as dense as its
 * bounding box on average, and at 10^7 uniform ones, a large share of the
 * tests fell through it, and Bowyer-Watson and flip ran 7-9% longer there,
 * for the unpredictable branch as much as for the permanent. */

/* The sign from the local bound alone, 0 when it cannot decide. */
static inline __attribute__((always_inline)) int
vor__incircle_local_filter(const double *a, const double *b, const double *c,
                           const double *d) {
    double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
    double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
    double alift = adx * adx + ady * ady;
    double blift = bdx * bdx + bdy * bdy;
    double clift = cdx * cdx + cdy * cdy;
    double det = alift * (bdx * cdy - cdx * bdy) +
                 blift * (cdx * ady - adx * cdy) +
                 clift * (adx * bdy - bdx * ady);
    double l = alift > blift ? alift : blift;
    l = l > clift ? l : clift;
    /* 4 L^2 first: where it overflows, det may too, and S must be inf */
    double s = VOR__ICC_BOUND * ((4.0 * l) * l) + 0x1p-900;
    return (det > s) - (det < -s); /* no branch on the sign */
}

/* Same result as vor_incircle(a, b, c, d). */
static inline __attribute__((always_inline)) int
vor__incircle_local(const double *a, const double *b, const double *c,
                    const double *d) {
    int r = vor__incircle_local_filter(a, b, c, d);
    return r ? r : vor__incircle_fast(a, b, c, d);
}

/* The counting form (see "Counting forms" above), which also adds 1 to
 * *cocircular when the four points are cocircular (only the exact
 * evaluation finds a 0: the count costs nothing on the filtered path). */
static inline __attribute__((always_inline)) int
vor__incircle_local_n(const double *a, const double *b, const double *c,
                      const double *d, uint64_t *exact, uint64_t *cocircular) {
    int r = vor__incircle_local_filter(a, b, c, d);
    if (r) return r;
    r = vor__incircle_filter(a, b, c, d);
    if (r) return r;
    r = vor__incircle_counted(a, b, c, d, exact);
    *cocircular += r == 0;
    return r;
}

/* ---- Orient2d with a static bound ------------------------------------------
 * Where every coordinate difference of the points a loop will test is known
 * to be at most M in magnitude (the span of all the sites, rounded up to a
 * power of two), |l| + |r| <= 2 M^2 in the filter above, so S =
 * VOR__CCW_BOUND * 4 M^2 exceeds the dynamic bound by half of itself, and
 * decides without the absolute values; the underflow margin (S >= 2^-450
 * for M >= 2^-200) dwarfs the 2^-1074 two underflowed products can lose.
 * Unlike incircle's, this determinant shrinks only with the square of the
 * points' extent, and stays above S even for sites 10^-7 of the span
 * apart. */
static inline double vor__orient2d_static_bound(double span) {
    if (!(span >= 0x1p-200 && span <= 0x1p200))
        return INFINITY;
    int ex;
    /* span = f 2^ex with f < 1 - 2^-53, so even the exact difference that
     * span is the rounding of stays below M = 2^ex */
    (void)frexp(span, &ex);
    double m = ldexp(1.0, ex);
    return VOR__CCW_BOUND * 4.0 * (m * m);
}

/* Same result as vor_orient2d(a, b, c), for points whose coordinate
 * differences are within the span that bound s was made for. */
/* The sign from the static bound alone, 0 when it cannot decide. */
static inline int vor__orient2d_static_filter(const double *a, const double *b,
                                              const double *c, double s) {
    double det = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]);
    return (det > s) - (det < -s); /* no branch on the sign */
}

static inline int vor__orient2d_static(const double *a, const double *b,
                                       const double *c, double s) {
    int r = vor__orient2d_static_filter(a, b, c, s);
    return r ? r : vor__orient2d_fast(a, b, c);
}

/* The counting form (see "Counting forms" above). */
static inline int vor__orient2d_static_n(const double *a, const double *b,
                                         const double *c, double s,
                                         uint64_t *exact) {
    int r = vor__orient2d_static_filter(a, b, c, s);
    if (r) return r;
    r = vor__orient2d_filter(a, b, c);
    return r ? r : vor__orient2d_counted(a, b, c, exact);
}

/* ---- Circumcentre, double path ---------------------------------------------
 * vor_circumcenter (geometry.c, where the formula and its range are
 * explained) is this double evaluation, with a long double fallback for
 * what it refuses: a coordinate difference outside [2^-300, 2^300] (0 is
 * fine) or a determinant that rounds to 0. Inlined here for the loops that
 * compute every vertex of a diagram; since vor_circumcenter itself calls
 * it, the two give the same bits. */

/* Nonzero |v| within the double path's window [2^-300, 2^300]; zero counts
 * as inside; inf and nan do not. On the bits: non-negative doubles are
 * ordered as their bit patterns are as integers, so the window is one
 * unsigned range check on |v|'s bits, without branches. */
static inline int vor__cc_in_window(double v) {
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    u &= 0x7fffffffffffffffu;
    const uint64_t lo = 0x2d30000000000000u; /* 2^-300: exponent 723 */
    const uint64_t hi = 0x52b0000000000000u; /* 2^300: exponent 1323 */
    return (u == 0) | (u - lo <= hi - lo);
}

/* Writes the centre of the circle through a, b, c to out[0..1] and
 * returns 1, or returns 0 with out untouched when the double path does not
 * apply (then vor_circumcenter's fallback must be used). */
static inline int vor__circumcenter_fast(const double *a, const double *b,
                                         const double *c, double *out) {
    double bx = b[0] - a[0], by = b[1] - a[1];
    double cx = c[0] - a[0], cy = c[1] - a[1];
    if (!(vor__cc_in_window(bx) & vor__cc_in_window(by) &
          vor__cc_in_window(cx) & vor__cc_in_window(cy)))
        return 0;
    /* a flat triangle (three sites nearly on a line, on the rounded edge
     * of a turned grid, sites along a curve): the rounded determinant has
     * an error below 2^-51 (|p| + |q|), so above 2^-20 of that it is
     * within 2^-30 of itself; below, its centre, far away, could be off
     * by a per cent, and the determinant is computed exactly and rounded
     * once instead (vor__orient2d_value: four terms for sites close beside
     * their magnitude, whose flat triangles all come here; until they did,
     * the long double fallback took a third of a run on a line). Not at
     * 2^-10: the ears of 10^6 sites on a circle, at 2^-17, would pay for
     * it, as they paid for the fallback (Bowyer-Watson a fifth longer). */
    double p = bx * cy, q = by * cx, d = 2 * (p - q);
    if (!(fabs(d) > 0x1p-20 * (fabs(p) + fabs(q)))) {
        d = 2 * (double)vor__orient2d_value(a, b, c);
        if (!(fabs(d) >= DBL_MIN)) /* collinear, or subnormal */
            return 0;
    }
    double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    /* likewise the numerators: a needle (two sites 10^-7 apart, the third
     * 3 away along a curve) cancels 25 bits of one, and its centre was off
     * by 2^-27 of its distance; then the fallback starts from an end of
     * the short side, where they do not cancel */
    double px = cy * b2, qx = by * c2, py = bx * c2, qy = cx * b2;
    double nx = px - qx, ny = py - qy;
    double n = fabs(nx) > fabs(ny) ? fabs(nx) : fabs(ny); /* not fmax: */
    double tx = fabs(px) + fabs(qx), ty = fabs(py) + fabs(qy); /* a call */
    if (!(n > 0x1p-20 * (tx > ty ? tx : ty)))
        return 0;
    double ux = nx / d, uy = ny / d; /* a flat triangle's may overflow */
    if (!(fabs(ux) <= DBL_MAX && fabs(uy) <= DBL_MAX))
        return 0;
    out[0] = a[0] + ux + 0.0; /* + 0.0: no -0.0 */
    out[1] = a[1] + uy + 0.0;
    return 1;
}

#endif /* VOR_PREDICATES_H */
