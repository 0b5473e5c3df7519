/* main.js -- the voronoid page's entry point.
 *
 * What it does: wires the panels together and starts: the controls (point
 * source, Compute, timings, downloads) drive the renderer (the diagram
 * canvas); Step through replays the algorithm's steps on the same canvas;
 * the compare and sweep views POST compare on their own; every
 * chart and the canvas follow the window's size and device pixel ratio.
 * The first diagram is computed at once. The modules, each by concern:
 *
 *   util.js      names, colours, number formats, window.voronoid
 *   api.js       the service client (requests, problems, compare)
 *   status.js    status line, busy state, error box
 *   decode.js    JSON and binary answers -> one diagram record
 *   geometry.js  a record prepared for drawing: frame, edges, grid index
 *   worker.js    fetches, decodes and prepares large answers off-thread
 *   renderer.js  the diagram canvas: view, drawing in slices, pan, zoom
 *   controls.js  point sources, Compute, timings, downloads
 *   stepper.js   Step through: the algorithm's traced steps, played
 *   replay.js    a trace replayed: the state after any step, the diagram
 *   replaydraw.js  what a step's frame shows, drawn and in words
 *   exact.js     the core's in-circle test, circumcentre and bisector
 *   compare.js   the compare view
 *   sweep.js     the size sweep
 *   charts.js    what the charts share
 */
import { $ } from './util.js';
import { resizeCanvas } from './renderer.js';
import { wireControls, compute } from './controls.js';
import { runCompare, drawBars } from './compare.js';
import { wireSweep, drawSweep } from './sweep.js';
import { wireStepper } from './stepper.js';

function redrawAll() {
    resizeCanvas();
    drawBars();
    drawSweep();
}

/* A change of device pixel ratio (browser zoom, another monitor) does
 * not resize the CSS box, so it is watched on its own; the media query
 * is renewed for each new ratio. */
function watchPixelRatio() {
    const mq = window.matchMedia('(resolution: ' + (window.devicePixelRatio || 1) + 'dppx)');
    mq.addEventListener('change', function once() {
        mq.removeEventListener('change', once);
        redrawAll();
        watchPixelRatio();
    });
}

function start() {
    wireControls();
    wireStepper();
    $('compare').addEventListener('click', runCompare);
    wireSweep();
    /* the canvas follows its box and the device pixel ratio */
    new ResizeObserver(redrawAll).observe(document.body);
    window.addEventListener('resize', resizeCanvas);
    watchPixelRatio();
    redrawAll();
    compute();
}

/* module scripts run once the document is parsed */
start();
