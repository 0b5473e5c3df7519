/* status.js -- the status line, the busy state and the error box.
 *
 * What it does: writes the toolbar's status text, marks the page busy
 * (body[data-state], which the stylesheet turns into a spinner), and shows
 * an error: a problem+json answer of the service with its title, detail,
 * line or pointer and a link to the page that explains its type, or an
 * error of the page itself in plain words. Every module reports through
 * these four functions.
 *
 * Invariants: pub.lastError is the error shown, null when the box is
 * closed; pub.errorCount counts every error shown.
 */
import { $, pub } from './util.js';
import { ServiceError } from './api.js';

export function setStatus(text) {
    $('status').textContent = text;
}

export function setBusy(on, text) {
    pub.busy = on;
    document.body.dataset.state = on ? 'busy' : (pub.lastError ? 'error' : 'idle');
    if (text) setStatus(text);
}

export function showError(err) {
    const p = err instanceof ServiceError ? err.problem
        : { title: 'Something went wrong in the page', detail: String(err && err.message || err) };
    pub.lastError = p;
    pub.errorCount++;
    let title = p.title || 'Error';
    if (p.status) title += ' (' + p.status + ')';
    const bits = [];
    if (p.detail) bits.push(p.detail);
    if (p.line && !new RegExp('\\bline ' + p.line + '\\b', 'i').test(p.detail || '')) bits.push('Line ' + p.line + '.');
    else if (p.pointer) bits.push('At ' + p.pointer + '.');
    if (p.retryAfter) bits.push('The service asks to try again in ' + p.retryAfter + ' s.');
    $('error-title').textContent = title;
    $('error-detail').textContent = bits.join(' ');
    /* the service documents each problem type at its type URI, written
     * from the root; read relative to the page so a path prefix holds */
    const more = $('error-more');
    more.hidden = !/^\/problems\/[a-z-]+$/.test(p.type || '');
    if (!more.hidden) more.href = new URL('.' + p.type, document.baseURI).toString();
    $('error').hidden = false;
    document.body.dataset.state = 'error';
    setStatus('Error: ' + title);
}

export function clearError() {
    pub.lastError = null;
    $('error').hidden = true;
    if (!pub.busy) document.body.dataset.state = 'idle';
}
