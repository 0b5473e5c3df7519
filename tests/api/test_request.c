/* test_request.c -- request options, content negotiation, problems and the
 * output buffer: every accepted value and every refusal, with its status
 * and the words of its detail. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include <jansson.h>

#include "../../api/api.h"

static void test_defaults(void **state) {
    (void)state;
    api_request r;
    api_request_init(&r);
    assert_int_equal(r.algorithm, VOR_FORTUNE);
    assert_int_equal(r.parts, API_PART_DEFAULT);
    assert_int_equal(r.format, API_FMT_JSON);
    assert_int_equal(r.has_bounds, 0);
    assert_null(r.xy);
    api_request_clear(&r);
}

static void test_options_accepted(void **state) {
    (void)state;
    api_request r;
    api_problem p;
    api_request_init(&r);
    assert_int_equal(api_request_option(&r, "algorithm", "flip", &p), API_OK);
    assert_int_equal(r.algorithm, VOR_FLIP);
    assert_int_equal(api_request_option(&r, "algorithm", "bowyer-watson", &p), API_OK);
    assert_int_equal(r.algorithm, VOR_BOWYER_WATSON);
    assert_int_equal(api_request_option(&r, "format", "svg", &p), API_OK);
    assert_int_equal(r.format, API_FMT_SVG);
    assert_int_equal(api_request_option(&r, "format", "timings", &p), API_OK);
    assert_int_equal(r.format, API_FMT_TIMINGS);
    assert_int_equal(api_request_option(&r, "bounds", "-1, -2.5,1e3 ,4", &p), API_OK);
    assert_true(r.has_bounds);
    assert_true(r.bounds[0] == -1 && r.bounds[1] == -2.5 && r.bounds[2] == 1000 &&
                r.bounds[3] == 4);
    assert_int_equal(api_request_option(&r, "include", "sites, triangles", &p), API_OK);
    assert_int_equal(r.parts, API_PART_SITES | API_PART_TRIANGLES);
    assert_true(r.parts_given);
    assert_int_equal(api_request_option(&r, "include", "", &p), API_OK);
    assert_int_equal(r.parts, 0);
    assert_int_equal(api_request_option(&r, "include", "counts,cells", &p), API_OK);
    assert_int_equal(r.parts, API_PART_COUNTS | API_PART_CELLS);
    assert_false(r.trace);
    assert_int_equal(api_request_option(&r, "trace", "true", &p), API_OK);
    assert_true(r.trace);
    assert_int_equal(api_request_option(&r, "trace", "false", &p), API_OK);
    assert_false(r.trace);
    api_request_clear(&r);
}

static void test_options_refused(void **state) {
    (void)state;
    static const struct {
        const char *key, *value;
        api_code code;
        const char *words;
    } cases[] = {
        {"algorithm", "delaunay", API_INVALID,
         "unknown algorithm \"delaunay\"; valid: fortune, bowyer-watson, flip"},
        {"format", "png", API_INVALID, "unknown format \"png\""},
        {"include", "edges,faces", API_INVALID,
         "unknown part \"faces\" in include; valid: vertices, edges, cells, "
         "triangles, sites, clipped, counts"},
        {"trace", "yes", API_INVALID, "trace must be true or false, got \"yes\""},
        {"trace", "", API_INVALID, "trace must be true or false"},
        {"bounds", "0,0,1", API_INVALID, "must be four comma-separated numbers"},
        {"bounds", "0,0,1,1,1", API_INVALID, "must be four comma-separated"},
        {"bounds", "0,0,x,1", API_INVALID, "must be four comma-separated"},
        {"bounds", "0,0,1e999,1", API_INVALID, "\"1e999\" is not a finite number"},
        {"bounds", "0,0,nan,1", API_INVALID, "\"nan\" is not a finite number"},
        {"bounds", "2,0,1,1", API_INVALID, "xmin 2 must be less than xmax 1"},
        {"bounds", "0,1,1,1", API_INVALID, "ymin 1 must be less than ymax 1"},
        {"repeat", "0", API_INVALID,
         "repeat 0 is out of range; give an integer from 1 to 50"},
        {"repeat", "51", API_INVALID, "repeat 51 is out of range"},
        {"repeat", "-1", API_INVALID, "repeat -1 is out of range"},
        {"repeat", "3.5", API_INVALID,
         "repeat 3.5 is not an integer; give an integer from 1 to 50"},
        {"repeat", "three", API_INVALID,
         "repeat \"three\" is not a number; give an integer from 1 to 50"},
        {"repeat", "", API_INVALID, "repeat \"\" is not a number"},
        {"repeat", "5x", API_INVALID, "repeat \"5x\" is not a number"},
        {"repeat", "nan", API_INVALID, "repeat \"nan\" is not a number"},
        {"colour", "red", API_MALFORMED,
         "unknown option \"colour\"; known: algorithm, bounds, format, "
         "include, repeat, trace"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        api_request r;
        api_problem p;
        api_request_init(&r);
        api_code c = api_request_option(&r, cases[i].key, cases[i].value, &p);
        if (c != cases[i].code || p.code != c ||
            strstr(p.detail, cases[i].words) == NULL) {
            fail_msg("%s=%s: code %d, detail \"%s\"", cases[i].key,
                     cases[i].value, (int)c, p.detail);
        }
        assert_int_equal(r.has_bounds, 0);
        assert_int_equal(r.repeat, 0);
        api_request_clear(&r);
    }
}

static void test_repeat_option_and_default(void **state) {
    (void)state;
    api_request r;
    api_problem p;
    api_request_init(&r);
    /* Absent: 5 up to 20,000 sites, 3 up to 200,000, then 1. */
    static const size_t sites[] = {0, 1, 20000, 20001, 200000, 200001, 1000000};
    static const int want[] = {5, 5, 5, 3, 3, 1, 1};
    for (size_t i = 0; i < sizeof sites / sizeof sites[0]; i++) {
        assert_int_equal(api_compare_repeat(&r, sites[i]), want[i]);
    }
    assert_int_equal(api_request_option(&r, "repeat", "1", &p), API_OK);
    assert_int_equal(r.repeat, 1);
    assert_int_equal(api_request_option(&r, "repeat", "50", &p), API_OK);
    assert_int_equal(r.repeat, 50);
    assert_int_equal(api_request_option(&r, "repeat", "1e1", &p), API_OK);
    assert_int_equal(r.repeat, 10);
    /* Given, it wins over the default at any size. */
    assert_int_equal(api_compare_repeat(&r, 5), 10);
    assert_int_equal(api_compare_repeat(&r, 900000), 10);
    /* A refused value leaves the last good one. */
    assert_int_equal(api_request_option(&r, "repeat", "51", &p), API_INVALID);
    assert_int_equal(r.repeat, 10);
    api_request_clear(&r);
}

static void test_content_types(void **state) {
    (void)state;
    static const struct {
        const char *ct;
        api_input in;
    } ok[] = {
        {NULL, API_IN_AUTO},
        {"", API_IN_AUTO},
        {"application/x-www-form-urlencoded", API_IN_AUTO},
        {"application/json", API_IN_JSON},
        {"Application/JSON; charset=utf-8", API_IN_JSON},
        {"text/json", API_IN_JSON},
        {"application/vnd.points+json", API_IN_JSON},
        {"text/csv", API_IN_TEXT},
        {" text/plain ;charset=us-ascii", API_IN_PLAIN},
        {"text/plain;charset=UTF-8", API_IN_PLAIN},
        {"TEXT/PLAIN", API_IN_PLAIN},
        {"text/tab-separated-values", API_IN_TEXT},
        {"application/octet-stream", API_IN_BINARY},
    };
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        api_input in = (api_input)-1;
        api_problem p;
        if (api_input_from_content_type(ok[i].ct, &in, &p) != API_OK ||
            in != ok[i].in) {
            fail_msg("Content-Type \"%s\" gave %d", ok[i].ct ? ok[i].ct : "(null)",
                     (int)in);
        }
    }
    api_input in;
    api_problem p;
    assert_int_equal(api_input_from_content_type("image/png", &in, &p),
                     API_MEDIA_TYPE);
    assert_int_equal(api_code_http(p.code), 415);
    assert_non_null(strstr(p.detail, "unsupported Content-Type \"image/png\""));
    assert_int_equal(api_input_from_content_type("multipart/form-data; boundary=x",
                                                 &in, &p),
                     API_MEDIA_TYPE);
}

static void test_accept(void **state) {
    (void)state;
    static const struct {
        const char *accept;
        api_format start, want;
    } ok[] = {
        {NULL, API_FMT_SVG, API_FMT_SVG},
        {"", API_FMT_SVG, API_FMT_SVG},
        {"*/*", API_FMT_GEOJSON, API_FMT_GEOJSON},
        {"application/json", API_FMT_SVG, API_FMT_JSON},
        {"application/geo+json", API_FMT_JSON, API_FMT_GEOJSON},
        {"image/svg+xml", API_FMT_JSON, API_FMT_SVG},
        {"image/*", API_FMT_JSON, API_FMT_SVG},
        {"application/octet-stream", API_FMT_JSON, API_FMT_BINARY},
        {"text/html, image/svg+xml;q=0.5, application/geo+json;q=0.9",
         API_FMT_JSON, API_FMT_GEOJSON},
        {"application/json;q=0, image/svg+xml;q=0.1", API_FMT_JSON, API_FMT_SVG},
        {"text/html,application/xhtml+xml,*/*;q=0.8", API_FMT_JSON, API_FMT_JSON},
    };
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        api_request r;
        api_problem p;
        api_request_init(&r);
        r.format = ok[i].start;
        if (api_format_from_accept(&r, ok[i].accept, &p) != API_OK ||
            r.format != ok[i].want) {
            fail_msg("Accept \"%s\" gave format %d", ok[i].accept, (int)r.format);
        }
    }
    api_request r;
    api_problem p;
    api_request_init(&r);
    assert_int_equal(api_format_from_accept(&r, "text/html", &p), API_NOT_ACCEPTABLE);
    assert_int_equal(api_code_http(p.code), 406);
    assert_non_null(strstr(p.detail, "\"text/html\""));
    assert_int_equal(api_format_from_accept(&r, "application/json;q=0", &p),
                     API_NOT_ACCEPTABLE);
    assert_string_equal(api_format_mime(API_FMT_GEOJSON), "application/geo+json");
    assert_string_equal(api_format_mime(API_FMT_SVG), "image/svg+xml");
    assert_string_equal(api_format_mime(API_FMT_BINARY), "application/octet-stream");
    assert_string_equal(api_format_mime(API_FMT_JSON), "application/json");
}

static void test_problem_json(void **state) {
    (void)state;
    api_problem p;
    memset(&p, 0, sizeof p);
    api_problem_set(&p, API_INVALID, "points[%d][%d] is not a number: \"%s\"", 17,
                    1, "a\"b\\c\n\x01");
    strcpy(p.pointer, "/points/17/1");
    p.line = 0;
    api_buf b;
    api_buf_init(&b);
    api_write_problem(&p, "/voronoi", &b);
    assert_false(b.oom);
    assert_true(b.len > 2 && memcmp(b.data + b.len - 2, "}\n", 2) == 0);
    json_error_t err;
    json_t *j = json_loadb(b.data, b.len, 0, &err);
    if (j == NULL) fail_msg("problem is not JSON: %s: %s", err.text, b.data);
    assert_string_equal(json_string_value(json_object_get(j, "type")),
                        "/problems/invalid");
    assert_string_equal(json_string_value(json_object_get(j, "title")),
                        "Invalid request");
    assert_int_equal(json_integer_value(json_object_get(j, "status")), 422);
    assert_string_equal(json_string_value(json_object_get(j, "detail")),
                        "points[17][1] is not a number: \"a\"b\\c\n\x01\"");
    assert_string_equal(json_string_value(json_object_get(j, "instance")), "/voronoi");
    assert_string_equal(json_string_value(json_object_get(j, "pointer")),
                        "/points/17/1");
    assert_null(json_object_get(j, "line"));
    json_decref(j);
    api_buf_clear(&b);

    api_problem_set(&p, API_MALFORMED, "line 12: bad");
    assert_string_equal(p.pointer, "");
    p.line = 12;
    api_write_problem(&p, NULL, &b);
    j = json_loadb(b.data, b.len, 0, &err);
    assert_non_null(j);
    assert_int_equal(json_integer_value(json_object_get(j, "line")), 12);
    assert_int_equal(json_integer_value(json_object_get(j, "status")), 400);
    assert_null(json_object_get(j, "instance"));
    assert_null(json_object_get(j, "pointer"));
    json_decref(j);
    api_buf_clear(&b);
}

static void test_problem_table(void **state) {
    (void)state;
    assert_int_equal(api_code_http(API_TOO_LARGE), 413);
    assert_string_equal(api_code_slug(API_MEDIA_TYPE), "unsupported-media-type");
    assert_int_equal(api_code_http(API_NOT_IMPLEMENTED), 501);
    assert_int_equal(api_code_http((api_code)999), 500);
    api_problem p;
    assert_int_equal(api_problem_from_status(&p, VOR_OK), API_OK);
    assert_int_equal(api_problem_from_status(&p, VOR_ENOMEM), API_UNAVAILABLE);
    assert_int_equal(api_problem_from_status(&p, VOR_EUNAVAILABLE),
                     API_NOT_IMPLEMENTED);
    assert_string_equal(p.detail, "algorithm not available");
    assert_int_equal(api_problem_from_status(&p, VOR_ETOOMANY), API_TOO_LARGE);
    assert_int_equal(api_problem_from_status(&p, VOR_EBOUNDS), API_INVALID);
}

static void test_buf(void **state) {
    (void)state;
    api_buf b;
    api_buf_init(&b);
    assert_int_equal(api_buf_append(&b, "abc", 3), 0);
    for (int i = 0; i < 1000; i++) {
        assert_int_equal(api_buf_printf(&b, "%d,", i), 0);
    }
    assert_int_equal(api_buf_printf(&b, "%0600d", 7), 0);
    assert_int_equal(b.len, strlen(b.data));
    assert_memory_equal(b.data, "abc0,1,2,", 9);
    size_t len;
    char *d = api_buf_take(&b, &len);
    assert_null(b.data);
    assert_int_equal(b.len, 0);
    assert_true(len > 3000 && d[len - 1] == '7');
    free(d);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_options_accepted),
        cmocka_unit_test(test_options_refused),
        cmocka_unit_test(test_repeat_option_and_default),
        cmocka_unit_test(test_content_types),
        cmocka_unit_test(test_accept),
        cmocka_unit_test(test_problem_json),
        cmocka_unit_test(test_problem_table),
        cmocka_unit_test(test_buf),
    };
    return cmocka_run_group_tests_name("api/request", tests, NULL, NULL);
}
