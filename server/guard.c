/* guard.c -- deadlines for slow clients and the lingering close (the
 * contract is in guard.h).
 *
 * Representation: every open connection is a srv_guard_conn in one
 * doubly linked list under the guard's lock. Its phase is an atomic the
 * connection's thread moves along
 *
 *   HEAD --first handler call--> BODY --last call--> BUSY --answer sent-->
 *   HEAD ...
 *
 * and the guard's thread moves HEAD or BODY to DEAD by compare-and-swap,
 * so that of a handler starting a request and the guard closing its
 * connection exactly one wins. `since` is when the phase began (HEAD: the
 * connection's start, or the end of the previous answer); `gen` counts
 * the HEAD phases, so that the thread notices a new one and takes the
 * socket's byte count (TCP_INFO's tcpi_bytes_received) as its baseline: a
 * kept-alive connection is waiting for a request while the count stays,
 * and is sending one (and under the deadline) once it grows.
 *
 * Lingering sockets (duplicates taken by srv_guard_conn_linger) are
 * handed over at close and polled by the thread until the client closes,
 * SRV_LINGER_BYTES were read, or --header-timeout passed.
 *
 * Lock order: the guard's lock is the only lock here; it is taken by
 * libmicrohttpd's threads inside its own callbacks (no lock of theirs
 * held) and by the guard's thread, which calls nothing of
 * libmicrohttpd's.
 */
#include "guard.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/tcp.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "../api/api.h"
#include "pool.h"

enum { PH_HEAD, PH_BODY, PH_BUSY, PH_DEAD };

/* Lingering sockets at most; beyond, a refused connection closes at once. */
#define MAX_LINGER 256
#define TICK_MS 100      /* the thread's wake-up */
#define SWEEP_NS 250000000LL /* walks of the connection list */
#define PRESSURE_DEADLINE_NS 250000000LL /* near the connection limit */

struct srv_guard_conn {
    srv_guard_conn *prev, *next;
    int fd;
    int linger_fd;            /* dup of fd for a lingering close, or -1 */
    atomic_int phase;
    atomic_llong since_ns;    /* start of the phase */
    atomic_ullong body_bytes; /* in BODY */
    atomic_uint gen;          /* HEAD phases begun */
    atomic_int served;        /* requests answered on this connection */
    atomic_int too_slow;      /* closed for its upload rate */
    /* The guard's thread's own view. */
    unsigned seen_gen;
    unsigned long long rx_base;
    int64_t partial_ns;       /* first seen sending a further request */
};

typedef struct lingering {
    int fd;
    size_t left;
    int64_t until_ns;
} lingering;

struct srv_guard {
    pthread_mutex_t lock;
    pthread_t thread;
    int stop;                 /* under lock */
    srv_guard_conn *head;     /* open connections, under lock */
    size_t n_open;            /* under lock */
    atomic_size_t n_open_pub;
    lingering linger[MAX_LINGER];
    size_t n_linger;          /* under lock */
    int64_t header_ns, linger_ns;
    double min_rate;
    size_t pressure_at;
    atomic_ullong closed[SRV_GUARD_REASONS];
    char answer[2][1024];     /* 408 for headers, 408 for the body */
    size_t answer_len[2];
};

/* ---- the 408 answers ------------------------------------------------------- */

/* A whole HTTP response: 408, a problem document, Connection: close. */
static size_t make_408(char *out, size_t size, const char *detail) {
    api_problem p;
    api_buf b;
    memset(&p, 0, sizeof p);
    p.code = API_REQUEST_TIMEOUT;
    snprintf(p.detail, sizeof p.detail, "%s", detail);
    api_buf_init(&b);
    api_write_problem(&p, NULL, &b);
    if (b.oom || b.data == NULL) {
        api_buf_clear(&b);
        return 0;
    }
    const char *body = b.data;
    int n = snprintf(out, size,
                     "HTTP/1.1 408 Request Timeout\r\n"
                     "Content-Type: application/problem+json\r\n"
                     "Content-Length: %zu\r\n"
                     "Connection: close\r\n"
                     "X-Content-Type-Options: nosniff\r\n"
                     "Access-Control-Allow-Origin: *\r\n"
                     "\r\n%s",
                     strlen(body), body);
    api_buf_clear(&b);
    return n > 0 && (size_t)n < size ? (size_t)n : 0;
}

/* ---- time and sockets -------------------------------------------------------- */

/* Bytes the kernel received on fd so far; -1 when it cannot tell. */
static long long bytes_received(int fd) {
    struct tcp_info ti;
    socklen_t len = sizeof ti;
    memset(&ti, 0, sizeof ti);
    if (getsockopt(fd, IPPROTO_TCP, TCP_INFO, &ti, &len) != 0 ||
        len < offsetof(struct tcp_info, tcpi_bytes_received) +
                  sizeof ti.tcpi_bytes_received)
        return -1;
    return (long long)ti.tcpi_bytes_received;
}

/* Closes k's connection for `why` if its phase is still `phase`: writes
 * the 408 when one is due, then shuts the socket down so that
 * libmicrohttpd sees the end of it and closes. Under the lock. */
static void condemn(srv_guard *g, srv_guard_conn *k, int phase,
                    srv_guard_reason why) {
    int expected = phase;
    if (!atomic_compare_exchange_strong(&k->phase, &expected, PH_DEAD))
        return; /* the connection's thread moved on first */
    int which = why == SRV_GUARD_UPLOAD_RATE ? 1 : 0;
    if (why != SRV_GUARD_SILENT && g->answer_len[which] > 0)
        (void)send(k->fd, g->answer[which], g->answer_len[which],
                   MSG_DONTWAIT | MSG_NOSIGNAL);
    if (why == SRV_GUARD_UPLOAD_RATE) atomic_store(&k->too_slow, 1);
    shutdown(k->fd, SHUT_RDWR);
    atomic_fetch_add(&g->closed[why], 1);
}

static void sweep(srv_guard *g, int64_t now) {
    int64_t head_ns = g->header_ns;
    if (g->n_open >= g->pressure_at && head_ns > PRESSURE_DEADLINE_NS)
        head_ns = PRESSURE_DEADLINE_NS;
    for (srv_guard_conn *k = g->head; k != NULL; k = k->next) {
        int phase = atomic_load(&k->phase);
        int64_t since = atomic_load(&k->since_ns);
        if (phase == PH_HEAD) {
            unsigned gen = atomic_load(&k->gen);
            int fresh = atomic_load(&k->served) == 0;
            if (fresh) {
                if (now - since <= head_ns) continue;
                long long rx = bytes_received(k->fd);
                condemn(g, k, PH_HEAD,
                        rx == 0 ? SRV_GUARD_SILENT : SRV_GUARD_HEADER_TIMEOUT);
                continue;
            }
            long long rx = bytes_received(k->fd);
            if (k->seen_gen != gen) {
                k->seen_gen = gen;
                k->rx_base = rx < 0 ? 0 : (unsigned long long)rx;
                k->partial_ns = 0;
                continue;
            }
            if (rx < 0 || (unsigned long long)rx <= k->rx_base) continue;
            if (k->partial_ns == 0) k->partial_ns = now;
            if (now - k->partial_ns > head_ns)
                condemn(g, k, PH_HEAD, SRV_GUARD_HEADER_TIMEOUT);
        } else if (phase == PH_BODY && g->min_rate > 0) {
            int64_t dt = now - since;
            if (dt <= g->header_ns) continue;
            double need = g->min_rate * ((double)dt / 1e9);
            if ((double)atomic_load(&k->body_bytes) < need)
                condemn(g, k, PH_BODY, SRV_GUARD_UPLOAD_RATE);
        }
    }
}

/* Reads and discards what lingering sockets hold; closes the finished
 * ones. Under the lock; the reads do not block. */
static void drain_lingering(srv_guard *g, const struct pollfd *p, size_t n,
                            int64_t now) {
    char sink[16384];
    for (size_t i = 0; i < n && i < g->n_linger; i++) {
        lingering *l = &g->linger[i];
        if (l->fd != p[i].fd) continue; /* the list changed meanwhile */
        int done = now >= l->until_ns;
        if (!done && (p[i].revents & (POLLIN | POLLHUP | POLLERR))) {
            for (int rounds = 0; rounds < 16 && !done; rounds++) {
                ssize_t got = recv(l->fd, sink,
                                   l->left < sizeof sink ? l->left : sizeof sink,
                                   MSG_DONTWAIT);
                if (got > 0) {
                    l->left -= (size_t)got;
                    done = l->left == 0;
                } else if (got == 0 || (errno != EAGAIN && errno != EINTR &&
                                        errno != EWOULDBLOCK)) {
                    done = 1;
                } else {
                    break;
                }
            }
        }
        if (done) l->fd = -l->fd - 2; /* marked; compacted below */
    }
    size_t k = 0;
    for (size_t i = 0; i < g->n_linger; i++) {
        if (g->linger[i].fd < 0) {
            close(-g->linger[i].fd - 2);
        } else {
            g->linger[k++] = g->linger[i];
        }
    }
    g->n_linger = k;
}

static void *guard_main(void *arg) {
    srv_guard *g = arg;
    struct pollfd p[MAX_LINGER];
    int64_t next_sweep = 0;
    pthread_mutex_lock(&g->lock);
    while (!g->stop) {
        size_t n = g->n_linger;
        for (size_t i = 0; i < n; i++) {
            p[i].fd = g->linger[i].fd;
            p[i].events = POLLIN;
            p[i].revents = 0;
        }
        pthread_mutex_unlock(&g->lock);
        if (n > 0) {
            (void)poll(p, (nfds_t)n, TICK_MS);
        } else {
            struct timespec ts = {0, TICK_MS * 1000000L};
            nanosleep(&ts, NULL);
        }
        pthread_mutex_lock(&g->lock);
        int64_t now = srv_now_ns();
        if (n > 0 || g->n_linger > 0) drain_lingering(g, p, n, now);
        if (now >= next_sweep || g->n_open >= g->pressure_at) {
            sweep(g, now);
            next_sweep = now + SWEEP_NS;
        }
    }
    pthread_mutex_unlock(&g->lock);
    return NULL;
}

/* ---- life cycle --------------------------------------------------------------- */

srv_guard *srv_guard_new(const srv_config *cfg) {
    srv_guard *g = calloc(1, sizeof *g);
    if (g == NULL) return NULL;
    g->header_ns = (int64_t)(cfg->header_timeout * 1e9);
    g->linger_ns = g->header_ns;
    g->min_rate = (double)cfg->min_upload_rate;
    size_t margin = cfg->max_connections / 10;
    if (margin < 16) margin = 16;
    g->pressure_at = cfg->max_connections > margin
                         ? cfg->max_connections - margin
                         : 1;
    g->answer_len[0] = make_408(
        g->answer[0], sizeof g->answer[0],
        "the request line and headers did not arrive within the service's "
        "deadline (--header-timeout); send the whole request at once");
    g->answer_len[1] = make_408(
        g->answer[1], sizeof g->answer[1],
        "the body arrived more slowly than the service's minimum upload "
        "rate (--min-upload-rate)");
    atomic_init(&g->n_open_pub, 0);
    for (int i = 0; i < SRV_GUARD_REASONS; i++) atomic_init(&g->closed[i], 0);
    if (pthread_mutex_init(&g->lock, NULL) != 0) {
        free(g);
        return NULL;
    }
    if (pthread_create(&g->thread, NULL, guard_main, g) != 0) {
        pthread_mutex_destroy(&g->lock);
        free(g);
        return NULL;
    }
    return g;
}

void srv_guard_free(srv_guard *g) {
    if (g == NULL) return;
    pthread_mutex_lock(&g->lock);
    g->stop = 1;
    pthread_mutex_unlock(&g->lock);
    pthread_join(g->thread, NULL);
    for (size_t i = 0; i < g->n_linger; i++) close(g->linger[i].fd);
    while (g->head != NULL) { /* not expected: every connection closed */
        srv_guard_conn *k = g->head;
        g->head = k->next;
        if (k->linger_fd >= 0) close(k->linger_fd);
        free(k);
    }
    pthread_mutex_destroy(&g->lock);
    free(g);
}

srv_guard_conn *srv_guard_conn_open(srv_guard *g, int fd) {
    srv_guard_conn *k = calloc(1, sizeof *k);
    if (k == NULL) return NULL;
    k->fd = fd;
    k->linger_fd = -1;
    atomic_init(&k->phase, PH_HEAD);
    atomic_init(&k->since_ns, srv_now_ns());
    atomic_init(&k->body_bytes, 0);
    atomic_init(&k->gen, 0);
    atomic_init(&k->served, 0);
    atomic_init(&k->too_slow, 0);
    pthread_mutex_lock(&g->lock);
    k->next = g->head;
    if (g->head != NULL) g->head->prev = k;
    g->head = k;
    g->n_open++;
    atomic_store(&g->n_open_pub, g->n_open);
    pthread_mutex_unlock(&g->lock);
    return k;
}

void srv_guard_conn_close(srv_guard *g, srv_guard_conn *k) {
    if (k == NULL) return;
    pthread_mutex_lock(&g->lock);
    if (k->prev != NULL) k->prev->next = k->next;
    else g->head = k->next;
    if (k->next != NULL) k->next->prev = k->prev;
    g->n_open--;
    atomic_store(&g->n_open_pub, g->n_open);
    if (k->linger_fd >= 0) {
        if (g->n_linger < MAX_LINGER && !g->stop) {
            /* The answer is in the socket's queue; the end of it follows
             * (libmicrohttpd may have sent it already). */
            shutdown(k->linger_fd, SHUT_WR);
            lingering *l = &g->linger[g->n_linger++];
            l->fd = k->linger_fd;
            l->left = SRV_LINGER_BYTES;
            l->until_ns = srv_now_ns() + g->linger_ns;
        } else {
            close(k->linger_fd);
        }
    }
    pthread_mutex_unlock(&g->lock);
    free(k);
}

int srv_guard_conn_headers(srv_guard_conn *k) {
    if (k == NULL) return 1;
    int expected = PH_HEAD;
    atomic_store(&k->body_bytes, 0);
    atomic_store(&k->since_ns, srv_now_ns());
    if (atomic_compare_exchange_strong(&k->phase, &expected, PH_BODY))
        return 1;
    return expected != PH_DEAD;
}

void srv_guard_conn_body(srv_guard_conn *k, size_t n) {
    if (k != NULL)
        atomic_fetch_add_explicit(&k->body_bytes, n, memory_order_relaxed);
}

void srv_guard_conn_busy(srv_guard_conn *k) {
    int expected = PH_BODY;
    if (k != NULL)
        atomic_compare_exchange_strong(&k->phase, &expected, PH_BUSY);
}

void srv_guard_conn_idle(srv_guard_conn *k) {
    if (k == NULL) return;
    atomic_fetch_add(&k->served, 1);
    atomic_store(&k->since_ns, srv_now_ns());
    atomic_fetch_add(&k->gen, 1);
    int phase = atomic_load(&k->phase);
    while (phase != PH_DEAD &&
           !atomic_compare_exchange_weak(&k->phase, &phase, PH_HEAD)) {
    }
}

void srv_guard_conn_linger(srv_guard_conn *k) {
    if (k != NULL && k->linger_fd < 0)
        k->linger_fd = fcntl(k->fd, F_DUPFD_CLOEXEC, 0);
}

int srv_guard_conn_too_slow(const srv_guard_conn *k) {
    return k != NULL && atomic_load(&((srv_guard_conn *)k)->too_slow);
}

uint64_t srv_guard_closed(const srv_guard *g, srv_guard_reason why) {
    return atomic_load(&((srv_guard *)g)->closed[why]);
}

size_t srv_guard_pending(srv_guard *g, double young_s) {
    size_t n = 0;
    int64_t now = srv_now_ns(), young = (int64_t)(young_s * 1e9);
    pthread_mutex_lock(&g->lock);
    for (srv_guard_conn *k = g->head; k != NULL; k = k->next) {
        if (atomic_load(&k->phase) != PH_HEAD || atomic_load(&k->served) != 0)
            continue;
        if (now - atomic_load(&k->since_ns) < young ||
            bytes_received(k->fd) > 0)
            n++;
    }
    pthread_mutex_unlock(&g->lock);
    return n;
}

size_t srv_guard_open(const srv_guard *g) {
    return atomic_load(&((srv_guard *)g)->n_open_pub);
}
