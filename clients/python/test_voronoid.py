"""test_voronoid.py -- the Python client against a live voronoid and scipy.

Run by `make python-client` (part of `make test`) with Debian's
/usr/bin/python3 (numpy and scipy from python3-numpy, python3-scipy). The
daemon is $VOR_DAEMON (default build/asan/voronoid), started on an
ephemeral loopback port and stopped with SIGTERM, which must exit 0.

For every point set the client's arrays are checked three ways:

1. Against the exact truth. qhull (scipy.spatial.Delaunay) is NOT taken on
   trust: its triangulation is verified with exact integer arithmetic
   (every triangle counter-clockwise, neighbours symmetric, every distinct
   point used, the boundary a convex cycle, Euler's count, every interior
   edge locally Delaunay). A verified triangulation is a Delaunay
   triangulation, and its edges minus the diagonals of cocircular
   neighbours (incircle exactly 0: zero-length ridges) are exactly the
   Voronoi ridges -- an oracle that holds on degenerate sets too. Sets
   with a known structure (a grid, lattice points on a circle, collinear
   points) are also checked against that structure, computed here.
2. Against scipy.spatial.Voronoi: its ridge_points must equal the
   client's as sets of pairs wherever qhull's answer is correct, which is
   decided by comparing it with the verified truth of 1 (so a tolerance
   merge of qhull that went wrong is reported, not blamed on us); on sets
   in general position the vertices and regions are compared too, to
   1e-9 relative.
3. Against the JSON answer of the same request: every array equal, exactly
   (vertices bit for bit), regions re-derived from cells[].edges by a
   separate walk, duplicates, triangles, clipped cells.

Duplicates: point_region of a repeated point is its first occurrence's
region, and ridge_points name first occurrences only. Random sets use
fixed seeds, printed.
"""

import json
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import unittest
import urllib.parse
import urllib.request
from fractions import Fraction

import numpy as np
from scipy.spatial import Delaunay, QhullError, Voronoi, cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import voronoid  # noqa: E402

DAEMON = os.environ.get("VOR_DAEMON", "build/asan/voronoid")
SEED = 20251125


# ---- the daemon ------------------------------------------------------------

class Daemon:
    def __init__(self, binary):
        self.log = tempfile.NamedTemporaryFile(prefix="voronoid-py-", suffix=".log",
                                               delete=False)
        self.proc = subprocess.Popen(
            [binary, "--bind", "127.0.0.1", "--port", "0", "--workers", "2"],
            stdout=subprocess.DEVNULL, stderr=self.log)
        self.log.close()
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            with open(self.log.name) as f:
                m = re.search(r"listening on (http://127\.0\.0\.1:\d+)/", f.read())
            if m:
                self.url = m.group(1)
                return
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        self.proc.kill()
        with open(self.log.name) as f:
            raise RuntimeError(f"{binary} did not start: {f.read()}")

    def stop(self):
        self.proc.send_signal(signal.SIGTERM)
        try:
            rc = self.proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rc = "hung"
        with open(self.log.name) as f:
            text = f.read()
        os.unlink(self.log.name)
        return rc, text


# ---- exact predicates on the doubles, with integers ---------------------------

def to_integers(xy):
    """The points as exact integers of one common scale: every double is
    m / 2^k, so multiplying by the largest 2^k is exact."""
    fr = [Fraction(float(v)) for v in xy.ravel()]
    den = max(f.denominator for f in fr) if fr else 1
    ints = [f.numerator * (den // f.denominator) for f in fr]
    return [(ints[2 * i], ints[2 * i + 1]) for i in range(len(xy))]


def orient(a, b, c):
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def incircle(a, b, c, d):
    """> 0 when d is strictly inside the circle of the ccw triangle abc."""
    rows = []
    for p in (a, b, c):
        dx, dy = p[0] - d[0], p[1] - d[1]
        rows.append((dx, dy, dx * dx + dy * dy))
    (a0, a1, a2), (b0, b1, b2), (c0, c1, c2) = rows
    return (a0 * (b1 * c2 - b2 * c1) - a1 * (b0 * c2 - b2 * c0)
            + a2 * (b0 * c1 - b1 * c0))


def verified_ridges(upts):
    """The true Voronoi ridges of distinct points upts ((m, 2), m >= 3, not
    all collinear) as a set of sorted index pairs, from qhull's Delaunay
    triangulation once it is verified exactly; None (with the reason) when
    qhull's triangulation is not a Delaunay triangulation of all points."""
    try:
        tri = Delaunay(upts)
    except QhullError as e:
        return None, f"qhull failed: {str(e).splitlines()[0]}"
    P = to_integers(upts)
    S, N = tri.simplices.copy(), tri.neighbors.copy()
    m, t = len(upts), len(S)
    if len(np.unique(S)) != m:
        return None, "qhull left points out of its triangulation"
    for k in range(t):
        a, b, c = S[k]
        o = orient(P[a], P[b], P[c])
        if o == 0:
            return None, f"qhull triangle {k} is flat"
        if o < 0:  # qhull's orientation varies: make it counter-clockwise
            S[k][[1, 2]] = S[k][[2, 1]]
            N[k][[1, 2]] = N[k][[2, 1]]
    boundary = {}
    edges, cocircular = set(), set()
    for k in range(t):
        for j in range(3):
            u, v = S[k][(j + 1) % 3], S[k][(j + 2) % 3]  # edge opposite j
            e = (min(u, v), max(u, v))
            edges.add(e)
            nb = N[k][j]
            if nb < 0:
                boundary[u] = v
                continue
            if k not in N[nb]:
                return None, "qhull neighbours are not symmetric"
            d = [w for w in S[nb] if w != u and w != v][0]
            s = incircle(P[S[k][0]], P[S[k][1]], P[S[k][2]], P[d])
            if s > 0:
                return None, f"qhull edge {e} is not locally Delaunay"
            if s == 0:
                cocircular.add(e)
    # The boundary: one cycle, convex (every turn left or straight).
    start = next(iter(boundary))
    cycle, u = [start], boundary[start]
    while u != start and len(cycle) <= len(boundary):
        cycle.append(u)
        u = boundary.get(u, start)
    if len(cycle) != len(boundary):
        return None, "qhull's boundary is not one cycle"
    h = len(cycle)
    for i in range(h):
        if orient(P[cycle[i - 1]], P[cycle[i]], P[cycle[(i + 1) % h]]) < 0:
            return None, "qhull's boundary is not convex"
    if t != 2 * m - h - 2:
        return None, "qhull's triangle count breaks Euler's formula"
    return edges - cocircular, None


def pairs(a):
    a = np.sort(np.asarray(a, dtype=np.int64).reshape(-1, 2), axis=1)
    return set(map(tuple, a.tolist()))


# ---- point sets ------------------------------------------------------------------

def lattice_circle(r):
    """The integer points on the circle x^2 + y^2 = r^2 (exactly
    cocircular), shuffled."""
    pts = [(x, y) for x in range(-r, r + 1) for y in range(-r, r + 1)
           if x * x + y * y == r * r]
    rng = np.random.default_rng(SEED)
    return np.array(pts, float)[rng.permutation(len(pts))]


def point_sets():
    rng = np.random.default_rng(SEED)
    sets = {}
    sets["uniform"] = (rng.random((3000, 2)), "general")
    sets["gaussian"] = (rng.standard_normal((3000, 2)) * 1e3, "general")
    centres = rng.random((12, 2))
    sets["clustered"] = (centres[rng.integers(0, 12, 3000)] +
                         rng.standard_normal((3000, 2)) * 0.01, "general")
    base = rng.random((1500, 2))
    dup = np.concatenate([base, base[rng.integers(0, 1500, 600)]])
    sets["uniform+duplicates"] = (dup[rng.permutation(len(dup))], "general")
    sets["pixels"] = (rng.integers(0, [800, 600], (2500, 2)).astype(float), "degenerate")
    g = np.array([(x, y) for y in range(15) for x in range(15)], float)
    sets["grid"] = (g[rng.permutation(len(g))], "grid")
    sets["circle"] = (lattice_circle(125), "circle")
    x = rng.permutation(60).astype(float)
    sets["collinear"] = (np.stack([x * 0.25 - 3, x * 0.5 + 1], axis=1), "collinear")
    return sets


# ---- independent structure of the degenerate sets -------------------------------

def grid_truth(xy):
    index = {(int(x), int(y)): i for i, (x, y) in enumerate(xy)}
    ridges = set()
    for (x, y), i in index.items():
        for q in ((x + 1, y), (x, y + 1)):
            if q in index:
                ridges.add((min(i, index[q]), max(i, index[q])))
    k = int(round(math.sqrt(len(xy))))
    return ridges, (k - 1) * (k - 1)


def circle_truth(xy):
    order = np.argsort(np.arctan2(xy[:, 1], xy[:, 0]))
    n = len(order)
    return {(min(order[i], order[(i + 1) % n]), max(order[i], order[(i + 1) % n]))
            for i in range(n)}


def collinear_truth(xy):
    order = np.lexsort((xy[:, 1], xy[:, 0]))
    return {(min(order[i], order[i + 1]), max(order[i], order[i + 1]))
            for i in range(len(order) - 1)}


# ---- the JSON answer of the same request -------------------------------------------

def json_answer(url, xy, query):
    q = dict(query, format="json")
    req = urllib.request.Request(
        url + "/voronoi?" + urllib.parse.urlencode(q), data=xy.tobytes(),
        method="POST", headers={"Content-Type": "application/octet-stream"})
    with urllib.request.urlopen(req, timeout=600) as r:
        return json.loads(r.read())


def regions_from_cells(j):
    """Regions walked from the JSON cells (a separate implementation: the
    vertex two consecutive edges share, by set intersection)."""
    ends = [e["ends"] for e in j["edges"]]
    out = []
    for c in j["cells"]:
        es = c["edges"]
        if not j["vertices"]:
            out.append([-1])
            continue
        reg = []
        for i, e in enumerate(es):
            if i == len(es) - 1 and not c["bounded"]:
                reg.append(-1)
                break
            f = es[(i + 1) % len(es)]
            common = {v for v in ends[e] if v is not None} & \
                     {v for v in ends[f] if v is not None}
            assert len(common) == 1, (e, f, common)
            reg.append(common.pop())
        out.append(reg)
    return out


class ClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        print(f"# seed {SEED}, daemon {DAEMON}", flush=True)
        cls.daemon = Daemon(DAEMON)
        cls.url = cls.daemon.url
        cls.sets = point_sets()

    @classmethod
    def tearDownClass(cls):
        rc, log = cls.daemon.stop()
        if rc != 0:
            raise AssertionError(f"daemon exit status {rc}:\n{log[-3000:]}")

    # -- 3. the JSON answer -----------------------------------------------------
    def check_against_json(self, name, xy, d, query):
        j = json_answer(self.url, xy, query)
        self.assertEqual(j["algorithm"], d.algorithm)
        self.assertEqual((j["n_input"], j["n_sites"]), (d.n_input, d.n_sites))
        v = np.array(j["vertices"], float).reshape(-1, 2)
        self.assertTrue(np.array_equal(v, d.vertices), name)  # bit for bit
        self.assertEqual([e["sites"] for e in j["edges"]], d.ridge_points.tolist())
        self.assertEqual([[-1 if x is None else x for x in e["ends"]] for e in j["edges"]],
                         d.ridge_vertices.tolist())
        rays = np.array([e.get("ray", [math.nan, math.nan]) for e in j["edges"]],
                        float).reshape(-1, 2)
        self.assertTrue(np.array_equal(rays, d.ridge_rays, equal_nan=True), name)
        for k, e in enumerate(j["edges"]):
            if "point" in e:  # a line: through the midpoint of its sites
                a, b = d.points[e["sites"][0]], d.points[e["sites"][1]]
                self.assertTrue(np.array_equal(e["point"], (a + b) / 2), name)
        self.assertEqual([c["site"] for c in j["cells"]], d.region_point.tolist())
        self.assertEqual([c["bounded"] for c in j["cells"]], d.region_bounded.tolist())
        self.assertEqual(regions_from_cells(j), d.regions, name)
        self.assertEqual(j["duplicates"], d.duplicates.tolist())
        if d.triangles is not None:
            self.assertEqual(j["triangles"], d.triangles.tolist())
        if d.clip_box is not None:
            c = j["clipped"]
            self.assertEqual(c["bounds"], d.clip_box.tolist())
            ce = np.array([[math.nan] * 4 if s is None else s for s in c["edges"]], float)
            self.assertTrue(np.array_equal(ce.reshape(-1, 4), d.clip_edges, equal_nan=True))
            for r, ring in enumerate(c["cells"]):
                got = d.cell_polygon(d.region_point[r]).tolist()
                self.assertEqual(ring, got, f"{name}: clipped cell {r}")
        self.assertEqual(set(j["timings"]), set(d.timings))
        if "counts" in j:  # the binary answer's counts are the JSON's
            self.assertEqual(j["counts"], d.counts, name)

    # -- our own invariants ---------------------------------------------------------
    def check_invariants(self, name, xy, d):
        n = len(xy)
        self.assertEqual(d.points.shape, (n, 2))
        self.assertEqual(len(d.point_region), n)
        first = d.region_point[d.point_region]
        # Duplicates: the first occurrence's region, the same coordinates.
        self.assertTrue(np.array_equal(xy[first], xy), name)
        self.assertTrue(np.all(first <= np.arange(n)), name)
        _, firsts = np.unique(xy, axis=0, return_index=True)
        self.assertEqual(sorted(firsts.tolist()), d.region_point.tolist())
        self.assertEqual(d.n_sites, len(firsts))
        for i, f in d.duplicates.tolist():
            self.assertEqual(d.point_region[i], d.point_region[f])
            self.assertTrue(np.array_equal(xy[i], xy[f]))
        # Ridges name first occurrences, each pair once.
        self.assertTrue(np.all(np.isin(d.ridge_points, d.region_point)), name)
        self.assertEqual(len(pairs(d.ridge_points)), len(d.ridge_points))
        nv, ne, ns = len(d.vertices), len(d.ridge_points), d.n_sites
        if nv == 0:
            self.assertEqual(ne, max(ns - 1, 0), name)
            self.assertTrue(np.all(d.ridge_vertices == -1))
        else:  # Euler, with one vertex at infinity closing the rays
            self.assertEqual(ns - ne + nv, 1, name)
        # Every finite end: as far from both points of its ridge as from
        # the nearest point (empty circle, to rounding).
        tree = cKDTree(xy) if n else None
        for col in (0, 1) if n else ():
            fin = d.ridge_vertices[:, col] >= 0
            vx = d.vertices[d.ridge_vertices[fin, col]]
            da = np.hypot(*(vx - xy[d.ridge_points[fin, 0]]).T)
            db = np.hypot(*(vx - xy[d.ridge_points[fin, 1]]).T)
            near, _ = tree.query(vx)
            scale = np.maximum(da, 1e-300)
            self.assertTrue(np.all(np.abs(da - db) <= 1e-9 * scale), name)
            self.assertTrue(np.all(near >= da * (1 - 1e-9)), name)
        # Bounded regions: counter-clockwise convex polygons around their point.
        for r in np.flatnonzero(d.region_bounded)[:500]:
            poly = d.vertices[d.region_vertices[d.region_indptr[r]:d.region_indptr[r + 1]]]
            x, y = poly[:, 0], poly[:, 1]
            area = np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))
            self.assertGreater(area, 0, f"{name}: region {r}")
            p = xy[d.region_point[r]]
            e = np.roll(poly, -1, axis=0) - poly
            cross = e[:, 0] * (p[1] - poly[:, 1]) - e[:, 1] * (p[0] - poly[:, 0])
            self.assertTrue(np.all(cross > 0), f"{name}: point outside region {r}")
        # Unbounded regions end with -1; rays are unit vectors.
        for r in np.flatnonzero(~d.region_bounded):
            reg = d.region_vertices[d.region_indptr[r]:d.region_indptr[r + 1]]
            if len(reg):
                self.assertEqual(reg[-1], -1)
        unb = (d.ridge_vertices < 0).any(axis=1)
        self.assertTrue(np.all(np.isnan(d.ridge_rays[~unb])))
        self.assertTrue(np.allclose(np.hypot(*d.ridge_rays[unb].T), 1, rtol=1e-12))

    # -- 1 and 2: the truth, and scipy where qhull is right -----------------------------
    def check_against_truth_and_scipy(self, name, xy, kind, d):
        ours = pairs(d.ridge_points)
        _, firsts = np.unique(xy, axis=0, return_index=True)
        firsts = np.sort(firsts)
        upts = xy[firsts]

        def to_input(s):  # indices into upts -> input indices
            return {(int(firsts[a]), int(firsts[b])) for a, b in s}

        if kind == "grid":
            truth, nv = grid_truth(xy)
            self.assertEqual(ours, truth, name)
            self.assertEqual(len(d.vertices), nv)
        elif kind == "circle":
            self.assertEqual(ours, circle_truth(xy), name)
            self.assertEqual(d.vertices.tolist(), [[0.0, 0.0]], name)
        elif kind == "collinear":
            self.assertEqual(ours, collinear_truth(xy), name)
        report = []
        verified, why = (None, "collinear") if kind == "collinear" else verified_ridges(upts)
        if verified is not None:
            self.assertEqual(ours, to_input(verified), f"{name}: against the verified truth")
            report.append("qhull's Delaunay verified exactly")
        else:
            report.append(f"no verified truth ({why})")
        try:
            sv = Voronoi(upts)
        except QhullError as e:
            report.append(f"scipy.Voronoi refused: {str(e).splitlines()[0]}")
            print(f"# {name}: " + "; ".join(report), flush=True)
            return
        theirs = to_input(pairs(sv.ridge_points))
        if verified is not None and theirs != to_input(verified):
            extra = len(theirs - to_input(verified))
            missing = len(to_input(verified) - theirs)
            report.append(f"scipy.Voronoi is wrong here ({extra} extra, {missing} "
                          f"missing ridges): not compared")
        elif verified is None:
            report.append("scipy.Voronoi not compared")
        else:
            self.assertEqual(ours, theirs, name)
            report.append(f"ridge_points equal scipy's ({len(ours)} pairs)")
            if kind == "general":
                self.compare_geometry(name, d, sv, firsts)
                report.append("vertices and regions equal to 1e-9")
        print(f"# {name}: " + "; ".join(report), flush=True)

    def compare_geometry(self, name, d, sv, firsts):
        """General position: the same vertex coordinates, per ridge and per
        region, to 1e-9 relative (scipy's are floating-point circumcentres,
        ours the exactly decided ones)."""
        scale = np.abs(d.points).max()

        def ends(vertices, rv):
            fin = [tuple(vertices[v]) for v in rv if v >= 0]
            return sorted(fin)

        theirs = {}
        for (a, b), rv in zip(sv.ridge_points.tolist(), sv.ridge_vertices):
            key = (min(firsts[a], firsts[b]), max(firsts[a], firsts[b]))
            theirs[key] = ends(sv.vertices, rv)
        for (a, b), rv in zip(d.ridge_points.tolist(), d.ridge_vertices.tolist()):
            mine, other = ends(d.vertices, rv), theirs[(min(a, b), max(a, b))]
            self.assertEqual(len(mine), len(other), f"{name}: ridge {a}-{b}")
            if mine:
                self.assertTrue(np.allclose(mine, other, rtol=1e-9, atol=1e-9 * scale),
                                f"{name}: ridge {a}-{b}: {mine} vs {other}")
        for k, f in enumerate(firsts):
            mine = d.regions[d.point_region[f]]
            other = sv.regions[sv.point_region[k]]
            self.assertEqual(-1 in mine, -1 in other, f"{name}: region of {f}")
            a = np.array(sorted(tuple(d.vertices[v]) for v in mine if v >= 0))
            b = np.array(sorted(tuple(sv.vertices[v]) for v in other if v >= 0))
            self.assertEqual(a.shape, b.shape, f"{name}: region of {f}")
            if len(a):
                self.assertTrue(np.allclose(a, b, rtol=1e-9, atol=1e-9 * scale))

    # -- the tests ---------------------------------------------------------------
    def test_point_sets(self):
        for name, (xy, kind) in self.sets.items():
            with self.subTest(name):
                alg = ["fortune", "bowyer-watson", "flip"][len(name) % 3]
                d = voronoid.voronoi(xy, url=self.url, algorithm=alg, triangles=True)
                self.assertEqual(d.algorithm, alg)
                self.check_invariants(name, xy, d)
                self.check_against_truth_and_scipy(name, xy, kind, d)
                self.check_against_json(name, xy, d, {
                    "algorithm": alg, "include": "vertices,edges,cells,triangles,counts"})

    def test_bounds_and_clipped_cells(self):
        xy = self.sets["uniform+duplicates"][0]
        d = voronoid.voronoi(xy, url=self.url, bounds=(0.25, 0.25, 0.75, 0.75))
        self.assertEqual(d.clip_box.tolist(), [0.25, 0.25, 0.75, 0.75])
        self.check_against_json("bounds", xy, d, {
            "bounds": "0.25,0.25,0.75,0.75", "include": "vertices,edges,cells,clipped"})
        # A point well inside: its clipped cell is its whole (bounded) region.
        i = int(np.argmin(np.hypot(*(xy - 0.5).T)))
        ring = d.cell_polygon(i)
        self.assertTrue(np.array_equal(ring[0], ring[-1]))
        reg = d.vertices[d.regions[d.point_region[i]]]
        self.assertEqual(len(ring) - 1, len(reg))
        self.assertEqual(sorted(map(tuple, ring[:-1].tolist())), sorted(map(tuple, reg.tolist())))
        # Duplicates share their first occurrence's polygon.
        for a, b in d.duplicates[:20].tolist():
            self.assertTrue(np.array_equal(d.cell_polygon(a), d.cell_polygon(b)))

    def test_small_inputs(self):
        for xy in (np.zeros((0, 2)), np.array([[1.0, 2.0]]), np.array([[0.0, 0], [1, 1]]),
                   np.array([[0.0, 0], [0, 0]])):
            d = voronoid.voronoi(xy, url=self.url)
            self.check_invariants(f"{len(xy)} points", xy, d)
            self.check_against_json(f"{len(xy)} points", xy, d, {})

    def test_errors(self):
        bad = np.array([[0.0, 0.0], [1.0, math.nan], [2.0, 2.0]])
        with self.assertRaises(voronoid.VoronoidError) as e:
            voronoid.voronoi(bad, url=self.url)
        self.assertEqual(e.exception.status, 422)
        self.assertEqual(e.exception.pointer, "/points/1/1")
        self.assertIn("not a finite number", e.exception.detail)
        with self.assertRaises(voronoid.VoronoidError) as e:
            voronoid.voronoi(bad[[0, 2]], url=self.url, algorithm="quickhull")
        self.assertIn("unknown algorithm", e.exception.detail)
        with self.assertRaises(ValueError):
            voronoid.voronoi(np.zeros((4, 3)), url=self.url)
        with self.assertRaises(voronoid.VoronoidError) as e:
            voronoid.compare(bad[[0, 2]], url=self.url, repeat=0)
        self.assertIn("repeat 0 is out of range", e.exception.detail)

    def test_compare(self):
        xy = self.sets["gaussian"][0]
        c = voronoid.compare(xy, url=self.url, repeat=3)
        self.assertTrue(c["agree"], c["disagreement"])
        self.assertEqual(c["repeat"], 3)
        self.assertEqual(c["n_input"], len(xy))
        for a in c["algorithms"]:
            self.assertEqual(len(a["runs_ms"]), 3)
            s = a["spread"]["compute_ms"]
            self.assertLessEqual(s["min"], s["median"])
            self.assertLessEqual(s["median"], s["max"])


if __name__ == "__main__":
    unittest.main(verbosity=2)
