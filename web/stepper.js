/* stepper.js -- "Step through": the algorithm's own steps replayed on the
 * diagram canvas.
 *
 * What it does: Step through asks the service for the diagram of the
 * current points with trace=true (at most TRACE_LIMIT points), and shows
 * the steps one frame each (replaydraw.js draws them through the
 * renderer's overlay, so pan, zoom and the Draw checkboxes keep working):
 * play and pause, a step forward and back, first and last, a scrubber, a
 * speed in steps per second, and keys (space, the arrows outside the
 * canvas, "," and ".", with Shift ten steps; Home, End). Beside the picture: the sentence
 * saying what the step did, and every count of the algorithm as it runs
 * next to the answer's final count. While the mode is on, whatever would
 * compute (Compute, Generate, another algorithm, a new seed, a clicked
 * point) traces instead; Step through again, or the close button, leaves
 * it and computes as usual.
 *
 * Never freezing: the trace is prepared (replay.js prepare) in slices of
 * about SLICE_MS on tasks of their own; a frame can be shown as soon as
 * its step is prepared. Seeking goes from the nearest snapshot, so a
 * step back costs what a step forward does. Playing draws at most one
 * frame per animation frame, however many steps a second it plays.
 *
 * Invariants: pub.replay mirrors the mode (active, algorithm, steps,
 * frame, prepared, ready, playing, speed, counts at the frame, the final
 * counts, whether the last frame equals the answer's diagram, loads);
 * pub.replay.frameDiagram() computes the diagram of the frame's
 * triangulation (replay.js diagramOf), for tests and the console.
 */
import { $, pub, jobs, ALGO_LABEL, fmtInt } from './util.js';
import { send, isAbort, ServiceError, parseServerTiming } from './api.js';
import { setStatus, setBusy, showError, clearError } from './status.js';
import { fromJson, unreadable } from './decode.js';
import { setResult, setOverlay, drawNow } from './renderer.js';
import {
    hooks, compute, requestSource, selectedAlgorithm, expectedPoints, revealDiagram,
    markStale, describeSource, syncLayers, showTimings,
} from './controls.js';
import { Replay, diagramOf } from './replay.js';
import { drawFrame, describe } from './replaydraw.js';

/* The most points the service traces (openapi.yaml, the trace option). */
export const TRACE_LIMIT = 2000;
const SLICE_MS = 8;
const SPEEDS = [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000];
/* A replay plays in about this many seconds at the speed first chosen. */
const PLAY_SECONDS = 25;

const rp = {
    R: null, f: 0, active: false, playing: false, speed: 10,
    what: '', loading: null, lastTick: 0, carry: 0, prepareTimer: null,
};

pub.replay = {
    active: false, algorithm: null, steps: 0, frame: 0, prepared: 0, ready: false,
    playing: false, speed: rp.speed, kind: null, counts: null, finalCounts: null,
    matches: null, loads: 0,
    frameDiagram: frameDiagram,
};

/* The diagram of the triangulation at the frame shown (the last frame:
 * the final diagram), in the answer's JSON shape. */
function frameDiagram() {
    const R = rp.R;
    if (!R) return null;
    const gen = diagramOf(R.xy, R.trianglesAt(rp.f));
    let r;
    do { r = gen.next(); } while (!r.done);
    return r.value;
}

/* ---- entering and leaving ----------------------------------------------- */

/* What a trace was asked for: the algorithm and the source (an object
 * source by identity, and its length, since clicks add to it). */
const sourceIds = new WeakMap();
function requestKey(src) {
    let id = '';
    if (src.kind === 'gen') id = JSON.stringify(src.generate);
    else {
        if (!sourceIds.has(src)) sourceIds.set(src, sourceIds.size + 1 + Math.random());
        id = src.kind + sourceIds.get(src) + ':' + (src.points ? src.points.length : '');
    }
    return selectedAlgorithm() + '|' + id;
}

/* Takes over compute while the mode is on: traces instead, unless the
 * trace shown is of the same request (a Draw checkbox changed): then
 * the frame is drawn again. */
function computeHook() {
    if (!rp.active) return false;
    if (rp.R && !rp.loading && rp.key === requestKey(requestSource())) drawNow();
    else load();
    return true;
}

async function load() {
    clearError();
    syncLayers();
    const src = requestSource();
    const n = expectedPoints(src);
    if (n > TRACE_LIMIT) {
        /* the diagram as usual (compute clears the error box first) */
        leave(false);
        compute();
        showError(new ServiceError({
            title: 'Too many points to step through',
            detail: 'Step through traces at most ' + fmtInt(TRACE_LIMIT) + ' points; this source has ' + fmtInt(Math.round(n)) +
                '. Lower N (or use fewer points) and press Step through again.',
        }));
        return;
    }
    pause();
    if (jobs.compute) jobs.compute.abort();
    const abort = new AbortController();
    jobs.compute = abort;
    const alg = selectedAlgorithm();
    const asked = describeSource();
    const key = requestKey(src);
    rp.loading = abort;
    setBusy(true, 'Tracing ' + ALGO_LABEL[alg] + '…');
    try {
        const r = await send('voronoi', {
            algorithm: alg, include: ['sites', 'vertices', 'edges', 'counts'], trace: true, signal: abort.signal,
        }, src);
        let res;
        try {
            res = JSON.parse(r.text);
        } catch (e) {
            throw unreadable('is not JSON the page can parse (' + e.message + ')');
        }
        if (abort !== jobs.compute || !rp.active) return;
        const D = fromJson(res);
        setResult(D, null);
        markStale(false, asked);
        showTimings(D, r.ms, null, parseServerTiming(r.resp.headers.get('server-timing')));
        rp.key = key;
        start(new Replay(res), res);
        pub.replay.loads++;
        setStatus(ALGO_LABEL[alg] + ': ' + fmtInt(rp.R.n) + ' steps for ' + fmtInt(D.nSites) + ' sites');
    } catch (e) {
        if (isAbort(e)) return;
        showError(e);
    } finally {
        if (rp.loading === abort) rp.loading = null;
        if (abort === jobs.compute) {
            jobs.compute = null;
            setBusy(false);
        }
    }
}

function start(R, res) {
    stopPreparing();
    rp.R = R;
    rp.f = 0;
    rp.answer = res;
    pub.replay.algorithm = R.algorithm;
    pub.replay.steps = R.n;
    pub.replay.prepared = 0;
    pub.replay.ready = false;
    pub.replay.matches = null;
    pub.replay.finalCounts = R.finalCounts;
    const scrub = $('rp-scrub');
    scrub.max = String(Math.max(0, R.n - 1));
    scrub.value = '0';
    if (!R.n) {
        /* fewer than three sites, or all on one line: no algorithm runs */
        setOverlay(null);
        drawNow();
        $('rp-what').textContent = 'Nothing to step through: with fewer than three distinct sites, or all of them on ' +
            'one line, the diagram is built without running the algorithm. It is drawn as the service returned it.';
        $('rp-counts').textContent = '';
        setFrameText();
        enableButtons();
        return;
    }
    /* a speed that plays the whole trace in about PLAY_SECONDS */
    if (!rp.speedChosen) {
        const want = R.n / PLAY_SECONDS;
        rp.speed = SPEEDS.reduce((best, s) => (Math.abs(Math.log(s / want)) < Math.abs(Math.log(best / want)) ? s : best));
        $('rp-speed').value = String(rp.speed);
        pub.replay.speed = rp.speed;
    }
    setOverlay({ draw: (ov, L) => drawFrame(R, rp.f, ov, L) });
    buildCounts(R);
    prepareInSlices(R);
}

/* Runs R.prepare() in tasks of about SLICE_MS each. */
function prepareInSlices(R) {
    const gen = R.prepare();
    let first = true;
    const run = () => {
        rp.prepareTimer = null;
        if (rp.R !== R) return;
        const t0 = performance.now();
        let done = false;
        while (performance.now() - t0 < SLICE_MS) {
            if (gen.next().done) { done = true; break; }
        }
        pub.replay.prepared = R.prepared;
        if (first && R.prepared > 0) {
            first = false;
            show(0);
        }
        if (done) {
            pub.replay.ready = true;
            pub.replay.matches = sameDiagram(R.final, rp.answer);
            enableButtons();
            setFrameText();
            if (rp.f === R.n - 1) show(rp.f);
            return;
        }
        setFrameText();
        rp.prepareTimer = setTimeout(run, 0);
    };
    run();
}

function stopPreparing() {
    if (rp.prepareTimer) clearTimeout(rp.prepareTimer);
    rp.prepareTimer = null;
}

/* The replay's final diagram against the answer's: the same vertices,
 * edges, ends and rays, bit for bit. */
function sameDiagram(F, res) {
    if (!F || !res || !Array.isArray(res.edges) || !Array.isArray(res.vertices)) return false;
    if (F.edges.length !== res.edges.length || F.vertices.length !== res.vertices.length) return false;
    for (let i = 0; i < F.vertices.length; i++) {
        const v = res.vertices[i], w = F.vertices[i];
        if (v === null ? isFinite(w[0]) : (v[0] !== w[0] || v[1] !== w[1])) return false;
    }
    for (let i = 0; i < F.edges.length; i++) {
        const e = res.edges[i], g = F.edges[i];
        if (e.sites[0] !== g.sites[0] || e.sites[1] !== g.sites[1] || e.ends[0] !== g.ends[0] || e.ends[1] !== g.ends[1]) return false;
        if (!!e.ray !== !!g.ray || (e.ray && (e.ray[0] !== g.ray[0] || e.ray[1] !== g.ray[1]))) return false;
    }
    return true;
}

function enter() {
    rp.active = true;
    pub.replay.active = true;
    $('step-through').setAttribute('aria-pressed', 'true');
    $('replay').hidden = false;
    $('view').classList.add('replaying');
    revealDiagram();
    load();
}

/* Leaves the mode; recompute: draw the normal diagram again. */
function leave(recompute) {
    pause();
    stopPreparing();
    rp.active = false;
    rp.R = null;
    Object.assign(pub.replay, { active: false, ready: false, steps: 0, frame: 0, prepared: 0, kind: null, counts: null, matches: null });
    $('step-through').setAttribute('aria-pressed', 'false');
    $('replay').hidden = true;
    $('view').classList.remove('replaying');
    setOverlay(null);
    if (recompute) compute();
    else drawNow();
}

/* ---- frames ---------------------------------------------------------------- */

/* Shows the frame after step f (clamped to what is prepared). */
function show(f) {
    const R = rp.R;
    if (!R || !R.n) return;
    f = Math.max(0, Math.min(Math.round(f), R.prepared - 1, R.n - 1));
    if (f < 0) return;
    rp.f = f;
    R.seek(f);
    $('rp-scrub').value = String(f);
    const st = R.steps[f];
    pub.replay.frame = f;
    pub.replay.kind = st.kind;
    pub.replay.counts = R.countsAt(f);
    $('rp-what').textContent = describe(R, f) + (f === R.n - 1 && pub.replay.matches === true
        ? ' The same diagram as the service’s answer, edge for edge.' : '');
    $('rp-what').dataset.kind = st.kind;
    showCounts(R, f);
    setFrameText();
    enableButtons();
    drawNow();
}

function setFrameText() {
    const R = rp.R;
    let t = '';
    if (R && R.n) {
        t = 'step ' + fmtInt(rp.f + 1) + ' / ' + fmtInt(R.n);
        if (R.prepared < R.n) t += ' (preparing ' + Math.floor(100 * R.prepared / R.n) + '%)';
    } else if (R) {
        t = 'no steps';
    }
    $('rp-frame').textContent = t;
}

function enableButtons() {
    const R = rp.R, n = R ? R.n : 0, f = rp.f;
    const top = R ? Math.min(R.prepared, n) - 1 : -1;
    $('rp-first').disabled = !n || f === 0;
    $('rp-back').disabled = !n || f === 0;
    $('rp-fwd').disabled = !n || f >= top;
    $('rp-last').disabled = !n || f >= n - 1;
    $('rp-play').disabled = !n;
    $('rp-scrub').disabled = !n;
}

/* ---- counts beside the picture ---------------------------------------------- */

function buildCounts(R) {
    const box = $('rp-counts');
    box.textContent = '';
    for (const name of R.countNames) {
        const div = document.createElement('div');
        div.dataset.count = name;
        const dt = document.createElement('dt');
        dt.textContent = name.replace(/_/g, ' ');
        const dd = document.createElement('dd');
        const now = document.createElement('span');
        now.className = 'now';
        const fin = document.createElement('small');
        const v = R.finalCounts ? R.finalCounts[name] : undefined;
        fin.textContent = typeof v === 'number' ? ' / ' + fmtInt(v) : '';
        dd.append(now, fin);
        div.append(dt, dd);
        box.appendChild(div);
    }
}

function showCounts(R, f) {
    const m = R.countNames.length;
    for (const div of $('rp-counts').children) {
        const j = R.countNames.indexOf(div.dataset.count);
        const v = R.counts[f * m + j];
        const before = f > 0 ? R.counts[(f - 1) * m + j] : 0;
        div.querySelector('.now').textContent = fmtInt(v);
        div.classList.toggle('changed', v !== before);
    }
}

/* ---- playing ----------------------------------------------------------------- */

function play() {
    const R = rp.R;
    if (!R || !R.n) return;
    if (rp.f >= R.n - 1) show(0);
    rp.playing = true;
    pub.replay.playing = true;
    rp.lastTick = performance.now();
    rp.carry = 0;
    $('rp-play').textContent = '❚❚';
    $('rp-play').setAttribute('aria-label', 'Pause');
    requestAnimationFrame(tick);
}

function pause() {
    rp.playing = false;
    pub.replay.playing = false;
    $('rp-play').textContent = '▶';
    $('rp-play').setAttribute('aria-label', 'Play');
}

function tick(now) {
    if (!rp.playing || !rp.R) return;
    const R = rp.R;
    rp.carry += (now - rp.lastTick) / 1000 * rp.speed;
    rp.lastTick = now;
    const k = Math.floor(rp.carry);
    if (k >= 1) {
        rp.carry -= k;
        const f = Math.min(R.n - 1, R.prepared - 1, rp.f + k);
        if (f !== rp.f) show(f);
        if (rp.f >= R.n - 1) {
            pause();
            return;
        }
    }
    requestAnimationFrame(tick);
}

function step(d) {
    if (!rp.R) return;
    pause();
    show(rp.f + d);
}

/* ---- wiring ------------------------------------------------------------------ */

export function wireStepper() {
    hooks.compute = computeHook;
    const sel = $('rp-speed');
    sel.textContent = '';
    for (const s of SPEEDS) {
        const o = document.createElement('option');
        o.value = String(s);
        o.textContent = s + (s === 1 ? ' step/s' : ' steps/s');
        sel.appendChild(o);
    }
    sel.value = String(rp.speed);
    $('step-through').addEventListener('click', () => {
        if (rp.active) leave(true);
        else enter();
    });
    $('rp-close').addEventListener('click', () => leave(true));
    /* no points, nothing to replay (the controls have cleared the diagram) */
    $('clear-points').addEventListener('click', () => { if (rp.active) leave(false); });
    $('rp-first').addEventListener('click', () => { pause(); show(0); });
    $('rp-back').addEventListener('click', () => step(-1));
    $('rp-fwd').addEventListener('click', () => step(1));
    $('rp-last').addEventListener('click', () => { pause(); if (rp.R) show(rp.R.n - 1); });
    $('rp-play').addEventListener('click', () => (rp.playing ? pause() : play()));
    $('rp-scrub').addEventListener('input', () => {
        pause();
        show(Number($('rp-scrub').value));
    });
    sel.addEventListener('change', () => {
        rp.speed = Number(sel.value);
        rp.speedChosen = true;
        pub.replay.speed = rp.speed;
    });
    document.addEventListener('keydown', (ev) => {
        if (!rp.active || !rp.R || ev.ctrlKey || ev.metaKey || ev.altKey) return;
        const t = ev.target;
        const tag = t && t.tagName;
        const typing = tag === 'INPUT' && t.type !== 'range' && t.type !== 'checkbox' && t.type !== 'radio' ||
            tag === 'SELECT' || tag === 'TEXTAREA';
        if (typing) return;
        const onCanvas = t && t.id === 'diagram', onRange = t && t.type === 'range';
        const big = ev.shiftKey ? 10 : 1;
        const keys = {
            ',': () => step(-big),
            '.': () => step(big),
            '<': () => step(-10),
            '>': () => step(10),
            Home: () => { pause(); show(0); },
            End: () => { pause(); show(rp.R.n - 1); },
        };
        if (!onCanvas && !onRange) {
            keys.ArrowLeft = () => step(-big);
            keys.ArrowRight = () => step(big);
        }
        if (ev.key === ' ' && tag !== 'BUTTON') keys[' '] = () => (rp.playing ? pause() : play());
        if (keys[ev.key]) {
            ev.preventDefault();
            keys[ev.key]();
        }
    });
}
