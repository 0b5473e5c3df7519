/* test_parse.c -- request bodies: JSON, text and binary.
 *
 * Every refusal is checked for its status, its JSON pointer or line and the
 * words of its detail; accepted bodies are checked value by value against
 * an independent reading (strtod, or the doubles that were encoded). A
 * random round trip prints its seed. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../api/api.h"

typedef struct outcome {
    api_code code;
    api_problem p;
    api_request r;
} outcome;

static api_code parse_kind(outcome *o, api_input kind, const char *body,
                           size_t len, size_t max) {
    api_limits lim = {max};
    api_request_init(&o->r);
    memset(&o->p, 0, sizeof o->p);
    o->code = api_parse_body(&o->r, kind, body, len, &lim, &o->p);
    return o->code;
}

static api_code parse_json(outcome *o, const char *body) {
    return parse_kind(o, API_IN_JSON, body, strlen(body), 1000);
}

/* A refusal: status code, pointer (NULL: must be empty), line (0: none),
 * and words the detail must contain. */
typedef struct refusal {
    const char *body;
    api_code code;
    const char *pointer;
    long line;
    const char *words;
} refusal;

static void check_refusals(api_input kind, const refusal *cases, size_t n,
                           size_t max) {
    for (size_t i = 0; i < n; i++) {
        outcome o;
        const refusal *c = &cases[i];
        parse_kind(&o, kind, c->body, strlen(c->body), max);
        const char *want_ptr = c->pointer ? c->pointer : "";
        if (o.code != c->code || o.p.code != c->code ||
            strcmp(o.p.pointer, want_ptr) != 0 || o.p.line != c->line ||
            strstr(o.p.detail, c->words) == NULL) {
            fail_msg("body %s\n  got code %d pointer \"%s\" line %ld detail "
                     "\"%s\"\n  want code %d pointer \"%s\" line %ld words \"%s\"",
                     c->body, (int)o.code, o.p.pointer, o.p.line, o.p.detail,
                     (int)c->code, want_ptr, c->line, c->words);
        }
        if (o.r.xy != NULL || o.r.n != 0) fail_msg("%s: points kept", c->body);
        api_request_clear(&o.r);
    }
}

static void test_json_accepted(void **state) {
    (void)state;
    outcome o;
    assert_int_equal(parse_json(&o, "{\"points\": [[1, 2], [-3.5e2, 0.1], "
                                    "[ 0 , -0 ]], \"algorithm\": \"flip\"}"),
                     API_OK);
    assert_int_equal(o.r.n, 3);
    assert_true(o.r.xy[0] == 1 && o.r.xy[1] == 2 && o.r.xy[2] == -350 &&
                o.r.xy[3] == 0.1 && o.r.xy[4] == 0 && signbit(o.r.xy[5]));
    assert_int_equal(o.r.algorithm, VOR_FLIP);
    assert_int_equal(o.r.generated, 0);
    api_request_clear(&o.r);

    /* Bare array, white space everywhere, a BOM. */
    assert_int_equal(parse_json(&o, "\xef\xbb\xbf \n[ [ 1 ,2 ] ,\r\n\t[3,4]]  \n"),
                     API_OK);
    assert_int_equal(o.r.n, 2);
    assert_true(o.r.xy[3] == 4);
    api_request_clear(&o.r);

    assert_int_equal(parse_json(&o, "[]"), API_OK);
    assert_int_equal(o.r.n, 0);
    assert_null(o.r.xy);
    api_request_clear(&o.r);
    assert_int_equal(parse_json(&o, "{\"points\":[]}"), API_OK);
    assert_int_equal(o.r.n, 0);
    api_request_clear(&o.r);

    /* Every option, in an order that differs from the order they apply. */
    assert_int_equal(
        parse_json(&o, "{\"include\": [\"sites\", \"triangles\"], \"format\": "
                       "\"geojson\", \"bounds\": [0, -1, 10.5, 1e1], "
                       "\"points\": [[0,0],[1,1]], \"algorithm\": "
                       "\"bowyer-watson\"}"),
        API_OK);
    assert_int_equal(o.r.parts, API_PART_SITES | API_PART_TRIANGLES);
    assert_true(o.r.parts_given);
    assert_int_equal(o.r.format, API_FMT_GEOJSON);
    assert_true(o.r.has_bounds && o.r.bounds[0] == 0 && o.r.bounds[1] == -1 &&
                o.r.bounds[2] == 10.5 && o.r.bounds[3] == 10);
    assert_int_equal(o.r.algorithm, VOR_BOWYER_WATSON);
    api_request_clear(&o.r);

    /* Names with escapes, or at the end of the object. */
    assert_int_equal(parse_json(&o, "{\"format\":\"s\\u0076g\",\"points\":[[0,0]],"
                                    "\"algorithm\":\"fl\\u0069p\"}"),
                     API_OK);
    assert_int_equal(o.r.format, API_FMT_SVG);
    assert_int_equal(o.r.algorithm, VOR_FLIP);
    api_request_clear(&o.r);
    assert_int_equal(parse_json(&o, "{\"points\":[[0,0]],\"format\":\"timings\","
                                    "\"algorithm\":\"bowyer-watson\"}"),
                     API_OK);
    assert_int_equal(o.r.format, API_FMT_TIMINGS);
    assert_int_equal(o.r.algorithm, VOR_BOWYER_WATSON);
    api_request_clear(&o.r);

    /* trace, and counts as a part */
    assert_int_equal(parse_json(&o, "{\"points\":[[0,0]],\"trace\":true,"
                                    "\"include\":[\"counts\",\"edges\"]}"),
                     API_OK);
    assert_true(o.r.trace);
    assert_int_equal(o.r.parts, API_PART_COUNTS | API_PART_EDGES);
    api_request_clear(&o.r);
    assert_int_equal(parse_json(&o, "{\"points\":[[0,0]],\"trace\":false}"), API_OK);
    assert_false(o.r.trace);
    api_request_clear(&o.r);

    /* include as a string; bounds null; escaped key. */
    assert_int_equal(parse_json(&o, "{\"include\": \"edges,cells\", \"bounds\": "
                                    "null, \"p\\u006fints\": [[5,6]]}"),
                     API_OK);
    assert_int_equal(o.r.parts, API_PART_EDGES | API_PART_CELLS);
    assert_false(o.r.has_bounds);
    assert_int_equal(o.r.n, 1);
    api_request_clear(&o.r);

    /* Numbers that need the exact slow path of the converter. */
    const char *hard = "[[2.2250738585072011e-308, 9007199254740993],"
                       "[1.7976931348623157e308, 4.9406564584124654e-324]]";
    assert_int_equal(parse_json(&o, hard), API_OK);
    assert_true(o.r.xy[0] == strtod("2.2250738585072011e-308", NULL));
    assert_true(o.r.xy[1] == 9007199254740992.0);
    assert_true(o.r.xy[2] == 1.7976931348623157e308);
    assert_true(o.r.xy[3] == 4.9406564584124654e-324);
    api_request_clear(&o.r);
}

static void test_json_generate(void **state) {
    (void)state;
    outcome o;
    assert_int_equal(parse_json(&o, "{\"generate\": {\"distribution\": \"grid\", "
                                    "\"n\": 10, \"seed\": 3}}"),
                     API_OK);
    assert_int_equal(o.r.n, 10);
    assert_true(o.r.generated);
    assert_true(o.r.xy[2 * 9] == 1 && o.r.xy[2 * 9 + 1] == 2); /* 4x4 grid */
    api_request_clear(&o.r);
    assert_int_equal(parse_json(&o, "{\"generate\": {\"n\": 1e2}}"), API_OK);
    assert_int_equal(o.r.n, 100); /* uniform by default */
    for (size_t i = 0; i < 200; i++) assert_true(o.r.xy[i] >= 0 && o.r.xy[i] < 1);
    api_request_clear(&o.r);
}

/* "repeat" (for /compare): an integer 1..50, an integral real too. */
static void test_json_repeat(void **state) {
    (void)state;
    outcome o;
    assert_int_equal(parse_json(&o, "{\"points\": [[0,0]], \"repeat\": 7}"), API_OK);
    assert_int_equal(o.r.repeat, 7);
    api_request_clear(&o.r);
    assert_int_equal(parse_json(&o, "{\"repeat\": 5e1, \"points\": []}"), API_OK);
    assert_int_equal(o.r.repeat, 50);
    api_request_clear(&o.r);
    assert_int_equal(parse_json(&o, "{\"points\": [[0,0]]}"), API_OK);
    assert_int_equal(o.r.repeat, 0); /* absent: the comparison's default */
    api_request_clear(&o.r);
    static const refusal cases[] = {
        {"{\"points\": [], \"repeat\": 0}", API_INVALID, "/repeat", 0,
         "repeat 0 is out of range; give an integer from 1 to 50"},
        {"{\"points\": [], \"repeat\": 51}", API_INVALID, "/repeat", 0,
         "repeat 51 is out of range; give an integer from 1 to 50"},
        {"{\"points\": [], \"repeat\": -2}", API_INVALID, "/repeat", 0,
         "repeat -2 is out of range"},
        {"{\"points\": [], \"repeat\": 2.5}", API_INVALID, "/repeat", 0,
         "repeat 2.5 is not an integer; give an integer from 1 to 50"},
        {"{\"points\": [], \"repeat\": 1e300}", API_INVALID, "/repeat", 0,
         "repeat 1e300 is out of range"},
        {"{\"points\": [], \"repeat\": \"3\"}", API_INVALID, "/repeat", 0,
         "repeat must be an integer from 1 to 50, got a string"},
        {"{\"points\": [], \"repeat\": null}", API_INVALID, "/repeat", 0,
         "got null"},
        {"{\"points\": [], \"repeat\": 3, \"repeat\": 4}", API_MALFORMED,
         "/repeat", 0, "duplicate key \"repeat\""},
        {"{\"points\": [], \"repeats\": 3}", API_MALFORMED, "/repeats", 0,
         "unknown key \"repeats\"; known: points, generate, algorithm, "
         "bounds, include, format, repeat, trace"},
    };
    check_refusals(API_IN_JSON, cases, sizeof cases / sizeof cases[0], 1000);
}

static void test_json_refusals(void **state) {
    (void)state;
    static const refusal cases[] = {
        /* syntax: 400 with byte offset, line and column */
        {"", API_MALFORMED, NULL, 0, "empty body"},
        {"  \n ", API_MALFORMED, NULL, 0, "empty body"},
        {"{\"points\": [[1,2],[3,", API_MALFORMED, "/points/1/1", 0,
         "JSON ends early: expected a number for points[1][1], found end of "
         "input at byte 21 (line 1, column 22)"},
        {"{\"points\": [[1,2],\n [3,4]", API_MALFORMED, "/points", 0,
         "JSON ends early: expected ',' or ']' after a point, found end of input "
         "at byte 25 (line 2, column 7)"},
        {"{\"points\": [[1,2] [3,4]]}", API_MALFORMED, "/points", 0,
         "expected ',' or ']' after a point, found '[' at byte 18"},
        {"{\"points\": [[1,2],]}", API_MALFORMED, "/points", 0,
         "trailing comma in points"},
        {"{\"points\": [[1 2]]}", API_MALFORMED, "/points/0", 0,
         "expected ',' or ']' in points[0]"},
        {"{\"points\": [[01,2]]}", API_MALFORMED, "/points/0/0", 0,
         "points[0][0] is not a valid JSON number: \"01\""},
        {"{\"points\": [[1.,2]]}", API_MALFORMED, "/points/0/0", 0,
         "points[0][0] is not a valid JSON number: \"1.\""},
        {"{\"points\": [[1,2e]]}", API_MALFORMED, "/points/0/1", 0,
         "not a valid JSON number: \"2e\""},
        {"{\"points\": [[1,0x10]]}", API_MALFORMED, "/points/0/1", 0,
         "not a valid JSON number: \"0x10\""},
        {"{\"points\": [[1,+2]]}", API_MALFORMED, "/points/0/1", 0,
         "expected a number for points[0][1], found '+'"},
        {"{\"points\": [[1,2]]} x", API_MALFORMED, NULL, 0,
         "unexpected data after the JSON document, found 'x' at byte 20"},
        {"{\"points\": [[1,2]] \"algorithm\": \"flip\"}", API_MALFORMED, NULL, 0,
         "expected ',' or '}' in the object"},
        {"{points: []}", API_MALFORMED, NULL, 0, "expected a string key"},
        {"{\"points\" []}", API_MALFORMED, "/points", 0, "expected ':' after a key"},
        {"{\"algorithm\": \"flip}", API_MALFORMED, "/algorithm", 0,
         "unterminated value"},
        {"{\"algorithm\": flip}", API_MALFORMED, "/algorithm", 0,
         "invalid JSON in /algorithm"},
        {"{\"include\": [\"edges\",]}", API_MALFORMED, "/include", 0,
         "invalid JSON in /include"},
        {"{\"points\": [[1,2]], \"points\": [[3,4]]}", API_MALFORMED, "/points",
         0, "duplicate key \"points\""},
        {"{\"algorithm\": \"flip\", \"algorithm\": \"flip\"}", API_MALFORMED,
         "/algorithm", 0, "duplicate key \"algorithm\""},
        {"{\"generate\": {\"n\": 1, \"n\": 2}}", API_MALFORMED, "/generate", 0,
         "duplicate object key"},
        /* a plain string and an escaped one are the same key twice, in
         * either order */
        {"{\"algorithm\": \"flip\", \"algorithm\": \"fl\\u0069p\"}",
         API_MALFORMED, "/algorithm", 0, "duplicate key \"algorithm\""},
        {"{\"algorithm\": \"fl\\u0069p\", \"algorithm\": \"flip\"}",
         API_MALFORMED, "/algorithm", 0, "duplicate key \"algorithm\""},
        {"{\"format\": \"svg\", \"points\": [], \"format\": \"svg\"}",
         API_MALFORMED, "/format", 0, "duplicate key \"format\""},
        /* unknown keys: 400 naming the key */
        {"{\"points\": [], \"colour\": \"red\"}", API_MALFORMED, "/colour", 0,
         "unknown key \"colour\"; known: points, generate, algorithm, bounds, "
         "include, format, repeat, trace"},
        {"{\"points\": [], \"trace\": true, \"trace\": false}", API_MALFORMED,
         "/trace", 0, "duplicate key \"trace\""},
        /* trace is a boolean */
        {"{\"points\": [], \"trace\": 1}", API_INVALID, "/trace", 0,
         "trace must be true or false, got a number"},
        {"{\"points\": [], \"trace\": \"true\"}", API_INVALID, "/trace", 0,
         "trace must be true or false, got a string"},
        {"{\"a/b~c\": 1}", API_MALFORMED, "/a~1b~0c", 0, "unknown key \"a/b~c\""},
        {"{\"generate\": {\"n\": 3, \"size\": 2}}", API_MALFORMED,
         "/generate/size", 0, "unknown key \"size\" in generate"},
        /* wrong types and values: 422 with a pointer */
        {"{\"points\": [[17, \"abc\"]]}", API_INVALID, "/points/0/1", 0,
         "points[0][1] is not a number: got a string \"abc\""},
        {"[[0,0],[1,1],[2,2],[3,true]]", API_INVALID, "/3/1", 0,
         "points[3][1] is not a number: got a boolean true"},
        {"[[0,null]]", API_INVALID, "/0/1", 0, "got null null"},
        {"[[0,[1]]]", API_INVALID, "/0/1", 0, "got an array [1]"},
        {"[[0,{\"x\":1}]]", API_INVALID, "/0/1", 0, "got an object {\"x\":1}"},
        {"{\"points\": [[1,2],[3,4,5]]}", API_INVALID, "/points/1", 0,
         "points[1] has 3 coordinates, expected 2"},
        {"{\"points\": [[1]]}", API_INVALID, "/points/0", 0,
         "points[0] has 1 coordinate, expected 2"},
        {"{\"points\": [[]]}", API_INVALID, "/points/0", 0,
         "points[0] has 0 coordinates, expected 2"},
        {"{\"points\": [1, 2]}", API_INVALID, "/points/0", 0,
         "points[0] is not a pair [x, y]: got a number 1"},
        {"{\"points\": {\"x\": [1]}}", API_INVALID, "/points", 0,
         "points is not an array of points [[x, y], ...]: got an object"},
        {"{\"points\": [[1,2],[NaN,0]]}", API_INVALID, "/points/1/0", 0,
         "points[1][0] is NaN, which is not a JSON number; coordinates must be "
         "finite numbers"},
        {"{\"points\": [[1,-Infinity]]}", API_INVALID, "/points/0/1", 0,
         "points[0][1] is -Infinity"},
        {"{\"points\": [[Infinity,1]]}", API_INVALID, "/points/0/0", 0,
         "points[0][0] is Infinity"},
        {"{\"points\": [[0,0],[0,0],[0,0],[0,0],[0,0],[1e999,1]]}", API_INVALID,
         "/points/5/0", 0, "coordinate 1e999 at /points/5/0 overflows a double"},
        {"[[1, -2e308]]", API_INVALID, "/0/1", 0, "coordinate -2e308 at /0/1 overflows"},
        {"\"hello\"", API_INVALID, NULL, 0,
         "the body is not a JSON object or an array of points: got a string"},
        {"42", API_INVALID, NULL, 0, "got a number 42"},
        {"{}", API_INVALID, NULL, 0, "neither \"points\" nor \"generate\""},
        {"{\"algorithm\": \"flip\"}", API_INVALID, NULL, 0, "neither"},
        {"{\"points\": [], \"algorithm\": \"delaunay\"}", API_INVALID,
         "/algorithm", 0,
         "unknown algorithm \"delaunay\"; valid: fortune, bowyer-watson, flip"},
        {"{\"points\": [], \"algorithm\": 3}", API_INVALID, "/algorithm", 0,
         "algorithm must be a string"},
        {"{\"points\": [], \"format\": \"png\"}", API_INVALID, "/format", 0,
         "unknown format \"png\""},
        /* names that are not plain ASCII, or long, or empty: the same
         * refusal whichever way the string is read */
        {"{\"points\": [], \"algorithm\": \"flip\\n\"}", API_INVALID,
         "/algorithm", 0, "unknown algorithm \"flip\\x0a\""},
        {"{\"points\": [], \"algorithm\": \"fortun\xc3\xa9\"}", API_INVALID,
         "/algorithm", 0, "unknown algorithm \"fortun\\xc3\\xa9\""},
        {"{\"points\": [], \"algorithm\": "
         "\"fortune-fortune-fortune-fortune-fortune\"}",
         API_INVALID, "/algorithm", 0,
         "unknown algorithm \"fortune-fortune-fortune-fortune-fortune\""},
        {"{\"points\": [], \"algorithm\": \"\"}", API_INVALID, "/algorithm",
         0, "unknown algorithm \"\""},
        {"{\"points\": [], \"format\": \"SVG\"}", API_INVALID, "/format", 0,
         "unknown format \"SVG\""},
        {"{\"points\": [], \"include\": [\"edges\", \"faces\"]}", API_INVALID,
         "/include/1", 0, "unknown part \"faces\""},
        {"{\"points\": [], \"include\": [\"edges\", 3]}", API_INVALID,
         "/include/1", 0, "include[1] must be a part name, got a number"},
        {"{\"points\": [], \"include\": 3}", API_INVALID, "/include", 0,
         "include must be an array of part names"},
        {"{\"points\": [], \"bounds\": [0, 0, 1]}", API_INVALID, "/bounds", 0,
         "bounds has 3 numbers, expected 4 [xmin, ymin, xmax, ymax]"},
        {"{\"points\": [], \"bounds\": [0, 0, 1, \"2\"]}", API_INVALID,
         "/bounds/3", 0, "bounds[3] is not a number: got a string \"2\""},
        {"{\"points\": [], \"bounds\": [1, 0, 0, 1]}", API_INVALID, "/bounds", 0,
         "xmin 1 must be less than xmax 0"},
        {"{\"points\": [], \"bounds\": [0, 0, 1e999, 1]}", API_INVALID,
         "/bounds/2", 0, "overflows a double"},
        {"{\"points\": [], \"bounds\": \"0,0,1,1\"}", API_INVALID, "/bounds", 0,
         "bounds is not an array [xmin, ymin, xmax, ymax]: got a string"},
        {"{\"points\": [], \"generate\": {\"n\": 5}}", API_INVALID, "/generate", 0,
         "give either points or generate, not both"},
        {"{\"generate\": {\"distribution\": \"poisson\", \"n\": 5}}", API_INVALID,
         "/generate/distribution", 0,
         "unknown distribution \"poisson\"; valid: uniform, gaussian, pixels "
         "(alias random), grid, circle, clustered, lognormal, outlier, decades"},
        {"{\"generate\": {\"distribution\": \"grid\"}}", API_INVALID,
         "/generate/n", 0, "generate.n (the number of points) is required"},
        {"{\"generate\": {\"n\": -4}}", API_INVALID, "/generate/n", 0,
         "generate.n must be a non-negative integer"},
        {"{\"generate\": {\"n\": 2.5}}", API_INVALID, "/generate/n", 0,
         "non-negative integer"},
        {"{\"generate\": {\"n\": \"7\"}}", API_INVALID, "/generate/n", 0,
         "got a string"},
        {"{\"generate\": {\"n\": 3, \"seed\": -1}}", API_INVALID,
         "/generate/seed", 0, "generate.seed must be a non-negative integer"},
        {"{\"generate\": {\"n\": 3, \"seed\": 99999999999999999999999}}",
         API_INVALID, "/generate", 0, "invalid JSON in /generate"},
        {"{\"generate\": [1]}", API_INVALID, "/generate", 0,
         "generate must be an object"},
        /* too many points: 413 */
        {"{\"generate\": {\"n\": 1001}}", API_TOO_LARGE, "/generate/n", 0,
         "generate.n = 1001 is more than 1000 points"},
        {"{\"generate\": {\"n\": 1e300}}", API_TOO_LARGE, "/generate/n", 0,
         "more than 1000 points"},
    };
    check_refusals(API_IN_JSON, cases, sizeof cases / sizeof cases[0], 1000);
}

static void test_json_too_many(void **state) {
    (void)state;
    static const refusal cases[] = {
        {"[[0,0],[1,1],[2,2],[3,3]]", API_TOO_LARGE, "/3", 0,
         "more than 3 points (the limit of this service)"},
        {"{\"points\": [[0,0],[1,1],[2,2],[3,3]]}", API_TOO_LARGE, "/points/3", 0,
         "more than 3 points"},
    };
    check_refusals(API_IN_JSON, cases, 2, 3);
    outcome o;
    assert_int_equal(parse_kind(&o, API_IN_JSON, "[[0,0],[1,1],[2,2]]", 19, 3),
                     API_OK);
    assert_int_equal(o.r.n, 3);
    api_request_clear(&o.r);
}

/* The body need not be NUL-terminated: a number cut by the length must not
 * run on into the bytes that follow. */
static void test_json_not_terminated(void **state) {
    (void)state;
    char body[] = "[[1,23]]45";
    outcome o;
    assert_int_equal(parse_kind(&o, API_IN_JSON, body, 8, 10), API_OK);
    assert_true(o.r.xy[1] == 23);
    api_request_clear(&o.r);
    assert_int_equal(parse_kind(&o, API_IN_JSON, body, 6, 10), API_MALFORMED);
    assert_non_null(strstr(o.p.detail, "JSON ends early"));
    api_request_clear(&o.r);
    /* Every prefix of a valid body is refused (400) or accepted, never read
     * beyond its length (ASan would see it: the copy is exactly sized). */
    const char *full = "{\"algorithm\": \"flip\", \"bounds\": [0,0,1,1], "
                       "\"include\": [\"sites\"], \"points\": [[1.5e3, -2], "
                       "[3, 4]], \"generate\": null}";
    size_t n = strlen(full);
    for (size_t k = 0; k < n; k++) {
        char *copy = malloc(k ? k : 1);
        memcpy(copy, full, k);
        api_code c = parse_kind(&o, API_IN_JSON, copy, k, 10);
        if (c != API_MALFORMED) fail_msg("prefix of %zu bytes gave %d", k, (int)c);
        api_request_clear(&o.r);
        free(copy);
    }
}

static void test_json_random_round_trip(void **state) {
    (void)state;
    const uint64_t seed = 0x9a55e001u;
    printf("# seed %#llx\n", (unsigned long long)seed);
    uint64_t s = seed;
    size_t n = 20000;
    double *want = malloc(2 * n * sizeof(double));
    char *body = malloc(n * 2 * 30 + 16);
    size_t len = 0;
    body[len++] = '[';
    for (size_t i = 0; i < 2 * n; i++) {
        s = s * 6364136223846793005u + 1442695040888963407u;
        uint64_t u = s ^ (s >> 29);
        double v;
        memcpy(&v, &u, sizeof v);
        if (!isfinite(v)) v = (double)(u >> 12) / 7.0;
        if (i % 2 == 0) len += (size_t)sprintf(body + len, "%s[", i ? "," : "");
        len += (size_t)sprintf(body + len, "%.17g%s", v, i % 2 ? "]" : ", ");
        want[i] = v; /* %.17g reads back exactly */
    }
    body[len++] = ']';
    outcome o;
    assert_int_equal(parse_kind(&o, API_IN_JSON, body, len, n), API_OK);
    assert_int_equal(o.r.n, n);
    for (size_t i = 0; i < 2 * n; i++) {
        if (memcmp(&o.r.xy[i], &want[i], sizeof(double)) != 0) {
            fail_msg("coordinate %zu: %a, wrote %a", i, o.r.xy[i], want[i]);
        }
    }
    api_request_clear(&o.r);
    free(body);
    free(want);
}

static void test_text_accepted(void **state) {
    (void)state;
    const char *body = "# points\r\n"
                       "x,y\r\n"
                       "1,2\r\n"
                       "\r\n"
                       "  3.5 \t -4e1  # comment\n"
                       "+5;.25\n"
                       "6 , 7\n"
                       "\t\n"
                       "-0\t8";
    outcome o;
    assert_int_equal(parse_kind(&o, API_IN_TEXT, body, strlen(body), 100), API_OK);
    assert_int_equal(o.r.n, 5);
    static const double want[] = {1, 2, 3.5, -40, 5, 0.25, 6, 7, -0.0, 8};
    for (int i = 0; i < 10; i++) assert_true(o.r.xy[i] == want[i]);
    assert_true(signbit(o.r.xy[8]));
    api_request_clear(&o.r);

    assert_int_equal(parse_kind(&o, API_IN_TEXT, "", 0, 10), API_OK);
    assert_int_equal(o.r.n, 0);
    api_request_clear(&o.r);
    /* Column names are skipped, quoted or not, numbers in names too. */
    assert_int_equal(parse_kind(&o, API_IN_TEXT, "\"lon1\";\"lat1\"\n1;2\n",
                                strlen("\"lon1\";\"lat1\"\n1;2\n"), 10), API_OK);
    assert_int_equal(o.r.n, 1);
    api_request_clear(&o.r);
    assert_int_equal(parse_kind(&o, API_IN_TEXT, "nancy infinite\n1 2\n", 19,
                                10), API_OK);
    assert_int_equal(o.r.n, 1);
    api_request_clear(&o.r);

    /* AUTO: text unless it starts like JSON. */
    assert_int_equal(parse_kind(&o, API_IN_AUTO, "1 2\n3 4\n", 8, 10), API_OK);
    assert_int_equal(o.r.n, 2);
    api_request_clear(&o.r);
    assert_int_equal(parse_kind(&o, API_IN_AUTO, " [[1,2]]", 8, 10), API_OK);
    assert_int_equal(o.r.n, 1);
    api_request_clear(&o.r);
    assert_int_equal(parse_kind(&o, API_IN_AUTO, "{\"x\":1}", 7, 10), API_MALFORMED);
    assert_non_null(strstr(o.p.detail, "unknown key \"x\""));
    api_request_clear(&o.r);
    assert_int_equal(parse_kind(&o, API_IN_AUTO, " \n", 2, 10), API_MALFORMED);
    assert_non_null(strstr(o.p.detail, "empty body"));
    api_request_clear(&o.r);
}

/* text/plain (API_IN_PLAIN): what a browser's fetch() sends for a JSON
 * string without a Content-Type. JSON when it starts with '{' or '['
 * after white space and a byte order mark, text otherwise; empty is text
 * (no points), as for text/csv. */
static void test_plain_sniffed(void **state) {
    (void)state;
    outcome o;
    static const char *const json_bodies[] = {
        "{\"points\": [[0,0],[1,0],[0,1]], \"algorithm\": \"flip\"}",
        "\xef\xbb\xbf {\"points\": [[0,0],[1,0],[0,1]], \"algorithm\": \"flip\"}",
        "\r\n\t [[0,0],[1,0],[0,1]]",
    };
    for (size_t i = 0; i < 3; i++) {
        const char *b = json_bodies[i];
        if (parse_kind(&o, API_IN_PLAIN, b, strlen(b), 10) != API_OK) {
            fail_msg("%s: %s", b, o.p.detail);
        }
        assert_int_equal(o.r.n, 3);
        assert_true(o.r.xy[2] == 1 && o.r.xy[5] == 1);
        assert_int_equal(o.r.algorithm, i < 2 ? VOR_FLIP : VOR_FORTUNE);
        api_request_clear(&o.r);
    }
    /* Errors are JSON's, with a pointer, not a text line's. */
    const char *bad = "{\"points\": [[0,0],[1,\"x\"]]}";
    assert_int_equal(parse_kind(&o, API_IN_PLAIN, bad, strlen(bad), 10), API_INVALID);
    assert_string_equal(o.p.pointer, "/points/1/1");
    assert_int_equal(o.p.line, 0);
    api_request_clear(&o.r);
    /* Text stays text. */
    assert_int_equal(parse_kind(&o, API_IN_PLAIN, "x y\n1 2\n3 4\n", 12, 10), API_OK);
    assert_int_equal(o.r.n, 2);
    api_request_clear(&o.r);
    assert_int_equal(parse_kind(&o, API_IN_PLAIN, "1 2\n{3 4\n", 9, 10), API_MALFORMED);
    assert_int_equal(o.p.line, 2);
    api_request_clear(&o.r);
    assert_int_equal(parse_kind(&o, API_IN_PLAIN, "  \n", 3, 10), API_OK);
    assert_int_equal(o.r.n, 0);
    api_request_clear(&o.r);
}

static void test_text_refusals(void **state) {
    (void)state;
    static const refusal cases[] = {
        {"1,2\n3,4\n5,6\n7,8\n9,10\n11,12\n13,14\n15,16\n17,18\n19,20\n21,22\n3.5,\n",
         API_MALFORMED, NULL, 12, "line 12: expected two numbers, got \"3.5,\""},
        {"1 2 3", API_MALFORMED, NULL, 1, "line 1: expected two numbers, got \"1 2 3\""},
        {"x,y\n1,2\nfoo,bar\n", API_MALFORMED, NULL, 3,
         "line 3: expected two numbers, got \"foo,bar\""},
        {"1,2\n3\n", API_MALFORMED, NULL, 2, "line 2: expected two numbers, got \"3\""},
        {"1,,2", API_MALFORMED, NULL, 1, "got \"1,,2\""},
        {"1x 2", API_MALFORMED, NULL, 1, "got \"1x 2\""},
        {"1 2x", API_MALFORMED, NULL, 1, "got \"1 2x\""},
        {"\n\n1 nan\n", API_INVALID, NULL, 3,
         "line 3: coordinate \"nan\" is not a finite number"},
        {"-inf 0", API_INVALID, NULL, 1, "coordinate \"-inf\" is not a finite"},
        {"1 2\n1e999 3", API_INVALID, NULL, 2, "line 2: coordinate 1e999 overflows"},
        /* A first line holding a number strtod reads is a point, never a
         * header to skip: nan and inf are refused with their line. */
        {"nan,0\n1,2\n3,4\n5,6\n", API_INVALID, NULL, 1,
         "line 1: coordinate \"nan\" is not a finite number"},
        {"inf 5\n1 2\n", API_INVALID, NULL, 1,
         "line 1: coordinate \"inf\" is not a finite number"},
        {"# c\nNaN;NAN\n", API_INVALID, NULL, 2, "coordinate \"NaN\""},
        {"x,5\n1,2\n", API_MALFORMED, NULL, 1,
         "line 1: expected two numbers, got \"x,5\""},
        {"Infinity x\n1,2\n", API_INVALID, NULL, 1, "\"Infinity\""},
        /* Only names: an error, not an empty diagram. */
        {"lon lat\n# none\n", API_MALFORMED, NULL, 1,
         "line 1 was taken for column names and no line holds a point"},
        {"\n\nx,y\n\n", API_MALFORMED, NULL, 3, "line 3 was taken"},
        {"hello\n", API_MALFORMED, NULL, 1, "no line holds a point"},
    };
    check_refusals(API_IN_TEXT, cases, sizeof cases / sizeof cases[0], 100);
    static const refusal too_many[] = {
        {"1 2\r\n3 4\r\n5 6\r\n", API_TOO_LARGE, NULL, 3, "more than 2 points"},
    };
    check_refusals(API_IN_TEXT, too_many, 1, 2);
}

static void put_le(unsigned char *b, double v) {
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    for (int i = 0; i < 8; i++) b[i] = (unsigned char)(u >> (8 * i));
}

static void test_binary(void **state) {
    (void)state;
    unsigned char b[64];
    double v[8] = {1, 2, -3.5, 1e300, 5e-324, -0.0, 7, 8};
    for (int i = 0; i < 8; i++) put_le(b + 8 * i, v[i]);
    outcome o;
    assert_int_equal(parse_kind(&o, API_IN_BINARY, (char *)b, 64, 10), API_OK);
    assert_int_equal(o.r.n, 4);
    assert_memory_equal(o.r.xy, v, sizeof v);
    api_request_clear(&o.r);

    assert_int_equal(parse_kind(&o, API_IN_BINARY, (char *)b, 0, 10), API_OK);
    assert_int_equal(o.r.n, 0);
    api_request_clear(&o.r);

    assert_int_equal(parse_kind(&o, API_IN_BINARY, (char *)b, 17, 10), API_MALFORMED);
    assert_non_null(strstr(o.p.detail, "binary body is 17 bytes, not a multiple of 16"));
    assert_int_equal(api_code_http(o.p.code), 400);
    api_request_clear(&o.r);

    assert_int_equal(parse_kind(&o, API_IN_BINARY, (char *)b, 64, 3), API_TOO_LARGE);
    assert_non_null(strstr(o.p.detail, "more than 3 points"));
    api_request_clear(&o.r);

    put_le(b + 40, NAN);
    assert_int_equal(parse_kind(&o, API_IN_BINARY, (char *)b, 64, 10), API_INVALID);
    assert_string_equal(o.p.pointer, "/points/2/1");
    assert_non_null(strstr(o.p.detail, "point 2 (bytes 32..47): y is NaN"));
    assert_null(o.r.xy);
    api_request_clear(&o.r);
    put_le(b + 40, 0);
    put_le(b + 48, -INFINITY);
    assert_int_equal(parse_kind(&o, API_IN_BINARY, (char *)b, 64, 10), API_INVALID);
    assert_non_null(strstr(o.p.detail, "point 3 (bytes 48..63): x is infinite"));
    api_request_clear(&o.r);
}

/* Parsing twice into one request replaces the points; a failed parse leaves
 * none. */
static void test_reuse(void **state) {
    (void)state;
    api_request r;
    api_problem p;
    api_limits lim = {10};
    api_request_init(&r);
    assert_int_equal(api_parse_body(&r, API_IN_JSON, "[[1,2]]", 7, &lim, &p), API_OK);
    assert_int_equal(api_parse_body(&r, API_IN_TEXT, "3 4\n5 6", 7, &lim, &p), API_OK);
    assert_int_equal(r.n, 2);
    assert_true(r.xy[0] == 3);
    assert_int_equal(api_parse_body(&r, API_IN_TEXT, "3 4\n5", 5, &lim, &p),
                     API_MALFORMED);
    assert_int_equal(r.n, 0);
    assert_null(r.xy);
    assert_int_equal(api_parse_body(&r, API_IN_JSON, "[[1,2]]", 7, NULL, &p), API_OK);
    api_request_clear(&r);
}

/* Random damage to valid bodies (bytes replaced, inserted, deleted, cut)
 * must give an answer, never a crash or a read out of bounds (ASan), and
 * only the statuses parsing can give. Each mutated body is an exactly
 * sized heap copy. */
static void test_mutations(void **state) {
    (void)state;
    static const char *const seeds[] = {
        "{\"points\": [[1.5, -2e3], [0, 0], [3, 4]], \"algorithm\": \"flip\", "
        "\"bounds\": [-1, -1, 5, 5], \"include\": [\"sites\", \"clipped\"], "
        "\"format\": \"svg\"}",
        "[[0,0],[1,1],[2,0.5]]",
        "{\"generate\": {\"distribution\": \"grid\", \"n\": 9, \"seed\": 4}}",
        "# x,y\n1,2\n3 4\r\n5;6\n",
    };
    static const char alphabet[] = "[]{},:\"\\0123456789.eE+-nNaItrufl \n\t#x";
    const uint64_t seed = 0x6d757401u;
    printf("# seed %#llx, 40000 mutated bodies\n", (unsigned long long)seed);
    uint64_t s = seed;
    for (int iter = 0; iter < 40000; iter++) {
        s = s * 6364136223846793005u + 1442695040888963407u;
        const char *base = seeds[(s >> 33) % 4];
        size_t len = strlen(base);
        char buf[512];
        memcpy(buf, base, len);
        int edits = 1 + (int)((s >> 40) % 4);
        for (int e = 0; e < edits; e++) {
            s = s * 6364136223846793005u + 1442695040888963407u;
            size_t at = len ? (size_t)(s >> 20) % len : 0;
            char c = alphabet[(s >> 50) % (sizeof alphabet - 1)];
            switch ((s >> 60) % 4) {
            case 0: if (len) buf[at] = c; break;
            case 1:
                if (len < sizeof buf - 1) {
                    memmove(buf + at + 1, buf + at, len - at);
                    buf[at] = c;
                    len++;
                }
                break;
            case 2:
                if (len) {
                    memmove(buf + at, buf + at + 1, len - at - 1);
                    len--;
                }
                break;
            default: len = at; break;
            }
        }
        char *body = malloc(len ? len : 1);
        memcpy(body, buf, len);
        for (int k = API_IN_JSON; k <= API_IN_PLAIN; k++) {
            outcome o;
            api_code c = parse_kind(&o, (api_input)k, body, len, 100);
            if (c != API_OK && c != API_MALFORMED && c != API_INVALID &&
                c != API_TOO_LARGE) {
                fail_msg("mutated body gave status %d: %.*s", (int)c, (int)len, body);
            }
            if (c != API_OK && o.p.detail[0] == 0) fail_msg("refusal without a detail");
            api_request_clear(&o.r);
        }
        free(body);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_json_accepted),
        cmocka_unit_test(test_json_generate),
        cmocka_unit_test(test_json_repeat),
        cmocka_unit_test(test_json_refusals),
        cmocka_unit_test(test_json_too_many),
        cmocka_unit_test(test_json_not_terminated),
        cmocka_unit_test(test_json_random_round_trip),
        cmocka_unit_test(test_text_accepted),
        cmocka_unit_test(test_plain_sniffed),
        cmocka_unit_test(test_text_refusals),
        cmocka_unit_test(test_binary),
        cmocka_unit_test(test_reuse),
        cmocka_unit_test(test_mutations),
    };
    return cmocka_run_group_tests_name("api/parse", tests, NULL, NULL);
}
