/* test_clip.c -- vor_clip: clipped edges and cell polygons.
 *
 * Diagrams come from the brute-force oracle (oracle_voronoi.h) through the
 * builder, and from the degenerate builder. Properties checked against
 * independent computations: the polygons tile the box (areas add up to the
 * box area, relative 1e-9), each is closed, counter-clockwise and convex,
 * every box corner lies in the polygon of its nearest site and in no other,
 * sites inside the box lie inside their own polygon, clipped edges lie in
 * the box on the bisector of their two sites. Random sets use fixed seeds,
 * printed.
 */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../core/internal.h"
#include "../support/testsets.h"
#include "oracle_voronoi.h"
#include "fault_alloc.h"

static vor_sites *sites_of(const double *xy, size_t n) {
    vor_sites *s = NULL;
    assert_int_equal(vor_sites_new(xy, n, &s, NULL), VOR_OK);
    assert_non_null(s);
    return s;
}

static void sites_done(vor_sites *s) { vor_sites_free(s); }

static vor_diagram *diagram_of(const vor_sites *s) {
    vor_diagram *d = NULL;
    if (vor__all_collinear(s)) {
        assert_int_equal(vor__diagram_degenerate(s, &d), VOR_OK);
        return d;
    }
    bf_voronoi b;
    assert_int_equal(bf_voronoi_make(s, &b), 0);
    uint32_t *edges;
    int32_t *ends;
    assert_int_equal(bf_raw(&b, 0, &edges, &ends), 0);
    assert_int_equal(vor__diagram_build(s, b.nv, edges, ends, b.ne, &d), VOR_OK);
    bf_free(&b);
    return d;
}

/* Scale applied to coordinate differences before they are multiplied, an
 * exact power of two chosen per box so that areas of boxes at 1e300 or
 * 1e-300 neither overflow nor underflow. */
static double sc = 1.0;

static double cross3(const double *o, const double *a, const double *b) {
    return ((a[0] - o[0]) * sc) * ((b[1] - o[1]) * sc) -
           ((a[1] - o[1]) * sc) * ((b[0] - o[0]) * sc);
}

/* Point p inside the closed convex ccw ring of m + 1 points, or outside by
 * at most dtol (a distance, in scaled units) plus the rounding of the
 * computed corners (atol, an area: a corner's error times p's distance).
 * The tolerance is a distance and not a fixed area: against a tiny cell
 * (multi-scale sets have cells a billionth of the box wide) a fixed area
 * would accept points far outside it. */
static int in_ring(const double *ring, size_t m, const double *p, double dtol,
                   double atol) {
    for (size_t u = 0; u < m; u++) {
        const double *a = ring + 2 * u, *b = a + 2;
        double len = hypot((b[0] - a[0]) * sc, (b[1] - a[1]) * sc);
        if (cross3(a, b, p) < -(dtol * len + atol)) return 0;
    }
    return 1;
}

/* in_ring's atol for ring (m + 1 points): a corner's rounding, at the
 * ring's own magnitude, times a distance across the box (w + h). With
 * the box's magnitude instead, a cell 10^-10 wide in a box 10^10 wide
 * (a dense cluster and a stray) took in every point of the box. */
static double ring_atol(const double *ring, size_t m, double w, double h) {
    double mag = 0;
    for (size_t u = 0; u <= m; u++)
        mag = fmax(mag, fmax(fabs(ring[2 * u]), fabs(ring[2 * u + 1])));
    return 64 * DBL_EPSILON * mag * sc * (w + h);
}

/* All the properties of one clipping. */
static void check_clip(const vor_diagram *d, const vor_sites *s,
                       const double *box, const char *what) {
    vor_clipped *c = NULL;
    assert_int_equal(vor_clip(d, s, box, &c), VOR_OK);
    assert_memory_equal(c->box, box, 4 * sizeof *box);
    sc = ldexp(1.0, -ilogb(fmax(box[2] - box[0], box[3] - box[1])));
    const double w = (box[2] - box[0]) * sc, h = (box[3] - box[1]) * sc;
    /* computed corners are off by a few ulps of the coordinates' magnitude:
     * far from the origin (offset 1e9) that dominates */
    double mag = 0;
    for (int k = 0; k < 4; k++) mag = fmax(mag, fabs(box[k]));
    const double ulps = 64 * DBL_EPSILON * mag * sc;
    const double tol = 1e-9 * w * h + ulps * (w + h);
    /* for in_ring: the relative part as a distance, with the rounding of
     * a point of the box's magnitude; a ring's corners' apart (ring_atol) */
    const double dtol = 1e-9 * w * h / (w + h) + ulps;
    double total = 0;
    assert_int_equal(c->poly_start[0], 0);
    for (size_t i = 0; i < s->n; i++) {
        size_t lo = c->poly_start[i], np = c->poly_start[i + 1] - lo;
        const double *ring = c->poly_xy + 2 * lo;
        if (np == 0) continue;
        if (np < 4) fail_msg("%s: cell %zu has %zu points", what, i, np);
        size_t m = np - 1;
        if (ring[0] != ring[2 * m] || ring[1] != ring[2 * m + 1])
            fail_msg("%s: cell %zu is not closed", what, i);
        double area2 = 0;
        for (size_t u = 0; u < m; u++) {
            const double *p = ring + 2 * u;
            if (p[0] < box[0] || p[0] > box[2] || p[1] < box[1] || p[1] > box[3])
                fail_msg("%s: cell %zu point %zu outside the box", what, i, u);
            area2 += cross3(ring, p, p + 2);
            /* convex and counter-clockwise: every corner turns left */
            const double *q = ring + 2 * ((u + 1) % m), *r = ring + 2 * ((u + 2) % m);
            if (cross3(p, q, r) < -tol)
                fail_msg("%s: cell %zu turns right at point %zu", what, i, u + 1);
        }
        if (!(area2 > 0)) fail_msg("%s: cell %zu is not counter-clockwise", what, i);
        total += area2 / 2;
        /* a site inside the box is inside its own polygon */
        const double *site = s->xy + 2 * i;
        if (site[0] > box[0] && site[0] < box[2] && site[1] > box[1] &&
            site[1] < box[3] &&
            !in_ring(ring, m, site, dtol, ring_atol(ring, m, w, h)))
            fail_msg("%s: site %zu is outside its own polygon", what, i);
    }
    if (s->n > 0 && fabs(total - w * h) > 1e-9 * w * h)
        fail_msg("%s: polygons cover %.17g of a box of area %.17g", what, total, w * h);

    /* each corner: in the polygon of the nearest site, in no other */
    for (int k = 0; k < 4 && s->n > 0; k++) {
        double corner[2] = {box[k == 1 || k == 2 ? 2 : 0], box[k >= 2 ? 3 : 1]};
        size_t best = 0;
        double bd = INFINITY, second = INFINITY;
        for (size_t i = 0; i < s->n; i++) {
            double dx = (s->xy[2 * i] - corner[0]) * sc;
            double dy = (s->xy[2 * i + 1] - corner[1]) * sc;
            double dd = dx * dx + dy * dy;
            if (dd < bd) {
                second = bd;
                bd = dd;
                best = i;
            } else if (dd < second) {
                second = dd;
            }
        }
        if (second - bd < 1e-6 * (bd + w * w)) continue; /* a near tie */
        for (size_t i = 0; i < s->n; i++) {
            size_t lo = c->poly_start[i], np = c->poly_start[i + 1] - lo;
            const double *ring = c->poly_xy + 2 * lo;
            int in = np > 0 && in_ring(ring, np - 1, corner, dtol,
                                      ring_atol(ring, np - 1, w, h));
            if (in != (i == best))
                fail_msg("%s: corner %d %s the polygon of site %zu (nearest: %zu)",
                         what, k, in ? "lies in" : "is missing from", i, best);
        }
    }

    /* clipped edges: in the box, on the bisector of their sites */
    for (size_t e = 0; e < d->n_edges; e++) {
        if (!c->seg_in[e]) continue;
        const double *g = c->seg + 4 * e;
        const double *a = s->xy + 2 * d->edge_sites[2 * e];
        const double *b = s->xy + 2 * d->edge_sites[2 * e + 1];
        for (int t = 0; t < 2; t++) {
            const double *p = g + 2 * t;
            if (p[0] < box[0] || p[0] > box[2] || p[1] < box[1] || p[1] > box[3])
                fail_msg("%s: edge %zu end %d outside the box", what, e, t);
            double da = hypot(p[0] - a[0], p[1] - a[1]);
            double db = hypot(p[0] - b[0], p[1] - b[1]);
            if (fabs(da - db) > 1e-7 * (da + db + w / sc) + ulps / sc)
                fail_msg("%s: edge %zu end %d is not on the bisector", what, e, t);
        }
    }
    vor_clipped_free(c);
}

/* ---- tests --------------------------------------------------------------- */

static void test_random_sets(void **state) {
    (void)state;
    const uint64_t seed0 = 9001;
    printf("random clips: seeds %llu..%llu\n", (unsigned long long)seed0,
           (unsigned long long)seed0 + 99);
    for (uint64_t seed = seed0; seed < seed0 + 100; seed++) {
        vt_rng r = {seed};
        size_t n = 3 + (size_t)(vt_next(&r) % 35);
        double *xy;
        if (seed % 2) {
            xy = vt_uniform(n, seed);
        } else { /* lattice: cocircular vertices, edges on grid lines */
            xy = malloc(2 * n * sizeof *xy);
            for (size_t i = 0; i < 2 * n; i++) xy[i] = (double)(vt_next(&r) % 8) / 8;
        }
        vor_sites *s = sites_of(xy, n);
        free(xy);
        vor_diagram *d = diagram_of(s);
        char what[80];
        const double boxes[5][4] = {
            {-0.5, -0.5, 1.5, 1.5},     /* everything inside */
            {0.2, 0.3, 0.7, 0.6},       /* cuts through the middle */
            {0.9, -2.0, 5.0, 0.05},     /* mostly outside the sites */
            {10.0, 10.0, 11.0, 12.0},   /* far away: a few cells */
            {0.41, 0.42, 0.41 + 1e-6, 0.42 + 1e-6}, /* tiny */
        };
        for (int k = 0; k < 5; k++) {
            double box[4];
            for (int j = 0; j < 4; j++) box[j] = boxes[k][j];
            snprintf(what, sizeof what, "seed %llu box %d", (unsigned long long)seed, k);
            check_clip(d, s, box, what);
        }
        vor_diagram_free(d);
        sites_done(s);
    }
}

/* Algorithm output on every standard set: the sites' bounding box grown by
 * 10% (every cell meets it) and a box over the middle third. */
static void test_standard_sets(void **state) {
    (void)state;
    for (size_t k = 0; k < vt_count(); k++) {
        vt_set set;
        assert_int_equal(vt_make(k, &set), 0);
        vor_sites *s = sites_of(set.xy, set.n);
        vor_diagram *d = NULL;
        assert_int_equal(vor_compute(s, VOR_FLIP, &d), VOR_OK);
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (size_t i = 0; i < s->n; i++)
            for (int j = 0; j < 2; j++) {
                if (s->xy[2 * i + j] < lo[j]) lo[j] = s->xy[2 * i + j];
                if (s->xy[2 * i + j] > hi[j]) hi[j] = s->xy[2 * i + j];
            }
        for (int j = 0; j < 2 && s->n > 0; j++)
            if (hi[j] == lo[j]) {
                lo[j] -= 1;
                hi[j] += 1;
            }
        double w = hi[0] - lo[0], h = hi[1] - lo[1];
        if (s->n == 0) {
            printf("  %-20s skipped\n", set.name);
        } else {
            char what[80];
            double grown[4] = {lo[0] - w / 10, lo[1] - h / 10, hi[0] + w / 10,
                               hi[1] + h / 10};
            double mid[4] = {lo[0] + w / 3, lo[1] + h / 3, hi[0] - w / 3, hi[1] - h / 3};
            snprintf(what, sizeof what, "%s, grown box", set.name);
            check_clip(d, s, grown, what);
            snprintf(what, sizeof what, "%s, middle box", set.name);
            check_clip(d, s, mid, what);
            /* grown box: every cell meets it */
            vor_clipped *c = NULL;
            assert_int_equal(vor_clip(d, s, grown, &c), VOR_OK);
            for (size_t i = 0; i < s->n; i++)
                if (c->poly_start[i + 1] == c->poly_start[i])
                    fail_msg("%s: cell %zu misses the grown bounding box", set.name, i);
            vor_clipped_free(c);
            printf("  %-20s ok\n", set.name);
        }
        vor_diagram_free(d);
        sites_done(s);
        vt_set_free(&set);
    }
}

static void test_square_exact(void **state) {
    (void)state;
    /* square with centre: the centre's cell is the diamond |x|+|y| <= 1
     * (through the bisectors), clipped by the box [-1,1]^2 it stays whole */
    static const double pts[] = {-1, -1, 1, -1, 1, 1, -1, 1, 0, 0};
    vor_sites *s = sites_of(pts, 5);
    vor_diagram *d = diagram_of(s);
    const double box[4] = {-1, -1, 1, 1};
    check_clip(d, s, box, "square");
    vor_clipped *c = NULL;
    assert_int_equal(vor_clip(d, s, box, &c), VOR_OK);
    size_t lo = c->poly_start[4], np = c->poly_start[5] - lo;
    assert_int_equal(np, 5);
    double area2 = 0;
    const double *q = c->poly_xy + 2 * lo;
    for (size_t u = 0; u + 1 < np; u++)
        area2 += q[2 * u] * q[2 * u + 3] - q[2 * u + 2] * q[2 * u + 1];
    assert_true(area2 == 4.0); /* the diamond has area 2, exactly */
    /* each corner cell: a triangle of area 1/2 */
    for (int i = 0; i < 4; i++)
        assert_int_equal(c->poly_start[i + 1] - c->poly_start[i], 4);
    /* segments (the centre's edges) are inside whole, ends copied from the
     * vertices; rays start on the box boundary and leave it at once */
    for (size_t e = 0; e < d->n_edges; e++) {
        const int32_t *en = d->edge_ends + 2 * e;
        if (en[1] < 0) {
            assert_int_equal(c->seg_in[e], 0);
            continue;
        }
        assert_int_equal(c->seg_in[e], 1);
        assert_memory_equal(c->seg + 4 * e, d->vertex_xy + 2 * en[0], 2 * sizeof(double));
        assert_memory_equal(c->seg + 4 * e + 2, d->vertex_xy + 2 * en[1], 2 * sizeof(double));
    }
    vor_clipped_free(c);
    vor_diagram_free(d);
    sites_done(s);
}

static void test_degenerate_cells(void **state) {
    (void)state;
    const double box[4] = {-3, -2, 4, 5};
    static const double one[] = {0.5, 0.5};
    vor_sites *s = sites_of(one, 1);
    vor_diagram *d = diagram_of(s);
    check_clip(d, s, box, "one site");
    vor_clipped *c = NULL;
    assert_int_equal(vor_clip(d, s, box, &c), VOR_OK);
    assert_int_equal(c->poly_start[1], 5); /* the box itself, closed */
    vor_clipped_free(c);
    vor_diagram_free(d);
    sites_done(s);

    static const double two[] = {0, 0, 1, 2};
    s = sites_of(two, 2);
    d = diagram_of(s);
    check_clip(d, s, box, "two sites");
    vor_diagram_free(d);
    sites_done(s);

    /* collinear, slanted and vertical and horizontal: strips */
    static const double col[] = {2, 1, -4, -2, 0, 0, 6, 3, 4, 2, 1, 0.5};
    s = sites_of(col, 6);
    d = diagram_of(s);
    check_clip(d, s, box, "collinear slanted");
    const double far[4] = {100, 100, 101, 101};
    check_clip(d, s, far, "collinear, far box");
    vor_diagram_free(d);
    sites_done(s);
    static const double vert[] = {1, 5, 1, -1, 1, 2, 1, 0};
    s = sites_of(vert, 4);
    d = diagram_of(s);
    check_clip(d, s, box, "collinear vertical");
    vor_diagram_free(d);
    sites_done(s);
    static const double hor[] = {3, 0, -1, 0, 0, 0};
    s = sites_of(hor, 3);
    d = diagram_of(s);
    check_clip(d, s, box, "collinear horizontal");
    vor_diagram_free(d);
    sites_done(s);

    static const double none[] = {0};
    s = sites_of(none, 0);
    d = diagram_of(s);
    assert_int_equal(vor_clip(d, s, box, &c), VOR_OK);
    assert_int_equal(c->poly_start[0], 0);
    vor_clipped_free(c);
    vor_diagram_free(d);
    sites_done(s);
}

/* A vertex whose coordinates overflow: the cells are cut from the box by
 * bisectors instead. Sites (-1e300, 0), (1e300, 0), (0, 1e-300): the circle
 * through them has its centre near y = -5e899. */
static void test_overflowing_vertex(void **state) {
    (void)state;
    static const double pts[] = {-1e300, 0, 1e300, 0, 0, 1e-300};
    vor_sites *s = sites_of(pts, 3);
    uint32_t *edges = malloc(6 * sizeof *edges);
    int32_t *ends = malloc(6 * sizeof *ends);
    const uint32_t E[] = {0, 1, 1, 2, 0, 2};
    const int32_t N[] = {0, VOR_NONE, 0, VOR_NONE, 0, VOR_NONE};
    memcpy(edges, E, sizeof E);
    memcpy(ends, N, sizeof N);
    vor_diagram *d = NULL;
    assert_int_equal(vor__diagram_build(s, 1, edges, ends, 3, &d), VOR_OK);
    if (isfinite(d->vertex_xy[0]) && isfinite(d->vertex_xy[1]))
        printf("  note: vertex is finite (%g, %g)\n", d->vertex_xy[0], d->vertex_xy[1]);
    const double box[4] = {-1, -1, 1, 1};
    check_clip(d, s, box, "overflowing vertex");
    vor_clipped *c = NULL;
    assert_int_equal(vor_clip(d, s, box, &c), VOR_OK);
    assert_int_equal(c->poly_start[2] - c->poly_start[0], 0);
    assert_int_equal(c->poly_start[3] - c->poly_start[2], 5); /* the box */
    vor_clipped_free(c);
    vor_diagram_free(d);
    sites_done(s);
}

/* Each allocation of vor_clip fails in turn: VOR_ENOMEM, *out NULL,
 * nothing leaked (LeakSanitizer checks at exit). Diagrams with and without
 * vertices. */
static void test_allocation_failures(void **state) {
    (void)state;
    static const double pts[] = {0, 10, -9, -5, 9, -5, 0, 0, 3, 1, 1, 1};
    static const double col[] = {0, 0, 1, 1, 3, 3};
    const double box[4] = {-2, -2, 2, 2};
    for (int set = 0; set < 2; set++) {
        vor_sites *s = set ? sites_of(col, 3) : sites_of(pts, 6);
        vor_diagram *d = diagram_of(s);
        long k;
        for (k = 0;; k++) {
            vor_clipped *c = (vor_clipped *)1;
            fault_arm(k);
            vor_status st = vor_clip(d, s, box, &c);
            fault_disarm();
            if (st == VOR_OK) {
                vor_clipped_free(c);
                break;
            }
            assert_int_equal(st, VOR_ENOMEM);
            assert_null(c);
        }
        printf("  %s: %ld allocations failed in turn\n", set ? "lines" : "vertices", k);
        assert_true(k >= 5);
        vor_diagram_free(d);
        sites_done(s);
    }
}

static void test_bad_boxes(void **state) {
    (void)state;
    static const double pts[] = {0, 0, 1, 0, 0, 1};
    vor_sites *s = sites_of(pts, 3);
    vor_diagram *d = diagram_of(s);
    const double bad[][4] = {
        {0, 0, 0, 1},  {0, 0, 1, 0},          {1, 0, 0, 1},
        {0, 1, 1, 0},  {NAN, 0, 1, 1},        {0, 0, INFINITY, 1},
        {-INFINITY, 0, 1, 1}, {0, 0, 1, NAN},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        vor_clipped *c = (vor_clipped *)1;
        assert_int_equal(vor_clip(d, s, bad[k], &c), VOR_EBOUNDS);
        assert_null(c);
    }
    const double ok[4] = {0, 0, 1, 1};
    vor_clipped *c = NULL;
    assert_int_equal(vor_clip(NULL, s, ok, &c), VOR_EINVAL);
    assert_int_equal(vor_clip(d, NULL, ok, &c), VOR_EINVAL);
    assert_int_equal(vor_clip(d, s, NULL, &c), VOR_EINVAL);
    assert_int_equal(vor_clip(d, s, ok, NULL), VOR_EINVAL);
    vor_clipped_free(NULL);
    vor_diagram_free(d);
    sites_done(s);
}

int main(void) {
    if (getenv("VOR_TEST_FILTER")) cmocka_set_test_filter(getenv("VOR_TEST_FILTER"));
    if (getenv("VOR_TEST_SKIP")) cmocka_set_skip_filter(getenv("VOR_TEST_SKIP"));
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_square_exact),
        cmocka_unit_test(test_random_sets),
        cmocka_unit_test(test_standard_sets),
        cmocka_unit_test(test_degenerate_cells),
        cmocka_unit_test(test_overflowing_vertex),
        cmocka_unit_test(test_allocation_failures),
        cmocka_unit_test(test_bad_boxes),
    };
    return cmocka_run_group_tests_name("core/clip", tests, NULL, NULL);
}
