/* clip.c -- vor_clip, clipping a diagram to a box (placeholder). */
#include <stdlib.h>

#include "internal.h"

vor_status vor_clip(const vor_diagram *d, const vor_sites *sites,
                    const double box[4], vor_clipped **out) {
    (void)d; (void)sites; (void)box;
    if (out) *out = NULL;
    return VOR_EUNAVAILABLE;
}

void vor_clipped_free(vor_clipped *c) {
    if (!c) return;
    free(c->seg);
    free(c->seg_in);
    free(c->poly_start);
    free(c->poly_xy);
    free(c);
}
