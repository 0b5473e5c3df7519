/* test_errors.c -- every error status of the service with its problem+json
 * body (type, title, status, detail, instance, and pointer or line where
 * the codec knows the place), against a daemon with small limits
 * (--max-body 64K, --max-points 1000). Oversized bodies must be refused
 * before they are sent. Responses are saved for the OpenAPI check. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "../../api/api.h"
#include "harness.h"

static it_daemon d;

static int setup(void **state) {
    (void)state;
    const char *args[] = {"--max-body", "64K", "--max-points", "1000", NULL};
    return it_group_start(&d, args);
}

static int teardown(void **state) {
    (void)state;
    return it_group_stop(&d);
}

typedef struct expect {
    const char *name;
    it_req q;
    long status;
    const char *type;       /* slug */
    const char *pointer;    /* NULL: must be absent */
    long line;              /* 0: must be absent */
    const char *in_detail;  /* substring of detail, or NULL */
    const char *allow;      /* Allow header, or NULL */
} expect;

/* Sends e->q and checks the problem document. */
static void check_problem(const expect *e) {
    it_resp r;
    it_http(&d, &e->q, &r);
    it_save(e->name, &e->q, &r);
    if (r.curl_rc != 0) fail_msg("%s: curl %s", e->name, r.err);
    if (r.status != e->status)
        fail_msg("%s: status %ld, expected %ld: %s", e->name, r.status,
                 e->status, r.body);
    char h[256];
    const char *ct = it_header(&r, "Content-Type", h, sizeof h);
    if (ct == NULL || strcmp(ct, "application/problem+json") != 0)
        fail_msg("%s: Content-Type %s", e->name, ct ? ct : "(none)");
    json_t *j = it_json(&r);
    if (j == NULL) fail_msg("%s: body is not JSON", e->name);
    char type[96];
    snprintf(type, sizeof type, "/problems/%s", e->type);
    const char *got_type = json_string_value(json_object_get(j, "type"));
    if (got_type == NULL || strcmp(got_type, type) != 0)
        fail_msg("%s: type %s, expected %s", e->name, got_type, type);
    assert_int_equal(json_integer_value(json_object_get(j, "status")), e->status);
    assert_non_null(json_string_value(json_object_get(j, "title")));
    const char *detail = json_string_value(json_object_get(j, "detail"));
    assert_non_null(detail);
    assert_true(strlen(detail) > 5);
    if (e->in_detail && strstr(detail, e->in_detail) == NULL)
        fail_msg("%s: detail \"%s\" lacks \"%s\"", e->name, detail, e->in_detail);
    const char *instance = json_string_value(json_object_get(j, "instance"));
    assert_non_null(instance);
    assert_int_equal(instance[0], '/');
    const char *ptr = json_string_value(json_object_get(j, "pointer"));
    if (e->pointer) {
        if (ptr == NULL || strcmp(ptr, e->pointer) != 0)
            fail_msg("%s: pointer %s, expected %s", e->name, ptr, e->pointer);
    } else if (ptr != NULL) {
        fail_msg("%s: unexpected pointer %s", e->name, ptr);
    }
    json_t *line = json_object_get(j, "line");
    if (e->line) assert_int_equal(json_integer_value(line), e->line);
    else assert_null(line);
    if (e->allow) {
        const char *allow = it_header(&r, "Allow", h, sizeof h);
        if (allow == NULL || strcmp(allow, e->allow) != 0)
            fail_msg("%s: Allow %s, expected %s", e->name, allow, e->allow);
    }
    /* Every answer can be traced and read cross-origin. */
    assert_non_null(it_header(&r, "X-Request-Id", h, sizeof h));
    assert_non_null(it_header(&r, "Access-Control-Allow-Origin", h, sizeof h));
    json_decref(j);
    it_free(&r);
}

#define JSON_CT "Content-Type: application/json"
#define BODY(s) .body = s, .len = sizeof s - 1

static void test_400_malformed(void **state) {
    (void)state;
    const expect cases[] = {
        {"err-400-syntax", {.path = "/voronoi", .headers = {JSON_CT},
                            BODY("{\"points\": [[0,0],")},
         400, "malformed", "/points/1", 0, "ends early", NULL},
        {"err-400-unknown-key", {.path = "/voronoi", .headers = {JSON_CT},
                                 BODY("{\"pts\": []}")},
         400, "malformed", "/pts", 0, "pts", NULL},
        {"err-400-empty", {.path = "/voronoi", .headers = {JSON_CT}, BODY("")},
         400, "malformed", NULL, 0, "empty", NULL},
        {"err-400-text-line", {.path = "/voronoi",
                               .headers = {"Content-Type: text/plain"},
                               BODY("0 0\n1 zz\n")},
         400, "malformed", NULL, 2, "line 2", NULL},
        {"err-400-binary-length", {.path = "/voronoi",
                                   .headers = {"Content-Type: application/octet-stream"},
                                   BODY("0123456789")},
         400, "malformed", NULL, 0, "16", NULL},
        {"err-400-query", {.path = "/voronoi?colour=red", BODY("[[0,0]]")},
         400, "malformed", NULL, 0, "colour", NULL},
        {"err-400-query-twice",
         {.path = "/voronoi?algorithm=flip&format=json&algorithm=fortune",
          BODY("[[0,0]]")},
         400, "malformed", NULL, 0, "\"algorithm\" given twice", NULL},
        {"err-400-compare", {.path = "/compare", .headers = {JSON_CT},
                             BODY("[[0,0],[1,")},
         400, "malformed", "/1/1", 0, NULL, NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        check_problem(&cases[i]);
}

static void test_404_405_406(void **state) {
    (void)state;
    const expect cases[] = {
        {"err-404", {.path = "/nope"}, 404, "not-found", NULL, 0, NULL, NULL},
        {"err-404-post", {.path = "/voronoi/extra", BODY("[[0,0]]")},
         404, "not-found", NULL, 0, NULL, NULL},
        {"err-404-options", {.method = "OPTIONS", .path = "/nope"},
         404, "not-found", NULL, 0, NULL, NULL},
        {"err-405-get-voronoi", {.path = "/voronoi"}, 405,
         "method-not-allowed", NULL, 0, "GET", "POST, OPTIONS"},
        {"err-405-put-page", {.method = "PUT", .path = "/", BODY("x")}, 405,
         "method-not-allowed", NULL, 0, "PUT", "GET, HEAD, OPTIONS"},
        {"err-405-delete-compare", {.method = "DELETE", .path = "/compare"},
         405, "method-not-allowed", NULL, 0, NULL, "POST, OPTIONS"},
        {"err-405-post-metrics", {.path = "/metrics", BODY("x")}, 405,
         "method-not-allowed", NULL, 0, NULL, "GET, HEAD, OPTIONS"},
        {"err-406", {.path = "/voronoi", .headers = {"Accept: text/html"},
                     BODY("[[0,0]]")},
         406, "not-acceptable", NULL, 0, "text/html", NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        check_problem(&cases[i]);
}

static void test_413_too_large(void **state) {
    (void)state;
    /* A body over --max-body, with Content-Length and chunked. */
    size_t n = 100 * 1024;
    char *big = malloc(n);
    for (size_t i = 0; i < n; i++) big[i] = "0 0\n"[i % 4];
    expect e1 = {"err-413-length", {.path = "/voronoi", .body = big, .len = n,
                                    .headers = {"Content-Type: text/plain"}},
                 413, "too-large", NULL, 0, "65536", NULL};
    check_problem(&e1);
    expect e2 = {"err-413-chunked", {.path = "/voronoi", .body = big, .len = n,
                                     .chunked = 1,
                                     .headers = {"Content-Type: text/plain"}},
                 413, "too-large", NULL, 0, "65536", NULL};
    check_problem(&e2);
    free(big);
    /* More points than --max-points. */
    expect e3 = {"err-413-points", {.path = "/voronoi", .headers = {JSON_CT},
                                    BODY("{\"generate\": {\"n\": 5000}}")},
                 413, "too-large", "/generate/n", 0, "1000", NULL};
    check_problem(&e3);
    char *many = malloc(20000);
    size_t k = (size_t)sprintf(many, "[");
    for (int i = 0; i < 1001; i++) k += (size_t)sprintf(many + k, "%s[%d,0]", i ? "," : "", i);
    many[k++] = ']';
    expect e4 = {"err-413-points-json", {.path = "/compare", .body = many,
                                         .len = k},
                 413, "too-large", NULL, 0, "1000", NULL};
    it_resp r;
    it_http(&d, &e4.q, &r);
    assert_int_equal(r.status, 413);
    it_free(&r);
    free(many);

    /* Refused before the body is sent: the answer comes back while the
     * client has sent nothing but the headers. */
    int fd = it_connect(d.port);
    assert_true(fd >= 0);
    const char *head = "POST /voronoi HTTP/1.1\r\nHost: x\r\n"
                       "Content-Type: text/csv\r\n"
                       "Content-Length: 1000000000\r\n\r\n";
    assert_int_equal(it_send_all(fd, head, strlen(head)), 0);
    char buf[4096];
    int closed;
    it_recv_until(fd, buf, sizeof buf, 30, &closed);
    assert_int_equal(it_raw_status(buf), 413);
    assert_non_null(strstr(buf, "application/problem+json"));
    assert_true(closed); /* the unread body is not waited for */
    close(fd);
}

static void test_415_422(void **state) {
    (void)state;
    const expect cases[] = {
        {"err-415", {.path = "/voronoi", .headers = {"Content-Type: application/xml"},
                     BODY("<points/>")},
         415, "unsupported-media-type", NULL, 0, "application/xml", NULL},
        {"err-415-multipart", {.path = "/compare",
                               .headers = {"Content-Type: multipart/form-data; boundary=x"},
                               BODY("--x--")},
         415, "unsupported-media-type", NULL, 0, "multipart", NULL},
        {"err-422-overflow", {.path = "/voronoi", .headers = {JSON_CT},
                              BODY("{\"points\": [[0,0],[1e999,1]]}")},
         422, "invalid", "/points/1/0", 0, "1e999", NULL},
        {"err-422-type", {.path = "/voronoi", .headers = {JSON_CT},
                          BODY("{\"points\": [[0,\"a\"]]}")},
         422, "invalid", "/points/0/1", 0, NULL, NULL},
        {"err-422-bounds", {.path = "/voronoi", .headers = {JSON_CT},
                            BODY("{\"points\":[[0,0]],\"bounds\":[1,0,0,1]}")},
         422, "invalid", "/bounds", 0, "xmin", NULL},
        {"err-422-nan-line", {.path = "/voronoi", .headers = {"Content-Type: text/csv"},
                              BODY("0,0\n1,nan\n")},
         422, "invalid", NULL, 2, "nan", NULL},
        {"err-422-algorithm", {.path = "/voronoi?algorithm=quick", BODY("[[0,0]]")},
         422, "invalid", NULL, 0, "quick", NULL},
        {"err-422-format", {.path = "/voronoi?format=png", BODY("[[0,0]]")},
         422, "invalid", NULL, 0, "png", NULL},
        {"err-422-include", {.path = "/voronoi?include=vertices,foo", BODY("[[0,0]]")},
         422, "invalid", NULL, 0, "foo", NULL},
        {"err-422-query-bounds", {.path = "/compare?bounds=1,2,3", BODY("[[0,0]]")},
         422, "invalid", NULL, 0, "1,2,3", NULL},
        {"err-422-generate", {.path = "/voronoi", .headers = {JSON_CT},
                              BODY("{\"generate\": {\"n\": 10, \"distribution\": \"zipf\"}}")},
         422, "invalid", "/generate/distribution", 0, "zipf", NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        check_problem(&cases[i]);
}

static void test_still_healthy(void **state) {
    (void)state;
    it_resp r;
    it_req q = {.path = "/healthz"};
    it_http(&d, &q, &r);
    assert_int_equal(r.status, 200);
    it_free(&r);
    /* Every problem above was counted. */
    q.path = "/metrics";
    it_http(&d, &q, &r);
    assert_non_null(strstr(r.body, "voronoid_requests_total{route=\"/voronoi\","
                                   "status=\"422\"}"));
    assert_non_null(strstr(r.body, "voronoid_requests_total{route=\"other\","
                                   "status=\"404\"}"));
    it_free(&r);
}

/* The type URI of every problem leads to a page about it. */
static void test_problem_type_pages(void **state) {
    (void)state;
    for (int c = 0; c < API_CODE_COUNT; c++) {
        if (c == API_OK) continue;
        char path[96];
        snprintf(path, sizeof path, "/problems/%s", api_code_slug((api_code)c));
        it_req q = {.path = path};
        it_resp r;
        it_http(&d, &q, &r);
        if (c == API_MALFORMED) it_save("problem-type", &q, &r);
        if (r.status != 200) fail_msg("%s: %ld", path, r.status);
        char h[128];
        assert_string_equal(it_header(&r, "Content-Type", h, sizeof h),
                            "text/html; charset=utf-8");
        assert_non_null(strstr(r.body, api_code_title((api_code)c)));
        it_free(&r);
    }
    it_req q = {.path = "/problems/no-such-thing"};
    it_resp r;
    it_http(&d, &q, &r);
    it_save("problem-type-404", &q, &r);
    assert_int_equal(r.status, 404);
    it_free(&r);
}

/* Runs $VOR_DAEMON with args; returns its exit status, its output in out. */
static int run_daemon(const char *const *args, char *out, size_t cap) {
    char tmpl[] = "/tmp/voronoid-flags-XXXXXX";
    int fd = mkstemp(tmpl);
    assert_true(fd >= 0);
    pid_t pid = fork();
    if (pid == 0) {
        dup2(fd, 1);
        dup2(fd, 2);
        const char *argv[16] = {getenv("VOR_DAEMON")};
        for (int i = 0; args[i] && i < 14; i++) argv[i + 1] = args[i];
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    int status;
    waitpid(pid, &status, 0);
    close(fd);
    char *text = it_read_file(tmpl, NULL);
    snprintf(out, cap, "%s", text ? text : "");
    free(text);
    unlink(tmpl);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

static void test_bad_flags_exit_2(void **state) {
    (void)state;
    static const struct {
        const char *args[4];
        const char *must_say;
    } cases[] = {
        {{"--port", "http", NULL}, "--port: 'http'"},
        {{"--workers=0", NULL}, "--workers: '0'"},
        {{"--max-body", "lots", NULL}, "--max-body: 'lots'"},
        {{"--timeout", "-1", NULL}, "--timeout: '-1'"},
        {{"--bind", "example.org", NULL}, "--bind: 'example.org'"},
        {{"--web-dir", "/no/such/dir", NULL}, "--web-dir: '/no/such/dir'"},
        {{"--colour", "red", NULL}, "--colour"},
        {{"--queue", NULL}, "missing value for --queue"},
    };
    char out[4096];
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int rc = run_daemon(cases[i].args, out, sizeof out);
        if (rc != 2 || strstr(out, cases[i].must_say) == NULL)
            fail_msg("case %zu: exit %d, said: %s", i, rc, out);
    }
    const char *help[] = {"--help", NULL};
    assert_int_equal(run_daemon(help, out, sizeof out), 0);
    assert_non_null(strstr(out, "VORONOID_PORT"));
    /* The environment is checked the same way. */
    setenv("VORONOID_QUEUE", "many", 1);
    const char *none[] = {NULL};
    int rc = run_daemon(none, out, sizeof out);
    unsetenv("VORONOID_QUEUE");
    assert_int_equal(rc, 2);
    assert_non_null(strstr(out, "VORONOID_QUEUE: 'many'"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_400_malformed),
        cmocka_unit_test(test_404_405_406),
        cmocka_unit_test(test_413_too_large),
        cmocka_unit_test(test_415_422),
        cmocka_unit_test(test_still_healthy),
        cmocka_unit_test(test_problem_type_pages),
        cmocka_unit_test(test_bad_flags_exit_2),
    };
    return cmocka_run_group_tests_name("integration/errors", tests, setup,
                                       teardown);
}
