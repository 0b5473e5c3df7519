/* metrics.c -- counters behind GET /metrics.
 *
 * Representation: fixed arrays of atomic counters, no allocation after
 * srv_metrics_new: requests[route][status - 100] (500 statuses x 10
 * routes), per-route histogram buckets (non-cumulative; made cumulative
 * when rendered), latency sums, per-algorithm points, runs and compute
 * time. Durations are summed as whole nanoseconds so that every counter is
 * an integer that one relaxed atomic addition updates: a request costs
 * four additions and no lock (a mutex shared by every connection thread
 * was taken on every request before). A render reads each counter once and
 * formats as it goes; it is not a snapshot of one instant, but each
 * histogram's _count is the sum of its buckets as read, so the two always
 * agree. Render cost is O(routes x (statuses + buckets)).
 */
#include "metrics.h"

#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>

#define N_STATUS 500 /* 100 .. 599 */

typedef _Atomic uint64_t counter;

struct srv_metrics {
    counter requests[SRV_ROUTE_COUNT][N_STATUS];
    counter aborted[SRV_ROUTE_COUNT];
    counter bucket[SRV_ROUTE_COUNT][SRV_N_LATENCY_BUCKETS + 1];
    counter latency_ns[SRV_ROUTE_COUNT];
    counter points[VOR_ALGORITHM_COUNT];
    counter runs[VOR_ALGORITHM_COUNT];
    counter compute_ns[VOR_ALGORITHM_COUNT];
    counter stopped;
};

static const double bounds[SRV_N_LATENCY_BUCKETS] = SRV_LATENCY_BUCKETS;

static void add(counter *c, uint64_t v) {
    atomic_fetch_add_explicit(c, v, memory_order_relaxed);
}

static uint64_t get(const counter *c) {
    return atomic_load_explicit((counter *)c, memory_order_relaxed);
}

/* Seconds (already checked >= 0) as whole nanoseconds, saturating. */
static uint64_t to_ns(double seconds) {
    double ns = nearbyint(seconds * 1e9);
    return ns < 1.8e19 ? (uint64_t)ns : UINT64_MAX / 2;
}

srv_metrics *srv_metrics_new(void) {
    srv_metrics *m = malloc(sizeof *m);
    if (m == NULL) return NULL;
    /* Every counter starts at zero (atomic_init, not memset, is the
     * portable way to give an atomic object its first value). */
    for (int r = 0; r < SRV_ROUTE_COUNT; r++) {
        for (int s = 0; s < N_STATUS; s++) atomic_init(&m->requests[r][s], 0);
        for (int b = 0; b <= SRV_N_LATENCY_BUCKETS; b++)
            atomic_init(&m->bucket[r][b], 0);
        atomic_init(&m->aborted[r], 0);
        atomic_init(&m->latency_ns[r], 0);
    }
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        atomic_init(&m->points[a], 0);
        atomic_init(&m->runs[a], 0);
        atomic_init(&m->compute_ns[a], 0);
    }
    return m;
}

void srv_metrics_free(srv_metrics *m) { free(m); }

void srv_metrics_request(srv_metrics *m, srv_route route, int status,
                         double seconds) {
    if ((unsigned)route >= SRV_ROUTE_COUNT) route = SRV_ROUTE_OTHER;
    if (status < 100 || status > 599) status = 599;
    if (!(seconds >= 0)) seconds = 0;
    int b = 0;
    while (b < SRV_N_LATENCY_BUCKETS && seconds > bounds[b]) b++;
    add(&m->requests[route][status - 100], 1);
    add(&m->latency_ns[route], to_ns(seconds));
    add(&m->bucket[route][b], 1);
}

void srv_metrics_aborted(srv_metrics *m, srv_route route) {
    if ((unsigned)route >= SRV_ROUTE_COUNT) route = SRV_ROUTE_OTHER;
    add(&m->aborted[route], 1);
}

void srv_metrics_compute(srv_metrics *m, vor_algorithm a, size_t n,
                         double seconds) {
    if ((unsigned)a >= VOR_ALGORITHM_COUNT) return;
    if (!(seconds >= 0)) seconds = 0;
    add(&m->points[a], n);
    add(&m->runs[a], 1);
    add(&m->compute_ns[a], to_ns(seconds));
}

void srv_metrics_stopped(srv_metrics *m) { add(&m->stopped, 1); }

static void header(api_buf *out, const char *name, const char *type,
                   const char *help) {
    api_buf_printf(out, "# HELP %s %s\n# TYPE %s %s\n", name, help, name,
                   type);
}

void srv_metrics_render(srv_metrics *m, const srv_gauges *g, api_buf *out) {
    const srv_metrics *c = m;
    header(out, "voronoid_requests_total", "counter",
           "Requests answered, by route and HTTP status.");
    for (int r = 0; r < SRV_ROUTE_COUNT; r++)
        for (int s = 0; s < N_STATUS; s++) {
            uint64_t v = get(&c->requests[r][s]);
            if (v)
                api_buf_printf(out,
                               "voronoid_requests_total{route=\"%s\","
                               "status=\"%d\"} %llu\n",
                               srv_route_name((srv_route)r), s + 100,
                               (unsigned long long)v);
        }

    header(out, "voronoid_requests_aborted_total", "counter",
           "Requests that ended before an answer was sent (client gone, "
           "connection timed out).");
    for (int r = 0; r < SRV_ROUTE_COUNT; r++)
        api_buf_printf(out,
                       "voronoid_requests_aborted_total{route=\"%s\"} %llu\n",
                       srv_route_name((srv_route)r),
                       (unsigned long long)get(&c->aborted[r]));

    header(out, "voronoid_request_duration_seconds", "histogram",
           "Time from a request's arrival to its answer being queued, by "
           "route.");
    for (int r = 0; r < SRV_ROUTE_COUNT; r++) {
        const char *name = srv_route_name((srv_route)r);
        uint64_t cum = 0;
        for (int b = 0; b < SRV_N_LATENCY_BUCKETS; b++) {
            cum += get(&c->bucket[r][b]);
            api_buf_printf(out,
                           "voronoid_request_duration_seconds_bucket{route="
                           "\"%s\",le=\"%g\"} %llu\n",
                           name, bounds[b], (unsigned long long)cum);
        }
        cum += get(&c->bucket[r][SRV_N_LATENCY_BUCKETS]);
        api_buf_printf(out,
                       "voronoid_request_duration_seconds_bucket{route="
                       "\"%s\",le=\"+Inf\"} %llu\n"
                       "voronoid_request_duration_seconds_sum{route=\"%s\"} "
                       "%.9g\n"
                       "voronoid_request_duration_seconds_count{route="
                       "\"%s\"} %llu\n",
                       name, (unsigned long long)cum, name,
                       (double)get(&c->latency_ns[r]) / 1e9, name,
                       (unsigned long long)cum);
    }

    header(out, "voronoid_points_total", "counter",
           "Input points processed, by algorithm.");
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++)
        api_buf_printf(out, "voronoid_points_total{algorithm=\"%s\"} %llu\n",
                       vor_algorithm_name((vor_algorithm)a),
                       (unsigned long long)get(&c->points[a]));
    header(out, "voronoid_computations_total", "counter",
           "Diagrams computed, by algorithm.");
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++)
        api_buf_printf(out,
                       "voronoid_computations_total{algorithm=\"%s\"} %llu\n",
                       vor_algorithm_name((vor_algorithm)a),
                       (unsigned long long)get(&c->runs[a]));
    header(out, "voronoid_compute_seconds_total", "counter",
           "Seconds spent computing diagrams, by algorithm.");
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++)
        api_buf_printf(out,
                       "voronoid_compute_seconds_total{algorithm=\"%s\"} "
                       "%.9g\n",
                       vor_algorithm_name((vor_algorithm)a),
                       (double)get(&c->compute_ns[a]) / 1e9);

    header(out, "voronoid_computations_stopped_total", "counter",
           "Computations stopped unfinished because their answer was given "
           "up on (--timeout passed, shutdown, or the client hung up).");
    api_buf_printf(out, "voronoid_computations_stopped_total %llu\n",
                   (unsigned long long)get(&c->stopped));
    header(out, "voronoid_queue_depth", "gauge",
           "Requests waiting for a compute worker.");
    api_buf_printf(out, "voronoid_queue_depth %zu\n", g->queue_depth);
    header(out, "voronoid_queue_capacity", "gauge",
           "Requests that may wait before 503.");
    api_buf_printf(out, "voronoid_queue_capacity %zu\n", g->queue_capacity);
    header(out, "voronoid_workers_busy", "gauge",
           "Compute workers running a request.");
    api_buf_printf(out, "voronoid_workers_busy %zu\n", g->running);
    header(out, "voronoid_workers", "gauge", "Compute workers.");
    api_buf_printf(out, "voronoid_workers %zu\n", g->workers);
    header(out, "voronoid_in_flight", "gauge",
           "Requests received and not yet answered.");
    api_buf_printf(out, "voronoid_in_flight %zu\n", g->in_flight);
    header(out, "voronoid_ready", "gauge",
           "1 when accepting work, 0 while shutting down.");
    api_buf_printf(out, "voronoid_ready %d\n", g->ready ? 1 : 0);
    header(out, "voronoid_answer_memory_bytes", "gauge",
           "Bytes held for requests in flight (bodies, computations, "
           "answers), against --answer-memory.");
    api_buf_printf(out, "voronoid_answer_memory_bytes %zu\n",
                   g->answer_memory);
    header(out, "voronoid_answer_memory_capacity_bytes", "gauge",
           "The budget, --answer-memory.");
    api_buf_printf(out, "voronoid_answer_memory_capacity_bytes %zu\n",
                   g->answer_memory_capacity);
    header(out, "voronoid_answer_memory_peak_bytes", "gauge",
           "The most held at once since the start.");
    api_buf_printf(out, "voronoid_answer_memory_peak_bytes %zu\n",
                   g->answer_memory_peak);
    header(out, "voronoid_answer_memory_refused_total", "counter",
           "Requests refused with 503 because they did not fit the budget.");
    api_buf_printf(out, "voronoid_answer_memory_refused_total %zu\n",
                   g->answer_memory_refused);
    header(out, "voronoid_connections", "gauge", "Open connections.");
    api_buf_printf(out, "voronoid_connections %zu\n", g->connections);
    header(out, "voronoid_connections_closed_total", "counter",
           "Connections closed for their slowness: headers past "
           "--header-timeout (408), silent new connections, bodies under "
           "--min-upload-rate (408).");
    api_buf_printf(out,
                   "voronoid_connections_closed_total{reason=\"header-"
                   "timeout\"} %llu\n"
                   "voronoid_connections_closed_total{reason=\"silent\"} "
                   "%llu\n"
                   "voronoid_connections_closed_total{reason=\"upload-"
                   "rate\"} %llu\n",
                   g->closed_header_timeout, g->closed_silent,
                   g->closed_upload_rate);
}
