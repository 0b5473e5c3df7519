/* server.c -- voronoid's HTTP front: libmicrohttpd callbacks, body intake,
 * dispatch to handlers, compute jobs, responses, access log and metrics.
 *
 * A request goes through the access handler several times (libmicrohttpd's
 * protocol):
 *
 *   1st call, headers only: a `req` is made; the route is matched. Whatever
 *      can be refused without the body is refused NOW, before the client
 *      sends it: 415 (Content-Type), 413 (Content-Length over --max-body),
 *      and 404/405 when a body is announced. A response queued in this call
 *      makes libmicrohttpd close the connection, which is what a refused
 *      upload needs; every other answer waits for the last call so that the
 *      connection stays open (keep-alive).
 *   data calls: the body is appended to a buffer sized from Content-Length
 *      (chunked bodies grow, limited to --max-body as they arrive; the rest
 *      of an oversized body is read and dropped, then 413, unless it goes
 *      on past 4 x --max-body: then the connection is closed).
 *   last call (no more data): static routes answer at once. POST /voronoi
 *      and /compare of at most --inline-points points (and a small body)
 *      are computed and answered at once too, on this thread (run_inline).
 *      Larger ones become a compute_job: the connection is suspended and
 *      the job queued in the srv_pool. Queue full -> 503 + Retry-After.
 *   after resume: the job's reply (diagram, problem, 504 or 503) is queued.
 *
 * A compute_job is shared by the connection and the pool (reference count
 * 2). Its reply is written exactly once, by the pool's done() callback (on
 * the worker when run() finished in time, on the timer thread at the
 * deadline, or by srv_server_cancel), and only then is the connection
 * resumed; run()'s own output lives in separate fields, so a late run()
 * never races the reply. The job is freed when both references are gone.
 *
 * Every response carries X-Request-Id (echoed or generated), CORS headers
 * and, while draining, Connection: close. Every request that got as far as
 * our handler ends in on_completed: one access-log line and the metrics.
 *
 * Cost: the connection threads copy the body once (O(body)) and otherwise
 * only write small documents (problems, metrics, health), hand out the
 * pre-compressed embedded files, and compute tiny requests (bounded by
 * --inline-points and SRV_INLINE_MAX_BODY: well under a millisecond);
 * parsing, computing, serializing and gzip of everything larger happen on
 * the workers. Memory per request: the body, then the codec's result and
 * the answer (the body is freed once parsed).
 */
#include "server.h"

#include <arpa/inet.h>
#include <math.h>
#include <microhttpd.h>
#include <netinet/in.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "../api/api.h"
#include "accesslog.h"
#include "assets.h"
#include "fmt.h"
#include "gzip.h"
#include "metrics.h"
#include "pool.h"
#include "routes.h"

#define MAX_OPTIONS 16      /* query parameters per request */
#define RETRY_AFTER_S 1     /* Retry-After on 503 */
/* Bodies up to this size may be computed inline (see run_inline): it
 * bounds what reading one costs the connection's thread, ~20 us. */
#define SRV_INLINE_MAX_BODY 16384
/* libmicrohttpd's memory per connection (its default is 32 KiB): request
 * headers and the read buffer live in it, and libmicrohttpd zeroes it,
 * and half of it again, for every request on a kept-alive connection --
 * 48 KiB of stores per request, a sixth of the instructions of a 10-point
 * request and the whole L1 cache. 16 KiB halves that and still takes
 * request headers of several KiB; bodies stream through the read buffer
 * in smaller pieces (8 KiB reads instead of 16 KiB). */
#define SRV_CONNECTION_MEMORY (16 * 1024)
/* Longest time an access-log line waits in the buffer before it is
 * written (accesslog.h): short enough for a person or a log shipper
 * watching the file, long enough to write hundreds of lines at once. */
#define SRV_LOG_DELAY_MS 20

struct srv_server {
    srv_config cfg;
    struct MHD_Daemon *daemon;
    MHD_socket quiesced_fd;
    srv_pool *pool;
    srv_metrics *metrics;
    srv_assets *assets;
    int port;
    srv_log *log;         /* access lines and libmicrohttpd's messages */
    atomic_int draining;
    atomic_int closing;   /* srv_server_free began: no new computations */
    atomic_long in_flight;
    atomic_ullong next_id;
    uint64_t id_seed;
};

/* ---- replies and jobs --------------------------------------------------- */

typedef struct reply {
    int status;
    char *body;            /* malloc'd, handed to libmicrohttpd */
    size_t len;
    const char *ctype;
    int gzipped;
    int retry_after;       /* seconds; 0 = no header */
    char timing[400];      /* Server-Timing value, "" for none */
    const char *algorithm; /* for the log, NULL when none */
    long long points;      /* for the log, -1 when unknown */
} reply;

typedef struct compute_job {
    srv_job base; /* first: the pool hands back &base */
    atomic_int refs;
    srv_server *srv;
    struct MHD_Connection *conn;
    int compare;
    api_input kind;
    char *body;
    size_t len;
    char *accept;
    size_t n_opts;
    char *opt_key[MAX_OPTIONS], *opt_val[MAX_OPTIONS];
    int gzip_ok;
    char instance[16];
    reply out;            /* run()'s result, private to run() and done(RAN) */
    reply r;              /* the answer, written once by done() */
    atomic_int answered;
} compute_job;

enum { PH_BODY, PH_WAIT, PH_DONE };

/* The request headers the handlers read, found in one pass over them
 * (collect_header) instead of a lookup each; NULL when absent. Borrowed
 * from libmicrohttpd, valid until the request completes. */
typedef struct req_headers {
    const char *accept, *accept_encoding, *content_length, *content_type,
        *transfer_encoding, *request_id;
} req_headers;

typedef struct req {
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
    req_headers h;
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
    /* outcome */
    int status;
    size_t bytes;
    const char *algorithm;
    long long points;
    compute_job *job;
} req;

static void reply_clear(reply *r) {
    free(r->body);
    r->body = NULL;
    r->len = 0;
}

static void job_unref(compute_job *j) {
    if (atomic_fetch_sub_explicit(&j->refs, 1, memory_order_acq_rel) != 1)
        return;
    free(j->body);
    free(j->accept);
    for (size_t i = 0; i < j->n_opts; i++) {
        free(j->opt_key[i]);
        free(j->opt_val[i]);
    }
    reply_clear(&j->out);
    reply_clear(&j->r);
    free(j);
}

/* Replaces non-printable and non-ASCII bytes so a value can go into a
 * problem detail (JSON strings must be valid UTF-8). */
static void printable(char *dst, size_t size, const char *src, size_t max) {
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

/* Fills r with the problem+json body for p. Cannot fail: without memory the
 * body is a fixed string. */
static void problem_reply(reply *r, const api_problem *p,
                          const char *instance) {
    api_buf b;
    api_buf_init(&b);
    api_write_problem(p, instance, &b);
    reply_clear(r);
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

static void problemf(reply *r, const char *instance, api_code code,
                     const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

static void problemf(reply *r, const char *instance, api_code code,
                     const char *fmt, ...) {
    api_problem p;
    memset(&p, 0, sizeof p);
    p.code = code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p.detail, sizeof p.detail, fmt, ap);
    va_end(ap);
    problem_reply(r, &p, instance);
}

/* Compresses r's body in place when the client takes gzip and it pays. */
static void maybe_gzip(reply *r, int gzip_ok) {
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

static double ms_since(int64_t t0_ns) {
    return (double)(srv_now_ns() - t0_ns) / 1e6;
}

/* A Server-Timing value being built: "queue;dur=0.012, parse;dur=...". */
typedef struct timing_buf {
    char *p;
    size_t len, size;
} timing_buf;

static timing_buf timing_start(char *p, size_t size) {
    timing_buf t = {p, 0, size};
    if (size > 0) p[0] = '\0';
    return t;
}

/* Appends "name;dur=ms" (ms as "%.3f"); an entry that does not fit is
 * left out. */
static void timing_add(timing_buf *t, const char *name, double ms) {
    char num[SRV_FMT_MS3_MAX];
    size_t k = srv_fmt_ms3(num, ms), nl = strlen(name);
    size_t sep = t->len > 0 ? 2 : 0;
    if (t->len + sep + nl + 5 + k + 1 > t->size) return;
    char *w = t->p + t->len;
    memcpy(w, ", ", sep);
    memcpy(w + sep, name, nl);
    memcpy(w + sep + nl, ";dur=", 5);
    memcpy(w + sep + nl + 5, num, k);
    t->len += sep + nl + 5 + k;
    t->p[t->len] = '\0';
}

/* What a computation reads: the request as received, borrowed. */
typedef struct job_input {
    int compare;
    api_input kind;
    const char *body;
    size_t len;
    const char *accept;            /* NULL when absent */
    size_t n_opts;
    const char *const *opt_key, *const *opt_val;
} job_input;

static int job_stopped(srv_job *base) {
    return base != NULL && srv_job_abandoned(base);
}

/* Stage 1: Accept, then the body, then the query options into r, so that
 * query parameters > JSON body > Accept > defaults. More than max_points
 * points give API_TOO_LARGE before they are read or generated. */
static api_code read_input(api_request *r, const job_input *in,
                           size_t max_points, api_problem *p) {
    api_limits lim = {max_points};
    api_code c = API_OK;
    if (in->accept != NULL) c = api_format_from_accept(r, in->accept, p);
    if (c == API_OK)
        c = api_parse_body(r, in->kind, in->body ? in->body : "", in->len,
                           &lim, p);
    for (size_t i = 0; c == API_OK && i < in->n_opts; i++)
        c = api_request_option(r, in->opt_key[i], in->opt_val[i], p);
    return c;
}

/* The answer to a request that could not be read. */
static void input_problem(reply *out, const api_problem *p,
                          const char *instance, double queue_ms,
                          double parse_ms) {
    problem_reply(out, p, instance);
    timing_buf tb = timing_start(out->timing, sizeof out->timing);
    timing_add(&tb, "queue", queue_ms);
    timing_add(&tb, "parse", parse_ms);
}

/* Stage 2: computes the diagram (or the comparison) of a parsed request
 * and writes the answer into out: 200 with the document and its
 * Server-Timing, or a problem. base is the pool's job, polled so that work
 * nobody will read stops early; NULL when the request runs inline. */
static void compute_answer(srv_server *s, const api_request *r, int compare,
                           double queue_ms, double parse_ms, srv_job *base,
                           const char *instance, reply *out) {
    api_problem p;
    api_buf b;
    api_code c = API_OK;
    memset(&p, 0, sizeof p);
    api_buf_init(&b);
    out->points = (long long)r->n;
    out->algorithm = compare ? "all" : vor_algorithm_name(r->algorithm);

    if (!compare) {
        api_result res;
        api_result_init(&res);
        c = api_compute(r, &res, &p);
        if (c == API_OK) {
            srv_metrics_compute(s->metrics, r->algorithm, r->n,
                                res.t.compute_ms / 1e3);
            if (!job_stopped(base)) {
                api_timings t = res.t;
                t.queue_ms = queue_ms;
                t.parse_ms = parse_ms;
                t.total_ms += queue_ms + parse_ms;
                c = api_write_result(r, &res, &t, &b, &p);
                if (c == API_OK) {
                    out->status = 200;
                    out->ctype = api_format_mime(r->format);
                    out->body = api_buf_take(&b, &out->len);
                    timing_buf tb =
                        timing_start(out->timing, sizeof out->timing);
                    timing_add(&tb, "queue", t.queue_ms);
                    timing_add(&tb, "parse", t.parse_ms);
                    timing_add(&tb, "prepare", t.prepare_ms);
                    timing_add(&tb, "compute", t.compute_ms);
                    timing_add(&tb, "clip", t.clip_ms);
                    timing_add(&tb, "serialize", t.serialize_ms);
                    timing_add(&tb, "total", t.total_ms);
                }
            }
        }
        api_result_clear(&res);
    } else {
        api_compare *cmp = malloc(sizeof *cmp);
        if (cmp == NULL) {
            c = api_problem_set(&p, API_UNAVAILABLE, "out of memory");
        } else {
            api_compare_init(cmp);
            cmp->t.queue_ms = queue_ms;
            cmp->t.parse_ms = parse_ms;
            c = api_compare_run(r, cmp, &p);
            if (c == API_OK) {
                for (int a = 0; a < VOR_ALGORITHM_COUNT; a++)
                    if (cmp->status[a] == VOR_OK)
                        srv_metrics_compute(s->metrics, (vor_algorithm)a, r->n,
                                            cmp->res[a].t.compute_ms / 1e3);
                if (!job_stopped(base)) {
                    int64_t t_ser = srv_now_ns();
                    c = api_write_compare(r, cmp, &b, &p);
                    double ser_ms = ms_since(t_ser);
                    if (c == API_OK) {
                        out->status = 200;
                        out->ctype = "application/json";
                        out->body = api_buf_take(&b, &out->len);
                        timing_buf tb =
                            timing_start(out->timing, sizeof out->timing);
                        timing_add(&tb, "queue", queue_ms);
                        timing_add(&tb, "parse", parse_ms);
                        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++)
                            timing_add(&tb,
                                       vor_algorithm_name((vor_algorithm)a),
                                       cmp->res[a].t.total_ms);
                        timing_add(&tb, "serialize", ser_ms);
                        timing_add(&tb, "total", cmp->t.total_ms + ser_ms);
                    }
                }
            }
            api_compare_clear(cmp);
            free(cmp);
        }
    }
    if (c != API_OK) problem_reply(out, &p, instance);
    api_buf_clear(&b);
}

/* The 504 for a request whose deadline passed; started: it was being
 * computed (else it was still waiting in the queue). */
static void timeout_reply(reply *r, const srv_server *s, const char *instance,
                          int started) {
    problemf(r, instance, API_TIMEOUT,
             "the deadline of %g s passed before the answer was ready "
             "(the request was %s); send fewer points or ask the "
             "operator for a longer --timeout",
             s->cfg.timeout,
             started ? "being computed" : "waiting in the queue");
    r->points = -1;
}

static job_input job_input_of(const compute_job *j) {
    job_input in = {j->compare, j->kind, j->body, j->len, j->accept,
                    j->n_opts, (const char *const *)j->opt_key,
                    (const char *const *)j->opt_val};
    return in;
}

/* The worker's part: parse, compute, serialize, compress. Writes j->out. */
static void job_run(srv_job *base) {
    compute_job *j = (compute_job *)base;
    reply *out = &j->out;
    double queue_ms = (double)(base->started_ns - base->queued_ns) / 1e6;
    api_request r;
    api_problem p;
    memset(&p, 0, sizeof p);
    api_request_init(&r);
    out->points = -1;
    out->algorithm = NULL;

    job_input in = job_input_of(j);
    int64_t t_parse = srv_now_ns();
    api_code c = read_input(&r, &in, j->srv->cfg.max_points, &p);
    free(j->body);
    j->body = NULL;
    double parse_ms = ms_since(t_parse);
    if (c != API_OK)
        input_problem(out, &p, j->instance, queue_ms, parse_ms);
    else if (!srv_job_abandoned(base)) /* else nobody will read it */
        compute_answer(j->srv, &r, j->compare, queue_ms, parse_ms, base,
                       j->instance, out);
    api_request_clear(&r);
    if (!srv_job_abandoned(base) && out->body != NULL)
        maybe_gzip(out, j->gzip_ok);
}

/* Publishes the answer and resumes the connection. Exactly once per job. */
static void job_done(srv_job *base, srv_job_outcome outcome) {
    compute_job *j = (compute_job *)base;
    if (outcome == SRV_JOB_RAN) {
        j->r = j->out;
        memset(&j->out, 0, sizeof j->out);
        if (j->r.body == NULL && j->r.status == 0)
            problemf(&j->r, j->instance, API_INTERNAL,
                     "the computation produced no answer");
    } else if (outcome == SRV_JOB_EXPIRED) {
        timeout_reply(&j->r, j->srv, j->instance, base->started_ns != 0);
    } else {
        problemf(&j->r, j->instance, API_UNAVAILABLE,
                 "the service is shutting down and could not finish this "
                 "request; retry");
        j->r.retry_after = RETRY_AFTER_S;
        j->r.points = -1;
    }
    atomic_store_explicit(&j->answered, 1, memory_order_release);
    MHD_resume_connection(j->conn);
}

static void job_release(srv_job *base) { job_unref((compute_job *)base); }

/* ---- responses ----------------------------------------------------------- */

static void add_common_headers(req *q, struct MHD_Response *resp) {
    MHD_add_response_header(resp, "X-Request-Id", q->id);
    MHD_add_response_header(resp, "Access-Control-Allow-Origin", "*");
    MHD_add_response_header(resp, "Access-Control-Expose-Headers",
                            "Server-Timing, X-Request-Id, Retry-After, "
                            "Content-Encoding");
    MHD_add_response_header(resp, "Timing-Allow-Origin", "*");
    if (atomic_load(&q->srv->draining))
        MHD_add_response_header(resp, "Connection", "close");
}

/* Queues resp (destroyed here) with status; records what the log needs. */
static enum MHD_Result send_response(req *q, struct MHD_Connection *conn,
                                     unsigned status,
                                     struct MHD_Response *resp,
                                     size_t body_len) {
    if (resp == NULL) return MHD_NO; /* out of memory: drop the connection */
    add_common_headers(q, resp);
    enum MHD_Result rc = MHD_queue_response(conn, status, resp);
    MHD_destroy_response(resp);
    q->status = (int)status;
    q->bytes = q->method == SRV_M_HEAD ? 0 : body_len; /* as sent */
    q->phase = PH_DONE;
    return rc;
}

/* Sends a reply (its body is taken). */
static enum MHD_Result send_reply(req *q, struct MHD_Connection *conn,
                                  reply *r, const char *allow,
                                  const char *cache_control) {
    struct MHD_Response *resp = MHD_create_response_from_buffer(
        r->len, r->body ? r->body : (void *)"",
        r->body ? MHD_RESPMEM_MUST_FREE : MHD_RESPMEM_PERSISTENT);
    if (resp == NULL) {
        reply_clear(r);
        return MHD_NO;
    }
    size_t len = r->len;
    r->body = NULL;
    r->len = 0;
    MHD_add_response_header(resp, "Content-Type", r->ctype);
    if (r->gzipped) MHD_add_response_header(resp, "Content-Encoding", "gzip");
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
    return send_response(q, conn, (unsigned)r->status, resp, len);
}

static enum MHD_Result send_problem(req *q, struct MHD_Connection *conn,
                                    api_code code, const char *allow,
                                    int retry_after, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 6, 7)))
#endif
    ;

static enum MHD_Result send_problem(req *q, struct MHD_Connection *conn,
                                    api_code code, const char *allow,
                                    int retry_after, const char *fmt, ...) {
    api_problem p;
    reply r;
    memset(&p, 0, sizeof p);
    memset(&r, 0, sizeof r);
    p.code = code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p.detail, sizeof p.detail, fmt, ap);
    va_end(ap);
    char inst[256];
    printable(inst, sizeof inst, q->path, 200);
    problem_reply(&r, &p, inst);
    r.retry_after = retry_after;
    return send_reply(q, conn, &r, allow, NULL);
}

static enum MHD_Result send_api_problem(req *q, struct MHD_Connection *conn,
                                        const api_problem *p) {
    reply r;
    memset(&r, 0, sizeof r);
    char inst[256];
    printable(inst, sizeof inst, q->path, 200);
    problem_reply(&r, p, inst);
    return send_reply(q, conn, &r, NULL, NULL);
}

static enum MHD_Result send_text(req *q, struct MHD_Connection *conn,
                                 unsigned status, const char *ctype,
                                 char *body, size_t len, int gzip_ok) {
    reply r;
    memset(&r, 0, sizeof r);
    r.status = (int)status;
    r.ctype = ctype;
    r.body = body;
    r.len = len;
    maybe_gzip(&r, gzip_ok);
    return send_reply(q, conn, &r, NULL, NULL);
}

/* ---- handlers ------------------------------------------------------------ */

static const char *header(struct MHD_Connection *conn, const char *name) {
    return MHD_lookup_connection_value(conn, MHD_HEADER_KIND, name);
}

static int client_takes_gzip(const req *q) {
    return srv_accepts_gzip(q->h.accept_encoding);
}

/* MHD_get_connection_values callback: the first of each header in
 * req_headers, matched without regard to case as libmicrohttpd's own
 * lookup does. */
static enum MHD_Result collect_header(void *cls, enum MHD_ValueKind kind,
                                      const char *key, const char *value) {
    req_headers *h = cls;
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

static enum MHD_Result handle_asset(req *q, struct MHD_Connection *conn,
                                    const char *path) {
    srv_server *s = q->srv;
    srv_asset a;
    int rc = srv_assets_get(s->assets, path, &a);
    if (rc == -1)
        return send_problem(q, conn, API_NOT_FOUND, NULL, 0,
                            "no resource at this path");
    if (rc != 0)
        return send_problem(q, conn, API_UNAVAILABLE, NULL, RETRY_AFTER_S,
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
    } else if (client_takes_gzip(q) && a.gz != NULL) {
        len = a.gz_len;
        gz = 1;
        resp = MHD_create_response_from_buffer(len, (void *)a.gz,
                                               MHD_RESPMEM_PERSISTENT);
    } else if (client_takes_gzip(q) && a.owned != NULL &&
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
    return send_response(q, conn, status, resp, len);
}

static enum MHD_Result handle_metrics(req *q, struct MHD_Connection *conn) {
    srv_server *s = q->srv;
    srv_gauges g;
    memset(&g, 0, sizeof g);
    srv_pool_stats(s->pool, &g.queue_depth, &g.running);
    g.queue_capacity = (size_t)s->cfg.queue;
    g.workers = (size_t)s->cfg.workers;
    g.in_flight = srv_server_in_flight(s);
    g.ready = !atomic_load(&s->draining);
    api_buf b;
    api_buf_init(&b);
    srv_metrics_render(s->metrics, &g, &b);
    if (b.oom) {
        api_buf_clear(&b);
        return send_problem(q, conn, API_UNAVAILABLE, NULL, RETRY_AFTER_S,
                            "out of memory");
    }
    size_t len;
    char *text = api_buf_take(&b, &len);
    return send_text(q, conn, 200, "text/plain; version=0.0.4; charset=utf-8",
                     text, len, client_takes_gzip(q));
}

static enum MHD_Result handle_json_status(req *q, struct MHD_Connection *conn,
                                          const char *json) {
    size_t n = strlen(json);
    char *body = malloc(n + 1);
    if (body == NULL) return MHD_NO;
    memcpy(body, json, n + 1);
    return send_text(q, conn, 200, "application/json", body, n, 0);
}

static enum MHD_Result handle_options(req *q, struct MHD_Connection *conn) {
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
    return send_response(q, conn, 204, resp, 0);
}

/* What each problem type means, for GET /problems/<type> (the type URIs
 * of problem documents are relative, so they lead here). */
static const char *const problem_help[API_CODE_COUNT] = {
    [API_MALFORMED] = "The request body or a query parameter could not be "
                      "read: a syntax error, an unknown or repeated key, a "
                      "binary body whose length is not a multiple of 16, or "
                      "an unknown query parameter. The pointer (JSON) or "
                      "line (text) member says where.",
    [API_NOT_FOUND] = "Nothing is served at this path.",
    [API_METHOD] = "The path exists but not with this method; the Allow "
                   "header lists the methods it takes.",
    [API_TOO_LARGE] = "The body is larger than the service accepts "
                      "(--max-body), or it holds or asks for more points "
                      "than the service computes at once (--max-points).",
    [API_MEDIA_TYPE] = "The Content-Type is not one the service reads: "
                       "application/json, text/csv, text/plain or "
                       "application/octet-stream.",
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
                            "this build of the service.",
};

static enum MHD_Result handle_problem_type(req *q, struct MHD_Connection *conn) {
    const char *slug = q->path + strlen("/problems/");
    int code = -1;
    for (int c = 0; c < API_CODE_COUNT; c++)
        if (c != API_OK && strcmp(api_code_slug((api_code)c), slug) == 0)
            code = c;
    if (code < 0)
        return send_problem(q, conn, API_NOT_FOUND, NULL, 0,
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
    if (b.oom) {
        api_buf_clear(&b);
        return send_problem(q, conn, API_UNAVAILABLE, NULL, RETRY_AFTER_S,
                            "out of memory");
    }
    size_t len;
    char *text = api_buf_take(&b, &len);
    return send_text(q, conn, 200, "text/html; charset=utf-8", text, len, 0);
}

typedef struct opt_list {
    size_t n;
    int overflow;
    const char *key[MAX_OPTIONS], *val[MAX_OPTIONS];
} opt_list;

static enum MHD_Result collect_option(void *cls, enum MHD_ValueKind kind,
                                      const char *key, const char *value) {
    (void)kind;
    opt_list *l = cls;
    if (l->n >= MAX_OPTIONS) {
        l->overflow = 1;
        return MHD_NO;
    }
    l->key[l->n] = key ? key : "";
    l->val[l->n] = value ? value : "";
    l->n++;
    return MHD_YES;
}

static char *dup_str(const char *s) {
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d != NULL) memcpy(d, s, n);
    return d;
}

/* The inline path: a request with a small body is read here, on the
 * connection's thread, with a limit of cfg.inline_points points (a third
 * of that for /compare, which runs three algorithms, and that again
 * divided by its repeat count). If it fits, it is
 * computed and answered here too; if it holds or generates more points
 * (API_TOO_LARGE under the small limit only), it is left for the pool,
 * which reads it again with the full limit, so every answer is the one
 * the pool would give. Why: handing a job to a worker (queueing it, waking
 * the worker, suspending the connection, resuming it through the
 * inter-thread channel, three context switches) cost ~40 us of CPU per
 * request on the 2-core development machine -- half of all the work for a
 * 10-point request, more than computing it. Why 128 points: computing and
 * writing that many takes ~0.2 ms there, about as long as the other
 * connections of this thread should wait; larger requests gain little from
 * skipping the hand-off. Inline requests skip the queue (no 503, queue_ms
 * 0, not counted in voronoid_workers_busy); the deadline still holds: an
 * answer ready after it is replaced by the 504 the pool would have sent.
 * Returns 1 when the request was answered (*rc set), 0 when it is the
 * pool's. */
static int run_inline(req *q, struct MHD_Connection *conn,
                      const job_input *in, const char *instance,
                      int gzip_ok, int64_t deadline_ns, enum MHD_Result *rc) {
    srv_server *s = q->srv;
    size_t lim = s->cfg.inline_points /
                 (in->compare ? (size_t)VOR_ALGORITHM_COUNT : 1);
    if (lim == 0 || in->len > SRV_INLINE_MAX_BODY ||
        atomic_load_explicit(&s->closing, memory_order_acquire))
        return 0;
    if (lim > s->cfg.max_points) lim = s->cfg.max_points;

    api_request r;
    api_problem p;
    reply out;
    memset(&p, 0, sizeof p);
    memset(&out, 0, sizeof out);
    api_request_init(&r);
    out.points = -1;
    int64_t t_parse = srv_now_ns();
    api_code c = read_input(&r, in, lim, &p);
    double parse_ms = ms_since(t_parse);
    if (c == API_TOO_LARGE && lim < s->cfg.max_points) {
        api_request_clear(&r);
        return 0; /* too many points to compute here: the pool's job */
    }
    /* A comparison runs every algorithm repeat times: the budget is for
     * all of its runs. */
    if (c == API_OK && in->compare &&
        r.n * (size_t)api_compare_repeat(&r, r.n) > lim) {
        api_request_clear(&r);
        return 0;
    }
    if (c != API_OK)
        input_problem(&out, &p, instance, 0, parse_ms);
    else
        compute_answer(s, &r, in->compare, 0, parse_ms, NULL, instance, &out);
    api_request_clear(&r);
    if (srv_now_ns() > deadline_ns) {
        reply_clear(&out);
        memset(&out, 0, sizeof out);
        timeout_reply(&out, s, instance, 1);
    } else if (out.body != NULL) {
        maybe_gzip(&out, gzip_ok);
    }
    q->algorithm = out.algorithm;
    q->points = out.points;
    *rc = send_reply(q, conn, &out, NULL, NULL);
    return 1;
}

static enum MHD_Result start_compute(req *q, struct MHD_Connection *conn) {
    srv_server *s = q->srv;
    int64_t deadline_ns = srv_now_ns() + (int64_t)(s->cfg.timeout * 1e9);
    opt_list opts;
    api_problem p;
    memset(&opts, 0, sizeof opts);
    memset(&p, 0, sizeof p);

    /* Refuse bad options and Accept now, while it is cheap. */
    MHD_get_connection_values(conn, MHD_GET_ARGUMENT_KIND, collect_option,
                              &opts);
    if (opts.overflow)
        return send_problem(q, conn, API_MALFORMED, NULL, 0,
                            "more than %d query parameters", MAX_OPTIONS);
    const char *accept = q->h.accept;
    api_request scratch;
    api_request_init(&scratch);
    api_code c = api_format_from_accept(&scratch, accept, &p);
    for (size_t i = 0; c == API_OK && i < opts.n; i++)
        c = api_request_option(&scratch, opts.key[i], opts.val[i], &p);
    api_request_clear(&scratch);
    if (c != API_OK) return send_api_problem(q, conn, &p);

    int compare = q->route == SRV_ROUTE_COMPARE;
    const char *instance = compare ? "/compare" : "/voronoi";
    int gzip_ok = client_takes_gzip(q);
    job_input in = {compare, q->kind, q->body, q->len, accept,
                    opts.n, opts.key, opts.val};
    enum MHD_Result rc;
    if (run_inline(q, conn, &in, instance, gzip_ok, deadline_ns, &rc))
        return rc;

    compute_job *j = calloc(1, sizeof *j);
    if (j == NULL)
        return send_problem(q, conn, API_UNAVAILABLE, NULL, RETRY_AFTER_S,
                            "out of memory");
    atomic_init(&j->refs, 2);
    atomic_init(&j->answered, 0);
    j->srv = s;
    j->conn = conn;
    j->compare = compare;
    snprintf(j->instance, sizeof j->instance, "%s", instance);
    j->kind = q->kind;
    j->body = q->body;
    j->len = q->len;
    q->body = NULL;
    q->len = q->cap = 0;
    j->gzip_ok = gzip_ok;
    int oom = 0;
    if (accept != NULL && (j->accept = dup_str(accept)) == NULL) oom = 1;
    for (size_t i = 0; i < opts.n && !oom; i++) {
        j->opt_key[i] = dup_str(opts.key[i]);
        j->opt_val[i] = dup_str(opts.val[i]);
        j->n_opts = i + 1;
        if (j->opt_key[i] == NULL || j->opt_val[i] == NULL) oom = 1;
    }
    if (oom) {
        atomic_store(&j->refs, 1);
        job_unref(j);
        return send_problem(q, conn, API_UNAVAILABLE, NULL, RETRY_AFTER_S,
                            "out of memory");
    }
    j->base.run = job_run;
    j->base.done = job_done;
    j->base.release = job_release;
    j->base.deadline_ns = deadline_ns;

    q->job = j;
    q->phase = PH_WAIT;
    MHD_suspend_connection(conn);
    int st = srv_pool_submit(s->pool, &j->base);
    if (st != SRV_POOL_OK) {
        /* Not accepted: no callback will come; answer here. */
        if (st == SRV_POOL_FULL)
            problemf(&j->r, j->instance, API_UNAVAILABLE,
                     "all %d workers are busy and %d requests are waiting; "
                     "retry after %d s",
                     s->cfg.workers, s->cfg.queue, RETRY_AFTER_S);
        else
            problemf(&j->r, j->instance, API_UNAVAILABLE,
                     "the service is shutting down; retry");
        j->r.retry_after = RETRY_AFTER_S;
        j->r.points = -1;
        atomic_fetch_sub(&j->refs, 1); /* the pool's reference */
        atomic_store_explicit(&j->answered, 1, memory_order_release);
        MHD_resume_connection(conn);
    }
    return MHD_YES;
}

static enum MHD_Result finish_compute(req *q, struct MHD_Connection *conn) {
    compute_job *j = q->job;
    if (!atomic_load_explicit(&j->answered, memory_order_acquire))
        return MHD_YES; /* not yet; called again after resume */
    q->algorithm = j->r.algorithm;
    q->points = j->r.points;
    return send_reply(q, conn, &j->r, NULL, NULL);
}

static int has_asset(const char *path, void *ctx) {
    return srv_assets_has(ctx, path);
}

static void make_request_id(req *q) {
    const char *given = q->h.request_id;
    if (given != NULL) {
        size_t n = strlen(given);
        int ok = n > 0 && n < 72;
        for (size_t i = 0; ok && i < n; i++) {
            char c = given[i];
            ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                 (c >= '0' && c <= '9') || c == '-' || c == '_' ||
                 c == '.' || c == ':';
        }
        if (ok) {
            memcpy(q->id, given, n + 1);
            return;
        }
    }
    /* splitmix64 of a per-process seed plus a counter: unique, unguessable
     * enough for correlation, cheap. */
    uint64_t z = q->srv->id_seed +
                 atomic_fetch_add(&q->srv->next_id, 1) * 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    q->id[srv_fmt_hex64(q->id, z)] = '\0';
}

/* Body announced? (Content-Length > 0 or a transfer coding.) */
static int body_announced(const req *q) {
    return (q->has_cl && q->content_length > 0) ||
           q->h.transfer_encoding != NULL;
}

/* First call: headers are in, no body yet. */
static enum MHD_Result on_headers(req *q, struct MHD_Connection *conn) {
    srv_server *s = q->srv;
    const char *cl = q->h.content_length;
    if (cl != NULL) {
        char *end;
        unsigned long long v = strtoull(cl, &end, 10);
        q->has_cl = end != cl && *end == '\0';
        q->content_length = q->has_cl ? v : 0;
    }
    if (q->match == SRV_MATCH_NOT_FOUND && body_announced(q))
        return send_problem(q, conn, API_NOT_FOUND, NULL, 0,
                            "no resource at this path");
    if (q->match == SRV_MATCH_METHOD && body_announced(q))
        return send_problem(q, conn, API_METHOD, q->allow, 0,
                            "%s is not allowed here; allowed: %s",
                            q->method_name, q->allow);
    if (q->has_cl && q->content_length > s->cfg.max_body)
        return send_problem(q, conn, API_TOO_LARGE, NULL, 0,
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
            return send_api_problem(q, conn, &p);
        q->collect = 1;
    }
    return MHD_YES;
}

static enum MHD_Result on_data(req *q, const char *data, size_t n) {
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

/* Last call: the whole request is in. */
static enum MHD_Result on_complete(req *q, struct MHD_Connection *conn) {
    srv_server *s = q->srv;
    if (q->too_large)
        return send_problem(q, conn, API_TOO_LARGE, NULL, 0,
                            "the body is larger than the limit of %zu bytes "
                            "(--max-body)",
                            s->cfg.max_body);
    if (q->match == SRV_MATCH_NOT_FOUND)
        return send_problem(q, conn, API_NOT_FOUND, NULL, 0,
                            "no resource at this path");
    if (q->match == SRV_MATCH_METHOD)
        return send_problem(q, conn, API_METHOD, q->allow, 0,
                            "%s is not allowed here; allowed: %s",
                            q->method_name, q->allow);
    if (q->method == SRV_M_OPTIONS) return handle_options(q, conn);

    switch (q->route) {
    case SRV_ROUTE_VORONOI:
    case SRV_ROUTE_COMPARE:
        return start_compute(q, conn);
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
            return send_problem(q, conn, API_UNAVAILABLE, NULL, RETRY_AFTER_S,
                                "shutting down: not taking new work");
        return handle_json_status(q, conn, "{\"status\":\"ready\"}\n");
    case SRV_ROUTE_METRICS:
        return handle_metrics(q, conn);
    case SRV_ROUTE_PROBLEM:
        return handle_problem_type(q, conn);
    case SRV_ROUTE_OTHER:
    case SRV_ROUTE_COUNT:
        break;
    }
    return send_problem(q, conn, API_NOT_FOUND, NULL, 0,
                        "no resource at this path");
}

/* url into dst (size > 0), cut to fit and terminated as snprintf would,
 * without its cost on every request. NULL gives "". */
static void copy_path(char *dst, size_t size, const char *url) {
    size_t n = url != NULL ? strnlen(url, size - 1) : 0;
    if (n > 0) memcpy(dst, url, n);
    dst[n] = '\0';
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *conn,
                                  const char *url, const char *method,
                                  const char *version,
                                  const char *upload_data,
                                  size_t *upload_data_size, void **con_cls) {
    srv_server *s = cls;
    req *q = *con_cls;
    (void)version;

    if (q == NULL) {
        q = calloc(1, sizeof *q);
        if (q == NULL) return MHD_NO;
        *con_cls = q;
        q->srv = s;
        q->t0_ns = srv_now_ns();
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        q->unix_t0 = (double)ts.tv_sec + (double)ts.tv_nsec / 1e9;
        q->points = -1;
        printable(q->method_name, sizeof q->method_name, method, 8);
        copy_path(q->path, sizeof q->path, url);
        q->method = srv_method_bit(method);
        MHD_get_connection_values(conn, MHD_HEADER_KIND, collect_header,
                                  &q->h);
        make_request_id(q);
        atomic_fetch_add(&s->in_flight, 1);
        q->match = srv_route_match(method, q->path, has_asset, s->assets,
                                   &q->route, q->allow, sizeof q->allow);
        return on_headers(q, conn);
    }
    if (*upload_data_size > 0) {
        size_t n = *upload_data_size;
        *upload_data_size = 0;
        return on_data(q, upload_data, n);
    }
    if (q->phase == PH_WAIT) return finish_compute(q, conn);
    if (q->phase == PH_DONE) return MHD_YES;
    return on_complete(q, conn);
}

static const char *termination_note(enum MHD_RequestTerminationCode toe) {
    switch (toe) {
    case MHD_REQUEST_TERMINATED_COMPLETED_OK: return NULL;
    case MHD_REQUEST_TERMINATED_WITH_ERROR: return "error";
    case MHD_REQUEST_TERMINATED_TIMEOUT_REACHED: return "connection-timeout";
    case MHD_REQUEST_TERMINATED_DAEMON_SHUTDOWN: return "shutdown";
    case MHD_REQUEST_TERMINATED_READ_ERROR: return "read-error";
    case MHD_REQUEST_TERMINATED_CLIENT_ABORT: return "client-gone";
    }
    return "unknown";
}

static void on_completed(void *cls, struct MHD_Connection *conn,
                         void **con_cls,
                         enum MHD_RequestTerminationCode toe) {
    srv_server *s = cls;
    req *q = *con_cls;
    (void)conn;
    if (q == NULL) return;
    *con_cls = NULL;
    double ms = ms_since(q->t0_ns);
    if (q->status > 0)
        srv_metrics_request(s->metrics, q->route, q->status, ms / 1e3);
    else
        srv_metrics_aborted(s->metrics, q->route);
    srv_access e = {
        .unix_time = q->unix_t0,
        .method = q->method_name,
        .path = q->path,
        .status = q->status,
        .bytes = q->bytes,
        .ms = ms,
        .algorithm = q->algorithm,
        .points = q->points,
        .request_id = q->id,
        .note = termination_note(toe),
    };
    srv_log_access(s->log, &e);
    if (q->job != NULL) job_unref(q->job);
    free(q->body);
    free(q);
    atomic_fetch_sub(&s->in_flight, 1);
}

static void mhd_log(void *cls, const char *fmt, va_list ap) {
    srv_server *s = cls;
    char msg[512];
    int n = vsnprintf(msg, sizeof msg, fmt, ap);
    if (n < 0) return;
    char line[600];
    /* libmicrohttpd's messages end with a newline already. */
    int k = snprintf(line, sizeof line, "voronoid: http: %s", msg);
    if (k > 0) {
        size_t len = (size_t)k < sizeof line ? (size_t)k : sizeof line - 1;
        if (len > 0 && line[len - 1] != '\n' && len + 1 < sizeof line)
            line[len++] = '\n';
        srv_log_text(s->log, line, len);
    }
}

/* ---- life cycle ---------------------------------------------------------- */

srv_server *srv_server_new(const srv_config *cfg, int log_fd, char *err,
                           size_t err_size) {
    srv_server *s = calloc(1, sizeof *s);
    if (s == NULL) {
        snprintf(err, err_size, "out of memory");
        return NULL;
    }
    s->cfg = *cfg;
    s->quiesced_fd = MHD_INVALID_SOCKET;
    atomic_init(&s->draining, 0);
    atomic_init(&s->closing, 0);
    atomic_init(&s->in_flight, 0);
    atomic_init(&s->next_id, 1);
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    s->id_seed = ((uint64_t)ts.tv_sec << 32) ^ (uint64_t)ts.tv_nsec ^
                 ((uint64_t)getpid() << 16);

    s->log = srv_log_new(log_fd, SRV_LOG_DELAY_MS);
    s->metrics = srv_metrics_new();
    s->assets = srv_assets_new(cfg->web_dir);
    s->pool = srv_pool_new(cfg->workers, cfg->queue);
    if (s->log == NULL || s->metrics == NULL || s->assets == NULL ||
        s->pool == NULL) {
        snprintf(err, err_size, "cannot allocate the service's state or "
                 "start its %d worker threads", cfg->workers);
        goto fail;
    }

    struct sockaddr_storage addr;
    memset(&addr, 0, sizeof addr);
    unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_POLL |
                     MHD_ALLOW_SUSPEND_RESUME | MHD_USE_ITC |
                     MHD_USE_ERROR_LOG;
    struct sockaddr_in *a4 = (struct sockaddr_in *)&addr;
    struct sockaddr_in6 *a6 = (struct sockaddr_in6 *)&addr;
    if (inet_pton(AF_INET, cfg->bind, &a4->sin_addr) == 1) {
        a4->sin_family = AF_INET;
        a4->sin_port = htons((uint16_t)cfg->port);
    } else if (inet_pton(AF_INET6, cfg->bind, &a6->sin6_addr) == 1) {
        a6->sin6_family = AF_INET6;
        a6->sin6_port = htons((uint16_t)cfg->port);
        /* "::" means every address, IPv4 ones included. */
        flags |= IN6_IS_ADDR_UNSPECIFIED(&a6->sin6_addr) ? MHD_USE_DUAL_STACK
                                                         : MHD_USE_IPv6;
    } else {
        snprintf(err, err_size, "cannot use bind address '%s'", cfg->bind);
        goto fail;
    }

    s->daemon = MHD_start_daemon(
        flags, (uint16_t)cfg->port, NULL, NULL, on_request, s,
        MHD_OPTION_EXTERNAL_LOGGER, mhd_log, s,
        MHD_OPTION_SOCK_ADDR, (struct sockaddr *)&addr,
        MHD_OPTION_THREAD_POOL_SIZE, (unsigned)cfg->http_threads,
        MHD_OPTION_CONNECTION_TIMEOUT, cfg->connection_timeout,
        MHD_OPTION_CONNECTION_LIMIT, cfg->max_connections,
        MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)SRV_CONNECTION_MEMORY,
        MHD_OPTION_NOTIFY_COMPLETED, on_completed, s,
        MHD_OPTION_END);
    if (s->daemon == NULL) {
        snprintf(err, err_size, "cannot listen on %s port %d (address in "
                 "use, or not an address of this machine?)", cfg->bind,
                 cfg->port);
        goto fail;
    }
    const union MHD_DaemonInfo *info =
        MHD_get_daemon_info(s->daemon, MHD_DAEMON_INFO_BIND_PORT);
    s->port = info != NULL ? (int)info->port : cfg->port;
    return s;

fail:
    srv_pool_free(s->pool, 0);
    srv_assets_free(s->assets);
    srv_metrics_free(s->metrics);
    srv_log_free(s->log);
    free(s);
    return NULL;
}

int srv_server_port(const srv_server *s) { return s->port; }

void srv_server_flush_log(srv_server *s) { srv_log_flush(s->log); }

/* Draining stops new connections at the kernel: libmicrohttpd stops
 * accepting, and the listening socket is shut down (not closed: its threads
 * may still look at the descriptor until MHD_stop_daemon), so connections
 * that would wait in its backlog are refused and a load balancer sends them
 * to another daemon at once. Connections already open are served. The
 * daemon does not set SO_REUSEPORT, so no second daemon can share its port
 * and take a share of the connections unnoticed. */
void srv_server_drain(srv_server *s) {
    if (atomic_exchange(&s->draining, 1)) return;
    s->quiesced_fd = MHD_quiesce_daemon(s->daemon);
    if (s->quiesced_fd != MHD_INVALID_SOCKET)
        shutdown(s->quiesced_fd, SHUT_RDWR);
}

size_t srv_server_in_flight(const srv_server *s) {
    long n = atomic_load(&((srv_server *)s)->in_flight);
    return n > 0 ? (size_t)n : 0;
}

int srv_server_wait_idle(const srv_server *s, double seconds) {
    int64_t until = srv_now_ns() + (int64_t)(seconds * 1e9);
    for (;;) {
        if (srv_server_in_flight(s) == 0) return 0;
        if (srv_now_ns() >= until) return -1;
        struct timespec nap = {0, 5 * 1000 * 1000};
        nanosleep(&nap, NULL);
    }
}

void srv_server_cancel(srv_server *s) { srv_pool_cancel_all(s->pool); }

int srv_server_free(srv_server *s) {
    if (s == NULL) return 0;
    /* libmicrohttpd must not be stopped with a connection suspended. A
     * request that reaches start_compute from now on is refused by the
     * closed pool and resumes itself at once; every job accepted before is
     * answered (and its connection resumed) by cancel_all. The inline path
     * sends such requests to the closed pool too. */
    atomic_store_explicit(&s->closing, 1, memory_order_release);
    srv_pool_close(s->pool);
    srv_pool_cancel_all(s->pool);
    MHD_stop_daemon(s->daemon);
    if (s->quiesced_fd != MHD_INVALID_SOCKET) close(s->quiesced_fd);
    /* Every request has had its on_completed now: its line is in. */
    srv_log_flush(s->log);
    if (srv_pool_free(s->pool, 0.5) != 0) return -1;
    srv_assets_free(s->assets);
    srv_metrics_free(s->metrics);
    srv_log_free(s->log);
    free(s);
    return 0;
}
