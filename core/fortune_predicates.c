/* fortune_predicates.c -- out-of-line parts of the sweep's predicates (see
 * fortune_predicates.h): the rescaled filters and the exact evaluations.
 *
 * Exact stage. Every finite double is an odd integer times a power of two
 * 2^e with e >= -1074. The inputs of one call are written as integers times
 * 2^E, E the smallest such exponent among them; every expression here is a
 * homogeneous polynomial in differences of the inputs, so its sign does not
 * depend on the common factor, and it is evaluated on those integers. They
 * have at most 2098 bits, so an expression of degree k has at most about
 * 2100 k bits: the breakpoint polynomial (degree 3) and the site-versus-
 * circle test (degree 6) use limb arrays on the stack (at most about
 * 25 KiB), the comparison of two circle events (degree 20) a workspace the
 * caller allocates once. GMP's mpn layer, which does not allocate, does the
 * arithmetic, so nothing here can fail.
 *
 * Cost: rescaled filters some tens of nanoseconds; exact evaluation a few
 * microseconds (more for inputs spanning many binary orders of magnitude).
 */
#include <assert.h>
#include <float.h>
#include <gmp.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fortune_predicates.h"

#if GMP_NUMB_BITS != 64 || GMP_NAIL_BITS != 0
#error "fortune_predicates.c assumes 64-bit GMP limbs without nail bits"
#endif

/* ---- Signed integers on limb arrays -------------------------------------- */

/* n: number of limbs in use, negated for a negative value; 0 is zero;
 * d[|n| - 1] != 0 when n != 0. d has room for cap limbs (the callers size
 * every variable for the largest value it can receive). */
typedef struct big {
    int n;
    int cap;
    mp_limb_t *d;
} big;

/* A big named `name` with `limbs` limbs of automatic storage. */
#define BIG_LOCAL(name, limbs)     \
    mp_limb_t name##_limbs[limbs]; \
    big name = {0, (limbs), name##_limbs}

/* Limbs of an input converted by big_from_doubles: at most 2098 bits. */
#define IN_LIMBS 34

static int big_sign(const big *x) {
    return (x->n > 0) - (x->n < 0);
}

/* x = m * 2^shift, m a nonzero integer of at most 53 bits (sign included). */
static void big_set_shifted(big *x, int64_t m, int shift) {
    uint64_t u = m < 0 ? (uint64_t)(-m) : (uint64_t)m;
    int limb = shift / GMP_NUMB_BITS, bit = shift % GMP_NUMB_BITS;
    assert(u != 0 && limb + 2 <= x->cap);
    memset(x->d, 0, (size_t)(limb + 2) * sizeof x->d[0]);
    x->d[limb] = (mp_limb_t)u << bit;
    x->d[limb + 1] = bit ? (mp_limb_t)(u >> (GMP_NUMB_BITS - bit)) : 0;
    int n = limb + 2;
    while (n > 0 && x->d[n - 1] == 0) n--;
    x->n = m < 0 ? -n : n;
}

/* v = *m * 2^*e with *m odd; v != 0 and finite. From the bits (frexp and
 * ldexp are library calls: 4% of Fortune's time on a grid turned by 45
 * degrees, whose ties go to the exact comparisons). */
static void split_double(double v, int64_t *m, int *e) {
    uint64_t b;
    memcpy(&b, &v, sizeof b);
    int ex = (int)((b >> 52) & 0x7ff);
    uint64_t u = b & 0xfffffffffffffull;
    if (ex != 0) u |= 0x10000000000000ull; /* else subnormal: 2^-1074 units */
    int p = (ex != 0 ? ex : 1) - 1075;
    /* strip the trailing zero bits at once: small integers (pixel
     * coordinates) have about 45 of them, and a loop over them was a
     * quarter of the sweep's time on such input */
    int tz = __builtin_ctzll(u);
    u >>= tz;
    *m = (b >> 63) ? -(int64_t)u : (int64_t)u;
    *e = p + tz;
}

/* Converts k <= 12 doubles to integers sharing the factor 2^E (see
 * above); every out[i] needs IN_LIMBS limbs. Returns E (INT32_MAX when
 * every value is 0). */
static int big_from_doubles(big *out, const double *v, int k) {
    int64_t m[12] = {0};
    int e[12] = {0}, emin = INT32_MAX;
    assert(k <= 12);
    for (int i = 0; i < k; i++) {
        if (v[i] == 0) continue;
        split_double(v[i], &m[i], &e[i]);
        if (e[i] < emin) emin = e[i];
    }
    for (int i = 0; i < k; i++) {
        if (v[i] == 0)
            out[i].n = 0;
        else
            big_set_shifted(&out[i], m[i], e[i] - emin);
    }
    return emin;
}

/* |r| = |x| + |y|; r distinct from x and y. */
static void mag_add(big *r, const big *x, const big *y) {
    int nx = abs(x->n), ny = abs(y->n);
    if (nx < ny) {
        const big *t = x;
        x = y;
        y = t;
        int tn = nx;
        nx = ny;
        ny = tn;
    }
    assert(nx + 1 <= r->cap);
    if (ny == 0) {
        memcpy(r->d, x->d, (size_t)nx * sizeof r->d[0]);
        r->n = nx;
        return;
    }
    mp_limb_t carry = mpn_add(r->d, x->d, nx, y->d, ny);
    r->d[nx] = carry;
    r->n = nx + (carry != 0);
}

static int mag_cmp(const big *x, const big *y) {
    int nx = abs(x->n), ny = abs(y->n);
    if (nx != ny) return nx < ny ? -1 : 1;
    return mpn_cmp(x->d, y->d, nx);
}

/* |r| = |x| - |y| with |x| >= |y|; r distinct from x and y. */
static void mag_sub(big *r, const big *x, const big *y) {
    int nx = abs(x->n), ny = abs(y->n);
    assert(nx <= r->cap);
    if (ny == 0)
        memcpy(r->d, x->d, (size_t)nx * sizeof r->d[0]);
    else
        mpn_sub(r->d, x->d, nx, y->d, ny);
    while (nx > 0 && r->d[nx - 1] == 0) nx--;
    r->n = nx;
}

static void big_copy(big *r, const big *x, int sign) {
    int n = abs(x->n);
    assert(n <= r->cap);
    memcpy(r->d, x->d, (size_t)n * sizeof r->d[0]);
    r->n = sign * n;
}

/* r = x + sy * y, sy = +1 or -1; r distinct from x and y. */
static void big_addsub(big *r, const big *x, const big *y, int sy) {
    int sx = big_sign(x), s2 = big_sign(y) * sy;
    if (s2 == 0) {
        big_copy(r, x, sx);
        return;
    }
    if (sx == 0) {
        big_copy(r, y, s2);
        return;
    }
    if (sx == s2) {
        mag_add(r, x, y);
        r->n *= sx;
        return;
    }
    int c = mag_cmp(x, y);
    if (c == 0) {
        r->n = 0;
    } else if (c > 0) {
        mag_sub(r, x, y);
        r->n *= sx;
    } else {
        mag_sub(r, y, x);
        r->n *= s2;
    }
}

static void big_add(big *r, const big *x, const big *y) {
    big_addsub(r, x, y, 1);
}
static void big_sub(big *r, const big *x, const big *y) {
    big_addsub(r, x, y, -1);
}

/* r = x * y; r distinct from x and y. */
static void big_mul(big *r, const big *x, const big *y) {
    int nx = abs(x->n), ny = abs(y->n);
    if (nx == 0 || ny == 0) {
        r->n = 0;
        return;
    }
    assert(nx + ny <= r->cap);
    if (nx >= ny)
        mpn_mul(r->d, x->d, nx, y->d, ny);
    else
        mpn_mul(r->d, y->d, ny, x->d, nx);
    int n = nx + ny;
    while (n > 0 && r->d[n - 1] == 0) n--;
    r->n = (big_sign(x) * big_sign(y)) * n;
}

/* Signed comparison: -1, 0, +1 for x <, =, > y. */
static int big_cmp(const big *x, const big *y) {
    int sx = big_sign(x), sy = big_sign(y);
    if (sx != sy) return sx < sy ? -1 : 1;
    if (sx == 0) return 0;
    return sx * mag_cmp(x, y);
}

/* out[2(i-1)], out[2(i-1)+1] = point i minus point 0, for the k <= 4
 * points (x,y pairs) of v, as integers sharing one factor 2^E (returned);
 * each out needs IN_LIMBS + 1 limbs. A separate frame, so that the converted inputs
 * do not stay on the stack. */
static int big_diffs(big *out, const double *v, int k) {
    mp_limb_t store[8][IN_LIMBS];
    big in[8];
    assert(k <= 4);
    for (int i = 0; i < 2 * k; i++) in[i] = (big){0, IN_LIMBS, store[i]};
    int e = big_from_doubles(in, v, 2 * k);
    for (int i = 1; i < k; i++) {
        big_sub(&out[2 * (i - 1)], &in[2 * i], &in[0]);
        big_sub(&out[2 * (i - 1) + 1], &in[2 * i + 1], &in[1]);
    }
    return e;
}

/* ---- Small integers ----------------------------------------------------------
 *
 * Lattice input (pixels, grids, integer coordinates) makes exact ties the
 * rule, not the exception: circle events of different triangles with the
 * same top, sites exactly at the top of a circle. When the differences
 * the test needs are integers times one power of two that fit in a few
 * dozen bits, 64- and 128-bit integer arithmetic decides them at a few
 * nanoseconds instead of the microsecond the limb arrays cost. */

/* 128-bit integers: i128 and u128 (internal.h). */

/* The exponent of the lowest set bit of the nonzero normal double d, or
 * INT32_MIN for a subnormal (not handled here). */
static inline int low_bit(double d) {
    uint64_t u;
    memcpy(&u, &d, sizeof u);
    int ex = (int)((u >> 52) & 0x7ff);
    if (ex == 0) return INT32_MIN;
    uint64_t m = (u & 0xfffffffffffffull) | 0x10000000000000ull;
    return ex - 1075 + __builtin_ctzll(m);
}

/* out[i] = (v[i] - v[0]) / 2^E for the k points (x, y pairs) of v,
 * i = 1 .. k - 1, as 2(k - 1) integers, E the lowest bit among the
 * differences; every difference must be exact in doubles and, in units of
 * 2^E, below 2^bits[i - 1] in magnitude. Returns 0 if not. */
static int small_diffs(const double *v, int k, const int *bits,
                       int64_t *out) {
    double d[10];
    int e = INT32_MAX;
    assert(k <= 6);
    for (int i = 1; i < k; i++) {
        for (int j = 0; j < 2; j++) {
            double a = v[2 * i + j], b = v[j], x = a - b;
            /* exact iff the two-sum error is zero */
            double bv = a - x, av = x + bv;
            if ((a - av) + (bv - b) != 0) return 0;
            d[2 * (i - 1) + j] = x;
            if (x != 0) {
                int lb = low_bit(x);
                if (lb == INT32_MIN) return 0;
                if (lb < e) e = lb;
            }
        }
    }
    if (e > 1022 || e < -1022) return 0;
    /* 2^-e from its bits (ldexp is a call, and slow) */
    uint64_t ub = (uint64_t)(1023 - e) << 52;
    double scale;
    memcpy(&scale, &ub, sizeof scale);
    for (int i = 0; i < 2 * (k - 1); i++) {
        double x = d[i] * scale; /* exact: an integer times a power of 2 */
        double lim = (double)((int64_t)1 << bits[i / 2]);
        if (!(fabs(x) < lim)) return 0;
        out[i] = (int64_t)x;
    }
    return 1;
}

/* Integer square root of v < 2^104 if v is a perfect square: 1 with *r,
 * else 0. */
static int exact_sqrt(u128 v, uint64_t *r) {
    uint64_t s = (uint64_t)sqrt((double)v);
    /* the double is within a few units of the root: settle it */
    while (s > 0 && (u128)s * s > v) s--;
    while ((u128)(s + 1) * (s + 1) <= v) s++;
    *r = s;
    return (u128)s * s == v;
}

/* The circle through a, b + a, c + a for integer b, c below 2^11: D,
 * N = (Nx, Ny) and R as in "Circles exactly" below; |D| < 2^23,
 * |N| < 2^35, R < 2^71. */
typedef struct small_circle {
    int64_t d, nx, ny;
    u128 r;
} small_circle;

static void small_circle_of(small_circle *c, int64_t bx, int64_t by,
                            int64_t cx, int64_t cy) {
    int64_t b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    c->d = bx * cy - by * cx;
    c->nx = cy * b2 - by * c2;
    c->ny = bx * c2 - cx * b2;
    c->r = (u128)((i128)c->nx * c->nx) +
           (u128)((i128)c->ny * c->ny);
}

static inline int sign128(i128 v) {
    return (v > 0) - (v < 0);
}

int vor__fortune_site_first_small(const double *s, const double *a,
                                  const double *b, const double *c) {
    const double v[8] = {a[0], a[1], b[0], b[1], c[0], c[1], s[0], s[1]};
    static const int bits[3] = {11, 11, 30};
    int64_t q[6];
    if (!small_diffs(v, 4, bits, q)) return -1;
    small_circle ci;
    small_circle_of(&ci, q[0], q[1], q[2], q[3]);
    if (ci.d <= 0) return -1; /* not an event (not reached) */
    /* w = 2D sy - Ny; the site is lower iff w < sqrt(R) */
    i128 w = (i128)(2 * ci.d) * q[5] - ci.ny;
    if (w < 0) return 1;
    u128 w2 = (u128)(w * w);
    if (w2 != ci.r) return w2 < ci.r;
    /* same y: the site comes first iff it is left of the centre */
    return (i128)(2 * ci.d) * q[4] < (i128)ci.nx;
}

int vor__fortune_circle_cmp_small(const double *a1, const double *b1,
                                  const double *c1, const double *a2,
                                  const double *b2, const double *c2,
                                  int *res) {
    const double v[12] = {a1[0], a1[1], b1[0], b1[1], c1[0], c1[1],
                          a2[0], a2[1], b2[0], b2[1], c2[0], c2[1]};
    /* b1, c1 local; a2 may be far; b2, c2 within 2^11 of a2 */
    static const int bits[5] = {11, 11, 40, 40, 40};
    int64_t q[10];
    if (!small_diffs(v, 6, bits, q)) return 0;
    int64_t u[4] = {q[6] - q[4], q[7] - q[5], q[8] - q[4], q[9] - q[5]};
    for (int i = 0; i < 4; i++)
        if (u[i] <= -2048 || u[i] >= 2048) return 0;
    small_circle e1, e2;
    small_circle_of(&e1, q[0], q[1], q[2], q[3]);
    small_circle_of(&e2, u[0], u[1], u[2], u[3]);
    if (e1.d <= 0 || e2.d <= 0) return 0;
    /* 2 D1 D2 (y2 - y1) for the centres, relative to a1:
     * cy1 - cy2 = (D2 Ny1 - D1 Ny2 - 2 D1 D2 oy) / (2 D1 D2) */
    i128 dprod = (i128)e1.d * e2.d;
    i128 dy = (i128)e2.d * e1.ny - (i128)e1.d * e2.ny -
                  2 * dprod * q[5];
    /* r1^2 - r2^2 = (R1 D2^2 - R2 D1^2) / (4 D1^2 D2^2) */
    u128 r1 = e1.r * (u128)(e2.d * e2.d);
    u128 r2 = e2.r * (u128)(e1.d * e1.d);
    int sy = sign128(dy), sr = (r1 > r2) - (r1 < r2);
    /* top = cy + r: equal signs (or one zero) decide; opposite signs
     * need the square roots, which a lattice often has as integers
     * (Pythagorean radii: circles of different sizes touching one row) */
    int top = sy != 0 ? sy : sr;
    if (sy != 0 && sr != 0 && sy != sr) {
        uint64_t s1, s2;
        if (!exact_sqrt(e1.r, &s1) || !exact_sqrt(e2.r, &s2)) return 0;
        /* 2 D1 D2 (top1 - top2) = D2 (Ny1 + s1) - D1 (Ny2 + s2)
         *                         - 2 D1 D2 oy */
        i128 dt = (i128)e2.d * ((i128)e1.ny + (i128)s1) -
                  (i128)e1.d * ((i128)e2.ny + (i128)s2) - 2 * dprod * q[5];
        top = sign128(dt);
    }
    if (top != 0) {
        *res = top < 0 ? -1 : 1;
        return 1;
    }
    /* the same top: by the centres' x */
    i128 dx = (i128)e2.d * e1.nx - (i128)e1.d * e2.nx -
                  2 * dprod * q[4];
    *res = sign128(dx);
    return 1;
}

/* ---- Wide-range numbers ------------------------------------------------- */

/* A positive number m 2^e kept as a double m in [0.5, 1) and an int e:
 * the integers of a circle can have thousands of bits, past the range of
 * a double, and here they are only multiplied, divided, square-rooted and
 * added to each other when positive, each time with a relative error of
 * at most one rounding. */
typedef struct fe {
    double m;
    long e;
} fe;

static fe fe_norm(double m, long e) {
    int k;
    double f = frexp(m, &k);
    return (fe){f, e + k};
}

/* |x| rounded to a double's precision: the top 64 bits, truncated (a
 * relative error below 2^-63), then rounded to 53 bits. x != 0. */
static fe fe_of_big(const big *x) {
    int n = x->n < 0 ? -x->n : x->n;
    mp_limb_t hi = x->d[n - 1], lo = n > 1 ? x->d[n - 2] : 0;
    int z = __builtin_clzll(hi);
    uint64_t top = z ? (hi << z) | (lo >> (GMP_NUMB_BITS - z)) : hi;
    return fe_norm((double)top, (long)(n - 1) * GMP_NUMB_BITS - z);
}

static fe fe_mul(fe a, fe b) { return fe_norm(a.m * b.m, a.e + b.e); }
static fe fe_div(fe a, fe b) { return fe_norm(a.m / b.m, a.e - b.e); }

static fe fe_sqrt(fe a) {
    if (a.e % 2) return fe_norm(sqrt(a.m * 2), (a.e - 1) / 2);
    return fe_norm(sqrt(a.m), a.e / 2);
}

static fe fe_add(fe a, fe b) { /* both positive */
    if (a.e < b.e) {
        fe t = a;
        a = b;
        b = t;
    }
    long d = a.e - b.e; /* the smaller one past 2^-1100 of the sum: gone */
    return fe_norm(a.m + (d > 1100 ? 0 : ldexp(b.m, (int)-d)), a.e);
}

/* ---- Breakpoint polynomial F --------------------------------------------- */

/* Largest magnitude of four values (nan propagates as "not <= DBL_MAX"). */
static double max4(double a, double b, double c, double d) {
    double m = fabs(a);
    if (!(fabs(b) <= m)) m = fabs(b);
    if (!(fabs(c) <= m)) m = fabs(c);
    if (!(fabs(d) <= m)) m = fabs(d);
    return m;
}

/* 1 if every nonzero value among four is at least 2^-300 in magnitude. */
static int min4_ok(double a, double b, double c, double d) {
    const double lim = 0x1p-300;
    return (a == 0 || fabs(a) >= lim) && (b == 0 || fabs(b) >= lim) &&
           (c == 0 || fabs(c) >= lim) && (d == 0 || fabs(d) >= lim);
}

static int bp_poly_exact(const double *a, const double *b, const double *p) {
    /* differences from p: (a - p, b - p) = -(u, v); F is odd in them, so
     * negate the result */
    const double v[6] = {p[0], p[1], a[0], a[1], b[0], b[1]};
    mp_limb_t store[4][IN_LIMBS + 1];
    big dif[4];
    for (int i = 0; i < 4; i++) dif[i] = (big){0, IN_LIMBS + 1, store[i]};
    BIG_LOCAL(s1, 2 * IN_LIMBS + 2);
    BIG_LOCAL(s2, 2 * IN_LIMBS + 2);
    BIG_LOCAL(f, 2 * IN_LIMBS + 3);
    BIG_LOCAL(t1, 3 * IN_LIMBS + 4);
    BIG_LOCAL(t2, 3 * IN_LIMBS + 4);
    big_diffs(dif, v, 3);
    const big *ux = &dif[0], *uy = &dif[1], *vx = &dif[2], *vy = &dif[3];
    /* t1 = (ux^2 + uy^2) vy */
    big_mul(&s1, ux, ux);
    big_mul(&s2, uy, uy);
    big_add(&f, &s1, &s2);
    big_mul(&t1, &f, vy);
    /* t2 = (vx^2 + vy^2) uy */
    big_mul(&s1, vx, vx);
    big_mul(&s2, vy, vy);
    big_add(&f, &s1, &s2);
    big_mul(&t2, &f, uy);
    return -big_cmp(&t1, &t2);
}

/* Sign of F on a small lattice (differences from p exact and, in units
 * of their lowest bit, below 2^24: F has at most 75 bits), or -2 when the
 * input is not one. */
static int bp_poly_small(const double *a, const double *b, const double *p) {
    const double v[6] = {p[0], p[1], a[0], a[1], b[0], b[1]};
    static const int bits[2] = {24, 24};
    int64_t q[4];
    if (!small_diffs(v, 3, bits, q)) return -2;
    /* with d = a - p = -u and e = b - p = -v, F = -(|d|^2 ey - |e|^2 dy) */
    i128 t1 = (i128)(q[0] * q[0] + q[1] * q[1]) * q[3];
    i128 t2 = (i128)(q[2] * q[2] + q[3] * q[3]) * q[1];
    return sign128(t2 - t1);
}

/* x^2 + y^2 of finite doubles, not both 0, as a wide-range number: the
 * squares exact in range, two roundings. */
static fe fe_sum_squares(double x, double y) {
    fe fx = fe_norm(fabs(x), 0), fy = fe_norm(fabs(y), 0);
    if (x == 0) return fe_mul(fy, fy);
    if (y == 0) return fe_mul(fx, fx);
    return fe_add(fe_mul(fx, fx), fe_mul(fy, fy));
}

/* F's sign from the rounded differences u = p - a, v = p - b when they
 * span more than the rescaled filter's range (a difference below 2^-300
 * of the largest: sites over hundreds of binary orders of magnitude):
 * t1 = |u|^2 vy and t2 = |v|^2 uy in wide-range numbers, which neither
 * overflow nor underflow. The signs of the differences are exact
 * (rounding keeps a sign, and 0 only for equal coordinates), so t1 or t2
 * being 0, or their signs differing, decides exactly; otherwise their
 * magnitudes, each within 5 eps (a difference, a square, a sum, a
 * product, a double's conversion being exact), must differ by more than
 * 2^-46 of them. 0 when they do not (the caller goes to integers). */
static int bp_poly_wide(double ux, double uy, double vx, double vy) {
    int s1 = ux == 0 && uy == 0 ? 0 : (vy > 0) - (vy < 0);
    int s2 = vx == 0 && vy == 0 ? 0 : (uy > 0) - (uy < 0);
    if (s1 != s2 || s1 == 0) return s1 != 0 ? s1 : -s2;
    fe m1 = fe_mul(fe_sum_squares(ux, uy), fe_norm(fabs(vy), 0));
    fe m2 = fe_mul(fe_sum_squares(vx, vy), fe_norm(fabs(uy), 0));
    long d = m1.e - m2.e;
    if (d >= 2) return s1;
    if (d <= -2) return -s1;
    double r = ldexp(m1.m / m2.m, (int)d);
    if (r > 1 + 0x1p-46) return s1;
    if (r < 1 - 0x1p-46) return -s1;
    return 0;
}

int vor__fortune_bp_poly_slow(const double *a, const double *b,
                              const double *p) {
    int sm = bp_poly_small(a, b, p);
    if (sm != -2) return sm;
    const double ux = p[0] - a[0], uy = p[1] - a[1];
    const double vx = p[0] - b[0], vy = p[1] - b[1];
    double m = max4(ux, uy, vx, vy);
    if (!(m > 0 && m <= DBL_MAX)) return bp_poly_exact(a, b, p);
    /* A power-of-two rescale is exact as long as nothing becomes
     * subnormal, which the range test below makes sure of; F is
     * homogeneous, so its sign is unchanged. */
    int e;
    (void)frexp(m, &e);
    double sux = ldexp(ux, -e), suy = ldexp(uy, -e);
    double svx = ldexp(vx, -e), svy = ldexp(vy, -e);
    int c = 0;
    if (min4_ok(sux, suy, svx, svy)) {
        double t1 = (sux * sux + suy * suy) * svy;
        double t2 = (svx * svx + svy * svy) * suy;
        double f = t1 - t2, bound = VOR__BP_BOUND * (fabs(t1) + fabs(t2));
        if (f > bound) return 1;
        if (-f > bound) return -1;
    } else {
        c = bp_poly_wide(ux, uy, vx, vy);
    }
    return c != 0 ? c : bp_poly_exact(a, b, p);
}

/* ---- Top of a circle --------------------------------------------------------
 *
 * With b = B - A, c = C - A (rounded differences), the centre is
 * A + (nx, ny) / (2d) with d = bx cy - by cx, nx = cy |b|^2 - by |c|^2,
 * ny = bx |c|^2 - cx |b|^2, and the top is A.y + g with
 * g = uy + sqrt(ux^2 + uy^2), (ux, uy) = (nx, ny) / (2d). For uy < 0 the sum
 * cancels, so g is computed as ux^2 / (r - uy) instead (same value).
 *
 * Errors, against the exact values for the exact differences:
 *   d:  |d~ - d| <= ed = 4 eps (|bx cy| + |by cx|)   (Shewchuk's orient2d
 *       bound (3 + 16 eps) eps, with room for rounding the bound), or
 *       about 4 eps |d~| when d cancels (recomputed, see the code);
 *   nx: |nx~ - nx| <= enx = 8 eps (|cy |b|^2| + |by |c|^2|) (as F above);
 *   ux: with ed <= |d~| / 2 (else no bound is attempted), |d| >= |d~| / 2 and
 *       |nx~/d~ - nx/d| <= enx/|d~| + (|nx~| + enx) ed / (|d~| |d|), so
 *       eux = enx / (2|d~|) + (|nx~| + enx) ed / d~^2 + 4 eps |ux~|
 *       (the last term for the rounded reciprocal 1 / (2 d~) and product,
 *       with room); likewise euy;
 *   g:  as a function of (ux, uy) g is 1-Lipschitz in ux and 2-Lipschitz in
 *       uy (gradient (ux/r, 1 + uy/r)), so the inputs contribute
 *       eux + 2 euy; evaluating g rounds by at most 4 eps g (uy >= 0: two
 *       squares, a sum, a root, an addition) or 8 eps g (uy < 0: one more
 *       division and subtraction);
 *   top: A.y + g rounds once more.
 * The sum is doubled to cover second-order terms and the rounding of the
 * bound's own arithmetic. Range: with every nonzero difference in
 * [2^-302, 4] no product underflows except possibly ux^2 or uy^2 when that
 * coordinate of the centre offset is tiny; since r >= 2^-303 (half the
 * distance of two distinct sites) such an underflow changes g by less than
 * 2^-770, covered by an absolute 2^-700. Outside that range the
 * differences are first rescaled by a power of two (exact when the range
 * test passes) and the result scaled back, with an absolute 2^-1060 for a
 * possible underflow there. Overflow makes a value inf or nan, which the
 * final test turns into "no bound". */
/* (p - q) - fl(p - q), exactly (the error term of two_diff). */
static inline double diff_err(double p, double q) {
    double x = p - q, bv = p - x, av = x + bv;
    return (p - av) + (bv - q);
}

/* How much of the error eux of the centre's x (relative to a) reaches
 * the top y = uy + sqrt(ux^2 + uy^2), the error of uy being euy: by the
 * mean value theorem, at most eux times the largest |d rho / d ux| = |x| /
 * rho(x, y) <= |x| / |y| on the box around (ux, uy), which is below
 * (|ux| + eux) / (|uy| - euy) where that is positive; and rho is
 * 1-Lipschitz, so never more than eux. The factor's own rounding (three
 * operations) is covered by 1 + 2^-50. A circle through two close sites
 * of one row and a site of the next has its centre nearly below or above
 * them (|ux| / |uy| about 10^-5 for a million sites on 64 rows): the x
 * error, large there because nx cancels, then hardly moves the top, and
 * the interval narrows from 10^-11 of the top to a few ulps. */
static inline double x_share(double ux, double uy, double eux, double euy) {
    double den = fabs(uy) - euy;
    if (!(den > 0)) return eux;
    double k = (fabs(ux) + eux) / den * (1 + 0x1p-50);
    return k < 1 ? eux * k : eux;
}

/* The refinement of a nearly cancelling orient2d for
 * vor__fortune_circle_top (see there): d with *ed its error bound. Out of
 * line and cloned for FMA: only nearly collinear triples come here, and
 * without the instruction each fma() is a library call. */
VOR__FMA_CLONES
static double orient_refined(const double *a, const double *b,
                             const double *c, int e, double bx, double by,
                             double cx, double cy, double l, double r,
                             double *ed, int *exact) {
    double sc = e ? ldexp(1.0, -e) : 1.0; /* ldexp is a call */
    double ebx = diff_err(b[0], a[0]) * sc, eby = diff_err(b[1], a[1]) * sc;
    double ecx = diff_err(c[0], a[0]) * sc, ecy = diff_err(c[1], a[1]) * sc;
    double d1 = fma(bx, cy, -r) + fma(-by, cx, r);
    double t2 = (bx * ecy + ebx * cy) - (by * ecx + eby * cx);
    double d = d1 + t2;
    /* Kahan's d1 is within 2u |D1| of D1 = bx cy - by cx, t2 within
     * 8u^2 (|l| + |r|) of T2, |T3| <= 2u^2 (|l| + |r|), and d = d1 + t2
     * rounds by u |d|: 3u |d1| + u |d| + 10 u^2 (|l| + |r|) with room
     * (|D1| <= |d1| (1 + 3u)); the scaled errors lose at most 2^-1074
     * each to underflow, so 2^-1000 covers T2's share of those. */
    *ed = 0x1.8p-52 * fabs(d1) + 0x1.01p-53 * fabs(d) +
          0x1p-102 * (fabs(l) + fabs(r)) + 0x1p-1000;
    *exact = ebx == 0 && eby == 0 && ecx == 0 && ecy == 0;
    return d;
}

/* The error bound of vor__fortune_circle_top's t = A.y + g after d was
 * refined (orient_refined: ed is about 4u |d| where the float bound was
 * 2^-51 (|l| + |r|), a thousand times more for the thin triangles of
 * sites nearly on a circle). The general bound's slack, harmless for a
 * wide d, would then make the interval some four hundred ulps wide, where
 * the tops of consecutive triples of 10^5 sites on a circle lie
 * thousands of ulps apart: a tenth of their comparisons overlapped and
 * went to the double-double bounds, a fifth of Fortune's time there. So
 * each step is bounded as it is (u = 2^-53; each bound below holds to
 * first order and its second-order terms are below 2^-40 of it, covered
 * by the final factor with the rounding of the bound's own arithmetic):
 *   nx: with exact differences (exact: no rounding in b - a, c - a),
 *       t1 = cy b2 rounds three times (two squares and their sum, the
 *       product) and nx = t1 - t2 once: 3u (|t1| + |t2|) + u |nx|; with
 *       rounded differences (each within u of the exact one) 6u for 3u.
 *       (A rounding error that the scaling by 2^-e took below 2^-1074,
 *       and so counts as none, is below 2^-770 of its difference, at
 *       least 2^-302: far inside the final factor.)
 *   ux: nx / (2d) against Nx / (2D), with |d - D| <= ed < |d| / 2:
 *       enx / (2|d|) + (|nx| + enx) ed / (2 |d| (|d| - ed)), and the
 *       rounded reciprocal and product 2u |ux|; likewise uy.
 *   g:  on the box of (ux, uy) +- (eux, euy) the gradient of g is
 *       (ux / rho, 1 + uy / rho) with rho >= rho_min = rr (1 - 4u) -
 *       eux - euy (rr within 2u of rho(ux, uy)): |ux| / rho <= (|ux| +
 *       eux) / rho_min and uy / rho <= (uy + euy) / rho_min, each at most
 *       1, 1 where rho_min <= 0. g's own evaluation: eg as before.
 *   t:  A.y + g rounds by u |t|, and t -+ err by u (|t| + err) more:
 *       err = (E + 2u |t|) (1 + 2^-40) with E the bound on t before its
 *       rounding (the scaling back by 2^e and its 2^-1060 included). */
static inline double refined_err(double ux, double uy, double rr, double eux,
                                 double euy) {
    double rho = rr * (1 - 0x1p-49) - (eux + euy) * (1 + 0x1p-49);
    double kx = 1, ky = 2;
    if (rho > 0) {
        double x = (fabs(ux) + eux) / rho, y = (uy + euy) / rho;
        kx = x < 1 ? x : 1;
        ky = 1 + (y < 0 ? 0 : y < 1 ? y : 1);
    }
    return kx * eux + ky * euy;
}

static inline __attribute__((always_inline)) int
circle_top(const double *a, const double *b, const double *c, int safe,
           double *lo, double *hi, double *off) {
    double bx = b[0] - a[0], by = b[1] - a[1];
    double cx = c[0] - a[0], cy = c[1] - a[1];
    int e = 0;
    if (!safe && !vor__fortune_in_range4(bx, by, cx, cy)) {
        double m = max4(bx, by, cx, cy);
        if (!(m > 0 && m <= DBL_MAX)) goto undecided;
        (void)frexp(m, &e);
        bx = ldexp(bx, -e);
        by = ldexp(by, -e);
        cx = ldexp(cx, -e);
        cy = ldexp(cy, -e);
        if (!min4_ok(bx, by, cx, cy)) goto undecided;
    }
    double l = bx * cy, r = by * cx, d = l - r;
    double ed = 0x1p-51 * (fabs(l) + fabs(r));
    double ad = fabs(d);
    /* Nearly collinear sites: d cancels and its bound dominates every
     * later one. d is then recomputed with a relative error of about 3u
     * (u = 2^-53): with the differences' rounding errors from two_diff
     * (b - a = bx + ebx exactly, before the scaling by 2^-e, which keeps
     * them exact but for an underflow below 2^-1000), the exact
     * determinant is D1 + T2 + T3 with D1 = bx cy - by cx, T2 = bx ecy +
     * ebx cy - by ecx - eby cx and |T3| <= 2u^2 (|l| + |r|). D1 comes from
     * Kahan's fma algorithm (relative error 2u: Jeannerod, Louvet and
     * Muller, 2013), T2 in plain doubles (|T2| <= 2u (|l| + |r|), so its
     * error is below 8u^2 (|l| + |r|)), and their sum rounds once (ed:
     * see orient_refined). The interval then shrinks by the factor d's
     * relative error does, and its remaining slack is bounded step by
     * step (refined_err): the neighbouring tops of sites on a circle,
     * thousands of ulps apart, separate instead of overlapping. Done
     * where d cancels more than 5 binary digits (the triples of 10^5
     * sites on a circle that had cancelled only 5 to 10 kept intervals
     * thousands of ulps wide; below 2^-3 uniform sites ran 1% slower). */
    int refined = 0, exact = 0;
    /* The heights (off) are wanted where two tops lie closer than their
     * intervals can tell, and only then: refined always, their error is
     * a sixth of the general bound's (a grid jittered by 10^-12, whose
     * ties the heights decided 92% of, against 84%) */
    if (off || ad < 0x1p-5 * (fabs(l) + fabs(r))) {
        d = orient_refined(a, b, c, e, bx, by, cx, cy, l, r, &ed, &exact);
        ad = fabs(d);
        refined = 1;
    }
    /* d is orient2d(a, b, c) with an error below ed (Shewchuk's bound is
     * (3 + 16 eps) eps (|l| + |r|)): its sign is proven when |d| > 2 ed */
    if (!(ad > 2 * ed)) goto undecided;
    if (d < 0) return -1;
    double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    double t1 = cy * b2, t2 = by * c2, t3 = bx * c2, t4 = cx * b2;
    double nx = t1 - t2, ny = t3 - t4;
    double inv = 0.5 / d, iad = fabs(inv);
    double ux = nx * inv, uy = ny * inv;
    double rr = sqrt(ux * ux + uy * uy);
    double g, eg;
    if (uy >= 0) {
        g = uy + rr;
        eg = 0x1p-51 * g;
    } else {
        g = (ux * ux) / (rr - uy);
        eg = 0x1p-50 * g;
    }
    double err;
    if (refined) { /* see refined_err */
        double k = exact ? 0x1.8p-52 : 0x1.8p-51;
        double enx = k * (fabs(t1) + fabs(t2)) + 0x1p-53 * fabs(nx);
        double eny = k * (fabs(t3) + fabs(t4)) + 0x1p-53 * fabs(ny);
        double w = ed / (ad - ed);
        double eux = (enx + (fabs(nx) + enx) * w) * iad + 0x1p-52 * fabs(ux);
        double euy = (eny + (fabs(ny) + eny) * w) * iad + 0x1p-52 * fabs(uy);
        err = refined_err(ux, uy, rr, eux, euy) + eg + 0x1p-700;
    } else {
        double enx = VOR__BP_BOUND * (fabs(t1) + fabs(t2));
        double eny = VOR__BP_BOUND * (fabs(t3) + fabs(t4));
        double q = ed * iad;
        double eux =
            (enx + 4 * (fabs(nx) + enx) * q) * iad + 0x1p-51 * fabs(ux);
        double euy =
            (eny + 4 * (fabs(ny) + eny) * q) * iad + 0x1p-51 * fabs(uy);
        err = eux + 2 * euy + eg + 0x1p-700;
        if (err > 0x1p-40 * g) /* wide: the division is worth it */
            err = x_share(ux, uy, eux, euy) + 2 * euy + eg + 0x1p-700;
    }
    if (e != 0) {
        g = ldexp(g, e);
        err = ldexp(err, e) + 0x1p-1060;
    }
    if (off) {
        /* the error of g, as the bounds below take it */
        off[0] = g;
        off[1] = err * (1 + 0x1p-40); /* refined */
        if (!(off[1] <= DBL_MAX) || !(fabs(g) <= DBL_MAX)) off[1] = -1;
    }
    double t = a[1] + g;
    if (refined)
        err = (err + 0x1p-52 * fabs(t)) * (1 + 0x1p-40);
    else
        err = 2 * err + 0x1p-51 * (fabs(a[1]) + g + fabs(t));
    if (!(err <= DBL_MAX) || !(fabs(t) <= DBL_MAX)) goto unknown;
    *lo = t - err;
    *hi = t + err;
    return 1;
undecided: {
    int o = vor_orient2d(a, b, c);
    if (o <= 0) return o;
}
unknown:
    *lo = -INFINITY;
    *hi = INFINITY;
    if (off) off[1] = -1;
    return 1;
}

int vor__fortune_circle_top(const double *a, const double *b, const double *c,
                            int safe, double *lo, double *hi) {
    return circle_top(a, b, c, safe, lo, hi, NULL);
}

int vor__fortune_circle_top_off(const double *a, const double *b,
                                const double *c, int safe, double *lo,
                                double *hi, double *off) {
    return circle_top(a, b, c, safe, lo, hi, off);
}

/* ---- Double-double evaluation of the top ------------------------------------
 *
 * A second filter for events whose float intervals overlap (nearly equal
 * tops, as for sites nearly on one circle). The same formulas as above in
 * double-double arithmetic (a value is hi + lo, |lo| <= ulp(hi) / 2):
 * differences are exact (two_diff), and every operation below has a
 * relative error of at most 6 u^2 (u = 2^-53): addition 3 u^2 (the
 * accurate double-word addition), multiplication 4 u^2 (with fma), division
 * and square root about 4 u^2 (one correction step each), following Joldes,
 * Muller and Popescu, "Tight and rigorous error bounds for basic building
 * blocks of double-word arithmetic" (2017). The error analysis of the float
 * version holds with eps replaced by E2 = 2^-100 = 64 u^2 (a margin of ten
 * over the per-operation bound covers the roundings of the bound itself).
 * Requires the safe range; not attempted otherwise. */

typedef struct dd {
    double hi, lo;
} dd;

#define E2 0x1p-100

static inline dd two_sum(double a, double b) {
    double s = a + b, bb = s - a;
    return (dd){s, (a - (s - bb)) + (b - bb)};
}

static inline dd fast_two_sum(double a, double b) { /* |a| >= |b| or a = 0 */
    double s = a + b;
    return (dd){s, b - (s - a)};
}

static inline dd two_prod(double a, double b) {
    double p = a * b;
    return (dd){p, fma(a, b, -p)};
}

static inline dd dd_add(dd x, dd y) {
    dd s = two_sum(x.hi, y.hi), t = two_sum(x.lo, y.lo);
    dd v = fast_two_sum(s.hi, s.lo + t.hi);
    return fast_two_sum(v.hi, t.lo + v.lo);
}

static inline dd dd_neg(dd x) {
    return (dd){-x.hi, -x.lo};
}

static inline dd dd_mul(dd x, dd y) {
    dd c = two_prod(x.hi, y.hi);
    double t = fma(x.hi, y.lo, x.lo * y.lo);
    return fast_two_sum(c.hi, c.lo + fma(x.lo, y.hi, t));
}

static inline dd dd_div(dd x, dd y) {
    double q1 = x.hi / y.hi;
    dd r = dd_add(x, dd_neg(dd_mul(y, (dd){q1, 0})));
    return fast_two_sum(q1, r.hi / y.hi);
}

static inline dd dd_sqrt(dd x) {
    double r0 = sqrt(x.hi);
    if (r0 == 0) return (dd){0, 0};
    dd e = dd_add(x, dd_neg(two_prod(r0, r0)));
    return fast_two_sum(r0, e.hi / (2 * r0));
}

/* The index of the point of triangle t whose other two share coordinate
 * k (k = 1: a level pair; k = 0: a vertical pair), or -1 if no two do (a
 * triangle has at most one such pair). */
static inline int odd_one(const double *const t[3], int k) {
    for (int i = 0; i < 3; i++)
        if (t[(i + 1) % 3][k] == t[(i + 2) % 3][k]) return i;
    return -1;
}

/* The top of the circle through two level sites p, q (p.y == q.y) and a
 * third, v, above them and nearly halfway between them in x: a grid of
 * decimal spacing with a hole makes such triangles of two sites of a row
 * and the one between them on the next, rounded out of symmetry by an ulp.
 * Their tops lie above v by about d^2 / 2r (d = v.x - (p.x + q.x) / 2):
 * 10^-33 of the top, which the bounds of vor__fortune_circle_top_dd, a
 * few 2^-100 of the top, cannot tell apart, though two such tops differ
 * in their leading bits of d. With a = |q.x - p.x| / 2 and h = v.y - p.y,
 * the centre is at cy = p.y + (h^2 + d^2 - a^2) / 2h, and v.y - cy =
 * (h^2 - d^2 + a^2) / 2h; the top is v.y + eps with
 *
 *   eps = r - (v.y - cy) = d^2 / (r + v.y - cy),
 *
 * a quotient of positive terms: when d^2 <= (h^2 + a^2) / 4, v.y - cy >=
 * 3 (h^2 + a^2) / 8h and r >= v.y - cy, and every rounding (d from the
 * accurate double-double sum of two exact differences, relative 3u^2; then
 * about twenty operations in doubles) costs eps less than 20u relative,
 * far within the 2^-46 allowed. 1 with v.y + eps as top_hi + top_lo (a
 * two-sum: exact) and that bound in *err, else 0. */
static int level_top(const double *const t[3], double *top_hi,
                     double *top_lo, double *err) {
    int k = odd_one(t, 1);
    if (k < 0) return 0;
    const double *v = t[k], *p = t[(k + 1) % 3], *q = t[(k + 2) % 3];
    if (!(v[1] > p[1])) return 0;
    dd d2x = dd_add(two_sum(v[0], -p[0]), two_sum(v[0], -q[0]));
    double d = 0.5 * d2x.hi, a = 0.5 * fabs(q[0] - p[0]), h = v[1] - p[1];
    double dd2 = d * d, a2 = a * a, h2 = h * h;
    /* normal magnitudes only: no underflow, no overflow */
    if (!(h2 >= 0x1p-900 && a2 >= 0x1p-900 && h2 + a2 <= 0x1p900)) return 0;
    if (d != 0 && !(dd2 >= 0x1p-900)) return 0;
    if (!(dd2 <= 0.25 * (h2 + a2))) return 0;
    double c0 = (h2 + dd2 - a2) / (2 * h), c1 = (h2 - dd2 + a2) / (2 * h);
    double eps = dd2 / (sqrt(a2 + c0 * c0) + c1);
    /* a flat triangle (h tiny beside a) can overflow the centre's height,
     * and then eps would be 0 or tiny without being so */
    if (!(c0 * c0 <= DBL_MAX && c1 <= DBL_MAX)) return 0;
    if (d != 0 && !(eps >= 0x1p-900)) return 0;
    dd t2 = two_sum(v[1], eps);
    *top_hi = t2.hi;
    *top_lo = t2.lo;
    *err = 0x1p-46 * eps;
    return 1;
}

/* The centre of the circle through a, b, c less a, (ux, uy), in
 * double-double with error bounds eux, euy; 0 when the orientation does
 * not dominate its rounding (nearly collinear). */
static inline __attribute__((always_inline)) int
centre_dd(const double *a, const double *b, const double *c, dd *pux, dd *puy,
          double *peux, double *peuy) {
    dd bx = two_sum(b[0], -a[0]), by = two_sum(b[1], -a[1]);
    dd cx = two_sum(c[0], -a[0]), cy = two_sum(c[1], -a[1]);
    dd l = dd_mul(bx, cy), r = dd_mul(by, cx);
    dd d = dd_add(l, dd_neg(r));
    double ed = 4 * E2 * (fabs(l.hi) + fabs(r.hi));
    double ad = fabs(d.hi);
    if (!(ad > 2 * ed)) return 0;
    dd b2 = dd_add(dd_mul(bx, bx), dd_mul(by, by));
    dd c2 = dd_add(dd_mul(cx, cx), dd_mul(cy, cy));
    dd t1 = dd_mul(cy, b2), t2 = dd_mul(by, c2);
    dd t3 = dd_mul(bx, c2), t4 = dd_mul(cx, b2);
    dd nx = dd_add(t1, dd_neg(t2)), ny = dd_add(t3, dd_neg(t4));
    double enx = 8 * E2 * (fabs(t1.hi) + fabs(t2.hi));
    double eny = 8 * E2 * (fabs(t3.hi) + fabs(t4.hi));
    dd d2 = {2 * d.hi, 2 * d.lo};
    dd ux = dd_div(nx, d2), uy = dd_div(ny, d2);
    double q = ed / ad;
    double eux =
        0.5 * enx / ad + (fabs(nx.hi) + enx) / ad * q + 2 * E2 * fabs(ux.hi);
    double euy =
        0.5 * eny / ad + (fabs(ny.hi) + eny) / ad * q + 2 * E2 * fabs(uy.hi);
    *pux = ux;
    *puy = uy;
    *peux = eux;
    *peuy = euy;
    return 1;
}

VOR__FMA_CLONES
int vor__fortune_circle_top_dd(const double *a, const double *b,
                               const double *c, double *top_hi, double *top_lo,
                               double *err) {
    dd ux, uy;
    double eux, euy;
    if (!centre_dd(a, b, c, &ux, &uy, &eux, &euy)) return 0;
    dd ux2 = dd_mul(ux, ux);
    dd rr = dd_sqrt(dd_add(ux2, dd_mul(uy, uy)));
    dd g;
    double eg;
    if (uy.hi >= 0) {
        g = dd_add(uy, rr);
        eg = 4 * E2 * g.hi;
    } else {
        g = dd_div(ux2, dd_add(rr, dd_neg(uy)));
        eg = 8 * E2 * g.hi;
    }
    dd t = dd_add((dd){a[1], 0}, g);
    double e = 2 * (x_share(ux.hi, uy.hi, eux, euy) + 2 * euy + eg + 0x1p-700) +
               4 * E2 * (fabs(a[1]) + fabs(g.hi) + fabs(t.hi));
    if (!(e <= DBL_MAX) || !(fabs(t.hi) <= DBL_MAX) || !(fabs(t.lo) <= DBL_MAX))
        return 0;
    *top_hi = t.hi;
    *top_lo = t.lo;
    *err = e;
    /* nearly isosceles on a level base: the top above the apex by a
     * margin known to 2^-46 of itself, tighter when the margin is small */
    const double *tt[3] = {a, b, c};
    double lh, ll, le;
    if (level_top(tt, &lh, &ll, &le) && le < e) {
        *top_hi = lh;
        *top_lo = ll;
        *err = le;
    }
    return 1;
}


/* The centre's x of the circle through a, b, c in double-double, as
 * vor__fortune_circle_top_dd gives its top (the same requirements). */
VOR__FMA_CLONES
static int centre_x_dd(const double *a, const double *b, const double *c,
                       double *x_hi, double *x_lo, double *err) {
    dd ux, uy;
    double eux, euy;
    if (!centre_dd(a, b, c, &ux, &uy, &eux, &euy)) return 0;
    dd x = dd_add((dd){a[0], 0}, ux);
    double e = 2 * (eux + 0x1p-700) +
               4 * E2 * (fabs(a[0]) + fabs(ux.hi) + fabs(x.hi));
    if (!(e <= DBL_MAX) || !(fabs(x.hi) <= DBL_MAX) || !(fabs(x.lo) <= DBL_MAX))
        return 0;
    *x_hi = x.hi;
    *x_lo = x.lo;
    *err = e;
    return 1;
}

/* ---- Exact ties in floating point ---------------------------------------- */

/* 1 if a - b is exactly representable; *d receives it. */
static inline int exact_diff(double a, double b, double *d) {
    dd s = two_sum(a, -b);
    *d = s.hi;
    return s.lo == 0;
}

/* 1 if a * b is exactly representable; *p receives it. The residual
 * a b - p is a multiple of the product of the inputs' last bits, at least
 * 2^-104 |a b|, so when |p| >= 2^-960 a nonzero residual is not below
 * 2^-1074 and fma() cannot round it to zero. Smaller products are not
 * certified (a zero factor is). Always inlined: called out of line from
 * the FMA clone of its caller, it would call the library's fma(). */
static inline __attribute__((always_inline)) int exact_mul(double a, double b,
                                                           double *p) {
    *p = a * b;
    if (*p == 0) return a == 0 || b == 0;
    return fabs(*p) >= 0x1p-960 && fma(a, b, -*p) == 0;
}

/* 1 if a + b is exactly representable; *s receives it. */
static inline int exact_add(double a, double b, double *s) {
    dd t = two_sum(a, b);
    *s = t.hi;
    return t.lo == 0;
}

/* The circle from its exact numerators nx, ny and determinant d (the
 * centre's offset from a is (nx, ny) / 2d): 1 with out = {x, y, r^2} if
 * they are exact in doubles. */
static inline __attribute__((always_inline)) int
circle_from(const double *a, double nx, double ny, double d, double *out) {
    double ux, uy, x, y, r2, s, t, p, q;
    if (!exact_mul(2, d, &t) || t == 0) return 0;
    ux = nx / t;
    uy = ny / t;
    if (!exact_mul(ux, t, &s) || s != nx || !exact_mul(uy, t, &s) || s != ny)
        return 0;
    if (!exact_add(a[0], ux, &x) || !exact_add(a[1], uy, &y)) return 0;
    if (!exact_mul(ux, ux, &p) || !exact_mul(uy, uy, &q) ||
        !exact_add(p, q, &r2))
        return 0;
    out[0] = x;
    out[1] = y;
    out[2] = r2;
    return 1;
}

VOR__FMA_CLONES
int vor__fortune_circle_exact_double(const double *a, const double *b,
                                     const double *c, double *out) {
    double bx, by, cx, cy, p, q, d, b2, c2, nx, ny;
    if (!exact_diff(b[0], a[0], &bx) || !exact_diff(b[1], a[1], &by) ||
        !exact_diff(c[0], a[0], &cx) || !exact_diff(c[1], a[1], &cy))
        return 0;
    if (!exact_mul(bx, cy, &p) || !exact_mul(by, cx, &q) ||
        !exact_diff(p, q, &d))
        return 0;
    if (!exact_mul(bx, bx, &p) || !exact_mul(by, by, &q) ||
        !exact_add(p, q, &b2))
        return 0;
    if (!exact_mul(cx, cx, &p) || !exact_mul(cy, cy, &q) ||
        !exact_add(p, q, &c2))
        return 0;
    if (!exact_mul(cy, b2, &p) || !exact_mul(by, c2, &q) ||
        !exact_diff(p, q, &nx))
        return 0;
    if (!exact_mul(bx, c2, &p) || !exact_mul(cx, b2, &q) ||
        !exact_diff(p, q, &ny))
        return 0;
    return circle_from(a, nx, ny, d, out);
}

VOR__FMA_CLONES
int vor__fortune_circle_exact_small(const double *a, const double *b,
                                    const double *c, double *out) {
    double bx = b[0] - a[0], by = b[1] - a[1];
    double cx = c[0] - a[0], cy = c[1] - a[1];
    double d = bx * cy - by * cx;
    double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    return circle_from(a, cy * b2 - by * c2, bx * c2 - cx * b2, d, out);
}

VOR__FMA_CLONES
int vor__fortune_exact_top(const double *circle, double *hi, double *lo) {
    double r2 = circle[2], r, p;
    if (!(r2 > 0)) return 0;
    r = sqrt(r2); /* correctly rounded: exact if r2 is a double's square */
    if (!exact_mul(r, r, &p) || p != r2) return 0;
    dd t = two_sum(circle[1], r);
    *hi = t.hi;
    *lo = t.lo;
    return 1;
}

/* Order of the exact sums p and q, each as a two-sum (hi = fl(sum)): fl is
 * monotone, so unequal high parts decide. */
static inline int sum_cmp(dd p, dd q) {
    if (p.hi != q.hi) return p.hi < q.hi ? -1 : 1;
    return (p.lo > q.lo) - (p.lo < q.lo);
}

/* Index of the first of three points in sweep order (least y, then least
 * x). */
static inline int first_of(const double *const t[3]) {
    int m = 0;
    for (int k = 1; k < 3; k++)
        if (t[k][1] < t[m][1] || (t[k][1] == t[m][1] && t[k][0] < t[m][0]))
            m = k;
    return m;
}

/* 1 if t2 is t1 moved by a vector (equal differences from their first
 * points in sweep order, in the same cyclic order); *o1, *o2 the first
 * points. */
static int moved(const double *const t1[3], const double *const t2[3],
                 const double **o1, const double **o2) {
    int m1 = first_of(t1), m2 = first_of(t2);
    *o1 = t1[m1];
    *o2 = t2[m2];
    for (int k = 1; k < 3; k++) {
        const double *p = t1[(m1 + k) % 3], *q = t2[(m2 + k) % 3];
        for (int j = 0; j < 2; j++) {
            /* equal differences as reals: equal two-sums (an overflow
             * leaves a NaN low part, which equals nothing) */
            dd u = two_sum(p[j], -(*o1)[j]), v = two_sum(q[j], -(*o2)[j]);
            if (u.hi != v.hi || u.lo != v.lo) return 0;
        }
    }
    return 1;
}

/* Twice a coordinate of the centre of a triangle with two sites p, q of
 * equal coordinate k (their bisector holds the centre): the sum of their
 * other coordinates, p + q, as a two-sum; 0 if there are no such two
 * (k = 1: level sites give the centre's x; k = 0: a vertical pair its y). */
static inline int pair_centre(const double *const t[3], int k, dd *sum) {
    int i = odd_one(t, k);
    if (i < 0) return 0;
    *sum = two_sum(t[(i + 1) % 3][1 - k], t[(i + 2) % 3][1 - k]);
    return fabs(sum->hi) <= DBL_MAX;
}

/* The order of two circles' centres in x by their double-double bounds,
 * in the safe range: 1 with *c when they separate them, else 0 (the same
 * centre, or too close to tell). */
static int centres_x(const double *const t1[3], const double *const t2[3],
                     int safe, int *c) {
    double h1, l1, e1, h2, l2, e2;
    if (!safe || !centre_x_dd(t1[0], t1[1], t1[2], &h1, &l1, &e1) ||
        !centre_x_dd(t2[0], t2[1], t2[2], &h2, &l2, &e2))
        return 0;
    *c = vor__fortune_dd_cmp(h1, l1, e1, h2, l2, e2);
    return *c != 0;
}

/* The order of the centres' x of t1 and of an image t2 of it whose
 * centre is t1's mirrored in x and moved by vx (c2.x = -(c1.x + vx)):
 * the sign of c1.x - c2.x = 2 c1.x + vx. On a small lattice (see
 * vor__fortune_circle_exact_small; vx a difference of two of its x) that
 * is exact in doubles: with the offsets from a = t1[0], 2 c1.x + vx =
 * W + nx / d, W = 2 a.x + vx, so its sign is that of d times that of
 * W d + nx. In units of the lattice's step h: |a.x|, |vx| < 2^17, so W
 * takes 18 bits; d takes 35 and nx 53 (as there), W d at most 53, and
 * the sum rounds once, which keeps its sign and its zero. Elsewhere the
 * two centres' double-double bounds (centres_x). 1 with *c, else 0. */
static int image_centres_x(const double *const t1[3],
                           const double *const t2[3], double vx, int safe,
                           int small, int *c) {
    if (!small) return centres_x(t1, t2, safe, c);
    const double *a = t1[0], *b = t1[1], *p = t1[2];
    double bx = b[0] - a[0], by = b[1] - a[1];
    double cx = p[0] - a[0], cy = p[1] - a[1];
    double d = bx * cy - by * cx;
    if (d == 0) return 0;
    double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    double nx = cy * b2 - by * c2;
    double s = (2 * a[0] + vx) * d + nx;
    *c = ((s > 0) - (s < 0)) * (d > 0 ? 1 : -1);
    return 1;
}

int vor__fortune_translate_cmp(const double *a1, const double *b1,
                               const double *c1, const double *a2,
                               const double *b2, const double *c2, int safe,
                               int small, int *res) {
    const double *t1[3] = {a1, b1, c1}, *t2[3] = {a2, b2, c2}, *o1, *o2;
    if (moved(t1, t2, &o1, &o2)) {
        /* moved by o2 - o1: the top by its y, the centre by its x */
        int c = (o1[1] > o2[1]) - (o1[1] < o2[1]);
        *res = c ? c : (o1[0] > o2[0]) - (o1[0] < o2[0]);
        return 1;
    }
    /* a mirror image (x negated, the order reversed to stay counter-
     * clockwise), moved: the top moves by the vector's y; at equal
     * tops, the centres of level triangles are known exactly */
    double m[3][2] = {{-c2[0], c2[1]}, {-b2[0], b2[1]}, {-a2[0], a2[1]}};
    const double *t3[3] = {m[0], m[1], m[2]};
    int c;
    if (moved(t1, t3, &o1, &o2)) {
        c = (o1[1] > o2[1]) - (o1[1] < o2[1]);
        dd x1, x2;
        if (c == 0 && pair_centre(t1, 1, &x1) && pair_centre(t2, 1, &x2))
            c = sum_cmp(x1, x2);
        else if (c == 0 &&
                 !image_centres_x(t1, t2, o2[0] - o1[0], safe, small, &c))
            return 0;
        *res = c;
        return 1;
    }
    /* turned upside down (y negated, the order reversed) or half a turn
     * (both negated), then moved by v: t2's top is the bottom of t1's
     * circle moved, so top1 - top2 = 2 cy1 + v.y, which a vertical pair
     * p, q of t1 gives exactly (2 cy1 = p.y + q.y: the centre is on their
     * bisector). At equal tops the upturned centre is moved by v.x, the
     * turned one mirrored. */
    dd y2;
    if (!pair_centre(t1, 0, &y2)) return 0;
    for (int half = 0; half < 2; half++) {
        for (int k = 0; k < 3; k++) {
            const double *q = half ? t2[k] : t2[2 - k];
            m[k][0] = half ? -q[0] : q[0];
            m[k][1] = -q[1];
        }
        if (!moved(t1, t3, &o1, &o2)) continue;
        dd s = dd_add(y2, two_sum(o2[1], -o1[1])); /* sign exact */
        if (!(fabs(s.hi) <= DBL_MAX)) return 0;
        c = (s.hi > 0) - (s.hi < 0);
        if (c == 0 && !half)
            c = (o1[0] > o2[0]) - (o1[0] < o2[0]);
        else if (c == 0 &&
                 !image_centres_x(t1, t2, o2[0] - o1[0], safe, small, &c))
            return 0;
        *res = c;
        return 1;
    }
    return 0;
}

/* *d = p - q, 1 if exactly (diff_err: an overflow leaves a NaN, not 0). */
static inline int exact_sub(double p, double q, double *d) {
    *d = p - q;
    return diff_err(p, q) == 0;
}

int vor__fortune_shape_of(const double *a, const double *b, const double *c,
                          double v[VOR__FORTUNE_SHAPE]) {
    const double *t[3] = {a, b, c};
    int m = first_of(t), mm = 0; /* mm: least y, then greatest x */
    for (int k = 1; k < 3; k++)
        if (t[k][1] < t[mm][1] || (t[k][1] == t[mm][1] && t[k][0] > t[mm][0]))
            mm = k;
    const double *o = t[m], *p = t[(m + 1) % 3], *q = t[(m + 2) % 3];
    v[0] = o[0];
    v[1] = o[1];
    if (!(exact_sub(p[0], o[0], &v[2]) & exact_sub(p[1], o[1], &v[3]) &
          exact_sub(q[0], o[0], &v[4]) & exact_sub(q[1], o[1], &v[5])))
        return 0;
    /* mirrored, x is negated and the site after t[k] is t[k - 1] */
    o = t[mm];
    p = t[(mm + 2) % 3];
    q = t[(mm + 1) % 3];
    if (!(exact_sub(o[0], p[0], &v[6]) & exact_sub(p[1], o[1], &v[7]) &
          exact_sub(o[0], q[0], &v[8]) & exact_sub(q[1], o[1], &v[9])))
        v[6] = NAN;
    dd x;
    if (pair_centre(t, 1, &x)) {
        v[10] = x.hi;
        v[11] = x.lo;
    } else {
        v[10] = NAN;
    }
    return 1;
}

/* A triangle with two level sites p, q and a third, v: the rows of the
 * pair (y1) and of v (y0); the pair's width |q.x - p.x| and p.x + q.x
 * (twice the centre's x), as two-sums; twice v's offset from their
 * bisector, (v.x - p.x) + (v.x - q.x), as a two-sum when the two
 * differences are exact in doubles (else 0 is returned). */
typedef struct level {
    double y1, y0;
    dd w, m2, d2;
} level;

static int level_of(const double *const t[3], level *L) {
    int k = odd_one(t, 1);
    if (k < 0) return 0;
    const double *v = t[k], *p = t[(k + 1) % 3], *q = t[(k + 2) % 3];
    dd e1 = two_sum(v[0], -p[0]), e2 = two_sum(v[0], -q[0]);
    if (e1.lo != 0 || e2.lo != 0) return 0; /* NaN on overflow too */
    L->y1 = p[1];
    L->y0 = v[1];
    L->w = p[0] < q[0] ? two_sum(q[0], -p[0]) : two_sum(p[0], -q[0]);
    if (!pair_centre(t, 1, &L->m2)) return 0;
    L->d2 = two_sum(e1.hi, e2.hi);
    if (L->d2.hi < 0) L->d2 = (dd){-L->d2.hi, -L->d2.lo}; /* |2d| */
    return fabs(L->w.hi) <= DBL_MAX && fabs(L->d2.hi) <= DBL_MAX;
}

int vor__fortune_level_cmp(const double *a1, const double *b1,
                           const double *c1, const double *a2,
                           const double *b2, const double *c2, int *res) {
    const double *t1[3] = {a1, b1, c1}, *t2[3] = {a2, b2, c2};
    level A, B;
    if (!level_of(t1, &A) || !level_of(t2, &B)) return 0;
    if (A.y1 != B.y1 || A.y0 != B.y0 || sum_cmp(A.w, B.w) != 0) return 0;
    /* With the pair at m -+ a on row y1 and v at (m + d, y0), h = y1 - y0,
     * the centre lies s = (h^2 - a^2 + d^2) / 2h below the pair's row and
     * the top at y1 - s + sqrt(a^2 + s^2), whose derivative in d^2 is
     * (s / r - 1) / 2h: of the sign of -h, since |s| < r. So at the same
     * rows and width the tops are ordered by |d|, the other way round
     * when v is the lower; at equal |d| they are equal, and the centres'
     * x are m. */
    int c = sum_cmp(A.d2, B.d2);
    if (c != 0)
        *res = A.y0 < A.y1 ? -c : c;
    else
        *res = sum_cmp(A.m2, B.m2);
    return 1;
}

/* Three corners of a box with sides parallel to the axes (among the
 * three points, two distinct x and two distinct y): 1 with the box in
 * v = {x0, x1, y0, y1}, x0 < x1, y0 < y1; else 0. */
int vor__fortune_box_of(const double *a, const double *b, const double *c,
                        double v[4]) {
    for (int k = 0; k < 2; k++) {
        double p = a[k], q;
        if (b[k] == p) {
            if (c[k] == p) return 0;
            q = c[k];
        } else if (c[k] == p || c[k] == b[k]) {
            q = b[k];
        } else {
            return 0;
        }
        v[2 * k] = p < q ? p : q;
        v[2 * k + 1] = p < q ? q : p;
    }
    return 1;
}

int vor__fortune_box_cmp(const double *a1, const double *b1, const double *c1,
                         const double *a2, const double *b2, const double *c2,
                         int *res) {
    double p[4], q[4];
    return vor__fortune_box_of(a1, b1, c1, p) &&
           vor__fortune_box_of(a2, b2, c2, q) &&
           vor__fortune_boxes_cmp(p, q, res);
}

int vor__fortune_boxes_cmp(const double p[4], const double q[4], int *res) {
    /* the circle of a box: centre ((x0 + x1) / 2, (y0 + y1) / 2), radius
     * half the diagonal; its top rises with the width at a fixed height */
    dd w1 = two_sum(p[1], -p[0]), w2 = two_sum(q[1], -q[0]);
    dd x1 = two_sum(p[0], p[1]), x2 = two_sum(q[0], q[1]);
    if (!(fabs(w1.hi) <= DBL_MAX && fabs(w2.hi) <= DBL_MAX &&
          fabs(x1.hi) <= DBL_MAX && fabs(x2.hi) <= DBL_MAX))
        return 0; /* overflow: no exact sums */
    int c;
    if (p[2] == q[2] && p[3] == q[3]) { /* the same rows */
        c = sum_cmp(w1, w2);
    } else {
        dd h1 = two_sum(p[3], -p[2]), h2 = two_sum(q[3], -q[2]);
        dd y1 = two_sum(p[2], p[3]), y2 = two_sum(q[2], q[3]);
        if (!(fabs(h1.hi) <= DBL_MAX && fabs(h2.hi) <= DBL_MAX &&
              fabs(y1.hi) <= DBL_MAX && fabs(y2.hi) <= DBL_MAX))
            return 0;
        if (sum_cmp(w1, w2) != 0 || sum_cmp(h1, h2) != 0)
            return 0; /* unequal radii at unequal heights: square roots */
        c = sum_cmp(y1, y2); /* equal radii: the centres' heights */
    }
    *res = c ? c : sum_cmp(x1, x2);
    return 1;
}

/* ---- Circles exactly --------------------------------------------------------
 *
 * For a circle through A, B, C with integer differences b = B - A,
 * c = C - A: D = bx cy - by cx (> 0 when orient2d(A, B, C) > 0),
 * N = (cy |b|^2 - by |c|^2, bx |c|^2 - cx |b|^2), R = Nx^2 + Ny^2. The
 * centre is A + N / (2D), the radius sqrt(R) / (2D), the top's y
 * A.y + (Ny + sqrt(R)) / (2D). With k-bit differences, D has 2k + 1 bits,
 * N 3k + 3, R 6k + 7. */
typedef struct circle {
    big d, nx, ny, r;
} circle;

/* Fills c's D and N from the differences; t1, t2, b2, c2 are scratch. */
static void circle_centre(circle *c, const big *bx, const big *by,
                          const big *cx, const big *cy, big *t1, big *t2,
                          big *b2, big *c2) {
    big_mul(t1, bx, cy);
    big_mul(t2, by, cx);
    big_sub(&c->d, t1, t2);
    big_mul(t1, bx, bx);
    big_mul(t2, by, by);
    big_add(b2, t1, t2);
    big_mul(t1, cx, cx);
    big_mul(t2, cy, cy);
    big_add(c2, t1, t2);
    big_mul(t1, cy, b2);
    big_mul(t2, by, c2);
    big_sub(&c->nx, t1, t2);
    big_mul(t1, bx, c2);
    big_mul(t2, cx, b2);
    big_sub(&c->ny, t1, t2);
}

/* c's R from its N; t1, t2 are scratch. */
static void circle_r(circle *c, big *t1, big *t2) {
    big_mul(t1, &c->nx, &c->nx);
    big_mul(t2, &c->ny, &c->ny);
    big_add(&c->r, t1, t2);
}

/* Fills c from the differences; t1, t2, b2, c2 are scratch. */
static void circle_of(circle *c, const big *bx, const big *by, const big *cx,
                      const big *cy, big *t1, big *t2, big *b2, big *c2) {
    circle_centre(c, bx, by, cx, cy, t1, t2, b2, c2);
    circle_r(c, t1, t2);
}

/* Site against circle event. With s = S - A: the site is lower when
 * w = 2D sy - Ny < sqrt(R): true if w < 0, else decided by w^2 against R;
 * equal means the same y, and then the site comes first when
 * 2D sx < Nx. Degree 6: 220 limbs hold every value (2098-bit inputs). */
int vor__fortune_site_first_exact(const double *s, const double *a,
                                  const double *b, const double *c) {
    enum { L = 220 };
    const double v[8] = {a[0], a[1], b[0], b[1], c[0], c[1], s[0], s[1]};
    mp_limb_t store[6][IN_LIMBS + 1];
    big dif[6];
    for (int i = 0; i < 6; i++) dif[i] = (big){0, IN_LIMBS + 1, store[i]};
    big_diffs(dif, v, 4);
    const big *sx = &dif[4], *sy = &dif[5];
    BIG_LOCAL(t1, L);
    BIG_LOCAL(t2, L);
    BIG_LOCAL(b2, L);
    BIG_LOCAL(c2, L);
    BIG_LOCAL(cd, L);
    BIG_LOCAL(cnx, L);
    BIG_LOCAL(cny, L);
    BIG_LOCAL(cr, L);
    BIG_LOCAL(twod, L);
    BIG_LOCAL(w, L);
    circle ci = {cd, cnx, cny, cr};
    circle_of(&ci, &dif[0], &dif[1], &dif[2], &dif[3], &t1, &t2, &b2, &c2);
    assert(big_sign(&ci.d) > 0);
    if (big_sign(&ci.d) <= 0) return 1; /* collinear: no event (not reached) */
    big_add(&twod, &ci.d, &ci.d);
    /* w = 2D sy - Ny */
    big_mul(&t1, &twod, sy);
    big_sub(&w, &t1, &ci.ny);
    if (big_sign(&w) < 0) return 1;
    big_mul(&t1, &w, &w);
    int cmp = big_cmp(&t1, &ci.r);
    if (cmp != 0) return cmp < 0;
    /* same y: compare x with the centre's */
    big_mul(&t1, &twod, sx);
    return big_cmp(&t1, &ci.nx) < 0;
}

/* The tight interval when A.y < 0 and the offset g 2^E nearly cancel it
 * (a top well below |A.y|: sites of both signs over hundreds of binary
 * orders, whose circles through a site far below 0 top out near 0),
 * where an error relative to |A.y| would be wide against the top itself.
 * In units of 2^E, A.y is an integer and top 2D = W + sqrt(R) with
 * W = 2D A.y + Ny, R = Nx^2 + Ny^2, exact; for W < 0 the sum is
 * (R - W^2) / (sqrt(R) + |W|), R - W^2 exact too, so only positive
 * numbers meet again and the top's relative error stays under 2^-49
 * (five conversions and six operations); the bound takes 2^-46. Degree
 * 6: 254 limbs hold every value. ci is the circle's D and N in those
 * units (circle_centre); its R is filled here. 1 with the interval, 0 if
 * the top is past the doubles. */
static int top_cancelled(const double *a, int e, circle *ci, double *lo,
                         double *hi) {
    enum { L = 7 * IN_LIMBS + 16 };
    int64_t m;
    int ex;
    split_double(a[1], &m, &ex);
    BIG_LOCAL(ay, IN_LIMBS + 2);
    big_set_shifted(&ay, m, ex - e);
    BIG_LOCAL(twod, L);
    BIG_LOCAL(t1, L);
    BIG_LOCAL(t2, L);
    BIG_LOCAL(w, L);
    const big *r = &ci->r;
    circle_r(ci, &t1, &t2);
    big_add(&twod, &ci->d, &ci->d);
    big_mul(&t1, &twod, &ay);
    big_add(&w, &t1, &ci->ny);
    fe root = fe_sqrt(fe_of_big(r)), num;
    int sign = 1;
    if (big_sign(&w) >= 0) {
        num = big_sign(&w) ? fe_add(fe_of_big(&w), root) : root;
    } else {
        big_mul(&t1, &w, &w);
        big_sub(&t2, r, &t1);
        sign = big_sign(&t2);
        if (sign == 0) { /* the top is exactly 0 */
            *lo = *hi = 0;
            return 1;
        }
        num = fe_div(fe_of_big(&t2), fe_add(root, fe_of_big(&w)));
    }
    fe top = fe_div(num, fe_of_big(&twod));
    long te = top.e + e;
    if (te > 1100) return 0;
    double t = sign * (te < -1200 ? 0 : ldexp(top.m, (int)te));
    double err = 0x1p-46 * fabs(t) + 0x1p-1060;
    *lo = t - err;
    *hi = t + err;
    return isfinite(*lo) && isfinite(*hi);
}

/* An interval around the y of the top of the circle through a, b, c
 * (orient2d > 0) from the circle's exact integers: 1 with [*lo, *hi]
 * at most about 2^-44 of the top wide, 0 if the top lies
 * beyond the doubles. For the sweep's events whose float interval is
 * wide or unbounded (vor__fortune_circle_top): sites over hundreds of
 * orders of magnitude, where neither the float filter nor the
 * double-double bounds (whose range they leave) can say more, and two
 * such events would otherwise meet the exact comparison every time.
 *
 * With D, N (circle_of) in units of 2^E (big_diffs), the top is A.y + g
 * 2^E, g = (Ny + sqrt(R)) / (2D); for Ny < 0 the sum cancels and g =
 * Nx^2 / (2D (sqrt(R) + |Ny|)) instead (the same value). Either way
 * only positive numbers meet: D, Nx, Ny exact, each rounded once to a
 * double's precision (2^-52), then at most seven operations of one
 * rounding each, so g's relative error is under 16 eps = 2^-49; the
 * bound below takes 2^-46 of it, then 4 eps of the top for its rounding
 * and that of t -+ err (with the bound's own), and an absolute 2^-1060
 * for an underflow of g 2^E. Where A.y < 0 takes away over half of the
 * offset, the top is computed from exact integers instead
 * (top_cancelled), so that the interval is always within about 2^-44 of
 * the top itself. Where g 2^E passes 2^1023 the top is summed in units of
 * 2^E (below); one past the doubles gets [DBL_MAX, inf] and its key,
 * m 2^e. */
/* What circle_offset fills and works in: the circle's D and N (its R
 * left to the caller) and four scratch integers, all of degree 3 at
 * most. */
enum { CW_LIMBS = 4 * IN_LIMBS + 8 };
typedef struct circle_work {
    mp_limb_t limbs[7][CW_LIMBS];
    big t[4];
    circle ci;
} circle_work;

static void circle_work_init(circle_work *cw, big r) {
    big *b[7] = {&cw->t[0], &cw->t[1], &cw->t[2], &cw->t[3],
                 &cw->ci.d, &cw->ci.nx, &cw->ci.ny};
    for (int i = 0; i < 7; i++) *b[i] = (big){0, CW_LIMBS, cw->limbs[i]};
    cw->ci.r = r;
}

/* The circle through a, b, c (orient2d > 0) in units of 2^E: fills cw's
 * D and N (circle_centre) and returns
 * g = (Ny + sqrt(R)) / (2D), the top's offset from A.y in those units,
 * evaluated with positive numbers only (relative error under 2^-49, see
 * vor__fortune_circle_top_tight); *e receives E. 0 if the sites are
 * collinear or not distinct (not reached from the sweep). */
static int circle_offset(const double *a, const double *b, const double *c,
                         circle_work *cw, fe *g, int *e) {
    const double v[6] = {a[0], a[1], b[0], b[1], c[0], c[1]};
    mp_limb_t store[4][IN_LIMBS + 1];
    big dif[4];
    for (int i = 0; i < 4; i++) dif[i] = (big){0, IN_LIMBS + 1, store[i]};
    *e = big_diffs(dif, v, 3);
    circle *ci = &cw->ci;
    circle_centre(ci, &dif[0], &dif[1], &dif[2], &dif[3], &cw->t[0],
                  &cw->t[1], &cw->t[2], &cw->t[3]);
    const big *d = &ci->d, *nx = &ci->nx, *ny = &ci->ny;
    if (big_sign(d) <= 0) return 0; /* not reached: orient2d > 0 */
    fe twod = fe_of_big(d);
    twod.e++;
    if (big_sign(ny) == 0 && big_sign(nx) == 0) {
        return 0; /* not reached: the sites are distinct */
    } else if (big_sign(nx) == 0) {
        /* the centre straight above or below A: g = (Ny + |Ny|) / 2D */
        if (big_sign(ny) < 0) *g = (fe){0, 0};
        else *g = fe_div(fe_of_big(ny), twod), g->e++;
    } else {
        fe fx = fe_of_big(nx), fx2 = fe_mul(fx, fx);
        if (big_sign(ny) == 0) {
            *g = fe_div(fe_sqrt(fx2), twod);
        } else {
            fe fy = fe_of_big(ny);
            fe r = fe_sqrt(fe_add(fx2, fe_mul(fy, fy)));
            if (big_sign(ny) > 0)
                *g = fe_div(fe_add(fy, r), twod);
            else
                *g = fe_div(fx2, fe_mul(twod, fe_add(r, fy)));
        }
    }
    return 1;
}

int vor__fortune_circle_offset(const double *a, const double *b,
                               const double *c, double *base, double *off,
                               double *err) {
    /* the highest site first: the same circle, the same orientation */
    const double *p[3] = {a, b, c};
    int h = a[1] >= b[1] ? (a[1] >= c[1] ? 0 : 2) : (b[1] >= c[1] ? 1 : 2);
    circle_work cw;
    circle_work_init(&cw, (big){0, 0, NULL});
    fe g;
    int e;
    if (!circle_offset(p[h], p[(h + 1) % 3], p[(h + 2) % 3], &cw, &g, &e))
        return 0;
    long ge = g.e + e;
    if (g.m != 0 && ge > 1000) return 0;
    *base = p[h][1];
    *off = g.m == 0 || ge < -1200 ? 0 : ldexp(g.m, (int)ge);
    /* g's 2^-49 and the rounding of the scaling (an underflow: 2^-1074) */
    *err = 0x1p-46 * *off + 0x1p-1060;
    return 1;
}

int vor__fortune_circle_top_tight(const double *a, const double *b,
                                  const double *c, double *lo, double *hi,
                                  double key[2]) {
    enum { LR = 7 * IN_LIMBS + 16 }; /* R: degree 6 */
    BIG_LOCAL(cr, LR); /* filled only where needed, by top_cancelled */
    circle_work cw;
    circle_work_init(&cw, cr);
    fe g;
    int e;
    if (!circle_offset(a, b, c, &cw, &g, &e)) return 0;
    long ge = g.e + e;
    if (g.m != 0 && ge >= 1024) {
        /* G = g 2^E >= 2^1023, and |A.y| < 2^1024: in units of U = 2^E
         * the top is s = g + A.y / U, |A.y| / U < 1, within 2^-47 (g's
         * 2^-49, s's rounding 2^-52). Past DBL_MAX by more than that (s
         * then at least 1/4, as G >= 4 |A.y| from E = 1026 on), the key
         * m 2^e is within 2^-45 of it; else an interval, if a double. */
        fe ay = fe_norm(fabs(a[1]), 0);
        long apart = ge - ay.e;
        double share =
            a[1] == 0 || apart > 1100 ? 0 : ldexp(ay.m, (int)-apart);
        double sum = a[1] < 0 ? g.m - share : g.m + share, eu = 0x1p-47;
        if (sum < 0.5 * g.m) /* A.y < 0 takes away over half of G */
            return top_cancelled(a, e, &cw.ci, lo, hi);
        if (sum - eu > ldexp(DBL_MAX, (int)-(ge > 2100 ? 2100 : ge))) {
            fe top = fe_norm(sum, ge);
            *lo = DBL_MAX;
            *hi = INFINITY;
            key[0] = top.m;
            key[1] = (double)top.e;
            return 2;
        }
        double t = ldexp(sum, (int)ge), err = ldexp(eu, (int)ge);
        err += 0x1p-51 * fabs(t) + 0x1p-1060;
        *lo = t - err;
        *hi = t + err;
        return isfinite(*lo) && isfinite(*hi);
    }
    double gd = g.m == 0 ? 0 : ge > 1100 ? INFINITY
                             : ge < -1200 ? 0 : ldexp(g.m, (int)ge);
    double t = a[1] + gd;
    if (a[1] < 0 && gd > 0 && !(fabs(t) >= -0.5 * a[1]))
        return top_cancelled(a, e, &cw.ci, lo, hi);
    double err = 0x1p-46 * gd + 0x1p-51 * fabs(t) + 0x1p-1060;
    *lo = t - err;
    *hi = t + err;
    return isfinite(*lo) && isfinite(*hi);
}

/* Workspace of the circle comparison: degree 20 in the inputs, so up to
 * 42004 bits (657 limbs) for 2098-bit inputs. */
#define WS_LIMBS 664
#define WS_BIGS 18

struct vor__fortune_ws {
    mp_limb_t limbs[WS_BIGS][WS_LIMBS];
};

vor__fortune_ws *vor__fortune_ws_new(void) {
    return malloc(sizeof(vor__fortune_ws));
}

void vor__fortune_ws_free(vor__fortune_ws *ws) {
    free(ws);
}

/* Circle event against circle event. Both tops relative to A1, times
 * 2 D1 D2 > 0:  T1 -> D2 Ny1 + sqrt(D2^2 R1),
 *               T2 -> 2 D1 D2 oy + D1 Ny2 + sqrt(D1^2 R2)   (o = A2 - A1),
 * so sign(T1 - T2) = sign(P + sqrt(Q1) - sqrt(Q2)) with
 * P = D2 Ny1 - 2 D1 D2 oy - D1 Ny2, Q1 = D2^2 R1, Q2 = D1^2 R2 (both > 0).
 * If P and sqrt(Q1) - sqrt(Q2) (sign of Q1 - Q2) agree in sign or one is
 * zero, that is the answer; otherwise compare their magnitudes:
 * P^2 - (sqrt(Q1) - sqrt(Q2))^2 = e + 2 sqrt(Q1 Q2) with e = P^2 - Q1 - Q2,
 * positive if e >= 0, else of the sign of 4 Q1 Q2 - e^2. Equal tops: the
 * x of the centres, D2 Nx1 against 2 D1 D2 ox + D1 Nx2. */
int vor__fortune_circle_cmp_exact(const double *a1, const double *b1,
                                  const double *c1, const double *a2,
                                  const double *b2, const double *c2,
                                  vor__fortune_ws *ws) {
    const double v[12] = {a1[0], a1[1], b1[0], b1[1], c1[0], c1[1],
                          a2[0], a2[1], b2[0], b2[1], c2[0], c2[1]};
    mp_limb_t store[12][IN_LIMBS];
    mp_limb_t dstore[10][IN_LIMBS + 1];
    big in[12], dif[10];
    for (int i = 0; i < 12; i++) in[i] = (big){0, IN_LIMBS, store[i]};
    for (int i = 0; i < 10; i++) dif[i] = (big){0, IN_LIMBS + 1, dstore[i]};
    big_from_doubles(in, v, 12);
    big_sub(&dif[0], &in[2], &in[0]); /* b1 - a1 */
    big_sub(&dif[1], &in[3], &in[1]);
    big_sub(&dif[2], &in[4], &in[0]); /* c1 - a1 */
    big_sub(&dif[3], &in[5], &in[1]);
    big_sub(&dif[4], &in[6], &in[0]); /* o = a2 - a1 */
    big_sub(&dif[5], &in[7], &in[1]);
    big_sub(&dif[6], &in[8], &in[6]); /* b2 - a2 */
    big_sub(&dif[7], &in[9], &in[7]);
    big_sub(&dif[8], &in[10], &in[6]); /* c2 - a2 */
    big_sub(&dif[9], &in[11], &in[7]);

    big t[WS_BIGS];
    for (int i = 0; i < WS_BIGS; i++) t[i] = (big){0, WS_LIMBS, ws->limbs[i]};
    circle e1 = {t[0], t[1], t[2], t[3]}, e2 = {t[4], t[5], t[6], t[7]};
    big *t1 = &t[8], *t2 = &t[9], *t3 = &t[10], *t4 = &t[11];
    big *p = &t[12], *q1 = &t[13], *q2 = &t[14], *e = &t[15], *twod = &t[16];
    circle_of(&e1, &dif[0], &dif[1], &dif[2], &dif[3], t1, t2, t3, t4);
    circle_of(&e2, &dif[6], &dif[7], &dif[8], &dif[9], t1, t2, t3, t4);
    assert(big_sign(&e1.d) > 0 && big_sign(&e2.d) > 0);

    /* twod = 2 D1 D2 */
    big_mul(t1, &e1.d, &e2.d);
    big_add(twod, t1, t1);
    /* P = D2 Ny1 - twod oy - D1 Ny2 */
    big_mul(t1, &e2.d, &e1.ny);
    big_mul(t2, twod, &dif[5]);
    big_sub(t3, t1, t2);
    big_mul(t1, &e1.d, &e2.ny);
    big_sub(p, t3, t1);
    /* Q1 = D2^2 R1, Q2 = D1^2 R2 */
    big_mul(t1, &e2.d, &e2.d);
    big_mul(q1, t1, &e1.r);
    big_mul(t1, &e1.d, &e1.d);
    big_mul(q2, t1, &e2.r);

    int sp = big_sign(p), sq = big_cmp(q1, q2), res;
    if (sp == 0 || sq == 0 || sp == sq) {
        res = sp != 0 ? sp : sq;
    } else {
        big_mul(t1, p, p);
        big_sub(t2, t1, q1);
        big_sub(e, t2, q2);
        int m;
        if (big_sign(e) >= 0) {
            m = 1;
        } else {
            big_mul(t1, q1, q2);
            big_add(t2, t1, t1);
            big_add(t3, t2, t2); /* 4 Q1 Q2 */
            big_mul(t4, e, e);
            m = big_cmp(t3, t4);
        }
        res = m > 0 ? sp : m < 0 ? sq : 0;
    }
    if (res != 0) return res;
    /* same y: x of the centres */
    big_mul(t1, &e2.d, &e1.nx);
    big_mul(t2, twod, &dif[4]);
    big_sub(t3, t1, t2);
    big_mul(t1, &e1.d, &e2.nx);
    return big_cmp(t3, t1);
}
