/* app.js -- the voronoid page: inputs, requests, drawing, comparison, sweep.
 *
 * What it does: builds a request from the current point source (generator
 * parameters, an uploaded file sent as it is, or explicit points from a
 * JSON file or from clicks), POSTs it to "voronoi" or "compare" (relative
 * to the page, so a path prefix in front of the service keeps working),
 * draws the answer on a canvas, shows the server's timings next to the
 * round trip, and runs size sweeps whose times it plots on log-log axes.
 * Up to 20000 points it asks for JSON with only the parts it draws; above,
 * for the binary diagram, read in place through typed arrays. Both are
 * decoded into one record of typed arrays (see fromJson, fromBinary).
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
 * Invariants: at most one compute request is in flight (a new one aborts
 * the old); the view is kept in model units, so it survives a recompute
 * of the same data; window.voronoid mirrors what is shown (last result,
 * last error, counts drawn) for tests and for the console.
 *
 * Cost: a result of n sites costs O(n) to prepare; a frame costs O(n) for
 * the site culling plus the rasterisation of the cached paths.
 */
(function () {
    'use strict';

    const ALGORITHMS = ['fortune', 'bowyer-watson', 'flip'];
    const ALGO_LABEL = {
        fortune: 'Fortune',
        'bowyer-watson': 'Bowyer–Watson',
        flip: 'Flipping',
    };
    const ALGO_COLOR = {
        fortune: '#1f77b4',
        'bowyer-watson': '#d9730d',
        flip: '#2e8b57',
    };
    const PHASE_COLOR = {
        queue: '#9aa5b1',
        parse: '#5b8def',
        prepare: '#8e6bd6',
        compute: '#1f4e79',
        build: '#2e8b57',
        clip: '#e0a100',
        serialize: '#d9730d',
    };
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
    const CLICK_RECOMPUTE_LIMIT = 200000;
    /* Paths with more segments than this are stroked as hairlines. */
    const HAIRLINE_ABOVE = 20000;
    /* More sites than this are drawn as pixels, not discs. */
    const DOTS_AS_PIXELS = 5000;
    /* Above this many points the page asks for the binary answer. */
    const BINARY_ABOVE = 20000;
    const LITTLE_ENDIAN = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;

    const $ = (id) => document.getElementById(id);

    /* ---- state mirrored for tests and the console ------------------------ */
    const pub = {
        lastResult: null,     /* counts of the last diagram (see summary()) */
        diagram: null,        /* the last diagram record itself */
        lastError: null,      /* {status, title, detail, pointer, line} */
        lastCompare: null,    /* normalised compare answer */
        lastSweep: null,      /* {distribution, seed, rows, done} */
        timings: null,        /* {server_ms, roundtrip_ms, draw_ms, phases} */
        frameMs: 0,           /* script time of the last frame */
        framePaintMs: 0,      /* the last pan/zoom frame until painted */
        edgesDrawn: 0,        /* edges stroked in the last frame */
        raysDrawn: 0,         /* of which rays and lines */
        sitesDrawn: 0,
        trianglesDrawn: 0,
        busy: false,
        computeCount: 0,      /* successful computes */
        compareCount: 0,
        sweepCount: 0,        /* finished sweeps */
        errorCount: 0,
        downloadCount: 0,
        source: null,
        view: null,
    };
    window.voronoid = pub;

    /* ---- point source ---------------------------------------------------
     * {kind: 'generate'}                      parameters read from the form
     * {kind: 'points', points, label}         explicit [[x, y], ...]
     * {kind: 'json', obj, name}               a JSON request body from a file
     * {kind: 'file', name, type, data, size}  bytes sent as they are */
    let source = { kind: 'generate' };

    /* Prepared drawing of the last result (see prepare()). */
    let geom = null;
    /* Model frame: model = (world - c) * k. */
    let frame = { cx: 0.5, cy: 0.5, k: 1 };
    /* View: the model point at the canvas centre and CSS px per model unit. */
    const view = { mx: 0, my: 0, zoom: 1, fitted: true };
    let fitNext = true;

    const canvas = $('diagram');
    const ctx = canvas.getContext('2d');
    let cssW = 1, cssH = 1, dpr = 1;

    let computeAbort = null;
    let sweepAbort = null;
    let compareBusy = false;

    /* ---- small helpers ---------------------------------------------------- */

    function fmtMs(ms) {
        if (ms == null || !isFinite(ms)) return '–';
        if (ms >= 10000) return (ms / 1000).toFixed(1) + ' s';
        if (ms >= 1000) return (ms / 1000).toFixed(2) + ' s';
        if (ms >= 100) return ms.toFixed(0) + ' ms';
        if (ms >= 10) return ms.toFixed(1) + ' ms';
        if (ms >= 1) return ms.toFixed(2) + ' ms';
        return ms.toFixed(3) + ' ms';
    }

    function fmtInt(n) {
        return n == null ? '–' : Number(n).toLocaleString('en-US');
    }

    function fmtBytes(b) {
        if (b < 1024) return b + ' B';
        if (b < 1048576) return (b / 1024).toFixed(1) + ' kB';
        return (b / 1048576).toFixed(1) + ' MB';
    }

    /* Shortest decimal that names x to within tol (for clicked points and
     * grid labels, so they read 0.25 rather than 0.2500000001). */
    function roundTo(x, tol) {
        if (!(tol > 0)) return x;
        const p = Math.pow(10, Math.floor(Math.log10(tol)));
        return Math.round(x / p) * p;
    }

    function fmtCoord(x, step) {
        if (x === 0) return '0';
        const ax = Math.abs(x);
        if (ax >= 1e6 || ax < 1e-4) {
            const digits = Math.max(1, Math.min(12, Math.ceil(Math.log10(ax / step)) + 1));
            return x.toPrecision(digits).replace(/\.?0+e/, 'e');
        }
        const decimals = Math.max(0, Math.min(12, -Math.floor(Math.log10(step))));
        return x.toFixed(decimals);
    }

    function selectedAlgorithm() {
        const r = document.querySelector('input[name=algorithm]:checked');
        return r ? r.value : 'fortune';
    }

    function genParams() {
        const n = Math.max(0, Math.floor(Number($('n').value) || 0));
        const seed = Math.max(0, Math.floor(Number($('seed').value) || 0));
        return { distribution: $('distribution').value, n: n, seed: seed };
    }

    function setStatus(text) {
        $('status').textContent = text;
    }

    function setBusy(on, text) {
        pub.busy = on;
        document.body.dataset.state = on ? 'busy' : (pub.lastError ? 'error' : 'idle');
        if (text) setStatus(text);
    }

    /* A user-facing error: what the problem+json said, or our own words. */
    class ServiceError extends Error {
        constructor(p) {
            super(p.title + (p.detail ? ': ' + p.detail : ''));
            this.problem = p;
        }
    }

    /* ---- errors ----------------------------------------------------------- */

    function showError(err) {
        const p = err instanceof ServiceError ? err.problem
            : { title: 'Something went wrong in the page', detail: String(err && err.message || err) };
        pub.lastError = p;
        pub.errorCount++;
        let title = p.title || 'Error';
        if (p.status) title += ' (' + p.status + ')';
        const bits = [];
        if (p.detail) bits.push(p.detail);
        if (p.line && !new RegExp('\\bline ' + p.line + '\\b', 'i').test(p.detail || '')) bits.push('Line ' + p.line + '.');
        else if (p.pointer) bits.push('At ' + p.pointer + '.');
        if (p.retryAfter) bits.push('The service asks to try again in ' + p.retryAfter + ' s.');
        $('error-title').textContent = title;
        $('error-detail').textContent = bits.join(' ');
        /* the service documents each problem type at its type URI, written
         * from the root; read relative to the page so a path prefix holds */
        const more = $('error-more');
        more.hidden = !/^\/problems\/[a-z-]+$/.test(p.type || '');
        if (!more.hidden) more.href = new URL('.' + p.type, document.baseURI).toString();
        $('error').hidden = false;
        document.body.dataset.state = 'error';
        setStatus('Error: ' + title);
    }

    function clearError() {
        pub.lastError = null;
        $('error').hidden = true;
        if (!pub.busy) document.body.dataset.state = 'idle';
    }

    /* Turns a non-2xx answer into a ServiceError, reading problem+json
     * {type, title, status, detail, pointer, line} when it is one. */
    function problemFrom(resp, text) {
        let p = null;
        const ct = resp.headers.get('content-type') || '';
        if (/json/i.test(ct)) {
            try { p = JSON.parse(text); } catch (e) { p = null; }
        }
        if (!p || typeof p !== 'object') {
            const snippet = String(text || '').replace(/<[^>]*>/g, ' ').replace(/\s+/g, ' ').trim();
            p = { detail: snippet.slice(0, 300) || 'The service answered with status ' + resp.status + '.' };
        }
        return new ServiceError({
            status: p.status || resp.status,
            title: p.title || ('HTTP ' + resp.status + (resp.statusText ? ' ' + resp.statusText : '')),
            detail: p.detail || '',
            pointer: p.pointer || '',
            line: p.line || 0,
            type: p.type || '',
            retryAfter: resp.headers.get('retry-after') || '',
        });
    }

    /* ---- requests --------------------------------------------------------- */

    /* The clip box from the form: null when not clipping or when the field
     * is empty (the service then clips to a margin around the sites);
     * throws a ServiceError when the text is not four numbers. */
    function clipBounds() {
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

    /* Builds {url, init} for POST path with the current source and options:
     * include (array of part names) and format (json, geojson, svg). A JSON
     * source carries its options in the body; raw files carry them in the
     * query string, since their body is the file itself. */
    function buildRequest(path, opt, src) {
        src = src || source;
        const url = new URL(path, document.baseURI);
        const params = url.searchParams;
        const alg = opt.algorithm || selectedAlgorithm();
        const bounds = opt.noBounds ? null : clipBounds();
        if (opt.format && opt.format !== 'json') params.set('format', opt.format);
        const init = { method: 'POST', headers: {}, signal: opt.signal };
        if (src.kind === 'file') {
            params.set('algorithm', alg);
            if (opt.include) params.set('include', opt.include.join(','));
            if (bounds) params.set('bounds', bounds.join(','));
            init.headers['Content-Type'] = src.type;
            init.body = src.data;
        } else {
            let body;
            if (src.kind === 'generate') body = { generate: genParams() };
            else if (src.kind === 'gen') body = { generate: src.generate };
            else if (src.kind === 'json') body = Object.assign({}, src.obj);
            else body = { points: src.points };
            body.algorithm = alg;
            if (opt.include) body.include = opt.include;
            else delete body.include;
            if (bounds) body.bounds = bounds;
            init.headers['Content-Type'] = 'application/json';
            init.body = JSON.stringify(body);
        }
        if (opt.format === 'binary') init.headers.Accept = 'application/octet-stream';
        else if (opt.format === 'svg') init.headers.Accept = 'image/svg+xml';
        else if (opt.format === 'geojson') init.headers.Accept = 'application/geo+json';
        else init.headers.Accept = 'application/json';
        return { url: url.toString(), init: init };
    }

    /* POSTs and reads the answer; resolves to {resp, text | blob, ms} or
     * rejects with a ServiceError (or an AbortError when aborted). */
    async function send(path, opt, src) {
        const req = buildRequest(path, opt, src);
        const t0 = performance.now();
        let resp;
        try {
            resp = await fetch(req.url, req.init);
        } catch (e) {
            if (e.name === 'AbortError') throw e;
            throw new ServiceError({
                title: 'Cannot reach the service',
                detail: 'The request did not get an answer (' + e.message + '). Is voronoid running?',
            });
        }
        if (!resp.ok) {
            const text = await resp.text();
            throw problemFrom(resp, text);
        }
        const out = { resp: resp };
        if (opt.blob) out.blob = await resp.blob();
        else if (opt.buffer) out.buffer = await resp.arrayBuffer();
        else out.text = await resp.text();
        out.ms = performance.now() - t0;
        return out;
    }

    function isAbort(e) {
        return e && e.name === 'AbortError';
    }

    /* "queue;dur=0.01, parse;dur=1.2;desc=..." -> [{name, dur, desc}] */
    function parseServerTiming(h) {
        if (!h) return [];
        return h.split(',').map((s) => s.trim()).filter(Boolean).map((entry) => {
            const parts = entry.split(';');
            const m = { name: parts[0].trim(), dur: null, desc: '' };
            for (const part of parts.slice(1)) {
                const eq = part.indexOf('=');
                const key = (eq < 0 ? part : part.slice(0, eq)).trim().toLowerCase();
                let val = eq < 0 ? '' : part.slice(eq + 1).trim();
                if (val.startsWith('"')) val = val.slice(1, -1);
                if (key === 'dur') m.dur = parseFloat(val);
                else if (key === 'desc') m.desc = val;
            }
            return m;
        });
    }

    /* ---- compute ---------------------------------------------------------- */

    function includeParts() {
        const parts = ['sites', 'vertices', 'edges'];
        if ($('show-delaunay').checked) parts.push('triangles');
        if ($('show-clip').checked) parts.push('clipped');
        return parts;
    }

    async function compute() {
        clearError();
        if (computeAbort) computeAbort.abort();
        const abort = new AbortController();
        computeAbort = abort;
        const alg = selectedAlgorithm();
        setBusy(true, 'Computing with ' + ALGO_LABEL[alg] + '…');
        try {
            /* large answers come as binary arrays: no text to parse */
            const binary = LITTLE_ENDIAN && expectedPoints(source) > BINARY_ABOVE;
            const r = await send('voronoi', {
                include: includeParts(), format: binary ? 'binary' : 'json',
                buffer: binary, signal: abort.signal,
            });
            const tp = performance.now();
            let D;
            if (binary) {
                D = fromBinary(r.buffer);
            } else {
                let res;
                try {
                    res = JSON.parse(r.text);
                } catch (e) {
                    throw unreadable('is not JSON the page can parse (' + e.message + ')');
                }
                D = fromJson(res);
            }
            const roundtrip = r.ms + (performance.now() - tp);
            if (abort !== computeAbort) return;
            const td = performance.now();
            setResult(D);
            drawNow();
            const phases = parseServerTiming(r.resp.headers.get('server-timing'));
            showTimings(D, roundtrip, performance.now() - td, phases);
            const count = ++pub.computeCount;
            afterPaint(() => {
                if (count !== pub.computeCount) return;
                const drawMs = performance.now() - td;
                $('t-draw').textContent = fmtMs(drawMs);
                pub.timings.draw_ms = drawMs;
            });
            setStatus((ALGO_LABEL[D.algorithm] || D.algorithm) + ': ' + fmtInt(D.nSites) + ' sites, computed in ' +
                fmtMs(timingOf(D, 'compute')));
        } catch (e) {
            if (isAbort(e)) return;
            showError(e);
        } finally {
            if (abort === computeAbort) {
                computeAbort = null;
                setBusy(false);
            }
        }
    }

    function timingOf(res, name) {
        const t = res && res.timings;
        if (!t) return null;
        if (t[name + '_ms'] != null) return t[name + '_ms'];
        return t[name] != null ? t[name] : null;
    }

    /* How many points a source will send, as far as the page can tell
     * before asking (a raw file is estimated from its size). */
    function expectedPoints(src) {
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

    function showTimings(res, roundtrip, drawMs, phases) {
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
        if (geom) {
            bits.push(fmtInt(geom.nVertices) + ' vertices', fmtInt(geom.nEdges) + ' edges');
            if (geom.nTriangles) bits.push(fmtInt(geom.nTriangles) + ' triangles');
        }
        if (res.format === 'binary') bits.push('binary answer');
        $('counts').textContent = bits.join(' · ');
    }

    /* ---- answers -> one diagram representation ---------------------------- */

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

    function unreadable(why) {
        return new ServiceError({ title: 'Unreadable answer', detail: 'The diagram sent by the service ' + why + '.' });
    }

    /* The JSON document (openapi.yaml, Diagram): "sites" per input point,
     * site numbers are input indices, "clipped": {bounds, edges, cells}. */
    function fromJson(res) {
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
    function fromBinary(buf) {
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
    function summary(D) {
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

    /* Builds geom from a diagram record: model frame, cached paths, ray
     * list. Keeps the view where it was in world terms unless fitNext is
     * set. A preview (a clicked point before its diagram arrives) is drawn
     * but not published as the last result. */
    function setResult(D, preview) {
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
        if (box && !$('bounds').value.trim()) {
            const tol = Math.max(box[2] - box[0], box[3] - box[1]) * 1e-6;
            $('bounds').placeholder = 'auto: ' + box.map((v) => +roundTo(v, tol).toPrecision(10)).join(', ');
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

    /* A diagram record of points alone (no answer yet). */
    function pointsOnly(points) {
        const xy = new Float64Array(2 * points.length);
        points.forEach((p, i) => { xy[2 * i] = p[0]; xy[2 * i + 1] = p[1]; });
        return {
            format: 'none', algorithm: null, nInput: points.length, nSites: points.length,
            nVertices: 0, nEdges: 0, nTriangles: 0, timings: null, xy: xy, dups: [],
            vxy: new Float64Array(0), ends: new Int32Array(0), esites: new Int32Array(0),
            rayEdge: new Int32Array(0), rayDir: new Float64Array(0), tri: null, clip: null,
        };
    }

    function clearResult() {
        geom = null;
        pub.lastResult = null;
        pub.diagram = null;
        $('counts').textContent = '';
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
        if (geom.clipBox && $('show-clip').checked) {
            const b = geom.clipBox;
            x0 = Math.min(x0, b[0]); y0 = Math.min(y0, b[1]);
            x1 = Math.max(x1, b[2]); y1 = Math.max(y1, b[3]);
        }
        if (!(x0 <= x1)) return [-0.5, -0.5, 0.5, 0.5];
        return [x0, y0, x1, y1];
    }

    function fitView() {
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

    function zoomAbout(factor, px, py) {
        view.fitted = false;
        const mx = view.mx + (px - cssW / 2) / view.zoom;
        const my = view.my - (py - cssH / 2) / view.zoom;
        view.zoom *= factor;
        clampZoom();
        view.mx = mx - (px - cssW / 2) / view.zoom;
        view.my = my + (py - cssH / 2) / view.zoom;
        scheduleDraw();
    }

    /* CSS px -> world coordinates */
    function toWorld(px, py) {
        const mx = view.mx + (px - cssW / 2) / view.zoom;
        const my = view.my - (py - cssH / 2) / view.zoom;
        return [mx / frame.k + frame.cx, my / frame.k + frame.cy];
    }

    function visibleWorld() {
        const a = toWorld(0, cssH), b = toWorld(cssW, 0);
        return [a[0], a[1], b[0], b[1]];
    }

    /* ---- drawing ---------------------------------------------------------- */

    let drawPending = false;
    function scheduleDraw() {
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
    function afterPaint(fn) {
        requestAnimationFrame(() => setTimeout(fn, 0));
    }

    function resizeCanvas() {
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

    function drawNow() {
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
            const clipOn = $('show-clip').checked;
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
            if ($('show-delaunay').checked && geom.triPath) {
                ctx.strokeStyle = COLOR.delaunay;
                ctx.lineWidth = geom.nTriangles > HAIRLINE_ABOVE ? hairline : 0.8 / z;
                ctx.stroke(geom.triPath);
                trisDrawn = geom.nTriangles;
            }
            if ($('show-edges').checked) {
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
            if ($('show-sites').checked && geom.ns) {
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

    /* ---- sources ---------------------------------------------------------- */

    function describeSource() {
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
    }

    function setSource(s, fit) {
        source = s;
        if (fit) fitNext = true;
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
                    return compute();
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
        return compute();
    }

    /* Adds a clicked point (rounded to the screen's resolution); the source
     * becomes the explicit list of the current sites plus the new point. */
    let clickTimer = 0;
    function addPoint(px, py) {
        const w = toWorld(px, py);
        const tol = 1 / (view.zoom * frame.k);
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
        view.fitted = false; /* the view stays put while points are added */
        /* show the point at once; the diagram follows */
        if (!geom) setResult(pointsOnly([p]), true);
        else {
            const ns = geom.ns + 1;
            const mxs = new Float64Array(ns), mys = new Float64Array(ns), dup = new Uint8Array(ns);
            mxs.set(geom.mxs); mys.set(geom.mys); dup.set(geom.dup);
            mxs[ns - 1] = (p[0] - frame.cx) * frame.k;
            mys[ns - 1] = (p[1] - frame.cy) * frame.k;
            Object.assign(geom, { ns: ns, mxs: mxs, mys: mys, dup: dup });
        }
        scheduleDraw();
        if (source.points.length <= CLICK_RECOMPUTE_LIMIT) {
            clearTimeout(clickTimer);
            clickTimer = setTimeout(compute, 120);
        }
    }

    /* ---- compare ---------------------------------------------------------- */

    /* Reads the compare answer, whichever arrangement the codec uses:
     * {agree, disagreement, results: [{algorithm, timings, ...}]} or
     * {agree, algorithms: {name: {...}}}. Returns {agree, disagreement,
     * rows: [{algorithm, compute_ms, total_ms, vertices, edges}]}. */
    function normaliseCompare(j) {
        let list = j.results || j.algorithms || j.runs || [];
        if (!Array.isArray(list)) {
            list = Object.keys(list).map((name) => Object.assign({ algorithm: name }, list[name]));
        }
        const num = (...vals) => vals.find((v) => typeof v === 'number');
        const rows = list.map((r) => {
            const t = r.timings || r;
            const counts = r.counts || {};
            return {
                algorithm: r.algorithm || r.name,
                status: r.status || 'ok',
                detail: r.detail || '',
                compute_ms: num(t.compute_ms, t.compute),
                total_ms: num(t.total_ms, t.total),
                vertices: num(r.n_vertices, r.vertices, counts.vertices),
                edges: num(r.n_edges, r.edges, counts.edges),
            };
        });
        rows.sort((a, b) => ALGORITHMS.indexOf(a.algorithm) - ALGORITHMS.indexOf(b.algorithm));
        return {
            agree: j.agree === true,
            disagreement: j.disagreement || '',
            n_sites: j.n_sites,
            rows: rows,
        };
    }

    /* One POST compare; the sweep leaves the clip box out (it times the
     * algorithms, not the clipping). */
    async function compareOnce(src, signal, noBounds) {
        const r = await send('compare', { signal: signal, noBounds: !!noBounds }, src);
        let j;
        try {
            j = JSON.parse(r.text);
        } catch (e) {
            throw new ServiceError({ title: 'Unreadable answer', detail: 'The compare answer is not JSON: ' + e.message });
        }
        const c = normaliseCompare(j);
        c.raw = j;
        c.roundtrip_ms = r.ms;
        return c;
    }

    async function runCompare() {
        if (compareBusy) return;
        clearError();
        compareBusy = true;
        $('compare').disabled = true;
        setBusy(true, 'Comparing the three algorithms…');
        try {
            const c = await compareOnce(source);
            pub.lastCompare = c;
            showCompare(c);
            pub.compareCount++;
            setStatus('Compared: ' + (c.agree ? 'the three diagrams agree' : 'the diagrams differ'));
        } catch (e) {
            if (!isAbort(e)) showError(e);
        } finally {
            compareBusy = false;
            $('compare').disabled = !!sweepAbort;
            setBusy(!!computeAbort);
        }
    }

    function showCompare(c) {
        const agree = $('agree');
        agree.textContent = '';
        agree.className = 'agree ' + (c.agree ? 'yes' : 'no');
        agree.append(c.agree ? '✓ The three diagrams are identical' : '✗ The diagrams differ');
        const why = c.disagreement || c.rows.filter((r) => r.status !== 'ok')
            .map((r) => (ALGO_LABEL[r.algorithm] || r.algorithm) + ': ' + (r.detail || r.status)).join('; ');
        if (!c.agree && why) {
            const s = document.createElement('small');
            s.textContent = why;
            agree.appendChild(s);
        }
        agree.dataset.agree = c.agree ? 'yes' : 'no';
        const tbody = $('compare-table').tBodies[0];
        tbody.textContent = '';
        const best = Math.min(...c.rows.filter((r) => r.status === 'ok').map((r) => r.compute_ms).filter((v) => v != null));
        for (const r of c.rows) {
            const tr = document.createElement('tr');
            tr.dataset.algorithm = r.algorithm;
            const failed = r.status !== 'ok';
            const cells = [ALGO_LABEL[r.algorithm] || r.algorithm, failed ? r.status : fmtMs(r.compute_ms),
                failed ? '–' : fmtInt(r.vertices), failed ? '–' : fmtInt(r.edges)];
            if (failed) tr.title = r.detail || r.status;
            if (r.total_ms != null) tr.title = 'total on the server ' + fmtMs(r.total_ms);
            cells.forEach((text, i) => {
                const td = document.createElement(i === 0 ? 'th' : 'td');
                if (i === 0) td.scope = 'row';
                td.textContent = text;
                if (i === 1 && !failed && r.compute_ms === best && c.rows.length > 1) td.className = 'best';
                if (i === 1 && failed) td.className = 'failed';
                tr.appendChild(td);
            });
            tbody.appendChild(tr);
        }
        $('compare-table').hidden = false;
        drawBars();
    }

    /* ---- charts ----------------------------------------------------------- */

    /* Sizes a chart canvas to its CSS box at the device pixel ratio and
     * returns a context drawing in CSS px, or null when it is not shown. */
    function chartContext(cv) {
        const w = cv.clientWidth, h = cv.clientHeight;
        if (!w || !h) return null;
        const d = window.devicePixelRatio || 1;
        cv.width = Math.round(w * d);
        cv.height = Math.round(h * d);
        const c = cv.getContext('2d');
        c.setTransform(d, 0, 0, d, 0, 0);
        c.clearRect(0, 0, w, h);
        c.font = '12px system-ui, sans-serif';
        return { c: c, w: w, h: h };
    }

    function drawBars() {
        const g = chartContext($('compare-chart'));
        if (!g) return;
        const c = g.c;
        const comp = pub.lastCompare;
        if (!comp || !comp.rows.length) {
            c.fillStyle = '#8a918f';
            c.fillText('Press "Compare all three" to time them side by side', 4, g.h / 2);
            return;
        }
        const rows = comp.rows;
        const left = 10 + Math.max(...rows.map((r) => c.measureText(ALGO_LABEL[r.algorithm] || r.algorithm).width));
        const right = 70, rowH = Math.min(28, (g.h - 8) / rows.length);
        const ok = (r) => r.status === 'ok' && typeof r.compute_ms === 'number';
        const max = Math.max(...rows.map((r) => ok(r) ? r.compute_ms : 0)) || 1;
        rows.forEach((r, i) => {
            const y = 4 + i * rowH;
            const len = ok(r) ? (g.w - left - right) * r.compute_ms / max : 0;
            c.fillStyle = '#1d2329';
            c.textAlign = 'right';
            c.textBaseline = 'middle';
            c.fillText(ALGO_LABEL[r.algorithm] || r.algorithm, left - 6, y + rowH / 2);
            c.fillStyle = ALGO_COLOR[r.algorithm] || '#888';
            if (ok(r)) c.fillRect(left, y + 4, Math.max(1, len), rowH - 8);
            c.fillStyle = ok(r) ? '#1d2329' : '#a4262c';
            c.textAlign = 'left';
            c.fillText(ok(r) ? fmtMs(r.compute_ms) : r.status, left + len + 5, y + rowH / 2);
        });
    }

    /* Least-squares slope of log t against log n: the empirical exponent. */
    function slope(pts) {
        if (pts.length < 2) return null;
        let sx = 0, sy = 0, sxx = 0, sxy = 0;
        for (const p of pts) {
            const x = Math.log(p[0]), y = Math.log(p[1]);
            sx += x; sy += y; sxx += x * x; sxy += x * y;
        }
        const n = pts.length, den = n * sxx - sx * sx;
        return den > 0 ? (n * sxy - sx * sy) / den : null;
    }

    function fmtN(n) {
        if (n >= 1e6 && n % 1e6 === 0) return n / 1e6 + 'M';
        if (n >= 1e3 && n % 1e3 === 0) return n / 1e3 + 'k';
        return String(n);
    }

    function fmtAxisMs(v) {
        if (v >= 1000) return v / 1000 + ' s';
        return String(+v.toPrecision(3));
    }

    function drawSweep() {
        const g = chartContext($('sweep-chart'));
        if (!g) return;
        const c = g.c;
        const sw = pub.lastSweep;
        const series = {};
        for (const a of ALGORITHMS) series[a] = [];
        if (sw) {
            for (const row of sw.rows) {
                for (const a of ALGORITHMS) {
                    const v = row.ms[a];
                    if (v != null && v > 0) series[a].push([row.n, v]);
                }
            }
        }
        const all = ALGORITHMS.flatMap((a) => series[a]);
        const L = 50, R = 18, T = 10, B = 38;
        const pw = g.w - L - R, ph = g.h - T - B;
        if (!all.length) {
            c.strokeStyle = '#cfd2ca';
            c.strokeRect(L + 0.5, T + 0.5, pw, ph);
            c.fillStyle = '#8a918f';
            c.textAlign = 'center';
            c.fillText('Run a sweep to plot time against N', L + pw / 2, T + ph / 2);
            return;
        }
        const lx0 = Math.floor(Math.log10(Math.min(...all.map((p) => p[0]))));
        let lx1 = Math.ceil(Math.log10(Math.max(...all.map((p) => p[0]))));
        const ly0 = Math.floor(Math.log10(Math.min(...all.map((p) => p[1]))));
        let ly1 = Math.ceil(Math.log10(Math.max(...all.map((p) => p[1]))));
        if (lx1 <= lx0) lx1 = lx0 + 1;
        if (ly1 <= ly0) ly1 = ly0 + 1;
        const X = (n) => L + pw * (Math.log10(n) - lx0) / (lx1 - lx0);
        const Y = (t) => T + ph - ph * (Math.log10(t) - ly0) / (ly1 - ly0);

        /* grid: decades strong, 2 and 5 faint */
        c.lineWidth = 1;
        for (let e = lx0; e <= lx1; e++) {
            for (const m of [1, 2, 5]) {
                const v = m * Math.pow(10, e);
                if (Math.log10(v) > lx1 + 1e-9) continue;
                const x = Math.round(X(v)) + 0.5;
                c.strokeStyle = m === 1 ? '#d6d9d2' : '#eeefeb';
                c.beginPath(); c.moveTo(x, T); c.lineTo(x, T + ph); c.stroke();
                if (m === 1 || lx1 - lx0 <= 2) {
                    c.fillStyle = '#5d6670';
                    c.textAlign = 'center';
                    c.textBaseline = 'top';
                    c.fillText(fmtN(v), x, T + ph + 4);
                }
            }
        }
        for (let e = ly0; e <= ly1; e++) {
            for (const m of [1, 2, 5]) {
                const v = m * Math.pow(10, e);
                if (Math.log10(v) > ly1 + 1e-9) continue;
                const y = Math.round(Y(v)) + 0.5;
                c.strokeStyle = m === 1 ? '#d6d9d2' : '#eeefeb';
                c.beginPath(); c.moveTo(L, y); c.lineTo(L + pw, y); c.stroke();
                if (m === 1 || ly1 - ly0 <= 2) {
                    c.fillStyle = '#5d6670';
                    c.textAlign = 'right';
                    c.textBaseline = 'middle';
                    c.fillText(fmtAxisMs(v), L - 5, y);
                }
            }
        }
        c.strokeStyle = '#9aa19a';
        c.strokeRect(L + 0.5, T + 0.5, pw, ph);
        c.fillStyle = '#1d2329';
        c.textAlign = 'center';
        c.textBaseline = 'bottom';
        c.fillText('N (points), log scale', L + pw / 2, g.h - 1);
        c.save();
        c.translate(12, T + ph / 2);
        c.rotate(-Math.PI / 2);
        c.textBaseline = 'middle';
        c.fillText('compute time (ms), log scale', 0, 0);
        c.restore();

        /* series */
        c.save();
        c.beginPath();
        c.rect(L, T, pw, ph);
        c.clip();
        for (const a of ALGORITHMS) {
            const s = series[a];
            if (!s.length) continue;
            c.strokeStyle = c.fillStyle = ALGO_COLOR[a];
            c.lineWidth = 2;
            c.beginPath();
            s.forEach((p, i) => (i ? c.lineTo(X(p[0]), Y(p[1])) : c.moveTo(X(p[0]), Y(p[1]))));
            c.stroke();
            for (const p of s) {
                c.beginPath();
                c.arc(X(p[0]), Y(p[1]), 3, 0, 2 * Math.PI);
                c.fill();
            }
        }
        c.restore();

        /* legend with the fitted exponent */
        c.font = '11px system-ui, sans-serif';
        c.textAlign = 'left';
        c.textBaseline = 'middle';
        const lw = 150, lh = 16 * ALGORITHMS.length + 6;
        c.fillStyle = 'rgba(255, 255, 255, 0.88)';
        c.fillRect(L + 6, T + 6, lw, lh);
        ALGORITHMS.forEach((a, i) => {
            const y = T + 14 + i * 16;
            c.fillStyle = ALGO_COLOR[a];
            c.fillRect(L + 12, y - 4, 14, 8);
            c.fillStyle = '#1d2329';
            const k = slope(series[a]);
            c.fillText(ALGO_LABEL[a] + (k != null ? '  slope ' + k.toFixed(2) : ''), L + 32, y);
        });
    }

    /* ---- sweep ------------------------------------------------------------ */

    function parseSizes(text) {
        const sizes = text.split(/[\s,;]+/).filter(Boolean).map((s) => {
            const m = /^(\d+(?:\.\d+)?)([kKmM]?)$/.exec(s);
            if (!m) return NaN;
            return Math.round(Number(m[1]) * (m[2] ? (/[kK]/.test(m[2]) ? 1e3 : 1e6) : 1));
        });
        if (!sizes.length || sizes.some((n) => !(n >= 1))) return null;
        return Array.from(new Set(sizes)).sort((a, b) => a - b);
    }

    async function runSweep() {
        if (sweepAbort) return;
        clearError();
        const sizes = parseSizes($('sweep-sizes').value);
        if (!sizes) {
            showError(new ServiceError({
                title: 'Sweep sizes are not a list of numbers',
                detail: 'Give positive point counts separated by commas, e.g. 1000, 2000, 5000 (10k and 1M work too).',
            }));
            return;
        }
        const g = genParams();
        const abort = new AbortController();
        sweepAbort = abort;
        $('sweep').disabled = true;
        $('compare').disabled = true;
        $('sweep-stop').disabled = false;
        const sw = { distribution: g.distribution, seed: g.seed, rows: [], done: false };
        pub.lastSweep = sw;
        const tbody = $('sweep-table').tBodies[0];
        tbody.textContent = '';
        $('sweep-table').hidden = false;
        drawSweep();
        try {
            for (let i = 0; i < sizes.length; i++) {
                const n = sizes[i];
                $('sweep-status').textContent = 'N = ' + fmtInt(n) + ' (' + (i + 1) + ' of ' + sizes.length + ')…';
                const c = await compareOnce({ kind: 'gen', generate: { distribution: g.distribution, n: n, seed: g.seed } }, abort.signal, true);
                const ms = {};
                const status = {};
                for (const r of c.rows) {
                    ms[r.algorithm] = r.status === 'ok' ? r.compute_ms : null;
                    status[r.algorithm] = r.status;
                }
                sw.rows.push({ n: n, ms: ms, status: status, agree: c.agree });
                const tr = document.createElement('tr');
                const cells = [fmtInt(n)].concat(ALGORITHMS.map((a) => ms[a] != null ? fmtMs(ms[a]) : (status[a] || '–')),
                    [c.agree ? 'yes' : 'NO']);
                cells.forEach((text, j) => {
                    const td = document.createElement(j === 0 ? 'th' : 'td');
                    if (j === 0) td.scope = 'row';
                    td.textContent = text;
                    tr.appendChild(td);
                });
                tbody.appendChild(tr);
                drawSweep();
            }
            sw.done = true;
            pub.sweepCount++;
            $('sweep-status').textContent = 'Done: ' + g.distribution + ', seed ' + g.seed + ', ' + sizes.length + ' sizes' +
                (sw.rows.every((r) => r.agree) ? '; all diagrams agree.' : '; some diagrams differ!');
        } catch (e) {
            if (isAbort(e)) {
                $('sweep-status').textContent = 'Stopped after ' + sw.rows.length + ' of ' + sizes.length + ' sizes.';
            } else {
                $('sweep-status').textContent = 'Stopped by an error.';
                showError(e);
            }
        } finally {
            sweepAbort = null;
            $('sweep').disabled = false;
            $('compare').disabled = compareBusy;
            $('sweep-stop').disabled = true;
        }
    }

    /* ---- download --------------------------------------------------------- */

    async function download(format) {
        clearError();
        const ext = { json: 'json', geojson: 'geojson', svg: 'svg' }[format];
        const include = format === 'json' ? ['sites', 'vertices', 'edges', 'cells'].concat(
            $('show-delaunay').checked ? ['triangles'] : [], $('show-clip').checked ? ['clipped'] : []) : null;
        setBusy(true, 'Preparing ' + format.toUpperCase() + '…');
        try {
            const r = await send('voronoi', { include: include, format: format, blob: true });
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
            setBusy(!!computeAbort);
        }
    }

    /* ---- wiring ----------------------------------------------------------- */

    function wire() {
        $('compute-form').addEventListener('submit', (ev) => {
            ev.preventDefault();
            compute();
        });
        for (const r of document.querySelectorAll('input[name=algorithm]')) {
            r.addEventListener('change', () => { if (pub.lastResult || source.kind !== 'generate') compute(); });
        }
        for (const id of ['distribution', 'n', 'seed']) {
            $(id).addEventListener('change', () => setSource({ kind: 'generate' }, true));
        }
        $('n').addEventListener('keydown', (ev) => { if (ev.key === 'Enter') setSource({ kind: 'generate' }, true); });
        $('generate').addEventListener('click', () => {
            setSource({ kind: 'generate' }, true);
            compute();
        });
        $('new-seed').addEventListener('click', () => {
            $('seed').value = String(Math.floor(Math.random() * 1e6));
            setSource({ kind: 'generate' }, true);
            compute();
        });
        $('file').addEventListener('change', () => {
            const f = $('file').files[0];
            if (f) loadFile(f).finally(() => { $('file').value = ''; });
        });
        $('clear-points').addEventListener('click', () => {
            clearTimeout(clickTimer);
            if (computeAbort) computeAbort.abort();
            setSource({ kind: 'points', points: [], label: 'clicked points' }, false);
            clearResult();
            setStatus('Cleared: click on the diagram to add points');
        });
        $('show-sites').addEventListener('change', scheduleDraw);
        $('show-edges').addEventListener('change', scheduleDraw);
        $('show-delaunay').addEventListener('change', () => {
            if ($('show-delaunay').checked && pub.diagram && !pub.diagram.tri) compute();
            else scheduleDraw();
        });
        $('show-clip').addEventListener('change', () => {
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

        $('zoom-in').addEventListener('click', () => zoomAbout(1.5, cssW / 2, cssH / 2));
        $('zoom-out').addEventListener('click', () => zoomAbout(1 / 1.5, cssW / 2, cssH / 2));
        $('zoom-fit').addEventListener('click', fitView);

        $('compare').addEventListener('click', runCompare);
        $('sweep').addEventListener('click', runSweep);
        $('sweep-stop').addEventListener('click', () => { if (sweepAbort) sweepAbort.abort(); });
        for (const b of document.querySelectorAll('.download button')) {
            b.addEventListener('click', () => download(b.dataset.format));
        }

        /* pan, zoom and click on the canvas */
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
            const w = toWorld(p[0], p[1]);
            const tol = 1 / (view.zoom * frame.k);
            $('cursor').textContent = 'x ' + fmtCoord(roundTo(w[0], tol), tol) + ', y ' + fmtCoord(roundTo(w[1], tol), tol);
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
            if (wasClick && $('click-add').checked) {
                const p = local(ev);
                addPoint(p[0], p[1]);
            }
        };
        canvas.addEventListener('pointerup', (ev) => release(ev, false));
        canvas.addEventListener('pointercancel', (ev) => release(ev, true));
        canvas.addEventListener('pointerleave', () => { $('cursor').textContent = ''; });
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

        /* the canvas follows its box and the device pixel ratio */
        new ResizeObserver(() => {
            resizeCanvas();
            drawBars();
            drawSweep();
        }).observe(document.body);
        window.addEventListener('resize', resizeCanvas);
        watchPixelRatio();
    }

    /* A change of device pixel ratio (browser zoom, another monitor) does
     * not resize the CSS box, so it is watched on its own; the media query
     * is renewed for each new ratio. */
    function watchPixelRatio() {
        const mq = window.matchMedia('(resolution: ' + (window.devicePixelRatio || 1) + 'dppx)');
        mq.addEventListener('change', function once() {
            mq.removeEventListener('change', once);
            resizeCanvas();
            drawBars();
            drawSweep();
            watchPixelRatio();
        });
    }

    function start() {
        wire();
        describeSource();
        resizeCanvas();
        drawBars();
        drawSweep();
        compute();
    }

    if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
    else start();
})();
