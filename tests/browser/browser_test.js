/* browser_test.js -- the voronoid page driven in a real Chromium.
 *
 * Starts the daemon (VOR_DAEMON, default $B/voronoid, B defaulting to
 * build) on 127.0.0.1 with --port 0, reads the port it announces, opens
 * GET / in Debian's Chromium (through playwright-core, headless, a fresh
 * profile) and acts as a person would: generates points and computes with
 * each algorithm, uploads a CSV file and a broken one, drops a JSON file,
 * clicks points in, pans and zooms, changes N and seed (recomputed, or
 * marked out of date), compares the three algorithms (an answer shaped as
 * the contract says, with repeat, spread, runs and counts, and the
 * service's own), runs a sweep of two distributions and exports it as
 * CSV, PNG and SVG, downloads the diagram, lays the page out on a phone,
 * draws 10^5 points and then 10^6 with every layer on while typing and
 * dragging (the long tasks the browser reports are printed, never judged:
 * the test asserts that input was handled while the frame was being
 * drawn), and steps through each algorithm's trace of a degenerate set to
 * the end (the last frame's edges and vertices against a normal answer;
 * the frame counter and counts against the trace, stepping back and
 * forth), on a phone too, and through 2,000 points. Each step asserts on what
 * the page shows (text, table rows, canvas pixels) and on the state it
 * exposes in window.voronoid; any console error, uncaught page error or
 * failed request fails the run. The page's own files are served with the
 * service's Content-Security-Policy (added by the test where the daemon
 * does not send it), so a policy violation fails the run too. Screenshots
 * go to VOR_BROWSER_OUT (default $B/browser). The daemon is stopped at the
 * end, also on failure.
 *
 * Environment: VOR_DAEMON (daemon binary), VOR_WEB_DIR (serve the page from
 * this directory with --web-dir instead of the embedded copy), VOR_CHROMIUM
 * (default /usr/bin/chromium), VOR_BROWSER_OUT (screenshot directory).
 * Exit status 0 when every step passed; the last line reads
 * "browser: N passed, M failed".
 */
'use strict';

const { spawn } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');
const { chromium } = require('playwright-core');

const ROOT = path.resolve(__dirname, '..', '..');
/* make exports a B given on its command line (make B=build-x browser) */
const BUILD = process.env.B || 'build';
const DAEMON = path.resolve(ROOT, process.env.VOR_DAEMON || path.join(BUILD, 'voronoid'));
const CHROMIUM = process.env.VOR_CHROMIUM || '/usr/bin/chromium';
const OUT = path.resolve(ROOT, process.env.VOR_BROWSER_OUT || path.join(BUILD, 'browser'));
const WEB_DIR = process.env.VOR_WEB_DIR ? path.resolve(ROOT, process.env.VOR_WEB_DIR) : '';
const STEP_TIMEOUT = 60000;

const ALGORITHMS = ['fortune', 'bowyer-watson', 'flip'];
const CSP = "default-src 'self'; script-src 'self'; style-src 'self'; connect-src 'self'; " +
    "img-src 'self' data: blob:; worker-src 'self'; frame-ancestors 'none'";

/* ---- the daemon ------------------------------------------------------ */

/* Starts the daemon and resolves {proc, port, log} once it has printed the
 * port it listens on. */
function startDaemon() {
    return new Promise((resolve, reject) => {
        if (!fs.existsSync(DAEMON)) {
            reject(new Error(DAEMON + ' does not exist (build it: make)'));
            return;
        }
        const args = ['--bind', '127.0.0.1', '--port', '0'];
        if (WEB_DIR) args.push('--web-dir', WEB_DIR);
        const proc = spawn(DAEMON, args, { cwd: ROOT, stdio: ['ignore', 'pipe', 'pipe'] });
        const log = [];
        let done = false;
        const timer = setTimeout(() => finish(new Error('the daemon announced no port within 20 s:\n' + log.join(''))), 20000);
        function finish(err, port) {
            if (done) return;
            done = true;
            clearTimeout(timer);
            if (err) {
                proc.kill('SIGKILL');
                reject(err);
            } else {
                resolve({ proc: proc, port: port, log: log });
            }
        }
        const onData = (chunk) => {
            const text = chunk.toString();
            log.push(text);
            if (log.length > 2000) log.splice(0, 1000);
            const all = log.join('');
            /* "listening on http://127.0.0.1:40123", "port 40123", ... */
            const m = /127\.0\.0\.1:(\d{1,5})\b/.exec(all) || /\bport[\s=:]+(\d{1,5})\b/i.exec(all);
            if (m && Number(m[1]) > 0) finish(null, Number(m[1]));
        };
        proc.stdout.on('data', onData);
        proc.stderr.on('data', onData);
        proc.on('error', (e) => finish(e));
        proc.on('exit', (code, sig) => finish(new Error('the daemon exited early (' + (sig || code) + '):\n' + log.join(''))));
    });
}

function stopDaemon(d) {
    return new Promise((resolve) => {
        if (!d || d.proc.exitCode !== null || d.proc.signalCode !== null) {
            resolve(d ? d.proc.exitCode : null);
            return;
        }
        const kill = setTimeout(() => d.proc.kill('SIGKILL'), 8000);
        d.proc.once('exit', (code, sig) => {
            clearTimeout(kill);
            resolve(sig || code);
        });
        d.proc.kill('SIGTERM');
    });
}

/* ---- small helpers --------------------------------------------------- */

function assert(cond, msg) {
    if (!cond) throw new Error(msg);
}

/* Counts pixels of the diagram canvas: not background, and edge-coloured
 * (the page strokes Voronoi edges in a dark blue, #1f4e79). */
function canvasPixels(page, id) {
    return page.evaluate((canvasId) => {
        const c = document.getElementById(canvasId);
        const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
        let nonbg = 0, edge = 0, colour = 0;
        for (let i = 0; i < d.length; i += 4) {
            const r = d[i], g = d[i + 1], b = d[i + 2], a = d[i + 3];
            if (a === 0) continue;
            if (Math.abs(r - 251) + Math.abs(g - 251) + Math.abs(b - 248) > 40) nonbg++;
            if (b > r + 40 && b > 90 && r < 150) edge++;
            if (Math.max(r, g, b) - Math.min(r, g, b) > 60) colour++;
        }
        return { nonbg: nonbg, edge: edge, colour: colour, width: c.width, height: c.height, cssWidth: c.clientWidth };
    }, id);
}

async function state(page) {
    return page.evaluate(() => {
        const v = window.voronoid;
        const r = v.lastResult;
        return {
            busy: v.busy,
            computeCount: v.computeCount,
            compareCount: v.compareCount,
            sweepCount: v.sweepCount,
            errorCount: v.errorCount,
            downloadCount: v.downloadCount,
            edgesDrawn: v.edgesDrawn,
            sitesDrawn: v.sitesDrawn,
            delaunayEdgesDrawn: v.delaunayEdgesDrawn,
            lod: v.lod,
            drawing: v.drawing,
            frameSlices: v.frameSlices,
            frameRasterMs: v.frameRasterMs,
            decodedIn: v.decodedIn,
            lastError: v.lastError,
            view: v.view,
            timings: v.timings,
            frameMs: v.frameMs,
            result: r,
        };
    });
}

/* Waits until the page has finished a compute after `before` (a count from
 * state()) and drawn it, and is idle; fails early if an error shows up
 * instead. */
async function waitComputed(page, before, timeout) {
    await page.waitForFunction((b) => {
        const v = window.voronoid;
        return !v.busy && !v.drawing && (v.computeCount > b.computeCount || v.errorCount > b.errorCount);
    }, before, { timeout: timeout || STEP_TIMEOUT });
    const s = await state(page);
    if (s.errorCount > before.errorCount) {
        throw new Error('the page shows an error: ' + JSON.stringify(s.lastError));
    }
    return s;
}

/* Waits for fn(arg) in the page, failing at once if the page shows a new
 * error meanwhile (errors counted from `errorsBefore`). */
async function waitOrError(page, fn, arg, errorsBefore, timeout) {
    /* two waits raced, not one combined function: the page's policy
     * forbids evaluating a function passed as a string */
    const opts = { timeout: timeout || STEP_TIMEOUT, polling: 50 };
    const error = page.waitForFunction((e) => window.voronoid && window.voronoid.errorCount > e && !window.voronoid.busy,
        errorsBefore, opts)
        .then(() => 'error');
    const done = page.waitForFunction(fn, arg, opts).then(() => 'ok');
    const first = await Promise.race([done, error]);
    /* the loser keeps polling until its timeout; its rejection is of no interest */
    done.catch(() => {});
    error.catch(() => {});
    if (first === 'error') {
        throw new Error('the page shows an error: ' + JSON.stringify((await state(page)).lastError));
    }
}

async function text(page, selector) {
    return (await page.locator(selector).innerText()).trim();
}

/* A time figure as the page prints it: "1.23 ms", "0.456 ms", "2.1 s". */
const TIME_RE = /^\d+(\.\d+)? (ms|s)$/;

/* ---- the steps ------------------------------------------------------- */

function csvOf(points) {
    return '# x,y\n' + points.map((p) => p[0] + ',' + p[1]).join('\n') + '\n';
}

async function main() {
    fs.mkdirSync(OUT, { recursive: true });
    const results = [];
    const problems = [];      /* console errors and page errors */
    let allowHttpErrors = 0;  /* while > 0, a failed-resource console line is expected */
    let daemon = null;
    let context = null;
    const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'voronoid-browser-'));

    const cleanup = async () => {
        if (context) await context.close().catch(() => {});
        context = null;
        const d = daemon;
        daemon = null;
        if (d) await stopDaemon(d);
        fs.rmSync(profile, { recursive: true, force: true });
    };
    for (const sig of ['SIGINT', 'SIGTERM']) {
        process.on(sig, () => {
            cleanup().finally(() => process.exit(130));
        });
    }

    async function step(name, fn) {
        const t0 = Date.now();
        try {
            await fn();
            results.push({ name: name, ok: true });
            console.log('ok   ' + name + ' (' + (Date.now() - t0) + ' ms)');
        } catch (e) {
            results.push({ name: name, ok: false });
            console.log('FAIL ' + name + ': ' + (e && e.stack || e));
        }
    }

    try {
        daemon = await startDaemon();
        const base = 'http://127.0.0.1:' + daemon.port + '/';
        console.log('daemon ' + path.relative(ROOT, DAEMON) + ' on ' + base + (WEB_DIR ? ' (page from ' + WEB_DIR + ')' : ''));

        context = await chromium.launchPersistentContext(profile, {
            executablePath: CHROMIUM,
            headless: true,
            args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
                '--disable-background-networking', '--disable-component-update', '--disable-sync'],
            viewport: { width: 1280, height: 800 },
            deviceScaleFactor: 1,
            acceptDownloads: true,
        });
        /* The page must run under the service's Content-Security-Policy
         * (no inline script or style, no eval, workers and fetches from
         * its own origin only). Where a daemon does not send it, the test
         * adds it to the page's own files, so the page is always tried
         * under it; any violation is a console error, which fails the run. */
        await context.route((url) => url.pathname === '/' || /^\/[A-Za-z0-9_-]+\.(html|js|css)$/.test(url.pathname), async (route) => {
            const resp = await route.fetch();
            const headers = resp.headers();
            if (!headers['content-security-policy']) headers['content-security-policy'] = CSP;
            await route.fulfill({ response: resp, headers: headers });
        });
        const page = context.pages()[0] || await context.newPage();
        page.setDefaultTimeout(STEP_TIMEOUT);
        page.on('console', (msg) => {
            if (msg.type() !== 'error') return;
            const t = msg.text();
            if (allowHttpErrors > 0 && /Failed to load resource: the server responded with a status of (4\d\d|503)/.test(t)) return;
            problems.push('console error: ' + t);
        });
        page.on('pageerror', (err) => problems.push('page error: ' + (err && err.stack || err)));
        page.on('requestfailed', (req) => {
            const f = req.failure();
            if (f && /ERR_ABORTED/.test(f.errorText)) return; /* a compute superseded by a newer one */
            problems.push('request failed: ' + req.url() + ' ' + (f ? f.errorText : ''));
        });

        await step('page loads with labelled controls and a first diagram', async () => {
            const resp = await page.goto(base, { waitUntil: 'load' });
            assert(resp && resp.status() === 200, 'GET / answered ' + (resp && resp.status()));
            assert(/text\/html/.test(resp.headers()['content-type'] || ''), 'GET / is not text/html');
            assert((await page.title()).includes('voronoid'), 'title does not name voronoid');
            await page.waitForFunction(() => window.voronoid && !window.voronoid.busy && !window.voronoid.drawing &&
                (window.voronoid.computeCount > 0 || window.voronoid.errorCount > 0));
            const s = await state(page);
            assert(s.computeCount === 1 && !s.lastError, 'the first compute failed: ' + JSON.stringify(s.lastError));
            /* every form control has a label a screen reader can read */
            const unlabelled = await page.evaluate(() => Array.from(document.querySelectorAll('input, select, button'))
                .filter((el) => !(el.labels && el.labels.length) && !el.getAttribute('aria-label') && !el.textContent.trim())
                .map((el) => el.id || el.outerHTML.slice(0, 60)));
            assert(unlabelled.length === 0, 'controls without a label: ' + unlabelled.join(', '));
            /* the daemon serves the page as it is in the tree (a stale
             * embedded copy means the binary needs a rebuild) */
            const dir = WEB_DIR || path.join(ROOT, 'web');
            const files = fs.readdirSync(dir).filter((f) => fs.statSync(path.join(dir, f)).isFile());
            assert(files.includes('main.js') && files.includes('index.html'), 'web files: ' + files.join(', '));
            for (const f of files) {
                const served = await page.evaluate((u) => fetch(u).then(async (r) =>
                    ({ status: r.status, type: r.headers.get('content-type') || '', text: await r.text() })),
                base + (f === 'index.html' ? '' : f));
                assert(served.status === 200, f + ' answers ' + served.status);
                assert(served.text === fs.readFileSync(path.join(dir, f), 'utf8'),
                    f + ' as served differs from ' + path.relative(ROOT, path.join(dir, f)) + ' (rebuild the daemon: make)');
                /* a module script runs only when served as JavaScript */
                if (f.endsWith('.js')) assert(/^text\/javascript\b/.test(served.type), f + ' is served as ' + served.type);
            }
            /* every module is one of these files, loaded by the page from its own origin */
            const loaded = await page.evaluate(() => performance.getEntriesByType('resource')
                .map((e) => new URL(e.name)).filter((u) => u.origin === location.origin && /\.js$/.test(u.pathname))
                .map((u) => u.pathname.slice(1)));
            for (const f of files.filter((x) => x.endsWith('.js'))) {
                assert(loaded.includes(f), f + ' was not loaded by the page (loaded: ' + loaded.join(', ') + ')');
            }
        });

        await step('1000 generated points computed with each algorithm are drawn and timed', async () => {
            await page.selectOption('#distribution', 'uniform');
            await page.fill('#n', '1000');
            await page.fill('#seed', '7');
            let before = await state(page);
            await page.click('#generate');
            await waitComputed(page, before);
            for (const alg of ALGORITHMS) {
                before = await state(page);
                const radio = page.locator('input[name=algorithm][value="' + alg + '"]');
                if (await radio.isChecked()) await page.click('#compute');
                else await radio.check();
                const s = await waitComputed(page, before);
                assert(s.result.algorithm === alg, alg + ': result names ' + s.result.algorithm);
                assert(s.result.format === 'json', alg + ': answer format ' + s.result.format);
                assert(s.result.n_input === 1000 && s.result.n_sites === 1000, alg + ': expected 1000 sites, got ' + s.result.n_sites);
                /* Euler for a Voronoi diagram of n sites, not all collinear:
                 * V - E + n = 1; in general position E is about 3n */
                assert(s.result.n_edges === s.result.n_vertices + 1000 - 1,
                    alg + ': V = ' + s.result.n_vertices + ', E = ' + s.result.n_edges + ' break Euler');
                assert(s.result.n_edges > 2900 && s.result.n_edges < 3000, alg + ': ' + s.result.n_edges + ' edges for 1000 sites');
                assert(s.edgesDrawn > 2000 && s.edgesDrawn <= s.result.n_edges, alg + ': ' + s.edgesDrawn + ' edges drawn');
                assert(s.sitesDrawn === 1000, alg + ': ' + s.sitesDrawn + ' sites drawn');
                const px = await canvasPixels(page, 'diagram');
                assert(px.edge > 20000, alg + ': only ' + px.edge + ' edge-coloured pixels on the canvas');
                const tc = await text(page, '#t-compute'), tr = await text(page, '#t-roundtrip');
                assert(TIME_RE.test(tc), alg + ': server compute time shows "' + tc + '"');
                assert(TIME_RE.test(tr), alg + ': round trip shows "' + tr + '"');
                assert(s.timings.roundtrip_ms >= s.timings.server_ms, alg + ': round trip shorter than the server time');
                const phases = await page.locator('#phases li').count();
                assert(phases >= 3, alg + ': ' + phases + ' timing phases listed');
                assert(s.timings.phases.some((p) => p.name === 'compute'), alg + ': no compute phase in ' + JSON.stringify(s.timings.phases));
                await page.screenshot({ path: path.join(OUT, 'diagram-' + alg + '.png') });
            }
        });

        await step('Delaunay triangles, pan and zoom', async () => {
            let before = await state(page);
            await page.check('#show-delaunay');
            let s = await waitComputed(page, before);
            /* a Voronoi vertex of degree k is k - 2 Delaunay triangles, so
             * there are at least as many triangles as vertices */
            assert(s.result.n_triangles >= s.result.n_vertices && s.result.n_triangles > 1900,
                'expected about 2n triangles, got ' + s.result.n_triangles);
            /* each Delaunay edge is drawn once: a triangulation of n sites
             * with h on the hull (h rays) has 3n - 3 - h edges, each in two
             * triangles but the h on the hull, (3T + h) / 2 */
            const n = s.result.n_sites, h = s.result.n_rays;
            assert(s.delaunayEdgesDrawn === 3 * n - 3 - h && 2 * s.delaunayEdgesDrawn === 3 * s.result.n_triangles + h,
                'Delaunay edges drawn ' + s.delaunayEdgesDrawn + ' for ' + n + ' sites, ' + h + ' on the hull, ' +
                s.result.n_triangles + ' triangles');
            assert(s.lod.delaunay.pixels < s.delaunayEdgesDrawn / 10, 'at 1000 sites the Delaunay edges should be lines: ' +
                JSON.stringify(s.lod));
            /* edges off: the blue pixels must go, so they were the edges */
            const withEdges = await canvasPixels(page, 'diagram');
            await page.uncheck('#show-edges');
            await page.waitForFunction(() => window.voronoid.edgesDrawn === 0);
            const without = await canvasPixels(page, 'diagram');
            assert(without.edge < withEdges.edge / 10, 'edge pixels ' + withEdges.edge + ' -> ' + without.edge + ' with edges hidden');
            await page.check('#show-edges');
            await page.waitForFunction(() => window.voronoid.edgesDrawn > 0);

            const z0 = (await state(page)).view.zoom;
            await page.click('#zoom-in');
            await page.waitForFunction((z) => window.voronoid.view.zoom > z * 1.4, z0);
            const box = await page.locator('#diagram').boundingBox();
            const v1 = (await state(page)).view;
            await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
            await page.mouse.down();
            await page.mouse.move(box.x + box.width / 2 + 120, box.y + box.height / 2 + 60, { steps: 6 });
            await page.mouse.up();
            await page.waitForFunction((mx) => window.voronoid.view.mx !== mx, v1.mx);
            const v2 = (await state(page)).view;
            assert(v2.mx < v1.mx && v2.my > v1.my, 'dragging right and down should move the view left and up');
            assert((await state(page)).result.n_sites === 1000, 'a drag must not add a point');
            await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
            await page.mouse.wheel(0, 400);
            await page.waitForFunction((z) => window.voronoid.view.zoom < z, v2.zoom);
            await page.click('#zoom-fit');
            await page.screenshot({ path: path.join(OUT, 'delaunay.png') });

            await page.uncheck('#show-delaunay');
            await page.waitForFunction(() => window.voronoid.delaunayEdgesDrawn === 0);
        });

        await step('on a HiDPI screen the canvas has device pixels', async () => {
            /* device pixel ratio 2 (emulated, then reloaded: the emulation
             * sends the page no change event) */
            const lowres = await canvasPixels(page, 'diagram');
            const cdp = await context.newCDPSession(page);
            const reload = async () => {
                await page.reload({ waitUntil: 'load' });
                await page.waitForFunction(() => window.voronoid && !window.voronoid.busy && !window.voronoid.drawing &&
                    (window.voronoid.computeCount > 0 || window.voronoid.errorCount > 0));
            };
            try {
                await cdp.send('Emulation.setDeviceMetricsOverride', { width: 1280, height: 800, deviceScaleFactor: 2, mobile: false });
                await reload();
                const dims = await page.evaluate(() => {
                    const c = document.getElementById('diagram');
                    return [c.width, c.height, c.clientWidth, c.clientHeight, window.devicePixelRatio];
                });
                assert(dims[4] === 2, 'device pixel ratio ' + dims[4]);
                assert(dims[0] === 2 * dims[2] && dims[1] === 2 * dims[3], 'canvas ' + dims[0] + 'x' + dims[1] +
                    ' for a CSS box of ' + dims[2] + 'x' + dims[3]);
                const hi = await canvasPixels(page, 'diagram');
                assert(hi.edge > 2 * lowres.edge, 'HiDPI edge pixels ' + hi.edge + ' against ' + lowres.edge + ' at ratio 1');
                await page.screenshot({ path: path.join(OUT, 'hidpi.png'), clip: { x: 300, y: 80, width: 500, height: 400 } });
            } finally {
                await cdp.send('Emulation.clearDeviceMetricsOverride');
                await cdp.detach();
                await reload();
            }
            const dims = await page.evaluate(() => [document.getElementById('diagram').width, document.getElementById('diagram').clientWidth]);
            assert(dims[0] === dims[1], 'canvas back at ratio 1: ' + dims);
        });

        await step('a CSV file is uploaded and drawn', async () => {
            const pts = [[0, 0], [4, 0], [4, 3], [0, 3], [2, 1.5], [1, 2.5], [3, 0.5], [1.5, 0.4], [3.3, 2.2], [0.7, 1.1], [2.6, 2.8]];
            const csv = csvOf(pts) + '2,1.5\n'; /* one duplicate */
            const before = await state(page);
            await page.setInputFiles('#file', { name: 'small.csv', mimeType: 'text/csv', buffer: Buffer.from(csv) });
            const s = await waitComputed(page, before);
            assert(s.result.n_input === 12, 'n_input ' + s.result.n_input);
            assert(s.result.n_sites === 11, 'n_sites ' + s.result.n_sites);
            assert(Array.isArray(s.result.duplicates) && s.result.duplicates.length === 1 &&
                s.result.duplicates[0][0] === 11 && s.result.duplicates[0][1] === 4,
                'duplicates ' + JSON.stringify(s.result.duplicates));
            assert(s.edgesDrawn > 10 && s.sitesDrawn === 11, 'drawn: ' + s.edgesDrawn + ' edges, ' + s.sitesDrawn + ' sites');
            const px = await canvasPixels(page, 'diagram');
            assert(px.edge > 500, 'edge pixels ' + px.edge);
            assert((await text(page, '#source')).includes('small.csv'), 'the source line does not name the file');
            assert(await page.locator('#error').isHidden(), 'an error is shown');
            await page.screenshot({ path: path.join(OUT, 'csv.png') });
        });

        await step('a JSON file dropped on the diagram is drawn', async () => {
            const pts = [[10, 10], [20, 12], [15, 20], [12, 16], [18, 17], [25, 25]];
            const before = await state(page);
            await page.evaluate((json) => {
                const dt = new DataTransfer();
                dt.items.add(new File([json], 'dropped.json', { type: 'application/json' }));
                const wrap = document.getElementById('canvas-wrap');
                for (const type of ['dragenter', 'dragover', 'drop']) {
                    wrap.dispatchEvent(new DragEvent(type, { dataTransfer: dt, bubbles: true, cancelable: true }));
                }
            }, JSON.stringify(pts));
            const s = await waitComputed(page, before);
            assert(s.result.n_input === 6 && s.result.n_sites === 6, 'sites ' + s.result.n_sites);
            assert(s.result.n_edges === s.result.n_vertices + 6 - 1, 'Euler: V ' + s.result.n_vertices + ', E ' + s.result.n_edges);
            assert(s.sitesDrawn === 6 && s.edgesDrawn >= s.result.n_edges - s.result.n_rays && s.edgesDrawn <= s.result.n_edges, 'drawn ' + s.sitesDrawn + ' sites, ' + s.edgesDrawn + ' edges');
            assert((await text(page, '#source')).includes('dropped.json'), 'the source line does not name the file');
            assert(await page.locator('#drop').isHidden(), 'the drop overlay stays');
        });

        await step('a malformed file shows the service\'s problem title and detail', async () => {
            allowHttpErrors++;
            try {
                const before = await state(page);
                await page.setInputFiles('#file', { name: 'broken.csv', mimeType: 'text/csv', buffer: Buffer.from('1,2\n3,4\n5,oops\n') });
                await page.waitForFunction((b) => window.voronoid.errorCount > b && !window.voronoid.busy, before.errorCount);
                const s = await state(page);
                assert(s.lastError && s.lastError.status === 400, 'expected a 400 problem, got ' + JSON.stringify(s.lastError));
                assert(s.lastError.title && s.lastError.detail, 'problem without title or detail: ' + JSON.stringify(s.lastError));
                assert(await page.locator('#error').isVisible(), 'the error box is not visible');
                const title = await text(page, '#error-title'), detail = await text(page, '#error-detail');
                assert(title.includes(s.lastError.title), 'shown title "' + title + '"');
                assert(detail.includes(s.lastError.detail), 'shown detail "' + detail + '"');
                assert(/\b3\b/.test(detail), 'the message does not name line 3: "' + detail + '"');
                const more = await page.locator('#error-more').getAttribute('href');
                assert(more && more.endsWith('/problems/malformed'), 'link to the problem type: ' + more);
                const status = await page.evaluate((u) => fetch(u).then((r) => r.status), more);
                assert(status === 200, more + ' answers ' + status);
                /* the previous diagram stays on screen */
                assert((await canvasPixels(page, 'diagram')).edge > 500, 'the canvas went blank');
                await page.screenshot({ path: path.join(OUT, 'error.png') });

                /* too many points: a 413 with the limit in words */
                const b2 = await state(page);
                await page.evaluate(() => {
                    const n = document.getElementById('n');
                    n.value = '2000000000';
                    n.dispatchEvent(new Event('change'));
                });
                await page.click('#compute');
                await page.waitForFunction((b) => window.voronoid.errorCount > b && !window.voronoid.busy, b2.errorCount);
                const s2 = await state(page);
                assert(s2.lastError.status === 413 || s2.lastError.status === 422,
                    'too many points gave ' + JSON.stringify(s2.lastError));
                assert((await text(page, '#error-title')).length > 0, 'no title for the size error');
                await page.click('#error-close');
                assert(await page.locator('#error').isHidden(), 'the error box does not close');
            } finally {
                allowHttpErrors--;
            }
        });

        await step('clicking on the diagram adds points', async () => {
            await page.click('#clear-points');
            const before = await state(page);
            const box = await page.locator('#diagram').boundingBox();
            const spots = [[0.3, 0.3], [0.7, 0.35], [0.5, 0.7], [0.35, 0.6], [0.62, 0.55]];
            for (const [fx, fy] of spots) {
                await page.mouse.click(box.x + box.width * fx, box.y + box.height * fy);
                await page.waitForTimeout(40);
            }
            await waitOrError(page, () => {
                const v = window.voronoid;
                return !v.busy && v.lastResult && v.lastResult.n_sites === 5;
            }, null, before.errorCount);
            const s = await state(page);
            assert(s.edgesDrawn >= 5, 'edges drawn for 5 clicked points: ' + s.edgesDrawn);
            assert((await canvasPixels(page, 'diagram')).edge > 300, 'no edges on the canvas');
        });

        await step('changing N or seed recomputes a small diagram and marks a large one out of date', async () => {
            await page.fill('#n', '1000');
            let before = await state(page);
            await page.click('#compute');
            await waitComputed(page, before);
            /* a new seed for 1000 points: recomputed without pressing anything */
            before = await state(page);
            await page.fill('#seed', '11');
            const s = await waitComputed(page, before);
            assert(s.result.n_sites === 1000, 'recomputed ' + s.result.n_sites + ' sites');
            assert(!(await page.evaluate(() => window.voronoid.stale)), 'marked stale after the recompute');
            assert(await page.locator('#stale').isHidden(), 'the out-of-date note shows');
            assert((await text(page, '#source')).includes('seed 11'), 'source line ' + await text(page, '#source'));
            /* typing several digits of N computes once, for the last value */
            before = await state(page);
            await page.locator('#n').fill('');
            await page.locator('#n').pressSequentially('1500', { delay: 30 });
            const s2 = await waitComputed(page, before);
            await page.waitForTimeout(600);
            const s3 = await state(page);
            assert(s2.result.n_sites === 1500 && s3.computeCount === before.computeCount + 1,
                'typing 1500 gave ' + (s3.computeCount - before.computeCount) + ' computes, the last of ' + s3.result.n_sites + ' sites');
            /* 50000 points: not recomputed, marked out of date */
            before = await state(page);
            await page.fill('#n', '50000');
            await page.waitForFunction(() => window.voronoid.stale);
            await page.waitForTimeout(700); /* longer than the recompute's delay */
            const stale = await state(page);
            assert(stale.computeCount === before.computeCount && !stale.busy, 'a large N was recomputed by itself');
            assert(await page.locator('#stale').isVisible(), 'no out-of-date note');
            const note = await text(page, '#stale-text');
            assert(/N = 1,500/.test(note) && /N = 50,000/.test(note), 'the note does not say what is shown and what would be: ' + note);
            assert(await page.evaluate(() => document.getElementById('canvas-wrap').classList.contains('stale')), 'the canvas is not dimmed');
            await page.screenshot({ path: path.join(OUT, 'stale.png') });
            /* the note's button computes */
            await page.click('#stale-compute');
            const s4 = await waitComputed(page, before);
            assert(s4.result.n_sites === 50000, 'computed ' + s4.result.n_sites);
            assert(await page.locator('#stale').isHidden() && !(await page.evaluate(() => window.voronoid.stale)), 'still marked stale');
        });

        await step('compare shows each algorithm\'s median, spread, runs and counts (contract answer)', async () => {
            /* an answer shaped as the contract says (openapi.yaml,
             * names.md): repeat, spread per phase, runs_ms, counts */
            let sent = null;
            const answer = {
                n_input: 1000, n_sites: 1000, agree: true, disagreement: null, repeat: 5,
                algorithms: [
                    ['fortune', 2.5, 2.25, 3.5, [2.5, 2.25, 3.5, 2.4, 2.6], { site_events: 1000, circle_events: 2400, false_alarms: 410, beach_max: 61 }],
                    ['bowyer-watson', 1.5, 1.25, 4.75, [1.5, 4.75, 1.25, 1.4, 1.6], { orient2d: 12000, incircle: 9000, walk_steps: 5300 }],
                    ['flip', 1.75, 1.5, 2, [1.75, 1.5, 2, 1.7, 1.8], { orient2d: 11000, flips: 2900 }],
                ].map(([alg, med, min, max, runs, counts]) => ({
                    algorithm: alg, status: 'ok', n_vertices: 1978, n_edges: 2977, n_rays: 20,
                    timings: { queue_ms: 0, parse_ms: 0, prepare_ms: 0.02, compute_ms: med, clip_ms: 0, serialize_ms: 0, total_ms: med + 0.1 },
                    spread: { compute_ms: { median: med, min: min, max: max }, total_ms: { median: med + 0.1, min: min + 0.1, max: max + 0.1 } },
                    runs_ms: runs, counts: counts,
                })),
                timings: { queue_ms: 0, parse_ms: 0.02, prepare_ms: 0, compute_ms: 0, clip_ms: 0, serialize_ms: 0, total_ms: 30 },
            };
            await page.route('**/compare', async (route) => {
                sent = route.request().postDataJSON();
                await route.fulfill({ status: 200, contentType: 'application/json', body: JSON.stringify(answer) });
            });
            try {
                await page.selectOption('#repeat', '5');
                const before = await state(page);
                await page.click('#compare');
                await waitOrError(page, (b) => window.voronoid.compareCount > b.compareCount, before, before.errorCount);
            } finally {
                await page.unroute('**/compare');
            }
            assert(sent && sent.repeat === 5 && sent.generate, 'the request did not ask for 5 runs: ' + JSON.stringify(sent));
            /* the median, and under it the fastest and slowest run */
            const rows = await page.locator('#compare-table tbody tr').evaluateAll((trs) => trs.map((tr) =>
                [tr.cells[1].firstChild.textContent, (tr.cells[1].querySelector('.spread') || {}).textContent]));
            assert(rows.length === 3, 'rows ' + JSON.stringify(rows));
            assert(rows[0][0] === '2.50 ms' && rows[0][1] === '2.25 ms – 3.50 ms', 'Fortune: ' + rows[0].join(' | '));
            assert(rows[1][0] === '1.50 ms' && rows[1][1] === '1.25 ms – 4.75 ms', 'Bowyer–Watson: ' + rows[1].join(' | '));
            assert(rows[2][0] === '1.75 ms' && rows[2][1] === '1.50 ms – 2.00 ms', 'Flipping: ' + rows[2].join(' | '));
            assert(await page.locator('#compare-table td.best').evaluate((td) => td.firstChild.textContent) === '1.50 ms',
                'fastest median not marked');
            assert(/median of 5 runs/.test(await text(page, '#compare-note')), 'note: ' + await text(page, '#compare-note'));
            /* every count of every algorithm, named as the service names it */
            const counts = await page.locator('#counts-table tbody tr').evaluateAll((trs) => trs.map((tr) =>
                [tr.dataset.count].concat(Array.from(tr.cells).slice(1).map((c) => c.textContent.trim()))));
            const names = counts.map((r) => r[0]);
            for (const k of ['site_events', 'circle_events', 'false_alarms', 'beach_max', 'orient2d', 'incircle', 'walk_steps', 'flips']) {
                assert(names.includes(k), 'count ' + k + ' not shown: ' + names.join(', '));
            }
            const orient = counts.find((r) => r[0] === 'orient2d');
            assert(orient[1] === '–' && orient[2] === '12,00012.0 /site' && orient[3] === '11,00011.0 /site', 'orient2d row ' + orient.join(' | '));
            const bars = await canvasPixels(page, 'compare-chart');
            assert(bars.colour > 300, 'the bar chart is empty (' + bars.colour + ' coloured pixels)');
            await page.locator('aside.analysis').screenshot({ path: path.join(OUT, 'compare-spread.png') });
        });

        await step('compare runs all three algorithms on the service and they agree', async () => {
            await page.fill('#n', '1000');
            await page.fill('#seed', '7');
            let before = await state(page);
            await page.click('#generate');
            await waitComputed(page, before);
            await page.selectOption('#repeat', '3');
            before = await state(page);
            await page.click('#compare');
            await waitOrError(page, (b) => window.voronoid.compareCount > b.compareCount, before, before.errorCount);
            const c = await page.evaluate(() => window.voronoid.lastCompare);
            assert(c, 'no compare result: ' + JSON.stringify((await state(page)).lastError));
            const rows = await page.locator('#compare-table tbody tr').count();
            assert(rows === 3, rows + ' rows in the compare table');
            assert(c.rows.map((r) => r.algorithm).join() === ALGORITHMS.join(), 'algorithms ' + c.rows.map((r) => r.algorithm));
            for (const r of c.rows) {
                assert(typeof r.compute_ms === 'number' && r.compute_ms >= 0, r.algorithm + ': compute_ms ' + r.compute_ms);
            }
            assert(c.agree === true, 'the algorithms disagree: ' + c.disagreement);
            const agree = await text(page, '#agree');
            assert(/identical/.test(agree), 'agreement line "' + agree + '"');
            const note = await text(page, '#compare-note');
            assert(c.repeat === 3, 'asked for 3 runs, the answer says ' + c.repeat);
            for (const r of c.rows) {
                const t = r.spread && r.spread.compute_ms;
                assert(t && t.min <= t.median && t.median <= t.max, r.algorithm + ': spread ' + JSON.stringify(r.spread));
                assert(Array.isArray(r.runs_ms) && r.runs_ms.length === 3, r.algorithm + ': runs ' + JSON.stringify(r.runs_ms));
                assert(r.counts && Object.keys(r.counts).length > 0, r.algorithm + ': no counts');
            }
            assert(/median of 3 runs/.test(note), 'note: ' + note);
            /* three runs of real timings: a spread under each median (or
             * none where all three took the same time) */
            const spreads = await page.locator('#compare-table .spread').allInnerTexts();
            assert(spreads.length >= 2 && spreads.every((t) => / – /.test(t)), 'spread cells ' + spreads.join(' | '));
            /* a time cell: the median, and under it (with repeats) the
             * spread */
            const cells = await page.locator('#compare-table tbody td').allInnerTexts();
            assert(cells.filter((t) => TIME_RE.test(t.trim().split('\n')[0].trim())).length >= 3,
                'times in the table: ' + cells.join(' | '));
            const bars = await canvasPixels(page, 'compare-chart');
            assert(bars.colour > 300, 'the bar chart is empty (' + bars.colour + ' coloured pixels)');
        });

        await step('the sweep fits slopes only where they mean something (oracle)', async () => {
            /* the page's fit against the same least squares done here */
            const pts = [[1000, 1.1], [2000, 2.3], [5000, 5.2], [10000, 11.5], [20000, 22.0]];
            const got = await page.evaluate((p) => import('./charts.js').then((m) => [m.fitSlope(p), m.fitSlope(p.slice(0, 2))]), pts);
            const xs = pts.map((q) => Math.log(q[0])), ys = pts.map((q) => Math.log(q[1]));
            const mx = xs.reduce((a, b) => a + b) / 5, my = ys.reduce((a, b) => a + b) / 5;
            const sxx = xs.reduce((a, x) => a + (x - mx) ** 2, 0);
            const slope = xs.reduce((a, x, i) => a + (x - mx) * (ys[i] - my), 0) / sxx;
            const ssr = xs.reduce((a, x, i) => a + (ys[i] - (my + slope * (x - mx))) ** 2, 0);
            const ci = 3.182 * Math.sqrt(ssr / 3 / sxx); /* Student's t, 3 degrees of freedom, 95% */
            assert(Math.abs(got[0].slope - slope) < 1e-12 && Math.abs(got[0].ci - ci) < 1e-12 && got[0].m === 5,
                'fit ' + JSON.stringify(got[0]) + ', expected slope ' + slope + ' ± ' + ci);
            assert(got[1] === null, 'two sizes gave a slope: ' + JSON.stringify(got[1]));
        });

        await step('a sweep of two distributions: table, plot with spread and slopes, CSV, PNG and SVG', async () => {
            await page.selectOption('#repeat', '3');
            for (const el of await page.locator('input[name=sweep-dist]').all()) await el.uncheck();
            await page.check('input[name=sweep-dist][value=uniform]');
            await page.check('input[name=sweep-dist][value=gaussian]');
            await page.fill('#sweep-sizes', '500, 1000, 2000, 5000, 10000, 20000');
            const before = await state(page);
            await page.click('#sweep');
            await waitOrError(page, (b) => window.voronoid.sweepCount > b.sweepCount, before, before.errorCount);
            const sw = await page.evaluate(() => window.voronoid.lastSweep);
            assert(sw && sw.done, 'the sweep did not finish: ' + JSON.stringify((await state(page)).lastError));
            /* sizes in order, the two distributions interleaved at each */
            assert(sw.rows.map((r) => r.distribution[0] + r.n).join() ===
                'u500,g500,u1000,g1000,u2000,g2000,u5000,g5000,u10000,g10000,u20000,g20000', 'rows ' + sw.rows.map((r) => r.distribution + r.n));
            for (const r of sw.rows) {
                for (const a of ALGORITHMS) {
                    const t = r.times[a];
                    assert(t && t.min <= t.median && t.median <= t.max, r.distribution + ' ' + r.n + ' ' + a + ': ' + JSON.stringify(t));
                    assert(t.runs && t.runs.length === 3, 'runs ' + JSON.stringify(t));
                }
                assert(r.agree, r.distribution + ' N=' + r.n + ': the algorithms disagree');
            }
            assert(await page.locator('#sweep-table tbody tr[data-n]').count() === 12, 'sweep table rows');
            /* a slope exactly where three sizes have N >= 1000 and t >= 1 ms */
            const series = await page.evaluate(() => window.voronoid.sweepSeries);
            assert(series.length === 6, series.length + ' series');
            for (const s of series) {
                const usable = sw.rows.filter((r) => r.distribution === s.distribution && r.n >= 1000 && r.times[s.algorithm].median >= 1);
                if (usable.length >= 3) {
                    assert(s.fit && s.fit.sizes === usable.length && s.fit.n0 >= 1000 && s.fit.ci >= 0,
                        s.label + ': fit ' + JSON.stringify(s.fit) + ' over ' + usable.length + ' usable sizes');
                } else {
                    assert(s.fit === null, s.label + ': a slope from ' + usable.length + ' usable sizes');
                }
            }
            const plot = await canvasPixels(page, 'sweep-chart');
            assert(plot.colour > 300, 'the sweep plot has no coloured series (' + plot.colour + ')');
            await page.locator('section[aria-labelledby=sweep-h]').screenshot({ path: path.join(OUT, 'sweep.png') });
            await page.locator('#sweep-chart').scrollIntoViewIfNeeded();
            await page.screenshot({ path: path.join(OUT, 'page.png') });

            const download = async (id) => {
                const [dl] = await Promise.all([page.waitForEvent('download'), page.click('#' + id)]);
                return { name: dl.suggestedFilename(), data: fs.readFileSync(await dl.path()) };
            };
            const csv = await download('sweep-csv');
            assert(csv.name.endsWith('.csv'), 'CSV file name ' + csv.name);
            const lines = csv.data.toString('utf8').trim().split('\n');
            const head = lines[0].split(',');
            assert(head.join() === 'sweep,distribution,seed,repeat,n,algorithm,status,median_ms,min_ms,max_ms,runs_ms,agree', 'CSV header ' + lines[0]);
            assert(lines.length === 1 + 12 * 3, lines.length - 1 + ' CSV lines');
            for (const line of lines.slice(1)) {
                const f = Object.fromEntries(line.split(',').map((v, i) => [head[i], v]));
                const row = sw.rows.find((r) => r.distribution === f.distribution && r.n === Number(f.n));
                assert(row, 'CSV line for no row: ' + line);
                const t = row.times[f.algorithm];
                assert(Number(f.median_ms) === t.median && Number(f.min_ms) === t.min && Number(f.max_ms) === t.max,
                    'CSV line ' + line + ' against ' + JSON.stringify(t));
                assert(f.runs_ms.split(';').length === 3 && f.repeat === '3', 'CSV runs ' + line);
                assert(f.status === 'ok' && f.agree === 'yes' && f.seed === String(sw.seed), 'CSV line ' + line);
            }
            const png = await download('sweep-png');
            assert(png.name.endsWith('.png') && png.data.slice(1, 4).toString() === 'PNG' && png.data.length > 5000,
                'PNG export: ' + png.name + ', ' + png.data.length + ' bytes');
            const svg = await download('sweep-svg');
            const svgText = svg.data.toString('utf8');
            assert(svg.name.endsWith('.svg') && /<svg[\s>]/.test(svgText), 'SVG export ' + svg.name);
            assert((svgText.match(/<polyline/g) || []).length >= 6, 'SVG export: ' + (svgText.match(/<polyline/g) || []).length + ' series lines');
            assert(/uniform · Fortune/.test(svgText) && /gaussian · Flip/.test(svgText), 'SVG export without the legend');
            fs.writeFileSync(path.join(OUT, 'sweep-export.svg'), svgText);
            fs.writeFileSync(path.join(OUT, 'sweep-export.png'), png.data);

            /* a second sweep is added, the first stays until Clear */
            await page.uncheck('input[name=sweep-dist][value=gaussian]');
            await page.fill('#sweep-sizes', '1000, 2000');
            const b2 = await state(page);
            await page.click('#sweep');
            await waitOrError(page, (b) => window.voronoid.sweepCount > b.sweepCount, b2, b2.errorCount);
            const kept = await page.evaluate(() => ({ sweeps: window.voronoid.sweeps.length, series: window.voronoid.sweepSeries.length }));
            assert(kept.sweeps === 2 && kept.series === 9, 'after a second sweep: ' + JSON.stringify(kept));
            assert(await page.locator('#sweep-table tbody tr[data-n]').count() === 14, 'both sweeps in the table');
            await page.click('#sweep-clear');
            const cleared = await page.evaluate(() => ({ sweeps: window.voronoid.sweeps.length, series: window.voronoid.sweepSeries.length }));
            assert(cleared.sweeps === 0 && cleared.series === 0, 'after Clear: ' + JSON.stringify(cleared));
            assert(await page.locator('#sweep-table').isHidden() && await page.locator('#sweep-csv').isDisabled(), 'Clear left the table or exports');
            await page.fill('#sweep-sizes', '500, 1000, 2000, 4000');
        });

        await step('the JSON, GeoJSON and SVG downloads hold the diagram', async () => {
            /* the last diagram is the compare step's 1000 generated points */
            const shown = (await state(page)).result;
            const fetchDownload = async (format) => {
                const before = await state(page);
                const [dl] = await Promise.all([
                    Promise.race([
                        page.waitForEvent('download'),
                        waitOrError(page, () => false, null, before.errorCount),
                    ]),
                    page.click('.download button[data-format=' + format + ']'),
                ]);
                assert(dl.suggestedFilename().endsWith('.' + format), 'file name ' + dl.suggestedFilename());
                return fs.readFileSync(await dl.path(), 'utf8');
            };
            const json = JSON.parse(await fetchDownload('json'));
            assert(json.n_sites === shown.n_sites && json.n_edges === shown.n_edges,
                'JSON download: ' + json.n_sites + ' sites, ' + json.n_edges + ' edges; shown ' + shown.n_sites + ', ' + shown.n_edges);
            assert(Array.isArray(json.cells) && json.cells.length === json.n_sites, 'JSON download without cells');
            assert(Array.isArray(json.edges) && json.edges.length === json.n_edges, 'JSON download without edges');
            const geo = JSON.parse(await fetchDownload('geojson'));
            assert(geo.type === 'FeatureCollection' && Array.isArray(geo.features) && geo.features.length > 0,
                'GeoJSON download: ' + JSON.stringify(geo).slice(0, 80));
            const svg = await fetchDownload('svg');
            assert(/<svg[\s>]/.test(svg), 'not an SVG: ' + svg.slice(0, 80));
            assert((svg.match(/<(line|path|polyline|polygon)\b/g) || []).length > 0, 'the SVG draws nothing');
        });

        await step('100000 points come back as binary arrays and are drawn', async () => {
            await page.fill('#n', '100000');
            await page.fill('#seed', '3');
            const before = await state(page);
            await page.click('#generate');
            const s = await waitComputed(page, before);
            assert(s.result.format === 'binary', 'answer format ' + s.result.format);
            assert(s.result.n_input === 100000 && s.result.n_sites === 100000, 'sites ' + s.result.n_sites);
            assert(s.result.n_edges === s.result.n_vertices + 100000 - 1,
                'V = ' + s.result.n_vertices + ', E = ' + s.result.n_edges + ' break Euler');
            assert(s.edgesDrawn > 290000, 'edges drawn ' + s.edgesDrawn);
            assert(s.sitesDrawn === 100000, 'sites drawn ' + s.sitesDrawn);
            assert(s.decodedIn === 'worker', 'the answer was decoded in ' + s.decodedIn);
            const px = await canvasPixels(page, 'diagram');
            assert(px.edge > 100000, 'edge pixels ' + px.edge);
            /* zoomed in 27 times, the frame visits only what is in view and
             * the edges there are long enough to be lines */
            for (let i = 0; i < 8; i++) await page.click('#zoom-in');
            await page.waitForFunction(() => !window.voronoid.drawing && window.voronoid.view.zoom > 0);
            await page.waitForTimeout(400);
            await page.waitForFunction(() => !window.voronoid.drawing);
            const zoomed = await state(page);
            assert(zoomed.edgesDrawn > 50 && zoomed.edgesDrawn < s.edgesDrawn / 100,
                'zoomed in: ' + zoomed.edgesDrawn + ' edges drawn of ' + s.edgesDrawn);
            assert(zoomed.lod.edges.pixels < zoomed.lod.edges.lines / 10, 'zoomed in, edges as pixels: ' + JSON.stringify(zoomed.lod));
            await page.screenshot({ path: path.join(OUT, 'large-zoomed.png') });
            await page.click('#zoom-fit');
            await page.waitForTimeout(400);
            await page.waitForFunction(() => !window.voronoid.drawing);
            /* a zoom redraws from the prepared diagram; its cost is printed, not judged */
            await page.waitForTimeout(300);
            const painted = (await state(page)).timings.draw_ms;
            await page.evaluate(() => { window.voronoid.framePaintMs = 0; });
            await page.click('#zoom-in');
            await page.waitForFunction(() => window.voronoid.framePaintMs > 0);
            const frame = await page.evaluate(() => window.voronoid.framePaintMs);
            console.log('     100000 points: round trip ' + s.timings.roundtrip_ms.toFixed(0) + ' ms, server compute ' +
                s.timings.server_ms.toFixed(0) + ' ms, decode+draw until painted ' + painted.toFixed(0) +
                ' ms, a zoom frame ' + frame.toFixed(0) + ' ms');
            await page.screenshot({ path: path.join(OUT, 'large.png') });
            await page.click('#zoom-fit');
        });

        await step('10^6 points with every layer on: the page answers input while it draws', async () => {
            /* every main-thread task over 50 ms, as the browser reports it */
            await page.evaluate(() => {
                window.__longTasks = [];
                window.__longObserver = new PerformanceObserver((list) => {
                    for (const e of list.getEntries()) window.__longTasks.push({ start: e.startTime, ms: e.duration });
                });
                window.__longObserver.observe({ type: 'longtask' });
                /* an input event handled while a frame is being drawn */
                window.__inputs = [];
                document.getElementById('sweep-sizes').addEventListener('input', () => {
                    window.__inputs.push({ drawing: window.voronoid.drawing, at: performance.now() });
                });
            });
            for (const id of ['#show-sites', '#show-edges', '#show-delaunay', '#show-clip']) await page.check(id);
            await page.waitForFunction(() => !window.voronoid.busy && !window.voronoid.drawing, null, { timeout: 180000 });
            await page.fill('#n', '1000000');
            await page.fill('#seed', '5');
            const before = await state(page);
            const t0 = await page.evaluate(() => performance.now());
            await page.click('#compute');
            /* once the diagram is on its way to the canvas, type */
            await page.waitForFunction((b) => window.voronoid.computeCount > b.computeCount || window.voronoid.errorCount > b.errorCount,
                before, { timeout: 180000 });
            const typedWhile = await page.evaluate(() => window.voronoid.drawing);
            await page.locator('#sweep-sizes').pressSequentially('1');
            /* and drag the view */
            const box = await page.locator('#diagram').boundingBox();
            await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
            await page.mouse.down();
            await page.mouse.move(box.x + box.width / 2 + 80, box.y + box.height / 2 + 40, { steps: 8 });
            await page.mouse.up();
            const s = await waitComputed(page, before, 180000);
            const t1 = await page.evaluate(() => performance.now());
            const r = await page.evaluate(() => ({ tasks: window.__longTasks, inputs: window.__inputs }));
            await page.evaluate(() => window.__longObserver.disconnect());
            assert(s.result.n_sites === 1000000 && s.result.format === 'binary', 'result ' + JSON.stringify(s.result).slice(0, 200));
            assert(s.decodedIn === 'worker', 'decoded in ' + s.decodedIn);
            assert(r.inputs.length >= 1, 'the typed key was not handled');
            if (typedWhile) {
                assert(r.inputs[0].drawing, 'the key typed while drawing was handled only after the frame was done');
            }
            assert(s.frameSlices > 1, 'the frame was drawn in ' + s.frameSlices + ' slice(s)');
            /* at this density the diagram is plotted as pixels, not stroked */
            assert(s.lod.edges.pixels > s.lod.edges.lines && s.lod.delaunay.pixels > s.lod.delaunay.lines &&
                s.lod.cells.pixels > s.lod.cells.paths, 'level of detail ' + JSON.stringify(s.lod));
            assert(s.edgesDrawn > 0.9 * s.result.n_edges, s.edgesDrawn + ' of ' + s.result.n_edges + ' edges drawn');
            assert((await canvasPixels(page, 'diagram')).edge > 10000, 'no edges on the canvas');
            const tasks = r.tasks.filter((t) => t.start >= t0);
            const worst = tasks.reduce((m, t) => Math.max(m, t.ms), 0);
            console.log('     10^6 points, every layer: ' + ((t1 - t0) / 1000).toFixed(1) + ' s from Compute to the drawn frame (server compute ' +
                (s.timings.server_ms / 1000).toFixed(2) + ' s, round trip ' + (s.timings.roundtrip_ms / 1000).toFixed(2) +
                ' s); frame of ' + s.frameSlices + ' slices, ' + s.frameMs.toFixed(0) + ' ms on the page\'s thread (' +
                s.frameRasterMs.toFixed(0) + ' ms of it rasterising); long tasks (> 50 ms): ' +
                tasks.length + ', longest ' + worst.toFixed(0) + ' ms' + (tasks.length ? ' [' + tasks.map((t) => t.ms.toFixed(0)).join(', ') + ']' : '') +
                '; key typed ' + (typedWhile ? 'while drawing, handled while drawing: ' + r.inputs[0].drawing : 'after the frame'));
            await page.screenshot({ path: path.join(OUT, 'million.png') });
            await page.fill('#sweep-sizes', '500, 1000, 2000, 4000');
            for (const id of ['#show-delaunay', '#show-clip']) await page.uncheck(id);
            await page.fill('#n', '1000');
            before.computeCount = (await state(page)).computeCount;
            await page.click('#compute');
            await waitComputed(page, before);
        });

        await step('narrow window layout', async () => {
            await page.setViewportSize({ width: 900, height: 800 });
            await page.waitForFunction(() => window.voronoid.view && document.getElementById('diagram').clientWidth < 700);
            const px = await canvasPixels(page, 'diagram');
            assert(px.edge > 1000, 'the diagram is not drawn after a resize');
            await page.screenshot({ path: path.join(OUT, 'narrow.png'), fullPage: true });
            await page.setViewportSize({ width: 1280, height: 800 });
        });

        await step('on a phone (390x844) the diagram comes first and Compute brings it into view', async () => {
            await page.setViewportSize({ width: 390, height: 844 });
            try {
                await page.goto(base, { waitUntil: 'load' });
                await page.waitForFunction(() => window.voronoid && window.voronoid.computeCount > 0 &&
                    !window.voronoid.busy && !window.voronoid.drawing);
                const inView = () => page.evaluate(() => {
                    const r = document.getElementById('diagram').getBoundingClientRect();
                    return { top: r.top, bottom: r.bottom, height: r.height, width: r.width, vh: window.innerHeight };
                });
                let r = await inView();
                assert(r.top >= 0 && r.top < r.vh && r.bottom <= r.vh, 'the canvas is not within the first screen: ' + JSON.stringify(r));
                assert(r.width >= 380 && r.height >= 300, 'the canvas is small: ' + JSON.stringify(r));
                assert((await canvasPixels(page, 'diagram')).edge > 5000, 'no diagram on the first screen');
                /* the controls come after the diagram */
                const order = await page.evaluate(() => ['view', 'compute', 'compare'].map((id) =>
                    document.getElementById(id).getBoundingClientRect().top + window.scrollY));
                assert(order[0] < order[1] && order[1] < order[2], 'diagram, controls, compare out of order: ' + order);
                await page.screenshot({ path: path.join(OUT, 'phone.png') });
                /* Compute, pressed from below the diagram, brings it back into view */
                await page.fill('#n', '3000');
                await page.locator('#compute').scrollIntoViewIfNeeded();
                r = await inView();
                assert(r.top < 0, 'the canvas should be scrolled away at the Compute button: ' + JSON.stringify(r));
                const before = await state(page);
                await page.click('#compute');
                const s = await waitComputed(page, before);
                assert(s.result.n_sites === 3000, 'computed ' + s.result.n_sites);
                await page.waitForFunction(() => {
                    const t = document.getElementById('diagram').getBoundingClientRect().top;
                    return t >= 0 && t < window.innerHeight / 2;
                });
                await page.screenshot({ path: path.join(OUT, 'phone-after-compute.png') });
                await page.screenshot({ path: path.join(OUT, 'phone-full.png'), fullPage: true });
            } finally {
                await page.setViewportSize({ width: 1280, height: 800 });
            }
        });

        /* ---- step through ------------------------------------------------ */

        /* A small degenerate set: a 5 x 5 grid (cocircular fours
         * everywhere, collinear hull sides), eight points on a circle of
         * radius 3 around its centre (four of them exactly cocircular),
         * and two duplicates. */
        const replayPoints = [];
        for (let i = 0; i < 5; i++) for (let j = 0; j < 5; j++) replayPoints.push([i, j]);
        for (let k = 0; k < 8; k++) replayPoints.push([2 + 3 * Math.cos(k * Math.PI / 4), 2 + 3 * Math.sin(k * Math.PI / 4)]);
        replayPoints.push([2, 2], [4, 0]);
        const post = async (body) => {
            const r = await fetch(base + 'voronoi', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
            const j = await r.json();
            assert(r.status === 200, 'POST voronoi answered ' + r.status + ': ' + JSON.stringify(j));
            return j;
        };
        /* the running counts after step f, merged from the trace here */
        const countsAt = (steps, f) => {
            const c = {};
            for (let k = 0; k <= f; k++) Object.assign(c, steps[k].counts);
            return c;
        };
        /* edges as site pairs -> [end, end, ray] with the ends as vertex
         * coordinates (null for an unbounded end) */
        const edgeMap = (d) => new Map(d.edges.map((e) => [e.sites.join(','),
            JSON.stringify([e.ends.map((i) => (i == null ? null : d.vertices[i])), e.ray || null])]));
        const replayState = () => page.evaluate(() => {
            const r = window.voronoid.replay;
            return {
                active: r.active, algorithm: r.algorithm, steps: r.steps, frame: r.frame, prepared: r.prepared,
                ready: r.ready, playing: r.playing, kind: r.kind, counts: r.counts, matches: r.matches, loads: r.loads,
                text: document.getElementById('rp-frame').textContent,
                what: document.getElementById('rp-what').textContent,
                shown: Object.fromEntries(Array.from(document.querySelectorAll('#rp-counts > div')).map((d) =>
                    [d.dataset.count, d.querySelector('.now').textContent.replace(/,/g, '')])),
            };
        });
        /* the frame shown is f (0-based): counter, state and the counts
         * beside the picture, against the trace */
        const checkFrame = async (steps, f, what) => {
            await page.waitForFunction((g) => window.voronoid.replay.frame === g, f);
            const s = await replayState();
            assert(s.text.startsWith('step ' + (f + 1).toLocaleString('en-US') + ' / ' + steps.length.toLocaleString('en-US')),
                what + ': the counter reads "' + s.text + '" at step ' + (f + 1));
            assert(s.kind === steps[f].kind, what + ': kind ' + s.kind + ', the trace says ' + steps[f].kind);
            const want = countsAt(steps, f);
            for (const k of Object.keys(want)) {
                assert(s.counts[k] === want[k] && s.shown[k] === String(want[k]),
                    what + ': count ' + k + ' is ' + s.counts[k] + ' (shown ' + s.shown[k] + '), the trace says ' + want[k]);
            }
            return s;
        };
        const scrubTo = (f) => page.evaluate((g) => {
            const s = document.getElementById('rp-scrub');
            s.value = String(g);
            s.dispatchEvent(new Event('input', { bubbles: true }));
        }, f);
        /* the frame nearest the middle whose step is of this kind (and
         * passes ok) */
        const middleOf = (steps, kinds, ok) => {
            let best = -1;
            steps.forEach((st, i) => {
                if (kinds.includes(st.kind) && (!ok || ok(st)) && (best < 0 || Math.abs(i - steps.length / 2) < Math.abs(best - steps.length / 2))) best = i;
            });
            return best;
        };

        await step('step through: each algorithm, stepped to the end of a degenerate set, ends in the service\'s diagram', async () => {
            const before = await state(page);
            await page.setInputFiles('#file', { name: 'degenerate.csv', mimeType: 'text/csv', buffer: Buffer.from(csvOf(replayPoints)) });
            await waitComputed(page, before);
            await page.locator('input[name=algorithm][value=fortune]').check();
            await page.waitForFunction(() => !window.voronoid.busy && !window.voronoid.drawing);
            let loads = (await replayState()).loads;
            await page.click('#step-through');
            for (const alg of ALGORITHMS) {
                if (alg !== 'fortune') {
                    loads = (await replayState()).loads;
                    await page.locator('input[name=algorithm][value="' + alg + '"]').check();
                }
                await waitOrError(page, (a) => window.voronoid.replay.loads > a.loads && window.voronoid.replay.ready &&
                    window.voronoid.replay.algorithm === a.alg && !window.voronoid.busy, { loads: loads, alg: alg }, (await state(page)).errorCount);
                const traced = await post({ points: replayPoints, algorithm: alg, trace: true, include: ['counts'] });
                const normal = await post({ points: replayPoints, algorithm: alg, include: ['vertices', 'edges', 'counts'] });
                const steps = traced.trace.steps;
                let s = await replayState();
                assert(s.active && s.algorithm === alg && s.steps === steps.length && s.prepared === steps.length,
                    alg + ': replay state ' + JSON.stringify(s).slice(0, 300));
                assert(await page.locator('#replay').isVisible() && await page.getAttribute('#step-through', 'aria-pressed') === 'true',
                    alg + ': the step-through panel is not shown');
                await checkFrame(steps, 0, alg + ' first frame');
                /* to the end */
                await page.click('#rp-last');
                s = await checkFrame(steps, steps.length - 1, alg + ' last frame');
                assert(s.kind === 'end', alg + ': the last step is ' + s.kind);
                for (const k of Object.keys(normal.counts)) {
                    assert(s.counts[k] === normal.counts[k], alg + ': final count ' + k + ' ' + s.counts[k] + ', the answer has ' + normal.counts[k]);
                }
                /* the last frame's diagram, rebuilt from the replayed
                 * triangulation, is the normal answer's: the same site
                 * pairs, vertex positions and rays, bit for bit */
                const frame = await page.evaluate(() => window.voronoid.replay.frameDiagram());
                assert(frame.vertices.length === normal.n_vertices && frame.edges.length === normal.n_edges,
                    alg + ': last frame has ' + frame.vertices.length + ' vertices, ' + frame.edges.length + ' edges; the answer ' +
                    normal.n_vertices + ', ' + normal.n_edges);
                const got = edgeMap(frame), want = edgeMap(normal);
                for (const [k, v] of want) {
                    assert(got.get(k) === v, alg + ': edge ' + k + ' is ' + got.get(k) + ' in the last frame, ' + v + ' in the answer');
                }
                assert(s.matches === true && /same diagram as the service/.test(s.what), alg + ': the page does not say the last frame is the answer: ' + s.what);
                /* back and forth: buttons, keys, the scrubber */
                const n = steps.length;
                for (let i = 0; i < 3; i++) await page.click('#rp-back');
                await checkFrame(steps, n - 4, alg + ' three steps back');
                await page.locator('#rp-first').focus();
                await page.keyboard.press('ArrowRight');
                await checkFrame(steps, n - 3, alg + ' arrow right');
                await page.keyboard.press('Home');
                await checkFrame(steps, 0, alg + ' Home');
                for (let i = 0; i < 5; i++) await page.click('#rp-fwd');
                await checkFrame(steps, 5, alg + ' five steps forward');
                await page.keyboard.press('Shift+Period');
                await checkFrame(steps, 15, alg + ' shift-period');
                await page.keyboard.press('Comma');
                await checkFrame(steps, 14, alg + ' comma');
                const mid = middleOf(steps, alg === 'fortune' ? ['circle'] : (alg === 'flip' ? ['flip'] : ['insert']),
                    (st) => !st.cavity || st.cavity.length >= 3);
                assert(mid > 0, alg + ': no step to show mid-replay');
                await scrubTo(mid);
                await checkFrame(steps, mid, alg + ' scrubbed to the middle');
                await page.keyboard.press('End');
                await checkFrame(steps, n - 1, alg + ' End');
                await scrubTo(mid);
                await checkFrame(steps, mid, alg + ' back to the middle');
                await page.waitForFunction(() => !window.voronoid.drawing);
                const px = await canvasPixels(page, 'diagram');
                assert(px.colour > 300 && px.nonbg > 3000, alg + ': the frame draws little: ' + JSON.stringify(px));
                await page.screenshot({ path: path.join(OUT, 'replay-' + alg + '.png') });
                /* playing runs to the end by itself */
                await page.selectOption('#rp-speed', '500');
                await page.click('#rp-play');
                await page.waitForFunction((last) => window.voronoid.replay.frame === last && !window.voronoid.replay.playing, n - 1);
            }
        });

        await step('step through on a phone (390x844): the picture first, the controls under it', async () => {
            await page.setViewportSize({ width: 390, height: 844 });
            try {
                const traced = await post({ points: replayPoints, algorithm: 'flip', trace: true });
                const mid = middleOf(traced.trace.steps, ['flip']);
                await scrubTo(mid);
                await checkFrame(traced.trace.steps, mid, 'phone');
                await page.locator('#diagram').scrollIntoViewIfNeeded();
                await page.waitForFunction(() => !window.voronoid.drawing && document.getElementById('diagram').clientWidth < 400);
                const r = await page.evaluate(() => {
                    const box = (id) => { const b = document.getElementById(id).getBoundingClientRect(); return { top: b.top, bottom: b.bottom, left: b.left, right: b.right }; };
                    return { canvas: box('diagram'), bar: box('rp-scrub'), play: box('rp-play'), counts: box('rp-counts'),
                        vw: window.innerWidth, scrollW: document.documentElement.scrollWidth };
                });
                assert(r.scrollW <= r.vw, 'the page is wider than the phone: ' + JSON.stringify(r));
                assert(r.canvas.bottom - r.canvas.top >= 300 && r.canvas.right - r.canvas.left >= 380, 'the canvas is small: ' + JSON.stringify(r));
                assert(r.play.top >= r.canvas.bottom && r.bar.right <= r.vw && r.counts.right <= r.vw, 'controls not under the picture: ' + JSON.stringify(r));
                await page.screenshot({ path: path.join(OUT, 'replay-phone.png') });
                const px = await canvasPixels(page, 'diagram');
                assert(px.colour > 200 && px.nonbg > 2000, 'no frame on the phone: ' + JSON.stringify(px));
            } finally {
                await page.setViewportSize({ width: 1280, height: 800 });
            }
        });

        await step('step through 2000 points: prepared in slices, played, scrubbed; too many points refused', async () => {
            await page.evaluate(() => {
                window.__longTasks = [];
                window.__longObserver = new PerformanceObserver((list) => {
                    for (const e of list.getEntries()) window.__longTasks.push({ start: e.startTime, ms: e.duration });
                });
                window.__longObserver.observe({ type: 'longtask' });
            });
            const traced = await post({ generate: { distribution: 'uniform', n: 2000, seed: 4 }, algorithm: 'fortune', trace: true });
            const steps = traced.trace.steps, n = steps.length;
            const t0 = await page.evaluate(() => performance.now());
            await page.locator('input[name=algorithm][value=fortune]').check();
            await page.fill('#n', '2000');
            await page.selectOption('#distribution', 'uniform');
            await page.fill('#seed', '4');
            await page.click('#generate');
            await waitOrError(page, (k) => window.voronoid.replay.steps === k && window.voronoid.replay.algorithm === 'fortune' &&
                window.voronoid.replay.ready && !window.voronoid.busy, n, (await state(page)).errorCount);
            let s = await replayState();
            assert(s.steps === n && s.matches === true, 'replay of ' + s.steps + ' steps (the trace has ' + n + '), matches ' + s.matches);
            await page.selectOption('#rp-speed', '2000');
            await page.click('#rp-play');
            await page.waitForFunction(() => window.voronoid.replay.frame > 200);
            await page.click('#rp-play');
            s = await replayState();
            assert(!s.playing && s.frame > 200, 'pause: ' + JSON.stringify({ playing: s.playing, frame: s.frame }));
            await checkFrame(steps, s.frame, 'paused');
            for (const f of [n - 1, Math.floor(n / 3), n - 2, 1, Math.floor(n / 2)]) {
                await scrubTo(f);
                await checkFrame(steps, f, 'scrubbed');
            }
            await page.click('#rp-back');
            await checkFrame(steps, Math.floor(n / 2) - 1, 'a step back');
            await page.waitForFunction(() => !window.voronoid.drawing);
            const t1 = await page.evaluate(() => performance.now());
            const tasks = (await page.evaluate(() => window.__longTasks)).filter((t) => t.start >= t0 && t.start <= t1);
            await page.evaluate(() => window.__longObserver.disconnect());
            console.log('     2000 points, Fortune: ' + n + ' steps; long tasks (> 50 ms) from Generate to here: ' + tasks.length +
                (tasks.length ? ', longest ' + Math.max(...tasks.map((t) => t.ms)).toFixed(0) + ' ms' : ''));
            await page.screenshot({ path: path.join(OUT, 'replay-2000.png') });
            /* beyond the trace limit: said so, and the mode is left */
            const b0 = await state(page);
            await page.fill('#n', '2500');
            await page.click('#generate');
            await page.waitForFunction((c) => window.voronoid.computeCount > c && !window.voronoid.busy && !window.voronoid.drawing,
                b0.computeCount);
            const err = (await state(page)).lastError;
            assert(err && /at most 2,000 points/.test(err.detail), 'no word on the limit: ' + JSON.stringify(err));
            s = await replayState();
            assert(!s.active && await page.locator('#replay').isHidden(), 'the step-through mode stays on');
            await page.click('#error-close');
            /* leaving by the button computes as usual */
            const b = await state(page);
            await page.fill('#n', '500');
            await page.click('#step-through');
            await waitOrError(page, () => window.voronoid.replay.ready && !window.voronoid.busy, null, b.errorCount);
            await page.click('#rp-close');
            const after = await waitComputed(page, b);
            assert(!(await replayState()).active && after.result.n_sites === 500 && after.edgesDrawn > 0,
                'after leaving: ' + JSON.stringify(after.result).slice(0, 200));
        });

        await step('no console errors, page errors or failed requests', async () => {
            assert(problems.length === 0, problems.join('\n'));
        });
    } catch (e) {
        results.push({ name: 'setup', ok: false });
        console.log('FAIL setup: ' + (e && e.stack || e));
    } finally {
        const d = daemon;
        await cleanup();
        if (d && d.log.length && results.some((r) => !r.ok)) {
            console.log('--- daemon output (last lines) ---');
            console.log(d.log.join('').split('\n').slice(-30).join('\n'));
        }
    }
    const passed = results.filter((r) => r.ok).length;
    const failed = results.length - passed;
    console.log('screenshots in ' + path.relative(ROOT, OUT) + '/');
    console.log('browser: ' + passed + ' passed, ' + failed + ' failed');
    return failed === 0 && passed > 0 ? 0 : 1;
}

main().then((code) => process.exit(code), (e) => {
    console.error(e);
    console.log('browser: 0 passed, 1 failed');
    process.exit(1);
});
