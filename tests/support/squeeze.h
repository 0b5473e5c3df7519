/* squeeze.h -- request bodies compressed for the tests of decoded bodies
 * (the server's decoder and the daemon's framing): zlib at level 9 in
 * one of the three wrappings a Content-Encoding can name. Include after
 * cmocka.h. */
#ifndef VT_SQUEEZE_H
#define VT_SQUEEZE_H

#include <stdlib.h>
#include <string.h>
#include <zlib.h>

/* in compressed: format 0 gzip, 1 zlib, 2 raw deflate. The caller frees
 * the result; *out_len is its length. */
static inline unsigned char *vt_squeeze(const void *in, size_t n, int format,
                                        size_t *out_len) {
    z_stream z;
    memset(&z, 0, sizeof z);
    int bits = format == 0 ? 15 + 16 : format == 1 ? 15 : -15;
    assert_int_equal(deflateInit2(&z, 9, Z_DEFLATED, bits, 8,
                                  Z_DEFAULT_STRATEGY), Z_OK);
    size_t cap = deflateBound(&z, (uLong)n) + 64;
    unsigned char *out = malloc(cap);
    assert_non_null(out);
    z.next_in = (Bytef *)in;
    z.avail_in = (uInt)n;
    z.next_out = out;
    z.avail_out = (uInt)cap;
    assert_int_equal(deflate(&z, Z_FINISH), Z_STREAM_END);
    *out_len = z.total_out;
    deflateEnd(&z);
    return out;
}

#endif
