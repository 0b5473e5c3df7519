/* codec.h -- contracts shared between the codec's source files (not part of
 * the interface in api.h).
 *
 * Names: api__ internal. Problems built here always fill detail, and pointer
 * or line when the offending value has one. */
#ifndef VOR_API_CODEC_H
#define VOR_API_CODEC_H

#include "api.h"
#include "buf.h"

/* api_problem_set plus a JSON pointer (may be NULL) and a text line (0 if
 * none). Returns code. */
api_code api__problem_at(api_problem *p, api_code code, const char *pointer,
                         long line, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* ---- Option values (request.c), shared by JSON bodies and options ------- */

/* Each validates one option value and stores it in r; errors are
 * API_INVALID naming the value and listing the valid ones, with pointer
 * (may be NULL) attached. */
api_code api__set_algorithm(api_request *r, const char *name,
                            const char *pointer, api_problem *p);
api_code api__set_format(api_request *r, const char *name,
                         const char *pointer, api_problem *p);
/* "json", "geojson", "svg", "binary", "timings". */
const char *api__format_name(api_format f);
/* Adds the part called name (n bytes) to *parts. */
api_code api__add_part(unsigned *parts, const char *name, size_t n,
                       const char *pointer, api_problem *p);
/* Checks a box (finite, xmin < xmax, ymin < ymax) and stores it as r's
 * bounds. */
api_code api__set_bounds(api_request *r, const double box[4],
                         const char *pointer, api_problem *p);

/* Checks a comparison's repeat count (an integer 1..API_REPEAT_MAX; v is
 * the number as given) and stores it in r. */
api_code api__set_repeat(api_request *r, double v, const char *pointer,
                         api_problem *p);

/* Parts the writers produce for r: r->parts, plus API_PART_CLIPPED when
 * bounds were given and the parts were not chosen explicitly. */
unsigned api__effective_parts(const api_request *r);

/* Non-zero when the result needs a clipped diagram: clipped output, GeoJSON
 * or SVG. */
int api__needs_clip(const api_request *r);

/* The box used when clipping without bounds: the sites' bounding box
 * expanded by 10% of its larger side on every side (a degenerate box is
 * widened to at least 1 unit, or 10% of the coordinates' magnitude), always
 * finite with xmin < xmax and ymin < ymax; [-1,-1,1,1] when there are no
 * sites. */
void api__default_box(const vor_sites *s, double box[4]);

/* Writes the first difference between diagrams p (computed by a) and q
 * (by b) into msg, in terms of counts, then vertices, edges, rays, cells;
 * returns 0 (msg untouched) if there is none. (compute.c) */
int api__diagram_difference(const vor_diagram *p, const vor_diagram *q,
                            const char *a, const char *b, char *msg,
                            size_t size);

/* ---- Writers (write_*.c) ------------------------------------------------- */

/* Each appends one document for res to out; the timings member is written
 * last, after api__finish_timings. They return 0, or -1 when out ran out of
 * memory. */
int api__write_json(const api_request *r, const api_result *res,
                    api_timings *t, double t0, api_buf *out);
int api__write_geojson(const api_request *r, const api_result *res,
                       api_timings *t, double t0, api_buf *out);
int api__write_svg(const api_request *r, const api_result *res,
                   api_timings *t, double t0, api_buf *out);
int api__write_binary(const api_request *r, const api_result *res,
                      api_timings *t, double t0, api_buf *out);

/* ---- Counts and traces (write_trace.c) ----------------------------------- */

/* Appends the counts that apply to algorithm a as a JSON object
 * {"name": value, ...}, in the order of vor.h's table. -1 if out of
 * memory. */
int api__put_counts(api_buf *out, const vor_counts *c, vor_algorithm a);

/* The trace hook's state: steps go to out as JSON objects separated by
 * commas, site numbers as input indices of s. */
typedef struct api__tracer {
    api_buf *out;
    const vor_sites *s;
    vor_algorithm algorithm;
    vor_counts last; /* the counts of the previous step */
    size_t steps;
} api__tracer;

/* The vor_trace_fn of a tracer (ctx). Out of memory is recorded in
 * out->oom. */
void api__trace_step(void *ctx, const vor_step *st);

/* Sets t->serialize_ms to the time since t0 (api_clock_ms) and adds it to
 * t->total_ms. */
void api__finish_timings(api_timings *t, double t0);
/* Appends the timings as a JSON object. */
int api__put_timings(api_buf *out, const api_timings *t);

/* Input index of site i. Without duplicates the map is the identity, and
 * skipping it saves a cache miss per index on large diagrams. */
static inline uint32_t api__input_index(const vor_sites *s, uint32_t i) {
    return s->n == s->n_input ? i : s->input_of[i];
}

/* Midpoint of sites a and b, finite for finite sites. */
void api__midpoint(const double *a, const double *b, double *out);

#endif /* VOR_API_CODEC_H */
