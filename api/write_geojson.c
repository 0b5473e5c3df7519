/* write_geojson.c -- the diagram as application/geo+json (RFC 7946).
 *
 * A FeatureCollection with one Feature per distinct site, in increasing
 * input index: its geometry is the site's cell clipped to the box, a
 * Polygon whose one ring is closed (first point repeated) and
 * counter-clockwise as RFC 7946 asks, or null when the cell misses the box;
 * its properties are {"site": input index, "bounded": whether the unclipped
 * cell is finite}. The box is the request's bounds, or else the sites'
 * bounding box expanded by 10% on every side; the collection says which in
 * foreign members ("bounds_given", and a "bounds_note" for the default) and
 * gives the box as its "bbox". Timings come last, as a foreign member, and
 * a newline ends the document.
 * Coordinates are written exactly as computed (shortest round trip), not
 * rounded to RFC 7946's suggested 6 digits: the planar coordinates need not
 * be degrees. O(output). */
#include "codec.h"

int api__write_geojson(const api_request *r, const api_result *res,
                       api_timings *t, double t0, api_buf *out) {
    const vor_sites *s = res->sites;
    const vor_clipped *c = res->clipped;
    if (c == NULL) return -1;
    api_buf_printf(out, "{\"type\":\"FeatureCollection\",\"algorithm\":\"%s\","
                        "\"n_input\":%zu,\"n_sites\":%zu,\"bbox\":[",
                   vor_algorithm_name(res->algorithm), s->n_input, s->n);
    if (api__reserve(out, 4 * API_NUM_MAXLEN + 200)) return -1;
    for (int k = 0; k < 4; k++) {
        if (k) api__putc(out, ',');
        api__put_double(out, c->box[k]);
    }
    if (r->has_bounds) {
        API__PUTS(out, "],\"bounds_given\":true,\"features\":[");
    } else {
        API__PUTS(out, "],\"bounds_given\":false,\"bounds_note\":\"no bounds "
                       "given: cells are clipped to the sites' bounding box "
                       "expanded by 10% on every side\",\"features\":[");
    }
    for (size_t i = 0; i < s->n; i++) {
        uint32_t lo = c->poly_start[i], hi = c->poly_start[i + 1];
        if (api__reserve(out, 160)) return -1;
        if (i) api__putc(out, ',');
        API__PUTS(out, "{\"type\":\"Feature\",\"geometry\":");
        if (hi - lo < 3) {
            API__PUTS(out, "null");
        } else {
            /* vor_clip closes its rings; close one that is not. */
            const double *first = c->poly_xy + 2 * (size_t)lo;
            const double *last = c->poly_xy + 2 * (size_t)(hi - 1);
            uint32_t end = first[0] == last[0] && first[1] == last[1] ? hi : hi + 1;
            API__PUTS(out, "{\"type\":\"Polygon\",\"coordinates\":[[");
            for (uint32_t k = lo; k < end; k++) {
                const double *xy = k < hi ? c->poly_xy + 2 * (size_t)k : first;
                if (api__reserve(out, 2 * API_NUM_MAXLEN + 8)) return -1;
                if (k > lo) api__putc(out, ',');
                api__putc(out, '[');
                api__put_double(out, xy[0]);
                api__putc(out, ',');
                api__put_double(out, xy[1]);
                api__putc(out, ']');
            }
            API__PUTS(out, "]]}");
        }
        if (api__reserve(out, 64)) return -1;
        API__PUTS(out, ",\"properties\":{\"site\":");
        api__put_u32(out, api__input_index(s, i));
        if (res->diagram->cell_bounded[i]) {
            API__PUTS(out, ",\"bounded\":true}}");
        } else {
            API__PUTS(out, ",\"bounded\":false}}");
        }
    }
    if (API_BUF_LIT(out, "],\"timings\":")) return -1;
    api__finish_timings(t, t0);
    if (api__put_timings(out, t)) return -1;
    return API_BUF_LIT(out, "}\n");
}
