/* request.c -- request options: defaults, the values every front end
 * shares (algorithm, format, parts, bounds, repeat) and the HTTP negotiation of
 * input (Content-Type) and output (Accept) formats.
 *
 * One validator per option value, used by JSON bodies (with a JSON pointer)
 * and by api_request_option (query strings, command-line flags), so a value
 * is accepted or refused with the same words everywhere. Header parsing is
 * linear in the header's length and allocates nothing. */
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "codec.h"

api_code api__problem_at(api_problem *p, api_code code, const char *pointer,
                         long line, const char *fmt, ...) {
    va_list ap;
    p->code = code;
    va_start(ap, fmt);
    vsnprintf(p->detail, sizeof p->detail, fmt, ap);
    va_end(ap);
    snprintf(p->pointer, sizeof p->pointer, "%s", pointer ? pointer : "");
    p->line = line;
    return code;
}

void api_request_init(api_request *r) {
    memset(r, 0, sizeof *r);
    r->algorithm = VOR_FORTUNE;
    r->parts = API_PART_DEFAULT;
    r->format = API_FMT_JSON;
}

void api_request_clear(api_request *r) {
    free(r->xy);
    api_request_init(r);
}

/* ---- Option values ------------------------------------------------------ */

static const char *const format_names[] = {
    [API_FMT_JSON] = "json",       [API_FMT_GEOJSON] = "geojson",
    [API_FMT_SVG] = "svg",         [API_FMT_BINARY] = "binary",
    [API_FMT_TIMINGS] = "timings",
};

static const struct {
    const char *name;
    unsigned bit;
} part_names[] = {
    {"vertices", API_PART_VERTICES}, {"edges", API_PART_EDGES},
    {"cells", API_PART_CELLS},       {"triangles", API_PART_TRIANGLES},
    {"sites", API_PART_SITES},       {"clipped", API_PART_CLIPPED},
    {"counts", API_PART_COUNTS},
};

const char *api__format_name(api_format f) {
    return (unsigned)f < sizeof format_names / sizeof format_names[0]
               ? format_names[f]
               : "json";
}

api_code api__set_algorithm(api_request *r, const char *name,
                            const char *pointer, api_problem *p) {
    vor_algorithm a;
    if (vor_algorithm_parse(name, &a) != VOR_OK) {
        char shown[80];
        api__quote_excerpt(shown, sizeof shown, name, strlen(name), 40);
        return api__problem_at(p, API_INVALID, pointer, 0,
                               "unknown algorithm \"%s\"; valid: %s, %s, %s",
                               shown, vor_algorithm_name(VOR_FORTUNE),
                               vor_algorithm_name(VOR_BOWYER_WATSON),
                               vor_algorithm_name(VOR_FLIP));
    }
    r->algorithm = a;
    return API_OK;
}

api_code api__set_format(api_request *r, const char *name,
                         const char *pointer, api_problem *p) {
    for (size_t i = 0; i < sizeof format_names / sizeof format_names[0]; i++) {
        if (strcmp(name, format_names[i]) == 0) {
            r->format = (api_format)i;
            return API_OK;
        }
    }
    char shown[80];
    api__quote_excerpt(shown, sizeof shown, name, strlen(name), 40);
    return api__problem_at(p, API_INVALID, pointer, 0,
                           "unknown format \"%s\"; valid: json, geojson, svg, "
                           "binary, timings",
                           shown);
}

api_code api__add_part(unsigned *parts, const char *name, size_t n,
                       const char *pointer, api_problem *p) {
    for (size_t i = 0; i < sizeof part_names / sizeof part_names[0]; i++) {
        if (strlen(part_names[i].name) == n &&
            memcmp(part_names[i].name, name, n) == 0) {
            *parts |= part_names[i].bit;
            return API_OK;
        }
    }
    char shown[80];
    api__quote_excerpt(shown, sizeof shown, name, n, 40);
    return api__problem_at(p, API_INVALID, pointer, 0,
                           "unknown part \"%s\" in include; valid: vertices, "
                           "edges, cells, triangles, sites, clipped, counts",
                           shown);
}

api_code api__set_bounds(api_request *r, const double b[4],
                         const char *pointer, api_problem *p) {
    static const char *const names[4] = {"xmin", "ymin", "xmax", "ymax"};
    for (int i = 0; i < 4; i++) {
        if (!isfinite(b[i])) {
            return api__problem_at(p, API_INVALID, pointer, 0,
                                   "bounds: %s is not a finite number",
                                   names[i]);
        }
    }
    for (int i = 0; i < 2; i++) {
        if (!(b[i] < b[i + 2])) {
            char lo[API_NUM_MAXLEN + 1], hi[API_NUM_MAXLEN + 1];
            lo[api_num_format(b[i], lo)] = 0;
            hi[api_num_format(b[i + 2], hi)] = 0;
            return api__problem_at(p, API_INVALID, pointer, 0,
                                   "bounds: %s %s must be less than %s %s "
                                   "([xmin, ymin, xmax, ymax])",
                                   names[i], lo, names[i + 2], hi);
        }
    }
    memcpy(r->bounds, b, sizeof r->bounds);
    r->has_bounds = 1;
    return API_OK;
}

api_code api__set_repeat(api_request *r, double v, const char *pointer,
                         api_problem *p) {
    if (v >= 1 && v <= API_REPEAT_MAX && v == floor(v)) {
        r->repeat = (int)v;
        return API_OK;
    }
    char shown[API_NUM_MAXLEN + 1];
    size_t n = api_num_format(v, shown);
    shown[n] = 0;
    return api__problem_at(p, API_INVALID, pointer, 0,
                           "repeat %s is %s; give an integer from 1 to %d",
                           n ? shown : "?",
                           v != floor(v) ? "not an integer" : "out of range",
                           API_REPEAT_MAX);
}

int api_compare_repeat(const api_request *r, size_t n_sites) {
    if (r->repeat > 0) return r->repeat;
    return n_sites <= 20000 ? 5 : n_sites <= 200000 ? 3 : 1;
}

unsigned api__effective_parts(const api_request *r) {
    unsigned parts = r->parts;
    if (r->has_bounds && !r->parts_given) parts |= API_PART_CLIPPED;
    return parts;
}

int api__needs_clip(const api_request *r) {
    if (r->format == API_FMT_GEOJSON || r->format == API_FMT_SVG) return 1;
    if (r->format == API_FMT_TIMINGS) return r->has_bounds;
    return (api__effective_parts(r) & API_PART_CLIPPED) != 0;
}

/* Moves lo down and hi up by pad, keeping them finite and distinct. */
static void widen(double *lo, double *hi, double pad) {
    double a = *lo - pad, b = *hi + pad;
    if (!isfinite(a)) a = -1.7976931348623157e308;
    if (!isfinite(b)) b = 1.7976931348623157e308;
    if (!(a < *lo) && a > -1.7976931348623157e308) a = nextafter(*lo, -INFINITY);
    if (!(b > *hi) && b < 1.7976931348623157e308) b = nextafter(*hi, INFINITY);
    *lo = a;
    *hi = b;
}

void api__default_box(const vor_sites *s, double box[4]) {
    if (s == NULL || s->n == 0) {
        box[0] = box[1] = -1;
        box[2] = box[3] = 1;
        return;
    }
    double x0 = s->xy[0], y0 = s->xy[1], x1 = x0, y1 = y0;
    for (size_t i = 1; i < s->n; i++) {
        double x = s->xy[2 * i], y = s->xy[2 * i + 1];
        if (x < x0) x0 = x;
        if (x > x1) x1 = x;
        if (y < y0) y0 = y;
        if (y > y1) y1 = y;
    }
    /* Halves first: the width of a box near DBL_MAX would overflow. */
    double w = x1 * 0.5 - x0 * 0.5, h = y1 * 0.5 - y0 * 0.5;
    double pad = 0.2 * (w > h ? w : h);
    if (pad == 0) {
        double m = fmax(fmax(fabs(x0), fabs(x1)), fmax(fabs(y0), fabs(y1)));
        pad = m > 10 ? 0.1 * m : 1;
    }
    widen(&x0, &x1, pad);
    widen(&y0, &y1, pad);
    box[0] = x0;
    box[1] = y0;
    box[2] = x1;
    box[3] = y1;
}

/* ---- api_request_option -------------------------------------------------- */

/* Parses "xmin,ymin,xmax,ymax" (spaces allowed around the numbers). */
static api_code option_bounds(api_request *r, const char *v, api_problem *p) {
    double b[4];
    const char *s = v, *end = v + strlen(v);
    for (int i = 0; i < 4; i++) {
        while (s < end && (*s == ' ' || *s == '\t')) s++;
        const char *stop;
        api_num st = api_num_parse_text(s, end, &b[i], &stop);
        while (stop < end && (*stop == ' ' || *stop == '\t')) stop++;
        int sep_ok = i < 3 ? (stop < end && *stop == ',') : stop == end;
        if (st == API_NUM_OVERFLOW || st == API_NUM_NONFINITE) {
            char shown[80];
            api__quote_excerpt(shown, sizeof shown, s, (size_t)(stop - s), 40);
            return api__problem_at(p, API_INVALID, NULL, 0,
                                   "bounds: \"%s\" is not a finite number",
                                   shown);
        }
        if (st != API_NUM_OK || !sep_ok) {
            char shown[120];
            api__quote_excerpt(shown, sizeof shown, v, strlen(v), 80);
            return api__problem_at(p, API_INVALID, NULL, 0,
                                   "bounds \"%s\" must be four comma-separated "
                                   "numbers xmin,ymin,xmax,ymax",
                                   shown);
        }
        s = stop + (i < 3);
    }
    return api__set_bounds(r, b, NULL, p);
}

api_code api_request_option(api_request *r, const char *key, const char *value,
                            api_problem *p) {
    if (key == NULL) key = "";
    if (value == NULL) value = "";
    if (strcmp(key, "algorithm") == 0) {
        return api__set_algorithm(r, value, NULL, p);
    }
    if (strcmp(key, "format") == 0) return api__set_format(r, value, NULL, p);
    if (strcmp(key, "bounds") == 0) return option_bounds(r, value, p);
    if (strcmp(key, "repeat") == 0) {
        double v;
        const char *stop, *end = value + strlen(value);
        if (api_num_parse_text(value, end, &v, &stop) != API_NUM_OK ||
            stop != end) {
            char shown[80];
            api__quote_excerpt(shown, sizeof shown, value, strlen(value), 40);
            return api__problem_at(p, API_INVALID, NULL, 0,
                                   "repeat \"%s\" is not a number; give an "
                                   "integer from 1 to %d",
                                   shown, API_REPEAT_MAX);
        }
        return api__set_repeat(r, v, NULL, p);
    }
    if (strcmp(key, "include") == 0) {
        unsigned parts = 0;
        const char *s = value;
        while (*s) {
            const char *e = strchr(s, ',');
            size_t n = e ? (size_t)(e - s) : strlen(s);
            while (n > 0 && *s == ' ') { s++; n--; }
            while (n > 0 && s[n - 1] == ' ') n--;
            if (n > 0 && api__add_part(&parts, s, n, NULL, p) != API_OK) {
                return p->code;
            }
            if (e == NULL) break;
            s = e + 1;
        }
        r->parts = parts;
        r->parts_given = 1;
        return API_OK;
    }
    if (strcmp(key, "trace") == 0) {
        if (strcmp(value, "true") == 0 || strcmp(value, "false") == 0) {
            r->trace = value[0] == 't';
            return API_OK;
        }
        char shown[80];
        api__quote_excerpt(shown, sizeof shown, value, strlen(value), 40);
        return api__problem_at(p, API_INVALID, NULL, 0,
                               "trace must be true or false, got \"%s\"",
                               shown);
    }
    char shown[80];
    api__quote_excerpt(shown, sizeof shown, key, strlen(key), 40);
    return api__problem_at(p, API_MALFORMED, NULL, 0,
                           "unknown option \"%s\"; known: algorithm, bounds, "
                           "format, include, repeat, trace",
                           shown);
}

/* ---- Content negotiation -------------------------------------------------- */

/* Copies the media type of a header value (before ';', trimmed, lower
 * case) into dst; returns its length, or (size_t)-1 if it does not fit. */
static size_t media_type(const char *v, size_t n, char *dst, size_t size) {
    while (n > 0 && (*v == ' ' || *v == '\t')) { v++; n--; }
    const char *semi = memchr(v, ';', n);
    if (semi) n = (size_t)(semi - v);
    while (n > 0 && (v[n - 1] == ' ' || v[n - 1] == '\t')) n--;
    if (n >= size) return (size_t)-1;
    for (size_t i = 0; i < n; i++) dst[i] = (char)tolower((unsigned char)v[i]);
    dst[n] = 0;
    return n;
}

api_code api_input_from_content_type(const char *content_type, api_input *out,
                                     api_problem *p) {
    char t[128];
    size_t n = content_type ? media_type(content_type, strlen(content_type), t,
                                         sizeof t)
                            : 0;
    if (n == 0 || (n != (size_t)-1 &&
                   strcmp(t, "application/x-www-form-urlencoded") == 0)) {
        *out = API_IN_AUTO;
        return API_OK;
    }
    if (n != (size_t)-1) {
        if (strcmp(t, "application/json") == 0 || strcmp(t, "text/json") == 0 ||
            (strncmp(t, "application/", 12) == 0 && n > 5 &&
             strcmp(t + n - 5, "+json") == 0)) {
            *out = API_IN_JSON;
            return API_OK;
        }
        if (strcmp(t, "text/csv") == 0 ||
            strcmp(t, "text/tab-separated-values") == 0) {
            *out = API_IN_TEXT;
            return API_OK;
        }
        if (strcmp(t, "text/plain") == 0) {
            *out = API_IN_PLAIN;
            return API_OK;
        }
        if (strcmp(t, "application/octet-stream") == 0) {
            *out = API_IN_BINARY;
            return API_OK;
        }
    }
    char shown[80];
    api__quote_excerpt(shown, sizeof shown, content_type,
                       strlen(content_type), 60);
    return api__problem_at(p, API_MEDIA_TYPE, NULL, 0,
                           "unsupported Content-Type \"%s\"; send "
                           "application/json, text/csv, text/plain or "
                           "application/octet-stream",
                           shown);
}

static const struct {
    const char *mime;
    api_format format;
} produced[] = {
    {"application/json", API_FMT_JSON},
    {"application/geo+json", API_FMT_GEOJSON},
    {"image/svg+xml", API_FMT_SVG},
    {"application/octet-stream", API_FMT_BINARY},
};

const char *api_format_mime(api_format f) {
    for (size_t i = 0; i < sizeof produced / sizeof produced[0]; i++) {
        if (produced[i].format == f) return produced[i].mime;
    }
    return "application/json"; /* timings */
}

/* The q value of a media range's parameters (1 when absent; -1 if
 * malformed). */
static double quality(const char *params, size_t n) {
    const char *s = params, *end = params + n;
    while (s < end) {
        while (s < end && (*s == ';' || *s == ' ' || *s == '\t')) s++;
        if (end - s >= 2 && (s[0] == 'q' || s[0] == 'Q') && s[1] == '=') {
            double q;
            const char *stop;
            if (api_num_parse_text(s + 2, end, &q, &stop) != API_NUM_OK ||
                q < 0 || q > 1) {
                return -1;
            }
            return q;
        }
        while (s < end && *s != ';') s++;
    }
    return 1;
}

/* Index in produced[] for a media range, -2 for a full wildcard, -1 for no
 * match. */
static int match_range(const char *t) {
    if (strcmp(t, "*/*") == 0) return -2;
    size_t n = strlen(t);
    for (size_t i = 0; i < sizeof produced / sizeof produced[0]; i++) {
        const char *m = produced[i].mime;
        if (strcmp(t, m) == 0) return (int)i;
        if (n >= 2 && strcmp(t + n - 2, "/*") == 0 &&
            strncmp(t, m, n - 1) == 0) {
            return (int)i;
        }
    }
    return -1;
}

api_code api_format_from_accept(api_request *r, const char *accept,
                                api_problem *p) {
    if (accept == NULL) return API_OK;
    const char *s = accept;
    double best_q = 0;
    int best = -1, any = 0, seen_range = 0;
    while (*s) {
        const char *e = strchr(s, ',');
        size_t n = e ? (size_t)(e - s) : strlen(s);
        char t[96];
        size_t tn = media_type(s, n, t, sizeof t);
        if (tn != (size_t)-1 && tn > 0) {
            seen_range = 1;
            const char *semi = memchr(s, ';', n);
            double q = semi ? quality(semi, n - (size_t)(semi - s)) : 1;
            int m = match_range(t);
            if (q > best_q && m != -1) {
                best_q = q;
                best = m;
                any = 1;
            }
        }
        if (e == NULL) break;
        s = e + 1;
    }
    if (!seen_range) return API_OK;
    if (!any) {
        char shown[120];
        api__quote_excerpt(shown, sizeof shown, accept, strlen(accept), 80);
        return api__problem_at(p, API_NOT_ACCEPTABLE, NULL, 0,
                               "cannot produce any of \"%s\"; available: "
                               "application/json, application/geo+json, "
                               "image/svg+xml, application/octet-stream",
                               shown);
    }
    if (best >= 0) r->format = produced[best].format;
    return API_OK;
}
