/* compare.js -- the compare view: the same points through all three
 * algorithms, each run several times.
 *
 * What it does: POSTs compare with the current source and the chosen
 * number of runs per algorithm (repeat; the service runs the three in
 * rotating order on the same prepared sites), then shows whether the
 * three diagrams are identical, a table of each algorithm's median
 * compute time with the fastest and slowest run and the diagram's size,
 * a bar chart (median bar, min-max whisker, a dot per run) and, when the
 * service counts its operations, a table of every count it returns, per
 * algorithm and per site, whatever their names.
 *
 * Invariants: one compare at a time (jobs.compare); pub.lastCompare is
 * the answer shown.
 */
import { $, pub, jobs, ALGORITHMS, ALGO_LABEL, ALGO_COLOR, fmtMs, fmtInt } from './util.js';
import { compareOnce, computeSpread, isAbort } from './api.js';
import { setStatus, setBusy, showError, clearError } from './status.js';
import { chartContext, canvasPainter, drawBars as paintBars } from './charts.js';
import { requestSource, clipBounds } from './controls.js';

/* The runs per algorithm chosen in the panel: a number, or null for the
 * service's default. */
export function repeatChoice() {
    const v = $('repeat').value;
    return v === '' ? null : Number(v);
}

/* "median of 5 runs per algorithm ...", "one run per algorithm". */
export function runsNote(c) {
    const k = c.repeat || 1;
    return k > 1 ? 'median of ' + k + ' runs per algorithm, run in rotating order; bars from the fastest to the slowest run'
        : 'one run per algorithm';
}

export async function runCompare() {
    if (jobs.compare) return;
    clearError();
    jobs.compare = true;
    $('compare').disabled = true;
    setBusy(true, 'Comparing the three algorithms…');
    try {
        const c = await compareOnce(requestSource(), { bounds: clipBounds(), repeat: repeatChoice() });
        pub.lastCompare = c;
        showCompare(c);
        pub.compareCount++;
        setStatus('Compared: ' + (c.agree ? 'the three diagrams agree' : 'the diagrams differ'));
    } catch (e) {
        if (!isAbort(e)) showError(e);
    } finally {
        jobs.compare = false;
        $('compare').disabled = !!jobs.sweep;
        setBusy(!!jobs.compute);
    }
}

function cell(tr, text, cls, header) {
    const td = document.createElement(header ? 'th' : 'td');
    if (header) td.scope = 'row';
    td.textContent = text;
    if (cls) td.className = cls;
    tr.appendChild(td);
    return td;
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
    $('compare-note').textContent = 'Compute time: ' + runsNote(c) + '.';

    const tbody = $('compare-table').tBodies[0];
    tbody.textContent = '';
    const times = c.rows.map(computeSpread);
    const okTimes = c.rows.map((r, i) => r.status === 'ok' && times[i] ? times[i].median : Infinity);
    const best = Math.min(...okTimes);
    c.rows.forEach((r, i) => {
        const tr = document.createElement('tr');
        tr.dataset.algorithm = r.algorithm;
        const failed = r.status !== 'ok';
        const t = times[i];
        cell(tr, ALGO_LABEL[r.algorithm] || r.algorithm, '', true);
        const time = cell(tr, failed ? r.status : fmtMs(t && t.median), failed ? 'failed' : (okTimes[i] === best && c.rows.length > 1 ? 'best' : ''));
        if (!failed && t && t.max > t.min) {
            /* the fastest and the slowest run, under the median */
            const spread = document.createElement('small');
            spread.className = 'spread';
            spread.textContent = fmtMs(t.min) + ' – ' + fmtMs(t.max);
            time.appendChild(spread);
        }
        if (t && t.runs) time.title = 'runs: ' + t.runs.map(fmtMs).join(', ');
        cell(tr, failed ? '–' : fmtInt(r.vertices));
        cell(tr, failed ? '–' : fmtInt(r.edges));
        if (failed) tr.title = r.detail || r.status;
        else if (r.total_ms != null) tr.title = 'total on the server ' + fmtMs(r.total_ms);
        tbody.appendChild(tr);
    });
    $('compare-table').hidden = false;
    showCounts(c);
    drawBars();
}

/* Every count any algorithm returned, one row each, with the value per
 * site under it (counts are per run, and deterministic). */
function showCounts(c) {
    const table = $('counts-table');
    const withCounts = c.rows.filter((r) => r.counts && Object.keys(r.counts).length);
    table.hidden = withCounts.length === 0;
    if (table.hidden) return;
    const algs = ALGORITHMS.filter((a) => c.rows.some((r) => r.algorithm === a));
    const head = table.tHead.rows[0];
    head.textContent = '';
    const th = document.createElement('th');
    th.scope = 'col';
    th.textContent = 'Count';
    head.appendChild(th);
    for (const a of algs) {
        const h = document.createElement('th');
        h.scope = 'col';
        h.textContent = ALGO_LABEL[a] || a;
        head.appendChild(h);
    }
    const names = [];
    for (const r of withCounts) for (const k of Object.keys(r.counts)) if (!names.includes(k)) names.push(k);
    const tbody = table.tBodies[0];
    tbody.textContent = '';
    const sites = c.n_sites || 0;
    for (const k of names) {
        const tr = document.createElement('tr');
        tr.dataset.count = k;
        cell(tr, k.replace(/_/g, ' '), '', true);
        for (const a of algs) {
            const r = c.rows.find((x) => x.algorithm === a);
            const v = r && r.counts ? r.counts[k] : undefined;
            const td = cell(tr, typeof v === 'number' ? fmtInt(v) : '–');
            if (typeof v === 'number' && sites > 0) {
                const per = document.createElement('small');
                per.textContent = (v / sites).toPrecision(3) + ' /site';
                td.appendChild(per);
            }
        }
        tbody.appendChild(tr);
    }
}

export function drawBars() {
    const g = chartContext($('compare-chart'));
    if (!g) return;
    const comp = pub.lastCompare;
    const rows = comp ? comp.rows.map((r) => ({
        algorithm: r.algorithm, status: r.status, color: ALGO_COLOR[r.algorithm] || '#888', t: computeSpread(r),
    })) : [];
    paintBars(canvasPainter(g.c), g.w, g.h, rows);
}
