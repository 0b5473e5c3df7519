/* test_accesslog.c -- access-log lines: every field, escaping of hostile
 * values, truncation, one line per call through a pipe. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "../../server/accesslog.h"

static void test_all_fields(void **state) {
    (void)state;
    srv_access a = {
        .unix_time = 1700000000.25, /* 2023-11-14T22:13:20.250Z */
        .method = "POST",
        .path = "/voronoi",
        .status = 200,
        .bytes = 5123,
        .ms = 4.2104,
        .algorithm = "bowyer-watson",
        .points = 1000,
        .request_id = "abc-123",
    };
    char line[SRV_ACCESS_LINE_MAX];
    size_t n = srv_access_format(&a, line, sizeof line);
    assert_int_equal(n, strlen(line));
    assert_string_equal(line,
                        "time=2023-11-14T22:13:20.250Z method=POST "
                        "path=/voronoi status=200 bytes=5123 ms=4.210 "
                        "algorithm=bowyer-watson points=1000 id=abc-123\n");
}

static void test_missing_values_and_note(void **state) {
    (void)state;
    srv_access a = {
        .unix_time = 0,
        .method = "GET",
        .path = "/healthz",
        .status = 0,
        .points = -1,
        .request_id = NULL,
        .note = "client-gone",
    };
    char line[SRV_ACCESS_LINE_MAX];
    srv_access_format(&a, line, sizeof line);
    assert_string_equal(line,
                        "time=1970-01-01T00:00:00.000Z method=GET "
                        "path=/healthz status=- bytes=0 ms=0.000 "
                        "algorithm=- points=- id=- note=client-gone\n");
}

static void test_hostile_values_are_escaped(void **state) {
    (void)state;
    srv_access a = {
        .method = "GET",
        .path = "/a b\"c\\d\n=e\x01\xff",
        .status = 404,
        .points = -1,
        .request_id = "x",
    };
    char line[SRV_ACCESS_LINE_MAX];
    srv_access_format(&a, line, sizeof line);
    assert_non_null(strstr(line, "path=\"/a b\\\"c\\\\d\\x0a=e\\x01\\xff\""));
    /* Exactly one newline, at the end. */
    assert_int_equal(strchr(line, '\n') - line, (long)strlen(line) - 1);
}

static void test_long_values_are_cut(void **state) {
    (void)state;
    char path[5000];
    memset(path, 'a', sizeof path - 1);
    path[sizeof path - 1] = '\0';
    path[0] = '/';
    char id[3000];
    memset(id, '\x7f', sizeof id - 1); /* escaped: 4 bytes each */
    id[sizeof id - 1] = '\0';
    srv_access a = {.method = path, .path = path, .status = 200,
                    .points = -1, .request_id = id, .algorithm = path,
                    .note = path};
    char line[SRV_ACCESS_LINE_MAX];
    size_t n = srv_access_format(&a, line, sizeof line);
    assert_true(n < SRV_ACCESS_LINE_MAX);
    assert_int_equal(line[n - 1], '\n');
    assert_non_null(strstr(line, "...")); /* marked as cut */
    /* A tiny buffer is still terminated. */
    char tiny[8];
    n = srv_access_format(&a, tiny, sizeof tiny);
    assert_true(n < sizeof tiny);
    assert_int_equal(tiny[n], '\0');
}

static void test_write_one_line(void **state) {
    (void)state;
    int fd[2];
    assert_int_equal(pipe(fd), 0);
    srv_access a = {.method = "GET", .path = "/", .status = 200,
                    .points = -1, .request_id = "r1"};
    srv_access_write(fd[1], &a);
    srv_access_write(fd[1], &a);
    close(fd[1]);
    char buf[4096];
    ssize_t got = read(fd[0], buf, sizeof buf - 1);
    close(fd[0]);
    assert_true(got > 0);
    buf[got] = '\0';
    int lines = 0;
    for (char *p = buf; *p; p++) lines += *p == '\n';
    assert_int_equal(lines, 2);
    assert_non_null(strstr(buf, "id=r1\ntime="));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_fields),
        cmocka_unit_test(test_missing_values_and_note),
        cmocka_unit_test(test_hostile_values_are_escaped),
        cmocka_unit_test(test_long_values_are_cut),
        cmocka_unit_test(test_write_one_line),
    };
    return cmocka_run_group_tests_name("server/accesslog", tests, NULL, NULL);
}
