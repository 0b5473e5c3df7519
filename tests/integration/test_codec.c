/* test_codec.c -- what the codec promises, seen through a real voronoid:
 * /compare's repeated runs (their count from the body, the query or the
 * default, medians inside their spread, agreement, the bounds on repeat
 * and its errors); a JSON body sent as text/plain, as a browser's fetch()
 * of a string does; format=timings labelled with the algorithm and the
 * sizes; every text answer ending with a newline; the 413 that any path
 * and method answers to a Content-Length over --max-body, as the contract
 * says.
 *
 * Timings are checked for their structure and their relations (a median
 * lies between the minimum and the maximum, and equals the median of the
 * runs listed), never for their size. Responses are saved for the OpenAPI
 * check. */
#include <math.h>
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

/* POSTs body with the Content-Type ctype (NULL: libcurl's default). */
static void post(const char *path, const char *ctype, const char *body,
                 it_resp *r, const char *save_as) {
    it_req q = {.path = path, .body = body, .len = strlen(body)};
    char h[128];
    if (ctype) {
        snprintf(h, sizeof h, "Content-Type: %s", ctype);
        q.headers[0] = h;
    }
    it_http(&d, &q, r);
    if (save_as) it_save(save_as, &q, r);
    if (r->curl_rc != 0) fail_msg("curl: %s", r->err);
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Checks one entry of algorithms[] of a /compare answer made with k runs:
 * runs_ms has k values; spread.compute_ms has min <= median <= max, min
 * and max are those of runs_ms and the median is theirs too (as written,
 * rounded to the microsecond, so within a microsecond for an even k), the
 * same value as timings.compute_ms; clip_ms only with bounds. */
static void check_algorithm_runs(json_t *a, int k, int with_bounds) {
    const char *name = json_string_value(json_object_get(a, "algorithm"));
    assert_string_equal(json_string_value(json_object_get(a, "status")), "ok");
    json_t *runs = json_object_get(a, "runs_ms");
    if (json_array_size(runs) != (size_t)k)
        fail_msg("%s: %zu runs, expected %d", name, json_array_size(runs), k);
    double v[64];
    for (int i = 0; i < k; i++) {
        json_t *x = json_array_get(runs, (size_t)i);
        assert_true(json_is_number(x));
        v[i] = json_number_value(x);
        assert_true(v[i] >= 0);
    }
    qsort(v, (size_t)k, sizeof v[0], cmp_double);
    json_t *spread = json_object_get(a, "spread");
    json_t *c = json_object_get(spread, "compute_ms");
    double med = json_number_value(json_object_get(c, "median"));
    double lo = json_number_value(json_object_get(c, "min"));
    double hi = json_number_value(json_object_get(c, "max"));
    if (!(lo <= med && med <= hi))
        fail_msg("%s: median %g outside [%g, %g]", name, med, lo, hi);
    assert_true(lo == v[0]);
    assert_true(hi == v[k - 1]);
    double want = k % 2 ? v[k / 2] : (v[k / 2 - 1] + v[k / 2]) / 2;
    if (fabs(med - want) > 0.0015)
        fail_msg("%s: median %g, runs give %g", name, med, want);
    json_t *t = json_object_get(a, "timings");
    assert_true(json_number_value(json_object_get(t, "compute_ms")) == med);
    json_t *total = json_object_get(spread, "total_ms");
    assert_non_null(total);
    assert_true(json_number_value(json_object_get(total, "min")) <=
                json_number_value(json_object_get(total, "max")));
    assert_int_equal(json_object_get(spread, "clip_ms") != NULL, with_bounds);
}

static void test_compare_repeat(void **state) {
    (void)state;
    static const struct {
        const char *path, *body, *save;
        int k, n, bounds;
    } cases[] = {
        /* Given in the body, in the query (which wins), and absent (the
         * default: 5 runs up to 20,000 sites, 3 above). */
        {"/compare", "{\"generate\": {\"distribution\": \"gaussian\", \"n\": "
                     "3000, \"seed\": 4}, \"repeat\": 7}",
         "compare-repeat-body", 7, 3000, 0},
        {"/compare?repeat=4", "{\"generate\": {\"n\": 500}, \"repeat\": 9}",
         "compare-repeat-query", 4, 500, 0},
        {"/compare?bounds=0,0,1,1", "{\"generate\": {\"n\": 1000, \"seed\": 2}}",
         "compare-repeat-default", 5, 1000, 1},
        {"/compare", "{\"generate\": {\"distribution\": \"grid\", \"n\": 20001}}",
         NULL, 3, 20001, 0},
        /* A tiny request, answered on the connection's thread. */
        {"/compare?repeat=2", "[[0,0],[1,0],[0,1]]", NULL, 2, 3, 0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        it_resp r;
        post(cases[i].path, "application/json", cases[i].body, &r, cases[i].save);
        if (r.status != 200) fail_msg("%s: %ld %s", cases[i].path, r.status, r.body);
        json_t *j = it_json(&r);
        assert_non_null(j);
        assert_int_equal(json_integer_value(json_object_get(j, "repeat")), cases[i].k);
        assert_int_equal(json_integer_value(json_object_get(j, "n_input")), cases[i].n);
        if (!json_is_true(json_object_get(j, "agree")))
            fail_msg("%s: %s", cases[i].body,
                     json_string_value(json_object_get(j, "disagreement")));
        json_t *algs = json_object_get(j, "algorithms");
        assert_int_equal(json_array_size(algs), 3);
        for (size_t a = 0; a < 3; a++)
            check_algorithm_runs(json_array_get(algs, a), cases[i].k, cases[i].bounds);
        json_decref(j);
        it_free(&r);
    }
}

static void test_compare_repeat_refused(void **state) {
    (void)state;
    static const struct {
        const char *path, *body, *save, *pointer, *words;
    } cases[] = {
        {"/compare?repeat=0", "[[0,0]]", "err-422-compare-repeat-range", NULL,
         "repeat 0 is out of range; give an integer from 1 to 50"},
        {"/compare?repeat=51", "[[0,0]]", NULL, NULL, "repeat 51 is out of range"},
        {"/compare?repeat=2.5", "[[0,0]]", NULL, NULL, "repeat 2.5 is not an integer"},
        {"/compare?repeat=x", "[[0,0]]", NULL, NULL, "repeat \"x\" is not a number"},
        {"/compare", "{\"points\": [[0,0]], \"repeat\": 2.5}", NULL, "/repeat",
         "repeat 2.5 is not an integer; give an integer from 1 to 50"},
        {"/compare", "{\"points\": [[0,0]], \"repeat\": \"3\"}", NULL, "/repeat",
         "got a string"},
        {"/compare", "{\"generate\": {\"n\": 300000}, \"repeat\": 40}",
         "err-422-compare-repeat-work", NULL,
         "repeat 40 with 300000 points: repeat times points must be at most "
         "10000000, so at most 33 repeats here"},
        {"/voronoi?repeat=3", "[[0,0]]", "err-422-voronoi-repeat", NULL,
         "repeat applies only to a comparison of the algorithms"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        it_resp r;
        post(cases[i].path, "application/json", cases[i].body, &r, cases[i].save);
        if (r.status != 422) fail_msg("%s %s: %ld %s", cases[i].path, cases[i].body,
                                      r.status, r.body);
        char h[128];
        assert_string_equal(it_header(&r, "Content-Type", h, sizeof h),
                            "application/problem+json");
        json_t *j = it_json(&r);
        const char *detail = json_string_value(json_object_get(j, "detail"));
        if (detail == NULL || strstr(detail, cases[i].words) == NULL)
            fail_msg("%s: detail \"%s\"", cases[i].path, detail ? detail : "(none)");
        json_t *ptr = json_object_get(j, "pointer");
        if (cases[i].pointer)
            assert_string_equal(json_string_value(ptr), cases[i].pointer);
        else
            assert_null(ptr);
        json_decref(j);
        it_free(&r);
    }
}

/* fetch(url, {method: "POST", body: JSON.stringify(...)}) sends
 * text/plain;charset=UTF-8: a body that starts like JSON is JSON. */
static void test_plain_json(void **state) {
    (void)state;
    it_resp r;
    post("/voronoi?format=timings", "text/plain;charset=UTF-8",
         " {\"points\": [[0,0],[1,0],[0,1],[1,1]], \"algorithm\": \"flip\"}",
         &r, "voronoi-plain-json");
    if (r.status != 200) fail_msg("%ld %s", r.status, r.body);
    json_t *j = it_json(&r);
    assert_non_null(json_object_get(j, "compute_ms"));
    json_decref(j);
    it_free(&r);
    post("/compare?repeat=1", "text/plain;charset=UTF-8", "[[0,0],[2,0],[0,2]]",
         &r, NULL);
    assert_int_equal(r.status, 200);
    j = it_json(&r);
    assert_int_equal(json_integer_value(json_object_get(j, "n_input")), 3);
    json_decref(j);
    it_free(&r);
    /* Its errors are JSON's, with a pointer. */
    post("/voronoi", "text/plain", "{\"points\": [[0,0],[1]]}", &r, NULL);
    assert_int_equal(r.status, 422);
    j = it_json(&r);
    assert_string_equal(json_string_value(json_object_get(j, "pointer")), "/points/1");
    json_decref(j);
    it_free(&r);
    /* Text is still text. */
    post("/voronoi", "text/plain", "0 0\n1 0\n0 1\n", &r, NULL);
    assert_int_equal(r.status, 200);
    it_free(&r);
}

static void test_timings_labelled(void **state) {
    (void)state;
    it_resp r;
    post("/voronoi?format=timings&algorithm=bowyer-watson", "application/json",
         "[[0,0],[1,0],[0,1],[0,0],[1,1]]", &r, "voronoi-timings-labelled");
    assert_int_equal(r.status, 200);
    json_t *j = it_json(&r);
    assert_string_equal(json_string_value(json_object_get(j, "algorithm")),
                        "bowyer-watson");
    assert_int_equal(json_integer_value(json_object_get(j, "n_input")), 5);
    assert_int_equal(json_integer_value(json_object_get(j, "n_sites")), 4);
    static const char *const phases[] = {"queue_ms", "parse_ms", "prepare_ms",
                                         "compute_ms", "clip_ms", "serialize_ms",
                                         "total_ms"};
    for (int k = 0; k < 7; k++) assert_true(json_is_number(json_object_get(j, phases[k])));
    assert_int_equal(json_object_size(j), 10);
    json_decref(j);
    it_free(&r);
}

/* Every answer body but binary ends with exactly one newline: diagrams in
 * every text format, timings, comparisons, problems of every origin
 * (codec, routing, limits), health and readiness. */
static void test_trailing_newline(void **state) {
    (void)state;
    static const struct {
        const char *method, *path, *ctype, *body, *accept;
        long status;
    } cases[] = {
        {"POST", "/voronoi", "application/json", "[[0,0],[1,0],[0,1]]", NULL, 200},
        {"POST", "/voronoi?format=geojson", NULL, "[[0,0],[1,0],[0,1]]", NULL, 200},
        {"POST", "/voronoi?format=svg", NULL, "[[0,0],[1,0],[0,1]]", NULL, 200},
        {"POST", "/voronoi?format=timings", NULL, "[[0,0],[1,0],[0,1]]", NULL, 200},
        {"POST", "/compare", NULL, "[[0,0],[1,0],[0,1]]", NULL, 200},
        {"POST", "/voronoi", "application/json", "[[0,0],[1,\"y\"]]", NULL, 422},
        {"POST", "/voronoi", "text/plain", "0 0\n1 x\n", NULL, 400},
        {"POST", "/voronoi", "image/png", "x", NULL, 415},
        {"POST", "/voronoi", NULL, "[[0,0]]", "text/html", 406},
        {"GET", "/nowhere", NULL, NULL, NULL, 404},
        {"DELETE", "/voronoi", NULL, NULL, NULL, 405},
        {"GET", "/healthz", NULL, NULL, NULL, 200},
        {"GET", "/readyz", NULL, NULL, NULL, 200},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        it_req q = {.method = cases[i].method, .path = cases[i].path,
                    .body = cases[i].body,
                    .len = cases[i].body ? strlen(cases[i].body) : 0};
        char ct[96], ac[96];
        int h = 0;
        if (cases[i].ctype) {
            snprintf(ct, sizeof ct, "Content-Type: %s", cases[i].ctype);
            q.headers[h++] = ct;
        }
        if (cases[i].accept) {
            snprintf(ac, sizeof ac, "Accept: %s", cases[i].accept);
            q.headers[h++] = ac;
        }
        it_resp r;
        it_http(&d, &q, &r);
        if (r.curl_rc != 0) fail_msg("curl: %s", r.err);
        if (r.status != cases[i].status)
            fail_msg("%s %s: %ld, expected %ld", cases[i].method, cases[i].path,
                     r.status, cases[i].status);
        if (r.len < 2 || r.body[r.len - 1] != '\n' || r.body[r.len - 2] == '\n')
            fail_msg("%s %s (%ld): the body does not end with one newline: %.80s",
                     cases[i].method, cases[i].path, r.status, r.body);
        it_free(&r);
    }
    /* Binary ends with its float64 timings. */
    it_req q = {.path = "/voronoi?format=binary", .body = "[[0,0],[1,0],[0,1]]",
                .len = 19};
    it_resp r;
    it_http(&d, &q, &r);
    assert_int_equal(r.status, 200);
    assert_int_equal(r.len % 8, 0);
    it_free(&r);
}

static void test_announced_too_large_anywhere(void **state) {
    (void)state;
    static const struct {
        const char *method, *path, *save;
    } cases[] = {
        {"GET", "/healthz", "err-413-healthz-length"},
        {"GET", "/metrics", "err-413-metrics-length"},
        {"GET", "/", "err-413-page-length"},
        {"OPTIONS", "/compare", "err-413-preflight-length"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        it_req q = {.method = cases[i].method, .path = cases[i].path,
                    .headers = {"Content-Length: 99999999999"}};
        it_resp r;
        it_http(&d, &q, &r);
        it_save(cases[i].save, &q, &r);
        if (r.status != 413) fail_msg("%s %s: %ld", cases[i].method, cases[i].path, r.status);
        json_t *j = it_json(&r);
        assert_string_equal(json_string_value(json_object_get(j, "type")),
                            "/problems/too-large");
        assert_non_null(strstr(json_string_value(json_object_get(j, "detail")),
                               "99999999999 bytes"));
        json_decref(j);
        it_free(&r);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_compare_repeat),
        cmocka_unit_test(test_compare_repeat_refused),
        cmocka_unit_test(test_plain_json),
        cmocka_unit_test(test_timings_labelled),
        cmocka_unit_test(test_trailing_newline),
        cmocka_unit_test(test_announced_too_large_anywhere),
    };
    return cmocka_run_group_tests_name("integration/codec", tests, setup, teardown);
}
