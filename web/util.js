/* util.js -- names, colours and number formats shared by the page's modules.
 *
 * What it holds: the algorithm names the service knows and how the page
 * labels and colours them, the colours of the timing phases, the number
 * formats every panel uses (times, counts, sizes, coordinates), the
 * element lookup $, and pub, the state the page mirrors into
 * window.voronoid for tests and for the console. Nothing here talks to the
 * service or draws.
 *
 * Invariants: pub is the one object behind window.voronoid; modules write
 * their own fields of it and never replace it.
 */

export const ALGORITHMS = ['fortune', 'bowyer-watson', 'flip'];
export const ALGO_LABEL = {
    fortune: 'Fortune',
    'bowyer-watson': 'Bowyer–Watson',
    flip: 'Flipping',
};
export const ALGO_COLOR = {
    fortune: '#1f77b4',
    'bowyer-watson': '#d9730d',
    flip: '#2e8b57',
};
/* The generators of the service (one name everywhere: API, command line,
 * page, bench), with how the page describes them. */
export const DISTRIBUTIONS = [
    ['uniform', 'uniform', 'unit square'],
    ['gaussian', 'gaussian', 'N(0,1) per axis'],
    ['pixels', 'pixels', 'integer pixels of an 800x600 window, with duplicates'],
    ['grid', 'grid', 'a square grid'],
    ['circle', 'circle', 'points on a circle'],
    ['clustered', 'clustered', 'gaussian clusters'],
    ['lognormal', 'lognormal', 'exp(2 N(0,1)) per axis, heavy-tailed'],
    ['outlier', 'outlier', 'a 0.1 x 0.1 city and one point at (0, 0)'],
    ['decades', 'decades', '|x|, |y| log-uniform over twelve decades'],
];
export const DIST_LABEL = Object.fromEntries(DISTRIBUTIONS.map((d) => [d[0], d[1]]));

export const PHASE_COLOR = {
    queue: '#9aa5b1',
    parse: '#5b8def',
    prepare: '#8e6bd6',
    compute: '#1f4e79',
    build: '#2e8b57',
    clip: '#e0a100',
    serialize: '#d9730d',
};
export const LITTLE_ENDIAN = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;

export const $ = (id) => document.getElementById(id);

/* ---- state mirrored for tests and the console ---------------------------- */
export const pub = {
    lastResult: null,     /* counts of the last diagram (see summary()) */
    diagram: null,        /* the last diagram record itself */
    lastError: null,      /* {status, title, detail, pointer, line} */
    lastCompare: null,    /* normalised compare answer */
    lastSweep: null,      /* the newest sweep (sweep.js), sweeps: all kept */
    replay: null,         /* the step-through replay (stepper.js) */
    timings: null,        /* {server_ms, roundtrip_ms, draw_ms, phases} */
    decodedIn: null,      /* 'worker' or 'page': where the last answer was read */
    frameMs: 0,           /* script time of the last frame, all its slices */
    frameSlices: 0,       /* slices (tasks) the last frame took */
    frameRasterMs: 0,     /* of frameMs, waiting for the canvas to rasterise */
    framePaintMs: 0,      /* the last pan/zoom frame until painted */
    edgesDrawn: 0,        /* Voronoi edges drawn in the last frame */
    raysDrawn: 0,         /* of which rays and lines */
    delaunayEdgesDrawn: 0,
    sitesDrawn: 0,
    lod: null,            /* per layer: items drawn as lines or paths, and as pixels */
    busy: false,
    computeCount: 0,      /* successful computes */
    compareCount: 0,
    sweepCount: 0,        /* finished sweeps */
    errorCount: 0,
    downloadCount: 0,
    source: null,
    view: null,
    stale: false,         /* the diagram shows other points than the form */
    drawing: false,       /* a frame is being drawn (renderer.js) */
    drawCount: 0,         /* frames finished */
};
if (typeof window !== 'undefined') window.voronoid = pub;

/* Work in flight, so that one panel can tell what another is doing: the
 * compute request's AbortController, the sweep's, whether a compare runs. */
export const jobs = { compute: null, sweep: null, compare: false };

/* ---- formats --------------------------------------------------------------- */

export function fmtMs(ms) {
    if (ms == null || !isFinite(ms)) return '–';
    if (ms >= 10000) return (ms / 1000).toFixed(1) + ' s';
    if (ms >= 1000) return (ms / 1000).toFixed(2) + ' s';
    if (ms >= 100) return ms.toFixed(0) + ' ms';
    if (ms >= 10) return ms.toFixed(1) + ' ms';
    if (ms >= 1) return ms.toFixed(2) + ' ms';
    return ms.toFixed(3) + ' ms';
}

export function fmtInt(n) {
    return n == null ? '–' : Number(n).toLocaleString('en-US');
}

export function fmtBytes(b) {
    if (b < 1024) return b + ' B';
    if (b < 1048576) return (b / 1024).toFixed(1) + ' kB';
    return (b / 1048576).toFixed(1) + ' MB';
}

/* Shortest decimal that names x to within tol (for clicked points and
 * grid labels, so they read 0.25 rather than 0.2500000001). */
export function roundTo(x, tol) {
    if (!(tol > 0)) return x;
    const p = Math.pow(10, Math.floor(Math.log10(tol)));
    return Math.round(x / p) * p;
}

export function fmtCoord(x, step) {
    if (x === 0) return '0';
    const ax = Math.abs(x);
    if (ax >= 1e6 || ax < 1e-4) {
        const digits = Math.max(1, Math.min(12, Math.ceil(Math.log10(ax / step)) + 1));
        return x.toPrecision(digits).replace(/\.?0+e/, 'e');
    }
    const decimals = Math.max(0, Math.min(12, -Math.floor(Math.log10(step))));
    return x.toFixed(decimals);
}

/* 1000 -> "1k", 2000000 -> "2M", 1500 -> "1500" (axis labels). */
export function fmtN(n) {
    if (n >= 1e6 && n % 1e6 === 0) return n / 1e6 + 'M';
    if (n >= 1e3 && n % 1e3 === 0) return n / 1e3 + 'k';
    return String(n);
}

export function fmtAxisMs(v) {
    if (v >= 1000) return v / 1000 + ' s';
    return String(+v.toPrecision(3));
}
