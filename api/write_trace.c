/* write_trace.c -- operation counts and traces as JSON.
 *
 * Counts (vor_counts) are written as an object of the counts that apply to
 * the algorithm, named as in core/vor.h's table, in its order:
 *
 *   {"orient2d": 6314, "incircle": 8918, "exact": 0, ...}
 *
 * A trace is written while the algorithm runs: api__trace_step is its
 * vor_trace_fn and appends one object per step to a buffer, which the
 * JSON writer later places in "trace": {"steps": [...]}. Shapes
 * (documented in openapi.yaml, components/schemas/TraceStep; every site
 * number is an input index, -1 the vertex at infinity of a ghost
 * triangle):
 *
 *   {"kind": "order", "sites": [s, ...]}
 *   {"kind": "begin", "triangle": [a, b, c]}               incremental
 *   {"kind": "begin", "y": y, "beach": [s, ...]}             Fortune
 *   {"kind": "insert", "site": p, "located": [a, b, c],
 *    "cavity": [[a, b, c], ...], "star": [[a, b, p], ...]}   Bowyer-Watson
 *      flip adds "split": "triangle" | "edge" | "hull", and "edge": [a, b]
 *   {"kind": "flip", "removed": [a, b], "added": [p, d],
 *    "circle": [a, b, p]}
 *   {"kind": "site", "site": i, "y": y, "at": k, "arc": b}   splits arc b
 *   {"kind": "site", "site": i, "y": y, "at": k, "breakpoint": [l, r],
 *    "triangle": [l, r, i], "vertex": [x, y]}
 *   {"kind": "circle", "y": y, "arcs": [a, b, c], "at": k,
 *    "vertex": [x, y]}
 *   {"kind": "schedule" | "cancel", "arcs": [a, b, c], "y": y,
 *    "vertex": [x, y]}
 *   {"kind": "end"}
 *
 * and every step carries "counts": the counts that changed since the step
 * before (all of the algorithm's at the first), with their totals so far.
 * Fortune's beach line is not repeated at every step (points on a circle
 * keep about 2n arcs on it, and n copies of that would make a 2000-point
 * trace some 50 MB): "begin" gives it whole and every later step says
 * where it changed, which determines it exactly -- a site splits the arc
 * at k - 1 into that arc, the new one at k and another arc of the split
 * site at k + 1 (or, below a breakpoint, goes in at k alone); a circle
 * event removes the arc at k. O(1) per step but the order and the first
 * row; a few dozen bytes each. */
#include <stdio.h>
#include <string.h>

#include "codec.h"

int api__put_counts(api_buf *out, const vor_counts *c, vor_algorithm a) {
    if (api__reserve(out, VOR_COUNT_FIELDS * 48 + 4)) return -1;
    api__putc(out, '{');
    int first = 1;
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++) {
        if (!(vor_count_algorithms(i) & (1u << a))) continue;
        if (!first) api__putc(out, ',');
        first = 0;
        const char *name = vor_count_name(i);
        api__putc(out, '"');
        api__put(out, name, strlen(name));
        API__PUTS(out, "\":");
        char num[24];
        int n = snprintf(num, sizeof num, "%llu",
                         (unsigned long long)vor_count_value(c, i));
        api__put(out, num, (size_t)n);
    }
    api__putc(out, '}');
    out->data[out->len] = 0;
    return 0;
}

/* Room for one step's fixed part: a few numbers, names and the counts. */
#define STEP_ROOM (256 + 8 * API_NUM_MAXLEN + VOR_COUNT_FIELDS * 48)

static inline void put_site(api__tracer *t, uint32_t v) {
    if (v == VOR_INFINITE) {
        API__PUTS(t->out, "-1");
    } else {
        api__put_u32(t->out, api__input_index(t->s, v));
    }
}

/* [a,b] or [a,b,c] */
static void put_array(api__tracer *t, const uint32_t *v, int k) {
    api__putc(t->out, '[');
    for (int i = 0; i < k; i++) {
        if (i) api__putc(t->out, ',');
        put_site(t, v[i]);
    }
    api__putc(t->out, ']');
}

/* ,"key":[a,b] or [a,b,c] */
static void put_sites(api__tracer *t, const char *key, const uint32_t *v,
                      int k) {
    api_buf *b = t->out;
    api__putc(b, ',');
    api__putc(b, '"');
    api__put(b, key, strlen(key));
    API__PUTS(b, "\":");
    put_array(t, v, k);
}

static void put_num(api__tracer *t, const char *key, double v) {
    api_buf *b = t->out;
    api__putc(b, ',');
    api__putc(b, '"');
    api__put(b, key, strlen(key));
    API__PUTS(b, "\":");
    api__put_double(b, v);
}

static void put_vertex(api__tracer *t, const double *v) {
    API__PUTS(t->out, ",\"vertex\":[");
    api__put_double(t->out, v[0]);
    api__putc(t->out, ',');
    api__put_double(t->out, v[1]);
    api__putc(t->out, ']');
}

/* ,"key":[ -- the opening of a member whose value is a list; -1 if out of
 * memory. */
static int open_list(api__tracer *t, const char *key) {
    if (api__reserve(t->out, 16 + strlen(key))) return -1;
    api__putc(t->out, ',');
    api__putc(t->out, '"');
    api__put(t->out, key, strlen(key));
    API__PUTS(t->out, "\":[");
    return 0;
}

/* ,"key":[[a,b,c],...] for n triangles; -1 if out of memory. */
static int put_triangles(api__tracer *t, const char *key, const uint32_t *v,
                         size_t n) {
    if (open_list(t, key)) return -1;
    for (size_t i = 0; i < n; i++) {
        if (api__reserve(t->out, 40)) return -1;
        if (i) api__putc(t->out, ',');
        put_array(t, v + 3 * i, 3);
    }
    api__putc(t->out, ']');
    return 0;
}

/* A list of site numbers, ,"key":[...]; -1 if out of memory. */
static int put_list(api__tracer *t, const char *key, const uint32_t *v,
                    size_t n) {
    if (open_list(t, key)) return -1;
    for (size_t i = 0; i < n; i++) {
        if (i % 1024 == 0 && api__reserve(t->out, 1024 * 12 + 4)) return -1;
        if (i) api__putc(t->out, ',');
        put_site(t, v[i]);
    }
    api__putc(t->out, ']');
    return 0;
}

/* ,"counts":{...} with the counts that changed since the last step; all
 * of the algorithm's at the first step. */
static void put_changed(api__tracer *t, const vor_counts *c) {
    api_buf *b = t->out;
    API__PUTS(b, ",\"counts\":{");
    int first = 1;
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++) {
        uint64_t v = vor_count_value(c, i);
        if (!(vor_count_algorithms(i) & (1u << t->algorithm)) ||
            (t->steps > 1 && v == vor_count_value(&t->last, i)))
            continue;
        if (!first) api__putc(b, ',');
        first = 0;
        const char *name = vor_count_name(i);
        api__putc(b, '"');
        api__put(b, name, strlen(name));
        API__PUTS(b, "\":");
        char num[24];
        int n = snprintf(num, sizeof num, "%llu", (unsigned long long)v);
        api__put(b, num, (size_t)n);
    }
    api__putc(b, '}');
    t->last = *c;
}

void api__trace_step(void *ctx, const vor_step *st) {
    api__tracer *t = ctx;
    api_buf *b = t->out;
    if (api__reserve(b, STEP_ROOM)) return;
    if (t->steps++) api__putc(b, ',');
    API__PUTS(b, "{\"kind\":\"");
    const char *kind = vor_step_kind_name(st->kind);
    api__put(b, kind, strlen(kind));
    api__putc(b, '"');
    switch (st->kind) {
    case VOR_STEP_ORDER:
        if (put_list(t, "sites", st->order, st->n_order)) return;
        break;
    case VOR_STEP_BEGIN:
        if (st->beach) {
            put_num(t, "y", st->y);
            if (put_list(t, "beach", st->beach, st->n_beach)) return;
        } else {
            put_sites(t, "triangle", st->tri, 3);
        }
        break;
    case VOR_STEP_INSERT:
        API__PUTS(b, ",\"site\":");
        put_site(t, st->site);
        put_sites(t, "located", st->tri, 3);
        if (st->split != VOR_SPLIT_NONE) {
            API__PUTS(b, ",\"split\":\"");
            const char *split = vor_split_name(st->split);
            api__put(b, split, strlen(split));
            api__putc(b, '"');
            if (st->split == VOR_SPLIT_EDGE) put_sites(t, "edge", st->edge, 2);
        }
        if (put_triangles(t, "cavity", st->cavity, st->n_cavity) ||
            put_triangles(t, "star", st->star, st->n_star))
            return;
        break;
    case VOR_STEP_FLIP:
        put_sites(t, "removed", st->edge, 2);
        put_sites(t, "added", st->added, 2);
        put_sites(t, "circle", st->tri, 3);
        break;
    case VOR_STEP_SITE:
        API__PUTS(b, ",\"site\":");
        put_site(t, st->site);
        put_num(t, "y", st->y);
        API__PUTS(b, ",\"at\":");
        api__put_u32(b, st->at);
        if (st->arc != VOR_INFINITE) {
            API__PUTS(b, ",\"arc\":");
            put_site(t, st->arc);
        } else {
            put_sites(t, "breakpoint", st->breakpoint, 2);
            put_sites(t, "triangle", st->tri, 3);
            put_vertex(t, st->vertex);
        }
        break;
    case VOR_STEP_CIRCLE:
        put_num(t, "y", st->y);
        put_sites(t, "arcs", st->tri, 3);
        API__PUTS(b, ",\"at\":");
        api__put_u32(b, st->at);
        put_vertex(t, st->vertex);
        break;
    case VOR_STEP_SCHEDULE:
    case VOR_STEP_CANCEL:
        put_sites(t, "arcs", st->tri, 3);
        put_num(t, "y", st->y);
        put_vertex(t, st->vertex);
        break;
    default:
        break;
    }
    if (api__reserve(b, VOR_COUNT_FIELDS * 48 + 16)) return;
    if (st->counts) put_changed(t, st->counts);
    api__putc(b, '}');
    b->data[b->len] = 0;
}
