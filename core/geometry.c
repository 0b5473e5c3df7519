/* geometry.c -- circumcentre and bisector direction (placeholder: being
 * written; not overflow-safe yet). */
#include <math.h>

#include "vor.h"

void vor_circumcenter(const double *a, const double *b, const double *c,
                      double *out) {
    double bx = b[0] - a[0], by = b[1] - a[1];
    double cx = c[0] - a[0], cy = c[1] - a[1];
    double d = 2 * (bx * cy - by * cx);
    double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    out[0] = a[0] + (cy * b2 - by * c2) / d;
    out[1] = a[1] + (bx * c2 - cx * b2) / d;
}

void vor_bisector_dir(const double *a, const double *b, double *out) {
    double x = -(b[1] - a[1]), y = b[0] - a[0];
    double h = hypot(x, y);
    out[0] = x / h;
    out[1] = y / h;
}
