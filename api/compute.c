/* compute.c -- from a parsed request to a result: sites, diagram, clipping,
 * triangles and their timings; and the comparison of all algorithms.
 *
 * The steps are the core's (vor_sites_new, vor_compute, vor_clip,
 * vor_diagram_triangles); this file maps their statuses to problems,
 * decides which optional steps a request needs, and times each step with
 * the monotonic clock. A comparison runs every algorithm on its own copy of
 * the sites and compares the diagrams field by field (vor_diagram_equal
 * decides; a field-by-field walk explains the first difference). Cost: the
 * core's, plus O(n) for the comparison. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "codec.h"

double api_clock_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

void api_result_init(api_result *res) {
    memset(res, 0, sizeof *res);
    res->algorithm = VOR_FORTUNE;
}

void api_result_clear(api_result *res) {
    vor_clipped_free(res->clipped);
    vor_diagram_free(res->diagram);
    vor_sites_free(res->sites);
    free(res->triangles);
    api_buf_clear(&res->trace);
    api_result_init(res);
}

/* The trace's conditions (api_compute): JSON, at most
 * API_TRACE_MAX_POINTS points. */
static api_code check_trace(const api_request *r, api_problem *p) {
    if (!r->trace) return API_OK;
    if (r->format != API_FMT_JSON) {
        return api__problem_at(p, API_INVALID, "/trace", 0,
                               "trace is written in JSON only, not with "
                               "format %s",
                               api__format_name(r->format));
    }
    if (r->n > API_TRACE_MAX_POINTS) {
        return api__problem_at(p, API_INVALID, "/trace", 0,
                               "trace: at most %d points can be traced, this "
                               "request has %zu",
                               API_TRACE_MAX_POINTS, r->n);
    }
    return API_OK;
}

/* Like api_compute, also reporting the core's status (VOR_OK when the
 * failure is not the core's). */
static api_code compute(const api_request *r, api_result *res, api_problem *p,
                        vor_status *core) {
    api_timings keep = res->t;
    api_result_clear(res);
    res->t.queue_ms = keep.queue_ms;
    res->t.parse_ms = keep.parse_ms;
    res->algorithm = r->algorithm;
    *core = VOR_OK;
    if (check_trace(r, p) != API_OK) return p->code;

    double t0 = api_clock_ms();
    size_t bad = 0;
    vor_status st = vor_sites_new(r->xy, r->n, &res->sites, &bad);
    if (st == VOR_ENONFINITE) {
        int k = bad < r->n && isfinite(r->xy[2 * bad]) ? 1 : 0;
        char ptr[64];
        snprintf(ptr, sizeof ptr, "/points/%zu/%d", bad, k);
        double v = bad < r->n ? r->xy[2 * bad + k] : NAN;
        return api__problem_at(p, API_INVALID, ptr, 0,
                               "points[%zu][%d] is %s, not a finite number",
                               bad, k,
                               isnan(v) ? "NaN" : v > 0 ? "Infinity" : "-Infinity");
    }
    if (st != VOR_OK) {
        *core = st;
        api_problem_from_status(p, st);
        if (st == VOR_ETOOMANY) {
            snprintf(p->detail, sizeof p->detail, "%zu points: more than %zu",
                     r->n, (size_t)VOR_MAX_POINTS);
        }
        return p->code;
    }
    double t1 = api_clock_ms();
    res->t.prepare_ms = t1 - t0;

    api__tracer tracer = {&res->trace, res->sites, r->algorithm, {0}, 0};
    vor_options opt = {&res->counts, r->trace ? api__trace_step : NULL,
                       &tracer};
    st = vor_compute_ex(res->sites, r->algorithm, &opt, &res->diagram);
    res->traced = r->trace;
    if (st == VOR_OK && res->trace.oom) st = VOR_ENOMEM;
    if (st == VOR_OK && (api__effective_parts(r) & API_PART_TRIANGLES)) {
        st = vor_diagram_triangles(res->diagram, res->sites, &res->triangles,
                                   &res->n_triangles);
    }
    if (st != VOR_OK) {
        *core = st;
        api_problem_from_status(p, st);
        snprintf(p->detail, sizeof p->detail, "%s: %s",
                 vor_algorithm_name(r->algorithm), vor_status_message(st));
        api_result_clear(res);
        return p->code;
    }
    double t2 = api_clock_ms();
    res->t.compute_ms = t2 - t1;

    if (api__needs_clip(r)) {
        double box[4];
        if (r->has_bounds) {
            memcpy(box, r->bounds, sizeof box);
        } else {
            api__default_box(res->sites, box);
        }
        st = vor_clip(res->diagram, res->sites, box, &res->clipped);
        if (st != VOR_OK) {
            *core = st;
            api_problem_from_status(p, st);
            snprintf(p->detail, sizeof p->detail, "clipping to [%g, %g, %g, %g]: %s",
                     box[0], box[1], box[2], box[3], vor_status_message(st));
            if (st == VOR_EBOUNDS) snprintf(p->pointer, sizeof p->pointer, "/bounds");
            api_result_clear(res);
            return p->code;
        }
        res->t.clip_ms = api_clock_ms() - t2;
    }
    res->t.total_ms = res->t.queue_ms + res->t.parse_ms + res->t.prepare_ms +
                      res->t.compute_ms + res->t.clip_ms;
    p->code = API_OK;
    return API_OK;
}

api_code api_compute(const api_request *r, api_result *res, api_problem *p) {
    vor_status core;
    return compute(r, res, p, &core);
}

void api_compare_init(api_compare *c) {
    memset(c, 0, sizeof *c);
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) api_result_init(&c->res[a]);
}

void api_compare_clear(api_compare *c) {
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) api_result_clear(&c->res[a]);
    api_compare_init(c);
}

int api__diagram_difference(const vor_diagram *p, const vor_diagram *q,
                            const char *a, const char *b, char *msg,
                            size_t size) {
#define DIFF_COUNT(field, what)                                              \
    if (p->field != q->field) {                                              \
        snprintf(msg, size, "%s has %zu " what ", %s has %zu", b, q->field, a, \
                 p->field);                                                  \
        return 1;                                                            \
    }
    DIFF_COUNT(n_sites, "sites")
    DIFF_COUNT(n_vertices, "vertices")
    DIFF_COUNT(n_edges, "edges")
    DIFF_COUNT(n_rays, "rays")
#undef DIFF_COUNT
    for (size_t v = 0; v < p->n_vertices; v++) {
        const uint32_t *ps = p->vertex_sites + 3 * v, *qs = q->vertex_sites + 3 * v;
        const double *px = p->vertex_xy + 2 * v, *qx = q->vertex_xy + 2 * v;
        if (memcmp(ps, qs, 3 * sizeof *ps) || memcmp(px, qx, 2 * sizeof *px)) {
            snprintf(msg, size,
                     "vertex %zu: %s has sites (%u, %u, %u) at (%.17g, %.17g), "
                     "%s has (%u, %u, %u) at (%.17g, %.17g)",
                     v, a, ps[0], ps[1], ps[2], px[0], px[1], b, qs[0], qs[1],
                     qs[2], qx[0], qx[1]);
            return 1;
        }
    }
    for (size_t e = 0; e < p->n_edges; e++) {
        const uint32_t *ps = p->edge_sites + 2 * e, *qs = q->edge_sites + 2 * e;
        const int32_t *pe = p->edge_ends + 2 * e, *qe = q->edge_ends + 2 * e;
        if (memcmp(ps, qs, 2 * sizeof *ps) || memcmp(pe, qe, 2 * sizeof *pe)) {
            snprintf(msg, size,
                     "edge %zu: %s has sites (%u, %u) ends (%d, %d), %s has "
                     "sites (%u, %u) ends (%d, %d) (site indices)",
                     e, a, ps[0], ps[1], pe[0], pe[1], b, qs[0], qs[1], qe[0],
                     qe[1]);
            return 1;
        }
    }
    for (size_t r = 0; r < p->n_rays; r++) {
        if (p->ray_edge[r] != q->ray_edge[r] ||
            memcmp(p->ray_dir + 2 * r, q->ray_dir + 2 * r, 2 * sizeof(double))) {
            snprintf(msg, size, "ray %zu differs: %s edge %u, %s edge %u", r, a,
                     p->ray_edge[r], b, q->ray_edge[r]);
            return 1;
        }
    }
    for (size_t i = 0; i < p->n_sites; i++) {
        if (p->cell_start[i + 1] != q->cell_start[i + 1] ||
            p->cell_bounded[i] != q->cell_bounded[i] ||
            memcmp(p->cell_edges + p->cell_start[i], q->cell_edges + q->cell_start[i],
                   (p->cell_start[i + 1] - p->cell_start[i]) * sizeof(uint32_t))) {
            snprintf(msg, size, "cell of site %zu differs between %s and %s", i,
                     a, b);
            return 1;
        }
    }
    return 0;
}

api_code api_compare_run(const api_request *r, api_compare *c, api_problem *p) {
    api_timings shared = c->t;
    api_compare_clear(c);
    c->t.queue_ms = shared.queue_ms;
    c->t.parse_ms = shared.parse_ms;
    if (r->trace) {
        return api__problem_at(p, API_INVALID, "/trace", 0,
                               "trace is available from /voronoi, which "
                               "runs one algorithm; /compare does not trace");
    }
    api_request sub = *r;
    sub.format = API_FMT_JSON;
    sub.parts = 0;
    sub.parts_given = 1;
    sub.has_bounds = 0;
    double work = 0;
    int ok = 0;
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        sub.algorithm = (vor_algorithm)a;
        api_problem pa;
        vor_status core;
        api_code code = compute(&sub, &c->res[a], &pa, &core);
        if (code != API_OK && core == VOR_OK) { /* the input's fault */
            *p = pa;
            api_compare_clear(c);
            return code;
        }
        if (code != API_OK && core == VOR_ETOOMANY) {
            *p = pa;
            api_compare_clear(c);
            return code;
        }
        c->status[a] = code == API_OK ? VOR_OK : core;
        ok += code == API_OK;
        work += c->res[a].t.prepare_ms + c->res[a].t.compute_ms;
    }
    if (ok == 0 && c->status[0] == VOR_ENOMEM) {
        api_compare_clear(c);
        return api_problem_from_status(p, VOR_ENOMEM);
    }
    c->agree = ok == VOR_ALGORITHM_COUNT;
    int ref = -1;
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        const char *name = vor_algorithm_name((vor_algorithm)a);
        if (c->status[a] != VOR_OK) {
            if (c->disagreement[0] == 0) {
                snprintf(c->disagreement, sizeof c->disagreement, "%s: %s", name,
                         vor_status_message(c->status[a]));
            }
            continue;
        }
        if (ref < 0) {
            ref = a;
            continue;
        }
        const vor_diagram *dp = c->res[ref].diagram, *dq = c->res[a].diagram;
        if (!vor_diagram_equal(dp, dq)) {
            c->agree = 0;
            if (c->disagreement[0] == 0 &&
                !api__diagram_difference(dp, dq, vor_algorithm_name((vor_algorithm)ref),
                                  name, c->disagreement, sizeof c->disagreement)) {
                snprintf(c->disagreement, sizeof c->disagreement,
                         "%s and %s differ", vor_algorithm_name((vor_algorithm)ref),
                         name);
            }
        }
    }
    c->t.total_ms = c->t.queue_ms + c->t.parse_ms + work;
    p->code = API_OK;
    return API_OK;
}
