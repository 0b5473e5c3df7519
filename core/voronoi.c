/* voronoi.c -- vor_compute: the one entry point that picks an algorithm.
 *
 * Arguments are checked here once; input the algorithms must never see
 * (fewer than three sites, or all of them on one line, decided exactly with
 * vor_orient2d) goes to the degenerate builder; everything else through a
 * table of vor__algorithm_fn indexed by vor_algorithm. Cost: O(n) on top of
 * the chosen algorithm.
 */
#include <stddef.h>

#include "internal.h"

static const vor__algorithm_fn algorithms[VOR_ALGORITHM_COUNT] = {
    [VOR_FORTUNE] = vor__fortune,
    [VOR_BOWYER_WATSON] = vor__bowyer_watson,
    [VOR_FLIP] = vor__flip,
};

/* On error *out is NULL. VOR_EINVAL for NULL arguments (or sites whose
 * arrays are missing), VOR_EALGORITHM for an algorithm outside the enum. */
vor_status vor_compute(const vor_sites *sites, vor_algorithm algorithm,
                       vor_diagram **out) {
    if (!out) return VOR_EINVAL;
    *out = NULL;
    if (!sites || (sites->n > 0 && !sites->xy)) return VOR_EINVAL;
    if ((unsigned)algorithm >= VOR_ALGORITHM_COUNT) return VOR_EALGORITHM;
    if (sites->n > VOR_MAX_POINTS) return VOR_ETOOMANY;
    if (vor__all_collinear(sites)) return vor__diagram_degenerate(sites, out);
    vor_status st = algorithms[algorithm](sites, out);
    if (st != VOR_OK && *out) { /* an algorithm must not leave a result */
        vor_diagram_free(*out);
        *out = NULL;
    }
    return st;
}
