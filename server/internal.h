/* internal.h -- what the files of the HTTP front share (not part of the
 * interface in server.h): the service's state, one request's state, and
 * the functions that pass a request from one file to the next.
 *
 *   server.c    the daemon's life cycle and libmicrohttpd's callbacks: a
 *               request's calls are dispatched from here
 *   intake.c    the request's way in: headers, framing, body intake
 *   work.c      the compute routes: options, the inline path, pool jobs
 *   handlers.c  every other route: page, files, health, metrics, ...
 *   answer.c    the request's way out: replies, problem documents, the
 *               headers every answer carries
 *
 * Names: srv__ for functions shared between these files; the structs are
 * shared as they are (one owner: the connection's thread, except where a
 * field says otherwise).
 */
#ifndef VOR_SRV_INTERNAL_H
#define VOR_SRV_INTERNAL_H

#include <microhttpd.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "../api/api.h"
#include "accesslog.h"
#include "assets.h"
#include "config.h"
#include "metrics.h"
#include "pool.h"
#include "routes.h"
#include "server.h"

#define SRV_MAX_OPTIONS 16  /* query parameters per request */
#define SRV_RETRY_AFTER_S 1 /* Retry-After on 503 */

typedef struct srv_guard srv_guard;
typedef struct srv_budget srv_budget;
typedef struct srv_streams srv_streams;
typedef struct srv_stream srv_stream;

struct srv_server {
    srv_config cfg;
    srv_guard *guard;
    srv_budget *budget;   /* --answer-memory (budget.h) */
    srv_streams *streams; /* answers being streamed (stream.h) */
    struct MHD_Daemon *daemon;
    srv_pool *pool;
    srv_metrics *metrics;
    srv_assets *assets;
    int port;
    srv_log *log;         /* access lines and libmicrohttpd's messages */
    int listen_closed;    /* srv_server_stop_listening ran (main thread) */
    size_t accepted_late; /* connections taken from the queue by hand */
    atomic_int draining;
    atomic_int closing;   /* srv_server_free began: no new computations */
    atomic_long in_flight;
    atomic_ullong next_id;
    uint64_t id_seed;
};

/* ---- replies ------------------------------------------------------------- */

/* An answer being prepared: status, body and the headers that vary. */
typedef struct srv_reply {
    int status;
    char *body;            /* malloc'd, handed to libmicrohttpd */
    size_t len;
    const char *ctype;
    int gzipped;
    int retry_after;       /* seconds; 0 = no header */
    char timing[400];      /* Server-Timing value, "" for none */
    const char *algorithm; /* for the log, NULL when none */
    long long points;      /* for the log, -1 when unknown */
    srv_stream *stream;    /* instead of body: an answer made as it is
                              sent (stream.h) */
    size_t held;           /* bytes of the budget the body stands for,
                              given back when it is freed */
    srv_budget *budget;
} srv_reply;

/* ---- one request --------------------------------------------------------- */

enum { SRV_PH_BODY, SRV_PH_WAIT, SRV_PH_DONE };

/* The request headers the handlers read, found in one pass over them
 * (srv__collect_headers) instead of a lookup each; NULL when absent.
 * Borrowed from libmicrohttpd, valid until the request completes. */
typedef struct srv_req_headers {
    const char *accept, *accept_encoding, *content_length, *content_type,
        *transfer_encoding, *request_id, *content_encoding;
    /* How often the framing headers came (a second one is an error unless
     * it repeats the first Content-Length exactly). */
    int n_content_length, n_transfer_encoding, n_content_encoding;
    const char *content_length_2; /* a Content-Length that differs */
} srv_req_headers;

typedef struct srv_compute_job srv_compute_job;
typedef struct srv_decoder srv_decoder;
typedef struct srv_guard_conn srv_guard_conn;

typedef struct srv_req {
    srv_server *srv;
    int64_t t0_ns;
    double unix_t0;
    srv_route route;
    srv_match match;
    unsigned method;
    char method_name[16];
    char path[256];
    char id[80];
    char allow[48];
    srv_req_headers h;
    int phase;
    /* body intake */
    int collect;          /* keep the body (compute routes) */
    char *body;
    size_t len, cap;
    int too_large;
    size_t dropped;       /* body bytes read and thrown away */
    uint64_t content_length;
    int has_cl;
    api_input kind;
    srv_decoder *decoder; /* Content-Encoding gzip or deflate, else NULL */
    int bad_body;         /* the body could not be decoded: 400 at the end */
    char bad_detail[200];
    srv_guard_conn *gconn; /* the connection's deadlines (guard.h) */
    int started;          /* the access handler has seen the request */
    int refused;          /* answered before the handler: refuse it */
    int bare;             /* answer on the socket directly (the request
                             filled the connection's memory) */
    int send_timeout_set; /* the connection's timeout is --send-timeout */
    /* outcome */
    int status;
    size_t bytes;
    const char *algorithm;
    long long points;
    srv_compute_job *job;
} srv_req;

/* ---- answer.c ------------------------------------------------------------ */

void srv__reply_clear(srv_reply *r);

/* Fills r with the problem+json body for p. Cannot fail: without memory the
 * body is a fixed string. */
void srv__problem_reply(srv_reply *r, const api_problem *p,
                        const char *instance);

/* srv__problem_reply with a problem made of code and a printf-style
 * detail. */
void srv__problemf(srv_reply *r, const char *instance, api_code code,
                   const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* Compresses r's body in place when the client takes gzip and it pays. */
void srv__maybe_gzip(srv_reply *r, int gzip_ok);

/* Replaces non-printable and non-ASCII bytes so a value can go into a
 * problem detail (JSON strings must be valid UTF-8); at most max bytes of
 * src, then "...". */
void srv__printable(char *dst, size_t size, const char *src, size_t max);

/* Queues resp (destroyed here) with status and the headers every answer
 * carries; records what the log needs. resp NULL (out of memory): MHD_NO,
 * which drops the connection. */
enum MHD_Result srv__send_response(srv_req *q, struct MHD_Connection *conn,
                                   unsigned status, struct MHD_Response *resp,
                                   size_t body_len);

/* Adds the Content-Security-Policy and X-Frame-Options of what a browser
 * renders. */
void srv__add_page_headers(struct MHD_Response *resp);

/* Sends a reply (its body is taken). allow and cache_control may be NULL
 * (no Allow header; Cache-Control: no-store). */
enum MHD_Result srv__send_reply(srv_req *q, struct MHD_Connection *conn,
                                srv_reply *r, const char *allow,
                                const char *cache_control);

/* Writes r (taken) as a whole response straight to the socket and has
 * libmicrohttpd close the connection (returns MHD_NO): for a request that
 * filled the connection's memory, where libmicrohttpd has no room left to
 * build an answer. */
enum MHD_Result srv__send_direct(srv_req *q, struct MHD_Connection *conn,
                                 srv_reply *r);

/* Longest request line and request head (line and headers) the service
 * reads; beyond, 414 and 431. Well inside the connection's memory
 * (SRV_CONNECTION_MEMORY in server.c). */
#define SRV_MAX_REQUEST_LINE 8192
#define SRV_MAX_REQUEST_HEAD 12288

/* A problem document for this request, detail printf-style. */
enum MHD_Result srv__send_problem(srv_req *q, struct MHD_Connection *conn,
                                  api_code code, const char *allow,
                                  int retry_after, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 6, 7)))
#endif
    ;

enum MHD_Result srv__send_api_problem(srv_req *q, struct MHD_Connection *conn,
                                      const api_problem *p);

/* A body of our own (taken), gzipped when the client takes it. */
enum MHD_Result srv__send_text(srv_req *q, struct MHD_Connection *conn,
                               unsigned status, const char *ctype, char *body,
                               size_t len, int gzip_ok);

/* ---- intake.c ------------------------------------------------------------ */

/* Finds the headers of srv_req_headers in one pass. */
void srv__collect_headers(struct MHD_Connection *conn, srv_req_headers *h);

/* First call: the headers are in, no body yet. Refuses now what can be
 * refused without the body. */
enum MHD_Result srv__on_headers(srv_req *q, struct MHD_Connection *conn,
                                const char *url);

/* A piece of the body. */
enum MHD_Result srv__on_data(srv_req *q, const char *data, size_t n);

/* Last call: the whole request is in; refusals decided while the body
 * came (413, 400 for a body that cannot be decoded) are sent. Returns 1
 * with *rc set when it answered. */
int srv__intake_refusal(srv_req *q, struct MHD_Connection *conn,
                        enum MHD_Result *rc);

/* Frees what intake holds for q (the decoder). */
void srv__intake_clear(srv_req *q);

/* ---- work.c -------------------------------------------------------------- */

/* POST /voronoi or /compare with its whole body: computed inline or handed
 * to the pool (the connection is then suspended). */
enum MHD_Result srv__start_compute(srv_req *q, struct MHD_Connection *conn);

/* Called again after the pool resumed the connection: sends the answer. */
enum MHD_Result srv__finish_compute(srv_req *q, struct MHD_Connection *conn);

/* Drops the request's reference to its job (on_completed). */
void srv__job_unref(srv_compute_job *j);

/* 1 if the job stopped because its client had hung up (for the log; read
 * after the answer was published). */
int srv__job_client_gone(srv_compute_job *j);

/* ---- handlers.c ---------------------------------------------------------- */

/* Answers the whole request q on a route that is not a computation (and
 * the errors of routing: 404, 405). */
enum MHD_Result srv__handle_static(srv_req *q, struct MHD_Connection *conn);

int srv__client_takes_gzip(const srv_req *q);

#endif /* VOR_SRV_INTERNAL_H */
