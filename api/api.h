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
    X(API_TIMEOUT, "timeout", 504, "Deadline exceeded")

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
} api_buf;

void api_buf_init(api_buf *b);
void api_buf_clear(api_buf *b);
/* Hands the data to the caller (free with free()); b is left empty. */
char *api_buf_take(api_buf *b, size_t *len);

/* ---- Requests ----------------------------------------------------------- */

typedef enum api_input { API_IN_JSON, API_IN_TEXT, API_IN_BINARY } api_input;
typedef enum api_format {
    API_FMT_JSON,
    API_FMT_GEOJSON,
    API_FMT_SVG,
    API_FMT_BINARY
} api_format;

/* Parts of the diagram to return (JSON "include": [...]). */
enum {
    API_PART_SITES = 1u << 0,
    API_PART_VERTICES = 1u << 1,
    API_PART_EDGES = 1u << 2,
    API_PART_CELLS = 1u << 3,
    API_PART_TRIANGLES = 1u << 4,
    API_PART_CLIPPED = 1u << 5, /* clipped edges and cell polygons; needs bounds */
    API_PART_DEFAULT = API_PART_VERTICES | API_PART_EDGES | API_PART_CELLS
};

typedef struct api_limits {
    size_t max_points; /* input or generated points */
} api_limits;

typedef struct api_request {
    vor_algorithm algorithm;
    int has_bounds;
    double bounds[4]; /* xmin, ymin, xmax, ymax */
    unsigned parts;
    api_format format;
    double *xy;      /* 2 * n, owned */
    size_t n;
    int generated;   /* points came from a "generate" request */
} api_request;

void api_request_init(api_request *r); /* fortune, default parts, JSON */
void api_request_clear(api_request *r);

/* Content-Type header (parameters allowed, case-insensitive) -> input kind.
 * NULL or empty means JSON. API_MEDIA_TYPE otherwise. */
api_code api_input_from_content_type(const char *content_type, api_input *out,
                                     api_problem *p);

/* Parses a request body into r (options found in a JSON body included).
 * Points beyond lim->max_points give API_TOO_LARGE. */
api_code api_parse_body(api_request *r, api_input kind, const char *body,
                        size_t len, const api_limits *lim, api_problem *p);

/* Applies one option given outside the body (query string, CLI flag):
 * "algorithm", "bounds" ("xmin,ymin,xmax,ymax"), "format" (json, geojson,
 * svg, binary), "include" (comma-separated part names). Unknown keys give
 * API_MALFORMED; bad values API_INVALID. */
api_code api_request_option(api_request *r, const char *key, const char *value,
                            api_problem *p);

/* Accept header -> format; leaves r->format unchanged for * / * or absent.
 * API_NOT_ACCEPTABLE if nothing we produce is acceptable. */
api_code api_format_from_accept(api_request *r, const char *accept,
                                api_problem *p);

/* Generated point sets: uniform, gaussian, random (integer pixels in an
 * 800x600 window), grid, circle, clustered. Deterministic for a seed.
 * *xy is a new array of 2*n doubles (free with free()). */
api_code api_generate(const char *distribution, size_t n, uint64_t seed,
                      double **xy, api_problem *p);

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
} api_result;

void api_result_init(api_result *res);
void api_result_clear(api_result *res);

/* Prepares sites, computes the diagram with r->algorithm, clips, derives
 * triangles, filling res and its timings (res->t.parse_ms is left for the
 * caller). Non-finite points give API_INVALID with pointer/detail naming the
 * input index. */
api_code api_compute(const api_request *r, api_result *res, api_problem *p);

typedef struct api_compare {
    api_result res[VOR_ALGORITHM_COUNT];
    int agree;              /* all diagrams identical */
    char disagreement[256]; /* first difference found, "" if they agree */
} api_compare;

void api_compare_init(api_compare *c);
void api_compare_clear(api_compare *c);
api_code api_compare_run(const api_request *r, api_compare *c, api_problem *p);

/* ---- Writing ------------------------------------------------------------ */

/* MIME type of a format ("application/json", "application/geo+json",
 * "image/svg+xml", "application/octet-stream"). */
const char *api_format_mime(api_format f);

/* Writes the result in r->format. Timings in t are written into the body. */
api_code api_write_result(const api_request *r, const api_result *res,
                          const api_timings *t, api_buf *out, api_problem *p);
/* JSON only: per-algorithm timings, counts and agreement. */
api_code api_write_compare(const api_request *r, const api_compare *c,
                           api_buf *out, api_problem *p);
/* application/problem+json body for p. instance may be NULL. */
void api_write_problem(const api_problem *p, const char *instance,
                       api_buf *out);

#endif /* VOR_API_H */
