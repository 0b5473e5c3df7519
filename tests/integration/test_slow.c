/* test_slow.c -- deadlines for slow clients, against a daemon with short
 * ones (--header-timeout 1, --min-upload-rate 16K,
 * --max-connections-per-ip 8, --connection-timeout 30 so that only the
 * guard can be what closes):
 *   - headers trickled a byte at a time get a 408 problem and the
 *     connection closes; so do the headers of a second request on a
 *     kept-alive connection;
 *   - a body slower than the minimum rate gets a 408 (logged as such);
 *   - a fresh connection that sends nothing is closed without a word, a
 *     kept-alive connection between requests is left open;
 *   - an address may hold at most 8 connections; another address is
 *     still served meanwhile;
 *   - while trickling connections come and go, others are served.
 * Waits are hang guards; nothing asserts on how long a step took. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "harness.h"

static it_daemon d;

static int setup(void **state) {
    (void)state;
    const char *args[] = {"--header-timeout", "1", "--min-upload-rate", "16K",
                          "--max-connections-per-ip", "8",
                          "--connection-timeout", "30", NULL};
    return it_group_start(&d, args);
}

static int teardown(void **state) {
    (void)state;
    return it_group_stop(&d);
}

/* A connection from the given loopback address (127.0.0.x). */
static int connect_from(const char *src) {
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) return -1;
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    inet_pton(AF_INET, src, &a.sin_addr);
    if (bind(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        close(fd);
        return -1;
    }
    a.sin_port = htons((uint16_t)d.port);
    inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
    if (connect(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

/* Sends text a byte every `gap` seconds until the peer closes or `max`
 * bytes went out; then reads what it answered. Returns 1 if the peer
 * closed before all of text was sent. */
static int trickle(int fd, const char *text, double gap, char *buf,
                   size_t cap) {
    size_t n = strlen(text);
    int cut = 0;
    for (size_t i = 0; i < n; i++) {
        struct pollfd p = {fd, POLLIN, 0};
        if (poll(&p, 1, (int)(gap * 1000)) > 0) { /* an answer: stop */
            cut = 1;
            break;
        }
        if (send(fd, text + i, 1, MSG_NOSIGNAL) != 1) {
            cut = 1;
            break;
        }
    }
    int closed;
    it_recv_until(fd, buf, cap, 30, &closed);
    return cut;
}

static void test_trickled_headers_get_408(void **state) {
    (void)state;
    int fd = it_connect(d.port);
    assert_true(fd >= 0);
    char buf[4096];
    const char *req = "GET /healthz HTTP/1.1\r\nHost: x\r\nX-A: aaaaaaaaaaaaaaa"
                      "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa\r\n\r\n";
    assert_true(trickle(fd, req, 0.1, buf, sizeof buf));
    close(fd);
    assert_int_equal(it_raw_status(buf), 408);
    assert_non_null(strstr(buf, "\"type\":\"/problems/request-timeout\""));
    assert_non_null(strstr(buf, "--header-timeout"));

    /* Kept alive: one request answered, then the next trickled. */
    fd = it_connect(d.port);
    const char *first = "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n";
    assert_int_equal(it_send_all(fd, first, strlen(first)), 0);
    int closed;
    it_recv_response(fd, buf, sizeof buf, 30, &closed);
    assert_int_equal(it_raw_status(buf), 200);
    assert_false(closed);
    assert_true(trickle(fd, req, 0.1, buf, sizeof buf));
    close(fd);
    assert_int_equal(it_raw_status(buf), 408);
}

static void test_slow_body_gets_408(void **state) {
    (void)state;
    int fd = it_connect(d.port);
    const char *head = "POST /voronoi HTTP/1.1\r\nHost: x\r\nContent-Type: "
                       "text/plain\r\nContent-Length: 100000\r\n\r\n0 0\n";
    assert_int_equal(it_send_all(fd, head, strlen(head)), 0);
    char buf[4096];
    /* 20 bytes a second against a minimum of 16K a second. */
    trickle(fd, "1 1\n2 2\n3 3\n4 4\n5 5\n6 6\n7 7\n8 8\n9 9\n", 0.2, buf,
            sizeof buf);
    close(fd);
    assert_int_equal(it_raw_status(buf), 408);
    assert_non_null(strstr(buf, "--min-upload-rate"));
    assert_true(it_log_has(&d, "status=408"));
    assert_true(it_log_has(&d, "note=upload-too-slow"));
}

static void test_idle_connections(void **state) {
    (void)state;
    /* Fresh and silent: closed, nothing written. */
    int fresh = it_connect(d.port);
    /* Kept alive and idle between requests: left open. */
    int kept = it_connect(d.port);
    const char *req = "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n";
    char buf[4096];
    int closed;
    assert_int_equal(it_send_all(kept, req, strlen(req)), 0);
    it_recv_response(kept, buf, sizeof buf, 30, &closed);
    assert_int_equal(it_raw_status(buf), 200);

    size_t n = it_recv_until(fresh, buf, sizeof buf, 30, &closed);
    assert_true(closed);
    assert_int_equal(n, 0);
    close(fresh);

    /* Well past the header deadline, the kept-alive one still works. */
    it_sleep(2.5);
    assert_int_equal(it_send_all(kept, req, strlen(req)), 0);
    it_recv_response(kept, buf, sizeof buf, 30, &closed);
    assert_int_equal(it_raw_status(buf), 200);
    close(kept);
}

static void test_per_address_limit(void **state) {
    (void)state;
    int fds[8];
    for (int i = 0; i < 8; i++) {
        fds[i] = connect_from("127.0.0.3");
        assert_true(fds[i] >= 0);
        const char *req = "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n";
        char buf[1024];
        int closed;
        assert_int_equal(it_send_all(fds[i], req, strlen(req)), 0);
        it_recv_response(fds[i], buf, sizeof buf, 30, &closed);
        assert_int_equal(it_raw_status(buf), 200);
    }
    /* The ninth from that address is closed at once... */
    int extra = connect_from("127.0.0.3");
    assert_true(extra >= 0);
    const char *req = "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n";
    (void)send(extra, req, strlen(req), MSG_NOSIGNAL);
    char buf[1024];
    int closed;
    size_t n = it_recv_until(extra, buf, sizeof buf, 30, &closed);
    assert_true(closed);
    assert_int_equal(it_raw_status(n ? buf : ""), 0);
    close(extra);
    /* ...while another address is served. */
    int other = connect_from("127.0.0.4");
    assert_true(other >= 0);
    assert_int_equal(it_send_all(other, req, strlen(req)), 0);
    it_recv_response(other, buf, sizeof buf, 30, &closed);
    assert_int_equal(it_raw_status(buf), 200);
    close(other);
    for (int i = 0; i < 8; i++) close(fds[i]);
}

static void test_tricklers_block_nobody(void **state) {
    (void)state;
    /* 6 connections trickling headers from one address... */
    int fds[6];
    for (int i = 0; i < 6; i++) {
        fds[i] = connect_from("127.0.0.5");
        assert_true(fds[i] >= 0);
        assert_int_equal(it_send_all(fds[i], "GET / HTTP/1.1\r\n", 16), 0);
    }
    /* ...and everyone else is served meanwhile, for longer than the
     * header deadline. */
    double until = it_now() + 2.5;
    int served = 0;
    while (it_now() < until) {
        for (int i = 0; i < 6; i++) (void)send(fds[i], "X", 1, MSG_NOSIGNAL);
        it_req q = {.path = "/voronoi", .body = "[[0,0],[1,0],[0,1]]",
                    .len = 19};
        it_resp r;
        it_http(&d, &q, &r);
        assert_int_equal(r.status, 200);
        it_free(&r);
        served++;
        it_sleep(0.05);
    }
    assert_true(served > 0);
    /* The tricklers were cut off with a 408 each. */
    for (int i = 0; i < 6; i++) {
        char buf[2048];
        int closed;
        it_recv_until(fds[i], buf, sizeof buf, 30, &closed);
        assert_true(closed);
        assert_int_equal(it_raw_status(buf), 408);
        close(fds[i]);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_trickled_headers_get_408),
        cmocka_unit_test(test_slow_body_gets_408),
        cmocka_unit_test(test_idle_connections),
        cmocka_unit_test(test_per_address_limit),
        cmocka_unit_test(test_tricklers_block_nobody),
    };
    return cmocka_run_group_tests_name("integration/slow", tests, setup,
                                       teardown);
}
