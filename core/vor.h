/* vor.h -- libvor, the voronoid geometry library: public interface.
 *
 * libvor computes the Voronoi diagram (and its dual Delaunay triangulation)
 * of a set of 2D points with one of three interchangeable algorithms:
 * Fortune's sweep line, Bowyer-Watson incremental insertion and Lawson
 * flipping. All three fill the same canonical result, so for the same input
 * they return the identical diagram; that identity is the central test oracle.
 *
 * The library does no I/O, allocates only through malloc/realloc/free, keeps
 * no global state, starts no threads and never aborts or exits on input or on
 * a failed allocation: every fallible function returns a vor_status.
 *
 * Pipeline:
 *
 *     input xy --vor_sites_new--> vor_sites --vor_compute--> vor_diagram
 *                                                  |
 *                                      vor_clip (optional box) --> vor_clipped
 *
 * Indices: "input index" is a point's position in the caller's array;
 * "site index" numbers the distinct points in order of first occurrence, so
 * sorting by site index and sorting by input index agree.
 */
#ifndef VOR_VOR_H
#define VOR_VOR_H

#include <stddef.h>
#include <stdint.h>

/* ---- Status codes -------------------------------------------------------
 * One table: enum name, HTTP status a service should answer with, message.
 * The names (lower-cased, without VOR_E) appear in openapi.yaml as problem
 * types. */
#define VOR_STATUS_TABLE(X)                                                   \
    X(VOR_OK, 200, "ok")                                                      \
    X(VOR_ENOMEM, 503, "out of memory")                                       \
    X(VOR_ENONFINITE, 422, "coordinate is not a finite number")               \
    X(VOR_ETOOMANY, 413, "too many points")                                   \
    X(VOR_EBOUNDS, 422, "bounds must be finite with xmin < xmax, ymin < ymax") \
    X(VOR_EALGORITHM, 422, "unknown algorithm")                               \
    X(VOR_EINVAL, 400, "invalid argument")                                    \
    X(VOR_EUNAVAILABLE, 501, "algorithm not available")                      \
    X(VOR_ESTOPPED, 503, "stopped by the caller before it finished")

typedef enum vor_status {
#define VOR__ENUM(name, http, msg) name,
    VOR_STATUS_TABLE(VOR__ENUM)
#undef VOR__ENUM
    VOR_STATUS_COUNT
} vor_status;

/* Static message for a status; never NULL. */
const char *vor_status_message(vor_status s);
/* Enum name as a string ("VOR_ENONFINITE"); never NULL. */
const char *vor_status_name(vor_status s);
/* HTTP status a service should answer with. */
int vor_status_http(vor_status s);

/* ---- Algorithms --------------------------------------------------------- */
typedef enum vor_algorithm {
    VOR_FORTUNE = 0,
    VOR_BOWYER_WATSON = 1,
    VOR_FLIP = 2,
    VOR_ALGORITHM_COUNT
} vor_algorithm;

/* "fortune", "bowyer-watson", "flip". */
const char *vor_algorithm_name(vor_algorithm a);
/* Parses one of the names above; VOR_EALGORITHM otherwise. */
vor_status vor_algorithm_parse(const char *name, vor_algorithm *out);

/* Largest number of input points accepted (indices are 32-bit). */
#define VOR_MAX_POINTS ((size_t)1 << 30)

/* ---- Sites: validated, de-duplicated input ------------------------------ */
typedef struct vor_sites {
    size_t n_input;     /* points given by the caller */
    size_t n;           /* distinct sites, n <= n_input */
    double *xy;         /* 2*n: site coordinates, exactly as given (a -0.0
                           is stored as +0.0), in order of first occurrence */
    uint32_t *input_of; /* n: input index of each site's first occurrence
                           (strictly increasing) */
    uint32_t *site_of;  /* n_input: site index of each input point */
} vor_sites;

/* Validates and de-duplicates n points given as interleaved x,y doubles.
 * Two points are duplicates when their coordinates compare equal (so -0.0
 * equals 0.0). On a non-finite coordinate returns VOR_ENONFINITE and stores
 * the offending input index in *bad_index (if not NULL); n > VOR_MAX_POINTS
 * gives VOR_ETOOMANY. On success *out is a new vor_sites (free with
 * vor_sites_free); on error *out is NULL and nothing leaks. xy may be NULL
 * when n == 0; out == NULL, or xy == NULL with n > 0, gives VOR_EINVAL.
 * Expected O(n). */
vor_status vor_sites_new(const double *xy, size_t n, vor_sites **out,
                         size_t *bad_index);
void vor_sites_free(vor_sites *s);

/* ---- The Voronoi diagram ------------------------------------------------- */

/* An end of an edge that is not a vertex: the edge is unbounded there. */
#define VOR_NONE (-1)

/* The diagram is a set of flat arrays with documented strides (memory is
 * about 140 bytes per site for uniform input).
 *
 * Vertex v: the centre of the circle through three or more sites.
 *   vertex_sites[3v..3v+2] are the three smallest site indices on that
 *   circle, increasing; vertex_xy[2v], vertex_xy[2v+1] are computed by
 *   vor_circumcenter() from exactly those three sites in that order, so every
 *   algorithm gives bit-identical coordinates. The centre of 4+ cocircular
 *   sites is ONE vertex. Canonical order: by (s0, s1, s2).
 *
 * Edge e: the part of the bisector of sites a < b that bounds both cells,
 *   a = edge_sites[2e], b = edge_sites[2e+1]. Ends edge_ends[2e], [2e+1] are
 *   vertex indices or VOR_NONE:
 *     segment: both >= 0 and end0 < end1 (never zero length);
 *     ray:     end0 >= 0, end1 == VOR_NONE: leaves vertex end0 outwards;
 *     line:    both VOR_NONE (two sites, or all sites collinear): through
 *              the midpoint of a and b, unbounded both ways.
 *   Canonical order: by (a, b); a pair of sites has at most one edge.
 *
 * Ray r (for every unbounded edge, rays and lines): ray_edge[r] is the edge
 *   (increasing in r), ray_dir[2r..2r+1] its unit direction from
 *   vor_bisector_dir(): outward for a ray; for a line, the direction with
 *   site a on its left.
 *
 * Cell of site i: cell_edges[cell_start[i] .. cell_start[i+1]-1], edge
 *   indices counter-clockwise around the site. A bounded cell starts at its
 *   smallest edge index; an unbounded cell starts with the edge that comes in
 *   from infinity and ends with the one that leaves to infinity.
 *   cell_bounded[i] is 1 for a closed polygon. Without vertices (all sites
 *   collinear), a site between two parallel lines lists them in edge order;
 *   each is walked with the site on its left. */
typedef struct vor_diagram {
    size_t n_sites; /* copy of sites->n */

    size_t n_vertices;
    double *vertex_xy;       /* 2 * n_vertices */
    uint32_t *vertex_sites;  /* 3 * n_vertices */

    size_t n_edges;
    uint32_t *edge_sites;    /* 2 * n_edges */
    int32_t *edge_ends;      /* 2 * n_edges */

    size_t n_rays;
    uint32_t *ray_edge;      /* n_rays */
    double *ray_dir;         /* 2 * n_rays */

    uint32_t *cell_start;    /* n_sites + 1 */
    uint32_t *cell_edges;    /* cell_start[n_sites] == 2 * n_edges entries */
    uint8_t *cell_bounded;   /* n_sites */
} vor_diagram;

/* Computes the canonical Voronoi diagram of the sites with the chosen
 * algorithm. On success *out is a new diagram (free with vor_diagram_free).
 * On error *out is NULL and nothing leaks. Sites are borrowed. The sites
 * must be finite and distinct, as vor_sites_new makes them; a vor_sites
 * filled by hand gets VOR_ENONFINITE for an infinite or NaN coordinate
 * and VOR_EINVAL for a repeated point. */
vor_status vor_compute(const vor_sites *sites, vor_algorithm algorithm,
                       vor_diagram **out);
void vor_diagram_free(vor_diagram *d);

/* ---- Operation counts --------------------------------------------------
 * What an algorithm did, counted as it runs: deterministic for a given
 * input (the same sites, in the same order, give the same counts on every
 * run and machine), and cheap enough to be always on. One table: the
 * count's name (also its key in the service's "counts" objects), the
 * algorithms it applies to (VOR_IN_* bits; the others leave it 0) and
 * what it counts. The counts cover building the Delaunay triangulation
 * (for Fortune: the sweep) and the insertion order; the conversion to the
 * diagram, which is the same for all three, is not counted. Input that no
 * algorithm sees (fewer than three sites, or all of them on one line)
 * counts nothing.
 *
 * "Ghost" triangles are those on the vertex at infinity that close the
 * convex hull during construction (one per hull edge); the incremental
 * algorithms create and remove them like the others, so they count. */
#define VOR_IN_FORTUNE (1u << VOR_FORTUNE)
#define VOR_IN_BOWYER_WATSON (1u << VOR_BOWYER_WATSON)
#define VOR_IN_FLIP (1u << VOR_FLIP)
#define VOR_IN_INCREMENTAL (VOR_IN_BOWYER_WATSON | VOR_IN_FLIP)
#define VOR_IN_ALL (VOR_IN_FORTUNE | VOR_IN_INCREMENTAL)

#define VOR_COUNTS_TABLE(X)                                                  \
    X(orient2d, VOR_IN_INCREMENTAL,                                          \
      "orientation tests: point location, the hull, the first triangle")    \
    X(incircle, VOR_IN_INCREMENTAL,                                          \
      "in-circle tests: the cavity search (Bowyer-Watson), the legality "    \
      "of edges (flip)")                                                     \
    X(exact, VOR_IN_ALL,                                                     \
      "predicate calls that the inline floating-point filters could not "    \
      "decide, handed to exact arithmetic (which first rescales and tries "  \
      "once more in floating point)")                                        \
    X(order_rounds, VOR_IN_INCREMENTAL,                                      \
      "rounds of the biased randomised insertion order")                    \
    X(order_refinements, VOR_IN_INCREMENTAL,                                 \
      "crowded cells of the insertion order's grid ordered again on a "     \
      "grid of their own")                                                   \
    X(order_keys, VOR_IN_INCREMENTAL,                                        \
      "Hilbert keys computed for the insertion order: one per site, plus "  \
      "one per site of every refinement")                                    \
    X(walk_steps, VOR_IN_INCREMENTAL,                                        \
      "triangles point location stepped through, hull ghosts included")      \
    X(triangles_created, VOR_IN_INCREMENTAL,                                 \
      "triangles made, ghosts included: the first triangle and its three "  \
      "ghosts, then the stars (Bowyer-Watson) or the splits and flips "     \
      "(flip)")                                                              \
    X(cavity_triangles, VOR_IN_BOWYER_WATSON,                                \
      "triangles removed because their circumcircle contained the new "     \
      "site, ghosts included")                                               \
    X(flips, VOR_IN_FLIP, "edges flipped")                                   \
    X(site_events, VOR_IN_FORTUNE,                                           \
      "site events: one per distinct site, the first row included")          \
    X(circle_events, VOR_IN_FORTUNE,                                         \
      "circle events that happened (each removes an arc and makes a "       \
      "Delaunay triangle)")                                                  \
    X(false_alarms, VOR_IN_FORTUNE,                                          \
      "circle events scheduled and cancelled before they happened")         \
    X(breakpoint_hits, VOR_IN_FORTUNE,                                       \
      "site events exactly below a breakpoint (each makes a Delaunay "      \
      "triangle at once)")                                                   \
    X(beach_max, VOR_IN_FORTUNE, "the most arcs on the beach line at once") \
    X(breakpoint_tests, VOR_IN_FORTUNE,                                      \
      "tests of a site against a breakpoint while locating its arc")         \
    X(breakpoint_exact, VOR_IN_FORTUNE,                                      \
      "breakpoint tests that needed exact arithmetic")                       \
    X(circle_tops, VOR_IN_FORTUNE,                                           \
      "triples of arcs tested for a circle event (orientation and the "     \
      "interval of the circle's top)")                                       \
    X(circle_top_exact, VOR_IN_FORTUNE,                                      \
      "circle tests that needed exact arithmetic: collinear triples, and "  \
      "circle events whose top floating point could not bound")             \
    X(event_compares, VOR_IN_FORTUNE,                                        \
      "comparisons of two events, or of an event and the next site, in "    \
      "sweep order")                                                         \
    X(event_exact, VOR_IN_FORTUNE,                                           \
      "event comparisons that needed exact (integer) arithmetic")

typedef struct vor_counts {
#define VOR__COUNT_FIELD(name, algorithms, what) uint64_t name;
    VOR_COUNTS_TABLE(VOR__COUNT_FIELD)
#undef VOR__COUNT_FIELD
} vor_counts;

/* Number of counts in the table. */
#define VOR_COUNT_FIELDS (sizeof(vor_counts) / sizeof(uint64_t))

/* The i-th count of the table (i < VOR_COUNT_FIELDS): its name
 * ("orient2d"), what it counts, the VOR_IN_* bits of the algorithms it
 * applies to, and its value in c. NULL / 0 for i out of range. */
const char *vor_count_name(size_t i);
const char *vor_count_what(size_t i);
unsigned vor_count_algorithms(size_t i);
uint64_t vor_count_value(const vor_counts *c, size_t i);

/* ---- Trace of an algorithm's steps ----------------------------------------
 * With a trace hook, the algorithm reports its steps as it takes them, in
 * order; replaying them rebuilds its Delaunay triangulation exactly, and
 * hence (through the same conversion) the returned diagram. The hook
 * never changes a decision; without one the only cost is a branch per
 * site or event. Every site number is a site index (vor_sites); in a
 * triangle, VOR_INFINITE stands for the vertex at infinity (a ghost
 * triangle (a, b, VOR_INFINITE) is the outside of the hull edge b->a).
 * Triangles are counter-clockwise triples; arrays are borrowed for the
 * call only.
 *
 * Steps (fields not named are 0, NULL or VOR_INFINITE):
 *
 *   ORDER     every algorithm, first: order[0..n_order-1], the sites in
 *             the order the algorithm takes them (the insertion order, or
 *             Fortune's sweep order, by y then x).
 *   BEGIN     Bowyer-Watson, flip: tri, the first triangle (order[0..2]);
 *             its three ghosts close the hull. Fortune: the first row,
 *             the sites of the lowest y left to right, as the beach line
 *             (beach, n_beach), at sweep position y.
 *   INSERT    Bowyer-Watson, flip: site, inserted; tri, the triangle
 *             where point location ended (a ghost when the site is
 *             outside the hull); cavity (n_cavity triangles, 3 site
 *             numbers each), the triangles removed, and star (n_star
 *             triangles), those made, each with the site as its third
 *             vertex. Bowyer-Watson's cavity is every triangle whose
 *             circumcircle contains the site; flip's is the triangle
 *             split (split VOR_SPLIT_TRIANGLE), the two triangles of the
 *             edge the site lies on (VOR_SPLIT_EDGE, edge = its ends) or
 *             the ghosts of the hull edges the site sees (VOR_SPLIT_HULL).
 *   FLIP      flip, after its INSERT: tri = (a, b, p), p the site being
 *             inserted, whose circumcircle strictly contains the vertex d
 *             across edge a-b; edge = (a, b), removed; added = (p, d).
 *             Triangles (a, b, p) and (b, a, d) become (a, d, p) and
 *             (d, b, p).
 *   SITE      Fortune: site, at sweep position y (its y). Either its arc
 *             splits the arc of site arc (the new arc at position at of
 *             the beach line after, between two arcs of that site), or it
 *             lies exactly below the breakpoint of the arcs of
 *             breakpoint[0], breakpoint[1] (then arc is VOR_INFINITE, the
 *             new arc at position at goes between them, and tri = the
 *             Delaunay triangle (left, right, site) with its circumcentre
 *             vertex). beach: the beach line after the event.
 *   CIRCLE    Fortune: the arc at position at (of the beach line before)
 *             vanishes at sweep position y (the top of the circle, as a
 *             double); tri, the arcs' sites left to right, is the Delaunay
 *             triangle made, vertex its circumcentre; beach: after.
 *   SCHEDULE  Fortune: a circle event for the arcs tri (left to right) at
 *   CANCEL    y, the top of the circle around vertex; or that event
 *             cancelled because the arc's triple changed. A CIRCLE step
 *             consumes the scheduled event of its triple; live events have
 *             distinct triples.
 *   END       every algorithm, last: the triangulation is complete.
 *
 * Every step carries counts, the run's counts so far, the step's own work
 * included (the END step's are the run's final counts); so a replay can
 * show them growing.
 *
 * y and vertex are computed in doubles from the input coordinates
 * (vor_circumcenter of the three sites in increasing index order, as the
 * diagram's vertices), for drawing; they may be inf or nan when the circle
 * overflows, and play no part in the algorithm's exact decisions. */
#define VOR_INFINITE UINT32_MAX

typedef enum vor_step_kind {
    VOR_STEP_ORDER,
    VOR_STEP_BEGIN,
    VOR_STEP_INSERT,
    VOR_STEP_FLIP,
    VOR_STEP_SITE,
    VOR_STEP_CIRCLE,
    VOR_STEP_SCHEDULE,
    VOR_STEP_CANCEL,
    VOR_STEP_END,
    VOR_STEP_KIND_COUNT
} vor_step_kind;

typedef enum vor_split {
    VOR_SPLIT_NONE,     /* Bowyer-Watson */
    VOR_SPLIT_TRIANGLE, /* flip: strictly inside a triangle, 1 -> 3 */
    VOR_SPLIT_EDGE,     /* flip: on an edge, 2 -> 4 */
    VOR_SPLIT_HULL      /* flip: outside the hull */
} vor_split;

typedef struct vor_step {
    vor_step_kind kind;
    uint32_t site;
    uint32_t tri[3];
    uint32_t edge[2];
    uint32_t added[2];
    uint32_t arc;
    uint32_t breakpoint[2];
    uint32_t at;
    vor_split split;
    double y;
    double vertex[2];
    const uint32_t *order;
    size_t n_order;
    const uint32_t *beach;
    size_t n_beach;
    const uint32_t *cavity; /* 3 * n_cavity */
    size_t n_cavity;
    const uint32_t *star;   /* 3 * n_star */
    size_t n_star;
    const vor_counts *counts;
} vor_step;

/* "order", "begin", "insert", "flip", "site", "circle", "schedule",
 * "cancel", "end"; "?" out of range. */
const char *vor_step_kind_name(vor_step_kind k);
/* "", "triangle", "edge", "hull". */
const char *vor_split_name(vor_split s);

typedef void (*vor_trace_fn)(void *ctx, const vor_step *step);

typedef struct vor_options {
    vor_counts *counts; /* filled when not NULL (zeroed first) */
    vor_trace_fn trace; /* called for every step when not NULL */
    void *trace_ctx;    /* its first argument */
    /* When not NULL, asked now and then whether the caller still wants the
     * answer (non-zero: stop). The algorithm asks before its first site and
     * then every VOR_STOP_EVERY sites or events, so that however slow the
     * input makes its sites and events, it gives up soon after the answer
     * is given up on (the phases before and after them, sorting and the
     * conversion to the diagram, are O(n log n) and not interrupted); it
     * then returns VOR_ESTOPPED, having freed everything. Called on the
     * computing thread; may read a flag another thread sets. */
    int (*stop)(void *ctx);
    void *stop_ctx; /* its first argument */
} vor_options;

/* How many sites (Bowyer-Watson, flip) or events and sites (Fortune) the
 * algorithms take between two questions to vor_options.stop. */
#define VOR_STOP_EVERY 1024

/* vor_compute with options: opt (may be NULL) asks for the counts and a
 * trace, and may say when to stop. The diagram is the same as
 * vor_compute's, bit for bit. On error the counts and the steps traced so
 * far describe the work done until then. */
vor_status vor_compute_ex(const vor_sites *sites, vor_algorithm algorithm,
                          const vor_options *opt, vor_diagram **out);

/* Non-zero when the two diagrams are identical in every field, bit for bit
 * (vertex coordinates included). */
int vor_diagram_equal(const vor_diagram *p, const vor_diagram *q);

/* The Delaunay triangles dual to the diagram: each vertex of degree k gives
 * k-2 triangles, fanned from its smallest site, counter-clockwise, listed
 * vertex by vertex in vertex order. *out is a
 * new array of 3 * *n_tri site indices (free with free()). Identical for all
 * algorithms, because it is derived from the canonical diagram. */
vor_status vor_diagram_triangles(const vor_diagram *d, const vor_sites *sites,
                                 uint32_t **out, size_t *n_tri);

/* ---- Checking ----------------------------------------------------------- */

/* Verifies the diagram's invariants against the sites with exact
 * predicates: every vertex is equidistant from its defining sites and no
 * site lies strictly inside its circle (empty circle, checked exactly, in
 * O(n log n) expected via the cells, not against all sites), edges join
 * vertices that belong to both sites' cells, cells are closed or correctly
 * unbounded, counter-clockwise, Euler's relation holds, canonical order is
 * respected, no zero-length edges. Returns 0 if valid; otherwise non-zero and
 * writes a one-line reason into msg (if msg != NULL). */
int vor_check(const vor_diagram *d, const vor_sites *sites, char *msg,
              size_t msg_size);

/* ---- Clipping to a box -------------------------------------------------- */

typedef struct vor_clipped {
    double box[4]; /* xmin, ymin, xmax, ymax */
    /* For every diagram edge e, its part inside the box:
     * seg[4e .. 4e+3] = x0, y0, x1, y1, valid when seg_in[e] != 0. */
    double *seg;
    uint8_t *seg_in;
    /* For every site i, its cell intersected with the box, a closed
     * counter-clockwise ring, closed by repeating its first point at the
     * end, of (poly_start[i+1] - poly_start[i]) points at
     * poly_xy[2*poly_start[i] ..]; empty when the site's cell misses the box
     * or meets it only in a point or a segment (a site outside the box can
     * still have a cell inside it). */
    uint32_t *poly_start; /* n_sites + 1 */
    double *poly_xy;
} vor_clipped;

/* Clips the diagram to box = {xmin, ymin, xmax, ymax}. VOR_EBOUNDS if the box
 * is not finite or empty. On error *out is NULL and nothing leaks. */
vor_status vor_clip(const vor_diagram *d, const vor_sites *sites,
                    const double box[4], vor_clipped **out);
void vor_clipped_free(vor_clipped *c);

/* ---- Geometry helpers shared by all algorithms -------------------------- */

/* Centre of the circle through a, b, c (each x,y). The caller passes the
 * three sites in increasing site index order so that the result is the
 * same whichever algorithm asks. Finite for any non-collinear finite
 * input unless the true centre overflows, and within about 2^-30 of its
 * distance from a however flat or thin the triangle (core/geometry.c). */
void vor_circumcenter(const double *a, const double *b, const double *c,
                      double *out);

/* Unit direction of the bisector of a and b that has a on its left:
 * normalise(-(b.y - a.y), b.x - a.x). For a ray leaving the hull edge
 * (p -> q counter-clockwise along the hull) outwards, call with (q, p):
 * outward points to the right of p->q. Overflow-safe. a == b gives (0, 0);
 * zero components are +0.0, so swapping a and b negates the result as
 * numbers (bit for bit in its nonzero components). */
void vor_bisector_dir(const double *a, const double *b, double *out);

#endif /* VOR_VOR_H */
