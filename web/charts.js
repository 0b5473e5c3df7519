/* charts.js -- what the compare and sweep charts share.
 *
 * What it holds: sizing a chart canvas to its CSS box at the device pixel
 * ratio, so that every chart draws in CSS pixels and stays sharp on HiDPI
 * screens.
 */

/* Sizes a chart canvas to its CSS box at the device pixel ratio and
 * returns a context drawing in CSS px, or null when it is not shown. */
export function chartContext(cv) {
    const w = cv.clientWidth, h = cv.clientHeight;
    if (!w || !h) return null;
    const d = window.devicePixelRatio || 1;
    cv.width = Math.round(w * d);
    cv.height = Math.round(h * d);
    const c = cv.getContext('2d');
    c.setTransform(d, 0, 0, d, 0, 0);
    c.clearRect(0, 0, w, h);
    c.font = '12px system-ui, sans-serif';
    return { c: c, w: w, h: h };
}
