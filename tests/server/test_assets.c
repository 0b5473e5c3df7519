/* test_assets.c -- the embedded page and openapi.yaml, their gzip copies
 * (checked by inflating them with zlib), ETags, --web-dir lookups and the
 * paths --web-dir must refuse; and Accept-Encoding negotiation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include <cmocka.h>

#include "../../server/assets.h"
#include "../../server/gzip.h"

static int contains(const unsigned char *d, size_t n, const char *needle) {
    size_t k = strlen(needle);
    for (size_t i = 0; i + k <= n; i++)
        if (memcmp(d + i, needle, k) == 0) return 1;
    return 0;
}

/* Inflates a gzip buffer; returns a new buffer of *n bytes. */
static unsigned char *gunzip(const void *z, size_t zn, size_t *n) {
    z_stream s;
    memset(&s, 0, sizeof s);
    assert_int_equal(inflateInit2(&s, 15 + 16), Z_OK);
    size_t cap = zn * 8 + 1024;
    unsigned char *out = malloc(cap);
    s.next_in = (Bytef *)(uintptr_t)z;
    s.avail_in = (uInt)zn;
    int rc;
    do {
        if (s.total_out == cap) {
            cap *= 2;
            out = realloc(out, cap);
        }
        s.next_out = out + s.total_out;
        s.avail_out = (uInt)(cap - s.total_out);
        rc = inflate(&s, Z_NO_FLUSH);
        assert_true(rc == Z_OK || rc == Z_STREAM_END);
    } while (rc != Z_STREAM_END);
    *n = s.total_out;
    inflateEnd(&s);
    return out;
}

static void test_accept_encoding(void **state) {
    (void)state;
    assert_true(srv_accepts_gzip("gzip"));
    assert_true(srv_accepts_gzip("deflate, gzip, br"));
    assert_true(srv_accepts_gzip("GZIP;q=0.5"));
    assert_true(srv_accepts_gzip("x-gzip"));
    assert_true(srv_accepts_gzip("*"));
    assert_true(srv_accepts_gzip("br;q=1.0, gzip;q=0.8, *;q=0.1"));
    assert_false(srv_accepts_gzip(NULL));
    assert_false(srv_accepts_gzip(""));
    assert_false(srv_accepts_gzip("identity"));
    assert_false(srv_accepts_gzip("br, deflate"));
    assert_false(srv_accepts_gzip("gzip;q=0"));
    assert_false(srv_accepts_gzip("gzip;q=0.000"));
    assert_false(srv_accepts_gzip("*, gzip;q=0")); /* explicit refusal wins */
    assert_false(srv_accepts_gzip("*;q=0"));
    assert_false(srv_accepts_gzip("gzip;q=abc"));
    assert_false(srv_accepts_gzip("gzipx"));
}

static void test_gzip_round_trip(void **state) {
    (void)state;
    size_t n = 300000;
    char *in = malloc(n);
    for (size_t i = 0; i < n; i++) in[i] = (char)("0123456789,.[]\n"[i % 15]);
    for (int level = 1; level <= 9; level += 4) {
        char *z;
        size_t zn, back_n;
        assert_int_equal(srv_gzip(in, n, level, &z, &zn), 0);
        assert_true(zn < n / 10);
        assert_true((unsigned char)z[0] == 0x1f && (unsigned char)z[1] == 0x8b);
        unsigned char *back = gunzip(z, zn, &back_n);
        assert_int_equal(back_n, n);
        assert_memory_equal(back, in, n);
        free(back);
        free(z);
    }
    char *z;
    size_t zn, back_n;
    assert_int_equal(srv_gzip("", 0, 6, &z, &zn), 0); /* empty input */
    unsigned char *back = gunzip(z, zn, &back_n);
    assert_int_equal(back_n, 0);
    free(back);
    free(z);
    free(in);
}

static void test_embedded(void **state) {
    (void)state;
    srv_assets *a = srv_assets_new(NULL);
    assert_non_null(a);
    assert_true(srv_embedded_count >= 2);
    assert_true(srv_assets_has(a, "/"));
    assert_true(srv_assets_has(a, "/index.html"));
    assert_true(srv_assets_has(a, "/openapi.yaml"));
    assert_false(srv_assets_has(a, "/nope.js"));
    assert_false(srv_assets_has(a, "/../Makefile"));

    srv_asset x;
    assert_int_equal(srv_assets_get(a, "/", &x), 0);
    assert_string_equal(x.mime, "text/html; charset=utf-8");
    assert_true(x.len > 100);
    assert_true(contains(x.data, x.len, "<html"));
    assert_true(x.etag[0] == '"' && strlen(x.etag) == 18);
    if (x.gz != NULL) {
        size_t n;
        unsigned char *back = gunzip(x.gz, x.gz_len, &n);
        assert_int_equal(n, x.len);
        assert_memory_equal(back, x.data, n);
        free(back);
    }
    char etag_page[24];
    strcpy(etag_page, x.etag);
    srv_asset_release(&x);

    assert_int_equal(srv_assets_get(a, "/openapi.yaml", &x), 0);
    assert_string_equal(x.mime, "application/yaml");
    assert_true(contains(x.data, x.len, "openapi: 3.1"));
    assert_string_not_equal(x.etag, etag_page);
    srv_asset_release(&x);

    /* Every embedded file is served under its name with a MIME type. */
    for (size_t i = 0; i < srv_embedded_count; i++) {
        assert_int_equal(srv_assets_get(a, srv_embedded_assets[i].path, &x),
                         0);
        assert_int_equal(x.len, srv_embedded_assets[i].len);
        srv_asset_release(&x);
    }
    assert_int_equal(srv_assets_get(a, "/nope", &x), -1);
    srv_assets_free(a);
    srv_assets_free(NULL);
}

static void test_web_dir(void **state) {
    (void)state;
    char dir[] = "/tmp/voronoid-assets-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[256];
    snprintf(path, sizeof path, "%s/index.html", dir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    for (int i = 0; i < 200; i++) fputs("<p>from disk</p>\n", f);
    fclose(f);
    snprintf(path, sizeof path, "%s/.secret", dir);
    f = fopen(path, "w");
    fputs("no", f);
    fclose(f);
    snprintf(path, sizeof path, "%s/sub", dir);
    mkdir(path, 0755);

    srv_assets *a = srv_assets_new(dir);
    assert_non_null(a);
    srv_asset x;
    assert_int_equal(srv_assets_get(a, "/", &x), 0);
    assert_non_null(x.owned);
    assert_true(x.len == 200 * 17);
    assert_true(contains(x.data, x.len, "from disk"));
    srv_asset_release(&x);
    assert_null(x.owned);
    /* openapi.yaml stays the built-in one. */
    assert_true(srv_assets_has(a, "/openapi.yaml"));
    assert_int_equal(srv_assets_get(a, "/openapi.yaml", &x), 0);
    assert_null(x.owned);
    /* Nothing outside the directory, no dot files, no directories. */
    const char *refused[] = {"/.secret", "/../etc/passwd", "/sub", "/sub/",
                             "//etc/passwd", "/a/../index.html", "/%2e%2e",
                             "/index.html/", NULL};
    for (int i = 0; refused[i]; i++) {
        if (srv_assets_has(a, refused[i]))
            fail_msg("served %s", refused[i]);
        assert_int_equal(srv_assets_get(a, refused[i], &x), -1);
    }
    srv_assets_free(a);
    snprintf(path, sizeof path, "rm -rf '%s'", dir);
    assert_int_equal(system(path), 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_accept_encoding),
        cmocka_unit_test(test_gzip_round_trip),
        cmocka_unit_test(test_embedded),
        cmocka_unit_test(test_web_dir),
    };
    return cmocka_run_group_tests_name("server/assets", tests, NULL, NULL);
}
