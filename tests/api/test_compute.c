/* test_compute.c -- api_compute and api_compare_run on real diagrams from
 * the core, and the writers' round trips on them.
 *
 * For every standard test set (tests/support/testsets.h) and every
 * algorithm: compute with all parts and a box, check the diagram with
 * vor_check, write it in every format and read it back with the
 * independent readers of result_check.h (bit-identical coordinates). Then
 * the comparison (the algorithms must agree whenever all of them run),
 * the refusals (non-finite points with their pointer), and the default
 * box. An algorithm the core does not provide yet (501) is reported and
 * skipped, never counted as a pass of its checks.
 *
 * Traces: the JSON steps of real runs are replayed from the document alone
 * (triangles from the insertions' cavities and stars and from the flips,
 * or from Fortune's vertex events; Fortune's beach line from its first row
 * and each step's position) and must give as many triangles as the
 * answer's Delaunay triangulation -- the very same ones where it is unique
 * -- and running counts that end at the answer's counts; and the trace's
 * limits and refusals. */
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
#include "../support/testsets.h"
#include "result_check.h"

static int available[VOR_ALGORITHM_COUNT];

static int setup(void **state) {
    (void)state;
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        double xy[] = {0, 0, 1, 0, 0, 1, 1, 1.5};
        vor_sites *s;
        vor_diagram *d = NULL;
        if (vor_sites_new(xy, 4, &s, NULL) != VOR_OK) {
            printf("# vor_sites_new fails: nothing here can run\n");
            return -1;
        }
        available[a] = vor_compute(s, (vor_algorithm)a, &d) == VOR_OK;
        vor_diagram_free(d);
        vor_sites_free(s);
        if (!available[a]) {
            printf("# %s: not available from the core; its checks are skipped\n",
                   vor_algorithm_name((vor_algorithm)a));
        }
    }
    return 0;
}

static api_request request_for(const double *xy, size_t n, vor_algorithm a,
                               unsigned parts, const double *box) {
    api_request r;
    api_request_init(&r);
    r.algorithm = a;
    r.parts = parts;
    r.parts_given = 1;
    if (n > 0) {
        r.xy = malloc(2 * n * sizeof(double));
        memcpy(r.xy, xy, 2 * n * sizeof(double));
    }
    r.n = n;
    if (box) {
        memcpy(r.bounds, box, sizeof r.bounds);
        r.has_bounds = 1;
    }
    return r;
}

/* Computes and writes every format for one set and one algorithm. */
static void round_trip(const char *name, const double *xy, size_t n, vor_algorithm a) {
    double box[4];
    api_request r = request_for(xy, n, a, API_PART_ALL, NULL);
    api_result res;
    api_problem p;
    api_result_init(&res);
    /* No bounds: "clipped" uses the default box. */
    api_code c = api_compute(&r, &res, &p);
    if (c != API_OK) fail_msg("%s/%s: %s", name, vor_algorithm_name(a), p.detail);
    api__default_box(res.sites, box);
    assert_true(box[0] == res.clipped->box[0] && box[3] == res.clipped->box[3]);
    char msg[256];
    if (vor_check(res.diagram, res.sites, msg, sizeof msg) != 0) {
        fail_msg("%s/%s: invalid diagram: %s", name, vor_algorithm_name(a), msg);
    }
    assert_true(res.t.prepare_ms >= 0 && res.t.compute_ms >= 0 && res.t.clip_ms >= 0);
    for (int f = API_FMT_JSON; f <= API_FMT_BINARY; f++) {
        r.format = (api_format)f;
        api_buf out;
        api_buf_init(&out);
        api_timings t = res.t;
        if (api_write_result(&r, &res, &t, &out, &p) != API_OK) {
            fail_msg("%s: write %d: %s", name, f, p.detail);
        }
        switch (f) {
        case API_FMT_JSON: rc_check_json(out.data, out.len, &res, API_PART_ALL, 0); break;
        case API_FMT_GEOJSON: rc_check_geojson(out.data, out.len, &res); break;
        case API_FMT_SVG:
            /* Sites far outside the picture are left out; these sets have
             * none (the box holds every site). */
            rc_check_svg(out.data, out.len, &res);
            break;
        default: rc_check_binary(out.data, out.len, &res, 1); break;
        }
        api_buf_clear(&out);
    }
    api_result_clear(&res);
    api_request_clear(&r);
}

static void test_sets_round_trip(void **state) {
    (void)state;
    size_t count = vt_count();
    for (size_t i = 0; i < count; i++) {
        vt_set set;
        if (vt_make(i, &set) != 0) fail_msg("cannot make set %zu", i);
        /* The writers are O(output); keep the biggest sets to a sample. */
        size_t n = set.n > 3000 ? 3000 : set.n;
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            if (available[a]) round_trip(set.name, set.xy, n, (vor_algorithm)a);
        }
        vt_set_free(&set);
    }
}

static void test_compare_agrees(void **state) {
    (void)state;
    size_t count = vt_count();
    for (size_t i = 0; i < count; i++) {
        vt_set set;
        if (vt_make(i, &set) != 0) fail_msg("cannot make set %zu", i);
        size_t n = set.n > 3000 ? 3000 : set.n;
        api_request r = request_for(set.xy, n, VOR_FORTUNE, API_PART_DEFAULT, NULL);
        r.repeat = 2; /* every run is checked against the first */
        api_compare c;
        api_problem p;
        api_compare_init(&c);
        c.t.parse_ms = 1;
        if (api_compare_run(&r, &c, &p) != API_OK) fail_msg("%s: %s", set.name, p.detail);
        int all = 1;
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            assert_int_equal(c.status[a] == VOR_OK, available[a]);
            all &= available[a];
        }
        if (all != c.agree) {
            fail_msg("%s: agree = %d with all algorithms available = %d: %s", set.name,
                     c.agree, all, c.disagreement);
        }
        if (!c.agree) assert_true(c.disagreement[0] != 0);
        api_buf out;
        api_buf_init(&out);
        assert_int_equal(api_write_compare(&r, &c, &out, &p), API_OK);
        json_error_t err;
        json_t *j = json_loadb(out.data, out.len, 0, &err);
        if (j == NULL) fail_msg("compare document: %s", err.text);
        assert_int_equal(json_is_true(json_object_get(j, "agree")), c.agree);
        assert_int_equal(json_integer_value(json_object_get(j, "n_input")), (json_int_t)n);
        json_decref(j);
        api_buf_clear(&out);
        api_compare_clear(&c);
        api_request_clear(&r);
        vt_set_free(&set);
    }
}

/* Milliseconds as the writers round them (to the microsecond). */
static double ms_rounded(double v) { return round(v * 1000) / 1000; }

/* The median of n values, computed independently of compute.c: sort a copy
 * with qsort, take the middle (the mean of the middle two for even n). */
static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}
static double median_of(const double *v, int n) {
    double w[API_REPEAT_MAX];
    memcpy(w, v, (size_t)n * sizeof *w);
    qsort(w, (size_t)n, sizeof *w, cmp_double);
    return n % 2 ? w[n / 2] : (w[n / 2 - 1] + w[n / 2]) / 2;
}

/* Checks one spread entry {"median", "min", "max"} against the runs. */
static void check_spread(json_t *spread, const char *phase, const double *v,
                         int n, double timing) {
    json_t *e = json_object_get(spread, phase);
    if (!json_is_object(e)) fail_msg("no spread of %s", phase);
    double med = json_number_value(json_object_get(e, "median"));
    double lo = json_number_value(json_object_get(e, "min"));
    double hi = json_number_value(json_object_get(e, "max"));
    double want_lo = v[0], want_hi = v[0];
    for (int i = 1; i < n; i++) {
        if (v[i] < want_lo) want_lo = v[i];
        if (v[i] > want_hi) want_hi = v[i];
    }
    if (!(lo <= med && med <= hi)) fail_msg("%s: median %g not in [%g, %g]", phase, med, lo, hi);
    assert_true(lo == ms_rounded(want_lo));
    assert_true(hi == ms_rounded(want_hi));
    assert_true(med == ms_rounded(median_of(v, n)));
    assert_true(med == ms_rounded(timing));
}

/* repeat: every available algorithm runs k times on the same sites; the
 * timings are the medians of the runs, the document gives each run's
 * compute ms in order and the spread of every phase, and the diagrams
 * still agree. With bounds the runs clip too. */
static void test_compare_repeat(void **state) {
    (void)state;
    vt_set set;
    if (vt_make(0, &set) != 0) fail_msg("cannot make set 0");
    size_t n = set.n > 2000 ? 2000 : set.n;
    static const int ks[] = {1, 2, 4, 7};
    for (size_t t = 0; t < 2 * sizeof ks / sizeof ks[0]; t++) {
        int k = ks[t % 4], with_box = t >= 4;
        double box[4] = {-10, -10, 10, 10};
        api_request r = request_for(set.xy, n, VOR_FORTUNE, API_PART_DEFAULT,
                                    with_box ? box : NULL);
        r.repeat = k;
        api_compare c;
        api_problem p;
        api_compare_init(&c);
        if (api_compare_run(&r, &c, &p) != API_OK) fail_msg("%s: %s", set.name, p.detail);
        assert_int_equal(c.repeat, k);
        assert_int_equal(c.has_clip, with_box);
        assert_non_null(c.sites);
        int all = 1;
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            all &= available[a];
            if (!available[a]) continue;
            assert_int_equal(c.n_runs[a], k);
            assert_null(c.res[a].sites); /* shared: c.sites */
            /* The timings are the medians over the runs. */
            double v[API_REPEAT_MAX];
            for (int i = 0; i < k; i++) v[i] = c.runs[a][i][API_RUN_COMPUTE];
            assert_true(c.res[a].t.compute_ms == median_of(v, k));
            for (int i = 0; i < k; i++) {
                const double *run = c.runs[a][i];
                assert_true(run[API_RUN_COMPUTE] >= 0 && run[API_RUN_CLIP] >= 0);
                assert_true(run[API_RUN_TOTAL] == c.t.prepare_ms +
                                                      run[API_RUN_COMPUTE] +
                                                      run[API_RUN_CLIP]);
                if (!with_box) assert_true(run[API_RUN_CLIP] == 0);
            }
            assert_true(c.res[a].t.prepare_ms == c.t.prepare_ms);
        }
        if (all != c.agree) fail_msg("repeat %d: agree %d: %s", k, c.agree, c.disagreement);

        api_buf out;
        api_buf_init(&out);
        assert_int_equal(api_write_compare(&r, &c, &out, &p), API_OK);
        json_error_t err;
        json_t *j = json_loadb(out.data, out.len, JSON_REJECT_DUPLICATES, &err);
        if (j == NULL) fail_msg("compare document: %s", err.text);
        assert_int_equal(json_integer_value(json_object_get(j, "repeat")), k);
        json_t *algos = json_object_get(j, "algorithms");
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            if (!available[a]) continue;
            json_t *e = json_array_get(algos, (size_t)a);
            json_t *runs = json_object_get(e, "runs_ms");
            assert_int_equal(json_array_size(runs), (size_t)k);
            double v[API_RUN_PHASES][API_REPEAT_MAX];
            for (int i = 0; i < k; i++) {
                for (int ph = 0; ph < API_RUN_PHASES; ph++) v[ph][i] = c.runs[a][i][ph];
                assert_true(json_number_value(json_array_get(runs, (size_t)i)) ==
                            ms_rounded(c.runs[a][i][API_RUN_COMPUTE]));
            }
            json_t *spread = json_object_get(e, "spread");
            json_t *tj = json_object_get(e, "timings");
            rc_check_timings(tj);
            check_spread(spread, "compute_ms", v[API_RUN_COMPUTE], k,
                         json_number_value(json_object_get(tj, "compute_ms")));
            check_spread(spread, "total_ms", v[API_RUN_TOTAL], k,
                         json_number_value(json_object_get(tj, "total_ms")));
            if (with_box) {
                check_spread(spread, "clip_ms", v[API_RUN_CLIP], k,
                             json_number_value(json_object_get(tj, "clip_ms")));
            } else {
                assert_null(json_object_get(spread, "clip_ms"));
            }
            assert_int_equal(json_object_size(spread), with_box ? 3 : 2);
        }
        json_decref(j);
        api_buf_clear(&out);
        api_compare_clear(&c);
        api_request_clear(&r);
    }
    vt_set_free(&set);
}

/* Without a repeat the count follows the number of distinct sites;
 * repeat times points is bounded; repeat belongs to comparisons only. */
static void test_compare_repeat_default_and_limits(void **state) {
    (void)state;
    double xy[] = {0, 0, 1, 0, 0, 1, 1, 1, 0, 0};
    api_request r = request_for(xy, 5, VOR_FORTUNE, API_PART_DEFAULT, NULL);
    api_compare c;
    api_problem p;
    api_compare_init(&c);
    assert_int_equal(api_compare_run(&r, &c, &p), API_OK);
    assert_int_equal(c.repeat, 5);
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        assert_int_equal(c.n_runs[a], available[a] ? 5 : 0);
    }
    api_compare_clear(&c);
    api_request_clear(&r);

    /* 50 x 200,001 points is over 10^7: refused before any work (the
     * points are zeros, never looked at). */
    size_t big = 200001;
    api_request rb;
    api_request_init(&rb);
    rb.xy = calloc(2 * big, sizeof(double));
    assert_non_null(rb.xy);
    rb.n = big;
    rb.repeat = 50;
    api_compare_init(&c);
    assert_int_equal(api_compare_run(&rb, &c, &p), API_INVALID);
    if (strstr(p.detail, "repeat 50 with 200001 points: repeat times points must "
                         "be at most 10000000, so at most 49 repeats here") == NULL) {
        fail_msg("detail: %s", p.detail);
    }
    assert_null(c.sites);
    assert_int_equal(c.n_runs[0], 0);
    api_compare_clear(&c);
    api_request_clear(&rb);

    /* repeat on a single computation is refused, naming where it applies. */
    r = request_for(xy, 5, VOR_FLIP, API_PART_DEFAULT, NULL);
    r.repeat = 3;
    api_result res;
    api_result_init(&res);
    assert_int_equal(api_compute(&r, &res, &p), API_INVALID);
    if (strstr(p.detail, "repeat 3: repeat applies only to a comparison of the "
                         "algorithms (POST /compare") == NULL) {
        fail_msg("detail: %s", p.detail);
    }
    assert_null(res.diagram);
    api_request_clear(&r);
}

/* The caller's stop (api_request.stop): asked by the algorithm, a yes
 * fails the computation, or the whole comparison, with 503 and a detail
 * that says so; nothing is kept. */
static int stop_asked;
static int stop_now(void *ctx) {
    (void)ctx;
    stop_asked++;
    return 1;
}

/* The stop was asked once and the answer is a 503 that names it. */
static void check_stopped(const api_problem *p) {
    assert_int_equal(stop_asked, 1);
    assert_int_equal(api_code_http(p->code), 503);
    if (strstr(p->detail, "stopped by the caller") == NULL)
        fail_msg("detail: %s", p->detail);
}

/* A request of the 5000 points at xy for algorithm a that says stop. */
static api_request stopping_request(const double *xy, vor_algorithm a) {
    api_request r = request_for(xy, 5000, a, API_PART_DEFAULT, NULL);
    r.stop = stop_now;
    stop_asked = 0;
    return r;
}

static void test_stopped(void **state) {
    (void)state;
    double *xy = vt_uniform(5000, 3);
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        if (!available[a]) continue;
        api_request r = stopping_request(xy, (vor_algorithm)a);
        api_result res;
        api_problem p;
        api_result_init(&res);
        assert_int_equal(api_compute(&r, &res, &p), API_UNAVAILABLE);
        check_stopped(&p);
        assert_null(res.diagram);
        api_result_clear(&res);
        api_request_clear(&r);
    }
    api_request r = stopping_request(xy, VOR_FORTUNE);
    api_compare c;
    api_problem p;
    api_compare_init(&c);
    assert_int_equal(api_compare_run(&r, &c, &p), API_UNAVAILABLE);
    check_stopped(&p); /* the first run stops; no other runs */
    assert_null(c.sites);
    api_compare_clear(&c);
    api_request_clear(&r);
    free(xy);
}

/* A first difference is explained, in the terms of the canonical form. */
static void test_difference_explained(void **state) {
    (void)state;
    int a = -1;
    for (int k = 0; k < VOR_ALGORITHM_COUNT; k++) if (available[k]) a = k;
    if (a < 0) skip();
    /* Moving the fourth site changes a vertex; a fifth site adds some. */
    double xy1[] = {0, 0, 1, 0, 0, 1, 1, 1.5, 5, 5};
    double xy2[] = {0, 0, 1, 0, 0, 1, 1, 2, 5, 5};
    api_request r1 = request_for(xy1, 5, (vor_algorithm)a, 0, NULL);
    api_request r2 = request_for(xy2, 5, (vor_algorithm)a, 0, NULL);
    api_request r3 = request_for(xy1, 4, (vor_algorithm)a, 0, NULL);
    api_result x, y, z;
    api_problem p;
    api_result_init(&x);
    api_result_init(&y);
    api_result_init(&z);
    assert_int_equal(api_compute(&r1, &x, &p), API_OK);
    assert_int_equal(api_compute(&r2, &y, &p), API_OK);
    assert_int_equal(api_compute(&r3, &z, &p), API_OK);
    char msg[256] = "";
    assert_int_equal(api__diagram_difference(x.diagram, x.diagram, "A", "B", msg,
                                             sizeof msg), 0);
    assert_string_equal(msg, "");
    assert_int_equal(api__diagram_difference(x.diagram, y.diagram, "A", "B", msg,
                                             sizeof msg), 1);
    if (strncmp(msg, "vertex ", 7) != 0 && strstr(msg, "B has") == NULL) {
        fail_msg("unexpected explanation: %s", msg);
    }
    assert_int_equal(api__diagram_difference(x.diagram, z.diagram, "A", "B", msg,
                                             sizeof msg), 1);
    assert_string_equal(msg, "B has 4 sites, A has 5");
    api_result_clear(&x);
    api_result_clear(&y);
    api_result_clear(&z);
    api_request_clear(&r1);
    api_request_clear(&r2);
    api_request_clear(&r3);
}

static void test_nonfinite(void **state) {
    (void)state;
    static const struct {
        double xy[6];
        const char *pointer, *words;
    } cases[] = {
        {{0, 0, NAN, 1, 2, 2}, "/points/1/0", "points[1][0] is NaN"},
        {{0, 0, 1, 1, 2, -INFINITY}, "/points/2/1", "points[2][1] is -Infinity"},
        {{INFINITY, 0, 1, 1, 2, 2}, "/points/0/0", "points[0][0] is Infinity"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        api_request r = request_for(cases[i].xy, 3, VOR_BOWYER_WATSON, API_PART_DEFAULT, NULL);
        api_result res;
        api_problem p;
        api_result_init(&res);
        assert_int_equal(api_compute(&r, &res, &p), API_INVALID);
        assert_string_equal(p.pointer, cases[i].pointer);
        if (strstr(p.detail, cases[i].words) == NULL) fail_msg("detail: %s", p.detail);
        assert_null(res.sites);
        assert_null(res.diagram);
        api_compare c;
        api_compare_init(&c);
        assert_int_equal(api_compare_run(&r, &c, &p), API_INVALID);
        assert_string_equal(p.pointer, cases[i].pointer);
        api_request_clear(&r);
    }
}

static void test_small_inputs(void **state) {
    (void)state;
    /* 0, 1 and 2 points, and all duplicates: the degenerate diagrams. */
    static const double xy[] = {3, 4, 3, 4, 5, 4};
    static const size_t sizes[] = {0, 1, 2, 3};
    for (size_t k = 0; k < 4; k++) {
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            api_request r = request_for(xy, sizes[k], (vor_algorithm)a, API_PART_ALL, NULL);
            api_result res;
            api_problem p;
            api_result_init(&res);
            api_code c = api_compute(&r, &res, &p);
            if (c != API_OK) fail_msg("n=%zu %s: %s", sizes[k], vor_algorithm_name(a), p.detail);
            api_buf out;
            api_buf_init(&out);
            assert_int_equal(api_write_result(&r, &res, &res.t, &out, &p), API_OK);
            rc_check_json(out.data, out.len, &res, API_PART_ALL, 0);
            api_buf_clear(&out);
            r.format = API_FMT_GEOJSON;
            assert_int_equal(api_write_result(&r, &res, &res.t, &out, &p), API_OK);
            rc_check_geojson(out.data, out.len, &res);
            api_buf_clear(&out);
            api_result_clear(&res);
            api_request_clear(&r);
        }
    }
}

static void test_default_box(void **state) {
    (void)state;
    static const struct {
        double xy[4];
        size_t n;
    } cases[] = {
        {{0, 0, 10, 5}, 2},         {{3, 3, 0, 0}, 1},      {{1e300, -1e300, 0, 0}, 1},
        {{-1.7976931348623157e308, 1.7976931348623157e308, 0, 0}, 1},
        {{-1.7976931348623157e308, -1, 1.7976931348623157e308, 1}, 2},
        {{1e-300, 0, 2e-300, 0}, 2}, {{5e-324, 0, 0, 0}, 1},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        vor_sites *s;
        assert_int_equal(vor_sites_new(cases[i].xy, cases[i].n, &s, NULL), VOR_OK);
        double b[4];
        api__default_box(s, b);
        for (int k = 0; k < 4; k++) assert_true(isfinite(b[k]));
        assert_true(b[0] < b[2] && b[1] < b[3]);
        for (size_t j = 0; j < s->n; j++) {
            double x = s->xy[2 * j], y = s->xy[2 * j + 1];
            assert_true(b[0] <= x && x <= b[2] && b[1] <= y && y <= b[3]);
            /* Strictly inside unless the site sits at the end of the doubles. */
            if (fabs(x) < 1.7976931348623157e308) assert_true(b[0] < x && x < b[2]);
        }
        vor_sites_free(s);
    }
    double b[4];
    api__default_box(NULL, b);
    assert_true(b[0] == -1 && b[1] == -1 && b[2] == 1 && b[3] == 1);
    /* 10% of the larger side, both ways. */
    vor_sites *s;
    double xy[] = {0, 0, 10, 5};
    assert_int_equal(vor_sites_new(xy, 2, &s, NULL), VOR_OK);
    api__default_box(s, b);
    assert_true(b[0] == -1 && b[1] == -1 && b[2] == 11 && b[3] == 6);
    vor_sites_free(s);
}

/* ---- Traces ----------------------------------------------------------------- */

/* A triangle as three input indices (-1: the vertex at infinity), rotated
 * to start at its smallest. */
typedef struct tri3 {
    long long v[3];
} tri3;

static tri3 tri_of(const json_t *a) {
    tri3 t;
    for (int k = 0; k < 3; k++) {
        json_t *x = json_array_get(a, (size_t)k);
        if (!json_is_integer(x)) fail_msg("triangle: not integers");
        t.v[k] = json_integer_value(x);
    }
    if (t.v[0] < 0) t.v[0] = 1LL << 40; /* infinity sorts last */
    if (t.v[1] < 0) t.v[1] = 1LL << 40;
    if (t.v[2] < 0) t.v[2] = 1LL << 40;
    int k = t.v[0] <= t.v[1] && t.v[0] <= t.v[2] ? 0 : t.v[1] <= t.v[2] ? 1 : 2;
    tri3 r;
    for (int j = 0; j < 3; j++) r.v[j] = t.v[(k + j) % 3];
    return r;
}

static int tri_finite(const tri3 *t) {
    return t->v[0] != 1LL << 40 && t->v[1] != 1LL << 40 && t->v[2] != 1LL << 40;
}

typedef struct tri_set {
    tri3 *t;
    size_t n, cap;
} tri_set;

static void set_add(tri_set *s, tri3 t) {
    for (size_t i = 0; i < s->n; i++)
        if (!memcmp(&s->t[i], &t, sizeof t)) fail_msg("triangle added twice");
    if (s->n == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 256;
        s->t = realloc(s->t, s->cap * sizeof *s->t);
        assert_non_null(s->t);
    }
    s->t[s->n++] = t;
}

static void set_remove(tri_set *s, tri3 t) {
    for (size_t i = 0; i < s->n; i++) {
        if (!memcmp(&s->t[i], &t, sizeof t)) {
            s->t[i] = s->t[--s->n];
            return;
        }
    }
    fail_msg("triangle (%lld, %lld, %lld) removed but not there", t.v[0], t.v[1], t.v[2]);
}

static int cmp_tri(const void *a, const void *b) {
    return memcmp(a, b, sizeof(tri3)) ? (memcmp(a, b, sizeof(tri3)) < 0 ? -1 : 1) : 0;
}

/* Replays the trace of document j (algorithm a) into the finite triangles
 * of *out, checking Fortune's beach line on the way and the running
 * counts against the document's. */
static void replay_json(const json_t *j, vor_algorithm a, tri_set *out) {
    json_t *steps = json_object_get(json_object_get(j, "trace"), "steps");
    if (!json_is_array(steps) || json_array_size(steps) < 2) fail_msg("no steps");
    tri_set s = {0};
    long long *beach = NULL;
    size_t nb = 0, cap = 0;
    json_t *counts = json_object(); /* running */
    for (size_t i = 0; i < json_array_size(steps); i++) {
        json_t *st = json_array_get(steps, i);
        const char *kind = json_string_value(json_object_get(st, "kind"));
        if (kind == NULL) fail_msg("step %zu: no kind", i);
        json_t *c = json_object_get(st, "counts");
        if (!json_is_object(c)) fail_msg("step %zu: no counts", i);
        json_object_update(counts, c);
        if ((i == 0) != !strcmp(kind, "order")) fail_msg("step %zu: order", i);
        if (!strcmp(kind, "begin") && a != VOR_FORTUNE) {
            json_t *t = json_object_get(st, "triangle");
            set_add(&s, tri_of(t));
            for (int k = 0; k < 3; k++) {
                json_t *g = json_pack("[O,O,i]", json_array_get(t, (size_t)(k + 1) % 3),
                                      json_array_get(t, (size_t)k), -1);
                set_add(&s, tri_of(g));
                json_decref(g);
            }
        } else if (!strcmp(kind, "begin")) {
            json_t *b = json_object_get(st, "beach");
            nb = json_array_size(b);
            cap = 2 * nb + 4096;
            beach = realloc(beach, cap * sizeof *beach);
            for (size_t k = 0; k < nb; k++) beach[k] = json_integer_value(json_array_get(b, k));
        } else if (!strcmp(kind, "insert")) {
            json_t *cav = json_object_get(st, "cavity"), *star = json_object_get(st, "star");
            if (json_array_size(star) != json_array_size(cav) + 2) fail_msg("star size");
            for (size_t k = 0; k < json_array_size(cav); k++)
                set_remove(&s, tri_of(json_array_get(cav, k)));
            for (size_t k = 0; k < json_array_size(star); k++)
                set_add(&s, tri_of(json_array_get(star, k)));
        } else if (!strcmp(kind, "flip")) {
            json_t *rm = json_object_get(st, "removed"), *ad = json_object_get(st, "added");
            json_t *t1 = json_pack("[O,O,O]", json_array_get(rm, 0), json_array_get(rm, 1),
                                   json_array_get(ad, 0));
            json_t *t2 = json_pack("[O,O,O]", json_array_get(rm, 1), json_array_get(rm, 0),
                                   json_array_get(ad, 1));
            json_t *n1 = json_pack("[O,O,O]", json_array_get(rm, 0), json_array_get(ad, 1),
                                   json_array_get(ad, 0));
            json_t *n2 = json_pack("[O,O,O]", json_array_get(ad, 1), json_array_get(rm, 1),
                                   json_array_get(ad, 0));
            set_remove(&s, tri_of(t1));
            set_remove(&s, tri_of(t2));
            set_add(&s, tri_of(n1));
            set_add(&s, tri_of(n2));
            json_decref(t1);
            json_decref(t2);
            json_decref(n1);
            json_decref(n2);
        } else if (!strcmp(kind, "site")) {
            long long p = json_integer_value(json_object_get(st, "site"));
            size_t at = (size_t)json_integer_value(json_object_get(st, "at"));
            if (at == 0 || at > nb || nb + 2 > cap) fail_msg("site %lld: at %zu", p, at);
            json_t *arc = json_object_get(st, "arc");
            if (arc) {
                if (beach[at - 1] != json_integer_value(arc)) fail_msg("site %lld: arc", p);
                memmove(beach + at + 2, beach + at, (nb - at) * sizeof *beach);
                beach[at] = p;
                beach[at + 1] = beach[at - 1];
                nb += 2;
            } else {
                json_t *bp = json_object_get(st, "breakpoint");
                if (beach[at - 1] != json_integer_value(json_array_get(bp, 0)) ||
                    beach[at] != json_integer_value(json_array_get(bp, 1)))
                    fail_msg("site %lld: breakpoint", p);
                memmove(beach + at + 1, beach + at, (nb - at) * sizeof *beach);
                beach[at] = p;
                nb++;
                set_add(&s, tri_of(json_object_get(st, "triangle")));
            }
        } else if (!strcmp(kind, "circle")) {
            size_t at = (size_t)json_integer_value(json_object_get(st, "at"));
            json_t *arcs = json_object_get(st, "arcs");
            if (at == 0 || at + 1 >= nb) fail_msg("circle at %zu", at);
            for (int k = 0; k < 3; k++)
                if (beach[at - 1 + (size_t)k] != json_integer_value(json_array_get(arcs, (size_t)k)))
                    fail_msg("circle: arcs not at %zu", at);
            memmove(beach + at, beach + at + 1, (nb - at - 1) * sizeof *beach);
            nb--;
            set_add(&s, tri_of(arcs));
        }
    }
    const char *last = json_string_value(json_object_get(
        json_array_get(steps, json_array_size(steps) - 1), "kind"));
    if (strcmp(last, "end")) fail_msg("last step: %s", last);
    if (!json_equal(counts, json_object_get(j, "counts"))) fail_msg("running counts differ");
    json_decref(counts);
    free(beach);
    out->n = 0;
    for (size_t i = 0; i < s.n; i++)
        if (tri_finite(&s.t[i])) set_add(out, s.t[i]);
    free(s.t);
}

static void test_trace_replays(void **state) {
    (void)state;
    const char *sets[] = {"uniform-1000", "pixels-2000", "grid-7x7", "int-circle-1105",
                          "duplicates-3000", "equal-y-first"};
    for (size_t k = 0; k < sizeof sets / sizeof sets[0]; k++) {
        vt_set set;
        if (vt_make_named(sets[k], &set) != 0) fail_msg("no set %s", sets[k]);
        size_t n = set.n > 400 ? 400 : set.n;
        int unique = !strcmp(sets[k], "uniform-1000"); /* no 4 cocircular */
        for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
            if (!available[a]) continue;
            api_request r = request_for(set.xy, n, (vor_algorithm)a,
                                        API_PART_TRIANGLES | API_PART_COUNTS, NULL);
            r.trace = 1;
            api_result res;
            api_problem p;
            api_result_init(&res);
            if (api_compute(&r, &res, &p) != API_OK) fail_msg("%s: %s", sets[k], p.detail);
            api_buf out;
            api_buf_init(&out);
            assert_int_equal(api_write_result(&r, &res, &res.t, &out, &p), API_OK);
            rc_check_json(out.data, out.len, &res, r.parts, 0);
            json_error_t err;
            json_t *j = json_loadb(out.data, out.len, JSON_REJECT_DUPLICATES, &err);
            assert_non_null(j);
            tri_set got = {0};
            replay_json(j, (vor_algorithm)a, &got);
            json_t *want = json_object_get(j, "triangles");
            if (got.n != json_array_size(want))
                fail_msg("%s %s: %zu triangles replayed, answer has %zu", sets[k],
                         vor_algorithm_name(a), got.n, json_array_size(want));
            if (unique) {
                tri3 *w = malloc(got.n * sizeof *w);
                for (size_t i = 0; i < got.n; i++) w[i] = tri_of(json_array_get(want, i));
                qsort(w, got.n, sizeof *w, cmp_tri);
                qsort(got.t, got.n, sizeof *got.t, cmp_tri);
                if (memcmp(w, got.t, got.n * sizeof *w))
                    fail_msg("%s %s: replayed triangles differ", sets[k], vor_algorithm_name(a));
                free(w);
            }
            print_message("%s %s: %zu steps, %zu triangles replayed\n", sets[k],
                          vor_algorithm_name(a),
                          json_array_size(json_object_get(json_object_get(j, "trace"), "steps")),
                          got.n);
            free(got.t);
            json_decref(j);
            api_buf_clear(&out);
            api_result_clear(&res);
            api_request_clear(&r);
        }
        vt_set_free(&set);
    }
}

static void test_trace_refusals(void **state) {
    (void)state;
    double *xy = vt_uniform(API_TRACE_MAX_POINTS + 1, 4);
    assert_non_null(xy);
    api_result res;
    api_problem p;
    /* one point too many */
    api_request r = request_for(xy, API_TRACE_MAX_POINTS + 1, VOR_FLIP, API_PART_DEFAULT, NULL);
    r.trace = 1;
    api_result_init(&res);
    assert_int_equal(api_compute(&r, &res, &p), API_INVALID);
    assert_string_equal(p.pointer, "/trace");
    assert_non_null(strstr(p.detail, "2000"));
    assert_non_null(strstr(p.detail, "2001"));
    assert_null(res.diagram);
    api_request_clear(&r);
    /* exactly the limit */
    r = request_for(xy, API_TRACE_MAX_POINTS, VOR_BOWYER_WATSON, API_PART_DEFAULT, NULL);
    r.trace = 1;
    assert_int_equal(api_compute(&r, &res, &p), API_OK);
    assert_true(res.traced && res.trace.len > 0);
    api_result_clear(&res);
    /* not JSON */
    r.format = API_FMT_BINARY;
    assert_int_equal(api_compute(&r, &res, &p), API_INVALID);
    assert_string_equal(p.pointer, "/trace");
    assert_non_null(strstr(p.detail, "binary"));
    r.format = API_FMT_TIMINGS;
    assert_int_equal(api_compute(&r, &res, &p), API_INVALID);
    r.format = API_FMT_JSON;
    /* not /compare */
    api_compare c;
    api_compare_init(&c);
    assert_int_equal(api_compare_run(&r, &c, &p), API_INVALID);
    assert_string_equal(p.pointer, "/trace");
    api_compare_clear(&c);
    /* without a trace, the same request is fine everywhere */
    r.trace = 0;
    assert_int_equal(api_compare_run(&r, &c, &p), API_OK);
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        if (!available[a]) continue;
        assert_true(a == VOR_FORTUNE ? c.res[a].counts.site_events == API_TRACE_MAX_POINTS
                                     : c.res[a].counts.orient2d > 0);
        assert_false(c.res[a].traced);
    }
    api_compare_clear(&c);
    api_request_clear(&r);
    free(xy);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sets_round_trip),
        cmocka_unit_test(test_compare_agrees),
        cmocka_unit_test(test_compare_repeat),
        cmocka_unit_test(test_compare_repeat_default_and_limits),
        cmocka_unit_test(test_stopped),
        cmocka_unit_test(test_difference_explained),
        cmocka_unit_test(test_nonfinite),
        cmocka_unit_test(test_small_inputs),
        cmocka_unit_test(test_default_box),
        cmocka_unit_test(test_trace_replays),
        cmocka_unit_test(test_trace_refusals),
    };
    return cmocka_run_group_tests_name("api/compute", tests, setup, NULL);
}
