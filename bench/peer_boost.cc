// peer_boost.cc -- Boost.Polygon's Voronoi builder timed on a points file.
//
// Boost.Polygon's construct_voronoi is a sweep line (Fortune's algorithm)
// with exact predicates, but it accepts integer coordinates only (int32).
// The driver therefore quantises the points first, outside the timer: an
// exact power-of-two scale maps the bounding box onto [0, 2^30] and each
// coordinate is rounded to the nearest integer. Unit-square doubles keep
// about 30 bits per axis that way; points that collapse onto the same
// integers are reported. The timer covers construct_voronoi (the full
// diagram: vertices, half-edges, cells) only.
//
// With --tris, the dual triangles are written (each Voronoi vertex of degree
// k fanned into k - 2 triangles, sites taken counter-clockwise around it)
// together with the quantised points (--qpoints), so that bench_algo can
// check Boost's diagram exactly against the input Boost really had.
//
// usage: peer_boost --points FILE[,FILE...] [--runs R]
//                   [--tris FILE --qpoints FILE]
// prints: RESULT name=boost n=... ms=... min_ms=... runs=... peak_bpp=...
//         vertices=... collapsed=... triangles=... status=ok
#include <boost/polygon/voronoi.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <utility>
#include <vector>

#include "bench_util.h"

typedef boost::polygon::point_data<int32_t> IPoint;
typedef boost::polygon::voronoi_diagram<double> VD;

// Fans every finite Voronoi vertex into triangles of site indices.
static void dual_triangles(const VD &vd, std::vector<uint32_t> &tri) {
    for (const auto &v : vd.vertices()) {
        std::vector<uint32_t> around;
        const VD::edge_type *e = v.incident_edge(), *start = e;
        do {
            around.push_back((uint32_t)e->cell()->source_index());
            e = e->rot_next();
        } while (e != start);
        for (size_t k = 1; k + 1 < around.size(); k++) {
            tri.push_back(around[0]);
            tri.push_back(around[k]);
            tri.push_back(around[k + 1]);
        }
    }
}

// One input quantised: the points, their doubles (for --qpoints) and how
// many collapsed onto an earlier point.
struct Quantised {
    std::vector<IPoint> pts;
    std::vector<double> qxy;
    size_t collapsed = 0;
};

// Quantise: scale 2^k so that the larger side of the box fits 2^30.
static void quantise(const double *xy, size_t n, Quantised &q) {
    double xmin = xy[0], xmax = xy[0], ymin = xy[1], ymax = xy[1];
    for (size_t i = 1; i < n; i++) {
        xmin = std::fmin(xmin, xy[2 * i]);
        xmax = std::fmax(xmax, xy[2 * i]);
        ymin = std::fmin(ymin, xy[2 * i + 1]);
        ymax = std::fmax(ymax, xy[2 * i + 1]);
    }
    double side = std::fmax(xmax - xmin, ymax - ymin);
    int ex = 0;
    std::frexp(side > 0 ? side : 1.0, &ex); // side < 2^ex
    double scale = std::ldexp(1.0, 30 - ex);
    q.pts.reserve(n);
    q.qxy.reserve(2 * n);
    std::set<std::pair<int32_t, int32_t>> seen;
    for (size_t i = 0; i < n; i++) {
        int32_t x = (int32_t)std::llround((xy[2 * i] - xmin) * scale);
        int32_t y = (int32_t)std::llround((xy[2 * i + 1] - ymin) * scale);
        q.pts.emplace_back(x, y);
        q.qxy.push_back(x);
        q.qxy.push_back(y);
        if (!seen.insert(std::make_pair(x, y)).second)
            q.collapsed++;
    }
}

int main(int argc, char **argv) {
    char *points = nullptr;
    const char *tris = nullptr, *qpoints = nullptr;
    int runs = 3;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--points"))
            points = argv[i + 1];
        else if (!std::strcmp(argv[i], "--runs"))
            runs = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--tris"))
            tris = argv[i + 1];
        else if (!std::strcmp(argv[i], "--qpoints"))
            qpoints = argv[i + 1];
    }
    char *paths[64];
    int files = bu_split_paths(points, paths, 64);
    std::vector<Quantised> sets((size_t)files);
    size_t n = 0;
    for (int f = 0; f < files; f++) {
        size_t m = 0;
        double *xy = bu_read_points(paths[f], &m);
        if (!xy || m == 0 || (f > 0 && m != n)) {
            std::free(xy);
            files = 0;
            break;
        }
        n = m;
        quantise(xy, n, sets[(size_t)f]);
        std::free(xy);
    }
    if (files == 0 || runs < 1 || (tris && !qpoints)) {
        std::fputs("usage: peer_boost --points FILE[,FILE...] [--runs R] "
                   "[--tris FILE --qpoints FILE]\n",
                   stderr);
        return 2;
    }

    std::vector<double> ms;
    double peak = -1;
    size_t vertices = 0;
    long nt = -1;
    for (int r = 0; r < runs; r++) {
        const Quantised &q = sets[(size_t)(r % files)];
        long base = r == 0 ? bu_peak_reset() : -1;
        VD vd;
        uint64_t t0 = bu_now_ns();
        boost::polygon::construct_voronoi(q.pts.begin(), q.pts.end(), &vd);
        uint64_t t1 = bu_now_ns();
        ms.push_back((double)(t1 - t0) / 1e6);
        if (r == 0) {
            peak = bu_peak_bytes(base);
            vertices = vd.num_vertices();
            if (tris) {
                std::vector<uint32_t> tri;
                dual_triangles(vd, tri);
                if (bu_write_file(tris, tri.data(), tri.size() * 4) == 0 &&
                    bu_write_file(qpoints, q.qxy.data(), q.qxy.size() * 8) == 0)
                    nt = (long)(tri.size() / 3);
            }
        }
    }
    double min_ms = ms[0];
    for (double v : ms)
        min_ms = v < min_ms ? v : min_ms;
    double med = bu_median(ms.data(), ms.size());
    std::printf("RESULT name=boost n=%zu ms=%.3f min_ms=%.3f runs=%d "
                "peak_bpp=%.1f vertices=%zu collapsed=%zu triangles=%ld "
                "status=%s\n",
                n, med, min_ms, runs, peak >= 0 ? peak / (double)n : -1.0,
                vertices, sets[0].collapsed, nt,
                tris && nt < 0 ? "write-failed" : "ok");
    return tris && nt < 0 ? 1 : 0;
}
