/* test_decode.c -- request body decoding (server/decode.c): the names of
 * codings, gzip, zlib and raw deflate against zlib's own encoder, gzip
 * members one after another, bodies fed a byte at a time, the output
 * limit (a bomb stops after `limit` bytes), and corrupt or truncated
 * data. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include <zlib.h>

#include "../support/squeeze.h"

#include "../../server/decode.h"

typedef struct sink {
    char *p;
    size_t n, cap;
} sink;

static int put(void *ctx, const char *data, size_t n) {
    sink *s = ctx;
    if (s->n + n > s->cap) {
        s->cap = (s->n + n) * 2;
        s->p = realloc(s->p, s->cap);
    }
    memcpy(s->p + s->n, data, n);
    s->n += n;
    return 0;
}

static char *sample(size_t n) {
    char *s = malloc(n);
    uint64_t x = 0x5eed;
    for (size_t i = 0; i < n; i++) {
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        s[i] = "0123456789 ,\n."[(x >> 33) % 14];
    }
    return s;
}

static void test_names(void **state) {
    (void)state;
    assert_int_equal(srv_coding_of(NULL), SRV_CODING_IDENTITY);
    assert_int_equal(srv_coding_of(" Identity "), SRV_CODING_IDENTITY);
    assert_int_equal(srv_coding_of("GZIP"), SRV_CODING_GZIP);
    assert_int_equal(srv_coding_of("x-gzip"), SRV_CODING_GZIP);
    assert_int_equal(srv_coding_of("deflate"), SRV_CODING_DEFLATE);
    assert_int_equal(srv_coding_of("br"), SRV_CODING_UNKNOWN);
    assert_int_equal(srv_coding_of("gzip, gzip"), SRV_CODING_UNKNOWN);
    assert_int_equal(srv_coding_of("gzipx"), SRV_CODING_UNKNOWN);
}

static void test_round_trips(void **state) {
    (void)state;
    size_t n = 300000;
    char *plain = sample(n);
    for (int format = 0; format < 3; format++) {
        for (int bytewise = 0; bytewise < 2; bytewise++) {
            size_t zn;
            unsigned char *z = vt_squeeze(plain, n, format, &zn);
            srv_decoder *d = srv_decoder_new(
                format == 0 ? SRV_CODING_GZIP : SRV_CODING_DEFLATE, n);
            assert_non_null(d);
            sink s = {0};
            size_t step = bytewise ? 1 : zn;
            for (size_t i = 0; i < zn; i += step) {
                size_t k = zn - i < step ? zn - i : step;
                assert_int_equal(srv_decoder_feed(d, (char *)z + i, k, put, &s),
                                 SRV_DECODE_OK);
            }
            assert_int_equal(srv_decoder_finish(d), SRV_DECODE_OK);
            assert_int_equal(s.n, n);
            assert_int_equal(srv_decoder_out(d), n);
            assert_memory_equal(s.p, plain, n);
            srv_decoder_free(d);
            free(s.p);
            free(z);
        }
    }
    /* Two gzip members are one body. */
    size_t an, bn;
    unsigned char *a = vt_squeeze(plain, 1000, 0, &an);
    unsigned char *b = vt_squeeze(plain + 1000, 2000, 0, &bn);
    unsigned char *ab = malloc(an + bn);
    memcpy(ab, a, an);
    memcpy(ab + an, b, bn);
    srv_decoder *d = srv_decoder_new(SRV_CODING_GZIP, n);
    sink s = {0};
    assert_int_equal(srv_decoder_feed(d, (char *)ab, an + bn, put, &s),
                     SRV_DECODE_OK);
    assert_int_equal(srv_decoder_finish(d), SRV_DECODE_OK);
    assert_int_equal(s.n, 3000);
    assert_memory_equal(s.p, plain, 3000);
    srv_decoder_free(d);
    free(s.p);
    free(a);
    free(b);
    free(ab);
    free(plain);
}

static void test_limit_and_corruption(void **state) {
    (void)state;
    /* 64 MiB of zeros: stopped at the limit, with the limit handed out
     * at most. */
    size_t big = 64u << 20;
    char *zeros = calloc(1, big);
    size_t zn;
    unsigned char *z = vt_squeeze(zeros, big, 0, &zn);
    free(zeros);
    srv_decoder *d = srv_decoder_new(SRV_CODING_GZIP, 100000);
    sink s = {0};
    assert_int_equal(srv_decoder_feed(d, (char *)z, zn, put, &s),
                     SRV_DECODE_LIMIT);
    assert_true(s.n <= 100000);
    srv_decoder_free(d);
    free(s.p);

    /* Truncated: fine while fed, refused at the end. */
    d = srv_decoder_new(SRV_CODING_GZIP, big);
    memset(&s, 0, sizeof s);
    assert_int_equal(srv_decoder_feed(d, (char *)z, zn / 2, put, &s),
                     SRV_DECODE_OK);
    assert_int_equal(srv_decoder_finish(d), SRV_DECODE_CORRUPT);
    assert_non_null(strstr(srv_decoder_error(d), "ends early"));
    srv_decoder_free(d);
    free(s.p);
    free(z);

    /* Not gzip at all. */
    d = srv_decoder_new(SRV_CODING_GZIP, 1000);
    memset(&s, 0, sizeof s);
    assert_int_equal(srv_decoder_feed(d, "hello, world, not gzip", 22, put, &s),
                     SRV_DECODE_CORRUPT);
    assert_true(strlen(srv_decoder_error(d)) > 0);
    srv_decoder_free(d);
    free(s.p);

    /* Garbage after a deflate stream. */
    unsigned char *y = vt_squeeze("abc", 3, 1, &zn);
    unsigned char *yy = malloc(zn + 3);
    memcpy(yy, y, zn);
    memcpy(yy + zn, "xyz", 3);
    d = srv_decoder_new(SRV_CODING_DEFLATE, 1000);
    memset(&s, 0, sizeof s);
    assert_int_equal(srv_decoder_feed(d, (char *)yy, zn + 3, put, &s),
                     SRV_DECODE_CORRUPT);
    srv_decoder_free(d);
    free(s.p);
    free(y);
    free(yy);

    /* Empty body. */
    d = srv_decoder_new(SRV_CODING_DEFLATE, 1000);
    assert_int_equal(srv_decoder_finish(d), SRV_DECODE_CORRUPT);
    srv_decoder_free(d);
    assert_null(srv_decoder_new(SRV_CODING_IDENTITY, 10));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_round_trips),
        cmocka_unit_test(test_limit_and_corruption),
    };
    return cmocka_run_group_tests_name("server/decode", tests, NULL, NULL);
}
