/* gzip.h -- response compression: does the client take gzip, and the
 * gzip encoding of a buffer (zlib). */
#ifndef VOR_SRV_GZIP_H
#define VOR_SRV_GZIP_H

#include <stddef.h>

/* Smallest body worth compressing. */
#define SRV_GZIP_MIN 1024

/* Non-zero when an Accept-Encoding value allows gzip: "gzip" or "x-gzip"
 * or "*" listed with q > 0, and gzip not refused by q=0. NULL: no. */
int srv_accepts_gzip(const char *accept_encoding);

/* Compresses in[0..n) into a new buffer *out (free with free()), *out_len
 * bytes, gzip format, zlib level 1..9. 0 on success; -1 on failure
 * (allocation), with *out NULL. */
int srv_gzip(const void *in, size_t n, int level, char **out,
             size_t *out_len);

#endif /* VOR_SRV_GZIP_H */
