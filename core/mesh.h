/* mesh.h -- construction helpers shared by the two incremental Delaunay
 * triangulations (core/bowyer_watson.c, core/flip.c); the mesh type itself
 * and its public operations are declared in internal.h.
 *
 * During construction the convex hull is closed by a symbolic vertex at
 * infinity, VOR__GHOST: every hull edge a->b (interior on its left) has a
 * ghost triangle (b, a, GHOST) on its other side, so the mesh is a
 * triangulation of the sphere. With k sites inserted it holds exactly
 * 2k - 2 triangles (Euler), ghosts included, and no half-edge has adj -1.
 * The ghost vertex may sit at any of the three positions of a ghost
 * triangle. vor__mesh_finish() removes the ghosts and leaves the public
 * form: finite counter-clockwise triangles, adj -1 on the hull, compact.
 *
 * The "circumcircle" of a ghost triangle (a, b, GHOST) is the open half-plane
 * to the left of a->b (outside the hull) plus the open segment ab: a point
 * exactly on a hull edge conflicts with both triangles of that edge, a point
 * on the line through a hull edge but beyond its ends conflicts with neither.
 * With this rule Bowyer-Watson cavities stay star-shaped from the new point
 * and Lawson flips never create a flat triangle.
 */
#ifndef VOR_MESH_H
#define VOR_MESH_H

#include <stdint.h>

#include "internal.h"
#include "predicates.h"

/* The vertex at infinity. Never a site index: sites are < 2^30. */
#define VOR__GHOST UINT32_MAX

/* Walk state kept between insertions: where the last point went (the next
 * one, close in insertion order, starts its walk there), the random bits
 * of the walk, and the static bound (predicates.h) of orient2d among the
 * sites, for the walk (incircle's bound is each test's own).
 * Also the construction's counts of predicate calls and walk steps
 * (vor_counts): vor__mesh_begin and vor__mesh_locate add theirs, the
 * algorithms theirs. */
typedef struct vor__walk {
    uint32_t tri;
    uint32_t rng;
    double occ;
    uint64_t steps, orient2d, incircle, exact;
    uint64_t cocircular; /* incircle tests that found four cocircular sites */
} vor__walk;

/* Non-zero if triangle t is a ghost. */
static inline int vor__mesh_is_ghost(const uint32_t *tri, uint32_t t) {
    return tri[3 * t] == VOR__GHOST || tri[3 * t + 1] == VOR__GHOST ||
           tri[3 * t + 2] == VOR__GHOST;
}

/* Allocates *m (zeroed by the caller) for n sites and builds the first
 * triangle and its three ghosts; sets up *w, the bounds included (one
 * pass over the sites). order[0..n-1] is the insertion order of the
 * sites at xy (2n doubles); the first site after order[0], order[1] that is
 * not collinear with them is swapped into order[2].
 *
 * The mesh is built on local vertex ids, the ranks in insertion order:
 * *pxy receives an array (free with free()) of the 2n coordinates in
 * insertion order, so that vertex i is at (*pxy)[2i]: the block *pxy held
 * on entry if it was not NULL (room for 2n doubles whose contents are no
 * longer needed, such as the insertion order's scratch, whose pages are
 * then not touched afresh; it is this function's either way), else a new
 * one. Spatial insertion
 * order thereby becomes spatial memory order, which is what keeps the walk
 * and the predicates in cache; vor__mesh_finish() maps the ids back to
 * site indices. The caller inserts vertices 3..n-1 afterwards.
 *
 * VOR_EINVAL if n < 3 or all sites are collinear, VOR_ETOOMANY if
 * half-edge ids would not fit in int32_t, VOR_ENOMEM; on error *m is left
 * empty and *pxy NULL. O(n), plus O(k) predicates when the first k sites in
 * order are collinear. */
vor_status vor__mesh_begin(vor__mesh *m, const double *xy, size_t n,
                           uint32_t *order, double **pxy, vor__walk *w);

/* Finds where vertex p goes, walking from w->tri with a remembering
 * stochastic visibility walk (orient2d only; each step crosses an edge that
 * p is strictly beyond, so the walk cannot cycle in a triangulation and the
 * random choice of the edge to test first keeps it from cycling forever).
 * Returns either a finite triangle containing p in its closure, with
 * *on_edge the half-edge p lies on (orient2d == 0) or -1 if p is strictly
 * inside, or a ghost triangle whose hull edge has p strictly on its outer
 * side (*on_edge == -1). Updates w->tri. Expected O(distance walked). */
uint32_t vor__mesh_locate(const vor__mesh *m, const double *xy, uint32_t p,
                          vor__walk *w, int32_t *on_edge);

/* 1 if vertex p lies at an end of half-edge e, which vor__mesh_locate
 * gave as *on_edge: p repeats a vertex of the mesh. vor_sites_new never
 * makes such sites; a vor_sites filled by hand can, and the insertions
 * answer VOR_EINVAL rather than build a mesh with a triangle of no area
 * (flip's walks then cycle; Bowyer-Watson's cavity leaves p unlinked).
 * Only where p lies on an edge, which is rare: no cost to the common
 * path. */
static inline int vor__mesh_at_vertex(const vor__mesh *m, const double *xy,
                                      uint32_t p, uint32_t e) {
    const double *q = xy + 2 * (size_t)p;
    const double *a = xy + 2 * (size_t)m->tri[e];
    const double *b = xy + 2 * (size_t)m->tri[vor__next(e)];
    return (q[0] == a[0] && q[1] == a[1]) || (q[0] == b[0] && q[1] == b[1]);
}

/* The larger side of the bounding box of the n >= 1 points at xy (2n
 * doubles), as rounded by one subtraction: the span to give
 * vor__orient2d_static_bound (predicates.h) for orientation tests among
 * these points. O(n). */
double vor__span(const double *xy, size_t n);

/* Non-zero if p is in the "circumcircle" of ghost triangle with hull edge
 * a->b (see the file comment): strictly left of a->b, or strictly inside
 * the segment ab. */
int vor__ghost_conflict(const double *a, const double *b, const double *p);
/* The same, adding 1 to *exact when its orientation test needed exact
 * arithmetic (predicates.h). */
int vor__ghost_conflict_n(const double *a, const double *b, const double *p,
                          uint64_t *exact);

/* Removes the ghost triangles and maps the local vertex ids back to site
 * indices through order: the finite twins of hull edges get adj -1 and the
 * finite triangles stored after the first n_tri - h slots move into the
 * holes. O(n_tri). Cannot fail. */
void vor__mesh_finish(vor__mesh *m, const uint32_t *order);

/* Builds the ghost-closed mesh of all sites in local ids, inserting them
 * in the given order (permuted as by vor__mesh_begin); on success *pxy is
 * the coordinates in insertion order (free with free()), made of the
 * block *pxy held on entry if not NULL (as vor__mesh_begin); on error
 * nothing is left allocated and m is empty. Adds its counts to run->counts and
 * reports its steps to run->trace (internal.h), the ORDER step included.
 * bowyer_watson.c and flip.c have one each. */
typedef vor_status (*vor__mesh_build_fn)(const vor_sites *s, uint32_t *order,
                                         vor__mesh *m, double **pxy,
                                         vor__run *run);

/* The walk's counts added to run's (the end of a build). */
static inline void vor__walk_count(const vor__walk *w, vor__run *run) {
    run->counts.walk_steps += w->steps;
    run->counts.orient2d += w->orient2d;
    run->counts.incircle += w->incircle;
    run->counts.exact += w->exact;
    run->cocircular_signs += w->cocircular;
}

/* The ORDER and BEGIN steps of an incremental build, reported after
 * vor__mesh_begin: order[0..n-1] (site indices, as permuted there) and
 * the first triangle (local vertices 0, 1, 2 as the mesh's slot 0 holds
 * them), with the counts so far, when run->trace is set. Cannot fail
 * (mesh.c). */
void vor__mesh_trace_begin(const vor__mesh *m, const uint32_t *order,
                           size_t n, vor__run *run, const vor_counts *so_far);

/* The canonical Voronoi diagram read straight off a ghost-closed mesh, as
 * a vor__mesh_build_fn or Fortune's sweep leaves it (any numbering of
 * vertices and triangles): vertex v is site order[v], at lxy[2v]
 * (mesh_dual.c). Bit-identical to vor__mesh_to_diagram of the finished
 * mesh, cocircular sites included. Consumes m
 * (cleared), lxy and order (freed), also on error; on error *out is NULL.
 * degenerate > 0: the construction met many signs of cocircular sites
 * (vor__run's cocircular_signs), so that they are likely: they are
 * looked for first, not met in the records (a hint; the result is the
 * same either way); < 0: the construction proved that there are none
 * (vor__mesh_hint), and the records pass tests no edge for them. O(n) for
 * sites of bounded degree; at its peak about 157 bytes per site, the
 * result included (mesh_dual.c). */
vor_status vor__mesh_dual(const vor_sites *s, vor__mesh *m, double *lxy,
                          uint32_t *order, int degenerate, vor_diagram **out);

/* The degenerate hint of vor__mesh_dual for a run of n sites whose
 * construction is done: cocircular_signs for more than one site in 64,
 * unless a test forces it (vor__run). Fewer signs leave few polygons (one
 * in 10^6 points on a circle, which leave one sign), which the records
 * pass notes and patches in at less cost than a search of every edge. */
static inline int vor__cocircular_first(const vor__run *run, size_t n) {
    return run->cocircular_first ? run->cocircular_first > 0
                                 : run->cocircular_signs > n / 64;
}

/* vor__mesh_dual's degenerate argument after Bowyer-Watson or flipping:
 * vor__cocircular_first, or -1 when their construction met no sign at
 * all. That is a proof: if a, b, c, d are cocircular with an edge a-c of
 * triangles abc and acd in the final mesh, d inserted last of the four,
 * then abc (whose sites came before d, and which lives to the end) was
 * there when d came, across the boundary edge a-c of d's new star, and
 * the construction tested d against it (the cavity's boundary, or the
 * flip test of the edge opposite d), exactly: a zero, a sign. Not for
 * Fortune's sweep, whose signs are its ties, not such tests: it has a
 * proof of its own (fortune.c, vertex_at). */
static inline int vor__mesh_hint(const vor__run *run, size_t n) {
    if (!run->cocircular_first && run->cocircular_signs == 0) return -1;
    return vor__cocircular_first(run, n);
}

/* vor__bowyer_watson and vor__flip: the insertion order
 * (vor__insertion_order), the mesh from build, then vor__mesh_dual. Same
 * contract as a vor__algorithm_run_fn (mesh_dual.c). */
vor_status vor__mesh_voronoi(const vor_sites *s, vor__mesh_build_fn build,
                             vor__run *run, vor_diagram **out);

/* *order = a new array (free with free()) of the insertion order of the
 * sites (vor__insertion_order), its work added to counts (may be NULL).
 * With coords not NULL, *coords = the block of 2n doubles in which the
 * order was sorted, for the build to make its coordinates of
 * (vor__mesh_begin). VOR_EINVAL if n < 3, VOR_ENOMEM; on error *order
 * and *coords are NULL (mesh.c). */
vor_status vor__mesh_order_new(const vor_sites *s, uint32_t **order,
                               double **coords, vor_counts *counts);

/* The finished (public form) mesh from build with the given insertion
 * order, as vor__bowyer_watson_mesh_ordered and vor__flip_mesh_ordered
 * return it; and with the usual insertion order, as vor__bowyer_watson_mesh
 * and vor__flip_mesh do (mesh.c). */
vor_status vor__mesh_build_ordered(const vor_sites *s,
                                   vor__mesh_build_fn build, uint32_t *order,
                                   vor__mesh *m);
vor_status vor__mesh_build(const vor_sites *s, vor__mesh_build_fn build,
                           vor__mesh *m);

/* The triangulations with a given insertion order (tests use this to force
 * degenerate starts). order holds n site indices, each once; it is
 * permuted in place. Same contract as vor__bowyer_watson_mesh and
 * vor__flip_mesh otherwise. */
vor_status vor__bowyer_watson_mesh_ordered(const vor_sites *s,
                                           uint32_t *order, vor__mesh *m);
vor_status vor__flip_mesh_ordered(const vor_sites *s, uint32_t *order,
                                  vor__mesh *m);

#endif /* VOR_MESH_H */
