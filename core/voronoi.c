/* voronoi.c -- vor_compute, the algorithm dispatcher (placeholder). */
#include <stddef.h>

#include "internal.h"

vor_status vor_compute(const vor_sites *sites, vor_algorithm algorithm,
                       vor_diagram **out) {
    if (out) *out = NULL;
    if (!sites || !out) return VOR_EINVAL;
    if ((unsigned)algorithm >= VOR_ALGORITHM_COUNT) return VOR_EALGORITHM;
    return VOR_EUNAVAILABLE;
}
