/* test_config.c -- flags and environment into srv_config: defaults,
 * precedence, every accepted form and every refusal (each bad value must
 * name its flag or variable and the value). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "../../server/config.h"

/* A fake environment: NAME=value strings. */
static const char *const *fake_env;
static const char *env_get(const char *name) {
    size_t n = strlen(name);
    for (size_t i = 0; fake_env && fake_env[i]; i++)
        if (strncmp(fake_env[i], name, n) == 0 && fake_env[i][n] == '=')
            return fake_env[i] + n + 1;
    return NULL;
}

static srv_config_result parse(srv_config *c, char *err, size_t size,
                               const char *const *env, ...) {
    char *argv[32] = {"voronoid"};
    int argc = 1;
    va_list ap;
    va_start(ap, env);
    for (const char *a; (a = va_arg(ap, const char *)) != NULL;)
        argv[argc++] = (char *)a;
    va_end(ap);
    fake_env = env;
    return srv_config_parse(argc, argv, env_get, 4, c, err, size);
}

static void test_defaults(void **state) {
    (void)state;
    srv_config c;
    char err[256];
    assert_int_equal(parse(&c, err, sizeof err, NULL, NULL), SRV_CONFIG_OK);
    assert_string_equal(c.bind, "127.0.0.1");
    assert_int_equal(c.port, 8080);
    assert_int_equal(c.workers, 4);
    assert_int_equal(c.http_threads, 4);
    assert_int_equal(c.queue, 64);
    assert_int_equal(c.max_body, 64u << 20);
    assert_int_equal(c.max_points, 1000000);
    assert_true(c.timeout == 60.0);
    assert_true(c.grace == 10.0);
    assert_int_equal(c.connection_timeout, 30);
    assert_int_equal(c.max_connections_per_ip, 128);
    assert_true(c.header_timeout == 10.0);
    assert_int_equal(c.min_upload_rate, 1024);
    assert_true(c.send_timeout == 10.0);
    assert_true(c.drain == 5.0);
    assert_true(c.answer_memory >= (64u << 20) &&
                c.answer_memory <= (1u << 30));
    assert_string_equal(c.web_dir, "");
    assert_string_equal(err, "");
}

/* The default answer budget: a quarter of the machine's memory, between
 * 64 MiB and 1 GiB; 1 GiB when the memory is not known. */
static void test_answer_memory_default(void **state) {
    (void)state;
    const unsigned long long g = 1ull << 30;
    assert_int_equal(srv_config_answer_memory_for(24 * g), 1u << 30);
    assert_int_equal(srv_config_answer_memory_for(4 * g), 1u << 30);
    assert_int_equal(srv_config_answer_memory_for(2 * g), 512u << 20);
    assert_int_equal(srv_config_answer_memory_for(g / 8), 64u << 20);
    assert_int_equal(srv_config_answer_memory_for(0), 1u << 30);
}

static void test_every_flag_both_forms(void **state) {
    (void)state;
    srv_config c;
    char err[256];
    assert_int_equal(
        parse(&c, err, sizeof err, NULL, "--bind", "::1", "--port=0",
              "--workers", "3", "--queue=7", "--max-body", "2M",
              "--max-points=500", "--timeout", "0.25", "--grace=1.5",
              "--http-threads", "2", "--connection-timeout=5",
              "--max-connections", "99", "--web-dir", "/tmp",
              "--max-connections-per-ip=0", "--header-timeout", "2.5",
              "--min-upload-rate=0", "--send-timeout", "3", "--drain=0",
              "--answer-memory", "256M", NULL),
        SRV_CONFIG_OK);
    assert_int_equal(c.max_connections_per_ip, 0);
    assert_true(c.header_timeout == 2.5);
    assert_int_equal(c.min_upload_rate, 0);
    assert_true(c.send_timeout == 3.0);
    assert_true(c.drain == 0.0);
    assert_int_equal(c.answer_memory, 256u << 20);
    assert_string_equal(c.bind, "::1");
    assert_int_equal(c.port, 0);
    assert_int_equal(c.workers, 3);
    assert_int_equal(c.queue, 7);
    assert_int_equal(c.max_body, 2u << 20);
    assert_int_equal(c.max_points, 500);
    assert_true(c.timeout == 0.25);
    assert_true(c.grace == 1.5);
    assert_int_equal(c.http_threads, 2);
    assert_int_equal(c.connection_timeout, 5);
    assert_int_equal(c.max_connections, 99);
    assert_string_equal(c.web_dir, "/tmp");
}

static void test_size_suffixes(void **state) {
    (void)state;
    srv_config c;
    char err[256];
    assert_int_equal(parse(&c, err, sizeof err, NULL, "--max-body=4096", NULL),
                     SRV_CONFIG_OK);
    assert_int_equal(c.max_body, 4096);
    assert_int_equal(parse(&c, err, sizeof err, NULL, "--max-body=8k", NULL),
                     SRV_CONFIG_OK);
    assert_int_equal(c.max_body, 8192);
    assert_int_equal(parse(&c, err, sizeof err, NULL, "--max-body=1G", NULL),
                     SRV_CONFIG_OK);
    assert_int_equal(c.max_body, (size_t)1 << 30);
}

static void test_environment_and_precedence(void **state) {
    (void)state;
    srv_config c;
    char err[256];
    const char *env[] = {"VORONOID_PORT=9000", "VORONOID_WORKERS=2",
                         "VORONOID_TIMEOUT=3", "VORONOID_BIND=0.0.0.0",
                         NULL};
    assert_int_equal(parse(&c, err, sizeof err, env, NULL), SRV_CONFIG_OK);
    assert_int_equal(c.port, 9000);
    assert_int_equal(c.workers, 2);
    assert_true(c.timeout == 3.0);
    assert_string_equal(c.bind, "0.0.0.0");
    /* A flag wins over the environment. */
    assert_int_equal(parse(&c, err, sizeof err, env, "--port", "9001", NULL),
                     SRV_CONFIG_OK);
    assert_int_equal(c.port, 9001);
    assert_int_equal(c.workers, 2);
}

static void test_help(void **state) {
    (void)state;
    srv_config c;
    char err[256];
    assert_int_equal(parse(&c, err, sizeof err, NULL, "--port", "1", "--help",
                           NULL),
                     SRV_CONFIG_HELP);
    assert_int_equal(parse(&c, err, sizeof err, NULL, "-h", NULL),
                     SRV_CONFIG_HELP);
    char text[8192];
    FILE *f = fmemopen(text, sizeof text, "w");
    assert_non_null(f);
    srv_config_usage(f);
    fclose(f);
    /* Every flag and variable is documented. */
    const char *names[] = {"--bind", "--port", "--workers", "--queue",
                           "--max-body", "--max-points", "--timeout",
                           "--grace", "--web-dir", "--http-threads",
                           "--connection-timeout", "--max-connections",
                           "--max-connections-per-ip", "--header-timeout",
                           "--min-upload-rate", "--send-timeout", "--drain",
                           "--answer-memory", "VORONOID_ANSWER_MEMORY",
                           "VORONOID_PORT", "VORONOID_WEB_DIR", NULL};
    for (int i = 0; names[i]; i++) assert_non_null(strstr(text, names[i]));
}

/* One refused input: the message must name what and the value. */
typedef struct bad_case {
    const char *env;  /* NAME=value or NULL */
    const char *a1, *a2;
    const char *must_name, *must_show;
} bad_case;

static void test_every_bad_value(void **state) {
    (void)state;
    static const bad_case cases[] = {
        {NULL, "--port", "abc", "--port", "'abc'"},
        {NULL, "--port", "65536", "--port", "65536"},
        {NULL, "--port", "-1", "--port", "-1"},
        {NULL, "--port", "", "--port", "''"},
        {NULL, "--port", " 80", "--port", "' 80'"},
        {NULL, "--port", "80x", "--port", "80x"},
        {NULL, "--port", "99999999999999999999", "--port", "9999"},
        {NULL, "--workers", "0", "--workers", "'0'"},
        {NULL, "--workers", "257", "--workers", "257"},
        {NULL, "--queue", "0", "--queue", "'0'"},
        {NULL, "--queue", "1e3", "--queue", "1e3"},
        {NULL, "--max-body", "12", "--max-body", "1K to 4G"},
        {NULL, "--max-body", "5G", "--max-body", "5G"},
        {NULL, "--max-body", "1T", "--max-body", "1T"},
        {NULL, "--max-body", "K", "--max-body", "'K'"},
        {NULL, "--max-body", "-4K", "--max-body", "-4K"},
        {NULL, "--max-points", "0", "--max-points", "'0'"},
        {NULL, "--max-points", "2000000000", "--max-points", "2000000000"},
        {NULL, "--timeout", "0", "--timeout", "'0'"},
        {NULL, "--timeout", "nan", "--timeout", "nan"},
        {NULL, "--timeout", "inf", "--timeout", "inf"},
        {NULL, "--timeout", "1s", "--timeout", "1s"},
        {NULL, "--grace", "-1", "--grace", "-1"},
        {NULL, "--grace", "4000", "--grace", "4000"},
        {NULL, "--http-threads", "0", "--http-threads", "'0'"},
        {NULL, "--connection-timeout", "0", "--connection-timeout", "'0'"},
        {NULL, "--max-connections", "0", "--max-connections", "'0'"},
        {NULL, "--max-connections-per-ip", "-1", "--max-connections-per-ip",
         "-1"},
        {NULL, "--max-connections-per-ip", "100001", "--max-connections-per-ip",
         "100001"},
        {NULL, "--header-timeout", "0", "--header-timeout", "'0'"},
        {NULL, "--header-timeout", "0.05", "--header-timeout", "0.05"},
        {NULL, "--min-upload-rate", "fast", "--min-upload-rate", "fast"},
        {NULL, "--min-upload-rate", "2G", "--min-upload-rate", "0 to 1G"},
        {NULL, "--send-timeout", "0.5", "--send-timeout", "0.5"},
        {NULL, "--drain", "-1", "--drain", "-1"},
        {NULL, "--drain", "3601", "--drain", "3601"},
        {NULL, "--answer-memory", "1M", "--answer-memory", "16M to 1024G"},
        {NULL, "--answer-memory", "2048G", "--answer-memory", "2048G"},
        {"VORONOID_ANSWER_MEMORY=half", NULL, NULL, "VORONOID_ANSWER_MEMORY",
         "half"},
        {"VORONOID_DRAIN=soon", NULL, NULL, "VORONOID_DRAIN", "soon"},
        {NULL, "--bind", "localhost", "--bind", "localhost"},
        {NULL, "--bind", "1.2.3.256", "--bind", "1.2.3.256"},
        {NULL, "--web-dir", "/nonexistent/dir", "--web-dir", "/nonexistent"},
        {NULL, "--web-dir", "/etc/passwd", "--web-dir", "/etc/passwd"},
        {NULL, "--frobnicate", "1", "--frobnicate", "--frobnicate"},
        {NULL, "port", "80", "port", "'port'"},
        {NULL, "--", NULL, "'--'", "'--'"},
        {NULL, "--port", NULL, "--port", "missing value"},
        {"VORONOID_PORT=http", NULL, NULL, "VORONOID_PORT", "'http'"},
        {"VORONOID_WORKERS=many", NULL, NULL, "VORONOID_WORKERS", "many"},
        {"VORONOID_MAX_BODY=lots", NULL, NULL, "VORONOID_MAX_BODY", "lots"},
        {"VORONOID_TIMEOUT=", NULL, NULL, "VORONOID_TIMEOUT", "''"},
        {"VORONOID_BIND=::g", NULL, NULL, "VORONOID_BIND", "::g"},
        {"VORONOID_WEB_DIR=/nope", NULL, NULL, "VORONOID_WEB_DIR", "/nope"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const bad_case *b = &cases[i];
        const char *env[] = {b->env, NULL};
        srv_config c;
        char err[256];
        srv_config_result r =
            parse(&c, err, sizeof err, b->env ? env : NULL, b->a1, b->a2, NULL);
        if (r != SRV_CONFIG_ERROR || strstr(err, b->must_name) == NULL ||
            strstr(err, b->must_show) == NULL)
            fail_msg("case %zu (%s %s %s): result %d, message \"%s\"", i,
                     b->env ? b->env : "", b->a1 ? b->a1 : "",
                     b->a2 ? b->a2 : "", (int)r, err);
    }
}

static void test_print(void **state) {
    (void)state;
    srv_config c;
    char err[256], text[2048];
    assert_int_equal(parse(&c, err, sizeof err, NULL, "--port", "1234", NULL),
                     SRV_CONFIG_OK);
    FILE *f = fmemopen(text, sizeof text, "w");
    assert_non_null(f);
    srv_config_print(&c, f);
    fclose(f);
    assert_non_null(strstr(text, "port=1234"));
    assert_non_null(strstr(text, "web-dir=(built in)"));
    assert_non_null(strstr(text, "drain=5s"));
    assert_non_null(strstr(text, "header-timeout=10s"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_answer_memory_default),
        cmocka_unit_test(test_every_flag_both_forms),
        cmocka_unit_test(test_size_suffixes),
        cmocka_unit_test(test_environment_and_precedence),
        cmocka_unit_test(test_help),
        cmocka_unit_test(test_every_bad_value),
        cmocka_unit_test(test_print),
    };
    return cmocka_run_group_tests_name("server/config", tests, NULL, NULL);
}
