/* test_cli.c -- the voronoi command, run as a separate process.
 *
 * The binary's path comes from VOR_CLI (set by `make unit`). Inputs are
 * written to a fresh temporary directory; the command runs through
 * posix_spawn with stdin, stdout and stderr redirected to files, and its
 * exit status, output (read back with jansson) and messages are checked.
 * Also the command line `make run` starts the service with (make -n). */
#include <errno.h>
#include <fcntl.h>
#include <jansson.h>
#include <setjmp.h>
#include <spawn.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>

extern char **environ;

static const char *cli;
static char dir[256];

typedef struct run {
    int status;  /* exit status, or -1 if killed */
    char *out;   /* whole stdout, NUL-terminated */
    size_t out_len;
    char *err;   /* whole stderr */
} run;

static char *slurp(const char *path, size_t *len) {
    FILE *f = fopen(path, "rb");
    if (f == NULL) fail_msg("cannot read %s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    if (fread(buf, 1, (size_t)n, f) != (size_t)n) fail_msg("short read of %s", path);
    buf[n] = 0;
    fclose(f);
    if (len) *len = (size_t)n;
    return buf;
}

static void put_file(const char *name, const void *data, size_t len) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (f == NULL || fwrite(data, 1, len, f) != len) fail_msg("cannot write %s", path);
    fclose(f);
}

static void put_text(const char *name, const char *text) { put_file(name, text, strlen(text)); }

/* Runs the command with args (NULL-terminated, without argv[0]); stdin
 * from the file named stdin_name in dir (NULL: /dev/null). File arguments
 * starting with '@' are taken relative to dir. */
static run run_cli(const char *stdin_name, const char *const *args) {
    char in[512], out[512], err[512];
    snprintf(in, sizeof in, "%s/%s", dir, stdin_name ? stdin_name : "");
    snprintf(out, sizeof out, "%s/stdout", dir);
    snprintf(err, sizeof err, "%s/stderr", dir);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, stdin_name ? in : "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 1, out, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    posix_spawn_file_actions_addopen(&fa, 2, err, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    char *argv[32];
    char paths[16][512];
    int n = 0, np = 0;
    argv[n++] = (char *)cli;
    for (; *args; args++) {
        if ((*args)[0] == '@') {
            snprintf(paths[np], sizeof paths[np], "%s/%s", dir, *args + 1);
            argv[n++] = paths[np++];
        } else {
            argv[n++] = (char *)*args;
        }
    }
    argv[n] = NULL;
    pid_t pid;
    int rc = posix_spawn(&pid, cli, &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) fail_msg("cannot run %s: %s", cli, strerror(rc));
    int ws;
    while (waitpid(pid, &ws, 0) < 0 && errno == EINTR) {}
    run r;
    r.status = WIFEXITED(ws) ? WEXITSTATUS(ws) : -1;
    r.out = slurp(out, &r.out_len);
    r.err = slurp(err, NULL);
    return r;
}

static void run_free(run *r) {
    free(r->out);
    free(r->err);
}

#define RUN(stdin_name, ...) run_cli((stdin_name), (const char *const[]){__VA_ARGS__, NULL})

static void expect_status(const run *r, int status) {
    if (r->status != status) {
        fail_msg("exit status %d, expected %d; stderr: %s", r->status, status, r->err);
    }
}

static json_t *json_out(const run *r) {
    json_error_t e;
    json_t *j = json_loadb(r->out, r->out_len, 0, &e);
    if (j == NULL) fail_msg("output is not JSON (%s): %.300s", e.text, r->out);
    return j;
}

static long long jint(json_t *j, const char *key) {
    json_t *v = json_object_get(j, key);
    if (!json_is_integer(v)) fail_msg("no integer \"%s\"", key);
    return json_integer_value(v);
}

static int setup(void **state) {
    (void)state;
    cli = getenv("VOR_CLI");
    if (cli == NULL || access(cli, X_OK) != 0) return 0;
    snprintf(dir, sizeof dir, "%s/voronoi-cli-XXXXXX",
             getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
    if (mkdtemp(dir) == NULL) return -1;
    return 0;
}

static int teardown(void **state) {
    (void)state;
    if (dir[0]) {
        static const char *const names[] = {"stdout", "stderr", "p.csv", "p.json",
                                            "p.bin", "odd.bin", "bad.csv", "bad.json",
                                            "flip.json", "p.txt", "noext", "rep.json"};
        for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
            char path[512];
            snprintf(path, sizeof path, "%s/%s", dir, names[i]);
            unlink(path);
        }
        rmdir(dir);
    }
    return 0;
}

#define NEED_CLI()                                                     \
    do {                                                               \
        if (cli == NULL || access(cli, X_OK) != 0) {                   \
            printf("# VOR_CLI not set or not executable: skipped\n");  \
            skip();                                                    \
        }                                                              \
    } while (0)

/* Five points: a square and its centre (one duplicated). */
static const char csv[] = "# a square and its centre\n"
                          "x,y\n"
                          "0,0\r\n"
                          "4 0\n"
                          "4\t4\n"
                          "0,4\n"
                          "2, 2\n"
                          "0,0\n";

static void check_square(json_t *j) {
    assert_int_equal(jint(j, "n_input"), 6);
    assert_int_equal(jint(j, "n_sites"), 5);
    assert_int_equal(jint(j, "n_vertices"), 4);
    assert_int_equal(jint(j, "n_edges"), 8);
    json_t *d = json_object_get(j, "duplicates");
    assert_int_equal(json_array_size(d), 1);
    assert_int_equal(json_integer_value(json_array_get(json_array_get(d, 0), 0)), 5);
    assert_int_equal(json_integer_value(json_array_get(json_array_get(d, 0), 1)), 0);
    assert_int_equal(json_array_size(json_object_get(j, "cells")), 5);
}

static void test_csv_file(void **state) {
    (void)state;
    NEED_CLI();
    put_text("p.csv", csv);
    run r = RUN(NULL, "@p.csv");
    expect_status(&r, 0);
    json_t *j = json_out(&r);
    check_square(j);
    assert_string_equal(json_string_value(json_object_get(j, "algorithm")), "fortune");
    json_decref(j);
    run_free(&r);
    /* .txt is text too; no extension is sniffed. */
    put_text("p.txt", csv);
    r = RUN(NULL, "-a", "flip", "@p.txt");
    expect_status(&r, 0);
    j = json_out(&r);
    check_square(j);
    json_decref(j);
    run_free(&r);
    put_text("noext", csv);
    r = RUN(NULL, "@noext");
    expect_status(&r, 0);
    run_free(&r);
}

static void test_json_file_and_stdin(void **state) {
    (void)state;
    NEED_CLI();
    const char *body = "{\"points\": [[0,0],[4,0],[4,4],[0,4],[2,2],[0,0]], "
                       "\"include\": [\"vertices\", \"triangles\", \"sites\"]}";
    put_text("p.json", body);
    run r = RUN(NULL, "--algorithm", "bowyer-watson", "@p.json");
    expect_status(&r, 0);
    json_t *j = json_out(&r);
    assert_int_equal(jint(j, "n_sites"), 5);
    assert_int_equal(json_array_size(json_object_get(j, "triangles")), 4);
    assert_int_equal(json_array_size(json_object_get(j, "sites")), 6);
    assert_null(json_object_get(j, "edges"));
    json_decref(j);
    run_free(&r);
    /* The same body on standard input, named "-" or not named at all. */
    r = RUN("p.json", "-", "--algorithm", "flip");
    expect_status(&r, 0);
    j = json_out(&r);
    assert_string_equal(json_string_value(json_object_get(j, "algorithm")), "flip");
    json_decref(j);
    run_free(&r);
    put_text("p.csv", csv);
    r = RUN("p.csv", "--input", "csv", "-a", "flip");
    expect_status(&r, 0);
    j = json_out(&r);
    check_square(j);
    json_decref(j);
    run_free(&r);
    /* The command line wins over the body. */
    put_text("flip.json", "{\"algorithm\": \"flip\", \"points\": [[0,0],[1,0],[0,1]]}");
    r = RUN(NULL, "-a", "bowyer-watson", "@flip.json");
    expect_status(&r, 0);
    j = json_out(&r);
    assert_string_equal(json_string_value(json_object_get(j, "algorithm")),
                        "bowyer-watson");
    json_decref(j);
    run_free(&r);
}

static void test_binary_file(void **state) {
    (void)state;
    NEED_CLI();
    double v[] = {0, 0, 4, 0, 4, 4, 0, 4, 2, 2, 0, 0};
    unsigned char b[sizeof v];
    for (size_t i = 0; i < 12; i++) {
        uint64_t u;
        memcpy(&u, &v[i], 8);
        for (int k = 0; k < 8; k++) b[8 * i + (size_t)k] = (unsigned char)(u >> (8 * k));
    }
    put_file("p.bin", b, sizeof b);
    run r = RUN(NULL, "-a", "flip", "@p.bin");
    expect_status(&r, 0);
    json_t *j = json_out(&r);
    check_square(j);
    json_decref(j);
    run_free(&r);
    /* Binary output: the magic and the counts. */
    r = RUN(NULL, "-a", "flip", "--format", "binary", "@p.bin");
    expect_status(&r, 0);
    assert_true(r.out_len > 48);
    assert_memory_equal(r.out, "VORB", 4);
    assert_int_equal((unsigned char)r.out[16], 6); /* n_input */
    assert_int_equal((unsigned char)r.out[20], 5); /* n_sites */
    run_free(&r);
}

static void test_generate_and_formats(void **state) {
    (void)state;
    NEED_CLI();
    run r = RUN(NULL, "--generate", "grid:16", "--format", "timings", "-a", "flip");
    expect_status(&r, 0);
    json_t *j = json_out(&r);
    assert_int_equal(json_object_size(j), 10); /* 3 labels, 7 timings */
    assert_string_equal(json_string_value(json_object_get(j, "algorithm")), "flip");
    assert_int_equal(jint(j, "n_input"), 16);
    assert_int_equal(jint(j, "n_sites"), 16);
    assert_true(json_is_number(json_object_get(j, "compute_ms")));
    assert_true(json_is_number(json_object_get(j, "total_ms")));
    json_decref(j);
    run_free(&r);

    r = RUN(NULL, "-g", "random:2000:5", "-a", "bowyer-watson");
    expect_status(&r, 0);
    j = json_out(&r);
    assert_int_equal(jint(j, "n_input"), 2000);
    assert_true(jint(j, "n_sites") < 2000); /* 2000 pixels of 480000 repeat */
    json_decref(j);
    run_free(&r);
    /* Same seed, same output (timings aside): compare the counts. */
    run a = RUN(NULL, "-g", "uniform:500:9", "-a", "flip", "--include", "vertices");
    run b = RUN(NULL, "-g", "uniform:500:9", "-a", "flip", "--include", "vertices");
    expect_status(&a, 0);
    expect_status(&b, 0);
    json_t *ja = json_out(&a), *jb = json_out(&b);
    assert_true(json_equal(json_object_get(ja, "vertices"), json_object_get(jb, "vertices")));
    json_decref(ja);
    json_decref(jb);
    run_free(&a);
    run_free(&b);

    r = RUN(NULL, "-g", "circle:12", "-a", "flip", "--format", "geojson");
    expect_status(&r, 0);
    j = json_out(&r);
    assert_string_equal(json_string_value(json_object_get(j, "type")), "FeatureCollection");
    assert_int_equal(json_array_size(json_object_get(j, "features")), 12);
    json_decref(j);
    run_free(&r);

    r = RUN(NULL, "-g", "uniform:50:3", "-a", "flip", "-f", "svg", "-b", "0,0,1,1");
    expect_status(&r, 0);
    assert_memory_equal(r.out, "<svg ", 5);
    size_t circles = 0;
    for (const char *p = r.out; (p = strstr(p, "<circle ")) != NULL; p++) circles++;
    assert_int_equal(circles, 50);
    run_free(&r);

    r = RUN(NULL, "-g", "uniform:50:3", "-a", "flip", "-b", "0,0,1,1");
    expect_status(&r, 0);
    j = json_out(&r);
    assert_true(json_is_object(json_object_get(j, "clipped")));
    json_decref(j);
    run_free(&r);
}

/* Text output ends with exactly one newline; binary output with none. */
static void test_trailing_newline(void **state) {
    (void)state;
    NEED_CLI();
    static const char *const formats[] = {"json", "geojson", "svg", "timings", NULL};
    for (int i = 0; i <= 4; i++) {
        run r = formats[i] ? RUN(NULL, "-g", "uniform:10", "-f", formats[i])
                           : RUN(NULL, "-c", "-r", "1", "-g", "uniform:10");
        expect_status(&r, 0);
        if (r.out_len < 2 || r.out[r.out_len - 1] != '\n' || r.out[r.out_len - 2] == '\n')
            fail_msg("%s: output does not end with one newline",
                     formats[i] ? formats[i] : "--compare");
        run_free(&r);
    }
    run r = RUN(NULL, "-g", "uniform:10", "-f", "binary");
    expect_status(&r, 0);
    assert_int_equal(r.out_len % 8, 0);
    assert_memory_equal(r.out, "VORB", 4);
    run_free(&r);
}

/* The voronoid command line `make run` would run (make -n), from the
 * repository root with a clean make environment; env is prepended to the
 * make command (e.g. "VORONOID_PORT=1234"). Returns a new string: the
 * last line that runs voronoid. */
static char *make_run_line(const char *env, const char *args) {
    char cmd[512];
    snprintf(cmd, sizeof cmd,
             "env -u PORT -u ARGS -u MAKEFLAGS -u MFLAGS -u MAKELEVEL %s "
             "make -n -s --no-print-directory run %s 2>&1",
             env, args);
    FILE *f = popen(cmd, "r");
    if (f == NULL) fail_msg("cannot run %s", cmd);
    char line[1024], *found = NULL;
    while (fgets(line, sizeof line, f) != NULL) {
        if (strstr(line, "/voronoid") != NULL && strncmp(line, "./", 2) == 0) {
            free(found);
            found = strdup(line);
        }
    }
    int rc = pclose(f);
    if (rc != 0 || found == NULL) fail_msg("%s: status %d, no voronoid line", cmd, rc);
    return found;
}

/* make run PORT=... ARGS=...: the port only when given, so that
 * VORONOID_PORT in the environment is not overridden by a fixed flag. */
static void test_make_run(void **state) {
    (void)state;
    if (access("Makefile", R_OK) != 0 || access("cli/voronoi.c", R_OK) != 0) {
        fail_msg("run from the repository root (make unit does)");
    }
    char *l = make_run_line("", "PORT=0 ARGS='--workers 1 --queue 5'");
    if (strstr(l, "voronoid --port 0 --workers 1 --queue 5") == NULL) fail_msg("%s", l);
    free(l);
    l = make_run_line("VORONOID_PORT=1234", "");
    if (strstr(l, "--port") != NULL || strstr(l, "--bind") != NULL) fail_msg("%s", l);
    free(l);
    l = make_run_line("", "ARGS=--help");
    if (strstr(l, "voronoid --help") == NULL) fail_msg("%s", l);
    free(l);
}

static void test_compare(void **state) {
    (void)state;
    NEED_CLI();
    run r = RUN(NULL, "--compare", "-g", "uniform:300:4");
    expect_status(&r, 0);
    json_t *j = json_out(&r);
    json_t *algos = json_object_get(j, "algorithms");
    assert_int_equal(json_array_size(algos), 3);
    int all_ok = 1;
    for (size_t i = 0; i < 3; i++) {
        json_t *a = json_array_get(algos, i);
        const char *st = json_string_value(json_object_get(a, "status"));
        all_ok &= strcmp(st, "ok") == 0;
        /* every algorithm's counts: Fortune sees each of the 300 sites */
        json_t *c = json_object_get(a, "counts");
        assert_true(json_is_object(c));
        if (i == 0) assert_int_equal(json_integer_value(json_object_get(c, "site_events")), 300);
        else assert_true(json_integer_value(json_object_get(c, "incircle")) > 0);
    }
    /* The algorithms must agree whenever all of them ran. */
    assert_true(json_is_boolean(json_object_get(j, "agree")));
    if (all_ok && !json_is_true(json_object_get(j, "agree"))) {
        fail_msg("the algorithms disagree: %s",
                 json_string_value(json_object_get(j, "disagreement")));
    }
    json_decref(j);
    run_free(&r);
    r = RUN(NULL, "--compare", "-f", "svg", "-g", "uniform:3");
    expect_status(&r, 2);
    run_free(&r);

    /* --repeat: that many runs per algorithm, medians inside the spread. */
    r = RUN(NULL, "--compare", "--repeat", "4", "-g", "gaussian:500:2");
    expect_status(&r, 0);
    j = json_out(&r);
    assert_int_equal(jint(j, "repeat"), 4);
    algos = json_object_get(j, "algorithms");
    for (size_t i = 0; i < 3; i++) {
        json_t *a = json_array_get(algos, i);
        if (strcmp(json_string_value(json_object_get(a, "status")), "ok") != 0) continue;
        assert_int_equal(json_array_size(json_object_get(a, "runs_ms")), 4);
        json_t *sp = json_object_get(json_object_get(a, "spread"), "compute_ms");
        double med = json_number_value(json_object_get(sp, "median"));
        assert_true(json_number_value(json_object_get(sp, "min")) <= med);
        assert_true(med <= json_number_value(json_object_get(sp, "max")));
    }
    if (all_ok && !json_is_true(json_object_get(j, "agree"))) {
        fail_msg("the algorithms disagree over repeated runs: %s",
                 json_string_value(json_object_get(j, "disagreement")));
    }
    json_decref(j);
    run_free(&r);
    /* From a JSON file's "repeat" too, and the flag wins over it. */
    put_text("rep.json", "{\"points\": [[0,0],[1,0],[0,1],[1,1]], \"repeat\": 2}");
    r = RUN(NULL, "-c", "@rep.json");
    expect_status(&r, 0);
    j = json_out(&r);
    assert_int_equal(jint(j, "repeat"), 2);
    json_decref(j);
    run_free(&r);
    r = RUN(NULL, "-c", "-r", "3", "@rep.json");
    expect_status(&r, 0);
    j = json_out(&r);
    assert_int_equal(jint(j, "repeat"), 3);
    json_decref(j);
    run_free(&r);
    /* Without --compare the file's repeat is an input error (exit 1). */
    r = RUN(NULL, "@rep.json");
    expect_status(&r, 1);
    assert_non_null(strstr(r.err, "repeat applies only to a comparison"));
    run_free(&r);
    /* repeat x points over 10^7: refused, naming the limit. */
    r = RUN(NULL, "-c", "-r", "50", "-g", "uniform:300000");
    expect_status(&r, 1);
    assert_non_null(strstr(r.err, "at most 10000000, so at most 33 repeats"));
    run_free(&r);
}

static void test_trace_and_counts(void **state) {
    (void)state;
    NEED_CLI();
    run r = RUN(NULL, "--trace", "-a", "flip", "--include", "counts", "-g", "grid:9");
    expect_status(&r, 0);
    json_t *j = json_out(&r);
    json_t *steps = json_object_get(json_object_get(j, "trace"), "steps");
    assert_true(json_array_size(steps) >= 9); /* order, begin, 6 inserts, end */
    assert_string_equal(json_string_value(json_object_get(json_array_get(steps, 0), "kind")),
                        "order");
    assert_string_equal(json_string_value(json_object_get(
                            json_array_get(steps, json_array_size(steps) - 1), "kind")),
                        "end");
    /* a grid: every insertion hits an edge or a cocircular quadruple */
    assert_true(json_integer_value(json_object_get(json_object_get(j, "counts"), "exact")) > 0);
    assert_null(json_object_get(j, "edges")); /* include names the parts */
    json_decref(j);
    run_free(&r);

    r = RUN(NULL, "-g", "grid:16", "--format", "timings", "--include", "counts");
    expect_status(&r, 0);
    j = json_out(&r);
    assert_int_equal(json_integer_value(json_object_get(json_object_get(j, "counts"),
                                                        "site_events")),
                     16);
    json_decref(j);
    run_free(&r);

    r = RUN(NULL, "--trace", "-g", "uniform:2001");
    expect_status(&r, 1);
    assert_non_null(strstr(r.err, "at most 2000 points can be traced, this request has 2001"));
    run_free(&r);
    r = RUN(NULL, "--trace", "--compare", "-g", "uniform:20");
    expect_status(&r, 1);
    assert_non_null(strstr(r.err, "/compare does not trace"));
    run_free(&r);
    r = RUN(NULL, "--trace", "-f", "svg", "-g", "uniform:20");
    expect_status(&r, 1);
    assert_non_null(strstr(r.err, "trace is written in JSON only"));
    run_free(&r);
}

/* The distributions beyond the first six, and the alias: random is
 * pixels, point for point; the skewed sets give agreeing diagrams. */
static void test_generate_distributions(void **state) {
    (void)state;
    NEED_CLI();
    run a = RUN(NULL, "-g", "random:2000:5", "-a", "flip", "--include", "vertices");
    run b = RUN(NULL, "-g", "pixels:2000:5", "-a", "flip", "--include", "vertices");
    expect_status(&a, 0);
    expect_status(&b, 0);
    json_t *ja = json_out(&a), *jb = json_out(&b);
    assert_true(json_array_size(json_object_get(ja, "vertices")) > 1000);
    assert_true(json_equal(json_object_get(ja, "vertices"), json_object_get(jb, "vertices")));
    json_decref(ja);
    json_decref(jb);
    run_free(&a);
    run_free(&b);
    static const char *const gens[] = {"lognormal:3000:2", "outlier:3000:2",
                                       "decades:3000:2", "pixels:3000:2"};
    for (size_t i = 0; i < sizeof gens / sizeof gens[0]; i++) {
        run r = RUN(NULL, "--compare", "-g", gens[i]);
        expect_status(&r, 0);
        json_t *j = json_out(&r);
        assert_int_equal(jint(j, "n_input"), 3000);
        if (!json_is_true(json_object_get(j, "agree"))) {
            fail_msg("%s: the algorithms disagree: %s", gens[i],
                     json_string_value(json_object_get(j, "disagreement")));
        }
        json_decref(j);
        run_free(&r);
    }
}

static void test_input_errors(void **state) {
    (void)state;
    NEED_CLI();
    put_text("bad.csv", "1,2\n3,4\n5;x\n");
    run r = RUN(NULL, "@bad.csv");
    expect_status(&r, 1);
    assert_non_null(strstr(r.err, "bad.csv: line 3: expected two numbers, got \"5;x\""));
    assert_int_equal(r.out_len, 0);
    run_free(&r);

    put_text("bad.json", "{\"points\": [[1,2],[\"a\",3]]}");
    r = RUN(NULL, "@bad.json");
    expect_status(&r, 1);
    assert_non_null(strstr(r.err, "points[1][0] is not a number"));
    assert_non_null(strstr(r.err, "(at /points/1/0)"));
    run_free(&r);

    r = RUN("bad.json", "-");
    expect_status(&r, 1);
    assert_non_null(strstr(r.err, "standard input: points[1][0]"));
    run_free(&r);

    put_text("bad.json", "{\"points\": [[1,2],[3,");
    r = RUN(NULL, "@bad.json");
    expect_status(&r, 1);
    assert_non_null(strstr(r.err, "JSON ends early"));
    run_free(&r);

    put_file("odd.bin", "0123456789abcdefXYZ", 19);
    r = RUN(NULL, "@odd.bin");
    expect_status(&r, 1);
    assert_non_null(strstr(r.err, "binary body is 19 bytes, not a multiple of 16"));
    run_free(&r);

    r = RUN(NULL, "@does-not-exist.csv");
    expect_status(&r, 1);
    assert_non_null(strstr(r.err, "does-not-exist.csv: No such file or directory"));
    run_free(&r);
}

static void test_usage_errors(void **state) {
    (void)state;
    NEED_CLI();
    static const struct {
        const char *args[5];
        const char *words;
    } cases[] = {
        {{"--frobnicate", NULL}, "unknown option --frobnicate"},
        {{"--algorithm", "delaunay", NULL}, "unknown algorithm \"delaunay\""},
        {{"--format", "png", NULL}, "unknown format \"png\""},
        {{"--bounds", "1,2,3", NULL}, "four comma-separated numbers"},
        {{"--include", "faces", NULL}, "unknown part \"faces\""},
        {{"--input", "xml", NULL}, "--input must be json, csv or binary"},
        {{"--generate", "poisson:10", NULL}, "unknown distribution \"poisson\""},
        {{"--generate", "uniform", NULL}, "--generate wants DIST:N[:SEED]"},
        {{"--generate", "uniform:-3", NULL}, "N must be a non-negative integer"},
        {{"--generate", "uniform:3:x", NULL}, "SEED must be a non-negative integer"},
        {{"a.csv", "b.csv", NULL}, "one input at most"},
        {{"-g", "grid:4", "a.csv", NULL}, "exclude each other"},
        {{"--algorithm", NULL}, "needs a value"},
        {{"--compare", "--repeat", "0", NULL}, "repeat 0 is out of range; give an integer from 1 to 50"},
        {{"-c", "-r", "2.5", NULL}, "repeat 2.5 is not an integer"},
        {{"-c", "--repeat", "many", NULL}, "repeat \"many\" is not a number"},
        {{"--repeat", "3", "-g", "grid:4", NULL}, "--repeat applies to --compare only"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *args[6] = {0};
        memcpy(args, cases[i].args, sizeof cases[i].args);
        run r = run_cli(NULL, args);
        if (r.status != 2 || strstr(r.err, cases[i].words) == NULL) {
            fail_msg("%s: status %d, stderr \"%s\"", cases[i].args[0], r.status, r.err);
        }
        assert_non_null(strstr(r.err, "try 'voronoi --help'"));
        run_free(&r);
    }
    run r = RUN(NULL, "--help");
    expect_status(&r, 0);
    static const char *const documented[] = {"--algorithm", "--bounds", "--format",
                                             "--input", "--include", "--generate",
                                             "--compare", "--repeat", "timings", "Exit status",
                                             "uniform", "gaussian", "pixels", "random",
                                             "grid", "circle", "clustered", "lognormal",
                                             "outlier", "decades", "--trace", "counts"};
    for (size_t i = 0; i < sizeof documented / sizeof documented[0]; i++) {
        if (strstr(r.out, documented[i]) == NULL) fail_msg("--help lacks %s", documented[i]);
    }
    run_free(&r);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_csv_file),
        cmocka_unit_test(test_json_file_and_stdin),
        cmocka_unit_test(test_binary_file),
        cmocka_unit_test(test_generate_and_formats),
        cmocka_unit_test(test_generate_distributions),
        cmocka_unit_test(test_compare),
        cmocka_unit_test(test_trace_and_counts),
        cmocka_unit_test(test_trailing_newline),
        cmocka_unit_test(test_input_errors),
        cmocka_unit_test(test_usage_errors),
        cmocka_unit_test(test_make_run),
    };
    return cmocka_run_group_tests_name("cli", tests, setup, teardown);
}
