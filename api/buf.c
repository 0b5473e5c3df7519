/* buf.c -- api_buf, the growable output buffer, and the escaping and
 * integer formatting the writers share.
 *
 * The buffer is one malloc'd array, grown by doubling (realloc), always
 * NUL-terminated after len so callers can treat small outputs as strings.
 * A failed growth sets oom and keeps what was written; every later append
 * fails too, so a writer may check once at the end. Cost: amortised O(1) a
 * byte. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "buf.h"

void api_buf_init(api_buf *b) { memset(b, 0, sizeof *b); }

void api_buf_clear(api_buf *b) {
    free(b->data);
    memset(b, 0, sizeof *b);
}

char *api_buf_take(api_buf *b, size_t *len) {
    char *d = b->data;
    if (len) *len = b->len;
    memset(b, 0, sizeof *b);
    return d;
}

/* Hands what the buffer holds to its flush hook (api.h); -1 (oom set)
 * when the hook refuses. */
static int flush_out(api_buf *b) {
    size_t give = b->len & ~(size_t)7;
    if (give == 0) return 0;
    if (b->flush(b->flush_ctx, b->data, give) != 0) {
        b->oom = 1;
        return -1;
    }
    memmove(b->data, b->data + give, b->len - give);
    b->len -= give;
    b->data[b->len] = 0;
    return 0;
}

int api__buf_reserve(api_buf *b, size_t extra) {
    if (b->oom) return -1;
    if (extra <= b->cap - b->len && b->cap - b->len - extra >= 1) return 0;
    if (b->flush != NULL && b->len >= b->flush_at) {
        if (flush_out(b)) return -1;
        if (extra <= b->cap - b->len && b->cap - b->len - extra >= 1)
            return 0;
    }
    size_t need = b->len + extra + 1;
    if (need < b->len) { /* overflow */
        b->oom = 1;
        return -1;
    }
    size_t cap = b->cap ? b->cap : 256;
    while (cap < need) {
        if (cap > SIZE_MAX / 2) {
            cap = need;
            break;
        }
        cap *= 2;
    }
    char *d = realloc(b->data, cap);
    if (d == NULL) {
        b->oom = 1;
        return -1;
    }
    b->data = d;
    b->cap = cap;
    return 0;
}

int api_buf_append(api_buf *b, const void *data, size_t n) {
    if (api__buf_reserve(b, n)) return -1;
    if (n) api__put(b, data, n);
    b->data[b->len] = 0;
    return 0;
}

int api_buf_printf(api_buf *b, const char *fmt, ...) {
    va_list ap;
    char small[256];
    va_start(ap, fmt);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (n < 0) {
        b->oom = 1;
        return -1;
    }
    if ((size_t)n < sizeof small) return api_buf_append(b, small, (size_t)n);
    if (api__buf_reserve(b, (size_t)n)) return -1;
    va_start(ap, fmt);
    vsnprintf(b->data + b->len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    b->len += (size_t)n;
    return 0;
}

const char api__digit_pairs[201] =
    "0001020304050607080910111213141516171819"
    "2021222324252627282930313233343536373839"
    "4041424344454647484950515253545556575859"
    "6061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

/* Length of the valid UTF-8 sequence at s (1..4), or 0 if invalid. */
static size_t utf8_len(const unsigned char *s) {
    unsigned c = s[0];
    if (c < 0x80) return 1;
    size_t n;
    unsigned min;
    if ((c & 0xe0) == 0xc0) { n = 2; min = 0x80; c &= 0x1f; }
    else if ((c & 0xf0) == 0xe0) { n = 3; min = 0x800; c &= 0x0f; }
    else if ((c & 0xf8) == 0xf0) { n = 4; min = 0x10000; c &= 0x07; }
    else return 0;
    for (size_t i = 1; i < n; i++) {
        if ((s[i] & 0xc0) != 0x80) return 0;
        c = (c << 6) | (s[i] & 0x3f);
    }
    if (c < min || c > 0x10ffff || (c >= 0xd800 && c <= 0xdfff)) return 0;
    return n;
}

int api__put_json_string(api_buf *b, const char *s) {
    size_t n = strlen(s);
    /* Worst case: every byte becomes \u00XX (6) or U+FFFD (3). */
    if (n > (SIZE_MAX - 2) / 6 || api__buf_reserve(b, 6 * n + 2)) return -1;
    api__putc(b, '"');
    const unsigned char *p = (const unsigned char *)s;
    while (*p) {
        unsigned c = *p;
        if (c >= 0x80) {
            size_t k = utf8_len(p);
            if (k == 0) {
                API__PUTS(b, "\xef\xbf\xbd");
                p++;
            } else {
                api__put(b, (const char *)p, k);
                p += k;
            }
            continue;
        }
        p++;
        switch (c) {
        case '"': API__PUTS(b, "\\\""); break;
        case '\\': API__PUTS(b, "\\\\"); break;
        case '\n': API__PUTS(b, "\\n"); break;
        case '\r': API__PUTS(b, "\\r"); break;
        case '\t': API__PUTS(b, "\\t"); break;
        default:
            if (c < 0x20 || c == 0x7f) {
                char esc[7];
                snprintf(esc, sizeof esc, "\\u%04x", c);
                api__put(b, esc, 6);
            } else {
                api__putc(b, (char)c);
            }
        }
    }
    api__putc(b, '"');
    b->data[b->len] = 0;
    return 0;
}

int api__put_xml_text(api_buf *b, const char *s) {
    size_t n = strlen(s);
    if (n > SIZE_MAX / 6 || api__buf_reserve(b, 6 * n)) return -1;
    for (; *s; s++) {
        switch (*s) {
        case '<': API__PUTS(b, "&lt;"); break;
        case '>': API__PUTS(b, "&gt;"); break;
        case '&': API__PUTS(b, "&amp;"); break;
        case '"': API__PUTS(b, "&quot;"); break;
        case '\'': API__PUTS(b, "&#39;"); break;
        default: api__putc(b, *s);
        }
    }
    b->data[b->len] = 0;
    return 0;
}

void api__quote_excerpt(char *dst, size_t dst_size, const char *s, size_t n,
                        size_t max) {
    size_t o = 0;
    if (dst_size == 0) return;
    int cut = n > max;
    if (cut) n = max;
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        char tmp[5];
        size_t k;
        if (c >= 0x20 && c < 0x7f) {
            tmp[0] = (char)c;
            k = 1;
        } else {
            snprintf(tmp, sizeof tmp, "\\x%02x", c);
            k = 4;
        }
        if (o + k + 4 >= dst_size) {
            cut = 1;
            break;
        }
        memcpy(dst + o, tmp, k);
        o += k;
    }
    if (cut && o + 3 < dst_size) {
        memcpy(dst + o, "...", 3);
        o += 3;
    }
    dst[o] = 0;
}
