/* accesslog.h -- one line per request, logfmt style, on stderr.
 *
 *   time=2025-01-31T12:00:00.123Z method=POST path=/voronoi status=200
 *   bytes=5123 ms=4.210 algorithm=fortune points=1000 id=6f1c0b2a9d3e4f50
 *
 * (one line in reality). Values that could break the line (spaces, quotes,
 * control bytes from a hostile request) are quoted and escaped; long ones
 * are cut. Formatting is a pure function so it can be tested; writing is
 * one write(2) per line so that lines from several threads never mix.
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

#endif /* VOR_SRV_ACCESSLOG_H */
