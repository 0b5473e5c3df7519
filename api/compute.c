/* compute.c -- from a parsed request to a result: sites, diagram, clipping,
 * triangles and their timings; and the comparison of all algorithms.
 *
 * The steps are the core's (vor_sites_new, vor_compute, vor_clip,
 * vor_diagram_triangles); this file maps their statuses to problems,
 * decides which optional steps a request needs, and times each step with
 * the monotonic clock. A comparison prepares the sites once and runs every
 * algorithm on them `repeat` times in rounds whose order rotates, so that
 * caches warmed by one algorithm, or a machine slowing down, do not always
 * favour the same one; it keeps each algorithm's first diagram, checks
 * every later run against it (vor_diagram_equal) and the algorithms
 * against each other (a field-by-field walk explains the first
 * difference), and reports the median, minimum and maximum of every phase.
 * Cost: the core's times the runs, plus O(n) a run for the checks. */
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

/* Validates and de-duplicates r's points into *sites; a non-finite point
 * is API_INVALID naming it, a failure of the core (out of memory, too
 * many points) is the core's problem, with its status in *core (VOR_OK
 * when the failure is not the core's). */
static api_code prepare(const api_request *r, vor_sites **sites,
                        api_problem *p, vor_status *core) {
    *core = VOR_OK;
    size_t bad = 0;
    vor_status st = vor_sites_new(r->xy, r->n, sites, &bad);
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
    if (prepare(r, &res->sites, p, core) != API_OK) return p->code;
    double t1 = api_clock_ms();
    res->t.prepare_ms = t1 - t0;

    api__tracer tracer = {&res->trace, res->sites, r->algorithm, {0}, 0};
    vor_options opt = {.counts = &res->counts,
                       .trace = r->trace ? api__trace_step : NULL,
                       .trace_ctx = &tracer,
                       .stop = r->stop,
                       .stop_ctx = r->stop_ctx};
    vor_status st = vor_compute_ex(res->sites, r->algorithm, &opt, &res->diagram);
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
    if (r->repeat != 0) {
        api_timings keep = res->t;
        api_result_clear(res);
        res->t = keep;
        return api__problem_at(p, API_INVALID, NULL, 0,
                               "repeat %d: repeat applies only to a "
                               "comparison of the algorithms (POST /compare, "
                               "voronoi --compare); one diagram is computed "
                               "once",
                               r->repeat);
    }
    vor_status core;
    return compute(r, res, p, &core);
}

void api_compare_init(api_compare *c) {
    memset(c, 0, sizeof *c);
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) api_result_init(&c->res[a]);
}

void api_compare_clear(api_compare *c) {
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) api_result_clear(&c->res[a]);
    vor_sites_free(c->sites);
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

/* The median of v[0..n-1] (the mean of the middle two for even n), n <=
 * API_REPEAT_MAX; 0 for n == 0. */
static double median(const double *v, int n) {
    double w[API_REPEAT_MAX];
    for (int i = 0; i < n; i++) {
        int j = i;
        for (; j > 0 && w[j - 1] > v[i]; j--) w[j] = w[j - 1];
        w[j] = v[i];
    }
    if (n == 0) return 0;
    return n % 2 ? w[n / 2] : (w[n / 2 - 1] + w[n / 2]) / 2;
}

/* One run of algorithm a on c->sites: the diagram, clipped to box when
 * box != NULL (the clipped diagram is not kept), timed into c->runs.
 * Returns the core's status; on success *d is the new diagram. */
static vor_status run_once(api_compare *c, const api_request *r,
                           vor_algorithm a, const double *box,
                           vor_diagram **d) {
    double t0 = api_clock_ms();
    vor_counts counts;
    vor_options opt = {.counts = &counts, .stop = r->stop,
                       .stop_ctx = r->stop_ctx};
    vor_status st = vor_compute_ex(c->sites, a, &opt, d);
    double t1 = api_clock_ms(), t2 = t1;
    if (st == VOR_OK) c->res[a].counts = counts; /* the same every run */
    if (st == VOR_OK && box != NULL) {
        vor_clipped *cl = NULL;
        st = vor_clip(*d, c->sites, box, &cl);
        t2 = api_clock_ms();
        vor_clipped_free(cl);
    }
    if (st != VOR_OK) {
        vor_diagram_free(*d);
        *d = NULL;
        return st;
    }
    double *run = c->runs[a][c->n_runs[a]++];
    run[API_RUN_COMPUTE] = t1 - t0;
    run[API_RUN_CLIP] = t2 - t1;
    run[API_RUN_TOTAL] = c->t.prepare_ms + (t1 - t0) + (t2 - t1);
    c->t.compute_ms += t1 - t0;
    c->t.clip_ms += t2 - t1;
    return VOR_OK;
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
    if (r->repeat > 1 && r->n > API_REPEAT_WORK_MAX / (size_t)r->repeat) {
        return api__problem_at(
            p, API_INVALID, NULL, 0,
            "repeat %d with %zu points: repeat times points must be at most "
            "%zu, so at most %zu repeats here",
            r->repeat, r->n, API_REPEAT_WORK_MAX,
            r->n > API_REPEAT_WORK_MAX ? (size_t)1 : API_REPEAT_WORK_MAX / r->n);
    }

    double t0 = api_clock_ms();
    vor_status core;
    if (prepare(r, &c->sites, p, &core) != API_OK) {
        api_compare_clear(c);
        return p->code;
    }
    c->t.prepare_ms = api_clock_ms() - t0;
    c->repeat = api_compare_repeat(r, c->sites->n);
    c->has_clip = r->has_bounds;
    const double *box = r->has_bounds ? r->bounds : NULL;

    /* Round k runs the algorithms in the order k, k+1, ... (mod count). */
    char run_diff[256] = "";
    for (int k = 0; k < c->repeat; k++) {
        for (int i = 0; i < VOR_ALGORITHM_COUNT; i++) {
            vor_algorithm a = (vor_algorithm)((k + i) % VOR_ALGORITHM_COUNT);
            api_result *res = &c->res[a];
            if (c->status[a] != VOR_OK) continue;
            vor_diagram *d = NULL;
            vor_status st = run_once(c, r, a, box, &d);
            if (st != VOR_OK && st != VOR_ENOMEM && st != VOR_EUNAVAILABLE) {
                /* Not the algorithm's own failure: the request's. */
                api_problem_from_status(p, st);
                snprintf(p->detail, sizeof p->detail, "%s: %s",
                         vor_algorithm_name(a), vor_status_message(st));
                if (st == VOR_EBOUNDS) {
                    snprintf(p->pointer, sizeof p->pointer, "/bounds");
                }
                api_compare_clear(c);
                return p->code;
            }
            if (st != VOR_OK) {
                c->status[a] = st;
                vor_diagram_free(res->diagram);
                res->diagram = NULL;
                continue;
            }
            if (res->diagram == NULL) {
                res->diagram = d;
                continue;
            }
            if (run_diff[0] == 0 && !vor_diagram_equal(res->diagram, d)) {
                char first[128] = "";
                const char *name = vor_algorithm_name(a);
                api__diagram_difference(res->diagram, d, "run 1", "this run",
                                        first, sizeof first);
                snprintf(run_diff, sizeof run_diff,
                         "%s: run %d gave another diagram than run 1 (%s)",
                         name, c->n_runs[a], first);
            }
            vor_diagram_free(d);
        }
    }

    int ok = 0;
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        api_result *res = &c->res[a];
        res->algorithm = (vor_algorithm)a;
        if (c->status[a] != VOR_OK) continue;
        ok++;
        double v[API_REPEAT_MAX];
        double med[API_RUN_PHASES];
        for (int ph = 0; ph < API_RUN_PHASES; ph++) {
            for (int i = 0; i < c->n_runs[a]; i++) v[i] = c->runs[a][i][ph];
            med[ph] = median(v, c->n_runs[a]);
        }
        res->t.prepare_ms = c->t.prepare_ms;
        res->t.compute_ms = med[API_RUN_COMPUTE];
        res->t.clip_ms = med[API_RUN_CLIP];
        res->t.total_ms = med[API_RUN_TOTAL];
    }
    if (ok == 0 && c->status[0] == VOR_ENOMEM) {
        api_compare_clear(c);
        return api_problem_from_status(p, VOR_ENOMEM);
    }
    c->agree = ok == VOR_ALGORITHM_COUNT && run_diff[0] == 0;
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
    if (c->disagreement[0] == 0 && run_diff[0] != 0) {
        snprintf(c->disagreement, sizeof c->disagreement, "%s", run_diff);
    }
    c->t.total_ms = c->t.queue_ms + c->t.parse_ms + c->t.prepare_ms +
                    c->t.compute_ms + c->t.clip_ms;
    p->code = API_OK;
    return API_OK;
}
