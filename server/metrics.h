/* metrics.h -- voronoid's counters and their Prometheus text exposition.
 *
 * Counted here: requests by route and status, a latency histogram per
 * route, requests that ended without an answer (client gone, connection
 * timed out), points and compute seconds per algorithm, computations
 * stopped because nobody waited for them any more. Gauges that other
 * modules own (queue depth, in-flight requests, readiness) are passed in at
 * render time. All functions are thread-safe and take no lock (atomic
 * counters).
 */
#ifndef VOR_SRV_METRICS_H
#define VOR_SRV_METRICS_H

#include <stddef.h>

#include "../core/vor.h"
#include "../api/api.h"
#include "routes.h"

typedef struct srv_metrics srv_metrics;

typedef struct srv_gauges {
    size_t queue_depth, queue_capacity;
    size_t running, workers;
    size_t in_flight;  /* requests received and not yet answered */
    int ready;         /* 0 while draining */
    size_t answer_memory, answer_memory_capacity, answer_memory_peak;
    size_t answer_memory_refused;   /* requests refused for the budget */
    size_t connections;             /* open, as the guard counts them */
    unsigned long long closed_header_timeout, closed_silent,
        closed_upload_rate;         /* connections closed by the guard */
} srv_gauges;

srv_metrics *srv_metrics_new(void); /* NULL on allocation failure */
void srv_metrics_free(srv_metrics *m);

/* One answered request. status 100..599 (others count as 599). */
void srv_metrics_request(srv_metrics *m, srv_route route, int status,
                         double seconds);
/* One request that ended before an answer was sent. */
void srv_metrics_aborted(srv_metrics *m, srv_route route);
/* One algorithm run over n points taking `seconds` of compute. */
void srv_metrics_compute(srv_metrics *m, vor_algorithm a, size_t n,
                         double seconds);

/* One computation stopped when its answer was given up on (deadline,
 * shutdown). */
void srv_metrics_stopped(srv_metrics *m);

/* Appends the text exposition (format 0.0.4) to out. */
void srv_metrics_render(srv_metrics *m, const srv_gauges *g, api_buf *out);

/* Histogram upper bounds in seconds (the +Inf bucket is implicit). */
#define SRV_LATENCY_BUCKETS                                              \
    {0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, \
     2.5, 5, 10, 30, 60}
#define SRV_N_LATENCY_BUCKETS 16

#endif /* VOR_SRV_METRICS_H */
