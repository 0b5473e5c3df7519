/* test_endpoints.c -- every endpoint of a real voronoid, every input format
 * (JSON, CSV, text, binary, curl's form default, generate) and output
 * format (JSON, GeoJSON, SVG, binary, timings), gzip, CORS, request ids,
 * Server-Timing, the page and its files, health, readiness, metrics and
 * the access log. Bodies are checked for real content: the diagram of a
 * square's four corners and its centre is known (4 vertices at the side
 * midpoints, 8 edges: 4 segments round the centre and 4 rays). Responses
 * are saved for the OpenAPI check. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "harness.h"

static it_daemon d;

static const char square_json[] =
    "{\"points\": [[0,0],[1,0],[0,1],[1,1],[0.5,0.5]]}";

static int setup(void **state) {
    (void)state;
    return it_group_start(&d, NULL);
}

static int teardown(void **state) {
    (void)state;
    return it_group_stop(&d);
}

static void post(const char *path, const char *ctype, const void *body,
                 size_t len, it_resp *r, const char *save_as) {
    it_req q = {.path = path, .body = body, .len = len};
    char h[128];
    if (ctype) {
        snprintf(h, sizeof h, "Content-Type: %s", ctype);
        q.headers[0] = h;
    }
    it_http(&d, &q, r);
    if (save_as) it_save(save_as, &q, r);
    if (r->curl_rc != 0) fail_msg("curl: %s", r->err);
}

/* Checks the canonical diagram of the square and its centre. */
static void check_square_diagram(json_t *j, const char *algorithm) {
    assert_non_null(j);
    assert_string_equal(json_string_value(json_object_get(j, "algorithm")),
                        algorithm);
    assert_int_equal(json_integer_value(json_object_get(j, "n_input")), 5);
    assert_int_equal(json_integer_value(json_object_get(j, "n_sites")), 5);
    assert_int_equal(json_integer_value(json_object_get(j, "n_vertices")), 4);
    assert_int_equal(json_integer_value(json_object_get(j, "n_edges")), 8);
    json_t *v = json_object_get(j, "vertices");
    assert_int_equal(json_array_size(v), 4);
    /* The vertices are the midpoints of the sides, in some order. */
    int seen[4] = {0, 0, 0, 0};
    static const double mid[4][2] = {{0.5, 0}, {1, 0.5}, {0.5, 1}, {0, 0.5}};
    for (size_t i = 0; i < 4; i++) {
        double x = json_number_value(json_array_get(json_array_get(v, i), 0));
        double y = json_number_value(json_array_get(json_array_get(v, i), 1));
        for (int k = 0; k < 4; k++)
            if (x == mid[k][0] && y == mid[k][1]) seen[k]++;
    }
    for (int k = 0; k < 4; k++) assert_int_equal(seen[k], 1);
    json_t *edges = json_object_get(j, "edges");
    assert_int_equal(json_array_size(edges), 8);
    int rays = 0, segments = 0;
    for (size_t i = 0; i < 8; i++) {
        json_t *ends = json_object_get(json_array_get(edges, i), "ends");
        int nulls = json_is_null(json_array_get(ends, 0)) +
                    json_is_null(json_array_get(ends, 1));
        rays += nulls == 1;
        segments += nulls == 0;
    }
    assert_int_equal(rays, 4);
    assert_int_equal(segments, 4);
    json_t *cells = json_object_get(j, "cells");
    assert_int_equal(json_array_size(cells), 5);
    for (size_t i = 0; i < 5; i++) {
        json_t *c = json_array_get(cells, i);
        int site = (int)json_integer_value(json_object_get(c, "site"));
        int bounded = json_is_true(json_object_get(c, "bounded"));
        assert_int_equal(bounded, site == 4); /* only the centre is closed */
        assert_int_equal(json_array_size(json_object_get(c, "edges")),
                         site == 4 ? 4 : 3);
    }
    json_t *t = json_object_get(j, "timings");
    assert_non_null(json_object_get(t, "compute_ms"));
    assert_true(json_number_value(json_object_get(t, "total_ms")) >=
                json_number_value(json_object_get(t, "compute_ms")));
}

static void test_voronoi_json_every_algorithm(void **state) {
    (void)state;
    const char *algs[] = {"fortune", "bowyer-watson", "flip"};
    for (int a = 0; a < 3; a++) {
        char path[64], name[64];
        snprintf(path, sizeof path, "/voronoi?algorithm=%s", algs[a]);
        snprintf(name, sizeof name, "voronoi-json-%s", algs[a]);
        it_resp r;
        post(path, "application/json", square_json, strlen(square_json), &r,
             name);
        if (r.status != 200) fail_msg("%s: %ld %s", algs[a], r.status, r.body);
        char h[256];
        assert_string_equal(it_header(&r, "Content-Type", h, sizeof h),
                            "application/json");
        json_t *j = it_json(&r);
        check_square_diagram(j, algs[a]);
        json_decref(j);
        it_free(&r);
    }
    /* The algorithm can also come from the body. */
    const char *body = "{\"algorithm\": \"flip\", \"points\": "
                       "[[0,0],[1,0],[0,1],[1,1],[0.5,0.5]]}";
    it_resp r;
    post("/voronoi", "application/json", body, strlen(body), &r, NULL);
    assert_int_equal(r.status, 200);
    json_t *j = it_json(&r);
    check_square_diagram(j, "flip");
    json_decref(j);
    it_free(&r);
}

static void test_input_formats(void **state) {
    (void)state;
    static const struct {
        const char *name, *ctype, *body, *query;
    } cases[] = {
        {"csv", "text/csv", "x,y\n0,0\n1,0\n0,1\n1,1\n0.5,0.5\n",
         "?algorithm=flip"},
        {"text", "text/plain", "# a square\n0 0\n1 0\n\n0 1\n1 1\n0.5 0.5\n",
         "?algorithm=bowyer-watson"},
        {"form-sniffed-json", "application/x-www-form-urlencoded",
         "[[0,0],[1,0],[0,1],[1,1],[0.5,0.5]]", ""},
        {"form-sniffed-text", NULL, "0,0\n1,0\n0,1\n1,1\n0.5,0.5\n", ""},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char path[64], name[64];
        snprintf(path, sizeof path, "/voronoi%s", cases[i].query);
        snprintf(name, sizeof name, "voronoi-in-%s", cases[i].name);
        it_resp r;
        post(path, cases[i].ctype, cases[i].body, strlen(cases[i].body), &r,
             name);
        if (r.status != 200) fail_msg("%s: %ld %s", cases[i].name, r.status, r.body);
        json_t *j = it_json(&r);
        const char *alg = strstr(cases[i].query, "flip") ? "flip"
                          : strstr(cases[i].query, "bowyer") ? "bowyer-watson"
                                                             : "fortune";
        check_square_diagram(j, alg);
        json_decref(j);
        it_free(&r);
    }
    /* Binary: little-endian float64 pairs. */
    double xy[10] = {0, 0, 1, 0, 0, 1, 1, 1, 0.5, 0.5};
    unsigned char bin[80];
    for (int i = 0; i < 10; i++) {
        uint64_t u;
        memcpy(&u, &xy[i], 8);
        for (int b = 0; b < 8; b++) bin[8 * i + b] = (unsigned char)(u >> (8 * b));
    }
    it_resp r;
    post("/voronoi", "application/octet-stream", bin, sizeof bin, &r,
         "voronoi-in-binary");
    assert_int_equal(r.status, 200);
    json_t *j = it_json(&r);
    check_square_diagram(j, "fortune");
    json_decref(j);
    it_free(&r);
}

static void test_generate_and_parts(void **state) {
    (void)state;
    const char *body = "{\"generate\": {\"distribution\": \"uniform\", "
                       "\"n\": 1000, \"seed\": 7}, \"algorithm\": "
                       "\"bowyer-watson\"}";
    it_resp r;
    post("/voronoi", "application/json", body, strlen(body), &r,
         "voronoi-generate");
    assert_int_equal(r.status, 200);
    json_t *j = it_json(&r);
    assert_int_equal(json_integer_value(json_object_get(j, "n_input")), 1000);
    assert_int_equal(json_integer_value(json_object_get(j, "n_sites")), 1000);
    /* Euler for a Voronoi diagram of points in general position:
     * every one of the n cells is there. */
    assert_int_equal(json_array_size(json_object_get(j, "cells")), 1000);
    size_t nv = (size_t)json_integer_value(json_object_get(j, "n_vertices"));
    size_t ne = (size_t)json_integer_value(json_object_get(j, "n_edges"));
    assert_true(nv > 1000 && nv < 2000);
    assert_true(ne == json_array_size(json_object_get(j, "edges")));
    json_decref(j);
    it_free(&r);

    /* include and bounds from the query string. */
    post("/voronoi?include=vertices,edges,cells,triangles,sites,clipped"
         "&bounds=0,0,1,1",
         "application/json", square_json, strlen(square_json), &r,
         "voronoi-parts");
    assert_int_equal(r.status, 200);
    j = it_json(&r);
    assert_int_equal(json_array_size(json_object_get(j, "triangles")), 4);
    assert_int_equal(json_array_size(json_object_get(j, "sites")), 5);
    json_t *clipped = json_object_get(j, "clipped");
    assert_non_null(clipped);
    assert_true(json_is_true(json_object_get(clipped, "bounds_given")));
    assert_int_equal(json_array_size(json_object_get(clipped, "cells")), 5);
    /* The centre's cell clipped to the unit square is the diamond: four
     * corners (a closing repeat of the first one allowed). */
    json_t *centre = json_array_get(json_object_get(clipped, "cells"), 4);
    size_t corners = json_array_size(centre);
    if (corners == 5 && json_equal(json_array_get(centre, 0),
                                   json_array_get(centre, 4)))
        corners = 4;
    assert_int_equal(corners, 4);
    json_decref(j);
    it_free(&r);
}

static void test_output_formats(void **state) {
    (void)state;
    it_resp r;
    char h[256];
    /* GeoJSON by query. */
    post("/voronoi?format=geojson", "application/json", square_json,
         strlen(square_json), &r, "voronoi-out-geojson");
    assert_int_equal(r.status, 200);
    assert_string_equal(it_header(&r, "Content-Type", h, sizeof h),
                        "application/geo+json");
    json_t *j = it_json(&r);
    assert_string_equal(json_string_value(json_object_get(j, "type")),
                        "FeatureCollection");
    json_t *features = json_object_get(j, "features");
    assert_int_equal(json_array_size(features), 5);
    json_t *g = json_object_get(json_array_get(features, 4), "geometry");
    assert_string_equal(json_string_value(json_object_get(g, "type")),
                        "Polygon");
    /* The centre's diamond: a closed ring of 4 + 1 points. */
    assert_int_equal(
        json_array_size(json_array_get(json_object_get(g, "coordinates"), 0)),
        5);
    json_decref(j);
    it_free(&r);

    /* SVG by Accept. */
    it_req q = {.path = "/voronoi", .body = square_json,
                .len = strlen(square_json),
                .headers = {"Content-Type: application/json",
                            "Accept: image/svg+xml"}};
    it_http(&d, &q, &r);
    it_save("voronoi-out-svg", &q, &r);
    assert_int_equal(r.status, 200);
    assert_string_equal(it_header(&r, "Content-Type", h, sizeof h),
                        "image/svg+xml");
    assert_non_null(strstr(r.body, "<svg"));
    assert_non_null(strstr(r.body, "</svg>"));
    it_free(&r);

    /* Binary by Accept with q values. */
    it_req qb = {.path = "/voronoi", .body = square_json,
                 .len = strlen(square_json),
                 .headers = {"Accept: text/html;q=0.9, "
                             "application/octet-stream"}};
    it_http(&d, &qb, &r);
    it_save("voronoi-out-binary", &qb, &r);
    assert_int_equal(r.status, 200);
    assert_string_equal(it_header(&r, "Content-Type", h, sizeof h),
                        "application/octet-stream");
    assert_true(r.len >= 48);
    assert_memory_equal(r.body, "VORB", 4);
    uint32_t hdr[12];
    for (int i = 0; i < 12; i++)
        hdr[i] = (uint32_t)(unsigned char)r.body[4 * i] |
                 (uint32_t)(unsigned char)r.body[4 * i + 1] << 8 |
                 (uint32_t)(unsigned char)r.body[4 * i + 2] << 16 |
                 (uint32_t)(unsigned char)r.body[4 * i + 3] << 24;
    assert_int_equal(hdr[1], 1);  /* version */
    assert_int_equal(hdr[4], 5);  /* n_input */
    assert_int_equal(hdr[5], 5);  /* n_sites */
    assert_int_equal(hdr[6], 4);  /* n_vertices */
    assert_int_equal(hdr[7], 8);  /* n_edges */
    it_free(&r);

    /* Only the timings. */
    post("/voronoi?format=timings", NULL, square_json, strlen(square_json),
         &r, "voronoi-out-timings");
    assert_int_equal(r.status, 200);
    j = it_json(&r);
    assert_non_null(j);
    assert_non_null(strstr(r.body, "compute_ms"));
    json_decref(j);
    it_free(&r);
}

static void test_compare(void **state) {
    (void)state;
    it_resp r;
    post("/compare", "application/json", square_json, strlen(square_json), &r,
         "compare-square");
    assert_int_equal(r.status, 200);
    json_t *j = it_json(&r);
    assert_true(json_is_true(json_object_get(j, "agree")));
    assert_true(json_is_null(json_object_get(j, "disagreement")));
    json_t *algs = json_object_get(j, "algorithms");
    assert_int_equal(json_array_size(algs), 3);
    for (size_t i = 0; i < 3; i++) {
        json_t *a = json_array_get(algs, i);
        assert_string_equal(json_string_value(json_object_get(a, "status")), "ok");
        assert_int_equal(json_integer_value(json_object_get(a, "n_vertices")), 4);
        assert_int_equal(json_integer_value(json_object_get(a, "n_edges")), 8);
    }
    json_decref(j);
    char h[512];
    const char *st = it_header(&r, "Server-Timing", h, sizeof h);
    assert_non_null(st);
    assert_non_null(strstr(st, "fortune;dur="));
    assert_non_null(strstr(st, "bowyer-watson;dur="));
    assert_non_null(strstr(st, "flip;dur="));
    it_free(&r);

    const char *gen = "{\"generate\": {\"distribution\": \"clustered\", "
                      "\"n\": 2000, \"seed\": 3}}";
    post("/compare", "application/json", gen, strlen(gen), &r,
         "compare-generated");
    assert_int_equal(r.status, 200);
    j = it_json(&r);
    assert_true(json_is_true(json_object_get(j, "agree")));
    assert_int_equal(json_integer_value(json_object_get(j, "n_input")), 2000);
    json_decref(j);
    it_free(&r);
}

static void test_gzip_timing_cors_ids(void **state) {
    (void)state;
    const char *gen = "{\"generate\": {\"n\": 2000, \"seed\": 11}}";
    it_req q = {.path = "/voronoi", .body = gen, .len = strlen(gen),
                .gzip = 1,
                .headers = {"Content-Type: application/json",
                            "X-Request-Id: it-gzip-1",
                            "Origin: http://elsewhere.example"}};
    it_resp r;
    it_http(&d, &q, &r);
    it_save("voronoi-gzip", &q, &r);
    assert_int_equal(r.status, 200);
    char h[512];
    assert_string_equal(it_header(&r, "Content-Encoding", h, sizeof h), "gzip");
    assert_string_equal(it_header(&r, "X-Request-Id", h, sizeof h), "it-gzip-1");
    assert_string_equal(it_header(&r, "Access-Control-Allow-Origin", h, sizeof h),
                        "*");
    assert_non_null(strstr(it_header(&r, "Vary", h, sizeof h), "Accept-Encoding"));
    const char *st = it_header(&r, "Server-Timing", h, sizeof h);
    assert_non_null(st);
    const char *stages[] = {"queue;dur=", "parse;dur=", "compute;dur=",
                            "serialize;dur=", "total;dur=", NULL};
    for (int i = 0; stages[i]; i++) assert_non_null(strstr(st, stages[i]));
    json_t *j = it_json(&r); /* libcurl decoded the gzip body */
    assert_int_equal(json_integer_value(json_object_get(j, "n_input")), 2000);
    json_decref(j);
    it_free(&r);

    /* Without Accept-Encoding: plain, and a generated 16-hex-digit id. */
    it_req q2 = {.path = "/voronoi", .body = gen, .len = strlen(gen)};
    it_http(&d, &q2, &r);
    assert_int_equal(r.status, 200);
    assert_null(it_header(&r, "Content-Encoding", h, sizeof h));
    const char *id = it_header(&r, "X-Request-Id", h, sizeof h);
    assert_non_null(id);
    assert_int_equal(strlen(id), 16);
    assert_int_equal(strspn(id, "0123456789abcdef"), 16);
    it_free(&r);

    /* A hostile request id is replaced, not echoed. */
    it_req q3 = {.path = "/healthz", .headers = {"X-Request-Id: a b<c>"}};
    it_http(&d, &q3, &r);
    assert_int_equal(r.status, 200);
    assert_int_equal(strlen(it_header(&r, "X-Request-Id", h, sizeof h)), 16);
    it_free(&r);

    /* Preflight. */
    it_req p = {.method = "OPTIONS", .path = "/voronoi",
                .headers = {"Origin: http://elsewhere.example",
                            "Access-Control-Request-Method: POST",
                            "Access-Control-Request-Headers: content-type"}};
    it_http(&d, &p, &r);
    it_save("voronoi-preflight", &p, &r);
    assert_int_equal(r.status, 204);
    assert_non_null(strstr(it_header(&r, "Access-Control-Allow-Methods", h, sizeof h),
                           "POST"));
    assert_non_null(strstr(it_header(&r, "Access-Control-Allow-Headers", h,
                                     sizeof h),
                           "Content-Type"));
    assert_string_equal(it_header(&r, "Allow", h, sizeof h), "POST, OPTIONS");
    assert_int_equal(r.len, 0);
    it_free(&r);
    p.path = "/compare";
    it_http(&d, &p, &r);
    it_save("compare-preflight", &p, &r);
    assert_int_equal(r.status, 204);
    it_free(&r);
}

/* The security headers of everything a browser may render: a policy
 * that allows only the service's own scripts and styles and no framing,
 * no MIME sniffing, no referrer. */
static void check_page_headers(const it_resp *r, const char *what) {
    char h[512];
    const char *csp = it_header(r, "Content-Security-Policy", h, sizeof h);
    if (csp == NULL) fail_msg("%s: no Content-Security-Policy", what);
    static const char *const must[] = {
        "default-src 'none'", "script-src 'self'", "style-src 'self'",
        "connect-src 'self'", "frame-ancestors 'none'", "base-uri 'none'",
    };
    for (size_t i = 0; i < sizeof must / sizeof must[0]; i++)
        if (strstr(csp, must[i]) == NULL)
            fail_msg("%s: policy \"%s\" lacks %s", what, csp, must[i]);
    if (strstr(csp, "unsafe-inline") || strstr(csp, "unsafe-eval"))
        fail_msg("%s: policy allows inline code: %s", what, csp);
    const char *nosniff = it_header(r, "X-Content-Type-Options", h, sizeof h);
    if (nosniff == NULL || strcmp(nosniff, "nosniff") != 0)
        fail_msg("%s: X-Content-Type-Options %s", what, nosniff);
    const char *ref = it_header(r, "Referrer-Policy", h, sizeof h);
    if (ref == NULL || strcmp(ref, "no-referrer") != 0)
        fail_msg("%s: Referrer-Policy %s", what, ref);
}

static void test_page_and_files(void **state) {
    (void)state;
    it_resp r;
    char h[256], etag[64];
    it_req q = {.path = "/"};
    it_http(&d, &q, &r);
    it_save("page", &q, &r);
    assert_int_equal(r.status, 200);
    assert_string_equal(it_header(&r, "Content-Type", h, sizeof h),
                        "text/html; charset=utf-8");
    assert_non_null(strstr(r.body, "<html"));
    assert_non_null(strstr(r.body, "main.js"));
    check_page_headers(&r, "/");
    size_t page_len = r.len;
    snprintf(etag, sizeof etag, "%s", it_header(&r, "ETag", h, sizeof h));
    it_free(&r);

    /* HEAD: same headers, no body. */
    it_req qh = {.method = "HEAD", .path = "/"};
    it_http(&d, &qh, &r);
    assert_int_equal(r.status, 200);
    assert_int_equal(r.len, 0);
    assert_int_equal(atol(it_header(&r, "Content-Length", h, sizeof h)),
                     (long)page_len);
    it_free(&r);

    /* Conditional GET. */
    char inm[96];
    snprintf(inm, sizeof inm, "If-None-Match: %s", etag);
    it_req qc = {.path = "/", .headers = {inm}};
    it_http(&d, &qc, &r);
    it_save("page-not-modified", &qc, &r);
    assert_int_equal(r.status, 304);
    assert_int_equal(r.len, 0);
    it_free(&r);

    static const struct {
        const char *path, *ctype, *needle;
    } files[] = {
        {"/main.js", "text/javascript; charset=utf-8", "import"},
        {"/style.css", "text/css; charset=utf-8", "{"},
        {"/index.html", "text/html; charset=utf-8", "<html"},
        {"/openapi.yaml", "application/yaml", "openapi: 3.1"},
    };
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        it_req qf = {.path = files[i].path, .gzip = 1};
        it_http(&d, &qf, &r);
        char name[64];
        snprintf(name, sizeof name, "file-%zu", i);
        it_save(name, &qf, &r);
        if (r.status != 200) fail_msg("%s: %ld", files[i].path, r.status);
        assert_string_equal(it_header(&r, "Content-Type", h, sizeof h),
                            files[i].ctype);
        assert_non_null(strstr(r.body, files[i].needle));
        check_page_headers(&r, files[i].path);
        it_free(&r);
    }

    /* Problem pages, problem documents of other routes, and SVG answers
     * carry the policy too; JSON answers at least nosniff. */
    static const char *const more[] = {"/problems/invalid", "/nowhere",
                                       "/healthz", "/metrics"};
    for (size_t i = 0; i < sizeof more / sizeof more[0]; i++) {
        it_req qp = {.path = more[i]};
        it_http(&d, &qp, &r);
        check_page_headers(&r, more[i]);
        it_free(&r);
    }
    static const char pts[] = "[[0,0],[1,0],[0,1],[1,1]]";
    it_req qs = {.path = "/voronoi?format=svg", .body = pts,
                 .len = sizeof pts - 1};
    it_http(&d, &qs, &r);
    assert_int_equal(r.status, 200);
    check_page_headers(&r, "svg answer");
    it_free(&r);
    it_req qj = {.path = "/voronoi", .body = pts, .len = sizeof pts - 1};
    it_http(&d, &qj, &r);
    assert_int_equal(r.status, 200);
    assert_string_equal(it_header(&r, "X-Content-Type-Options", h, sizeof h),
                        "nosniff");
    it_free(&r);
}

static void test_health_ready_metrics_log(void **state) {
    (void)state;
    it_resp r;
    it_req q = {.path = "/healthz"};
    it_http(&d, &q, &r);
    it_save("healthz", &q, &r);
    assert_int_equal(r.status, 200);
    json_t *j = it_json(&r);
    assert_string_equal(json_string_value(json_object_get(j, "status")), "ok");
    json_decref(j);
    it_free(&r);

    q.path = "/readyz";
    it_http(&d, &q, &r);
    it_save("readyz", &q, &r);
    assert_int_equal(r.status, 200);
    j = it_json(&r);
    assert_string_equal(json_string_value(json_object_get(j, "status")), "ready");
    json_decref(j);
    it_free(&r);

    /* A request we can find in the metrics and the log. */
    it_req v = {.path = "/voronoi?algorithm=flip", .body = square_json,
                .len = strlen(square_json),
                .headers = {"X-Request-Id: it-log-check-42"}};
    it_http(&d, &v, &r);
    assert_int_equal(r.status, 200);
    it_free(&r);

    q.path = "/metrics";
    it_http(&d, &q, &r);
    it_save("metrics", &q, &r);
    assert_int_equal(r.status, 200);
    char h[128];
    assert_non_null(strstr(it_header(&r, "Content-Type", h, sizeof h),
                           "text/plain"));
    assert_true(it_metric(r.body, "voronoid_requests_total{route=\"/voronoi\","
                               "status=\"200\"}") >= 1);
    assert_true(it_metric(r.body, "voronoid_points_total{algorithm=\"flip\"}") >= 5);
    assert_true(it_metric(r.body, "voronoid_computations_total{algorithm=\"flip\"}")
                >= 1);
    assert_true(it_metric(r.body, "voronoid_request_duration_seconds_count{route="
                               "\"/voronoi\"}") >= 1);
    assert_int_equal(it_metric(r.body, "voronoid_queue_depth"), 0);
    assert_int_equal(it_metric(r.body, "voronoid_ready"), 1);
    assert_non_null(strstr(r.body, "voronoid_compute_seconds_total{algorithm="
                                   "\"fortune\"}"));
    /* The /metrics request itself is in flight while it is rendered. An
     * earlier request leaves the count only when libmicrohttpd reports it
     * completed, which may be just after its answer reached us: ask again
     * for a moment until only this request is counted. */
    double in_flight = it_metric(r.body, "voronoid_in_flight");
    for (int tries = 0; tries < 300 && in_flight != 1; tries++) {
        it_free(&r);
        it_sleep(0.01);
        it_http(&d, &q, &r);
        assert_int_equal(r.status, 200);
        in_flight = it_metric(r.body, "voronoid_in_flight");
    }
    assert_true(in_flight == 1);
    it_free(&r);

    /* The access log line (written once the answer is sent). */
    char *line = it_log_line(&d, "id=it-log-check-42");
    assert_non_null(line);
    assert_non_null(strstr(line, "method=POST path=/voronoi status=200 bytes="));
    assert_non_null(strstr(line, "algorithm=flip points=5 id=it-log-check-42"));
    assert_int_equal(strncmp(line, "time=20", 7), 0);
    free(line);
}

/* Answers are sent on the last handler call, so one connection carries
 * many requests: successes, computations and errors alike. */
static void test_keep_alive(void **state) {
    (void)state;
    int fd = it_connect(d.port);
    assert_true(fd >= 0);
    char body[64], req[512], buf[65536];
    snprintf(body, sizeof body, "%s", square_json);
    const char *steps[] = {"GET /healthz", "POST /voronoi", "GET /nope",
                           "GET /voronoi", "POST /compare", "GET /readyz"};
    const int want[] = {200, 200, 404, 405, 200, 200};
    for (int i = 0; i < 6; i++) {
        int post = strncmp(steps[i], "POST", 4) == 0;
        snprintf(req, sizeof req,
                 "%s HTTP/1.1\r\nHost: x\r\n%s%s\r\n%s", steps[i],
                 post ? "Content-Type: application/json\r\nContent-Length: " : "",
                 post ? "47\r\n" : "", post ? body : "");
        assert_int_equal(strlen(body), 47);
        assert_int_equal(it_send_all(fd, req, strlen(req)), 0);
        int closed;
        it_recv_response(fd, buf, sizeof buf, 60, &closed);
        if (it_raw_status(buf) != want[i])
            fail_msg("%s: %d: %.200s", steps[i], it_raw_status(buf), buf);
        assert_false(closed);
        assert_null(strstr(buf, "Connection: close"));
    }
    close(fd);
}

/* --web-dir serves the page from disk; openapi.yaml stays built in. */
static void test_web_dir(void **state) {
    (void)state;
    char dir[] = "/tmp/voronoid-web-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[128];
    snprintf(path, sizeof path, "%s/index.html", dir);
    FILE *f = fopen(path, "w");
    fputs("<!doctype html><html><body>from the disk</body></html>\n", f);
    fclose(f);
    it_daemon d2;
    const char *args[] = {"--web-dir", dir, NULL};
    assert_int_equal(it_start(&d2, args), 0);
    it_req q = {.path = "/"};
    it_resp r;
    it_http(&d2, &q, &r);
    assert_int_equal(r.status, 200);
    assert_non_null(strstr(r.body, "from the disk"));
    it_free(&r);
    q.path = "/main.js"; /* not in that directory */
    it_http(&d2, &q, &r);
    assert_int_equal(r.status, 404);
    it_free(&r);
    q.path = "/openapi.yaml";
    it_http(&d2, &q, &r);
    assert_int_equal(r.status, 200);
    it_free(&r);
    assert_int_equal(it_cleanup(&d2), 0);
    snprintf(path, sizeof path, "rm -rf '%s'", dir);
    assert_int_equal(system(path), 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_voronoi_json_every_algorithm),
        cmocka_unit_test(test_input_formats),
        cmocka_unit_test(test_generate_and_parts),
        cmocka_unit_test(test_output_formats),
        cmocka_unit_test(test_compare),
        cmocka_unit_test(test_gzip_timing_cors_ids),
        cmocka_unit_test(test_page_and_files),
        cmocka_unit_test(test_health_ready_metrics_log),
        cmocka_unit_test(test_keep_alive),
        cmocka_unit_test(test_web_dir),
    };
    return cmocka_run_group_tests_name("integration/endpoints", tests, setup,
                                       teardown);
}
