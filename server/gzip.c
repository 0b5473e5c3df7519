/* gzip.c -- Accept-Encoding negotiation and one-shot gzip.
 *
 * srv_accepts_gzip parses the comma-separated codings with their q values
 * (RFC 9110 section 12.5.3), case-insensitively; an explicit gzip entry wins
 * over "*". srv_gzip sizes the output with deflateBound so one deflate call
 * finishes; cost O(n), memory about n plus zlib's ~256 KiB state.
 */
#include "gzip.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <zlib.h>

/* q value of the parameters after a coding ("; q=0.5"); 1 if absent. */
static double q_value(const char *p, const char *end) {
    while (p < end) {
        while (p < end && (*p == ';' || *p == ' ' || *p == '\t')) p++;
        if (end - p >= 2 && (p[0] == 'q' || p[0] == 'Q') && p[1] == '=') {
            char tmp[16];
            size_t n = 0;
            p += 2;
            while (p < end && n + 1 < sizeof tmp && *p != ';' && *p != ' ')
                tmp[n++] = *p++;
            tmp[n] = '\0';
            char *e;
            double q = strtod(tmp, &e);
            if (e == tmp || *e != '\0' || !(q >= 0) || q > 1) return 0;
            return q;
        }
        while (p < end && *p != ';') p++;
    }
    return 1;
}

int srv_accepts_gzip(const char *ae) {
    double gzip_q = -1, star_q = -1;
    if (ae == NULL) return 0;
    const char *p = ae;
    while (*p) {
        while (*p == ' ' || *p == '\t' || *p == ',') p++;
        const char *start = p;
        while (*p && *p != ',') p++;
        const char *end = p;
        const char *name_end = start;
        while (name_end < end && *name_end != ';' && *name_end != ' ' &&
               *name_end != '\t')
            name_end++;
        size_t len = (size_t)(name_end - start);
        if (len == 0) continue;
        double q = q_value(name_end, end);
        if ((len == 4 && strncasecmp(start, "gzip", 4) == 0) ||
            (len == 6 && strncasecmp(start, "x-gzip", 6) == 0))
            gzip_q = q;
        else if (len == 1 && *start == '*')
            star_q = q;
    }
    if (gzip_q >= 0) return gzip_q > 0;
    return star_q > 0;
}

int srv_gzip(const void *in, size_t n, int level, char **out,
             size_t *out_len) {
    z_stream z;
    *out = NULL;
    *out_len = 0;
    if (level < 1) level = 1;
    if (level > 9) level = 9;
    memset(&z, 0, sizeof z);
    if (deflateInit2(&z, level, Z_DEFLATED, 15 + 16, 8,
                     Z_DEFAULT_STRATEGY) != Z_OK)
        return -1;
    /* deflateBound takes uLong; feed in pieces of at most 1 GiB. */
    size_t cap = (size_t)deflateBound(&z, (uLong)(n > 0x40000000u ? 0x40000000u : n));
    if (n > 0x40000000u) cap = n + n / 8 + 1024;
    char *buf = malloc(cap);
    if (buf == NULL) {
        deflateEnd(&z);
        return -1;
    }
    const unsigned char *src = in;
    size_t left = n;
    int rc;
    do {
        uInt chunk = left > 0x40000000u ? 0x40000000u : (uInt)left;
        z.next_in = (Bytef *)(uintptr_t)src;
        z.avail_in = chunk;
        src += chunk;
        left -= chunk;
        for (;;) {
            if (z.total_out >= cap) {
                size_t ncap = cap * 2;
                char *nb = realloc(buf, ncap);
                if (nb == NULL) {
                    free(buf);
                    deflateEnd(&z);
                    return -1;
                }
                buf = nb;
                cap = ncap;
            }
            size_t room = cap - (size_t)z.total_out;
            z.next_out = (Bytef *)buf + z.total_out;
            z.avail_out = room > 0x40000000u ? 0x40000000u : (uInt)room;
            rc = deflate(&z, left == 0 ? Z_FINISH : Z_NO_FLUSH);
            if (rc == Z_STREAM_ERROR) {
                free(buf);
                deflateEnd(&z);
                return -1;
            }
            if (left == 0 ? rc == Z_STREAM_END : z.avail_in == 0) break;
        }
    } while (left > 0);
    *out_len = (size_t)z.total_out;
    *out = buf;
    deflateEnd(&z);
    return 0;
}
