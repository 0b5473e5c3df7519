/* stream.c -- large answers produced as the socket drains (the contract
 * and the threads are in stream.h).
 *
 * Chunks: the writer fills `fill` (the codec's output, deflated when
 * gzip) and publishes it as `next` once it holds SRV_STREAM_CHUNK bytes,
 * waiting while `next` is still taken; the consumer copies from `cur` and
 * moves `next` into `cur` when `cur` is used up. So at most three chunks
 * exist: the one being read, the one ready, the one being filled.
 *
 * A stream has two references: the writer thread's and libmicrohttpd's
 * (the response); the last one frees it. `gone` says libmicrohttpd freed
 * the response (the connection must not be resumed any more), `stop`
 * says the service is shutting down.
 */
#include "stream.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

struct srv_streams {
    pthread_mutex_t lock;
    pthread_cond_t idle;
    srv_stream *head;   /* live streams */
    int writers;        /* writer threads running */
    int stopping;
};

struct srv_stream {
    srv_streams *g;
    srv_stream *prev, *next_st; /* in g->head, under g->lock */
    srv_budget *budget;
    size_t held;
    api_request r;
    api_result res;
    api_timings t;
    int gzip;
    z_stream z;
    int z_ready;
    struct MHD_Connection *conn;
    size_t *sent; /* the request's byte count (srv_stream_start) */

    pthread_mutex_t lock;
    pthread_cond_t cond;
    char *cur;
    size_t cur_len, cur_off;
    char *next;
    size_t next_len;
    char *fill;          /* the writer's, no lock */
    size_t fill_len, fill_cap;
    int done, failed, waiting, gone, stop;
    int refs;
};

/* ---- the registry ------------------------------------------------------ */

srv_streams *srv_streams_new(void) {
    srv_streams *g = calloc(1, sizeof *g);
    if (g == NULL) return NULL;
    pthread_mutex_init(&g->lock, NULL);
    pthread_cond_init(&g->idle, NULL);
    return g;
}

void srv_streams_stop(srv_streams *g) {
    if (g == NULL) return;
    pthread_mutex_lock(&g->lock);
    g->stopping = 1;
    for (srv_stream *st = g->head; st != NULL; st = st->next_st) {
        pthread_mutex_lock(&st->lock);
        st->stop = 1;
        pthread_cond_broadcast(&st->cond);
        pthread_mutex_unlock(&st->lock);
    }
    while (g->writers > 0) pthread_cond_wait(&g->idle, &g->lock);
    pthread_mutex_unlock(&g->lock);
}

void srv_streams_free(srv_streams *g) {
    if (g == NULL) return;
    pthread_mutex_destroy(&g->lock);
    pthread_cond_destroy(&g->idle);
    free(g);
}

/* ---- one stream ----------------------------------------------------------- */

size_t srv_result_bytes(const api_result *res) {
    size_t b = 0;
    const vor_sites *s = res->sites;
    const vor_diagram *d = res->diagram;
    const vor_clipped *c = res->clipped;
    if (s != NULL) b += s->n_input * 4 + s->n * 20;
    if (d != NULL)
        b += d->n_vertices * 28 + d->n_edges * 24 + d->n_rays * 20 +
             (d->n_sites + 1) * 4 + d->n_sites;
    if (c != NULL && d != NULL)
        b += d->n_edges * 33 + (d->n_sites + 1) * 4 +
             (size_t)c->poly_start[d->n_sites] * 16;
    b += res->n_triangles * 12;
    return b;
}

static void give(srv_stream *st, size_t n) {
    if (n > st->held) n = st->held;
    st->held -= n;
    srv_budget_give(st->budget, n);
}

static void unref(srv_stream *st) {
    pthread_mutex_lock(&st->lock);
    int last = --st->refs == 0;
    pthread_mutex_unlock(&st->lock);
    if (!last) return;
    srv_streams *g = st->g;
    pthread_mutex_lock(&g->lock);
    if (st->prev != NULL) st->prev->next_st = st->next_st;
    else if (g->head == st) g->head = st->next_st;
    if (st->next_st != NULL) st->next_st->prev = st->prev;
    pthread_mutex_unlock(&g->lock);
    free(st->cur);
    free(st->next);
    free(st->fill);
    if (st->z_ready) deflateEnd(&st->z);
    api_result_clear(&st->res);
    api_request_clear(&st->r);
    give(st, st->held);
    pthread_mutex_destroy(&st->lock);
    pthread_cond_destroy(&st->cond);
    free(st);
}

srv_stream *srv_stream_new(srv_streams *g, srv_budget *b, api_request *r,
                           api_result *res, const api_timings *t, int gzip,
                           size_t held) {
    srv_stream *st = calloc(1, sizeof *st);
    if (st == NULL) return NULL;
    st->fill_cap = SRV_STREAM_CHUNK + (64 << 10);
    st->fill = malloc(st->fill_cap);
    if (st->fill == NULL) {
        free(st);
        return NULL;
    }
    if (gzip) {
        if (deflateInit2(&st->z, 1, Z_DEFLATED, 15 + 16, 8,
                         Z_DEFAULT_STRATEGY) != Z_OK) {
            free(st->fill);
            free(st);
            return NULL;
        }
        st->z_ready = 1;
    }
    st->g = g;
    st->budget = b;
    st->held = held;
    st->r = *r;
    api_request_init(r);
    free(st->r.xy); /* the sites have their own copy */
    st->r.xy = NULL;
    st->r.n = 0;
    st->res = *res;
    api_result_init(res);
    st->t = *t;
    st->gzip = gzip;
    st->refs = 2;
    pthread_mutex_init(&st->lock, NULL);
    pthread_cond_init(&st->cond, NULL);
    pthread_mutex_lock(&g->lock);
    st->next_st = g->head;
    if (g->head != NULL) g->head->prev = st;
    g->head = st;
    pthread_mutex_unlock(&g->lock);
    return st;
}

void srv_stream_discard(srv_stream *st) {
    if (st == NULL) return;
    st->refs = 1;
    unref(st);
}

/* ---- the writer ---------------------------------------------------------------- */

/* Hands `fill` over as the next chunk, waiting while one is pending.
 * -1 when nobody will read it any more. */
static int publish(srv_stream *st) {
    pthread_mutex_lock(&st->lock);
    while (st->next != NULL && !st->gone && !st->stop)
        pthread_cond_wait(&st->cond, &st->lock);
    if (st->gone || st->stop) {
        pthread_mutex_unlock(&st->lock);
        return -1;
    }
    st->next = st->fill;
    st->next_len = st->fill_len;
    if (st->waiting) {
        st->waiting = 0;
        MHD_resume_connection(st->conn);
    }
    pthread_mutex_unlock(&st->lock);
    st->fill_cap = SRV_STREAM_CHUNK + (64 << 10);
    st->fill = malloc(st->fill_cap);
    st->fill_len = 0;
    return st->fill == NULL ? -1 : 0;
}

/* Appends n bytes to fill (growing it if need be). */
static int fill_with(srv_stream *st, const char *data, size_t n) {
    if (st->fill_len + n > st->fill_cap) {
        size_t cap = st->fill_cap * 2;
        while (cap < st->fill_len + n) cap *= 2;
        char *f = realloc(st->fill, cap);
        if (f == NULL) return -1;
        st->fill = f;
        st->fill_cap = cap;
    }
    memcpy(st->fill + st->fill_len, data, n);
    st->fill_len += n;
    return 0;
}

/* Deflates n bytes (finish: the end of the stream) into fill. */
static int deflate_into(srv_stream *st, const char *data, size_t n,
                        int finish) {
    st->z.next_in = (Bytef *)data;
    st->z.avail_in = (uInt)n;
    for (;;) {
        if (st->fill_cap - st->fill_len < 65536) {
            char *f = realloc(st->fill, st->fill_cap * 2);
            if (f == NULL) return -1;
            st->fill = f;
            st->fill_cap *= 2;
        }
        st->z.next_out = (Bytef *)st->fill + st->fill_len;
        st->z.avail_out = (uInt)(st->fill_cap - st->fill_len);
        int rc = deflate(&st->z, finish ? Z_FINISH : Z_NO_FLUSH);
        st->fill_len = (size_t)((char *)st->z.next_out - st->fill);
        if (rc == Z_STREAM_ERROR) return -1;
        if (finish ? rc == Z_STREAM_END : st->z.avail_in == 0) return 0;
    }
}

/* The codec's flush hook: its output so far. */
static int push(void *ctx, const char *data, size_t n) {
    srv_stream *st = ctx;
    while (n > 0) {
        size_t k = n > SRV_STREAM_CHUNK ? SRV_STREAM_CHUNK : n;
        int rc = st->gzip ? deflate_into(st, data, k, 0)
                          : fill_with(st, data, k);
        if (rc != 0) return -1;
        data += k;
        n -= k;
        if (st->fill_len >= SRV_STREAM_CHUNK && publish(st) != 0) return -1;
    }
    return 0;
}

static void *writer_main(void *arg) {
    srv_stream *st = arg;
    api_buf b;
    api_problem p;
    api_buf_init(&b);
    b.flush = push;
    b.flush_ctx = st;
    b.flush_at = SRV_STREAM_CHUNK;
    memset(&p, 0, sizeof p);
    int ok = api_write_result(&st->r, &st->res, &st->t, &b, &p) == API_OK;
    /* Every byte is out of the result now: give its memory back. */
    size_t result = srv_result_bytes(&st->res);
    api_result_clear(&st->res);
    pthread_mutex_lock(&st->lock);
    give(st, result);
    pthread_mutex_unlock(&st->lock);
    if (ok && b.len > 0) ok = push(st, b.data, b.len) == 0;
    api_buf_clear(&b);
    if (ok && st->gzip) ok = deflate_into(st, "", 0, 1) == 0;
    if (ok && st->fill_len > 0) ok = publish(st) == 0;

    pthread_mutex_lock(&st->lock);
    st->done = 1;
    st->failed = !ok;
    if (st->waiting && !st->gone) {
        st->waiting = 0;
        MHD_resume_connection(st->conn);
    }
    pthread_mutex_unlock(&st->lock);
    srv_streams *g = st->g;
    unref(st);
    pthread_mutex_lock(&g->lock);
    if (--g->writers == 0) pthread_cond_broadcast(&g->idle);
    pthread_mutex_unlock(&g->lock);
    return NULL;
}

/* ---- the consumer (libmicrohttpd's content reader) ------------------------- */

static ssize_t reader(void *cls, uint64_t pos, char *buf, size_t max) {
    srv_stream *st = cls;
    (void)pos;
    pthread_mutex_lock(&st->lock);
    for (;;) {
        if (st->cur != NULL && st->cur_off < st->cur_len) {
            size_t n = st->cur_len - st->cur_off;
            if (n > max) n = max;
            memcpy(buf, st->cur + st->cur_off, n);
            st->cur_off += n;
            *st->sent += n;
            pthread_mutex_unlock(&st->lock);
            return (ssize_t)n;
        }
        free(st->cur);
        st->cur = NULL;
        if (st->next != NULL) {
            st->cur = st->next;
            st->cur_len = st->next_len;
            st->cur_off = 0;
            st->next = NULL;
            pthread_cond_broadcast(&st->cond);
            continue;
        }
        if (st->done) {
            ssize_t end = st->failed ? MHD_CONTENT_READER_END_WITH_ERROR
                                     : MHD_CONTENT_READER_END_OF_STREAM;
            pthread_mutex_unlock(&st->lock);
            return end;
        }
        /* Nothing ready yet: sleep until the writer has a chunk. */
        st->waiting = 1;
        MHD_suspend_connection(st->conn);
        pthread_mutex_unlock(&st->lock);
        return 0;
    }
}

static void reader_free(void *cls) {
    srv_stream *st = cls;
    pthread_mutex_lock(&st->lock);
    st->gone = 1;
    pthread_cond_broadcast(&st->cond);
    pthread_mutex_unlock(&st->lock);
    unref(st);
}

struct MHD_Response *srv_stream_start(srv_stream *st,
                                      struct MHD_Connection *conn,
                                      size_t *sent) {
    st->conn = conn;
    st->sent = sent;
    struct MHD_Response *resp = MHD_create_response_from_callback(
        MHD_SIZE_UNKNOWN, 64 * 1024, reader, st, reader_free);
    if (resp == NULL) {
        srv_stream_discard(st);
        return NULL;
    }
    MHD_add_response_header(resp, "Content-Type",
                            api_format_mime(st->r.format));
    if (st->gzip) MHD_add_response_header(resp, "Content-Encoding", "gzip");
    srv_streams *g = st->g;
    pthread_mutex_lock(&g->lock);
    int refused = g->stopping;
    if (!refused) g->writers++;
    pthread_mutex_unlock(&g->lock);
    pthread_t th;
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
    if (refused || pthread_create(&th, &attr, writer_main, st) != 0) {
        if (!refused) {
            pthread_mutex_lock(&g->lock);
            if (--g->writers == 0) pthread_cond_broadcast(&g->idle);
            pthread_mutex_unlock(&g->lock);
        }
        /* No writer: the response ends at once, with an error. */
        pthread_mutex_lock(&st->lock);
        st->done = 1;
        st->failed = 1;
        st->refs--; /* the writer's */
        pthread_mutex_unlock(&st->lock);
    }
    pthread_attr_destroy(&attr);
    return resp;
}
