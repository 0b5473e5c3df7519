/* decode.c -- Content-Encoding gzip and deflate for request bodies (the
 * contract is in decode.h).
 *
 * One zlib inflate stream: gzip with windowBits 15+16; deflate as the
 * zlib format when the first two bytes are a zlib header (RFC 1950: CM 8,
 * the pair a multiple of 31), else as raw deflate (windowBits -15), which
 * some clients send under that name. A gzip stream that ends with more
 * input behind it starts over (concatenated members are one body, RFC
 * 1952). Output goes through a 16 KiB buffer to the sink, and stops once
 * `limit` bytes were handed out. O(output).
 */
#include "decode.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <zlib.h>

struct srv_decoder {
    z_stream z;
    srv_coding coding;
    int started;        /* inflateInit2 done */
    int ended;          /* the last stream ended, nothing after it yet */
    unsigned char head[2];
    size_t n_head;      /* deflate: bytes kept to tell zlib from raw */
    size_t limit, out;
    char error[160];
};

srv_coding srv_coding_of(const char *ce) {
    if (ce == NULL) return SRV_CODING_IDENTITY;
    while (*ce == ' ' || *ce == '\t') ce++;
    size_t n = strlen(ce);
    while (n > 0 && (ce[n - 1] == ' ' || ce[n - 1] == '\t')) n--;
    if (n == 0 || (n == 8 && strncasecmp(ce, "identity", 8) == 0))
        return SRV_CODING_IDENTITY;
    if ((n == 4 && strncasecmp(ce, "gzip", 4) == 0) ||
        (n == 6 && strncasecmp(ce, "x-gzip", 6) == 0))
        return SRV_CODING_GZIP;
    if (n == 7 && strncasecmp(ce, "deflate", 7) == 0)
        return SRV_CODING_DEFLATE;
    return SRV_CODING_UNKNOWN;
}

srv_decoder *srv_decoder_new(srv_coding coding, size_t limit) {
    if (coding != SRV_CODING_GZIP && coding != SRV_CODING_DEFLATE)
        return NULL;
    srv_decoder *d = calloc(1, sizeof *d);
    if (d == NULL) return NULL;
    d->coding = coding;
    d->limit = limit;
    return d;
}

void srv_decoder_free(srv_decoder *d) {
    if (d == NULL) return;
    if (d->started) inflateEnd(&d->z);
    free(d);
}

size_t srv_decoder_out(const srv_decoder *d) { return d->out; }

const char *srv_decoder_error(const srv_decoder *d) { return d->error; }

static int corrupt(srv_decoder *d, const char *what) {
    snprintf(d->error, sizeof d->error, "%s", what);
    return SRV_DECODE_CORRUPT;
}

static int start(srv_decoder *d, int raw) {
    int bits = d->coding == SRV_CODING_GZIP ? 15 + 16 : raw ? -15 : 15;
    if (inflateInit2(&d->z, bits) != Z_OK) return SRV_DECODE_NOMEM;
    d->started = 1;
    return SRV_DECODE_OK;
}

/* Runs inflate over in[0..n), handing output to sink. */
static int inflate_some(srv_decoder *d, const unsigned char *in, size_t n,
                        srv_decode_sink sink, void *ctx) {
    unsigned char buf[16384];
    while (n > 0) {
        if (d->ended) {
            /* Bytes after the end of a stream: another gzip member, or
             * garbage. */
            if (d->coding != SRV_CODING_GZIP)
                return corrupt(d, "data after the end of the deflate stream");
            if (inflateReset(&d->z) != Z_OK)
                return corrupt(d, "cannot restart the gzip stream");
            d->ended = 0;
        }
        uInt chunk = n > 0x40000000u ? 0x40000000u : (uInt)n;
        d->z.next_in = (Bytef *)in;
        d->z.avail_in = chunk;
        int rc;
        do {
            d->z.next_out = buf;
            d->z.avail_out = sizeof buf;
            rc = inflate(&d->z, Z_NO_FLUSH);
            if (rc == Z_NEED_DICT || rc == Z_DATA_ERROR || rc == Z_STREAM_ERROR)
                return corrupt(d, d->z.msg ? d->z.msg : "bad data");
            if (rc == Z_MEM_ERROR) return SRV_DECODE_NOMEM;
            size_t got = sizeof buf - d->z.avail_out;
            if (got > 0) {
                if (got > d->limit - d->out) return SRV_DECODE_LIMIT;
                d->out += got;
                if (sink(ctx, (const char *)buf, got) != 0)
                    return SRV_DECODE_NOMEM;
            }
        } while (rc == Z_OK && (d->z.avail_in > 0 || d->z.avail_out == 0));
        size_t used = chunk - d->z.avail_in;
        if (rc == Z_STREAM_END) d->ended = 1;
        else if (used == 0) break; /* no progress: wait for more input */
        in += used;
        n -= used;
    }
    return SRV_DECODE_OK;
}

int srv_decoder_feed(srv_decoder *d, const char *in, size_t n,
                     srv_decode_sink sink, void *ctx) {
    const unsigned char *u = (const unsigned char *)in;
    if (!d->started) {
        if (d->coding == SRV_CODING_DEFLATE) {
            /* Keep the first two bytes to tell zlib's format from raw
             * deflate. */
            while (d->n_head < 2 && n > 0) {
                d->head[d->n_head++] = *u++;
                n--;
            }
            if (d->n_head < 2) return SRV_DECODE_OK;
            int zlib = (d->head[0] & 0x0f) == 8 &&
                       ((d->head[0] << 8) | d->head[1]) % 31 == 0;
            int rc = start(d, !zlib);
            if (rc == SRV_DECODE_OK)
                rc = inflate_some(d, d->head, 2, sink, ctx);
            if (rc != SRV_DECODE_OK) return rc;
        } else {
            int rc = start(d, 0);
            if (rc != SRV_DECODE_OK) return rc;
        }
    }
    return n > 0 ? inflate_some(d, u, n, sink, ctx) : SRV_DECODE_OK;
}

int srv_decoder_finish(srv_decoder *d) {
    if (!d->started && d->n_head == 0)
        return corrupt(d, "the body is empty");
    if (!d->ended) return corrupt(d, "the compressed data ends early");
    return SRV_DECODE_OK;
}
