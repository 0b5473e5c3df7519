/* geometry.c -- the two constructions every algorithm shares: the centre of
 * the circle through three sites (a Voronoi vertex) and the unit direction
 * of a bisector (a Voronoi ray); and the sites' bounding box, which the
 * insertion order and orient2d's static bound both start from.
 *
 * These produce output coordinates, not topology, so they are computed in
 * floating point (topology comes from the exact predicates). What they owe
 * the rest of the library is determinism and range: the same arguments in
 * the same order give bit-identical results (every branch depends on the
 * arguments alone, so every algorithm gets the same vertex), any finite
 * input gives a finite, accurate result unless the true result overflows,
 * and no result is -0.0.
 *
 * vor_circumcenter works relative to a, with (bx, by) = b - a,
 * (cx, cy) = c - a, d = 2 (bx cy - by cx):
 *
 *     centre = a + ((cy |b|^2 - by |c|^2) / d, (bx |c|^2 - cx |b|^2) / d)
 *
 * In doubles when every nonzero difference lies in [2^-300, 2^300]: then
 * the degree-3 numerators lie within [2^-900, 2^903], d is 0 or at least
 * 2^-652, and nothing overflows or underflows; and when neither d nor the
 * larger numerator has cancelled to below 2^-20 of its terms, so that
 * each is within about 2^-30 of itself and the centre within 2^-30 of its
 * distance from a (tests/core/test_geometry.c checks 2^-28 against exact
 * centres); a flat triangle's determinant is computed exactly and
 * rounded once there instead. Otherwise -- huge, tiny or mixed
 * magnitudes, a needle -- in long double, from an end of the triangle's
 * shortest side: its 15-bit exponent holds any product of three doubles,
 * so 1e300 next to 1e-300 needs no rescaling at all; d comes from the
 * exact determinant (vor__orient2d_value), so a flat triangle still gets
 * its far-away centre; and from the short side's end the numerators do
 * not cancel, and the short side is not rounded away by differences
 * taken from a far corner (a site 10^10 away from two 10^-10 apart). The
 * build requires such a long double (x86 extended or binary128); a static
 * assertion says so.
 *
 * Cost: about 10 ns in doubles, more for a flat triangle (its exact
 * determinant), about 100 ns on the long double path, which none of the
 * 2 * 10^6 vertices of 10^6 uniform, gaussian or circle sites takes.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "predicates.h"

_Static_assert(LDBL_MAX_EXP >= 4096 && LDBL_MIN_EXP <= -4096,
               "geometry.c needs a long double with a wide exponent range");

/* The squared length of (x, y): with the wide exponent no difference of
 * two doubles overflows or underflows when squared, so, unlike hypotl,
 * nothing needs scaling (hypotl was a third of a run on sites near a
 * line, where most triangles take the long double path). */
static long double len2(long double x, long double y) {
    return x * x + y * y;
}

/* The same formula in long double, from the original coordinates, with
 * the determinant computed exactly and then rounded (so that a very flat
 * triangle, whose rounded determinant may be 0 or of the wrong size, still
 * gets a finite, accurate centre). The differences are rounded to 64 bits
 * (exact when the operands are within 2^11 of each other in magnitude); no
 * intermediate can overflow or underflow. A collinear triple gives a
 * non-finite result. */
static void circumcenter_long(const double *a, const double *b,
                              const double *c, double *out) {
    /* from an end of the shortest side: from the far corner of a sliver
     * (two sites 10^-10 apart, the third 10^10 away) the differences
     * would round away the short side, and the centre with it (it came
     * out at the far site itself). A turn of the corners keeps the
     * orientation, and so the exact determinant. */
    long double ab = len2((long double)b[0] - a[0], (long double)b[1] - a[1]);
    long double bc = len2((long double)c[0] - b[0], (long double)c[1] - b[1]);
    long double ca = len2((long double)a[0] - c[0], (long double)a[1] - c[1]);
    if (bc < ab && bc < ca) {
        const double *t = a;
        a = b;
        b = c;
        c = t;
    }
    long double bx = (long double)b[0] - a[0], by = (long double)b[1] - a[1];
    long double cx = (long double)c[0] - a[0], cy = (long double)c[1] - a[1];
    long double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    long double d = 2 * vor__orient2d_value(a, b, c);
    long double ux = (cy * b2 - by * c2) / d;
    long double uy = (bx * c2 - cx * b2) / d;
    out[0] = (double)(a[0] + ux) + 0.0; /* + 0.0: no -0.0 in the output */
    out[1] = (double)(a[1] + uy) + 0.0;
}

void vor_circumcenter(const double *a, const double *b, const double *c,
                      double *out) {
    /* the double path is inlined in predicates.h for the hot loops */
    if (!vor__circumcenter_fast(a, b, c, out))
        circumcenter_long(a, b, c, out);
}

void vor_bisector_dir(const double *a, const double *b, double *out) {
    /* IEEE subtraction and negation are exact mirror images, so swapping a
     * and b negates x and y exactly, and everything after is odd in (x, y)
     * -- except that a zero difference is +0.0 both ways. A zero component
     * is therefore returned as +0.0 always: the results for (a, b) and
     * (b, a) compare equal to each other's negation (and JSON never sees
     * a -0). */
    double x = -(b[1] - a[1]), y = b[0] - a[0];
    if (isinf(x) || isinf(y)) { /* the difference overflowed: use halves */
        x = -(b[1] * 0.5 - a[1] * 0.5);
        y = b[0] * 0.5 - a[0] * 0.5;
    }
    double m = fabs(x) > fabs(y) ? fabs(x) : fabs(y);
    if (m == 0) { /* a == b: no direction */
        out[0] = 0;
        out[1] = 0;
        return;
    }
    /* scale by a power of two so the larger component is in [1/2, 1):
     * exact (bar underflow of a negligible component), and the sum of
     * squares can neither overflow nor underflow. For a normal m the
     * factor 2^-e is built from its bits and multiplied in, which rounds
     * an underflowing component exactly as ldexp() does (both round the
     * exact product to nearest); ldexp and frexp are library calls, and
     * a diagram of sites in convex position has a ray per site. */
    uint64_t u;
    memcpy(&u, &m, sizeof u);
    int ex = (int)(u >> 52); /* m >= 0: no sign bit */
    if (ex >= 1 && ex <= 2044) {
        int e = ex - 1022; /* m = f 2^e, f in [1/2, 1) */
        uint64_t v = (uint64_t)(1023 - e) << 52;
        double f;
        memcpy(&f, &v, sizeof f);
        x *= f;
        y *= f;
    } else {
        int e;
        frexp(m, &e);
        x = ldexp(x, -e);
        y = ldexp(y, -e);
    }
    double h = sqrt(x * x + y * y);
    out[0] = x / h + 0.0;
    out[1] = y / h + 0.0;
}

void vor__bbox(const double *xy, size_t n, double box[4]) {
    double x0 = xy[0], x1 = xy[0], y0 = xy[1], y1 = xy[1];
    for (size_t i = 1; i < n; i++) {
        double x = xy[2 * i], y = xy[2 * i + 1];
        x0 = x < x0 ? x : x0; /* selects, not branches: the compiler */
        x1 = x > x1 ? x : x1; /* makes them minsd/maxsd */
        y0 = y < y0 ? y : y0;
        y1 = y > y1 ? y : y1;
    }
    box[0] = x0;
    box[1] = y0;
    box[2] = x1;
    box[3] = y1;
}
