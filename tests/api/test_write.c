/* test_write.c -- the writers (JSON, GeoJSON, SVG, binary, timings,
 * compare) on hand-made diagrams, read back by independent readers
 * (result_check.h) and compared value by value.
 *
 * The diagrams are written out by hand so that these tests depend on no
 * algorithm: three sites around one vertex (with a duplicate input point),
 * two sites (one line), and a vertex whose coordinates overflowed. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../api/codec.h"
#include "../../api/numconv.h"
#include "../../core/internal.h"
#include "result_check.h"

/* Sites (0,0), (2,0), (0,2) and input 3 = (2,0) again. One vertex (1,1);
 * three rays; three unbounded cells. Clipped to [-1,-1,3,3]. */
static double tri_xy[] = {0, 0, 2, 0, 0, 2};
static uint32_t tri_input_of[] = {0, 1, 2};
static uint32_t tri_site_of[] = {0, 1, 2, 1};
static vor_sites tri_sites = {4, 3, tri_xy, tri_input_of, tri_site_of};
static double tri_vxy[] = {1, 1};
static uint32_t tri_vsites[] = {0, 1, 2};
static uint32_t tri_esites[] = {0, 1, 0, 2, 1, 2};
static int32_t tri_eends[] = {0, -1, 0, -1, 0, -1};
static uint32_t tri_ray_edge[] = {0, 1, 2};
static double tri_ray_dir[] = {0, -1, -1, 0, 0.70710678118654757, 0.70710678118654757};
static uint32_t tri_cell_start[] = {0, 2, 4, 6};
static uint32_t tri_cell_edges[] = {0, 1, 2, 0, 1, 2};
static uint8_t tri_bounded[] = {0, 0, 0};
static vor_diagram tri_diagram = {3,           1,          tri_vxy,        tri_vsites,
                                  3,           tri_esites, tri_eends,      3,
                                  tri_ray_edge, tri_ray_dir, tri_cell_start, tri_cell_edges,
                                  tri_bounded};
static double tri_seg[] = {1, 1, 1, -1, 1, 1, -1, 1, 1, 1, 3, 3};
static uint8_t tri_seg_in[] = {1, 1, 1};
/* Closed rings, as vor_clip gives them; the third is left open to check
 * that GeoJSON closes it. */
static uint32_t tri_poly_start[] = {0, 5, 10, 14};
static double tri_poly_xy[] = {-1, -1, 1, -1, 1, 1, -1, 1, -1, -1,
                               1,  -1, 3, -1, 3, 3, 1,  1, 1,  -1,
                               -1, 1,  1, 1,  3, 3, -1, 3};
static vor_clipped tri_clipped = {{-1, -1, 3, 3}, tri_seg, tri_seg_in, tri_poly_start,
                                  tri_poly_xy};
static uint32_t tri_triangles[] = {0, 1, 2};

static api_result tri_result(void) {
    api_result res;
    api_result_init(&res);
    res.algorithm = VOR_BOWYER_WATSON;
    res.sites = &tri_sites;
    res.diagram = &tri_diagram;
    res.clipped = &tri_clipped;
    res.triangles = tri_triangles;
    res.n_triangles = 1;
    res.t.parse_ms = 1.25;
    res.t.prepare_ms = 0.5;
    res.t.compute_ms = 2;
    /* made-up counts, some of them not Bowyer-Watson's (never written) */
    res.counts.orient2d = 12;
    res.counts.incircle = 3;
    res.counts.cavity_triangles = 1;
    res.counts.triangles_created = 6;
    res.counts.flips = 7;
    res.counts.circle_events = 9;
    res.counts.order_keys = (uint64_t)1 << 40; /* beyond 32 bits */
    return res;
}

/* Two sites (1e308, 0) and (1.5e308, 0): one line, x = 1.25e308, whose
 * midpoint overflows when computed as (a + b) / 2. Clipped to a box around
 * the first site only: the line misses it, the first cell is the whole box,
 * the second cell's polygon is empty. */
static double line_xy[] = {1e308, 0, 1.5e308, 0};
static uint32_t line_input_of[] = {0, 1};
static uint32_t line_site_of[] = {0, 1};
static vor_sites line_sites = {2, 2, line_xy, line_input_of, line_site_of};
static uint32_t line_esites[] = {0, 1};
static int32_t line_eends[] = {-1, -1};
static uint32_t line_ray_edge[] = {0};
static double line_ray_dir[] = {0, 1};
static uint32_t line_cell_start[] = {0, 1, 2};
static uint32_t line_cell_edges[] = {0, 0};
static uint8_t line_bounded[] = {0, 0};
static vor_diagram line_diagram = {2, 0, NULL, NULL, 1, line_esites, line_eends,
                                   1, line_ray_edge, line_ray_dir, line_cell_start,
                                   line_cell_edges, line_bounded};
static double line_seg[] = {0, 0, 0, 0};
static uint8_t line_seg_in[] = {0};
static uint32_t line_poly_start[] = {0, 5, 5};
static double line_poly_xy[] = {0.9e308, -1, 1.1e308, -1, 1.1e308, 1, 0.9e308, 1,
                                0.9e308, -1};
static vor_clipped line_clipped = {{0.9e308, -1, 1.1e308, 1}, line_seg, line_seg_in,
                                   line_poly_start, line_poly_xy};

static api_result line_result(void) {
    api_result res;
    api_result_init(&res);
    res.sites = &line_sites;
    res.diagram = &line_diagram;
    res.clipped = &line_clipped;
    return res;
}

static api_request request(api_format f, unsigned parts, int parts_given) {
    api_request r;
    api_request_init(&r);
    r.format = f;
    r.parts = parts;
    r.parts_given = parts_given;
    return r;
}

static void write_ok(const api_request *r, const api_result *res, api_buf *out) {
    api_problem p;
    api_timings t = res->t;
    api_buf_init(out);
    api_code c = api_write_result(r, res, &t, out, &p);
    if (c != API_OK) fail_msg("write: %s", p.detail);
    assert_false(out->oom);
    assert_true(t.serialize_ms >= 0);
    assert_true(t.total_ms >= t.parse_ms + t.prepare_ms + t.compute_ms);
}

static void test_json_all_parts(void **state) {
    (void)state;
    api_result res = tri_result();
    api_request r = request(API_FMT_JSON, API_PART_ALL, 1);
    r.has_bounds = 1;
    api_buf out;
    write_ok(&r, &res, &out);
    rc_check_json(out.data, out.len, &res, API_PART_ALL, 1);
    /* A few literal checks, so the oracle itself is anchored. */
    assert_non_null(strstr(out.data, "\"algorithm\":\"bowyer-watson\""));
    assert_non_null(strstr(out.data, "\"duplicates\":[[3,1]]"));
    assert_non_null(strstr(out.data, "\"sites\":[[0,0],[2,0],[0,2],[2,0]]"));
    assert_non_null(strstr(out.data, "\"vertices\":[[1,1]]"));
    assert_non_null(strstr(out.data, "{\"sites\":[1,2],\"ends\":[0,null],"
                                     "\"ray\":[0.7071067811865476,0.7071067811865476]}"));
    assert_non_null(strstr(out.data, "{\"site\":0,\"edges\":[0,1],\"bounded\":false}"));
    assert_non_null(strstr(out.data, "\"triangles\":[[0,1,2]]"));
    assert_non_null(strstr(out.data, "\"clipped\":{\"bounds\":[-1,-1,3,3],"
                                     "\"bounds_given\":true,\"edges\":[[1,1,1,-1]"));
    assert_non_null(strstr(out.data, "\"parse_ms\":1.25,\"prepare_ms\":0.5,"
                                     "\"compute_ms\":2,"));
    assert_int_equal(out.data[out.len - 2], '}');
    assert_int_equal(out.data[out.len - 1], '\n');
    api_buf_clear(&out);
}

/* Every text document ends with exactly one newline (a shell prompt then
 * starts on its own line, and documents concatenate line by line); the
 * binary one ends with its timings. */
static void test_trailing_newline(void **state) {
    (void)state;
    api_result res = tri_result();
    static const char *const ends[] = {
        [API_FMT_JSON] = "}}\n", [API_FMT_GEOJSON] = "}}\n",
        [API_FMT_SVG] = "</svg>\n", [API_FMT_TIMINGS] = "}\n"};
    for (int f = API_FMT_JSON; f <= API_FMT_TIMINGS; f++) {
        api_request r = request((api_format)f, API_PART_ALL, 1);
        api_buf out;
        write_ok(&r, &res, &out);
        if (f == API_FMT_BINARY) {
            assert_int_equal(out.len % 8, 0); /* f64 timings, no newline */
        } else {
            size_t n = strlen(ends[f]);
            if (out.len < n + 1 || memcmp(out.data + out.len - n, ends[f], n) != 0 ||
                out.data[out.len - 2] == '\n') {
                fail_msg("format %d ends with \"%s\"", f,
                         out.data + (out.len > 12 ? out.len - 12 : 0));
            }
        }
        api_buf_clear(&out);
    }
    api_compare c;
    api_compare_init(&c);
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) c.res[a] = tri_result();
    api_request r = request(API_FMT_JSON, API_PART_DEFAULT, 0);
    api_buf out;
    api_problem p;
    api_buf_init(&out);
    assert_int_equal(api_write_compare(&r, &c, &out, &p), API_OK);
    assert_true(out.len > 3 && memcmp(out.data + out.len - 3, "}}\n", 3) == 0);
    api_buf_clear(&out);
}

static void test_json_default_and_chosen_parts(void **state) {
    (void)state;
    api_result res = tri_result();
    /* Defaults: vertices, edges, cells; bounds add "clipped". */
    api_request r = request(API_FMT_JSON, API_PART_DEFAULT, 0);
    api_buf out;
    write_ok(&r, &res, &out);
    rc_check_json(out.data, out.len, &res, API_PART_DEFAULT, 0);
    api_buf_clear(&out);
    r.has_bounds = 1;
    write_ok(&r, &res, &out);
    rc_check_json(out.data, out.len, &res, API_PART_DEFAULT | API_PART_CLIPPED, 1);
    api_buf_clear(&out);
    /* Chosen parts are exactly what is written, bounds or not. */
    r = request(API_FMT_JSON, API_PART_SITES, 1);
    r.has_bounds = 1;
    write_ok(&r, &res, &out);
    rc_check_json(out.data, out.len, &res, API_PART_SITES, 1);
    api_buf_clear(&out);
    r = request(API_FMT_JSON, 0, 1);
    write_ok(&r, &res, &out);
    rc_check_json(out.data, out.len, &res, 0, 0);
    api_buf_clear(&out);
}

static void test_json_line_and_overflow(void **state) {
    (void)state;
    api_result res = line_result();
    api_request r = request(API_FMT_JSON, API_PART_ALL, 1);
    api_buf out;
    write_ok(&r, &res, &out);
    rc_check_json(out.data, out.len, &res, API_PART_ALL, 0);
    assert_non_null(strstr(out.data, "\"ends\":[null,null],\"ray\":[0,1],"
                                     "\"point\":[1.25e308,0]"));
    assert_non_null(strstr(out.data, "\"cells\":[[[9e307,-1],[1.1e308,-1],"
                                     "[1.1e308,1],[9e307,1],[9e307,-1]],[]]"));
    api_buf_clear(&out);

    /* A vertex whose coordinates overflowed is written as null. */
    double vxy[] = {INFINITY, -INFINITY};
    vor_diagram d = tri_diagram;
    d.vertex_xy = vxy;
    res = tri_result();
    res.diagram = &d;
    r = request(API_FMT_JSON, API_PART_VERTICES, 1);
    write_ok(&r, &res, &out);
    assert_non_null(strstr(out.data, "\"vertices\":[[null,null]]"));
    rc_check_json(out.data, out.len, &res, API_PART_VERTICES, 0);
    api_buf_clear(&out);
}

static void test_geojson(void **state) {
    (void)state;
    api_result res = tri_result();
    api_request r = request(API_FMT_GEOJSON, API_PART_DEFAULT, 0);
    api_buf out;
    write_ok(&r, &res, &out);
    rc_check_geojson(out.data, out.len, &res);
    assert_non_null(strstr(out.data, "\"bounds_given\":false,\"bounds_note\":"));
    assert_non_null(strstr(out.data, "{\"type\":\"Polygon\",\"coordinates\":"
                                     "[[[-1,-1],[1,-1],[1,1],[-1,1],[-1,-1]]]}"));
    assert_non_null(strstr(out.data, "{\"type\":\"Polygon\",\"coordinates\":"
                                     "[[[-1,1],[1,1],[3,3],[-1,3],[-1,1]]]}"));
    api_buf_clear(&out);
    res = line_result();
    r.has_bounds = 1;
    write_ok(&r, &res, &out);
    rc_check_geojson(out.data, out.len, &res); /* the second geometry is null */
    assert_non_null(strstr(out.data, "\"geometry\":null"));
    assert_null(strstr(out.data, "bounds_note"));
    api_buf_clear(&out);
}

static void test_svg(void **state) {
    (void)state;
    api_result res = tri_result();
    api_request r = request(API_FMT_SVG, API_PART_DEFAULT, 0);
    api_buf out;
    write_ok(&r, &res, &out);
    rc_check_svg(out.data, out.len, &res);
    /* Box [-1,-1,3,3] -> viewBox 1000 x 1000; site (2,0) at (750, 750);
     * edge (1,1)-(3,3) from (500,500) to (1000,0). */
    assert_non_null(strstr(out.data, "viewBox=\"0 0 1000 1000\""));
    assert_non_null(strstr(out.data, "<circle cx=\"750\" cy=\"750\""));
    assert_non_null(strstr(out.data, "M500 500L1000 0"));
    api_buf_clear(&out);
    res = line_result();
    write_ok(&r, &res, &out);
    rc_check_svg(out.data, out.len, &res);
    api_buf_clear(&out);
}

static void test_binary(void **state) {
    (void)state;
    api_result res = tri_result();
    api_request r = request(API_FMT_BINARY, API_PART_DEFAULT | API_PART_TRIANGLES, 1);
    api_buf out;
    write_ok(&r, &res, &out);
    rc_check_binary(out.data, out.len, &res, 1);
    api_buf_clear(&out);
    r = request(API_FMT_BINARY, API_PART_DEFAULT, 0);
    res.clipped = NULL;
    write_ok(&r, &res, &out);
    rc_check_binary(out.data, out.len, &res, 0);
    api_buf_clear(&out);
    res = line_result();
    write_ok(&r, &res, &out);
    rc_check_binary(out.data, out.len, &res, 0);
    api_buf_clear(&out);
}

static void test_timings_only(void **state) {
    (void)state;
    api_result res = tri_result();
    api_request r = request(API_FMT_TIMINGS, API_PART_DEFAULT, 0);
    api_buf out;
    api_problem p;
    api_buf_init(&out);
    res.t.total_ms = 100; /* the caller's wall clock so far wins over the sum */
    assert_int_equal(api_write_result(&r, &res, &res.t, &out, &p), API_OK);
    json_error_t err;
    json_t *j = json_loadb(out.data, out.len, JSON_REJECT_DUPLICATES, &err);
    assert_non_null(j);
    /* Labelled: the algorithm and the sizes first, then the timings. */
    assert_memory_equal(out.data, "{\"algorithm\":\"", 14);
    assert_string_equal(json_string_value(json_object_get(j, "algorithm")),
                        vor_algorithm_name(res.algorithm));
    assert_int_equal(json_integer_value(json_object_get(j, "n_input")), 4);
    assert_int_equal(json_integer_value(json_object_get(j, "n_sites")), 3);
    json_t *t = json_deep_copy(j);
    json_object_del(t, "algorithm");
    json_object_del(t, "n_input");
    json_object_del(t, "n_sites");
    rc_check_timings(t);
    json_decref(t);
    assert_true(json_number_value(json_object_get(j, "total_ms")) >= 100);
    assert_true(res.t.total_ms >= 100 && res.t.total_ms == 100 + res.t.serialize_ms);
    json_decref(j);
    api_buf_clear(&out);
}

/* format=timings with include=counts: the timings object gains the
 * counts, and nothing else. */
static void test_timings_with_counts(void **state) {
    (void)state;
    api_result res = tri_result();
    api_request r = request(API_FMT_TIMINGS, API_PART_COUNTS, 1);
    api_buf out;
    write_ok(&r, &res, &out);
    json_error_t err;
    json_t *j = json_loadb(out.data, out.len, JSON_REJECT_DUPLICATES, &err);
    if (j == NULL) fail_msg("not JSON: %s: %s", err.text, out.data);
    rc_check_counts(json_object_get(j, "counts"), &res.counts, VOR_BOWYER_WATSON);
    assert_int_equal(json_object_size(j), 11); /* labels, timings, counts */
    assert_int_equal(json_integer_value(json_object_get(json_object_get(j, "counts"),
                                                        "order_keys")),
                     (json_int_t)1 << 40);
    json_object_del(j, "counts");
    json_object_del(j, "algorithm");
    json_object_del(j, "n_input");
    json_object_del(j, "n_sites");
    rc_check_timings(j);
    json_decref(j);
    api_buf_clear(&out);
}

/* A traced result carries "trace": {"steps": [...]} with the steps as
 * the tracer wrote them, before the timings. */
static void test_json_trace_member(void **state) {
    (void)state;
    api_result res = tri_result();
    res.traced = 1;
    api_buf_init(&res.trace);
    assert_int_equal(api_buf_append(&res.trace, "{\"kind\":\"end\"}", 14), 0);
    api_request r = request(API_FMT_JSON, API_PART_DEFAULT, 0);
    api_buf out;
    write_ok(&r, &res, &out);
    json_error_t err;
    json_t *j = json_loadb(out.data, out.len, JSON_REJECT_DUPLICATES, &err);
    if (j == NULL) fail_msg("not JSON: %s: %s", err.text, out.data);
    json_t *steps = json_object_get(json_object_get(j, "trace"), "steps");
    assert_int_equal(json_array_size(steps), 1);
    assert_string_equal(json_string_value(json_object_get(json_array_get(steps, 0), "kind")),
                        "end");
    assert_null(json_object_get(j, "counts")); /* not asked for */
    assert_non_null(strstr(out.data, "]},\"timings\":{"));
    json_decref(j);
    api_buf_clear(&out);
    api_buf_clear(&res.trace);
}

/* Every kind of step through the tracer, on sites whose input indices
 * differ from their site indices (input 1 repeats input 0). */
static void test_trace_steps(void **state) {
    (void)state;
    static double xy[] = {0, 0, 4, 0, 0, 4};
    static uint32_t input_of[] = {0, 2, 3};
    static uint32_t site_of[] = {0, 0, 1, 2};
    vor_sites s = {4, 3, xy, input_of, site_of};
    api_buf out;
    api_buf_init(&out);
    api__tracer t = {&out, &s, VOR_FLIP, {0}, 0};
    vor_counts c;
    memset(&c, 0, sizeof c);
    vor_step st;
    const uint32_t order[] = {2, 0, 1};
    vor__step_init(&st, VOR_STEP_ORDER);
    st.order = order;
    st.n_order = 3;
    c.order_keys = 3;
    c.order_rounds = 1;
    c.site_events = 5; /* not flip's: never written */
    st.counts = &c;
    api__trace_step(&t, &st);
    vor__step_init(&st, VOR_STEP_BEGIN);
    st.tri[0] = 0, st.tri[1] = 1, st.tri[2] = 2;
    c.triangles_created = 4;
    st.counts = &c;
    api__trace_step(&t, &st);
    const uint32_t cav[] = {1, 0, VOR_INFINITE, 0, 2, VOR_INFINITE};
    const uint32_t star[] = {1, 0, 2, 0, 2, 1, 2, 1, VOR_INFINITE, 1, 0, VOR_INFINITE};
    vor__step_init(&st, VOR_STEP_INSERT);
    st.site = 2;
    st.tri[0] = 1, st.tri[1] = 0, st.tri[2] = VOR_INFINITE;
    st.split = VOR_SPLIT_HULL;
    st.cavity = cav;
    st.n_cavity = 2;
    st.star = star;
    st.n_star = 4;
    c.walk_steps = 2;
    st.counts = &c;
    api__trace_step(&t, &st);
    vor__step_init(&st, VOR_STEP_FLIP);
    st.edge[0] = st.tri[0] = 0;
    st.edge[1] = st.tri[1] = 1;
    st.added[0] = st.tri[2] = 2;
    st.added[1] = 1;
    c.flips = 1;
    st.counts = &c;
    api__trace_step(&t, &st);
    vor__step_init(&st, VOR_STEP_END);
    st.counts = &c; /* nothing changed */
    api__trace_step(&t, &st);
    assert_false(out.oom);

    api_buf doc;
    api_buf_init(&doc);
    api_buf_printf(&doc, "[%s]", out.data);
    json_error_t err;
    json_t *j = json_loadb(doc.data, doc.len, JSON_REJECT_DUPLICATES, &err);
    if (j == NULL) fail_msg("steps are not JSON: %s: %s", err.text, doc.data);
    assert_int_equal(json_array_size(j), 5);
    json_t *o = json_array_get(j, 0);
    assert_string_equal(json_string_value(json_object_get(o, "kind")), "order");
    json_t *sites = json_object_get(o, "sites");
    assert_int_equal(json_integer_value(json_array_get(sites, 0)), 3); /* input index */
    assert_int_equal(json_integer_value(json_array_get(sites, 1)), 0);
    assert_int_equal(json_integer_value(json_array_get(sites, 2)), 2);
    json_t *cn = json_object_get(o, "counts");
    size_t flip_counts = 0;
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++)
        flip_counts += (vor_count_algorithms(i) & VOR_IN_FLIP) != 0;
    assert_int_equal(json_object_size(cn), flip_counts); /* all at the first */
    assert_int_equal(json_integer_value(json_object_get(cn, "order_keys")), 3);
    assert_int_equal(json_integer_value(json_object_get(cn, "flips")), 0);
    assert_null(json_object_get(cn, "site_events"));
    o = json_array_get(j, 1);
    assert_string_equal(json_string_value(json_object_get(o, "kind")), "begin");
    assert_int_equal(json_array_size(json_object_get(o, "triangle")), 3);
    assert_int_equal(json_integer_value(json_object_get(json_object_get(o, "counts"),
                                                        "triangles_created")), 4);
    o = json_array_get(j, 2);
    assert_string_equal(json_string_value(json_object_get(o, "kind")), "insert");
    assert_int_equal(json_integer_value(json_object_get(o, "site")), 3);
    assert_string_equal(json_string_value(json_object_get(o, "split")), "hull");
    assert_int_equal(json_integer_value(json_array_get(json_object_get(o, "located"), 2)), -1);
    assert_int_equal(json_array_size(json_object_get(o, "cavity")), 2);
    json_t *s3 = json_object_get(o, "star");
    assert_int_equal(json_array_size(s3), 4);
    assert_int_equal(json_integer_value(json_array_get(json_array_get(s3, 3), 2)), -1);
    assert_int_equal(json_integer_value(json_array_get(json_array_get(s3, 3), 0)), 2);
    assert_int_equal(json_object_size(json_object_get(o, "counts")), 1); /* walk_steps */
    o = json_array_get(j, 3);
    assert_string_equal(json_string_value(json_object_get(o, "kind")), "flip");
    assert_int_equal(json_integer_value(json_array_get(json_object_get(o, "added"), 0)), 3);
    assert_int_equal(json_integer_value(json_array_get(json_object_get(o, "removed"), 1)), 2);
    assert_int_equal(json_array_size(json_object_get(o, "circle")), 3);
    o = json_array_get(j, 4);
    assert_string_equal(json_string_value(json_object_get(o, "kind")), "end");
    assert_int_equal(json_object_size(json_object_get(o, "counts")), 0);
    json_decref(j);

    /* Fortune's kinds */
    api_buf_clear(&out);
    api_buf_clear(&doc);
    api__tracer f = {&out, &s, VOR_FORTUNE, {0}, 0};
    const uint32_t beach[] = {0, 1};
    vor__step_init(&st, VOR_STEP_BEGIN);
    st.y = 0;
    st.beach = beach;
    st.n_beach = 2;
    memset(&c, 0, sizeof c);
    st.counts = &c;
    api__trace_step(&f, &st);
    vor__step_init(&st, VOR_STEP_SITE);
    st.site = 2;
    st.y = 4;
    st.at = 1;
    st.breakpoint[0] = st.tri[0] = 0;
    st.breakpoint[1] = st.tri[1] = 1;
    st.tri[2] = 2;
    st.vertex[0] = 2;
    st.vertex[1] = 2;
    st.counts = &c;
    api__trace_step(&f, &st);
    vor__step_init(&st, VOR_STEP_SITE);
    st.site = 2;
    st.y = 0.5;
    st.at = 1;
    st.arc = 0;
    st.counts = &c;
    api__trace_step(&f, &st);
    vor__step_init(&st, VOR_STEP_SCHEDULE);
    st.tri[0] = 0, st.tri[1] = 2, st.tri[2] = 1;
    st.y = INFINITY; /* an overflowing top is written as null */
    st.vertex[0] = 2;
    st.vertex[1] = -1.5;
    st.counts = &c;
    api__trace_step(&f, &st);
    st.kind = VOR_STEP_CANCEL;
    api__trace_step(&f, &st);
    vor__step_init(&st, VOR_STEP_CIRCLE);
    st.tri[0] = 0, st.tri[1] = 2, st.tri[2] = 1;
    st.y = 1;
    st.at = 1;
    st.counts = &c;
    api__trace_step(&f, &st);
    api_buf_printf(&doc, "[%s]", out.data);
    j = json_loadb(doc.data, doc.len, JSON_REJECT_DUPLICATES, &err);
    if (j == NULL) fail_msg("steps are not JSON: %s: %s", err.text, doc.data);
    assert_int_equal(json_array_size(j), 6);
    o = json_array_get(j, 0);
    assert_int_equal(json_integer_value(json_array_get(json_object_get(o, "beach"), 1)), 2);
    o = json_array_get(j, 1);
    assert_int_equal(json_integer_value(json_array_get(json_object_get(o, "breakpoint"), 1)), 2);
    assert_int_equal(json_integer_value(json_array_get(json_object_get(o, "triangle"), 2)), 3);
    assert_true(json_number_value(json_array_get(json_object_get(o, "vertex"), 0)) == 2);
    assert_null(json_object_get(o, "arc"));
    o = json_array_get(j, 2);
    assert_int_equal(json_integer_value(json_object_get(o, "arc")), 0);
    assert_int_equal(json_integer_value(json_object_get(o, "at")), 1);
    assert_null(json_object_get(o, "breakpoint"));
    o = json_array_get(j, 3);
    assert_string_equal(json_string_value(json_object_get(o, "kind")), "schedule");
    assert_true(json_is_null(json_object_get(o, "y")));
    assert_int_equal(json_integer_value(json_array_get(json_object_get(o, "arcs"), 1)), 3);
    assert_string_equal(json_string_value(json_object_get(json_array_get(j, 4), "kind")),
                        "cancel");
    o = json_array_get(j, 5);
    assert_string_equal(json_string_value(json_object_get(o, "kind")), "circle");
    assert_int_equal(json_integer_value(json_object_get(o, "at")), 1);
    json_decref(j);
    api_buf_clear(&out);
    api_buf_clear(&doc);
}

static void test_out_of_memory(void **state) {
    (void)state;
    api_result res = tri_result();
    for (int f = API_FMT_JSON; f <= API_FMT_TIMINGS; f++) {
        api_request r = request((api_format)f, API_PART_ALL, 1);
        api_buf out;
        api_problem p;
        api_buf_init(&out);
        out.oom = 1; /* as if an earlier growth had failed */
        api_timings t = res.t;
        assert_int_equal(api_write_result(&r, &res, &t, &out, &p), API_UNAVAILABLE);
        assert_int_equal(api_code_http(p.code), 503);
        assert_null(out.data);
        assert_int_equal(out.len, 0);
    }
    /* Writing without a result is our own error, not a crash. */
    api_result empty;
    api_result_init(&empty);
    api_request r = request(API_FMT_JSON, API_PART_ALL, 1);
    api_buf out;
    api_problem p;
    api_buf_init(&out);
    assert_int_equal(api_write_result(&r, &empty, &empty.t, &out, &p), API_INTERNAL);
}

static void test_compare_document(void **state) {
    (void)state;
    api_compare c;
    api_compare_init(&c);
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        c.res[a] = tri_result();
        c.res[a].algorithm = (vor_algorithm)a;
    }
    c.status[VOR_FORTUNE] = VOR_EUNAVAILABLE;
    /* Three runs each of the other two, given by hand: compute, clip, total. */
    c.repeat = 3;
    c.has_clip = 1;
    static const double runs[3][3] = {{2.5, 0.25, 3}, {1.25, 0.5, 2}, {4, 0.125, 4.5}};
    for (int a = VOR_BOWYER_WATSON; a < VOR_ALGORITHM_COUNT; a++) {
        c.n_runs[a] = 3;
        memcpy(c.runs[a], runs, sizeof runs);
        c.res[a].t.compute_ms = 2.5;
        c.res[a].t.clip_ms = 0.25;
        c.res[a].t.total_ms = 3;
    }
    c.agree = 0;
    strcpy(c.disagreement, "fortune: algorithm not available");
    c.t.parse_ms = 3;
    api_request r = request(API_FMT_JSON, API_PART_DEFAULT, 0);
    api_buf out;
    api_problem p;
    api_buf_init(&out);
    assert_int_equal(api_write_compare(&r, &c, &out, &p), API_OK);
    json_error_t err;
    json_t *j = json_loadb(out.data, out.len, JSON_REJECT_DUPLICATES, &err);
    if (j == NULL) fail_msg("compare is not JSON: %s: %s", err.text, out.data);
    assert_int_equal(json_integer_value(json_object_get(j, "n_input")), 4);
    assert_int_equal(json_integer_value(json_object_get(j, "n_sites")), 3);
    assert_true(json_is_false(json_object_get(j, "agree")));
    assert_string_equal(json_string_value(json_object_get(j, "disagreement")),
                        "fortune: algorithm not available");
    json_t *algos = json_object_get(j, "algorithms");
    assert_int_equal(json_array_size(algos), 3);
    json_t *f = json_array_get(algos, 0);
    assert_string_equal(json_string_value(json_object_get(f, "algorithm")), "fortune");
    assert_string_equal(json_string_value(json_object_get(f, "status")), "not-implemented");
    assert_null(json_object_get(f, "n_edges"));
    assert_null(json_object_get(f, "spread"));
    assert_null(json_object_get(f, "runs_ms"));
    assert_int_equal(json_integer_value(json_object_get(j, "repeat")), 3);
    json_t *b = json_array_get(algos, 1);
    assert_string_equal(json_string_value(json_object_get(b, "algorithm")), "bowyer-watson");
    assert_string_equal(json_string_value(json_object_get(b, "status")), "ok");
    assert_int_equal(json_integer_value(json_object_get(b, "n_edges")), 3);
    assert_int_equal(json_integer_value(json_object_get(b, "n_vertices")), 1);
    rc_check_timings(json_object_get(b, "timings"));
    json_t *runs_ms = json_object_get(b, "runs_ms");
    assert_int_equal(json_array_size(runs_ms), 3);
    assert_true(json_number_value(json_array_get(runs_ms, 0)) == 2.5);
    assert_true(json_number_value(json_array_get(runs_ms, 1)) == 1.25);
    assert_true(json_number_value(json_array_get(runs_ms, 2)) == 4);
    json_t *spread = json_object_get(b, "spread");
    static const struct {
        const char *phase;
        double median, min, max;
    } want[] = {{"compute_ms", 2.5, 1.25, 4}, {"clip_ms", 0.25, 0.125, 0.5},
                {"total_ms", 3, 2, 4.5}};
    assert_int_equal(json_object_size(spread), 3);
    for (int k = 0; k < 3; k++) {
        json_t *e = json_object_get(spread, want[k].phase);
        assert_int_equal(json_object_size(e), 3);
        assert_true(json_number_value(json_object_get(e, "median")) == want[k].median);
        assert_true(json_number_value(json_object_get(e, "min")) == want[k].min);
        assert_true(json_number_value(json_object_get(e, "max")) == want[k].max);
    }
    for (int a = 1; a < VOR_ALGORITHM_COUNT; a++)
        rc_check_counts(json_object_get(json_array_get(algos, (size_t)a), "counts"),
                        &c.res[a].counts, (vor_algorithm)a);
    assert_null(json_object_get(f, "counts")); /* failed: nothing counted */
    rc_check_timings(json_object_get(j, "timings"));
    assert_true(json_number_value(json_object_get(json_object_get(j, "timings"),
                                                  "parse_ms")) == 3);
    json_decref(j);
    api_buf_clear(&out);
}

/* The timings are milliseconds rounded to the microsecond and written
 * without the general converter where that is exact: every value must
 * read exactly as api_num_format writes round(v * 1000) / 1000. Edge
 * values, then random ones over many magnitudes (seed printed). */
static void test_timings_digits(void **state) {
    (void)state;
    static const double edge[] = {
        0, -0.0, 0.0004, 0.0005, 0.0015, 0.001, 0.01, 0.1, 0.1005, 1, 10, 100,
        0.999, 0.9995, 999.9995, 12.3456, 1e-300, -0.0004, -1.5, 4294967.295,
        4294967.2955, 4294967.296, 4294967.2965, 1e12, 1e15, 1e300, INFINITY,
        -INFINITY, NAN};
    const uint64_t seed = 0x71417;
    uint64_t x = seed;
    print_message("timings digits: seed %llu\n", (unsigned long long)seed);
    for (size_t i = 0; i < 20000; i++) {
        double v[5];
        for (int k = 0; k < 5; k++) {
            size_t j = i * 5 + (size_t)k;
            if (j < sizeof edge / sizeof edge[0]) {
                v[k] = edge[j];
                continue;
            }
            x = x * 6364136223846793005ull + 1442695040888963407ull;
            double u = (double)(x >> 11) / 9007199254740992.0;
            v[k] = u * pow(10, (double)((x >> 3) % 16) - 6);
        }
        api_request r;
        api_request_init(&r);
        r.format = API_FMT_TIMINGS;
        api_result res = tri_result();
        api_timings t = {v[0], v[1], v[2], v[3], v[4], 0, 0};
        api_buf b;
        api_problem p;
        api_buf_init(&b);
        assert_int_equal(api_write_result(&r, &res, &t, &b, &p), API_OK);
        const char *at = strstr(b.data, "\"queue_ms\"");
        assert_non_null(at);
        for (int k = 0; k < 5; k++) {
            char want[API_NUM_MAXLEN + 1];
            size_t n = api_num_format(round(v[k] * 1000) / 1000, want);
            if (n == 0) n = (size_t)snprintf(want, sizeof want, "null");
            want[n] = 0;
            at = strchr(at, ':');
            assert_non_null(at);
            at++;
            if (strncmp(at, want, n) != 0 || (at[n] != ',' && at[n] != '}'))
                fail_msg("value %.17g: wrote %.30s, want %s", v[k], at, want);
        }
        api_buf_clear(&b);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_json_all_parts),
        cmocka_unit_test(test_json_default_and_chosen_parts),
        cmocka_unit_test(test_json_line_and_overflow),
        cmocka_unit_test(test_geojson),
        cmocka_unit_test(test_svg),
        cmocka_unit_test(test_binary),
        cmocka_unit_test(test_timings_only),
        cmocka_unit_test(test_timings_with_counts),
        cmocka_unit_test(test_json_trace_member),
        cmocka_unit_test(test_trace_steps),
        cmocka_unit_test(test_timings_digits),
        cmocka_unit_test(test_out_of_memory),
        cmocka_unit_test(test_compare_document),
        cmocka_unit_test(test_trailing_newline),
    };
    return cmocka_run_group_tests_name("api/write", tests, NULL, NULL);
}
