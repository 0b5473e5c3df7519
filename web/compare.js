/* compare.js -- the compare view: the same points through all three
 * algorithms.
 *
 * What it does: POSTs compare with the current source, then shows whether
 * the three diagrams are identical, a table of each algorithm's compute
 * time and diagram size, and a bar chart of the times.
 *
 * Invariants: one compare at a time (jobs.compare); pub.lastCompare is
 * the answer shown.
 */
import { $, pub, jobs, ALGO_LABEL, ALGO_COLOR, fmtMs, fmtInt } from './util.js';
import { compareOnce, isAbort } from './api.js';
import { setStatus, setBusy, showError, clearError } from './status.js';
import { chartContext } from './charts.js';
import { requestSource, selectedAlgorithm, clipBounds } from './controls.js';

export async function runCompare() {
    if (jobs.compare) return;
    clearError();
    jobs.compare = true;
    $('compare').disabled = true;
    setBusy(true, 'Comparing the three algorithms…');
    try {
        const c = await compareOnce(requestSource(), { algorithm: selectedAlgorithm(), bounds: clipBounds() });
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

export function drawBars() {
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
