/* browser_test.js -- the voronoid page driven in a real Chromium.
 *
 * Starts the daemon (VOR_DAEMON, default $B/voronoid, B defaulting to
 * build) on 127.0.0.1 with --port 0, reads the port it announces, opens
 * GET / in Debian's Chromium (through playwright-core, headless, a fresh
 * profile) and acts as a person would: generates points and computes with
 * each algorithm, uploads a CSV file and a broken one, drops a JSON file,
 * clicks points in, pans and zooms, compares the three algorithms, runs a
 * small size sweep, downloads an SVG, draws 10^5 points. Each step asserts
 * on what the page shows (text, table rows, canvas pixels) and on the
 * state it exposes in window.voronoid; any console error, uncaught page
 * error or failed request fails the run. Screenshots go to VOR_BROWSER_OUT
 * (default $B/browser). The daemon is stopped at the end, also on failure.
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
            trianglesDrawn: v.trianglesDrawn,
            lastError: v.lastError,
            view: v.view,
            timings: v.timings,
            frameMs: v.frameMs,
            result: r,
        };
    });
}

/* Waits until the page has finished a compute after `before` (a count from
 * state()) and is idle; fails early if an error shows up instead. */
async function waitComputed(page, before) {
    await page.waitForFunction((b) => {
        const v = window.voronoid;
        return !v.busy && (v.computeCount > b.computeCount || v.errorCount > b.errorCount);
    }, before, { timeout: STEP_TIMEOUT });
    const s = await state(page);
    if (s.errorCount > before.errorCount) {
        throw new Error('the page shows an error: ' + JSON.stringify(s.lastError));
    }
    return s;
}

/* Waits for fn(arg) in the page, failing at once if the page shows a new
 * error meanwhile (errors counted from `errorsBefore`). Polls with
 * page.evaluate rather than a predicate that evals fn's source inside the
 * page: the page's Content-Security-Policy forbids eval there. */
async function waitOrError(page, fn, arg, errorsBefore) {
    const until = Date.now() + STEP_TIMEOUT;
    for (;;) {
        const failed = await page.evaluate((e) => {
            const v = window.voronoid;
            return v.errorCount > e && !v.busy;
        }, errorsBefore);
        if (failed) {
            throw new Error('the page shows an error: ' + JSON.stringify((await state(page)).lastError));
        }
        if (await page.evaluate(fn, arg)) return;
        if (Date.now() > until) throw new Error('timed out waiting for ' + fn.toString());
        await new Promise((resolve) => setTimeout(resolve, 20));
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
            viewport: { width: 1440, height: 900 },
            deviceScaleFactor: 1,
            acceptDownloads: true,
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
            await page.waitForFunction(() => window.voronoid && !window.voronoid.busy &&
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
            for (const f of ['index.html', 'app.js', 'style.css']) {
                const served = await page.evaluate((u) => fetch(u).then((r) => r.text()), base + (f === 'index.html' ? '' : f));
                assert(served === fs.readFileSync(path.join(dir, f), 'utf8'),
                    f + ' as served differs from ' + path.relative(ROOT, path.join(dir, f)) + ' (rebuild the daemon: make)');
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
            assert(s.trianglesDrawn === s.result.n_triangles, 'triangles drawn ' + s.trianglesDrawn);
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
            await page.waitForFunction(() => window.voronoid.trianglesDrawn === 0);
        });

        await step('on a HiDPI screen the canvas has device pixels', async () => {
            /* device pixel ratio 2 (emulated, then reloaded: the emulation
             * sends the page no change event) */
            const lowres = await canvasPixels(page, 'diagram');
            const cdp = await context.newCDPSession(page);
            const reload = async () => {
                await page.reload({ waitUntil: 'load' });
                await page.waitForFunction(() => window.voronoid && !window.voronoid.busy &&
                    (window.voronoid.computeCount > 0 || window.voronoid.errorCount > 0));
            };
            try {
                await cdp.send('Emulation.setDeviceMetricsOverride', { width: 1440, height: 900, deviceScaleFactor: 2, mobile: false });
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

        await step('compare runs all three algorithms and they agree', async () => {
            await page.fill('#n', '1000');
            await page.fill('#seed', '7');
            let before = await state(page);
            await page.click('#generate');
            await waitComputed(page, before);
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
            const cells = await page.locator('#compare-table tbody td').allInnerTexts();
            assert(cells.filter((t) => TIME_RE.test(t.trim())).length >= 3, 'times in the table: ' + cells.join(' | '));
            const bars = await canvasPixels(page, 'compare-chart');
            assert(bars.colour > 300, 'the bar chart is empty (' + bars.colour + ' coloured pixels)');
        });

        await step('a size sweep fills the table and the log-log plot', async () => {
            await page.fill('#sweep-sizes', '500, 1000, 2000, 4000');
            const before = await state(page);
            await page.click('#sweep');
            await waitOrError(page, (b) => window.voronoid.sweepCount > b.sweepCount, before, before.errorCount);
            const sw = await page.evaluate(() => window.voronoid.lastSweep);
            assert(sw && sw.done, 'the sweep did not finish: ' + JSON.stringify((await state(page)).lastError));
            assert(sw.rows.map((r) => r.n).join() === '500,1000,2000,4000', 'sizes ' + sw.rows.map((r) => r.n));
            for (const r of sw.rows) {
                for (const a of ALGORITHMS) assert(typeof r.ms[a] === 'number', 'N=' + r.n + ' ' + a + ': ' + r.status[a]);
                assert(r.agree, 'N=' + r.n + ': the algorithms disagree');
            }
            assert(await page.locator('#sweep-table tbody tr').count() === 4, 'sweep table rows');
            const plot = await canvasPixels(page, 'sweep-chart');
            assert(plot.colour > 300, 'the sweep plot has no coloured series (' + plot.colour + ')');
            await page.screenshot({ path: path.join(OUT, 'page.png'), fullPage: true });
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
            const px = await canvasPixels(page, 'diagram');
            assert(px.edge > 100000, 'edge pixels ' + px.edge);
            /* a pan redraws from the cached paths; its cost is printed, not judged */
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

        await step('narrow window layout', async () => {
            await page.setViewportSize({ width: 900, height: 800 });
            await page.waitForFunction(() => window.voronoid.view && document.getElementById('diagram').clientWidth < 700);
            const px = await canvasPixels(page, 'diagram');
            assert(px.edge > 1000, 'the diagram is not drawn after a resize');
            await page.screenshot({ path: path.join(OUT, 'narrow.png'), fullPage: true });
            await page.setViewportSize({ width: 1440, height: 900 });
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
