// peer_cgal.cc -- CGAL's 2D Delaunay triangulation timed on a points file.
//
// The reference the algorithm table is held against: CGAL's
// Delaunay_triangulation_2 with the Exact_predicates_inexact_constructions
// kernel (exact predicates by filtering, like ours), built by inserting the
// whole range at once, which sorts the points spatially (Hilbert order)
// before inserting them. The points are read and converted to Point_2
// outside the timer; the timer covers construction of the triangulation
// only (CGAL builds no Voronoi diagram here: its Voronoi adaptor derives
// vertices and edges lazily from this triangulation).
//
// The first run also measures peak memory and the kernel's CPU time
// (bench_util.h). With --tris, an
// extra untimed build that carries each point's index writes the finite
// triangles of the first file for bench_algo's exact check.
//
// usage: peer_cgal --points FILE[,FILE...] [--runs R] [--tris FILE]
// prints: RESULT name=cgal n=... ms=... min_ms=... runs=... peak_bpp=...
//         sys_ms=... triangles=... status=ok
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "bench_util.h"

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_2 Point;
typedef CGAL::Delaunay_triangulation_2<K> DT;
typedef CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K> Vb;
typedef CGAL::Triangulation_data_structure_2<Vb> Tds;
typedef CGAL::Delaunay_triangulation_2<K, Tds> DTI;

// Builds the indexed triangulation and writes its finite faces
// (counter-clockwise, as CGAL orients them). Returns the count, or -1.
static long write_triangles(const std::vector<Point> &pts, const char *path) {
    std::vector<std::pair<Point, uint32_t>> with_index;
    with_index.reserve(pts.size());
    for (size_t i = 0; i < pts.size(); i++)
        with_index.emplace_back(pts[i], (uint32_t)i);
    DTI dt(with_index.begin(), with_index.end());
    std::vector<uint32_t> tri;
    tri.reserve(6 * pts.size());
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f)
        for (int k = 0; k < 3; k++)
            tri.push_back(f->vertex(k)->info());
    if (bu_write_file(path, tri.data(), tri.size() * sizeof(uint32_t)) != 0)
        return -1;
    return (long)(tri.size() / 3);
}

int main(int argc, char **argv) {
    char *points = nullptr;
    const char *tris = nullptr;
    int runs = 3;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--points"))
            points = argv[i + 1];
        else if (!std::strcmp(argv[i], "--runs"))
            runs = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--tris"))
            tris = argv[i + 1];
    }
    char *paths[64];
    int files = bu_split_paths(points, paths, 64);
    std::vector<std::vector<Point>> sets((size_t)files);
    size_t n = 0;
    for (int f = 0; f < files; f++) {
        size_t m = 0;
        double *xy = bu_read_points(paths[f], &m);
        if (!xy || (f > 0 && m != n)) {
            std::free(xy);
            files = 0;
            break;
        }
        n = m;
        sets[(size_t)f].reserve(n);
        for (size_t i = 0; i < n; i++)
            sets[(size_t)f].emplace_back(xy[2 * i], xy[2 * i + 1]);
        std::free(xy);
    }
    if (files == 0 || runs < 1) {
        std::fputs("usage: peer_cgal --points FILE[,FILE...] [--runs R] "
                   "[--tris FILE]\n",
                   stderr);
        return 2;
    }

    std::vector<double> ms;
    double peak = -1, sys = -1;
    size_t faces = 0;
    for (int r = 0; r < runs; r++) {
        const std::vector<Point> &pts = sets[(size_t)(r % files)];
        long base = r == 0 ? bu_peak_reset() : -1;
        double s0 = bu_sys_ms();
        uint64_t t0 = bu_now_ns();
        {
            DT dt;
            dt.insert(pts.begin(), pts.end());
            uint64_t t1 = bu_now_ns();
            double s1 = bu_sys_ms();
            ms.push_back((double)(t1 - t0) / 1e6);
            if (r == 0) {
                sys = s0 >= 0 && s1 >= 0 ? s1 - s0 : -1.0;
                peak = bu_peak_bytes(base);
                faces = dt.number_of_faces();
            }
        }
    }
    double min_ms = ms[0];
    for (double v : ms)
        min_ms = v < min_ms ? v : min_ms;
    double med = bu_median(ms.data(), ms.size());
    long nt = (long)faces;
    if (tris)
        nt = write_triangles(sets[0], tris);
    std::printf("RESULT name=cgal n=%zu ms=%.3f min_ms=%.3f runs=%d "
                "peak_bpp=%.1f sys_ms=%.1f triangles=%ld status=%s\n",
                n, med, min_ms, runs, peak >= 0 ? peak / (double)n : -1.0, sys, nt,
                nt >= 0 ? "ok" : "write-failed");
    return nt >= 0 ? 0 : 1;
}
