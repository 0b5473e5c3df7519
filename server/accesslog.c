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
 *
 * srv_log batches the lines of all threads into one buffer written by a
 * background thread (see the section below), replacing a write(2) per
 * request -- about a tenth of the daemon's time on 10-point requests --
 * with one per batch.
 */
#include "accesslog.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "fmt.h"

#define VALUE_MAX 200

typedef struct line {
    char *p;
    size_t len, size;
} line;

/* Byte by byte on purpose: the pieces are short (a key, a number, a path),
 * and a memcpy whose size the compiler can bound here is inlined as
 * `rep movs`, whose start-up cost made this function half of the time of
 * a whole line. */
static void put_raw(line *l, const char *s, size_t n) {
    if (l->len + 2 >= l->size) return;                     /* room: \n\0 */
    if (n > l->size - l->len - 2) n = l->size - l->len - 2;
    char *w = l->p + l->len;
    for (size_t i = 0; i < n; i++) w[i] = s[i];
    l->len += n;
}

static void put_key(line *l, const char *key) {
    if (l->len > 0) put_raw(l, " ", 1);
    put_raw(l, key, strlen(key));
    put_raw(l, "=", 1);
}

/* Whether c may appear in a value without quotes: printable ASCII
 * except space, '"', '=' and '\\'. A table, because the common case
 * tests every byte of every value (a tenth of a line's cost as five
 * comparisons); NUL is not plain, so the copy loop below needs no test
 * of its own for the end of the string. */
#define P16 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1
static const unsigned char plain_byte[256] = {
    [0x21] = 1, [0x23] = 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, /* !, #../ */
    [0x30] = 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, [0x3e] = 1, 1, /* 0..? */
    [0x40] = P16,                                                  /* @..O */
    [0x50] = 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, [0x5d] = 1, 1, 1, /* P.._ */
    [0x60] = P16,                                                  /* `..o */
    [0x70] = 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,          /* p..~ */
};
#undef P16

static int plain(unsigned char c) { return plain_byte[c]; }

static void put_value(line *l, const char *key, const char *v) {
    if (v == NULL || *v == '\0') v = "-";
    put_key(l, key);
    /* The common case, a short plain value: copied as it is, in the same
     * pass that checks it. */
    size_t room = l->len + 2 < l->size ? l->size - l->len - 2 : 0;
    char *w = l->p + l->len;
    size_t i = 0;
    while (i <= VALUE_MAX && plain((unsigned char)v[i])) {
        if (i < room) w[i] = v[i];
        i++;
    }
    if (v[i] == '\0' && i <= VALUE_MAX) {
        l->len += i < room ? i : room;
        return;
    }
    /* Quoted and escaped, or cut. */
    char tmp[VALUE_MAX * 4 + 8];
    size_t k = 0, n = strlen(v);
    int quote = 0;
    for (i = 0; i < n; i++)
        if (!plain((unsigned char)v[i])) quote = 1;
    if (quote) tmp[k++] = '"';
    for (i = 0; i < n && i < VALUE_MAX; i++) {
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

/* ---- the buffered log ---------------------------------------------------
 *
 * Two buffers of LOG_CAP bytes: `buf` takes lines under `mu`; a flush swaps
 * it with `out` and writes `out` without holding `mu`, so appenders never
 * wait for the file. `write_mu` lets one flush run at a time, which keeps
 * batches (and so lines) in order. Lock order: write_mu, then mu; an
 * appender holds only mu. The writer thread sleeps on `cv` until a line
 * arrives, then waits delay_ms more (or until the buffer is half full) and
 * flushes. */

#define LOG_CAP (64 * 1024)

struct srv_log {
    int fd;
    int delay_ms;
    pthread_mutex_t mu;       /* buf, len, stop */
    pthread_mutex_t write_mu; /* out; one flush at a time */
    pthread_cond_t cv;        /* writer: a first line, half full, stop */
    char *buf, *out;
    size_t len;
    int stop;
    pthread_t thread;
};

static void write_all(int fd, const char *p, size_t n) {
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return; /* a log that cannot be written is not fatal */
        p += (size_t)w;
        n -= (size_t)w;
    }
}

void srv_log_flush(srv_log *l) {
    pthread_mutex_lock(&l->write_mu);
    pthread_mutex_lock(&l->mu);
    char *full = l->buf;
    size_t n = l->len;
    l->buf = l->out;
    l->len = 0;
    l->out = full;
    pthread_mutex_unlock(&l->mu);
    if (n > 0) write_all(l->fd, full, n);
    pthread_mutex_unlock(&l->write_mu);
}

static void *log_writer(void *arg) {
    srv_log *l = arg;
    pthread_mutex_lock(&l->mu);
    while (!l->stop) {
        if (l->len == 0) {
            pthread_cond_wait(&l->cv, &l->mu);
            continue;
        }
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += (long)l->delay_ms * 1000000L;
        until.tv_sec += until.tv_nsec / 1000000000L;
        until.tv_nsec %= 1000000000L;
        while (!l->stop && l->len < LOG_CAP / 2 &&
               pthread_cond_timedwait(&l->cv, &l->mu, &until) != ETIMEDOUT) {
        }
        pthread_mutex_unlock(&l->mu);
        srv_log_flush(l);
        pthread_mutex_lock(&l->mu);
    }
    pthread_mutex_unlock(&l->mu);
    return NULL;
}

srv_log *srv_log_new(int fd, int delay_ms) {
    srv_log *l = calloc(1, sizeof *l);
    if (l == NULL) return NULL;
    l->fd = fd;
    l->delay_ms = delay_ms < 1 ? 1 : delay_ms;
    l->buf = malloc(LOG_CAP);
    l->out = malloc(LOG_CAP);
    if (l->buf == NULL || l->out == NULL) goto fail_mem;
    if (pthread_mutex_init(&l->mu, NULL) != 0) goto fail_mem;
    if (pthread_mutex_init(&l->write_mu, NULL) != 0) goto fail_mu;
    if (pthread_cond_init(&l->cv, NULL) != 0) goto fail_write_mu;
    if (pthread_create(&l->thread, NULL, log_writer, l) != 0) goto fail_cv;
    return l;
fail_cv:
    pthread_cond_destroy(&l->cv);
fail_write_mu:
    pthread_mutex_destroy(&l->write_mu);
fail_mu:
    pthread_mutex_destroy(&l->mu);
fail_mem:
    free(l->buf);
    free(l->out);
    free(l);
    return NULL;
}

/* Appends n <= LOG_CAP bytes, flushing first when they do not fit. */
static void log_append(srv_log *l, const char *p, size_t n) {
    pthread_mutex_lock(&l->mu);
    while (LOG_CAP - l->len < n) { /* the writer is behind: catch up here */
        pthread_mutex_unlock(&l->mu);
        srv_log_flush(l);
        pthread_mutex_lock(&l->mu);
    }
    size_t before = l->len;
    memcpy(l->buf + before, p, n);
    l->len = before + n;
    /* Wake the writer for a first line (it sleeps without a deadline) and
     * when half full (it should not wait for its deadline). */
    if (before == 0 || (before < LOG_CAP / 2 && l->len >= LOG_CAP / 2))
        pthread_cond_signal(&l->cv);
    pthread_mutex_unlock(&l->mu);
}

void srv_log_access(srv_log *l, const srv_access *a) {
    char text[SRV_ACCESS_LINE_MAX];
    size_t n = srv_access_format(a, text, sizeof text);
    log_append(l, text, n);
}

void srv_log_text(srv_log *l, const char *text, size_t n) {
    while (n > 0) {
        size_t k = n < LOG_CAP ? n : LOG_CAP;
        log_append(l, text, k);
        text += k;
        n -= k;
    }
    srv_log_flush(l);
}

void srv_log_free(srv_log *l) {
    if (l == NULL) return;
    pthread_mutex_lock(&l->mu);
    l->stop = 1;
    pthread_cond_signal(&l->cv);
    pthread_mutex_unlock(&l->mu);
    pthread_join(l->thread, NULL);
    srv_log_flush(l);
    pthread_cond_destroy(&l->cv);
    pthread_mutex_destroy(&l->write_mu);
    pthread_mutex_destroy(&l->mu);
    free(l->buf);
    free(l->out);
    free(l);
}
