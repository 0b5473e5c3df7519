// peer_js.mjs -- the JavaScript peers timed on a points file: delaunator
// (Delaunay triangulation by sweep-hull and flips, floating-point
// in-circle test) and d3-delaunay (the same triangulation plus the Voronoi
// diagram, clipped to a box, that the web world draws with).
//
// bench/run copies this file next to the node_modules it installed from
// bench/package.json (npm ci), so the imports below resolve there. The
// points are read into a Float64Array outside the timer; timed are
//   delaunator:  new Delaunator(coords)
//   d3-delaunay: new Delaunay(coords).voronoi(bbox)  (full diagram)
// Median of --runs runs, after a small untimed warm-up. The first run also measures peak memory the way
// bench_util.h does (clear_refs, then VmHWM growth), after a forced garbage
// collection when node runs with --expose-gc. With --tris the triangles are
// written as uint32 triples, counter-clockwise in the usual y-up sense, for
// bench_algo's exact check.
//
// usage: node peer_js.mjs --lib delaunator|d3-delaunay --points FILE[,FILE...]
//                         [--runs R] [--tris FILE]
// prints: RESULT name=... n=... ms=... min_ms=... runs=... peak_bpp=...
//         triangles=... status=ok
import fs from 'node:fs';
import Delaunator from 'delaunator';
import { Delaunay } from 'd3-delaunay';

function arg(name, dflt) {
  const i = process.argv.indexOf(name);
  return i > 0 && i + 1 < process.argv.length ? process.argv[i + 1] : dflt;
}

function statusKiB(field) {
  const m = fs.readFileSync('/proc/self/status', 'utf8')
    .match(new RegExp('^' + field + ':\\s+(\\d+)', 'm'));
  return m ? Number(m[1]) : -1;
}

function peakReset() {
  if (globalThis.gc) globalThis.gc();
  try {
    fs.writeFileSync('/proc/self/clear_refs', '5');
  } catch {
    return -1;
  }
  return statusKiB('VmHWM');
}

const lib = arg('--lib', 'delaunator');
const file = arg('--points');
const runs = Number(arg('--runs', '3'));
const trisOut = arg('--tris');
if (!file || !(runs >= 1) || !['delaunator', 'd3-delaunay'].includes(lib)) {
  console.error('usage: node peer_js.mjs --lib delaunator|d3-delaunay ' +
                '--points FILE[,FILE...] [--runs R] [--tris FILE]');
  process.exit(2);
}
// --points may name several files of one n, comma-separated: run r
// computes file r mod count, so that no input is repeated back to back.
const sets = file.split(',').map((path) => {
  const raw = fs.readFileSync(path);
  const coords = new Float64Array(raw.buffer.slice(raw.byteOffset,
                                                   raw.byteOffset + raw.length));
  const m = coords.length / 2;
  let xmin = Infinity, ymin = Infinity, xmax = -Infinity, ymax = -Infinity;
  for (let i = 0; i < m; i++) {
    xmin = Math.min(xmin, coords[2 * i]); xmax = Math.max(xmax, coords[2 * i]);
    ymin = Math.min(ymin, coords[2 * i + 1]);
    ymax = Math.max(ymax, coords[2 * i + 1]);
  }
  return { coords, bbox: [xmin, ymin, xmax, ymax] };
});
const n = sets[0].coords.length / 2;
if (sets.some((t) => t.coords.length !== 2 * n)) {
  console.error('peer_js: the points files differ in size');
  process.exit(2);
}

// One untimed warm-up on at most 10^4 of the points, so that the timed runs
// measure optimised code rather than the JIT compiler's first passes.
{
  const warm = sets[0].coords.subarray(0, 2 * Math.min(n, 10000));
  new Delaunator(warm);
  if (lib === 'd3-delaunay') new Delaunay(warm).voronoi(sets[0].bbox);
}

const ms = [];
let peak = -1, triangles = null;
for (let r = 0; r < runs; r++) {
  const base = r === 0 ? peakReset() : -1;
  const t0 = process.hrtime.bigint();
  const { coords, bbox } = sets[r % sets.length];
  let tri;
  if (lib === 'delaunator') {
    tri = new Delaunator(coords).triangles;
  } else {
    const d = new Delaunay(coords);
    d.voronoi(bbox);
    tri = d.triangles;
  }
  const t1 = process.hrtime.bigint();
  ms.push(Number(t1 - t0) / 1e6);
  if (r === 0) {
    const hwm = statusKiB('VmHWM');
    if (base >= 0 && hwm >= 0) peak = (hwm - base) * 1024;
    triangles = tri;
  }
}
const sorted = [...ms].sort((a, b) => a - b);
const mid = sorted.length >> 1;
const med = sorted.length % 2 ? sorted[mid] : (sorted[mid - 1] + sorted[mid]) / 2;
const nt = triangles.length / 3;
if (trisOut) {
  // delaunator's triangles turn clockwise in y-up coordinates (it follows
  // the screen's y-down convention): reverse each to counter-clockwise.
  const out = new Uint32Array(triangles.length);
  for (let t = 0; t < nt; t++) {
    out[3 * t] = triangles[3 * t];
    out[3 * t + 1] = triangles[3 * t + 2];
    out[3 * t + 2] = triangles[3 * t + 1];
  }
  fs.writeFileSync(trisOut, Buffer.from(out.buffer));
}
console.log(`RESULT name=${lib} n=${n} ms=${med.toFixed(3)} ` +
            `min_ms=${sorted[0].toFixed(3)} runs=${runs} ` +
            `peak_bpp=${peak >= 0 ? (peak / n).toFixed(1) : '-1.0'} ` +
            `triangles=${nt} status=ok`);
