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
#include <stdint.h>
#include <string.h>

#include "internal.h"

/* 1 if none of the m doubles at v is an infinity or a NaN (exponent bits
 * all set). vor_sites_new refuses those; a vor_sites filled by hand may
 * hold them, and no predicate has a sign for them. One pass without
 * branches, bound by memory: 1.5 ms for 10^6 sites here. */
static int all_finite(const double *v, size_t m) {
    const uint64_t e = UINT64_C(0x7ff0000000000000);
    uint64_t bad = 0;
    for (size_t i = 0; i < m; i++) {
        uint64_t b;
        memcpy(&b, v + i, sizeof b);
        bad |= (b & e) == e;
    }
    return !bad;
}

static const vor__algorithm_run_fn algorithms[VOR_ALGORITHM_COUNT] = {
    [VOR_FORTUNE] = vor__fortune_run,
    [VOR_BOWYER_WATSON] = vor__bowyer_watson_run,
    [VOR_FLIP] = vor__flip_run,
};

/* On error *out is NULL. VOR_EINVAL for NULL arguments (or sites whose
 * arrays are missing), VOR_EALGORITHM for an algorithm outside the enum,
 * VOR_ENONFINITE for a coordinate that is not a finite number. */
vor_status vor_compute_ex(const vor_sites *sites, vor_algorithm algorithm,
                          const vor_options *opt, vor_diagram **out) {
    if (opt && opt->counts) memset(opt->counts, 0, sizeof *opt->counts);
    if (!out) return VOR_EINVAL;
    *out = NULL;
    if (!sites || (sites->n > 0 && !sites->xy)) return VOR_EINVAL;
    if ((unsigned)algorithm >= VOR_ALGORITHM_COUNT) return VOR_EALGORITHM;
    if (sites->n > VOR_MAX_POINTS) return VOR_ETOOMANY;
    if (!all_finite(sites->xy, 2 * sites->n)) return VOR_ENONFINITE;
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
