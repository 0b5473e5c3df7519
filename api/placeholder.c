/* placeholder.c -- temporary stand-ins for the codec's entry points so that
 * the server and the command line link while the real codec is written.
 * Every function answers "unavailable"; each is removed from this file as
 * its real implementation lands, and the file itself goes away. */
#include <stdlib.h>
#include <string.h>

#include "api.h"

static api_code unavailable(api_problem *p) {
    return api_problem_set(p, API_UNAVAILABLE, "the codec is not built yet");
}

void api_result_init(api_result *res) { memset(res, 0, sizeof *res); }
void api_result_clear(api_result *res) { memset(res, 0, sizeof *res); }
api_code api_compute(const api_request *r, api_result *res, api_problem *p) {
    (void)r; (void)res; return unavailable(p);
}
void api_compare_init(api_compare *c) { memset(c, 0, sizeof *c); }
void api_compare_clear(api_compare *c) { memset(c, 0, sizeof *c); }
api_code api_compare_run(const api_request *r, api_compare *c, api_problem *p) {
    (void)r; (void)c; return unavailable(p);
}
api_code api_write_result(const api_request *r, const api_result *res,
                          api_timings *t, api_buf *out, api_problem *p) {
    (void)r; (void)res; (void)t; (void)out; return unavailable(p);
}
api_code api_write_compare(const api_request *r, const api_compare *c,
                           api_buf *out, api_problem *p) {
    (void)r; (void)c; (void)out; return unavailable(p);
}
double api_clock_ms(void) { return 0; }
