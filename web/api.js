/* api.js -- the page's client of the service: POST voronoi and compare.
 *
 * What it does: turns a point source and request options into a fetch
 * (JSON body, or a raw file sent as it is with its options in the query
 * string), reads the answer as text, bytes or a blob, and turns every
 * non-2xx answer into a ServiceError carrying the problem+json fields.
 * Paths are relative to the page (document.baseURI), so a path prefix in
 * front of the service keeps working.
 *
 * A source here is already concrete (the controls resolve the form):
 *   {kind: 'gen', generate: {distribution, n, seed}}
 *   {kind: 'points', points: [[x, y], ...]}
 *   {kind: 'json', obj}                       a request body from a file
 *   {kind: 'file', type, data}                bytes sent as they are
 * Nothing here reads the DOM beyond document.baseURI.
 */

/* A user-facing error: what the problem+json said, or our own words. */
export class ServiceError extends Error {
    constructor(p) {
        super(p.title + (p.detail ? ': ' + p.detail : ''));
        this.problem = p;
    }
}

export function isAbort(e) {
    return e && e.name === 'AbortError';
}

/* Turns a non-2xx answer into a ServiceError, reading problem+json
 * {type, title, status, detail, pointer, line} when it is one. */
export function problemFrom(resp, text) {
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

/* Builds {url, init} for POST path with the source src and the options
 * opt: algorithm, bounds (four numbers or null), include (array of part
 * names), format (json, geojson, svg, binary), repeat (compare: runs per
 * algorithm, null for the service's default), trace (voronoi: true adds
 * the algorithm's steps), signal. A JSON source
 * carries its options in the body; raw files carry them in the query
 * string, since their body is the file itself. */
export function buildRequest(path, opt, src) {
    const url = new URL(path, document.baseURI);
    const params = url.searchParams;
    const alg = opt.algorithm;
    const bounds = opt.bounds || null;
    if (opt.format && opt.format !== 'json') params.set('format', opt.format);
    const repeat = opt.repeat != null ? opt.repeat : null;
    const init = { method: 'POST', headers: {}, signal: opt.signal };
    if (src.kind === 'file') {
        if (alg) params.set('algorithm', alg);
        if (opt.include) params.set('include', opt.include.join(','));
        if (bounds) params.set('bounds', bounds.join(','));
        if (repeat != null) params.set('repeat', String(repeat));
        if (opt.trace) params.set('trace', 'true');
        init.headers['Content-Type'] = src.type;
        init.body = src.data;
    } else {
        let body;
        if (src.kind === 'gen') body = { generate: src.generate };
        else if (src.kind === 'json') body = Object.assign({}, src.obj);
        else body = { points: src.points };
        if (alg) body.algorithm = alg;
        if (opt.include) body.include = opt.include;
        else delete body.include;
        if (bounds) body.bounds = bounds;
        if (repeat != null) body.repeat = repeat;
        else delete body.repeat;
        if (opt.trace) body.trace = true;
        else delete body.trace;
        init.headers['Content-Type'] = 'application/json';
        init.body = JSON.stringify(body);
    }
    if (opt.format === 'binary') init.headers.Accept = 'application/octet-stream';
    else if (opt.format === 'svg') init.headers.Accept = 'image/svg+xml';
    else if (opt.format === 'geojson') init.headers.Accept = 'application/geo+json';
    else init.headers.Accept = 'application/json';
    return { url: url.toString(), init: init };
}

/* POSTs and reads the answer; resolves to {resp, text | blob | buffer, ms}
 * or rejects with a ServiceError (or an AbortError when aborted). */
export async function send(path, opt, src) {
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

/* "queue;dur=0.01, parse;dur=1.2;desc=..." -> [{name, dur, desc}] */
export function parseServerTiming(h) {
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

export function timingOf(res, name) {
    const t = res && res.timings;
    if (!t) return null;
    if (t[name + '_ms'] != null) return t[name + '_ms'];
    return t[name] != null ? t[name] : null;
}

/* ---- compare ---------------------------------------------------------- */

const ALGORITHM_ORDER = ['fortune', 'bowyer-watson', 'flip'];

/* Reads the compare answer (openapi.yaml, Comparison). Returns {agree,
 * disagreement, n_sites, repeat, rows: [{algorithm, status, detail,
 * compute_ms, total_ms, vertices, edges, spread: {phase: {median, min,
 * max}} | null, runs_ms: [...] | null, counts: {name: integer} | null}]},
 * the rows in the page's order of algorithms. compute_ms is the median
 * over the runs. */
export function normaliseCompare(j) {
    const list = Array.isArray(j.algorithms) ? j.algorithms : [];
    const rows = list.map((r) => {
        const t = r.timings || {};
        const runs = Array.isArray(r.runs_ms) ? r.runs_ms.filter((v) => typeof v === 'number') : null;
        return {
            algorithm: r.algorithm,
            status: r.status || 'ok',
            detail: r.detail || '',
            compute_ms: t.compute_ms,
            total_ms: t.total_ms,
            vertices: r.n_vertices,
            edges: r.n_edges,
            spread: r.spread && typeof r.spread === 'object' ? r.spread : null,
            runs_ms: runs && runs.length ? runs : null,
            counts: r.counts && typeof r.counts === 'object' ? r.counts : null,
        };
    });
    rows.sort((a, b) => ALGORITHM_ORDER.indexOf(a.algorithm) - ALGORITHM_ORDER.indexOf(b.algorithm));
    return {
        agree: j.agree === true,
        disagreement: j.disagreement || '',
        n_sites: j.n_sites,
        repeat: typeof j.repeat === 'number' ? j.repeat : null,
        rows: rows,
    };
}

/* The compute time of a compare row as {median, min, max, runs}: from its
 * spread when the service repeated the runs, else its single time. */
export function computeSpread(row) {
    const s = row.spread && row.spread.compute_ms;
    const runs = row.runs_ms;
    if (s && typeof s.median === 'number') {
        return { median: s.median, min: s.min != null ? s.min : s.median, max: s.max != null ? s.max : s.median, runs: runs };
    }
    if (runs && runs.length) {
        const sorted = runs.slice().sort((a, b) => a - b);
        const m = sorted.length >> 1;
        const median = sorted.length % 2 ? sorted[m] : (sorted[m - 1] + sorted[m]) / 2;
        return { median: median, min: sorted[0], max: sorted[sorted.length - 1], runs: runs };
    }
    if (typeof row.compute_ms === 'number') {
        return { median: row.compute_ms, min: row.compute_ms, max: row.compute_ms, runs: null };
    }
    return null;
}

/* One POST compare of src with opt (algorithm, bounds, repeat, signal);
 * resolves to the normalised answer with the raw one in .raw. */
export async function compareOnce(src, opt) {
    const r = await send('compare', opt, src);
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
