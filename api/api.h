/* api.h -- the codec between the outside world and libvor.
 *
 * Requests come in as bytes (JSON, CSV/text, little-endian float64 pairs)
 * plus options (from a JSON body or a query string); results go out as JSON,
 * GeoJSON, SVG or binary. Every failure is an api_problem: the HTTP status,
 * a problem type slug, a title and a detail that names the offending value,
 * with a JSON pointer or a line number where there is one. This is the only
 * layer that knows jansson. Used by server/ and cli/ alike; no threads, no
 * globals, no I/O beyond the buffers it is given.
 *
 * Ownership: api_request, api_result, api_compare and api_buf are caller-
 * owned structs; *_init zeroes them, *_clear frees what they hold and may be
 * called on a zeroed or partially filled struct.
 */
#ifndef VOR_API_H
#define VOR_API_H

#include <stddef.h>
#include <stdint.h>

#include "../core/vor.h"

/* ---- Problems ----------------------------------------------------------- */

/* One table: slug (the problem type, also in openapi.yaml), HTTP status,
 * title. */
#define API_PROBLEM_TABLE(X)                                                 \
    X(API_OK, "ok", 200, "OK")                                               \
    X(API_MALFORMED, "malformed", 400, "Malformed request")                  \
    X(API_NOT_FOUND, "not-found", 404, "Not found")                          \
    X(API_METHOD, "method-not-allowed", 405, "Method not allowed")           \
    X(API_TOO_LARGE, "too-large", 413, "Request too large")                  \
    X(API_MEDIA_TYPE, "unsupported-media-type", 415,                         \
      "Unsupported media type")                                              \
    X(API_NOT_ACCEPTABLE, "not-acceptable", 406, "Not acceptable")           \
    X(API_INVALID, "invalid", 422, "Invalid request")                        \
    X(API_INTERNAL, "internal", 500, "Internal error")                       \
    X(API_UNAVAILABLE, "unavailable", 503, "Service unavailable")            \
    X(API_TIMEOUT, "timeout", 504, "Deadline exceeded")                      \
    X(API_NOT_IMPLEMENTED, "not-implemented", 501, "Not implemented")      \
    X(API_REQUEST_TIMEOUT, "request-timeout", 408, "Request timeout")      \
    X(API_URI_TOO_LONG, "uri-too-long", 414, "Request line too long")      \
    X(API_HEADERS_TOO_LARGE, "headers-too-large", 431,                     \
      "Request headers too large")

typedef enum api_code {
#define API__ENUM(name, slug, http, title) name,
    API_PROBLEM_TABLE(API__ENUM)
#undef API__ENUM
    API_CODE_COUNT
} api_code;

typedef struct api_problem {
    api_code code;      /* API_OK when there is no problem */
    char detail[512];   /* names the offending value */
    char pointer[128];  /* JSON pointer ("/points/3/1"), "" if none */
    long line;          /* 1-based line of a text body, 0 if none */
} api_problem;

int api_code_http(api_code c);
const char *api_code_slug(api_code c);
const char *api_code_title(api_code c);

/* Problem type URIs are relative: API_PROBLEM_TYPE_PREFIX followed by the
 * slug, e.g. "/problems/too-large" (resolved against the service's own
 * address, so they work behind any host name). */
#define API_PROBLEM_TYPE_PREFIX "/problems/"

/* Problem for a core status (VOR_ENOMEM -> API_UNAVAILABLE, VOR_ETOOMANY ->
 * API_TOO_LARGE, VOR_EUNAVAILABLE -> API_NOT_IMPLEMENTED, ...), with the
 * core's message as detail; returns the code (API_OK for VOR_OK). */
api_code api_problem_from_status(api_problem *p, vor_status s);

/* Sets p (code, printf-style detail); returns code. */
api_code api_problem_set(api_problem *p, api_code code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* ---- Output buffer ------------------------------------------------------ */
typedef struct api_buf {
    char *data;
    size_t len, cap;
    int oom; /* set when an append failed; the contents are then incomplete */
    /* Streaming (optional, NULL by default): once len reaches flush_at and
     * more room is needed, the bytes written so far are handed to
     * flush(flush_ctx, data, n) and dropped from the buffer (all but the
     * last len % 8, so that offsets modulo 8 -- the binary writer's
     * padding -- stay those of the whole document); a non-zero return
     * stops the writer as if memory ran out. The writer then never holds
     * much more than flush_at bytes. */
    int (*flush)(void *flush_ctx, const char *data, size_t n);
    void *flush_ctx;
    size_t flush_at;
} api_buf;

void api_buf_init(api_buf *b);
void api_buf_clear(api_buf *b);
/* Hands the data to the caller (free with free()); b is left empty. */
char *api_buf_take(api_buf *b, size_t *len);
/* Appends n bytes (or a printf-formatted string); on failure sets b->oom,
 * keeps the contents and returns -1, else 0. The data stay terminated by a
 * NUL byte that len does not count. */
int api_buf_append(api_buf *b, const void *data, size_t n);
int api_buf_printf(api_buf *b, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* ---- Requests ----------------------------------------------------------- */

/* API_IN_AUTO: JSON if the first byte that is not white space (after a
 * UTF-8 byte order mark) is '{' or '[', text otherwise (binary is never
 * guessed); an empty body is JSON's "empty body" problem. API_IN_PLAIN
 * (text/plain): the same guess, but an empty body is text (no points) --
 * a browser's fetch() of a JSON string without a Content-Type sends
 * text/plain;charset=UTF-8, and a text body never starts with '{' or '['. */
typedef enum api_input {
    API_IN_JSON,
    API_IN_TEXT,
    API_IN_BINARY,
    API_IN_AUTO,
    API_IN_PLAIN
} api_input;
/* API_FMT_TIMINGS: only the JSON timings object (command line, benchmarks). */
typedef enum api_format {
    API_FMT_JSON,
    API_FMT_GEOJSON,
    API_FMT_SVG,
    API_FMT_BINARY,
    API_FMT_TIMINGS
} api_format;

/* Parts of the diagram to return (JSON "include": [...]). */
enum {
    API_PART_SITES = 1u << 0,
    API_PART_VERTICES = 1u << 1,
    API_PART_EDGES = 1u << 2,
    API_PART_CELLS = 1u << 3,
    API_PART_TRIANGLES = 1u << 4,
    API_PART_CLIPPED = 1u << 5, /* clipped edges and cell polygons */
    API_PART_COUNTS = 1u << 6,  /* the algorithm's operation counts */
    API_PART_DEFAULT = API_PART_VERTICES | API_PART_EDGES | API_PART_CELLS,
    API_PART_ALL = (1u << 7) - 1
};
/* When the parts were not chosen explicitly (parts_given == 0), bounds add
 * API_PART_CLIPPED. "clipped" without bounds clips to the default box: the
 * sites' bounding box expanded by 10% on every side (GeoJSON and SVG use the
 * same box when no bounds are given). */

typedef struct api_limits {
    size_t max_points; /* input or generated points */
} api_limits;

/* Most points a request may ask to trace ("trace": true): a trace has a
 * few steps per site, each a small object, so a traced answer of this
 * many points stays within a few megabytes of JSON. */
#define API_TRACE_MAX_POINTS 2000

typedef struct api_request {
    vor_algorithm algorithm;
    int repeat;      /* runs per algorithm of a comparison; 0 = default
                        (api_compare_repeat) */
    int has_bounds;
    double bounds[4]; /* xmin, ymin, xmax, ymax */
    unsigned parts;
    int parts_given; /* parts were chosen by an "include" */
    api_format format;
    double *xy;      /* 2 * n, owned */
    size_t n;
    int generated;   /* points came from a "generate" request */
    int trace;       /* report the algorithm's steps (JSON only) */
    /* the caller's (not the request's): when set, the algorithms ask it now
     * and then whether to go on (vor_options.stop); a computation it stops
     * fails with API_UNAVAILABLE */
    int (*stop)(void *ctx);
    void *stop_ctx;
} api_request;

void api_request_init(api_request *r); /* fortune, default parts, JSON */
void api_request_clear(api_request *r);

/* Content-Type header (parameters allowed, case-insensitive) -> input kind:
 * application/json, text/json and any application/...+json -> JSON;
 * text/csv, text/tab-separated-values -> text; text/plain -> API_IN_PLAIN;
 * application/octet-stream -> binary; NULL, empty or
 * application/x-www-form-urlencoded (what `curl --data-binary` sends
 * unless told otherwise) -> API_IN_AUTO. API_MEDIA_TYPE otherwise. */
api_code api_input_from_content_type(const char *content_type, api_input *out,
                                     api_problem *p);

/* Parses a request body into r (options found in a JSON body included).
 * Points beyond lim->max_points give API_TOO_LARGE (lim may be NULL:
 * VOR_MAX_POINTS). Statuses: syntax errors, unknown or duplicate keys and
 * a binary length that is not a multiple of 16 are API_MALFORMED (400);
 * well-formed values of the wrong type or range (a string where a number
 * belongs, NaN, 1e999, bad bounds, unknown algorithm) are API_INVALID
 * (422); p->pointer (JSON) or p->line (text) names the place. On error r's
 * points are left empty. */
api_code api_parse_body(api_request *r, api_input kind, const char *body,
                        size_t len, const api_limits *lim, api_problem *p);

/* Applies one option given outside the body (query string, CLI flag):
 * "algorithm", "bounds" ("xmin,ymin,xmax,ymax"), "format" (json, geojson,
 * svg, binary, timings), "include" (comma-separated part names, possibly
 * none), "repeat" (an integer 1..API_REPEAT_MAX, for comparisons), "trace"
 * (true or false). Applied after api_parse_body, they win over the body's
 * options. Unknown keys give API_MALFORMED; bad values API_INVALID (r
 * unchanged). */
api_code api_request_option(api_request *r, const char *key, const char *value,
                            api_problem *p);

/* Accept header -> format; leaves r->format unchanged for * / * or absent.
 * Media ranges are taken in order of their q values (q=0 refuses);
 * application/json, application/geo+json, image/svg+xml,
 * application/octet-stream are produced, and "application/ *" or "image/ *"
 * ranges match them. API_NOT_ACCEPTABLE if nothing we produce is
 * acceptable. */
api_code api_format_from_accept(api_request *r, const char *accept,
                                api_problem *p);

/* Generated point sets, deterministic for (distribution, n, seed): uniform,
 * gaussian, pixels (alias "random"), grid, circle, clustered, lognormal,
 * outlier, decades -- each defined in distribution.h, which the test point
 * sets and the benchmark share.
 * *xy is a new array of 2*n doubles (free with free()); NULL when n == 0.
 * Unknown distribution: API_INVALID listing the valid names; n >
 * VOR_MAX_POINTS: API_TOO_LARGE. */
api_code api_generate(const char *distribution, size_t n, uint64_t seed,
                      double **xy, api_problem *p);

/* The canonical name of a distribution name or alias ("pixels" for
 * "random"), for answers that echo it; NULL if name is unknown. A borrowed
 * constant. */
const char *api_distribution_name(const char *name);

/* ---- Computing ---------------------------------------------------------- */

typedef struct api_timings {
    double queue_ms;     /* set by the server */
    double parse_ms;     /* body -> points */
    double prepare_ms;   /* vor_sites_new */
    double compute_ms;   /* vor_compute: prepared input -> finished diagram */
    double clip_ms;
    double serialize_ms; /* set by the writer for the Server-Timing header */
    double total_ms;
} api_timings;

typedef struct api_result {
    vor_algorithm algorithm;
    vor_sites *sites;
    vor_diagram *diagram;
    vor_clipped *clipped;   /* when bounds were given */
    uint32_t *triangles;    /* when API_PART_TRIANGLES; 3 * n_triangles */
    size_t n_triangles;
    api_timings t;
    vor_counts counts;      /* the algorithm's work, always */
    int traced;             /* trace holds the steps (the request's trace) */
    api_buf trace;          /* the steps as JSON objects, comma-separated */
} api_result;

void api_result_init(api_result *res);
void api_result_clear(api_result *res);

/* Milliseconds on the monotonic clock, for timings. */
double api_clock_ms(void);

/* Prepares sites, computes the diagram with r->algorithm, clips (when the
 * effective parts include "clipped", or the format is GeoJSON or SVG; to
 * r->bounds or the default box), derives triangles (API_PART_TRIANGLES),
 * filling res and its timings (prepare, compute, clip -- triangles count in
 * compute; queue_ms and parse_ms are left for the caller, total_ms is the
 * sum of all parts so far) and counts; with r->trace, the steps (in
 * res->trace). Non-finite points give API_INVALID with pointer
 * "/points/i/k" and a detail naming the input index; so does a request
 * with a repeat count (r->repeat != 0), which belongs to comparisons; a
 * trace of more than API_TRACE_MAX_POINTS points, or in a format other
 * than JSON, gives API_INVALID with pointer "/trace". */
api_code api_compute(const api_request *r, api_result *res, api_problem *p);

/* Repeated measurement in a comparison: each algorithm runs `repeat`
 * times (1..API_REPEAT_MAX) on the same prepared sites, and repeat times
 * the number of points is at most API_REPEAT_WORK_MAX, so that one request
 * stays within a deadline. */
#define API_REPEAT_MAX 50
#define API_REPEAT_WORK_MAX ((size_t)10000000)

/* The runs per algorithm a comparison of r makes once it has n_sites
 * distinct sites: r->repeat when given, else 5 up to 20,000 sites, 3 up to
 * 200,000, 1 beyond. */
int api_compare_repeat(const api_request *r, size_t n_sites);

/* The phases measured in every run of a comparison, in the order of
 * api_compare.runs. */
enum { API_RUN_COMPUTE, API_RUN_CLIP, API_RUN_TOTAL, API_RUN_PHASES };

typedef struct api_compare {
    api_timings t;          /* the request's: queue_ms and parse_ms are the
                               caller's; prepare_ms the one preparation of
                               the sites; compute_ms and clip_ms summed over
                               every run; total_ms is set by the run */
    vor_sites *sites;       /* prepared once, shared by every run */
    int repeat;             /* runs per algorithm */
    int has_clip;           /* the runs clip (bounds were given) */
    /* Per algorithm: res.diagram is its first run's diagram (res.sites
     * stays NULL: the sites are c->sites); res.t holds the median of each
     * phase over its runs, prepare_ms the shared preparation; runs[a][i]
     * is run i's compute, clip and total ms (total = prepare + compute +
     * clip), in run order; n_runs[a] runs were made. */
    api_result res[VOR_ALGORITHM_COUNT];
    double runs[VOR_ALGORITHM_COUNT][API_REPEAT_MAX][API_RUN_PHASES];
    int n_runs[VOR_ALGORITHM_COUNT];
    vor_status status[VOR_ALGORITHM_COUNT]; /* per algorithm: VOR_OK or why
                                               it has no diagram */
    int agree;              /* all diagrams computed and identical (every
                               run of every algorithm) */
    char disagreement[256]; /* first difference found, "" if they agree */
} api_compare;

void api_compare_init(api_compare *c);
void api_compare_clear(api_compare *c);
/* Prepares r's sites once, then runs every algorithm api_compare_repeat
 * times in rounds (round k runs each algorithm once, the order rotated by
 * k, so no algorithm always runs first or last), clipping each run's
 * diagram when r has bounds. Every run's diagram must equal the
 * algorithm's first and the algorithms' first diagrams must equal each
 * other, else agree is 0 with the first difference in disagreement. An
 * algorithm that fails on its own (not available, out of memory) is
 * recorded in c->status, is not run again, and makes agree 0; invalid
 * input fails the whole call as api_compute would, and so does a repeat
 * over API_REPEAT_WORK_MAX / points, or a trace (API_INVALID: /compare
 * does not trace). Each algorithm's counts (res[a].counts) are its first
 * run's; a run's counts are the same in every run. */
api_code api_compare_run(const api_request *r, api_compare *c, api_problem *p);

/* ---- Writing ------------------------------------------------------------ */

/* MIME type of a format ("application/json", "application/geo+json",
 * "image/svg+xml", "application/octet-stream"). */
const char *api_format_mime(api_format f);

/* Writes the result in r->format (appending to out); every format but
 * binary ends with a newline. The timings are the body's last member: the writer measures its own time into
 * t->serialize_ms and sets t->total_ms = max(t->total_ms, queue + parse +
 * prepare + compute + clip) + serialize_ms before writing them (so a caller
 * may put its own wall-clock time so far in total_ms, and can reuse t for a
 * Server-Timing header). t may be &res->t. API_UNAVAILABLE when memory runs
 * out (out is then cleared). */
api_code api_write_result(const api_request *r, const api_result *res,
                          api_timings *t, api_buf *out, api_problem *p);
/* JSON only: repeat, per-algorithm status, counts, median timings, their
 * spread (median, min, max of each phase measured per run) and the compute
 * ms of every run, agreement, and the shared timings (c->t, with the
 * writer's serialize_ms). */
api_code api_write_compare(const api_request *r, const api_compare *c,
                           api_buf *out, api_problem *p);
/* application/problem+json body for p: type (API_PROBLEM_TYPE_PREFIX +
 * slug), title, status, detail, instance (when not NULL), pointer (when
 * set), line (when set), and a newline. */
void api_write_problem(const api_problem *p, const char *instance,
                       api_buf *out);

#endif /* VOR_API_H */
