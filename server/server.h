/* server.h -- the voronoid HTTP service: a libmicrohttpd daemon, the
 * compute pool behind it, metrics and the access log.
 *
 * Life cycle (main.c):
 *
 *     srv_server_new  -- listening, serving
 *     srv_server_drain        -- SIGTERM: /readyz 503, Connection: close
 *     srv_server_stop_listening -- after --drain: stop accepting, serve
 *                                  what the kernel had queued
 *     srv_server_wait_idle    -- until every accepted request is answered
 *     srv_server_cancel       -- grace over: answer what is left with 503
 *     srv_server_free         -- stop the daemon and the pool
 *
 * Threads: libmicrohttpd's pool (config http_threads) accepts connections,
 * reads requests and writes answers; compute requests are handed to the
 * srv_pool (config workers) while their connection is suspended; the main
 * thread only waits for signals. No thread blocks on a client.
 */
#ifndef VOR_SRV_SERVER_H
#define VOR_SRV_SERVER_H

#include <stddef.h>

#include "config.h"

typedef struct srv_server srv_server;

/* Starts the service described by cfg (copied). On failure returns NULL
 * with a one-line reason in err. log_fd receives the access log
 * (buffered: see srv_server_flush_log). */
srv_server *srv_server_new(const srv_config *cfg, int log_fd, char *err,
                           size_t err_size);

/* The port actually bound (useful when cfg->port was 0). */
int srv_server_port(const srv_server *s);

/* Writes out the access-log lines waiting in the buffer (they are written
 * within a few milliseconds anyway): before a message of one's own on the
 * same file, so the file stays in order. */
void srv_server_flush_log(srv_server *s);

/* Turns /readyz to 503 and has every answer say Connection: close; new
 * connections are still accepted and served. Idempotent. */
void srv_server_drain(srv_server *s);

/* Stops accepting connections (draining, if not yet): no connection
 * that reached the kernel's accept queue is reset -- those already queued
 * are accepted and served -- and later ones are refused. Requests on open
 * connections are still served. Idempotent; main thread only. */
void srv_server_stop_listening(srv_server *s);

/* Connections taken from the accept queue by srv_server_stop_listening. */
size_t srv_server_accepted_late(const srv_server *s);

/* Requests received and not yet answered. */
size_t srv_server_in_flight(const srv_server *s);

/* Waits until no request is in flight, at most `seconds` (once the
 * daemon stopped listening, also until the connections it took from the
 * kernel's queue have sent their requests, or a second has passed, or
 * they sent part of one and wait for --header-timeout). 0 when idle. */
int srv_server_wait_idle(const srv_server *s, double seconds);

/* Answers every request still queued or computing with 503 (the result of
 * a computation that is still running will be discarded). */
void srv_server_cancel(srv_server *s);

/* Stops the daemon and the compute pool and frees everything. Returns 0;
 * -1 when a computation was still running and could not be waited for:
 * memory is then left to the process exit. */
int srv_server_free(srv_server *s);

#endif /* VOR_SRV_SERVER_H */
