/* replay.js -- a trace of the service (POST voronoi with trace=true)
 * replayed step by step: the state of the algorithm after any step, and
 * the diagram the last step ends in.
 *
 * What it does: new Replay(answer) takes a traced JSON answer
 * (openapi.yaml, Trace: site numbers are input indices, -1 the vertex at
 * infinity). prepare() walks the steps once, as a generator that yields
 * every few hundred steps so that the page can run it in slices; on the
 * way it records the running counts of every step, the things each step
 * adds for good (Fortune's traced edge pieces, vertices and triangles)
 * and a snapshot of the state every SNAP steps; at the end it builds the
 * diagram of the final triangulation (diagramOf). seek(f) then puts the
 * state after step f in place: from the nearest snapshot at or before f
 * (or from where it is, when that is closer), replaying at most SNAP - 1
 * steps, so stepping back costs no more than stepping forward.
 *
 * State after a step:
 *   Bowyer-Watson and flip: the triangulation, ghosts included, as a map
 *     of directed edges (u, v) -> the third vertex w of the triangle
 *     (u, v, w); next, how many sites of the order are in.
 *   Fortune: the beach line (the arcs' sites, left to right), for each
 *     breakpoint the point where its edge began (or -1: a first-row edge,
 *     which comes up from y = -infinity), the pending circle events (the
 *     schedule steps that made them), the sweep line's y, next (how many
 *     sites of the order were reached), and how much of the append-only
 *     logs (pieces, points, triangles) the steps so far have written.
 *
 * diagramOf(xy, triangles) is the canonical diagram of a Delaunay
 * triangulation, as core/diagram.c builds it: triangles that share an
 * edge and a circle (exact in-circle test) are one vertex, whose three
 * smallest sites give its place in the order and its coordinates
 * (vor_circumcenter of those three, exact.js); an edge per pair of sites
 * whose triangles are different vertices, a ray (vor_bisector_dir) per
 * hull edge; edges by (a, b). It is the JSON answer's shape, so the last
 * frame can be compared with the service's diagram directly.
 *
 * Invariants: pure computation, no DOM; seek() needs f < prepared. Cost:
 * prepare is O(steps x beach line) for Fortune (a splice per event) and
 * O(steps) map operations for the others; the snapshots hold the whole
 * triangulation (incremental) or beach line and events (Fortune) every
 * SNAP steps: for 2,000 sites a few megabytes at most.
 */
import { incircle, circumcenter, bisectorDir } from './exact.js';

/* Steps between snapshots. */
export const SNAP = 48;
/* Steps prepared between yields. */
const PREPARE_BLOCK = 400;

/* "a,b,c" of a triple, the key of a Fortune circle event. */
function tripleKey(t) {
    return t[0] + ',' + t[1] + ',' + t[2];
}

export class Replay {
    /* answer: the parsed JSON answer with sites, trace and counts. */
    constructor(answer) {
        this.algorithm = answer.algorithm;
        this.fortune = this.algorithm === 'fortune';
        const sites = Array.isArray(answer.sites) ? answer.sites : [];
        this.nInput = sites.length;
        this.xy = sites.map((p) => [+p[0], +p[1]]);
        this.steps = answer.trace && Array.isArray(answer.trace.steps) ? answer.trace.steps : [];
        this.n = this.steps.length;
        this.finalCounts = answer.counts || null;
        /* count names: the first step carries every count of the algorithm */
        const first = this.n ? this.steps[0].counts || {} : {};
        this.countNames = Object.keys(Object.assign({}, first, this.finalCounts || {}));
        this.counts = new Float64Array(this.n * this.countNames.length);
        this.order = this.n && this.steps[0].kind === 'order' ? this.steps[0].sites : [];
        /* Fortune's logs, written once by prepare(): points (x, y pairs:
         * where edges start and end), pieces (start point or -1, end
         * point, the two sites), triangles (3 sites), and how long each
         * was after every step */
        this.points = [];
        this.pieces = [];
        this.tris = [];
        this.logEnd = new Int32Array(3 * this.n);
        this.snaps = [];
        this.prepared = 0;
        this.final = null;
        this.M = this.nInput + 1;
        this.state = null;
        this.at = -1;
    }

    /* ---- state ---------------------------------------------------------- */

    emptyState() {
        if (this.fortune) {
            return { beach: [], starts: [], pending: new Map(), sweep: -Infinity, next: 0, nPoints: 0, nPieces: 0, nTris: 0 };
        }
        return { edges: new Map(), next: 0 };
    }

    /* the key of directed edge (u, v); -1 is the vertex at infinity */
    ek(u, v) {
        return (u + 1) * this.M + (v + 1);
    }

    addTri(S, a, b, c) {
        S.edges.set(this.ek(a, b), c);
        S.edges.set(this.ek(b, c), a);
        S.edges.set(this.ek(c, a), b);
    }

    removeTri(S, a, b, c) {
        S.edges.delete(this.ek(a, b));
        S.edges.delete(this.ek(b, c));
        S.edges.delete(this.ek(c, a));
    }

    /* Every triangle of an incremental state once, as (u, v, w) with u
     * the smallest number (-1 for a ghost): fn(u, v, w). */
    eachTriangle(S, fn) {
        const M = this.M;
        for (const [k, w] of S.edges) {
            const u = Math.floor(k / M) - 1, v = (k % M) - 1;
            if (u < v && u < w) fn(u, v, w);
        }
    }

    snapshot(S) {
        if (this.fortune) {
            return {
                beach: Int32Array.from(S.beach), starts: Int32Array.from(S.starts),
                pending: Int32Array.from(S.pending.values()), sweep: S.sweep, next: S.next,
            };
        }
        const t = [];
        this.eachTriangle(S, (u, v, w) => t.push(u, v, w));
        return { tris: Int32Array.from(t), next: S.next };
    }

    restore(snap) {
        const S = this.emptyState();
        S.next = snap.next;
        if (this.fortune) {
            S.beach = Array.from(snap.beach);
            S.starts = Array.from(snap.starts);
            for (const k of snap.pending) S.pending.set(tripleKey(this.steps[k].arcs), k);
            S.sweep = snap.sweep;
        } else {
            const t = snap.tris;
            for (let i = 0; i < t.length; i += 3) this.addTri(S, t[i], t[i + 1], t[i + 2]);
        }
        return S;
    }

    /* ---- one step --------------------------------------------------------- */

    /* Applies step k to S; rec: write the logs (prepare's one pass). */
    apply(S, k, rec) {
        const st = this.steps[k];
        if (this.fortune) this.applyFortune(S, k, st, rec);
        else this.applyIncremental(S, st);
        if (!this.fortune) return;
        if (rec) {
            this.logEnd[3 * k] = this.points.length / 2;
            this.logEnd[3 * k + 1] = this.pieces.length / 4;
            this.logEnd[3 * k + 2] = this.tris.length / 3;
        }
        this.logsAfter(S, k);
    }

    /* Fortune: the logs as step k left them. */
    logsAfter(S, k) {
        S.nPoints = this.logEnd[3 * k];
        S.nPieces = this.logEnd[3 * k + 1];
        S.nTris = this.logEnd[3 * k + 2];
    }

    applyIncremental(S, st) {
        switch (st.kind) {
        case 'begin': {
            const [a, b, c] = st.triangle;
            this.addTri(S, a, b, c);
            this.addTri(S, b, a, -1);
            this.addTri(S, c, b, -1);
            this.addTri(S, a, c, -1);
            S.next = 3;
            break;
        }
        case 'insert':
            for (const t of st.cavity) this.removeTri(S, t[0], t[1], t[2]);
            for (const t of st.star) this.addTri(S, t[0], t[1], t[2]);
            S.next++;
            break;
        case 'flip': {
            const [a, b, p] = st.circle, d = st.added[1];
            this.removeTri(S, a, b, p);
            this.removeTri(S, b, a, d);
            this.addTri(S, a, d, p);
            this.addTri(S, d, b, p);
            break;
        }
        default:
            break;
        }
    }

    /* A point of the log: index i of the step's new points (in the order
     * the step writes them), written when rec. */
    point(S, k, i, x, y, rec) {
        const base = k > 0 ? this.logEnd[3 * (k - 1)] : 0;
        if (rec) this.points.push(x, y);
        return base + i;
    }

    applyFortune(S, k, st, rec) {
        const xy = this.xy;
        switch (st.kind) {
        case 'begin':
            S.beach = st.beach.slice();
            S.starts = new Array(Math.max(0, S.beach.length - 1)).fill(-1);
            S.sweep = st.y;
            S.next = st.beach.length;
            break;
        case 'site': {
            const p = st.site, at = st.at;
            S.sweep = st.y;
            S.next++;
            if (st.breakpoint) {
                /* below a breakpoint: its edge ends at the new vertex, two
                 * new ones start there */
                const v = st.vertex || [NaN, NaN];
                const pi = this.point(S, k, 0, v[0] == null ? NaN : v[0], v[1] == null ? NaN : v[1], rec);
                if (rec) {
                    this.pieces.push(S.starts[at - 1], pi, st.breakpoint[0], st.breakpoint[1]);
                    this.tris.push(st.triangle[0], st.triangle[1], st.triangle[2]);
                }
                S.beach.splice(at, 0, p);
                S.starts.splice(at - 1, 1, pi, pi);
            } else {
                /* the new arc splits the arc of q: both new breakpoints
                 * start on q's parabola right above p */
                const q = st.arc;
                const P = xy[p], Q = xy[q];
                /* equally far from Q and from the sweep line y = P[1] */
                const dy = Q[1] - P[1], dx = P[0] - Q[0];
                const y = dy !== 0 ? (Q[1] + P[1]) / 2 + dx * dx / (2 * dy) : -Infinity;
                const pi = this.point(S, k, 0, P[0], y, rec);
                S.beach.splice(at, 0, p, q);
                S.starts.splice(at - 1, 0, pi, pi);
            }
            break;
        }
        case 'circle': {
            const at = st.at, v = st.vertex || [NaN, NaN];
            S.sweep = st.y;
            const pi = this.point(S, k, 0, v[0] == null ? NaN : v[0], v[1] == null ? NaN : v[1], rec);
            if (rec) {
                const b = S.beach;
                this.pieces.push(S.starts[at - 1], pi, b[at - 1], b[at]);
                this.pieces.push(S.starts[at], pi, b[at], b[at + 1]);
                this.tris.push(st.arcs[0], st.arcs[1], st.arcs[2]);
            }
            S.beach.splice(at, 1);
            S.starts.splice(at - 1, 2, pi);
            S.pending.delete(tripleKey(st.arcs));
            break;
        }
        case 'schedule':
            S.pending.set(tripleKey(st.arcs), k);
            break;
        case 'cancel':
            S.pending.delete(tripleKey(st.arcs));
            break;
        default:
            break;
        }
    }

    /* ---- preparing and seeking ------------------------------------------ */

    /* Walks every step once (yielding every PREPARE_BLOCK steps): counts,
     * logs, snapshots; then the final diagram. */
    *prepare() {
        const S = this.emptyState();
        const m = this.countNames.length;
        const running = new Float64Array(m);
        for (let k = 0; k < this.n; k++) {
            const c = this.steps[k].counts || {};
            for (let j = 0; j < m; j++) {
                const v = c[this.countNames[j]];
                if (typeof v === 'number') running[j] = v;
            }
            this.counts.set(running, k * m);
            this.apply(S, k, true);
            if (k % SNAP === 0) this.snaps.push(this.snapshot(S));
            this.prepared = k + 1;
            if ((k + 1) % PREPARE_BLOCK === 0) yield;
        }
        /* the final triangulation and its diagram */
        const t = [];
        if (this.fortune) {
            for (let i = 0; i < this.tris.length; i++) t.push(this.tris[i]);
        } else {
            this.eachTriangle(S, (u, v, w) => { if (u >= 0) t.push(u, v, w); });
        }
        this.finalTriangles = t;
        this.final = yield* diagramOf(this.xy, t);
        this.state = S;
        this.at = this.n - 1;
    }

    /* The state after step f (0 <= f < prepared); the replay's own object,
     * valid until the next seek. */
    seek(f) {
        if (!(f >= 0 && f < this.prepared)) throw new RangeError('step ' + f + ' is not prepared');
        if (f === this.at) return this.state;
        const s = Math.floor(f / SNAP);
        let S = this.state, from = this.at;
        if (!S || f < from || f - from > f - s * SNAP) {
            S = this.restore(this.snaps[s]);
            from = s * SNAP;
            if (this.fortune) this.logsAfter(S, from);
        }
        for (let k = from + 1; k <= f; k++) this.apply(S, k, false);
        this.state = S;
        this.at = f;
        return S;
    }

    /* The running counts after step f: {name: value}. */
    countsAt(f) {
        const m = this.countNames.length, out = {};
        for (let j = 0; j < m; j++) out[this.countNames[j]] = this.counts[f * m + j];
        return out;
    }

    /* The finite triangles of the state after step f, 3 sites each. */
    trianglesAt(f) {
        const S = this.seek(f);
        if (this.fortune) return this.tris.slice(0, 3 * S.nTris);
        const t = [];
        this.eachTriangle(S, (u, v, w) => { if (u >= 0) t.push(u, v, w); });
        return t;
    }
}

/* ---- the diagram of a triangulation ---------------------------------- */

/* Union-find root of i with path halving. */
function root(parent, i) {
    while (parent[i] !== i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

/* The canonical diagram of the Delaunay triangles t (flat, 3 input
 * indices each, counter-clockwise) of the points xy: {vertices: [[x, y]],
 * vertexSites: [[s0, s1, s2]], edges: [{sites: [a, b], ends: [i, j | null],
 * ray?: [dx, dy]}]}, as the service's JSON answer lists them. A
 * generator (yields now and then; returns the diagram). */
export function* diagramOf(xy, t) {
    const nt = t.length / 3;
    const M = xy.length + 1;
    const half = new Map(); /* directed edge a -> b: its triangle */
    for (let i = 0; i < nt; i++) {
        for (let j = 0; j < 3; j++) half.set(t[3 * i + j] * M + t[3 * i + (j + 1) % 3], i);
    }
    /* triangles across an edge on one circle are one vertex */
    const parent = Int32Array.from({ length: nt }, (_, i) => i);
    for (let i = 0; i < nt; i++) {
        for (let j = 0; j < 3; j++) {
            const u = t[3 * i + j], v = t[3 * i + (j + 1) % 3];
            if (u > v) continue;
            const o = half.get(v * M + u);
            if (o === undefined) continue;
            const w = t[3 * o] !== u && t[3 * o] !== v ? t[3 * o] : (t[3 * o + 1] !== u && t[3 * o + 1] !== v ? t[3 * o + 1] : t[3 * o + 2]);
            if (incircle(xy[t[3 * i]], xy[t[3 * i + 1]], xy[t[3 * i + 2]], xy[w]) === 0) {
                const ra = root(parent, i), rb = root(parent, o);
                if (ra !== rb) parent[ra] = rb;
            }
        }
        if ((i + 1) % 2048 === 0) yield;
    }
    /* each vertex: its three smallest sites */
    const groups = new Map();
    for (let i = 0; i < nt; i++) {
        const r = root(parent, i);
        let g = groups.get(r);
        if (!g) groups.set(r, g = []);
        for (let j = 0; j < 3; j++) {
            const s = t[3 * i + j];
            if (!g.includes(s)) g.push(s);
        }
    }
    const verts = [];
    for (const [r, g] of groups) {
        g.sort((a, b) => a - b);
        verts.push({ r: r, s: g.slice(0, 3) });
    }
    verts.sort((p, q) => p.s[0] - q.s[0] || p.s[1] - q.s[1] || p.s[2] - q.s[2]);
    const vid = new Map();
    verts.forEach((v, i) => vid.set(v.r, i));
    yield;
    const vertices = verts.map((v) => circumcenter(xy[v.s[0]], xy[v.s[1]], xy[v.s[2]]));
    /* an edge per pair of sites between two vertices, a ray per hull edge */
    const edges = [];
    for (let i = 0; i < nt; i++) {
        for (let j = 0; j < 3; j++) {
            const u = t[3 * i + j], v = t[3 * i + (j + 1) % 3];
            const o = half.get(v * M + u);
            const a = Math.min(u, v), b = Math.max(u, v);
            if (o === undefined) {
                /* the outside of hull edge u -> v is on its right */
                edges.push({ sites: [a, b], ends: [vid.get(root(parent, i)), null], ray: bisectorDir(xy[v], xy[u]) });
            } else if (u < v) {
                const p = vid.get(root(parent, i)), q = vid.get(root(parent, o));
                if (p !== q) edges.push({ sites: [a, b], ends: [Math.min(p, q), Math.max(p, q)] });
            }
        }
    }
    edges.sort((e, f) => e.sites[0] - f.sites[0] || e.sites[1] - f.sites[1]);
    return { vertices: vertices, vertexSites: verts.map((v) => v.s), edges: edges };
}
