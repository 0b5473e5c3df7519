/* decode.js -- the service's answers turned into one diagram record.
 *
 * What it does: reads a JSON diagram (openapi.yaml, Diagram) or the binary
 * layout (BinaryDiagram) into the same plain record of typed arrays, so
 * that everything after it -- drawing, summaries, tests -- has one input
 * whatever the format. Pure functions of their input: no DOM, so they run
 * as well in a worker as on the page.
 *
 * fetchDiagram() fetches an answer and does the same, and the drawing's
 * preparation, in a worker (worker.js), so that a large answer never
 * holds the page.
 *
 * Cost: O(size of the answer); the binary sections are read in place
 * through typed-array views, only the per-input arrays are copied.
 */
import { ALGORITHMS } from './util.js';
import { ServiceError, problemFrom } from './api.js';

/* Both decoders return the same plain record of typed arrays:
 *   algorithm, format ('json' | 'binary'), nInput, nSites, nVertices,
 *   nEdges, nTriangles, timings {name_ms: ...},
 *   xy       Float64Array(2 nInput)  every input point (duplicates too)
 *   dups     [[input, first input], ...]
 *   vxy      Float64Array(2 nVertices) (NaN where a vertex overflowed)
 *   ends     Int32Array(2 nEdges)    vertex index or -1
 *   esites   Int32Array(2 nEdges)    the two sites, as input indices
 *   rayEdge  Int32Array(nRays), rayDir Float64Array(2 nRays)
 *   tri      Uint32Array(3 nTriangles) input indices, or null
 *   clip     {box, start: Uint32Array(nSites + 1), xy: Float64Array} or null
 * The page draws only from this record, so the JSON and the binary
 * answers are drawn by the same code. */

export function unreadable(why) {
    return new ServiceError({ title: 'Unreadable answer', detail: 'The diagram sent by the service ' + why + '.' });
}

/* The JSON document (openapi.yaml, Diagram): "sites" per input point,
 * site numbers are input indices, "clipped": {bounds, edges, cells}. */
export function fromJson(res) {
    if (!res || typeof res !== 'object') throw unreadable('is not a JSON object');
    const sites = Array.isArray(res.sites) ? res.sites : [];
    const verts = Array.isArray(res.vertices) ? res.vertices : [];
    const edges = Array.isArray(res.edges) ? res.edges : [];
    const nIn = sites.length, nv = verts.length, ne = edges.length;
    const xy = new Float64Array(2 * nIn);
    for (let i = 0; i < nIn; i++) {
        const p = sites[i];
        xy[2 * i] = p ? +p[0] : NaN;
        xy[2 * i + 1] = p ? +p[1] : NaN;
    }
    const vxy = new Float64Array(2 * nv);
    for (let i = 0; i < nv; i++) {
        const p = verts[i];
        vxy[2 * i] = p && p[0] != null ? +p[0] : NaN;
        vxy[2 * i + 1] = p && p[1] != null ? +p[1] : NaN;
    }
    const ends = new Int32Array(2 * ne), esites = new Int32Array(2 * ne);
    const rayEdge = [], rayDir = [];
    for (let e = 0; e < ne; e++) {
        const ed = edges[e];
        const en = ed && Array.isArray(ed.ends) ? ed.ends : [null, null];
        const st = ed && Array.isArray(ed.sites) ? ed.sites : [0, 0];
        ends[2 * e] = en[0] == null ? -1 : en[0];
        ends[2 * e + 1] = en[1] == null ? -1 : en[1];
        esites[2 * e] = st[0];
        esites[2 * e + 1] = st[1];
        if (Array.isArray(ed.ray)) {
            rayEdge.push(e);
            rayDir.push(+ed.ray[0], +ed.ray[1]);
        }
    }
    let tri = null;
    if (Array.isArray(res.triangles)) {
        tri = new Uint32Array(3 * res.triangles.length);
        res.triangles.forEach((t, i) => tri.set(t, 3 * i));
    }
    let clip = null;
    const c = res.clipped;
    if (c && typeof c === 'object' && Array.isArray(c.cells)) {
        const start = new Uint32Array(c.cells.length + 1);
        let n = 0;
        c.cells.forEach((poly, i) => {
            n += Array.isArray(poly) ? poly.length : 0;
            start[i + 1] = n;
        });
        const cxy = new Float64Array(2 * n);
        c.cells.forEach((poly, i) => {
            if (!Array.isArray(poly)) return;
            poly.forEach((q, j) => {
                cxy[2 * (start[i] + j)] = q[0];
                cxy[2 * (start[i] + j) + 1] = q[1];
            });
        });
        clip = { box: c.bounds || c.box || null, start: start, xy: cxy };
    }
    return {
        format: 'json',
        algorithm: res.algorithm,
        nInput: res.n_input != null ? res.n_input : nIn,
        nSites: res.n_sites != null ? res.n_sites : nIn,
        nVertices: res.n_vertices != null ? res.n_vertices : nv,
        nEdges: res.n_edges != null ? res.n_edges : ne,
        nTriangles: tri ? tri.length / 3 : 0,
        timings: res.timings || null,
        xy: xy,
        dups: Array.isArray(res.duplicates) ? res.duplicates : [],
        vxy: vxy, ends: ends, esites: esites,
        rayEdge: Int32Array.from(rayEdge), rayDir: Float64Array.from(rayDir),
        tri: tri, clip: clip,
    };
}

/* The binary answer (openapi.yaml, BinaryDiagram): a 48-byte header
 * ("VORB", version 1, algorithm, flags, counts) and little-endian
 * sections, each padded to 8 bytes, read in place through typed array
 * views (the page asks for it only on little-endian hosts). */
export function fromBinary(buf) {
    if (buf.byteLength < 48) throw unreadable('is too short to be binary');
    const magic = String.fromCharCode.apply(null, new Uint8Array(buf, 0, 4));
    const h = new Uint32Array(buf, 0, 12);
    if (magic !== 'VORB' || h[1] !== 1) throw unreadable('is not version 1 of the binary format');
    const flags = h[3], nIn = h[4], ns = h[5], nv = h[6], ne = h[7], nr = h[8], nt = h[9], ncp = h[10];
    let off = 48;
    const take = (Type, count) => {
        const bytes = count * Type.BYTES_PER_ELEMENT;
        if (off + bytes > buf.byteLength) throw unreadable('ends early');
        const a = new Type(buf, off, count);
        off = (off + bytes + 7) & ~7;
        return a;
    };
    const siteInput = take(Uint32Array, ns);
    const inputSite = take(Uint32Array, nIn);
    const sxy = take(Float64Array, 2 * ns);
    const vxy = take(Float64Array, 2 * nv);
    const edges = take(Int32Array, 4 * ne);
    const rayEdge = take(Int32Array, nr);
    const rayDir = take(Float64Array, 2 * nr);
    take(Uint32Array, ns + 1);      /* cell_start */
    take(Uint32Array, 2 * ne);      /* cell_edges */
    take(Uint8Array, ns);           /* cell_bounded */
    const tri = flags & 1 ? take(Uint32Array, 3 * nt) : null;
    let clip = null;
    if (flags & 2) {
        const box = Array.from(take(Float64Array, 4));
        take(Float64Array, 4 * ne); /* clipped edges */
        clip = { box: box, start: take(Uint32Array, ns + 1), xy: take(Float64Array, 2 * ncp) };
    }
    const tv = take(Float64Array, 7);
    const names = ['queue', 'parse', 'prepare', 'compute', 'clip', 'serialize', 'total'];
    const timings = {};
    names.forEach((n, i) => { timings[n + '_ms'] = tv[i]; });
    const xy = new Float64Array(2 * nIn);
    const dups = [];
    for (let i = 0; i < nIn; i++) {
        const site = inputSite[i];
        xy[2 * i] = sxy[2 * site];
        xy[2 * i + 1] = sxy[2 * site + 1];
        if (siteInput[site] !== i) dups.push([i, siteInput[site]]);
    }
    const ends = new Int32Array(2 * ne), esites = new Int32Array(2 * ne);
    for (let e = 0; e < ne; e++) {
        esites[2 * e] = edges[4 * e];
        esites[2 * e + 1] = edges[4 * e + 1];
        ends[2 * e] = edges[4 * e + 2];
        ends[2 * e + 1] = edges[4 * e + 3];
    }
    return {
        format: 'binary',
        algorithm: ALGORITHMS[h[2]] || String(h[2]),
        nInput: nIn, nSites: ns, nVertices: nv, nEdges: ne, nTriangles: tri ? nt : 0,
        timings: timings, xy: xy, dups: dups, vxy: vxy, ends: ends, esites: esites,
        rayEdge: rayEdge, rayDir: rayDir, tri: tri, clip: clip,
    };
}

/* What window.voronoid.lastResult shows of a diagram: counts, not the
 * arrays (the diagram itself is in window.voronoid.diagram). */
export function summary(D) {
    return {
        format: D.format,
        algorithm: D.algorithm,
        n_input: D.nInput,
        n_sites: D.nSites,
        n_vertices: D.nVertices,
        n_edges: D.nEdges,
        n_rays: D.rayEdge.length,
        n_triangles: D.tri ? D.nTriangles : null,
        duplicates: D.dups.slice(0, 1000),
        n_duplicates: D.dups.length,
        clipped: D.clip ? { bounds: D.clip.box, cells: D.clip.start.length - 1 } : null,
        timings: D.timings,
    };
}

/* A diagram record of points alone (no answer yet). */
export function pointsOnly(points) {
    const xy = new Float64Array(2 * points.length);
    points.forEach((p, i) => { xy[2 * i] = p[0]; xy[2 * i + 1] = p[1]; });
    return {
        format: 'none', algorithm: null, nInput: points.length, nSites: points.length,
        nVertices: 0, nEdges: 0, nTriangles: 0, timings: null, xy: xy, dups: [],
        vxy: new Float64Array(0), ends: new Int32Array(0), esites: new Int32Array(0),
        rayEdge: new Int32Array(0), rayDir: new Float64Array(0), tri: null, clip: null,
    };
}

/* ---- off the page's thread ------------------------------------------------ */

let worker = null;
let ready = null;         /* resolves to whether the worker runs */
let nextId = 1;
const pending = new Map();

/* Starts the worker once; the promise tells whether it loaded (it posts
 * 'ready' after its imports). Until then nothing is handed over, so a
 * worker that cannot start (no module workers, a policy against it)
 * costs only the fallback of decoding here. */
function workerReady() {
    if (ready) return ready;
    ready = new Promise((resolve) => {
        let w;
        try {
            w = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
        } catch (e) {
            resolve(false);
            return;
        }
        w.onmessage = (ev) => {
            const m = ev.data;
            if (m === 'ready') {
                worker = w;
                resolve(true);
                return;
            }
            const p = pending.get(m.id);
            if (!p) return;
            pending.delete(m.id);
            if (m.problem) p.reject(new ServiceError(m.problem));
            else if (m.message) p.reject(new Error(m.message));
            else if (m.unreachable) p.reject(unreachable({ message: m.unreachable }));
            else p.resolve({ D: m.D, G: m.G, serverTiming: m.serverTiming, ms: m.ms });
        };
        w.onerror = (ev) => {
            ev.preventDefault();
            if (worker) {
                /* failed while working: what waits fails with it */
                for (const p of pending.values()) p.reject(new Error('the decoding worker failed: ' + (ev.message || 'error')));
                pending.clear();
            }
            worker = null;
            ready = Promise.resolve(false);
            w.terminate();
            resolve(false);
        };
    });
    return ready;
}

/* The diagram record of a fetched answer, binary or JSON; a ServiceError
 * for a problem answer, an unreadable one for a body that is neither.
 * Shared by the page and the worker. */
export async function readAnswer(resp, binary) {
    if (!resp.ok) throw problemFrom(resp, await resp.text());
    if (binary) return fromBinary(await resp.arrayBuffer());
    const text = await resp.text();
    let res;
    try {
        res = JSON.parse(text);
    } catch (e) {
        throw unreadable('is not JSON the page can parse (' + e.message + ')');
    }
    return fromJson(res);
}

/* Fetches a diagram, decodes it and prepares it for drawing with
 * prepareFn (geometry prepare): all in the worker (worker.js) when one can
 * run, so that not even the assembly of a body of hundreds of megabytes
 * happens on the page's thread; else here. req is api.js buildRequest's
 * {url, init} (init without its signal); signal aborts it. Resolves to
 * {D, G, serverTiming, ms, where: 'worker' | 'page'}; rejects with a
 * ServiceError for a problem answer, an AbortError when aborted. */
export async function fetchDiagram(req, signal, binary, nColours, prepareFn) {
    if (signal && signal.aborted) throw new DOMException('aborted', 'AbortError');
    if (!(await workerReady()) || !worker) {
        const t0 = performance.now();
        const init = Object.assign({}, req.init, { signal: signal });
        let resp;
        try {
            resp = await fetch(req.url, init);
        } catch (e) {
            if (e.name === 'AbortError') throw e;
            throw unreachable(e);
        }
        const D = await readAnswer(resp, binary);
        return {
            D: D, G: prepareFn(D, nColours), serverTiming: resp.headers.get('server-timing'),
            ms: performance.now() - t0, where: 'page',
        };
    }
    const id = nextId++;
    const out = await new Promise((resolve, reject) => {
        pending.set(id, { resolve: resolve, reject: reject });
        if (signal) {
            signal.addEventListener('abort', () => {
                if (!pending.has(id)) return;
                pending.delete(id);
                worker.postMessage({ abort: id });
                reject(new DOMException('aborted', 'AbortError'));
            }, { once: true });
        }
        worker.postMessage({ id: id, url: req.url, init: req.init, binary: binary, nColours: nColours });
    });
    out.where = 'worker';
    return out;
}

/* The ServiceError for a request that got no answer at all. */
export function unreachable(e) {
    return new ServiceError({
        title: 'Cannot reach the service',
        detail: 'The request did not get an answer (' + e.message + '). Is voronoid running?',
    });
}
