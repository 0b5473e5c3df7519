/* controls.js -- the left panel: where the points come from, Compute, the
 * timings, what to draw, and the downloads.
 *
 * What it does: keeps the current point source (the generator form, an
 * uploaded file sent as it is, a JSON file, or points clicked onto the
 * diagram), builds the compute request from it and the form (algorithm,
 * clip box, parts to draw), sends it, hands the answer to the decoder and
 * the renderer, and shows the server's timings next to the round trip.
 * Up to BINARY_ABOVE points it asks for JSON with only the parts it draws
 * and reads it here; above, for the binary diagram, which the worker
 * fetches, decodes and prepares (decode.js fetchDiagram) so that the page
 * never waits on it.
 *
 * Invariants: at most one compute request is in flight (a new one aborts
 * the old, jobs.compute holds its AbortController); renderer.layers
 * matches the Draw checkboxes before anything is drawn.
 */
import {
    $, pub, jobs, ALGO_LABEL, PHASE_COLOR, LITTLE_ENDIAN,
    fmtMs, fmtInt, fmtBytes, roundTo, fmtCoord,
} from './util.js';
import {
    ServiceError, send, buildRequest, isAbort, parseServerTiming, timingOf,
} from './api.js';
import { fromJson, unreadable, fetchDiagram } from './decode.js';
import { prepare } from './geometry.js';
import { setStatus, setBusy, showError, clearError } from './status.js';
import {
    layers, setResult, clearResult, drawNow, scheduleDraw, afterPaint, geomInfo, CELL_COLOURS,
    fitNextResult, addPreviewPoint, toWorld, visibleWorld, pixelSize, attachInteraction,
} from './renderer.js';

const CLICK_RECOMPUTE_LIMIT = 200000;
/* Above this many points the page asks for the binary answer. */
const BINARY_ABOVE = 20000;

/* ---- point source -----------------------------------------------------
 * {kind: 'generate'}                      parameters read from the form
 * {kind: 'points', points, label}         explicit [[x, y], ...]
 * {kind: 'json', obj, name}               a JSON request body from a file
 * {kind: 'file', name, type, data, size}  bytes sent as they are */
let source = { kind: 'generate' };

export function selectedAlgorithm() {
    const r = document.querySelector('input[name=algorithm]:checked');
    return r ? r.value : 'fortune';
}

export function genParams() {
    const n = Math.max(0, Math.floor(Number($('n').value) || 0));
    const seed = Math.max(0, Math.floor(Number($('seed').value) || 0));
    return { distribution: $('distribution').value, n: n, seed: seed };
}

/* The source as api.js sends it: the generator form read now. */
export function requestSource() {
    return source.kind === 'generate' ? { kind: 'gen', generate: genParams() } : source;
}

/* The clip box from the form: null when not clipping or when the field
 * is empty (the service then clips to a margin around the sites);
 * throws a ServiceError when the text is not four numbers. */
export function clipBounds() {
    if (!$('show-clip').checked) return null;
    const text = $('bounds').value.trim();
    if (text === '') return null; /* the service picks a box around the sites */
    const parts = text.split(/[\s,;]+/).filter(Boolean).map(Number);
    if (parts.length !== 4 || !parts.every(isFinite)) {
        throw new ServiceError({
            title: 'Clip box needs four numbers',
            detail: 'Type xmin, ymin, xmax, ymax into the box field, or press "Use view".',
        });
    }
    return parts;
}

export function syncLayers() {
    layers.sites = $('show-sites').checked;
    layers.edges = $('show-edges').checked;
    layers.delaunay = $('show-delaunay').checked;
    layers.clip = $('show-clip').checked;
}

/* ---- compute ------------------------------------------------------------ */

function includeParts() {
    const parts = ['sites', 'vertices', 'edges'];
    if ($('show-delaunay').checked) parts.push('triangles');
    if ($('show-clip').checked) parts.push('clipped');
    return parts;
}

/* The placeholder of the box field shows the box the service chose. */
function showAutoBox(D) {
    const box = D.clip && D.clip.box;
    if (box && !$('bounds').value.trim()) {
        const tol = Math.max(box[2] - box[0], box[3] - box[1]) * 1e-6;
        $('bounds').placeholder = 'auto: ' + box.map((v) => +roundTo(v, tol).toPrecision(10)).join(', ');
    }
}

/* On a phone the diagram sits above the controls: when the user asks for
 * a diagram from down there, it is brought into view. */
export function revealDiagram() {
    if (!window.matchMedia('(max-width: 720px)').matches) return;
    const top = $('view').getBoundingClientRect().top;
    if (top >= 0 && top < window.innerHeight / 3) return;
    const smooth = !window.matchMedia('(prefers-reduced-motion: reduce)').matches;
    $('view').scrollIntoView({ block: 'start', behavior: smooth ? 'smooth' : 'auto' });
}

/* Another mode may take over what Compute does (the step-through
 * replay, stepper.js): hooks.compute(opts) returns true when it did. */
export const hooks = { compute: null };

/* Computes the diagram of the current source with the form's options.
 * opts.reveal: the user asked (Compute, Generate), so on a phone the
 * diagram is scrolled into view. */
export async function compute(opts) {
    if (opts && opts.reveal) revealDiagram();
    clearTimeout(genTimer);
    if (hooks.compute && hooks.compute(opts || {})) return;
    clearError();
    syncLayers();
    const asked = describeSource();
    if (jobs.compute) jobs.compute.abort();
    const abort = new AbortController();
    jobs.compute = abort;
    const alg = selectedAlgorithm();
    setBusy(true, 'Computing with ' + ALGO_LABEL[alg] + '…');
    try {
        /* large answers come as binary arrays: no text to parse, and they
         * are fetched, decoded and prepared off the page's thread */
        const binary = LITTLE_ENDIAN && expectedPoints(source) > BINARY_ABOVE;
        const opt = {
            algorithm: alg, bounds: clipBounds(),
            include: includeParts(), format: binary ? 'binary' : 'json', signal: abort.signal,
        };
        const t0 = performance.now();
        let D, G = null, serverTiming;
        if (binary) {
            const out = await fetchDiagram(buildRequest('voronoi', Object.assign({}, opt, { signal: undefined }), requestSource()),
                abort.signal, true, CELL_COLOURS, prepare);
            D = out.D;
            G = out.G;
            serverTiming = out.serverTiming;
            pub.decodedIn = out.where;
        } else {
            const r = await send('voronoi', opt, requestSource());
            let res;
            try {
                res = JSON.parse(r.text);
            } catch (e) {
                throw unreadable('is not JSON the page can parse (' + e.message + ')');
            }
            D = fromJson(res);
            serverTiming = r.resp.headers.get('server-timing');
            pub.decodedIn = 'page';
        }
        const roundtrip = performance.now() - t0;
        if (abort !== jobs.compute) return;
        const td = performance.now();
        setResult(D, G);
        markStale(false, asked);
        showAutoBox(D);
        const drawn = drawNow();
        const phases = parseServerTiming(serverTiming);
        showTimings(D, roundtrip, null, phases);
        const count = ++pub.computeCount;
        drawn.then(() => afterPaint(() => {
            if (count !== pub.computeCount) return;
            const drawMs = performance.now() - td;
            $('t-draw').textContent = fmtMs(drawMs);
            pub.timings.draw_ms = drawMs;
        }));
        setStatus((ALGO_LABEL[D.algorithm] || D.algorithm) + ': ' + fmtInt(D.nSites) + ' sites, computed in ' +
            fmtMs(timingOf(D, 'compute')));
    } catch (e) {
        if (isAbort(e)) return;
        showError(e);
    } finally {
        if (abort === jobs.compute) {
            jobs.compute = null;
            setBusy(false);
        }
    }
}

/* How many points a source will send, as far as the page can tell
 * before asking (a raw file is estimated from its size). */
export function expectedPoints(src) {
    if (src.kind === 'generate') return genParams().n;
    if (src.kind === 'gen') return src.generate.n;
    if (src.kind === 'points') return src.points.length;
    if (src.kind === 'json') {
        const o = src.obj;
        if (Array.isArray(o.points)) return o.points.length;
        return o.generate ? Number(o.generate.n) || 0 : 0;
    }
    return src.type === 'application/octet-stream' ? src.size / 16 : src.size / 12;
}

export function showTimings(res, roundtrip, drawMs, phases) {
    const server = timingOf(res, 'compute');
    $('t-compute').textContent = fmtMs(server);
    $('t-roundtrip').textContent = fmtMs(roundtrip);
    $('t-draw').textContent = fmtMs(drawMs);
    let list = phases.filter((p) => p.dur != null && isFinite(p.dur));
    if (list.length === 0 && res.timings) {
        /* no Server-Timing header (a proxy may drop it): use the body */
        list = Object.keys(res.timings).map((k) => ({ name: k.replace(/_ms$/, ''), dur: res.timings[k] }))
            .filter((p) => typeof p.dur === 'number');
    }
    const total = list.find((p) => p.name === 'total');
    const parts = list.filter((p) => p.name !== 'total');
    const box = $('phases');
    box.textContent = '';
    if (parts.length) {
        const sum = parts.reduce((a, p) => a + Math.max(0, p.dur), 0) || 1;
        const bar = document.createElement('div');
        bar.className = 'bar';
        for (const p of parts) {
            const s = document.createElement('span');
            s.style.width = (100 * Math.max(0, p.dur) / sum) + '%';
            s.style.background = PHASE_COLOR[p.name] || '#b7bdb3';
            s.title = p.name + ' ' + fmtMs(p.dur);
            bar.appendChild(s);
        }
        box.appendChild(bar);
    }
    const ul = document.createElement('ul');
    const item = (name, ms, color) => {
        const li = document.createElement('li');
        if (!color) li.className = 'sum';
        const key = document.createElement('span');
        key.className = 'key';
        key.style.background = color || 'transparent';
        const label = document.createElement('span');
        label.textContent = name;
        const val = document.createElement('span');
        val.className = 'ms';
        val.textContent = fmtMs(ms);
        li.append(key, label, val);
        ul.appendChild(li);
    };
    for (const p of parts) item(p.name, p.dur, PHASE_COLOR[p.name] || '#b7bdb3');
    if (total) {
        item('server total', total.dur, null);
        item('network + page', Math.max(0, roundtrip - total.dur), null);
        ul.lastChild.title = 'Round trip less the server total: transfer and decoding in the page';
    }
    box.appendChild(ul);
    pub.timings = { server_ms: server, roundtrip_ms: roundtrip, draw_ms: drawMs, phases: list };

    const bits = [fmtInt(res.nInput) + ' points', fmtInt(res.nSites) + ' sites'];
    if (res.dups.length) bits.push(fmtInt(res.dups.length) + ' duplicates');
    const g = geomInfo();
    if (g) {
        bits.push(fmtInt(g.nVertices) + ' vertices', fmtInt(g.nEdges) + ' edges');
        if (g.nTriangles) bits.push(fmtInt(g.nTriangles) + ' triangles');
    }
    if (res.format === 'binary') bits.push('binary answer');
    $('counts').textContent = bits.join(' · ');
}

/* ---- sources ------------------------------------------------------------ */

/* Up to this many points a change of distribution, N or seed recomputes
 * by itself, once the input has been still for GEN_DEBOUNCE_MS; above,
 * the diagram is marked out of date until Compute is pressed. */
const AUTO_RECOMPUTE_MAX = 20000;
const GEN_DEBOUNCE_MS = 350;
let genTimer = 0;
/* What the diagram on the canvas shows (describeSource's text). */
let shown = null;

function generatorChanged() {
    setSource({ kind: 'generate' }, true);
    clearTimeout(genTimer);
    if (genParams().n <= AUTO_RECOMPUTE_MAX) {
        genTimer = setTimeout(compute, GEN_DEBOUNCE_MS);
        markStale(false);
    } else {
        markStale(true);
    }
}

/* Marks the diagram as out of date (or not), saying what it shows and
 * what Compute would draw; text, when given, is what it shows now. */
export function markStale(on, text) {
    if (text !== undefined) shown = text;
    on = on && shown !== null;
    pub.stale = on;
    $('canvas-wrap').classList.toggle('stale', on);
    $('stale').hidden = !on;
    if (on) {
        $('stale-text').textContent = 'Out of date: the diagram shows ' + shown + '. Compute draws ' +
            pub.source.text + '.';
    }
}

export function describeSource() {
    let text;
    if (source.kind === 'generate') {
        const g = genParams();
        const name = $('distribution').selectedOptions[0].textContent;
        text = 'generated ' + name + ', N = ' + fmtInt(g.n) + ', seed ' + g.seed;
    } else if (source.kind === 'file') {
        text = 'file ' + source.name + ' (' + fmtBytes(source.size) + ')';
    } else if (source.kind === 'json') {
        text = 'file ' + source.name + ' (JSON request)';
    } else {
        text = source.label + ': ' + fmtInt(source.points.length) + ' points';
    }
    $('source').textContent = 'Source: ' + text;
    pub.source = { kind: source.kind, text: text };
    return text;
}

function setSource(s, fit) {
    source = s;
    if (fit) fitNextResult();
    describeSource();
}

/* Points out of a parsed JSON file: an array of [x, y] or {x, y}, or
 * GeoJSON points. null when the file is some other JSON object (it is
 * then sent as a request body of its own). */
function pointsFromJson(obj) {
    const fromList = (list) => list.map((p) => (p && !Array.isArray(p) && typeof p === 'object' && 'x' in p) ? [p.x, p.y] : p);
    if (Array.isArray(obj)) return fromList(obj);
    if (!obj || typeof obj !== 'object') return null;
    const out = [];
    const geo = (g) => {
        if (!g) return;
        if (g.type === 'Point') out.push(g.coordinates);
        else if (g.type === 'MultiPoint') out.push(...g.coordinates);
        else if (g.type === 'GeometryCollection') (g.geometries || []).forEach(geo);
    };
    if (obj.type === 'FeatureCollection') {
        (obj.features || []).forEach((f) => geo(f && f.geometry));
        return out;
    }
    if (obj.type === 'Feature') { geo(obj.geometry); return out; }
    if (obj.type === 'Point' || obj.type === 'MultiPoint' || obj.type === 'GeometryCollection') { geo(obj); return out; }
    return null;
}

async function loadFile(file) {
    clearError();
    const lower = file.name.toLowerCase();
    try {
        if (/\.(json|geojson)$/.test(lower) || /json/.test(file.type)) {
            const text = await file.text();
            let obj;
            try {
                obj = JSON.parse(text);
            } catch (e) {
                /* the service explains what is wrong with it, with a line */
                setSource({ kind: 'file', name: file.name, type: 'application/json', data: text, size: file.size }, true);
                return compute({ reveal: true });
            }
            const pts = pointsFromJson(obj);
            if (pts) setSource({ kind: 'points', points: pts, label: file.name }, true);
            else if (obj && typeof obj === 'object') setSource({ kind: 'json', obj: obj, name: file.name }, true);
            else setSource({ kind: 'file', name: file.name, type: 'application/json', data: text, size: file.size }, true);
        } else if (/\.(bin|f64)$/.test(lower)) {
            const data = await file.arrayBuffer();
            setSource({ kind: 'file', name: file.name, type: 'application/octet-stream', data: data, size: file.size }, true);
        } else {
            const data = await file.text();
            const type = /\.csv$/.test(lower) || file.type === 'text/csv' ? 'text/csv' : 'text/plain';
            setSource({ kind: 'file', name: file.name, type: type, data: data, size: file.size }, true);
        }
    } catch (e) {
        showError(new ServiceError({ title: 'Cannot read the file', detail: file.name + ': ' + e.message }));
        return;
    }
    return compute({ reveal: true });
}

/* Adds a clicked point (rounded to the screen's resolution); the source
 * becomes the explicit list of the current sites plus the new point. */
let clickTimer = 0;
function addPoint(px, py) {
    const w = toWorld(px, py);
    const tol = pixelSize();
    const p = [roundTo(w[0], tol), roundTo(w[1], tol)].map((v) => +v.toPrecision(15));
    if (source.kind !== 'points') {
        const base = [];
        const D = pub.diagram;
        if (D) {
            for (let i = 0; i < D.xy.length / 2; i++) base.push([D.xy[2 * i], D.xy[2 * i + 1]]);
        }
        setSource({ kind: 'points', points: base, label: 'edited points' }, false);
    }
    source.points.push(p);
    describeSource();
    /* show the point at once; the diagram follows */
    addPreviewPoint(p);
    if (source.points.length <= CLICK_RECOMPUTE_LIMIT) {
        clearTimeout(clickTimer);
        clickTimer = setTimeout(compute, 120);
    }
}

/* ---- download ----------------------------------------------------------- */

async function download(format) {
    clearError();
    const ext = { json: 'json', geojson: 'geojson', svg: 'svg' }[format];
    const include = format === 'json' ? ['sites', 'vertices', 'edges', 'cells'].concat(
        $('show-delaunay').checked ? ['triangles'] : [], $('show-clip').checked ? ['clipped'] : []) : null;
    setBusy(true, 'Preparing ' + format.toUpperCase() + '…');
    try {
        const r = await send('voronoi', {
            algorithm: selectedAlgorithm(), bounds: clipBounds(), include: include, format: format, blob: true,
        }, requestSource());
        const a = document.createElement('a');
        a.href = URL.createObjectURL(r.blob);
        a.download = 'voronoi-' + selectedAlgorithm() + '.' + ext;
        document.body.appendChild(a);
        a.click();
        a.remove();
        setTimeout(() => URL.revokeObjectURL(a.href), 10000);
        pub.downloadCount++;
        setStatus('Downloaded ' + a.download + ' (' + fmtBytes(r.blob.size) + ')');
    } catch (e) {
        if (!isAbort(e)) showError(e);
    } finally {
        setBusy(!!jobs.compute);
    }
}

/* ---- wiring ------------------------------------------------------------- */

export function wireControls() {
    $('compute-form').addEventListener('submit', (ev) => {
        ev.preventDefault();
        compute({ reveal: true });
    });
    for (const r of document.querySelectorAll('input[name=algorithm]')) {
        r.addEventListener('change', () => { if (pub.lastResult || source.kind !== 'generate') compute(); });
    }
    for (const id of ['distribution', 'n', 'seed']) {
        $(id).addEventListener('input', generatorChanged);
        $(id).addEventListener('change', generatorChanged);
    }
    $('n').addEventListener('keydown', (ev) => {
        if (ev.key !== 'Enter') return;
        ev.preventDefault();
        setSource({ kind: 'generate' }, true);
        compute({ reveal: true });
    });
    $('stale-compute').addEventListener('click', () => compute());
    $('generate').addEventListener('click', () => {
        setSource({ kind: 'generate' }, true);
        compute({ reveal: true });
    });
    $('new-seed').addEventListener('click', () => {
        $('seed').value = String(Math.floor(Math.random() * 1e6));
        setSource({ kind: 'generate' }, true);
        compute({ reveal: true });
    });
    $('file').addEventListener('change', () => {
        const f = $('file').files[0];
        if (f) loadFile(f).finally(() => { $('file').value = ''; });
    });
    $('clear-points').addEventListener('click', () => {
        clearTimeout(clickTimer);
        if (jobs.compute) jobs.compute.abort();
        setSource({ kind: 'points', points: [], label: 'clicked points' }, false);
        clearResult();
        $('counts').textContent = '';
        setStatus('Cleared: click on the diagram to add points');
    });
    $('show-sites').addEventListener('change', () => { syncLayers(); scheduleDraw(); });
    $('show-edges').addEventListener('change', () => { syncLayers(); scheduleDraw(); });
    $('show-delaunay').addEventListener('change', () => {
        syncLayers();
        if ($('show-delaunay').checked && pub.diagram && !pub.diagram.tri) compute();
        else scheduleDraw();
    });
    $('show-clip').addEventListener('change', () => {
        syncLayers();
        if (pub.lastResult) compute();
        else scheduleDraw();
    });
    $('bounds').addEventListener('change', () => {
        if ($('show-clip').checked && pub.lastResult) compute();
    });
    $('bounds').addEventListener('keydown', (ev) => {
        if (ev.key !== 'Enter') return;
        ev.preventDefault();
        $('show-clip').checked = true;
        compute();
    });
    $('bounds-view').addEventListener('click', () => {
        const w = visibleWorld();
        const tol = (w[2] - w[0]) * 1e-4;
        $('bounds').value = w.map((v) => +roundTo(v, tol).toPrecision(12)).join(', ');
        $('show-clip').checked = true;
        if (pub.lastResult) compute();
    });
    $('error-close').addEventListener('click', clearError);
    for (const b of document.querySelectorAll('.download button')) {
        b.addEventListener('click', () => download(b.dataset.format));
    }

    attachInteraction((px, py) => {
        if ($('click-add').checked) addPoint(px, py);
    }, (w) => {
        if (!w) {
            $('cursor').textContent = '';
            return;
        }
        const tol = pixelSize();
        $('cursor').textContent = 'x ' + fmtCoord(roundTo(w[0], tol), tol) + ', y ' + fmtCoord(roundTo(w[1], tol), tol);
    });

    /* drop a file anywhere on the diagram */
    const wrap = $('canvas-wrap');
    let depth = 0;
    const hasFiles = (ev) => ev.dataTransfer && Array.from(ev.dataTransfer.types || []).includes('Files');
    wrap.addEventListener('dragenter', (ev) => {
        if (!hasFiles(ev)) return;
        ev.preventDefault();
        depth++;
        $('drop').hidden = false;
    });
    wrap.addEventListener('dragover', (ev) => {
        if (!hasFiles(ev)) return;
        ev.preventDefault();
        ev.dataTransfer.dropEffect = 'copy';
    });
    wrap.addEventListener('dragleave', () => {
        depth = Math.max(0, depth - 1);
        if (!depth) $('drop').hidden = true;
    });
    wrap.addEventListener('drop', (ev) => {
        ev.preventDefault();
        depth = 0;
        $('drop').hidden = true;
        const f = ev.dataTransfer.files && ev.dataTransfer.files[0];
        if (f) loadFile(f);
    });
    syncLayers();
    describeSource();
}
