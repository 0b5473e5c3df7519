/* predicates.c -- exact orient2d and incircle (placeholder: being written;
 * currently naive floating point, NOT exact). */
#include "internal.h"

int vor_orient2d(const double *a, const double *b, const double *c) {
    double d = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]);
    return (d > 0) - (d < 0);
}

int vor_incircle(const double *a, const double *b, const double *c,
                 const double *d) {
    double adx = a[0] - d[0], ady = a[1] - d[1];
    double bdx = b[0] - d[0], bdy = b[1] - d[1];
    double cdx = c[0] - d[0], cdy = c[1] - d[1];
    double al = adx * adx + ady * ady, bl = bdx * bdx + bdy * bdy;
    double cl = cdx * cdx + cdy * cdy;
    double det = al * (bdx * cdy - cdx * bdy) + bl * (cdx * ady - adx * cdy) +
                 cl * (adx * bdy - bdx * ady);
    return (det > 0) - (det < 0);
}
