/* write.c -- the writers' entry points: format dispatch, the timings
 * member every document ends with, and the comparison document.
 *
 * Each format has its own file (write_json.c, write_geojson.c,
 * write_svg.c, write_binary.c) appending to one api_buf; this file measures
 * the serialisation time they report and turns a failed allocation into a
 * problem with an empty buffer. Every document but the binary one ends
 * with a newline, so that it prints and concatenates cleanly in a shell. */
#include <math.h>
#include <string.h>

#include "codec.h"

void api__finish_timings(api_timings *t, double t0) {
    double parts = t->queue_ms + t->parse_ms + t->prepare_ms + t->compute_ms +
                   t->clip_ms;
    t->serialize_ms = api_clock_ms() - t0;
    t->total_ms = (t->total_ms > parts ? t->total_ms : parts) + t->serialize_ms;
}

/* Milliseconds rounded to the microsecond, so the document shows "12.345"
 * rather than seventeen digits of clock noise: the double nearest k / 1000
 * for k = round(v * 1000), written as api__put_double writes it. For
 * 0 <= k < 2^32 (49 days), that is k / 1000 itself, digit by digit: a
 * decimal of at most 15 significant digits is the only one that short to
 * read back as its double, so it is the shortest, and the converter
 * writes it in plain notation without trailing zeros. Anything else (-0,
 * negative, huge, not finite) goes through the converter. Every request
 * writes seven of these; the digits cost a tenth of the converter. */
static void put_ms(api_buf *out, double v) {
    double k = round(v * 1000);
    if (!(k >= 0 && k < 4294967296.0) || signbit(k)) {
        api__put_double(out, k / 1000);
        return;
    }
    uint32_t q = (uint32_t)k, frac = q % 1000;
    api__put_u32(out, q / 1000);
    if (frac != 0) {
        char d[3] = {(char)('0' + frac / 100), (char)('0' + frac / 10 % 10),
                     (char)('0' + frac % 10)};
        api__putc(out, '.');
        api__put(out, d, d[2] != '0' ? 3 : d[1] != '0' ? 2 : 1);
    }
}

/* The timings' members, "queue_ms":...,"total_ms":... (no braces). */
static int put_timing_members(api_buf *out, const api_timings *t) {
    static const char *const keys[] = {
        "\"queue_ms\":", ",\"parse_ms\":",     ",\"prepare_ms\":",
        ",\"compute_ms\":", ",\"clip_ms\":",    ",\"serialize_ms\":",
        ",\"total_ms\":",
    };
    const double v[] = {t->queue_ms,   t->parse_ms,     t->prepare_ms,
                        t->compute_ms, t->clip_ms,      t->serialize_ms,
                        t->total_ms};
    if (api__reserve(out, 7 * (20 + API_NUM_MAXLEN) + 2)) return -1;
    for (int i = 0; i < 7; i++) {
        api__put(out, keys[i], strlen(keys[i]));
        put_ms(out, v[i]);
    }
    out->data[out->len] = 0;
    return 0;
}

int api__put_timings(api_buf *out, const api_timings *t) {
    if (API_BUF_LIT(out, "{") || put_timing_members(out, t)) return -1;
    return API_BUF_LIT(out, "}");
}

/* format=timings: the timings labelled with the algorithm and the sizes,
 * one flat object, so that rows of a scripted sweep carry their own
 * labels: {"algorithm":"fortune","n_input":N,"n_sites":M,"queue_ms":...};
 * with include=counts, the counts last ("counts":{...}). */
static int write_timings_only(const api_request *r, const api_result *res,
                              api_timings *t, double t0, api_buf *out) {
    const char *name = vor_algorithm_name(res->algorithm);
    if (api__reserve(out, 64 + strlen(name))) return -1;
    API__PUTS(out, "{\"algorithm\":\"");
    api__put(out, name, strlen(name));
    API__PUTS(out, "\",\"n_input\":");
    api__put_u32(out, (uint32_t)res->sites->n_input);
    API__PUTS(out, ",\"n_sites\":");
    api__put_u32(out, (uint32_t)res->sites->n);
    api__putc(out, ',');
    api__finish_timings(t, t0);
    if (put_timing_members(out, t)) return -1;
    if ((api__effective_parts(r) & API_PART_COUNTS) &&
        (API_BUF_LIT(out, ",\"counts\":") ||
         api__put_counts(out, &res->counts, res->algorithm)))
        return -1;
    return API_BUF_LIT(out, "}\n");
}

void api__midpoint(const double *a, const double *b, double *out) {
    for (int k = 0; k < 2; k++) {
        double m = (a[k] + b[k]) / 2;
        if (!isfinite(m)) m = a[k] / 2 + b[k] / 2; /* the sum overflowed */
        out[k] = m;
    }
}

static api_code out_of_memory(api_buf *out, api_problem *p) {
    api_buf_clear(out);
    return api_problem_set(p, API_UNAVAILABLE,
                           "out of memory while writing the response");
}

api_code api_write_result(const api_request *r, const api_result *res,
                          api_timings *t, api_buf *out, api_problem *p) {
    double t0 = api_clock_ms();
    if (res->sites == NULL || res->diagram == NULL) {
        return api_problem_set(p, API_INTERNAL, "no result to write");
    }
    int rc;
    switch (r->format) {
    case API_FMT_GEOJSON: rc = api__write_geojson(r, res, t, t0, out); break;
    case API_FMT_SVG: rc = api__write_svg(r, res, t, t0, out); break;
    case API_FMT_BINARY: rc = api__write_binary(r, res, t, t0, out); break;
    case API_FMT_TIMINGS: rc = write_timings_only(r, res, t, t0, out); break;
    default: rc = api__write_json(r, res, t, t0, out); break;
    }
    if (rc != 0 || out->oom) return out_of_memory(out, p);
    p->code = API_OK;
    return API_OK;
}

/* "name":{"median":m,"min":a,"max":b} for phase ph of c's runs of a. */
static void put_spread(api_buf *out, const api_compare *c, int a, int ph,
                       const char *name, double med) {
    double lo = 0, hi = 0;
    for (int i = 0; i < c->n_runs[a]; i++) {
        double v = c->runs[a][i][ph];
        if (i == 0 || v < lo) lo = v;
        if (i == 0 || v > hi) hi = v;
    }
    if (api__reserve(out, 64 + 3 * API_NUM_MAXLEN)) return;
    api__putc(out, '"');
    api__put(out, name, strlen(name));
    API__PUTS(out, "\":{\"median\":");
    put_ms(out, med);
    API__PUTS(out, ",\"min\":");
    put_ms(out, lo);
    API__PUTS(out, ",\"max\":");
    put_ms(out, hi);
    api__putc(out, '}');
}

api_code api_write_compare(const api_request *r, const api_compare *c,
                           api_buf *out, api_problem *p) {
    (void)r;
    double t0 = api_clock_ms();
    const vor_sites *s = c->sites;
    for (int a = 0; a < VOR_ALGORITHM_COUNT && s == NULL; a++) s = c->res[a].sites;
    api_buf_printf(out, "{\"n_input\":%zu,\"n_sites\":%zu,\"repeat\":%d,"
                        "\"agree\":%s,\"disagreement\":",
                   s ? s->n_input : 0, s ? s->n : 0, c->repeat,
                   c->agree ? "true" : "false");
    if (c->disagreement[0]) {
        api__put_json_string(out, c->disagreement);
    } else {
        API_BUF_LIT(out, "null");
    }
    API_BUF_LIT(out, ",\"algorithms\":[");
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        const api_result *res = &c->res[a];
        api_problem pa;
        api_code code = api_problem_from_status(&pa, c->status[a]);
        api_buf_printf(out, "%s{\"algorithm\":\"%s\",\"status\":\"%s\"",
                       a ? "," : "", vor_algorithm_name((vor_algorithm)a),
                       code == API_OK ? "ok" : api_code_slug(code));
        if (code != API_OK) {
            API_BUF_LIT(out, ",\"detail\":");
            api__put_json_string(out, pa.detail);
        } else {
            const vor_diagram *d = res->diagram;
            api_buf_printf(out, ",\"n_vertices\":%zu,\"n_edges\":%zu,"
                                "\"n_rays\":%zu",
                           d->n_vertices, d->n_edges, d->n_rays);
            API_BUF_LIT(out, ",\"counts\":");
            api__put_counts(out, &res->counts, (vor_algorithm)a);
        }
        API_BUF_LIT(out, ",\"timings\":");
        api__put_timings(out, &res->t);
        if (code == API_OK) {
            /* The spread of every phase measured per run; the medians are
             * the timings' own. */
            API_BUF_LIT(out, ",\"spread\":{");
            put_spread(out, c, a, API_RUN_COMPUTE, "compute_ms", res->t.compute_ms);
            if (c->has_clip) {
                API_BUF_LIT(out, ",");
                put_spread(out, c, a, API_RUN_CLIP, "clip_ms", res->t.clip_ms);
            }
            API_BUF_LIT(out, ",");
            put_spread(out, c, a, API_RUN_TOTAL, "total_ms", res->t.total_ms);
            API_BUF_LIT(out, "},\"runs_ms\":[");
            for (int i = 0; i < c->n_runs[a]; i++) {
                if (api__reserve(out, API_NUM_MAXLEN + 2)) break;
                if (i) api__putc(out, ',');
                put_ms(out, c->runs[a][i][API_RUN_COMPUTE]);
            }
            API_BUF_LIT(out, "]");
        }
        API_BUF_LIT(out, "}");
    }
    API_BUF_LIT(out, "],\"timings\":");
    api_timings t = c->t;
    api__finish_timings(&t, t0);
    api__put_timings(out, &t);
    API_BUF_LIT(out, "}\n");
    if (out->oom) return out_of_memory(out, p);
    p->code = API_OK;
    return API_OK;
}
