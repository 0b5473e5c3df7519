/* renderer.js -- the diagram canvas: model frame, view, drawing, pan and zoom.
 *
 * What it does: turns a diagram record (decode.js) into a drawing and
 * keeps it on the canvas while the user pans and zooms (drag, wheel,
 * keys, the toolbar buttons) or the window changes size.
 *
 * Representation: the result's coordinates are mapped once into a "model"
 * frame, (world - centre) * k with k = 1 / (extent of the sites), so that
 * the cached Path2D objects (stored by the browser in single precision)
 * keep full pixel accuracy for data at 1e9 offsets or 1e-9 scales. Finite
 * edges and Delaunay triangles live in two such cached paths; pan and zoom
 * only change the canvas transform, so a frame is a handful of stroke
 * calls whatever the size. Rays and lines are clipped to the visible
 * rectangle in double precision on every frame (there are O(hull) rays,
 * or n - 1 lines for collinear input), and sites are culled and batched
 * into one path per frame (or written as pixels when there are many) so
 * their dots keep a constant size on screen. Big paths are stroked one
 * device pixel wide, which the rasteriser draws as a fast hairline.
 *
 * Invariants: the view is kept in model units, so it survives a recompute
 * of the same data; which layers are drawn is the layers object, set by
 * the controls; pub mirrors what the last frame drew.
 *
 * Cost: a result of n sites costs O(n) to prepare; a frame costs O(n) for
 * the site culling plus the rasterisation of the cached paths.
 */
import { $, pub, LITTLE_ENDIAN, fmtCoord } from './util.js';
import { summary, pointsOnly } from './decode.js';

const COLOR = {
    background: '#fbfbf8',
    grid: '#e7e8e2',
    gridAxis: '#cfd2ca',
    gridText: '#8a918f',
    edge: '#1f4e79',
    site: '#c0392b',
    delaunay: 'rgba(46, 139, 87, 0.6)',
    clip: '#e08a00',
    cells: ['#dbe9f6', '#fde7cf', '#dcefdc', '#efe0f3', '#fbf3c8', '#d9f0ee', '#f6dcdc'],
};
const MAX_ZOOM_IN = 1e7;    /* model units are the data's extent */
const MIN_ZOOM_OUT = 1e-4;
const CLICK_SLOP = 4;       /* CSS px a press may move and still be a click */
/* Paths with more segments than this are stroked as hairlines. */
const HAIRLINE_ABOVE = 20000;
/* More sites than this are drawn as pixels, not discs. */
const DOTS_AS_PIXELS = 5000;

/* What to draw; the controls keep it in step with the Draw checkboxes. */
export const layers = { sites: true, edges: true, delaunay: false, clip: false };

/* Prepared drawing of the last result (see setResult()). */
let geom = null;
/* Model frame: model = (world - c) * k. */
let frame = { cx: 0.5, cy: 0.5, k: 1 };
/* View: the model point at the canvas centre and CSS px per model unit. */
const view = { mx: 0, my: 0, zoom: 1, fitted: true };
let fitNext = true;

const canvas = $('diagram');
const ctx = canvas.getContext('2d');
let cssW = 1, cssH = 1, dpr = 1;

/* The next result is fitted to the window (a new source). */
export function fitNextResult() {
    fitNext = true;
}

/* Counts of what the current drawing holds, or null when there is none. */
export function geomInfo() {
    return geom ? { nVertices: geom.nVertices, nEdges: geom.nEdges, nTriangles: geom.nTriangles } : null;
}

/* Builds geom from a diagram record: model frame, cached paths, ray
 * list. Keeps the view where it was in world terms unless fitNext is
 * set. A preview (a clicked point before its diagram arrives) is drawn
 * but not published as the last result. */
export function setResult(D, preview) {
    if (!preview) {
        pub.diagram = D;
        pub.lastResult = summary(D);
    }
    const nIn = D.nInput === D.xy.length / 2 ? D.nInput : D.xy.length / 2;
    const xy = D.xy;
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (let i = 0; i < nIn; i++) {
        const x = xy[2 * i], y = xy[2 * i + 1];
        if (x < x0) x0 = x;
        if (x > x1) x1 = x;
        if (y < y0) y0 = y;
        if (y > y1) y1 = y;
    }
    const box = D.clip && D.clip.box;
    let ref = nIn ? [x0, y0, x1, y1] : null;
    if (!ref && box) ref = box;

    /* keep the view's world centre and world scale across the change */
    const worldC = [view.mx / frame.k + frame.cx, view.my / frame.k + frame.cy];
    const worldZoom = view.zoom * frame.k;
    if (ref) {
        const w = ref[2] - ref[0], h = ref[3] - ref[1];
        const cx = ref[0] / 2 + ref[2] / 2, cy = ref[1] / 2 + ref[3] / 2;
        const ext = Math.max(w, h);
        const k = ext > 0 && isFinite(1 / ext) ? 1 / ext
            : 1 / Math.max(Math.abs(cx), Math.abs(cy), 1);
        frame = { cx: cx, cy: cy, k: k };
    }
    view.mx = (worldC[0] - frame.cx) * frame.k;
    view.my = (worldC[1] - frame.cy) * frame.k;
    view.zoom = worldZoom / frame.k;

    const k = frame.k, cx = frame.cx, cy = frame.cy;
    const mxs = new Float64Array(nIn), mys = new Float64Array(nIn);
    for (let i = 0; i < nIn; i++) {
        mxs[i] = (xy[2 * i] - cx) * k;
        mys[i] = (xy[2 * i + 1] - cy) * k;
    }
    /* every index in an answer is an input index; a duplicate is
     * drawn once */
    const dup = new Uint8Array(nIn);
    for (const d of D.dups) {
        if (d[0] >= 0 && d[0] < nIn) dup[d[0]] = 1;
    }

    /* finite edges into one cached path */
    const vxy = D.vxy, ends = D.ends;
    const segPath = new Path2D();
    let nSeg = 0;
    const ne = ends.length / 2;
    for (let e = 0; e < ne; e++) {
        const a = ends[2 * e], b = ends[2 * e + 1];
        if (a < 0 || b < 0) continue;
        segPath.moveTo((vxy[2 * a] - cx) * k, (vxy[2 * a + 1] - cy) * k);
        segPath.lineTo((vxy[2 * b] - cx) * k, (vxy[2 * b + 1] - cy) * k);
        nSeg++;
    }
    /* rays leave their vertex; lines pass through the midpoint of
     * their two sites (computed as the codec does) */
    const rays = [];
    for (let r = 0; r < D.rayEdge.length; r++) {
        const e = D.rayEdge[r];
        const a = ends[2 * e];
        const dx = D.rayDir[2 * r], dy = D.rayDir[2 * r + 1];
        if (a >= 0) {
            rays.push({ ox: (vxy[2 * a] - cx) * k, oy: (vxy[2 * a + 1] - cy) * k, dx: dx, dy: dy, line: false });
        } else {
            const p = D.esites[2 * e], q = D.esites[2 * e + 1];
            let mx = (xy[2 * p] + xy[2 * q]) / 2, my = (xy[2 * p + 1] + xy[2 * q + 1]) / 2;
            if (!isFinite(mx)) mx = xy[2 * p] / 2 + xy[2 * q] / 2;
            if (!isFinite(my)) my = xy[2 * p + 1] / 2 + xy[2 * q + 1] / 2;
            rays.push({ ox: (mx - cx) * k, oy: (my - cy) * k, dx: dx, dy: dy, line: true });
        }
    }

    let triPath = null;
    if (D.tri && D.tri.length) {
        triPath = new Path2D();
        const t = D.tri;
        for (let i = 0; i + 2 < t.length; i += 3) {
            triPath.moveTo(mxs[t[i]], mys[t[i]]);
            triPath.lineTo(mxs[t[i + 1]], mys[t[i + 1]]);
            triPath.lineTo(mxs[t[i + 2]], mys[t[i + 2]]);
            triPath.closePath();
        }
    }

    /* clipped cells: a few colour buckets, one fill each */
    let cellPaths = null;
    if (D.clip && D.clip.start.length > 1) {
        const st = D.clip.start, cxy = D.clip.xy;
        const colour = colourCells(D, dup, st.length - 1);
        cellPaths = COLOR.cells.map(() => new Path2D());
        for (let i = 0; i + 1 < st.length; i++) {
            if (st[i + 1] - st[i] < 3) continue;
            const path = cellPaths[colour[i]];
            path.moveTo((cxy[2 * st[i]] - cx) * k, (cxy[2 * st[i] + 1] - cy) * k);
            for (let j = st[i] + 1; j < st[i + 1]; j++) path.lineTo((cxy[2 * j] - cx) * k, (cxy[2 * j + 1] - cy) * k);
            path.closePath();
        }
    }

    geom = {
        ns: nIn, mxs: mxs, mys: mys, dup: dup,
        segPath: segPath, nSeg: nSeg, rays: rays,
        triPath: triPath, nTriangles: D.tri ? D.nTriangles : 0,
        cellPaths: cellPaths,
        clipBox: box ? [(box[0] - cx) * k, (box[1] - cy) * k, (box[2] - cx) * k, (box[3] - cy) * k] : null,
        nVertices: D.nVertices,
        nEdges: D.nEdges,
        /* model area the sites cover (their box), for dot sizes */
        area: ref ? Math.max((ref[2] - ref[0]) * k * (ref[3] - ref[1]) * k, 1e-3) : 1,
    };
    if (fitNext || view.fitted) {
        fitView();
        fitNext = false;
    }
}

/* Colours for the cells (one per distinct site, in input order) so that
 * neighbours differ: greedy over the sites, a neighbour being a site
 * across a Voronoi edge. With few colours greedy can run out at a
 * site of high degree; that site then takes a hashed colour. O(E). */
function colourCells(D, dup, nSites) {
    const nIn = dup.length, nc = COLOR.cells.length;
    const siteOf = new Int32Array(nIn).fill(-1);
    let j = 0;
    for (let i = 0; i < nIn; i++) if (!dup[i]) siteOf[i] = j++;
    const start = new Uint32Array(nSites + 1), ne = D.esites.length / 2;
    for (let e = 0; e < ne; e++) {
        const a = siteOf[D.esites[2 * e]], b = siteOf[D.esites[2 * e + 1]];
        if (a >= 0 && b >= 0 && a < nSites && b < nSites) { start[a + 1]++; start[b + 1]++; }
    }
    for (let i = 0; i < nSites; i++) start[i + 1] += start[i];
    const adj = new Int32Array(start[nSites]), fill = start.slice(0, nSites);
    for (let e = 0; e < ne; e++) {
        const a = siteOf[D.esites[2 * e]], b = siteOf[D.esites[2 * e + 1]];
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

/* Shows a clicked point at once, before its diagram arrives. */
export function addPreviewPoint(p) {
    if (!geom) {
        setResult(pointsOnly([p]), true);
    } else {
        const ns = geom.ns + 1;
        const mxs = new Float64Array(ns), mys = new Float64Array(ns), dup = new Uint8Array(ns);
        mxs.set(geom.mxs); mys.set(geom.mys); dup.set(geom.dup);
        mxs[ns - 1] = (p[0] - frame.cx) * frame.k;
        mys[ns - 1] = (p[1] - frame.cy) * frame.k;
        Object.assign(geom, { ns: ns, mxs: mxs, mys: mys, dup: dup });
    }
    view.fitted = false; /* the view stays put while points are added */
    scheduleDraw();
}

export function clearResult() {
    geom = null;
    pub.lastResult = null;
    pub.diagram = null;
    drawNow();
}

/* ---- view ------------------------------------------------------------- */

function contentBox() {
    if (!geom) return [-0.5, -0.5, 0.5, 0.5];
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (let i = 0; i < geom.ns; i++) {
        const x = geom.mxs[i], y = geom.mys[i];
        if (x < x0) x0 = x;
        if (x > x1) x1 = x;
        if (y < y0) y0 = y;
        if (y > y1) y1 = y;
    }
    if (geom.clipBox && layers.clip) {
        const b = geom.clipBox;
        x0 = Math.min(x0, b[0]); y0 = Math.min(y0, b[1]);
        x1 = Math.max(x1, b[2]); y1 = Math.max(y1, b[3]);
    }
    if (!(x0 <= x1)) return [-0.5, -0.5, 0.5, 0.5];
    return [x0, y0, x1, y1];
}

export function fitView() {
    const b = contentBox();
    let w = b[2] - b[0], h = b[3] - b[1];
    if (!(w > 0) && !(h > 0)) { w = 1; h = 1; }
    view.mx = (b[0] + b[2]) / 2;
    view.my = (b[1] + b[3]) / 2;
    const zx = w > 0 ? cssW / w : Infinity, zy = h > 0 ? cssH / h : Infinity;
    view.zoom = 0.9 * Math.min(zx, zy);
    clampZoom();
    view.fitted = true;
    scheduleDraw();
}

function clampZoom() {
    const base = Math.min(cssW, cssH) || 1;
    view.zoom = Math.min(Math.max(view.zoom, base * MIN_ZOOM_OUT), base * MAX_ZOOM_IN);
}

export function zoomAbout(factor, px, py) {
    view.fitted = false;
    const mx = view.mx + (px - cssW / 2) / view.zoom;
    const my = view.my - (py - cssH / 2) / view.zoom;
    view.zoom *= factor;
    clampZoom();
    view.mx = mx - (px - cssW / 2) / view.zoom;
    view.my = my + (py - cssH / 2) / view.zoom;
    scheduleDraw();
}

/* World units per CSS pixel at the current zoom. */
export function pixelSize() {
    return 1 / (view.zoom * frame.k);
}

/* CSS px -> world coordinates */
export function toWorld(px, py) {
    const mx = view.mx + (px - cssW / 2) / view.zoom;
    const my = view.my - (py - cssH / 2) / view.zoom;
    return [mx / frame.k + frame.cx, my / frame.k + frame.cy];
}

export function visibleWorld() {
    const a = toWorld(0, cssH), b = toWorld(cssW, 0);
    return [a[0], a[1], b[0], b[1]];
}

/* ---- drawing ---------------------------------------------------------- */

let drawPending = false;
export function scheduleDraw() {
    if (drawPending) return;
    drawPending = true;
    requestAnimationFrame(() => {
        drawPending = false;
        const t = performance.now();
        drawNow();
        afterPaint(() => { pub.framePaintMs = performance.now() - t; });
    });
}

/* Calls fn once the frame that shows what was just drawn has been
 * produced: a canvas records its drawing and rasterises it with the
 * frame, so timing the script alone would miss most of the cost. */
export function afterPaint(fn) {
    requestAnimationFrame(() => setTimeout(fn, 0));
}

export function resizeCanvas() {
    const wrap = $('canvas-wrap');
    const w = Math.max(1, wrap.clientWidth), h = Math.max(1, wrap.clientHeight);
    const d = window.devicePixelRatio || 1;
    if (w === cssW && h === cssH && d === dpr && canvas.width === Math.round(w * d)) return;
    cssW = w; cssH = h; dpr = d;
    canvas.width = Math.round(w * d);
    canvas.height = Math.round(h * d);
    /* a view nobody has moved follows the window */
    if (view.fitted) fitView();
    drawNow();
}

/* Parametric clip of o + t d to the rectangle r, t in [t0, t1]. */
function clipRay(ox, oy, dx, dy, t0, t1, r) {
    const p = [-dx, dx, -dy, dy];
    const q = [ox - r[0], r[2] - ox, oy - r[1], r[3] - oy];
    for (let i = 0; i < 4; i++) {
        if (p[i] === 0) {
            if (q[i] < 0) return null;
        } else {
            const t = q[i] / p[i];
            if (p[i] < 0) { if (t > t0) t0 = t; } else if (t < t1) t1 = t;
        }
    }
    return t0 <= t1 ? [t0, t1] : null;
}

/* Grid lines at round world coordinates under the diagram; returns
 * their labels, which drawLabels() writes over everything. */
function drawGrid() {
    const w = visibleWorld();
    const spanX = w[2] - w[0];
    if (!(spanX > 0) || !isFinite(spanX)) return [];
    const target = spanX / Math.max(2, cssW / 110);
    const mag = Math.pow(10, Math.floor(Math.log10(target)));
    const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= target) || 10 * mag;
    ctx.save();
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.lineWidth = 1;
    const sxOf = (x) => cssW / 2 + ((x - frame.cx) * frame.k - view.mx) * view.zoom;
    const syOf = (y) => cssH / 2 - ((y - frame.cy) * frame.k - view.my) * view.zoom;
    const path = new Path2D(), axes = new Path2D();
    const labels = [];
    const i0 = Math.ceil(w[0] / step), i1 = Math.floor(w[2] / step);
    if (i1 - i0 < 200) {
        for (let i = i0; i <= i1; i++) {
            const x = i * step, s = Math.round(sxOf(x)) + 0.5;
            (i === 0 ? axes : path).moveTo(s, 0);
            (i === 0 ? axes : path).lineTo(s, cssH);
            labels.push([fmtCoord(x, step), s + 3, cssH - 4, 'left']);
        }
    }
    const j0 = Math.ceil(w[1] / step), j1 = Math.floor(w[3] / step);
    if (j1 - j0 < 200) {
        for (let j = j0; j <= j1; j++) {
            const y = j * step, s = Math.round(syOf(y)) + 0.5;
            (j === 0 ? axes : path).moveTo(0, s);
            (j === 0 ? axes : path).lineTo(cssW, s);
            labels.push([fmtCoord(y, step), 3, s - 3, 'left']);
        }
    }
    ctx.strokeStyle = COLOR.grid;
    ctx.stroke(path);
    ctx.strokeStyle = COLOR.gridAxis;
    ctx.stroke(axes);
    ctx.restore();
    return labels;
}

function drawLabels(labels) {
    ctx.save();
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.font = '11px system-ui, sans-serif';
    ctx.lineJoin = 'round';
    ctx.lineWidth = 3;
    ctx.strokeStyle = 'rgba(251, 251, 248, 0.85)';
    ctx.fillStyle = COLOR.gridText;
    for (const l of labels) {
        ctx.textAlign = l[3];
        ctx.strokeText(l[0], l[1], l[2]);
        ctx.fillText(l[0], l[1], l[2]);
    }
    ctx.restore();
}

/* Sites as small discs, culled, one fill: for up to DOTS_AS_PIXELS. */
function drawSiteDiscs(z) {
    const r = geom.ns <= 200 ? 3 : (geom.ns <= 2000 ? 2.3 : 1.6);
    const path = new Path2D();
    const hw = cssW / 2, hh = cssH / 2;
    let drawn = 0;
    for (let i = 0; i < geom.ns; i++) {
        if (geom.dup[i]) continue;
        const x = hw + (geom.mxs[i] - view.mx) * z;
        const y = hh - (geom.mys[i] - view.my) * z;
        if (x < -r || y < -r || x > cssW + r || y > cssH + r) continue;
        path.moveTo(x + r, y);
        path.arc(x, y, r, 0, 2 * Math.PI);
        drawn++;
    }
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = COLOR.site;
    ctx.fill(path);
    return drawn;
}

/* Many sites: square dots written straight into a pixel buffer and
 * composited in one drawImage, since 10^5 anti-aliased shapes cost
 * the rasteriser far more than 10^5 stores. */
let dots = null;
function drawSitePixels(z) {
    const W = canvas.width, H = canvas.height;
    if (!dots || dots.canvas.width !== W || dots.canvas.height !== H) {
        const c = document.createElement('canvas');
        c.width = W;
        c.height = H;
        const g = c.getContext('2d');
        const img = g.createImageData(W, H);
        dots = { canvas: c, ctx: g, img: img, px: new Uint32Array(img.data.buffer) };
    }
    const px = dots.px;
    px.fill(0);
    const rgb = parseInt(COLOR.site.slice(1), 16);
    const colour = LITTLE_ENDIAN
        ? (0xff000000 | ((rgb & 0xff) << 16) | (rgb & 0xff00) | (rgb >>> 16)) >>> 0
        : ((rgb << 8) | 0xff) >>> 0;
    /* dense: one pixel per site, or the dots merge into a carpet */
    const density = geom.ns / (geom.area * z * z);
    const size = (density > 0.04 ? 1 : 2) + (dpr >= 2 ? 1 : 0);
    const s = z * dpr, ox = W / 2 - view.mx * s, oy = H / 2 + view.my * s;
    let drawn = 0;
    for (let i = 0; i < geom.ns; i++) {
        if (geom.dup[i]) continue;
        const x = Math.round(ox + geom.mxs[i] * s - size / 2);
        const y = Math.round(oy - geom.mys[i] * s - size / 2);
        if (x < 0 || y < 0 || x > W - size || y > H - size) continue;
        for (let dy = 0; dy < size; dy++) {
            const row = (y + dy) * W + x;
            for (let dx = 0; dx < size; dx++) px[row + dx] = colour;
        }
        drawn++;
    }
    dots.ctx.putImageData(dots.img, 0, 0);
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.drawImage(dots.canvas, 0, 0);
    return drawn;
}

export function drawNow() {
    const t0 = performance.now();
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = COLOR.background;
    ctx.fillRect(0, 0, cssW, cssH);
    const labels = drawGrid();
    let edgesDrawn = 0, raysDrawn = 0, sitesDrawn = 0, trisDrawn = 0;
    if (geom) {
        const z = view.zoom;
        /* model -> device pixels */
        ctx.setTransform(dpr * z, 0, 0, -dpr * z,
            dpr * (cssW / 2 - view.mx * z), dpr * (cssH / 2 + view.my * z));
        const clipOn = layers.clip;
        if (clipOn && geom.cellPaths) {
            geom.cellPaths.forEach((p, i) => {
                ctx.fillStyle = COLOR.cells[i];
                ctx.fill(p);
            });
        }
        /* A stroke of one device pixel is rasterised as a hairline,
         * tens of times faster than a wider one on a path of 10^5
         * segments; small diagrams get the slightly bolder line. */
        const hairline = 1 / (z * dpr);
        if (layers.delaunay && geom.triPath) {
            ctx.strokeStyle = COLOR.delaunay;
            ctx.lineWidth = geom.nTriangles > HAIRLINE_ABOVE ? hairline : 0.8 / z;
            ctx.stroke(geom.triPath);
            trisDrawn = geom.nTriangles;
        }
        if (layers.edges) {
            ctx.strokeStyle = COLOR.edge;
            ctx.lineWidth = geom.nSeg > HAIRLINE_ABOVE ? hairline : 1.15 / z;
            ctx.lineJoin = 'round';
            ctx.stroke(geom.segPath);
            edgesDrawn = geom.nSeg;
            /* rays and lines: clipped to the view (plus a margin) here,
             * in double precision, so that no huge coordinate reaches
             * the rasteriser */
            if (geom.rays.length) {
                const m = 4 / z;
                const r = [view.mx - cssW / 2 / z - m, view.my - cssH / 2 / z - m,
                    view.mx + cssW / 2 / z + m, view.my + cssH / 2 / z + m];
                const rp = new Path2D();
                for (const ray of geom.rays) {
                    const t = clipRay(ray.ox, ray.oy, ray.dx, ray.dy,
                        ray.line ? -Infinity : 0, Infinity, r);
                    if (!t) continue;
                    rp.moveTo(ray.ox + t[0] * ray.dx, ray.oy + t[0] * ray.dy);
                    rp.lineTo(ray.ox + t[1] * ray.dx, ray.oy + t[1] * ray.dy);
                    raysDrawn++;
                }
                ctx.stroke(rp);
                edgesDrawn += raysDrawn;
            }
        }
        ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
        if (clipOn && geom.clipBox) {
            const b = geom.clipBox;
            const x0 = cssW / 2 + (b[0] - view.mx) * z, x1 = cssW / 2 + (b[2] - view.mx) * z;
            const y0 = cssH / 2 - (b[3] - view.my) * z, y1 = cssH / 2 - (b[1] - view.my) * z;
            ctx.save();
            ctx.strokeStyle = COLOR.clip;
            ctx.lineWidth = 1.5;
            ctx.setLineDash([6, 4]);
            ctx.strokeRect(x0, y0, x1 - x0, y1 - y0);
            ctx.restore();
        }
        if (layers.sites && geom.ns) {
            sitesDrawn = geom.ns <= DOTS_AS_PIXELS ? drawSiteDiscs(z) : drawSitePixels(z);
        }
    }
    drawLabels(labels);
    pub.edgesDrawn = edgesDrawn;
    pub.raysDrawn = raysDrawn;
    pub.sitesDrawn = sitesDrawn;
    pub.trianglesDrawn = trisDrawn;
    pub.view = { mx: view.mx, my: view.my, zoom: view.zoom, world: visibleWorld() };
    pub.frameMs = performance.now() - t0;
}


/* ---- pan, zoom and click ---------------------------------------------- */

/* Wires the canvas and the zoom buttons: drag pans, the wheel and the
 * keys +, -, 0 and the arrows zoom and move, and a press that does not
 * move is a click, handed to onClick(px, py) in CSS px. onMove(world)
 * gets the world position under the pointer, or null when it leaves. */
export function attachInteraction(onClick, onMove) {
    $('zoom-in').addEventListener('click', () => zoomAbout(1.5, cssW / 2, cssH / 2));
    $('zoom-out').addEventListener('click', () => zoomAbout(1 / 1.5, cssW / 2, cssH / 2));
    $('zoom-fit').addEventListener('click', fitView);

    let press = null;
    const local = (ev) => {
        const r = canvas.getBoundingClientRect();
        return [ev.clientX - r.left, ev.clientY - r.top];
    };
    canvas.addEventListener('pointerdown', (ev) => {
        if (ev.button !== 0) return;
        const p = local(ev);
        press = { x: p[0], y: p[1], mx: view.mx, my: view.my, moved: false, id: ev.pointerId };
        canvas.setPointerCapture(ev.pointerId);
    });
    canvas.addEventListener('pointermove', (ev) => {
        const p = local(ev);
        onMove(toWorld(p[0], p[1]));
        if (!press || press.id !== ev.pointerId) return;
        const dx = p[0] - press.x, dy = p[1] - press.y;
        if (!press.moved && Math.abs(dx) + Math.abs(dy) > CLICK_SLOP) {
            press.moved = true;
            canvas.classList.add('panning');
        }
        if (press.moved) {
            view.fitted = false;
            view.mx = press.mx - dx / view.zoom;
            view.my = press.my + dy / view.zoom;
            scheduleDraw();
        }
    });
    const release = (ev, cancelled) => {
        if (!press || press.id !== ev.pointerId) return;
        const wasClick = !press.moved && !cancelled;
        press = null;
        canvas.classList.remove('panning');
        if (wasClick) {
            const p = local(ev);
            onClick(p[0], p[1]);
        }
    };
    canvas.addEventListener('pointerup', (ev) => release(ev, false));
    canvas.addEventListener('pointercancel', (ev) => release(ev, true));
    canvas.addEventListener('pointerleave', () => onMove(null));
    canvas.addEventListener('wheel', (ev) => {
        ev.preventDefault();
        const unit = ev.deltaMode === 1 ? 16 : (ev.deltaMode === 2 ? cssH : 1);
        const p = local(ev);
        zoomAbout(Math.exp(-ev.deltaY * unit * 0.0015), p[0], p[1]);
    }, { passive: false });
    canvas.addEventListener('keydown', (ev) => {
        const step = 60 / view.zoom;
        const keys = {
            '+': () => zoomAbout(1.5, cssW / 2, cssH / 2),
            '=': () => zoomAbout(1.5, cssW / 2, cssH / 2),
            '-': () => zoomAbout(1 / 1.5, cssW / 2, cssH / 2),
            '0': fitView,
            ArrowLeft: () => { view.mx -= step; view.fitted = false; scheduleDraw(); },
            ArrowRight: () => { view.mx += step; view.fitted = false; scheduleDraw(); },
            ArrowUp: () => { view.my += step; view.fitted = false; scheduleDraw(); },
            ArrowDown: () => { view.my -= step; view.fitted = false; scheduleDraw(); },
        };
        if (keys[ev.key]) {
            ev.preventDefault();
            keys[ev.key]();
        }
    });
}
