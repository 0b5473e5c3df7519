/* test_buf_flush.c -- api_buf's flush hook, which streamed answers use
 * (server/stream.c): every writer, fed through a buffer that hands out
 * what it holds once it reaches a small flush_at, must produce exactly
 * the bytes it produces into a plain buffer (the timings aside, which
 * differ run to run), and the buffer must never hold more than flush_at
 * and one reservation; the binary writer's padding must survive flushes at offsets
 * that are not multiples of 8; a hook that refuses stops the writer. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../api/api.h"

typedef struct sink {
    char *p;
    size_t n, cap, calls, most_held;
    api_buf *buf;
    int refuse_after;
} sink;

static int collect(void *ctx, const char *data, size_t n) {
    sink *s = ctx;
    if (s->refuse_after > 0 && (int)s->calls >= s->refuse_after) return -1;
    if (s->buf->len > s->most_held) s->most_held = s->buf->len;
    if (s->n + n > s->cap) {
        s->cap = (s->n + n) * 2;
        s->p = realloc(s->p, s->cap);
    }
    memcpy(s->p + s->n, data, n);
    s->n += n;
    s->calls++;
    return 0;
}

/* Length of a document without its timings (JSON: from ",\"timings\"";
 * SVG: from "<!-- timings"; binary: the 56 bytes before the counts, which
 * come last, n_counts u64 as the header's word at offset 44 says). */
static size_t body_len(const char *p, size_t n, api_format f) {
    if (f == API_FMT_BINARY) {
        const unsigned char *h = (const unsigned char *)p + 44;
        size_t n_counts = (size_t)h[0] | (size_t)h[1] << 8 | (size_t)h[2] << 16 |
                          (size_t)h[3] << 24;
        return n - 56 - 8 * n_counts;
    }
    const char *key = f == API_FMT_SVG ? "<!-- timings" : ",\"timings\":";
    size_t k = strlen(key);
    for (size_t i = n - k; i > 0; i--)
        if (memcmp(p + i, key, k) == 0) return i;
    return n;
}

static void test_every_format_streams_the_same(void **state) {
    (void)state;
    static const api_format formats[] = {API_FMT_JSON, API_FMT_GEOJSON,
                                         API_FMT_SVG, API_FMT_BINARY};
    for (size_t f = 0; f < 4; f++) {
        api_request r;
        api_problem p;
        api_result res;
        api_request_init(&r);
        api_result_init(&res);
        memset(&p, 0, sizeof p);
        /* 3001 points: odd counts, so that sections end off multiples
         * of 8 in the binary layout. */
        assert_int_equal(api_generate("clustered", 3001, 9, &r.xy, &p), API_OK);
        r.n = 3001;
        r.format = formats[f];
        r.parts = API_PART_ALL;
        r.parts_given = 1;
        assert_int_equal(api_compute(&r, &res, &p), API_OK);

        api_timings t = res.t;
        api_buf plain;
        api_buf_init(&plain);
        assert_int_equal(api_write_result(&r, &res, &t, &plain, &p), API_OK);

        for (size_t at = 1000; at <= 9000; at += 4001) {
            sink s = {0};
            api_buf b;
            api_buf_init(&b);
            s.buf = &b;
            b.flush = collect;
            b.flush_ctx = &s;
            b.flush_at = at;
            t = res.t;
            assert_int_equal(api_write_result(&r, &res, &t, &b, &p), API_OK);
            collect(&s, b.data, b.len); /* what is left */
            size_t want = body_len(plain.data, plain.len, r.format);
            assert_true(s.calls > 2);
            assert_int_equal(body_len(s.p, s.n, r.format), want);
            assert_memory_equal(s.p, plain.data, want);
            /* Held: flush_at plus at most one reservation (the binary
             * writer reserves up to 128 KiB at a time). */
            if (s.most_held > at + (256u << 10))
                fail_msg("format %zu held %zu bytes with flush_at %zu", f,
                         s.most_held, at);
            api_buf_clear(&b);
            free(s.p);
        }
        /* A hook that refuses stops the writer with an error. */
        sink s = {0};
        api_buf b;
        api_buf_init(&b);
        s.buf = &b;
        s.refuse_after = 2;
        b.flush = collect;
        b.flush_ctx = &s;
        b.flush_at = 1000;
        t = res.t;
        assert_int_not_equal(api_write_result(&r, &res, &t, &b, &p), API_OK);
        api_buf_clear(&b);
        free(s.p);

        api_buf_clear(&plain);
        api_result_clear(&res);
        api_request_clear(&r);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_format_streams_the_same),
    };
    return cmocka_run_group_tests_name("api/buf_flush", tests, NULL, NULL);
}
