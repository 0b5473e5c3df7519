/* test_fortune.c -- Fortune's sweep (core/fortune.c) and its predicates
 * (core/fortune_predicates.c).
 *
 * Oracles, none of them the code under test:
 *   - the sweep's predicates against exact rational arithmetic (GMP mpq,
 *     doubles converted exactly with mpq_set_d) on random and deliberately
 *     degenerate inputs: breakpoint polynomial, the proven intervals of the
 *     circle tops (float and double-double), site-versus-event and
 *     event-versus-event order, the cheap tie certificates;
 *   - every diagram: vor_check, a brute-force check (n <= 2000: every
 *     vertex's circle has no site strictly inside, exact vor_incircle
 *     against all sites, and the sites exactly on it are those of the
 *     vertex's edges), and bit-identity with Bowyer-Watson and flipping
 *     (when vor_compute offers them);
 *   - the inputs where sweeps go wrong: equal-y first sites, rows of equal
 *     y, a site exactly below a breakpoint, a site at the top of an event's
 *     circle, many cocircular sites, huge and tiny coordinates, and small
 *     random integer sets (thousands of fixed seeds, printed) where such
 *     coincidences are the rule;
 *   - every allocation of the sweep made to fail in turn: VOR_ENOMEM,
 *     nothing leaks (LeakSanitizer).
 * No timing is asserted anywhere.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <cmocka.h>
#include <gmp.h>

#include "../../core/fortune_predicates.h"
#include "../../core/internal.h"
#include "../support/testsets.h"
#include "fault_alloc.h"

/* ---- Exact rational oracle ----------------------------------------------- */

/* Centre (X, Y) and squared radius R2 of the circle through a, b, c
 * (not collinear), exactly. */
static void q_circle(const double *a, const double *b, const double *c, mpq_t X,
                     mpq_t Y, mpq_t R2) {
    mpq_t ax, ay, bx, by, cx, cy, d, t, u, b2, c2;
    mpq_inits(ax, ay, bx, by, cx, cy, d, t, u, b2, c2, NULL);
    mpq_set_d(ax, a[0]);
    mpq_set_d(ay, a[1]);
    mpq_set_d(bx, b[0]);
    mpq_set_d(by, b[1]);
    mpq_set_d(cx, c[0]);
    mpq_set_d(cy, c[1]);
    mpq_sub(bx, bx, ax);
    mpq_sub(by, by, ay);
    mpq_sub(cx, cx, ax);
    mpq_sub(cy, cy, ay);
    mpq_mul(t, bx, cy);
    mpq_mul(u, by, cx);
    mpq_sub(d, t, u);
    mpq_add(d, d, d);
    mpq_mul(t, bx, bx);
    mpq_mul(u, by, by);
    mpq_add(b2, t, u);
    mpq_mul(t, cx, cx);
    mpq_mul(u, cy, cy);
    mpq_add(c2, t, u);
    mpq_mul(t, cy, b2); /* ux = (cy b2 - by c2) / d */
    mpq_mul(u, by, c2);
    mpq_sub(t, t, u);
    mpq_div(t, t, d);
    mpq_mul(u, bx, c2); /* uy = (bx c2 - cx b2) / d */
    mpq_mul(R2, cx, b2);
    mpq_sub(u, u, R2);
    mpq_div(u, u, d);
    mpq_add(X, ax, t);
    mpq_add(Y, ay, u);
    mpq_mul(t, t, t);
    mpq_mul(u, u, u);
    mpq_add(R2, t, u);
    mpq_clears(ax, ay, bx, by, cx, cy, d, t, u, b2, c2, NULL);
}

/* Sign of (a + sqrt(b)) - (c + sqrt(d)), b, d >= 0. */
static int q_cmp_sum_sqrt(const mpq_t a, const mpq_t b, const mpq_t c,
                          const mpq_t d) {
    mpq_t p, e, t;
    mpq_inits(p, e, t, NULL);
    mpq_sub(p, a, c);
    int sp = mpq_sgn(p), s = mpq_cmp(b, d);
    s = (s > 0) - (s < 0);
    int r;
    if (sp == 0 || s == 0 || sp == s) {
        r = sp != 0 ? sp : s;
    } else {
        /* |p| against |sqrt b - sqrt d|: p^2 - (b + d) + 2 sqrt(bd) */
        mpq_mul(e, p, p);
        mpq_sub(e, e, b);
        mpq_sub(e, e, d);
        int m;
        if (mpq_sgn(e) >= 0) {
            mpq_mul(t, b, d);
            m = (mpq_sgn(e) > 0 || mpq_sgn(t) > 0) ? 1 : 0;
        } else {
            mpq_mul(t, b, d);
            mpq_mul_2exp(t, t, 2);
            mpq_mul(e, e, e);
            m = mpq_cmp(t, e);
            m = (m > 0) - (m < 0);
        }
        r = m > 0 ? sp : m < 0 ? s : 0;
    }
    mpq_clears(p, e, t, NULL);
    return r;
}

/* Sign of T - y, T the y of the top of the circle through a, b, c. */
static int q_top_vs(const double *a, const double *b, const double *c,
                    double y) {
    mpq_t X, Y, R2, q, z;
    mpq_inits(X, Y, R2, q, z, NULL);
    q_circle(a, b, c, X, Y, R2);
    mpq_set_d(q, y);
    int r = q_cmp_sum_sqrt(Y, R2, q, z);
    mpq_clears(X, Y, R2, q, z, NULL);
    return r;
}

/* The same against m 2^e (a value past the doubles, e an integer). */
static int q_top_vs_2exp(double t[3][2], double m, double e) {
    mpq_t X, Y, R2, q, z;
    mpq_inits(X, Y, R2, q, z, NULL);
    q_circle(t[0], t[1], t[2], X, Y, R2);
    mpq_set_d(q, m);
    if (e >= 0)
        mpq_mul_2exp(q, q, (mp_bitcnt_t)e);
    else
        mpq_div_2exp(q, q, (mp_bitcnt_t)-e);
    int r = q_cmp_sum_sqrt(Y, R2, q, z);
    mpq_clears(X, Y, R2, q, z, NULL);
    return r;
}

/* 1 if two circle events have equal tops; *same (if not NULL) is set
 * when their centres are the same point too. */
static int q_equal_tops(const double *const e1[3], const double *const e2[3],
                        int *same) {
    mpq_t X1, Y1, R1, X2, Y2, R2;
    mpq_inits(X1, Y1, R1, X2, Y2, R2, NULL);
    q_circle(e1[0], e1[1], e1[2], X1, Y1, R1);
    q_circle(e2[0], e2[1], e2[2], X2, Y2, R2);
    int eq = q_cmp_sum_sqrt(Y1, R1, Y2, R2) == 0;
    if (same) *same = eq && mpq_equal(X1, X2) != 0;
    mpq_clears(X1, Y1, R1, X2, Y2, R2, NULL);
    return eq;
}

/* Sweep order of two circle events: sign of (T1, X1) - (T2, X2). */
static int q_event_cmp(const double *const e1[3], const double *const e2[3]) {
    mpq_t X1, Y1, R1, X2, Y2, R2;
    mpq_inits(X1, Y1, R1, X2, Y2, R2, NULL);
    q_circle(e1[0], e1[1], e1[2], X1, Y1, R1);
    q_circle(e2[0], e2[1], e2[2], X2, Y2, R2);
    int r = q_cmp_sum_sqrt(Y1, R1, Y2, R2);
    if (r == 0) {
        r = mpq_cmp(X1, X2);
        r = (r > 0) - (r < 0);
    }
    mpq_clears(X1, Y1, R1, X2, Y2, R2, NULL);
    return r;
}

/* 1 if site s comes strictly before the event of a, b, c (circle first at
 * the same point). */
static int q_site_first(const double *s, const double *a, const double *b,
                        const double *c) {
    mpq_t X, Y, R2, sy, z;
    mpq_inits(X, Y, R2, sy, z, NULL);
    q_circle(a, b, c, X, Y, R2);
    mpq_set_d(sy, s[1]);
    int r = q_cmp_sum_sqrt(sy, z, Y, R2);
    if (r == 0) {
        mpq_set_d(sy, s[0]);
        r = mpq_cmp(sy, X) < 0 ? -1 : 1;
    }
    mpq_clears(X, Y, R2, sy, z, NULL);
    return r < 0;
}

/* Sign of |p-a|^2 (py - by) - |p-b|^2 (py - ay). */
static int q_bp_poly(const double *a, const double *b, const double *p) {
    mpq_t ux, uy, vx, vy, t, u;
    mpq_inits(ux, uy, vx, vy, t, u, NULL);
    mpq_set_d(ux, p[0]);
    mpq_set_d(t, a[0]);
    mpq_sub(ux, ux, t);
    mpq_set_d(uy, p[1]);
    mpq_set_d(t, a[1]);
    mpq_sub(uy, uy, t);
    mpq_set_d(vx, p[0]);
    mpq_set_d(t, b[0]);
    mpq_sub(vx, vx, t);
    mpq_set_d(vy, p[1]);
    mpq_set_d(t, b[1]);
    mpq_sub(vy, vy, t);
    mpq_mul(t, ux, ux);
    mpq_mul(u, uy, uy);
    mpq_add(t, t, u);
    mpq_mul(t, t, vy);
    mpq_mul(u, vx, vx);
    mpq_mul(ux, vy, vy);
    mpq_add(u, u, ux);
    mpq_mul(u, u, uy);
    int r = mpq_cmp(t, u);
    mpq_clears(ux, uy, vx, vy, t, u, NULL);
    return (r > 0) - (r < 0);
}

/* ---- Random points with many coincidences -------------------------------- */

/* One coordinate pair of kind k (see the switch); all exact doubles. */
static void random_point(vt_rng *r, int kind, double *p) {
    switch (kind) {
    case 0: /* small integers: ties and cocircularity everywhere */
        p[0] = (double)(long)(vt_next(r) % 9) - 4;
        p[1] = (double)(long)(vt_next(r) % 9) - 4;
        break;
    case 1: /* uniform */
        p[0] = vt_unit(r);
        p[1] = vt_unit(r);
        break;
    case 2: { /* nearly cocircular */
        double t = 6.283185307179586 * vt_unit(r);
        p[0] = cos(t);
        p[1] = sin(t);
        break;
    }
    case 3: /* a small integer moved by a few ulps */
        p[0] = (double)(long)(vt_next(r) % 5) - 2 +
               (double)(long)(vt_next(r) % 5 - 2) * 0x1p-52;
        p[1] = (double)(long)(vt_next(r) % 5) - 2 +
               (double)(long)(vt_next(r) % 5 - 2) * 0x1p-52;
        break;
    case 4: /* far from the origin, exactly representable steps */
        p[0] = 1e9 + (double)(long)(vt_next(r) % 9) * 0.125;
        p[1] = -1e9 + (double)(long)(vt_next(r) % 9) * 0.125;
        break;
    case 5: { /* small integers at an extreme scale (unsafe range) */
        int e = (int)(vt_next(r) % 1200) - 600;
        p[0] = ldexp((double)(long)(vt_next(r) % 9) - 4, e);
        p[1] = ldexp((double)(long)(vt_next(r) % 9) - 4, e);
        break;
    }
    case 6: /* x over a thousand binary orders, y in [0, 1) */
        p[0] = ldexp(1 + vt_unit(r), (int)(vt_next(r) % 1000) - 500);
        p[1] = vt_unit(r);
        break;
    default: /* both over two thousand orders, either sign */
        for (int k = 0; k < 2; k++)
            p[k] = ldexp(vt_unit(r) - 0.5, (int)(vt_next(r) % 2000) - 1000);
        break;
    }
}

#define KINDS 8

/* 1 if the point is inside the range that lets the filters skip their
 * range tests (as fortune.c establishes for its rescaled copy). */
static int in_safe_range(const double *p) {
    for (int k = 0; k < 2; k++) {
        double m = fabs(p[k]);
        if (m != 0 && (m < 0x1p-250 || m >= 2)) return 0;
    }
    return 1;
}

/* A triple with orient2d > 0 of kind k; 0 if the draw was collinear. */
static int random_triple(vt_rng *r, int kind, double t[3][2]) {
    for (int i = 0; i < 3; i++) random_point(r, kind, t[i]);
    int o = vor_orient2d(t[0], t[1], t[2]);
    if (o == 0) return 0;
    if (o < 0) {
        double s[2] = {t[1][0], t[1][1]};
        t[1][0] = t[2][0];
        t[1][1] = t[2][1];
        t[2][0] = s[0];
        t[2][1] = s[1];
    }
    return 1;
}

/* ---- Predicate tests ----------------------------------------------------- */

static void test_bp_poly(void **state) {
    (void)state;
    uint64_t seed = 101;
    print_message("bp_poly: seed %llu\n", (unsigned long long)seed);
    vt_rng r = {seed};
    for (int it = 0; it < 40000; it++) {
        int kind = it % KINDS;
        double a[2], b[2], p[2];
        random_point(&r, kind, a);
        random_point(&r, kind, b);
        random_point(&r, kind, p);
        int want = q_bp_poly(a, b, p);
        assert_int_equal(vor__fortune_bp_poly(a, b, p, 0), want);
        if (in_safe_range(a) && in_safe_range(b) && in_safe_range(p))
            assert_int_equal(vor__fortune_bp_poly(a, b, p, 1), want);
    }
    /* lattices far from the origin and in halves, many exact zeros (p
     * exactly below the breakpoint): the small integer path */
    int zeros = 0;
    for (int it = 0; it < 30000; it++) {
        double off = (double)(long)(vt_next(&r) % 2000000) - 1e6,
               unit = it % 2 ? 1.0 : 0.5;
        double a[2], b[2], p[2];
        for (int k = 0; k < 2; k++) {
            a[k] = off + unit * (double)(long)(vt_next(&r) % 9);
            b[k] = off + unit * (double)(long)(vt_next(&r) % 9);
            p[k] = off + unit * (double)(long)(vt_next(&r) % 9);
        }
        int want = q_bp_poly(a, b, p);
        zeros += want == 0;
        assert_int_equal(vor__fortune_bp_poly_slow(a, b, p), want);
    }
    print_message("bp_poly: %d exact zeros on lattices\n", zeros);
    assert_true(zeros > 1000);
    /* nearly mirror-image sites far below p, over hundreds of binary
     * orders (the wide-range filter's near ties, and its exact zeros) */
    for (int it = 0; it < 4000; it++) {
        int es = (int)(vt_next(&r) % 1200) - 600;
        int et = (int)(vt_next(&r) % 1200) - 600;
        int ep = (int)(vt_next(&r) % 1200) - 600;
        double sx = ldexp(1 + vt_unit(&r), es), ty = ldexp(vt_unit(&r), et);
        double nudge = (double)(long)(vt_next(&r) % 5) - 2;
        double a[2] = {sx, ty};
        double b[2] = {-sx * (1 + nudge * 0x1p-52), it % 3 ? ty : -ty};
        double p[2] = {it % 2 ? 0 : ldexp(1, es - 60), ldexp(1, ep)};
        if (it % 5 == 0) p[0] = ldexp(vt_unit(&r) - 0.5, es);
        int want = q_bp_poly(a, b, p);
        assert_int_equal(vor__fortune_bp_poly(a, b, p, 0), want);
        assert_int_equal(vor__fortune_bp_poly_slow(a, b, p), want);
    }
}

/* Two sites of equal y and a site p above them: the breakpoint is their
 * vertical bisector, and bp_side's own filter (the sign of 2 px - ax - bx)
 * must agree with F's everywhere: p near and at the midpoint, far above
 * (where F's filter fails) or just above, over hundreds of binary orders,
 * with the pair either way round. */
static void test_bp_side_equal_y(void **state) {
    (void)state;
    vt_rng r = {103};
    print_message("bp_side, equal y: seed 103\n");
    int zeros = 0, tests = 0;
    for (int it = 0; it < 20000; it++) {
        int es = (int)(vt_next(&r) % 1200) - 600;
        int eh = es + (int)(vt_next(&r) % 200) - 100;
        double ax = ldexp(vt_unit(&r) - 0.5, es);
        double bx = ax + ldexp(vt_unit(&r), es - (int)(vt_next(&r) % 60));
        double y = ldexp(vt_unit(&r) - 0.5, es);
        double py = y + ldexp(1 + vt_unit(&r), eh);
        if (!(bx > ax) || !(py > y)) continue;
        double mid = ax / 2 + bx / 2, nudge = (double)(long)(vt_next(&r) % 5) - 2;
        double px = it % 4 ? mid + nudge * fabs(mid) * 0x1p-52
                           : ldexp(vt_unit(&r) - 0.5, es);
        double a[2] = {ax, y}, b[2] = {bx, y}, p[2] = {px, py};
        for (int swap = 0; swap < 2; swap++) {
            const double *u = swap ? b : a, *v = swap ? a : b;
            int want = q_bp_poly(u, v, p);
            tests++;
            zeros += want == 0;
            assert_int_equal(vor__fortune_bp_side(u, v, p, 0), want);
            if (in_safe_range(a) && in_safe_range(b) && in_safe_range(p))
                assert_int_equal(vor__fortune_bp_side(u, v, p, 1), want);
        }
    }
    print_message("bp_side, equal y: %d tests, %d exactly at the midpoint\n",
                  tests, zeros);
    assert_true(tests > 20000 && zeros > 100);
}

/* The breakpoint predicate's meaning: a site exactly on a circle through
 * a and b that touches the sweep line at it is "on" the breakpoint. */
static void test_bp_side_on_circle(void **state) {
    (void)state;
    /* centre (0, 5), radius 5: through a = (0, 0) and b = (3, 1), touching
     * y = 10 at p = (0, 10); a is lower, so (a, b) is the left meeting point
     * of their arcs and p, left of b, lies exactly below it */
    const double a[2] = {0, 0}, b[2] = {3, 1}, p[2] = {0, 10};
    assert_int_equal(vor__fortune_bp_side(a, b, p, 1), 0);
    assert_int_equal(vor__fortune_bp_side(a, b, p, 0), 0);
    /* the other meeting point (b, a) is to the right of b */
    assert_int_equal(vor__fortune_bp_side(b, a, p, 1), -1);
    const double left[2] = {-0.5, 10}, right[2] = {0.5, 10};
    assert_int_equal(vor__fortune_bp_side(a, b, left, 1), -1);
    assert_int_equal(vor__fortune_bp_side(a, b, right, 1), 1);
    /* equal y: the vertical bisector */
    const double c[2] = {2, 0}, m[2] = {1, 7}, m2[2] = {1 + 0x1p-52, 7};
    assert_int_equal(vor__fortune_bp_side(a, c, m, 1), 0);
    assert_int_equal(vor__fortune_bp_side(a, c, m2, 1), 1);
}

/* The top of the circle through t lies within err of th + tl, exactly. */
/* Puts triple t in counter-clockwise order, swapping its first two points
 * if needed; 0 if it is collinear. */
static int make_ccw(double t[3][2]) {
    int o = vor_orient2d(t[0], t[1], t[2]);
    if (o < 0) {
        double sw[2] = {t[0][0], t[0][1]};
        t[0][0] = t[1][0], t[0][1] = t[1][1];
        t[1][0] = sw[0], t[1][1] = sw[1];
    }
    return o != 0;
}

/* vor__fortune_off_cmp against the exact comparison: pairs of triples of
 * two close sites of a row and a site of the next (the events over a
 * row), rows at y from 2^-30 to 2^40 and as far as 2^600 (past the safe
 * range) with x jittered by a few ulps; the second triple of each pair
 * moved along x by an exact step, its y left or moved by an ulp or a
 * row, and its shape kept, jittered, or taken from another row. A
 * decision must be the exact order of the tops (which then differ), and
 * a translate along x, whose top is the same, must stay undecided. Of
 * the pairs an ulp of y apart whose float intervals overlap, most must be
 * decided (65%; the tops of those an ulp of x apart are mostly closer
 * than the heights' errors). */
static void test_off_cmp(void **state) {
    (void)state;
    vt_rng r = {97};
    print_message("off_cmp: seed 97\n");
    vor__fortune_ws *ws = vor__fortune_ws_new();
    assert_non_null(ws);
    /* kind 2 (y moved by an ulp): pairs whose intervals overlap, and
     * how many of them were decided */
    int overlap = 0, decided = 0, same = 0;
    for (int it = 0; it < 40000; it++) {
        int far = it % 8 == 7;
        double y0 = ldexp(1.0 + (double)(vt_next(&r) % 1000) / 1000.0,
                          far ? 600 : (int)(vt_next(&r) % 70) - 30);
        double unit = ldexp(1.0, far ? 590 : -10);
        double dx = unit * ldexp(1.0 + vt_unit(&r), -(int)(vt_next(&r) % 12));
        double x0 = unit * (double)(vt_next(&r) % 1000);
        double side = vt_next(&r) % 2 ? unit : -unit;
        double t1[3][2] = {{x0, y0},
                           {x0 + dx, y0},
                           {x0 + dx * (2 * vt_unit(&r) - 0.5), y0 + side}};
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 2; j++)
                if (vt_next(&r) % 4 == 0)
                    t1[k][j] = nextafter(t1[k][j], vt_next(&r) % 2 ? INFINITY
                                                                   : -INFINITY);
        if (!make_ccw(t1)) continue;
        int kind = (int)(vt_next(&r) % 4);
        double step = unit * (double)(1 + vt_next(&r) % 64), t2[3][2];
        for (int k = 0; k < 3; k++) {
            t2[k][0] = t1[k][0] + step;
            t2[k][1] = t1[k][1];
            if (kind == 1 && vt_next(&r) % 2)
                t2[k][0] = nextafter(t2[k][0], INFINITY);
            if (kind == 2) t2[k][1] = nextafter(t1[k][1], INFINITY);
            if (kind == 3) t2[k][1] = t1[k][1] + side;
        }
        if (!make_ccw(t2)) continue;
        /* a translate only if every moved coordinate is exact */
        int translate = kind == 0;
        for (int k = 0; k < 3 && translate; k++)
            translate = t2[k][0] - step == t1[k][0];
        for (int safe = 0; safe < 2; safe++) {
            if (safe && far) continue;
            double lo1, hi1, lo2, hi2, o1[2], o2[2];
            if (vor__fortune_circle_top_off(t1[0], t1[1], t1[2], safe, &lo1,
                                            &hi1, o1) != 1 ||
                vor__fortune_circle_top_off(t2[0], t2[1], t2[2], safe, &lo2,
                                            &hi2, o2) != 1)
                continue;
            int c, got = vor__fortune_off_cmp(t1[0][1], o1, t2[0][1], o2, &c);
            int ov = kind == 2 && !(hi1 < lo2 || hi2 < lo1);
            overlap += ov;
            if (translate) {
                same++;
                assert_int_equal(got, 0);
                continue;
            }
            if (!got) continue;
            decided += ov;
            int e = vor__fortune_circle_cmp_exact(t1[0], t1[1], t1[2], t2[0],
                                                  t2[1], t2[2], ws);
            assert_int_equal(c, e);
        }
    }
    vor__fortune_ws_free(ws);
    print_message("off_cmp: %d translates undecided; a row an ulp higher: "
                  "%d of %d overlapping intervals decided\n", same, decided,
                  overlap);
    assert_true(same > 1000);
    assert_true(decided > overlap / 2);
}

/* u = triple t with its points rotated by rot places. */
static void rotated(double u[3][2], double t[3][2], int rot) {
    for (int k = 0; k < 3; k++) {
        u[k][0] = t[(k + rot) % 3][0];
        u[k][1] = t[(k + rot) % 3][1];
    }
}

/* vor__fortune_circle_top of the counter-clockwise triple u in range mode
 * safe: 0 where the mode does not apply (sites outside the safe range) or
 * the interval is unbounded; else 1 with [*lo, *hi], which must hold the
 * exact top (GMP). */
static int top_checked(double u[3][2], int safe, double *lo, double *hi) {
    if (safe &&
        !(in_safe_range(u[0]) && in_safe_range(u[1]) && in_safe_range(u[2])))
        return 0;
    assert_int_equal(vor__fortune_circle_top(u[0], u[1], u[2], safe, lo, hi),
                     1);
    if (!isfinite(*lo)) return 0;
    if (q_top_vs(u[0], u[1], u[2], *lo) < 0 ||
        q_top_vs(u[0], u[1], u[2], *hi) > 0)
        fail_msg("[%a, %a] misses the top of (%a, %a) (%a, %a) (%a, %a)", *lo,
                 *hi, u[0][0], u[0][1], u[1][0], u[1][1], u[2][0], u[2][1]);
    return 1;
}

static void check_dd_top(double t[3][2], double th, double tl, double err) {
    mpq_t X, Y, R2, c, e, z;
    mpq_inits(X, Y, R2, c, e, z, NULL);
    q_circle(t[0], t[1], t[2], X, Y, R2);
    mpq_set_d(c, th);
    mpq_set_d(e, tl);
    mpq_add(c, c, e);
    mpq_set_d(e, err);
    mpq_sub(c, c, e); /* lower end */
    assert_true(q_cmp_sum_sqrt(Y, R2, c, z) >= 0);
    mpq_add(c, c, e);
    mpq_add(c, c, e); /* upper end */
    assert_true(q_cmp_sum_sqrt(Y, R2, c, z) <= 0);
    mpq_clears(X, Y, R2, c, e, z, NULL);
}

static void test_circle_top_bounds(void **state) {
    (void)state;
    uint64_t seed = 202;
    print_message("circle_top: seed %llu\n", (unsigned long long)seed);
    vt_rng r = {seed};
    int finite = 0, dd_ok = 0, n_tight = 0, n_beyond = 0, triples = 0,
        n_offset = 0;
    for (int it = 0; it < 40000; it++) {
        double t[3][2];
        if (!random_triple(&r, it % KINDS, t)) continue;
        triples++;
        /* the interval from the exact circle: it holds the top and is
         * under 2^-43 of it wide wherever the top lies within the doubles
         * (a top near 0 under a site far below included) */
        double tlo, thi, key[2];
        int k = vor__fortune_circle_top_tight(t[0], t[1], t[2], &tlo, &thi,
                                              key);
        if (k == 2) {
            /* past the doubles: a key within 2^-45 of the top */
            n_tight++;
            n_beyond++;
            assert_true(q_top_vs(t[0], t[1], t[2], DBL_MAX) > 0);
            assert_true(q_top_vs_2exp(t, key[0] * (1 - 0x1p-44), key[1]) >= 0);
            assert_true(q_top_vs_2exp(t, key[0] * (1 + 0x1p-44), key[1]) <= 0);
        } else if (k == 1) {
            n_tight++;
            assert_true(q_top_vs(t[0], t[1], t[2], tlo) >= 0);
            assert_true(q_top_vs(t[0], t[1], t[2], thi) <= 0);
            double top = fabs(tlo) > fabs(thi) ? fabs(tlo) : fabs(thi);
            if (!(thi - tlo <= 0x1p-43 * top + 0x1p-1050))
                fail_msg("tight interval [%a, %a] of (%a, %a) (%a, %a) "
                         "(%a, %a)", tlo, thi, t[0][0], t[0][1], t[1][0],
                         t[1][1], t[2][0], t[2][1]);
        }
        for (int safe = 0; safe < 2; safe++) {
            if (safe && !(in_safe_range(t[0]) && in_safe_range(t[1]) &&
                          in_safe_range(t[2])))
                continue;
            double lo, hi;
            double m[3][2] = {{t[0][0], t[0][1]}, {t[2][0], t[2][1]},
                              {t[1][0], t[1][1]}};
            assert_int_equal(
                vor__fortune_circle_top(m[0], m[1], m[2], safe, &lo, &hi), -1);
            assert_int_equal(
                vor__fortune_circle_top(t[0], t[1], t[2], safe, &lo, &hi), 1);
            assert_true(lo <= hi);
            if (isfinite(lo)) {
                finite++;
                assert_true(q_top_vs(t[0], t[1], t[2], lo) >= 0);
                assert_true(q_top_vs(t[0], t[1], t[2], hi) <= 0);
            }
        }
        double th, tl, err;
        if (in_safe_range(t[0]) && in_safe_range(t[1]) && in_safe_range(t[2]) &&
            vor__fortune_circle_top_dd(t[0], t[1], t[2], &th, &tl, &err)) {
            dd_ok++;
            check_dd_top(t, th, tl, err);
        }
        /* bounds relative to the highest site: they hold the top, their
         * base is that site's y, and they are within 2^-45 of the offset
         * above it */
        if (vor__fortune_circle_offset(t[0], t[1], t[2], &th, &tl, &err)) {
            n_offset++;
            check_dd_top(t, th, tl, err);
            assert_true(th == fmax(t[0][1], fmax(t[1][1], t[2][1])));
            assert_true(tl >= 0 && err <= 0x1p-45 * tl + 0x1p-1059);
        }
    }
    print_message("circle_top: %d of %d offset bounds\n", n_offset, triples);
    assert_true(n_offset > triples - triples / 16);
    /* the filters must be useful, not just safe; the tight interval is
     * missing only for tops beyond the doubles (kind 7: sites 2^1000
     * apart in a nearly collinear triple) */
    assert_true(finite > 20000);
    assert_true(dd_ok > 10000);
    print_message("circle_top: %d of %d tight intervals, %d of them keys "
                  "past the doubles\n", n_tight, triples, n_beyond);
    assert_true(n_beyond > 100);
    assert_true(n_tight > triples - triples / 16);

    /* consecutive sites of a circle, rounded: nearly collinear triples,
     * mostly with exact differences (the accurate orientation), some
     * across an axis (without); radii from 2^-20 to 2^19 */
    int tight = 0, tried = 0;
    for (int it = 0; it < 20000; it++) {
        double rad = ldexp(1.0, (int)(vt_next(&r) % 40) - 20);
        double n = 1000.0 * (double)(1 + vt_next(&r) % 10000);
        double i0 = (double)(vt_next(&r) % (uint64_t)n), t[3][2];
        for (int k = 0; k < 3; k++) {
            double a = 6.283185307179586 * (i0 + k) / n;
            t[k][0] = rad * cos(a);
            t[k][1] = rad * sin(a);
        }
        int want = vor_orient2d(t[0], t[1], t[2]);
        for (int safe = 0; safe < 2; safe++) {
            if (safe && !(in_safe_range(t[0]) && in_safe_range(t[1]) &&
                          in_safe_range(t[2])))
                continue;
            double lo, hi;
            int o = vor__fortune_circle_top(t[0], t[1], t[2], safe, &lo, &hi);
            assert_int_equal(o, want);
            if (o <= 0 || !isfinite(lo)) continue;
            tried++;
            tight += hi - lo <= 0x1p-40 * fabs(lo);
            assert_true(q_top_vs(t[0], t[1], t[2], lo) >= 0);
            assert_true(q_top_vs(t[0], t[1], t[2], hi) <= 0);
        }
    }
    print_message("circle_top: %d of %d intervals on circles within "
                  "2^-40 relative\n", tight, tried);
    assert_true(tight > tried * 9 / 10);

    /* two close sites of one row and a site of the next, above or below:
     * the centre is nearly below or above the pair, its x error large
     * (nx cancels) but of little weight in the top */
    tight = tried = 0;
    int dd_tried = 0;
    for (int it = 0; it < 20000; it++) {
        double gap = ldexp(1.0, (int)(vt_next(&r) % 40) - 20);
        double y0 = gap * (double)(vt_next(&r) % 1000);
        double x0 = gap * ((double)(vt_next(&r) % 1000000) / 1000.0);
        double dx = gap * ldexp(1.0 + (double)(vt_next(&r) % 1000) / 1000.0,
                                -(int)(vt_next(&r) % 30) - 3);
        double side = vt_next(&r) % 2 ? gap : -gap;
        double t[3][2] = {{x0, y0},
                          {x0 + dx, y0},
                          {x0 + dx * ((double)(vt_next(&r) % 200) / 100.0 - 0.5),
                           y0 + side}};
        if (!make_ccw(t)) continue; /* converging order */
        /* each rotation, the lone site first among them (the sweep
         * meets all three) */
        for (int rot = 0; rot < 3; rot++) {
            double u[3][2];
            rotated(u, t, rot + 2);
            for (int safe = 0; safe < 2; safe++) {
                double lo, hi;
                if (!top_checked(u, safe, &lo, &hi)) continue;
                tried++;
                tight += hi - lo <= 0x1p-40 * fabs(lo) + 0x1p-1000;
            }
        }
        double th, tl, err;
        double v[3][2] = {{t[2][0], t[2][1]}, {t[0][0], t[0][1]},
                          {t[1][0], t[1][1]}};
        if (in_safe_range(v[0]) && in_safe_range(v[1]) && in_safe_range(v[2]) &&
            vor__fortune_circle_top_dd(v[0], v[1], v[2], &th, &tl, &err)) {
            dd_tried++;
            check_dd_top(v, th, tl, err);
        }
    }
    print_message("circle_top: %d of %d intervals on rows within "
                  "2^-40 relative, %d double-double\n", tight, tried,
                  dd_tried);
    assert_true(tight > tried * 9 / 10);
    assert_true(dd_tried > 5000);

    /* two sites of a row and the one between them on the next, of grids of
     * decimal spacing, some moved off the middle by a few ulps or more:
     * tops above the apex by 10^-33 of themselves or less, which only
     * the level form of the double-double bounds separates */
    int near = 0, level = 0;
    for (int it = 0; it < 20000; it++) {
        /* spacings of two decimals, scaled into the safe range by powers
         * of two; every eighth grid flat (rows 2^-200 apart) */
        double sx = 0x1p-17 * 0.01 * (double)(1 + vt_next(&r) % 100),
               sy = ldexp(0.01 * (double)(1 + vt_next(&r) % 100),
                          it % 8 == 7 ? -200 : -10);
        double i = (double)(vt_next(&r) % 100000),
               j = (double)(vt_next(&r) % 1000);
        int span = 1 + (int)(vt_next(&r) % 3);
        double t[3][2] = {{sx * i, sy * j},
                          {sx * (i + 2 * span), sy * j},
                          {sx * (i + span), sy * (j + 1)}};
        if (it % 4 == 1) /* off the middle by some ulps */
            t[2][0] = nextafter(nextafter(t[2][0], 0), 0);
        else if (it % 4 == 2) /* farther: the usual bounds win */
            t[2][0] += sx * 0.3;
        else if (it % 4 == 3) /* the apex below: no level form */
            t[2][1] = sy * (j - 1);
        (void)make_ccw(t);
        for (int rot = 0; rot < 3; rot++) {
            double u[3][2];
            rotated(u, t, rot);
            double th, tl, err;
            assert_true(in_safe_range(u[0]) && in_safe_range(u[1]) &&
                        in_safe_range(u[2]));
            if (!vor__fortune_circle_top_dd(u[0], u[1], u[2], &th, &tl, &err))
                continue;
            check_dd_top(u, th, tl, err);
            if (it % 4 < 2) {
                near++;
                level += err < 0x1p-110 * fabs(th);
            }
        }
    }
    print_message("circle_top: %d of %d nearly isosceles tops within 2^-110 "
                  "relative\n", level, near);
    assert_true(level > near * 9 / 10);
}

/* Thin triangles, whose orientation vor__fortune_circle_top refines and
 * whose top it then bounds step by step (refined_err in
 * fortune_predicates.c): consecutive sites (or every few) of circles of
 * radius 2^-20 to 2^19 about centres at the origin, nearby (some
 * differences rounded) or far away (coordinates of large magnitude), some
 * sites moved by an ulp or two, and sites nearly on a line in any
 * direction. Each interval must hold the exact top (GMP), in each
 * rotation of the triple and both ranges; on circles about the origin,
 * where the differences are exact, it must also be within 2^-46 of the
 * top (64 ulps; the general bound gave about 400). */
static void test_circle_top_refined(void **state) {
    (void)state;
    uint64_t seed = 212;
    print_message("circle_top_refined: seed %llu\n", (unsigned long long)seed);
    vt_rng r = {seed};
    int tried = 0, narrow = 0, centred = 0;
    for (int it = 0; it < 24000; it++) {
        int kind = it % 4;
        double rad = ldexp(1.0, (int)(vt_next(&r) % 40) - 20), t[3][2];
        if (kind < 3) {
            double n = 100.0 * (double)(1 + vt_next(&r) % 100000);
            double i0 = (double)(vt_next(&r) % (uint64_t)n);
            double step = (double)(1 + vt_next(&r) % 4);
            double ox = 0, oy = 0;
            if (kind == 1) { /* nearby: some differences rounded */
                ox = rad * (vt_unit(&r) * 8 - 4);
                oy = rad * (vt_unit(&r) * 8 - 4);
            } else if (kind == 2) { /* far: large coordinates */
                ox = rad * ldexp(vt_unit(&r) - 0.5, 20);
                oy = rad * ldexp(vt_unit(&r) - 0.5, 20);
            }
            for (int k = 0; k < 3; k++) {
                double a = 6.283185307179586 * (i0 + step * k) / n;
                t[k][0] = ox + rad * cos(a);
                t[k][1] = oy + rad * sin(a);
                if (kind > 0 && vt_next(&r) % 4 == 0) { /* an ulp or two off */
                    int c = (int)(vt_next(&r) % 2);
                    double to = vt_next(&r) % 2 ? 1e300 : -1e300;
                    t[k][c] = nextafter(t[k][c], to);
                    if (vt_next(&r) % 2) t[k][c] = nextafter(t[k][c], to);
                }
            }
        } else { /* nearly on a line through a random point */
            double px = rad * (vt_unit(&r) - 0.5),
                   py = rad * (vt_unit(&r) - 0.5);
            double th = 6.283185307179586 * vt_unit(&r);
            double gap = rad * ldexp(1.0, -(int)(vt_next(&r) % 30));
            double off =
                gap * ldexp(vt_unit(&r) - 0.5, -(int)(vt_next(&r) % 20));
            double s[3] = {0, gap * (1 + vt_unit(&r)),
                           gap * (2 + 2 * vt_unit(&r))};
            for (int k = 0; k < 3; k++) {
                t[k][0] = px + s[k] * cos(th) - (k == 1) * off * sin(th);
                t[k][1] = py + s[k] * sin(th) + (k == 1) * off * cos(th);
            }
        }
        if (!make_ccw(t)) continue;
        for (int rot = 0; rot < 3; rot++) {
            double u[3][2];
            rotated(u, t, rot);
            for (int safe = 0; safe < 2; safe++) {
                double lo, hi;
                if (!top_checked(u, safe, &lo, &hi)) continue;
                tried++;
                if (kind == 0) {
                    centred++;
                    narrow += hi - lo <= 0x1p-46 * fabs(hi);
                }
            }
        }
    }
    print_message("circle_top_refined: %d intervals hold their tops; %d of "
                  "%d on circles about the origin within 2^-46\n", tried,
                  narrow, centred);
    assert_true(tried > 100000);
    assert_true(narrow > centred * 9 / 10);
}

static void test_site_first(void **state) {
    (void)state;
    uint64_t seed = 303;
    print_message("site_first: seed %llu\n", (unsigned long long)seed);
    vt_rng r = {seed};
    int small = 0;
    for (int it = 0; it < 20000; it++) {
        int kind = it % KINDS;
        double t[3][2], s[2];
        if (!random_triple(&r, kind, t)) continue;
        random_point(&r, kind, s);
        int want = q_site_first(s, t[0], t[1], t[2]);
        assert_int_equal(vor__fortune_site_first_exact(s, t[0], t[1], t[2]),
                         want);
        int sm = vor__fortune_site_first_small(s, t[0], t[1], t[2]);
        if (sm >= 0) {
            small++;
            assert_int_equal(sm, want);
        }
    }
    /* lattice triples anywhere in a large window, sites at and near the
     * tops of their circles (the small integer path's home) */
    for (int it = 0; it < 20000; it++) {
        double t[3][2], s[2];
        long ox = (long)(vt_next(&r) % 4000) - 2000,
             oy = (long)(vt_next(&r) % 4000) - 2000;
        for (int i = 0; i < 3; i++) {
            t[i][0] = (double)(ox + (long)(vt_next(&r) % 41) - 20);
            t[i][1] = (double)(oy + (long)(vt_next(&r) % 41) - 20);
        }
        int o = vor_orient2d(t[0], t[1], t[2]);
        if (o == 0) continue;
        if (o < 0) {
            double sw[2] = {t[1][0], t[1][1]};
            memcpy(t[1], t[2], sizeof sw);
            memcpy(t[2], sw, sizeof sw);
        }
        s[0] = (double)(ox + (long)(vt_next(&r) % 61) - 30);
        s[1] = (double)(oy + (long)(vt_next(&r) % 61) - 30);
        if (it % 3 == 0) { /* on the circle's top row, if it has one */
            mpq_t X, Y, R2;
            mpq_inits(X, Y, R2, NULL);
            q_circle(t[0], t[1], t[2], X, Y, R2);
            s[1] = floor(mpq_get_d(Y) + sqrt(mpq_get_d(R2)) + 0.5);
            mpq_clears(X, Y, R2, NULL);
        }
        int want = q_site_first(s, t[0], t[1], t[2]);
        int sm = vor__fortune_site_first_small(s, t[0], t[1], t[2]);
        assert_true(sm >= 0);
        small++;
        assert_int_equal(sm, want);
        assert_int_equal(vor__fortune_site_first_exact(s, t[0], t[1], t[2]),
                         want);
    }
    print_message("site_first: %d decided by small integers\n", small);
    assert_true(small > 20000);
    /* subnormal coordinates beside normal ones (the exact stage reads the
     * doubles' bits: a subnormal's unit is 2^-1074) */
    int mixed = 0;
    for (int it = 0; it < 5000; it++) {
        double t[3][2], s[2], *v[8] = {t[0], t[0] + 1, t[1], t[1] + 1,
                                       t[2], t[2] + 1, s, s + 1};
        for (int k = 0; k < 8; k++) { /* 2^-1022 is the least normal */
            double m = (double)((long)(vt_next(&r) % 2001) - 1000);
            *v[k] = ldexp(m, -1074) + (vt_next(&r) % 2 ? 0x1p-1022 : 0);
        }
        if (!make_ccw(t)) continue;
        assert_int_equal(vor__fortune_site_first_exact(s, t[0], t[1], t[2]),
                         q_site_first(s, t[0], t[1], t[2]));
        mixed++;
    }
    assert_true(mixed > 1000);
    /* sites exactly at the top of integer circles, and beside it */
    const double a[2] = {-4, -3}, b[2] = {0, -5}, c[2] = {4, -3};
    const double top[2] = {0, 5}, l[2] = {-1, 5}, rr[2] = {1, 5};
    assert_int_equal(vor__fortune_site_first_exact(top, a, b, c), 0);
    assert_int_equal(vor__fortune_site_first_exact(l, a, b, c), 1);
    assert_int_equal(vor__fortune_site_first_exact(rr, a, b, c), 0);
    for (int x = -5; x <= 5; x++)
        for (int y = -5; y <= 5; y++) {
            double p[2] = {x, y};
            int want = q_site_first(p, a, b, c);
            assert_int_equal(vor__fortune_site_first_exact(p, a, b, c), want);
        }
}

/* The circle c = {x, y, r^2} of triple t, said to be exact, must be the
 * rational one (GMP). */
static void check_exact_circle(double t[3][2], const double *c) {
    mpq_t X, Y, R2, q;
    mpq_inits(X, Y, R2, q, NULL);
    q_circle(t[0], t[1], t[2], X, Y, R2);
    mpq_set_d(q, c[0]);
    assert_true(mpq_equal(q, X));
    mpq_set_d(q, c[1]);
    assert_true(mpq_equal(q, Y));
    mpq_set_d(q, c[2]);
    assert_true(mpq_equal(q, R2));
    mpq_clears(X, Y, R2, q, NULL);
}

/* The small lattice's circle (vor__fortune_circle_exact_small) within its
 * precondition: coordinates m 2^k, |m| < 2^16, k from -300 to 40, spread
 * over the whole range or near one point, the extremes +-(2^16 - 1)
 * included. It must give what vor__fortune_circle_exact_double gives, bit
 * for bit, and its exact circles must be the circle (GMP). */
static void test_circle_exact_small(void **state) {
    (void)state;
    uint64_t seed = 317;
    print_message("circle_exact_small: seed %llu\n", (unsigned long long)seed);
    vt_rng r = {seed};
    const int ks[] = {-300, -15, -3, 0, 7, 40};
    int n_exact = 0, n = 0;
    for (int it = 0; it < 60000; it++) {
        int k = ks[it % 6];
        long lim = (1L << 16) - 1, span = it % 3 == 0 ? lim : 20;
        long o[2] = {0, 0};
        if (span < lim)
            for (int a = 0; a < 2; a++)
                o[a] = (long)(vt_next(&r) % (uint64_t)(2 * (lim - span) + 1)) -
                       (lim - span);
        double t[3][2];
        for (int i = 0; i < 3; i++)
            for (int a = 0; a < 2; a++) {
                long m = o[a] + (long)(vt_next(&r) % (uint64_t)(2 * span + 1)) -
                         span;
                if (vt_next(&r) % 16 == 0) m = vt_next(&r) % 2 ? lim : -lim;
                t[i][a] = ldexp((double)m, k);
            }
        if (!make_ccw(t)) continue;
        n++;
        double c1[3] = {0, 0, 0}, c2[3] = {0, 0, 0};
        int g1 = vor__fortune_circle_exact_small(t[0], t[1], t[2], c1);
        int g2 = vor__fortune_circle_exact_double(t[0], t[1], t[2], c2);
        assert_int_equal(g1, g2);
        if (!g1) continue;
        assert_memory_equal(c1, c2, sizeof c1);
        n_exact++;
        check_exact_circle(t, c1);
    }
    print_message("circle_exact_small: %d of %d circles exact in doubles\n",
                  n_exact, n);
    assert_true(n_exact > n / 20);
}

/* Tops known exactly (vor__fortune_exact_top): for lattice triples, at
 * integer scale and scaled by powers of two, whose circles are exact in
 * doubles, the top is reported iff the squared radius is a rational
 * square, and then equals y + r exactly; and the order of two such tops
 * by (hi, lo) is the exact order. */
static void test_exact_top(void **state) {
    (void)state;
    uint64_t seed = 313;
    print_message("exact_top: seed %llu\n", (unsigned long long)seed);
    vt_rng r = {seed};
    enum { KEEP = 4000 };
    static double kept[KEEP][3][2];
    int n_exact = 0, n_top = 0, n_kept = 0;
    mpq_t X, Y, R2, Y2, X2, R22, q, z;
    mpq_inits(X, Y, R2, Y2, X2, R22, q, z, NULL);
    for (int it = 0; it < 40000; it++) {
        double t[3][2], c[3], hi, lo;
        double scale = ldexp(1.0, (int)(vt_next(&r) % 41) - 20);
        long ox = (long)(vt_next(&r) % 2000) - 1000,
             oy = (long)(vt_next(&r) % 2000) - 1000;
        for (int i = 0; i < 3; i++) {
            t[i][0] = (double)(ox + (long)(vt_next(&r) % 21) - 10) * scale;
            t[i][1] = (double)(oy + (long)(vt_next(&r) % 21) - 10) * scale;
        }
        int o = vor_orient2d(t[0], t[1], t[2]);
        if (o == 0) continue;
        if (o < 0) {
            double sw[2] = {t[1][0], t[1][1]};
            memcpy(t[1], t[2], sizeof sw);
            memcpy(t[2], sw, sizeof sw);
        }
        if (!vor__fortune_circle_exact_double(t[0], t[1], t[2], c)) continue;
        n_exact++;
        q_circle(t[0], t[1], t[2], X, Y, R2);
        int square = mpz_perfect_square_p(mpq_numref(R2)) &&
                     mpz_perfect_square_p(mpq_denref(R2));
        int got = vor__fortune_exact_top(c, &hi, &lo);
        assert_int_equal(got, square);
        if (!got) continue;
        n_top++;
        /* Y + sqrt(R2) - (hi + lo) = 0 */
        mpq_set_d(q, hi);
        mpq_set_d(z, lo);
        mpq_add(q, q, z);
        mpq_set_ui(z, 0, 1);
        assert_int_equal(q_cmp_sum_sqrt(Y, R2, q, z), 0);
        if (n_kept < KEEP) memcpy(kept[n_kept++], t, sizeof t);
    }
    print_message("exact_top: %d of %d exact circles have exact tops\n",
                  n_top, n_exact);
    assert_true(n_top > 200);
    /* pairs of kept triples, and each with a translate along x (equal
     * tops): the order of (hi, lo) against the exact one */
    int equal = 0;
    for (int i = 0; i + 1 < n_kept; i++) {
        double (*a)[2] = kept[i], b[3][2], ca[3], cb[3], ha, la, hb, lb;
        memcpy(b, i % 2 ? kept[i + 1] : kept[i], sizeof b);
        const double dx = 7 * fabs(b[0][0] - b[1][0]);
        if (i % 2 == 0)
            for (int k = 0; k < 3; k++) b[k][0] += dx;
        assert_true(vor__fortune_circle_exact_double(a[0], a[1], a[2], ca));
        if (!vor__fortune_circle_exact_double(b[0], b[1], b[2], cb)) continue;
        assert_true(vor__fortune_exact_top(ca, &ha, &la));
        assert_true(vor__fortune_exact_top(cb, &hb, &lb));
        int got = ha != hb ? (ha < hb ? -1 : 1) : (la > lb) - (la < lb);
        q_circle(a[0], a[1], a[2], X, Y, R2);
        q_circle(b[0], b[1], b[2], X2, Y2, R22);
        assert_int_equal(got, q_cmp_sum_sqrt(Y, R2, Y2, R22));
        equal += got == 0;
    }
    print_message("exact_top: %d pairs of equal tops\n", equal);
    assert_true(equal > n_kept / 4);
    mpq_clears(X, Y, R2, Y2, X2, R22, q, z, NULL);
}

static void test_circle_cmp(void **state) {
    (void)state;
    uint64_t seed = 404;
    print_message("circle_cmp: seed %llu\n", (unsigned long long)seed);
    vt_rng r = {seed};
    vor__fortune_ws *ws = vor__fortune_ws_new();
    assert_non_null(ws);
    int equal = 0, dd_decided = 0, small = 0;
    int tried[3] = {0, 0, 0}, found[3] = {0, 0, 0}; /* by kind made */
    for (int it = 0; it < 20000; it++) {
        int kind = it % KINDS;
        double t1[3][2], t2[3][2];
        if (!random_triple(&r, kind, t1) || !random_triple(&r, kind, t2))
            continue;
        int made = 0; /* 1 a translate, 2 a mirror image's */
        if (it % 7 == 0 || it % 7 == 3 || it % 7 == 5) {
            /* a translate, horizontal (equal tops) or not, its vertices
             * rotated, or (5) of its mirror image, the order reversed;
             * kept where the rounding left it one */
            double dx = (double)(long)(vt_next(&r) % 7) - 3, t3[3][2];
            double dy = it % 7 == 3 ? 0.001 * (double)(vt_next(&r) % 5) : 0;
            int rot = (int)(vt_next(&r) % 3), exact = 1, mirror = it % 7 == 5;
            for (int i = 0; i < 3; i++) {
                double *v = t3[mirror ? (3 - i + rot) % 3 : (i + rot) % 3];
                double x = mirror ? -t1[i][0] : t1[i][0];
                v[0] = x + dx;
                v[1] = t1[i][1] + dy;
                exact &= v[0] - dx == x && v[0] - x == dx;
                exact &= v[1] - dy == t1[i][1] && v[1] - t1[i][1] == dy;
            }
            if (exact) memcpy(t2, t3, sizeof t3);
            made = exact ? 1 + mirror : 0;
        }
        const double *e1[3] = {t1[0], t1[1], t1[2]},
                     *e2[3] = {t2[0], t2[1], t2[2]};
        int want = q_event_cmp(e1, e2);
        int safe_pair = in_safe_range(t1[0]) && in_safe_range(t1[1]) &&
                        in_safe_range(t1[2]) && in_safe_range(t2[0]) &&
                        in_safe_range(t2[1]) && in_safe_range(t2[2]);
        equal += want == 0;
        assert_int_equal(vor__fortune_circle_cmp_exact(t1[0], t1[1], t1[2],
                                                       t2[0], t2[1], t2[2], ws),
                         want);
        int res;
        if (vor__fortune_circle_cmp_small(t1[0], t1[1], t1[2], t2[0], t2[1],
                                          t2[2], &res)) {
            small++;
            assert_int_equal(res, want);
        }
        double h1, l1, r1, h2, l2, r2;
        if (in_safe_range(t1[0]) && in_safe_range(t1[1]) &&
            in_safe_range(t1[2]) && in_safe_range(t2[0]) &&
            in_safe_range(t2[1]) && in_safe_range(t2[2]) &&
            vor__fortune_circle_top_dd(t1[0], t1[1], t1[2], &h1, &l1, &r1) &&
            vor__fortune_circle_top_dd(t2[0], t2[1], t2[2], &h2, &l2, &r2)) {
            int c = vor__fortune_dd_cmp(h1, l1, r1, h2, l2, r2);
            if (c != 0) {
                dd_decided++;
                /* the dd order is that of the tops' y alone */
                mpq_t X1, Y1, R1, X2, Y2, R2;
                mpq_inits(X1, Y1, R1, X2, Y2, R2, NULL);
                q_circle(t1[0], t1[1], t1[2], X1, Y1, R1);
                q_circle(t2[0], t2[1], t2[2], X2, Y2, R2);
                assert_int_equal(q_cmp_sum_sqrt(Y1, R1, Y2, R2), c);
                mpq_clears(X1, Y1, R1, X2, Y2, R2, NULL);
            }
        }
        double c1[3], c2[3];
        if (vor__fortune_circle_exact_double(t1[0], t1[1], t1[2], c1)) {
            check_exact_circle(t1, c1);
            if (vor__fortune_circle_exact_double(t2[0], t2[1], t2[2], c2) &&
                c1[1] == c2[1] && c1[2] == c2[2])
                assert_int_equal(want, c1[0] < c2[0] ? -1 : c1[0] > c2[0]);
        }
        if (vor__fortune_translate_cmp(t1[0], t1[1], t1[2], t2[0], t2[1],
                                       t2[2], safe_pair, 0, &res)) {
            found[made]++;
            assert_int_equal(res, want);
        }
        tried[made]++;
    }
    /* lattice triangles and their copies turned by quarter turns and
     * moved by a whole vector, one row up or down at most: equal radii,
     * tops equal or one row apart, centres level or not (the small
     * integer path must decide or decline each correctly) */
    int declined = 0;
    for (int it = 0; it < 20000; it++) {
        double t1[3][2], t2[3][2];
        long ox = (long)(vt_next(&r) % 2000) - 1000,
             oy = (long)(vt_next(&r) % 2000) - 1000;
        for (int i = 0; i < 3; i++) {
            t1[i][0] = (double)(ox + (long)(vt_next(&r) % 21) - 10);
            t1[i][1] = (double)(oy + (long)(vt_next(&r) % 21) - 10);
        }
        int o = vor_orient2d(t1[0], t1[1], t1[2]);
        if (o == 0) continue;
        if (o < 0) {
            double sw[2] = {t1[1][0], t1[1][1]};
            memcpy(t1[1], t1[2], sizeof sw);
            memcpy(t1[2], sw, sizeof sw);
        }
        int turns = (int)(vt_next(&r) % 4);
        long dx = (long)(vt_next(&r) % 101) - 50,
             dy = (long)(vt_next(&r) % 3) - 1;
        for (int i = 0; i < 3; i++) {
            double x = t1[i][0] - (double)ox, y = t1[i][1] - (double)oy;
            for (int k = 0; k < turns; k++) {
                double tt = x;
                x = -y;
                y = tt;
            }
            t2[i][0] = x + (double)(ox + dx);
            t2[i][1] = y + (double)(oy + dy);
        }
        const double *e1[3] = {t1[0], t1[1], t1[2]},
                     *e2[3] = {t2[0], t2[1], t2[2]};
        int want = q_event_cmp(e1, e2), res;
        if (vor__fortune_circle_cmp_small(t1[0], t1[1], t1[2], t2[0], t2[1],
                                          t2[2], &res)) {
            small++;
            assert_int_equal(res, want);
        } else {
            declined++;
        }
    }
    /* circles of integer radius (Pythagorean: three lattice points on
     * each) whose tops meet on one row or miss it by one, the centre
     * higher on the smaller circle: the tops' order then needs the
     * radii's square roots, which are integers here */
    static const long radii[] = {5, 10, 13, 17, 25, 29};
    int rooted = 0;
    for (int it = 0; it < 4000; it++) {
        double t[2][3][2];
        long r0 = radii[vt_next(&r) % 6], r1 = radii[vt_next(&r) % 6];
        long cx0 = (long)(vt_next(&r) % 41) - 20, cy0 = (long)(vt_next(&r) % 41);
        long cx1 = cx0 + (long)(vt_next(&r) % 3) - 1;
        long cy1 = cy0 + r0 - r1 + (long)(vt_next(&r) % 3) - 1;
        for (int c = 0; c < 2; c++) {
            long rad = c ? r1 : r0, cx = c ? cx1 : cx0, cy = c ? cy1 : cy0;
            long pts[64][2];
            int np = 0;
            for (long x = -rad; x <= rad; x++)
                for (long y = -rad; y <= rad; y++)
                    if (x * x + y * y == rad * rad && np < 64) {
                        pts[np][0] = x;
                        pts[np++][1] = y;
                    }
            int i0 = (int)(vt_next(&r) % (uint64_t)np), i1, i2;
            do i1 = (int)(vt_next(&r) % (uint64_t)np); while (i1 == i0);
            do i2 = (int)(vt_next(&r) % (uint64_t)np); while (i2 == i0 || i2 == i1);
            int ix[3] = {i0, i1, i2};
            for (int k = 0; k < 3; k++) {
                t[c][k][0] = (double)(cx + pts[ix[k]][0]);
                t[c][k][1] = (double)(cy + pts[ix[k]][1]);
            }
            if (vor_orient2d(t[c][0], t[c][1], t[c][2]) < 0) {
                double sw[2] = {t[c][1][0], t[c][1][1]};
                memcpy(t[c][1], t[c][2], sizeof sw);
                memcpy(t[c][2], sw, sizeof sw);
            }
        }
        const double *e1[3] = {t[0][0], t[0][1], t[0][2]},
                     *e2[3] = {t[1][0], t[1][1], t[1][2]};
        int want = q_event_cmp(e1, e2), res;
        assert_int_equal(vor__fortune_circle_cmp_small(t[0][0], t[0][1],
                                                       t[0][2], t[1][0],
                                                       t[1][1], t[1][2], &res),
                         1);
        assert_int_equal(res, want);
        rooted += (r0 != r1) && cy0 != cy1;
    }
    assert_true(rooted > 1000);
    print_message("circle_cmp: %d decided by small integers, %d declined\n",
                  small, declined);
    vor__fortune_ws_free(ws);
    print_message("circle_cmp: translates %d of %d found, of mirror images "
                  "%d of %d\n", found[1], tried[1], found[2], tried[2]);
    /* every translate; mirror images at equal tops only where the centres
     * are level or the bounds tell them apart (in the safe range, not
     * nearly collinear: a third of the random triples) */
    assert_true(found[1] == tried[1] && tried[1] > 1000);
    assert_true(found[2] > tried[2] / 4 && tried[2] > 1000);
    assert_true(small > 15000);
    assert_true(equal > 100);
    assert_true(dd_decided > 1000);
    /* small-integer circles are exact in doubles */
    const double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {1, 1};
    double cc[3];
    assert_int_equal(vor__fortune_circle_exact_double(a, b, c, cc), 1);
    assert_true(cc[0] == 0.5 && cc[1] == 0.5 && cc[2] == 0.5);
}

/* Three corners of the box [x0, x1] x [y0, y1] (corner k = (x of bit 0,
 * y of bit 1), `skip` left out), counter-clockwise. */
static void box_triple(double t[3][2], const double *x, const double *y,
                       int skip, int rot) {
    int k = 0;
    for (int c = 0; c < 4; c++) {
        if (c == skip) continue;
        double *v = t[(k++ + rot) % 3];
        v[0] = x[c & 1];
        v[1] = y[c >> 1];
    }
    if (vor_orient2d(t[0], t[1], t[2]) < 0) {
        double sw[2] = {t[1][0], t[1][1]};
        memcpy(t[1], t[2], sizeof sw);
        memcpy(t[2], sw, sizeof sw);
    }
}

/* Circle events of grid cells: vor__fortune_box_cmp decides when both
 * triples are boxes between the same rows or of the same size, and then
 * as the exact order does; it declines everything else. Columns of a
 * decimal grid (0.37 i: equal widths come and go with the rounding), of a
 * binary one (every width exact) and random doubles; rows the same. */
static void test_box_cmp(void **state) {
    (void)state;
    vt_rng r = {4242};
    print_message("box_cmp: seed 4242\n");
    int decided = 0, equal_tops = 0, same_circle = 0, declined = 0;
    for (int it = 0; it < 30000; it++) {
        int kind = it % 3;
        double x[2][2], y[2][2];
        for (int b = 0; b < 2; b++) {
            for (int i = 0; i < 2; i++) {
                long k = (long)(vt_next(&r) % 40);
                x[b][i] = kind == 0   ? 0.37 * (double)k
                          : kind == 1 ? 1000 + (double)k / 64
                                      : vt_unit(&r) * 10;
                y[b][i] = kind == 0 ? 0.11 * (double)(vt_next(&r) % 6)
                                    : (double)(vt_next(&r) % 6) / 8;
            }
            if (x[b][0] == x[b][1] || y[b][0] == y[b][1]) goto next;
        }
        switch (vt_next(&r) % 4) {
        case 0: /* the same rows */
            y[1][0] = y[0][0];
            y[1][1] = y[0][1];
            break;
        case 1: /* the same box: the same circle, or the same cell's
                 * other triangle */
            memcpy(x[1], x[0], sizeof x[0]);
            memcpy(y[1], y[0], sizeof y[0]);
            break;
        case 2: { /* the same size, elsewhere (exactly, where it is):
                   * along the same rows or not */
            if (vt_next(&r) % 2) y[1][0] = y[0][0];
            double dx = x[1][0] - x[0][0], dy = y[1][0] - y[0][0];
            x[1][1] = x[0][1] + dx;
            y[1][1] = y[0][1] + dy;
            if (x[1][0] == x[1][1] || y[1][0] == y[1][1]) goto next;
            break;
        }
        default: /* anything */
            break;
        }
        double t1[3][2], t2[3][2];
        for (int b = 0; b < 2; b++) {
            int skip = (int)(vt_next(&r) % 4);
            box_triple(b ? t2 : t1, x[b], y[b], skip, (int)(vt_next(&r) % 3));
        }
        if (it % 10 == 9) t2[1][0] = nextafter(t2[1][0], INFINITY); /* no box */
        const double *e1[3] = {t1[0], t1[1], t1[2]},
                     *e2[3] = {t2[0], t2[1], t2[2]};
        int res;
        if (!vor__fortune_box_cmp(t1[0], t1[1], t1[2], t2[0], t2[1], t2[2],
                                  &res)) {
            declined++;
            continue;
        }
        int want = q_event_cmp(e1, e2), same;
        assert_int_equal(res, want);
        decided++;
        equal_tops += q_equal_tops(e1, e2, &same);
        same_circle += same;
    next:;
    }
    print_message("box_cmp: %d decided (%d equal tops, %d the same circle), "
                  "%d declined\n",
                  decided, equal_tops, same_circle, declined);
    assert_true(decided > 10000);
    assert_true(equal_tops - same_circle > 1000);
    assert_true(same_circle > 1000);
    assert_true(declined > 3000);
}

/* Triangles with two sites of equal x (a grid of decimal spacing with
 * holes makes them) against their images turned upside down or by half
 * a turn, then moved: placed so that the tops are equal (where the
 * rounding lets them be) or not. vor__fortune_translate_cmp must find
 * them and decide as the exact order does. */
static void test_turned_cmp(void **state) {
    (void)state;
    vt_rng r = {4545};
    print_message("turned_cmp: seed 4545\n");
    int made[2] = {0, 0}, found[2] = {0, 0}, equal_tops = 0;
    for (int it = 0; it < 20000; it++) {
        double i = (double)(vt_next(&r) % 1000),
               j = (double)(vt_next(&r) % 1000);
        int span = 1 + (int)(vt_next(&r) % 3);
        double k = (double)(vt_next(&r) % 5) - 2,
               m = (double)(vt_next(&r) % 5) - 1;
        if (k == 0) continue;
        double t1[3][2] = {{0.37 * i, 0.11 * j},
                           {0.37 * i, 0.11 * (j + span)},
                           {0.37 * (i + k), 0.11 * (j + m)}};
        if (!make_ccw(t1)) continue;
        int half = it % 2;
        /* t2 = T(t1) + w, w.y = p.y + q.y (equal tops) or that plus a row */
        double wx = 0.37 * (double)(vt_next(&r) % 1000);
        double wy = t1[0][0] == t1[1][0]   ? t1[0][1] + t1[1][1]
                    : t1[1][0] == t1[2][0] ? t1[1][1] + t1[2][1]
                                           : t1[0][1] + t1[2][1];
        if (vt_next(&r) % 3 == 0) wy += 0.11;
        double t2[3][2];
        for (int a = 0; a < 3; a++) {
            const double *q = half ? t1[a] : t1[2 - a];
            t2[a][0] = (half ? -q[0] : q[0]) + wx;
            t2[a][1] = -q[1] + wy;
        }
        made[half]++;
        const double *e1[3] = {t1[0], t1[1], t1[2]},
                     *e2[3] = {t2[0], t2[1], t2[2]};
        int res;
        if (!vor__fortune_translate_cmp(t1[0], t1[1], t1[2], t2[0], t2[1],
                                        t2[2], 0, 0, &res) &&
            !vor__fortune_translate_cmp(t1[0], t1[1], t1[2], t2[0], t2[1],
                                        t2[2], 1, 0, &res))
            continue;
        found[half]++;
        int want = q_event_cmp(e1, e2);
        assert_int_equal(res, want);
        equal_tops += q_equal_tops(e1, e2, NULL);
    }
    print_message("turned_cmp: upside down %d of %d found, half turns %d of "
                  "%d, %d at equal tops\n",
                  found[0], made[0], found[1], made[1], equal_tops);
    assert_true(found[0] > made[0] / 4 && found[1] > made[1] / 4);
    assert_true(equal_tops > 1000);
}

/* Triangles of a small lattice (m 2^k, |m| < 2^15, k from -300 to 40)
 * against their mirror images (x negated) and their images turned by
 * half a turn, moved so that the tops are equal or a step apart: with
 * small set, vor__fortune_translate_cmp orders the centres of equal tops
 * in doubles, and must decide every such pair as the exact order does,
 * including those without two level sites (no exact sum for the centre)
 * and those whose centres lie one above the other. */
static void test_image_cmp_small(void **state) {
    (void)state;
    vt_rng r = {4747};
    print_message("image_cmp_small: seed 4747\n");
    int made = 0, decided = 0, equal_tops = 0, same_x = 0, unlevel = 0;
    for (int it = 0; it < 20000; it++) {
        int k = (int)(vt_next(&r) % 341) - 300, half = it % 2;
        double h = ldexp(1.0, k), t1[3][2], t2[3][2];
        long span = it % 3 == 0 ? 8 : 1L << 13;
        /* one time in eight, three of the twelve lattice points at
         * distance 5 from a lattice point (cx, cy): a centre known */
        static const int p5[12][2] = {{5, 0}, {4, 3}, {3, 4}, {0, 5},
                                      {-3, 4}, {-4, 3}, {-5, 0}, {-4, -3},
                                      {-3, -4}, {0, -5}, {3, -4}, {4, -3}};
        int on5 = it % 8 == 7;
        long cx = (long)(vt_next(&r) % 2000) - 1000,
             cy = (long)(vt_next(&r) % 2000) - 1000;
        for (int a = 0; a < 3; a++) {
            const int *q = p5[vt_next(&r) % 12];
            for (int j = 0; j < 2; j++)
                t1[a][j] = h * (on5 ? (double)((j ? cy : cx) + q[j])
                                    : (double)((long)(vt_next(&r) %
                                                      (2 * span + 1)) -
                                               span));
        }
        if (half) { /* a vertical pair gives the centre's y: equal tops */
            t1[1][0] = t1[0][0];
            if (t1[1][1] == t1[0][1]) continue;
        }
        if (!make_ccw(t1)) continue;
        /* the move: x anywhere, or (about the circle of 5) so that the
         * centres' x are equal (-c + wx = c); y so that the tops are
         * equal or, one time in four, a step apart */
        double wx = on5 ? 2 * h * (double)cx
                        : h * (double)((long)(vt_next(&r) % (1L << 14)) -
                                       (1L << 13));
        double wy = half ? t1[0][1] + t1[1][1] : 0;
        if (vt_next(&r) % 4 == 0) wy += h;
        for (int a = 0; a < 3; a++) {
            /* a mirror image reversed, to stay counter-clockwise */
            const double *q = half ? t1[a] : t1[2 - a];
            t2[a][0] = -q[0] + wx;
            t2[a][1] = (half ? -q[1] : q[1]) + wy;
        }
        made++;
        const double *e1[3] = {t1[0], t1[1], t1[2]},
                     *e2[3] = {t2[0], t2[1], t2[2]};
        int res, want = q_event_cmp(e1, e2);
        int level = t1[0][1] == t1[1][1] || t1[1][1] == t1[2][1] ||
                    t1[0][1] == t1[2][1];
        assert_true(vor__fortune_translate_cmp(t1[0], t1[1], t1[2], t2[0],
                                               t2[1], t2[2], 0, 1, &res));
        decided++;
        assert_int_equal(res, want);
        if (q_equal_tops(e1, e2, NULL)) {
            equal_tops++;
            unlevel += !level;
            same_x += want == 0;
        }
    }
    print_message("image_cmp_small: %d of %d decided, %d at equal tops (%d "
                  "without a level pair), %d at one point\n",
                  decided, made, equal_tops, unlevel, same_x);
    assert_true(made > 15000 && equal_tops > made / 2);
    assert_true(unlevel > equal_tops / 2 && same_x > 100);
}

/* Triangles of a decimal lattice in doubles (0.37 by 0.11, rounded), and
 * the same moved by a lattice vector, or mirrored and moved, each
 * rounded again (so that their differences from the first site are, or
 * are not, the same doubles), beside unrelated triangles: whatever
 * vor__fortune_shapes_cmp decides must be the exact order of the two
 * events, tops then centres' x (what the sweep cannot see: two events of
 * one top at different points commute), and agree with
 * vor__fortune_translate_cmp where that decides too. */
static void test_shape_cmp(void **state) {
    (void)state;
    vt_rng r = {4646};
    print_message("shape_cmp: seed 4646\n");
    int made[3] = {0, 0, 0}, decided[3] = {0, 0, 0}, equal_tops = 0;
    int agreed = 0;
    for (int it = 0; it < 30000; it++) {
        /* sites 0.37 i, 0.11 j, each rounded once, as a grid computes
         * them: a shape of offsets (di, dj) at (i1, j1) and at (i2, j2) */
        int di[3], dj[3];
        for (int a = 0; a < 3; a++) {
            di[a] = (int)(vt_next(&r) % 5) - 2;
            dj[a] = (int)(vt_next(&r) % 5) - 2;
        }
        int i1 = 2 + (int)(vt_next(&r) % 60), j1 = 2 + (int)(vt_next(&r) % 60);
        int i2 = 2 + (int)(vt_next(&r) % 60),
            j2 = vt_next(&r) % 2 ? j1 : 2 + (int)(vt_next(&r) % 60);
        int kind = it % 3; /* moved, mirrored and moved, unrelated */
        double t1[3][2], t2[3][2];
        for (int a = 0; a < 3; a++) {
            t1[a][0] = 0.37 * (double)(i1 + di[a]);
            t1[a][1] = 0.11 * (double)(j1 + dj[a]);
            int b = kind == 1 ? 2 - a : a; /* reversed: counter-clockwise */
            int ei = kind == 2 ? (int)(vt_next(&r) % 5) - 2
                     : kind == 1 ? -di[b] : di[b];
            int ej = kind == 2 ? (int)(vt_next(&r) % 5) - 2 : dj[b];
            t2[a][0] = 0.37 * (double)(i2 + ei);
            t2[a][1] = 0.11 * (double)(j2 + ej);
        }
        if (vor_orient2d(t1[0], t1[1], t1[2]) <= 0 ||
            (kind < 2 && vor_orient2d(t2[0], t2[1], t2[2]) <= 0) ||
            (kind == 2 && !make_ccw(t2)))
            continue;
        made[kind]++;
        double u[VOR__FORTUNE_SHAPE], v[VOR__FORTUNE_SHAPE];
        int res, tres;
        if (!vor__fortune_shape_of(t1[0], t1[1], t1[2], u) ||
            !vor__fortune_shape_of(t2[0], t2[1], t2[2], v) ||
            !vor__fortune_shapes_cmp(u, v, &res))
            continue;
        decided[kind]++;
        const double *e1[3] = {t1[0], t1[1], t1[2]},
                     *e2[3] = {t2[0], t2[1], t2[2]};
        assert_int_equal(res, q_event_cmp(e1, e2));
        /* its first two cases decide whatever the shapes decide */
        if (vor__fortune_translate_cmp(t1[0], t1[1], t1[2], t2[0], t2[1],
                                       t2[2], 1, 0, &tres)) {
            assert_int_equal(res, tres);
            agreed++;
        }
        equal_tops += q_equal_tops(e1, e2, NULL);
    }
    print_message("shape_cmp: decided %d of %d moved, %d of %d mirrored, "
                  "%d of %d unrelated; %d at equal tops\n",
                  decided[0], made[0], decided[1], made[1], decided[2],
                  made[2], equal_tops);
    /* rounded once a site, a shape's differences are the same doubles
     * elsewhere about one time in seven here */
    assert_true(decided[0] > made[0] / 10 && decided[1] > made[1] / 20);
    assert_int_equal(agreed, decided[0] + decided[1] + decided[2]);
    assert_true(equal_tops > 500);
}

/* Triangles of two sites on one row and a third on another, as a
 * triangular grid of decimal spacing makes them: vor__fortune_level_cmp
 * decides pairs between the same rows with level pairs of equal width
 * (the third sites off the middle by ulps, or farther, above or below),
 * and then as the exact order does; it declines the rest. */
static void test_level_cmp(void **state) {
    (void)state;
    vt_rng r = {4343};
    print_message("level_cmp: seed 4343\n");
    int decided = 0, equal_tops = 0, declined = 0;
    for (int it = 0; it < 30000; it++) {
        double sx = 0.01 * (double)(1 + vt_next(&r) % 100),
               sy = 0.01 * (double)(1 + vt_next(&r) % 100);
        double j = (double)(vt_next(&r) % 1000);
        int below = (int)(vt_next(&r) % 2), span = 1 + (int)(vt_next(&r) % 3);
        double t[2][3][2];
        for (int b = 0; b < 2; b++) {
            double i = (double)(vt_next(&r) % 100000);
            if (it % 4 == 0 && b == 1) j += (double)(vt_next(&r) % 2);
            double y1 = sy * j, y0 = sy * (below ? j - 1 : j + 1);
            double p[2] = {sx * i, y1}, q[2] = {sx * (i + 2 * span), y1};
            double v[2] = {sx * (i + span), y0};
            switch (vt_next(&r) % 4) {
            case 0: break; /* the decimal grid's rounding alone */
            case 1: v[0] = nextafter(v[0], INFINITY); break;
            case 2: v[0] = nextafter(nextafter(v[0], 0), 0); break;
            default: v[0] += sx * 0.25; break;
            }
            if (it % 5 == 4 && b == 1) /* no level pair */
                p[1] = nextafter(p[1], INFINITY);
            memcpy(t[b][0], p, sizeof p);
            memcpy(t[b][1], q, sizeof q);
            memcpy(t[b][2], v, sizeof v);
            if (!make_ccw(t[b])) goto next;
            double u[3][2];
            rotated(u, t[b], (int)(vt_next(&r) % 3));
            memcpy(t[b], u, sizeof u);
        }
        int res;
        if (!vor__fortune_level_cmp(t[0][0], t[0][1], t[0][2], t[1][0],
                                    t[1][1], t[1][2], &res)) {
            declined++;
            continue;
        }
        const double *e1[3] = {t[0][0], t[0][1], t[0][2]},
                     *e2[3] = {t[1][0], t[1][1], t[1][2]};
        int want = q_event_cmp(e1, e2);
        assert_int_equal(res, want);
        decided++;
        equal_tops += q_equal_tops(e1, e2, NULL);
    next:;
    }
    print_message("level_cmp: %d decided (%d equal tops), %d declined\n",
                  decided, equal_tops, declined);
    assert_true(decided > 5000);
    assert_true(equal_tops > 500 && decided - equal_tops > 2000);
    assert_true(declined > 5000);
}

/* ---- Diagram checks ------------------------------------------------------ */

static vor_sites *sites_of(const double *xy, size_t n) {
    vor_sites *s = NULL;
    assert_int_equal(vor_sites_new(xy, n, &s, NULL), VOR_OK);
    assert_non_null(s);
    return s;
}

/* Brute force (see the top of the file); "" if the diagram passes. */
static void brute_force(const vor_diagram *d, const vor_sites *s, char *msg,
                        size_t size) {
    msg[0] = '\0';
    size_t n = s->n, nv = d->n_vertices;
    uint32_t *start = calloc(nv + 1, sizeof *start);
    uint32_t *inc = malloc((4 * d->n_edges + 1) * sizeof *inc);
    uint8_t *mark = calloc(n ? n : 1, 1);
    assert_true(start && inc && mark);
    for (size_t e = 0; e < d->n_edges; e++)
        for (int k = 0; k < 2; k++)
            if (d->edge_ends[2 * e + k] >= 0)
                start[d->edge_ends[2 * e + k] + 1] += 2;
    for (size_t v = 0; v < nv; v++) start[v + 1] += start[v];
    uint32_t *fill = malloc((nv + 1) * sizeof *fill);
    assert_non_null(fill);
    memcpy(fill, start, (nv + 1) * sizeof *fill);
    for (size_t e = 0; e < d->n_edges; e++)
        for (int k = 0; k < 2; k++) {
            int32_t v = d->edge_ends[2 * e + k];
            if (v < 0) continue;
            inc[fill[v]++] = d->edge_sites[2 * e];
            inc[fill[v]++] = d->edge_sites[2 * e + 1];
        }
    for (size_t v = 0; v < nv && !msg[0]; v++) {
        for (uint32_t k = start[v]; k < start[v + 1]; k++) mark[inc[k]] = 1;
        const uint32_t *t = d->vertex_sites + 3 * v;
        const double *a = s->xy + 2 * (size_t)t[0],
                     *b = s->xy + 2 * (size_t)t[1],
                     *c = s->xy + 2 * (size_t)t[2];
        int o = vor_orient2d(a, b, c);
        if (o == 0) {
            snprintf(msg, size, "vertex %zu: collinear sites", v);
        } else {
            for (size_t i = 0; i < n; i++) {
                int ic = vor_incircle(a, b, c, s->xy + 2 * i) * o;
                if (ic > 0) {
                    snprintf(msg, size, "vertex %zu: site %zu strictly inside",
                             v, i);
                    break;
                }
                if ((ic == 0) != mark[i]) {
                    snprintf(msg, size, "vertex %zu: site %zu %s", v, i,
                             ic == 0 ? "on the circle but not at the vertex"
                                     : "at the vertex but not on the circle");
                    break;
                }
            }
        }
        for (uint32_t k = start[v]; k < start[v + 1]; k++) mark[inc[k]] = 0;
    }
    free(start);
    free(inc);
    free(mark);
    free(fill);
}

#define BRUTE_MAX 2000

/* The whole check of one input: Fortune through vor_compute, vor_check, the
 * brute force (n <= BRUTE_MAX), and identity with the other algorithms. */
static void check_points(const char *name, const double *xy, size_t n,
                         int others) {
    vor_sites *s = sites_of(xy, n);
    vor_diagram *f = NULL;
    char msg[256];
    vor_status st = vor_compute(s, VOR_FORTUNE, &f);
    if (st != VOR_OK) fail_msg("%s: fortune: %s", name, vor_status_name(st));
    if (vor_check(f, s, msg, sizeof msg))
        fail_msg("%s: vor_check: %s", name, msg);
    if (s->n <= BRUTE_MAX) {
        brute_force(f, s, msg, sizeof msg);
        if (msg[0]) fail_msg("%s: brute force: %s", name, msg);
    }
    for (int alg = VOR_BOWYER_WATSON; others && alg <= VOR_FLIP; alg++) {
        vor_diagram *g = NULL;
        st = vor_compute(s, (vor_algorithm)alg, &g);
        if (st == VOR_EUNAVAILABLE) continue;
        if (st != VOR_OK)
            fail_msg("%s: %s: %s", name, vor_algorithm_name(alg),
                     vor_status_name(st));
        if (!vor_diagram_equal(f, g))
            fail_msg(
                "%s: fortune and %s differ (vertices %zu/%zu, edges %zu/%zu)",
                name, vor_algorithm_name(alg), f->n_vertices, g->n_vertices,
                f->n_edges, g->n_edges);
        vor_diagram_free(g);
    }
    vor_diagram_free(f);
    vor_sites_free(s);
}

static void test_standard_sets(void **state) {
    (void)state;
    for (size_t i = 0; i < vt_count(); i++) {
        vt_set t;
        assert_int_equal(vt_make(i, &t), 0);
        check_points(t.name, t.xy, t.n, 1);
        vt_set_free(&t);
    }
}

/* n = 3..30 sites from a tiny integer range (degeneracies are the rule),
 * sometimes scaled or moved far away; against both other algorithms and
 * the brute force. */
static void test_small_random(void **state) {
    (void)state;
    const uint64_t base = 7777;
    const int count = 4000;
    print_message("small random: seeds %llu..%llu\n", (unsigned long long)base,
                  (unsigned long long)(base + count - 1));
    for (int k = 0; k < count; k++) {
        uint64_t seed = base + (uint64_t)k;
        vt_rng r = {seed};
        size_t n = 3 + (size_t)(vt_next(&r) % 28);
        long range = 2 + (long)(vt_next(&r) % 7);
        int variant = (int)(vt_next(&r) % 4);
        double xy[60];
        for (size_t i = 0; i < 2 * n; i++) {
            double v = (double)(vt_next(&r) % (uint64_t)range);
            if (variant == 1) v = ldexp(v, -40);
            if (variant == 2) v = 1e9 + v * 0.25;
            if (variant == 3) v = ldexp(v, 700);
            xy[i] = v;
        }
        char name[64];
        snprintf(name, sizeof name, "seed %llu (n %zu, range %ld, variant %d)",
                 (unsigned long long)seed, n, range, variant);
        check_points(name, xy, n, 1);
    }
}

static void test_grid_1000(void **state) {
    (void)state;
    double *xy = vt_grid(1000, 1000);
    assert_non_null(xy);
    check_points("grid 1000x1000", xy, 1000000, 1);
    free(xy);
}

/* Fortune's counts on xy (n sites) into *c; the diagram must be right. */
static void counts_of(const char *name, const double *xy, size_t n,
                      vor_counts *c) {
    check_points(name, xy, n, 1);
    vor_options o = {.counts = c};
    vor_sites *s = sites_of(xy, n);
    vor_diagram *f = NULL;
    assert_int_equal(vor_compute_ex(s, VOR_FORTUNE, &o, &f), VOR_OK);
    vor_diagram_free(f);
    vor_sites_free(s);
}

/* counts_of, and the queue must have taken fewer than per comparisons
 * per circle event. */
static void compares_under(const char *name, const double *xy, size_t n,
                           unsigned per) {
    vor_counts c;
    counts_of(name, xy, n, &c);
    print_message("%s: %llu comparisons for %llu circle events\n", name,
                  (unsigned long long)c.event_compares,
                  (unsigned long long)c.circle_events);
    assert_true(c.event_compares < per * c.circle_events);
}

/* Sites on a circle: every event's top lies just above the circle's top,
 * above all but its last few dozen sites, whose buckets the events crowd
 * before the last site: the buckets are fitted to the events once the
 * heap holds most of them (refit), and the queue then orders them in a
 * few comparisons each (18 each with the heap alone). */
static void test_unit_circle_1e5(void **state) {
    (void)state;
    size_t n = 100000;
    double *xy = vt_unit_circle(n);
    assert_non_null(xy);
    compares_under("unit circle, 1e5 points", xy, n, 8);
    free(xy);
}

/* Integer pixels, a fifth of a 400 x 200 window: rows of equal y, and
 * circles of Pythagorean radius whose tops lie on rows and equal one
 * another's. Their tops, known exactly in doubles, order them against
 * the sites of a row and each other without integers (exact comparisons
 * were half the circle events), and the buckets, spread over the rows by
 * the linear map of y, keep the heap in front of them short (7.7
 * comparisons per circle event with the coarser rank map). */
static void test_pixels(void **state) {
    (void)state;
    enum { N = 16000 };
    static double xy[2 * N];
    vt_rng r = {71};
    print_message("pixels: seed 71\n");
    for (size_t i = 0; i < N; i++) {
        xy[2 * i] = (double)(vt_next(&r) % 400);
        xy[2 * i + 1] = (double)(vt_next(&r) % 200);
    }
    vor_counts c;
    counts_of("integer pixels", xy, N, &c);
    print_message("pixels: %llu exact and %llu comparisons for %llu circle "
                  "events\n",
                  (unsigned long long)c.event_exact,
                  (unsigned long long)c.event_compares,
                  (unsigned long long)c.circle_events);
    assert_true(c.event_exact < c.circle_events / 10);
    assert_true(c.event_compares < 6 * c.circle_events);
}

/* Grids of decimal spacing (0.37 by 0.11, not a small lattice in
 * binary): every cell four cocircular sites, many cells of exactly equal
 * size along a row (their circles' tops equal), whole or with holes; and
 * triangular ones (every other row shifted by half a step), whose
 * triangles are isosceles but for the rounding. */
static void test_decimal_grid(void **state) {
    (void)state;
    vt_rng r = {37};
    print_message("decimal grid: seed 37\n");
    static double xy[2 * 200 * 200];
    const size_t dims[][2] = {{30, 20}, {200, 200}};
    for (int d = 0; d < 4; d++)
        for (int holes = 0; holes < 2; holes++) {
            size_t n = 0;
            const int tri = d >= 2;
            for (size_t j = 0; j < dims[d % 2][1]; j++)
                for (size_t i = 0; i < dims[d % 2][0]; i++) {
                    if (holes && vt_next(&r) % 3 == 0) continue;
                    xy[2 * n] = tri ? 0.3 * ((double)i + 0.5 * (double)(j % 2))
                                    : 0.37 * (double)i;
                    xy[2 * n + 1] = tri ? 0.26 * (double)j
                                        : -5 + 0.11 * (double)j;
                    n++;
                }
            char name[64];
            snprintf(name, sizeof name, "%s grid %zux%zu%s",
                     tri ? "triangular decimal" : "decimal", dims[d % 2][0],
                     dims[d % 2][1], holes ? " with holes" : "");
            vor_counts c;
            counts_of(name, xy, n, &c);
            if (holes) continue;
            /* ties of cells' circles, and of the triangles of a triangular
             * grid, are decided by sums of coordinates, never by the exact
             * comparison of two tops */
            assert_true(c.event_compares > 0);
            assert_int_equal(c.event_exact, 0);
        }
}

/* The circle events of a traced run, in the order the sweep took them. */
typedef struct circles {
    uint32_t *tri; /* 3 per event */
    size_t n, cap;
} circles;

static void on_circle(void *ctx, const vor_step *st) {
    circles *c = ctx;
    if (st->kind != VOR_STEP_CIRCLE) return;
    if (c->n == c->cap) {
        c->cap = c->cap ? 2 * c->cap : 1024;
        c->tri = realloc(c->tri, 3 * c->cap * sizeof *c->tri);
        assert_non_null(c->tri);
    }
    memcpy(c->tri + 3 * c->n++, st->tri, sizeof st->tri);
}

/* check_points, and the circle events of a traced run must come with
 * their tops in increasing order, by the exact oracle: a wrong answer of
 * the queue's tie-breaking need not change the diagram (two events far
 * apart on the beach line commute), but it does change their order. */
static void check_sweep_order(const char *name, const double *xy, size_t n) {
    check_points(name, xy, n, 1);
    circles c = {0};
    vor_options o = {.trace = on_circle, .trace_ctx = &c};
    vor_sites *s = sites_of(xy, n);
    vor_diagram *f = NULL;
    assert_int_equal(vor_compute_ex(s, VOR_FORTUNE, &o, &f), VOR_OK);
    mpq_t X, Y[2], R[2];
    mpq_inits(X, Y[0], Y[1], R[0], R[1], NULL);
    for (size_t k = 0; k < c.n; k++) {
        const uint32_t *t = c.tri + 3 * k;
        const double *in = s->xy;
        q_circle(in + 2 * (size_t)t[0], in + 2 * (size_t)t[1],
                 in + 2 * (size_t)t[2], X, Y[k % 2], R[k % 2]);
        if (k > 0 &&
            q_cmp_sum_sqrt(Y[(k + 1) % 2], R[(k + 1) % 2], Y[k % 2], R[k % 2]) > 0)
            fail_msg("%s: circle event %zu has its top below the one before",
                     name, k);
    }
    print_message("%s: %zu circle events in order\n", name, c.n);
    mpq_clears(X, Y[0], Y[1], R[0], R[1], NULL);
    free(c.tri);
    vor_diagram_free(f);
    vor_sites_free(s);
}

/* Long rows, which the site sort sorts by x apart (row_sort): rows of 300
 * random x; rows whose x bunch near 0 with a few far out (one
 * sub-bucket holds nearly all) or span more than the doubles (their
 * range overflows: sorted by comparisons instead); one row of 9,000
 * sites (longer than the counts on the stack) among a few others; and a
 * dense band of distinct y beside a sparse spread (buckets of several y,
 * if the map leaves any). Each against vor_check and the other
 * algorithms. */
static void test_long_rows(void **state) {
    (void)state;
    vt_rng r = {43};
    enum { N = 9050 };
    double *xy = malloc(2 * N * sizeof *xy);
    assert_non_null(xy);
    for (int kind = 0; kind < 5; kind++) {
        size_t n = 0;
        if (kind < 3) {
            for (int row = 0; row < 30; row++)
                for (int k = 0; k < 300; k++) {
                    double x = vt_unit(&r);
                    if (kind == 1) {
                        x *= 1e-9;
                        if (k % 100 == 0)
                            x = (k % 200 ? 1e300 : -1e300) * vt_unit(&r);
                    } else if (kind == 2 && k < 2) {
                        x = k ? 1.7e308 : -1.7e308;
                    }
                    xy[2 * n] = x;
                    xy[2 * n + 1] = row;
                    n++;
                }
        } else if (kind == 3) {
            for (int k = 0; k < 9000; k++, n++) {
                xy[2 * n] = vt_unit(&r);
                xy[2 * n + 1] = 0.5;
            }
            for (int k = 0; k < 50; k++, n++) {
                xy[2 * n] = vt_unit(&r);
                xy[2 * n + 1] = vt_unit(&r);
            }
        } else {
            for (int k = 0; k < 9000; k++, n++) {
                xy[2 * n] = vt_unit(&r);
                xy[2 * n + 1] = k % 2 ? 0.5 + 1e-12 * vt_unit(&r) : vt_unit(&r);
            }
        }
        char name[32];
        snprintf(name, sizeof name, "long rows %d", kind);
        check_points(name, xy, n, 1);
    }
    free(xy);
}

/* Hexagonal lattices in doubles (spacing 0.1: x = 0.1 i, shifted by half
 * a step on odd rows, y = 0.1 j sqrt(3) / 2, each rounded): most of
 * their triangles are translates of one another, or mirror images moved,
 * with exact differences, whose ties the sweep decides by the triangles'
 * shapes once it has seen them decide ties (event_shape), the others by
 * the bounds; with their x moved by an ulp here and there, and with a
 * row of sites missing, fewer are. Rows 2^-60 apart make ties of tops
 * that differ by less than the bounds resolve. Against brute force and
 * the other algorithms, and the order of the events against the exact
 * tops. */
static void test_hex_doubles(void **state) {
    (void)state;
    vt_rng r = {41};
    print_message("hexagonal lattices in doubles: seed 41\n");
    static double xy[2 * 44 * 44];
    for (int kind = 0; kind < 4; kind++) {
        size_t n = 0;
        for (int j = 0; j < 44; j++) {
            if (kind == 2 && j == 20) continue;
            for (int i = 0; i < 44; i++, n++) {
                double x = 0.1 * ((double)i + 0.5 * (double)(j % 2)) + 3;
                if (kind == 1 && vt_next(&r) % 4 == 0)
                    x = nextafter(x, vt_next(&r) % 2 ? 10.0 : 0.0);
                xy[2 * n] = x;
                xy[2 * n + 1] =
                    kind == 3 ? ldexp((double)j, -60)
                              : 0.1 * (double)j * 0.8660254037844386 - 1;
            }
        }
        const char *name[] = {"hexagonal lattice in doubles 44 x 44",
                              "the same, x moved by an ulp at random",
                              "the same but a row",
                              "the same with rows 2^-60 apart"};
        check_sweep_order(name[kind], xy, n);
    }
}

/* Sites on several curves at once keep one front on the beach line for
 * each side of each curve, more than the fingers follow: on ten
 * concentric rings and on sixteen rays from a point each site falls in
 * or next to the arc of the last site split in within its slice of x
 * (locate_hint), once the beach line is long enough to have slices.
 * Against the other algorithms, with random sites mixed in at rates
 * that shorten the beach line or turn the slices off and on again; on
 * the rings and rays alone, the sweep must take well under the
 * breakpoint tests a site of a search of this beach line (16.2 on the
 * rings and 14.8 on the rays without the slices, 5.6 and 6.3 with). */
static void test_fronts(void **state) {
    (void)state;
    enum { N = 50000 };
    static double xy[2 * N];
    static const char *const shapes[] = {"ten rings", "sixteen rays"};
    static const int stray[] = {0, 5, 30}; /* random sites, per cent */
    vt_rng r = {61};
    print_message("fronts: seed 61\n");
    for (int shape = 0; shape < 2; shape++)
        for (int k = 0; k < 3; k++) {
            for (size_t i = 0; i < N; i++) {
                double a = 6.283185307179586 * vt_unit(&r), rad;
                if ((int)(vt_next(&r) % 100) < stray[k]) {
                    xy[2 * i] = 20 * vt_unit(&r) - 10;
                    xy[2 * i + 1] = 20 * vt_unit(&r) - 10;
                    continue;
                }
                if (shape == 0) {
                    rad = 1 + (double)(vt_next(&r) % 10);
                } else {
                    rad = 10 * vt_unit(&r);
                    a = 6.283185307179586 * (double)(vt_next(&r) % 16) / 16;
                }
                xy[2 * i] = rad * cos(a);
                xy[2 * i + 1] = rad * sin(a);
            }
            char name[64];
            snprintf(name, sizeof name, "%s, %d%% random sites", shapes[shape],
                     stray[k]);
            vor_counts c;
            counts_of(name, xy, N, &c);
            print_message("%s: %.2f breakpoint tests a site, beach line %llu\n",
                          name, (double)c.breakpoint_tests / N,
                          (unsigned long long)c.beach_max);
            if (stray[k] == 0) {
                assert_true(c.beach_max > 2 * 4096);
                assert_true(c.breakpoint_tests < 8 * (uint64_t)N);
            }
        }
}

/* Sites along curves fall in the arc of one of the last two sites split
 * in, which the sweep tries before a search of the beach line
 * (locate_near), as long as most sites lately did. On a parabola, an
 * arc of a circle, a spiral and near a line, each with random sites
 * mixed in at a rate that turns the fingers off and on again, against
 * brute force and the other algorithms; near a line, where nearly every
 * site falls in the last one's arc, the sweep must then take about two
 * breakpoint tests a site (a search takes a dozen at this size). */
static void test_curves(void **state) {
    (void)state;
    enum { N = 2000 };
    static double xy[2 * N];
    static const char *const shapes[] = {"parabola", "arc of a circle",
                                         "spiral", "near a line"};
    static const int stray[] = {0, 3, 20}; /* random sites, per cent */
    vt_rng r = {59};
    print_message("curves: seed 59\n");
    for (int shape = 0; shape < 4; shape++)
        for (int k = 0; k < 3; k++) {
            for (size_t i = 0; i < N; i++) {
                double u = vt_unit(&r), x, y;
                if ((int)(vt_next(&r) % 100) < stray[k]) {
                    x = 2 * u - 1;
                    y = vt_unit(&r);
                } else if (shape == 0) {
                    x = 2 * u - 1;
                    y = x * x;
                } else if (shape == 1) {
                    x = cos(3 * u);
                    y = sin(3 * u);
                } else if (shape == 2) {
                    double t = 30 * sqrt(u);
                    x = t * cos(t);
                    y = t * sin(t);
                } else {
                    x = u;
                    y = 0.5 * u + 1e-9 * vt_gauss(&r);
                }
                xy[2 * i] = x;
                xy[2 * i + 1] = y;
            }
            char name[64];
            snprintf(name, sizeof name, "%s, %d%% random sites", shapes[shape],
                     stray[k]);
            vor_counts c;
            counts_of(name, xy, N, &c);
            if (shape == 3 && stray[k] == 0)
                assert_true(c.breakpoint_tests < 3 * (uint64_t)N);
            /* a closed curve's sites alternate between its two sides:
             * the last four arcs split in hold both sides' last two */
            if (shape <= 1 && stray[k] == 0)
                assert_true(c.breakpoint_tests < 5 * (uint64_t)N);
        }
}

/* n sites on y = k x^2, x uniform in [-1, 1) from rng r. */
static void parabola_sites(double *xy, size_t n, vt_rng *r, double k) {
    for (size_t i = 0; i < n; i++) {
        double x = 2 * vt_unit(r) - 1;
        xy[2 * i] = x;
        xy[2 * i + 1] = k * x * x;
    }
}

/* Events after the last site: on a parabola about half of them, whose
 * tops the sites' map sends to its last bucket; the buckets are fitted
 * to the events instead (refit), and the queue must then order them in a
 * comparison or two each, not a heap's dozen. Two rows of integer sites
 * leave every event after the last site with the same top: the fitted
 * buckets crowd again, are fitted again and give way to the heap. Both
 * against the other algorithms (too many sites for brute force). */
static void test_after_last_site(void **state) {
    (void)state;
    enum { N = 20000 };
    static double xy[2 * N];
    vt_rng r = {61};
    print_message("after the last site: seed 61\n");
    parabola_sites(xy, N, &r, 1);
    vor_counts c;
    counts_of("parabola, 20000 sites", xy, N, &c);
    assert_true(c.event_compares < 2 * c.circle_events);
    for (size_t i = 0; i < N; i++) {
        xy[2 * i] = (double)(i / 2);
        xy[2 * i + 1] = (double)(i % 2);
    }
    counts_of("two rows of 10000 integer sites", xy, N, &c);
}

/* Rows of equal y, long enough that the events each row's sites make,
 * whose tops lie just above the row, crowd the heap: it spills into near
 * buckets fitted to them, and the queue orders them in a few comparisons
 * each (10.8 each with the heap alone, 3.1 with the near buckets); the
 * same with one more site just above the last row. Then rows of equally
 * spaced integer x, whose rectangles' events all have one top, which no
 * map spreads (the heap keeps them). Each against the other
 * algorithms. */
static void test_crowded_rows(void **state) {
    (void)state;
    enum { ROWS = 4, PER = 3000, N = ROWS * PER + 1 };
    static double xy[2 * N];
    vt_rng r = {67};
    print_message("crowded rows: seed 67\n");
    for (size_t i = 0; i < ROWS * PER; i++) {
        xy[2 * i] = vt_unit(&r);
        xy[2 * i + 1] = (double)(i / PER);
    }
    compares_under("4 rows of 3000 random x", xy, ROWS * PER, 4);
    xy[2 * ROWS * PER] = 0.5;
    xy[2 * ROWS * PER + 1] = ROWS - 1 + 0x1p-40;
    vor_counts c;
    counts_of("the same and a site just above", xy, N, &c);
    for (size_t i = 0; i < ROWS * PER; i++) {
        xy[2 * i] = (double)(i % PER);
        xy[2 * i + 1] = 1000.0 * (double)(i / PER);
    }
    counts_of("4 rows of x = 0 .. 2999, 1000 apart", xy, ROWS * PER, &c);
}

/* Columns of equal x in a box more than four times wider than tall:
 * swept along y, every site would stay on the beach line until the
 * sweep is half a column's gap past it, all of them here; the sweep runs
 * along x instead (choose_frame), where the beach line stays short. */
static void test_columns(void **state) {
    (void)state;
    enum { COLS = 100, PER = 300, N = COLS * PER };
    static double xy[2 * N];
    vt_rng r = {71};
    print_message("columns: seed 71\n");
    for (size_t i = 0; i < N; i++) {
        xy[2 * i] = (double)(i % COLS);
        xy[2 * i + 1] = vt_unit(&r);
    }
    vor_counts c;
    counts_of("100 columns of 300 sites", xy, N, &c);
    print_message("  beach line: at most %llu arcs\n",
                  (unsigned long long)c.beach_max);
    assert_true(c.beach_max < N / 8);
}

/* A long beach line (more than LOCATE_AHEAD, 4096 arcs), whose search
 * prefetches both children of each arc it tests. Coordinates over twelve
 * decades, both signs, hold two fifths of the sites on the beach line at
 * once. Half the sites on a circle and half inside it, in no order: the
 * circle's arcs stay on the beach line until its top, and the sites
 * inside fall between them. Each diagram is checked against the other
 * algorithms (check_points). */
static void test_long_beach(void **state) {
    (void)state;
    enum { N = 40000 };
    static double xy[2 * N];
    vt_rng r = {81};
    print_message("long beach line: seed 81\n");
    for (size_t i = 0; i < 2 * N; i++)
        xy[i] = pow(10, 12 * vt_unit(&r) - 6) * (vt_next(&r) & 1 ? 1 : -1);
    vor_counts c;
    counts_of("x and y over twelve decades", xy, N, &c);
    print_message("  beach line: at most %llu arcs\n",
                  (unsigned long long)c.beach_max);
    assert_true(c.beach_max > 4096);
    for (size_t i = 0; i < N; i++) {
        double a = 6.283185307179586 * vt_unit(&r);
        double q = i % 2 ? 1 : sqrt(vt_unit(&r)); /* uniform in the disk */
        xy[2 * i] = q * cos(a);
        xy[2 * i + 1] = q * sin(a);
    }
    counts_of("a circle and the disk inside it", xy, N, &c);
    print_message("  beach line: at most %llu arcs\n",
                  (unsigned long long)c.beach_max);
    assert_true(c.beach_max > 4096);
}

/* Sites on a curve that bends down from the sweep (y = -x^2): swept up,
 * every site keeps its arc until the sweep is past the last, and the
 * events come in no order along the beach line (1.85 comparisons a
 * circle event at 10^5 sites, and a third more time than swept down).
 * A sample's upper hull chain holds it all, the lower one two sites, so
 * the sweep runs down (choose_frame): about 0.5 comparisons an event.
 * y = x^2, swept up as before, the same. Then y = -x^2 at integer x,
 * each site twice (rows of two sites, duplicates), swept down. Each
 * diagram is checked against the other algorithms (check_points). */
static void test_far_chain(void **state) {
    (void)state;
    enum { N = 20000 };
    static double xy[2 * N];
    vt_rng r = {83};
    print_message("far chain: seed 83\n");
    parabola_sites(xy, N, &r, -1);
    compares_under("y = -x^2", xy, N, 1);
    for (size_t i = 0; i < N; i++) xy[2 * i + 1] = -xy[2 * i + 1];
    compares_under("y = x^2", xy, N, 1);
    /* integers, swept down too: x and -x share a y (rows of two), and
     * every site comes twice */
    for (size_t i = 0; i < N; i++) {
        double x = (double)((long)(i / 2) - N / 4);
        xy[2 * i] = x;
        xy[2 * i + 1] = -x * x;
    }
    vor_counts c;
    counts_of("y = -x^2 at integer x, each site twice", xy, N, &c);
}

/* Data far from the origin for its extent: the sweep moves it to an
 * origin within it (choose_frame), exactly, so that a grid at 2^50 is
 * swept as the same grid at 0 -- every count the same -- and keeps its
 * lattice. Then the edges of that rule (all coordinates within a factor
 * of two of the offset, or just beyond it; negative offsets; one axis
 * moved, the other not) against brute force and the other algorithms. */
static void test_offset_frames(void **state) {
    (void)state;
    vt_rng r = {41};
    print_message("offset frames: seed 41\n");
    enum { W = 30, H = 25 };
    static double base[2 * W * H], moved[2 * W * H];
    size_t n = 0;
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            if (vt_next(&r) % 4 == 0) continue; /* holes */
            base[2 * n] = i;
            base[2 * n + 1] = -j; /* y in [-H + 1, 0]: no offset */
            n++;
        }
    const double ox = 0x1p50, oy = -0x1.8p50; /* ulp 1/4: exact */
    for (size_t i = 0; i < n; i++) {
        moved[2 * i] = base[2 * i] + ox;
        moved[2 * i + 1] = base[2 * i + 1] + oy;
    }
    vor_counts cb, cm;
    counts_of("integer grid with holes", base, n, &cb);
    counts_of("the grid at (2^50, -1.5 2^50)", moved, n, &cm);
    assert_int_equal(cm.site_events, cb.site_events);
    assert_int_equal(cm.circle_events, cb.circle_events);
    assert_int_equal(cm.breakpoint_tests, cb.breakpoint_tests);
    assert_int_equal(cm.circle_tops, cb.circle_tops);
    assert_int_equal(cm.event_compares, cb.event_compares);
    assert_int_equal(cm.event_exact, cb.event_exact);
    assert_int_equal(cm.exact, cb.exact);

    /* random sites in [lo, hi] per axis, some on the bounds, on a grid of
     * step ulp(lo) (every value a double) or coarser */
    static const double bounds[][2] = {
        {1, 2},                   /* hi = 2 lo: moved by 1 */
        {1, 0x1.0000000000001p1}, /* just beyond: not moved */
        {-2, -1},                 /* negative: moved by -1 */
        {1e15, 1e15 + 1000},      /* ulp 1/8 */
        {-1e15 - 1000, -1e15},
        {-1, 1},                  /* across zero: not moved */
        {0, 1},                   /* from zero: not moved */
        {0x1p-1000, 0x1p-999},    /* tiny: moved to [0, 2^-1000] */
    };
    const size_t nb = sizeof bounds / sizeof bounds[0];
    for (int k = 0; k < 200; k++) {
        double xy[2 * 40];
        const double *bx = bounds[vt_next(&r) % nb];
        const double *by = bounds[vt_next(&r) % nb];
        size_t m = 3 + (size_t)(vt_next(&r) % 38);
        for (size_t i = 0; i < 2 * m; i++) {
            const double *b = i % 2 ? by : bx;
            uint64_t pick = vt_next(&r) % 8;
            double t = (double)(vt_next(&r) % 9) / 8; /* few values: ties */
            xy[i] = pick == 0   ? b[0]
                    : pick == 1 ? b[1]
                                : b[0] + t * (b[1] - b[0]);
            if (xy[i] > b[1]) xy[i] = b[1];
        }
        check_points("offset axes", xy, m, 1);
    }
}

/* Rows of equal y: one row is collinear (the degenerate diagram), many
 * rows are not; with integer and random x, and rows of one or two sites. */
static void test_rows(void **state) {
    (void)state;
    vt_rng r = {55};
    print_message("rows: seed 55\n");
    double xy[2 * 600];
    for (int shape = 0; shape < 6; shape++) {
        size_t rows = shape == 0   ? 1
                      : shape == 1 ? 2
                      : shape == 2 ? 40
                      : shape == 3 ? 150
                                   : 12;
        size_t per = 600 / rows;
        size_t n = rows * per;
        for (size_t i = 0; i < n; i++) {
            size_t row = i / per;
            xy[2 * i] =
                shape == 5 ? (double)(vt_next(&r) % 17) : vt_unit(&r) * 10;
            xy[2 * i + 1] = (double)row * (shape == 4 ? 0.001 : 1.0);
        }
        char name[64];
        snprintf(name, sizeof name, "rows shape %d (%zu x %zu)", shape, rows,
                 per);
        check_points(name, xy, n, 1);
    }
}

/* The first sites in sweep order share the lowest y. */
static void test_equal_y_first(void **state) {
    (void)state;
    static const double two[] = {0, 0, 4, 0, 1, 3, 3, 5, 2, 1};
    static const double three[] = {0, 0, 2, 0, 5, 0, 1, 1, 4, 2, 2.5, 7};
    static const double wide[] = {-3, 0, -1, 0, 0,    0, 2,
                                  0,  3, 0,  0, 1e-9, 0, 1e9};
    static const double mid[] = {0, 0, 2,
                                 0, 1, 1}; /* third site above the bisector */
    check_points("two equal-y first", two, 5, 1);
    check_points("three equal-y first", three, 6, 1);
    check_points("five equal-y first", wide, 7, 1);
    check_points("equal-y first, site above their bisector", mid, 3, 1);
}

/* Sites exactly below a breakpoint, so that a vertex appears at once. */
static void test_site_below_breakpoint(void **state) {
    (void)state;
    /* (0, 10) lies below the breakpoint of (0, 0) and (3, 1): the circle
     * centred at (0, 5) through both touches y = 10 there */
    static const double a[] = {0, 0, 3, 1, 0, 10, 6, 12, -5, 4};
    check_points("below a breakpoint", a, 5, 1);
    /* a vertical bisector of two equal-y sites, hit later in the sweep, and
     * a second site at the same point of the same circle from the other
     * side */
    static const double b[] = {0, 0, 2, 0, 1, 5, -3, 8, 5, 8, 1, 9};
    check_points("below a vertical breakpoint", b, 6, 1);
    /* the whole family of lattice circles through two sites */
    vt_rng r = {66};
    print_message("below breakpoints: seed 66\n");
    for (int k = 0; k < 200; k++) {
        double xy[14];
        long cx = (long)(vt_next(&r) % 7) - 3, cy = (long)(vt_next(&r) % 7) - 3;
        /* radius 5: twelve lattice points; take the top and three others */
        static const int pts[12][2] = {{5, 0},   {4, 3},  {3, 4},  {0, 5},
                                       {-3, 4},  {-4, 3}, {-5, 0}, {-4, -3},
                                       {-3, -4}, {0, -5}, {3, -4}, {4, -3}};
        xy[0] = (double)cx;
        xy[1] = (double)(cy + 5); /* the top */
        for (int i = 1; i < 4; i++) {
            int j = (int)(vt_next(&r) % 12);
            xy[2 * i] = (double)(cx + pts[j][0]);
            xy[2 * i + 1] = (double)(cy + pts[j][1]);
        }
        for (int i = 4; i < 7; i++) {
            xy[2 * i] = (double)((long)(vt_next(&r) % 21) - 10);
            xy[2 * i + 1] = (double)((long)(vt_next(&r) % 21) - 10);
        }
        check_points("lattice circle with its top", xy, 7, 1);
    }
}

/* A site at the top of an event's circle: the event and the site are at
 * the same point; one vertex for all five cocircular sites. */
static void test_site_at_event_point(void **state) {
    (void)state;
    static const double xy[] = {-4, -3, 0, -5, 4, -3, 0, 5, 3, 4};
    vor_sites *s = sites_of(xy, 5);
    vor_diagram *d = NULL;
    assert_int_equal(vor_compute(s, VOR_FORTUNE, &d), VOR_OK);
    assert_int_equal(d->n_vertices, 1);
    assert_int_equal(d->n_edges, 5);
    assert_true(d->vertex_xy[0] == 0 && d->vertex_xy[1] == 0);
    vor_diagram_free(d);
    vor_sites_free(s);
    check_points("site at the event point", xy, 5, 1);
    static const double xy2[] = {-4, -3, 0, -5, 4,  -3, 0,   5,
                                 3,  4,  0, 0,  10, 10, -10, 9};
    check_points("site at the event point, with the centre", xy2, 8, 1);
}

/* All sites on one circle: one vertex with a ray per site. */
static void test_all_cocircular(void **state) {
    (void)state;
    size_t n;
    double *xy = vt_int_circle(1105, 0, &n);
    assert_non_null(xy);
    vor_sites *s = sites_of(xy, n);
    vor_diagram *d = NULL;
    assert_int_equal(vor_compute(s, VOR_FORTUNE, &d), VOR_OK);
    assert_int_equal(d->n_vertices, 1);
    assert_int_equal(d->n_edges, n);
    assert_int_equal(d->n_rays, n);
    vor_diagram_free(d);
    vor_sites_free(s);
    check_points("integer circle without centre", xy, n, 1);
    free(xy);
}

/* Coordinates of wildly different magnitudes in one input: the filters'
 * range conditions fail and the exact paths decide. */
static void test_extreme_ranges(void **state) {
    (void)state;
    static const double a[] = {0,     0,     1e-300, 0,     0, 1e-300,
                               1e300, 1e300, -1e300, 1e300, 1, 1};
    check_points("1e-300 with 1e300", a, 6, 1);
    vt_rng r = {77};
    print_message("extreme ranges: seed 77\n");
    for (int k = 0; k < 300; k++) {
        double xy[24];
        size_t n = 4 + (size_t)(vt_next(&r) % 9);
        for (size_t i = 0; i < 2 * n; i++) {
            double m = (double)((long)(vt_next(&r) % 5) - 2);
            int e = (int)(vt_next(&r) % 3) * 400 - 400 + (int)(vt_next(&r) % 3);
            xy[i] = ldexp(m, e);
        }
        check_points("mixed magnitudes", xy, n, 1);
    }
}

/* Sites more than four times wider than tall, which the sweep runs
 * along x (choose_frame), against the brute force and the other
 * algorithms: sites log-uniform in x over 2^-60 .. 2^60 and uniform in y
 * in [0, 1] (swept along y, the circles of sites far apart in x have tops
 * known only to the scale of x: 39% of the event comparisons were exact;
 * along x, under one in eight), a 1000 x 1 box, a hexagonal lattice of
 * horizontal rows five times wider than tall (its columns, swept along
 * x, are rows of equal sweep coordinate), an integer grid with
 * duplicates, sites on a line but one, and boxes of exactly four and
 * just over four times their height. */
/* Reports part of whole and requires it to be under one in k. */
static void under_one_in(uint64_t k, uint64_t part, const char *part_name,
                         uint64_t whole, const char *whole_name) {
    print_message("  %llu %s, %llu %s\n", (unsigned long long)whole,
                  whole_name, (unsigned long long)part, part_name);
    assert_true(part * k < whole);
}

static void test_wide_sets(void **state) {
    (void)state;
    enum { N = 2000 };
    static double xy[2 * N];
    vt_rng r = {91};
    print_message("wide sets: seed 91\n");
    for (size_t i = 0; i < N; i++) {
        xy[2 * i] = pow(2, 120 * vt_unit(&r) - 60);
        xy[2 * i + 1] = vt_unit(&r);
    }
    vor_counts c;
    size_t n;
    counts_of("x log-uniform over 2^-60 .. 2^60, y in [0, 1]", xy, N, &c);
    /* nearly collinear triples of sites far apart in x: tops close
     * together just above their highest site, which the bounds relative
     * to that site separate (901 of 18,496 comparisons went exact with
     * the double-double bounds alone) */
    under_one_in(100, c.exact, "exact", c.event_compares,
                 "event comparisons");
    /* past the filters' safe range: the events' intervals come from
     * their exact circles (tight_top), and two events meet the exact
     * comparison about never (before: 37,730 of 51,099 comparisons) */
    for (size_t i = 0; i < N; i++) {
        xy[2 * i] = pow(2, 1000 * vt_unit(&r) - 500);
        xy[2 * i + 1] = vt_unit(&r);
    }
    counts_of("x log-uniform over 2^-500 .. 2^500, y in [0, 1]", xy, N, &c);
    under_one_in(100, c.event_exact, "exact", c.event_compares,
                 "event comparisons");
    /* a city and one stray point at 10^300: the set is out of the
     * filters' range, but the city's sites are scaled into it
     * (bulk_scale) and their predicates pass the range check of each
     * call: under 1 in 100 breakpoint tests leaves the inline filter
     * (before: 7,411 of 12,975, each rescaled) */
    for (size_t i = 0; i < N; i++) {
        xy[2 * i] = 8.45 + 0.1 * vt_unit(&r);
        xy[2 * i + 1] = 47.3 + 0.1 * vt_unit(&r);
    }
    xy[0] = xy[1] = 1e300;
    counts_of("a city and a stray point at 10^300", xy, N, &c);
    under_one_in(100, c.breakpoint_exact, "past the inline filter",
                 c.breakpoint_tests, "breakpoint tests");
    /* two lines of sites 10^-3 long, 10^6 apart: the upper line's sites meet the
     * breakpoints of the lower line's pairs, vertical bisectors, which
     * bp_side decides itself (F's filter failed nearly every test), and
     * events whose tops lie just above the upper line, which the bounds
     * relative to the highest site order (double-double bounds could not)
     * and which wait after the last site once shown to come after it */
    for (size_t i = 0; i < N; i++) {
        xy[2 * i] = 1e-3 * vt_unit(&r);
        xy[2 * i + 1] = i % 2 ? 1e6 : 0;
    }
    counts_of("two lines 1e-3 long, 10^6 apart", xy, N, &c);
    under_one_in(100, c.breakpoint_exact, "past the inline filter",
                 c.breakpoint_tests, "breakpoint tests");
    under_one_in(100, c.event_exact, "exact", c.event_compares,
                 "event comparisons");
    /* a grid turned by 30 degrees and rounded: a third of its cells stay
     * exactly cocircular, and their two triangles' events, equal tops
     * that no bounds separate, are shown equal by one incircle test
     * (one_circle), not by the exact comparison of their circles */
    n = 0;
    for (int i = 0; i < 44; i++)
        for (int j = 0; j < 44; j++, n++) {
            xy[2 * n] = i * 0.8660254037844387 - j * 0.5;
            xy[2 * n + 1] = i * 0.5 + j * 0.8660254037844387;
        }
    counts_of("44 x 44 grid turned by 30 degrees", xy, n, &c);
    under_one_in(100, c.event_exact, "exact", c.event_compares,
                 "event comparisons");
    for (size_t i = 0; i < N; i++) {
        xy[2 * i] = 1000 * vt_unit(&r);
        xy[2 * i + 1] = vt_unit(&r);
    }
    check_points("1000 x 1 box", xy, N, 1);
    n = 0;
    for (int j = 0; j < 9; j++) /* rows sqrt(3)/2 apart, 9 x 100 */
        for (int i = 0; i < 100; i++, n++) {
            xy[2 * n] = i + 0.5 * (j % 2);
            xy[2 * n + 1] = j * 0.8660254037844386;
        }
    check_points("hexagonal lattice, 100 x 9", xy, n, 1);
    for (size_t i = 0; i < N; i++) {
        xy[2 * i] = (double)(vt_next(&r) % 60);
        xy[2 * i + 1] = (double)(vt_next(&r) % 8);
    }
    check_points("integer grid 60 x 8 with duplicates", xy, N, 1);
    for (size_t i = 0; i < 500; i++) {
        xy[2 * i] = (double)i;
        xy[2 * i + 1] = i == 250 ? 1e-3 : 0;
    }
    check_points("a line and one site off it", xy, 500, 1);
    for (int k = 0; k < 2; k++) {
        for (size_t i = 0; i < 500; i++) {
            xy[2 * i] = i == 0 ? 0 : i == 1 ? (k ? 4.000000000000001 : 4)
                                            : 4 * vt_unit(&r);
            xy[2 * i + 1] = i == 0 ? 0 : i == 1 ? 1 : vt_unit(&r);
        }
        check_points(k ? "just over 4 x 1" : "4 x 1", xy, 500, 1);
    }
}

/* Every path of the site sort, each checked against the other algorithms:
 * the bucket sort with one huge bucket (an outlier stretches the y range,
 * so the other sites share the first bucket and are heapsorted), the
 * radix fallback (a y range beyond the doubles), a row of equal y (one
 * crowded bucket), and the small sorts just below and above TINY_SORT. */
static void test_sort_paths(void **state) {
    (void)state;
    size_t n = 3000;
    double *xy = vt_uniform(n, 21);
    assert_non_null(xy);
    print_message("sort paths: vt_uniform seed 21\n");
    xy[1] = 1e300; /* one far outlier above */
    check_points("outlier y 1e300", xy, n, 1);
    xy[1] = 1e308;
    xy[3] = -1e308; /* y1 - y0 overflows */
    check_points("y range beyond the doubles", xy, n, 1);
    for (size_t i = 0; i < n; i++) xy[2 * i + 1] = 0.5; /* one row... */
    xy[1] = 0.25; /* ...but for one site, so not collinear */
    check_points("one row and a site", xy, n, 1);
    free(xy);
    /* the rank map's crowded bins and its clamps: a dense city and one
     * stray point, log-normal and twelve-decade y with both signs, nested
     * clusters, a few rows of equal y */
    xy = vt_uniform(n, 23);
    assert_non_null(xy);
    vt_rng r = {23};
    for (size_t i = 0; i < n; i++) {
        xy[2 * i] = 8.45 + 0.1 * xy[2 * i];
        xy[2 * i + 1] = 47.25 + 0.1 * xy[2 * i + 1];
    }
    xy[0] = xy[1] = 0;
    check_points("a city and a stray point at (0, 0)", xy, n, 1);
    for (size_t i = 0; i < n; i++) xy[2 * i + 1] = exp(2 * vt_gauss(&r));
    check_points("log-normal y", xy, n, 1);
    for (size_t i = 0; i < n; i++)
        xy[2 * i + 1] = pow(10, 12 * vt_unit(&r) - 6) *
                        (vt_next(&r) & 1 ? 1 : -1);
    check_points("y over twelve decades, both signs", xy, n, 1);
    for (size_t i = 0; i < n; i++)
        xy[2 * i + 1] = (double)(i % 5) + pow(10, -(double)(i % 7)) *
                                              vt_unit(&r);
    check_points("nested clusters in y", xy, n, 1);
    for (size_t i = 0; i < n; i++) xy[2 * i + 1] = (double)(i % 7);
    check_points("seven rows of equal y", xy, n, 1);
    free(xy);
    /* a bulk and a few strays, at sizes whose maps are fitted to the bulk
     * (bulk_range): the strays' ranks clamp to the ends, in the sort and
     * in the event buckets; up to n / 1024 strays, and more (the whole
     * range); an even bulk (the linear map) and a gaussian one (the grid) */
    n = 20000;
    xy = vt_uniform(n, 24);
    assert_non_null(xy);
    for (int k = 0; k < 8; k++) {
        const size_t strays[] = {1, 1, 2, 19, 20, 40, 3, 19};
        for (size_t i = 0; i < n; i++) {
            double u = vt_unit(&r), v = vt_unit(&r);
            xy[2 * i] = 8.45 + 0.1 * u;
            xy[2 * i + 1] = k >= 6 ? 47.3 + 0.01 * vt_gauss(&r)
                                   : 47.25 + 0.1 * v;
        }
        for (size_t j = 0; j < strays[k]; j++) {
            size_t i = (size_t)(vt_next(&r) % n);
            xy[2 * i] = -100 + 200 * vt_unit(&r);
            xy[2 * i + 1] = k == 1 || (k >= 4 && j % 2) ? 1e6 : -1e3 * (double)j;
        }
        char name[80];
        snprintf(name, sizeof name, "a %s city and %zu strays",
                 k >= 6 ? "gaussian" : "square", strays[k]);
        check_points(name, xy, n, 1);
    }
    free(xy);
    for (size_t k = 15; k <= 18; k++) {
        double *u = vt_uniform(k, 22 + (unsigned)k);
        assert_non_null(u);
        check_points("few sites", u, k, 1);
        free(u);
    }
}

/* The event queue's paths (fortune.c, "Event queue"): buckets for the whole
 * sweep (uniform sites); events whose tops lie exactly on bucket
 * boundaries, so that the earliest event is looked for in the next bucket
 * too (a thin checkerboard of 4R sites over a y range of R: one bucket per
 * quarter unit, and each square of four sites has its top at an integer);
 * buckets poured into the heap wholesale (a flat band and one far site;
 * events of unbounded interval from nearly collinear sites); buckets
 * crowded by events of nearly equal tops (concentric rings), which the
 * heap in front of the buckets orders in O(log) comparisons each, where
 * a scan of the crowded bucket per event took about twenty; and small
 * integer sets just above the size from which buckets are used, where
 * equal tops are the rule. */
static void test_event_queue(void **state) {
    (void)state;
    size_t n = 20000;
    double *xy = vt_uniform(n, 31);
    assert_non_null(xy);
    print_message("event queue: vt_uniform seed 31\n");
    check_points("uniform, buckets throughout", xy, n, 1);
    /* the y maps behind the buckets: the grid of equal y steps, and the
     * key tables when a far site crowds the grid */
    double *yv = malloc(2 * n * sizeof *yv);
    assert_non_null(yv);
    vt_rng g = {31};
    for (size_t i = 0; i < n; i++) {
        yv[2 * i] = xy[2 * i];
        yv[2 * i + 1] = vt_gauss(&g);
    }
    check_points("gaussian y: the grid of equal y steps", yv, n, 1);
    for (size_t i = 0; i < n; i++)
        yv[2 * i + 1] = exp(2 * vt_gauss(&g)) + (i == 7 ? 1e9 : 0);
    check_points("log-normal y and a far site: the tables", yv, n, 1);
    free(yv);
    for (size_t i = 0; i < n; i++) xy[2 * i + 1] *= 1e-6;
    xy[1] = 1e3;
    check_points("flat band and a far site", xy, n, 1);
    /* nearly collinear triples, whose float orientation is undecided:
     * events with unbounded intervals, which read every bucket */
    for (size_t i = 0; i < n; i++) xy[2 * i + 1] = xy[2 * i] / 3;
    xy[1] = 0.9;
    check_points("sites rounded onto a line, and one off it", xy, n, 1);
    /* the lower half of a circle: every circle's top lies above the last
     * site, so every event waits until the sites are done */
    for (size_t i = 0; i < n; i++) {
        double a = 3.141592653589793 * (1 + (double)i / (double)n);
        xy[2 * i] = cos(a);
        xy[2 * i + 1] = sin(a);
    }
    check_points("lower half circle: events after the last site", xy, n, 1);
    check_points("lower half circle, small: the heap", xy, 40, 1);
    /* 20 rings around the origin, sites at random angles: the events of a
     * ring have their tops near its top, a bucket or two apart */
    for (size_t i = 0; i < n; i++) {
        double a = 6.283185307179586 * vt_unit(&g), k = (double)(1 + i % 20);
        xy[2 * i] = k * cos(a);
        xy[2 * i + 1] = k * sin(a);
    }
    compares_under("20 rings, buckets crowded by nearly equal tops", xy, n, 8);
    free(xy);

    enum { R = 400 };
    double *cb = malloc(2 * 4 * (size_t)R * sizeof *cb);
    assert_non_null(cb);
    size_t m = 0;
    for (int y = 0; y <= R; y++) {
        int row = y == 0 ? 3 : y == R ? 1 : 4; /* 4 (R + 1) - 4 sites */
        for (int k = 0; k < row; k++) {
            cb[2 * m] = 2 * k + (y & 1);
            cb[2 * m + 1] = y;
            m++;
        }
    }
    assert_int_equal(m, 4 * (size_t)R);
    check_points("checkerboard, tops on bucket boundaries", cb, m, 1);
    free(cb);

    const uint64_t base = 4242;
    const int count = 200;
    print_message("event queue: integer seeds %llu..%llu\n",
                  (unsigned long long)base,
                  (unsigned long long)(base + count - 1));
    for (int k = 0; k < count; k++) {
        vt_rng r = {base + (uint64_t)k};
        size_t c = 64 + (size_t)(vt_next(&r) % 200);
        long range = 8 + (long)(vt_next(&r) % 40);
        double pts[2 * 264];
        for (size_t i = 0; i < 2 * c; i++)
            pts[i] = (double)(vt_next(&r) % (uint64_t)range);
        char name[64];
        snprintf(name, sizeof name, "seed %llu (n %zu, range %ld)",
                 (unsigned long long)(base + (uint64_t)k), c, range);
        check_points(name, pts, c, 1);
    }
}

/* 0, 1, 2 and collinear sites through vor_compute (the degenerate builder),
 * and the entry point's own argument checks. */
static void test_trivial_inputs(void **state) {
    (void)state;
    static const double pts[] = {0.5, 0.25, 1.5, 2.25, 2.5, 4.25, 3.5, 6.25};
    for (size_t n = 0; n <= 4; n++) {
        vor_sites *s = sites_of(n ? pts : NULL, n);
        vor_diagram *d = NULL;
        char msg[256];
        assert_int_equal(vor_compute(s, VOR_FORTUNE, &d), VOR_OK);
        if (vor_check(d, s, msg, sizeof msg)) fail_msg("n = %zu: %s", n, msg);
        assert_int_equal(d->n_vertices, 0);
        if (n < 3) {
            vor_diagram *e = (vor_diagram *)1;
            assert_int_equal(vor__fortune(s, &e), VOR_EINVAL);
            assert_null(e);
        } else {
            /* collinear sites given to the sweep directly: it finds no
             * vertex and returns the degenerate diagram */
            vor_diagram *e = NULL;
            assert_int_equal(vor__fortune(s, &e), VOR_OK);
            assert_true(vor_diagram_equal(d, e));
            vor_diagram_free(e);
        }
        vor_diagram_free(d);
        vor_sites_free(s);
    }
    assert_int_equal(vor__fortune(NULL, NULL), VOR_EINVAL);
}

/* The allocations one sweep of s makes (none refused; it must succeed). */
static long allocations_of(const vor_sites *s) {
    fault_arm(-1);
    vor_diagram *d = NULL;
    vor_status st = vor__fortune(s, &d);
    long count = fault_seen;
    fault_disarm();
    assert_int_equal(st, VOR_OK);
    vor_diagram_free(d);
    return count;
}

/* One sweep of s with allocation k refused (and allocation k2 too, if
 * k2 >= 0): 1 if it still made the very diagram want, 0 if it failed
 * with VOR_ENOMEM and no diagram; anything else fails the test. */
static int sweep_refused(const vor_sites *s, long k2, long k,
                         const vor_diagram *want) {
    if (k2 >= 0)
        fault_arm_two(k2, k);
    else
        fault_arm(k);
    vor_diagram *d = (vor_diagram *)1;
    vor_status st = vor__fortune(s, &d);
    fault_disarm();
    if (st == VOR_OK) {
        assert_true(vor_diagram_equal(d, want));
        vor_diagram_free(d);
        return 1;
    }
    assert_int_equal(st, VOR_ENOMEM);
    assert_null(d);
    return 0;
}

/* Every allocation of a sweep whose heap spills into near buckets (rows
 * of equal y, as test_crowded_rows) fails in turn: VOR_ENOMEM and no
 * diagram, or the very diagram -- a spill refused its memory leaves the
 * events in the heap, and so does a near-bucket map that cannot be
 * built. LeakSanitizer checks at exit that nothing was lost. */
static void test_alloc_failures_spill(void **state) {
    (void)state;
    enum { ROWS = 4, PER = 3000, N = ROWS * PER };
    static double xy[2 * N];
    vt_rng r = {67};
    for (size_t i = 0; i < N; i++) {
        xy[2 * i] = vt_unit(&r);
        xy[2 * i + 1] = (double)(i / PER);
    }
    vor_sites *s = sites_of(xy, N);
    vor_diagram *want = NULL;
    assert_int_equal(vor__fortune(s, &want), VOR_OK);
    long count = allocations_of(s);
    int harmless = 0;
    for (long k = 0; k < count; k++) harmless += sweep_refused(s, -1, k, want);
    print_message("spilling rows: %ld allocations, %d refused harmlessly\n",
                  count, harmless);
    vor_diagram_free(want);
    vor_sites_free(s);
}

/* Every allocation of the sweep fails in turn. */
static void test_alloc_failures(void **state) {
    (void)state;
    size_t n = 3000;
    double *xy = vt_uniform(n, 9);
    assert_non_null(xy);
    /* cocircular groups too, so that the exact tie comparison and the
     * cocircular conversion allocate */
    for (size_t i = 0; i < 400; i++) {
        xy[2 * i] = (double)(i % 20);
        xy[2 * i + 1] = (double)(i / 20) + 2;
    }
    vor_sites *s = sites_of(xy, n);
    vor_diagram *want = NULL;
    assert_int_equal(vor__fortune(s, &want), VOR_OK);
    long count = allocations_of(s);
    print_message("allocations: %ld\n", count);
    int tolerated = 0, in_room = 0;
    long room = -1;
    for (long k = 0; k < count; k++) {
        if (!sweep_refused(s, -1, k, want)) continue;
        /* only two kinds of allocation may fail without harm: the
         * sweep's room for every arc and record it can hold (four
         * blocks: then it starts small and doubles), and the two
         * shrinking reallocs of the cocircular conversion
         * (vor__mesh_to_diagram) */
        if (room < 0) room = k;
        if (k - room < 4)
            in_room++;
        else
            tolerated++;
    }
    /* the room's four blocks (arcs, colours, records, their shapes) come
     * one after another, and each one refused makes the sweep start
     * small */
    assert_true(room >= 0);
    assert_int_equal(in_room, 4);
    assert_true(tolerated <= 2);
    /* Without the room taken at once: each allocation of the small
     * arrays and their doubling fails in turn, and only the conversion's
     * shrinking reallocs may fail without harm. */
    vor_diagram *d = NULL;
    fault_arm(room);
    assert_int_equal(vor__fortune(s, &d), VOR_OK);
    long count_small = fault_seen;
    fault_disarm();
    vor_diagram_free(d);
    int failed = 0, harmless = 0;
    for (long k = room + 1; k < count_small; k++) {
        if (sweep_refused(s, room, k, want))
            harmless++;
        else
            failed++;
    }
    print_message("allocations with small arrays: %ld, of which %d fail "
                  "the sweep\n", count_small, failed);
    assert_true(count_small > count);
    assert_true(harmless <= 2);
    assert_int_equal(vor__fortune(s, &d), VOR_OK);
    assert_true(vor_diagram_equal(d, want));
    vor_diagram_free(d);
    vor_diagram_free(want);
    vor_sites_free(s);
    free(xy);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bp_poly),
        cmocka_unit_test(test_bp_side_on_circle),
        cmocka_unit_test(test_bp_side_equal_y),
        cmocka_unit_test(test_circle_top_bounds),
        cmocka_unit_test(test_circle_top_refined),
        cmocka_unit_test(test_off_cmp),
        cmocka_unit_test(test_circle_exact_small),
        cmocka_unit_test(test_long_rows),
        cmocka_unit_test(test_site_first),
        cmocka_unit_test(test_exact_top),
        cmocka_unit_test(test_circle_cmp),
        cmocka_unit_test(test_box_cmp),
        cmocka_unit_test(test_level_cmp),
        cmocka_unit_test(test_turned_cmp),
        cmocka_unit_test(test_image_cmp_small),
        cmocka_unit_test(test_shape_cmp),
        cmocka_unit_test(test_trivial_inputs),
        cmocka_unit_test(test_equal_y_first),
        cmocka_unit_test(test_site_below_breakpoint),
        cmocka_unit_test(test_site_at_event_point),
        cmocka_unit_test(test_all_cocircular),
        cmocka_unit_test(test_rows),
        cmocka_unit_test(test_decimal_grid),
        cmocka_unit_test(test_hex_doubles),
        cmocka_unit_test(test_offset_frames),
        cmocka_unit_test(test_curves),
        cmocka_unit_test(test_fronts),
        cmocka_unit_test(test_after_last_site),
        cmocka_unit_test(test_crowded_rows),
        cmocka_unit_test(test_columns),
        cmocka_unit_test(test_far_chain),
        cmocka_unit_test(test_extreme_ranges),
        cmocka_unit_test(test_wide_sets),
        cmocka_unit_test(test_sort_paths),
        cmocka_unit_test(test_event_queue),
        cmocka_unit_test(test_alloc_failures),
        cmocka_unit_test(test_alloc_failures_spill),
        cmocka_unit_test(test_standard_sets),
        cmocka_unit_test(test_small_random),
        cmocka_unit_test(test_unit_circle_1e5),
        cmocka_unit_test(test_grid_1000),
        cmocka_unit_test(test_pixels),
        cmocka_unit_test(test_long_beach),
    };
    return cmocka_run_group_tests_name("core/fortune", tests, NULL, NULL);
}
