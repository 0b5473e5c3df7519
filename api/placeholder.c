/* placeholder.c -- temporary stand-ins for the codec's entry points so that
 * the server and the command line link while the real codec is written.
 * Every function answers "unavailable"; each is removed from this file as
 * its real implementation lands, and the file itself goes away. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api.h"

static const struct {
    const char *slug;
    int http;
    const char *title;
} info[] = {
#define API__INFO(name, slug, http, title) {slug, http, title},
    API_PROBLEM_TABLE(API__INFO)
#undef API__INFO
};

int api_code_http(api_code c) { return (unsigned)c < API_CODE_COUNT ? info[c].http : 500; }
const char *api_code_slug(api_code c) { return (unsigned)c < API_CODE_COUNT ? info[c].slug : "internal"; }
const char *api_code_title(api_code c) { return (unsigned)c < API_CODE_COUNT ? info[c].title : "Internal error"; }

api_code api_problem_set(api_problem *p, api_code code, const char *fmt, ...) {
    va_list ap;
    p->code = code;
    va_start(ap, fmt);
    vsnprintf(p->detail, sizeof p->detail, fmt, ap);
    va_end(ap);
    return code;
}

static api_code unavailable(api_problem *p) {
    return api_problem_set(p, API_UNAVAILABLE, "the codec is not built yet");
}

void api_buf_init(api_buf *b) { memset(b, 0, sizeof *b); }
void api_buf_clear(api_buf *b) { free(b->data); memset(b, 0, sizeof *b); }
char *api_buf_take(api_buf *b, size_t *len) {
    char *d = b->data;
    *len = b->len;
    memset(b, 0, sizeof *b);
    return d;
}

void api_request_init(api_request *r) {
    memset(r, 0, sizeof *r);
    r->algorithm = VOR_FORTUNE;
    r->parts = API_PART_DEFAULT;
    r->format = API_FMT_JSON;
}
void api_request_clear(api_request *r) { free(r->xy); api_request_init(r); }

api_code api_input_from_content_type(const char *ct, api_input *out, api_problem *p) {
    (void)ct; (void)out; return unavailable(p);
}
api_code api_parse_body(api_request *r, api_input kind, const char *body,
                        size_t len, const api_limits *lim, api_problem *p) {
    (void)r; (void)kind; (void)body; (void)len; (void)lim; return unavailable(p);
}
api_code api_request_option(api_request *r, const char *key, const char *value,
                            api_problem *p) {
    (void)r; (void)key; (void)value; return unavailable(p);
}
api_code api_format_from_accept(api_request *r, const char *accept, api_problem *p) {
    (void)r; (void)accept; return unavailable(p);
}
api_code api_generate(const char *distribution, size_t n, uint64_t seed,
                      double **xy, api_problem *p) {
    (void)distribution; (void)n; (void)seed; *xy = NULL; return unavailable(p);
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
const char *api_format_mime(api_format f) {
    (void)f; return "application/json";
}
api_code api_write_result(const api_request *r, const api_result *res,
                          api_timings *t, api_buf *out, api_problem *p) {
    (void)r; (void)res; (void)t; (void)out; return unavailable(p);
}
api_code api_write_compare(const api_request *r, const api_compare *c,
                           api_buf *out, api_problem *p) {
    (void)r; (void)c; (void)out; return unavailable(p);
}
void api_write_problem(const api_problem *p, const char *instance, api_buf *out) {
    (void)p; (void)instance; (void)out;
}
api_code api_problem_from_status(api_problem *p, vor_status s) {
    (void)s; return unavailable(p);
}
double api_clock_ms(void) { return 0; }
int api_buf_append(api_buf *b, const void *data, size_t n) {
    (void)data; (void)n; b->oom = 1; return -1;
}
int api_buf_printf(api_buf *b, const char *fmt, ...) {
    (void)fmt; b->oom = 1; return -1;
}
