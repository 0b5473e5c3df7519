/* test_accesslog.c -- access-log lines: every field, escaping of hostile
 * values, truncation, one line per call through a pipe; the buffered log
 * (srv_log): no line lost, split or reordered under several writers and a
 * full buffer, lines written without a flush, messages written at once. */
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
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

/* ---- the buffered log ---------------------------------------------------- */

/* An unlinked temporary file (a pipe would block the writer when full). */
static int temp_fd(void) {
    char path[] = "/tmp/test_accesslog_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    unlink(path);
    return fd;
}

/* The whole file, NUL-terminated; free it. */
static char *file_text(int fd) {
    off_t n = lseek(fd, 0, SEEK_END);
    assert_true(n >= 0);
    char *t = malloc((size_t)n + 1);
    assert_non_null(t);
    assert_int_equal(pread(fd, t, (size_t)n, 0), n);
    t[n] = '\0';
    return t;
}

#define WRITERS 4
#define LINES_EACH 3000

typedef struct writer_arg {
    srv_log *log;
    int who;
} writer_arg;

static void *writer(void *p) {
    writer_arg *w = p;
    char id[32], path[160];
    memset(path, 'p', sizeof path - 1);
    path[0] = '/';
    path[sizeof path - 1] = '\0';
    for (int i = 0; i < LINES_EACH; i++) {
        snprintf(id, sizeof id, "w%d-%d", w->who, i);
        srv_access a = {.method = "POST", .path = path, .status = 200,
                        .points = i, .request_id = id};
        srv_log_access(w->log, &a);
    }
    return NULL;
}

/* Several threads, far more than one buffer of lines: every line arrives
 * whole, once, and each thread's lines in the order it wrote them. */
static void test_log_many_writers(void **state) {
    (void)state;
    int fd = temp_fd();
    srv_log *log = srv_log_new(fd, 5);
    assert_non_null(log);
    pthread_t t[WRITERS];
    writer_arg args[WRITERS];
    for (int k = 0; k < WRITERS; k++) {
        args[k] = (writer_arg){log, k};
        assert_int_equal(pthread_create(&t[k], NULL, writer, &args[k]), 0);
    }
    for (int k = 0; k < WRITERS; k++) pthread_join(t[k], NULL);
    srv_log_free(log);

    char *text = file_text(fd);
    int next[WRITERS] = {0};
    int lines = 0;
    for (char *line = text; *line; lines++) {
        char *end = strchr(line, '\n');
        assert_non_null(end);
        *end = '\0';
        assert_int_equal(strncmp(line, "time=", 5), 0);
        const char *id = strstr(line, " id=w");
        assert_non_null(id);
        int who = -1, i = -1;
        assert_int_equal(sscanf(id, " id=w%d-%d", &who, &i), 2);
        assert_true(who >= 0 && who < WRITERS);
        assert_int_equal(i, next[who]); /* in order, none missing */
        next[who]++;
        char want[32];
        snprintf(want, sizeof want, " points=%d ", i);
        assert_non_null(strstr(line, want));
        line = end + 1;
    }
    assert_int_equal(lines, WRITERS * LINES_EACH);
    free(text);
    close(fd);
}

/* A line reaches the file without a flush (the writer thread's deadline),
 * and a message is written at once, after the lines before it. The wait
 * is a hang guard, not a timing requirement. */
static void test_log_written_without_flush(void **state) {
    (void)state;
    int fd = temp_fd();
    srv_log *log = srv_log_new(fd, 1);
    assert_non_null(log);
    srv_access a = {.method = "GET", .path = "/x", .status = 200,
                    .points = -1, .request_id = "lonely"};
    srv_log_access(log, &a);
    int seen = 0;
    for (int i = 0; i < 3000 && !seen; i++) {
        char *text = file_text(fd);
        seen = strstr(text, "id=lonely\n") != NULL;
        free(text);
        if (!seen) {
            struct timespec nap = {0, 10 * 1000 * 1000};
            nanosleep(&nap, NULL);
        }
    }
    assert_true(seen);

    srv_log *slow = srv_log_new(fd, 1000000); /* never on its own */
    assert_non_null(slow);
    a.request_id = "before";
    srv_log_access(slow, &a);
    srv_log_text(slow, "voronoid: a message\n", 20);
    char *text = file_text(fd);
    assert_non_null(strstr(text, "id=lonely\ntime="));
    assert_non_null(strstr(text, "id=before\nvoronoid: a message\n"));
    free(text);
    a.request_id = "last";
    srv_log_access(slow, &a);
    srv_log_free(slow); /* flushes */
    text = file_text(fd);
    assert_non_null(strstr(text, "voronoid: a message\ntime="));
    assert_non_null(strstr(text, "id=last\n"));
    free(text);
    srv_log_free(log);
    srv_log_free(NULL);
    close(fd);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_fields),
        cmocka_unit_test(test_missing_values_and_note),
        cmocka_unit_test(test_hostile_values_are_escaped),
        cmocka_unit_test(test_long_values_are_cut),
        cmocka_unit_test(test_write_one_line),
        cmocka_unit_test(test_log_many_writers),
        cmocka_unit_test(test_log_written_without_flush),
    };
    return cmocka_run_group_tests_name("server/accesslog", tests, NULL, NULL);
}
