/* work.c -- the compute routes, POST /voronoi and POST /compare: their
 * options, the inline path for tiny requests, and jobs for the pool.
 *
 * A request whose whole body is in (srv__start_compute) first has its
 * query options and Accept header checked, cheaply, on the connection's
 * thread. Then:
 *   - at most --inline-points points (a third for /compare) and a small
 *     body: read, computed and answered at once, on this thread
 *     (run_inline);
 *   - else a srv_compute_job: the connection is suspended and the job
 *     queued in the srv_pool. Queue full -> 503 + Retry-After. The worker
 *     parses, computes, serializes and compresses (job_run); the pool's
 *     done() callback publishes the answer and resumes the connection, and
 *     srv__finish_compute sends it.
 *
 * A job is shared by the connection and the pool (reference count 2). Its
 * answer is written exactly once, by the pool's done() callback (on the
 * worker when run() finished in time, on the timer thread at the
 * deadline, or by srv_server_cancel), and only then is the connection
 * resumed; run()'s own output lives in separate fields, so a late run()
 * never races the answer. A run() whose answer was given up on stops: the
 * algorithms ask job_stop every VOR_STOP_EVERY sites or events, which
 * also says stop once the client has closed its connection (job_stop
 * looks at the suspended connection's socket). The job is freed when
 * both references are gone.
 *
 * Cost: parsing, computing, serializing and gzip happen on the workers,
 * except for inline requests (bounded by --inline-points and
 * SRV_INLINE_MAX_BODY: well under a millisecond). Memory per request: the
 * body, then the codec's result and the answer (the body is freed once
 * parsed).
 */
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

#include "budget.h"
#include "fmt.h"
#include "internal.h"
#include "stream.h"
#include "server.h"

/* Bodies up to this size may be computed inline (see run_inline): it
 * bounds what reading one costs the connection's thread, ~20 us. */
#define SRV_INLINE_MAX_BODY 16384

struct srv_compute_job {
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
    char *opt_key[SRV_MAX_OPTIONS], *opt_val[SRV_MAX_OPTIONS];
    int gzip_ok;
    char instance[16];
    srv_reply out;        /* run()'s result, private to run() and done(RAN) */
    srv_reply r;          /* the answer, written once by done() */
    atomic_int answered;
    int stopped;          /* run(): the core was told to stop (job_stop) */
    atomic_int gone;      /* job_stop found the client gone */
    /* The client's socket, -1 if unknown or once the answer is published:
     * then libmicrohttpd may close it and the number be reused, so job_stop
     * looks at it and job_done clears it under fd_lock. */
    int fd;
    pthread_mutex_t fd_lock;
    int64_t peeked_ns;    /* job_stop: when it last looked at fd */
};


void srv__job_unref(srv_compute_job *j) {
    if (atomic_fetch_sub_explicit(&j->refs, 1, memory_order_acq_rel) != 1)
        return;
    pthread_mutex_destroy(&j->fd_lock);
    free(j->body);
    free(j->accept);
    for (size_t i = 0; i < j->n_opts; i++) {
        free(j->opt_key[i]);
        free(j->opt_val[i]);
    }
    srv__reply_clear(&j->out);
    srv__reply_clear(&j->r);
    free(j);
}


int srv__job_client_gone(srv_compute_job *j) {
    return atomic_load_explicit(&j->gone, memory_order_relaxed);
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

/* out's Server-Timing for the phases done before the answer is written:
 * queue, parse, prepare, compute, clip; returns the buffer for more. */
static timing_buf timing_phases(srv_reply *out, const api_timings *t) {
    timing_buf tb = timing_start(out->timing, sizeof out->timing);
    timing_add(&tb, "queue", t->queue_ms);
    timing_add(&tb, "parse", t->parse_ms);
    timing_add(&tb, "prepare", t->prepare_ms);
    timing_add(&tb, "compute", t->compute_ms);
    timing_add(&tb, "clip", t->clip_ms);
    return tb;
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

/* How often job_stop looks whether the client is still there. */
#define SRV_PEEK_NS 50000000

/* 1 if the client has closed its side of the connection (or it broke):
 * a read of the suspended connection's socket that would not block finds
 * its end. A client may send a second request meanwhile (pipelining):
 * data is not the end, and MSG_PEEK leaves it for libmicrohttpd. A client
 * that half-closes after its request counts as gone, as reverse proxies
 * count it. */
static int client_gone(int fd) {
    char c;
    ssize_t k = recv(fd, &c, 1, MSG_PEEK | MSG_DONTWAIT);
    return k == 0 || (k < 0 && errno != EAGAIN && errno != EWOULDBLOCK &&
                      errno != EINTR);
}

/* The core's question (api_request.stop): nobody waits for the answer any
 * more (deadline, shutdown, or the client hung up), so the worker stops
 * computing it and is free for the next request. The socket is looked at
 * every SRV_PEEK_NS at most (the question comes every VOR_STOP_EVERY
 * sites, a few times a millisecond). */
static int job_stop(void *ctx) {
    srv_compute_job *j = ctx;
    if (!srv_job_abandoned(&j->base)) {
        int64_t now = srv_now_ns();
        if (now - j->peeked_ns < SRV_PEEK_NS) return 0;
        j->peeked_ns = now;
        pthread_mutex_lock(&j->fd_lock);
        int gone = j->fd >= 0 && client_gone(j->fd);
        pthread_mutex_unlock(&j->fd_lock);
        if (!gone) return 0;
        atomic_store_explicit(&j->gone, 1, memory_order_relaxed);
    }
    j->stopped = 1;
    return 1;
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
static void input_problem(srv_reply *out, const api_problem *p,
                          const char *instance, double queue_ms,
                          double parse_ms) {
    srv__problem_reply(out, p, instance);
    timing_buf tb = timing_start(out->timing, sizeof out->timing);
    timing_add(&tb, "queue", queue_ms);
    timing_add(&tb, "parse", parse_ms);
}

/* ---- the answer budget ------------------------------------------------------
 * What a request holds at its peak, by point, measured on 10^6 uniform
 * points (bench/ and `make soak` print the figures): computing takes
 * about 215 bytes a point, result included (sites 24, diagram about 150),
 * clipping about 200 more; three algorithms for /compare about 520; the
 * JSON answer about 320 bytes a point with the default parts. The
 * estimates below round these up, and cover the worst inputs measured
 * (bench_algo's peak_bpp over about seventy kinds of point set): Fortune's
 * sweep keeps two arcs for every site of a set in convex position, and
 * an event for most, and three arcs for two sites on two lines: up to
 * 313 bytes a point in the core at 10^6 points (two lines; 235 for a
 * parabola, 226 for a circle, 289 for 10^4 points on a circle). On the
 * whole, VmHWM of `voronoi --algorithm fortune --format timings` less
 * that of 10 points, the most was 353 bytes a point (two lines, 10^6)
 * and 319 (a polygon, 10^4), where flip stays under 220. A comparison
 * that runs each algorithm more than once runs Fortune again with the
 * other two diagrams held: with two runs each, `voronoi --compare
 * --repeat 2` on 10^6 points held 666 bytes a point for two lines, 640
 * for uniform points and 607 for a circle; with one run, 380 for two
 * lines. */
#define BPP_COMPUTE 260
#define BPP_FORTUNE 450
#define BPP_CLIP 260
#define BPP_COMPARE 600
#define BPP_COMPARE_REPEAT 900

static int needs_clip(const api_request *r) {
    return r->format == API_FMT_GEOJSON || r->format == API_FMT_SVG ||
           (r->parts & API_PART_CLIPPED) ||
           (r->has_bounds && !r->parts_given);
}

/* Bytes a point of the answer takes, about. */
static size_t answer_bpp(const api_request *r) {
    int clip = needs_clip(r);
    switch (r->format) {
    case API_FMT_TIMINGS: return 0;
    case API_FMT_GEOJSON: return 320;
    case API_FMT_SVG: return 180;
    case API_FMT_BINARY: return 140 + (clip ? 230 : 0);
    case API_FMT_JSON: break;
    }
    size_t b = 340;
    if (r->parts & API_PART_SITES) b += 50;
    if (r->parts & API_PART_TRIANGLES) b += 50;
    if (clip) b += 420;
    return b;
}

/* Whether the answer is large enough to be streamed (stream.h). */
static int streams(const api_request *r, int compare) {
    return !compare && answer_bpp(r) * r->n > SRV_STREAM_MIN_ANSWER;
}

/* What the request will hold at its peak, computing and answering. */
static size_t estimate(const api_request *r, int compare, int stream) {
    size_t n = r->n, per;
    if (compare)
        per = api_compare_repeat(r, r->n) > 1 ? BPP_COMPARE_REPEAT
                                               : BPP_COMPARE;
    else
        per = (r->algorithm == VOR_FORTUNE ? BPP_FORTUNE : BPP_COMPUTE) +
              (needs_clip(r) ? BPP_CLIP : 0);
    size_t answer = stream ? SRV_STREAM_OVERHEAD
                           : n * answer_bpp(r) + n * answer_bpp(r) / 4;
    return (256u << 10) + n * per + answer;
}

/* Stage 2: computes the diagram (or the comparison) of a parsed request
 * and writes the answer into out: 200 with the document and its
 * Server-Timing, or a problem. base is the pool's job, polled so that work
 * nobody will read stops early; NULL when the request runs inline. With
 * may_stream, a large answer becomes a stream (out->stream) that takes r
 * and the result, owning *stream_held bytes of the budget. */
static void compute_answer(srv_server *s, api_request *r, int compare,
                           double queue_ms, double parse_ms, srv_job *base,
                           const char *instance, srv_reply *out,
                           int may_stream, int gzip_ok,
                           size_t *stream_held) {
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
            if (!job_stopped(base) && may_stream && streams(r, 0)) {
                api_timings t = res.t;
                t.queue_ms = queue_ms;
                t.parse_ms = parse_ms;
                t.total_ms += queue_ms + parse_ms;
                size_t held = srv_result_bytes(&res) + SRV_STREAM_OVERHEAD;
                api_format fmt = r->format;
                srv_stream *st = srv_stream_new(
                    s->streams, s->budget, r, &res, &t,
                    gzip_ok && fmt != API_FMT_BINARY, held);
                if (st == NULL) {
                    c = api_problem_set(&p, API_UNAVAILABLE, "out of memory");
                } else {
                    *stream_held = held;
                    out->stream = st;
                    out->status = 200;
                    out->ctype = api_format_mime(fmt);
                    timing_phases(out, &t);
                }
            } else if (!job_stopped(base)) {
                api_timings t = res.t;
                t.queue_ms = queue_ms;
                t.parse_ms = parse_ms;
                t.total_ms += queue_ms + parse_ms;
                c = api_write_result(r, &res, &t, &b, &p);
                if (c == API_OK) {
                    out->status = 200;
                    out->ctype = api_format_mime(r->format);
                    out->body = api_buf_take(&b, &out->len);
                    timing_buf tb = timing_phases(out, &t);
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
    if (c != API_OK) srv__problem_reply(out, &p, instance);
    api_buf_clear(&b);
}

/* The 504 for a request whose deadline passed; started: it was being
 * computed (else it was still waiting in the queue). */
static void timeout_reply(srv_reply *r, const srv_server *s,
                          const char *instance,
                          int started) {
    srv__problemf(r, instance, API_TIMEOUT,
                  "the deadline of %g s passed before the answer was ready "
                  "(the request was %s); send fewer points or ask the "
                  "operator for a longer --timeout",
                  s->cfg.timeout,
                  started ? "being computed" : "waiting in the queue");
    r->points = -1;
}

static job_input job_input_of(const srv_compute_job *j) {
    job_input in = {j->compare, j->kind, j->body, j->len, j->accept,
                    j->n_opts, (const char *const *)j->opt_key,
                    (const char *const *)j->opt_val};
    return in;
}

/* The worker's part: parse, compute, serialize, compress. Writes j->out. */
static void job_run(srv_job *base) {
    srv_compute_job *j = (srv_compute_job *)base;
    srv_reply *out = &j->out;
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
    srv_server *s = j->srv;
    if (c != API_OK) {
        input_problem(out, &p, j->instance, queue_ms, parse_ms);
    } else if (!srv_job_abandoned(base)) { /* else nobody will read it */
        /* What it will hold at its peak must fit the budget first. */
        int stream = streams(&r, j->compare);
        size_t est = estimate(&r, j->compare, stream);
        if (srv_budget_take(s->budget, est) != 0) {
            size_t mib = 1u << 20;
            srv__problemf(out, j->instance, API_UNAVAILABLE,
                          "the service holds %zu MiB for requests in flight "
                          "and this one needs about %zu MiB more, past its "
                          "budget of %zu MiB (--answer-memory); retry after "
                          "%d s", srv_budget_used(s->budget) / mib,
                          est / mib + 1, srv_budget_capacity(s->budget) / mib,
                          SRV_RETRY_AFTER_S);
            out->retry_after = SRV_RETRY_AFTER_S;
            out->points = (long long)r.n;
        } else {
            size_t stream_held = 0;
            r.stop = job_stop;
            r.stop_ctx = j;
            compute_answer(s, &r, j->compare, queue_ms, parse_ms, base,
                           j->instance, out, 1, j->gzip_ok, &stream_held);
            if (j->stopped) srv_metrics_stopped(s->metrics);
            if (!srv_job_abandoned(base) && out->body != NULL)
                srv__maybe_gzip(out, j->gzip_ok);
            /* Keep what the answer holds (the body until libmicrohttpd
             * has sent it, or the stream's share), give back the rest. */
            size_t keep = out->stream != NULL ? stream_held
                          : out->body != NULL && out->len > (64u << 10)
                              ? out->len : 0;
            if (keep > est) srv_budget_force(s->budget, keep - est);
            else srv_budget_give(s->budget, est - keep);
            if (out->stream == NULL && keep > 0) {
                out->held = keep;
                out->budget = s->budget;
            }
        }
    }
    api_request_clear(&r);
}

/* Publishes the answer and resumes the connection. Exactly once per job. */
static void job_done(srv_job *base, srv_job_outcome outcome) {
    srv_compute_job *j = (srv_compute_job *)base;
    if (outcome == SRV_JOB_RAN) {
        j->r = j->out;
        memset(&j->out, 0, sizeof j->out);
        if (j->r.body == NULL && j->r.status == 0)
            srv__problemf(&j->r, j->instance, API_INTERNAL,
                          "the computation produced no answer");
    } else if (outcome == SRV_JOB_EXPIRED) {
        timeout_reply(&j->r, j->srv, j->instance, base->started_ns != 0);
    } else {
        srv__problemf(&j->r, j->instance, API_UNAVAILABLE,
                      "the service is shutting down and could not finish this "
                      "request; retry");
        j->r.retry_after = SRV_RETRY_AFTER_S;
        j->r.points = -1;
    }
    atomic_store_explicit(&j->answered, 1, memory_order_release);
    pthread_mutex_lock(&j->fd_lock);
    j->fd = -1; /* job_stop may be looking at it (a late run()) */
    pthread_mutex_unlock(&j->fd_lock);
    MHD_resume_connection(j->conn);
}

static void job_release(srv_job *base) {
    srv__job_unref((srv_compute_job *)base);
}


typedef struct opt_list {
    size_t n;
    int overflow;
    const char *key[SRV_MAX_OPTIONS], *val[SRV_MAX_OPTIONS];
} opt_list;

static enum MHD_Result collect_option(void *cls, enum MHD_ValueKind kind,
                                      const char *key, const char *value) {
    (void)kind;
    opt_list *l = cls;
    if (l->n >= SRV_MAX_OPTIONS) {
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
static int run_inline(srv_req *q, struct MHD_Connection *conn,
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
    srv_reply out;
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
        compute_answer(s, &r, in->compare, 0, parse_ms, NULL, instance, &out,
                       0, 0, NULL);
    api_request_clear(&r);
    if (srv_now_ns() > deadline_ns) {
        srv__reply_clear(&out);
        memset(&out, 0, sizeof out);
        timeout_reply(&out, s, instance, 1);
    } else if (out.body != NULL) {
        srv__maybe_gzip(&out, gzip_ok);
    }
    q->algorithm = out.algorithm;
    q->points = out.points;
    *rc = srv__send_reply(q, conn, &out, NULL, NULL);
    return 1;
}

enum MHD_Result srv__start_compute(srv_req *q, struct MHD_Connection *conn) {
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
        return srv__send_problem(q, conn, API_MALFORMED, NULL, 0,
                                 "more than %d query parameters",
                                 SRV_MAX_OPTIONS);
    /* a parameter given twice is refused, as a key repeated in the body
     * is (the body's parser refuses duplicates) */
    for (size_t i = 1; i < opts.n; i++)
        for (size_t k = 0; k < i; k++)
            if (strcmp(opts.key[i], opts.key[k]) == 0) {
                char name[72];
                srv__printable(name, sizeof name, opts.key[i], 64);
                return srv__send_problem(q, conn, API_MALFORMED, NULL, 0,
                                         "query parameter \"%s\" given "
                                         "twice", name);
            }
    const char *accept = q->h.accept;
    api_request scratch;
    api_request_init(&scratch);
    api_code c = api_format_from_accept(&scratch, accept, &p);
    for (size_t i = 0; c == API_OK && i < opts.n; i++)
        c = api_request_option(&scratch, opts.key[i], opts.val[i], &p);
    api_request_clear(&scratch);
    if (c != API_OK) return srv__send_api_problem(q, conn, &p);

    int compare = q->route == SRV_ROUTE_COMPARE;
    const char *instance = compare ? "/compare" : "/voronoi";
    int gzip_ok = srv__client_takes_gzip(q);
    job_input in = {compare, q->kind, q->body, q->len, accept,
                    opts.n, opts.key, opts.val};
    enum MHD_Result rc;
    if (run_inline(q, conn, &in, instance, gzip_ok, deadline_ns, &rc))
        return rc;

    srv_compute_job *j = calloc(1, sizeof *j);
    if (j == NULL)
        return srv__send_problem(q, conn, API_UNAVAILABLE, NULL,
                                 SRV_RETRY_AFTER_S,
                                 "out of memory");
    atomic_init(&j->refs, 2);
    atomic_init(&j->answered, 0);
    atomic_init(&j->gone, 0);
    pthread_mutex_init(&j->fd_lock, NULL);
    j->srv = s;
    j->conn = conn;
    const union MHD_ConnectionInfo *ci =
        MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
    j->fd = ci != NULL ? ci->connect_fd : -1;
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
        srv__job_unref(j);
        return srv__send_problem(q, conn, API_UNAVAILABLE, NULL,
                                 SRV_RETRY_AFTER_S,
                                 "out of memory");
    }
    j->base.run = job_run;
    j->base.done = job_done;
    j->base.release = job_release;
    j->base.deadline_ns = deadline_ns;

    q->job = j;
    q->phase = SRV_PH_WAIT;
    MHD_suspend_connection(conn);
    int st = srv_pool_submit(s->pool, &j->base);
    if (st != SRV_POOL_OK) {
        /* Not accepted: no callback will come; answer here. */
        if (st == SRV_POOL_FULL)
            srv__problemf(&j->r, j->instance, API_UNAVAILABLE,
                          "all %d workers are busy and %d requests are "
                          "waiting; retry after %d s",
                          s->cfg.workers, s->cfg.queue, SRV_RETRY_AFTER_S);
        else
            srv__problemf(&j->r, j->instance, API_UNAVAILABLE,
                          "the service is shutting down; retry");
        j->r.retry_after = SRV_RETRY_AFTER_S;
        j->r.points = -1;
        atomic_fetch_sub(&j->refs, 1); /* the pool's reference */
        atomic_store_explicit(&j->answered, 1, memory_order_release);
        MHD_resume_connection(conn);
    }
    return MHD_YES;
}

enum MHD_Result srv__finish_compute(srv_req *q, struct MHD_Connection *conn) {
    srv_compute_job *j = q->job;
    if (!atomic_load_explicit(&j->answered, memory_order_acquire))
        return MHD_YES; /* not yet; called again after resume */
    q->algorithm = j->r.algorithm;
    q->points = j->r.points;
    return srv__send_reply(q, conn, &j->r, NULL, NULL);
}

