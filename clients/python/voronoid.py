"""voronoid.py -- a Python client for the voronoid service, at full speed.

Sends a numpy array of points to a running voronoid as little-endian
float64 pairs (POST /voronoi, Content-Type application/octet-stream) and
asks for the binary answer (format=binary), which numpy reads in place:
no JSON is encoded or decoded, so a million points cost about as much
time in Python as the service spends computing them. The result is named
like scipy.spatial.Voronoi, so code written for scipy mostly runs
unchanged::

    import numpy as np, voronoid
    vor = voronoid.voronoi(np.random.default_rng(1).random((100000, 2)))
    print(vor.vertices.shape, vor.ridge_points[:3], vor.timings["compute_ms"])

Standard library and numpy only; one module, nothing to build.

What the Diagram holds (scipy's names first; every index is a numpy int):

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
                    and are the fast way for large diagrams; ``regions`` is
                    built from them on first use.
- ``point_region``  (n,) int, the region of every point (a duplicate has
                    its first occurrence's region).
- ``region_point``  (nr,) int, the first-occurrence index of each region's
                    point; ``region_bounded`` (nr,) bool.
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
- ``algorithm``, ``n_input``, ``n_sites``.

``compare(points, repeat=...)`` runs all three algorithms on the service
(POST /compare) and returns its JSON answer as a dict. Errors of the
service raise VoronoidError with its problem document (status, detail,
pointer).
"""

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
_HEADER = struct.Struct("<4s11I")  # "VORB", version, ..., reserved: 48 bytes


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
    module's documentation for every attribute). Arrays are read-only views
    into the answer's bytes, except those derived here."""

    def __init__(self, points, answer):
        self.points = points
        self._parse(memoryview(answer))
        self._regions = None

    def _parse(self, buf):
        (magic, version, algorithm, flags, n_input, n_sites, n_vertices,
         n_edges, n_rays, n_tri, n_clip, _reserved) = _HEADER.unpack_from(buf, 0)
        if magic != b"VORB" or version != 1:
            raise ValueError(f"not a version 1 voronoid binary answer: {bytes(magic)!r}")
        pos = _HEADER.size

        def take(dtype, count, pad=True):
            nonlocal pos
            a = np.frombuffer(buf, dtype=dtype, count=count, offset=pos)
            pos += a.nbytes
            if pad:
                pos = (pos + 7) // 8 * 8
            return a

        self.algorithm = _ALGORITHMS[algorithm]
        self.n_input, self.n_sites = n_input, n_sites
        site_input = take("<u4", n_sites)
        input_site = take("<u4", n_input)
        take("<f8", 2 * n_sites)  # the sites themselves: points[region_point]
        self.vertices = take("<f8", 2 * n_vertices).reshape(n_vertices, 2)
        edges = take("<i4", 4 * n_edges).reshape(n_edges, 4)
        ray_edge = take("<u4", n_rays)
        ray_dir = take("<f8", 2 * n_rays).reshape(n_rays, 2)
        cell_start = take("<u4", n_sites + 1)
        cell_edges = take("<u4", 2 * n_edges)
        bounded = take("u1", n_sites)
        self.triangles = None
        if flags & 1:
            self.triangles = take("<u4", 3 * n_tri).reshape(n_tri, 3).astype(np.intp)
        self.clip_box = self.clip_edges = None
        self._clip_start = self._clip_xy = None
        if flags & 2:
            self.clip_box = take("<f8", 4)
            self.clip_edges = take("<f8", 4 * n_edges).reshape(n_edges, 4)
            self._clip_start = take("<u4", n_sites + 1)
            self._clip_xy = take("<f8", 2 * n_clip).reshape(n_clip, 2)
        tv = take("<f8", 7)
        if pos != len(buf):
            raise ValueError(f"answer of {len(buf)} bytes, layout ends at {pos}")
        self.timings = dict(zip(_TIMINGS, tv.tolist()))

        self.ridge_points = edges[:, :2].astype(np.intp)
        self.ridge_vertices = edges[:, 2:].astype(np.intp)
        rays = np.full((n_edges, 2), np.nan)
        rays[ray_edge] = ray_dir
        self.ridge_rays = rays
        self.region_point = site_input.astype(np.intp)
        self.point_region = input_site.astype(np.intp)
        self.region_bounded = bounded.astype(bool)
        dup = np.flatnonzero(self.region_point[self.point_region] != np.arange(n_input))
        self.duplicates = np.stack([dup, self.region_point[self.point_region[dup]]],
                                   axis=1) if dup.size else np.zeros((0, 2), np.intp)
        self._region_arrays(cell_start.astype(np.intp), cell_edges.astype(np.intp))

    def _region_arrays(self, start, cell_edges):
        """Regions from the cells' counter-clockwise edge lists: between two
        consecutive edges of a cell lies the vertex they share; an unbounded
        cell's last pair (the edge to infinity, then the one coming back)
        shares none and gives -1. Vectorised: O(edges)."""
        n = self.n_sites
        if len(self.vertices) == 0:  # at most two points, or all collinear
            self.region_indptr = np.arange(n + 1, dtype=np.intp)
            self.region_vertices = np.full(n, -1, dtype=np.intp)
            return
        counts = np.diff(start)
        last = start[1:] - 1
        nxt = np.arange(1, len(cell_edges) + 1, dtype=np.intp)
        nxt[last] = start[:-1]  # wrap around each cell
        ends = self.ridge_vertices
        a, b = ends[cell_edges, 0], ends[cell_edges, 1]
        c, d = ends[cell_edges[nxt], 0], ends[cell_edges[nxt], 1]
        shared = np.where((a == c) | (a == d), a, b)
        open_cells = ~self.region_bounded & (counts > 0)
        shared[last[open_cells]] = -1
        self.region_indptr = start
        self.region_vertices = shared

    @property
    def regions(self):
        """One list of vertex indices per region, as scipy's ``regions``."""
        if self._regions is None:
            flat = self.region_vertices.tolist()
            ptr = self.region_indptr.tolist()
            self._regions = [flat[ptr[r]:ptr[r + 1]] for r in range(self.n_sites)]
        return self._regions

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
