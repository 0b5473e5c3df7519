/* charts.js -- the compare bars and the sweep's log-log plot, drawn once
 * for the screen and once more, by the same code, for a PNG or SVG file.
 *
 * What it does: each chart is a function of a "painter" -- a handful of
 * drawing calls (line, polyline, marker, rect, text, clip) in CSS pixels
 * -- with two implementations: canvasPainter draws on a 2D context (the
 * page's charts, and the PNG export at twice the resolution), svgPainter
 * writes the same calls as SVG elements (the SVG export). So the three
 * always show the same picture.
 *
 * The plot: log-log axes with decades labelled, one series per
 * (distribution, algorithm) and run, each point the median with a
 * vertical bar from the fastest to the slowest run, the fitted line of
 * log t on log N over the sizes the fit used, and a legend below the
 * axes with each series' slope and its 95% interval.
 */
import { ALGO_LABEL, fmtMs, fmtN, fmtAxisMs } from './util.js';

/* ---- painters -------------------------------------------------------------- */

const FONT = 'system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif';

/* A painter over the 2D context c (already scaled to CSS px). */
export function canvasPainter(c) {
    const style = (s) => {
        c.strokeStyle = s.color || '#000';
        c.fillStyle = s.fill || s.color || '#000';
        c.lineWidth = s.width || 1;
        c.globalAlpha = s.alpha == null ? 1 : s.alpha;
        c.setLineDash(s.dash || []);
    };
    return {
        line(x0, y0, x1, y1, s) {
            style(s);
            c.beginPath();
            c.moveTo(x0, y0);
            c.lineTo(x1, y1);
            c.stroke();
            c.globalAlpha = 1;
        },
        polyline(pts, s) {
            if (pts.length < 2) return;
            style(s);
            c.beginPath();
            pts.forEach((p, i) => (i ? c.lineTo(p[0], p[1]) : c.moveTo(p[0], p[1])));
            c.stroke();
            c.globalAlpha = 1;
            c.setLineDash([]);
        },
        marker(x, y, shape, r, s) {
            style(s);
            c.setLineDash([]);
            c.beginPath();
            if (shape === 'circle') c.arc(x, y, r, 0, 2 * Math.PI);
            else markerPath(shape, x, y, r).forEach((p, i) => (i ? c.lineTo(p[0], p[1]) : c.moveTo(p[0], p[1])));
            c.closePath();
            c.fill();
            c.globalAlpha = 1;
        },
        rect(x, y, w, h, s) {
            style(s);
            if (s.fill) c.fillRect(x, y, w, h);
            if (s.stroke) {
                c.strokeStyle = s.stroke;
                c.strokeRect(x, y, w, h);
            }
            c.globalAlpha = 1;
        },
        text(str, x, y, s) {
            c.save();
            c.font = (s.bold ? '600 ' : '') + (s.size || 12) + 'px ' + FONT;
            c.fillStyle = s.color || '#1d2329';
            c.textAlign = s.align || 'left';
            c.textBaseline = s.baseline || 'alphabetic';
            c.translate(x, y);
            if (s.rotate) c.rotate(s.rotate * Math.PI / 180);
            c.fillText(str, 0, 0);
            c.restore();
        },
        measure(str, size) {
            c.font = (size || 12) + 'px ' + FONT;
            return c.measureText(str).width;
        },
        clip(x, y, w, h) {
            c.save();
            c.beginPath();
            c.rect(x, y, w, h);
            c.clip();
        },
        unclip() {
            c.restore();
        },
    };
}

function markerPath(shape, x, y, r) {
    if (shape === 'square') return [[x - r, y - r], [x + r, y - r], [x + r, y + r], [x - r, y + r]];
    if (shape === 'triangle') return [[x, y - 1.2 * r], [x + 1.1 * r, y + 0.8 * r], [x - 1.1 * r, y + 0.8 * r]];
    if (shape === 'diamond') return [[x, y - 1.3 * r], [x + 1.3 * r, y], [x, y + 1.3 * r], [x - 1.3 * r, y]];
    if (shape === 'down') return [[x, y + 1.2 * r], [x + 1.1 * r, y - 0.8 * r], [x - 1.1 * r, y - 0.8 * r]];
    return [];
}

const esc = (t) => String(t).replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;').replace(/"/g, '&quot;');
const num = (v) => +v.toFixed(2);

/* A painter that records SVG; .svg(w, h) returns the document. measure()
 * borrows a canvas to measure text as the screen does. */
export function svgPainter() {
    const out = [];
    const meas = document.createElement('canvas').getContext('2d');
    let clips = 0;
    const stroke = (s) => ' stroke="' + esc(s.color || '#000') + '" stroke-width="' + (s.width || 1) + '"' +
        (s.dash && s.dash.length ? ' stroke-dasharray="' + s.dash.join(' ') + '"' : '') +
        (s.alpha != null && s.alpha < 1 ? ' opacity="' + s.alpha + '"' : '');
    return {
        line(x0, y0, x1, y1, s) {
            out.push('<line x1="' + num(x0) + '" y1="' + num(y0) + '" x2="' + num(x1) + '" y2="' + num(y1) + '"' + stroke(s) + '/>');
        },
        polyline(pts, s) {
            if (pts.length < 2) return;
            out.push('<polyline fill="none" points="' + pts.map((p) => num(p[0]) + ',' + num(p[1])).join(' ') + '"' + stroke(s) + '/>');
        },
        marker(x, y, shape, r, s) {
            const fill = ' fill="' + esc(s.fill || s.color || '#000') + '"' +
                (s.alpha != null && s.alpha < 1 ? ' opacity="' + s.alpha + '"' : '');
            if (shape === 'circle') out.push('<circle cx="' + num(x) + '" cy="' + num(y) + '" r="' + r + '"' + fill + '/>');
            else out.push('<polygon points="' + markerPath(shape, x, y, r).map((p) => num(p[0]) + ',' + num(p[1])).join(' ') + '"' + fill + '/>');
        },
        rect(x, y, w, h, s) {
            out.push('<rect x="' + num(x) + '" y="' + num(y) + '" width="' + num(w) + '" height="' + num(h) + '"' +
                ' fill="' + esc(s.fill || 'none') + '"' + (s.stroke ? ' stroke="' + esc(s.stroke) + '"' : '') +
                (s.alpha != null && s.alpha < 1 ? ' opacity="' + s.alpha + '"' : '') + '/>');
        },
        text(str, x, y, s) {
            const anchor = { left: 'start', center: 'middle', right: 'end' }[s.align || 'left'];
            const base = { top: 'hanging', middle: 'central', bottom: 'text-after-edge' }[s.baseline] || 'auto';
            out.push('<text x="' + num(x) + '" y="' + num(y) + '" font-size="' + (s.size || 12) + '"' +
                (s.bold ? ' font-weight="600"' : '') + ' fill="' + esc(s.color || '#1d2329') + '" text-anchor="' + anchor +
                '" dominant-baseline="' + base + '"' +
                (s.rotate ? ' transform="rotate(' + s.rotate + ' ' + num(x) + ' ' + num(y) + ')"' : '') + '>' + esc(str) + '</text>');
        },
        measure(str, size) {
            meas.font = (size || 12) + 'px ' + FONT;
            return meas.measureText(str).width;
        },
        clip(x, y, w, h) {
            clips++;
            out.push('<clipPath id="c' + clips + '"><rect x="' + num(x) + '" y="' + num(y) + '" width="' + num(w) +
                '" height="' + num(h) + '"/></clipPath><g clip-path="url(#c' + clips + ')">');
        },
        unclip() {
            out.push('</g>');
        },
        svg(w, h) {
            return '<?xml version="1.0" encoding="UTF-8"?>\n<svg xmlns="http://www.w3.org/2000/svg" width="' + w +
                '" height="' + h + '" viewBox="0 0 ' + w + ' ' + h + '" font-family="' + esc(FONT) + '">\n' +
                '<rect width="100%" height="100%" fill="#ffffff"/>\n' + out.join('\n') + '\n</svg>\n';
        },
    };
}

/* Sizes a chart canvas to its CSS box at the device pixel ratio and
 * returns {c, w, h} drawing in CSS px, or null when it is not shown. */
export function chartContext(cv) {
    const w = cv.clientWidth, h = cv.clientHeight;
    if (!w || !h) return null;
    const d = window.devicePixelRatio || 1;
    cv.width = Math.round(w * d);
    cv.height = Math.round(h * d);
    const c = cv.getContext('2d');
    c.setTransform(d, 0, 0, d, 0, 0);
    c.clearRect(0, 0, w, h);
    c.font = '12px ' + FONT;
    return { c: c, w: w, h: h };
}

/* ---- the compare bars ------------------------------------------------------ */

/* rows: [{algorithm, color, status, t: {median, min, max, runs} | null}].
 * A bar to the median, a whisker from the fastest to the slowest run and
 * a dot per run. */
export function drawBars(p, w, h, rows) {
    if (!rows.length) {
        p.text('Press "Compare all three" to time them side by side', 4, h / 2, { color: '#8a918f', baseline: 'middle' });
        return;
    }
    const left = 10 + Math.max(...rows.map((r) => p.measure(ALGO_LABEL[r.algorithm] || r.algorithm)));
    const right = 74, rowH = Math.min(28, (h - 8) / rows.length);
    const ok = rows.filter((r) => r.status === 'ok' && r.t);
    const max = Math.max(...ok.map((r) => r.t.max)) || 1;
    const X = (v) => left + (w - left - right) * v / max;
    rows.forEach((r, i) => {
        const y = 4 + i * rowH, mid = y + rowH / 2;
        p.text(ALGO_LABEL[r.algorithm] || r.algorithm, left - 6, mid, { align: 'right', baseline: 'middle' });
        if (r.status !== 'ok' || !r.t) {
            p.text(r.status, left + 5, mid, { color: '#a4262c', baseline: 'middle' });
            return;
        }
        const t = r.t;
        p.rect(left, y + 5, Math.max(1, X(t.median) - left), rowH - 10, { fill: r.color, alpha: 0.85 });
        if (t.max > t.min) {
            p.line(X(t.min), mid, X(t.max), mid, { color: '#1d2329', width: 1.2 });
            p.line(X(t.min), mid - 5, X(t.min), mid + 5, { color: '#1d2329', width: 1.2 });
            p.line(X(t.max), mid - 5, X(t.max), mid + 5, { color: '#1d2329', width: 1.2 });
        }
        if (t.runs && t.runs.length > 1) {
            for (const v of t.runs) p.marker(X(v), mid, 'circle', 1.8, { color: '#1d2329', alpha: 0.55 });
        }
        p.text(fmtMs(t.median), Math.max(X(t.max), X(t.median)) + 6, mid, { baseline: 'middle' });
    });
}

/* ---- the sweep plot ---------------------------------------------------------- */

/* Least-squares fit of log t on log n over pts [[n, t], ...]: {slope, ci,
 * intercept, n0, n1, m}, ci the half-width of the slope's 95% interval
 * (Student's t with m - 2 degrees of freedom), or null with fewer than
 * three points. */
export function fitSlope(pts) {
    const m = pts.length;
    if (m < 3) return null;
    let sx = 0, sy = 0;
    for (const p of pts) { sx += Math.log(p[0]); sy += Math.log(p[1]); }
    const mx = sx / m, my = sy / m;
    let sxx = 0, sxy = 0;
    for (const p of pts) {
        const dx = Math.log(p[0]) - mx;
        sxx += dx * dx;
        sxy += dx * (Math.log(p[1]) - my);
    }
    if (!(sxx > 0)) return null;
    const slope = sxy / sxx, intercept = my - slope * mx;
    let ssr = 0;
    for (const p of pts) {
        const r = Math.log(p[1]) - (intercept + slope * Math.log(p[0]));
        ssr += r * r;
    }
    const se = Math.sqrt(ssr / (m - 2) / sxx);
    const T = [12.71, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131];
    const t = m - 2 <= T.length ? T[m - 3] : 1.96 + 2.4 / (m - 2);
    return {
        slope: slope, ci: t * se, intercept: intercept, m: m,
        n0: Math.min(...pts.map((p) => p[0])), n1: Math.max(...pts.map((p) => p[0])),
    };
}

export const MARKERS = ['circle', 'square', 'triangle', 'diamond', 'down'];
export const DASHES = [[], [6, 3], [2, 3], [8, 3, 2, 3], [12, 4]];

/* Height the plot needs at width w for legend lines of the series. */
export function plotHeight(w, series, axesHeight) {
    return axesHeight + 10 + 15 * legendLines(series).length;
}

function legendLines(series) {
    const shown = series.filter((s) => s.legend);
    const lines = shown.map((s) => s);
    const faded = series.length - shown.length;
    if (faded > 0) lines.push({ note: faded + ' earlier series, faded (Clear removes them)' });
    return lines;
}

/* series: [{label, color, dash, marker, alpha, legend, points: [{n,
 * median, min, max}], fit (fitSlope's) | null, why (no fit) }]. */
export function drawLogLog(p, w, h, series, axesHeight, emptyText) {
    const L = 52, R = 22, T = 10, B = 38;
    const pw = w - L - R, ph = axesHeight - T - B;
    const all = series.flatMap((s) => s.points);
    if (!all.length) {
        p.rect(L + 0.5, T + 0.5, pw, ph, { stroke: '#cfd2ca' });
        p.text(emptyText, L + pw / 2, T + ph / 2, { align: 'center', baseline: 'middle', color: '#8a918f' });
        return;
    }
    const lx0 = Math.floor(Math.log10(Math.min(...all.map((q) => q.n))));
    let lx1 = Math.ceil(Math.log10(Math.max(...all.map((q) => q.n))));
    const ly0 = Math.floor(Math.log10(Math.min(...all.map((q) => Math.max(q.min, 1e-4)))));
    let ly1 = Math.ceil(Math.log10(Math.max(...all.map((q) => q.max))));
    if (lx1 <= lx0) lx1 = lx0 + 1;
    if (ly1 <= ly0) ly1 = ly0 + 1;
    const X = (n) => L + pw * (Math.log10(n) - lx0) / (lx1 - lx0);
    const Y = (t) => T + ph - ph * (Math.log10(Math.max(t, 1e-4)) - ly0) / (ly1 - ly0);

    /* grid: decades strong, 2 and 5 faint */
    for (let e = lx0; e <= lx1; e++) {
        for (const m of [1, 2, 5]) {
            const v = m * Math.pow(10, e);
            if (Math.log10(v) > lx1 + 1e-9) continue;
            const x = Math.round(X(v)) + 0.5;
            p.line(x, T, x, T + ph, { color: m === 1 ? '#d6d9d2' : '#eeefeb' });
            if (m === 1 || lx1 - lx0 <= 2) p.text(fmtN(v), x, T + ph + 4, { align: 'center', baseline: 'top', color: '#5d6670' });
        }
    }
    for (let e = ly0; e <= ly1; e++) {
        for (const m of [1, 2, 5]) {
            const v = m * Math.pow(10, e);
            if (Math.log10(v) > ly1 + 1e-9) continue;
            const y = Math.round(Y(v)) + 0.5;
            p.line(L, y, L + pw, y, { color: m === 1 ? '#d6d9d2' : '#eeefeb' });
            if (m === 1 || ly1 - ly0 <= 2) p.text(fmtAxisMs(v), L - 5, y, { align: 'right', baseline: 'middle', color: '#5d6670' });
        }
    }
    p.rect(L + 0.5, T + 0.5, pw, ph, { stroke: '#9aa19a' });
    p.text('N (points), log scale', L + pw / 2, axesHeight - 2, { align: 'center', baseline: 'bottom' });
    p.text('compute time (ms), log scale', 12, T + ph / 2, { align: 'center', baseline: 'middle', rotate: -90 });

    /* series: fitted line, error bars, medians joined, markers */
    p.clip(L, T, pw, ph);
    for (const s of series) {
        const a = s.alpha == null ? 1 : s.alpha;
        if (s.fit) {
            const f = s.fit;
            const y = (n) => Y(Math.exp(f.intercept + f.slope * Math.log(n)));
            p.line(X(f.n0), y(f.n0), X(f.n1), y(f.n1), { color: s.color, width: 1, dash: [3, 3], alpha: 0.9 * a });
        }
        for (const q of s.points) {
            if (q.max > q.min) {
                const x = X(q.n);
                p.line(x, Y(q.min), x, Y(q.max), { color: s.color, width: 1.2, alpha: a });
                p.line(x - 3, Y(q.min), x + 3, Y(q.min), { color: s.color, width: 1.2, alpha: a });
                p.line(x - 3, Y(q.max), x + 3, Y(q.max), { color: s.color, width: 1.2, alpha: a });
            }
        }
        p.polyline(s.points.map((q) => [X(q.n), Y(q.median)]), { color: s.color, width: 1.6, dash: s.dash, alpha: a });
        for (const q of s.points) p.marker(X(q.n), Y(q.median), s.marker, 3.2, { color: s.color, alpha: a });
    }
    p.unclip();

    /* legend below the axes */
    let y = axesHeight + 12;
    for (const s of legendLines(series)) {
        if (s.note) {
            p.text(s.note, L, y, { size: 11, color: '#5d6670', baseline: 'middle' });
            y += 15;
            continue;
        }
        p.line(4, y, 30, y, { color: s.color, width: 1.6, dash: s.dash, alpha: s.alpha });
        p.marker(17, y, s.marker, 3.2, { color: s.color, alpha: s.alpha });
        const fit = s.fit ? 'slope ' + s.fit.slope.toFixed(2) + ' ± ' + s.fit.ci.toFixed(2) + ' (' + s.fit.m + ' sizes)'
            : (s.why || 'no fit');
        p.text(s.label + ': ' + fit, 36, y, { size: 11, baseline: 'middle' });
        y += 15;
    }
}
