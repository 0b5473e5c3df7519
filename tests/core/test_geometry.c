/* test_geometry.c -- vor_circumcenter and vor_bisector_dir against exact
 * references.
 *
 * The circumcentre reference is computed with GMP rationals from the exact
 * coordinates. These are output values, not decisions, so the comparison
 * uses an error bound, derived from the triangle's conditioning: with
 * u = a + n / (2 det), a relative perturbation of eps in every difference
 * and operation moves u by about eps (P_n / (2 |det|) + |u - a| P_d / |det|)
 * where P_n, P_d are the numerator's and det's sums of absolute terms; we
 * allow 16 times that plus one ulp of the result. Random tests use a fixed
 * seed, printed; VOR_TEST_SEED replays another.
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

#include "../../core/internal.h"
#include "../support/testsets.h"

static uint64_t seed;
static vt_rng rng;

static int setup_seed(void **state) {
    (void)state;
    const char *s = getenv("VOR_TEST_SEED");
    seed = s ? strtoull(s, NULL, 0) : 20240613u;
    rng.s = seed;
    printf("# test_geometry seed %llu (set VOR_TEST_SEED to change)\n",
           (unsigned long long)seed);
    return 0;
}

static double sym(void) { return 2 * vt_unit(&rng) - 1; }

/* ---- circumcentre reference ---------------------------------------------- */

typedef struct ref {
    double u[2];     /* exact centre, rounded toward zero */
    double tol[2];   /* allowed error per coordinate */
    int finite;      /* 0 if collinear or the centre is out of range */
} ref;

static void make_ref(const double *a, const double *b, const double *c,
                     ref *r) {
    mpq_t bx, by, cx, cy, t, u, b2, c2, det, nx, ny, ox, oy;
    mpq_inits(bx, by, cx, cy, t, u, b2, c2, det, nx, ny, ox, oy, NULL);
    mpq_set_d(bx, b[0]);
    mpq_set_d(t, a[0]);
    mpq_sub(bx, bx, t);
    mpq_set_d(cx, c[0]);
    mpq_sub(cx, cx, t);
    mpq_set_d(by, b[1]);
    mpq_set_d(t, a[1]);
    mpq_sub(by, by, t);
    mpq_set_d(cy, c[1]);
    mpq_sub(cy, cy, t);
    mpq_mul(t, bx, bx);
    mpq_mul(u, by, by);
    mpq_add(b2, t, u);
    mpq_mul(t, cx, cx);
    mpq_mul(u, cy, cy);
    mpq_add(c2, t, u);
    mpq_mul(t, bx, cy);
    mpq_mul(u, by, cx);
    mpq_sub(det, t, u);
    r->finite = mpq_sgn(det) != 0;
    if (r->finite) {
        mpq_mul(t, cy, b2);
        mpq_mul(u, by, c2);
        mpq_sub(nx, t, u);
        mpq_mul(t, bx, c2);
        mpq_mul(u, cx, b2);
        mpq_sub(ny, t, u);
        mpq_add(t, det, det);
        mpq_div(ox, nx, t); /* offset from a */
        mpq_div(oy, ny, t);
        mpq_set_d(t, a[0]);
        mpq_add(t, t, ox);
        mpq_set_d(u, 0x1p1020);
        mpq_abs(nx, t);
        if (mpq_cmp(nx, u) > 0)
            r->finite = 0;
        r->u[0] = mpq_get_d(t);
        mpq_set_d(t, a[1]);
        mpq_add(t, t, oy);
        mpq_abs(ny, t);
        if (mpq_cmp(ny, u) > 0)
            r->finite = 0;
        r->u[1] = mpq_get_d(t);
    }
    if (r->finite) {
        /* the bound, in long double (no overflow for any double input) */
        long double lbx = mpq_get_d(bx), lby = mpq_get_d(by);
        long double lcx = mpq_get_d(cx), lcy = mpq_get_d(cy);
        long double lb2 = lbx * lbx + lby * lby, lc2 = lcx * lcx + lcy * lcy;
        long double ldet = fabsl(lbx * lcy - lby * lcx);
        long double pd = fabsl(lbx * lcy) + fabsl(lby * lcx);
        long double pnx = fabsl(lcy) * lb2 + fabsl(lby) * lc2;
        long double pny = fabsl(lbx) * lc2 + fabsl(lcx) * lb2;
        long double offx = mpq_get_d(ox), offy = mpq_get_d(oy);
        const long double eps = 0x1p-53L;
        long double tx =
            16 * eps * (pnx / (2 * ldet) + fabsl(offx) * pd / ldet);
        long double ty =
            16 * eps * (pny / (2 * ldet) + fabsl(offy) * pd / ldet);
        /* plus rounding of a + offset and of the reference itself */
        tx += 4 * eps * (fabsl((long double)a[0]) + fabsl(offx)) +
              2 * DBL_TRUE_MIN;
        ty += 4 * eps * (fabsl((long double)a[1]) + fabsl(offy)) +
              2 * DBL_TRUE_MIN;
        r->tol[0] = tx > DBL_MAX ? DBL_MAX : (double)tx;
        r->tol[1] = ty > DBL_MAX ? DBL_MAX : (double)ty;
    }
    mpq_clears(bx, by, cx, cy, t, u, b2, c2, det, nx, ny, ox, oy, NULL);
}

static long n_centres;
static double worst_ratio; /* largest error / tolerance seen */

/* Checks one triple; returns 1 if it was checkable (non-collinear, centre
 * in range). */
static int check_centre(const double *a, const double *b, const double *c) {
    ref r;
    make_ref(a, b, c, &r);
    if (!r.finite)
        return 0;
    double u[2], v[2];
    vor_circumcenter(a, b, c, u);
    vor_circumcenter(a, b, c, v);
    assert_memory_equal(u, v, sizeof u); /* deterministic */
    for (int k = 0; k < 2; k++) {
        assert_false(u[k] == 0 && signbit(u[k]));
        double err = fabs(u[k] - r.u[k]);
        if (!(err <= r.tol[k])) {
            print_error("centre of (%a,%a) (%a,%a) (%a,%a): [%d] = %a, "
                        "exact %a, error %g > bound %g\n",
                        a[0], a[1], b[0], b[1], c[0], c[1], k, u[k], r.u[k],
                        err, r.tol[k]);
            fail();
        }
        if (r.tol[k] > 0 && err / r.tol[k] > worst_ratio) {
            worst_ratio = err / r.tol[k];
            if (getenv("VOR_TEST_VERBOSE"))
                printf("# worst so far: (%a,%a) (%a,%a) (%a,%a) [%d] %a vs "
                       "%a, bound %a\n", a[0], a[1], b[0], b[1], c[0], c[1],
                       k, u[k], r.u[k], r.tol[k]);
        }
    }
    n_centres++;
    return 1;
}

/* ---- circumcentre tests -------------------------------------------------- */

static void test_centre_simple(void **state) {
    (void)state;
    const double a[2] = {0, 0}, b[2] = {2, 0}, c[2] = {0, 2};
    double u[2];
    vor_circumcenter(a, b, c, u);
    assert_true(u[0] == 1 && u[1] == 1);
    const double p[2] = {1, 1}, q[2] = {3, 1}, s[2] = {2, 2};
    vor_circumcenter(p, q, s, u);
    assert_true(u[0] == 2 && u[1] == 1);
    check_centre(a, b, c);
    check_centre(p, q, s);
}

static void test_centre_random_scales(void **state) {
    (void)state;
    const double scales[] = {1,     1e-300, 1e300, 1e15,    1e-9,
                             0x1p-1060, 1e-200, 1e200, 1e-320, 1e305,
                             1e-110, 1e-150, 1e120, 0x1p-301, 0x1p299};
    const int ns = (int)(sizeof scales / sizeof scales[0]);
    int checked = 0;
    for (int k = 0; k < 45000; k++) {
        double s = scales[k % ns];
        /* offsets of 1e9 times the spread */
        double off = (k / ns) % 3 == 0 || s > 1e290 ? 0 : 1e9 * s;
        double p[3][2];
        for (int i = 0; i < 3; i++) {
            p[i][0] = sym() * s + off;
            p[i][1] = sym() * s - off;
        }
        checked += check_centre(p[0], p[1], p[2]);
    }
    printf("# random scales: %d centres checked, worst error %.3g of the "
           "bound\n", checked, worst_ratio);
    assert_true(checked > 44000);
}

/* One call mixing magnitudes the double formula cannot hold at once. */
static void test_centre_mixed_ranges(void **state) {
    (void)state;
    const double big[] = {1e300, 0x1p1000, 1e200, 1, 3.5};
    const double tiny[] = {1e-300, 0x1p-1000, 1e-200, 1e-320, 0x1p-1074};
    for (int i = 0; i < 5; i++) {
        for (int j = 0; j < 5; j++) {
            /* right angle at a: the centre is the midpoint of b and c */
            const double a[2] = {0, 0}, b[2] = {big[i], 0},
                         c[2] = {0, tiny[j]};
            double u[2];
            vor_circumcenter(a, b, c, u);
            assert_true(u[0] == big[i] / 2);
            assert_true(u[1] == tiny[j] / 2 ||
                        (tiny[j] == 0x1p-1074 && u[1] <= 0x1p-1074));
            check_centre(a, b, c);
            check_centre(c, a, b);
            /* huge offset with a tiny triangle, and the reverse */
            const double p[2] = {big[i], -big[i]},
                         q[2] = {big[i] + 2 * big[i] * DBL_EPSILON, -big[i]},
                         r[2] = {big[i], -big[i] + 2 * big[i] * DBL_EPSILON};
            check_centre(p, q, r);
        }
    }
    /* differences that overflow */
    const double a[2] = {-DBL_MAX, -DBL_MAX}, b[2] = {DBL_MAX, -DBL_MAX},
                 c[2] = {-DBL_MAX, DBL_MAX};
    double u[2];
    vor_circumcenter(a, b, c, u);
    assert_true(u[0] == 0 && u[1] == 0);
    const double d[2] = {0, DBL_MAX / 2}, e[2] = {DBL_MAX / 2, 0},
                 f[2] = {-DBL_MAX / 2, 0};
    vor_circumcenter(d, e, f, u);
    assert_true(fabs(u[0]) <= 1e292 && u[1] == 0);
    check_centre(d, e, f);
}

/* Flat triangles, including ones whose double determinant rounds to 0
 * although the exact one (vor_orient2d) is not. */
/* However flat or thin the triangle, its centre is within 2^-28 of its
 * distance from a (check_centre's bound grows with the conditioning: a
 * rounded determinant passed it off by a per cent, and a needle's
 * cancelled numerator by 2^-27). */
static void check_close(const double *a, const double *b, const double *c) {
    ref r;
    make_ref(a, b, c, &r);
    if (!r.finite) return;
    double u[2];
    vor_circumcenter(a, b, c, u);
    double off = fmax(fabs(r.u[0] - a[0]), fabs(r.u[1] - a[1]));
    for (int j = 0; j < 2; j++) {
        double err = fabs(u[j] - r.u[j]);
        if (!(err <= 0x1p-28 * off + 4 * DBL_EPSILON * fabs(r.u[j]))) {
            print_error("centre of (%a,%a) (%a,%a) (%a,%a): [%d] = %a, exact "
                        "%a, off by %g of %g\n", a[0], a[1], b[0], b[1], c[0],
                        c[1], j, u[j], r.u[j], err, off);
            fail();
        }
    }
}

/* Needles and slivers: two sites 2^-10 to 2^-45 of the third's distance
 * apart, in every order; among them, the two found in use (a site 10^10
 * away from two 1.4 10^-10 apart, whose centre came out at the far site;
 * two sites 10^-7 apart on a sine curve and one 3 away). */
static void test_centre_needles(void **state) {
    (void)state;
    const double far[3][2] = {{0x1.2a05f2p+33, 0x1.2a05f2p+33},
                              {-0x1.8425f31e7df3ep-33, 0x1.b90f94b6cee1ap-32},
                              {-0x1.45024e691dd19p-35, 0x1.c1ba7f483f00fp-32}};
    const double sine[3][2] = {{0x1.c53707bfba27ep+5, 0x1.a5f7a7620cbb2p-4},
                               {0x1.dcb2149e2a947p+5, 0x1.a664b1d56aea5p-4},
                               {0x1.dcb214ab81f9ep+5, 0x1.a664974b0b01bp-4}};
    for (int k = 0; k < 3; k++) {
        check_close(far[k], far[(k + 1) % 3], far[(k + 2) % 3]);
        check_close(sine[k], sine[(k + 1) % 3], sine[(k + 2) % 3]);
    }
    for (int k = 0; k < 20000; k++) {
        double p[3][2], len = ldexp(1.0, -10 - (int)(vt_next(&rng) % 36));
        double t = 6.283185307179586 * vt_unit(&rng);
        p[0][0] = sym();
        p[0][1] = sym();
        p[1][0] = p[0][0] + len * cos(t);
        p[1][1] = p[0][1] + len * sin(t);
        p[2][0] = sym();
        p[2][1] = sym();
        int s = (int)(vt_next(&rng) % 3); /* which corner comes first */
        const double *a = p[s], *b = p[(s + 1) % 3], *c = p[(s + 2) % 3];
        if (vor_orient2d(a, b, c) < 0) {
            const double *x = b;
            b = c;
            c = x;
        }
        if (vor_orient2d(a, b, c) == 0) continue;
        check_close(a, b, c);
    }
}

/* Every vertex of every standard set (tests/support/testsets.c: grids
 * turned and jittered, a cluster beside a stray 10^20 times farther,
 * curves, twelve decades) within 2^-28 of its exact centre's distance
 * from its first site. */
static void test_centre_standard_sets(void **state) {
    (void)state;
    size_t checked = 0;
    for (size_t k = 0; k < vt_count(); k++) {
        vt_set set;
        assert_int_equal(vt_make(k, &set), 0);
        vor_sites *s = NULL;
        vor_diagram *d = NULL;
        assert_int_equal(vor_sites_new(set.xy, set.n, &s, NULL), VOR_OK);
        assert_int_equal(vor_compute(s, VOR_FLIP, &d), VOR_OK);
        for (size_t v = 0; v < d->n_vertices; v++) {
            const uint32_t *t = d->vertex_sites + 3 * v;
            const double *a = s->xy + 2 * (size_t)t[0],
                         *b = s->xy + 2 * (size_t)t[1],
                         *c = s->xy + 2 * (size_t)t[2];
            double u[2];
            vor_circumcenter(a, b, c, u);
            assert_memory_equal(u, d->vertex_xy + 2 * v, sizeof u);
            check_close(a, b, c);
            checked++;
        }
        vor_diagram_free(d);
        vor_sites_free(s);
        vt_set_free(&set);
    }
    printf("# %zu vertices of %zu sets checked\n", checked, vt_count());
    assert_true(checked > 10000);
}

static void test_centre_flat(void **state) {
    (void)state;
    int zero_d = 0, checked = 0;
    for (int k = 0; k < 200000 && checked < 20000; k++) {
        double a[2] = {sym(), sym()}, b[2] = {sym(), sym()};
        double t = 1 + vt_unit(&rng) * 3;
        double c[2] = {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
        int bump = (int)(vt_next(&rng) % 4);
        for (int i = 0; i < bump; i++)
            c[i % 2] = nextafter(c[i % 2], i < 2 ? 4.0 : -4.0);
        if (vor_orient2d(a, b, c) == 0)
            continue;
        double bx = b[0] - a[0], by = b[1] - a[1];
        double cx = c[0] - a[0], cy = c[1] - a[1];
        double d = 2 * (bx * cy - by * cx);
        zero_d += d == 0;
        checked += check_centre(a, b, c);
        double u[2];
        vor_circumcenter(a, b, c, u);
        assert_true(isfinite(u[0]) && isfinite(u[1]));
        check_close(a, b, c);
    }
    printf("# flat triangles: %d checked, %d with a double det of 0, worst "
           "error %.3g of the bound\n", checked, zero_d, worst_ratio);
    assert_true(zero_d > 0);
    /* sites within a factor of two of each other in every coordinate,
     * so that their differences are exact (vor_circumcenter's flat path:
     * the determinant from exact products), on a line and moved off it
     * by an ulp or three */
    int flat = 0;
    for (int k = 0; k < 200000 && flat < 20000; k++) {
        double a[2] = {1500 + 499 * sym(), 1500 + 499 * sym()};
        double b[2] = {a[0] + 0.25 * sym(), a[1] + 0.25 * sym()};
        double t = 1 + vt_unit(&rng) * 3;
        double c[2] = {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
        int bump = 1 + (int)(vt_next(&rng) % 3);
        for (int i = 0; i < bump; i++)
            c[i % 2] = nextafter(c[i % 2], i < 2 ? 4000.0 : 0.0);
        if (vor_orient2d(a, b, c) == 0)
            continue;
        flat += check_centre(a, b, c);
        check_close(a, b, c);
    }
    printf("# flat triangles with exact differences: %d checked, worst error "
           "%.3g of the bound\n", flat, worst_ratio);
    assert_true(flat > 10000);
}

/* ---- bisector direction -------------------------------------------------- */

static void check_bisector(const double *a, const double *b) {
    double u[2], v[2];
    vor_bisector_dir(a, b, u);
    vor_bisector_dir(b, a, v);
    /* exactly antisymmetric (compared as numbers: zero components are
     * +0.0 both ways), and never -0.0 */
    assert_true(u[0] == -v[0] && u[1] == -v[1]);
    for (int k = 0; k < 2; k++) {
        assert_false(u[k] == 0 && signbit(u[k]));
        assert_false(v[k] == 0 && signbit(v[k]));
        if (u[k] != 0) /* nonzero: the bits are the negated bits */
            assert_true(signbit(u[k]) != signbit(v[k]));
    }
    if (a[0] == b[0] && a[1] == b[1])
        return;
    /* against (-(by - ay), bx - ax) normalised, from exact differences */
    mpq_t dx, dy, t;
    mpq_inits(dx, dy, t, NULL);
    mpq_set_d(dx, b[0]);
    mpq_set_d(t, a[0]);
    mpq_sub(dx, dx, t);
    mpq_set_d(dy, b[1]);
    mpq_set_d(t, a[1]);
    mpq_sub(dy, dy, t);
    /* a common power of two keeps the direction and brings the larger
     * difference near 1 (a difference may overflow a double, or both be
     * subnormal, where mpq_get_d would lose bits) */
    long e = -100000;
    for (int k = 0; k < 2; k++) {
        mpq_srcptr q = k ? dy : dx;
        if (mpq_sgn(q) != 0) {
            long ek = (long)mpz_sizeinbase(mpq_numref(q), 2) -
                      (long)mpz_sizeinbase(mpq_denref(q), 2);
            if (ek > e)
                e = ek;
        }
    }
    if (e > 0) {
        mpq_div_2exp(dx, dx, (mp_bitcnt_t)e);
        mpq_div_2exp(dy, dy, (mp_bitcnt_t)e);
    } else {
        mpq_mul_2exp(dx, dx, (mp_bitcnt_t)-e);
        mpq_mul_2exp(dy, dy, (mp_bitcnt_t)-e);
    }
    long double x = -(long double)mpq_get_d(dy), y = mpq_get_d(dx);
    mpq_clears(dx, dy, t, NULL);
    long double h = hypotl(x, y);
    long double ex = fabsl(u[0] - x / h), ey = fabsl(u[1] - y / h);
    if (!(ex <= 4 * DBL_EPSILON && ey <= 4 * DBL_EPSILON)) {
        print_error("bisector of (%a,%a) (%a,%a) = (%a,%a), want (%La,%La)\n",
                    a[0], a[1], b[0], b[1], u[0], u[1], x / h, y / h);
        fail();
    }
    long double len = (long double)u[0] * u[0] + (long double)u[1] * u[1];
    assert_true(fabsl(len - 1) <= 4 * DBL_EPSILON);
}

static void test_bisector(void **state) {
    (void)state;
    const double o[2] = {0, 0}, x[2] = {1, 0};
    double u[2];
    vor_bisector_dir(o, x, u);
    assert_true(u[0] == 0 && u[1] == 1); /* o on the left of "up" */
    vor_bisector_dir(x, o, u);
    assert_true(u[0] == 0 && u[1] == -1);

    const double scales[] = {1, 1e-300, 1e300, 1e15, 1e-9, 0x1p-1074,
                             DBL_MAX, 1e-320};
    for (int k = 0; k < 40000; k++) {
        double s = scales[k % 8];
        double a[2] = {sym() * s, sym() * s}, b[2] = {sym() * s, sym() * s};
        if (k % 3 == 0) { /* mixed magnitudes */
            a[0] = sym() * 1e300;
            b[1] = sym() * 1e-300;
        }
        check_bisector(a, b);
    }
    /* overflowing differences */
    const double p[2] = {-DBL_MAX, DBL_MAX}, q[2] = {DBL_MAX, -DBL_MAX};
    check_bisector(p, q);
    vor_bisector_dir(p, q, u);
    assert_true(fabs(u[0] - u[1]) <= DBL_EPSILON &&
                fabs(u[0] - 0.70710678118654752440) <= DBL_EPSILON);
    check_bisector(o, o);
    vor_bisector_dir(o, o, u);
    assert_true(u[0] == 0 && u[1] == 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_centre_simple),
        cmocka_unit_test(test_centre_random_scales),
        cmocka_unit_test(test_centre_mixed_ranges),
        cmocka_unit_test(test_centre_flat),
        cmocka_unit_test(test_centre_needles),
        cmocka_unit_test(test_centre_standard_sets),
        cmocka_unit_test(test_bisector),
    };
    return cmocka_run_group_tests_name("core/geometry", tests, setup_seed,
                                       NULL);
}
