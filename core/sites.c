/* sites.c -- validation and de-duplication of input points (placeholder:
 * being written). */
#include <stdlib.h>

#include "vor.h"

vor_status vor_sites_new(const double *xy, size_t n, vor_sites **out,
                         size_t *bad_index) {
    (void)xy; (void)n; (void)bad_index;
    *out = NULL;
    return VOR_EUNAVAILABLE;
}

void vor_sites_free(vor_sites *s) {
    (void)s;
}
