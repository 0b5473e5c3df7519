/* accesslog.h -- one line per request, logfmt style, on stderr.
 *
 *   time=2025-01-31T12:00:00.123Z method=POST path=/voronoi status=200
 *   bytes=5123 ms=4.210 algorithm=fortune points=1000 id=6f1c0b2a9d3e4f50
 *
 * (one line in reality). Values that could break the line (spaces, quotes,
 * control bytes from a hostile request) are quoted and escaped; long ones
 * are cut. Formatting is a pure function so it can be tested.
 *
 * Writing: srv_access_write is one write(2) per line. The daemon uses an
 * srv_log instead: every thread appends its lines to one shared buffer,
 * and a background thread writes the buffer out in one write(2) at most
 * delay_ms after a line went in (sooner when the buffer is half full), so
 * a busy daemon does one write per few hundred requests rather than one
 * per request. Lines stay whole and in the order they were appended;
 * srv_log_flush and srv_log_free write out everything pending, so no line
 * is lost on an orderly exit (a crash loses at most delay_ms of lines).
 */
#ifndef VOR_SRV_ACCESSLOG_H
#define VOR_SRV_ACCESSLOG_H

#include <stddef.h>

typedef struct srv_access {
    double unix_time;       /* when the request arrived, seconds since 1970 */
    const char *method;
    const char *path;
    int status;             /* 0: no answer was sent */
    size_t bytes;           /* response body bytes (as sent, compressed) */
    double ms;              /* arrival to answer */
    const char *algorithm;  /* NULL when not a computation */
    long long points;       /* < 0 when unknown */
    const char *request_id;
    const char *note;       /* NULL, or why there was no answer */
} srv_access;

/* Longest line srv_access_format writes, newline included. */
#define SRV_ACCESS_LINE_MAX 1024

/* Writes the line (ending in '\n', NUL-terminated) into out, which has
 * room for size >= SRV_ACCESS_LINE_MAX bytes; returns its length. */
size_t srv_access_format(const srv_access *a, char *out, size_t size);

/* Formats and writes the line to fd in one write. */
void srv_access_write(int fd, const srv_access *a);

typedef struct srv_log srv_log;

/* A buffered log writing to fd (not closed by srv_log_free); lines wait at
 * most delay_ms (>= 1) before they are written. NULL when memory or the
 * writer thread cannot be had. */
srv_log *srv_log_new(int fd, int delay_ms);

/* Formats a's line and appends it. Thread-safe; does not block on the
 * file except when the buffer is full (the writer is behind). */
void srv_log_access(srv_log *l, const srv_access *a);

/* Appends n bytes of text (whole lines, each ending in '\n') and writes
 * out everything pending at once: for messages that should not wait. */
void srv_log_text(srv_log *l, const char *text, size_t n);

/* Writes out every line appended before the call. */
void srv_log_flush(srv_log *l);

/* Flushes, stops the writer thread, frees. srv_log_free(NULL) is a no-op. */
void srv_log_free(srv_log *l);

#endif /* VOR_SRV_ACCESSLOG_H */
