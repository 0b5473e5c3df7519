// body_check.mjs -- checks POST /voronoi answers for tests/deploy/run.
//
//   node body_check.mjs square FILE...    each FILE is the diagram of the
//       square (0,0) (2,0) (0,2) (2,2) and its centre (1,1): exactly the
//       four vertices (1,0) (2,1) (1,2) (0,1) -- the centre's cell is the
//       diamond through the sides' midpoints -- and 8 edges (4 around the
//       centre, 4 rays between neighbouring corners).
//   node body_check.mjs same REF FILE...  REF is a diagram and each FILE
//       equals it once the timings (which differ from request to request)
//       are set aside.
// Exits 1 naming the first file that does not match.
import fs from 'node:fs';

const [mode, ...files] = process.argv.slice(2);
const load = (f) => {
  try {
    return JSON.parse(fs.readFileSync(f, 'utf8'));
  } catch (e) {
    console.error(`${f}: not JSON (${e.message})`);
    process.exit(1);
  }
};
const fail = (f, msg) => {
  console.error(`${f}: ${msg}`);
  process.exit(1);
};
if (mode === 'square') {
  const want = JSON.stringify([[0, 1], [1, 0], [1, 2], [2, 1]]);
  for (const f of files) {
    const d = load(f);
    const got = JSON.stringify([...(d.vertices ?? [])].sort((a, b) => a[0] - b[0] || a[1] - b[1]));
    if (d.n_vertices !== 4 || got !== want) fail(f, `vertices ${got}, expected ${want}`);
    if (d.n_edges !== 8) fail(f, `${d.n_edges} edges, expected 8`);
  }
} else if (mode === 'same') {
  const strip = (d) => { delete d.timings; return JSON.stringify(d); };
  const refFile = files.shift();
  const refDoc = load(refFile);
  if (typeof refDoc.n_vertices !== 'number') fail(refFile, 'the direct answer is no diagram');
  const ref = strip(refDoc);
  for (const f of files)
    if (strip(load(f)) !== ref) fail(f, 'differs from the direct answer');
} else {
  console.error('usage: body_check.mjs square FILE... | same REF FILE...');
  process.exit(2);
}
if (files.length === 0) fail('(none)', 'no answers to check');
