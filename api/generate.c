/* generate.c -- generated point sets for requests that ask for them
 * ("generate": {"distribution", "n", "seed"}) and for the command line.
 *
 * The distributions themselves are in distribution.c, shared with the test
 * point sets and the benchmark; this file checks the request (a known name
 * or alias, at most VOR_MAX_POINTS points), allocates the array and words
 * the problems. Cost: O(n) time, one array of 2n doubles. */
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "distribution.h"

api_code api_generate(const char *distribution, size_t n, uint64_t seed,
                      double **xy, api_problem *p) {
    *xy = NULL;
    int d = api_dist_find(distribution);
    if (d < 0) {
        char shown[80];
        const char *s = distribution ? distribution : "";
        api__quote_excerpt(shown, sizeof shown, s, strlen(s), 40);
        return api__problem_at(p, API_INVALID, NULL, 0,
                               "unknown distribution \"%s\"; valid: %s", shown,
                               api_dist_list());
    }
    if (n > VOR_MAX_POINTS) {
        return api__problem_at(p, API_TOO_LARGE, NULL, 0,
                               "cannot generate %zu points: the limit is %zu", n,
                               (size_t)VOR_MAX_POINTS);
    }
    if (n == 0) return API_OK;
    double *out = malloc(n * 2 * sizeof(double));
    if (out == NULL) {
        return api__problem_at(p, API_UNAVAILABLE, NULL, 0,
                               "out of memory generating %zu points", n);
    }
    api_dist_fill((api_dist)d, seed, out, n);
    *xy = out;
    return API_OK;
}

const char *api_distribution_name(const char *name) {
    int d = api_dist_find(name);
    return d < 0 ? NULL : api_dist_name((api_dist)d);
}
