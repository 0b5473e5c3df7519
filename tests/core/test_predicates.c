/* test_predicates.c -- vor_orient2d and vor_incircle against an independent
 * exact oracle.
 *
 * The oracle converts every coordinate to a GMP rational (mpq_set_d is
 * exact) and evaluates the textbook determinants with rationals; it shares
 * no code with core/predicates.c. Every case is checked through all entry
 * points: the public functions, the inlined fast versions of predicates.h,
 * and the exact routines called directly (so that the expansion and integer
 * stages are exercised on ordinary input too, not only on what the filter
 * passes on). Random cases use a fixed seed, printed; set VOR_TEST_SEED to
 * replay another.
 */
#include <float.h>
#include <gmp.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../core/predicates.h"
#include "../support/testsets.h"

/* ---- oracle -------------------------------------------------------------- */

static int oracle_orient(const double *a, const double *b, const double *c) {
    mpq_t ax, ay, bx, by, cx, cy, l, r;
    mpq_inits(ax, ay, bx, by, cx, cy, l, r, NULL);
    mpq_set_d(ax, a[0]);
    mpq_set_d(ay, a[1]);
    mpq_set_d(bx, b[0]);
    mpq_set_d(by, b[1]);
    mpq_set_d(cx, c[0]);
    mpq_set_d(cy, c[1]);
    mpq_sub(ax, ax, cx); /* a - c */
    mpq_sub(ay, ay, cy);
    mpq_sub(bx, bx, cx); /* b - c */
    mpq_sub(by, by, cy);
    mpq_mul(l, ax, by);
    mpq_mul(r, ay, bx);
    mpq_sub(l, l, r);
    int s = mpq_sgn(l);
    mpq_clears(ax, ay, bx, by, cx, cy, l, r, NULL);
    return s;
}

/* | ax-dx  ay-dy  (ax-dx)^2+(ay-dy)^2 |
 * | bx-dx  by-dy  ...                 |   (cofactor expansion along the
 * | cx-dx  cy-dy  ...                 |    first column) */
static int oracle_incircle(const double *a, const double *b, const double *c,
                           const double *d) {
    mpq_t v[8], m[3][3], t, u, det;
    const double *p[4] = {a, b, c, d};
    for (int i = 0; i < 8; i++) {
        mpq_init(v[i]);
        mpq_set_d(v[i], p[i / 2][i % 2]);
    }
    mpq_inits(t, u, det, NULL);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            mpq_init(m[i][j]);
        mpq_sub(m[i][0], v[2 * i], v[6]);
        mpq_sub(m[i][1], v[2 * i + 1], v[7]);
        mpq_mul(t, m[i][0], m[i][0]);
        mpq_mul(u, m[i][1], m[i][1]);
        mpq_add(m[i][2], t, u);
    }
    mpq_set_ui(det, 0, 1);
    for (int i = 0; i < 3; i++) {
        int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        /* m[i][0] * (m[i1][1] m[i2][2] - m[i2][1] m[i1][2]) */
        mpq_mul(t, m[i1][1], m[i2][2]);
        mpq_mul(u, m[i2][1], m[i1][2]);
        mpq_sub(t, t, u);
        mpq_mul(t, t, m[i][0]);
        mpq_add(det, det, t);
    }
    int s = mpq_sgn(det);
    for (int i = 0; i < 8; i++)
        mpq_clear(v[i]);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            mpq_clear(m[i][j]);
    mpq_clears(t, u, det, NULL);
    return s;
}

/* ---- checks through every entry point ------------------------------------ */

static long n_checked;

static void fail_orient(const double *a, const double *b, const double *c,
                        const char *fn, int got, int want) {
    print_error("%s(%a,%a | %a,%a | %a,%a) = %d, oracle %d\n", fn, a[0], a[1],
                b[0], b[1], c[0], c[1], got, want);
    fail();
}

/* Checks orient2d on (a, b, c) and its rotations and reflection; returns
 * the sign. */
static int check_orient(const double *a, const double *b, const double *c) {
    int want = oracle_orient(a, b, c);
    int got = vor_orient2d(a, b, c);
    if (got != want)
        fail_orient(a, b, c, "vor_orient2d", got, want);
    got = vor__orient2d_fast(a, b, c);
    if (got != want)
        fail_orient(a, b, c, "vor__orient2d_fast", got, want);
    got = vor__orient2d_exact(a, b, c);
    if (got != want)
        fail_orient(a, b, c, "vor__orient2d_exact", got, want);
    if (vor_orient2d(b, c, a) != want || vor_orient2d(c, a, b) != want)
        fail_orient(a, b, c, "vor_orient2d rotated", -2, want);
    if (vor_orient2d(b, a, c) != -want)
        fail_orient(a, b, c, "vor_orient2d swapped", -2, want);
    n_checked++;
    return want;
}

static void fail_incircle(const double *a, const double *b, const double *c,
                          const double *d, const char *fn, int got, int want) {
    print_error("%s(%a,%a | %a,%a | %a,%a | %a,%a) = %d, oracle %d\n", fn,
                a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1], got, want);
    fail();
}

/* Checks incircle on (a, b, c, d) and an even and an odd permutation of
 * a, b, c; returns the sign. */
static int check_incircle(const double *a, const double *b, const double *c,
                          const double *d) {
    int want = oracle_incircle(a, b, c, d);
    int got = vor_incircle(a, b, c, d);
    if (got != want)
        fail_incircle(a, b, c, d, "vor_incircle", got, want);
    got = vor__incircle_fast(a, b, c, d);
    if (got != want)
        fail_incircle(a, b, c, d, "vor__incircle_fast", got, want);
    got = vor__incircle_exact(a, b, c, d);
    if (got != want)
        fail_incircle(a, b, c, d, "vor__incircle_exact", got, want);
    if (vor_incircle(b, c, a, d) != want)
        fail_incircle(a, b, c, d, "vor_incircle rotated", -2, want);
    if (vor_incircle(b, a, c, d) != -want)
        fail_incircle(a, b, c, d, "vor_incircle swapped", -2, want);
    n_checked++;
    return want;
}

/* ---- random numbers ----------------------------------------------------- */

static uint64_t rng_state;

static uint64_t rng_next(void) { /* splitmix64 */
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1). */
static double rng_unit(void) {
    return (double)(rng_next() >> 11) * 0x1p-53;
}

/* Uniform in [-1, 1). */
static double rng_sym(void) { return 2 * rng_unit() - 1; }

static int rng_int(int n) { return (int)(rng_next() % (uint64_t)n); }

/* Any finite double, uniform over bit patterns. */
static double rng_any_finite(void) {
    for (;;) {
        uint64_t u = rng_next();
        double x;
        memcpy(&x, &u, sizeof x);
        if (isfinite(x))
            return x;
    }
}

static uint64_t test_seed(void) {
    const char *s = getenv("VOR_TEST_SEED");
    return s ? strtoull(s, NULL, 0) : 20240611u;
}

static int setup_seed(void **state) {
    (void)state;
    rng_state = test_seed();
    printf("# test_predicates seed %llu (set VOR_TEST_SEED to change)\n",
           (unsigned long long)rng_state);
    return 0;
}

/* ---- (a) Shewchuk / Kettner near-collinear grid -------------------------- */

static void test_orient_near_collinear_grid(void **state) {
    (void)state;
    const double b[2] = {12, 12}, c[2] = {24, 24};
    int naive_wrong = 0, zeros = 0;
    for (int i = 0; i < 256; i++) {
        for (int j = 0; j < 256; j++) {
            double a[2] = {0.5 + i * 0x1p-53, 0.5 + j * 0x1p-53};
            /* the textbook formula in doubles, as most code writes it */
            double naive = (b[0] - a[0]) * (c[1] - a[1]) -
                           (b[1] - a[1]) * (c[0] - a[0]);
            int ns = (naive > 0) - (naive < 0);
            int want = check_orient(a, b, c);
            if (ns != want)
                naive_wrong++;
            zeros += want == 0;
        }
    }
    printf("# near-collinear grid: naive sign wrong in %d of 65536, "
           "%d exactly collinear\n", naive_wrong, zeros);
    assert_true(naive_wrong > 1000); /* the test has teeth */
    assert_int_equal(zeros, 256);    /* a on the diagonal: i == j */
}

/* ---- (b) near-cocircular: integer points on x^2 + y^2 = 1105^2 ----------- */

static int circle_points(int r, double (*pts)[2], int cap) {
    int n = 0;
    for (long x = -r; x <= r; x++) {
        long y2 = (long)r * r - x * x;
        long y = lround(sqrt((double)y2));
        if (y * y != y2)
            continue;
        if (n < cap) {
            pts[n][0] = (double)x;
            pts[n][1] = (double)y;
            n++;
        }
        if (y != 0 && n < cap) {
            pts[n][0] = (double)x;
            pts[n][1] = (double)-y;
            n++;
        }
    }
    return n;
}

static void test_incircle_near_cocircular(void **state) {
    (void)state;
    double pts[256][2];
    int n = circle_points(1105, pts, 256);
    printf("# %d integer points on x^2 + y^2 = 1105^2\n", n);
    assert_true(n >= 100);
    int signs[3] = {0, 0, 0};
    const double offsets[3] = {0, 1e9, -3.0e5};
    for (int k = 0; k < 20000; k++) {
        double p[4][2];
        double off = offsets[k % 3];
        for (int i = 0; i < 4; i++) {
            int m = rng_int(n);
            p[i][0] = pts[m][0] + off;
            p[i][1] = pts[m][1] - off;
        }
        int s = check_incircle(p[0], p[1], p[2], p[3]);
        signs[s + 1]++;
        check_orient(p[0], p[1], p[2]);
        /* one ulp either way, in x or y, of any one point */
        int which = rng_int(4), axis = rng_int(2);
        double dir = rng_int(2) ? INFINITY : -INFINITY;
        p[which][axis] = nextafter(p[which][axis], dir);
        s = check_incircle(p[0], p[1], p[2], p[3]);
        signs[s + 1]++;
        check_orient(p[0], p[1], p[2]);
    }
    printf("# near-cocircular: %d outside, %d on, %d inside\n", signs[0],
           signs[1], signs[2]);
    assert_true(signs[1] > 10000); /* exactly cocircular cases were seen */
    assert_true(signs[0] > 1000 && signs[2] > 1000);
}

/* ---- (c) random points at many scales and offsets ------------------------ */

/* A random near-degenerate configuration: c close to the line ab, d close to
 * the circle abc, both rounded to doubles, then scaled and shifted. */
static void random_config(double scale, double off, double p[4][2]) {
    for (int i = 0; i < 2; i++) {
        p[i][0] = rng_sym();
        p[i][1] = rng_sym();
    }
    int kind = rng_int(4);
    if (kind == 0) { /* general position */
        p[2][0] = rng_sym();
        p[2][1] = rng_sym();
        p[3][0] = rng_sym();
        p[3][1] = rng_sym();
    } else {
        double t = rng_sym() * 2;
        p[2][0] = p[0][0] + t * (p[1][0] - p[0][0]);
        p[2][1] = p[0][1] + t * (p[1][1] - p[0][1]);
        if (kind == 2) { /* c near the line, a somewhat off */
            p[2][0] += rng_sym() * 1e-12;
        }
        /* d near the circle through a, b and some c' off the line */
        double cx = rng_sym(), cy = rng_sym(), rr = 0.1 + rng_unit();
        double th[3] = {rng_unit() * 6.283, rng_unit() * 6.283,
                        rng_unit() * 6.283};
        if (kind == 3) { /* all four near one circle */
            for (int i = 0; i < 3; i++) {
                p[i][0] = cx + rr * cos(th[i]);
                p[i][1] = cy + rr * sin(th[i]);
            }
        }
        double t4 = rng_unit() * 6.283;
        p[3][0] = cx + rr * cos(t4);
        p[3][1] = cy + rr * sin(t4);
    }
    for (int i = 0; i < 4; i++) {
        p[i][0] = p[i][0] * scale + off;
        p[i][1] = p[i][1] * scale - off;
    }
}

static void test_random_scales(void **state) {
    (void)state;
    const double scales[] = {1, 1e-300, 1e300, 1e15, 1e-9, 0x1p-1060,
                             1e-308, 1e307};
    const double offsets[] = {0, 1e9, 1e9, 1e9};
    long before = n_checked;
    for (int k = 0; k < 60000; k++) {
        double scale = scales[k % 8];
        double off = offsets[rng_int(4)] * (scale > 1e200 ? 1e280 : 1);
        double p[4][2];
        random_config(scale, off, p);
        check_orient(p[0], p[1], p[2]);
        check_orient(p[0], p[1], p[3]);
        check_incircle(p[0], p[1], p[2], p[3]);
    }
    printf("# random scales: %ld checks\n", n_checked - before);
}

/* Nearly cocircular to second order: a, b, c on the unit circle (cos and
 * sin rounded), d pushed off a fourth point of the circle along the
 * tangent by 2^-k, so that its distance from the circle is about 2^-2k
 * (plus the rounding of d): determinants from about u down to u^2 of
 * their permanent, the range where a double-double evaluation must hand
 * over to the exact one. Also shifted by a large offset (inexact differences). */
static void test_incircle_tangent(void **state) {
    (void)state;
    long before = n_checked;
    int signs[3] = {0, 0, 0};
    for (int k = 0; k < 30000; k++) {
        double p[4][2];
        for (int i = 0; i < 4; i++) {
            double t = rng_unit() * 6.283185307179586;
            p[i][0] = cos(t);
            p[i][1] = sin(t);
        }
        int e = 20 + rng_int(33); /* 2^-20 .. 2^-52: less is rounded away */
        double h = ldexp(rng_sym(), -e);
        double tx = -p[3][1], ty = p[3][0];
        p[3][0] += h * tx;
        p[3][1] += h * ty;
        if (k % 3 == 1)
            for (int i = 0; i < 4; i++) {
                p[i][0] += 3.0;
                p[i][1] -= 5.0;
            }
        int sg = check_incircle(p[0], p[1], p[2], p[3]);
        signs[sg + 1]++;
    }
    printf("# tangent: %ld checks, %d outside, %d on, %d inside\n",
           n_checked - before, signs[0], signs[1], signs[2]);
    assert_true(signs[0] > 100 && signs[2] > 100);
}

/* ---- (d) mixed magnitudes in one call ------------------------------------ */

static void test_mixed_magnitudes(void **state) {
    (void)state;
    const double mags[] = {1e300, 1e-300, 1, 0, 1e-320, 1e150, 1e-150,
                           DBL_MAX, DBL_TRUE_MIN, 0x1p-1022};
    const int nm = (int)(sizeof mags / sizeof mags[0]);
    for (int k = 0; k < 20000; k++) {
        double p[4][2];
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 2; j++) {
                double m = mags[rng_int(nm)];
                /* small integers times the magnitude make coincidences */
                double v = m * (double)(rng_int(5) - 2);
                if (rng_int(3) == 0)
                    v = m * rng_sym();
                if (!isfinite(v))
                    v = m;
                p[i][j] = v;
            }
        check_orient(p[0], p[1], p[2]);
        check_incircle(p[0], p[1], p[2], p[3]);
    }
    /* the classic: one coordinate huge, another tiny, same call */
    const double a[2] = {1e300, 1e-300}, b[2] = {-1e300, 1e-300},
                 c[2] = {0, 1e-300}, d[2] = {0, -1e-300};
    assert_int_equal(check_orient(a, b, c), 0);
    assert_int_equal(check_orient(a, b, d), 1); /* a->b points to -x */
    check_incircle(a, b, c, d);
    /* random bit patterns: any finite doubles at all */
    for (int k = 0; k < 5000; k++) {
        double p[4][2];
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 2; j++)
                p[i][j] = rng_any_finite();
        check_orient(p[0], p[1], p[2]);
        check_incircle(p[0], p[1], p[2], p[3]);
    }
}

/* ---- (d) corners of axis-parallel rectangles ---------------------------- */

/* A grid of any spacing in x and in y (0.37 by 0.11: no small lattice)
 * puts four cocircular sites on every cell; the exact routine answers those
 * from the coordinates' equalities. Its corners in every order, with
 * duplicates, on one line, and with one corner moved by an ulp (then not
 * cocircular), against the oracle. */
static void test_incircle_axis_rectangles(void **state) {
    (void)state;
    int zeros = 0, moved_nonzero = 0;
    for (int k = 0; k < 40000; k++) {
        double x[2], y[2];
        for (int i = 0; i < 2; i++) {
            switch (k % 4) {
            case 0: /* a decimal grid */
                x[i] = 0.37 * (double)rng_int(100000);
                y[i] = 0.11 * (double)rng_int(100000);
                break;
            case 1: /* any doubles */
                x[i] = rng_any_finite();
                y[i] = rng_any_finite();
                break;
            case 2: /* tiny and huge: no common scale */
                x[i] = ldexp(rng_sym(), rng_int(2000) - 1000);
                y[i] = ldexp(rng_sym(), rng_int(2000) - 1000);
                break;
            default: /* near each other */
                x[i] = 1e6 + rng_sym();
                y[i] = -3 + ldexp(rng_sym(), -30);
            }
        }
        if (k % 13 == 0) x[1] = x[0]; /* all on one line */
        double p[4][2];
        int perm = rng_int(24), used = 0;
        for (int i = 0; i < 4; i++) {
            int c = perm % (4 - i), j = -1;
            perm /= 4 - i;
            while (c >= 0) /* the c-th corner not yet used */
                if (!(used & (1 << ++j))) c--;
            used |= 1 << j;
            p[i][0] = x[j & 1];
            p[i][1] = y[j >> 1];
        }
        if (k % 11 == 0) /* two pairs of duplicates */
            memcpy(p[2], p[0], sizeof p[0]), memcpy(p[3], p[1], sizeof p[1]);
        int moved = k % 5 == 0;
        if (moved) p[rng_int(4)][rng_int(2)] = nextafter(p[0][0], INFINITY);
        int sg = check_incircle(p[0], p[1], p[2], p[3]);
        zeros += sg == 0;
        moved_nonzero += moved && sg != 0;
    }
    printf("# axis rectangles: %d cocircular, %d moved off the circle\n", zeros,
           moved_nonzero);
    assert_true(zeros > 20000);
    assert_true(moved_nonzero > 1000);
}

/* ---- (d') wide dynamic range that only the integer stage gets right ------ */

/* Small integers mixed with small integers times 2^-e and with 2 - 2^-40
 * style values: the exact determinant then has bits far below the largest
 * term's, down to 2^(-4e), which expansions cannot hold once 4e exceeds the
 * exponent range; the threshold that sends such calls to the integer stage
 * is what this test checks (it fails if either threshold is raised by a
 * quarter). */
static void test_wide_dynamic_range(void **state) {
    (void)state;
    const int exps[] = {270, 280, 300, 330, 450, 540, 600, 800, 1000, 1070};
    for (int k = 0; k < 60000; k++) {
        int e = exps[k % 10];
        double p[4][2];
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 2; j++) {
                int r = rng_int(4);
                double v = (double)(rng_int(5) - 2);
                if (r == 0)
                    v = ldexp(v, -e);
                else if (r == 1)
                    v += ldexp((double)(rng_int(5) - 2), -40);
                p[i][j] = v;
            }
        check_orient(p[0], p[1], p[2]);
        check_incircle(p[0], p[1], p[2], p[3]);
    }
}

/* ---- (d) squares of a rotated grid ----------------------------------------- */

/* The corners of a grid's square turned by an angle, each computed in
 * doubles: the rounding leaves many squares exactly cocircular and the
 * rest within a few units of the last place of it, beyond what the
 * double-double evaluation decides; the exact stages (integers for
 * operands within 61 bits of each other, expansions otherwise) settle
 * them. Squares near the origin and far from it, and with one corner
 * moved by an ulp. */
static void test_rotated_grid(void **state) {
    (void)state;
    int zeros = 0;
    for (int k = 0; k < 40000; k++) {
        double th = rng_unit() * 1.5, co = cos(th), si = sin(th);
        double step = ldexp(1 + rng_unit(), rng_int(40) - 20);
        int i = rng_int(2000) - (k % 3 == 0 ? 1000 : 0), j = rng_int(2000);
        double p[4][2];
        for (int q = 0; q < 4; q++) {
            double u = (i + (q & 1)) * step, v = (j + (q >> 1)) * step;
            p[q][0] = u * co - v * si;
            p[q][1] = u * si + v * co;
        }
        if (k % 7 == 0)
            p[rng_int(4)][rng_int(2)] = nextafter(p[3][0], INFINITY);
        zeros += check_incircle(p[0], p[1], p[3], p[2]) == 0;
        check_incircle(p[3], p[0], p[1], p[2]);
    }
    printf("# rotated grid: %d squares exactly cocircular\n", zeros);
    assert_true(zeros > 1000);
}

/* ---- (d'') wide calls near a degeneracy ---------------------------------- */

/* A wide call (operands spanning more bits than the expansions hold) is
 * first tried by the filter on its points scaled below 1 and rounded to
 * multiples of 2^-1074 (predicates.c, "wide calls"); only what rounding
 * cannot have decided goes on to the integers. Here huge points lie
 * exactly on a line or a circle through the origin and a tiny point sits
 * on it, beside it or across it, so that rounding the tiny point away
 * leaves a determinant of zero or of a rounding's size; and points at many
 * scales at once, x = r 2^k for k in [-500, 500) beside y in [0, 1) (a set
 * spread over hundreds of decades), whose calls are mostly wide and far
 * from degenerate. All against the oracle. */
static void test_wide_near_degenerate(void **state) {
    (void)state;
    int on = 0;
    for (int k = 0; k < 20000; k++) {
        double h = ldexp(1, 300 + rng_int(700));
        double t = ldexp(1, -600 - rng_int(475));
        double u = (double)(rng_int(7) - 3), v = (double)(rng_int(7) - 3);
        double p = (double)(rng_int(7) - 3), q = (double)(rng_int(7) - 3);
        if (u == 0 && v == 0)
            u = 1;
        /* a line through the origin, direction (u, v) */
        double a[2] = {u * h, v * h}, b[2] = {-u * h, -v * h};
        double c[2] = {p * t, q * t};
        on += check_orient(a, b, c) == 0;
        check_orient(a, c, b);
        /* the circle of centre (h, 0) through the origin */
        double e[2] = {2 * h, 0}, f[2] = {h, h}, g[2] = {h, -h};
        on += check_incircle(e, f, g, c) == 0;
        check_incircle(c, e, f, g);
        /* many scales at once */
        double m[4][2];
        for (int i = 0; i < 4; i++) {
            m[i][0] = ldexp(rng_unit(), rng_int(1000) - 500);
            m[i][1] = rng_int(4) ? rng_unit() : ldexp(rng_unit(), -rng_int(1000));
        }
        check_orient(m[0], m[1], m[2]);
        check_incircle(m[0], m[1], m[2], m[3]);
    }
    printf("# wide calls: %d exactly on the line or circle\n", on);
    assert_true(on > 1000);
}

/* ---- (e') integer lattices near degeneracy ------------------------------- */

static double naive_incircle(const double *a, const double *b, const double *c,
                             const double *d) {
    double adx = a[0] - d[0], ady = a[1] - d[1], bdx = b[0] - d[0];
    double bdy = b[1] - d[1], cdx = c[0] - d[0], cdy = c[1] - d[1];
    return (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
           (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
           (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
}

/* Integer points with differences from 2^8 to 2^31, nearly collinear or
 * nearly cocircular (rounded to the lattice), some shifted by 2^-k so the
 * lattice is finer than 1: the sizes where a plain double evaluation stops
 * being exact, which the exact stage's lattice shortcut must respect. */
static void test_integer_lattices(void **state) {
    (void)state;
    int naive_wrong = 0;
    for (int k = 0; k < 40000; k++) {
        int bits = 8 + k % 24;
        double span = ldexp(1, bits);
        double scale = ldexp(1, -(rng_int(4) * 7));
        double p[4][2];
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 2; j++)
                p[i][j] = floor(rng_unit() * span);
        double t = floor(rng_sym() * 4);
        for (int j = 0; j < 2; j++) /* c: on the line ab, nudged */
            p[2][j] = p[0][j] + t * (p[1][j] - p[0][j]) + (rng_int(3) - 1);
        if (k & 1) { /* a, b, c around a circle, d rounded onto it */
            double cx = floor(rng_unit() * span), cy = floor(rng_unit() * span);
            double r = span / 4 + floor(rng_unit() * span / 4);
            for (int i = 0; i < 4; i++) {
                double th = rng_unit() * 6.283185307179586;
                p[i][0] = cx + round(r * cos(th));
                p[i][1] = cy + round(r * sin(th));
            }
        }
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 2; j++)
                p[i][j] *= scale;
        int o = check_orient(p[0], p[1], p[2]);
        int s = check_incircle(p[0], p[1], p[2], p[3]);
        double nd = naive_incircle(p[0], p[1], p[2], p[3]);
        naive_wrong += ((nd > 0) - (nd < 0)) != s;
        (void)o;
    }
    printf("# integer lattices: naive incircle wrong in %d of 40000\n",
           naive_wrong);
    assert_true(naive_wrong > 0);

    /* Unit-area lattice triangles: b - a = (p, q) coprime, c - a = (r, s)
     * + t (p, q) with p s - q r = 1, so orient2d is exactly +1 while the
     * products reach 2^90: the smallest nonzero determinant at every size
     * from 2^10 to 2^44. */
    int naive_orient_wrong = 0;
    for (int k = 0; k < 20000; k++) {
        int bits = 10 + k % 35;
        int64_t pq[2], rs[2];
        for (;;) {
            pq[0] = (int64_t)(rng_next() >> (64 - bits)) + 1;
            pq[1] = (int64_t)(rng_next() >> (64 - bits)) + 1;
            /* extended Euclid: r, s with p s - q r = gcd(p, q) */
            int64_t r0 = pq[0], r1 = pq[1], s0 = 1, s1 = 0, t0 = 0, t1 = 1;
            while (r1 != 0) {
                int64_t qt = r0 / r1;
                int64_t r2 = r0 - qt * r1, s2 = s0 - qt * s1,
                        t2 = t0 - qt * t1;
                r0 = r1, r1 = r2;
                s0 = s1, s1 = s2;
                t0 = t1, t1 = t2;
            }
            if (r0 != 1)
                continue; /* not coprime */
            /* s0 p + t0 q = 1: take (r, s) = (-t0, s0): p s0 - q (-t0) = 1 */
            rs[0] = -t0;
            rs[1] = s0;
            break;
        }
        int64_t t = rng_int(41) - 20;
        double base[2] = {floor(rng_sym() * 0x1p20), floor(rng_sym() * 0x1p20)};
        double a[2] = {base[0], base[1]};
        double b[2] = {base[0] + (double)pq[0], base[1] + (double)pq[1]};
        double c[2] = {base[0] + (double)(rs[0] + t * pq[0]),
                       base[1] + (double)(rs[1] + t * pq[1])};
        int e = rng_int(200) - 100;
        for (int j = 0; j < 2; j++) {
            a[j] = ldexp(a[j], e);
            b[j] = ldexp(b[j], e);
            c[j] = ldexp(c[j], e);
        }
        assert_int_equal(check_orient(a, b, c), 1);
        double nd = (a[0] - c[0]) * (b[1] - c[1]) -
                    (a[1] - c[1]) * (b[0] - c[0]);
        naive_orient_wrong += !(nd > 0);
    }
    printf("# unit-area lattice triangles: naive orient2d wrong in %d of "
           "20000\n", naive_orient_wrong);
    assert_true(naive_orient_wrong > 1000);
}

/* ---- (e) exact constructions: collinear and cocircular ------------------- */

static void test_exact_constructions(void **state) {
    (void)state;
    /* radii with many lattice points, differences from 2^13 to 2^24:
     * 5525 = 5^2 13 17, 32045 = 5 13 17 29, 160225 = 5^2 13 17 29,
     * 5928325 = 5^2 13 17 29 37 */
    static const int radii[4] = {5525, 32045, 160225, 5928325};
    static double circ[4][2048][2];
    int nc[4];
    for (int i = 0; i < 4; i++) {
        nc[i] = circle_points(radii[i], circ[i], 2048);
        assert_true(nc[i] >= 100);
    }
    int collinear = 0, cocircular = 0;
    for (int k = 0; k < 20000; k++) {
        /* exactly collinear: a + t (b - a) with integers (steps up to
         * 2^39), scaled by a power of two (exact) */
        int e = rng_int(1900) - 1000;
        double base[2] = {(double)(rng_int(2001) - 1000),
                          (double)(rng_int(2001) - 1000)};
        double step[2];
        int sb = rng_int(33);
        for (int j = 0; j < 2; j++)
            step[j] = ldexp((double)(rng_int(201) - 100), sb);
        double p[3][2];
        for (int i = 0; i < 3; i++) {
            int t = rng_int(41) - 20;
            for (int j = 0; j < 2; j++)
                p[i][j] = ldexp(base[j] + t * step[j], e);
        }
        collinear += check_orient(p[0], p[1], p[2]) == 0;

        /* exactly cocircular: lattice points on a circle about an integer
         * centre, scaled by a power of two */
        int ci = k % 4;
        double cx = (double)(rng_int(20001) - 10000);
        double cy = (double)(rng_int(20001) - 10000);
        double q[4][2];
        int f = rng_int(1800) - 900;
        for (int i = 0; i < 4; i++) {
            int m = rng_int(nc[ci]);
            q[i][0] = ldexp(circ[ci][m][0] + cx, f);
            q[i][1] = ldexp(circ[ci][m][1] + cy, f);
        }
        cocircular += check_incircle(q[0], q[1], q[2], q[3]) == 0;
    }
    printf("# exact constructions: %d collinear, %d cocircular of 20000\n",
           collinear, cocircular);
    assert_int_equal(collinear, 20000);
    assert_int_equal(cocircular, 20000);
}

/* ---- the determinant's value --------------------------------------------- */

/* vor__orient2d_value against the rational determinant: relative error
 * below 2^-62, zero exactly when collinear, on ordinary, near-collinear
 * and wide-range input, and on sites close beside their magnitude (exact
 * differences: the four-term path), nearly on a line or exactly on it. */
static void test_orient_value(void **state) {
    (void)state;
    mpq_t ax, ay, bx, by, cx, cy, l, r, got, err;
    mpq_inits(ax, ay, bx, by, cx, cy, l, r, got, err, NULL);
    const double mags[] = {1, 1e300, 1e-300, 0x1p-1074, 1e150, 3};
    for (int k = 0; k < 30000; k++) {
        double p[3][2];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 2; j++)
                p[i][j] = rng_sym() * mags[rng_int(k % 3 == 0 ? 6 : 1)];
        if (k % 4 == 1) /* near-collinear */
            for (int j = 0; j < 2; j++)
                p[2][j] = p[0][j] + 0.375 * (p[1][j] - p[0][j]);
        if (k % 4 == 3) { /* close together, on or near a line */
            double o[2] = {rng_sym() * 1e3, rng_sym() * 1e3};
            double dx = rng_sym(), dy = rng_sym();
            int lsb = rng_int(8); /* 0: exactly collinear */
            for (int i = 0; i < 3; i++) {
                double t = (double)(rng_int(2001) - 1000) / 1024;
                p[i][0] = o[0] + t * dx;
                p[i][1] = o[1] + t * dy + (lsb ? ldexp(rng_sym(), -30 - 3 * lsb) : 0);
            }
        }
        long double v = vor__orient2d_value(p[0], p[1], p[2]);
        mpq_set_d(ax, p[0][0]);
        mpq_set_d(ay, p[0][1]);
        mpq_set_d(bx, p[1][0]);
        mpq_set_d(by, p[1][1]);
        mpq_set_d(cx, p[2][0]);
        mpq_set_d(cy, p[2][1]);
        mpq_sub(ax, ax, cx);
        mpq_sub(ay, ay, cy);
        mpq_sub(bx, bx, cx);
        mpq_sub(by, by, cy);
        mpq_mul(l, ax, by);
        mpq_mul(r, ay, bx);
        mpq_sub(l, l, r); /* exact determinant */
        int sign = mpq_sgn(l);
        assert_int_equal((v > 0) - (v < 0), sign);
        if (sign == 0)
            continue;
        /* |v - det| <= 2^-62 |det|; v = +-M 2^(e-64) with a 64-bit M */
        int e;
        long double m = frexpl(fabsl(v), &e);
        mpz_set_ui(mpq_numref(got), (unsigned long)ldexpl(m, 64));
        mpz_set_ui(mpq_denref(got), 1);
        if (v < 0)
            mpq_neg(got, got);
        if (e - 64 >= 0)
            mpq_mul_2exp(got, got, (mp_bitcnt_t)(e - 64));
        else
            mpq_div_2exp(got, got, (mp_bitcnt_t)(64 - e));
        mpq_sub(err, got, l);
        mpq_abs(err, err);
        mpq_abs(l, l);
        mpq_div_2exp(l, l, 62);
        assert_true(mpq_cmp(err, l) <= 0);
        n_checked++;
    }
    mpq_clears(ax, ay, bx, by, cx, cy, l, r, got, err, NULL);
}

/* ---- small hand-made cases ---------------------------------------------- */

static void test_basic_signs(void **state) {
    (void)state;
    const double o[2] = {0, 0}, x[2] = {1, 0}, y[2] = {0, 1}, xy[2] = {1, 1};
    const double in[2] = {0.25, 0.25}, out[2] = {2, 2};
    assert_int_equal(check_orient(o, x, y), 1);
    assert_int_equal(check_orient(o, y, x), -1);
    assert_int_equal(check_orient(o, x, x), 0);
    assert_int_equal(check_orient(o, o, o), 0);
    assert_int_equal(check_incircle(o, x, y, in), 1);
    assert_int_equal(check_incircle(o, x, y, out), -1);
    assert_int_equal(check_incircle(o, x, y, xy), 0);
    assert_int_equal(check_incircle(o, x, y, o), 0);
    assert_int_equal(check_incircle(o, y, x, in), -1); /* clockwise */
    /* overflowing differences: the filter must not trust inf */
    const double big1[2] = {DBL_MAX, -DBL_MAX}, big2[2] = {-DBL_MAX, DBL_MAX};
    assert_int_equal(check_orient(big1, big2, o), 0);
    const double big3[2] = {-DBL_MAX, -DBL_MAX};
    assert_int_equal(check_orient(big1, big2, big3), 1);
    check_incircle(big1, big2, big3, o);
    /* subnormal differences: the filter must not trust underflow */
    const double t1[2] = {DBL_TRUE_MIN, 0}, t2[2] = {0, DBL_TRUE_MIN},
                 t3[2] = {3 * DBL_TRUE_MIN, 5 * DBL_TRUE_MIN};
    assert_int_equal(check_orient(o, t1, t2), 1);
    check_orient(t1, t2, t3);
    check_incircle(o, t1, t2, t3);
    check_incircle(t1, t2, t3, o);
    /* an underflowed product multiplied by a huge lift: the true term
     * alift (bdx cdy) = 2^1000 2^-1075 = 2^-75 decides, while the
     * permanent seen by a filter is only 2^-576 (predicates.h) */
    const double ua[2] = {0x1p500, 0}, ub[2] = {0.5, 0},
                 uc[2] = {0, DBL_TRUE_MIN};
    assert_int_equal(check_incircle(ua, ub, uc, o), 1);
}

/* ---- bulk random agreement ---------------------------------------------- */

static void test_random_bulk(void **state) {
    (void)state;
    long before = n_checked;
    for (int k = 0; k < 40000; k++) {
        double p[4][2];
        int mode = k % 3;
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 2; j++) {
                if (mode == 0) /* small integers: many exact degeneracies */
                    p[i][j] = (double)(rng_int(7) - 3);
                else if (mode == 1) /* integer pixels */
                    p[i][j] = (double)rng_int(1 << 12);
                else
                    p[i][j] = rng_sym();
            }
        check_orient(p[0], p[1], p[2]);
        check_incircle(p[0], p[1], p[2], p[3]);
    }
    printf("# random bulk: %ld checks; total so far %ld\n",
           n_checked - before, n_checked);
}

static int report_total(void **state) {
    (void)state;
    printf("# test_predicates: %ld cases checked against the oracle\n",
           n_checked);
    return 0;
}

/* The static orient2d filter and the local incircle filter
 * (vor__orient2d_static, vor__incircle_local) against
 * the rational oracles, on batches of points whose span gives the bound,
 * as the mesh code uses them: uniform points, points rounded onto a circle
 * (nearly cocircular, nearly collinear), lattice points (exactly
 * cocircular and collinear: the filter must pass them on) and the box's
 * corners one ulp in or out, at scales from 2^-199 to 2^199 and away from
 * the origin. Seed fixed and printed. */
static void test_static_filters(void **state) {
    (void)state;
    const uint64_t seed = 20261122;
    printf("  static filters: seed %llu\n", (unsigned long long)seed);
    vt_rng r = {seed};
    const double scales[] = {0x1p-199, 0x1p-60, 1.0, 0x1p40, 0x1p199};
    const double offsets[] = {0.0, 3.0, -1000.5};
    enum { N = 64 };
    double pts[2 * N];
    long decided = 0, total = 0;
    for (size_t si = 0; si < sizeof scales / sizeof *scales; si++) {
        for (size_t oi = 0; oi < sizeof offsets / sizeof *offsets; oi++) {
            for (int kind = 0; kind < 4; kind++) {
                const double L = scales[si], o = offsets[oi] * L;
                for (int i = 0; i < N; i++) {
                    double x, y;
                    if (kind == 0) {
                        x = vt_unit(&r);
                        y = vt_unit(&r);
                    } else if (kind == 1) {
                        double t = 6.283185307179586 * vt_unit(&r);
                        x = 0.5 + 0.5 * cos(t);
                        y = 0.5 + 0.5 * sin(t);
                    } else if (kind == 2) {
                        x = (double)(vt_next(&r) % 17) / 16;
                        y = (double)(vt_next(&r) % 17) / 16;
                    } else {
                        x = (double)(vt_next(&r) % 2);
                        y = (double)(vt_next(&r) % 2);
                    }
                    x = o + x * L;
                    y = o + y * L;
                    if (kind == 3) { /* nudge a corner by an ulp */
                        int k = (int)(vt_next(&r) % 3);
                        x = k == 0 ? x : nextafter(x, k == 1 ? INFINITY : -INFINITY);
                    }
                    pts[2 * i] = x;
                    pts[2 * i + 1] = y;
                }
                double x0 = pts[0], x1 = pts[0], y0 = pts[1], y1 = pts[1];
                for (int i = 1; i < N; i++) {
                    x0 = fmin(x0, pts[2 * i]);
                    x1 = fmax(x1, pts[2 * i]);
                    y0 = fmin(y0, pts[2 * i + 1]);
                    y1 = fmax(y1, pts[2 * i + 1]);
                }
                double span = fmax(x1 - x0, y1 - y0);
                double so = vor__orient2d_static_bound(span);
                assert_true(isfinite(so));
                for (int k = 0; k < 300; k++) {
                    const double *a = pts + 2 * (vt_next(&r) % N);
                    const double *b = pts + 2 * (vt_next(&r) % N);
                    const double *c = pts + 2 * (vt_next(&r) % N);
                    const double *d = pts + 2 * (vt_next(&r) % N);
                    assert_int_equal(vor__orient2d_static(a, b, c, so), oracle_orient(a, b, c));
                    assert_int_equal(vor__incircle_local(a, b, c, d),
                                     oracle_incircle(a, b, c, d));
                    total++;
                    decided += vor__incircle_filter(a, b, c, d) != 0;
                }
            }
        }
    }
    printf("  static filters: %ld tuples, %ld decided by the dynamic filter\n",
           total, decided);
    /* out of range: no bound, every call falls through */
    assert_true(isinf(vor__orient2d_static_bound(0.0)));
}

/* The local bound of incircle (vor__incircle_local) against the oracle
 * where a bound from the span would be far off: four points of a small
 * cluster (1 down to 2^-60 across) inside a span of 1, one of them far
 * (across the span) with three close, nearly cocircular quadruples of the
 * cluster, and whole sets at 2^-600, 2^-300, 2^300 and 2^600, outside any
 * span a static bound allowed, with and without an offset. */
static void test_local_incircle(void **state) {
    (void)state;
    const uint64_t seed = 20261126;
    printf("  local incircle: seed %llu\n", (unsigned long long)seed);
    vt_rng r = {seed};
    long decided = 0, total = 0;
    const double scales[] = {0x1p-600, 0x1p-300, 1.0, 0x1p300, 0x1p600};
    for (int it = 0; it < 200000; it++) {
        double L = scales[it % 5];
        double w = ldexp(1.0, -(int)(vt_next(&r) % 61)); /* cluster width */
        double cx = vt_unit(&r), cy = vt_unit(&r), off = it % 2 ? 0 : 3.0;
        double p[4][2];
        int kind = (int)(vt_next(&r) % 3);
        for (int k = 0; k < 4; k++) {
            double x, y;
            if (kind == 2) { /* nearly on a circle of the cluster */
                double t = 6.283185307179586 * vt_unit(&r);
                x = cx + w * cos(t);
                y = cy + w * sin(t);
            } else {
                x = cx + w * vt_unit(&r);
                y = cy + w * vt_unit(&r);
            }
            if (kind == 1 && k == (int)(it % 4)) { /* one far point */
                x = vt_unit(&r);
                y = vt_unit(&r);
            }
            p[k][0] = (off + x) * L;
            p[k][1] = (off + y) * L;
        }
        int want = oracle_incircle(p[0], p[1], p[2], p[3]);
        int got = vor__incircle_local(p[0], p[1], p[2], p[3]);
        if (got != want)
            fail_msg("incircle (%a, %a) (%a, %a) (%a, %a) (%a, %a): %d, not "
                     "%d", p[0][0], p[0][1], p[1][0], p[1][1], p[2][0],
                     p[2][1], p[3][0], p[3][1], got, want);
        if (L == 1.0) {
            total++;
            decided += vor__incircle_local_filter(p[0], p[1], p[2], p[3]) != 0;
        }
    }
    /* at the other scales a lift or the bound's square overflows or the
     * determinant underflows: every call goes on to the exact stages */
    printf("  local incircle: %ld tuples at scale 1, %ld decided by the "
           "local bound\n", total, decided);
    assert_true(decided > total / 2);
}

/* vor__circumcenter_fast decides its window on the bits of the
 * differences; the plain comparisons of the definition are the oracle, at
 * the window's edges (one ulp either side), at zeros, subnormals, inf and
 * nan, and the centre it writes must be the plain formula's. */
static int window_oracle(double v) {
    double m = fabs(v);
    return m == 0 || (m >= 0x1p-300 && m <= 0x1p300);
}

static void test_circumcenter_window(void **state) {
    (void)state;
    const double edges[] = {0x1p-300, 0x1p300, 1.0, 0x1p-1074, DBL_MIN, DBL_MAX};
    double vals[64];
    size_t nv = 0;
    for (size_t i = 0; i < sizeof edges / sizeof *edges; i++) {
        double e = edges[i];
        double around[3] = {nextafter(e, 0), e, nextafter(e, INFINITY)};
        for (int k = 0; k < 3; k++) {
            vals[nv++] = around[k];
            vals[nv++] = -around[k];
        }
    }
    vals[nv++] = 0.0;
    vals[nv++] = -0.0;
    vals[nv++] = INFINITY;
    vals[nv++] = -INFINITY;
    vals[nv++] = NAN;
    for (size_t i = 0; i < nv; i++)
        assert_int_equal(vor__cc_in_window(vals[i]), window_oracle(vals[i]));

    /* b - a takes each value; the centre is written exactly when the
     * plain formula's conditions hold, and then equals it */
    for (size_t i = 0; i < nv; i++) {
        double a[2] = {0, 0}, b[2] = {vals[i], 1}, c[2] = {1, 0};
        double out[2] = {42, 42};
        int ok = vor__circumcenter_fast(a, b, c, out);
        double bx = b[0], by = b[1], cx = c[0], cy = c[1];
        double d = 2 * (bx * cy - by * cx);
        int want = window_oracle(bx) && d != 0;
        assert_int_equal(ok, want);
        if (!ok) {
            assert_true(out[0] == 42 && out[1] == 42);
            continue;
        }
        double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
        double x = (cy * b2 - by * c2) / d + 0.0, y = (bx * c2 - cx * b2) / d + 0.0;
        assert_memory_equal(&out[0], &x, sizeof x);
        assert_memory_equal(&out[1], &y, sizeof y);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_basic_signs),
        cmocka_unit_test(test_orient_near_collinear_grid),
        cmocka_unit_test(test_incircle_near_cocircular),
        cmocka_unit_test(test_random_scales),
        cmocka_unit_test(test_incircle_tangent),
        cmocka_unit_test(test_mixed_magnitudes),
        cmocka_unit_test(test_incircle_axis_rectangles),
        cmocka_unit_test(test_wide_dynamic_range),
        cmocka_unit_test(test_wide_near_degenerate),
        cmocka_unit_test(test_rotated_grid),
        cmocka_unit_test(test_exact_constructions),
        cmocka_unit_test(test_integer_lattices),
        cmocka_unit_test(test_random_bulk),
        cmocka_unit_test(test_orient_value),
        cmocka_unit_test(test_circumcenter_window),
        cmocka_unit_test(test_static_filters),
        cmocka_unit_test(test_local_incircle),
    };
    return cmocka_run_group_tests_name("core/predicates", tests, setup_seed,
                                       report_total);
}
