/* guard.h -- deadlines for slow clients, and the lingering close.
 *
 * libmicrohttpd's own connection timeout counts only idle time: a client
 * that sends its request line and headers one byte a second, or its body
 * at a trickle, is never idle and would keep its connection (and, by the
 * thousand, every connection slot) forever. The guard knows every open
 * connection (from libmicrohttpd's connection notifications) and in which
 * phase its request is, and a thread of its own enforces:
 *
 *   - the header deadline: a request's line and headers must be complete
 *     within --header-timeout of the connection's start, or of the first
 *     byte of a further request on a kept-alive connection (a kept-alive
 *     connection with nothing sent waits under --connection-timeout as
 *     before). Near the connection limit (within a tenth of it) the
 *     deadline shrinks to a quarter of a second, so that trickling
 *     connections cannot hold every slot (a client's request line and
 *     headers come in one packet or a few, in far less);
 *   - the upload rate: once --header-timeout has passed since its
 *     headers, a body must have averaged --min-upload-rate bytes/s.
 *
 * A connection past its deadline gets a 408 problem document, written to
 * its socket by the guard where an answer can still be sent (the client
 * has sent part of a request and nothing has been answered), and is shut
 * down; libmicrohttpd then closes it. A fresh connection that sent
 * nothing at all is closed without a word.
 *
 * Lingering close: when a request with a body is refused before its body
 * is read (413 on Content-Length, 415, 501...), libmicrohttpd sends the
 * answer and closes the socket while the client may still be sending. A
 * client that does not read while it sends (Python's http.client without
 * Expect: 100-continue) then gets a reset and never sees the answer. For
 * such requests the guard keeps a duplicate of the socket: when
 * libmicrohttpd closes its own, the guard reads and discards what the
 * client still sends (at most SRV_LINGER_BYTES, for at most
 * --header-timeout seconds) and closes only then.
 *
 * Threads: the srv_guard_conn_* calls come from libmicrohttpd's threads,
 * each for its own connection; the guard's thread reads the phase fields
 * (atomics) and writes to a socket only under the guard's lock, which the
 * close notification also takes, so a socket is never written after
 * libmicrohttpd closed it. Cost: per request a few atomic stores; per
 * connection one allocation and the lock twice; the thread wakes every
 * 100 ms and walks the connections every 250 ms, every 100 ms near the
 * connection limit (one getsockopt per kept-alive connection waiting for a
 * request).
 */
#ifndef VOR_SRV_GUARD_H
#define VOR_SRV_GUARD_H

#include <stddef.h>
#include <stdint.h>

#include "config.h"

/* Most bytes read and thrown away in a lingering close. */
#define SRV_LINGER_BYTES (16u << 20)

typedef struct srv_guard srv_guard;
typedef struct srv_guard_conn srv_guard_conn;

/* Why the guard closed a connection. */
typedef enum srv_guard_reason {
    SRV_GUARD_HEADER_TIMEOUT, /* headers not complete in time: 408 */
    SRV_GUARD_SILENT,         /* a fresh connection that sent nothing */
    SRV_GUARD_UPLOAD_RATE,    /* body slower than --min-upload-rate: 408 */
    SRV_GUARD_REASONS
} srv_guard_reason;

/* Starts the guard's thread for the limits in cfg (copied). NULL if
 * memory or a thread cannot be had. */
srv_guard *srv_guard_new(const srv_config *cfg);

/* Stops the thread, closes lingering sockets, frees. Every connection
 * must have been closed (srv_guard_conn_close) before. NULL: no-op. */
void srv_guard_free(srv_guard *g);

/* A new connection on socket fd (libmicrohttpd's notification of its
 * start, on the connection's thread). NULL when out of memory: the
 * connection then simply has no deadlines. */
srv_guard_conn *srv_guard_conn_open(srv_guard *g, int fd);

/* libmicrohttpd closed the connection (its notification, before it
 * closes the socket). Hands a socket kept for lingering to the guard's
 * thread; frees k. NULL: no-op. */
void srv_guard_conn_close(srv_guard *g, srv_guard_conn *k);

/* The headers of a request are complete (the access handler's first
 * call). 0 when the guard already closed the connection: the handler
 * must then refuse the request (MHD_NO). */
int srv_guard_conn_headers(srv_guard_conn *k);

/* n more bytes of the body arrived. */
void srv_guard_conn_body(srv_guard_conn *k, size_t n);

/* The request is complete; no deadline of the guard applies while it is
 * computed and answered. */
void srv_guard_conn_busy(srv_guard_conn *k);

/* The answer was sent (or the request ended otherwise): the connection
 * waits for a further request. */
void srv_guard_conn_idle(srv_guard_conn *k);

/* Asks for a lingering close of this connection (call while the request
 * is being refused, before its body was read). */
void srv_guard_conn_linger(srv_guard_conn *k);

/* Non-zero when the guard closed this connection because its body came
 * too slowly (for the access log: 408). */
int srv_guard_conn_too_slow(const srv_guard_conn *k);

/* Connections the guard closed, by reason, since it started. */
uint64_t srv_guard_closed(const srv_guard *g, srv_guard_reason why);

/* Connections open now. */
size_t srv_guard_open(const srv_guard *g);

/* New connections that have not yet made a request but may be about to:
 * they sent part of one, or are younger than `young_s` seconds. A
 * stopping daemon waits for these too (see srv_server_wait_idle). */
size_t srv_guard_pending(srv_guard *g, double young_s);

#endif /* VOR_SRV_GUARD_H */
