/* write_svg.c -- the diagram as image/svg+xml: a picture, not data.
 *
 * The box (the request's bounds, or the sites' bounding box expanded by
 * 10%) is mapped onto a viewBox whose larger side is 1000 units, y pointing
 * up as in the plane (SVG's y points down): x' = (x - xmin) * k,
 * y' = (ymax - y) * k, computed on halves so that boxes near DBL_MAX do not
 * overflow, and rounded to 0.001 unit (a thousandth of a pixel at the
 * default size). Edges are the diagram's edges clipped to the box (rays and
 * lines drawn to its border) in one path; sites are circles, one per
 * distinct site, whose radius shrinks as the sites get denser; strokes keep
 * their width at any zoom. Sites far outside the picture are left out. The
 * timings close the document in a comment. O(output). */
#include <math.h>
#include <string.h>

#include "codec.h"

typedef struct view {
    double x0, y1, k; /* xmin, ymax, scale of half-coordinates */
} view;

static double round3(double v) { return round(v * 1000) / 1000; }

static double vx(const view *v, double x) { return round3((x * 0.5 - v->x0 * 0.5) * v->k); }
static double vy(const view *v, double y) { return round3((v->y1 * 0.5 - y * 0.5) * v->k); }

int api__write_svg(const api_request *r, const api_result *res,
                   api_timings *t, double t0, api_buf *out) {
    (void)r;
    const vor_sites *s = res->sites;
    const vor_diagram *d = res->diagram;
    const vor_clipped *c = res->clipped;
    if (c == NULL) return -1;
    const double *box = c->box;
    double w2 = box[2] * 0.5 - box[0] * 0.5, h2 = box[3] * 0.5 - box[1] * 0.5;
    view v = {box[0], box[3], 1000 / (w2 > h2 ? w2 : h2)};
    double vw = round3(w2 * v.k), vh = round3(h2 * v.k);
    double radius = s->n > 0 ? 300 / sqrt((double)s->n) : 4;
    if (radius > 4) radius = 4;
    if (radius < 0.3) radius = 0.3;
    radius = round3(radius);

    if (api__reserve(out, 1024)) return -1;
    API__PUTS(out, "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 ");
    api__put_double(out, vw);
    api__putc(out, ' ');
    api__put_double(out, vh);
    API__PUTS(out, "\" width=\"");
    api__put_double(out, round(vw * 0.8));
    API__PUTS(out, "\" height=\"");
    api__put_double(out, round(vh * 0.8));
    API__PUTS(out, "\">\n<title>Voronoi diagram of ");
    api__put_u32(out, (uint32_t)s->n);
    API__PUTS(out, " sites (");
    api__put(out, vor_algorithm_name(res->algorithm),
             strlen(vor_algorithm_name(res->algorithm)));
    API__PUTS(out, ")</title>\n<desc>box [");
    for (int k = 0; k < 4; k++) {
        if (k) api__putc(out, ',');
        api__put_double(out, box[k]);
    }
    API__PUTS(out, "]</desc>\n<rect class=\"box\" x=\"0\" y=\"0\" width=\"");
    api__put_double(out, vw);
    API__PUTS(out, "\" height=\"");
    api__put_double(out, vh);
    API__PUTS(out, "\" fill=\"#fff\" stroke=\"#999\" "
                   "vector-effect=\"non-scaling-stroke\"/>\n"
                   "<path class=\"edges\" fill=\"none\" stroke=\"#1f5fa8\" "
                   "stroke-width=\"1\" vector-effect=\"non-scaling-stroke\" d=\"");
    for (size_t e = 0; e < d->n_edges; e++) {
        if (!c->seg_in[e]) continue;
        const double *g = c->seg + 4 * e;
        if (api__reserve(out, 4 * API_NUM_MAXLEN + 8)) return -1;
        api__putc(out, 'M');
        api__put_double(out, vx(&v, g[0]));
        api__putc(out, ' ');
        api__put_double(out, vy(&v, g[1]));
        api__putc(out, 'L');
        api__put_double(out, vx(&v, g[2]));
        api__putc(out, ' ');
        api__put_double(out, vy(&v, g[3]));
    }
    if (API_BUF_LIT(out, "\"/>\n<g class=\"sites\" fill=\"#c0392b\">\n")) return -1;
    for (size_t i = 0; i < s->n; i++) {
        double x = vx(&v, s->xy[2 * i]), y = vy(&v, s->xy[2 * i + 1]);
        if (!(fabs(x) < 1e7 && fabs(y) < 1e7)) continue;
        if (api__reserve(out, 3 * API_NUM_MAXLEN + 64)) return -1;
        API__PUTS(out, "<circle cx=\"");
        api__put_double(out, x);
        API__PUTS(out, "\" cy=\"");
        api__put_double(out, y);
        API__PUTS(out, "\" r=\"");
        api__put_double(out, radius);
        API__PUTS(out, "\"/>\n");
    }
    if (API_BUF_LIT(out, "</g>\n<!-- timings ")) return -1;
    api__finish_timings(t, t0);
    if (api__put_timings(out, t)) return -1;
    return API_BUF_LIT(out, " -->\n</svg>\n");
}
