/* clip.c -- vor_clip: the diagram restricted to a box (edges and cell
 * polygons), for drawing, GeoJSON and areas.
 *
 * Edges: Liang-Barsky on the parametric form of each edge (segment between
 * its vertices, ray from its vertex along ray_dir, line through the
 * midpoint of its sites along ray_dir); ends that are diagram vertices are
 * copied exactly, computed ends are clamped into the box.
 *
 * Cells: each cell is first written as a convex polygon in homogeneous
 * coordinates (x, y, w): its vertices in counter-clockwise order (w = 1)
 * and, for an unbounded cell, the directions of its two rays as points at
 * infinity (w = 0); the arc at infinity between them closes the polygon.
 * That polygon is clipped by the four half-planes of the box with
 * Sutherland-Hodgman, which works unchanged on points at infinity: the
 * combination of a finite point P and a direction D is the point of the ray
 * P + sD on the clipping line. After the four clips only finite points are
 * left. This costs O(k) for a cell of k edges (O(total cell size) overall),
 * handles unbounded cells and sites outside the box, and gives neighbouring
 * polygons exactly the same shared corners (the diagram's own vertex
 * coordinates), so that the areas of all polygons add up to the box.
 The polygon must lie in an open half of the projective sphere, which
 * holds for every unbounded cell of a diagram with vertices (its two rays
 * span less than a half-turn). Cells without vertices (one site, or
 * collinear sites: the plane, half-planes and strips) do not satisfy it;
 * they, and cells with a vertex whose coordinates overflowed (possible for
 * nearly collinear sites of magnitude near DBL_MAX), are instead cut out of
 * the box by the bisector half-planes of their neighbours: O(1) for the
 * former, O(k^2) for the latter. Edges ending at an overflowed vertex are
 * reported as outside the box.
 *
 * Output polygons are counter-clockwise and explicitly closed (the first
 * point is repeated at the end, as GeoJSON rings are); a cell that misses
 * the box, or meets it in a point or a segment only, has no points.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

typedef struct hpt {
    double x, y, w; /* w = 1: the point (x, y); w = 0: the direction (x, y) */
} hpt;

void vor_clipped_free(vor_clipped *c) {
    if (!c) return;
    free(c->seg);
    free(c->seg_in);
    free(c->poly_start);
    free(c->poly_xy);
    free(c);
}

static double clampd(double v, double lo, double hi) {
    return v < lo ? lo : v > hi ? hi : v;
}

static int finite2(const double *p) { return isfinite(p[0]) && isfinite(p[1]); }

/* ---- edges: Liang-Barsky -------------------------------------------------- */

/* Clips P0 + t D, t in [*t0, *t1], to the box. Returns 1 if a piece of
 * positive parameter length remains, with [*t0, *t1] narrowed. */
static int liang_barsky(const double *box, const double *p0, const double *dir,
                        double *t0, double *t1) {
    const double p[4] = {-dir[0], dir[0], -dir[1], dir[1]};
    const double q[4] = {p0[0] - box[0], box[2] - p0[0], p0[1] - box[1],
                         box[3] - p0[1]};
    for (int k = 0; k < 4; k++) {
        if (p[k] == 0) {
            if (q[k] < 0) return 0;
            continue;
        }
        double r = q[k] / p[k];
        if (p[k] < 0) {
            if (r > *t0) *t0 = r;
        } else {
            if (r < *t1) *t1 = r;
        }
    }
    return *t0 < *t1;
}

/* How far p lies outside the box (0 inside), in the larger axis. */
static double far_from(const double *box, const double *p) {
    double dx = fmax(box[0] - p[0], p[0] - box[2]);
    double dy = fmax(box[1] - p[1], p[1] - box[3]);
    return fmax(fmax(dx, dy), 0);
}

static void clip_edge(const vor_diagram *d, const double *xy, const double *box,
                      size_t e, const size_t *ray_of, vor_clipped *c) {
    const int32_t *en = d->edge_ends + 2 * e;
    double *out = c->seg + 4 * e;
    double p0[2], dir[2], t0, t1;
    const double *v0 = en[0] >= 0 ? d->vertex_xy + 2 * (size_t)en[0] : NULL;
    const double *v1 = en[1] >= 0 ? d->vertex_xy + 2 * (size_t)en[1] : NULL;
    c->seg_in[e] = 0;
    memset(out, 0, 4 * sizeof *out);
    if ((v0 && !finite2(v0)) || (v1 && !finite2(v1))) return;
    /* from the end nearer the box: the parameters and the points are
     * computed relative to p0, and a far vertex (the centre of three
     * sites nearly on a line, 10^14 away) would leave its rounding, a
     * hundredth there, in the point on the box */
    int swapped = 0;
    if (v0 && v1 && far_from(box, v0) > far_from(box, v1)) {
        const double *t = v0;
        v0 = v1;
        v1 = t;
        swapped = 1;
    }
    if (v0 && v1) {
        p0[0] = v0[0];
        p0[1] = v0[1];
        dir[0] = v1[0] - v0[0];
        dir[1] = v1[1] - v0[1];
        t0 = 0;
        t1 = 1;
        if (!isfinite(dir[0]) || !isfinite(dir[1])) { /* far apart */
            dir[0] = v1[0] * 0.5 - v0[0] * 0.5;
            dir[1] = v1[1] * 0.5 - v0[1] * 0.5;
            t1 = 2;
        }
    } else {
        const double *r = d->ray_dir + 2 * ray_of[e];
        dir[0] = r[0];
        dir[1] = r[1];
        if (v0) {
            p0[0] = v0[0];
            p0[1] = v0[1];
            t0 = 0;
        } else {
            const double *a = xy + 2 * (size_t)d->edge_sites[2 * e];
            const double *b = xy + 2 * (size_t)d->edge_sites[2 * e + 1];
            p0[0] = a[0] * 0.5 + b[0] * 0.5;
            p0[1] = a[1] * 0.5 + b[1] * 0.5;
            t0 = -INFINITY;
        }
        t1 = INFINITY;
    }
    double s0 = t0, s1 = t1;
    if (!liang_barsky(box, p0, dir, &s0, &s1)) return;
    if (v0 && s0 == t0) {
        out[0] = v0[0];
        out[1] = v0[1];
    } else {
        out[0] = clampd(p0[0] + s0 * dir[0], box[0], box[2]);
        out[1] = clampd(p0[1] + s0 * dir[1], box[1], box[3]);
    }
    if (v1 && s1 == t1) {
        out[2] = v1[0];
        out[3] = v1[1];
    } else {
        out[2] = clampd(p0[0] + s1 * dir[0], box[0], box[2]);
        out[3] = clampd(p0[1] + s1 * dir[1], box[1], box[3]);
    }
    if (swapped) { /* the ends back in the edge's order */
        double x = out[0], y = out[1];
        out[0] = out[2];
        out[1] = out[3];
        out[2] = x;
        out[3] = y;
    }
    c->seg_in[e] = 1;
}

/* ---- cells: Sutherland-Hodgman in homogeneous coordinates ----------------- */

/* Signed distance-like value of h against the half-plane k of the box
 * (0: x >= xmin, 1: x <= xmax, 2: y >= ymin, 3: y <= ymax); inside <= 0.
 * For a direction it is the sign of its component across the boundary. */
static double side_of(const double *box, int k, const hpt *h) {
    switch (k) {
    case 0: return h->w ? box[0] - h->x : -h->x;
    case 1: return h->w ? h->x - box[2] : h->x;
    case 2: return h->w ? box[1] - h->y : -h->y;
    default: return h->w ? h->y - box[3] : h->y;
    }
}

/* The point of segment P-Q (either may be at infinity) on boundary k, given
 * their values hp, hq of opposite signs. */
static hpt crossing(const double *box, int k, const hpt *p, double hp,
                    const hpt *q, double hq) {
    hpt x;
    if (p->w && q->w) {
        double t = hp / (hp - hq);
        double dx = q->x - p->x, dy = q->y - p->y;
        if (isfinite(dx) && isfinite(dy)) {
            x.x = p->x + t * dx;
            x.y = p->y + t * dy;
        } else { /* corners near +-DBL_MAX: the difference overflows */
            x.x = p->x * (1 - t) + q->x * t;
            x.y = p->y * (1 - t) + q->y * t;
        }
        x.w = 1;
    } else if (p->w || q->w) { /* finite F, direction D: F + s D */
        const hpt *f = p->w ? p : q, *dd = p->w ? q : p;
        double hf = p->w ? hp : hq, hd = p->w ? hq : hp;
        double s = -hf / hd;
        x.x = f->x + s * dd->x;
        x.y = f->y + s * dd->y;
        x.w = 1;
    } else { /* two directions: the boundary's own direction at infinity */
        double lp = hq / (hq - hp), lq = -hp / (hq - hp); /* both > 0 */
        x.x = lp * p->x + lq * q->x;
        x.y = lp * p->y + lq * q->y;
        double m = fmax(fabs(x.x), fabs(x.y));
        if (m > 0) {
            x.x /= m;
            x.y /= m;
        }
        x.w = 0;
        return x;
    }
    switch (k) { /* exactly on the boundary */
    case 0: x.x = box[0]; break;
    case 1: x.x = box[2]; break;
    case 2: x.y = box[1]; break;
    default: x.y = box[3]; break;
    }
    return x;
}

/* Clips polygon in[0..n-1] by box half-plane k into out; returns the new
 * size (at most n + 1 for a convex polygon). */
static size_t clip_box_side(const double *box, int k, const hpt *in, size_t n,
                            hpt *out) {
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        const hpt *p = in + i, *q = in + (i + 1 == n ? 0 : i + 1);
        double hp = side_of(box, k, p), hq = side_of(box, k, q);
        if (hp <= 0) out[m++] = *p;
        if ((hp <= 0) != (hq <= 0) && !(hp == 0 || hq == 0))
            out[m++] = crossing(box, k, p, hp, q, hq);
    }
    return m;
}

/* Clips in[0..n-1] (scratch: both buffers, cap entries each) by the four
 * sides of the box; returns the size and leaves the result in *res. */
static size_t clip_to_box(const double *box, hpt *a, hpt *b, size_t n,
                          hpt **res) {
    for (int k = 0; k < 4 && n > 0; k++) {
        n = clip_box_side(box, k, a, n, b);
        hpt *t = a;
        a = b;
        b = t;
    }
    *res = a;
    return n;
}

/* Cell of site i, cut out of the box by its neighbours' bisector
 * half-planes (points p with (q - s) . (p - m) <= 0, m the midpoint):
 * for cells whose vertices are not finite. O(k^2). */
static size_t clip_by_bisectors(const vor_diagram *d, const double *xy,
                                const double *box, uint32_t i, hpt *a, hpt *b,
                                hpt **res) {
    static const int corner[4][2] = {{0, 1}, {2, 1}, {2, 3}, {0, 3}};
    size_t n = 4;
    for (int k = 0; k < 4; k++) {
        a[k].x = box[corner[k][0]];
        a[k].y = box[corner[k][1]];
        a[k].w = 1;
    }
    const double *s = xy + 2 * (size_t)i;
    for (uint32_t t = d->cell_start[i]; t < d->cell_start[i + 1] && n > 0; t++) {
        uint32_t e = d->cell_edges[t];
        uint32_t j = d->edge_sites[2 * (size_t)e] == i ? d->edge_sites[2 * (size_t)e + 1]
                                                        : d->edge_sites[2 * (size_t)e];
        const double *q = xy + 2 * (size_t)j;
        double nx = q[0] * 0.5 - s[0] * 0.5, ny = q[1] * 0.5 - s[1] * 0.5;
        double mx = s[0] * 0.5 + q[0] * 0.5, my = s[1] * 0.5 + q[1] * 0.5;
        double sc = fmax(fabs(nx), fabs(ny));
        nx /= sc;
        ny /= sc;
        size_t m = 0;
        for (size_t u = 0; u < n; u++) {
            const hpt *p = a + u, *r = a + (u + 1 == n ? 0 : u + 1);
            double hp = nx * (p->x - mx) + ny * (p->y - my);
            double hr = nx * (r->x - mx) + ny * (r->y - my);
            if (hp <= 0) b[m++] = *p;
            if ((hp < 0 && hr > 0) || (hp > 0 && hr < 0)) {
                double tt = hp / (hp - hr);
                b[m].x = clampd(p->x + tt * (r->x - p->x), box[0], box[2]);
                b[m].y = clampd(p->y + tt * (r->y - p->y), box[1], box[3]);
                b[m].w = 1;
                m++;
            }
        }
        n = m;
        hpt *x = a;
        a = b;
        b = x;
    }
    *res = a;
    return n;
}

/* Writes cell i of a diagram with vertices as a homogeneous polygon into
 * poly, and the bounding box of its finite points into bb (xmin, ymin,
 * xmax, ymax); returns its size, or 0 if a vertex is not finite. */
static size_t cell_polygon(const vor_diagram *d, const size_t *ray_of,
                           uint32_t i, hpt *poly, double *bb) {
    const uint32_t *L = d->cell_edges + d->cell_start[i];
    size_t k = d->cell_start[i + 1] - d->cell_start[i], m = 0;
    int bounded = d->cell_bounded[i];
    size_t steps = bounded ? k : k - 1;
    bb[0] = bb[1] = INFINITY;
    bb[2] = bb[3] = -INFINITY;
    if (!bounded) {
        const double *r = d->ray_dir + 2 * ray_of[L[0]];
        poly[m++] = (hpt){r[0], r[1], 0};
    }
    for (size_t t = 0; t < steps; t++) {
        const int32_t *p = d->edge_ends + 2 * (size_t)L[t];
        const int32_t *q = d->edge_ends + 2 * (size_t)L[t + 1 == k ? 0 : t + 1];
        int32_t v = p[0] >= 0 && (p[0] == q[0] || p[0] == q[1]) ? p[0] : p[1];
        const double *c = d->vertex_xy + 2 * (size_t)v;
        if (!finite2(c)) return 0;
        poly[m++] = (hpt){c[0], c[1], 1};
        bb[0] = c[0] < bb[0] ? c[0] : bb[0];
        bb[1] = c[1] < bb[1] ? c[1] : bb[1];
        bb[2] = c[0] > bb[2] ? c[0] : bb[2];
        bb[3] = c[1] > bb[3] ? c[1] : bb[3];
    }
    if (!bounded) {
        const double *r = d->ray_dir + 2 * ray_of[L[k - 1]];
        poly[m++] = (hpt){r[0], r[1], 0};
    }
    return m;
}

/* Appends the finite points of poly[0..n-1] to out as a closed ring, after
 * removing repeated points; nothing if fewer than three distinct points or
 * no area remain. sc is the power of two that scales the box's larger
 * side into [1, 2) (exact): differences are scaled by it before they are
 * multiplied, so that the area test neither overflows for boxes near
 * 1e300 nor underflows for boxes near 1e-300. Returns the number of
 * points written. */
static size_t emit_ring(const double *box, double sc, const hpt *poly,
                        size_t n, double *out) {
    size_t m = 0;
    for (size_t u = 0; u < n; u++) {
        if (poly[u].w == 0) continue;
        double x = clampd(poly[u].x, box[0], box[2]);
        double y = clampd(poly[u].y, box[1], box[3]);
        if (m > 0 && out[2 * m - 2] == x && out[2 * m - 1] == y) continue;
        out[2 * m] = x;
        out[2 * m + 1] = y;
        m++;
    }
    while (m > 1 && out[0] == out[2 * m - 2] && out[1] == out[2 * m - 1]) m--;
    if (m < 3) return 0;
    double area2 = 0;
    for (size_t u = 0; u < m; u++) {
        size_t v = u + 1 == m ? 0 : u + 1;
        area2 += ((out[2 * u] - out[0]) * sc) * ((out[2 * v + 1] - out[1]) * sc) -
                 ((out[2 * v] - out[0]) * sc) * ((out[2 * u + 1] - out[1]) * sc);
    }
    if (!(area2 > 0)) return 0;
    out[2 * m] = out[0];
    out[2 * m + 1] = out[1];
    return m + 1;
}

/* How far ahead the passes fetch: the edge pass, the vertices of the
 * edge this many on; the cell pass, the edges' ends of the cell
 * CELL_AHEAD on, and the vertices of the cell half as far (whose ends
 * have arrived by then). */
#define EDGE_AHEAD 16
#define CELL_AHEAD 8

/* The cell pass reads each cell's edges' ends and their vertices, at
 * random: fetched ahead in two steps, as the records of the conversion
 * are (mesh_dual.c); for an unbounded cell, the numbers of its two rays
 * too (every cell of sites in convex position). Fetching the rays'
 * directions as well, a step later, made uniform sites 70% slower. */
static inline void prefetch_cells(const vor_diagram *d, const size_t *ray_of,
                                  uint32_t i, size_t n) {
    if (i + CELL_AHEAD < n) {
        const uint32_t a = d->cell_start[i + CELL_AHEAD],
                       b = d->cell_start[i + CELL_AHEAD + 1];
        for (uint32_t t = a; t < b; t++)
            __builtin_prefetch(d->edge_ends + 2 * (size_t)d->cell_edges[t]);
        if (!d->cell_bounded[i + CELL_AHEAD]) { /* its rays' numbers */
            __builtin_prefetch(ray_of + d->cell_edges[a]);
            __builtin_prefetch(ray_of + d->cell_edges[b - 1]);
        }
    }
    if (i + CELL_AHEAD / 2 < n) {
        for (uint32_t t = d->cell_start[i + CELL_AHEAD / 2];
             t < d->cell_start[i + CELL_AHEAD / 2 + 1]; t++) {
            const int32_t *en = d->edge_ends + 2 * (size_t)d->cell_edges[t];
            if (en[0] >= 0) __builtin_prefetch(d->vertex_xy + 2 * (size_t)en[0]);
            if (en[1] >= 0) __builtin_prefetch(d->vertex_xy + 2 * (size_t)en[1]);
        }
    }
}

vor_status vor_clip(const vor_diagram *d, const vor_sites *sites,
                    const double box[4], vor_clipped **out) {
    vor_status st = VOR_ENOMEM;
    vor_clipped *c = NULL;
    size_t *ray_of = NULL;
    hpt *buf_a = NULL, *buf_b = NULL;

    if (!out) return VOR_EINVAL;
    *out = NULL;
    if (!d || !sites || !box || d->n_sites != sites->n) return VOR_EINVAL;
    for (int k = 0; k < 4; k++)
        if (!isfinite(box[k])) return VOR_EBOUNDS;
    if (!(box[0] < box[2] && box[1] < box[3])) return VOR_EBOUNDS;

    const size_t n = d->n_sites, ne = d->n_edges, nv = d->n_vertices;
    const double *xy = sites->xy;
    size_t maxk = 0;
    for (size_t i = 0; i < n; i++) {
        size_t k = d->cell_start[i + 1] - d->cell_start[i];
        if (k > maxk) maxk = k;
    }
    size_t cap_poly = 2 * ne + 9 * n; /* k + 9 points per cell at most */

    c = calloc(1, sizeof *c);
    if (!c) goto fail;
    memcpy(c->box, box, sizeof c->box);
    c->seg = vor__alloc_large(4 * ne, sizeof *c->seg);
    c->seg_in = vor__alloc_large(ne, 1);
    c->poly_start = vor__alloc_large(n + 1, sizeof *c->poly_start);
    c->poly_xy = vor__alloc_large(2 * cap_poly, sizeof *c->poly_xy);
    ray_of = vor__alloc_large(ne, sizeof *ray_of);
    buf_a = malloc((maxk + 12) * sizeof *buf_a);
    buf_b = malloc((maxk + 12) * sizeof *buf_b);
    if (!c->seg || !c->seg_in || !c->poly_start || !c->poly_xy || !ray_of ||
        !buf_a || !buf_b)
        goto fail;
    for (size_t r = 0; r < d->n_rays; r++) ray_of[d->ray_edge[r]] = r;

    /* Edges are in site order and their vertices all over the array:
     * the vertices of the edge EDGE_AHEAD on are fetched while this one
     * is clipped (at 10^6 sites each read was a miss, two thirds of
     * vor_clip's time went to waiting for them). */
    for (size_t e = 0; e < ne; e++) {
        if (e + EDGE_AHEAD < ne) {
            const int32_t *en = d->edge_ends + 2 * (e + EDGE_AHEAD);
            if (en[0] >= 0) __builtin_prefetch(d->vertex_xy + 2 * (size_t)en[0]);
            if (en[1] >= 0) __builtin_prefetch(d->vertex_xy + 2 * (size_t)en[1]);
        }
        clip_edge(d, xy, box, e, ray_of, c);
    }

    const double sc =
        ldexp(1.0, -ilogb(fmax(box[2] - box[0], box[3] - box[1])));
    size_t used = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (nv > 0) prefetch_cells(d, ray_of, i, n);
        c->poly_start[i] = (uint32_t)used;
        hpt *res = buf_a;
        size_t m;
        double bb[4]; /* the cell's vertices' bounding box */
        if (nv == 0) { /* the plane, a half-plane or a strip */
            m = clip_by_bisectors(d, xy, box, i, buf_a, buf_b, &res);
        } else if ((m = cell_polygon(d, ray_of, i, buf_a, bb)) > 0) {
            /* A bounded cell in the closed box is its own clip (the four
             * passes would copy it point for point), and one wholly
             * beyond a side of the box has none: nearly every cell of a
             * box around the sites, or of a small box, skips the passes. */
            const int bounded = d->cell_bounded[i];
            if (bounded && bb[0] >= box[0] && bb[1] >= box[1] &&
                bb[2] <= box[2] && bb[3] <= box[3])
                res = buf_a;
            else if (bounded && (bb[2] < box[0] || bb[0] > box[2] ||
                                 bb[3] < box[1] || bb[1] > box[3]))
                m = 0;
            else
                m = clip_to_box(box, buf_a, buf_b, m, &res);
        } else {
            m = clip_by_bisectors(d, xy, box, i, buf_a, buf_b, &res);
        }
        used += emit_ring(box, sc, res, m, c->poly_xy + 2 * used);
    }
    c->poly_start[n] = (uint32_t)used;
    if (used < cap_poly) {
        double *p = realloc(c->poly_xy, (used ? used : 1) * 2 * sizeof *p);
        if (p) c->poly_xy = p;
    }
    free(ray_of);
    free(buf_a);
    free(buf_b);
    *out = c;
    return VOR_OK;

fail:
    free(ray_of);
    free(buf_a);
    free(buf_b);
    vor_clipped_free(c);
    return st;
}
