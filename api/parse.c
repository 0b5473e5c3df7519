/* parse.c -- request bodies: JSON, CSV/text and binary points.
 *
 * JSON: a hand-written scanner walks the top level. The points array (the
 * only part that can be large) and the small number arrays ("bounds") are
 * read by our own streaming loop with the exact number shim (numconv.h), at
 * about 0.1 us a number, with no intermediate tree; "algorithm" and
 * "format" given as plain strings (printable ASCII, no escapes) are copied
 * as they stand; every other member is cut out of the body with a
 * structural skip and decoded by jansson, so string escapes and nested
 * objects get a complete JSON parser. jansson therefore only ever sees
 * small values, and its error positions are translated back into
 * positions in the whole body.
 *
 * Text: one point per line, two numbers separated by spaces, tabs, a comma
 * or a semicolon; '#' starts a comment; blank lines and a first line of
 * column names are skipped; CRLF works. Binary: little-endian float64
 * pairs.
 *
 * Points accumulate in one array grown by doubling (amortised O(1) a
 * point, peak 2x the final size); the whole parse is O(body length). No
 * recursion on input (depth is counted), never a read past the end of the
 * body (which need not be NUL-terminated). Errors: syntax -> API_MALFORMED
 * with the byte offset, line and column; wrong type or value ->
 * API_INVALID with a JSON pointer (or the text line); too many points ->
 * API_TOO_LARGE. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"

/* ---- Point accumulation ---------------------------------------------------- */

typedef struct points {
    double *xy;
    size_t n, cap; /* in points */
    size_t max;
} points;

/* Room for one more point; -1 when memory runs out. */
static int points_grow(points *pts) {
    if (pts->n < pts->cap) return 0;
    size_t cap = pts->cap ? 2 * pts->cap : 1024;
    if (cap > pts->max && pts->max >= pts->n + 1) cap = pts->max;
    if (cap > SIZE_MAX / (2 * sizeof(double))) return -1;
    double *xy = realloc(pts->xy, cap * 2 * sizeof(double));
    if (xy == NULL) return -1;
    pts->xy = xy;
    pts->cap = cap;
    return 0;
}

static api_code out_of_memory(api_problem *p) {
    return api_problem_set(p, API_UNAVAILABLE,
                           "out of memory while reading the points");
}

static api_code too_many(api_problem *p, const char *pointer, long line,
                         size_t max) {
    return api__problem_at(p, API_TOO_LARGE, pointer, line,
                           "more than %zu points (the limit of this service)",
                           max);
}

/* ---- JSON scanning ------------------------------------------------------------ */

typedef struct scan {
    const char *body, *end;
    api_problem *prob;
} scan;

static inline const char *skip_ws(const char *p, const char *end) {
    while (p < end && (*p == ' ' || *p == '\n' || *p == '\r' || *p == '\t')) p++;
    return p;
}

/* Line and column (1-based, in bytes) of offset off in the body. */
static void line_col(const scan *sc, size_t off, long *line, long *col) {
    long l = 1;
    size_t start = 0;
    for (size_t i = 0; i < off; i++) {
        if (sc->body[i] == '\n') {
            l++;
            start = i + 1;
        }
    }
    *line = l;
    *col = (long)(off - start) + 1;
}

/* A description of the bytes at p for a syntax error: "end of input" or
 * the character, quoted. */
static void describe_at(const scan *sc, const char *p, char *dst, size_t size) {
    if (p >= sc->end) {
        snprintf(dst, size, "end of input");
        return;
    }
    char ex[24];
    api__quote_excerpt(ex, sizeof ex, p, 1, 1);
    snprintf(dst, size, "'%s'", ex);
}

/* API_MALFORMED at p: "<what>: unexpected <x> at byte N (line L, column
 * C)". pointer names the value being read (may be NULL). */
static api_code syntax_error(const scan *sc, const char *p, const char *pointer,
                             const char *what) {
    size_t off = (size_t)(p - sc->body);
    long line, col;
    line_col(sc, off, &line, &col);
    char at[32];
    describe_at(sc, p, at, sizeof at);
    const char *how = p >= sc->end ? "JSON ends early" : "invalid JSON";
    return api__problem_at(sc->prob, API_MALFORMED, pointer, 0,
                           "%s: %s, found %s at byte %zu (line %ld, column %ld)",
                           how, what, at, off, line, col);
}

/* Returns the byte after the string starting at the quote p, or NULL if it
 * is not terminated. Escapes are skipped, not checked (jansson or the key
 * decoder checks them). */
static const char *skip_string(const char *p, const char *end) {
    for (p++; p < end; p++) {
        if (*p == '"') return p + 1;
        if (*p == '\\') p++;
    }
    return NULL;
}

/* Returns the byte after the JSON value starting at p (not validated: a
 * scalar extends to the next delimiter), or NULL if a string or a bracket
 * is not closed. */
static const char *skip_value(const char *p, const char *end) {
    size_t depth = 0;
    while (p < end) {
        char c = *p;
        if (c == '"') {
            p = skip_string(p, end);
            if (p == NULL) return NULL;
            if (depth == 0) return p;
            continue;
        }
        if (c == '[' || c == '{') {
            depth++;
        } else if (c == ']' || c == '}') {
            if (depth == 0) return p; /* a scalar followed by a closer */
            if (--depth == 0) return p + 1;
        } else if (depth == 0 && (c == ',' || c == ' ' || c == '\n' ||
                                  c == '\r' || c == '\t' || c == ':')) {
            return p;
        }
        p++;
    }
    return depth == 0 ? p : NULL;
}

/* Decodes [v, vend) with jansson. On a JSON error sets a problem with the
 * position translated into the body and returns NULL. */
static json_t *decode_value(const scan *sc, const char *v, const char *vend,
                            const char *pointer) {
    json_error_t err;
    json_t *j = json_loadb(v, (size_t)(vend - v),
                           JSON_DECODE_ANY | JSON_REJECT_DUPLICATES, &err);
    if (j != NULL) return j;
    size_t off = (size_t)(v - sc->body) + (size_t)(err.position > 0 ? err.position : 0);
    if (off > (size_t)(sc->end - sc->body)) off = (size_t)(sc->end - sc->body);
    long line, col;
    line_col(sc, off, &line, &col);
    api_code code = API_MALFORMED;
    if (json_error_code(&err) == json_error_numeric_overflow) code = API_INVALID;
    if (json_error_code(&err) == json_error_out_of_memory) {
        out_of_memory(sc->prob);
        return NULL;
    }
    api__problem_at(sc->prob, code, pointer, 0,
                    "invalid JSON in %s: %s, at byte %zu (line %ld, column %ld)",
                    pointer, err.text, off, line, col);
    return NULL;
}

static const char *json_type_name(const json_t *j) {
    switch (json_typeof(j)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY: return "an array";
    case JSON_STRING: return "a string";
    case JSON_INTEGER:
    case JSON_REAL: return "a number";
    case JSON_TRUE:
    case JSON_FALSE: return "a boolean";
    default: return "null";
    }
}

/* Where a number array sits, for messages: the JSON pointer of the array
 * ("/points/17", "/bounds", "/3" in a bare array) and its name as people
 * write it ("points[17]", "bounds"). */
typedef struct place {
    const char *ptr_base; /* "/points" or "" (bare array) or "/bounds" */
    const char *name;     /* "points" or "bounds" */
    long index;           /* element of ptr_base, or -1 */
} place;

static void place_pointer(const place *pl, long k, char *dst, size_t size) {
    if (pl->index >= 0 && k >= 0) {
        snprintf(dst, size, "%s/%ld/%ld", pl->ptr_base, pl->index, k);
    } else if (pl->index >= 0) {
        snprintf(dst, size, "%s/%ld", pl->ptr_base, pl->index);
    } else if (k >= 0) {
        snprintf(dst, size, "%s/%ld", pl->ptr_base, k);
    } else {
        snprintf(dst, size, "%s", pl->ptr_base[0] ? pl->ptr_base : "");
    }
}

static void place_name(const place *pl, long k, char *dst, size_t size) {
    if (pl->index >= 0 && k >= 0) {
        snprintf(dst, size, "%s[%ld][%ld]", pl->name, pl->index, k);
    } else if (pl->index >= 0) {
        snprintf(dst, size, "%s[%ld]", pl->name, pl->index);
    } else if (k >= 0) {
        snprintf(dst, size, "%s[%ld]", pl->name, k);
    } else {
        snprintf(dst, size, "%s", pl->name);
    }
}

/* The value at p is not what was expected (a number, or an array). If it is
 * well-formed JSON, API_INVALID naming its type and text; otherwise the
 * syntax error. */
static api_code wrong_value(const scan *sc, const char *p, const place *pl,
                            long k, const char *expected) {
    char ptr[128], name[96], shown[96];
    place_pointer(pl, k, ptr, sizeof ptr);
    place_name(pl, k, name, sizeof name);
    /* NaN and Infinity are what other JSON writers emit for non-finite
     * numbers: say so plainly. */
    const char *q = p < sc->end && *p == '-' ? p + 1 : p;
    size_t left = (size_t)(sc->end - q);
    const char *word = NULL;
    if (left >= 3 && memcmp(q, "NaN", 3) == 0) word = "NaN";
    if (left >= 8 && memcmp(q, "Infinity", 8) == 0) word = "Infinity";
    if (left >= 3 && memcmp(q, "nan", 3) == 0) word = "nan";
    if (left >= 3 && memcmp(q, "inf", 3) == 0) word = "inf";
    if (word != NULL) {
        return api__problem_at(sc->prob, API_INVALID, ptr, 0,
                               "%s is %s%s, which is not a JSON number; "
                               "coordinates must be finite numbers",
                               name, q > p ? "-" : "", word);
    }
    const char *vend = skip_value(p, sc->end);
    json_t *j = NULL;
    if (vend != NULL && vend > p) {
        json_error_t err;
        j = json_loadb(p, (size_t)(vend - p), JSON_DECODE_ANY, &err);
    }
    if (j == NULL) {
        char what[160];
        snprintf(what, sizeof what, "expected %s for %s", expected, name);
        return syntax_error(sc, p, ptr, what);
    }
    api__quote_excerpt(shown, sizeof shown, p, (size_t)(vend - p), 40);
    api__problem_at(sc->prob, API_INVALID, ptr, 0, "%s is not %s: got %s %s",
                    name, expected, json_type_name(j), shown);
    json_decref(j);
    return API_INVALID;
}

/* Reads one JSON number at p into *out. */
static api_code read_number(const scan *sc, const char **pp, const place *pl,
                            long k, double *out) {
    const char *p = *pp, *stop;
    char c = p < sc->end ? *p : 0;
    if ((c != '-' && !(c >= '0' && c <= '9')) ||
        (c == '-' && p + 1 < sc->end && (p[1] == 'I' || p[1] == 'N' ||
                                         p[1] == 'i' || p[1] == 'n'))) {
        return wrong_value(sc, p, pl, k, "a number");
    }
    api_num st = api_num_parse_json(p, sc->end, out, &stop);
    if (st == API_NUM_OK && stop < sc->end) {
        char d = *stop;
        if (!(d == ',' || d == ']' || d == ' ' || d == '\n' || d == '\r' ||
              d == '\t' || d == '}')) {
            st = API_NUM_SYNTAX;
        }
    }
    if (st == API_NUM_OK) {
        *pp = stop;
        return API_OK;
    }
    char ptr[128], name[96], shown[96];
    place_pointer(pl, k, ptr, sizeof ptr);
    place_name(pl, k, name, sizeof name);
    if (st == API_NUM_OVERFLOW) {
        api__quote_excerpt(shown, sizeof shown, p, (size_t)(stop - p), 40);
        return api__problem_at(sc->prob, API_INVALID, ptr, 0,
                               "coordinate %s at %s overflows a double "
                               "(largest magnitude 1.7976931348623157e308)",
                               shown, ptr);
    }
    /* Show the whole malformed token, up to the next delimiter. */
    const char *e = p;
    while (e < sc->end && *e != ',' && *e != ']' && *e != ' ' && *e != '\n' &&
           *e != '\r' && *e != '\t' && *e != '}') {
        e++;
    }
    api__quote_excerpt(shown, sizeof shown, p, (size_t)(e - p), 40);
    char what[224];
    snprintf(what, sizeof what, "%s is not a valid JSON number: \"%s\"", name,
             shown);
    size_t off = (size_t)(stop - sc->body);
    long line, col;
    line_col(sc, off, &line, &col);
    return api__problem_at(sc->prob, API_MALFORMED, ptr, 0,
                           "invalid JSON: %s (byte %zu, line %ld, column %ld)",
                           what, off, line, col);
}

/* Reads a JSON array of numbers at *pp (which must be '[') into out[0..want-1],
 * counting the elements into *count (elements beyond want are read and
 * counted but not stored). */
static api_code read_number_array(const scan *sc, const char **pp,
                                  const place *pl, double *out, size_t want,
                                  size_t *count) {
    const char *p = *pp, *end = sc->end;
    size_t k = 0;
    p = skip_ws(p + 1, end);
    if (p < end && *p == ']') {
        *pp = p + 1;
        *count = 0;
        return API_OK;
    }
    for (;;) {
        double v;
        if (read_number(sc, &p, pl, (long)k, &v) != API_OK) {
            return sc->prob->code;
        }
        if (k < want) out[k] = v;
        k++;
        p = skip_ws(p, end);
        if (p < end && *p == ',') {
            p = skip_ws(p + 1, end);
            continue;
        }
        if (p < end && *p == ']') break;
        char ptr[128], name[96], what[160];
        place_pointer(pl, -1, ptr, sizeof ptr);
        place_name(pl, -1, name, sizeof name);
        snprintf(what, sizeof what, "expected ',' or ']' in %s", name);
        return syntax_error(sc, p, ptr, what);
    }
    *pp = p + 1;
    *count = k;
    return API_OK;
}

/* Reads the array of points at *pp (which must be '['). ptr_base is the
 * pointer of the array ("/points", or "" for a bare array). */
static api_code read_points(const scan *sc, const char **pp,
                            const char *ptr_base, points *pts) {
    const char *p = *pp, *end = sc->end;
    place pl = {ptr_base, "points", -1};
    /* Every point opens a bracket: counting them bounds the number of
     * points, so one allocation replaces the copies of repeated growth
     * (a pass of memchr costs far less than those copies). */
    if (pts->cap == 0) {
        size_t brackets = 0;
        for (const char *q = p + 1; q < end; q++) {
            q = memchr(q, '[', (size_t)(end - q));
            if (q == NULL) break;
            brackets++;
        }
        size_t cap = brackets < pts->max ? brackets : pts->max;
        if (cap > 0 && cap <= SIZE_MAX / (2 * sizeof(double))) {
            pts->xy = malloc(cap * 2 * sizeof(double));
            if (pts->xy == NULL) return out_of_memory(sc->prob);
            pts->cap = cap;
        }
    }
    p = skip_ws(p + 1, end);
    if (p < end && *p == ']') {
        *pp = p + 1;
        return API_OK;
    }
    for (;;) {
        pl.index = (long)pts->n;
        if (pts->n >= pts->max) {
            char ptr[128];
            place_pointer(&pl, -1, ptr, sizeof ptr);
            return too_many(sc->prob, ptr, 0, pts->max);
        }
        if (p >= end || *p != '[') {
            return wrong_value(sc, p, &pl, -1, "a pair [x, y]");
        }
        if (points_grow(pts)) return out_of_memory(sc->prob);
        double *xy = pts->xy + 2 * pts->n;
        /* The common case inline: [x, y] */
        const char *q = skip_ws(p + 1, end), *stop;
        if (q < end && (*q == '-' || (*q >= '0' && *q <= '9')) &&
            api_num_parse_json(q, end, &xy[0], &stop) == API_NUM_OK) {
            q = skip_ws(stop, end);
            if (q < end && *q == ',') {
                q = skip_ws(q + 1, end);
                if (q < end && (*q == '-' || (*q >= '0' && *q <= '9')) &&
                    api_num_parse_json(q, end, &xy[1], &stop) == API_NUM_OK) {
                    q = skip_ws(stop, end);
                    if (q < end && *q == ']') {
                        p = q + 1;
                        goto next;
                    }
                }
            }
        }
        /* Anything else: the general path, which also explains errors. */
        {
            size_t count;
            if (read_number_array(sc, &p, &pl, xy, 2, &count) != API_OK) {
                return sc->prob->code;
            }
            if (count != 2) {
                char ptr[128], name[96];
                place_pointer(&pl, -1, ptr, sizeof ptr);
                place_name(&pl, -1, name, sizeof name);
                return api__problem_at(sc->prob, API_INVALID, ptr, 0,
                                       "%s has %zu coordinate%s, expected 2",
                                       name, count, count == 1 ? "" : "s");
            }
        }
    next:
        pts->n++;
        p = skip_ws(p, end);
        if (p < end && *p == ',') {
            p = skip_ws(p + 1, end);
            if (p < end && *p == ']') {
                return syntax_error(sc, p, ptr_base[0] ? ptr_base : NULL,
                                    "trailing comma in points");
            }
            continue;
        }
        if (p < end && *p == ']') break;
        return syntax_error(sc, p, ptr_base[0] ? ptr_base : NULL,
                            "expected ',' or ']' after a point");
    }
    *pp = p + 1;
    return API_OK;
}

/* ---- Members other than points ----------------------------------------------- */

/* Longest "algorithm" or "format" string read without jansson, with its
 * terminator (the valid names are far shorter). */
#define PLAIN_MAX 32

static const char *const known_keys = "points, generate, algorithm, bounds, "
                                      "include, format, repeat, trace";

/* Escapes a key for a JSON pointer (RFC 6901: ~ -> ~0, / -> ~1). */
static void key_pointer(const char *key, char *dst, size_t size) {
    size_t o = 0;
    if (size < 2) return;
    dst[o++] = '/';
    for (; *key && o + 3 < size; key++) {
        if (*key == '~' || *key == '/') {
            dst[o++] = '~';
            dst[o++] = *key == '~' ? '0' : '1';
        } else {
            dst[o++] = *key;
        }
    }
    dst[o] = 0;
}

static api_code apply_algorithm(api_request *r, json_t *v, api_problem *p) {
    if (!json_is_string(v)) {
        return api__problem_at(p, API_INVALID, "/algorithm", 0,
                               "algorithm must be a string (fortune, "
                               "bowyer-watson or flip), got %s",
                               json_type_name(v));
    }
    return api__set_algorithm(r, json_string_value(v), "/algorithm", p);
}

static api_code apply_format(api_request *r, json_t *v, api_problem *p) {
    if (!json_is_string(v)) {
        return api__problem_at(p, API_INVALID, "/format", 0,
                               "format must be a string (json, geojson, svg, "
                               "binary or timings), got %s",
                               json_type_name(v));
    }
    return api__set_format(r, json_string_value(v), "/format", p);
}

static api_code apply_include(api_request *r, json_t *v, api_problem *p) {
    unsigned parts = 0;
    if (json_is_string(v)) {
        api_code c = api_request_option(r, "include", json_string_value(v), p);
        if (c != API_OK) snprintf(p->pointer, sizeof p->pointer, "/include");
        return c;
    }
    if (!json_is_array(v)) {
        return api__problem_at(p, API_INVALID, "/include", 0,
                               "include must be an array of part names, got %s",
                               json_type_name(v));
    }
    for (size_t i = 0; i < json_array_size(v); i++) {
        json_t *e = json_array_get(v, i);
        char ptr[32];
        snprintf(ptr, sizeof ptr, "/include/%zu", i);
        if (!json_is_string(e)) {
            return api__problem_at(p, API_INVALID, ptr, 0,
                                   "include[%zu] must be a part name, got %s", i,
                                   json_type_name(e));
        }
        if (api__add_part(&parts, json_string_value(e), json_string_length(e),
                          ptr, p) != API_OK) {
            return p->code;
        }
    }
    r->parts = parts;
    r->parts_given = 1;
    return API_OK;
}

static api_code apply_trace(api_request *r, json_t *v, api_problem *p) {
    if (!json_is_boolean(v)) {
        return api__problem_at(p, API_INVALID, "/trace", 0,
                               "trace must be true or false, got %s",
                               json_type_name(v));
    }
    r->trace = json_is_true(v);
    return API_OK;
}

/* "repeat": an integer 1..API_REPEAT_MAX (an integral real like 5.0 too,
 * as JSON does not tell them apart). */
static api_code apply_repeat(api_request *r, json_t *v, api_problem *p) {
    if (!json_is_number(v)) {
        return api__problem_at(p, API_INVALID, "/repeat", 0,
                               "repeat must be an integer from 1 to %d, got %s",
                               API_REPEAT_MAX, json_type_name(v));
    }
    return api__set_repeat(r, json_number_value(v), "/repeat", p);
}

/* {"distribution": "...", "n": N, "seed": S} -> generated points. */
static api_code apply_generate(api_request *r, json_t *v, const api_limits *lim,
                               api_problem *p) {
    if (!json_is_object(v)) {
        return api__problem_at(p, API_INVALID, "/generate", 0,
                               "generate must be an object {\"distribution\": "
                               "..., \"n\": ..., \"seed\": ...}, got %s",
                               json_type_name(v));
    }
    const char *key;
    json_t *val;
    json_object_foreach(v, key, val) {
        if (strcmp(key, "distribution") && strcmp(key, "n") &&
            strcmp(key, "seed")) {
            char ptr[128], shown[80];
            snprintf(ptr, sizeof ptr, "/generate");
            key_pointer(key, ptr + 9, sizeof ptr - 9);
            api__quote_excerpt(shown, sizeof shown, key, strlen(key), 40);
            return api__problem_at(p, API_MALFORMED, ptr, 0,
                                   "unknown key \"%s\" in generate; known: "
                                   "distribution, n, seed",
                                   shown);
        }
    }
    const char *dist = "uniform";
    json_t *d = json_object_get(v, "distribution");
    if (d != NULL) {
        if (!json_is_string(d)) {
            return api__problem_at(p, API_INVALID, "/generate/distribution", 0,
                                   "generate.distribution must be a string, "
                                   "got %s",
                                   json_type_name(d));
        }
        dist = json_string_value(d);
    }
    json_t *jn = json_object_get(v, "n");
    if (jn == NULL) {
        return api__problem_at(p, API_INVALID, "/generate/n", 0,
                               "generate.n (the number of points) is required");
    }
    /* 1e6 is a real to jansson but an integer to people. */
    double dn = json_is_number(jn) ? json_number_value(jn) : -1;
    if (!json_is_number(jn) || dn < 0 || dn != floor(dn)) {
        return api__problem_at(p, API_INVALID, "/generate/n", 0,
                               "generate.n must be a non-negative integer, "
                               "got %s",
                               json_is_number(jn) ? "another number"
                                                  : json_type_name(jn));
    }
    json_int_t n = json_is_integer(jn) ? json_integer_value(jn)
                   : dn >= 9.2e18 ? (json_int_t)INT64_MAX : (json_int_t)dn;
    if ((unsigned long long)n > (unsigned long long)lim->max_points) {
        return api__problem_at(p, API_TOO_LARGE, "/generate/n", 0,
                               "generate.n = %lld is more than %zu points (the "
                               "limit of this service)",
                               (long long)n, lim->max_points);
    }
    uint64_t seed = 1;
    json_t *js = json_object_get(v, "seed");
    if (js != NULL) {
        if (!json_is_integer(js) || json_integer_value(js) < 0) {
            return api__problem_at(p, API_INVALID, "/generate/seed", 0,
                                   "generate.seed must be a non-negative "
                                   "integer, got %s",
                                   json_is_integer(js) ? "a negative number"
                                                       : json_type_name(js));
        }
        seed = (uint64_t)json_integer_value(js);
    }
    double *xy;
    api_code c = api_generate(dist, (size_t)n, seed, &xy, p);
    if (c != API_OK) {
        if (c == API_INVALID) {
            snprintf(p->pointer, sizeof p->pointer, "/generate/distribution");
        }
        return c;
    }
    free(r->xy);
    r->xy = xy;
    r->n = (size_t)n;
    r->generated = 1;
    return API_OK;
}

/* Members of the top-level object, kept until the object is read so they
 * apply in a fixed order whatever their order in the body. */
typedef struct members {
    json_t *algorithm, *format, *include, *generate, *repeat, *trace;
    int has_points, has_bounds_null;
    int has_bounds;
    double bounds[4];
    /* "algorithm" and "format" given as plain strings (see plain_string):
     * the text itself, without a jansson value */
    char algorithm_s[PLAIN_MAX], format_s[PLAIN_MAX];
} members;

/* Reads the string at p (a quote) into dst when it is plain -- printable
 * ASCII without escapes, shorter than PLAIN_MAX -- and returns the byte
 * after it; NULL otherwise (the value then goes to jansson). A plain
 * string is exactly the string jansson would decode, so the answer is the
 * same; the point is the cost: a small request's "algorithm" is a visible
 * share of its parse time when it needs a jansson value. */
static const char *plain_string(const char *p, const char *end, char *dst) {
    const char *s = p + 1;
    for (size_t n = 0; s + n < end && n < PLAIN_MAX; n++) {
        unsigned char c = (unsigned char)s[n];
        if (c == '"') {
            if (n == 0) return NULL; /* "" is left to the full path */
            memcpy(dst, s, n);
            dst[n] = '\0';
            return s + n + 1;
        }
        if (c < 0x20 || c >= 0x7f || c == '\\') return NULL;
    }
    return NULL;
}

static void members_free(members *m) {
    json_decref(m->algorithm);
    json_decref(m->format);
    json_decref(m->include);
    json_decref(m->generate);
    json_decref(m->repeat);
    json_decref(m->trace);
}

/* Reads the key string at *pp (a quote) into key (decoded; *pp moves past
 * it). Keys longer than the buffer are cut (they are unknown anyway). */
static api_code read_key(const scan *sc, const char **pp, char *key,
                         size_t size) {
    const char *p = *pp, *q = skip_string(p, sc->end);
    if (q == NULL) return syntax_error(sc, sc->end, NULL, "unterminated key");
    if (memchr(p + 1, '\\', (size_t)(q - p - 2)) == NULL) {
        size_t n = (size_t)(q - p - 2);
        if (n >= size) n = size - 1;
        memcpy(key, p + 1, n);
        key[n] = 0;
        for (size_t i = 0; i < n; i++) {
            if ((unsigned char)key[i] < 0x20) {
                return syntax_error(sc, p + 1 + i, NULL,
                                    "control character in a key");
            }
        }
    } else {
        json_t *j = decode_value(sc, p, q, "a key");
        if (j == NULL) return sc->prob->code;
        snprintf(key, size, "%s", json_string_value(j));
        json_decref(j);
    }
    *pp = q;
    return API_OK;
}

/* Cuts the value at *pp out and decodes it with jansson into *slot. */
static api_code take_value(const scan *sc, const char **pp, const char *pointer,
                           json_t **slot) {
    const char *v = *pp, *vend = skip_value(v, sc->end);
    if (vend == NULL) {
        return syntax_error(sc, sc->end, pointer, "unterminated value");
    }
    if (vend == v) return syntax_error(sc, v, pointer, "expected a value");
    json_t *j = decode_value(sc, v, vend, pointer);
    if (j == NULL) return sc->prob->code;
    *slot = j;
    *pp = vend;
    return API_OK;
}

static api_code read_object(const scan *sc, const char **pp, points *pts,
                            members *m) {
    const char *p = skip_ws(*pp + 1, sc->end), *end = sc->end;
    if (p < end && *p == '}') {
        *pp = p + 1;
        return API_OK;
    }
    for (;;) {
        if (p >= end || *p != '"') {
            return syntax_error(sc, p, NULL, "expected a string key");
        }
        char key[96], ptr[128];
        if (read_key(sc, &p, key, sizeof key) != API_OK) return sc->prob->code;
        key_pointer(key, ptr, sizeof ptr);
        p = skip_ws(p, end);
        if (p >= end || *p != ':') {
            return syntax_error(sc, p, ptr, "expected ':' after a key");
        }
        p = skip_ws(p + 1, end);
        json_t **slot = NULL;
        int dup = 0;
        if (strcmp(key, "points") == 0) {
            dup = m->has_points;
            if (!dup) {
                m->has_points = 1;
                if (p < end && *p == '[') {
                    if (read_points(sc, &p, "/points", pts) != API_OK) {
                        return sc->prob->code;
                    }
                } else {
                    place pl = {"/points", "points", -1};
                    return wrong_value(sc, p, &pl, -1,
                                       "an array of points [[x, y], ...]");
                }
            }
        } else if (strcmp(key, "bounds") == 0) {
            dup = m->has_bounds || m->has_bounds_null;
            if (!dup) {
                place pl = {"/bounds", "bounds", -1};
                if (end - p >= 4 && memcmp(p, "null", 4) == 0) {
                    m->has_bounds_null = 1;
                    p += 4;
                } else if (p < end && *p == '[') {
                    size_t count;
                    if (read_number_array(sc, &p, &pl, m->bounds, 4, &count) !=
                        API_OK) {
                        return sc->prob->code;
                    }
                    if (count != 4) {
                        return api__problem_at(
                            sc->prob, API_INVALID, "/bounds", 0,
                            "bounds has %zu number%s, expected 4 [xmin, ymin, "
                            "xmax, ymax]",
                            count, count == 1 ? "" : "s");
                    }
                    m->has_bounds = 1;
                } else {
                    return wrong_value(sc, p, &pl, -1,
                                       "an array [xmin, ymin, xmax, ymax]");
                }
            }
        } else if (strcmp(key, "algorithm") == 0 ||
                   strcmp(key, "format") == 0) {
            int alg = key[0] == 'a';
            char *plain = alg ? m->algorithm_s : m->format_s;
            slot = alg ? &m->algorithm : &m->format;
            const char *q;
            if (*slot == NULL && plain[0] == '\0' && p < end && *p == '"' &&
                (q = plain_string(p, end, plain)) != NULL) {
                p = q;
                slot = NULL;
            } else {
                dup = plain[0] != '\0';
            }
        } else if (strcmp(key, "include") == 0) {
            slot = &m->include;
        } else if (strcmp(key, "generate") == 0) {
            slot = &m->generate;
        } else if (strcmp(key, "repeat") == 0) {
            slot = &m->repeat;
        } else if (strcmp(key, "trace") == 0) {
            slot = &m->trace;
        } else {
            char shown[80];
            api__quote_excerpt(shown, sizeof shown, key, strlen(key), 40);
            return api__problem_at(sc->prob, API_MALFORMED, ptr, 0,
                                   "unknown key \"%s\"; known: %s", shown,
                                   known_keys);
        }
        if (slot != NULL && !dup) {
            dup = *slot != NULL;
            if (!dup && take_value(sc, &p, ptr, slot) != API_OK) {
                return sc->prob->code;
            }
        }
        if (dup) {
            return api__problem_at(sc->prob, API_MALFORMED, ptr, 0,
                                   "duplicate key \"%s\"", key);
        }
        p = skip_ws(p, end);
        if (p < end && *p == ',') {
            p = skip_ws(p + 1, end);
            continue;
        }
        if (p < end && *p == '}') break;
        return syntax_error(sc, p, NULL, "expected ',' or '}' in the object");
    }
    *pp = p + 1;
    return API_OK;
}

static api_code parse_json(api_request *r, const char *body, size_t len,
                           const api_limits *lim, api_problem *prob) {
    scan sc = {body, body + len, prob};
    points pts = {NULL, 0, 0, lim->max_points};
    members m;
    memset(&m, 0, sizeof m);
    const char *p = body, *end = body + len;
    if (len >= 3 && memcmp(p, "\xef\xbb\xbf", 3) == 0) p += 3; /* BOM */
    p = skip_ws(p, end);
    api_code c = API_OK;
    int is_object = 0;
    if (p >= end) {
        c = api__problem_at(prob, API_MALFORMED, NULL, 0,
                            "empty body: send {\"points\": [[x, y], ...]} or "
                            "an array of points");
        goto done;
    }
    if (*p == '[') {
        c = read_points(&sc, &p, "", &pts);
    } else if (*p == '{') {
        is_object = 1;
        c = read_object(&sc, &p, &pts, &m);
    } else {
        place pl = {"", "the body", -1};
        c = wrong_value(&sc, p, &pl, -1,
                        "a JSON object or an array of points");
    }
    if (c != API_OK) goto done;
    p = skip_ws(p, end);
    if (p < end) {
        c = syntax_error(&sc, p, NULL, "unexpected data after the JSON document");
        goto done;
    }
    if (is_object) {
        if (m.algorithm_s[0] &&
            (c = api__set_algorithm(r, m.algorithm_s, "/algorithm", prob))) {
            goto done;
        }
        if (m.algorithm && (c = apply_algorithm(r, m.algorithm, prob))) goto done;
        if (m.format_s[0] &&
            (c = api__set_format(r, m.format_s, "/format", prob))) {
            goto done;
        }
        if (m.format && (c = apply_format(r, m.format, prob))) goto done;
        if (m.has_bounds && (c = api__set_bounds(r, m.bounds, "/bounds", prob))) {
            goto done;
        }
        if (m.include && (c = apply_include(r, m.include, prob))) goto done;
        if (m.repeat && (c = apply_repeat(r, m.repeat, prob))) goto done;
        if (m.trace && (c = apply_trace(r, m.trace, prob))) goto done;
        if (m.generate && m.has_points) {
            c = api__problem_at(prob, API_INVALID, "/generate", 0,
                                "give either points or generate, not both");
            goto done;
        }
        if (!m.generate && !m.has_points) {
            c = api__problem_at(prob, API_INVALID, NULL, 0,
                                "the request has neither \"points\" nor "
                                "\"generate\"");
            goto done;
        }
        if (m.generate) {
            c = apply_generate(r, m.generate, lim, prob);
            goto done;
        }
    }
    free(r->xy);
    r->xy = pts.xy;
    r->n = pts.n;
    r->generated = 0;
    pts.xy = NULL;
done:
    free(pts.xy);
    members_free(&m);
    return c;
}

/* ---- Text ----------------------------------------------------------------------- */

static inline int is_blank(char c) { return c == ' ' || c == '\t'; }

/* Whether the word [s, e) (no separators in it) is a number as strtod
 * reads one, whole: "5", "+.5", "1e3", "0x1p3", and the words nan, inf and
 * infinity in any case. Quotes around the word are ignored. */
static int word_is_number(const char *s, const char *e) {
    if (e - s >= 2 && *s == '"' && e[-1] == '"') {
        s++;
        e--;
    }
    size_t n = (size_t)(e - s);
    if (n == 0) return 0;
    char small[128], *w = n < sizeof small ? small : malloc(n + 1);
    if (w == NULL) return 1; /* cannot tell: not a header, then */
    memcpy(w, s, n);
    w[n] = '\0';
    char *stop;
    (void)strtod(w, &stop);
    int whole = stop == w + n;
    if (w != small) free(w);
    return whole;
}

/* A first line of column names ("x,y", "lon lat", "\"x\";\"y\""): starts
 * with a letter or a quote, holds only name characters and separators, and
 * none of its words is a number that strtod would read ("nan,0" and
 * "inf 5" are points, refused for their values, not names to skip). */
static int is_header(const char *s, const char *e) {
    if (s >= e || !((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') ||
                    *s == '"')) {
        return 0;
    }
    for (const char *c = s; c < e; c++) {
        if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') ||
              (*c >= '0' && *c <= '9') || *c == '_' || *c == '"' ||
              *c == ',' || *c == ';' || is_blank(*c))) {
            return 0;
        }
    }
    while (s < e) {
        while (s < e && (is_blank(*s) || *s == ',' || *s == ';')) s++;
        const char *w = s;
        while (s < e && !(is_blank(*s) || *s == ',' || *s == ';')) s++;
        if (s > w && word_is_number(w, s)) return 0;
    }
    return 1;
}

static api_code text_line_error(api_problem *p, long line, const char *s,
                                const char *e) {
    char shown[96];
    api__quote_excerpt(shown, sizeof shown, s, (size_t)(e - s), 60);
    return api__problem_at(p, API_MALFORMED, NULL, line,
                           "line %ld: expected two numbers, got \"%s\"", line,
                           shown);
}

/* One number of a text line at *pp (line content ends at e). */
static api_code text_number(api_problem *p, long line, const char **pp,
                            const char *s, const char *e, double *out) {
    const char *stop;
    api_num st = api_num_parse_text(*pp, e, out, &stop);
    if (st == API_NUM_OK) {
        if (stop < e && !(is_blank(*stop) || *stop == ',' || *stop == ';')) {
            return text_line_error(p, line, s, e);
        }
        *pp = stop;
        return API_OK;
    }
    if (st == API_NUM_SYNTAX) return text_line_error(p, line, s, e);
    char shown[64];
    api__quote_excerpt(shown, sizeof shown, *pp, (size_t)(stop - *pp), 40);
    if (st == API_NUM_OVERFLOW) {
        return api__problem_at(p, API_INVALID, NULL, line,
                               "line %ld: coordinate %s overflows a double "
                               "(largest magnitude 1.7976931348623157e308)",
                               line, shown);
    }
    return api__problem_at(p, API_INVALID, NULL, line,
                           "line %ld: coordinate \"%s\" is not a finite number",
                           line, shown);
}

static api_code parse_text(api_request *r, const char *body, size_t len,
                           const api_limits *lim, api_problem *prob) {
    points pts = {NULL, 0, 0, lim->max_points};
    const char *p = body, *end = body + len;
    if (len >= 3 && memcmp(p, "\xef\xbb\xbf", 3) == 0) p += 3;
    long line = 0, header_line = 0;
    int seen_content = 0;
    api_code c = API_OK;
    while (p < end) {
        line++;
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *e = nl ? nl : end, *next = nl ? nl + 1 : end;
        const char *hash = memchr(p, '#', (size_t)(e - p));
        if (hash) e = hash;
        while (e > p && (is_blank(e[-1]) || e[-1] == '\r')) e--;
        const char *s = p;
        while (s < e && is_blank(*s)) s++;
        p = next;
        if (s == e) continue;
        if (!seen_content) {
            seen_content = 1;
            if (is_header(s, e)) {
                header_line = line;
                continue;
            }
        }
        double x, y;
        const char *q = s;
        if ((c = text_number(prob, line, &q, s, e, &x)) != API_OK) goto done;
        while (q < e && is_blank(*q)) q++;
        if (q < e && (*q == ',' || *q == ';')) q++;
        while (q < e && is_blank(*q)) q++;
        if (q >= e) {
            c = text_line_error(prob, line, s, e);
            goto done;
        }
        if ((c = text_number(prob, line, &q, s, e, &y)) != API_OK) goto done;
        if (q != e) {
            c = text_line_error(prob, line, s, e);
            goto done;
        }
        if (pts.n >= pts.max) {
            c = too_many(prob, NULL, line, pts.max);
            goto done;
        }
        if (points_grow(&pts)) {
            c = out_of_memory(prob);
            goto done;
        }
        pts.xy[2 * pts.n] = x;
        pts.xy[2 * pts.n + 1] = y;
        pts.n++;
    }
    if (pts.n == 0 && header_line > 0) {
        /* Only names: a file that lost its data, or data that looks like
         * names; either way not an empty point set. */
        c = api__problem_at(prob, API_MALFORMED, NULL, header_line,
                            "line %ld was taken for column names and no line "
                            "holds a point (two numbers)", header_line);
        goto done;
    }
    free(r->xy);
    r->xy = pts.xy;
    r->n = pts.n;
    r->generated = 0;
    pts.xy = NULL;
done:
    free(pts.xy);
    return c;
}

/* ---- Binary --------------------------------------------------------------------- */

static double read_le_double(const unsigned char *b) {
    uint64_t u = 0;
    for (int i = 7; i >= 0; i--) u = (u << 8) | b[i];
    double v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static api_code parse_binary(api_request *r, const char *body, size_t len,
                             const api_limits *lim, api_problem *prob) {
    if (len % 16 != 0) {
        return api__problem_at(prob, API_MALFORMED, NULL, 0,
                               "binary body is %zu bytes, not a multiple of 16 "
                               "(each point is two little-endian float64)",
                               len);
    }
    size_t n = len / 16;
    if (n > lim->max_points) return too_many(prob, NULL, 0, lim->max_points);
    double *xy = NULL;
    if (n > 0) {
        xy = malloc(n * 2 * sizeof(double));
        if (xy == NULL) return out_of_memory(prob);
    }
    const unsigned char *b = (const unsigned char *)body;
    for (size_t i = 0; i < 2 * n; i++) {
        double v = read_le_double(b + 8 * i);
        if (!isfinite(v)) {
            char ptr[64];
            snprintf(ptr, sizeof ptr, "/points/%zu/%zu", i / 2, i % 2);
            free(xy);
            return api__problem_at(prob, API_INVALID, ptr, 0,
                                   "point %zu (bytes %zu..%zu): %s is %s, not a "
                                   "finite number",
                                   i / 2, 16 * (i / 2), 16 * (i / 2) + 15,
                                   i % 2 ? "y" : "x", isnan(v) ? "NaN" : "infinite");
        }
        xy[i] = v;
    }
    free(r->xy);
    r->xy = xy;
    r->n = n;
    r->generated = 0;
    return API_OK;
}

/* ---- Entry point ------------------------------------------------------------------ */

api_code api_parse_body(api_request *r, api_input kind, const char *body,
                        size_t len, const api_limits *lim, api_problem *p) {
    api_limits eff = {lim ? lim->max_points : VOR_MAX_POINTS};
    if (eff.max_points > VOR_MAX_POINTS) eff.max_points = VOR_MAX_POINTS;
    lim = &eff;
    if (body == NULL) {
        body = "";
        len = 0;
    }
    if (kind == API_IN_AUTO || kind == API_IN_PLAIN) {
        const char *s = body, *end = body + len;
        if (len >= 3 && memcmp(s, "\xef\xbb\xbf", 3) == 0) s += 3;
        s = skip_ws(s, end);
        int empty_json = kind == API_IN_AUTO; /* empty: the JSON message */
        kind = s < end && (*s == '{' || *s == '[') ? API_IN_JSON : API_IN_TEXT;
        if (s == end && empty_json) kind = API_IN_JSON;
    }
    api_code c;
    switch (kind) {
    case API_IN_JSON: c = parse_json(r, body, len, lim, p); break;
    case API_IN_TEXT: c = parse_text(r, body, len, lim, p); break;
    case API_IN_BINARY: c = parse_binary(r, body, len, lim, p); break;
    default:
        c = api__problem_at(p, API_INTERNAL, NULL, 0, "unknown input kind %d",
                            (int)kind);
    }
    if (c != API_OK) {
        free(r->xy);
        r->xy = NULL;
        r->n = 0;
        r->generated = 0;
    } else {
        p->code = API_OK;
    }
    return c;
}
