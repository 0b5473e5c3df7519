/* sweep.js -- the size sweep: compute time against N, all three algorithms.
 *
 * What it does: for each N of the list, POSTs compare with the generator
 * of the form (distribution, seed) and that N, without the clip box (it
 * times the algorithms, not the clipping); fills a table row per N and
 * plots the times on log-log axes with each algorithm's fitted exponent.
 *
 * Invariants: one sweep at a time (jobs.sweep holds its AbortController;
 * Stop aborts it); pub.lastSweep is the sweep shown.
 */
import { $, pub, jobs, ALGORITHMS, ALGO_LABEL, ALGO_COLOR, fmtMs, fmtInt, fmtN, fmtAxisMs } from './util.js';
import { ServiceError, compareOnce, isAbort } from './api.js';
import { showError, clearError } from './status.js';
import { chartContext } from './charts.js';
import { genParams, selectedAlgorithm } from './controls.js';

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

export function drawSweep() {
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

function parseSizes(text) {
    const sizes = text.split(/[\s,;]+/).filter(Boolean).map((s) => {
        const m = /^(\d+(?:\.\d+)?)([kKmM]?)$/.exec(s);
        if (!m) return NaN;
        return Math.round(Number(m[1]) * (m[2] ? (/[kK]/.test(m[2]) ? 1e3 : 1e6) : 1));
    });
    if (!sizes.length || sizes.some((n) => !(n >= 1))) return null;
    return Array.from(new Set(sizes)).sort((a, b) => a - b);
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
    const g = genParams();
    const abort = new AbortController();
    jobs.sweep = abort;
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
            const c = await compareOnce({ kind: 'gen', generate: { distribution: g.distribution, n: n, seed: g.seed } },
                { algorithm: selectedAlgorithm(), signal: abort.signal });
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
        jobs.sweep = null;
        $('sweep').disabled = false;
        $('compare').disabled = jobs.compare;
        $('sweep-stop').disabled = true;
    }
}
