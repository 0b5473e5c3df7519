/* worker.js -- fetches, decodes and prepares diagrams off the page's thread.
 *
 * What it does: receives {id, url, init, binary, nColours} (a request
 * built by api.js), fetches it, reads the answer (binary or JSON), runs
 * decode.js and geometry.js on it, and posts back {id, D, G, serverTiming,
 * ms} -- the diagram record, its prepared drawing, the Server-Timing
 * header and the round trip -- with every typed array's buffer
 * transferred, so the page receives them in O(1). A problem answer posts
 * {id, problem} with the fields of a ServiceError, a request that got no
 * answer {id, unreachable}, anything else {id, message}. {abort: id}
 * aborts a request. Once loaded it posts 'ready', so the page knows it
 * may hand work over.
 *
 * Why: at 10^6 sites the binary answer is some 370 MB; assembling it,
 * decoding it and preparing the drawing take seconds of loops over typed
 * arrays, none of which may delay an input event or a frame of the page.
 * Loaded as a module worker from the page's own origin (worker-src
 * 'self'; fetches are same-origin, connect-src 'self').
 */
import { readAnswer } from './decode.js';
import { prepare, transferables } from './geometry.js';

const aborts = new Map();

async function handle(m) {
    const abort = new AbortController();
    aborts.set(m.id, abort);
    const t0 = performance.now();
    try {
        let resp;
        try {
            resp = await fetch(m.url, Object.assign({}, m.init, { signal: abort.signal }));
        } catch (e) {
            if (e.name === 'AbortError') return;
            self.postMessage({ id: m.id, unreachable: String(e && e.message || e) });
            return;
        }
        const D = await readAnswer(resp, m.binary);
        const ms = performance.now() - t0;
        if (abort.signal.aborted) return;
        const G = prepare(D, m.nColours);
        if (abort.signal.aborted) return;
        self.postMessage({ id: m.id, D: D, G: G, serverTiming: resp.headers.get('server-timing'), ms: ms },
            transferables(D, G));
    } catch (e) {
        if (e && e.name === 'AbortError') return;
        if (e && e.problem) self.postMessage({ id: m.id, problem: e.problem });
        else self.postMessage({ id: m.id, message: String(e && e.message || e) });
    } finally {
        aborts.delete(m.id);
    }
}

self.onmessage = (ev) => {
    const m = ev.data;
    if (m.abort) {
        const a = aborts.get(m.abort);
        if (a) a.abort();
        return;
    }
    handle(m);
};
self.postMessage('ready');
