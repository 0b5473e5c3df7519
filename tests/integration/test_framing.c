/* test_framing.c -- strict HTTP framing and request decoding, over raw
 * sockets where no HTTP client would send such a request:
 *   - Transfer-Encoding other than chunked -> one 501; Transfer-Encoding
 *     with Content-Length, or Content-Length values that disagree -> one
 *     well-formed 400; agreeing duplicates are served;
 *   - request lines from 8 KiB to 16,383 bytes (the band libmicrohttpd
 *     0.9.75 used to close without a word) -> one 414; request heads over
 *     12 KiB -> 431;
 *   - Content-Encoding gzip and deflate (zlib and raw) bodies decoded, the
 *     answer the same as for the plain body; other codings -> 415; a body
 *     that does not decode -> 400; a 1 GiB gzip bomb -> 413 after a
 *     bounded amount of work, the daemon still well;
 *   - lingering close: a client that sends a whole over-limit body before
 *     reading (as Python's http.client does) still reads the 413;
 *   - a chunked body over --max-body -> 413 once it ends;
 *   - a target in absolute form ("http://host/voronoi") served as its
 *     path.
 * Every answer is checked to be exactly one response. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <zlib.h>

#include "../support/squeeze.h"

#include "harness.h"

static it_daemon d;

static int setup(void **state) {
    (void)state;
    const char *args[] = {"--max-body", "2M", "--connection-timeout", "20",
                          NULL};
    return it_group_start(&d, args);
}

static int teardown(void **state) {
    (void)state;
    return it_group_stop(&d);
}

/* Sends req (len bytes) on a new connection, reads until the server
 * closes (or 30 s of silence: a hang guard). Returns a new buffer. */
static char *exchange(const void *req, size_t len, size_t *got) {
    int fd = it_connect(d.port);
    assert_true(fd >= 0);
    assert_int_equal(it_send_all(fd, req, len), 0);
    size_t cap = 1 << 20;
    char *buf = malloc(cap);
    int closed = 0;
    size_t n = it_recv_until(fd, buf, cap, 30, &closed);
    close(fd);
    if (got) *got = n;
    return buf;
}

/* Number of responses in buf: status lines at the start or right after a
 * body (counted by "HTTP/1.1 " at the start of a line). */
static int responses(const char *buf) {
    int n = 0;
    for (const char *p = buf; (p = strstr(p, "HTTP/1.1 ")) != NULL; p += 9)
        if (p == buf || p[-1] == '\n' || p[-1] == '}' || p[-1] == '>') n++;
    return n;
}

/* One response with this status and a problem document of this type. */
static void expect_one(const char *what, const char *buf, int status,
                       const char *type) {
    if (it_raw_status(buf) != status)
        fail_msg("%s: status %d, expected %d: %.300s", what,
                 it_raw_status(buf), status, buf);
    if (responses(buf) != 1)
        fail_msg("%s: %d responses: %.600s", what, responses(buf), buf);
    const char *body = strstr(buf, "\r\n\r\n");
    assert_non_null(body);
    const char *cl = strcasestr_like(buf, "\r\nContent-Length:");
    assert_non_null(cl);
    assert_int_equal((size_t)atol(cl + 17), strlen(body + 4));
    if (type != NULL) {
        char want[80];
        snprintf(want, sizeof want, "\"type\":\"/problems/%s\"", type);
        if (strstr(body, want) == NULL)
            fail_msg("%s: not a %s problem: %s", what, type, body + 4);
    }
}

static const char square[] = "{\"points\":[[0,0],[1,0],[0,1],[1,1],[0.5,0.5]]}";

static void test_transfer_encoding_and_length(void **state) {
    (void)state;
    char req[1024];
    static const struct {
        const char *name, *headers, *type;
        int status;
    } cases[] = {
        {"te-gzip-chunked", "Transfer-Encoding: gzip, chunked\r\n",
         "not-implemented", 501},
        {"te-identity", "Transfer-Encoding: identity\r\n", "not-implemented",
         501},
        {"te-twice", "Transfer-Encoding: chunked\r\nTransfer-Encoding: "
                     "chunked\r\n", "not-implemented", 501},
        {"te-and-cl", "Transfer-Encoding: chunked\r\nContent-Length: 5\r\n",
         "malformed", 400},
        {"cl-disagree", "Content-Length: 47\r\nContent-Length: 3\r\n",
         "malformed", 400},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int n = snprintf(req, sizeof req,
                         "POST /voronoi HTTP/1.1\r\nHost: x\r\n%s\r\n"
                         "5\r\nhello\r\n0\r\n\r\n", cases[i].headers);
        char *buf = exchange(req, (size_t)n, NULL);
        expect_one(cases[i].name, buf, cases[i].status, cases[i].type);
        free(buf);
    }
    /* Content-Length repeated with the same value is one length. */
    int n = snprintf(req, sizeof req,
                     "POST /voronoi HTTP/1.1\r\nHost: x\r\nContent-Length: "
                     "%zu\r\nContent-Length: %zu\r\nConnection: close\r\n\r\n"
                     "%s", strlen(square), strlen(square), square);
    char *buf = exchange(req, (size_t)n, NULL);
    expect_one("cl-same", buf, 200, NULL);
    assert_non_null(strstr(buf, "\"n_vertices\":4"));
    free(buf);
}

/* A request target in absolute form (RFC 9112, 3.2.2, which a server
 * must accept): served as its path, the same answer as the origin form;
 * no path is "/"; a path the service lacks is still a 404. */
static void test_absolute_form(void **state) {
    (void)state;
    char req[1024];
    static const char *const targets[] = {
        "/voronoi", "http://x/voronoi", "HTTP://x:8080/voronoi",
        "https://[::1]:443/voronoi?format=json"};
    char *first = NULL;
    for (size_t i = 0; i < sizeof targets / sizeof targets[0]; i++) {
        int n = snprintf(req, sizeof req,
                         "POST %s HTTP/1.1\r\nHost: x\r\nContent-Length: "
                         "%zu\r\nConnection: close\r\n\r\n%s",
                         targets[i], strlen(square), square);
        char *buf = exchange(req, (size_t)n, NULL);
        expect_one(targets[i], buf, 200, NULL);
        /* the diagram: the body up to its timings, which vary */
        char *body = strstr(buf, "\r\n\r\n");
        char *timings = strstr(body, "\"timings\"");
        assert_non_null(timings);
        *timings = '\0';
        assert_non_null(strstr(body, "\"n_vertices\":4"));
        if (first == NULL) {
            first = strdup(body);
        } else if (strcmp(first, body) != 0) {
            fail_msg("%s: another answer than /voronoi's: %.300s", targets[i],
                     body);
        }
        free(buf);
    }
    free(first);
    static const struct {
        const char *req;
        int status;
    } others[] = {
        {"GET http://x HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n",
         200},
        {"GET http://x/healthz HTTP/1.1\r\nHost: x\r\nConnection: "
         "close\r\n\r\n", 200},
        {"GET http://x/nowhere HTTP/1.1\r\nHost: x\r\nConnection: "
         "close\r\n\r\n", 404},
        {"GET http:/healthz HTTP/1.1\r\nHost: x\r\nConnection: "
         "close\r\n\r\n", 404},
    };
    for (size_t i = 0; i < sizeof others / sizeof others[0]; i++) {
        char *buf = exchange(others[i].req, strlen(others[i].req), NULL);
        if (it_raw_status(buf) != others[i].status)
            fail_msg("%.40s: status %d, expected %d", others[i].req,
                     it_raw_status(buf), others[i].status);
        assert_int_equal(responses(buf), 1);
        free(buf);
    }
}

/* "OPTIONS *" (RFC 9112, 3.2.4: the asterisk form) asks about the
 * server as a whole: 204 with every method the service takes. */
static void test_options_asterisk(void **state) {
    (void)state;
    static const char req[] =
        "OPTIONS * HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
    char *buf = exchange(req, sizeof req - 1, NULL);
    if (it_raw_status(buf) != 204)
        fail_msg("OPTIONS *: status %d: %.300s", it_raw_status(buf), buf);
    assert_int_equal(responses(buf), 1);
    assert_non_null(strstr(buf, "\r\nAllow: GET, HEAD, POST, OPTIONS\r\n"));
    free(buf);
}

static void test_long_request_lines_and_heads(void **state) {
    (void)state;
    /* Up to 16,381 bytes (the line and its CRLF within libmicrohttpd's
     * 16 KiB) the service answers itself; from there libmicrohttpd does,
     * with a 414 of its own. */
    static const size_t lines[] = {8300,  12000, 15000, 16000, 16100, 16200,
                                   16250, 16300, 16350, 16381, 16382, 16383,
                                   16384, 17000, 30000};
    char *req = malloc(40000);
    for (size_t i = 0; i < sizeof lines / sizeof lines[0]; i++) {
        /* "GET /aaa... HTTP/1.1" of lines[i] bytes. */
        size_t target = lines[i] - strlen("GET  HTTP/1.1");
        size_t k = 0;
        k += (size_t)sprintf(req, "GET /");
        memset(req + k, 'a', target - 1);
        k += target - 1;
        k += (size_t)sprintf(req + k, " HTTP/1.1\r\nHost: x\r\n\r\n");
        char *buf = exchange(req, k, NULL);
        char what[32];
        snprintf(what, sizeof what, "line of %zu", lines[i]);
        expect_one(what, buf, 414, lines[i] <= 16381 ? "uri-too-long" : NULL);
        free(buf);
    }
    /* Many headers: 431. */
    size_t k = (size_t)sprintf(req, "GET /healthz HTTP/1.1\r\nHost: x\r\n");
    for (int h = 0; h < 2; h++) {
        k += (size_t)sprintf(req + k, "X-Padding-%d: ", h);
        memset(req + k, 'p', 6400);
        k += 6400;
        k += (size_t)sprintf(req + k, "\r\n");
    }
    k += (size_t)sprintf(req + k, "\r\n");
    char *buf = exchange(req, k, NULL);
    expect_one("many headers", buf, 431, "headers-too-large");
    free(buf);
    free(req);
    /* Below the limits: served. */
    it_req q = {.path = "/healthz"};
    it_resp r;
    it_http(&d, &q, &r);
    assert_int_equal(r.status, 200);
    it_free(&r);
}

/* POST /voronoi with a Content-Encoding through libcurl (which sends
 * the body as given). */
static void post_encoded(const char *coding, const void *body, size_t len,
                         it_resp *r) {
    char ce[64];
    snprintf(ce, sizeof ce, "Content-Encoding: %s", coding);
    it_req q = {.path = "/voronoi", .body = body, .len = len,
                .headers = {"Content-Type: application/json", ce}};
    it_http(&d, &q, r);
}

/* The part of a diagram document before its timings. */
static size_t diagram_len(const it_resp *r) {
    const char *t = strstr(r->body, ",\"timings\":");
    return t ? (size_t)(t - r->body) : 0;
}

static void test_content_encoding(void **state) {
    (void)state;
    /* A few hundred points, so that compression does something. */
    char *plain = malloc(1 << 16);
    size_t n = (size_t)sprintf(plain, "{\"points\":[");
    for (int i = 0; i < 300; i++)
        n += (size_t)sprintf(plain + n, "%s[%d,%d]", i ? "," : "",
                             (i * 37) % 101, (i * 53) % 89);
    n += (size_t)sprintf(plain + n, "]}");
    it_resp base;
    post_encoded("identity", plain, n, &base);
    assert_int_equal(base.status, 200);
    size_t want = diagram_len(&base);
    assert_true(want > 0);

    static const char *const names[] = {"gzip", "deflate", "deflate",
                                        "x-gzip"};
    static const int formats[] = {0, 1, 2, 0};
    for (int f = 0; f < 4; f++) {
        size_t zn;
        unsigned char *z = vt_squeeze(plain, n, formats[f], &zn);
        it_resp r;
        post_encoded(names[f], z, zn, &r);
        if (r.status != 200)
            fail_msg("%s (format %d): %ld %s", names[f], formats[f], r.status,
                     r.body);
        assert_int_equal(diagram_len(&r), want);
        assert_memory_equal(r.body, base.body, want);
        it_free(&r);
        free(z);
    }
    /* Two gzip members one after the other are one body. */
    size_t h = n / 2, z1n, z2n;
    unsigned char *z1 = vt_squeeze(plain, h, 0, &z1n);
    unsigned char *z2 = vt_squeeze(plain + h, n - h, 0, &z2n);
    unsigned char *both = malloc(z1n + z2n);
    memcpy(both, z1, z1n);
    memcpy(both + z1n, z2, z2n);
    it_resp r;
    post_encoded("gzip", both, z1n + z2n, &r);
    assert_int_equal(r.status, 200);
    assert_int_equal(diagram_len(&r), want);
    it_free(&r);
    free(z1);
    free(z2);
    free(both);
    it_free(&base);

    /* Refusals. */
    static const struct {
        const char *coding, *body, *type, *detail;
        long status;
    } bad[] = {
        {"br", "[[0,0]]", "unsupported-media-type", "'br'", 415},
        {"gzip, gzip", "[[0,0]]", "unsupported-media-type", "gzip, gzip", 415},
        {"compress", "[[0,0]]", "unsupported-media-type", "compress", 415},
        {"gzip", "[[0,0],[1,1]]", "malformed", "does not decode", 400},
        {"deflate", "\x78\x9c garbage!", "malformed", "does not decode", 400},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        post_encoded(bad[i].coding, bad[i].body, strlen(bad[i].body), &r);
        it_save(i == 0 ? "err-415-content-encoding" : "err-content-encoding",
                &(it_req){.path = "/voronoi", .body = bad[i].body}, &r);
        if (r.status != bad[i].status || strstr(r.body, bad[i].type) == NULL ||
            strstr(r.body, bad[i].detail) == NULL)
            fail_msg("%s: %ld %s", bad[i].coding, r.status, r.body);
        it_free(&r);
    }
    free(plain);
}

static void test_gzip_bomb(void **state) {
    (void)state;
    /* 1 GiB of spaces compresses to about 1 MiB, under --max-body 2M. */
    z_stream z;
    memset(&z, 0, sizeof z);
    assert_int_equal(deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 8,
                                  Z_DEFAULT_STRATEGY), Z_OK);
    size_t cap = 4 << 20;
    unsigned char *out = malloc(cap);
    static char spaces[1 << 16];
    memset(spaces, ' ', sizeof spaces);
    z.next_out = out;
    z.avail_out = (uInt)cap;
    for (int i = 0; i < (1 << 14); i++) {
        z.next_in = (Bytef *)spaces;
        z.avail_in = sizeof spaces;
        assert_int_equal(deflate(&z, Z_NO_FLUSH), Z_OK);
    }
    assert_int_equal(deflate(&z, Z_FINISH), Z_STREAM_END);
    size_t zn = z.total_out;
    deflateEnd(&z);
    assert_true(zn < (2u << 20));
    it_resp r;
    post_encoded("gzip", out, zn, &r);
    it_save("err-413-gzip-bomb", &(it_req){.path = "/voronoi", .body = ""},
            &r);
    if (r.status != 413 || strstr(r.body, "counted decoded") == NULL)
        fail_msg("bomb: %ld %s", r.status, r.body);
    it_free(&r);
    free(out);
    it_req q = {.path = "/healthz"};
    it_http(&d, &q, &r);
    assert_int_equal(r.status, 200);
    it_free(&r);
}

/* A client that writes its whole request before it reads (Python's
 * http.client, no Expect: 100-continue): it must still read the 413. */
static void test_lingering_close(void **state) {
    (void)state;
    static const size_t sizes[] = {3u << 20, 9u << 20};
    for (size_t i = 0; i < 2; i++) {
        size_t body = sizes[i];
        char head[256];
        int hn = snprintf(head, sizeof head,
                          "POST /voronoi HTTP/1.1\r\nHost: x\r\n"
                          "Content-Type: text/plain\r\nContent-Length: %zu"
                          "\r\n\r\n", body);
        int fd = it_connect(d.port);
        assert_true(fd >= 0);
        assert_int_equal(it_send_all(fd, head, (size_t)hn), 0);
        char *junk = malloc(body);
        memset(junk, '7', body);
        /* Every byte goes out before the first read. */
        if (it_send_all(fd, junk, body) != 0)
            fail_msg("%zu-byte body: the server reset the connection while "
                     "the client was sending", body);
        char buf[4096];
        int closed;
        it_recv_until(fd, buf, sizeof buf, 30, &closed);
        close(fd);
        free(junk);
        expect_one("lingering 413", buf, 413, "too-large");
    }
    /* Chunked, over the limit: read and dropped, then 413. */
    int fd = it_connect(d.port);
    const char *head = "POST /voronoi HTTP/1.1\r\nHost: x\r\nContent-Type: "
                       "text/plain\r\nTransfer-Encoding: chunked\r\n\r\n";
    assert_int_equal(it_send_all(fd, head, strlen(head)), 0);
    static char chunk[65536 + 16];
    int k = sprintf(chunk, "10000\r\n");
    memset(chunk + k, '5', 65536);
    memcpy(chunk + k + 65536, "\r\n", 2);
    for (int i = 0; i < 40; i++)
        assert_int_equal(it_send_all(fd, chunk, (size_t)k + 65538), 0);
    assert_int_equal(it_send_all(fd, "0\r\n\r\n", 5), 0);
    char buf[4096];
    int closed;
    it_recv_response(fd, buf, sizeof buf, 30, &closed);
    close(fd);
    expect_one("chunked over the limit", buf, 413, "too-large");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_transfer_encoding_and_length),
        cmocka_unit_test(test_absolute_form),
        cmocka_unit_test(test_options_asterisk),
        cmocka_unit_test(test_long_request_lines_and_heads),
        cmocka_unit_test(test_content_encoding),
        cmocka_unit_test(test_gzip_bomb),
        cmocka_unit_test(test_lingering_close),
    };
    return cmocka_run_group_tests_name("integration/framing", tests, setup,
                                       teardown);
}
