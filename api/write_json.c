/* write_json.c -- the diagram as application/json.
 *
 * Shape (documented in openapi.yaml, components/schemas/Diagram):
 *
 *   {"algorithm": "fortune", "n_input": 5, "n_sites": 4, "n_vertices": 2,
 *    "n_edges": 5, "duplicates": [[4, 0]],
 *    "sites": [[x, y], ...]                       one per INPUT index
 *    "vertices": [[x, y], ...],
 *    "edges": [{"sites": [i, j], "ends": [v0, v1]},             segment
 *              {"sites": [i, j], "ends": [v0, null], "ray": [dx, dy]},
 *              {"sites": [i, j], "ends": [null, null], "ray": [dx, dy],
 *               "point": [x, y]}, ...],                          line
 *    "cells": [{"site": i, "edges": [e, ...], "bounded": true}, ...],
 *    "triangles": [[i, j, k], ...],
 *    "clipped": {"bounds": [...], "bounds_given": true,
 *                "edges": [[x0, y0, x1, y1] or null, ...],
 *                "cells": [[[x, y], ...], ...]},    closed rings
 *    "counts": {"orient2d": 6314, ...},           the algorithm's work
 *    "trace": {"steps": [{"kind": "order", ...}, ...]},  write_trace.c
 *    "timings": {...}}
 *
 * followed by a newline, as every text document of the service.
 * Every site number is an INPUT index (the first occurrence of a duplicated
 * point), so it indexes the caller's own array and "sites". Cells and
 * clipped cells come one per distinct site, in increasing input index.
 * Numbers are the shortest decimals that read back exactly; a vertex whose
 * coordinates overflow a double is written as null.
 *
 * The writer streams into the buffer with one reserve per item and the
 * unchecked appends of buf.h: about 0.1 us a number, O(output) time, no
 * intermediate tree. */
#include <string.h>

#include "codec.h"

/* Room for one item: a few numbers and punctuation. */
#define ITEM_ROOM (8 * API_NUM_MAXLEN + 128)

static inline void put_pair(api_buf *b, const double *xy) {
    api__putc(b, '[');
    api__put_double(b, xy[0]);
    api__putc(b, ',');
    api__put_double(b, xy[1]);
    api__putc(b, ']');
}

/* put_pair through a cursor (buf.h). */
static inline char *w_pair(char *w, const double *xy) {
    w = api__wc(w, '[');
    w = api__wdouble(w, xy[0]);
    w = api__wc(w, ',');
    w = api__wdouble(w, xy[1]);
    return api__wc(w, ']');
}

static int write_header(const api_result *res, api_buf *out) {
    const vor_sites *s = res->sites;
    const vor_diagram *d = res->diagram;
    /* Plain appends, not printf: this header is a visible share of the
     * cost of a small request. The counts fit 32 bits (VOR_MAX_POINTS). */
    const char *name = vor_algorithm_name(res->algorithm);
    if (api__reserve(out, 160 + strlen(name))) return -1;
    API__PUTS(out, "{\"algorithm\":\"");
    api__put(out, name, strlen(name));
    API__PUTS(out, "\",\"n_input\":");
    api__put_u32(out, (uint32_t)s->n_input);
    API__PUTS(out, ",\"n_sites\":");
    api__put_u32(out, (uint32_t)s->n);
    API__PUTS(out, ",\"n_vertices\":");
    api__put_u32(out, (uint32_t)d->n_vertices);
    API__PUTS(out, ",\"n_edges\":");
    api__put_u32(out, (uint32_t)d->n_edges);
    API__PUTS(out, ",\"duplicates\":[");
    int first = 1;
    for (size_t i = 0; i < s->n_input && s->n < s->n_input; i++) {
        uint32_t f = s->input_of[s->site_of[i]];
        if (f == i) continue;
        if (api__reserve(out, 32)) return -1;
        if (!first) api__putc(out, ',');
        first = 0;
        api__putc(out, '[');
        api__put_u32(out, (uint32_t)i);
        api__putc(out, ',');
        api__put_u32(out, f);
        api__putc(out, ']');
    }
    return API_BUF_LIT(out, "]");
}

static int write_sites(const api_result *res, api_buf *out) {
    const vor_sites *s = res->sites;
    if (API_BUF_LIT(out, ",\"sites\":[")) return -1;
    for (size_t i = 0; i < s->n_input; i++) {
        if (api__reserve(out, ITEM_ROOM)) return -1;
        if (i) api__putc(out, ',');
        put_pair(out, s->xy + 2 * (size_t)s->site_of[i]);
    }
    return API_BUF_LIT(out, "]");
}

static int write_vertices(const vor_diagram *d, api_buf *out) {
    if (API_BUF_LIT(out, ",\"vertices\":[")) return -1;
    for (size_t v = 0; v < d->n_vertices; v++) {
        if (api__reserve(out, ITEM_ROOM)) return -1;
        char *w = api__cur(out);
        if (v) w = api__wc(w, ',');
        api__cur_end(out, w_pair(w, d->vertex_xy + 2 * v));
    }
    return API_BUF_LIT(out, "]");
}

static inline char *w_end(char *w, int32_t v) {
    return v < 0 ? API__WLIT(w, "null") : api__wu32(w, (uint32_t)v);
}

static int write_edges(const api_result *res, api_buf *out) {
    const vor_sites *s = res->sites;
    const vor_diagram *d = res->diagram;
    size_t r = 0; /* next ray: rays are sorted by edge */
    if (API_BUF_LIT(out, ",\"edges\":[")) return -1;
    for (size_t e = 0; e < d->n_edges; e++) {
        if (api__reserve(out, ITEM_ROOM)) return -1;
        uint32_t a = d->edge_sites[2 * e], b = d->edge_sites[2 * e + 1];
        int32_t e0 = d->edge_ends[2 * e], e1 = d->edge_ends[2 * e + 1];
        char *w = api__cur(out);
        if (e) w = api__wc(w, ',');
        w = API__WLIT(w, "{\"sites\":[");
        w = api__wu32(w, api__input_index(s, a));
        w = api__wc(w, ',');
        w = api__wu32(w, api__input_index(s, b));
        w = API__WLIT(w, "],\"ends\":[");
        w = w_end(w, e0);
        w = api__wc(w, ',');
        w = w_end(w, e1);
        w = api__wc(w, ']');
        if (r < d->n_rays && d->ray_edge[r] == e) {
            w = API__WLIT(w, ",\"ray\":");
            w = w_pair(w, d->ray_dir + 2 * r);
            r++;
            if (e0 < 0) {
                double m[2];
                api__midpoint(s->xy + 2 * (size_t)a, s->xy + 2 * (size_t)b, m);
                w = API__WLIT(w, ",\"point\":");
                w = w_pair(w, m);
            }
        }
        api__cur_end(out, api__wc(w, '}'));
    }
    return API_BUF_LIT(out, "]");
}

static int write_cells(const api_result *res, api_buf *out) {
    const vor_sites *s = res->sites;
    const vor_diagram *d = res->diagram;
    if (API_BUF_LIT(out, ",\"cells\":[")) return -1;
    for (size_t i = 0; i < s->n; i++) {
        uint32_t lo = d->cell_start[i], hi = d->cell_start[i + 1];
        if (api__reserve(out, 64 + 12 * (size_t)(hi - lo))) return -1;
        char *w = api__cur(out);
        if (i) w = api__wc(w, ',');
        w = API__WLIT(w, "{\"site\":");
        w = api__wu32(w, api__input_index(s, i));
        w = API__WLIT(w, ",\"edges\":[");
        for (uint32_t k = lo; k < hi; k++) {
            if (k > lo) w = api__wc(w, ',');
            w = api__wu32(w, d->cell_edges[k]);
        }
        if (d->cell_bounded[i]) {
            w = API__WLIT(w, "],\"bounded\":true}");
        } else {
            w = API__WLIT(w, "],\"bounded\":false}");
        }
        api__cur_end(out, w);
    }
    return API_BUF_LIT(out, "]");
}

static int write_triangles(const api_result *res, api_buf *out) {
    const vor_sites *s = res->sites;
    if (API_BUF_LIT(out, ",\"triangles\":[")) return -1;
    for (size_t t = 0; t < res->n_triangles; t++) {
        if (api__reserve(out, 40)) return -1;
        if (t) api__putc(out, ',');
        api__putc(out, '[');
        for (int k = 0; k < 3; k++) {
            if (k) api__putc(out, ',');
            api__put_u32(out, api__input_index(s, res->triangles[3 * t + k]));
        }
        api__putc(out, ']');
    }
    return API_BUF_LIT(out, "]");
}

static int write_clipped(const api_request *r, const api_result *res,
                         api_buf *out) {
    const vor_clipped *c = res->clipped;
    const vor_diagram *d = res->diagram;
    if (api__reserve(out, ITEM_ROOM)) return -1;
    API__PUTS(out, ",\"clipped\":{\"bounds\":[");
    for (int k = 0; k < 4; k++) {
        if (k) api__putc(out, ',');
        api__put_double(out, c->box[k]);
    }
    if (r->has_bounds) {
        API__PUTS(out, "],\"bounds_given\":true,\"edges\":[");
    } else {
        API__PUTS(out, "],\"bounds_given\":false,\"edges\":[");
    }
    for (size_t e = 0; e < d->n_edges; e++) {
        if (api__reserve(out, ITEM_ROOM)) return -1;
        if (e) api__putc(out, ',');
        if (!c->seg_in[e]) {
            API__PUTS(out, "null");
            continue;
        }
        const double *g = c->seg + 4 * e;
        api__putc(out, '[');
        for (int k = 0; k < 4; k++) {
            if (k) api__putc(out, ',');
            api__put_double(out, g[k]);
        }
        api__putc(out, ']');
    }
    if (API_BUF_LIT(out, "],\"cells\":[")) return -1;
    for (size_t i = 0; i < d->n_sites; i++) {
        if (api__reserve(out, 4)) return -1;
        if (i) api__putc(out, ',');
        api__putc(out, '[');
        for (uint32_t k = c->poly_start[i]; k < c->poly_start[i + 1]; k++) {
            if (api__reserve(out, ITEM_ROOM)) return -1;
            if (k > c->poly_start[i]) api__putc(out, ',');
            put_pair(out, c->poly_xy + 2 * (size_t)k);
        }
        api__putc(out, ']');
    }
    return API_BUF_LIT(out, "]}");
}

int api__write_json(const api_request *r, const api_result *res,
                    api_timings *t, double t0, api_buf *out) {
    unsigned parts = api__effective_parts(r);
    /* Most of a large document is edges: reserve a good guess at once
     * (not when the document streams out through a flush hook). */
    size_t guess = 256 + 48 * res->diagram->n_vertices +
                   64 * res->diagram->n_edges + 48 * res->sites->n;
    if (out->flush == NULL && api__reserve(out, guess)) return -1;
    if (write_header(res, out)) return -1;
    if ((parts & API_PART_SITES) && write_sites(res, out)) return -1;
    if ((parts & API_PART_VERTICES) && write_vertices(res->diagram, out)) return -1;
    if ((parts & API_PART_EDGES) && write_edges(res, out)) return -1;
    if ((parts & API_PART_CELLS) && write_cells(res, out)) return -1;
    if ((parts & API_PART_TRIANGLES) && write_triangles(res, out)) return -1;
    if ((parts & API_PART_CLIPPED) && res->clipped && write_clipped(r, res, out)) {
        return -1;
    }
    if (parts & API_PART_COUNTS) {
        if (API_BUF_LIT(out, ",\"counts\":") ||
            api__put_counts(out, &res->counts, res->algorithm))
            return -1;
    }
    if (res->traced) {
        if (API_BUF_LIT(out, ",\"trace\":{\"steps\":[")) return -1;
        /* in pieces, so that a streamed answer flushes as it goes */
        for (size_t k = 0; k < res->trace.len; k += 16384) {
            size_t n = res->trace.len - k < 16384 ? res->trace.len - k : 16384;
            if (api_buf_append(out, res->trace.data + k, n)) return -1;
        }
        if (API_BUF_LIT(out, "]}")) return -1;
    }
    if (API_BUF_LIT(out, ",\"timings\":")) return -1;
    api__finish_timings(t, t0);
    if (api__put_timings(out, t)) return -1;
    return API_BUF_LIT(out, "}\n");
}
