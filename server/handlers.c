/* handlers.c -- the routes that are not computations: the page and its
 * files, openapi.yaml, /healthz, /readyz, /metrics, CORS preflight, the
 * problem type pages, and the answers of routing itself (404, 405).
 *
 * Each answers at once on the connection's thread from memory: the files
 * are embedded (or read from --web-dir) with their gzip form and ETag,
 * the rest are documents of a few hundred bytes. O(size of the answer).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "budget.h"
#include "guard.h"
#include "gzip.h"
#include "internal.h"
#include "server.h"

int srv__client_takes_gzip(const srv_req *q) {
    return srv_accepts_gzip(q->h.accept_encoding);
}

static const char *header(struct MHD_Connection *conn, const char *name) {
    return MHD_lookup_connection_value(conn, MHD_HEADER_KIND, name);
}

/* Sends the text built in b as a 200 of type ctype (b is consumed), or
 * a 503 when building it ran out of memory. */
static enum MHD_Result send_built(srv_req *q, struct MHD_Connection *conn,
                                  api_buf *b, const char *ctype,
                                  int gzip_ok) {
    if (b->oom) {
        api_buf_clear(b);
        return srv__send_problem(q, conn, API_UNAVAILABLE, NULL,
                                 SRV_RETRY_AFTER_S, "out of memory");
    }
    size_t len;
    char *text = api_buf_take(b, &len);
    return srv__send_text(q, conn, 200, ctype, text, len, gzip_ok);
}

static enum MHD_Result handle_asset(srv_req *q, struct MHD_Connection *conn,
                                    const char *path) {
    srv_server *s = q->srv;
    srv_asset a;
    int rc = srv_assets_get(s->assets, path, &a);
    if (rc == -1)
        return srv__send_problem(q, conn, API_NOT_FOUND, NULL, 0,
                                 "no resource at this path");
    if (rc != 0)
        return srv__send_problem(q, conn, API_UNAVAILABLE, NULL,
                                 SRV_RETRY_AFTER_S,
                                 "the file could not be read");

    const char *inm = header(conn, "If-None-Match");
    struct MHD_Response *resp;
    unsigned status = 200;
    size_t len = 0;
    int gz = 0;
    if (inm != NULL && strstr(inm, a.etag) != NULL) {
        status = 304;
        resp = MHD_create_response_from_buffer(0, (void *)"",
                                               MHD_RESPMEM_PERSISTENT);
    } else if (srv__client_takes_gzip(q) && a.gz != NULL) {
        len = a.gz_len;
        gz = 1;
        resp = MHD_create_response_from_buffer(len, (void *)a.gz,
                                               MHD_RESPMEM_PERSISTENT);
    } else if (srv__client_takes_gzip(q) && a.owned != NULL &&
               a.len >= SRV_GZIP_MIN) {
        char *z;
        size_t zn;
        if (srv_gzip(a.data, a.len, 6, &z, &zn) == 0 && zn < a.len) {
            len = zn;
            gz = 1;
            resp = MHD_create_response_from_buffer(len, z,
                                                   MHD_RESPMEM_MUST_FREE);
            if (resp == NULL) free(z);
        } else {
            free(z); /* NULL when compression failed */
            len = a.len;
            resp = MHD_create_response_from_buffer(len, (void *)a.data,
                                                   MHD_RESPMEM_MUST_COPY);
        }
    } else {
        len = a.len;
        resp = MHD_create_response_from_buffer(
            len, (void *)a.data,
            a.owned ? MHD_RESPMEM_MUST_COPY : MHD_RESPMEM_PERSISTENT);
    }
    if (resp != NULL) {
        MHD_add_response_header(resp, "Content-Type", a.mime);
        MHD_add_response_header(resp, "ETag", a.etag);
        MHD_add_response_header(resp, "Cache-Control", "no-cache");
        MHD_add_response_header(resp, "Vary", "Accept-Encoding");
        if (gz) MHD_add_response_header(resp, "Content-Encoding", "gzip");
    }
    srv_asset_release(&a);
    return srv__send_response(q, conn, status, resp, len);
}

static enum MHD_Result handle_metrics(srv_req *q, struct MHD_Connection *conn) {
    srv_server *s = q->srv;
    srv_gauges g;
    memset(&g, 0, sizeof g);
    srv_pool_stats(s->pool, &g.queue_depth, &g.running);
    g.queue_capacity = (size_t)s->cfg.queue;
    g.workers = (size_t)s->cfg.workers;
    g.in_flight = srv_server_in_flight(s);
    g.ready = !atomic_load(&s->draining);
    g.answer_memory = srv_budget_used(s->budget);
    g.answer_memory_capacity = srv_budget_capacity(s->budget);
    g.answer_memory_peak = srv_budget_peak(s->budget);
    g.answer_memory_refused = srv_budget_refused(s->budget);
    g.connections = srv_guard_open(s->guard);
    g.closed_header_timeout = srv_guard_closed(s->guard,
                                               SRV_GUARD_HEADER_TIMEOUT);
    g.closed_silent = srv_guard_closed(s->guard, SRV_GUARD_SILENT);
    g.closed_upload_rate = srv_guard_closed(s->guard, SRV_GUARD_UPLOAD_RATE);
    api_buf b;
    api_buf_init(&b);
    srv_metrics_render(s->metrics, &g, &b);
    return send_built(q, conn, &b, "text/plain; version=0.0.4; charset=utf-8",
                      srv__client_takes_gzip(q));
}

static enum MHD_Result handle_json_status(srv_req *q,
                                          struct MHD_Connection *conn,
                                          const char *json) {
    size_t n = strlen(json);
    char *body = malloc(n + 1);
    if (body == NULL) return MHD_NO;
    memcpy(body, json, n + 1);
    return srv__send_text(q, conn, 200, "application/json", body, n, 0);
}

static enum MHD_Result handle_options(srv_req *q, struct MHD_Connection *conn) {
    struct MHD_Response *resp =
        MHD_create_response_from_buffer(0, (void *)"", MHD_RESPMEM_PERSISTENT);
    if (resp != NULL) {
        MHD_add_response_header(resp, "Allow", q->allow);
        MHD_add_response_header(resp, "Access-Control-Allow-Methods",
                                q->allow);
        MHD_add_response_header(resp, "Access-Control-Allow-Headers",
                                "Content-Type, Accept, X-Request-Id");
        MHD_add_response_header(resp, "Access-Control-Max-Age", "600");
        MHD_add_response_header(resp, "Cache-Control", "no-store");
    }
    return srv__send_response(q, conn, 204, resp, 0);
}

/* What each problem type means, for GET /problems/<type> (the type URIs
 * of problem documents are relative, so they lead here). */
static const char *const problem_help[API_CODE_COUNT] = {
    [API_MALFORMED] = "The request body or a query parameter could not be "
                      "read: a syntax error, an unknown or repeated key, a "
                      "binary body whose length is not a multiple of 16, an "
                      "unknown query parameter, a compressed body that does "
                      "not decode, or framing that cannot be trusted "
                      "(Content-Length values that disagree, or both "
                      "Content-Length and Transfer-Encoding). The pointer "
                      "(JSON) or line (text) member says where.",
    [API_NOT_FOUND] = "Nothing is served at this path.",
    [API_METHOD] = "The path exists but not with this method; the Allow "
                   "header lists the methods it takes.",
    [API_TOO_LARGE] = "The body is larger than the service accepts "
                      "(--max-body), or it holds or asks for more points "
                      "than the service computes at once (--max-points).",
    [API_MEDIA_TYPE] = "The Content-Type is not one the service reads: "
                       "application/json, text/csv, text/plain or "
                       "application/octet-stream; or the Content-Encoding "
                       "is not gzip, deflate or identity.",
    [API_NOT_ACCEPTABLE] = "The Accept header names nothing the service "
                           "produces: application/json, "
                           "application/geo+json, image/svg+xml or "
                           "application/octet-stream.",
    [API_INVALID] = "The request is well-formed but a value is not "
                    "acceptable: a coordinate that is not finite, bounds "
                    "that are not a box, an unknown algorithm, format, part "
                    "or distribution. The pointer or line member says where.",
    [API_INTERNAL] = "The service failed in a way it should not; the "
                     "request id in X-Request-Id finds it in the log.",
    [API_UNAVAILABLE] = "The service cannot take the request now: every "
                        "worker is busy and the queue is full, memory ran "
                        "out, or it is shutting down. Retry after the "
                        "seconds in Retry-After.",
    [API_TIMEOUT] = "The answer was not ready within the service's "
                    "deadline (--timeout), counted from the moment the "
                    "request was received; send fewer points.",
    [API_NOT_IMPLEMENTED] = "The algorithm asked for is not available in "
                            "this build of the service, or the request "
                            "was sent with a Transfer-Encoding other than "
                            "chunked.",
    [API_REQUEST_TIMEOUT] = "The request did not arrive in time: its line "
                            "and headers took longer than the service "
                            "waits (--header-timeout), or its body came "
                            "more slowly than --min-upload-rate. The "
                            "connection is closed; send the request again, "
                            "whole.",
    [API_URI_TOO_LONG] = "The request line is longer than the service "
                         "reads (8 KiB); put the points in the body.",
    [API_HEADERS_TOO_LARGE] = "The request line and headers together are "
                              "longer than the service reads (12 KiB).",
};

static enum MHD_Result handle_problem_type(srv_req *q,
                                           struct MHD_Connection *conn) {
    const char *slug = q->path + strlen("/problems/");
    int code = -1;
    for (int c = 0; c < API_CODE_COUNT; c++)
        if (c != API_OK && strcmp(api_code_slug((api_code)c), slug) == 0)
            code = c;
    if (code < 0)
        return srv__send_problem(q, conn, API_NOT_FOUND, NULL, 0,
                                 "no such problem type");
    api_buf b;
    api_buf_init(&b);
    const char *help = problem_help[code] ? problem_help[code]
                                          : api_code_title((api_code)code);
    api_buf_printf(&b,
                   "<!doctype html>\n<html lang=\"en\">\n<head>\n"
                   "<meta charset=\"utf-8\">\n<title>%s - voronoid</title>\n"
                   "</head>\n<body>\n<h1>%s</h1>\n<p>HTTP status %d. %s</p>\n"
                   "<p>Problem documents of this type "
                   "(<code>application/problem+json</code>) have <code>"
                   "\"type\": \"/problems/%s\"</code>. The whole interface "
                   "is described in <a href=\"../openapi.yaml\">"
                   "openapi.yaml</a>.</p>\n</body>\n</html>\n",
                   api_code_title((api_code)code),
                   api_code_title((api_code)code),
                   api_code_http((api_code)code), help, slug);
    return send_built(q, conn, &b, "text/html; charset=utf-8", 0);
}

enum MHD_Result srv__handle_static(srv_req *q, struct MHD_Connection *conn) {
    srv_server *s = q->srv;
    if (q->match == SRV_MATCH_NOT_FOUND)
        return srv__send_problem(q, conn, API_NOT_FOUND, NULL, 0,
                                 "no resource at this path");
    if (q->match == SRV_MATCH_METHOD)
        return srv__send_problem(q, conn, API_METHOD, q->allow, 0,
                                 "%s is not allowed here; allowed: %s",
                                 q->method_name, q->allow);
    if (q->method == SRV_M_OPTIONS) return handle_options(q, conn);

    switch (q->route) {
    case SRV_ROUTE_PAGE:
        return handle_asset(q, conn, "/index.html");
    case SRV_ROUTE_OPENAPI:
        return handle_asset(q, conn, "/openapi.yaml");
    case SRV_ROUTE_ASSET:
        return handle_asset(q, conn, q->path);
    case SRV_ROUTE_HEALTHZ:
        return handle_json_status(q, conn, "{\"status\":\"ok\"}\n");
    case SRV_ROUTE_READYZ:
        if (atomic_load(&s->draining))
            return srv__send_problem(q, conn, API_UNAVAILABLE, NULL,
                                     SRV_RETRY_AFTER_S,
                                     "shutting down: not taking new work");
        return handle_json_status(q, conn, "{\"status\":\"ready\"}\n");
    case SRV_ROUTE_METRICS:
        return handle_metrics(q, conn);
    case SRV_ROUTE_PROBLEM:
        return handle_problem_type(q, conn);
    case SRV_ROUTE_VORONOI:
    case SRV_ROUTE_COMPARE:
    case SRV_ROUTE_OTHER:
    case SRV_ROUTE_COUNT:
        break;
    }
    return srv__send_problem(q, conn, API_NOT_FOUND, NULL, 0,
                             "no resource at this path");
}
