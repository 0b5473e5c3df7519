/* stream.h -- large answers produced as the socket drains.
 *
 * A diagram of 10^6 points is about 300 MB of JSON. Written whole before
 * the first byte goes out, it sat in memory until the client had read it
 * all -- or, for a client that never reads, until the connection timed
 * out; a dozen such clients took gigabytes. A stream instead keeps the
 * computed result (about half that size) and serialises it in chunks of
 * SRV_STREAM_CHUNK bytes, each only once the client has taken the one
 * before: libmicrohttpd's callback response pulls the bytes, a writer
 * thread of the stream's own runs the codec's writer (api_write_result)
 * with a flush hook on its buffer, compresses (gzip) when the client takes
 * it, and hands over one chunk at a time. The result is freed as soon as
 * the last chunk is made; everything the stream holds is accounted in the
 * answer budget (budget.h) and given back when libmicrohttpd lets go of
 * the response: on completion, when the client goes away, when it stops
 * reading past --send-timeout, or at shutdown.
 *
 * The body has no Content-Length (chunked transfer coding); its last
 * member is the timings, whose serialize_ms counts from the first byte
 * written to the last, client's reading included. A writer that fails
 * (out of memory) ends the stream with an error: libmicrohttpd closes the
 * connection without the final chunk, so the client sees a truncated
 * answer, never a wrong one.
 *
 * Threads: the writer thread produces, the connection's thread consumes
 * in libmicrohttpd's content reader callback; one mutex and one condition
 * variable per stream. When the consumer finds no chunk ready it suspends
 * its connection (libmicrohttpd allows that from the content reader) and
 * the writer resumes it with the next chunk. Lock order: the stream's
 * lock, then libmicrohttpd's (suspend, resume).
 */
#ifndef VOR_SRV_STREAM_H
#define VOR_SRV_STREAM_H

#include <microhttpd.h>
#include <stddef.h>

#include "../api/api.h"
#include "budget.h"

/* Answers estimated larger than this are streamed; smaller ones are
 * written whole, which costs less. */
#define SRV_STREAM_MIN_ANSWER ((size_t)1 << 20)
/* Bytes handed to libmicrohttpd at a time. */
#define SRV_STREAM_CHUNK ((size_t)256 << 10)
/* What a stream holds besides its result: its buffers and zlib's state. */
#define SRV_STREAM_OVERHEAD ((size_t)2 << 20)

typedef struct srv_stream srv_stream;
typedef struct srv_streams srv_streams;

/* The streams of one service, for its shutdown. NULL when out of memory. */
srv_streams *srv_streams_new(void);

/* Ends every stream (their connections get a truncated answer) and waits
 * until every writer thread has finished. Before MHD_stop_daemon. */
void srv_streams_stop(srv_streams *g);

/* After srv_streams_stop, and after libmicrohttpd freed every response. */
void srv_streams_free(srv_streams *g);

/* Bytes the result of res holds (its arrays). */
size_t srv_result_bytes(const api_result *res);

/* A stream of r's answer from res: r and res are moved into it (left
 * empty); t is copied. `held` bytes of the budget b now belong to the
 * stream and are given back as it frees what they stand for. gzip:
 * compress the answer. NULL when out of memory (r, res untouched; the
 * caller still owns `held`). */
srv_stream *srv_stream_new(srv_streams *g, srv_budget *b, api_request *r,
                           api_result *res, const api_timings *t, int gzip,
                           size_t held);

/* A stream that will not be sent: frees it and gives its bytes back. */
void srv_stream_discard(srv_stream *st);

/* Starts the writer and returns the response to queue on conn (with
 * Content-Type set; Content-Encoding too when compressed). NULL on
 * failure: the stream is freed. *sent (the request's count of body bytes,
 * for the access log) grows by every byte handed to libmicrohttpd, as
 * sent (compressed when gzip); libmicrohttpd asks for them only while the
 * request is alive, on its own thread. */
struct MHD_Response *srv_stream_start(srv_stream *st,
                                      struct MHD_Connection *conn,
                                      size_t *sent);

#endif /* VOR_SRV_STREAM_H */
