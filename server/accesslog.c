/* accesslog.c -- formatting and writing access-log lines.
 *
 * Each value goes through put_value(): bare when it is plain printable
 * ASCII without spaces, quotes or '=', otherwise in double quotes with
 * \" \\ and \xNN escapes; any value is cut at 200 bytes (marked "..."), so
 * a line never exceeds SRV_ACCESS_LINE_MAX. O(line length).
 *
 * A line is written for every request, so the common case is kept cheap:
 * plain values are copied as they are, numbers go through fmt.h instead of
 * printf, and each thread keeps the date and time of the last second it
 * formatted (gmtime_r once a second, not once a line).
 */
#include "accesslog.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "fmt.h"

#define VALUE_MAX 200

typedef struct line {
    char *p;
    size_t len, size;
} line;

static void put_raw(line *l, const char *s, size_t n) {
    if (l->len + 2 >= l->size) return;                     /* room: \n\0 */
    if (n > l->size - l->len - 2) n = l->size - l->len - 2;
    memcpy(l->p + l->len, s, n);
    l->len += n;
}

static void put_key(line *l, const char *key) {
    if (l->len > 0) put_raw(l, " ", 1);
    put_raw(l, key, strlen(key));
    put_raw(l, "=", 1);
}

static void put_value(line *l, const char *key, const char *v) {
    char tmp[VALUE_MAX * 4 + 8];
    size_t k = 0;
    int quote = 0;
    if (v == NULL || *v == '\0') v = "-";
    size_t n = strlen(v);
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)v[i];
        if (c <= ' ' || c >= 0x7f || c == '"' || c == '=' || c == '\\')
            quote = 1;
    }
    if (!quote && n <= VALUE_MAX) { /* the common case: as it is */
        put_key(l, key);
        put_raw(l, v, n);
        return;
    }
    if (quote) tmp[k++] = '"';
    for (size_t i = 0; i < n && i < VALUE_MAX; i++) {
        unsigned char c = (unsigned char)v[i];
        if (c == '"' || c == '\\') {
            tmp[k++] = '\\';
            tmp[k++] = (char)c;
        } else if (c < ' ' || c >= 0x7f) {
            k += (size_t)snprintf(tmp + k, sizeof tmp - k, "\\x%02x", c);
        } else {
            tmp[k++] = (char)c;
        }
    }
    if (n > VALUE_MAX) {
        memcpy(tmp + k, "...", 3);
        k += 3;
    }
    if (quote) tmp[k++] = '"';
    put_key(l, key);
    put_raw(l, tmp, k);
}

/* A number, or "-" when absent. */
static void put_count(line *l, const char *key, int present, uint64_t v) {
    char num[24];
    put_key(l, key);
    if (present) put_raw(l, num, srv_fmt_u64(num, v));
    else put_raw(l, "-", 1);
}

/* "2025-01-31T12:00:00" of secs into out (room for 64 bytes, NUL
 * included); the last second formatted is kept per thread. */
static void stamp_seconds(time_t secs, char out[64]) {
    static _Thread_local int cached_ok;
    static _Thread_local time_t cached_secs;
    static _Thread_local char cached[64];
    if (!cached_ok || secs != cached_secs) {
        struct tm tm;
        gmtime_r(&secs, &tm);
        snprintf(cached, sizeof cached, "%04d-%02d-%02dT%02d:%02d:%02d",
                 tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour,
                 tm.tm_min, tm.tm_sec);
        cached_secs = secs;
        cached_ok = 1;
    }
    memcpy(out, cached, sizeof cached);
}

size_t srv_access_format(const srv_access *a, char *out, size_t size) {
    line l = {out, 0, size};
    char num[SRV_FMT_MS3_MAX];
    if (size < 2) {
        if (size) out[0] = '\0';
        return 0;
    }

    double t = a->unix_time;
    time_t secs = (time_t)floor(t);
    int ms = (int)((t - floor(t)) * 1000.0);
    if (ms > 999) ms = 999;
    char stamp[96];
    stamp_seconds(secs, stamp);
    size_t k = strlen(stamp);
    stamp[k++] = '.';
    stamp[k++] = (char)('0' + ms / 100);
    stamp[k++] = (char)('0' + ms / 10 % 10);
    stamp[k++] = (char)('0' + ms % 10);
    stamp[k++] = 'Z';
    stamp[k] = '\0';
    put_value(&l, "time", stamp);
    put_value(&l, "method", a->method);
    put_value(&l, "path", a->path);
    put_count(&l, "status", a->status > 0, (uint64_t)a->status);
    put_count(&l, "bytes", 1, (uint64_t)a->bytes);
    put_key(&l, "ms");
    put_raw(&l, num, srv_fmt_ms3(num, a->ms));
    put_value(&l, "algorithm", a->algorithm);
    put_count(&l, "points", a->points >= 0, (uint64_t)a->points);
    put_value(&l, "id", a->request_id);
    if (a->note != NULL) put_value(&l, "note", a->note);
    out[l.len++] = '\n';
    out[l.len] = '\0';
    return l.len;
}

void srv_access_write(int fd, const srv_access *a) {
    char buf[SRV_ACCESS_LINE_MAX];
    size_t n = srv_access_format(a, buf, sizeof buf);
    size_t off = 0;
    while (off < n) {
        ssize_t w = write(fd, buf + off, n - off);
        if (w <= 0) return; /* a log that cannot be written is not fatal */
        off += (size_t)w;
    }
}
