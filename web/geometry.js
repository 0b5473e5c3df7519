/* geometry.js -- a diagram record prepared for drawing: model frame,
 * Delaunay edges once each, and a grid index per layer.
 *
 * What it does: prepare(D) maps the sites, vertices, rays and clipped
 * cells of a diagram record (decode.js) into the "model" frame,
 * (world - centre) * k with k = 1 / (extent of the sites), so that what
 * the canvas is given keeps full pixel accuracy for data at 1e9 offsets or
 * 1e-9 scales; lists the Delaunay edges once each (the triangles give
 * every interior edge twice, once per side); colours the cells so that
 * neighbours differ; and buckets every finite item of a layer (Voronoi
 * segment, Delaunay edge, clipped cell) into a uniform grid over the
 * sites' box so that a frame visits only what it shows.
 *
 * Representation: flat typed arrays only, so the result crosses from a
 * worker to the page without copying (transferables()). A grid index is
 * {G, x0, y0, bw, bh, start, order, long}: the items of bucket (gx, gy)
 * are order[start[gy G + gx] .. start[gy G + gx + 1]), a row of buckets
 * is one contiguous run of order, and an item whose box is wider or
 * taller than a bucket or whose centre lies outside the grid is in long
 * (checked on every frame). So a short item whose box meets the view has
 * its centre in a bucket that meets the view grown by one bucket.
 *
 * Invariants: pure functions of their input, no DOM: they run in the
 * decode worker for large answers and on the page for small ones.
 *
 * Cost: O(n) time and memory in the size of the diagram; the Delaunay
 * edges take one pass over the triangles plus a per-vertex adjacency
 * (about 12 bytes per triangle).
 */

/* Items per grid bucket, on average. */
const PER_BUCKET = 32;
const MAX_GRID = 1024;

/* Sets bw, bh and G of a grid over the box b for n items. */
function gridFor(b, n) {
    const G = Math.max(1, Math.min(MAX_GRID, Math.ceil(Math.sqrt(n / PER_BUCKET))));
    const w = Math.max(b[2] - b[0], 1e-300), h = Math.max(b[3] - b[1], 1e-300);
    /* a hair wider than the box, so its far edge falls in the last bucket */
    return { G: G, x0: b[0], y0: b[1], bw: w * (1 + 1e-9) / G, bh: h * (1 + 1e-9) / G };
}

/* The grid index of n items; box(i, out) writes item i's box
 * [x0, y0, x1, y1] into out, NaN for an item never drawn. */
function buildIndex(n, sitesBox, box) {
    const g = gridFor(sitesBox, n);
    const G = g.G, nb = G * G;
    const cell = new Int32Array(n);
    const start = new Uint32Array(nb + 1);
    const b = new Float64Array(4);
    let nLong = 0, nShort = 0;
    for (let i = 0; i < n; i++) {
        box(i, b);
        if (!(b[0] <= b[2] && b[1] <= b[3])) { cell[i] = -2; continue; }
        const gx = Math.floor(((b[0] + b[2]) / 2 - g.x0) / g.bw);
        const gy = Math.floor(((b[1] + b[3]) / 2 - g.y0) / g.bh);
        if (b[2] - b[0] > g.bw || b[3] - b[1] > g.bh || !(gx >= 0 && gy >= 0 && gx < G && gy < G)) {
            cell[i] = -1;
            nLong++;
            continue;
        }
        const c = gy * G + gx;
        cell[i] = c;
        start[c + 1]++;
        nShort++;
    }
    for (let c = 0; c < nb; c++) start[c + 1] += start[c];
    const fill = start.slice(0, nb);
    const order = new Uint32Array(nShort), long = new Uint32Array(nLong);
    let l = 0;
    for (let i = 0; i < n; i++) {
        const c = cell[i];
        if (c >= 0) order[fill[c]++] = i;
        else if (c === -1) long[l++] = i;
    }
    g.start = start;
    g.order = order;
    g.long = long;
    return g;
}

/* The Delaunay edges of the triangles t (3 input indices each, counter-
 * clockwise), once each, as pairs [a, b]: an interior edge is a -> b in
 * one triangle and b -> a in its neighbour, so it is kept where a < b; a
 * hull edge has no reverse and is kept in whichever direction it has. */
export function delaunayEdges(t, nIn) {
    const nt = t.length / 3;
    /* out-edges per vertex: adjacency in compressed rows */
    const start = new Uint32Array(nIn + 1);
    for (let i = 0; i < 3 * nt; i++) start[t[i] + 1]++;
    for (let v = 0; v < nIn; v++) start[v + 1] += start[v];
    const to = new Uint32Array(3 * nt), fill = start.slice(0, nIn);
    for (let j = 0; j < nt; j++) {
        const a = t[3 * j], b = t[3 * j + 1], c = t[3 * j + 2];
        to[fill[a]++] = b;
        to[fill[b]++] = c;
        to[fill[c]++] = a;
    }
    const hasEdge = (u, v) => {
        for (let k = start[u], e = start[u + 1]; k < e; k++) if (to[k] === v) return true;
        return false;
    };
    let m = 0;
    const out = new Uint32Array(2 * 3 * nt);
    for (let u = 0; u < nIn; u++) {
        for (let k = start[u], e = start[u + 1]; k < e; k++) {
            const v = to[k];
            if (u < v || !hasEdge(v, u)) {
                out[2 * m] = u;
                out[2 * m + 1] = v;
                m++;
            }
        }
    }
    return out.slice(0, 2 * m);
}

/* Colours for the cells (one per distinct site, in input order) so that
 * neighbours differ: greedy over the sites, a neighbour being a site
 * across a Voronoi edge. With nc colours greedy can run out at a site of
 * high degree; that site then takes a hashed colour. O(E). */
export function colourCells(esites, dup, nSites, nc) {
    const nIn = dup.length;
    const siteOf = new Int32Array(nIn).fill(-1);
    let j = 0;
    for (let i = 0; i < nIn; i++) if (!dup[i]) siteOf[i] = j++;
    const start = new Uint32Array(nSites + 1), ne = esites.length / 2;
    for (let e = 0; e < ne; e++) {
        const a = siteOf[esites[2 * e]], b = siteOf[esites[2 * e + 1]];
        if (a >= 0 && b >= 0 && a < nSites && b < nSites) { start[a + 1]++; start[b + 1]++; }
    }
    for (let i = 0; i < nSites; i++) start[i + 1] += start[i];
    const adj = new Int32Array(start[nSites]), fill = start.slice(0, nSites);
    for (let e = 0; e < ne; e++) {
        const a = siteOf[esites[2 * e]], b = siteOf[esites[2 * e + 1]];
        if (a >= 0 && b >= 0 && a < nSites && b < nSites) { adj[fill[a]++] = b; adj[fill[b]++] = a; }
    }
    const colour = new Int8Array(nSites).fill(-1);
    for (let i = 0; i < nSites; i++) {
        let used = 0;
        for (let k = start[i]; k < start[i + 1]; k++) {
            const c = colour[adj[k]];
            if (c >= 0) used |= 1 << c;
        }
        let c = 0;
        while (c < nc && (used & (1 << c))) c++;
        colour[i] = c < nc ? c : (Math.imul(i, 2654435761) >>> 0) % nc;
    }
    return colour;
}

/* The model frame of a diagram record: centre and scale of its sites'
 * box (or of the clip box when there are no sites). */
function frameOf(D) {
    const xy = D.xy, n = xy.length / 2;
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (let i = 0; i < n; i++) {
        const x = xy[2 * i], y = xy[2 * i + 1];
        if (x < x0) x0 = x;
        if (x > x1) x1 = x;
        if (y < y0) y0 = y;
        if (y > y1) y1 = y;
    }
    let ref = n && x0 <= x1 ? [x0, y0, x1, y1] : null;
    if (!ref && D.clip && D.clip.box) ref = D.clip.box;
    if (!ref) return null;
    const w = ref[2] - ref[0], h = ref[3] - ref[1];
    const cx = ref[0] / 2 + ref[2] / 2, cy = ref[1] / 2 + ref[3] / 2;
    const ext = Math.max(w, h);
    const k = ext > 0 && isFinite(1 / ext) ? 1 / ext : 1 / Math.max(Math.abs(cx), Math.abs(cy), 1);
    return { cx: cx, cy: cy, k: k, ref: ref };
}

/* Prepares a diagram record for drawing (see the file comment). nColours
 * is the number of cell colours. keep, when given, is a frame to use
 * instead of the record's own (a preview drawn in the current frame). */
export function prepare(D, nColours, keep) {
    const nIn = D.xy.length / 2;
    const fr = keep || frameOf(D) || { cx: 0, cy: 0, k: 1, ref: null };
    const k = fr.k, cx = fr.cx, cy = fr.cy;
    const xy = D.xy;
    const mxs = new Float64Array(nIn), mys = new Float64Array(nIn);
    let bx0 = Infinity, by0 = Infinity, bx1 = -Infinity, by1 = -Infinity;
    for (let i = 0; i < nIn; i++) {
        const x = (xy[2 * i] - cx) * k, y = (xy[2 * i + 1] - cy) * k;
        mxs[i] = x;
        mys[i] = y;
        if (x < bx0) bx0 = x;
        if (x > bx1) bx1 = x;
        if (y < by0) by0 = y;
        if (y > by1) by1 = y;
    }
    const sitesBox = nIn && bx0 <= bx1 ? [bx0, by0, bx1, by1] : [-0.5, -0.5, 0.5, 0.5];
    /* every index in an answer is an input index; a duplicate is drawn once */
    const dup = new Uint8Array(nIn);
    for (const d of D.dups) {
        if (d[0] >= 0 && d[0] < nIn) dup[d[0]] = 1;
    }

    /* vertices and the finite Voronoi edges */
    const nv = D.vxy.length / 2;
    const vx = new Float64Array(nv), vy = new Float64Array(nv);
    for (let i = 0; i < nv; i++) {
        vx[i] = (D.vxy[2 * i] - cx) * k;
        vy[i] = (D.vxy[2 * i + 1] - cy) * k;
    }
    const ends = D.ends, ne = ends.length / 2;
    const voronoi = buildIndex(ne, sitesBox, (e, b) => {
        const a = ends[2 * e], c = ends[2 * e + 1];
        if (a < 0 || c < 0) { b[0] = NaN; return; }
        b[0] = Math.min(vx[a], vx[c]); b[1] = Math.min(vy[a], vy[c]);
        b[2] = Math.max(vx[a], vx[c]); b[3] = Math.max(vy[a], vy[c]);
    });
    const nSeg = voronoi.order.length + voronoi.long.length;

    /* rays leave their vertex; lines pass through the midpoint of their
     * two sites (computed as the codec does) */
    const nr = D.rayEdge.length;
    const rayO = new Float64Array(2 * nr), rayD = new Float64Array(2 * nr), rayLine = new Uint8Array(nr);
    for (let r = 0; r < nr; r++) {
        const e = D.rayEdge[r];
        const a = ends[2 * e];
        rayD[2 * r] = D.rayDir[2 * r];
        rayD[2 * r + 1] = D.rayDir[2 * r + 1];
        if (a >= 0) {
            rayO[2 * r] = vx[a];
            rayO[2 * r + 1] = vy[a];
        } else {
            const p = D.esites[2 * e], q = D.esites[2 * e + 1];
            let mx = (xy[2 * p] + xy[2 * q]) / 2, my = (xy[2 * p + 1] + xy[2 * q + 1]) / 2;
            if (!isFinite(mx)) mx = xy[2 * p] / 2 + xy[2 * q] / 2;
            if (!isFinite(my)) my = xy[2 * p + 1] / 2 + xy[2 * q + 1] / 2;
            rayO[2 * r] = (mx - cx) * k;
            rayO[2 * r + 1] = (my - cy) * k;
            rayLine[r] = 1;
        }
    }

    /* Delaunay edges, once each. They are the duals of the Voronoi edges
     * (each separates the two sites it names), plus, where k > 3 sites
     * are cocircular, the k - 3 diagonals the triangulation adds inside
     * their polygon; so when there are as many triangles as vertices,
     * every vertex has degree 3 and the Voronoi edges' sites are all of
     * them. */
    let dedges = null, delaunay = null;
    if (D.tri && D.tri.length) {
        dedges = D.nTriangles === D.nVertices && D.tri.length === 3 * D.nTriangles
            ? D.esites : delaunayEdges(D.tri, nIn);
        delaunay = buildIndex(dedges.length / 2, sitesBox, (j, b) => {
            const p = dedges[2 * j], q = dedges[2 * j + 1];
            b[0] = Math.min(mxs[p], mxs[q]); b[1] = Math.min(mys[p], mys[q]);
            b[2] = Math.max(mxs[p], mxs[q]); b[3] = Math.max(mys[p], mys[q]);
        });
    }

    /* clipped cells, with a colour each */
    let cells = null;
    const box = D.clip && D.clip.box;
    if (D.clip && D.clip.start.length > 1) {
        const st = D.clip.start, cxyW = D.clip.xy;
        const nc = st.length - 1;
        const cxy = new Float64Array(cxyW.length);
        for (let i = 0; i < cxyW.length; i += 2) {
            cxy[i] = (cxyW[i] - cx) * k;
            cxy[i + 1] = (cxyW[i + 1] - cy) * k;
        }
        const colour = colourCells(D.esites, dup, nc, nColours);
        const index = buildIndex(nc, sitesBox, (i, b) => {
            if (st[i + 1] - st[i] < 3) { b[0] = NaN; return; }
            let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
            for (let j = st[i]; j < st[i + 1]; j++) {
                const x = cxy[2 * j], y = cxy[2 * j + 1];
                if (x < x0) x0 = x;
                if (x > x1) x1 = x;
                if (y < y0) y0 = y;
                if (y > y1) y1 = y;
            }
            b[0] = x0; b[1] = y0; b[2] = x1; b[3] = y1;
        });
        cells = { start: st, xy: cxy, colour: colour, index: index };
    }

    return {
        frame: { cx: cx, cy: cy, k: k },
        ns: nIn, mxs: mxs, mys: mys, dup: dup, sitesBox: sitesBox,
        vx: vx, vy: vy, ends: ends, voronoi: voronoi, nSeg: nSeg,
        rayO: rayO, rayD: rayD, rayLine: rayLine,
        dedges: dedges, delaunay: delaunay,
        cells: cells,
        clipBox: box ? [(box[0] - cx) * k, (box[1] - cy) * k, (box[2] - cx) * k, (box[3] - cy) * k] : null,
        nVertices: D.nVertices,
        nEdges: D.nEdges,
        nTriangles: D.tri ? D.nTriangles : 0,
        /* model area the sites cover (their box), for dot sizes */
        area: Math.max((sitesBox[2] - sitesBox[0]) * (sitesBox[3] - sitesBox[1]), 1e-3),
    };
}

/* The ArrayBuffers behind every typed array reachable from the values,
 * each once: the transfer list that moves them to another thread. */
export function transferables(...values) {
    const seen = new Set();
    const walk = (v, depth) => {
        if (!v || typeof v !== 'object' || depth > 4) return;
        if (ArrayBuffer.isView(v)) {
            seen.add(v.buffer);
            return;
        }
        if (v instanceof ArrayBuffer) {
            seen.add(v);
            return;
        }
        if (Array.isArray(v)) return; /* plain lists hold no typed arrays here */
        for (const key of Object.keys(v)) walk(v[key], depth + 1);
    };
    for (const v of values) walk(v, 0);
    return Array.from(seen);
}
