/* replaydraw.js -- what one frame of the step-through replay shows: the
 * picture on the diagram canvas, and the sentence that says what the step
 * did.
 *
 * What it draws (drawFrame, after step f of a Replay, replay.js):
 * - Fortune: the sweep line; the beach line, each arc a parabola between
 *   its breakpoints (computed from the arcs' sites and the sweep's y; a
 *   parabola piece is exactly a quadratic Bezier curve, and the canvas
 *   map is affine, so each arc is one curve); every pending circle event
 *   as its circle, with a tick where the sweep will meet it; the Voronoi
 *   edges traced so far (finished pieces, and from each breakpoint's
 *   start to where the breakpoint is now) and the vertices made.
 * - Bowyer-Watson and flip: the triangulation so far (ghosts left out)
 *   and the Voronoi diagram dual to it; for an insertion, the located
 *   triangle, the triangles removed (Bowyer-Watson's bad triangles, with
 *   their circumcircles; flip's split triangle, edge or hull edges), the
 *   cavity's boundary and the new star; for a flip, the edge removed,
 *   the edge added and the circle through the edge and the new site that
 *   held the far vertex.
 * - Every algorithm: the sites, those the algorithm has reached filled,
 *   the others hollow, and the step's own sites labelled with their
 *   numbers; the order step draws the order as a path. The last frame is
 *   the replay's final diagram (replay.js diagramOf), drawn as the page
 *   draws a normal answer.
 * Which layers show follows the Draw checkboxes (sites, Voronoi edges,
 * Delaunay triangles; the triangulation of the incremental algorithms is
 * their subject and shows until the last frame).
 *
 * The canvas side is the renderer's overlay hook (renderer.js setOverlay):
 * ov gives the 2D context, device pixel size and the world -> device map
 * X(x), Y(y), with the visible world rectangle. Everything is clipped to
 * the view in device coordinates before it reaches the canvas, so rays,
 * far vertices and huge circles never hand the rasteriser wild numbers.
 *
 * Cost: O(what the state holds) per frame -- for 2,000 sites a few
 * thousand segments and arcs, a few milliseconds.
 */
import { circumcenter } from './exact.js';
import { fmtInt } from './util.js';

const C = {
    edge: '#1f4e79',
    delaunay: '#2e8b57',
    site: '#c0392b',
    pending: '#9aa5b1',
    sweep: '#d35400',
    beach: '#e08a00',
    circle: '#8e44ad',
    cancel: '#7f8c8d',
    bad: '#c0392b',
    badFill: 'rgba(192, 57, 43, 0.16)',
    located: 'rgba(224, 161, 0, 0.38)',
    star: '#d9730d',
    order: '#9aa5b1',
    label: '#1d2329',
};

/* ---- world geometry -------------------------------------------------- */

/* The parabola of site s with the sweep line at y = Y (s[1] < Y). */
function parabolaY(s, Y, x) {
    const d = s[1] - Y;
    return (s[1] + Y) / 2 + (x - s[0]) * (x - s[0]) / (2 * d);
}

/* The x of the breakpoint between the arcs of L (left) and R (right) with
 * the sweep line at Y: the root of the parabolas' difference at which L
 * gives way to R, in a form without cancellation. */
export function breakpointX(L, R, Y) {
    const lx = L[0], ly = L[1], rx = R[0], ry = R[1];
    if (ly === Y && ry === Y) return (lx + rx) / 2;
    if (ly === Y) return lx;
    if (ry === Y) return rx;
    if (ly === ry) return (lx + rx) / 2;
    const dl = ly - Y, dr = ry - Y, w = rx - lx, h = ly - ry;
    const N = -dl * w;
    const s = Math.sqrt(dl * dr * (w * w + h * h));
    const x = N > 0 ? (-dl * w * w + dl * dr * h) / (N + s) : (N - s) / (dr - dl);
    return lx + x;
}

/* The beach line's height at x, on the arc of L or R (whichever is not
 * degenerate); -Infinity where both are. */
function beachY(L, R, Y, x) {
    if (L[1] < Y && R[1] < Y) {
        /* the flatter parabola (the farther site) rounds less */
        return L[1] < R[1] ? parabolaY(L, Y, x) : parabolaY(R, Y, x);
    }
    if (L[1] < Y) return parabolaY(L, Y, x);
    if (R[1] < Y) return parabolaY(R, Y, x);
    return -Infinity;
}

/* ---- drawing helpers --------------------------------------------------- */

/* Liang-Barsky in device coordinates: adds the part of segment p-q inside
 * the view (with a margin) to the path. */
function seg(ov, path, x0, y0, x1, y1) {
    if (!(x0 === x0 && y0 === y0 && x1 === x1 && y1 === y1)) return false;
    const m = 8, r = [-m, -m, ov.W + m, ov.H + m];
    const dx = x1 - x0, dy = y1 - y0;
    let t0 = 0, t1 = 1;
    const p = [-dx, dx, -dy, dy], q = [x0 - r[0], r[2] - x0, y0 - r[1], r[3] - y0];
    for (let i = 0; i < 4; i++) {
        if (p[i] === 0) {
            if (q[i] < 0) return false;
        } else if (isFinite(p[i])) {
            const t = q[i] / p[i];
            if (p[i] < 0) { if (t > t0) t0 = t; } else if (t < t1) t1 = t;
        }
    }
    if (t0 > t1) return false;
    path.moveTo(x0 + t0 * dx, y0 + t0 * dy);
    path.lineTo(x0 + t1 * dx, y0 + t1 * dy);
    return true;
}

/* A world segment; y = -Infinity stands for "from below the view". */
function wseg(ov, path, ax, ay, bx, by) {
    const low = ov.world[1] - (ov.world[3] - ov.world[1]);
    if (ay === -Infinity) ay = Math.min(low, by);
    if (by === -Infinity) by = Math.min(low, ay);
    return seg(ov, path, ov.X(ax), ov.Y(ay), ov.X(bx), ov.Y(by));
}

/* A world ray from (x, y) in direction d, to beyond the view. */
function wray(ov, path, x, y, d) {
    const w = ov.world;
    const far = Math.abs(x - (w[0] + w[2]) / 2) + Math.abs(y - (w[1] + w[3]) / 2) + 2 * (w[2] - w[0] + w[3] - w[1]);
    return wseg(ov, path, x, y, x + far * d[0], y + far * d[1]);
}

/* A world circle, when it meets the view and is not too large to draw as
 * an arc. */
function wcircle(ov, path, cx, cy, r) {
    const X = ov.X(cx), Y = ov.Y(cy), R = r * ov.scale;
    if (!(R > 0) || !isFinite(X) || !isFinite(Y) || R > 1e6) return false;
    if (X + R < 0 || X - R > ov.W || Y + R < 0 || Y - R > ov.H) return false;
    /* wholly around the view: nothing of it shows */
    const fx = Math.max(Math.abs(X), Math.abs(X - ov.W)), fy = Math.max(Math.abs(Y), Math.abs(Y - ov.H));
    if (fx * fx + fy * fy < R * R) return false;
    path.moveTo(X + R, Y);
    path.arc(X, Y, R, 0, 2 * Math.PI);
    return true;
}

function stroke(ov, path, colour, width, dash, alpha) {
    const c = ov.c;
    c.save();
    c.strokeStyle = colour;
    c.lineWidth = width * ov.dpr;
    c.globalAlpha = alpha == null ? 1 : alpha;
    c.lineJoin = 'round';
    if (dash) c.setLineDash(dash.map((v) => v * ov.dpr));
    c.stroke(path);
    c.restore();
}

function fill(ov, path, colour) {
    const c = ov.c;
    c.save();
    c.fillStyle = colour;
    c.fill(path);
    c.restore();
}

/* A triangle of world points as a closed path (none with the vertex at
 * infinity). */
function triPath(ov, path, xy, t) {
    if (t[0] < 0 || t[1] < 0 || t[2] < 0) return;
    const p = t.map((i) => xy[i]);
    const X = p.map((q) => ov.X(q[0])), Y = p.map((q) => ov.Y(q[1]));
    if (!X.every(isFinite) || !Y.every(isFinite)) return;
    if (Math.max(...X.map(Math.abs), ...Y.map(Math.abs)) > 1e7) return;
    path.moveTo(X[0], Y[0]);
    path.lineTo(X[1], Y[1]);
    path.lineTo(X[2], Y[2]);
    path.closePath();
}

function edgeOf(ov, path, xy, a, b) {
    if (a < 0 || b < 0) return;
    wseg(ov, path, xy[a][0], xy[a][1], xy[b][0], xy[b][1]);
}

function dot(ov, path, x, y, r) {
    const X = ov.X(x), Y = ov.Y(y);
    if (!(X > -r && Y > -r && X < ov.W + r && Y < ov.H + r)) return;
    path.moveTo(X + r, Y);
    path.arc(X, Y, r, 0, 2 * Math.PI);
}

/* ---- the frame ----------------------------------------------------------- */

/* Draws the frame after step f of replay R; L: the Draw layers. */
export function* drawFrame(R, f, ov, L) {
    const S = R.seek(f);
    const st = R.steps[f];
    const xy = R.xy;
    const last = f === R.n - 1;
    const dpr = ov.dpr;
    if (last && R.final) {
        drawFinal(R, ov, L);
    } else if (R.fortune) {
        drawFortune(R, S, st, ov, L);
    } else {
        drawIncremental(R, S, st, ov, L);
    }
    yield;
    /* the sites: reached filled, the others hollow */
    const labels = stepSites(R, st);
    if (L.sites) {
        const reached = new Uint8Array(xy.length);
        const order = R.order;
        const upTo = last ? order.length : Math.min(order.length, S.next);
        for (let i = 0; i < upTo; i++) reached[order[i]] = 1;
        const many = order.length > 600;
        const r = (many ? 1.9 : 2.8) * dpr;
        const on = new Path2D(), off = new Path2D();
        for (const i of order) dot(ov, reached[i] ? on : off, xy[i][0], xy[i][1], r);
        fill(ov, on, C.site);
        stroke(ov, off, C.pending, 1, null, 1);
    }
    /* the step's sites, ringed and numbered */
    if (labels.length && !last) {
        const ring = new Path2D();
        for (const i of labels) dot(ov, ring, xy[i][0], xy[i][1], 5.5 * dpr);
        stroke(ov, ring, '#000', 1.4, null, 0.85);
        const c = ov.c;
        c.save();
        c.font = (11 * dpr) + 'px system-ui, sans-serif';
        c.lineJoin = 'round';
        c.lineWidth = 3 * dpr;
        c.strokeStyle = 'rgba(251, 251, 248, 0.9)';
        c.fillStyle = C.label;
        for (const i of labels.slice(0, 8)) {
            const X = ov.X(xy[i][0]) + 7 * dpr, Y = ov.Y(xy[i][1]) - 6 * dpr;
            if (X < -20 || Y < -20 || X > ov.W + 20 || Y > ov.H + 20) continue;
            c.strokeText(String(i), X, Y);
            c.fillText(String(i), X, Y);
        }
        c.restore();
    }
}

/* The sites a step is about, for the rings and labels. */
function stepSites(R, st) {
    const out = [];
    const add = (v) => { if (typeof v === 'number' && v >= 0 && !out.includes(v)) out.push(v); };
    switch (st.kind) {
    case 'begin': (st.triangle || st.beach || []).forEach(add); break;
    case 'insert': add(st.site); break;
    case 'flip': add(st.circle[2]); add(st.added[1]); st.removed.forEach(add); break;
    case 'site': add(st.site); if (st.arc != null) add(st.arc); else (st.breakpoint || []).forEach(add); break;
    case 'circle': case 'schedule': case 'cancel': st.arcs.forEach(add); break;
    default: break;
    }
    return out;
}

function drawFinal(R, ov, L) {
    const F = R.final, xy = R.xy;
    if (L.delaunay) {
        const p = new Path2D();
        const t = R.finalTriangles;
        for (let i = 0; i < t.length; i += 3) {
            for (let j = 0; j < 3; j++) {
                const a = t[i + j], b = t[i + (j + 1) % 3];
                if (a < b) edgeOf(ov, p, xy, a, b);
            }
        }
        /* hull edges appear in one triangle only, maybe as b > a */
        for (const e of F.edges) if (e.ray) edgeOf(ov, p, xy, e.sites[0], e.sites[1]);
        stroke(ov, p, C.delaunay, 0.8, null, 0.6);
    }
    if (L.edges) {
        const p = new Path2D();
        for (const e of F.edges) {
            const a = F.vertices[e.ends[0]];
            if (e.ray) wray(ov, p, a[0], a[1], e.ray);
            else {
                const b = F.vertices[e.ends[1]];
                wseg(ov, p, a[0], a[1], b[0], b[1]);
            }
        }
        stroke(ov, p, C.edge, 1.15, null, 1);
    }
}

/* The incremental algorithms: triangulation, its dual, the step. */
function drawIncremental(R, S, st, ov, L) {
    const xy = R.xy;
    /* the step's removed triangles first, filled, under everything */
    if (st.kind === 'insert') {
        const bad = new Path2D(), loc = new Path2D();
        for (const t of st.cavity) triPath(ov, bad, xy, t);
        fill(ov, bad, C.badFill);
        triPath(ov, loc, xy, st.located);
        fill(ov, loc, C.located);
    } else if (st.kind === 'flip') {
        const p = new Path2D();
        triPath(ov, p, xy, [st.circle[0], st.added[1], st.circle[2]]);
        triPath(ov, p, xy, [st.added[1], st.circle[1], st.circle[2]]);
        fill(ov, p, C.located);
    } else if (st.kind === 'begin') {
        const p = new Path2D();
        triPath(ov, p, xy, st.triangle);
        fill(ov, p, C.located);
    }
    /* the triangulation so far and the Voronoi diagram dual to it */
    const tri = new Path2D(), vor = new Path2D();
    const M = R.M;
    for (const [k, w] of S.edges) {
        const u = Math.floor(k / M) - 1, v = (k % M) - 1;
        if (u < 0 || v < 0 || w < 0) continue; /* a ghost's edge */
        const o = S.edges.get(R.ek(v, u));
        if (u < v || o === -1) edgeOf(ov, tri, xy, u, v);
        if (!L.edges) continue;
        if (o === -1) {
            /* a hull edge: a ray from the circumcentre, outwards */
            const c = circumcenter(xy[u], xy[v], xy[w]);
            const dx = xy[v][0] - xy[u][0], dy = xy[v][1] - xy[u][1], h = Math.hypot(dx, dy);
            if (h > 0) wray(ov, vor, c[0], c[1], [dy / h, -dx / h]);
        } else if (o !== undefined && u < v) {
            const c = circumcenter(xy[u], xy[v], xy[w]), d = circumcenter(xy[v], xy[u], xy[o]);
            wseg(ov, vor, c[0], c[1], d[0], d[1]);
        }
    }
    stroke(ov, tri, C.delaunay, 0.8, null, 0.7);
    if (L.edges) stroke(ov, vor, C.edge, 1, null, 0.55);
    if (st.kind === 'order') drawOrder(R, ov);
    if (st.kind === 'insert') {
        /* the cavity's circles (Bowyer-Watson), boundary and new star */
        const p = st.site;
        if (R.algorithm === 'bowyer-watson') {
            const circles = new Path2D();
            for (const t of st.cavity) {
                if (t[0] < 0 || t[1] < 0 || t[2] < 0) continue;
                const c = circumcenter(xy[t[0]], xy[t[1]], xy[t[2]]);
                wcircle(ov, circles, c[0], c[1], Math.hypot(xy[t[0]][0] - c[0], xy[t[0]][1] - c[1]));
            }
            stroke(ov, circles, C.bad, 1.1, [5, 4], 0.85);
        }
        const boundary = new Path2D(), star = new Path2D();
        for (const t of st.star) {
            /* each star triangle is (x, y, p) in some rotation: x -> y
             * is on the cavity's boundary */
            const k = t.indexOf(p);
            const x = t[(k + 1) % 3], y = t[(k + 2) % 3];
            edgeOf(ov, boundary, xy, x, y);
            edgeOf(ov, star, xy, p, x);
        }
        if (st.split === 'edge' && st.edge) edgeOf(ov, boundary, xy, st.edge[0], st.edge[1]);
        stroke(ov, boundary, C.bad, 2.4, null, 0.9);
        stroke(ov, star, C.star, 2.2, null, 1);
    } else if (st.kind === 'flip') {
        const [a, b, p] = st.circle, d = st.added[1];
        const old = new Path2D(), now = new Path2D(), circle = new Path2D();
        edgeOf(ov, old, xy, a, b);
        edgeOf(ov, now, xy, p, d);
        const c = circumcenter(xy[a], xy[b], xy[p]);
        wcircle(ov, circle, c[0], c[1], Math.hypot(xy[a][0] - c[0], xy[a][1] - c[1]));
        stroke(ov, circle, C.bad, 1.3, [5, 4], 0.9);
        stroke(ov, old, C.bad, 2.2, [6, 4], 1);
        stroke(ov, now, C.star, 2.6, null, 1);
    }
}

function drawOrder(R, ov) {
    const p = new Path2D(), xy = R.xy, o = R.order;
    for (let i = 1; i < o.length; i++) wseg(ov, p, xy[o[i - 1]][0], xy[o[i - 1]][1], xy[o[i]][0], xy[o[i]][1]);
    stroke(ov, p, C.order, 1, null, 0.8);
}

/* Fortune: sweep line, beach line, pending circles, traced edges. */
function drawFortune(R, S, st, ov, L) {
    const xy = R.xy, pts = R.points, Y = S.sweep;
    const w = ov.world;
    if (st.kind === 'order') {
        drawOrder(R, ov);
        return;
    }
    if (L.delaunay) {
        const p = new Path2D(), t = R.tris;
        for (let i = 0; i < 3 * S.nTris; i += 3) {
            edgeOf(ov, p, xy, t[i], t[i + 1]);
            edgeOf(ov, p, xy, t[i + 1], t[i + 2]);
            edgeOf(ov, p, xy, t[i + 2], t[i]);
        }
        stroke(ov, p, C.delaunay, 0.8, null, 0.6);
    }
    /* pending circle events: thin circles, a tick at the top */
    const pend = new Path2D(), ticks = new Path2D();
    for (const k of S.pending.values()) {
        const e = R.steps[k];
        if (!e.vertex || e.vertex[0] == null || e.y == null) continue;
        wcircle(ov, pend, e.vertex[0], e.vertex[1], e.y - e.vertex[1]);
        const X = ov.X(e.vertex[0]), T = ov.Y(e.y);
        seg(ov, ticks, X - 4 * ov.dpr, T, X + 4 * ov.dpr, T);
    }
    stroke(ov, pend, C.circle, 1, null, 0.45);
    stroke(ov, ticks, C.circle, 1.5, null, 0.9);
    /* the step's own circle: scheduled, cancelled, fired; or the circle
     * of a site right below a breakpoint */
    const own = new Path2D();
    let ownColour = C.circle, ownDash = null;
    const circ = st.kind === 'schedule' || st.kind === 'cancel' || st.kind === 'circle' ? st
        : (st.kind === 'site' && st.breakpoint ? st : null);
    if (circ && circ.vertex && circ.vertex[0] != null) {
        const v = circ.vertex;
        const a = xy[(circ.arcs || circ.triangle)[0]];
        wcircle(ov, own, v[0], v[1], Math.hypot(a[0] - v[0], a[1] - v[1]));
        if (st.kind === 'cancel') { ownColour = C.cancel; ownDash = [5, 4]; }
    }
    stroke(ov, own, ownColour, 2, ownDash, 1);
    /* the edges traced so far: finished pieces, then each breakpoint's
     * from its start to where it is now */
    if (L.edges) {
        const p = new Path2D();
        const P = R.pieces;
        for (let i = 0; i < S.nPieces; i++) {
            const s = P[4 * i], e = P[4 * i + 1];
            const ex = pts[2 * e], ey = pts[2 * e + 1];
            if (s < 0) wseg(ov, p, ex, -Infinity, ex, ey);
            else wseg(ov, p, pts[2 * s], pts[2 * s + 1], ex, ey);
        }
        const b = S.beach;
        for (let i = 0; i + 1 < b.length; i++) {
            const l = xy[b[i]], r = xy[b[i + 1]];
            const x = breakpointX(l, r, Y), y = beachY(l, r, Y, x);
            const s = S.starts[i];
            if (s < 0) wseg(ov, p, x, -Infinity, x, y);
            else wseg(ov, p, pts[2 * s], pts[2 * s + 1], x, y);
        }
        stroke(ov, p, C.edge, 1.15, null, 1);
    }
    /* the beach line: one quadratic Bezier per visible arc */
    const beach = new Path2D(), spikes = new Path2D();
    const b = S.beach;
    const xl0 = w[0] - (w[2] - w[0]), xr0 = w[2] + (w[2] - w[0]);
    const bottom = w[1] - 0.05 * (w[3] - w[1]);
    for (let i = 0; i < b.length; i++) {
        const s = xy[b[i]];
        if (s[1] === Y) {
            /* a site on the sweep line: its arc is a spike down to the
             * arc below it */
            let yb = -Infinity;
            if (i > 0 && xy[b[i - 1]][1] < Y) yb = parabolaY(xy[b[i - 1]], Y, s[0]);
            else if (i + 1 < b.length && xy[b[i + 1]][1] < Y) yb = parabolaY(xy[b[i + 1]], Y, s[0]);
            wseg(ov, spikes, s[0], yb, s[0], Y);
            continue;
        }
        let x0 = i > 0 ? breakpointX(xy[b[i - 1]], s, Y) : -Infinity;
        let x1 = i + 1 < b.length ? breakpointX(s, xy[b[i + 1]], Y) : Infinity;
        /* only where the arc is above the view's bottom and in view */
        const top = (s[1] + Y) / 2;
        if (top < bottom) continue;
        const half = Math.sqrt(2 * (Y - s[1]) * (top - bottom));
        x0 = Math.max(x0, s[0] - half, xl0);
        x1 = Math.min(x1, s[0] + half, xr0);
        if (!(x0 < x1)) continue;
        const y0 = parabolaY(s, Y, x0), y1 = parabolaY(s, Y, x1);
        const slope = (x0 - s[0]) / (s[1] - Y);
        const cx = (x0 + x1) / 2, cy = y0 + slope * (x1 - x0) / 2;
        const X0 = ov.X(x0), Y0 = ov.Y(y0), CX = ov.X(cx), CY = ov.Y(cy), X1 = ov.X(x1), Y1 = ov.Y(y1);
        if (![X0, Y0, CX, CY, X1, Y1].every((v) => Math.abs(v) < 1e7)) continue;
        beach.moveTo(X0, Y0);
        beach.quadraticCurveTo(CX, CY, X1, Y1);
    }
    stroke(ov, beach, C.beach, 2, null, 1);
    stroke(ov, spikes, C.beach, 2, null, 1);
    /* the sweep line */
    if (isFinite(Y)) {
        const p = new Path2D();
        seg(ov, p, -10, ov.Y(Y), ov.W + 10, ov.Y(Y));
        stroke(ov, p, C.sweep, 1.5, null, 0.9);
    }
    /* the Voronoi vertices made so far: where the pieces end */
    if (L.edges) {
        const v = new Path2D(), P = R.pieces;
        for (let i = 0; i < S.nPieces; i++) {
            const e = P[4 * i + 1];
            dot(ov, v, pts[2 * e], pts[2 * e + 1], 1.7 * ov.dpr);
        }
        fill(ov, v, C.edge);
    }
    if ((st.kind === 'circle' || (st.kind === 'site' && st.breakpoint)) && st.vertex && st.vertex[0] != null) {
        const v = new Path2D();
        dot(ov, v, st.vertex[0], st.vertex[1], 4 * ov.dpr);
        fill(ov, v, C.circle);
    }
}

/* ---- words ---------------------------------------------------------------- */

function num(v) {
    if (v == null || !isFinite(v)) return String(v);
    return String(+v.toPrecision(6));
}

function pt(v) {
    return v && v[0] != null ? '(' + num(v[0]) + ', ' + num(v[1]) + ')' : '(overflows)';
}

function tri(t) {
    return '(' + t.map((v) => (v < 0 ? '∞' : v)).join(', ') + ')';
}

/* One sentence on what step f did. */
export function describe(R, f) {
    const st = R.steps[f];
    const F = R.final;
    switch (st.kind) {
    case 'order':
        if (R.fortune) return 'Sweep order: the ' + fmtInt(st.sites.length) + ' sites by y, then x (the path shows it).';
        return 'Insertion order: the ' + fmtInt(st.sites.length) + ' sites in ' +
            fmtInt(R.countsAt(f).order_rounds || 1) + ' randomised round(s), each along a Hilbert curve (the path shows it).';
    case 'begin':
        if (R.fortune) {
            return 'The sweep line starts at y = ' + num(st.y) + ': the ' + (st.beach.length > 1 ? fmtInt(st.beach.length) +
                ' sites of the lowest row are' : 'lowest site is') + ' the first beach line.';
        }
        return 'First triangle ' + tri(st.triangle) + '; three ghost triangles, on the vertex at infinity, close its hull.';
    case 'insert': {
        const where = st.located.includes(-1) ? 'outside the hull (ghost ' + tri(st.located) + ')' : 'in triangle ' + tri(st.located);
        if (R.algorithm === 'bowyer-watson') {
            return 'Site ' + st.site + ' located ' + where + '. ' + st.cavity.length + ' bad triangle' +
                (st.cavity.length === 1 ? '' : 's') + ' (circumcircle around the site) removed; a star of ' + st.star.length +
                ' triangles joins the site to the cavity’s boundary.';
        }
        if (st.split === 'edge') {
            return 'Site ' + st.site + ' lies on edge ' + st.edge[0] + '–' + st.edge[1] + ': its two triangles become four.';
        }
        if (st.split === 'hull') {
            return 'Site ' + st.site + ' lies outside the hull: the ' + st.cavity.length + ' hull edge' +
                (st.cavity.length === 1 ? '' : 's') + ' it sees become triangles with it.';
        }
        return 'Site ' + st.site + ' splits triangle ' + tri(st.located) + ' into three; the edges around it are checked next.';
    }
    case 'flip':
        return 'Edge ' + st.removed[0] + '–' + st.removed[1] + ' is illegal: site ' + st.added[1] +
            ' lies inside the circle through ' + st.circle.join(', ') + '. Flipped to ' + st.added[0] + '–' + st.added[1] + '.';
    case 'site':
        if (st.breakpoint) {
            return 'Site event at y = ' + num(st.y) + ': site ' + st.site + ' lies right below the breakpoint of arcs ' +
                st.breakpoint[0] + ' and ' + st.breakpoint[1] + ': Voronoi vertex ' + pt(st.vertex) + ' at once.';
        }
        return 'Site event at y = ' + num(st.y) + ': the arc of site ' + st.site + ' splits the arc of site ' + st.arc + '.';
    case 'circle':
        return 'Circle event at y = ' + num(st.y) + ': the arc of ' + st.arcs[1] + ' between ' + st.arcs[0] + ' and ' +
            st.arcs[2] + ' vanishes; Voronoi vertex ' + pt(st.vertex) + '.';
    case 'schedule':
        return 'Arcs ' + st.arcs.join(', ') + ' converge: circle event scheduled for y = ' + num(st.y) + '.';
    case 'cancel':
        return 'False alarm: the circle event of arcs ' + st.arcs.join(', ') + ' is cancelled (the middle arc’s neighbours changed).';
    case 'end':
        return 'Done: ' + (F ? fmtInt(F.vertices.length) + ' vertices and ' + fmtInt(F.edges.length) + ' edges' : 'the diagram') +
            (R.fortune ? '; the arcs left on the beach line are the convex hull.' : '.');
    default:
        return st.kind;
    }
}
