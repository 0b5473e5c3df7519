/* problem.c -- problems: the table of codes (slug, HTTP status, title),
 * setting a problem, mapping core statuses, and the RFC 9457
 * application/problem+json body.
 *
 * Everything here is generated from API_PROBLEM_TABLE in api.h, so a code is
 * declared in one place. Problem type URIs are relative ("/problems/<slug>",
 * API_PROBLEM_TYPE_PREFIX), which RFC 9457 allows; the service documents each
 * slug in openapi.yaml. Nothing here can fail except appends to the output
 * buffer, which record oom in the buffer. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "buf.h"

static const struct {
    const char *slug;
    int http;
    const char *title;
} info[] = {
#define API__INFO(name, slug, http, title) {slug, http, title},
    API_PROBLEM_TABLE(API__INFO)
#undef API__INFO
};

int api_code_http(api_code c) {
    return (unsigned)c < API_CODE_COUNT ? info[c].http : 500;
}

const char *api_code_slug(api_code c) {
    return (unsigned)c < API_CODE_COUNT ? info[c].slug : "internal";
}

const char *api_code_title(api_code c) {
    return (unsigned)c < API_CODE_COUNT ? info[c].title : "Internal error";
}

api_code api_problem_set(api_problem *p, api_code code, const char *fmt, ...) {
    va_list ap;
    p->code = code;
    p->pointer[0] = 0;
    p->line = 0;
    va_start(ap, fmt);
    vsnprintf(p->detail, sizeof p->detail, fmt, ap);
    va_end(ap);
    return code;
}

api_code api_problem_from_status(api_problem *p, vor_status s) {
    api_code c;
    switch (s) {
    case VOR_OK: return API_OK;
    case VOR_ENOMEM:
    case VOR_ESTOPPED: c = API_UNAVAILABLE; break;
    case VOR_ETOOMANY: c = API_TOO_LARGE; break;
    case VOR_ENONFINITE:
    case VOR_EBOUNDS:
    case VOR_EALGORITHM: c = API_INVALID; break;
    case VOR_EINVAL: c = API_MALFORMED; break;
    case VOR_EUNAVAILABLE: c = API_NOT_IMPLEMENTED; break;
    default: c = API_INTERNAL; break;
    }
    return api_problem_set(p, c, "%s", vor_status_message(s));
}

void api_write_problem(const api_problem *p, const char *instance,
                       api_buf *out) {
    api_buf_printf(out, "{\"type\":\"%s%s\",\"title\":", API_PROBLEM_TYPE_PREFIX,
                   api_code_slug(p->code));
    api__put_json_string(out, api_code_title(p->code));
    api_buf_printf(out, ",\"status\":%d,\"detail\":", api_code_http(p->code));
    api__put_json_string(out, p->detail[0] ? p->detail : api_code_title(p->code));
    if (instance != NULL) {
        API_BUF_LIT(out, ",\"instance\":");
        api__put_json_string(out, instance);
    }
    if (p->pointer[0]) {
        API_BUF_LIT(out, ",\"pointer\":");
        api__put_json_string(out, p->pointer);
    }
    if (p->line > 0) api_buf_printf(out, ",\"line\":%ld", p->line);
    API_BUF_LIT(out, "}\n");
}
