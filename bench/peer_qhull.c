/* peer_qhull.c -- qhull's Delaunay triangulation timed on a points file.
 *
 * qhull (libqhull_r, the reentrant library) computes the Delaunay
 * triangulation as the lower convex hull of the points lifted onto a
 * paraboloid, in floating point with merging of nearly coplanar facets
 * instead of exact predicates. Options as qdelaunay uses them: "d" Delaunay,
 * "Qbb" scale the lifted coordinate, "Qc" keep coplanar points, "Qz" add a
 * point at infinity (helps cocircular input), plus "Qt" to triangulate the
 * merged non-simplicial facets so that the output is triangles.
 *
 * The timer covers qh_new_qhull (lifting, hull, triangulation); freeing the
 * structures is outside it. The first run also measures peak memory
 * (bench_util.h). With --tris, the lower-hull triangles are written
 * counter-clockwise (oriented by the facet's orientation flag) for the
 * exact check in bench_algo.
 *
 * usage: peer_qhull --points FILE[,FILE...] [--runs R] [--tris FILE]
 * prints: RESULT name=qhull n=... ms=... min_ms=... runs=... peak_bpp=...
 *         triangles=... status=ok|qhull-error-N
 */
#include <libqhull_r/qhull_ra.h>

#include "bench_util.h"

/* Appends the lower-hull triangles of the finished hull to *out (3 ids
 * each). Returns the count or -1 on allocation failure. */
static long collect(qhT *qh, int numpoints, uint32_t **out) {
    facetT *facet;
    vertexT *vertex, **vertexp;
    size_t cap = 0, len = 0;
    uint32_t *tri = NULL;
    FORALLfacets {
        if (facet->upperdelaunay)
            continue;
        uint32_t v[3];
        int k = 0, skip = 0;
        FOREACHvertex_(facet->vertices) {
            int id = qh_pointid(qh, vertex->point);
            if (k < 3 && id >= 0 && id < numpoints)
                v[k] = (uint32_t)id;
            else
                skip = 1;
            k++;
        }
        if (skip || k != 3)
            continue;
        if (!facet->toporient) {
            uint32_t s = v[1];
            v[1] = v[2];
            v[2] = s;
        }
        if (len + 3 > cap) {
            size_t ncap = cap ? 2 * cap : 3 * 1024;
            uint32_t *p = realloc(tri, ncap * sizeof *p);
            if (!p) {
                free(tri);
                return -1;
            }
            tri = p;
            cap = ncap;
        }
        memcpy(tri + len, v, sizeof v);
        len += 3;
    }
    *out = tri;
    return (long)(len / 3);
}

int main(int argc, char **argv) {
    char *points = NULL;
    const char *tris = NULL;
    int runs = 3;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--points"))
            points = argv[i + 1];
        else if (!strcmp(argv[i], "--runs"))
            runs = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--tris"))
            tris = argv[i + 1];
    }
    char *paths[64];
    double *sets[64];
    int files = bu_split_paths(points, paths, 64);
    size_t n = 0;
    for (int f = 0; f < files; f++) {
        size_t m = 0;
        sets[f] = bu_read_points(paths[f], &m);
        if (!sets[f] || (f > 0 && m != n)) {
            files = f + (sets[f] != NULL);
            n = 0;
            break;
        }
        n = m;
    }
    if (files == 0 || n < 3 || runs < 1 || n > 0x7fffffff) {
        fputs("usage: peer_qhull --points FILE[,FILE...] [--runs R] "
              "[--tris FILE]\n",
              stderr);
        return 2;
    }
    double *ms = malloc(sizeof *ms * (size_t)runs), peak = -1;
    long nt = -1;
    int err = 0;
    char flags[] = "qhull d Qt Qbb Qc Qz";
    if (!ms)
        return 2;
    for (int r = 0; r < runs && !err; r++) {
        qhT qh_qh, *qh = &qh_qh;
        int curlong, totlong;
        long base = r == 0 ? bu_peak_reset() : -1;
        qh_zero(qh, stderr);
        uint64_t t0 = bu_now_ns();
        err = qh_new_qhull(qh, 2, (int)n, sets[r % files], False, flags, NULL,
                           stderr);
        uint64_t t1 = bu_now_ns();
        ms[r] = (double)(t1 - t0) / 1e6;
        if (r == 0 && !err) {
            peak = bu_peak_bytes(base);
            uint32_t *tri = NULL;
            nt = collect(qh, (int)n, &tri);
            if (nt >= 0 && tris &&
                bu_write_file(tris, tri, (size_t)nt * 12) != 0)
                nt = -1;
            free(tri);
        }
        qh_freeqhull(qh, !qh_ALL);
        qh_memfreeshort(qh, &curlong, &totlong);
    }
    if (err) {
        printf("RESULT name=qhull n=%zu status=qhull-error-%d\n", n, err);
        return 1;
    }
    double min_ms = ms[0];
    for (int r = 1; r < runs; r++)
        min_ms = ms[r] < min_ms ? ms[r] : min_ms;
    double med = bu_median(ms, (size_t)runs);
    printf("RESULT name=qhull n=%zu ms=%.3f min_ms=%.3f runs=%d "
           "peak_bpp=%.1f triangles=%ld status=%s\n",
           n, med, min_ms, runs, peak >= 0 ? peak / (double)n : -1.0, nt,
           nt >= 0 ? "ok" : "write-failed");
    free(ms);
    for (int f = 0; f < files; f++)
        free(sets[f]);
    return nt >= 0 ? 0 : 1;
}
