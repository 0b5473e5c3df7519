/* voronoi.c -- vor_compute and vor_compute_ex: the one entry point that
 * picks an algorithm.
 *
 * Arguments are checked here once; input the algorithms must never see
 * (fewer than three sites, or all of them on one line, decided exactly with
 * vor_orient2d) goes to the degenerate builder; everything else through a
 * table of vor__algorithm_run_fn indexed by vor_algorithm. The run's counts
 * live in this frame and are copied out when asked for, so that counting
 * costs the same whether or not anybody reads it. Cost: O(n) on top of
 * the chosen algorithm.
 */
#include <stddef.h>
#include <string.h>

#include "internal.h"

static const vor__algorithm_run_fn algorithms[VOR_ALGORITHM_COUNT] = {
    [VOR_FORTUNE] = vor__fortune_run,
    [VOR_BOWYER_WATSON] = vor__bowyer_watson_run,
    [VOR_FLIP] = vor__flip_run,
};

/* On error *out is NULL. VOR_EINVAL for NULL arguments (or sites whose
 * arrays are missing), VOR_EALGORITHM for an algorithm outside the enum. */
vor_status vor_compute_ex(const vor_sites *sites, vor_algorithm algorithm,
                          const vor_options *opt, vor_diagram **out) {
    if (opt && opt->counts) memset(opt->counts, 0, sizeof *opt->counts);
    if (!out) return VOR_EINVAL;
    *out = NULL;
    if (!sites || (sites->n > 0 && !sites->xy)) return VOR_EINVAL;
    if ((unsigned)algorithm >= VOR_ALGORITHM_COUNT) return VOR_EALGORITHM;
    if (sites->n > VOR_MAX_POINTS) return VOR_ETOOMANY;
    if (vor__all_collinear(sites)) return vor__diagram_degenerate(sites, out);
    vor__run run;
    memset(&run, 0, sizeof run);
    if (opt) {
        run.trace = opt->trace;
        run.trace_ctx = opt->trace_ctx;
        run.stop = opt->stop;
        run.stop_ctx = opt->stop_ctx;
    }
    vor_status st = algorithms[algorithm](sites, &run, out);
    if (st != VOR_OK && *out) { /* an algorithm must not leave a result */
        vor_diagram_free(*out);
        *out = NULL;
    }
    if (opt && opt->counts) *opt->counts = run.counts;
    return st;
}

vor_status vor_compute(const vor_sites *sites, vor_algorithm algorithm,
                       vor_diagram **out) {
    return vor_compute_ex(sites, algorithm, NULL, out);
}
