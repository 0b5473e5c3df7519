/* decode.h -- request bodies sent with a Content-Encoding: gzip or
 * deflate, decoded as they arrive (zlib).
 *
 * The limits of the service apply to what the body decodes to: the
 * decoder hands out at most `limit` decoded bytes and then says so, so a
 * small compressed body that would expand to gigabytes (a "bomb") costs
 * the service at most `limit` bytes of output and the time to produce
 * them. Memory: zlib's inflate state, about 40 KiB.
 */
#ifndef VOR_SRV_DECODE_H
#define VOR_SRV_DECODE_H

#include <stddef.h>

typedef enum srv_coding {
    SRV_CODING_IDENTITY, /* none, or "identity" */
    SRV_CODING_GZIP,     /* gzip, x-gzip (RFC 1952; members may follow
                            one another) */
    SRV_CODING_DEFLATE,  /* deflate: zlib format (RFC 1950), or raw deflate
                            as some clients send it */
    SRV_CODING_UNKNOWN   /* anything else, or several codings */
} srv_coding;

/* The coding named by a Content-Encoding value (NULL: identity); case
 * and surrounding blanks do not matter. */
srv_coding srv_coding_of(const char *content_encoding);

typedef struct srv_decoder srv_decoder;

/* Outcome of srv_decoder_feed and srv_decoder_finish. */
enum {
    SRV_DECODE_OK = 0,
    SRV_DECODE_LIMIT = 1,   /* the output would pass `limit` bytes */
    SRV_DECODE_CORRUPT = 2, /* not valid data of the coding (message set) */
    SRV_DECODE_NOMEM = 3
};

/* A decoder for coding (GZIP or DEFLATE) that hands out at most limit
 * bytes. NULL when out of memory. */
srv_decoder *srv_decoder_new(srv_coding coding, size_t limit);
void srv_decoder_free(srv_decoder *d);

/* Called with each decoded piece: 0 to go on, non-zero to stop (the feed
 * then returns SRV_DECODE_NOMEM). */
typedef int (*srv_decode_sink)(void *ctx, const char *data, size_t n);

/* Decodes n more bytes of the encoded body, passing the output to sink.
 * After an outcome other than OK, the decoder must not be fed again. */
int srv_decoder_feed(srv_decoder *d, const char *in, size_t n,
                     srv_decode_sink sink, void *ctx);

/* The encoded body ended: CORRUPT when its data stopped before the end of
 * the compressed stream. */
int srv_decoder_finish(srv_decoder *d);

/* Bytes handed out so far. */
size_t srv_decoder_out(const srv_decoder *d);

/* What was wrong when an outcome was CORRUPT ("" otherwise). */
const char *srv_decoder_error(const srv_decoder *d);

#endif /* VOR_SRV_DECODE_H */
