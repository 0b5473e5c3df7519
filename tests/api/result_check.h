/* result_check.h -- oracles for the writers' tests (header-only, static).
 *
 * Each check reads a written document back with an independent reader
 * (jansson for JSON and GeoJSON, a byte-by-byte decoder for the binary
 * layout) and compares every value with the api_result it came from, bit
 * for bit for coordinates. Used by test_write.c (hand-made diagrams) and
 * test_compute.c (diagrams from the core). */
#ifndef VOR_TESTS_RESULT_CHECK_H
#define VOR_TESTS_RESULT_CHECK_H

#include <jansson.h>
#include <math.h>
#include <string.h>

#include "../../api/api.h"

/* Bitwise equality, except that a written null stands for a non-finite
 * value. */
static inline void rc_check_double(const json_t *j, double want, const char *what,
                                   size_t i) {
    if (!isfinite(want)) {
        if (!json_is_null(j)) fail_msg("%s %zu: non-finite not written as null", what, i);
        return;
    }
    if (!json_is_number(j)) fail_msg("%s %zu: not a number", what, i);
    double got = json_number_value(j);
    if (memcmp(&got, &want, sizeof got) != 0 && !(got == 0 && want == 0)) {
        fail_msg("%s %zu: read back %.17g, was %.17g", what, i, got, want);
    }
}

static inline void rc_check_pair(const json_t *j, const double *xy, const char *what,
                                 size_t i) {
    if (!json_is_array(j) || json_array_size(j) != 2) fail_msg("%s %zu: not a pair", what, i);
    rc_check_double(json_array_get(j, 0), xy[0], what, i);
    rc_check_double(json_array_get(j, 1), xy[1], what, i);
}

static inline json_t *rc_get(const json_t *o, const char *key) {
    json_t *v = json_object_get(o, key);
    if (v == NULL) fail_msg("member \"%s\" missing", key);
    return v;
}

static inline long long rc_int(const json_t *o, const char *key) {
    json_t *v = rc_get(o, key);
    if (!json_is_integer(v)) fail_msg("member \"%s\" is not an integer", key);
    return json_integer_value(v);
}

static inline void rc_check_timings(const json_t *t) {
    static const char *const keys[] = {"queue_ms", "parse_ms", "prepare_ms",
                                       "compute_ms", "clip_ms", "serialize_ms",
                                       "total_ms"};
    if (!json_is_object(t) || json_object_size(t) != 7) fail_msg("timings: not 7 members");
    for (int k = 0; k < 7; k++) {
        json_t *v = rc_get(t, keys[k]);
        if (!json_is_number(v) || json_number_value(v) < 0) {
            fail_msg("timings.%s is not a non-negative number", keys[k]);
        }
    }
}

/* A counts object: exactly the counts that apply to algorithm a, with
 * res's values. */
static inline void rc_check_counts(const json_t *o, const vor_counts *c,
                                   vor_algorithm a) {
    if (!json_is_object(o)) fail_msg("counts: not an object");
    size_t want = 0;
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++) {
        if (!(vor_count_algorithms(i) & (1u << a))) {
            if (json_object_get(o, vor_count_name(i)))
                fail_msg("counts: %s does not apply to %s", vor_count_name(i),
                         vor_algorithm_name(a));
            continue;
        }
        want++;
        json_t *v = json_object_get(o, vor_count_name(i));
        if (!json_is_integer(v) ||
            (uint64_t)json_integer_value(v) != vor_count_value(c, i))
            fail_msg("counts: %s", vor_count_name(i));
    }
    if (json_object_size(o) != want) fail_msg("counts: %zu keys, want %zu",
                                              json_object_size(o), want);
}

/* The whole JSON document against res, for the given effective parts. */
static inline void rc_check_json(const char *doc, size_t len, const api_result *res,
                                 unsigned parts, int bounds_given) {
    json_error_t err;
    json_t *j = json_loadb(doc, len, JSON_REJECT_DUPLICATES, &err);
    if (j == NULL) fail_msg("not JSON: %s at %d: %.200s", err.text, err.position, doc);
    const vor_sites *s = res->sites;
    const vor_diagram *d = res->diagram;
    if (strcmp(json_string_value(rc_get(j, "algorithm")),
               vor_algorithm_name(res->algorithm)) != 0) {
        fail_msg("algorithm");
    }
    if (rc_int(j, "n_input") != (long long)s->n_input ||
        rc_int(j, "n_sites") != (long long)s->n ||
        rc_int(j, "n_vertices") != (long long)d->n_vertices ||
        rc_int(j, "n_edges") != (long long)d->n_edges) {
        fail_msg("counts differ");
    }
    /* duplicates: every input index whose first occurrence is another */
    json_t *dups = rc_get(j, "duplicates");
    size_t k = 0;
    for (size_t i = 0; i < s->n_input; i++) {
        uint32_t f = s->input_of[s->site_of[i]];
        if (f == i) continue;
        json_t *p = json_array_get(dups, k++);
        if (json_integer_value(json_array_get(p, 0)) != (json_int_t)i ||
            json_integer_value(json_array_get(p, 1)) != (json_int_t)f) {
            fail_msg("duplicates entry %zu", k - 1);
        }
    }
    if (json_array_size(dups) != k) fail_msg("duplicates: %zu entries, want %zu",
                                             json_array_size(dups), k);

    json_t *v = json_object_get(j, "sites");
    if (!(parts & API_PART_SITES) != (v == NULL)) fail_msg("sites presence");
    if (v) {
        if (json_array_size(v) != s->n_input) fail_msg("sites count");
        for (size_t i = 0; i < s->n_input; i++) {
            rc_check_pair(json_array_get(v, i), s->xy + 2 * (size_t)s->site_of[i],
                          "site", i);
        }
    }
    v = json_object_get(j, "vertices");
    if (!(parts & API_PART_VERTICES) != (v == NULL)) fail_msg("vertices presence");
    if (v) {
        if (json_array_size(v) != d->n_vertices) fail_msg("vertices count");
        for (size_t i = 0; i < d->n_vertices; i++) {
            rc_check_pair(json_array_get(v, i), d->vertex_xy + 2 * i, "vertex", i);
        }
    }
    v = json_object_get(j, "edges");
    if (!(parts & API_PART_EDGES) != (v == NULL)) fail_msg("edges presence");
    if (v) {
        if (json_array_size(v) != d->n_edges) fail_msg("edges count");
        size_t r = 0;
        for (size_t e = 0; e < d->n_edges; e++) {
            json_t *o = json_array_get(v, e);
            json_t *ss = rc_get(o, "sites"), *ends = rc_get(o, "ends");
            uint32_t a = d->edge_sites[2 * e], b = d->edge_sites[2 * e + 1];
            if (json_integer_value(json_array_get(ss, 0)) != s->input_of[a] ||
                json_integer_value(json_array_get(ss, 1)) != s->input_of[b]) {
                fail_msg("edge %zu: sites", e);
            }
            for (int q = 0; q < 2; q++) {
                int32_t want = d->edge_ends[2 * e + q];
                json_t *x = json_array_get(ends, (size_t)q);
                if (want < 0 ? !json_is_null(x) : json_integer_value(x) != want) {
                    fail_msg("edge %zu: end %d", e, q);
                }
            }
            json_t *ray = json_object_get(o, "ray"), *pt = json_object_get(o, "point");
            int has_ray = r < d->n_rays && d->ray_edge[r] == e;
            if (has_ray != (ray != NULL)) fail_msg("edge %zu: ray presence", e);
            if (has_ray) {
                rc_check_pair(ray, d->ray_dir + 2 * r, "ray", r);
                r++;
            }
            int line = d->edge_ends[2 * e] < 0;
            if (line != (pt != NULL)) fail_msg("edge %zu: point presence", e);
            if (line) {
                const double *pa = s->xy + 2 * (size_t)a, *pb = s->xy + 2 * (size_t)b;
                double m[2] = {(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2};
                if (!isfinite(m[0])) m[0] = pa[0] / 2 + pb[0] / 2;
                if (!isfinite(m[1])) m[1] = pa[1] / 2 + pb[1] / 2;
                rc_check_pair(pt, m, "line point", e);
            }
        }
    }
    v = json_object_get(j, "cells");
    if (!(parts & API_PART_CELLS) != (v == NULL)) fail_msg("cells presence");
    if (v) {
        if (json_array_size(v) != s->n) fail_msg("cells count");
        for (size_t i = 0; i < s->n; i++) {
            json_t *o = json_array_get(v, i);
            if (rc_int(o, "site") != s->input_of[i]) fail_msg("cell %zu: site", i);
            json_t *es = rc_get(o, "edges");
            uint32_t lo = d->cell_start[i], hi = d->cell_start[i + 1];
            if (json_array_size(es) != hi - lo) fail_msg("cell %zu: edge count", i);
            for (uint32_t q = lo; q < hi; q++) {
                if (json_integer_value(json_array_get(es, q - lo)) != d->cell_edges[q]) {
                    fail_msg("cell %zu: edge %u", i, q - lo);
                }
            }
            if (json_is_true(rc_get(o, "bounded")) != (d->cell_bounded[i] != 0)) {
                fail_msg("cell %zu: bounded", i);
            }
        }
    }
    v = json_object_get(j, "triangles");
    if (!(parts & API_PART_TRIANGLES) != (v == NULL)) fail_msg("triangles presence");
    if (v) {
        if (json_array_size(v) != res->n_triangles) fail_msg("triangles count");
        for (size_t t = 0; t < res->n_triangles; t++) {
            for (size_t q = 0; q < 3; q++) {
                if (json_integer_value(json_array_get(json_array_get(v, t), q)) !=
                    s->input_of[res->triangles[3 * t + q]]) {
                    fail_msg("triangle %zu", t);
                }
            }
        }
    }
    v = json_object_get(j, "clipped");
    if (!(parts & API_PART_CLIPPED) != (v == NULL)) fail_msg("clipped presence");
    if (v) {
        const vor_clipped *c = res->clipped;
        json_t *b = rc_get(v, "bounds");
        for (size_t q = 0; q < 4; q++) rc_check_double(json_array_get(b, q), c->box[q], "box", q);
        if (json_is_true(rc_get(v, "bounds_given")) != (bounds_given != 0)) {
            fail_msg("bounds_given");
        }
        json_t *es = rc_get(v, "edges");
        if (json_array_size(es) != d->n_edges) fail_msg("clipped edges count");
        for (size_t e = 0; e < d->n_edges; e++) {
            json_t *g = json_array_get(es, e);
            if (!c->seg_in[e]) {
                if (!json_is_null(g)) fail_msg("clipped edge %zu: not null", e);
                continue;
            }
            for (size_t q = 0; q < 4; q++) {
                rc_check_double(json_array_get(g, q), c->seg[4 * e + q], "clipped edge", e);
            }
        }
        json_t *cs = rc_get(v, "cells");
        if (json_array_size(cs) != s->n) fail_msg("clipped cells count");
        for (size_t i = 0; i < s->n; i++) {
            json_t *poly = json_array_get(cs, i);
            uint32_t lo = c->poly_start[i], hi = c->poly_start[i + 1];
            if (json_array_size(poly) != hi - lo) fail_msg("clipped cell %zu: size", i);
            for (uint32_t q = lo; q < hi; q++) {
                rc_check_pair(json_array_get(poly, q - lo), c->poly_xy + 2 * (size_t)q,
                              "clipped cell point", q);
            }
        }
    }
    v = json_object_get(j, "counts");
    if (!(parts & API_PART_COUNTS) != (v == NULL)) fail_msg("counts presence");
    if (v) rc_check_counts(v, &res->counts, res->algorithm);
    rc_check_timings(rc_get(j, "timings"));
    json_decref(j);
}

/* GeoJSON: a FeatureCollection of one Polygon (or null) per site. */
static inline void rc_check_geojson(const char *doc, size_t len, const api_result *res) {
    json_error_t err;
    json_t *j = json_loadb(doc, len, JSON_REJECT_DUPLICATES, &err);
    if (j == NULL) fail_msg("GeoJSON is not JSON: %s", err.text);
    const vor_sites *s = res->sites;
    const vor_clipped *c = res->clipped;
    if (strcmp(json_string_value(rc_get(j, "type")), "FeatureCollection")) {
        fail_msg("not a FeatureCollection");
    }
    json_t *bbox = rc_get(j, "bbox");
    for (size_t q = 0; q < 4; q++) rc_check_double(json_array_get(bbox, q), c->box[q], "bbox", q);
    json_t *fs = rc_get(j, "features");
    if (json_array_size(fs) != s->n) fail_msg("features: %zu, sites %zu", json_array_size(fs), s->n);
    for (size_t i = 0; i < s->n; i++) {
        json_t *f = json_array_get(fs, i);
        if (strcmp(json_string_value(rc_get(f, "type")), "Feature")) fail_msg("feature type");
        json_t *pr = rc_get(f, "properties");
        if (rc_int(pr, "site") != s->input_of[i]) fail_msg("feature %zu: site", i);
        if (json_is_true(rc_get(pr, "bounded")) != (res->diagram->cell_bounded[i] != 0)) {
            fail_msg("feature %zu: bounded", i);
        }
        json_t *g = rc_get(f, "geometry");
        uint32_t lo = c->poly_start[i], hi = c->poly_start[i + 1];
        if (hi - lo < 3) {
            if (!json_is_null(g)) fail_msg("feature %zu: geometry should be null", i);
            continue;
        }
        if (strcmp(json_string_value(rc_get(g, "type")), "Polygon")) fail_msg("not a Polygon");
        json_t *rings = rc_get(g, "coordinates");
        if (json_array_size(rings) != 1) fail_msg("feature %zu: rings", i);
        json_t *ring = json_array_get(rings, 0);
        /* The ring is the polygon, closed if it was not already. */
        const double *first = c->poly_xy + 2 * (size_t)lo, *last = c->poly_xy + 2 * (size_t)(hi - 1);
        size_t closed = first[0] == last[0] && first[1] == last[1];
        if (json_array_size(ring) != hi - lo + !closed) fail_msg("feature %zu: ring size", i);
        for (uint32_t q = lo; q < hi + !closed; q++) {
            rc_check_pair(json_array_get(ring, q - lo), c->poly_xy + 2 * (size_t)(q < hi ? q : lo),
                          "ring point", q);
        }
        json_t *r0 = json_array_get(ring, 0), *rl = json_array_get(ring, json_array_size(ring) - 1);
        if (!json_equal(r0, rl)) fail_msg("feature %zu: ring not closed", i);
    }
    rc_check_timings(rc_get(j, "timings"));
    json_decref(j);
}

/* SVG: the document's frame, one circle per site (all inside the picture
 * in these tests), no non-finite number anywhere. */
static inline void rc_check_svg(const char *doc, size_t len, const api_result *res) {
    if (len < 12 || strncmp(doc, "<svg ", 5) != 0) fail_msg("SVG does not start with <svg");
    if (strcmp(doc + len - 7, "</svg>\n") != 0) fail_msg("SVG does not end with </svg>");
    size_t circles = 0;
    for (const char *p = doc; (p = strstr(p, "<circle ")) != NULL; p++) circles++;
    if (circles != res->sites->n) fail_msg("%zu circles for %zu sites", circles, res->sites->n);
    if (strstr(doc, "null") || strstr(doc, "nan") || strstr(doc, "inf")) {
        fail_msg("SVG holds a non-finite number");
    }
    size_t lt = 0, gt = 0;
    for (size_t i = 0; i < len; i++) {
        lt += doc[i] == '<';
        gt += doc[i] == '>';
    }
    if (lt != gt) fail_msg("SVG: %zu '<' but %zu '>'", lt, gt);
}

/* Binary layout: reader over the documented little-endian sections. */
typedef struct rc_reader {
    const unsigned char *p, *end;
} rc_reader;

static inline uint32_t rc_u32(rc_reader *r) {
    if (r->end - r->p < 4) fail_msg("binary: truncated");
    uint32_t v = (uint32_t)r->p[0] | (uint32_t)r->p[1] << 8 | (uint32_t)r->p[2] << 16 |
                 (uint32_t)r->p[3] << 24;
    r->p += 4;
    return v;
}

static inline double rc_f64(rc_reader *r) {
    uint64_t lo = rc_u32(r), hi = rc_u32(r);
    uint64_t u = lo | hi << 32;
    double v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static inline void rc_align(rc_reader *r, const unsigned char *start) {
    while ((r->p - start) % 8) {
        if (*r->p != 0) fail_msg("binary: non-zero padding");
        r->p++;
    }
}

static inline void rc_check_binary(const char *doc, size_t len, const api_result *res,
                                   int want_tri) {
    const unsigned char *start = (const unsigned char *)doc;
    rc_reader r = {start, start + len};
    const vor_sites *s = res->sites;
    const vor_diagram *d = res->diagram;
    const vor_clipped *c = res->clipped;
    if (len < 48 || memcmp(doc, "VORB", 4) != 0) fail_msg("binary: magic");
    r.p += 4;
    if (rc_u32(&r) != 1) fail_msg("binary: version");
    if (rc_u32(&r) != (uint32_t)res->algorithm) fail_msg("binary: algorithm");
    uint32_t flags = rc_u32(&r);
    if (((flags & 1) != 0) != (want_tri != 0) || ((flags & 2) != 0) != (c != NULL) ||
        !(flags & 8)) {
        fail_msg("binary: flags %u", flags);
    }
    uint32_t want[] = {(uint32_t)s->n_input, (uint32_t)s->n, (uint32_t)d->n_vertices,
                       (uint32_t)d->n_edges, (uint32_t)d->n_rays,
                       want_tri ? (uint32_t)res->n_triangles : 0,
                       c ? c->poly_start[s->n] : 0, (uint32_t)VOR_COUNT_FIELDS};
    for (int i = 0; i < 8; i++) {
        if (rc_u32(&r) != want[i]) fail_msg("binary: header word %d", i);
    }
    for (size_t i = 0; i < s->n; i++) if (rc_u32(&r) != s->input_of[i]) fail_msg("binary: site_input");
    rc_align(&r, start);
    for (size_t i = 0; i < s->n_input; i++) if (rc_u32(&r) != s->site_of[i]) fail_msg("binary: input_site");
    rc_align(&r, start);
    for (size_t i = 0; i < 2 * s->n; i++) if (rc_f64(&r) != s->xy[i]) fail_msg("binary: sites_xy");
    for (size_t i = 0; i < 2 * d->n_vertices; i++) {
        double v = rc_f64(&r);
        if (memcmp(&v, &d->vertex_xy[i], 8)) fail_msg("binary: vertices");
    }
    for (size_t e = 0; e < d->n_edges; e++) {
        if (rc_u32(&r) != s->input_of[d->edge_sites[2 * e]] ||
            rc_u32(&r) != s->input_of[d->edge_sites[2 * e + 1]] ||
            (int32_t)rc_u32(&r) != d->edge_ends[2 * e] ||
            (int32_t)rc_u32(&r) != d->edge_ends[2 * e + 1]) {
            fail_msg("binary: edge %zu", e);
        }
    }
    for (size_t i = 0; i < d->n_rays; i++) if (rc_u32(&r) != d->ray_edge[i]) fail_msg("binary: ray_edge");
    rc_align(&r, start);
    for (size_t i = 0; i < 2 * d->n_rays; i++) if (rc_f64(&r) != d->ray_dir[i]) fail_msg("binary: ray_dir");
    for (size_t i = 0; i <= s->n; i++) if (rc_u32(&r) != d->cell_start[i]) fail_msg("binary: cell_start");
    rc_align(&r, start);
    for (size_t i = 0; i < 2 * d->n_edges; i++) if (rc_u32(&r) != d->cell_edges[i]) fail_msg("binary: cell_edges");
    rc_align(&r, start);
    for (size_t i = 0; i < s->n; i++) if (*r.p++ != d->cell_bounded[i]) fail_msg("binary: bounded");
    rc_align(&r, start);
    if (want_tri) {
        for (size_t i = 0; i < 3 * res->n_triangles; i++) {
            if (rc_u32(&r) != s->input_of[res->triangles[i]]) fail_msg("binary: triangles");
        }
        rc_align(&r, start);
    }
    if (c) {
        for (int k = 0; k < 4; k++) if (rc_f64(&r) != c->box[k]) fail_msg("binary: box");
        for (size_t e = 0; e < d->n_edges; e++) {
            for (int k = 0; k < 4; k++) {
                double v = rc_f64(&r);
                if (c->seg_in[e] ? v != c->seg[4 * e + k] : !isnan(v)) fail_msg("binary: clip edge");
            }
        }
        for (size_t i = 0; i <= s->n; i++) if (rc_u32(&r) != c->poly_start[i]) fail_msg("binary: clip_start");
        rc_align(&r, start);
        for (size_t i = 0; i < 2 * (size_t)c->poly_start[s->n]; i++) {
            if (rc_f64(&r) != c->poly_xy[i]) fail_msg("binary: clip_xy");
        }
    }
    for (int k = 0; k < 7; k++) {
        double t = rc_f64(&r);
        if (!(t >= 0)) fail_msg("binary: timing %d", k);
    }
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++) {
        uint64_t v = 0;
        if (r.end - r.p < 8) fail_msg("binary: truncated counts");
        for (int b = 0; b < 8; b++) v |= (uint64_t)r.p[b] << (8 * b);
        r.p += 8;
        if (v != vor_count_value(&res->counts, i)) fail_msg("binary: count %zu", i);
    }
    if (r.p != r.end) fail_msg("binary: %td bytes left over", r.end - r.p);
}

#endif /* VOR_TESTS_RESULT_CHECK_H */
