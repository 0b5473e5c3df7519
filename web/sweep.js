/* sweep.js -- the size sweep: compute time against N, all three
 * algorithms, for several distributions at once.
 *
 * What it does: for each N of the list and each distribution ticked (the
 * seed from the form), POSTs compare with the chosen runs per algorithm
 * and without the clip box (it times the algorithms, not the clipping),
 * size by size with the distributions interleaved, so that a sweep
 * stopped early still covers each of them. Each answer adds a table row
 * (median, fastest-slowest run) and a point with its bar to the log-log
 * plot. Each (distribution, algorithm) gets the slope of log t on log N
 * with its 95% interval, fitted only where it means something: sizes of
 * at least FIT_MIN_N points whose median is at least FIT_MIN_MS (well
 * above the timer's resolution and the fixed cost of a request), three
 * sizes at least. Earlier sweeps stay on the plot, faded, and in the
 * table until Clear. The table exports as CSV, the plot as PNG and SVG.
 *
 * Invariants: one sweep at a time (jobs.sweep holds its AbortController;
 * Stop aborts it); pub.sweeps lists every sweep kept, pub.lastSweep is
 * the newest.
 */
import { $, pub, jobs, ALGORITHMS, ALGO_COLOR, DIST_LABEL, fmtMs, fmtInt } from './util.js';
import { ServiceError, compareOnce, computeSpread, isAbort } from './api.js';
import { showError, clearError, setStatus } from './status.js';
import {
    chartContext, canvasPainter, svgPainter, drawLogLog, plotHeight, fitSlope, MARKERS, DASHES,
} from './charts.js';
import { genParams } from './controls.js';
import { repeatChoice, runsNote } from './compare.js';

export const FIT_MIN_N = 1000;
export const FIT_MIN_MS = 1;
const AXES_HEIGHT = 240;
const SHORT = { fortune: 'Fortune', 'bowyer-watson': 'B–W', flip: 'Flip' };

const sweeps = [];
pub.sweeps = sweeps;

function parseSizes(text) {
    const sizes = text.split(/[\s,;]+/).filter(Boolean).map((s) => {
        const m = /^(\d+(?:\.\d+)?)([kKmM]?)$/.exec(s);
        if (!m) return NaN;
        return Math.round(Number(m[1]) * (m[2] ? (/[kK]/.test(m[2]) ? 1e3 : 1e6) : 1));
    });
    if (!sizes.length || sizes.some((n) => !(n >= 1))) return null;
    return Array.from(new Set(sizes)).sort((a, b) => a - b);
}

function checkedDistributions() {
    return Array.from(document.querySelectorAll('input[name=sweep-dist]:checked')).map((el) => el.value);
}

function setButtons() {
    const running = !!jobs.sweep, any = sweeps.some((s) => s.rows.length);
    $('sweep').disabled = running;
    $('sweep-stop').disabled = !running;
    $('sweep-clear').disabled = running || !sweeps.length;
    for (const id of ['sweep-csv', 'sweep-png', 'sweep-svg']) $(id).disabled = !any;
    $('compare').disabled = running || jobs.compare;
}

export async function runSweep() {
    if (jobs.sweep) return;
    clearError();
    const sizes = parseSizes($('sweep-sizes').value);
    if (!sizes) {
        showError(new ServiceError({
            title: 'Sweep sizes are not a list of numbers',
            detail: 'Give positive point counts separated by commas, e.g. 1000, 2000, 5000 (10k and 1M work too).',
        }));
        return;
    }
    let dists = checkedDistributions();
    if (!dists.length) dists = [genParams().distribution];
    const seed = genParams().seed;
    const repeat = repeatChoice();
    const abort = new AbortController();
    jobs.sweep = abort;
    const sw = {
        id: sweeps.length ? sweeps[sweeps.length - 1].id + 1 : 1,
        seed: seed, repeat: repeat, distributions: dists, sizes: sizes,
        rows: [], done: false,
    };
    sweeps.push(sw);
    pub.lastSweep = sw;
    setButtons();
    $('sweep-table').hidden = false;
    drawSweep();
    const total = sizes.length * dists.length;
    let count = 0;
    try {
        for (const n of sizes) {
            for (const d of dists) {
                count++;
                $('sweep-status').textContent = DIST_LABEL[d] + ', N = ' + fmtInt(n) + ' (' + count + ' of ' + total + ')…';
                const c = await compareOnce({ kind: 'gen', generate: { distribution: d, n: n, seed: seed } },
                    { repeat: repeat, signal: abort.signal });
                const row = { distribution: d, n: n, agree: c.agree, repeat: c.repeat, times: {}, status: {}, counts: {} };
                for (const r of c.rows) {
                    row.status[r.algorithm] = r.status;
                    row.times[r.algorithm] = r.status === 'ok' ? computeSpread(r) : null;
                    if (r.counts) row.counts[r.algorithm] = r.counts;
                }
                /* the medians by algorithm, as a table shows them */
                row.ms = {};
                for (const a of ALGORITHMS) row.ms[a] = row.times[a] ? row.times[a].median : null;
                sw.rows.push(row);
                showTable();
                drawSweep();
                setButtons();
            }
        }
        sw.done = true;
        pub.sweepCount++;
        $('sweep-status').textContent = 'Done: ' + sw.rows.length + ' comparisons, ' + dists.length +
            ' distribution(s), seed ' + seed + '; ' + runsNote({ repeat: sw.rows.length ? sw.rows[0].repeat : repeat }) +
            (sw.rows.every((r) => r.agree) ? '; all diagrams agree.' : '; some diagrams differ!');
        setStatus('Sweep done');
    } catch (e) {
        if (isAbort(e)) {
            $('sweep-status').textContent = 'Stopped after ' + sw.rows.length + ' of ' + total + ' comparisons.';
        } else {
            $('sweep-status').textContent = 'Stopped by an error.';
            showError(e);
        }
    } finally {
        jobs.sweep = null;
        setButtons();
        showTable();
        drawSweep();
    }
}

export function stopSweep() {
    if (jobs.sweep) jobs.sweep.abort();
}

export function clearSweeps() {
    if (jobs.sweep) return;
    sweeps.length = 0;
    pub.lastSweep = null;
    $('sweep-status').textContent = '';
    showTable();
    drawSweep();
    setButtons();
}

/* ---- table ---------------------------------------------------------------- */

function showTable() {
    const table = $('sweep-table');
    const tbody = table.tBodies[0];
    tbody.textContent = '';
    table.hidden = !sweeps.length;
    for (const sw of sweeps) {
        const head = document.createElement('tr');
        head.className = 'run';
        const th = document.createElement('th');
        th.colSpan = 6;
        th.scope = 'rowgroup';
        th.textContent = 'Sweep ' + sw.id + ': seed ' + sw.seed + ', ' +
            (sw.rows.length && sw.rows[0].repeat ? sw.rows[0].repeat + ' runs each'
                : (sw.repeat ? sw.repeat + ' runs each' : 'runs: service default')) +
            (sw === sweeps[sweeps.length - 1] ? '' : ' (faded on the plot)');
        head.appendChild(th);
        tbody.appendChild(head);
        for (const r of sw.rows) {
            const tr = document.createElement('tr');
            tr.dataset.sweep = sw.id;
            tr.dataset.distribution = r.distribution;
            tr.dataset.n = r.n;
            const td0 = document.createElement('td');
            td0.textContent = DIST_LABEL[r.distribution] || r.distribution;
            tr.appendChild(td0);
            const tn = document.createElement('th');
            tn.scope = 'row';
            tn.textContent = fmtInt(r.n);
            tr.appendChild(tn);
            for (const a of ALGORITHMS) {
                const td = document.createElement('td');
                const t = r.times[a];
                if (t) {
                    td.append(fmtMs(t.median));
                    if (t.max > t.min) {
                        const s = document.createElement('small');
                        s.textContent = fmtMs(t.min) + '–' + fmtMs(t.max);
                        td.appendChild(s);
                    }
                } else {
                    td.textContent = r.status[a] || '–';
                    td.className = 'failed';
                }
                tr.appendChild(td);
            }
            const ta = document.createElement('td');
            ta.textContent = r.agree ? 'yes' : 'NO';
            if (!r.agree) ta.className = 'failed';
            tr.appendChild(ta);
            tbody.appendChild(tr);
        }
    }
}

/* ---- plot ----------------------------------------------------------------- */

/* The plot's series: one per sweep, distribution and algorithm; the
 * newest sweep's in full colour and in the legend. */
function buildSeries() {
    const series = [];
    const dists = [];
    for (const sw of sweeps) for (const d of sw.distributions) if (!dists.includes(d)) dists.push(d);
    sweeps.forEach((sw, k) => {
        const newest = k === sweeps.length - 1;
        for (const d of sw.distributions) {
            const di = dists.indexOf(d);
            for (const a of ALGORITHMS) {
                const points = sw.rows.filter((r) => r.distribution === d && r.times[a] && r.times[a].median > 0)
                    .map((r) => ({ n: r.n, median: r.times[a].median, min: r.times[a].min, max: r.times[a].max }));
                if (!points.length) continue;
                const usable = points.filter((q) => q.n >= FIT_MIN_N && q.median >= FIT_MIN_MS);
                const fit = fitSlope(usable.map((q) => [q.n, q.median]));
                series.push({
                    label: (sweeps.length > 1 ? '#' + sw.id + ' ' : '') + (DIST_LABEL[d] || d) + ' · ' + SHORT[a],
                    distribution: d, algorithm: a, sweep: sw.id,
                    color: ALGO_COLOR[a], marker: MARKERS[di % MARKERS.length], dash: DASHES[di % DASHES.length],
                    alpha: newest ? 1 : 0.3, legend: newest, points: points, fit: fit,
                    why: fit ? '' : 'no slope: ' + usable.length + ' of 3 sizes needed with N ≥ ' + fmtInt(FIT_MIN_N) +
                        ' and t ≥ ' + FIT_MIN_MS + ' ms',
                });
            }
        }
    });
    return series;
}

const EMPTY = 'Run a sweep to plot time against N';

export function drawSweep() {
    const cv = $('sweep-chart');
    const series = buildSeries();
    pub.sweepSeries = series.map((s) => ({
        label: s.label, distribution: s.distribution, algorithm: s.algorithm, sweep: s.sweep, points: s.points.length,
        fit: s.fit ? { slope: s.fit.slope, ci: s.fit.ci, sizes: s.fit.m, n0: s.fit.n0, n1: s.fit.n1 } : null,
    }));
    const w = cv.clientWidth;
    if (!w) return;
    cv.style.height = plotHeight(w, series, AXES_HEIGHT) + 'px';
    const g = chartContext(cv);
    if (!g) return;
    drawLogLog(canvasPainter(g.c), g.w, g.h, series, AXES_HEIGHT, EMPTY);
}

/* ---- export --------------------------------------------------------------- */

function save(blob, name) {
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = name;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
    pub.downloadCount++;
}

/* One line per sweep, distribution, N and algorithm. */
export function sweepCsv() {
    const lines = ['sweep,distribution,seed,repeat,n,algorithm,status,median_ms,min_ms,max_ms,runs_ms,agree'];
    for (const sw of sweeps) {
        for (const r of sw.rows) {
            for (const a of ALGORITHMS) {
                const t = r.times[a];
                const repeat = r.repeat || '';
                lines.push([sw.id, r.distribution, sw.seed, repeat, r.n, a, r.status[a] || '',
                    t ? t.median : '', t ? t.min : '', t ? t.max : '', t && t.runs ? t.runs.join(';') : '',
                    r.agree ? 'yes' : 'no'].join(','));
            }
        }
    }
    return lines.join('\n') + '\n';
}

function exportCsv() {
    save(new Blob([sweepCsv()], { type: 'text/csv' }), 'voronoid-sweep.csv');
}

function exportSize() {
    const cv = $('sweep-chart');
    return { w: Math.max(cv.clientWidth, 560), h: plotHeight(cv.clientWidth, buildSeries(), AXES_HEIGHT) };
}

function exportPng() {
    const { w, h } = exportSize();
    const scale = 2;
    const c = document.createElement('canvas');
    c.width = w * scale;
    c.height = h * scale;
    const g = c.getContext('2d');
    g.setTransform(scale, 0, 0, scale, 0, 0);
    g.fillStyle = '#ffffff';
    g.fillRect(0, 0, w, h);
    drawLogLog(canvasPainter(g), w, h, buildSeries(), AXES_HEIGHT, EMPTY);
    c.toBlob((blob) => { if (blob) save(blob, 'voronoid-sweep.png'); }, 'image/png');
}

function exportSvg() {
    const { w, h } = exportSize();
    const p = svgPainter();
    drawLogLog(p, w, h, buildSeries(), AXES_HEIGHT, EMPTY);
    save(new Blob([p.svg(w, h)], { type: 'image/svg+xml' }), 'voronoid-sweep.svg');
}

export function wireSweep() {
    $('sweep').addEventListener('click', runSweep);
    $('sweep-stop').addEventListener('click', stopSweep);
    $('sweep-clear').addEventListener('click', clearSweeps);
    $('sweep-csv').addEventListener('click', exportCsv);
    $('sweep-png').addEventListener('click', exportPng);
    $('sweep-svg').addEventListener('click', exportSvg);
    /* the form's distribution is ticked by default */
    $('distribution').addEventListener('change', () => {
        if (jobs.sweep || sweeps.length) return;
        for (const el of document.querySelectorAll('input[name=sweep-dist]')) el.checked = el.value === $('distribution').value;
    });
    setButtons();
}
