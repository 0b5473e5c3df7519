/* bowyer_watson.c -- Bowyer-Watson incremental Delaunay triangulation
 * (placeholder until the real insertion lands). */
#include "internal.h"

vor_status vor__bowyer_watson_mesh(const vor_sites *s, vor__mesh *m) {
    (void)s;
    (void)m;
    return VOR_EUNAVAILABLE;
}

vor_status vor__bowyer_watson(const vor_sites *s, vor_diagram **out) {
    (void)s;
    *out = NULL;
    return VOR_EUNAVAILABLE;
}
