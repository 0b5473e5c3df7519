/* renderer.js -- the diagram canvas: view, drawing in slices, pan and zoom.
 *
 * What it does: draws a prepared diagram (geometry.js) -- clipped cells,
 * Delaunay edges, Voronoi edges and rays, the clip box, sites, a grid
 * with labels -- and keeps it on the canvas while the user pans and zooms
 * (drag, wheel, keys, the toolbar buttons) or the window changes size,
 * without ever holding the page's thread for long, whatever the size.
 *
 * How:
 * - A frame is a job that draws into an off-screen canvas in slices of
 *   about SLICE_MS of script each; between slices the page handles input
 *   and paints. The finished frame is copied to the visible canvas in one
 *   drawImage. Until then the visible canvas shows the last finished frame
 *   moved and scaled to the current view (a preview), so a drag over 10^6
 *   sites moves at the display's rate and the full frame follows once the
 *   view has been still for SETTLE_MS. A small diagram finishes in its
 *   first slice, within the event that asked for it.
 * - Each layer visits only the grid buckets that meet the view (plus the
 *   few long items), so a zoomed-in frame costs what it shows.
 * - Level of detail, item by item: an edge shorter than LOD_PX device
 *   pixels, or a cell smaller than that, is not stroked or filled as a
 *   path but plotted into a pixel buffer (edges add coverage, shown as
 *   opacity), which is composited in one drawImage. At 10^6 sites the
 *   whole diagram is pixels; zoomed in, the same items become lines.
 * - Everything is computed in device pixels in double precision, and a
 *   path is given no coordinate beyond the view (rays and long edges are
 *   clipped first), so data at 1e9 offsets or 1e-9 scales and zooms of
 *   1e7 draw exactly.
 *
 * Invariants: the view is kept in model units (geometry.js), so it
 * survives a recompute of the same data; one frame job runs at a time (a
 * new one replaces it); which layers are drawn is the layers object, set
 * by the controls, and an overlay (the step-through replay), when set,
 * draws instead of them; pub mirrors the last finished frame (what it drew, in
 * vectors and in pixels) and pub.drawing says whether one is in progress.
 *
 * Cost: a frame is O(items in view + sites) of script and never more than
 * O(LOD pixels) of rasterising per item; the memory is two canvases and
 * two pixel buffers of the canvas's size.
 */
import { $, pub, LITTLE_ENDIAN, fmtCoord } from './util.js';
import { summary, pointsOnly } from './decode.js';
import { prepare } from './geometry.js';

const COLOR = {
    background: '#fbfbf8',
    grid: '#e7e8e2',
    gridAxis: '#cfd2ca',
    gridText: '#8a918f',
    edge: '#1f4e79',
    site: '#c0392b',
    delaunay: '#2e8b57',
    clip: '#e08a00',
    cells: ['#dbe9f6', '#fde7cf', '#dcefdc', '#efe0f3', '#fbf3c8', '#d9f0ee', '#f6dcdc'],
};
export const CELL_COLOURS = COLOR.cells.length;
const DELAUNAY_ALPHA = 0.6;
const MAX_ZOOM_IN = 1e7;    /* model units are the data's extent */
const MIN_ZOOM_OUT = 1e-4;
const CLICK_SLOP = 4;       /* CSS px a press may move and still be a click */
/* Layers with more items than this in view are stroked as one-device-
 * pixel hairlines, which the rasteriser draws fastest; fewer get bolder
 * lines. */
const HAIRLINE_ABOVE = 20000;
/* More sites in view than this are drawn as pixels, not discs. */
const DOTS_AS_PIXELS = 5000;
/* Items smaller than this on screen (device px) are plotted as pixels. */
const LOD_PX = 1.5;
/* Script time of one slice of a frame, and items between time checks.
 * The rasterising that follows a slice is measured too: when script and
 * rasterising together exceed TASK_MS, the next slices get less script
 * time (down to MIN_SLICE_MS), and more again when there is room. */
const SLICE_MS = 12;
const MIN_SLICE_MS = 3;
const TASK_MS = 24;
const BLOCK = 2048;
/* Pixel images are composited in bands of this many rows, a task each. */
const BAND_ROWS = 128;
/* A frame that needed more than one slice is redrawn only once the view
 * has been still this long; meanwhile the preview follows the pointer. */
const SETTLE_MS = 140;

/* What to draw; the controls keep it in step with the Draw checkboxes. */
export const layers = { sites: true, edges: true, delaunay: false, clip: false };

/* An overlay draws instead of the diagram's layers (the step-through
 * replay, stepper.js): {draw(ov, layers)}, a generator like the layers'
 * (see overlayView for ov). The grid, the view and everything else stay. */
let overlay = null;

export function setOverlay(o) {
    overlay = o;
}

/* The prepared drawing of the last result (geometry.js prepare()). */
let geom = null;
/* Model frame: model = (world - c) * k. */
let frame = { cx: 0.5, cy: 0.5, k: 1 };
/* View: the model point at the canvas centre and CSS px per model unit. */
const view = { mx: 0, my: 0, zoom: 1, fitted: true };
let fitNext = true;

const canvas = $('diagram');
const ctx = canvas.getContext('2d');
let cssW = 1, cssH = 1, dpr = 1;

/* Off-screen canvases: the frame being drawn, and the last finished one
 * (with the world-to-device map it was drawn with) for previews. Read
 * back on every slice, so they are kept in memory rather than on a GPU. */
function offscreen() {
    const c = document.createElement('canvas');
    return { canvas: c, ctx: c.getContext('2d', { willReadFrequently: true }) };
}
let work = offscreen();
let shot = offscreen();
let shotMap = null;

/* Pixel buffers of the canvas's size: coverage counts of the edge layer
 * being plotted, and the RGBA image composited from it (or written
 * directly by the cells and the sites). */
let px = null;

function pixelBuffers(W, H) {
    if (px && px.W === W && px.H === H) return px;
    const c = document.createElement('canvas');
    c.width = W;
    c.height = H;
    const g = c.getContext('2d', { willReadFrequently: true }); /* kept in memory: drawn from into the frame */
    const img = g.createImageData(W, H);
    px = {
        W: W, H: H, canvas: c, ctx: g, img: img,
        rgba: new Uint32Array(img.data.buffer), cov: new Uint8Array(W * H),
    };
    return px;
}

/* '#rrggbb' and an alpha in [0, 1] as one RGBA word of ImageData. */
function packColour(hex, alpha) {
    const rgb = parseInt(hex.slice(1), 16);
    const a = Math.round(255 * alpha) & 0xff;
    return LITTLE_ENDIAN
        ? ((a << 24) | ((rgb & 0xff) << 16) | (rgb & 0xff00) | (rgb >>> 16)) >>> 0
        : ((rgb << 8) | a) >>> 0;
}

/* ---- the result --------------------------------------------------------- */

/* The next result is fitted to the window (a new source). */
export function fitNextResult() {
    fitNext = true;
}

/* Counts of what the current drawing holds, or null when there is none. */
export function geomInfo() {
    return geom ? { nVertices: geom.nVertices, nEdges: geom.nEdges, nTriangles: geom.nTriangles } : null;
}

/* Shows the diagram record D, prepared as G (prepared here when null).
 * Keeps the view where it was in world terms unless fitNext is set. A
 * preview (a clicked point before its diagram arrives) is drawn but not
 * published as the last result. Call drawNow() after. */
export function setResult(D, G, preview) {
    if (!preview) {
        pub.diagram = D;
        pub.lastResult = summary(D);
    }
    if (!G) G = prepare(D, CELL_COLOURS);
    /* keep the view's world centre and world scale across the change */
    const worldC = [view.mx / frame.k + frame.cx, view.my / frame.k + frame.cy];
    const worldZoom = view.zoom * frame.k;
    frame = G.frame;
    view.mx = (worldC[0] - frame.cx) * frame.k;
    view.my = (worldC[1] - frame.cy) * frame.k;
    view.zoom = worldZoom / frame.k;
    geom = G;
    if (fitNext || view.fitted) {
        fitView();
        fitNext = false;
    }
}

/* Shows a clicked point at once, before its diagram arrives. */
export function addPreviewPoint(p) {
    if (!geom) {
        setResult(pointsOnly([p]), null, true);
    } else {
        const ns = geom.ns + 1;
        const mxs = new Float64Array(ns), mys = new Float64Array(ns), dup = new Uint8Array(ns);
        mxs.set(geom.mxs); mys.set(geom.mys); dup.set(geom.dup);
        const x = (p[0] - frame.cx) * frame.k, y = (p[1] - frame.cy) * frame.k;
        mxs[ns - 1] = x;
        mys[ns - 1] = y;
        const b = geom.sitesBox;
        const box = [Math.min(b[0], x), Math.min(b[1], y), Math.max(b[2], x), Math.max(b[3], y)];
        geom = Object.assign({}, geom, { ns: ns, mxs: mxs, mys: mys, dup: dup, sitesBox: box });
    }
    view.fitted = false; /* the view stays put while points are added */
    drawNow();
}

export function clearResult() {
    geom = null;
    pub.lastResult = null;
    pub.diagram = null;
    drawNow();
}

/* ---- view ------------------------------------------------------------- */

function contentBox() {
    if (!geom || !geom.ns) return [-0.5, -0.5, 0.5, 0.5];
    let [x0, y0, x1, y1] = geom.sitesBox;
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

export function zoomAbout(factor, px0, py0) {
    view.fitted = false;
    const mx = view.mx + (px0 - cssW / 2) / view.zoom;
    const my = view.my - (py0 - cssH / 2) / view.zoom;
    view.zoom *= factor;
    clampZoom();
    view.mx = mx - (px0 - cssW / 2) / view.zoom;
    view.my = my + (py0 - cssH / 2) / view.zoom;
    scheduleDraw();
}

/* World units per CSS pixel at the current zoom. */
export function pixelSize() {
    return 1 / (view.zoom * frame.k);
}

/* CSS px -> world coordinates */
export function toWorld(px0, py0) {
    const mx = view.mx + (px0 - cssW / 2) / view.zoom;
    const my = view.my - (py0 - cssH / 2) / view.zoom;
    return [mx / frame.k + frame.cx, my / frame.k + frame.cy];
}

export function visibleWorld() {
    const a = toWorld(0, cssH), b = toWorld(cssW, 0);
    return [a[0], a[1], b[0], b[1]];
}

/* The map from model coordinates to device pixels of the current view:
 * X = a mx + bx, Y = by - a my. */
function modelMap() {
    const a = dpr * view.zoom;
    return { a: a, bx: dpr * (cssW / 2 - view.mx * view.zoom), by: dpr * (cssH / 2 + view.my * view.zoom) };
}

/* The same map from world coordinates, which survives a change of frame. */
function worldMap() {
    const m = modelMap();
    const A = m.a * frame.k;
    return { A: A, Bx: m.bx - A * frame.cx, By: m.by + A * frame.cy };
}

function publishView() {
    pub.view = { mx: view.mx, my: view.my, zoom: view.zoom, world: visibleWorld() };
}

/* ---- scheduling frames ---------------------------------------------------- */

let current = null;       /* the frame job in progress */
let version = 0;          /* counts the changes that need a new frame */
let lastVersion = -1;     /* the change the last finished frame shows */
let lastSlices = 0;       /* slices the last finished frame took */
let settleTimer = 0;
let drawPending = false;
let waiters = [];

/* Slices run as tasks of their own: a message to ourselves queues one
 * without setTimeout's clamping, and input still goes first. */
const slicePort = new MessageChannel();
let queued = null;
slicePort.port1.onmessage = () => {
    const j = queued;
    queued = null;
    if (j && j === current) runSlice(j);
};
function queueSlice(j) {
    queued = j;
    slicePort.port2.postMessage(0);
}

/* Starts a frame of the current view now; its first slice runs before
 * this returns (a small diagram is then on the canvas). Resolves when
 * the frame is on the canvas. */
export function drawNow() {
    clearTimeout(settleTimer);
    version++;
    const p = whenDrawn();
    startFrame();
    return p;
}

/* A promise of the end of the frame in progress (or of the next one). */
export function whenDrawn() {
    return new Promise((resolve) => waiters.push(resolve));
}

/* A frame for a change of view, at the next animation frame: at once for
 * a diagram that draws in one slice; for a bigger one, the preview now
 * and the full frame once the view is still. */
export function scheduleDraw() {
    version++;
    if (drawPending) return;
    drawPending = true;
    requestAnimationFrame(() => {
        drawPending = false;
        /* a frame started since (drawNow) already shows this change */
        if (current ? current.version === version : lastVersion === version) return;
        const t = performance.now();
        if (lastSlices > 1 || current) {
            if (current) current = null;
            showProgress(null);
            showPreview();
            clearTimeout(settleTimer);
            settleTimer = setTimeout(() => {
                whenDrawn().then(() => afterPaint(() => { pub.framePaintMs = performance.now() - t; }));
                startFrame();
            }, SETTLE_MS);
            return;
        }
        whenDrawn().then(() => afterPaint(() => { pub.framePaintMs = performance.now() - t; }));
        startFrame();
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
    if (lastSlices > 1) showPreview();
    drawNow();
}

/* The last finished frame, moved and scaled to the current view. */
function showPreview() {
    publishView();
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = COLOR.background;
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    if (!shotMap) return;
    const m = worldMap();
    const s = m.A / shotMap.A;
    if (!(s > 0 && isFinite(s))) return;
    ctx.setTransform(s, 0, 0, s, m.Bx - s * shotMap.Bx, m.By - s * shotMap.By);
    ctx.imageSmoothingEnabled = s < 1;
    ctx.drawImage(shot.canvas, 0, 0);
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.imageSmoothingEnabled = true;
}

function startFrame() {
    const W = canvas.width, H = canvas.height;
    if (work.canvas.width !== W || work.canvas.height !== H) {
        work.canvas.width = W;
        work.canvas.height = H;
    }
    publishView();
    const job = {
        W: W, H: H, dpr: dpr, cssW: cssW, cssH: cssH,
        map: modelMap(), world: worldMap(), g: geom, layers: Object.assign({}, layers), overlay: overlay, frame: frame,
        c: work.ctx, t0: performance.now(), scriptMs: 0, rasterMs: 0, slices: 0, version: version,
        stats: { edges: 0, rays: 0, edgePixels: 0, delaunay: 0, delaunayPixels: 0, cells: 0, cellPixels: 0, sites: 0 },
    };
    job.steps = frameSteps(job);
    current = job;
    pub.drawing = true;
    runSlice(job);
}

let sliceMs = SLICE_MS;

function runSlice(job) {
    const t0 = performance.now();
    let done = false;
    for (;;) {
        if (job.steps.next().done) { done = true; break; }
        if (performance.now() - t0 > sliceMs) break;
    }
    /* reading a pixel makes the canvas rasterise what was recorded, so
     * that cost falls in this slice rather than piling up for the last */
    const t1 = performance.now();
    job.c.getImageData(0, 0, 1, 1);
    const t2 = performance.now();
    if (t2 - t0 > TASK_MS) sliceMs = Math.max(MIN_SLICE_MS, sliceMs * 0.7);
    else if (t2 - t0 < TASK_MS / 2) sliceMs = Math.min(SLICE_MS, sliceMs * 1.25);
    job.rasterMs += t2 - t1;
    job.slices++;
    job.scriptMs += t2 - t0;
    if (job !== current) return;
    if (done) finishFrame(job);
    else {
        if (job.slices === 1) showPreview();
        showProgress(job);
        queueSlice(job);
    }
}

function finishFrame(job) {
    current = null;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.drawImage(work.canvas, 0, 0);
    const t = work;
    work = shot;
    shot = t;
    shotMap = job.world;
    lastSlices = job.slices;
    lastVersion = job.version;
    const s = job.stats;
    pub.edgesDrawn = s.edges + s.edgePixels + s.rays;
    pub.raysDrawn = s.rays;
    pub.delaunayEdgesDrawn = s.delaunay + s.delaunayPixels;
    pub.sitesDrawn = s.sites;
    pub.lod = {
        edges: { lines: s.edges + s.rays, pixels: s.edgePixels },
        delaunay: { lines: s.delaunay, pixels: s.delaunayPixels },
        cells: { paths: s.cells, pixels: s.cellPixels },
    };
    pub.frameMs = job.scriptMs;
    pub.frameRasterMs = job.rasterMs;
    pub.frameSlices = job.slices;
    pub.drawing = false;
    pub.drawCount = (pub.drawCount || 0) + 1;
    showProgress(null);
    const w = waiters;
    waiters = [];
    for (const f of w) f(job);
}

function showProgress(job) {
    const el = $('drawing');
    if (!el) return;
    if (!job) {
        el.hidden = true;
        return;
    }
    el.hidden = false;
    el.textContent = 'Drawing… ' + Math.min(99, Math.round(100 * job.progress / Math.max(1, job.total))) + '%';
}

/* ---- one frame, as a sequence of steps ----------------------------------- */

/* The steps of a frame: a generator that yields every BLOCK items or so,
 * where runSlice may stop until the next task. */
function* frameSteps(job) {
    const c = job.c, g = job.g, L = job.layers;
    c.setTransform(1, 0, 0, 1, 0, 0);
    c.globalAlpha = 1;
    c.fillStyle = COLOR.background;
    c.fillRect(0, 0, job.W, job.H);
    const labels = drawGrid(job);
    job.progress = 0;
    job.total = 1;
    if (job.overlay) {
        yield* job.overlay.draw(overlayView(job), L);
    } else if (g) {
        const m = job.map;
        /* the model rectangle in view */
        const vr = [-m.bx / m.a, (m.by - job.H) / m.a, (job.W - m.bx) / m.a, m.by / m.a];
        const runs = {
            cells: L.clip && g.cells ? visibleRuns(g.cells.index, vr) : null,
            delaunay: L.delaunay && g.delaunay ? visibleRuns(g.delaunay, vr) : null,
            voronoi: L.edges ? visibleRuns(g.voronoi, vr) : null,
        };
        job.total = (runs.cells ? runs.cells.count : 0) + (runs.delaunay ? runs.delaunay.count : 0) +
            (runs.voronoi ? runs.voronoi.count + g.rayLine.length : 0) + (L.sites ? g.ns : 0) + 1;
        if (runs.cells) yield* drawCells(job, runs.cells);
        if (runs.delaunay) {
            yield* drawSegments(job, runs.delaunay, g.dedges, g.mxs, g.mys, COLOR.delaunay, DELAUNAY_ALPHA,
                runs.delaunay.count > HAIRLINE_ABOVE ? 1 : 0.8 * job.dpr, 'delaunay');
        }
        if (runs.voronoi) {
            const width = runs.voronoi.count > HAIRLINE_ABOVE ? 1 : 1.15 * job.dpr;
            yield* drawSegments(job, runs.voronoi, g.ends, g.vx, g.vy, COLOR.edge, 1, width, 'edges');
            yield* drawRays(job, vr, width);
        }
        if (L.clip && g.clipBox) drawClipBox(job);
        if (L.sites && g.ns) yield* drawSites(job);
    }
    drawLabels(job, labels);
}

/* What an overlay draws with: the frame's context c (device pixels, no
 * transform), its size W x H, dpr, the world -> device map X(x), Y(y)
 * (through the model frame, so that offsets and scales of the data keep
 * their precision), scale (device px per world unit) and the visible
 * world rectangle [x0, y0, x1, y1]. */
function overlayView(job) {
    const m = job.map, fr = job.frame;
    const a = m.a, k = fr.k, cx = fr.cx, cy = fr.cy, bx = m.bx, by = m.by;
    const toWorld = (X, Y) => [(X - bx) / a / k + cx, (by - Y) / a / k + cy];
    const lo = toWorld(0, job.H), hi = toWorld(job.W, 0);
    job.c.setTransform(1, 0, 0, 1, 0, 0);
    return {
        c: job.c, W: job.W, H: job.H, dpr: job.dpr, scale: a * k,
        X: (x) => a * ((x - cx) * k) + bx,
        Y: (y) => by - a * ((y - cy) * k),
        world: [lo[0], lo[1], hi[0], hi[1]],
    };
}

/* The runs of a grid index (geometry.js) that can meet the model
 * rectangle vr: one per bucket row, plus the long items. */
function visibleRuns(ix, vr) {
    const G = ix.G;
    const clampG = (v) => Math.max(0, Math.min(G - 1, v));
    const gx0 = Math.floor((vr[0] - ix.x0) / ix.bw) - 1, gx1 = Math.floor((vr[2] - ix.x0) / ix.bw) + 1;
    const gy0 = Math.floor((vr[1] - ix.y0) / ix.bh) - 1, gy1 = Math.floor((vr[3] - ix.y0) / ix.bh) + 1;
    const list = [];
    let count = 0;
    if (gx1 >= 0 && gy1 >= 0 && gx0 < G && gy0 < G) {
        const a = clampG(gx0), b = clampG(gx1);
        for (let gy = clampG(gy0); gy <= clampG(gy1); gy++) {
            const s = ix.start[gy * G + a], e = ix.start[gy * G + b + 1];
            if (e > s) {
                list.push(ix.order, s, e);
                count += e - s;
            }
        }
    }
    if (ix.long.length) {
        list.push(ix.long, 0, ix.long.length);
        count += ix.long.length;
    }
    return { list: list, count: count };
}

/* Liang-Barsky: the part t in [t0, t1] of o + t d inside rectangle r, or
 * null. */
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

/* Composites the coverage counts in px.cov (within the dirty box d) onto
 * the frame in colour hex at opacity alpha, and clears them. */
function* compositeCoverage(job, d, hex, alpha) {
    if (d[0] > d[2]) return;
    const P = px, W = P.W;
    const lut = new Uint32Array(256);
    for (let n = 1; n < 256; n++) lut[n] = packColour(hex, alpha * Math.min(1, 0.45 * n));
    for (let y = d[1]; y <= d[3]; y++) {
        const row = y * W;
        for (let x = d[0]; x <= d[2]; x++) {
            const n = P.cov[row + x];
            P.rgba[row + x] = lut[n];
            P.cov[row + x] = 0;
        }
        if ((y & 63) === 63) yield;
    }
    yield* compositeImage(job, d);
}

/* Puts px.rgba within the dirty box d onto the frame, a band of rows at
 * a time. */
function* compositeImage(job, d) {
    const P = px;
    const w = d[2] - d[0] + 1;
    job.c.setTransform(1, 0, 0, 1, 0, 0);
    for (let y = d[1]; y <= d[3]; y += BAND_ROWS) {
        const h = Math.min(BAND_ROWS, d[3] - y + 1);
        P.ctx.putImageData(P.img, 0, 0, d[0], y, w, h);
        job.c.drawImage(P.canvas, d[0], y, w, h, d[0], y, w, h);
        yield;
    }
}

/* Segments from point p to point q for each item i of runs, with
 * p = pairs[2 i], q = pairs[2 i + 1] indices into (xs, ys): stroked in
 * blocks, or plotted as coverage when shorter than LOD_PX. */
function* drawSegments(job, runs, pairs, xs, ys, hex, alpha, width, stat) {
    const c = job.c, W = job.W, H = job.H;
    const a = job.map.a, bx = job.map.bx, by = job.map.by;
    const P = pixelBuffers(W, H), cov = P.cov;
    const d = [W, H, -1, -1]; /* dirty box of the coverage */
    const margin = 4, lim = 1e6;
    const rect = [-margin, -margin, W + margin, H + margin];
    /* counts left by a frame abandoned halfway */
    if (P.covDirty) P.cov.fill(0);
    P.covDirty = true;
    let lines = 0, pixels = 0, inBlock = 0;
    c.setTransform(1, 0, 0, 1, 0, 0);
    c.strokeStyle = hex;
    c.globalAlpha = alpha;
    c.lineWidth = width;
    c.lineJoin = 'round';
    c.beginPath();
    const list = runs.list;
    for (let r = 0; r < list.length; r += 3) {
        const arr = list[r], e = list[r + 2];
        for (let k = list[r + 1]; k < e; k++) {
            const i = arr[k];
            const p = pairs[2 * i], q = pairs[2 * i + 1];
            let x0 = a * xs[p] + bx, y0 = by - a * ys[p];
            let x1 = a * xs[q] + bx, y1 = by - a * ys[q];
            if (++inBlock === BLOCK) {
                c.stroke();
                c.beginPath();
                job.progress += inBlock;
                inBlock = 0;
                yield;
            }
            /* both ends beyond one side of the view: not shown */
            if ((x0 < -margin && x1 < -margin) || (x0 > W + margin && x1 > W + margin) ||
                (y0 < -margin && y1 < -margin) || (y0 > H + margin && y1 > H + margin)) continue;
            if (!(x0 === x0 && y0 === y0 && x1 === x1 && y1 === y1)) continue; /* NaN: an overflowed vertex */
            const dx = x1 - x0, dy = y1 - y0;
            const len = Math.max(Math.abs(dx), Math.abs(dy));
            if (len < LOD_PX) {
                /* a dot or two of coverage */
                const n = len < 0.5 ? 0 : (len < 1 ? 1 : 2);
                for (let s = 0; s <= n; s++) {
                    const t = n ? s / n : 0.5;
                    const xi = Math.floor(x0 + t * dx), yi = Math.floor(y0 + t * dy);
                    if (xi < 0 || yi < 0 || xi >= W || yi >= H) continue;
                    const o = yi * W + xi;
                    if (cov[o] < 255) cov[o]++;
                    if (xi < d[0]) d[0] = xi;
                    if (xi > d[2]) d[2] = xi;
                    if (yi < d[1]) d[1] = yi;
                    if (yi > d[3]) d[3] = yi;
                }
                pixels++;
                continue;
            }
            if (Math.abs(x0) > lim || Math.abs(y0) > lim || Math.abs(x1) > lim || Math.abs(y1) > lim) {
                const t = clipRay(x0, y0, dx, dy, 0, 1, rect);
                if (!t) continue;
                x1 = x0 + t[1] * dx;
                y1 = y0 + t[1] * dy;
                x0 += t[0] * dx;
                y0 += t[0] * dy;
            }
            c.moveTo(x0, y0);
            c.lineTo(x1, y1);
            lines++;
        }
    }
    c.stroke();
    c.globalAlpha = 1;
    job.progress += inBlock;
    job.stats[stat] += lines;
    job.stats[stat === 'edges' ? 'edgePixels' : 'delaunayPixels'] += pixels;
    yield* compositeCoverage(job, d, hex, alpha);
    P.covDirty = false;
}

/* Rays and lines, clipped to the view in model coordinates (in double
 * precision) before anything reaches the rasteriser. */
function* drawRays(job, vr, width) {
    const g = job.g, c = job.c, n = g.rayLine.length;
    if (!n) return;
    const a = job.map.a, bx = job.map.bx, by = job.map.by;
    const m = 4 / a * job.dpr;
    const r = [vr[0] - m, vr[1] - m, vr[2] + m, vr[3] + m];
    c.setTransform(1, 0, 0, 1, 0, 0);
    c.strokeStyle = COLOR.edge;
    c.lineWidth = width;
    c.beginPath();
    let drawn = 0;
    for (let i = 0; i < n; i++) {
        const ox = g.rayO[2 * i], oy = g.rayO[2 * i + 1], dx = g.rayD[2 * i], dy = g.rayD[2 * i + 1];
        const t = clipRay(ox, oy, dx, dy, g.rayLine[i] ? -Infinity : 0, Infinity, r);
        if (t) {
            c.moveTo(a * (ox + t[0] * dx) + bx, by - a * (oy + t[0] * dy));
            c.lineTo(a * (ox + t[1] * dx) + bx, by - a * (oy + t[1] * dy));
            drawn++;
        }
        if ((i + 1) % BLOCK === 0) {
            c.stroke();
            c.beginPath();
            job.progress += BLOCK;
            yield;
        }
    }
    c.stroke();
    job.stats.rays += drawn;
}

/* Clipped cells, filled in their colours: as paths, one fill per colour
 * and block, or as their box's pixels when smaller than LOD_PX. */
function* drawCells(job, runs) {
    const g = job.g, c = job.c, W = job.W, H = job.H;
    const a = job.map.a, bx = job.map.bx, by = job.map.by;
    const st = g.cells.start, cxy = g.cells.xy, colour = g.cells.colour;
    const P = pixelBuffers(W, H), rgba = P.rgba;
    const words = COLOR.cells.map((h) => packColour(h, 1));
    const d = [W, H, -1, -1];
    const lim = 1e6;
    let paths = COLOR.cells.map(() => new Path2D());
    let nPath = 0, nPix = 0, inBlock = 0;
    const flush = () => {
        c.setTransform(1, 0, 0, 1, 0, 0);
        paths.forEach((p, i) => {
            c.fillStyle = COLOR.cells[i];
            c.fill(p);
        });
        paths = COLOR.cells.map(() => new Path2D());
    };
    /* the pixel image starts clear where it will be written */
    rgba.fill(0);
    const list = runs.list;
    for (let r = 0; r < list.length; r += 3) {
        const arr = list[r], e = list[r + 2];
        for (let k = list[r + 1]; k < e; k++) {
            const i = arr[k];
            if (++inBlock === BLOCK) {
                flush();
                job.progress += inBlock;
                inBlock = 0;
                yield;
            }
            const s = st[i], t = st[i + 1];
            let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
            for (let j = s; j < t; j++) {
                const x = a * cxy[2 * j] + bx, y = by - a * cxy[2 * j + 1];
                if (x < x0) x0 = x;
                if (x > x1) x1 = x;
                if (y < y0) y0 = y;
                if (y > y1) y1 = y;
            }
            if (x1 < 0 || y1 < 0 || x0 > W || y0 > H || !(x0 <= x1)) continue;
            if (x1 - x0 < LOD_PX && y1 - y0 < LOD_PX) {
                const word = words[colour[i]];
                const xa = Math.max(0, Math.floor(x0)), xb = Math.min(W - 1, Math.floor(x1));
                const ya = Math.max(0, Math.floor(y0)), yb = Math.min(H - 1, Math.floor(y1));
                for (let y = ya; y <= yb; y++) for (let x = xa; x <= xb; x++) rgba[y * W + x] = word;
                if (xa < d[0]) d[0] = xa;
                if (xb > d[2]) d[2] = xb;
                if (ya < d[1]) d[1] = ya;
                if (yb > d[3]) d[3] = yb;
                nPix++;
                continue;
            }
            const path = paths[colour[i]];
            if (x0 < -lim || y0 < -lim || x1 > lim || y1 > lim) {
                /* zoomed in far: only the part in view reaches the path */
                const poly = [];
                for (let j = s; j < t; j++) poly.push([a * cxy[2 * j] + bx, by - a * cxy[2 * j + 1]]);
                const part = clipPolygon(poly, [-8, -8, W + 8, H + 8]);
                if (part.length < 3) continue;
                path.moveTo(part[0][0], part[0][1]);
                for (let j = 1; j < part.length; j++) path.lineTo(part[j][0], part[j][1]);
            } else {
                path.moveTo(a * cxy[2 * s] + bx, by - a * cxy[2 * s + 1]);
                for (let j = s + 1; j < t; j++) path.lineTo(a * cxy[2 * j] + bx, by - a * cxy[2 * j + 1]);
            }
            path.closePath();
            nPath++;
        }
    }
    flush();
    job.progress += inBlock;
    job.stats.cells += nPath;
    job.stats.cellPixels += nPix;
    if (d[0] <= d[2]) yield* compositeImage(job, d);
}

/* Sutherland-Hodgman: the convex polygon pts ([[x, y], ...]) cut to the
 * rectangle r. */
function clipPolygon(pts, r) {
    const edges = [
        (p) => p[0] >= r[0], (p) => p[0] <= r[2], (p) => p[1] >= r[1], (p) => p[1] <= r[3],
    ];
    const cut = [
        (p, q) => [r[0], p[1] + (q[1] - p[1]) * (r[0] - p[0]) / (q[0] - p[0])],
        (p, q) => [r[2], p[1] + (q[1] - p[1]) * (r[2] - p[0]) / (q[0] - p[0])],
        (p, q) => [p[0] + (q[0] - p[0]) * (r[1] - p[1]) / (q[1] - p[1]), r[1]],
        (p, q) => [p[0] + (q[0] - p[0]) * (r[3] - p[1]) / (q[1] - p[1]), r[3]],
    ];
    let out = pts;
    for (let k = 0; k < 4 && out.length; k++) {
        const inp = out;
        out = [];
        for (let i = 0; i < inp.length; i++) {
            const p = inp[i], q = inp[(i + 1) % inp.length];
            const pin = edges[k](p), qin = edges[k](q);
            if (pin) out.push(p);
            if (pin !== qin) out.push(cut[k](p, q));
        }
    }
    return out;
}

function drawClipBox(job) {
    const b = job.g.clipBox, m = job.map, c = job.c;
    const x0 = m.a * b[0] + m.bx, x1 = m.a * b[2] + m.bx;
    const y0 = m.by - m.a * b[3], y1 = m.by - m.a * b[1];
    const lim = 1e6, cl = (v) => Math.max(-lim, Math.min(lim, v));
    c.save();
    c.setTransform(1, 0, 0, 1, 0, 0);
    c.strokeStyle = COLOR.clip;
    c.lineWidth = 1.5 * job.dpr;
    c.setLineDash([6 * job.dpr, 4 * job.dpr]);
    c.strokeRect(cl(x0), cl(y0), cl(x1) - cl(x0), cl(y1) - cl(y0));
    c.restore();
}

/* Sites: small discs, culled, one fill, while few are in view; else
 * square dots written straight into the pixel image and composited in
 * one drawImage, since 10^5 anti-aliased shapes cost the rasteriser far
 * more than 10^5 stores. */
function* drawSites(job) {
    const g = job.g, c = job.c, W = job.W, H = job.H;
    const a = job.map.a, bx = job.map.bx, by = job.map.by;
    const ns = g.ns, mxs = g.mxs, mys = g.mys, dup = g.dup;
    /* how many are in view decides discs or pixels */
    let inView = 0;
    for (let i = 0; i < ns; i++) {
        const x = a * mxs[i] + bx, y = by - a * mys[i];
        if (x >= 0 && y >= 0 && x < W && y < H && !dup[i]) inView++;
        if ((i + 1) % (16 * BLOCK) === 0) yield;
    }
    let drawn = 0;
    if (inView <= DOTS_AS_PIXELS) {
        const r = (inView <= 200 ? 3 : (inView <= 2000 ? 2.3 : 1.6)) * job.dpr;
        const path = new Path2D();
        for (let i = 0; i < ns; i++) {
            if (dup[i]) continue;
            const x = a * mxs[i] + bx, y = by - a * mys[i];
            if (x < -r || y < -r || x > W + r || y > H + r) continue;
            path.moveTo(x + r, y);
            path.arc(x, y, r, 0, 2 * Math.PI);
            drawn++;
        }
        c.setTransform(1, 0, 0, 1, 0, 0);
        c.fillStyle = COLOR.site;
        c.fill(path);
        job.progress += ns;
    } else {
        const P = pixelBuffers(W, H), rgba = P.rgba;
        rgba.fill(0);
        const word = packColour(COLOR.site, 1);
        /* dense: one pixel per site, or the dots merge into a carpet */
        const z = a / job.dpr;
        const density = ns / (g.area * z * z);
        const size = (density > 0.04 ? 1 : 2) + (job.dpr >= 2 ? 1 : 0);
        const d = [W, H, -1, -1];
        for (let i = 0; i < ns; i++) {
            if ((i + 1) % (8 * BLOCK) === 0) {
                job.progress += 8 * BLOCK;
                yield;
            }
            if (dup[i]) continue;
            const x = Math.round(a * mxs[i] + bx - size / 2);
            const y = Math.round(by - a * mys[i] - size / 2);
            if (x < 0 || y < 0 || x > W - size || y > H - size) continue;
            for (let dy = 0; dy < size; dy++) {
                const row = (y + dy) * W + x;
                for (let dx = 0; dx < size; dx++) rgba[row + dx] = word;
            }
            if (x < d[0]) d[0] = x;
            if (x + size - 1 > d[2]) d[2] = x + size - 1;
            if (y < d[1]) d[1] = y;
            if (y + size - 1 > d[3]) d[3] = y + size - 1;
            drawn++;
        }
        if (d[0] <= d[2]) yield* compositeImage(job, d);
    }
    job.stats.sites = drawn;
}

/* Grid lines at round world coordinates under the diagram; returns
 * their labels, which drawLabels() writes over everything. */
function drawGrid(job) {
    const c = job.c, w = job.world, cW = job.cssW, cH = job.cssH;
    /* world coordinates of the view's corners, from the world map */
    const A = w.A / job.dpr, Bx = w.Bx / job.dpr, By = w.By / job.dpr;
    const wx0 = (0 - Bx) / A, wx1 = (cW - Bx) / A, wy0 = (By - cH) / A, wy1 = By / A;
    const spanX = wx1 - wx0;
    if (!(spanX > 0) || !isFinite(spanX)) return [];
    const target = spanX / Math.max(2, cW / 110);
    const mag = Math.pow(10, Math.floor(Math.log10(target)));
    const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= target) || 10 * mag;
    c.save();
    c.setTransform(job.dpr, 0, 0, job.dpr, 0, 0);
    c.lineWidth = 1;
    const sxOf = (x) => A * x + Bx;
    const syOf = (y) => By - A * y;
    const path = new Path2D(), axes = new Path2D();
    const labels = [];
    const i0 = Math.ceil(wx0 / step), i1 = Math.floor(wx1 / step);
    if (i1 - i0 < 200) {
        for (let i = i0; i <= i1; i++) {
            const x = i * step, s = Math.round(sxOf(x)) + 0.5;
            (i === 0 ? axes : path).moveTo(s, 0);
            (i === 0 ? axes : path).lineTo(s, cH);
            labels.push([fmtCoord(x, step), s + 3, cH - 4, 'left']);
        }
    }
    const j0 = Math.ceil(wy0 / step), j1 = Math.floor(wy1 / step);
    if (j1 - j0 < 200) {
        for (let j = j0; j <= j1; j++) {
            const y = j * step, s = Math.round(syOf(y)) + 0.5;
            (j === 0 ? axes : path).moveTo(0, s);
            (j === 0 ? axes : path).lineTo(cW, s);
            labels.push([fmtCoord(y, step), 3, s - 3, 'left']);
        }
    }
    c.strokeStyle = COLOR.grid;
    c.stroke(path);
    c.strokeStyle = COLOR.gridAxis;
    c.stroke(axes);
    c.restore();
    return labels;
}

function drawLabels(job, labels) {
    const c = job.c;
    c.save();
    c.setTransform(job.dpr, 0, 0, job.dpr, 0, 0);
    c.font = '11px system-ui, sans-serif';
    c.lineJoin = 'round';
    c.lineWidth = 3;
    c.strokeStyle = 'rgba(251, 251, 248, 0.85)';
    c.fillStyle = COLOR.gridText;
    for (const l of labels) {
        c.textAlign = l[3];
        c.strokeText(l[0], l[1], l[2]);
        c.fillText(l[0], l[1], l[2]);
    }
    c.restore();
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
