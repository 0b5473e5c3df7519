/* test_overload.c -- back-pressure and deadlines:
 *   - with one worker and a queue of one, a burst of slow requests gets
 *     503 + Retry-After for what does not fit, 200 for the rest, and the
 *     service recovers once the burst is over;
 *   - with a short --timeout, a request being computed and one waiting in
 *     the queue both answer 504, and the service recovers;
 *   - a computation past its deadline stops (the core is asked whether
 *     to go on), and its worker is free again; so does one whose client
 *     hung up, but not one whose client pipelines its next request.
 * Slow requests are sized on this machine first (it_calibrate); the tests
 * assert outcomes, never durations. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "harness.h"

static size_t slow_n;

/* Waits (hang guard) until no worker is busy. */
static void wait_workers_idle(const it_daemon *d) {
    for (int i = 0; i < 6000; i++) {
        if (it_get_metric(d, "voronoid_workers_busy") == 0) return;
        it_sleep(0.02);
    }
    fail_msg("workers still busy");
}

static const char square_json[] =
    "{\"points\": [[0,0],[1,0],[0,1],[1,1],[0.5,0.5]]}";

static void small_request_works(const it_daemon *d) {
    it_req q = {.path = "/voronoi", .body = square_json,
                .len = strlen(square_json)};
    it_resp r;
    it_http(d, &q, &r);
    assert_int_equal(r.status, 200);
    json_t *j = it_json(&r);
    assert_int_equal(json_integer_value(json_object_get(j, "n_vertices")), 4);
    json_decref(j);
    it_free(&r);
}

static void test_full_queue_503_then_recovers(void **state) {
    (void)state;
    it_daemon d;
    const char *args[] = {"--workers", "1", "--queue", "1", NULL};
    assert_int_equal(it_start(&d, args), 0);
    slow_n = it_calibrate(&d, 0.4, 1000000);

    enum { N = 6 };
    char body[256];
    it_slow_body(body, sizeof body, slow_n);
    it_req q[N];
    it_resp r[N];
    memset(q, 0, sizeof q);
    for (int i = 0; i < N; i++) {
        q[i].path = "/voronoi";
        q[i].body = body;
        q[i].len = strlen(body);
    }
    it_parallel(&d, q, r, N);
    int ok = 0, busy = 0;
    for (int i = 0; i < N; i++) {
        if (r[i].curl_rc != 0) fail_msg("client %d: %s", i, r[i].err);
        char h[256];
        if (r[i].status == 200) {
            ok++;
            json_t *j = it_json(&r[i]);
            assert_non_null(json_object_get(j, "compute_ms"));
            json_decref(j);
        } else if (r[i].status == 503) {
            busy++;
            const char *ra = it_header(&r[i], "Retry-After", h, sizeof h);
            assert_non_null(ra);
            assert_true(atoi(ra) >= 1);
            json_t *j = it_json(&r[i]);
            assert_string_equal(json_string_value(json_object_get(j, "type")),
                                "/problems/unavailable");
            assert_non_null(strstr(json_string_value(json_object_get(j, "detail")),
                                   "busy"));
            json_decref(j);
            if (busy == 1) it_save("voronoi-503-queue-full", &q[i], &r[i]);
        } else {
            fail_msg("client %d: status %ld %s", i, r[i].status, r[i].body);
        }
        it_free(&r[i]);
    }
    printf("burst of %d: %d answered, %d refused with 503\n", N, ok, busy);
    assert_true(ok >= 2);   /* the running one and the queued one */
    assert_true(busy >= 1);
    /* Recovered. */
    small_request_works(&d);
    assert_int_equal(it_get_metric(&d, "voronoid_queue_depth"), 0);
    assert_true(it_get_metric(&d, "voronoid_requests_total{route=\"/voronoi\","
                               "status=\"503\"}") >= busy);
    assert_int_equal(it_cleanup(&d), 0);
}

static void test_deadline_504(void **state) {
    (void)state;
    it_daemon d;
    const char *args[] = {"--workers", "1", "--queue", "4", "--timeout",
                          "0.1", NULL};
    assert_int_equal(it_start(&d, args), 0);
    char body[256];
    it_slow_body(body, sizeof body, slow_n);
    it_req q[2];
    it_resp r[2];
    memset(q, 0, sizeof q);
    for (int i = 0; i < 2; i++) {
        q[i].path = i ? "/compare" : "/voronoi";
        q[i].body = body;
        q[i].len = strlen(body);
    }
    it_parallel(&d, q, r, 2);
    int running = 0, queued = 0;
    for (int i = 0; i < 2; i++) {
        if (r[i].status != 504)
            fail_msg("request %d: %ld %s", i, r[i].status, r[i].body);
        json_t *j = it_json(&r[i]);
        assert_string_equal(json_string_value(json_object_get(j, "type")),
                            "/problems/timeout");
        const char *detail = json_string_value(json_object_get(j, "detail"));
        running += strstr(detail, "being computed") != NULL;
        queued += strstr(detail, "waiting in the queue") != NULL;
        json_decref(j);
        if (i == 0) it_save("voronoi-504", &q[i], &r[i]);
        it_free(&r[i]);
    }
    /* One held the only worker past its deadline, the other never left
     * the queue. */
    assert_int_equal(running, 1);
    assert_int_equal(queued, 1);
    /* The abandoned computation stops in the background; then all is well
     * (a generous deadline is not needed for 5 points). */
    wait_workers_idle(&d);
    small_request_works(&d);
    assert_true(it_get_metric(&d, "voronoid_requests_total{route=\"/voronoi\","
                               "status=\"504\"}") == 1);
    assert_true(it_log_has(&d, "path=/compare status=504"));
    assert_int_equal(it_cleanup(&d), 0);
}

/* A daemon with one worker and --timeout timeout, sized (it_calibrate):
 * *n points make a /voronoi of about 0.2 s here; *stopped receives
 * voronoid_computations_stopped_total once the worker is idle. */
static void one_worker(it_daemon *d, const char *timeout, size_t *n,
                       double *stopped) {
    const char *args[] = {"--workers", "1", "--timeout", timeout, NULL};
    assert_int_equal(it_start(d, args), 0);
    *n = it_calibrate(d, 0.2, 1000000);
    wait_workers_idle(d);
    *stopped = it_get_metric(d, "voronoid_computations_stopped_total");
}

/* The body of a slow comparison of n generated points, timings only,
 * with repeat runs each (0: the default); its length. */
static int slow_compare(char *body, size_t size, size_t n, size_t repeat) {
    char rep[48] = "";
    if (repeat) snprintf(rep, sizeof rep, ", \"repeat\": %zu", repeat);
    return snprintf(body, size,
                    "{\"generate\": {\"distribution\": \"uniform\", \"n\": "
                    "%zu, \"seed\": 3}, \"format\": \"timings\"%s}",
                    n, rep);
}

/* A computation whose answer nobody waits for any more stops: a
 * comparison many times longer than the deadline (--timeout twice as long
 * as one slow /voronoi, so that it passes while the algorithms run, not
 * while the points are generated) answers 504, and the worker counts it
 * stopped. Were it left to finish, the count would not move. (A sizing
 * request past the deadline counts too: the count is compared with the
 * one before the comparison.) */
static void test_deadline_stops_computation(void **state) {
    (void)state;
    it_daemon d;
    size_t n;
    double before;
    one_worker(&d, "0.4", &n, &before);
    char body[256];
    slow_compare(body, sizeof body, n, 10000000 / n < 10 ? 10000000 / n : 10);
    it_req q = {.path = "/compare", .body = body, .len = strlen(body)};
    it_resp r;
    it_http(&d, &q, &r);
    if (r.status != 504) fail_msg("status %ld %s", r.status, r.body);
    it_free(&r);
    wait_workers_idle(&d);
    assert_true(it_get_metric(&d, "voronoid_computations_stopped_total") ==
                before + 1);
    small_request_works(&d);
    assert_int_equal(it_cleanup(&d), 0);
}

/* A client that hangs up while its comparison runs frees the worker: the
 * computation stops (the worker looks at the socket when the core asks
 * whether to go on) and is counted stopped, long before its deadline
 * (60 s here). Were it left to run, the count would not move. A client
 * that sends its next request meanwhile (pipelining) is no hang-up: its
 * comparison runs to the end and both answers come. */
static void test_hang_up_stops_computation(void **state) {
    (void)state;
    it_daemon d;
    size_t n;
    double before;
    one_worker(&d, "60", &n, &before);
    char body[256], req[512];
    int len = slow_compare(body, sizeof body, n, 10);
    int rl = snprintf(req, sizeof req,
                      "POST /compare HTTP/1.1\r\nHost: x\r\n"
                      "Content-Type: application/json\r\n"
                      "Content-Length: %d\r\n\r\n%s", len, body);
    int fd = it_connect(d.port);
    assert_true(fd >= 0);
    assert_int_equal(it_send_all(fd, req, (size_t)rl), 0);
    for (int i = 0; i < 3000 &&
                    it_get_metric(&d, "voronoid_workers_busy") == 0; i++)
        it_sleep(0.01);
    assert_true(it_get_metric(&d, "voronoid_workers_busy") == 1);
    close(fd);
    wait_workers_idle(&d);
    assert_true(it_get_metric(&d, "voronoid_computations_stopped_total") ==
                before + 1);
    small_request_works(&d);
    assert_true(it_log_has(&d, "note=client-gone"));

    /* pipelined: a small request right behind the slow one, then both
     * answers, 200 each, and nothing stopped */
    const char small[] = "{\"points\": [[0,0],[1,0],[0,1]]}";
    len = slow_compare(body, sizeof body, n, 0);
    char two[1024];
    int tl = snprintf(two, sizeof two,
                      "POST /compare HTTP/1.1\r\nHost: x\r\n"
                      "Content-Type: application/json\r\n"
                      "Content-Length: %d\r\n\r\n%s"
                      "POST /voronoi HTTP/1.1\r\nHost: x\r\n"
                      "Content-Type: application/json\r\n"
                      "Content-Length: %zu\r\n\r\n%s", len, body,
                      strlen(small), small);
    fd = it_connect(d.port);
    assert_true(fd >= 0);
    assert_int_equal(it_send_all(fd, two, (size_t)tl), 0);
    static char buf[1 << 16];
    int closed;
    it_recv_response(fd, buf, sizeof buf, 120, &closed);
    assert_int_equal(it_raw_status(buf), 200);
    /* the second answer may have come in the same read */
    const char *second = strstr(buf + 1, "HTTP/1.1 ");
    if (second == NULL) {
        it_recv_response(fd, buf, sizeof buf, 30, &closed);
        second = buf;
    }
    assert_int_equal(it_raw_status(second), 200);
    close(fd);
    assert_true(it_get_metric(&d, "voronoid_computations_stopped_total") ==
                before + 1);
    assert_int_equal(it_cleanup(&d), 0);
}

int main(void) {
    curl_global_init(CURL_GLOBAL_ALL);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full_queue_503_then_recovers),
        cmocka_unit_test(test_deadline_504),
        cmocka_unit_test(test_deadline_stops_computation),
        cmocka_unit_test(test_hang_up_stops_computation),
    };
    int rc = cmocka_run_group_tests_name("integration/overload", tests, NULL,
                                         NULL);
    curl_global_cleanup();
    return rc;
}
