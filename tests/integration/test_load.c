/* test_load.c -- the service under load and abuse:
 *   - 64 concurrent clients mixing small and large requests: all answered
 *     200 with the right content;
 *   - a stalled upload (headers and half a body, then silence) and a
 *     stalled header block do not block anyone else, and the server closes
 *     them after --connection-timeout;
 *   - 1000 hostile requests (garbage, huge headers, wrong methods,
 *     truncated bodies, absurd Content-Length, bad chunking, ...) are
 *     answered or closed, never hang, and the service still answers
 *     correctly afterwards with nothing left in flight.
 * Random choices use a fixed seed, printed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "harness.h"

static it_daemon d;
static const char square_json[] =
    "{\"points\": [[0,0],[1,0],[0,1],[1,1],[0.5,0.5]]}";

static int setup(void **state) {
    (void)state;
    const char *args[] = {"--queue", "128", "--connection-timeout", "2",
                          "--max-body", "1M", NULL};
    return it_group_start(&d, args);
}

static int teardown(void **state) {
    (void)state;
    return it_group_stop(&d);
}

/* The square's diagram is still right. */
static void check_square(void) {
    it_req q = {.path = "/voronoi", .body = square_json,
                .len = strlen(square_json)};
    it_resp r;
    it_http(&d, &q, &r);
    assert_int_equal(r.status, 200);
    json_t *j = it_json(&r);
    assert_int_equal(json_integer_value(json_object_get(j, "n_vertices")), 4);
    assert_int_equal(json_integer_value(json_object_get(j, "n_edges")), 8);
    json_decref(j);
    it_free(&r);
}

/* The part of a diagram document from "vertices" up to the timings:
 * the same bytes for every algorithm (the canonical diagram). */
static const char *diagram_part(const char *body, size_t *len) {
    const char *a = strstr(body, "\"vertices\":");
    const char *b = a ? strstr(a, ",\"timings\":") : NULL;
    if (a == NULL || b == NULL) return NULL;
    *len = (size_t)(b - a);
    return a;
}

static void test_64_concurrent_clients(void **state) {
    (void)state;
    enum { N = 64 };
    static const char *const algs[] = {"fortune", "bowyer-watson", "flip"};
    size_t large = it_tsan() ? 2000 : 10000;
    char large_body[3][160], expect_n[64];
    for (int a = 0; a < 3; a++)
        snprintf(large_body[a], sizeof large_body[a],
                 "{\"generate\": {\"n\": %zu, \"seed\": 5}, \"algorithm\": "
                 "\"%s\"}", large, algs[a]);
    snprintf(expect_n, sizeof expect_n, "\"n_input\":%zu,\"n_sites\":%zu,",
             large, large);
    it_req q[N];
    it_resp r[N];
    memset(q, 0, sizeof q);
    for (int i = 0; i < N; i++) {
        q[i].path = "/voronoi";
        if (i % 2) {
            q[i].body = large_body[(i / 2) % 3];
            q[i].len = strlen(q[i].body);
            q[i].gzip = i % 4 == 1;
        } else {
            q[i].body = square_json;
            q[i].len = strlen(square_json);
        }
    }
    it_parallel(&d, q, r, N);
    const char *ref = NULL;
    size_t ref_len = 0;
    for (int i = 0; i < N; i++) {
        if (r[i].curl_rc != 0 || r[i].status != 200)
            fail_msg("client %d: curl %d (%s) status %ld %.200s", i,
                     r[i].curl_rc, r[i].err, r[i].status, r[i].body);
        if (i % 2 == 0) {
            json_t *j = it_json(&r[i]);
            assert_non_null(j);
            assert_int_equal(json_integer_value(json_object_get(j, "n_input")), 5);
            assert_int_equal(json_integer_value(json_object_get(j, "n_vertices")), 4);
            json_decref(j);
            continue;
        }
        /* Large answers (megabytes): complete, the right size, and the
         * same diagram whichever algorithm computed it. */
        assert_non_null(strstr(r[i].body, expect_n));
        assert_true(r[i].len > 2 && r[i].body[r[i].len - 2] == '}' &&
                    r[i].body[r[i].len - 1] == '\n');
        size_t len = 0;
        const char *part = diagram_part(r[i].body, &len);
        if (part == NULL) fail_msg("client %d: no diagram in %.200s", i, r[i].body);
        if (ref == NULL) {
            ref = part;
            ref_len = len;
        } else if (len != ref_len || memcmp(part, ref, len) != 0) {
            fail_msg("client %d: its diagram differs from another algorithm's", i);
        }
    }
    /* One large answer fully parsed: every site has its cell. */
    json_t *j = it_json(&r[1]);
    assert_non_null(j);
    assert_int_equal(json_array_size(json_object_get(j, "cells")), large);
    json_decref(j);
    for (int i = 0; i < N; i++) it_free(&r[i]);
}

static void test_stalled_clients_block_nobody(void **state) {
    (void)state;
    /* Headers and half of the announced body, then nothing. */
    int stalled_body = it_connect(d.port);
    assert_true(stalled_body >= 0);
    char head[256];
    snprintf(head, sizeof head,
             "POST /voronoi HTTP/1.1\r\nHost: x\r\nContent-Type: text/csv\r\n"
             "Content-Length: 1000\r\n\r\n");
    assert_int_equal(it_send_all(stalled_body, head, strlen(head)), 0);
    char half[500];
    memset(half, '1', sizeof half);
    assert_int_equal(it_send_all(stalled_body, half, sizeof half), 0);
    /* Half a header block. */
    int stalled_head = it_connect(d.port);
    assert_true(stalled_head >= 0);
    const char *partial = "GET /healthz HTTP/1.1\r\nHost: x\r\nX-Slow: ";
    assert_int_equal(it_send_all(stalled_head, partial, strlen(partial)), 0);

    /* Everyone else is served meanwhile. */
    for (int i = 0; i < 20; i++) {
        it_req q = {.path = i % 2 ? "/healthz" : "/voronoi",
                    .body = i % 2 ? NULL : square_json,
                    .len = i % 2 ? 0 : strlen(square_json)};
        it_resp r;
        it_http(&d, &q, &r);
        assert_int_equal(r.status, 200);
        it_free(&r);
    }
    check_square();

    /* The server gives up on both after --connection-timeout (2 s); the
     * wait below is a hang guard, not a timing requirement. */
    char buf[1024];
    int closed = 0;
    it_recv_until(stalled_body, buf, sizeof buf, 60, &closed);
    assert_true(closed);
    assert_int_equal(it_raw_status(buf), 0); /* no answer to half a request */
    close(stalled_body);
    it_recv_until(stalled_head, buf, sizeof buf, 60, &closed);
    assert_true(closed);
    close(stalled_head);

    it_req m = {.path = "/metrics"};
    it_resp r;
    it_http(&d, &m, &r);
    assert_true(it_metric(r.body, "voronoid_requests_aborted_total{route="
                               "\"/voronoi\"}") >= 1);
    it_free(&r);
    assert_true(it_log_has(&d, "status=- bytes=0"));
    assert_true(it_log_has(&d, "note=connection-timeout"));
}

/* ---- hostile requests ------------------------------------------------- */

static uint64_t rng_state;
static uint64_t rnd(void) {
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

enum { K_GARBAGE, K_HUGE_HEADER, K_WRONG_METHOD, K_TRUNCATED, K_ABSURD_LENGTH,
       K_BAD_REQUEST_LINE, K_BAD_BODY, K_MANY_PARAMS, K_BAD_CHUNKS,
       K_LONG_URL, K_NO_COLON, K_PIPELINED, K_COUNT };

/* Builds hostile request number i of kind k into buf; returns its length. */
static size_t hostile(int k, char *buf, size_t cap) {
    size_t n = 0;
    switch (k) {
    case K_GARBAGE:
        n = 1 + rnd() % 600;
        for (size_t i = 0; i < n; i++) buf[i] = (char)(rnd() & 0xff);
        if (rnd() % 2) {
            memcpy(buf + n, "\r\n\r\n", 4);
            n += 4;
        }
        return n;
    case K_HUGE_HEADER:
        n = (size_t)snprintf(buf, cap, "GET /healthz HTTP/1.1\r\nHost: x\r\nX-Big: ");
        memset(buf + n, 'a', 100000);
        n += 100000;
        memcpy(buf + n, "\r\n\r\n", 4);
        return n + 4;
    case K_WRONG_METHOD: {
        const char *m[] = {"DELETE", "PUT", "PATCH", "BREW", "TRACE", "GET"};
        const char *p[] = {"/voronoi", "/compare", "/", "/metrics"};
        const char *mm = m[rnd() % 6], *pp = p[rnd() % 4];
        if (strcmp(mm, "GET") == 0) pp = "/compare";
        return (size_t)snprintf(buf, cap, "%s %s HTTP/1.1\r\nHost: x\r\n\r\n", mm, pp);
    }
    case K_TRUNCATED:
        n = (size_t)snprintf(buf, cap, "POST /voronoi HTTP/1.1\r\nHost: x\r\n"
                                       "Content-Type: application/json\r\n"
                                       "Content-Length: 100\r\n\r\n[[0,0],[1,");
        return n;
    case K_ABSURD_LENGTH: {
        const char *cl[] = {"99999999999999999999999", "1000000000000000",
                            "-1", "abc", "12 34", "0x10", "18446744073709551615"};
        return (size_t)snprintf(buf, cap, "POST /voronoi HTTP/1.1\r\nHost: x\r\n"
                                          "Content-Length: %s\r\n\r\n[[0,0]]",
                                cl[rnd() % 7]);
    }
    case K_BAD_REQUEST_LINE: {
        const char *l[] = {"GET\r\n\r\n", "GET / HTTP/9.9\r\nHost: x\r\n\r\n",
                           "\r\n\r\n\r\n", "GET / HTTP/1.1\r\n\r\n",
                           "GET  /  HTTP/1.1\r\nHost: x\r\n\r\n",
                           "G\x01T / HTTP/1.1\r\nHost: x\r\n\r\n",
                           "GET /%zz%ff HTTP/1.1\r\nHost: x\r\n\r\n"};
        return (size_t)snprintf(buf, cap, "%s", l[rnd() % 7]);
    }
    case K_BAD_BODY: {
        size_t len = 1 + rnd() % 300;
        const char *ct[] = {"application/json", "text/csv", "application/octet-stream"};
        n = (size_t)snprintf(buf, cap, "POST /%s HTTP/1.1\r\nHost: x\r\n"
                                       "Content-Type: %s\r\nContent-Length: %zu\r\n\r\n",
                             rnd() % 2 ? "voronoi" : "compare", ct[rnd() % 3], len);
        for (size_t i = 0; i < len; i++) buf[n + i] = "[]{},:\"0123456789.eE+-nul \n\x80\xff"[rnd() % 30];
        return n + len;
    }
    case K_MANY_PARAMS:
        n = (size_t)snprintf(buf, cap, "POST /voronoi?");
        for (int i = 0; i < 40; i++) n += (size_t)snprintf(buf + n, cap - n, "a%d=%d&", i, i);
        n += (size_t)snprintf(buf + n, cap - n,
                              " HTTP/1.1\r\nHost: x\r\nContent-Length: 7\r\n\r\n[[0,0]]");
        return n;
    case K_BAD_CHUNKS:
        return (size_t)snprintf(buf, cap, "POST /voronoi HTTP/1.1\r\nHost: x\r\n"
                                          "Transfer-Encoding: chunked\r\n\r\n"
                                          "ZZZ\r\nhello\r\n0\r\n\r\n");
    case K_LONG_URL:
        n = (size_t)snprintf(buf, cap, "GET /");
        memset(buf + n, 'x', 20000);
        n += 20000;
        return n + (size_t)snprintf(buf + n, cap - n, " HTTP/1.1\r\nHost: x\r\n\r\n");
    case K_NO_COLON:
        return (size_t)snprintf(buf, cap, "GET /healthz HTTP/1.1\r\nHost x\r\n"
                                          "garbage line\r\n\r\n");
    case K_PIPELINED: {
        /* A good request followed by the start of a TLS handshake. */
        static const char req[] = "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n"
                                  "\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03";
        memcpy(buf, req, sizeof req - 1);
        return sizeof req - 1;
    }
    }
    return 0;
}

static void test_1000_hostile_requests(void **state) {
    (void)state;
    uint64_t seed = 20240607;
    rng_state = seed;
    printf("hostile requests: seed %llu\n", (unsigned long long)seed);
    size_t cap = 200000;
    char *buf = malloc(cap), *resp = malloc(65536);
    int answered = 0, by_kind[K_COUNT] = {0};
    for (int i = 0; i < 1000; i++) {
        int k = i % K_COUNT;
        size_t n = hostile(k, buf, cap);
        int fd = it_connect(d.port);
        if (fd < 0) fail_msg("request %d: cannot connect", i);
        it_send_all(fd, buf, n); /* the server may close early: fine */
        /* A request that ends where HTTP says it ends waits for its
         * answer; an incomplete one (no blank line after the headers, a
         * body cut short) is ended by closing our side. Either way the
         * server must answer or close: no hang. */
        int complete = k != K_TRUNCATED && buf[0] != '\r' && /* blank lines
                       before a request line are skipped: still waiting */
                       (k != K_GARBAGE || (n >= 4 && memcmp(buf + n - 4, "\r\n\r\n", 4) == 0));
        if (!complete) shutdown(fd, SHUT_WR);
        int closed = 0;
        size_t got = complete ? it_recv_response(fd, resp, 65536, 30, &closed)
                              : it_recv_until(fd, resp, 65536, 30, &closed);
        close(fd);
        if (!closed && got == 0)
            fail_msg("request %d (kind %d): neither answered nor closed", i, k);
        int status = it_raw_status(resp);
        if (status) {
            answered++;
            by_kind[k]++;
            /* Lenient parsing may accept an odd request line, a header
             * without a colon or a body that happens to be points; the
             * rest can only be refused. */
            int may_succeed = k == K_PIPELINED || k == K_BAD_REQUEST_LINE ||
                              k == K_NO_COLON || k == K_BAD_BODY;
            if (status < 400 && !may_succeed)
                fail_msg("request %d (kind %d): status %d", i, k, status);
        }
        /* What our handler answers must be what the contract says. */
        if (k == K_WRONG_METHOD) assert_int_equal(status, 405);
        if (k == K_MANY_PARAMS) assert_int_equal(status, 400);
        if (k == K_PIPELINED) assert_int_equal(status, 200);
        if (status >= 400 && strstr(resp, "application/problem+json") == NULL &&
            (k == K_WRONG_METHOD || k == K_MANY_PARAMS || k == K_BAD_BODY))
            fail_msg("request %d (kind %d): not a problem document", i, k);
    }
    printf("hostile requests: %d of 1000 answered with a status\n", answered);
    assert_true(by_kind[K_WRONG_METHOD] > 0 && by_kind[K_BAD_BODY] > 0);
    free(buf);
    free(resp);

    /* Still healthy, still right, nothing stuck in flight. */
    check_square();
    long in_flight = -1;
    for (int tries = 0; tries < 1000 && in_flight != 1; tries++) {
        it_req m = {.path = "/metrics"};
        it_resp r;
        it_http(&d, &m, &r);
        assert_int_equal(r.status, 200);
        in_flight = it_metric(r.body, "voronoid_in_flight");
        it_free(&r);
        if (in_flight != 1) it_sleep(0.02);
    }
    assert_int_equal(in_flight, 1); /* the /metrics request itself */
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_64_concurrent_clients),
        cmocka_unit_test(test_stalled_clients_block_nobody),
        cmocka_unit_test(test_1000_hostile_requests),
    };
    return cmocka_run_group_tests_name("integration/load", tests, setup,
                                       teardown);
}
