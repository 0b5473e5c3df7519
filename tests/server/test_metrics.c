/* test_metrics.c -- the Prometheus text: counters by route and status,
 * cumulative histogram buckets, per-algorithm sums, gauges; and a parse of
 * the whole exposition checking every sample line's syntax and that every
 * metric has HELP and TYPE. Counts are checked against what was recorded
 * (also from several threads at once). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../server/metrics.h"

/* The value of the sample line that starts with `series ` (exact). */
static double sample(const char *text, const char *series) {
    size_t n = strlen(series);
    const char *p = text;
    while ((p = strstr(p, series)) != NULL) {
        if ((p == text || p[-1] == '\n') && p[n] == ' ')
            return strtod(p + n + 1, NULL);
        p += n;
    }
    fail_msg("no sample %s", series);
    return -1;
}

static char *render(srv_metrics *m, const srv_gauges *g) {
    api_buf b;
    api_buf_init(&b);
    srv_metrics_render(m, g, &b);
    assert_false(b.oom);
    size_t len;
    return api_buf_take(&b, &len);
}

static void test_counts_and_histogram(void **state) {
    (void)state;
    srv_metrics *m = srv_metrics_new();
    assert_non_null(m);
    srv_metrics_request(m, SRV_ROUTE_VORONOI, 200, 0.0004);
    srv_metrics_request(m, SRV_ROUTE_VORONOI, 200, 0.003);
    srv_metrics_request(m, SRV_ROUTE_VORONOI, 422, 0.2);
    srv_metrics_request(m, SRV_ROUTE_VORONOI, 200, 100.0); /* past 60 s */
    srv_metrics_request(m, SRV_ROUTE_OTHER, 404, 0.0001);
    srv_metrics_request(m, SRV_ROUTE_HEALTHZ, 42, 0.0001); /* odd status */
    srv_metrics_aborted(m, SRV_ROUTE_COMPARE);
    srv_metrics_compute(m, VOR_FLIP, 1000, 0.5);
    srv_metrics_compute(m, VOR_FLIP, 24, 0.25);
    srv_metrics_stopped(m);
    srv_metrics_stopped(m);
    srv_gauges g = {3, 64, 2, 2, 5, 1, 7000, 1 << 30, 9000, 4, 12, 6, 5, 3};
    char *t = render(m, &g);

    assert_true(sample(t, "voronoid_answer_memory_bytes") == 7000);
    assert_true(sample(t, "voronoid_answer_memory_capacity_bytes") ==
                1073741824.0);
    assert_true(sample(t, "voronoid_answer_memory_peak_bytes") == 9000);
    assert_true(sample(t, "voronoid_answer_memory_refused_total") == 4);
    assert_true(sample(t, "voronoid_connections") == 12);
    assert_true(sample(t, "voronoid_connections_closed_total{reason="
                          "\"header-timeout\"}") == 6);
    assert_true(sample(t, "voronoid_connections_closed_total{reason="
                          "\"upload-rate\"}") == 3);
    assert_true(sample(t, "voronoid_requests_total{route=\"/voronoi\","
                          "status=\"200\"}") == 3);
    assert_true(sample(t, "voronoid_requests_total{route=\"/voronoi\","
                          "status=\"422\"}") == 1);
    assert_true(sample(t, "voronoid_requests_total{route=\"other\","
                          "status=\"404\"}") == 1);
    assert_true(sample(t, "voronoid_requests_total{route=\"/healthz\","
                          "status=\"599\"}") == 1);
    assert_null(strstr(t, "status=\"500\"")); /* only what happened */
    assert_true(sample(t, "voronoid_requests_aborted_total{route="
                          "\"/compare\"}") == 1);
    /* Cumulative buckets: 0.0004 <= 0.0005; 0.003 <= 0.005; 0.2 <= 0.25;
     * 100 only in +Inf. */
    const char *h = "voronoid_request_duration_seconds_bucket{route="
                    "\"/voronoi\",le=";
    char s[160];
    snprintf(s, sizeof s, "%s\"0.0005\"}", h);
    assert_true(sample(t, s) == 1);
    snprintf(s, sizeof s, "%s\"0.0025\"}", h);
    assert_true(sample(t, s) == 1);
    snprintf(s, sizeof s, "%s\"0.005\"}", h);
    assert_true(sample(t, s) == 2);
    snprintf(s, sizeof s, "%s\"0.25\"}", h);
    assert_true(sample(t, s) == 3);
    snprintf(s, sizeof s, "%s\"60\"}", h);
    assert_true(sample(t, s) == 3);
    snprintf(s, sizeof s, "%s\"+Inf\"}", h);
    assert_true(sample(t, s) == 4);
    assert_true(sample(t, "voronoid_request_duration_seconds_count{route="
                          "\"/voronoi\"}") == 4);
    double sum = sample(t, "voronoid_request_duration_seconds_sum{route="
                           "\"/voronoi\"}");
    assert_true(sum > 100.2033 && sum < 100.2035);
    assert_true(sample(t, "voronoid_points_total{algorithm=\"flip\"}") ==
                1024);
    assert_true(sample(t, "voronoid_points_total{algorithm=\"fortune\"}") ==
                0);
    assert_true(sample(t, "voronoid_computations_total{algorithm=\"flip\"}") ==
                2);
    assert_true(sample(t, "voronoid_compute_seconds_total{algorithm=\"flip\"}")
                == 0.75);
    assert_true(sample(t, "voronoid_computations_stopped_total") == 2);
    assert_true(sample(t, "voronoid_queue_depth") == 3);
    assert_true(sample(t, "voronoid_queue_capacity") == 64);
    assert_true(sample(t, "voronoid_workers_busy") == 2);
    assert_true(sample(t, "voronoid_in_flight") == 5);
    assert_true(sample(t, "voronoid_ready") == 1);
    free(t);
    srv_metrics_free(m);
    srv_metrics_free(NULL);
}

/* Every line is a comment (# HELP name text / # TYPE name type) or a
 * sample `name{labels} value` whose metric family was declared. */
static void test_exposition_syntax(void **state) {
    (void)state;
    srv_metrics *m = srv_metrics_new();
    srv_metrics_request(m, SRV_ROUTE_PAGE, 304, 0.001);
    srv_gauges g = {0, 1, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0};
    char *t = render(m, &g);
    char declared[64][80];
    int n_declared = 0, helps = 0;
    for (char *line = strtok(t, "\n"); line; line = strtok(NULL, "\n")) {
        char name[80], kind[32];
        if (strncmp(line, "# HELP ", 7) == 0) {
            helps++;
            continue;
        }
        if (sscanf(line, "# TYPE %79s %31s", name, kind) == 2) {
            assert_true(strcmp(kind, "counter") == 0 ||
                        strcmp(kind, "gauge") == 0 ||
                        strcmp(kind, "histogram") == 0);
            assert_true(n_declared < 64);
            strcpy(declared[n_declared++], name);
            continue;
        }
        assert_true(line[0] != '#');
        size_t k = strspn(line, "abcdefghijklmnopqrstuvwxyz_");
        assert_true(k > 0);
        memcpy(name, line, k);
        name[k] = '\0';
        int found = 0;
        for (int i = 0; i < n_declared; i++) {
            size_t dl = strlen(declared[i]);
            if (strncmp(name, declared[i], dl) == 0 &&
                (name[dl] == '\0' || strcmp(name + dl, "_bucket") == 0 ||
                 strcmp(name + dl, "_sum") == 0 ||
                 strcmp(name + dl, "_count") == 0))
                found = 1;
        }
        if (!found) fail_msg("undeclared sample: %s", line);
        const char *rest = line + k;
        if (*rest == '{') {
            /* name="value" pairs; values may hold any character but an
             * unescaped quote. */
            rest++;
            while (*rest != '}') {
                size_t lk = strspn(rest, "abcdefghijklmnopqrstuvwxyz_");
                if (lk == 0 || rest[lk] != '=' || rest[lk + 1] != '"')
                    fail_msg("bad label in: %s", line);
                rest += lk + 2;
                while (*rest && *rest != '"') rest += *rest == '\\' ? 2 : 1;
                if (*rest != '"') fail_msg("unterminated label: %s", line);
                rest++;
                if (*rest == ',') rest++;
            }
            rest++;
        }
        if (*rest != ' ') fail_msg("bad sample line: %s", line);
        char *end;
        strtod(rest + 1, &end);
        assert_true(end != rest + 1 && *end == '\0');
    }
    assert_int_equal(helps, n_declared);
    free(t);
    srv_metrics_free(m);
}

static void *hammer(void *arg) {
    srv_metrics *m = arg;
    for (int i = 0; i < 10000; i++) {
        srv_metrics_request(m, SRV_ROUTE_COMPARE, 200, 0.001);
        srv_metrics_compute(m, VOR_FORTUNE, 1, 0.0);
    }
    return NULL;
}

static void test_threads(void **state) {
    (void)state;
    srv_metrics *m = srv_metrics_new();
    pthread_t th[4];
    for (int i = 0; i < 4; i++) pthread_create(&th[i], NULL, hammer, m);
    for (int i = 0; i < 4; i++) pthread_join(th[i], NULL);
    srv_gauges g = {0, 1, 0, 1, 0, 1, 0, 1, 0, 0, 0, 0, 0, 0};
    char *t = render(m, &g);
    assert_true(sample(t, "voronoid_requests_total{route=\"/compare\","
                          "status=\"200\"}") == 40000);
    assert_true(sample(t, "voronoid_points_total{algorithm=\"fortune\"}") ==
                40000);
    free(t);
    srv_metrics_free(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_counts_and_histogram),
        cmocka_unit_test(test_exposition_syntax),
        cmocka_unit_test(test_threads),
    };
    return cmocka_run_group_tests_name("server/metrics", tests, NULL, NULL);
}
