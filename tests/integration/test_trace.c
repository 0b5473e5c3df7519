/* test_trace.c -- operation counts and traces through a real voronoid.
 *
 * /voronoi with "trace": true (in the body and as ?trace=true) answers the
 * steps of each algorithm, whose running counts end at the counts that
 * include=counts returns, on a small degenerate set (a 5 x 5 grid with a
 * repeated point: cocircular quadruples, collinear rows, a duplicate whose
 * input index must not appear in the steps); the last step of each trace is
 * "end" and every site is taken once. /compare answers counts for every
 * algorithm, timings and binary formats carry them; more points than the
 * trace allows, a trace in another format or on /compare are 422 naming
 * the limit and the count. Responses are saved for the OpenAPI check. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "harness.h"

static it_daemon d;

static int setup(void **state) {
    (void)state;
    return it_group_start(&d, NULL);
}

static int teardown(void **state) {
    (void)state;
    return it_group_stop(&d);
}

static void post(const char *path, const char *body, it_resp *r,
                 const char *save_as) {
    it_req q = {.path = path, .body = body, .len = strlen(body),
                .headers = {"Content-Type: application/json"}};
    it_http(&d, &q, r);
    if (save_as) it_save(save_as, &q, r);
    if (r->curl_rc != 0) fail_msg("curl: %s", r->err);
}

/* A 5 x 5 grid, and input 25 repeating input 7. */
static char *grid_body(const char *extra) {
    static char body[2048];
    size_t k = (size_t)snprintf(body, sizeof body, "{\"points\": [");
    for (int i = 0; i < 25; i++)
        k += (size_t)snprintf(body + k, sizeof body - k, "[%d,%d],", i % 5, i / 5);
    snprintf(body + k, sizeof body - k, "[2,1]]%s}", extra);
    return body;
}

static void test_trace_each_algorithm(void **state) {
    (void)state;
    static const char *const algos[] = {"fortune", "bowyer-watson", "flip"};
    for (int a = 0; a < 3; a++) {
        char extra[128], path[128], save[64];
        snprintf(extra, sizeof extra,
                 ", \"algorithm\": \"%s\", \"trace\": true, \"include\": "
                 "[\"counts\", \"triangles\"]",
                 algos[a]);
        snprintf(save, sizeof save, "voronoi-trace-%s", algos[a]);
        it_resp r;
        post("/voronoi", grid_body(extra), &r, save);
        assert_int_equal(r.status, 200);
        json_t *j = it_json(&r);
        assert_non_null(j);
        json_t *steps = json_object_get(json_object_get(j, "trace"), "steps");
        size_t n = json_array_size(steps);
        assert_true(n >= 25);
        json_t *first = json_array_get(steps, 0), *last = json_array_get(steps, n - 1);
        assert_string_equal(json_string_value(json_object_get(first, "kind")), "order");
        assert_string_equal(json_string_value(json_object_get(last, "kind")), "end");
        /* the order: every distinct site once, as input indices (25 is the
         * duplicate of 7 and never appears) */
        json_t *order = json_object_get(first, "sites");
        assert_int_equal(json_array_size(order), 25);
        int seen[26] = {0};
        for (size_t i = 0; i < 25; i++) {
            json_int_t v = json_integer_value(json_array_get(order, i));
            assert_true(v >= 0 && v < 25);
            seen[v]++;
        }
        for (int i = 0; i < 25; i++) assert_int_equal(seen[i], 1);
        /* running counts end at the answer's counts */
        json_t *running = json_object();
        size_t sites = 0;
        for (size_t i = 0; i < n; i++) {
            json_t *st = json_array_get(steps, i);
            json_object_update(running, json_object_get(st, "counts"));
            const char *kind = json_string_value(json_object_get(st, "kind"));
            sites += !strcmp(kind, "insert") || !strcmp(kind, "site");
        }
        json_t *counts = json_object_get(j, "counts");
        assert_true(json_equal(running, counts));
        json_decref(running);
        if (a == 0) {
            json_t *begin = json_array_get(steps, 1);
            /* the first row: the five sites of y = 0 */
            assert_int_equal(json_array_size(json_object_get(begin, "beach")), 5);
            assert_int_equal(sites + 5, 25);
            assert_int_equal(json_integer_value(json_object_get(counts, "site_events")), 25);
        } else {
            assert_int_equal(sites + 3, 25);
            assert_true(json_integer_value(json_object_get(counts, "exact")) > 0);
        }
        json_decref(j);
        it_free(&r);

        /* the query string asks the same */
        snprintf(path, sizeof path, "/voronoi?trace=true&algorithm=%s&include=counts",
                 algos[a]);
        post(path, grid_body(""), &r, NULL);
        assert_int_equal(r.status, 200);
        j = it_json(&r);
        json_t *steps2 = json_object_get(json_object_get(j, "trace"), "steps");
        assert_int_equal(json_array_size(steps2), n);
        json_decref(j);
        it_free(&r);
    }
}

static void test_counts_everywhere(void **state) {
    (void)state;
    it_resp r;
    post("/compare", grid_body(""), &r, "compare-counts");
    assert_int_equal(r.status, 200);
    json_t *j = it_json(&r);
    json_t *algs = json_object_get(j, "algorithms");
    for (size_t i = 0; i < 3; i++) {
        json_t *c = json_object_get(json_array_get(algs, i), "counts");
        assert_true(json_is_object(c));
        assert_true(json_object_size(c) >= 5);
    }
    json_decref(j);
    it_free(&r);

    post("/voronoi?format=timings&include=counts&algorithm=bowyer-watson",
         grid_body(""), &r, "voronoi-timings-counts");
    assert_int_equal(r.status, 200);
    j = it_json(&r);
    assert_true(json_is_number(json_object_get(j, "compute_ms")));
    json_t *c = json_object_get(j, "counts");
    /* Bowyer-Watson: 2n - 2 more triangles made than removed */
    assert_int_equal(json_integer_value(json_object_get(c, "triangles_created")) -
                         json_integer_value(json_object_get(c, "cavity_triangles")),
                     2 * 25 - 2);
    json_decref(j);
    it_free(&r);

    /* binary: flag 8, n_counts in the header, the counts last */
    post("/voronoi?format=binary", grid_body(""), &r, "voronoi-binary-counts");
    assert_int_equal(r.status, 200);
    assert_true(r.len > 48);
    const unsigned char *b = (const unsigned char *)r.body;
    uint32_t flags = (uint32_t)b[12] | (uint32_t)b[13] << 8;
    uint32_t n_counts = (uint32_t)b[44] | (uint32_t)b[45] << 8;
    assert_true(flags & 8);
    assert_true(n_counts >= 15);
    assert_true(r.len >= 8 * (size_t)n_counts + 56);
    it_free(&r);
}

static void test_trace_refusals(void **state) {
    (void)state;
    it_resp r;
    const char *big = "{\"generate\": {\"n\": 2001, \"seed\": 1}, \"trace\": true}";
    post("/voronoi", big, &r, "voronoi-trace-too-many");
    assert_int_equal(r.status, 422);
    json_t *j = it_json(&r);
    assert_string_equal(json_string_value(json_object_get(j, "pointer")), "/trace");
    const char *detail = json_string_value(json_object_get(j, "detail"));
    assert_non_null(strstr(detail, "2000"));
    assert_non_null(strstr(detail, "2001"));
    json_decref(j);
    it_free(&r);

    post("/voronoi?format=svg", grid_body(", \"trace\": true"), &r, NULL);
    assert_int_equal(r.status, 422);
    it_free(&r);
    post("/compare?trace=true", grid_body(""), &r, "compare-trace");
    assert_int_equal(r.status, 422);
    it_free(&r);
    post("/voronoi?trace=maybe", grid_body(""), &r, NULL);
    assert_int_equal(r.status, 422);
    it_free(&r);
    post("/voronoi", grid_body(", \"trace\": \"yes\""), &r, NULL);
    assert_int_equal(r.status, 422);
    it_free(&r);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_trace_each_algorithm),
        cmocka_unit_test(test_counts_everywhere),
        cmocka_unit_test(test_trace_refusals),
    };
    return cmocka_run_group_tests_name("integration/trace", tests, setup, teardown);
}
