/* intake.c -- the request's way in: the headers it sends, its framing,
 * and its body.
 *
 * libmicrohttpd calls the access handler several times per request:
 *
 *   1st call, headers only: whatever can be refused without the body is
 *      refused NOW, before the client sends it:
 *        414 / 431  request line or headers too long (answered with few
 *                   headers: the connection's memory is nearly spent);
 *        501        a Transfer-Encoding other than chunked;
 *        400        Transfer-Encoding together with Content-Length, or
 *                   two Content-Length values that disagree (either is a
 *                   way to smuggle a second request past a proxy);
 *        404 / 405  a body announced where none is taken;
 *        413        Content-Length over --max-body;
 *        415        a Content-Type, or a Content-Encoding other than
 *                   gzip, deflate or identity, the service cannot read.
 *      A response queued in this call makes libmicrohttpd close the
 *      connection, which is what a refused upload needs; the guard keeps
 *      the socket open a little longer to read what the client still
 *      sends (lingering close, guard.h), so that a client that only reads
 *      after sending still gets the answer.
 *   data calls: the body (decoded, when it has a Content-Encoding) is
 *      appended to a buffer sized from Content-Length (chunked bodies
 *      grow), limited to --max-body as it arrives: past the limit the
 *      rest is read and dropped, then 413, unless it goes on past
 *      4 x --max-body: then the connection is closed. libmicrohttpd can
 *      queue no answer in the middle of a body, so this is as early as a
 *      413 can come for a chunked body.
 *   last call: srv__intake_refusal sends the 413 (or 400, for a body that
 *      does not decode) decided while the body came; everything else is
 *      the route's (server.c dispatches).
 *
 * What libmicrohttpd 0.9.75 refuses before this file sees the request
 * (a Content-Length that is not a number, a request line or headers that
 * do not fit the connection's memory) it answers itself; deploy/README.md
 * lists those cases and the nginx settings that keep them away.
 *
 * Cost: one pass over the headers, one copy of the body (O(body)), plus
 * inflate for encoded bodies (bounded by --max-body of output); memory
 * is the body, at most --max-body.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "decode.h"
#include "guard.h"
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
        if (strcasecmp(key, "Content-Length") == 0) {
            slot = &h->content_length;
            if (h->n_content_length++ > 0 && value != NULL &&
                h->content_length != NULL &&
                strcmp(value, h->content_length) != 0 &&
                h->content_length_2 == NULL)
                h->content_length_2 = value;
        } else if (strcasecmp(key, "Content-Type") == 0) {
            slot = &h->content_type;
        } else if (strcasecmp(key, "Content-Encoding") == 0) {
            slot = &h->content_encoding;
            h->n_content_encoding++;
        }
        break;
    case 'T': case 't':
        if (strcasecmp(key, "Transfer-Encoding") == 0) {
            slot = &h->transfer_encoding;
            h->n_transfer_encoding++;
        }
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

/* A refusal in the first call: the body, if one is coming, is read and
 * dropped after the answer (lingering close). */
static enum MHD_Result refuse(srv_req *q, struct MHD_Connection *conn,
                              api_code code, const char *allow,
                              const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

static enum MHD_Result refuse(srv_req *q, struct MHD_Connection *conn,
                              api_code code, const char *allow,
                              const char *fmt, ...) {
    char detail[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(detail, sizeof detail, fmt, ap);
    va_end(ap);
    if (body_announced(q)) srv_guard_conn_linger(q->gconn);
    return srv__send_problem(q, conn, code, allow, 0, "%s", detail);
}

/* Whether a Transfer-Encoding value is exactly "chunked" (blanks and case
 * aside): the one coding the service reads. */
static int is_chunked(const char *te) {
    while (*te == ' ' || *te == '\t') te++;
    if (strncasecmp(te, "chunked", 7) != 0) return 0;
    for (te += 7; *te; te++)
        if (*te != ' ' && *te != '\t') return 0;
    return 1;
}

/* The request head was too long for the service (or nearly for the
 * connection's memory): 414 or 431 with as few headers as possible. */
static int head_too_long(srv_req *q, struct MHD_Connection *conn,
                         const char *url, enum MHD_Result *rc) {
    size_t url_len = url != NULL ? strlen(url) : 0;
    const union MHD_ConnectionInfo *ci = MHD_get_connection_info(
        conn, MHD_CONNECTION_INFO_REQUEST_HEADER_SIZE);
    size_t head = ci != NULL ? ci->header_size : 0;
    if (url_len <= SRV_MAX_REQUEST_LINE && head <= SRV_MAX_REQUEST_HEAD)
        return 0;
    q->bare = 1;
    if (url_len > SRV_MAX_REQUEST_LINE)
        *rc = refuse(q, conn, API_URI_TOO_LONG, NULL,
                     "the request target is %zu bytes long; the service "
                     "reads at most %d", url_len, SRV_MAX_REQUEST_LINE);
    else
        *rc = refuse(q, conn, API_HEADERS_TOO_LARGE, NULL,
                     "the request line and headers are %zu bytes long; the "
                     "service reads at most %d", head, SRV_MAX_REQUEST_HEAD);
    return 1;
}

enum MHD_Result srv__on_headers(srv_req *q, struct MHD_Connection *conn,
                                const char *url) {
    srv_server *s = q->srv;
    const char *cl = q->h.content_length;
    if (cl != NULL) {
        char *end;
        unsigned long long v = strtoull(cl, &end, 10);
        q->has_cl = end != cl && *end == '\0';
        q->content_length = q->has_cl ? v : 0;
    }
    enum MHD_Result rc;
    if (head_too_long(q, conn, url, &rc)) return rc;

    /* Framing first: a request whose end cannot be told is answered and
     * the connection closed, whatever its route. */
    const char *te = q->h.transfer_encoding;
    if (te != NULL && (q->h.n_transfer_encoding > 1 || !is_chunked(te))) {
        char shown[64];
        srv__printable(shown, sizeof shown, te, 40);
        return refuse(q, conn, API_NOT_IMPLEMENTED, NULL,
                      "Transfer-Encoding '%s'%s is not supported: send the "
                      "body with Content-Length, or with Transfer-Encoding: "
                      "chunked alone (compression goes in Content-Encoding)",
                      shown, q->h.n_transfer_encoding > 1
                                 ? " in more than one header" : "");
    }
    if (te != NULL && q->h.content_length != NULL)
        return refuse(q, conn, API_MALFORMED, NULL,
                      "the request has both Transfer-Encoding and "
                      "Content-Length; send one of them");
    if (q->h.content_length_2 != NULL) {
        char a[32], b[32];
        srv__printable(a, sizeof a, q->h.content_length, 20);
        srv__printable(b, sizeof b, q->h.content_length_2, 20);
        return refuse(q, conn, API_MALFORMED, NULL,
                      "the request has Content-Length headers that "
                      "disagree: %s and %s", a, b);
    }

    if (q->match == SRV_MATCH_NOT_FOUND && body_announced(q))
        return refuse(q, conn, API_NOT_FOUND, NULL,
                      "no resource at this path");
    if (q->match == SRV_MATCH_METHOD && body_announced(q))
        return refuse(q, conn, API_METHOD, q->allow,
                      "%s is not allowed here; allowed: %s", q->method_name,
                      q->allow);
    if (q->has_cl && q->content_length > s->cfg.max_body)
        return refuse(q, conn, API_TOO_LARGE, NULL,
                      "the body of %llu bytes is larger than the limit of "
                      "%zu bytes (--max-body)",
                      (unsigned long long)q->content_length, s->cfg.max_body);
    if (q->match == SRV_MATCH_OK && q->method == SRV_M_POST &&
        (q->route == SRV_ROUTE_VORONOI || q->route == SRV_ROUTE_COMPARE)) {
        api_problem p;
        memset(&p, 0, sizeof p);
        if (api_input_from_content_type(q->h.content_type, &q->kind, &p) !=
            API_OK) {
            if (body_announced(q)) srv_guard_conn_linger(q->gconn);
            return srv__send_api_problem(q, conn, &p);
        }
        srv_coding coding = srv_coding_of(q->h.content_encoding);
        if (coding == SRV_CODING_UNKNOWN || q->h.n_content_encoding > 1) {
            char shown[64];
            srv__printable(shown, sizeof shown, q->h.content_encoding, 40);
            return refuse(q, conn, API_MEDIA_TYPE, NULL,
                          "Content-Encoding '%s'%s is not supported: send "
                          "gzip, deflate or identity", shown,
                          q->h.n_content_encoding > 1
                              ? " in more than one header" : "");
        }
        if (coding != SRV_CODING_IDENTITY) {
            q->decoder = srv_decoder_new(coding, s->cfg.max_body);
            if (q->decoder == NULL)
                return refuse(q, conn, API_UNAVAILABLE, NULL,
                              "out of memory");
        }
        q->collect = 1;
    }
    return MHD_YES;
}

/* Appends n bytes to the body buffer, sized from Content-Length for a
 * plain body, grown geometrically otherwise, at most max_body + 1. 0, or
 * -1 when memory ran out. */
static int append(srv_req *q, const char *data, size_t n) {
    size_t max = q->srv->cfg.max_body;
    if (q->len + n + 1 > q->cap) {
        size_t cap;
        if (q->decoder == NULL && q->has_cl &&
            q->content_length + 1 >= q->len + n + 1)
            cap = (size_t)q->content_length + 1;
        else {
            cap = q->cap ? q->cap : 65536;
            while (cap < q->len + n + 1) cap *= 2;
            if (cap > max + 1) cap = max + 1;
        }
        char *b = realloc(q->body, cap);
        if (b == NULL) return -1;
        q->body = b;
        q->cap = cap;
    }
    memcpy(q->body + q->len, data, n);
    q->len += n;
    q->body[q->len] = '\0';
    return 0;
}

/* Gives up the body: past --max-body, or not decodable. */
static void drop_body(srv_req *q, size_t also_read) {
    q->dropped = q->len + also_read;
    free(q->body);
    q->body = NULL;
    q->len = q->cap = 0;
}

static int decoded_sink(void *ctx, const char *data, size_t n) {
    srv_req *q = ctx;
    return append(q, data, n);
}

enum MHD_Result srv__on_data(srv_req *q, const char *data, size_t n) {
    size_t max = q->srv->cfg.max_body;
    srv_guard_conn_body(q->gconn, n);
    if (!q->collect || q->too_large || q->bad_body) {
        /* Read and dropped, so that the answer (413, 404, 405, 400) can
         * be sent on a connection that stays usable. A sender that goes
         * on far past the limit is cut off instead: that costs it the
         * answer, not us an unbounded transfer. */
        q->dropped += n;
        return q->dropped / 4 > max ? MHD_NO : MHD_YES;
    }
    if (q->decoder != NULL) {
        /* The encoded bytes count against the limit too. */
        q->dropped += n;
        int st = q->dropped > max
                     ? SRV_DECODE_LIMIT
                     : srv_decoder_feed(q->decoder, data, n, decoded_sink, q);
        if (st == SRV_DECODE_OK) return MHD_YES;
        if (st == SRV_DECODE_NOMEM) return MHD_NO;
        if (st == SRV_DECODE_LIMIT) {
            q->too_large = 1;
        } else {
            q->bad_body = 1;
            snprintf(q->bad_detail, sizeof q->bad_detail,
                     "the body does not decode as its Content-Encoding "
                     "says: %s", srv_decoder_error(q->decoder));
        }
        drop_body(q, 0);
        return MHD_YES;
    }
    if (n > max - q->len) {
        q->too_large = 1;
        drop_body(q, n);
        return MHD_YES;
    }
    if (append(q, data, n) != 0)
        return MHD_NO; /* cannot hold it: drop the connection */
    return MHD_YES;
}

void srv__collect_headers(struct MHD_Connection *conn, srv_req_headers *h) {
    MHD_get_connection_values(conn, MHD_HEADER_KIND, collect_header, h);
}

int srv__intake_refusal(srv_req *q, struct MHD_Connection *conn,
                        enum MHD_Result *rc) {
    if (q->decoder != NULL && !q->too_large && !q->bad_body &&
        srv_decoder_finish(q->decoder) != SRV_DECODE_OK) {
        q->bad_body = 1;
        snprintf(q->bad_detail, sizeof q->bad_detail,
                 "the body does not decode as its Content-Encoding says: %s",
                 srv_decoder_error(q->decoder));
        drop_body(q, 0);
    }
    if (q->too_large) {
        *rc = srv__send_problem(q, conn, API_TOO_LARGE, NULL, 0,
                                "the body is larger than the limit of %zu "
                                "bytes (--max-body)%s",
                                q->srv->cfg.max_body,
                                q->decoder != NULL ? ", counted decoded" : "");
        return 1;
    }
    if (q->bad_body) {
        *rc = srv__send_problem(q, conn, API_MALFORMED, NULL, 0, "%s",
                                q->bad_detail);
        return 1;
    }
    return 0;
}

void srv__intake_clear(srv_req *q) {
    srv_decoder_free(q->decoder);
    q->decoder = NULL;
}
