/* server.c -- voronoid's HTTP front: the daemon's life cycle and the
 * libmicrohttpd callbacks from which every request is dispatched.
 *
 * on_request is libmicrohttpd's access handler, called several times per
 * request: the first call makes a srv_req (request id, route) and hands
 * the headers to intake.c; data calls go to intake.c; the last call goes
 * to work.c for computations and to handlers.c for everything else; a
 * call after the pool resumed the connection sends the computed answer
 * (work.c). on_completed ends every request that reached the handler:
 * one access-log line and the metrics.
 *
 * The request's way in is intake.c, its way out answer.c (internal.h
 * lists the files).
 */
#include "server.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <linux/filter.h>
#include <microhttpd.h>
#include <netinet/in.h>
#include <poll.h>
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

#include "budget.h"
#include "fmt.h"
#include "guard.h"
#include "internal.h"
#include "stream.h"

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
/* Closing the listener, the accept queue must stay empty this long: a
 * handshake under way completes within a round trip (srv_server_stop_
 * listening). */
#define SRV_QUEUE_QUIET_MS 200

static double ms_since(int64_t t0_ns) {
    return (double)(srv_now_ns() - t0_ns) / 1e6;
}

static int has_asset(const char *path, void *ctx) {
    return srv_assets_has(ctx, path);
}

static void make_request_id(srv_req *q) {
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

/* Last call: the whole request is in. */
static enum MHD_Result on_complete(srv_req *q, struct MHD_Connection *conn) {
    enum MHD_Result rc;
    if (srv__intake_refusal(q, conn, &rc)) return rc;
    if (q->match == SRV_MATCH_OK && q->method == SRV_M_POST &&
        (q->route == SRV_ROUTE_VORONOI || q->route == SRV_ROUTE_COMPARE))
        return srv__start_compute(q, conn);
    return srv__handle_static(q, conn);
}

/* url into dst (size > 0), cut to fit and terminated as snprintf would,
 * without its cost on every request. NULL gives "". */
static void copy_path(char *dst, size_t size, const char *url) {
    size_t n = url != NULL ? strnlen(url, size - 1) : 0;
    if (n > 0) memcpy(dst, url, n);
    dst[n] = '\0';
}

/* A request target in absolute form, "http://host/path" (RFC 9112,
 * 3.2.2: a server must accept it, though clients send it only to
 * proxies), from the path on: "/voronoi" serves as for the origin form,
 * and a target with no path is "/" (its query, if any, kept after it by
 * the caller's copy). Any other target is returned as it is. */
static const char *origin_form(const char *url) {
    const char *p;
    if (url == NULL) return NULL;
    if (strncasecmp(url, "http://", 7) == 0)
        p = url + 7;
    else if (strncasecmp(url, "https://", 8) == 0)
        p = url + 8;
    else
        return url;
    p += strcspn(p, "/?#");
    return *p == '/' ? p : "/";
}

/* libmicrohttpd's URI log callback, called once the request line is in
 * (before the headers): the request's state begins here, so that every
 * request whose line arrived ends in on_completed with a log line, also
 * those libmicrohttpd refuses itself. A request line longer than the
 * service reads is answered 414 now, on the socket: libmicrohttpd keeps
 * the line in the connection's memory, and one that nearly fills it
 * leaves no room for an answer. */
static void *on_uri(void *cls, const char *uri, struct MHD_Connection *conn) {
    srv_server *s = cls;
    srv_req *q = calloc(1, sizeof *q);
    if (q == NULL) return NULL;
    q->srv = s;
    q->t0_ns = srv_now_ns();
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    q->unix_t0 = (double)ts.tv_sec + (double)ts.tv_nsec / 1e9;
    q->points = -1;
    q->route = SRV_ROUTE_OTHER;
    size_t n = uri != NULL ? strlen(uri) : 0;
    uri = origin_form(uri);
    size_t path_len = uri != NULL ? strcspn(uri, "?") : 0;
    copy_path(q->path, sizeof q->path, uri);
    if (path_len < sizeof q->path) q->path[path_len] = '\0';
    if (n > SRV_MAX_REQUEST_LINE) {
        make_request_id(q);
        srv_reply r;
        memset(&r, 0, sizeof r);
        char inst[256];
        srv__printable(inst, sizeof inst, q->path, 200);
        srv__problemf(&r, inst, API_URI_TOO_LONG,
                      "the request target is %zu bytes long; the service "
                      "reads at most %d", n, SRV_MAX_REQUEST_LINE);
        srv__send_direct(q, conn, &r);
        q->refused = 1;
    }
    return q;
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *conn,
                                  const char *url, const char *method,
                                  const char *version,
                                  const char *upload_data,
                                  size_t *upload_data_size, void **con_cls) {
    srv_server *s = cls;
    srv_req *q = *con_cls;
    (void)version;

    if (q == NULL || q->refused) return MHD_NO;
    if (!q->started) {
        q->started = 1;
        srv__printable(q->method_name, sizeof q->method_name, method, 8);
        copy_path(q->path, sizeof q->path, origin_form(url));
        q->method = srv_method_bit(method);
        srv__collect_headers(conn, &q->h);
        make_request_id(q);
        atomic_fetch_add(&s->in_flight, 1);
        q->match = srv_route_match(method, q->path, has_asset, s->assets,
                                   &q->route, q->allow, sizeof q->allow);
        const union MHD_ConnectionInfo *ci = MHD_get_connection_info(
            conn, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
        q->gconn = ci != NULL ? ci->socket_context : NULL;
        if (!srv_guard_conn_headers(q->gconn))
            return MHD_NO; /* the guard closed it (408) meanwhile */
        return srv__on_headers(q, conn, url);
    }
    if (*upload_data_size > 0) {
        size_t n = *upload_data_size;
        *upload_data_size = 0;
        return srv__on_data(q, upload_data, n);
    }
    if (q->phase == SRV_PH_WAIT) return srv__finish_compute(q, conn);
    if (q->phase == SRV_PH_DONE) return MHD_YES;
    srv_guard_conn_busy(q->gconn);
    return on_complete(q, conn);
}

/* libmicrohttpd's connection notifications: the guard follows every
 * connection from its start to its close. */
static void on_connection(void *cls, struct MHD_Connection *conn,
                          void **socket_context,
                          enum MHD_ConnectionNotificationCode code) {
    srv_server *s = cls;
    if (code == MHD_CONNECTION_NOTIFY_STARTED) {
        const union MHD_ConnectionInfo *ci =
            MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
        *socket_context =
            ci != NULL ? srv_guard_conn_open(s->guard, ci->connect_fd) : NULL;
    } else if (code == MHD_CONNECTION_NOTIFY_CLOSED) {
        srv_guard_conn_close(s->guard, *socket_context);
        *socket_context = NULL;
    }
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
    srv_req *q = *con_cls;
    if (q == NULL) return;
    *con_cls = NULL;
    double ms = ms_since(q->t0_ns);
    const char *note = termination_note(toe);
    if (!q->started && q->status == 0) {
        /* libmicrohttpd ended the request before the handler saw it: its
         * own answer (a header it could not read), or the client left. */
        const union MHD_ConnectionInfo *ci =
            MHD_get_connection_info(conn, MHD_CONNECTION_INFO_HTTP_STATUS);
        if (ci != NULL) {
            q->status = (int)ci->http_status;
            note = "refused-by-http-layer";
        }
        if (q->id[0] == '\0') make_request_id(q);
    }
    if (q->job != NULL && srv__job_client_gone(q->job))
        note = "client-gone"; /* it stopped for that, then could not send */
    if (q->status == 0 && srv_guard_conn_too_slow(q->gconn)) {
        q->status = 408; /* the guard answered for us */
        note = "upload-too-slow";
    }
    srv_guard_conn_idle(q->gconn);
    if (q->send_timeout_set)
        MHD_set_connection_option(conn, MHD_CONNECTION_OPTION_TIMEOUT,
                                  s->cfg.connection_timeout);
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
        .note = note,
    };
    srv_log_access(s->log, &e);
    if (q->job != NULL) srv__job_unref(q->job);
    srv__intake_clear(q);
    int counted = q->started;
    free(q->body);
    free(q);
    if (counted) atomic_fetch_sub(&s->in_flight, 1);
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
    s->guard = srv_guard_new(cfg);
    s->budget = srv_budget_new(cfg->answer_memory);
    s->streams = srv_streams_new();
    if (s->log == NULL || s->metrics == NULL || s->assets == NULL ||
        s->pool == NULL || s->guard == NULL || s->budget == NULL ||
        s->streams == NULL) {
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
        MHD_OPTION_NOTIFY_CONNECTION, on_connection, s,
        MHD_OPTION_URI_LOG_CALLBACK, on_uri, s,
        MHD_OPTION_PER_IP_CONNECTION_LIMIT, cfg->max_connections_per_ip,
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
    srv_streams_free(s->streams);
    srv_budget_free(s->budget);
    srv_guard_free(s->guard);
    srv_pool_free(s->pool, 0);
    srv_assets_free(s->assets);
    srv_metrics_free(s->metrics);
    srv_log_free(s->log);
    free(s);
    return NULL;
}

int srv_server_port(const srv_server *s) { return s->port; }

void srv_server_flush_log(srv_server *s) { srv_log_flush(s->log); }

/* Draining, first step: /readyz answers 503 from now on and every answer
 * says Connection: close, so that load balancers take the daemon out and
 * clients with kept-alive connections reconnect elsewhere; the listener
 * still accepts (see srv_server_stop_listening). */
void srv_server_drain(srv_server *s) { atomic_store(&s->draining, 1); }

/* Second step: stop listening without resetting a connection that
 * reached the kernel. libmicrohttpd stops accepting and hands back the
 * listening socket (MHD_quiesce_daemon). Closing it would reset every
 * connection still waiting in its accept queue, and closing right after
 * emptying the queue would reset those that complete their handshake in
 * between. So a socket filter is attached first that drops every new
 * connection attempt (a TCP segment with SYN and without ACK: the
 * client's SYN goes unanswered; it retries, and then finds the port
 * closed) but lets handshakes already under way complete. The queue is
 * then emptied by hand until it stays empty for SRV_QUEUE_QUIET_MS, each
 * connection given to libmicrohttpd to be served like any other (with
 * Connection: close), and the socket closed. */
void srv_server_stop_listening(srv_server *s) {
    srv_server_drain(s);
    if (s->listen_closed) return;
    s->listen_closed = 1;
    MHD_socket lfd = MHD_quiesce_daemon(s->daemon);
    if (lfd == MHD_INVALID_SOCKET) return;
    /* The filter sees the TCP header at offset 0; byte 13 holds the
     * flags. */
    struct sock_filter no_new[] = {
        BPF_STMT(BPF_LD | BPF_B | BPF_ABS, 13),
        BPF_STMT(BPF_ALU | BPF_AND | BPF_K, 0x12),           /* SYN|ACK */
        BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, 0x02, 0, 1),     /* SYN only */
        BPF_STMT(BPF_RET | BPF_K, 0),                         /* drop */
        BPF_STMT(BPF_RET | BPF_K, 0xffffffffu),               /* keep */
    };
    struct sock_fprog prog = {sizeof no_new / sizeof no_new[0], no_new};
    (void)setsockopt(lfd, SOL_SOCKET, SO_ATTACH_FILTER, &prog, sizeof prog);
    int fl = fcntl(lfd, F_GETFL);
    if (fl >= 0) fcntl(lfd, F_SETFL, fl | O_NONBLOCK);
    for (;;) {
        struct sockaddr_storage addr;
        socklen_t alen = sizeof addr;
        int fd = accept(lfd, (struct sockaddr *)&addr, &alen);
        if (fd < 0) {
            if (errno == EINTR) continue;
            /* Empty: wait for handshakes under way, or the quiet end. */
            struct pollfd p = {lfd, POLLIN, 0};
            if (poll(&p, 1, SRV_QUEUE_QUIET_MS) > 0) continue;
            break;
        }
        s->accepted_late++;
        /* libmicrohttpd closes fd itself when it cannot take it. */
        (void)MHD_add_connection(s->daemon, fd, (struct sockaddr *)&addr,
                                 alen);
    }
    close(lfd);
}

size_t srv_server_accepted_late(const srv_server *s) {
    return s->accepted_late;
}

size_t srv_server_in_flight(const srv_server *s) {
    long n = atomic_load(&((srv_server *)s)->in_flight);
    return n > 0 ? (size_t)n : 0;
}

int srv_server_wait_idle(const srv_server *s, double seconds) {
    int64_t until = srv_now_ns() + (int64_t)(seconds * 1e9);
    for (;;) {
        /* Requests received, and once the listener is closed, connections
         * taken from its queue whose request has not come in yet. */
        if (srv_server_in_flight(s) == 0 &&
            (!s->listen_closed || srv_guard_pending(s->guard, 1.0) == 0))
            return 0;
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
    /* Writers of streamed answers end theirs (the clients get them cut
     * short) and resume any connection waiting for a chunk. */
    srv_streams_stop(s->streams);
    MHD_stop_daemon(s->daemon);
    /* Every request has had its on_completed now: its line is in. */
    srv_log_flush(s->log);
    srv_guard_free(s->guard); /* every connection is closed now */
    srv_streams_free(s->streams);
    if (srv_pool_free(s->pool, 0.5) != 0) return -1;
    srv_budget_free(s->budget);
    srv_assets_free(s->assets);
    srv_metrics_free(s->metrics);
    srv_log_free(s->log);
    free(s);
    return 0;
}
