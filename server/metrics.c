/* metrics.c -- counters behind GET /metrics.
 *
 * Representation: fixed arrays, no allocation after srv_metrics_new:
 * requests[route][status - 100] (500 statuses x 9 routes), per-route
 * histogram buckets (non-cumulative; made cumulative when rendered), sums
 * and counts, per-algorithm points and compute seconds. One mutex; an update
 * is a few additions under it, a render copies the struct under it and
 * formats outside it. Render cost is O(routes x (statuses + buckets)).
 */
#include "metrics.h"

#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define N_STATUS 500 /* 100 .. 599 */

typedef struct counters {
    uint64_t requests[SRV_ROUTE_COUNT][N_STATUS];
    uint64_t aborted[SRV_ROUTE_COUNT];
    uint64_t bucket[SRV_ROUTE_COUNT][SRV_N_LATENCY_BUCKETS + 1];
    double latency_sum[SRV_ROUTE_COUNT];
    uint64_t latency_count[SRV_ROUTE_COUNT];
    uint64_t points[VOR_ALGORITHM_COUNT];
    uint64_t runs[VOR_ALGORITHM_COUNT];
    double compute_s[VOR_ALGORITHM_COUNT];
} counters;

struct srv_metrics {
    pthread_mutex_t mu;
    counters c;
};

static const double bounds[SRV_N_LATENCY_BUCKETS] = SRV_LATENCY_BUCKETS;

srv_metrics *srv_metrics_new(void) {
    srv_metrics *m = calloc(1, sizeof *m);
    if (m == NULL) return NULL;
    if (pthread_mutex_init(&m->mu, NULL) != 0) {
        free(m);
        return NULL;
    }
    return m;
}

void srv_metrics_free(srv_metrics *m) {
    if (m == NULL) return;
    pthread_mutex_destroy(&m->mu);
    free(m);
}

void srv_metrics_request(srv_metrics *m, srv_route route, int status,
                         double seconds) {
    if ((unsigned)route >= SRV_ROUTE_COUNT) route = SRV_ROUTE_OTHER;
    if (status < 100 || status > 599) status = 599;
    if (!(seconds >= 0)) seconds = 0;
    int b = 0;
    while (b < SRV_N_LATENCY_BUCKETS && seconds > bounds[b]) b++;
    pthread_mutex_lock(&m->mu);
    m->c.requests[route][status - 100]++;
    m->c.bucket[route][b]++;
    m->c.latency_sum[route] += seconds;
    m->c.latency_count[route]++;
    pthread_mutex_unlock(&m->mu);
}

void srv_metrics_aborted(srv_metrics *m, srv_route route) {
    if ((unsigned)route >= SRV_ROUTE_COUNT) route = SRV_ROUTE_OTHER;
    pthread_mutex_lock(&m->mu);
    m->c.aborted[route]++;
    pthread_mutex_unlock(&m->mu);
}

void srv_metrics_compute(srv_metrics *m, vor_algorithm a, size_t n,
                         double seconds) {
    if ((unsigned)a >= VOR_ALGORITHM_COUNT) return;
    if (!(seconds >= 0)) seconds = 0;
    pthread_mutex_lock(&m->mu);
    m->c.points[a] += n;
    m->c.runs[a]++;
    m->c.compute_s[a] += seconds;
    pthread_mutex_unlock(&m->mu);
}

static void header(api_buf *out, const char *name, const char *type,
                   const char *help) {
    api_buf_printf(out, "# HELP %s %s\n# TYPE %s %s\n", name, help, name,
                   type);
}

void srv_metrics_render(srv_metrics *m, const srv_gauges *g, api_buf *out) {
    counters *c = malloc(sizeof *c);
    if (c == NULL) {
        out->oom = 1;
        return;
    }
    pthread_mutex_lock(&m->mu);
    memcpy(c, &m->c, sizeof *c);
    pthread_mutex_unlock(&m->mu);

    header(out, "voronoid_requests_total", "counter",
           "Requests answered, by route and HTTP status.");
    for (int r = 0; r < SRV_ROUTE_COUNT; r++)
        for (int s = 0; s < N_STATUS; s++)
            if (c->requests[r][s])
                api_buf_printf(out,
                               "voronoid_requests_total{route=\"%s\","
                               "status=\"%d\"} %llu\n",
                               srv_route_name((srv_route)r), s + 100,
                               (unsigned long long)c->requests[r][s]);

    header(out, "voronoid_requests_aborted_total", "counter",
           "Requests that ended before an answer was sent (client gone, "
           "connection timed out).");
    for (int r = 0; r < SRV_ROUTE_COUNT; r++)
        api_buf_printf(out,
                       "voronoid_requests_aborted_total{route=\"%s\"} %llu\n",
                       srv_route_name((srv_route)r),
                       (unsigned long long)c->aborted[r]);

    header(out, "voronoid_request_duration_seconds", "histogram",
           "Time from a request's arrival to its answer being queued, by "
           "route.");
    for (int r = 0; r < SRV_ROUTE_COUNT; r++) {
        const char *name = srv_route_name((srv_route)r);
        uint64_t cum = 0;
        for (int b = 0; b < SRV_N_LATENCY_BUCKETS; b++) {
            cum += c->bucket[r][b];
            api_buf_printf(out,
                           "voronoid_request_duration_seconds_bucket{route="
                           "\"%s\",le=\"%g\"} %llu\n",
                           name, bounds[b], (unsigned long long)cum);
        }
        cum += c->bucket[r][SRV_N_LATENCY_BUCKETS];
        api_buf_printf(out,
                       "voronoid_request_duration_seconds_bucket{route="
                       "\"%s\",le=\"+Inf\"} %llu\n"
                       "voronoid_request_duration_seconds_sum{route=\"%s\"} "
                       "%.9g\n"
                       "voronoid_request_duration_seconds_count{route="
                       "\"%s\"} %llu\n",
                       name, (unsigned long long)cum, name,
                       c->latency_sum[r], name,
                       (unsigned long long)c->latency_count[r]);
    }

    header(out, "voronoid_points_total", "counter",
           "Input points processed, by algorithm.");
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++)
        api_buf_printf(out, "voronoid_points_total{algorithm=\"%s\"} %llu\n",
                       vor_algorithm_name((vor_algorithm)a),
                       (unsigned long long)c->points[a]);
    header(out, "voronoid_computations_total", "counter",
           "Diagrams computed, by algorithm.");
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++)
        api_buf_printf(out,
                       "voronoid_computations_total{algorithm=\"%s\"} %llu\n",
                       vor_algorithm_name((vor_algorithm)a),
                       (unsigned long long)c->runs[a]);
    header(out, "voronoid_compute_seconds_total", "counter",
           "Seconds spent computing diagrams, by algorithm.");
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++)
        api_buf_printf(out,
                       "voronoid_compute_seconds_total{algorithm=\"%s\"} "
                       "%.9g\n",
                       vor_algorithm_name((vor_algorithm)a), c->compute_s[a]);

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
    free(c);
}
