/* predicates.c -- exact orient2d and incircle for all finite doubles.
 *
 * Three stages, each used only when the one before cannot decide:
 *
 *   1. The floating-point filter of predicates.h (inlined into callers):
 *      the determinant in doubles with an a priori error bound.
 *   2. Exact arithmetic in doubles. The operands are rescaled by a power of
 *      two chosen per call so that the largest is just below 1 (exact: only
 *      the exponents change), and the filter is tried once more on the
 *      rescaled points. Small lattices (every coordinate a multiple of 2^lo
 *      and every difference below 2^(lo + 26) for orient2d, 2^(lo + 12) for
 *      incircle: grids, integer input) are then decided by the plain double
 *      evaluation, which is exact for them. incircle then tries a
 *      double-double evaluation (stage 2a), and operands within 61 bits of
 *      each other an exact one in 256-bit integers (stage 2b: sites
 *      exactly on one circle). Otherwise the determinant is
 *      evaluated exactly as a floating-point expansion: a sum of
 *      non-overlapping doubles ordered by increasing magnitude whose sign
 *      is the sign of the largest component. Differences are exact
 *      two-component expansions (two-sum), products exact two-component
 *      expansions (two-product via fma(), which is exact and correctly
 *      rounded), sums merge expansions. This is exact as long as no
 *      component would need bits below 2^-1074: every input is an integer
 *      multiple of 2^lo, so a degree-k polynomial in them is a multiple of
 *      2^(k lo), and after rescaling the largest input is below 2^0, so it
 *      is enough that the call's own dynamic range hi - lo (hi: every
 *      |input| < 2^hi) is at most 1074/k: 537 for orient2d (k = 2), 268
 *      for incircle (k = 4). The largest values stay below 2^16: no
 *      overflow.
 *   3. Otherwise (one call mixing, say, 1e300 and 1e-300): first the
 *      filter once more, on the points scaled so that the largest is below
 *      1 and rounded where the smallest fall below 2^-1074, with a bound
 *      widened by what that rounding can move the determinant (see "wide
 *      calls"): most such calls are far from degenerate and end here. Then
 *      integers. Every
 *      input becomes the integer x / 2^lo (at most 2098 bits) and the
 *      determinant is computed with GMP's mpn layer on fixed-size arrays on
 *      the stack. mpn does not allocate for these sizes, so this stage, like
 *      the others, cannot fail.
 *
 * Invariants: expansions are arrays of doubles, increasing magnitude,
 * non-overlapping, with zero components removed (an empty expansion is 0).
 * Cost (development machine): stage 1 2.4 ns (orient2d) and 7 ns
 * (incircle); stage 2 about 50 ns for the rescaled filter or a lattice,
 * up to a microsecond for incircle expansions with inexact differences;
 * stage 3 about 10 microseconds. Stack use is below 48 KiB (the incircle
 * expansions' buffers and the integers). No globals, thread-safe, never
 * fails.
 *
 * The expansion algorithms are those of J. R. Shewchuk, "Adaptive Precision
 * Floating-Point Arithmetic and Fast Robust Geometric Predicates" (1997),
 * whose theorems give exactness and non-overlap under round-to-nearest-even;
 * this file uses the unconditional two-sum everywhere for simplicity.
 */
#include <float.h>
#include <gmp.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "predicates.h"

#if GMP_NAIL_BITS != 0
#error "predicates.c assumes GMP limbs without nail bits"
#endif

/* ---- Public entry points ------------------------------------------------- */

int vor_orient2d(const double *a, const double *b, const double *c) {
    return vor__orient2d_fast(a, b, c);
}

int vor_incircle(const double *a, const double *b, const double *c,
                 const double *d) {
    return vor__incircle_fast(a, b, c, d);
}

int vor__orient2d_counted(const double *a, const double *b, const double *c,
                          uint64_t *exact) {
    ++*exact;
    return vor__orient2d_exact(a, b, c);
}

int vor__incircle_counted(const double *a, const double *b, const double *c,
                          const double *d, uint64_t *exact) {
    ++*exact;
    return vor__incircle_exact(a, b, c, d);
}

/* ---- Error-free transformations ------------------------------------------ */

/* s + e == a + b exactly, s = fl(a + b) (Knuth's two-sum; no branch on the
 * magnitudes). Exact unless a + b overflows; underflow is harmless because
 * sums below 2^-1022 are exact. */
static inline void two_sum(double a, double b, double *s, double *e) {
    double x = a + b;
    double bv = x - a;
    double av = x - bv;
    *e = (a - av) + (b - bv);
    *s = x;
}

/* s + e == a - b exactly, s = fl(a - b). */
static inline void two_diff(double a, double b, double *s, double *e) {
    double x = a - b;
    double bv = a - x;
    double av = x + bv;
    *e = (a - av) + (bv - b);
    *s = x;
}

/* p + e == a * b exactly, p = fl(a * b), provided a * b neither overflows
 * nor has bits below 2^-1074 (the callers' range checks guarantee both). */
static inline void two_prod(double a, double b, double *p, double *e) {
    double x = a * b;
    *e = fma(a, b, -x);
    *p = x;
}

/* ---- Expansions ---------------------------------------------------------- */

/* h = e + f. h must not alias e or f and has room for elen + flen
 * components. Returns the length of h. The components of both inputs are
 * merged by increasing magnitude and accumulated with two-sum; every
 * nonzero rounding error is emitted, smallest first, the final sum last.
 * A zero result is the empty expansion. */
static int exp_sum(int elen, const double *e, int flen, const double *f,
                   double *h) {
    if (elen == 0) {
        memcpy(h, f, (size_t)flen * sizeof *h);
        return flen;
    }
    if (flen == 0) {
        memcpy(h, e, (size_t)elen * sizeof *h);
        return elen;
    }
    int i = 0, j = 0, n = 0;
    double q;
    if (fabs(f[0]) < fabs(e[0]))
        q = f[j++];
    else
        q = e[i++];
    while (i < elen || j < flen) {
        double g;
        if (j >= flen || (i < elen && fabs(e[i]) <= fabs(f[j])))
            g = e[i++];
        else
            g = f[j++];
        double s, err;
        two_sum(q, g, &s, &err);
        if (err != 0)
            h[n++] = err;
        q = s;
    }
    if (q != 0)
        h[n++] = q;
    return n;
}

/* h = e * b. h (room for 2 elen) must not alias e. Returns its length. */
VOR__FMA_CLONES
static int exp_scale(int elen, const double *e, double b, double *h) {
    if (elen == 0 || b == 0)
        return 0;
    int n = 0;
    double q, err;
    two_prod(e[0], b, &q, &err);
    if (err != 0)
        h[n++] = err;
    for (int i = 1; i < elen; i++) {
        double p, perr, s;
        two_prod(e[i], b, &p, &perr);
        two_sum(q, perr, &s, &err);
        if (err != 0)
            h[n++] = err;
        two_sum(p, s, &q, &err);
        if (err != 0)
            h[n++] = err;
    }
    if (q != 0)
        h[n++] = q;
    return n;
}

/* Negates an expansion in place. */
static void exp_negate(int n, double *e) {
    for (int i = 0; i < n; i++)
        e[i] = -e[i];
}

/* Sign of an expansion: that of its largest (last) component. */
static int exp_sign(int n, const double *e) {
    if (n == 0)
        return 0;
    return e[n - 1] > 0 ? 1 : -1;
}

/* The exact difference a - b as an expansion of at most two components. */
static int exp_diff(double a, double b, double *h) {
    double s, e;
    two_diff(a, b, &s, &e);
    int n = 0;
    if (e != 0)
        h[n++] = e;
    if (s != 0)
        h[n++] = s;
    return n;
}

/* h = e * f for expansions of at most two components each (exact
 * differences); h has room for 8 components and aliases neither input.
 * Returns its length. */
static int exp_mul2(int elen, const double *e, int flen, const double *f,
                    double *h) {
    double p0[4], p1[4];
    if (elen == 0 || flen == 0)
        return 0;
    int n0 = exp_scale(elen, e, f[0], flen == 1 ? h : p0);
    if (flen == 1)
        return n0;
    int n1 = exp_scale(elen, e, f[1], p1);
    return exp_sum(n0, p0, n1, p1, h);
}

/* Largest incircle expansion: each row is a 16-component lift times a
 * 16-component cross term (at most 512 components), and three rows are
 * summed. */
#define INCIRCLE_MAX (3 * 512)

/* ---- Operand ranges ------------------------------------------------------ */

/* Splits a finite nonzero v into |v| = m 2^q with m odd (so m < 2^53)
 * and q >= -1074: q is the weight of v's lowest set bit. */
static void split_double(double v, uint64_t *m, int *q) {
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    u &= ~((uint64_t)1 << 63);
    int be = (int)(u >> 52);
    uint64_t f = u & (((uint64_t)1 << 52) - 1);
    if (be == 0) {
        *m = f;
        *q = -1074;
    } else {
        *m = f | (uint64_t)1 << 52;
        *q = be - 1075;
    }
    int t = __builtin_ctzll(*m);
    *m >>= t;
    *q += t;
}

/* Over the nonzero values among v[0..n-1]: *hi is the least integer with
 * every |v| < 2^hi, *lo the greatest with every v a multiple of 2^lo.
 * Returns 0 if all values are zero (then *hi, *lo are untouched). */
static int operand_range(const double *v, int n, int *hi, int *lo) {
    int h = INT32_MIN, l = INT32_MAX, any = 0;
    for (int i = 0; i < n; i++) {
        if (v[i] == 0)
            continue;
        uint64_t m;
        int q;
        split_double(v[i], &m, &q);
        int top = q + 64 - __builtin_clzll(m);
        if (top > h)
            h = top;
        if (q < l)
            l = q;
        any = 1;
    }
    if (any) {
        *hi = h;
        *lo = l;
    }
    return any;
}

/* The larger of two non-negative, non-nan values (fmax() is a call into
 * the C library on x86-64, and it handles nans we do not have). */
static inline double max2(double a, double b) { return a > b ? a : b; }

/* 2^e as a double, for -1022 <= e <= 1023. */
static double pow2(int e) {
    uint64_t u = (uint64_t)(e + 1023) << 52;
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

/* ---- Stage 3: integers on the stack (GMP mpn) ---------------------------- */

/* Inputs have at most 2098 bits as integers (2^1024 / 2^-1074); a degree-4
 * polynomial with small coefficients needs fewer than 8400 bits. */
#define BIG_LIMBS 160

typedef struct big {
    mp_size_t n;   /* limbs in use, d[n-1] != 0; 0 means the value 0 */
    int neg;       /* sign of a nonzero value */
    mp_limb_t d[BIG_LIMBS];
} big;

/* x = v / 2^lo, exactly; v is finite and a multiple of 2^lo. */
static void big_from_double(big *x, double v, int lo) {
    x->n = 0;
    x->neg = v < 0;
    if (v == 0)
        return;
    uint64_t m;
    int q;
    split_double(v, &m, &q);
    int shift = q - lo;
    int limb = shift / GMP_NUMB_BITS, bit = shift % GMP_NUMB_BITS;
    memset(x->d, 0, (size_t)(limb + 2) * sizeof x->d[0]);
    x->d[limb] = (mp_limb_t)m << bit;
    x->d[limb + 1] = bit ? (mp_limb_t)(m >> (GMP_NUMB_BITS - bit)) : 0;
    x->n = limb + 2;
    while (x->n > 0 && x->d[x->n - 1] == 0)
        x->n--;
}

/* r = a + (negate_b ? -b : b). r must not alias a or b. */
static void big_add(big *r, const big *a, const big *b, int negate_b) {
    int bneg = b->neg ^ negate_b;
    if (b->n == 0) {
        *r = *a;
        return;
    }
    if (a->n == 0) {
        *r = *b;
        r->neg = bneg;
        return;
    }
    if (a->neg == bneg) {
        const big *x = a->n >= b->n ? a : b, *y = a->n >= b->n ? b : a;
        mp_limb_t carry = mpn_add(r->d, x->d, x->n, y->d, y->n);
        r->n = x->n;
        if (carry)
            r->d[r->n++] = carry;
        r->neg = a->neg;
        return;
    }
    int cmp = a->n != b->n ? (a->n > b->n ? 1 : -1)
                           : mpn_cmp(a->d, b->d, a->n);
    if (cmp == 0) {
        r->n = 0;
        r->neg = 0;
        return;
    }
    const big *x = cmp > 0 ? a : b, *y = cmp > 0 ? b : a;
    mpn_sub(r->d, x->d, x->n, y->d, y->n);
    r->n = x->n;
    while (r->n > 0 && r->d[r->n - 1] == 0)
        r->n--;
    r->neg = cmp > 0 ? a->neg : bneg;
}

/* r = a * b. r must not alias a or b. */
static void big_mul(big *r, const big *a, const big *b) {
    if (a->n == 0 || b->n == 0) {
        r->n = 0;
        r->neg = 0;
        return;
    }
    if (a->n >= b->n)
        mpn_mul(r->d, a->d, a->n, b->d, b->n);
    else
        mpn_mul(r->d, b->d, b->n, a->d, a->n);
    r->n = a->n + b->n;
    while (r->n > 0 && r->d[r->n - 1] == 0)
        r->n--;
    r->neg = a->neg ^ b->neg;
}

static int big_sign(const big *x) {
    return x->n == 0 ? 0 : (x->neg ? -1 : 1);
}

/* Sign of (a.x-c.x)(b.y-c.y) - (a.y-c.y)(b.x-c.x), the six coordinates
 * being multiples of 2^lo. */
/* det = (a.x-c.x)(b.y-c.y) - (a.y-c.y)(b.x-c.x) / 2^(2 lo), the six
 * coordinates being multiples of 2^lo. */
static void orient2d_big_det(const double *a, const double *b,
                             const double *c, int lo, big *det) {
    big p, q, acx, acy, bcx, bcy, l, r;
    big_from_double(&p, a[0], lo);
    big_from_double(&q, c[0], lo);
    big_add(&acx, &p, &q, 1);
    big_from_double(&p, b[0], lo);
    big_add(&bcx, &p, &q, 1);
    big_from_double(&p, a[1], lo);
    big_from_double(&q, c[1], lo);
    big_add(&acy, &p, &q, 1);
    big_from_double(&p, b[1], lo);
    big_add(&bcy, &p, &q, 1);
    big_mul(&l, &acx, &bcy);
    big_mul(&r, &acy, &bcx);
    big_add(det, &l, &r, 1);
}

static int orient2d_big(const double *a, const double *b, const double *c,
                        int lo) {
    big det;
    orient2d_big_det(a, b, c, lo, &det);
    return big_sign(&det);
}

/* x * 2^e rounded to long double (relative error below 2^-63: the two
 * top limbs hold at least 65 significant bits). */
static long double big_to_long(const big *x, int e) {
    if (x->n == 0)
        return 0;
    long double v = (long double)x->d[x->n - 1];
    v = ldexpl(v, GMP_NUMB_BITS);
    if (x->n >= 2)
        v += (long double)x->d[x->n - 2];
    v = ldexpl(v, e + GMP_NUMB_BITS * (int)(x->n - 2));
    return x->neg ? -v : v;
}

/* One row of the incircle determinant: lift(p) * (qx ry - rx qy), where
 * p, q, r are differences from d. */
static void incircle_term_big(big *out, const big *px, const big *py,
                              const big *qx, const big *qy, const big *rx,
                              const big *ry) {
    big s, t, lift, cross;
    big_mul(&s, px, px);
    big_mul(&t, py, py);
    big_add(&lift, &s, &t, 0);
    big_mul(&s, qx, ry);
    big_mul(&t, rx, qy);
    big_add(&cross, &s, &t, 1);
    big_mul(out, &lift, &cross);
}

static int incircle_big(const double *a, const double *b, const double *c,
                        const double *d, int lo) {
    big dx, dy, p, ax, ay, bx, by, cx, cy, t1, t2, t3, sum;
    big_from_double(&dx, d[0], lo);
    big_from_double(&dy, d[1], lo);
    big_from_double(&p, a[0], lo);
    big_add(&ax, &p, &dx, 1);
    big_from_double(&p, a[1], lo);
    big_add(&ay, &p, &dy, 1);
    big_from_double(&p, b[0], lo);
    big_add(&bx, &p, &dx, 1);
    big_from_double(&p, b[1], lo);
    big_add(&by, &p, &dy, 1);
    big_from_double(&p, c[0], lo);
    big_add(&cx, &p, &dx, 1);
    big_from_double(&p, c[1], lo);
    big_add(&cy, &p, &dy, 1);
    incircle_term_big(&t1, &ax, &ay, &bx, &by, &cx, &cy);
    incircle_term_big(&t2, &bx, &by, &cx, &cy, &ax, &ay);
    incircle_term_big(&t3, &cx, &cy, &ax, &ay, &bx, &by);
    big_add(&p, &t1, &t2, 0);
    big_add(&sum, &p, &t3, 0);
    return big_sign(&sum);
}

/* ---- Stage 2: rescaling and expansions ----------------------------------- */

/* Copies n coordinates into out, multiplied by 2^s: exactly where the
 * callers ensure no result leaves the representable range, rounded to
 * the nearest multiple of 2^-1074 otherwise (wide calls, below). */
static void rescale(const double *const *pts, int npts, int s, double *out) {
    for (int i = 0; i < npts; i++) {
        out[2 * i] = s ? ldexp(pts[i][0], s) : pts[i][0];
        out[2 * i + 1] = s ? ldexp(pts[i][1], s) : pts[i][1];
    }
}

/* Power-of-two exponent that brings the largest operand below 1 but not
 * below 1/2 (hi, lo as from operand_range), or 0 when the operands already
 * fit the stage-2 window for a degree-k determinant: k lo >= -1074 (no
 * bits lost) and k (hi + 1) + 16 <= 1023 (no overflow, with room for the
 * coefficients). */
static int choose_scale(int hi, int lo, int k) {
    if (k * lo >= -1074 && k * (hi + 1) + 16 <= 1023)
        return 0;
    return -hi;
}

/* Wide calls. A call whose operands span more bits than stage 2 takes
 * (1e300 beside 1e-300; 2^500 beside points near 1, whose products with
 * the near ones underflow) is seldom near a degeneracy: the filter failed
 * because a product overflowed, or because underflow could have lost more
 * than its bound allows. Scaled by 2^-hi, every |operand| is below 1, and
 * rounded to a multiple of 2^-1074 (ldexp rounds correctly), it moves by at
 * most d = 2^-1075. Every coordinate difference then moves by at most 2d
 * and stays below 2 in magnitude, so the determinant, a sum of monomials
 * in the differences with coefficients of 1, moves by at most: orient2d,
 * 2 monomials of degree 2, 2 * 2 * 2 * 2d = 16 d; incircle, 12 monomials
 * of degree 4, 12 * 4 * 2^3 * 2d = 768 d; both below 2^-1064 (second-order
 * terms included). The filter on the rounded points, with 2^-1000 added to
 * its bound, thus proves the sign of the scaled points' exact determinant,
 * which is the original's times a power of two. Only the calls it cannot
 * decide go on to the integers. */
#define WIDE_SLACK 0x1p-1000

static int orient2d_wide(const double *a, const double *b, const double *c,
                         int hi) {
    const double *pts[3] = {a, b, c};
    double w[6];
    rescale(pts, 3, -hi, w);
    return vor__orient2d_filter_slack(w, w + 2, w + 4, WIDE_SLACK);
}

static int incircle_wide(const double *a, const double *b, const double *c,
                         const double *d, int hi) {
    const double *pts[4] = {a, b, c, d};
    double w[8];
    rescale(pts, 4, -hi, w);
    return vor__incircle_filter_slack(w, w + 2, w + 4, w + 6, WIDE_SLACK);
}

/* orient2d(a, b, c) = (a - c) x (b - c) of rescaled points, exactly, as an
 * expansion in det (at most 16 components); returns its length. */
static int orient2d_expansion(const double *a, const double *b,
                              const double *c, double *det) {
    double ex[2], ey[2], fx[2], fy[2], l[8], r[8];
    int nex = exp_diff(a[0], c[0], ex), ney = exp_diff(a[1], c[1], ey);
    int nfx = exp_diff(b[0], c[0], fx), nfy = exp_diff(b[1], c[1], fy);
    int nl = exp_mul2(nex, ex, nfy, fy, l);
    int nr = exp_mul2(ney, ey, nfx, fx, r);
    exp_negate(nr, r);
    return exp_sum(nl, l, nr, r, det);
}

/* The determinant of a flat triangle whose differences are exact (its
 * sites close beside their magnitude, as along a curve): the difference of
 * two exact products, each a double and its rounding error (two_prod), so
 * four terms, summed in long double with an error of at most 2^-64 of
 * each of the three partial sums. 1 with the value in *out when those do
 * not cancel, so that the error is below 2^-62 of the value (as the
 * expansion's sum below), else 0. Inlined into its callers, whose FMA
 * clones then make two_prod's fma an instruction, not a call. */
static inline __attribute__((always_inline)) int
orient2d_value_quick(const double *a, const double *b, const double *c,
                     long double *out) {
    double acx, acy, bcx, bcy, e0, e1, e2, e3;
    two_diff(a[0], c[0], &acx, &e0);
    two_diff(a[1], c[1], &acy, &e1);
    two_diff(b[0], c[0], &bcx, &e2);
    two_diff(b[1], c[1], &bcy, &e3);
    if (e0 != 0 || e1 != 0 || e2 != 0 || e3 != 0) return 0;
    double l, le, r, re;
    two_prod(acx, bcy, &l, &le);
    two_prod(acy, bcx, &r, &re);
    /* two_prod's error is exact for products in [2^-960, DBL_MAX]; a
     * product below (0 included) may have lost bits, unless a factor
     * is 0 */
    double al = fabs(l), ar = fabs(r);
    if (!(al <= DBL_MAX && ar <= DBL_MAX)) return 0;
    if ((al < 0x1p-960 && acx != 0 && bcy != 0) ||
        (ar < 0x1p-960 && acy != 0 && bcx != 0))
        return 0;
    long double hi = (long double)l - r, lo = (long double)le - re;
    long double sum = hi + lo;
    if (!(fabsl(hi) + fabsl(lo) <= 2.5L * fabsl(sum))) return 0;
    *out = sum;
    return 1;
}

VOR__FMA_CLONES
int vor__orient2d_exact(const double *a, const double *b, const double *c) {
    /* Products with an exactly zero factor (axis-parallel, shared points)
     * are common in grid-like input and need no arithmetic: differences of
     * doubles are zero exactly when the operands are equal, and a nonzero
     * difference has the sign of the exact one. */
    double acx = a[0] - c[0], bcx = b[0] - c[0];
    double acy = a[1] - c[1], bcy = b[1] - c[1];
    int lzero = acx == 0 || bcy == 0, rzero = acy == 0 || bcx == 0;
    if (lzero && rzero)
        return 0;
    if (lzero)
        return ((acy > 0) == (bcx > 0)) ? -1 : 1;
    if (rzero)
        return ((acx > 0) == (bcy > 0)) ? 1 : -1;
    /* Sites exactly on a line through sites close beside their magnitude
     * (collinear input): the four-term value is exactly 0 there, and its
     * sign is right whenever it is taken. */
    long double quick;
    if (orient2d_value_quick(a, b, c, &quick)) return (quick > 0) - (quick < 0);

    double v[6] = {a[0], a[1], b[0], b[1], c[0], c[1]};
    int hi, lo;
    if (!operand_range(v, 6, &hi, &lo))
        return 0;
    if (hi - lo > 537) {
        int f = orient2d_wide(a, b, c, hi);
        return f ? f : orient2d_big(a, b, c, lo);
    }

    const double *pts[3] = {a, b, c};
    double w[6];
    int s = choose_scale(hi, lo, 2);
    rescale(pts, 3, s, w);
    const double *sa = w, *sb = w + 2, *sc = w + 4;
    if (s != 0) {
        int f = vor__orient2d_filter(sa, sb, sc);
        if (f)
            return f;
    }

    /* Small lattice (grids, integer input): with every coordinate a
     * multiple of 2^lo and differences below 2^(lo + 26), both products
     * and their difference are exact in doubles. */
    double dx0 = sa[0] - sc[0], dy0 = sa[1] - sc[1];
    double dx1 = sb[0] - sc[0], dy1 = sb[1] - sc[1];
    double dmax = max2(max2(fabs(dx0), fabs(dy0)), max2(fabs(dx1), fabs(dy1)));
    if (dmax < pow2(lo + s + 26)) {
        double det = dx0 * dy1 - dy0 * dx1;
        return (det > 0) - (det < 0);
    }

    double det[16];
    return exp_sign(orient2d_expansion(sa, sb, sc, det), det);
}

VOR__FMA_CLONES
long double vor__orient2d_value(const double *a, const double *b,
                                const double *c) {
    long double quick;
    if (orient2d_value_quick(a, b, c, &quick)) return quick;
    double v[6] = {a[0], a[1], b[0], b[1], c[0], c[1]};
    int hi, lo;
    if (!operand_range(v, 6, &hi, &lo))
        return 0;
    if (hi - lo > 537) {
        big det;
        orient2d_big_det(a, b, c, lo, &det);
        return big_to_long(&det, 2 * lo);
    }
    const double *pts[3] = {a, b, c};
    double w[6];
    /* scaled (exactly, by a power of two) only where the products could
     * overflow or lose bits to underflow: the scale and its undoing were
     * a tenth of a run on sites near a line, whose flat triangles all come
     * here (vor_circumcenter) */
    int s = choose_scale(hi, lo, 2);
    const double *sa = a, *sb = b, *sc = c;
    if (s) {
        rescale(pts, 3, s, w);
        sa = w;
        sb = w + 2;
        sc = w + 4;
    }
    double det[16];
    int nd = orient2d_expansion(sa, sb, sc, det);
    /* smallest first: the long double sum of a non-overlapping expansion
     * is within an ulp or two of its value */
    long double sum = 0;
    for (int i = 0; i < nd; i++)
        sum += det[i];
    return s ? ldexpl(sum, -2 * s) : sum;
}

/* Adds one incircle row, lift(p) * (qx ry - rx qy), where p, q, r are
 * differences from d, to the expansion in *acc (length *nacc); *acc and
 * *tmp (each with room for INCIRCLE_MAX components) swap roles as the
 * partial products are summed in. */
static void incircle_term_exp(int npx, const double *px, int npy,
                              const double *py, int nqx, const double *qx,
                              int nqy, const double *qy, int nrx,
                              const double *rx, int nry, const double *ry,
                              double **acc, int *nacc, double **tmp) {
    double s[8], t[8], lift[16], cross[16], part[32];
    int ns = exp_mul2(npx, px, npx, px, s);
    int nt = exp_mul2(npy, py, npy, py, t);
    int nlift = exp_sum(ns, s, nt, t, lift);
    ns = exp_mul2(nqx, qx, nry, ry, s);
    nt = exp_mul2(nrx, rx, nqy, qy, t);
    exp_negate(nt, t);
    int ncross = exp_sum(ns, s, nt, t, cross);
    for (int j = 0; j < nlift; j++) {
        int np = exp_scale(ncross, cross, lift[j], part);
        *nacc = exp_sum(*nacc, *acc, np, part, *tmp);
        double *swap = *acc;
        *acc = *tmp;
        *tmp = swap;
    }
}

/* ---- Stage 2a: incircle in double-double ---------------------------------
 *
 * Sites on a circle (or nearly so) make the determinant tiny against its
 * permanent: the filter fails for nearly every call, yet the determinant
 * is rarely exactly zero. A double-double evaluation (each value an
 * unevaluated sum hi + lo, about 106 bits) decides those calls at a few
 * tens of flops, against about a microsecond for the expansions below.
 *
 * Error bound. Let u = 2^-53. The differences are exact (two_diff). A
 * double-double product or sum below returns its exact result on the
 * double-double inputs times (1 + d) with |d| <= 8 u^2 (the products drop
 * lo * lo, at most u^2 of the product, and round the cross terms, at most
 * 2 u^2 more; the sums follow Joldes, Muller and Popescu's accurate
 * addition, 3 u^2): generous, the proven figures are 5 and 3. The
 * determinant is three levels deep (lift and cross, their product, the
 * sum of three terms); to first order the errors add up to at most
 * 4 * 3 * 8 u^2 = 96 u^2 times the permanent, the sum of the absolute
 * values of the terms. The test requires 2^-90 = 2^16 u^2 times the
 * permanent computed in doubles from the hi parts (which is within a few
 * u of the true one): a margin of several hundred for the second-order
 * terms and the roundings of the bound.
 * Range: the caller has brought the points into stage 2's window (every
 * input a multiple of 2^lo with 4 lo >= -1074, every |input| below 2^251),
 * so no exact value underflows or overflows; rounded values that fall into
 * the subnormal range lose at most 2^-1074 each, a few hundred of those
 * at most, which the guard perm >= 2^-900 makes negligible against the
 * bound (2^-990 at least). */
typedef struct dd {
    double hi, lo;
} dd;

static inline dd dd_fast(double a, double b) { /* |a| >= |b| or a == 0 */
    double s = a + b;
    return (dd){s, b - (s - a)};
}

static inline dd dd_sub_exact(double a, double b) {
    dd r;
    two_diff(a, b, &r.hi, &r.lo);
    return r;
}

static inline dd dd_add(dd x, dd y) {
    dd s, t;
    two_sum(x.hi, y.hi, &s.hi, &s.lo);
    two_sum(x.lo, y.lo, &t.hi, &t.lo);
    s = dd_fast(s.hi, s.lo + t.hi);
    return dd_fast(s.hi, s.lo + t.lo);
}

static inline dd dd_mul(dd x, dd y) {
    dd p;
    two_prod(x.hi, y.hi, &p.hi, &p.lo);
    return dd_fast(p.hi, p.lo + (x.hi * y.lo + x.lo * y.hi));
}

static inline dd dd_neg(dd x) { return (dd){-x.hi, -x.lo}; }

/* Sign of incircle(a, b, c, d) for points in stage 2's window, or 0 when
 * the double-double evaluation cannot prove it. */
VOR__FMA_CLONES
static int incircle_dd(const double *a, const double *b, const double *c,
                       const double *d) {
    dd ax = dd_sub_exact(a[0], d[0]), ay = dd_sub_exact(a[1], d[1]);
    dd bx = dd_sub_exact(b[0], d[0]), by = dd_sub_exact(b[1], d[1]);
    dd cx = dd_sub_exact(c[0], d[0]), cy = dd_sub_exact(c[1], d[1]);
    dd bxcy = dd_mul(bx, cy), cxby = dd_mul(cx, by);
    dd cxay = dd_mul(cx, ay), axcy = dd_mul(ax, cy);
    dd axby = dd_mul(ax, by), bxay = dd_mul(bx, ay);
    dd alift = dd_add(dd_mul(ax, ax), dd_mul(ay, ay));
    dd blift = dd_add(dd_mul(bx, bx), dd_mul(by, by));
    dd clift = dd_add(dd_mul(cx, cx), dd_mul(cy, cy));
    dd det = dd_add(dd_add(dd_mul(alift, dd_add(bxcy, dd_neg(cxby))),
                           dd_mul(blift, dd_add(cxay, dd_neg(axcy)))),
                    dd_mul(clift, dd_add(axby, dd_neg(bxay))));
    double perm = alift.hi * (fabs(bxcy.hi) + fabs(cxby.hi)) +
                  blift.hi * (fabs(cxay.hi) + fabs(axcy.hi)) +
                  clift.hi * (fabs(axby.hi) + fabs(bxay.hi));
    if (!(perm >= 0x1p-900))
        return 0;
    double bound = 0x1p-90 * perm;
    return (det.hi > bound) - (det.hi < -bound);
}

/* ---- Stage 2b: incircle in 256-bit integers -----------------------------
 *
 * What the double-double evaluation leaves are mostly four sites exactly
 * on one circle (a rotated grid's squares, whose determinant is 0), which
 * only an exact evaluation settles: the expansions below take about a
 * microsecond for them. When the call's operands span at most 61 bits
 * (hi - lo <= 61: every coordinate an integer multiple of 2^lo below
 * 2^61 of it, as for any points within a few binary orders of magnitude
 * of each other and away from the origin), the determinant in units of
 * 2^(4 lo) is an integer, computed here exactly in a few dozen integer
 * operations: the differences below 2^62 (int64), their products and the
 * lifts and cross terms below 2^125 (int128), each row's product below
 * 2^250 and the sum of the three below 2^252, in four 64-bit words in
 * two's complement. */
#define INT_SPAN 61

/* r += sign * a * b for 0 <= a, b < 2^127 (sign +1 or -1); r holds a
 * 256-bit two's complement value. */
static void acc_mul(uint64_t r[4], u128 a, u128 b, int sign) {
    uint64_t a0 = (uint64_t)a, a1 = (uint64_t)(a >> 64);
    uint64_t b0 = (uint64_t)b, b1 = (uint64_t)(b >> 64);
    u128 p00 = (u128)a0 * b0, p01 = (u128)a0 * b1;
    u128 p10 = (u128)a1 * b0, p11 = (u128)a1 * b1;
    u128 mid = (p00 >> 64) + (uint64_t)p01 + (uint64_t)p10;
    u128 top = p11 + (p01 >> 64) + (p10 >> 64) + (mid >> 64);
    uint64_t t[4] = {(uint64_t)p00, (uint64_t)mid, (uint64_t)top,
                     (uint64_t)(top >> 64)};
    if (sign < 0) { /* two's complement: invert, add 1 */
        unsigned carry = 1;
        for (int i = 0; i < 4; i++) {
            t[i] = ~t[i] + carry;
            carry = carry && t[i] == 0;
        }
    }
    unsigned carry = 0;
    for (int i = 0; i < 4; i++) {
        uint64_t x = r[i] + t[i];
        unsigned c1 = x < r[i];
        r[i] = x + carry;
        carry = c1 | (r[i] < x);
    }
}

/* One row: lift(p) * (qx ry - rx qy), added to r. */
static void incircle_row_int(uint64_t r[4], int64_t px, int64_t py,
                             int64_t qx, int64_t qy, int64_t rx, int64_t ry) {
    u128 lift = (u128)((i128)px * px) + (u128)((i128)py * py);
    i128 cross = (i128)qx * ry - (i128)rx * qy;
    if (cross != 0)
        acc_mul(r, lift, (u128)(cross < 0 ? -cross : cross),
                cross < 0 ? -1 : 1);
}

/* Sign of incircle for operands spanning at most INT_SPAN bits from 2^lo
 * (the caller checks hi - lo <= INT_SPAN). */
static int incircle_int(const double *a, const double *b, const double *c,
                        const double *d, int lo) {
    const double *pts[4] = {a, b, c, d};
    int64_t v[8];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 2; j++) /* exact: an integer below 2^61 */
            v[2 * i + j] = (int64_t)ldexp(pts[i][j], -lo);
    int64_t ax = v[0] - v[6], ay = v[1] - v[7], bx = v[2] - v[6];
    int64_t by = v[3] - v[7], cx = v[4] - v[6], cy = v[5] - v[7];
    uint64_t r[4] = {0, 0, 0, 0};
    incircle_row_int(r, ax, ay, bx, by, cx, cy);
    incircle_row_int(r, bx, by, cx, cy, ax, ay);
    incircle_row_int(r, cx, cy, ax, ay, bx, by);
    if (r[3] >> 63)
        return -1;
    return (r[0] | r[1] | r[2] | r[3]) != 0;
}

/* 1 if the four values are two pairs of equal values, in any order. */
static inline int two_pairs(double a, double b, double c, double d) {
    return (a == b && c == d) || (a == c && b == d) || (a == d && b == c);
}

VOR__FMA_CLONES
int vor__incircle_exact(const double *a, const double *b, const double *c,
                        const double *d) {
    /* Corners of a rectangle with sides parallel to the axes are
     * cocircular, whatever their coordinates: a grid of any spacing in x
     * and in y (0.37 by 0.11, raster cell centres, degrees of latitude
     * and longitude) puts four on every cell, which no filter decides and
     * the expansions below would. When the x and the y both come in two
     * pairs, the points are the four corners or two pairs of duplicates
     * (or all share an x or a y): the determinant is zero in every case. */
    if (two_pairs(a[0], b[0], c[0], d[0]) && two_pairs(a[1], b[1], c[1], d[1]))
        return 0;
    double v[8] = {a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1]};
    int hi, lo;
    if (!operand_range(v, 8, &hi, &lo))
        return 0;
    if (hi - lo > 268) {
        int f = incircle_wide(a, b, c, d, hi);
        return f ? f : incircle_big(a, b, c, d, lo);
    }

    const double *pts[4] = {a, b, c, d};
    double w[8];
    int s = choose_scale(hi, lo, 4);
    rescale(pts, 4, s, w);
    const double *sa = w, *sb = w + 2, *sc = w + 4, *sd = w + 6;
    if (s != 0) {
        int f = vor__incircle_filter(sa, sb, sc, sd);
        if (f)
            return f;
    }

    /* Small lattice: every coordinate a multiple of 2^lo and differences
     * below 2^(lo + 12) make every intermediate value a multiple of
     * 2^(4 lo) (or 2^(2 lo)) below 2^53 times that, so the plain double
     * evaluation is exact (cocircular grid squares end here). */
    {
        double adx = sa[0] - sd[0], ady = sa[1] - sd[1];
        double bdx = sb[0] - sd[0], bdy = sb[1] - sd[1];
        double cdx = sc[0] - sd[0], cdy = sc[1] - sd[1];
        double dmax = max2(max2(max2(fabs(adx), fabs(ady)),
                                max2(fabs(bdx), fabs(bdy))),
                           max2(fabs(cdx), fabs(cdy)));
        if (dmax < pow2(lo + s + 12)) {
            double det = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
                         (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
                         (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
            return (det > 0) - (det < 0);
        }
    }

    int f = incircle_dd(sa, sb, sc, sd);
    if (f)
        return f;
    if (hi - lo <= INT_SPAN)
        return incircle_int(a, b, c, d, lo);

    double ax[2], ay[2], bx[2], by[2], cx[2], cy[2];
    int nax = exp_diff(sa[0], sd[0], ax), nay = exp_diff(sa[1], sd[1], ay);
    int nbx = exp_diff(sb[0], sd[0], bx), nby = exp_diff(sb[1], sd[1], by);
    int ncx = exp_diff(sc[0], sd[0], cx), ncy = exp_diff(sc[1], sd[1], cy);
    double buf0[INCIRCLE_MAX], buf1[INCIRCLE_MAX];
    double *acc = buf0, *tmp = buf1;
    int n = 0;
    incircle_term_exp(nax, ax, nay, ay, nbx, bx, nby, by, ncx, cx, ncy, cy,
                      &acc, &n, &tmp);
    incircle_term_exp(nbx, bx, nby, by, ncx, cx, ncy, cy, nax, ax, nay, ay,
                      &acc, &n, &tmp);
    incircle_term_exp(ncx, cx, ncy, cy, nax, ax, nay, ay, nbx, bx, nby, by,
                      &acc, &n, &tmp);
    return exp_sign(n, acc);
}
