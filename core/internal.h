/* internal.h -- contracts shared between libvor's source files.
 *
 * Not installed, not for callers of the library. Names are vor__ (internal)
 * or vor_ where tests and the codec may use them too.
 *
 * How vor_compute() and vor_compute_ex() (core/voronoi.c) run:
 *   1. sites->n < 3, or all sites collinear (exact orient2d): the degenerate
 *      diagram of parallel lines is built by vor__diagram_degenerate(); the
 *      algorithms below are never called for such input (nothing is counted
 *      or traced).
 *   2. otherwise the algorithm's entry point; every one has the signature
 *      vor__algorithm_run_fn (a vor__run collects its counts and passes its
 *      trace hook) and builds a Delaunay mesh (Fortune's sweep finds
 *      its triangles as vertex events), which vor__mesh_dual() (mesh.h)
 *      reads the diagram off. vor__diagram_build() alone defines the
 *      canonical form: vor__mesh_dual() produces the same bits without its
 *      sorting, cocircular sites included.
 */
#ifndef VOR_INTERNAL_H
#define VOR_INTERNAL_H

#include "vor.h"

/* 128-bit integers (a GCC and Clang extension, on every 64-bit target they
 * support): the integer stages of the exact predicates (predicates.c,
 * fortune_predicates.c). */
__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;

/* ---- Fused multiply-add ----------------------------------------------------
 * The error-free product of two doubles and the double-double arithmetic
 * of the predicates' second stages are built on fma(). x86-64's baseline
 * has no FMA instruction, so fma() is a call into the C library, a few
 * nanoseconds each, dozens per evaluation. VOR__FMA_CLONES on such a
 * function makes GCC and Clang compile it twice, with and without the
 * instruction, and pick once at load time for the machine it runs on
 * (an ifunc); elsewhere it is empty. Results are bit-identical either
 * way: fma() is correctly rounded by definition. */
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define VOR__SANITIZED 1 /* ifunc resolvers run before the sanitizers */
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define VOR__SANITIZED 1
#endif
#endif
#if defined(__x86_64__) && defined(__GNUC__) && defined(__linux__) && \
    !defined(VOR__SANITIZED) && !defined(VOR_NO_FMA_CLONES)
#define VOR__FMA_CLONES __attribute__((target_clones("fma", "default")))
#else
#define VOR__FMA_CLONES
#endif

/* ---- Exact predicates (core/predicates.c) --------------------------------
 * Exact for all finite double inputs: a floating-point filter answers when
 * its error bound proves the sign; otherwise exact expansion arithmetic (and
 * GMP where the exponent range of the operands would make expansions
 * underflow). Points are pointers to x,y pairs. Hot loops include
 * core/predicates.h for the inlined vor__orient2d_fast / vor__incircle_fast. */

/* +1 if c lies to the left of a->b (a, b, c counter-clockwise), -1 if to the
 * right, 0 if collinear. */
int vor_orient2d(const double *a, const double *b, const double *c);

/* For counter-clockwise a, b, c: +1 if d lies strictly inside their
 * circumcircle, -1 strictly outside, 0 on it. (For clockwise a, b, c the sign
 * is reversed, as the determinant's.) */
int vor_incircle(const double *a, const double *b, const double *c,
                 const double *d);

/* ---- Bounding box (core/geometry.c) --------------------------------------
 * box = {xmin, ymin, xmax, ymax} of the n >= 1 points at xy (2n doubles). */
void vor__bbox(const double *xy, size_t n, double box[4]);

/* ---- Big arrays (core/mesh.c) ---------------------------------------------
 * malloc(count * size) (NULL on overflow or failure; free with free();
 * never NULL for a count of 0 that succeeded, so that every array of a
 * successful diagram is non-NULL) for the big arrays of the sites, the
 * order, the mesh, the sweep and the diagram. A block of 4 MiB or more
 * is advised to the kernel as a candidate for huge pages (Linux's
 * MADV_HUGEPAGE, where available; a hint, errors ignored; only the whole
 * 2 MiB pages inside it): a cold run at 10^6 sites touches about 280
 * bytes a site for the first time, and at 10^6 sites nearly every visit
 * of the mesh misses the TLB with 4 KiB pages.
 *
 * What a first touch costs depends on the host. On a virtual machine
 * whose guest page faults are dear (a PVM guest: 10.6 us for every 4 KiB
 * page, against 6.2 us a 4 KiB share of a huge page the host has not
 * backed yet and 0.2 us of one it has), huge pages made cold runs at 10^6
 * a quarter to a third faster. On one whose 4 KiB faults were served
 * cheaply from pages freed a moment ago, but whose balloon reported free
 * 2 MiB blocks to the host (free page reporting), advising every array
 * made cold runs a quarter slower than advising only the mesh. Where
 * faults cost anything, one for 2 MiB beats 512 for 4 KiB each; the
 * advice is for every big array that is written densely (Fortune keeps
 * what it writes sparsely apart, see recs_resize). */
void *vor__alloc_large(size_t count, size_t size);
/* The same for an array whose first writes land at random (the
 * conversion's records and cell offsets, written in site order from a
 * walk in insertion order). A block of 1 MiB or more has its pages
 * mapped at once (Linux's MADV_POPULATE_WRITE, where available; errors
 * ignored): a page touched first by a random write costs a fault in the
 * middle of a pass whose prefetches of pages not yet mapped are dropped,
 * and at 10^6 sites the records pass ran 10 ms (5%) longer so than after
 * one call that maps the 72 MB in order. */
void *vor__alloc_scattered(size_t count, size_t size);
/* vor__alloc_large, zeroed (calloc: a fresh mapping is not written
 * twice), its pages mapped at once as vor__alloc_scattered's. */
void *vor__calloc_large(size_t count, size_t size);
/* A zeroed scratch array that dies before the computation's peak (NULL on
 * overflow or failure; free with vor__scratch_free, which takes NULL). A
 * block of 1 MiB or more is a mapping of its own, whose pages go back to
 * the kernel when it is freed: from the C library's heap, a block freed
 * below newer ones stays resident as a hole that the later, bigger arrays
 * do not fit in (4 bytes a site each for the conversion's degree counts
 * and Fortune's event buckets, at 10^6 sites); one of 4 MiB or more is
 * advised for huge pages as vor__alloc_large's. Smaller ones are
 * calloc's. */
void *vor__scratch_new(size_t count, size_t size);
void vor__scratch_free(void *p);

/* ---- Spatial order (core/hilbert.c) --------------------------------------
 * Fills order[0..n-1] with the site indices 0..n-1 in an order suited to
 * incremental insertion (Hilbert curve with biased randomised rounds, BRIO),
 * deterministic for a given input. VOR_ENOMEM on failure. */
vor_status vor__insertion_order(const double *xy, size_t n, uint32_t *order);
/* The same, adding its work to counts (order_rounds, order_refinements,
 * order_keys) when counts is not NULL. */
vor_status vor__insertion_order_counted(const double *xy, size_t n,
                                        uint32_t *order, vor_counts *counts);
/* The same in the caller's scratch, 2n words (none allocated), or in its
 * own if scratch is NULL. */
vor_status vor__insertion_order_in(const double *xy, size_t n,
                                   uint32_t *order, vor_counts *counts,
                                   uint64_t *scratch);

/* ---- Delaunay mesh (core/mesh.h, core/mesh.c) ----------------------------
 * delaunator's representation: half-edge e goes from tri[e] to
 * tri[vor__next(e)] in triangle e/3; triangles counter-clockwise;
 * adj[e] is the opposite half-edge (from tri[next(e)] to tri[e]) or -1 on
 * the convex hull. Finite triangles only in the public form. */
typedef struct vor__mesh {
    size_t n_tri;
    size_t cap_tri;
    uint32_t *tri;  /* 3 * n_tri site indices */
    int32_t *adj;   /* 3 * n_tri */
} vor__mesh;

static inline uint32_t vor__next(uint32_t e) { return e % 3 == 2 ? e - 2 : e + 1; }
static inline uint32_t vor__prev(uint32_t e) { return e % 3 == 0 ? e + 2 : e - 1; }

/* ---- Algorithms ----------------------------------------------------------
 * Each gets >= 3 distinct sites not all collinear; on success *out is the
 * canonical diagram; on error *out is NULL and nothing leaks. */
typedef vor_status (*vor__algorithm_fn)(const vor_sites *s, vor_diagram **out);

vor_status vor__fortune(const vor_sites *s, vor_diagram **out);
vor_status vor__bowyer_watson(const vor_sites *s, vor_diagram **out);
vor_status vor__flip(const vor_sites *s, vor_diagram **out);

/* What a run reports besides the diagram (vor_compute_ex). The algorithm
 * adds its counts into run->counts (zeroed by the caller; the algorithms
 * keep their counters in their own state and locals while they run, and
 * add them here once at the end, also on error) and, when run->trace is
 * not NULL, reports its steps through it (vor.h; core/trace.c has the
 * helpers). The functions above are these with a run that nobody reads. */
typedef struct vor__run {
    vor_counts counts;
    vor_trace_fn trace;
    void *trace_ctx;
    int (*stop)(void *ctx); /* vor_options.stop, or NULL */
    void *stop_ctx;
    /* signs of cocircular sites that the construction met: incircle tests
     * that found four (Bowyer-Watson, flip); ties of circle tops that
     * needed exact arithmetic or were proven equal, and a lattice
     * (Fortune). Not exact arithmetic as such: sites in rows need much
     * of it, for nearly collinear and nearly cocircular sites, and have
     * no cocircular four. The conversion looks for cocircular sites
     * before its records pass when there are any (vor__mesh_dual). */
    uint64_t cocircular_signs;
    /* for the tests: the conversion looks for cocircular sites first
     * (> 0), meets them in its records pass (< 0), or, as always outside
     * the tests, decides by cocircular_signs (0) */
    int cocircular_first;
} vor__run;

/* 1 when the caller asks the run to stop (vor_options.stop); asked only
 * when step is a multiple of VOR_STOP_EVERY, so that the loops of the
 * algorithms can call it with their counter at every step. */
static inline int vor__stop_now(const vor__run *run, uint64_t step) {
    return step % VOR_STOP_EVERY == 0 && run->stop && run->stop(run->stop_ctx);
}

typedef vor_status (*vor__algorithm_run_fn)(const vor_sites *s, vor__run *run,
                                            vor_diagram **out);

vor_status vor__fortune_run(const vor_sites *s, vor__run *run,
                            vor_diagram **out);
vor_status vor__bowyer_watson_run(const vor_sites *s, vor__run *run,
                                  vor_diagram **out);
vor_status vor__flip_run(const vor_sites *s, vor__run *run,
                         vor_diagram **out);

/* Delaunay triangulations alone, for the mesh checker and the tests: fill
 * *m (zeroed by the caller) with a Delaunay triangulation of the sites; free
 * with vor__mesh_clear. */
vor_status vor__bowyer_watson_mesh(const vor_sites *s, vor__mesh *m);
vor_status vor__flip_mesh(const vor_sites *s, vor__mesh *m);
void vor__mesh_clear(vor__mesh *m);

/* Verifies a Delaunay mesh: twin symmetry, counter-clockwise triangles, the
 * hull convex and containing every site, exact empty circumcircle across
 * every interior edge (local Delaunay, which implies global), Euler count.
 * 0 if valid, else non-zero with a reason in msg. */
int vor__mesh_check(const vor__mesh *m, const vor_sites *s, char *msg,
                    size_t msg_size);

/* Marks a function that runs only when tracing (or on other rare paths):
 * kept out of line and out of the hot code's way. */
#if defined(__GNUC__)
#define VOR__COLD __attribute__((cold, noinline))
#else
#define VOR__COLD
#endif

/* ---- Counts and steps (core/trace.c) ---------------------------------------
 * Every count of from added to to's. */
void vor__counts_add(vor_counts *to, const vor_counts *from);

/* A step of the given kind with every field empty: site numbers
 * VOR_INFINITE, arrays NULL, numbers 0. */
void vor__step_init(vor_step *st, vor_step_kind kind);

/* Reports the END step with run's counts, when run->trace is set. */
void vor__trace_end(vor__run *run);

/* For a trace's drawing: the circumcentre of sites a, b, c (site indices
 * into s, in any order: they are sorted first, as the diagram's vertices
 * are computed) into vertex, and the top of the circle, vertex y plus the
 * radius, into *top. Doubles, not exact. */
void vor__trace_circle(const vor_sites *s, uint32_t a, uint32_t b, uint32_t c,
                       double vertex[2], double *top);

/* ---- Building the canonical diagram (core/diagram.c) ---------------------
 * Converts a Delaunay mesh (any Delaunay triangulation of the sites: where
 * 4+ sites are cocircular, triangles sharing a circumcircle are merged into
 * one vertex, found exactly with vor_incircle) into the diagram. The mesh is
 * consumed (cleared) to keep peak memory low. */
vor_status vor__mesh_to_diagram(const vor_sites *s, vor__mesh *m,
                                vor_diagram **out);

/* The generic builder every algorithm ends in. Input: n_vertices raw
 * vertices (ids 0..n_vertices-1, cocircular centres already merged into one
 * id) and n_edges raw edges, edges[2e], edges[2e+1] = the two sites (any
 * order, distinct), ends[2e], ends[2e+1] = raw vertex ids or VOR_NONE (any
 * order). Every raw vertex must be the end of at least one edge. The
 * builder takes ownership of edges and ends (freed or reused, also on error).
 * It derives each vertex's three smallest sites from the edges that meet
 * there, computes coordinates with vor_circumcenter, ray directions with
 * vor_bisector_dir (outward decided exactly with vor_orient2d), orders
 * everything canonically and builds the counter-clockwise cells.
 * O(n) when each site is the smallest of a bounded number of circles;
 * O(n log n) at worst. */
vor_status vor__diagram_build(const vor_sites *s, size_t n_vertices,
                              uint32_t *edges, int32_t *ends, size_t n_edges,
                              vor_diagram **out);

/* Adds site x to t, the (at most three) smallest distinct sites seen so
 * far in increasing order, UINT32_MAX marking free slots. For a vertex's
 * defining sites: the three smallest on its circle. */
static inline void vor__min3_add(uint32_t *t, uint32_t x) {
    if (x == t[0] || x == t[1] || x == t[2]) return;
    if (x < t[0]) {
        t[2] = t[1];
        t[1] = t[0];
        t[0] = x;
    } else if (x < t[1]) {
        t[2] = t[1];
        t[1] = x;
    } else if (x < t[2]) {
        t[2] = x;
    }
}

/* Non-zero if all sites are collinear (or n < 3). */
int vor__all_collinear(const vor_sites *s);

/* The diagram of n < 3 sites or of collinear sites: parallel lines between
 * consecutive sites along the line. */
vor_status vor__diagram_degenerate(const vor_sites *s, vor_diagram **out);

/* vor_diagram_triangles by walking the cells, whatever the vertices'
 * degrees: the definition of its result, and the checker's derivation of
 * the dual triangles, which takes each vertex's sites and their order
 * from the cells and edges, and of vertex_sites only the first, checked
 * to be one of them (diagram.c). */
vor_status vor__diagram_triangles_cells(const vor_diagram *d,
                                        const vor_sites *sites,
                                        uint32_t **out, size_t *n_tri);

#endif /* VOR_INTERNAL_H */
