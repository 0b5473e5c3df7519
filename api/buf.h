/* buf.h -- the codec's internal output primitives over api_buf.
 *
 * Writers of large documents reserve room once per item with
 * api__buf_reserve() and then append with the unchecked api__put*()
 * helpers, so the inner loops carry no per-byte bounds checks. The amount
 * reserved must cover everything appended before the next reserve: numbers
 * take at most API_NUM_MAXLEN bytes (doubles, or "null" for a non-finite
 * one) and 11 bytes (32-bit integers). Growth is geometric, so appending n
 * bytes costs O(n) amortised. */
#ifndef VOR_API_BUF_H
#define VOR_API_BUF_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "api.h"
#include "numconv.h"

/* Ensures room for extra more bytes plus a terminator. 0 on success; -1
 * (b->oom set, contents kept) if memory runs out or b->oom was already
 * set. */
int api__buf_reserve(api_buf *b, size_t extra);

/* api__buf_reserve with the common case (room already there) inline. */
static inline int api__reserve(api_buf *b, size_t extra) {
    if (!b->oom && b->cap - b->len > extra) return 0;
    return api__buf_reserve(b, extra);
}

static inline void api__put(api_buf *b, const char *s, size_t n) {
    memcpy(b->data + b->len, s, n);
    b->len += n;
}

#define API__PUTS(b, lit) api__put((b), (lit), sizeof(lit) - 1)
/* Checked append of a string literal (reserves; records oom). */
#define API_BUF_LIT(b, lit) api_buf_append((b), (lit), sizeof(lit) - 1)

static inline void api__putc(api_buf *b, char c) { b->data[b->len++] = c; }

extern const char api__digit_pairs[201];

/* Decimal digits of v at buf (at most 10 bytes); returns the length. */
static inline size_t api__fmt_u32(uint32_t v, char *buf) {
    size_t n = v < 10 ? 1 : v < 100 ? 2 : v < 1000 ? 3 : v < 10000 ? 4
             : v < 100000 ? 5 : v < 1000000 ? 6 : v < 10000000 ? 7
             : v < 100000000 ? 8 : v < 1000000000 ? 9 : 10;
    char *p = buf + n;
    while (v >= 100) {
        uint32_t r = v % 100;
        v /= 100;
        p -= 2;
        memcpy(p, api__digit_pairs + 2 * r, 2);
    }
    if (v >= 10) {
        p -= 2;
        memcpy(p, api__digit_pairs + 2 * v, 2);
    } else {
        *--p = (char)('0' + v);
    }
    return n;
}

static inline void api__put_u32(api_buf *b, uint32_t v) {
    b->len += api__fmt_u32(v, b->data + b->len);
}

static inline void api__put_i32(api_buf *b, int32_t v) {
    if (v < 0) {
        api__putc(b, '-');
        api__put_u32(b, (uint32_t)0 - (uint32_t)v);
    } else {
        api__put_u32(b, (uint32_t)v);
    }
}

/* Shortest round-trip form, or null when v is not finite (JSON has no
 * infinities; a Voronoi vertex can overflow for finite sites). */
static inline void api__put_double(api_buf *b, double v) {
    size_t n = api_num_format(v, b->data + b->len);
    if (n == 0) {
        API__PUTS(b, "null");
    } else {
        b->len += n;
    }
}

/* ---- Cursors ----------------------------------------------------------
 * The appends above read and write b->len around every byte, because a
 * store through a char pointer may change any object, b included. A
 * writer's inner loop instead takes a cursor (api__cur), appends through
 * it with the api__w*() helpers below, which return the advanced cursor,
 * and stores it back once (api__cur_end). The same reservation rule
 * holds: everything written must fit the room reserved before. */
static inline char *api__cur(const api_buf *b) { return b->data + b->len; }

static inline void api__cur_end(api_buf *b, char *w) {
    b->len = (size_t)(w - b->data);
}

static inline char *api__w(char *w, const char *s, size_t n) {
    memcpy(w, s, n);
    return w + n;
}

#define API__WLIT(w, lit) api__w((w), (lit), sizeof(lit) - 1)

static inline char *api__wc(char *w, char c) {
    *w = c;
    return w + 1;
}

static inline char *api__wu32(char *w, uint32_t v) {
    return w + api__fmt_u32(v, w);
}

/* Shortest round-trip form, or null when v is not finite. */
static inline char *api__wdouble(char *w, double v) {
    size_t n = api_num_format(v, w);
    if (n == 0) return API__WLIT(w, "null");
    return w + n;
}

/* Appends s as a JSON string literal (quotes, escapes; bytes >= 0x80 are
 * passed through, invalid UTF-8 is replaced by U+FFFD). Reserves itself;
 * -1 on allocation failure. */
int api__put_json_string(api_buf *b, const char *s);

/* Appends the bytes of s with the five XML special characters escaped.
 * Reserves itself; -1 on allocation failure. */
int api__put_xml_text(api_buf *b, const char *s);

/* Appends the first n bytes of s for a problem detail: printable ASCII kept,
 * anything else as \xNN, cut with "..." beyond max bytes. Writes into dst
 * (size dst_size, always terminated). */
void api__quote_excerpt(char *dst, size_t dst_size, const char *s, size_t n,
                        size_t max);

#endif /* VOR_API_BUF_H */
