/* fortune.c -- Fortune's sweep-line algorithm for the Voronoi diagram.
 *
 * Placeholder: the sweep is being written; until then the entry point
 * reports that the algorithm is not available. */
#include "internal.h"

vor_status vor__fortune(const vor_sites *s, vor_diagram **out) {
    (void)s;
    *out = NULL;
    return VOR_EUNAVAILABLE;
}
