"""voronoid.py -- a Python client for the voronoid service, at full speed.

Sends a numpy array of points to a running voronoid as little-endian
float64 pairs (POST /voronoi, Content-Type application/octet-stream) and
asks for the binary answer (format=binary), which numpy reads in place:
no JSON is encoded or decoded, so Python's time goes to the transfer, not
to parsing. The result is named
like scipy.spatial.Voronoi, so code written for scipy mostly runs
unchanged::

    import numpy as np, voronoid
    vor = voronoid.voronoi(np.random.default_rng(1).random((100000, 2)))
    print(vor.vertices.shape, vor.ridge_points[:3], vor.timings["compute_ms"])

Standard library and numpy only; one module, nothing to build.

What the Diagram holds (scipy's names first; index arrays are int32, as
scipy's, and read-only views into the answer):

- ``points``        (n, 2) float64, the points as sent.
- ``vertices``      (nv, 2) float64, one per circle through three or more
                    points: the centre of four or more cocircular points
                    is ONE vertex (qhull may give several nearby ones).
- ``ridge_points``  (nr, 2) int, the two points each ridge (Voronoi edge)
                    separates, as indices into ``points``; a duplicated
                    point is represented by its first occurrence.
- ``ridge_vertices`` (nr, 2) int, the ridge's two ends as indices into
                    ``vertices``, -1 for an end at infinity (a ray has
                    [v, -1]; a line, when all points are collinear, has
                    [-1, -1]).
- ``ridge_rays``    (nr, 2) float64, our addition: the exact unit direction
                    of every unbounded ridge (outwards from its vertex for
                    a ray; for a line, the direction with ridge_points[k, 0]
                    on its left, through the midpoint of its two points),
                    NaN for a bounded ridge. scipy leaves this to
                    voronoi_plot_2d, which guesses a far point.
- ``regions``       list of lists of vertex indices, one region per
                    distinct point, counter-clockwise; an unbounded region
                    ends with -1 (where it opens to infinity), and a region
                    without vertices (collinear points) is [-1]. Unlike
                    scipy there is no empty region. ``region_indptr`` and
                    ``region_vertices`` hold the same as flat arrays (region
                    r is region_vertices[region_indptr[r]:region_indptr[r+1]])
                    and are the fast way for large diagrams. Both are
                    derived on first use, as are ``ridge_rays`` and
                    ``duplicates``: a caller that only wants the ridges
                    does not pay for them.
- ``point_region``  (n,) int, the region of every point (a duplicate has
                    its first occurrence's region).
- ``region_point``  (n_sites,) int, the first-occurrence index of each
                    region's point; ``region_bounded`` (n_sites,) bool.
- ``duplicates``    (k, 2) int, [index, index of its first occurrence] for
                    every repeated point.
- ``triangles``     (nt, 3) int, the Delaunay triangles counter-clockwise
                    (scipy.spatial.Delaunay(points).simplices), with
                    ``triangles=True``; else None.
- with ``bounds`` (xmin, ymin, xmax, ymax): ``clip_box``, ``clip_edges``
                    (nr, 4) the part of every ridge inside the box (NaN
                    when it misses it), and ``cell_polygon(i)``: the region
                    of point i clipped to the box, a closed ring
                    counter-clockwise (d3-delaunay's voronoi.cellPolygon).
- ``timings``       the service's milliseconds (queue, parse, prepare,
                    compute, clip, serialize, total), a dict.
- ``counts``        the algorithm's operation counts (openapi.yaml, Counts),
                    a dict of the counts that apply to it.
- ``algorithm``, ``n_input``, ``n_sites``.

``compare(points, repeat=...)`` runs all three algorithms on the service
(POST /compare) and returns its JSON answer as a dict. Errors of the
service raise VoronoidError with its problem document (status, detail,
pointer).
"""

import functools
import json
import struct
import urllib.error
import urllib.parse
import urllib.request

import numpy as np

__all__ = ["Diagram", "VoronoidError", "voronoi", "compare", "DEFAULT_URL"]

DEFAULT_URL = "http://127.0.0.1:8080"

_ALGORITHMS = ("fortune", "bowyer-watson", "flip")
_TIMINGS = ("queue_ms", "parse_ms", "prepare_ms", "compute_ms", "clip_ms",
            "serialize_ms", "total_ms")
_HEADER = struct.Struct("<4s11I")  # "VORB", version, ..., n_counts: 48 bytes
# The operation counts of the binary answer, in its order (openapi.yaml,
# BinaryDiagram), and the algorithms each applies to (0 fortune,
# 1 bowyer-watson, 2 flip).
_COUNTS = (("orient2d", (1, 2)), ("incircle", (1, 2)), ("exact", (0, 1, 2)),
           ("order_rounds", (1, 2)), ("order_refinements", (1, 2)),
           ("order_keys", (1, 2)), ("walk_steps", (1, 2)),
           ("triangles_created", (1, 2)), ("cavity_triangles", (1,)),
           ("flips", (2,)), ("site_events", (0,)), ("circle_events", (0,)),
           ("false_alarms", (0,)), ("breakpoint_hits", (0,)),
           ("beach_max", (0,)), ("breakpoint_tests", (0,)),
           ("breakpoint_exact", (0,)), ("circle_tops", (0,)),
           ("circle_top_exact", (0,)), ("event_compares", (0,)),
           ("event_exact", (0,)))


class VoronoidError(Exception):
    """An answer of the service that is not a diagram: ``status`` (HTTP),
    ``problem`` (the RFC 9457 document as a dict, possibly empty),
    ``detail`` and ``pointer`` (JSON pointer of the offending value, or
    None)."""

    def __init__(self, status, problem):
        self.status = status
        self.problem = problem or {}
        self.detail = self.problem.get("detail", "")
        self.pointer = self.problem.get("pointer")
        where = f" (at {self.pointer})" if self.pointer else ""
        super().__init__(f"voronoid answered {status}: {self.detail}{where}")


def _as_points(points):
    """(n, 2) C-contiguous little-endian float64 copy or view of points."""
    xy = np.ascontiguousarray(points, dtype="<f8")
    if xy.ndim != 2 or xy.shape[1] != 2:
        raise ValueError(f"points must be an (n, 2) array, got shape {xy.shape}")
    return xy


def _post(url, path, query, body, accept, timeout):
    q = urllib.parse.urlencode({k: v for k, v in query.items() if v is not None})
    req = urllib.request.Request(
        url.rstrip("/") + path + ("?" + q if q else ""), data=body,
        method="POST",
        headers={"Content-Type": "application/octet-stream", "Accept": accept})
    try:
        with urllib.request.urlopen(req, timeout=timeout) as resp:
            return resp.read()
    except urllib.error.HTTPError as e:
        raw = e.read()
        try:
            problem = json.loads(raw)
        except ValueError:
            problem = {"detail": raw.decode("utf-8", "replace").strip()}
        raise VoronoidError(e.code, problem) from None


def _bounds_param(bounds):
    if bounds is None:
        return None
    b = [float(v) for v in bounds]
    if len(b) != 4:
        raise ValueError("bounds must be (xmin, ymin, xmax, ymax)")
    return ",".join(repr(v) for v in b)


class Diagram:
    """The Voronoi diagram of ``points`` as the service computed it (see the
    module's documentation for every attribute). The arrays read from the
    answer are read-only views into its bytes (int32 indices, as scipy's);
    ``regions``, ``ridge_rays``, ``duplicates`` and the flat region arrays
    are derived on first use, so a caller that wants only ridges does not
    pay for them."""

    def __init__(self, points, answer):
        self.points = points
        self._parse(memoryview(answer))

    def _parse(self, buf):
        (magic, version, algorithm, flags, n_input, n_sites, n_vertices,
         n_edges, n_rays, n_tri, n_clip, n_counts) = _HEADER.unpack_from(buf, 0)
        if magic != b"VORB" or version != 1:
            raise ValueError(f"not a version 1 voronoid binary answer: {bytes(magic)!r}")
        pos = _HEADER.size

        def take(dtype, count):
            nonlocal pos
            a = np.frombuffer(buf, dtype=dtype, count=count, offset=pos)
            pos = (pos + a.nbytes + 7) // 8 * 8  # every section is padded to 8
            return a

        self.algorithm = _ALGORITHMS[algorithm]
        self.n_input, self.n_sites = n_input, n_sites
        # Indices are below 2^30 (the service's limit): u32 read as i32.
        self.region_point = take("<i4", n_sites)
        self.point_region = take("<i4", n_input)
        take("<f8", 2 * n_sites)  # the sites themselves: points[region_point]
        self.vertices = take("<f8", 2 * n_vertices).reshape(n_vertices, 2)
        edges = take("<i4", 4 * n_edges).reshape(n_edges, 4)
        self._ray_edge = take("<i4", n_rays)
        self._ray_dir = take("<f8", 2 * n_rays).reshape(n_rays, 2)
        self._cell_start = take("<i4", n_sites + 1)
        self._cell_edges = take("<i4", 2 * n_edges)
        self.region_bounded = take("u1", n_sites).view(bool)
        self.triangles = None
        if flags & 1:
            self.triangles = take("<i4", 3 * n_tri).reshape(n_tri, 3)
        self.clip_box = self.clip_edges = None
        self._clip_start = self._clip_xy = None
        if flags & 2:
            self.clip_box = take("<f8", 4)
            self.clip_edges = take("<f8", 4 * n_edges).reshape(n_edges, 4)
            self._clip_start = take("<i4", n_sites + 1)
            self._clip_xy = take("<f8", 2 * n_clip).reshape(n_clip, 2)
        tv = take("<f8", 7)
        self.counts = {}
        if flags & 8:
            cv = take("<u8", n_counts).tolist()
            self.counts = {name: v for (name, algos), v in zip(_COUNTS, cv)
                           if algorithm in algos}
        if pos != len(buf):
            raise ValueError(f"answer of {len(buf)} bytes, layout ends at {pos}")
        self.timings = dict(zip(_TIMINGS, tv.tolist()))
        self.ridge_points = edges[:, :2]
        self.ridge_vertices = edges[:, 2:]

    @functools.cached_property
    def ridge_rays(self):
        """(nr, 2): the unit direction of every unbounded ridge, NaN for the
        others."""
        rays = np.full((len(self.ridge_points), 2), np.nan)
        rays[self._ray_edge] = self._ray_dir
        return rays

    @functools.cached_property
    def duplicates(self):
        """(k, 2): [index, index of its first occurrence] of every repeated
        point."""
        first = self.region_point[self.point_region]
        dup = np.flatnonzero(first != np.arange(self.n_input))
        return np.stack([dup, first[dup]], axis=1)

    @functools.cached_property
    def _region_arrays(self):
        """Regions from the cells' counter-clockwise edge lists: between two
        consecutive edges of a cell lies the vertex they share; an unbounded
        cell's last pair (the edge to infinity, then the one coming back)
        shares none and gives -1. Vectorised: O(edges)."""
        n, start, cell_edges = self.n_sites, self._cell_start, self._cell_edges
        if len(self.vertices) == 0:  # at most two points, or all collinear
            return np.arange(n + 1, dtype=np.int32), np.full(n, -1, dtype=np.int32)
        last = start[1:] - 1
        nxt = np.arange(1, len(cell_edges) + 1, dtype=np.int32)
        nxt[last] = start[:-1]  # wrap around each cell
        e0, e1 = self.ridge_vertices[:, 0], self.ridge_vertices[:, 1]
        a, b = e0[cell_edges], e1[cell_edges]
        following = cell_edges[nxt]
        c, d = e0[following], e1[following]
        shared = np.where((a == c) | (a == d), a, b)
        open_cells = ~self.region_bounded & (start[1:] > start[:-1])
        shared[last[open_cells]] = -1
        return start, shared

    @property
    def region_indptr(self):
        """(n_sites + 1,): region r is region_vertices[indptr[r]:indptr[r+1]]."""
        return self._region_arrays[0]

    @property
    def region_vertices(self):
        """All regions' vertex indices, one after the other (-1: open)."""
        return self._region_arrays[1]

    @functools.cached_property
    def regions(self):
        """One list of vertex indices per region, as scipy's ``regions``."""
        ptr, flat = self.region_indptr.tolist(), self.region_vertices.tolist()
        return [flat[ptr[r]:ptr[r + 1]] for r in range(self.n_sites)]

    def cell_polygon(self, i):
        """The region of point i clipped to the box of ``bounds`` (or the
        default box of ``clipped=True``): a closed counter-clockwise ring
        (k, 2), its first point repeated last; empty when the region misses
        the box."""
        if self._clip_start is None:
            raise ValueError("no clipped cells: pass bounds= (or clipped=True)")
        r = self.point_region[i]
        return self._clip_xy[self._clip_start[r]:self._clip_start[r + 1]]

    def __repr__(self):
        return (f"<voronoid.Diagram {self.algorithm}: {self.n_input} points, "
                f"{self.n_sites} sites, {len(self.vertices)} vertices, "
                f"{len(self.ridge_points)} ridges>")


def voronoi(points, url=DEFAULT_URL, algorithm="fortune", bounds=None,
            triangles=False, clipped=False, timeout=600):
    """The Voronoi diagram of points ((n, 2) array-like of finite numbers)
    computed by the voronoid at url with algorithm ("fortune",
    "bowyer-watson" or "flip"). bounds=(xmin, ymin, xmax, ymax) also clips
    every cell to that box (clipped=True: to the service's default box, the
    points' bounding box grown by 10%); triangles=True also returns the
    Delaunay triangles. Raises VoronoidError when the service refuses (for
    example 422 for a NaN, naming /points/i/k), ValueError for a wrong
    shape."""
    xy = _as_points(points)
    parts = "vertices,edges,cells"
    if triangles:
        parts += ",triangles"
    if clipped or bounds is not None:
        parts += ",clipped"
    answer = _post(url, "/voronoi",
                   {"format": "binary", "algorithm": algorithm,
                    "bounds": _bounds_param(bounds), "include": parts},
                   xy.tobytes(), "application/octet-stream", timeout)
    return Diagram(xy, answer)


def compare(points, url=DEFAULT_URL, repeat=None, bounds=None, timeout=600):
    """Runs the three algorithms on points at the service (POST /compare):
    each `repeat` times (1..50; the service's default when None) in
    rotating order. Returns the answer as a dict: "agree", and per
    algorithm its median "timings", "spread" and "runs_ms"."""
    xy = _as_points(points)
    answer = _post(url, "/compare",
                   {"repeat": repeat, "bounds": _bounds_param(bounds)},
                   xy.tobytes(), "application/json", timeout)
    return json.loads(answer)
