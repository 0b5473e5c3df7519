/* hilbert.c -- insertion order (placeholder: being written; identity). */
#include "internal.h"

vor_status vor__insertion_order(const double *xy, size_t n, uint32_t *order) {
    (void)xy;
    for (size_t i = 0; i < n; i++)
        order[i] = (uint32_t)i;
    return VOR_OK;
}
