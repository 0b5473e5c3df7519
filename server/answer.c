/* answer.c -- the request's way out: replies, problem documents, and the
 * headers every answer carries.
 *
 * A handler prepares an srv_reply (status, body, content type, the
 * headers that vary) and sends it with srv__send_reply; a problem is a
 * reply whose body api_write_problem wrote. srv__send_response is the one
 * place where a response is queued: it adds X-Request-Id, CORS headers,
 * the security headers and, while draining, Connection: close, and it
 * records the status and size for the access log. Every answer says
 * X-Content-Type-Options: nosniff and Referrer-Policy: no-referrer; what a
 * browser may render (the page, its files, problem pages, SVG) also
 * carries the Content-Security-Policy (SRV_CSP) and X-Frame-Options.
 *
 * Cost: small documents only (problems, health, metrics); the bodies of
 * diagrams are made elsewhere (work.c) and only passed through. Bodies
 * over SRV_GZIP_MIN are compressed here when the client takes gzip.
 */
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/uio.h>

#include "budget.h"
#include "gzip.h"
#include "internal.h"
#include "stream.h"

/* Answers longer than this (about what the socket buffers take at once)
 * are under --send-timeout while they are sent. */
#define SRV_SEND_TIMEOUT_FROM (64 * 1024)

void srv__reply_clear(srv_reply *r) {
    free(r->body);
    r->body = NULL;
    r->len = 0;
    srv_stream_discard(r->stream);
    r->stream = NULL;
    if (r->held > 0) srv_budget_give(r->budget, r->held);
    r->held = 0;
}

/* A body libmicrohttpd frees once sent, with the budget it stands for. */
typedef struct held_body {
    char *body;
    size_t held;
    srv_budget *budget;
} held_body;

static void held_body_free(void *cls) {
    held_body *h = cls;
    free(h->body);
    srv_budget_give(h->budget, h->held);
    free(h);
}

void srv__printable(char *dst, size_t size, const char *src, size_t max) {
    size_t k = 0;
    if (size == 0) return;
    for (size_t i = 0; src != NULL && src[i] && k + 4 < size; i++) {
        if (i >= max) {
            memcpy(dst + k, "...", 3);
            k += 3;
            break;
        }
        unsigned char c = (unsigned char)src[i];
        dst[k++] = (c >= 0x20 && c < 0x7f) ? (char)c : '?';
    }
    dst[k] = '\0';
}

void srv__problem_reply(srv_reply *r, const api_problem *p,
                        const char *instance) {
    api_buf b;
    api_buf_init(&b);
    api_write_problem(p, instance, &b);
    srv__reply_clear(r);
    r->status = api_code_http(p->code);
    r->ctype = "application/problem+json";
    if (b.oom || b.data == NULL) {
        api_buf_clear(&b);
        static const char fallback[] =
            "{\"type\":\"/problems/unavailable\",\"title\":\"Service "
            "unavailable\",\"status\":503,\"detail\":\"out of memory\"}\n";
        r->status = 503;
        r->body = malloc(sizeof fallback);
        if (r->body != NULL) {
            memcpy(r->body, fallback, sizeof fallback);
            r->len = sizeof fallback - 1;
        }
        return;
    }
    r->body = api_buf_take(&b, &r->len);
}

/* A problem of the code, its detail formatted from fmt. */
__attribute__((format(printf, 3, 0))) static void
problem_vset(api_problem *p, api_code code, const char *fmt, va_list ap) {
    memset(p, 0, sizeof *p);
    p->code = code;
    vsnprintf(p->detail, sizeof p->detail, fmt, ap);
}

void srv__problemf(srv_reply *r, const char *instance, api_code code,
                   const char *fmt, ...) {
    api_problem p;
    va_list ap;
    va_start(ap, fmt);
    problem_vset(&p, code, fmt, ap);
    va_end(ap);
    srv__problem_reply(r, &p, instance);
}

void srv__maybe_gzip(srv_reply *r, int gzip_ok) {
    if (!gzip_ok || r->len < SRV_GZIP_MIN || r->body == NULL ||
        strcmp(r->ctype, "application/octet-stream") == 0)
        return;
    char *z;
    size_t zn;
    if (srv_gzip(r->body, r->len, r->len > ((size_t)1 << 20) ? 1 : 6, &z,
                 &zn) != 0)
        return; /* uncompressed is still a correct answer */
    if (zn >= r->len) {
        free(z);
        return;
    }
    free(r->body);
    r->body = z;
    r->len = zn;
    r->gzipped = 1;
}

/* The page's policy: scripts (ES modules included), styles, images and
 * fetches only from the service itself; images also from data: and blob:
 * URLs (the page draws on a canvas and offers results as blob: downloads);
 * nothing else -- no inline script or style, no plugins, no framing by
 * other sites, no <base>, forms only to the service. */
#define SRV_CSP                                                              \
    "default-src 'none'; script-src 'self'; style-src 'self'; "            \
    "img-src 'self' data: blob:; connect-src 'self'; worker-src 'self'; "  \
    "frame-ancestors 'none'; base-uri 'none'; form-action 'self'"

void srv__add_page_headers(struct MHD_Response *resp) {
    MHD_add_response_header(resp, "Content-Security-Policy", SRV_CSP);
    MHD_add_response_header(resp, "X-Frame-Options", "DENY");
}

static void add_common_headers(srv_req *q, struct MHD_Response *resp) {
    MHD_add_response_header(resp, "X-Request-Id", q->id);
    MHD_add_response_header(resp, "X-Content-Type-Options", "nosniff");
    MHD_add_response_header(resp, "Referrer-Policy", "no-referrer");
    /* Anything a browser may render: every route but the computations'
     * JSON (SVG answers get it in srv__send_reply). */
    if (q->route != SRV_ROUTE_VORONOI && q->route != SRV_ROUTE_COMPARE)
        srv__add_page_headers(resp);
    MHD_add_response_header(resp, "Access-Control-Allow-Origin", "*");
    MHD_add_response_header(resp, "Access-Control-Expose-Headers",
                            "Server-Timing, X-Request-Id, Retry-After, "
                            "Content-Encoding");
    MHD_add_response_header(resp, "Timing-Allow-Origin", "*");
    if (atomic_load(&q->srv->draining))
        MHD_add_response_header(resp, "Connection", "close");
}

enum MHD_Result srv__send_response(srv_req *q, struct MHD_Connection *conn,
                                   unsigned status, struct MHD_Response *resp,
                                   size_t body_len) {
    if (resp == NULL) return MHD_NO; /* out of memory: drop the connection */
    add_common_headers(q, resp);
    if (body_len > SRV_SEND_TIMEOUT_FROM &&
        q->srv->cfg.send_timeout != (double)q->srv->cfg.connection_timeout) {
        /* More than the socket buffers take at once: a client that stops
         * reading holds the answer, so it gets --send-timeout, not the
         * idle --connection-timeout (back to that once the answer is
         * out, in on_completed). */
        unsigned t = (unsigned)q->srv->cfg.send_timeout;
        MHD_set_connection_option(conn, MHD_CONNECTION_OPTION_TIMEOUT,
                                  t > 0 ? t : 1u);
        q->send_timeout_set = 1;
    }
    enum MHD_Result rc = MHD_queue_response(conn, status, resp);
    MHD_destroy_response(resp);
    q->status = (int)status;
    if (body_len != SIZE_MAX) /* a stream counts its own (stream.h) */
        q->bytes = q->method == SRV_M_HEAD ? 0 : body_len;
    q->phase = SRV_PH_DONE;
    return rc;
}

/* The reason phrase of the statuses srv__send_direct writes. */
static const char *reason_of(int status) {
    switch (status) {
    case 400: return "Bad Request";
    case 408: return "Request Timeout";
    case 414: return "URI Too Long";
    case 431: return "Request Header Fields Too Large";
    default: return "Error";
    }
}

/* srv__send_direct: libmicrohttpd builds its answers in the
 * connection's memory, and would close the connection without a word.
 * Nothing else was written on the socket for this request, and
 * libmicrohttpd writes nothing after MHD_NO (or fails to, on the socket
 * shut down for writing). */
enum MHD_Result srv__send_direct(srv_req *q, struct MHD_Connection *conn,
                                 srv_reply *r) {
    const union MHD_ConnectionInfo *ci =
        MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
    char head[512];
    int n = snprintf(head, sizeof head,
                     "HTTP/1.1 %d %s\r\nContent-Type: %s\r\n"
                     "Content-Length: %zu\r\nConnection: close\r\n"
                     "X-Request-Id: %s\r\nX-Content-Type-Options: nosniff"
                     "\r\nAccess-Control-Allow-Origin: *\r\n\r\n",
                     r->status, reason_of(r->status), r->ctype, r->len, q->id);
    if (ci != NULL && n > 0 && (size_t)n < sizeof head) {
        struct iovec iov[2] = {{head, (size_t)n}, {r->body, r->len}};
        struct msghdr m;
        memset(&m, 0, sizeof m);
        m.msg_iov = iov;
        m.msg_iovlen = r->body != NULL ? 2 : 1;
        if (sendmsg(ci->connect_fd, &m, MSG_DONTWAIT | MSG_NOSIGNAL) > 0) {
            q->status = r->status;
            q->bytes = r->len;
        }
        shutdown(ci->connect_fd, SHUT_WR);
    }
    srv__reply_clear(r);
    q->phase = SRV_PH_DONE;
    return MHD_NO;
}

enum MHD_Result srv__send_reply(srv_req *q, struct MHD_Connection *conn,
                                srv_reply *r, const char *allow,
                                const char *cache_control) {
    if (q->bare) return srv__send_direct(q, conn, r);
    struct MHD_Response *resp;
    size_t len = r->len;
    if (r->stream != NULL) {
        q->bytes = 0;
        resp = srv_stream_start(r->stream, conn, &q->bytes); /* and types */
        r->stream = NULL;
        len = SIZE_MAX; /* unknown, and large */
    } else if (r->held > 0 && r->body != NULL) {
        held_body *h = malloc(sizeof *h);
        resp = h == NULL ? NULL
                         : MHD_create_response_from_buffer_with_free_callback_cls(
                               r->len, r->body, held_body_free, h);
        if (resp != NULL) {
            h->body = r->body;
            h->held = r->held;
            h->budget = r->budget;
            r->held = 0;
        } else {
            free(h);
        }
    } else {
        resp = MHD_create_response_from_buffer(
            r->len, r->body ? r->body : (void *)"",
            r->body ? MHD_RESPMEM_MUST_FREE : MHD_RESPMEM_PERSISTENT);
    }
    if (resp == NULL) {
        srv__reply_clear(r);
        return MHD_NO;
    }
    r->body = NULL;
    r->len = 0;
    if (len != SIZE_MAX) MHD_add_response_header(resp, "Content-Type", r->ctype);
    if (r->gzipped) MHD_add_response_header(resp, "Content-Encoding", "gzip");
    if (strcmp(r->ctype, "image/svg+xml") == 0 &&
        (q->route == SRV_ROUTE_VORONOI || q->route == SRV_ROUTE_COMPARE))
        srv__add_page_headers(resp);
    if (r->timing[0]) MHD_add_response_header(resp, "Server-Timing", r->timing);
    if (r->retry_after > 0) {
        char ra[16];
        snprintf(ra, sizeof ra, "%d", r->retry_after);
        MHD_add_response_header(resp, "Retry-After", ra);
    }
    if (allow != NULL) MHD_add_response_header(resp, "Allow", allow);
    MHD_add_response_header(resp, "Cache-Control",
                            cache_control ? cache_control : "no-store");
    if (q->route == SRV_ROUTE_VORONOI || q->route == SRV_ROUTE_COMPARE)
        MHD_add_response_header(resp, "Vary", "Accept, Accept-Encoding");
    return srv__send_response(q, conn, (unsigned)r->status, resp, len);
}

enum MHD_Result srv__send_problem(srv_req *q, struct MHD_Connection *conn,
                                  api_code code, const char *allow,
                                  int retry_after, const char *fmt, ...) {
    api_problem p;
    srv_reply r;
    memset(&r, 0, sizeof r);
    va_list ap;
    va_start(ap, fmt);
    problem_vset(&p, code, fmt, ap);
    va_end(ap);
    char inst[256];
    srv__printable(inst, sizeof inst, q->path, 200);
    srv__problem_reply(&r, &p, inst);
    r.retry_after = retry_after;
    return srv__send_reply(q, conn, &r, allow, NULL);
}

enum MHD_Result srv__send_api_problem(srv_req *q, struct MHD_Connection *conn,
                                      const api_problem *p) {
    srv_reply r;
    memset(&r, 0, sizeof r);
    char inst[256];
    srv__printable(inst, sizeof inst, q->path, 200);
    srv__problem_reply(&r, p, inst);
    return srv__send_reply(q, conn, &r, NULL, NULL);
}

enum MHD_Result srv__send_text(srv_req *q, struct MHD_Connection *conn,
                               unsigned status, const char *ctype, char *body,
                               size_t len, int gzip_ok) {
    srv_reply r;
    memset(&r, 0, sizeof r);
    r.status = (int)status;
    r.ctype = ctype;
    r.body = body;
    r.len = len;
    srv__maybe_gzip(&r, gzip_ok);
    return srv__send_reply(q, conn, &r, NULL, NULL);
}
