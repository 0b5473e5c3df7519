/* intake.c -- the request's way in: the headers it sends, its framing,
 * and its body.
 *
 * libmicrohttpd calls the access handler several times per request:
 *
 *   1st call, headers only: whatever can be refused without the body is
 *      refused NOW, before the client sends it: 415 (Content-Type), 413
 *      (Content-Length over --max-body), and 404/405 when a body is
 *      announced. A response queued in this call makes libmicrohttpd
 *      close the connection, which is what a refused upload needs.
 *   data calls: the body is appended to a buffer sized from
 *      Content-Length (chunked bodies grow, limited to --max-body as they
 *      arrive; the rest of an oversized body is read and dropped, then
 *      413, unless it goes on past 4 x --max-body: then the connection is
 *      closed).
 *   last call: srv__intake_refusal sends the 413 decided while the body
 *      came; everything else is the route's (server.c dispatches).
 *
 * Cost: one pass over the headers, one copy of the body (O(body)); memory
 * is the body, at most --max-body.
 */
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "internal.h"

/* MHD_get_connection_values callback: the first of each header in
 * srv_req_headers, matched without regard to case as libmicrohttpd's own
 * lookup does. */
static enum MHD_Result collect_header(void *cls, enum MHD_ValueKind kind,
                                      const char *key, const char *value) {
    srv_req_headers *h = cls;
    const char **slot = NULL;
    (void)kind;
    if (key == NULL) return MHD_YES;
    switch (key[0]) {
    case 'A': case 'a':
        if (strcasecmp(key, "Accept") == 0) slot = &h->accept;
        else if (strcasecmp(key, "Accept-Encoding") == 0)
            slot = &h->accept_encoding;
        break;
    case 'C': case 'c':
        if (strcasecmp(key, "Content-Length") == 0) slot = &h->content_length;
        else if (strcasecmp(key, "Content-Type") == 0)
            slot = &h->content_type;
        break;
    case 'T': case 't':
        if (strcasecmp(key, "Transfer-Encoding") == 0)
            slot = &h->transfer_encoding;
        break;
    case 'X': case 'x':
        if (strcasecmp(key, "X-Request-Id") == 0) slot = &h->request_id;
        break;
    }
    if (slot != NULL && *slot == NULL) *slot = value;
    return MHD_YES;
}

/* Body announced? (Content-Length > 0 or a transfer coding.) */
static int body_announced(const srv_req *q) {
    return (q->has_cl && q->content_length > 0) ||
           q->h.transfer_encoding != NULL;
}

/* First call: headers are in, no body yet. */
enum MHD_Result srv__on_headers(srv_req *q, struct MHD_Connection *conn) {
    srv_server *s = q->srv;
    const char *cl = q->h.content_length;
    if (cl != NULL) {
        char *end;
        unsigned long long v = strtoull(cl, &end, 10);
        q->has_cl = end != cl && *end == '\0';
        q->content_length = q->has_cl ? v : 0;
    }
    if (q->match == SRV_MATCH_NOT_FOUND && body_announced(q))
        return srv__send_problem(q, conn, API_NOT_FOUND, NULL, 0,
                                 "no resource at this path");
    if (q->match == SRV_MATCH_METHOD && body_announced(q))
        return srv__send_problem(q, conn, API_METHOD, q->allow, 0,
                                 "%s is not allowed here; allowed: %s",
                                 q->method_name, q->allow);
    if (q->has_cl && q->content_length > s->cfg.max_body)
        return srv__send_problem(q, conn, API_TOO_LARGE, NULL, 0,
                                 "the body of %llu bytes is larger than the "
                                 "limit of %zu bytes (--max-body)",
                                 (unsigned long long)q->content_length,
                                 s->cfg.max_body);
    if (q->match == SRV_MATCH_OK && q->method == SRV_M_POST &&
        (q->route == SRV_ROUTE_VORONOI || q->route == SRV_ROUTE_COMPARE)) {
        api_problem p;
        memset(&p, 0, sizeof p);
        if (api_input_from_content_type(q->h.content_type,
                                        &q->kind, &p) != API_OK)
            return srv__send_api_problem(q, conn, &p);
        q->collect = 1;
    }
    return MHD_YES;
}

enum MHD_Result srv__on_data(srv_req *q, const char *data, size_t n) {
    size_t max = q->srv->cfg.max_body;
    if (!q->collect || q->too_large) {
        /* Read and dropped, so that the answer (413, 404, 405) can be sent
         * on a connection that stays usable. A sender that goes on far
         * past the limit is cut off instead: that costs it the answer,
         * not us an unbounded transfer. */
        q->dropped += n;
        return q->dropped / 4 > max ? MHD_NO : MHD_YES;
    }
    if (n > max - q->len) {
        q->too_large = 1;
        q->dropped = q->len + n;
        free(q->body);
        q->body = NULL;
        q->len = q->cap = 0;
        return MHD_YES;
    }
    if (q->len + n + 1 > q->cap) {
        size_t cap;
        if (q->has_cl && q->content_length + 1 >= q->len + n + 1)
            cap = (size_t)q->content_length + 1;
        else {
            cap = q->cap ? q->cap : 65536;
            while (cap < q->len + n + 1) cap *= 2;
            if (cap > max + 1) cap = max + 1;
        }
        char *b = realloc(q->body, cap);
        if (b == NULL) return MHD_NO; /* cannot hold it: drop the connection */
        q->body = b;
        q->cap = cap;
    }
    memcpy(q->body + q->len, data, n);
    q->len += n;
    q->body[q->len] = '\0';
    return MHD_YES;
}

void srv__collect_headers(struct MHD_Connection *conn, srv_req_headers *h) {
    MHD_get_connection_values(conn, MHD_HEADER_KIND, collect_header, h);
}

int srv__intake_refusal(srv_req *q, struct MHD_Connection *conn,
                        enum MHD_Result *rc) {
    if (!q->too_large) return 0;
    *rc = srv__send_problem(q, conn, API_TOO_LARGE, NULL, 0,
                            "the body is larger than the limit of %zu bytes "
                            "(--max-body)",
                            q->srv->cfg.max_body);
    return 1;
}
