/* exact.js -- the few geometric functions of the core that the replay needs
 * on the page, computed as the core computes them.
 *
 * What it holds:
 * - incircle(a, b, c, d): the exact sign of the in-circle determinant
 *   (> 0 when d lies inside the circle through the counter-clockwise a, b,
 *   c; 0 when the four are cocircular). A floating-point evaluation with
 *   Shewchuk's error bound decides almost every call; what it cannot
 *   decide is evaluated exactly with BigInt: every double is an integer
 *   times a power of two, so all eight coordinates become integers over
 *   one common power of two, and the determinant of integers is exact.
 * - circumcenter(a, b, c): the centre of the circle through three sites,
 *   bit for bit as core/geometry.c's vor_circumcenter computes it in
 *   doubles (JavaScript rounds every operation to double and never fuses
 *   a multiply and an add, exactly as the core is built). The core's long
 *   double fallback (coordinate differences beyond 2^±300, or a
 *   determinant that rounds to 0) has no JavaScript twin: there the
 *   centre is computed from rescaled differences and an exactly rounded
 *   determinant, to within a few ulps but not bit for bit.
 * - bisectorDir(a, b): the unit direction of the bisector of a and b with
 *   a on its left, bit for bit as vor_bisector_dir computes it.
 *
 * Points are [x, y] arrays (or any pair-indexable). Pure functions: no DOM.
 * Cost: a filtered in-circle test is a few dozen flops; the exact path
 * allocates BigInts and costs some microseconds (more for coordinates of
 * very different magnitudes).
 */

const EPS = Math.pow(2, -53);
/* Shewchuk's bound for the in-circle determinant evaluated in doubles */
const ICC_ERRBOUND_A = (10 + 96 * EPS) * EPS;
/* below this permanent, products may underflow and the bound fails */
const TINY = Math.pow(2, -800);
const TWO_M300 = Math.pow(2, -300);
const TWO_P300 = Math.pow(2, 300);

const dv = new DataView(new ArrayBuffer(8));

/* x (finite) as [m, e] with x = m 2^e, m a BigInt. */
function split(x) {
    dv.setFloat64(0, x);
    const hi = dv.getUint32(0), lo = dv.getUint32(4);
    const ex = (hi >>> 20) & 0x7ff;
    let m = (BigInt(hi & 0xfffff) << 32n) | BigInt(lo);
    let e = -1074;
    if (ex !== 0) {
        m |= 1n << 52n;
        e = ex - 1075;
    }
    return [hi >>> 31 ? -m : m, e];
}

/* The coordinates vals as BigInts over one common power of two. */
function toIntegers(vals) {
    const parts = vals.map(split);
    let emin = Infinity;
    for (const p of parts) if (p[0] !== 0n && p[1] < emin) emin = p[1];
    if (emin === Infinity) emin = 0;
    return parts.map((p) => p[0] << BigInt(p[1] - emin));
}

function incircleExact(a, b, c, d) {
    const [ax, ay, bx, by, cx, cy, dx, dy] = toIntegers([a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1]]);
    const adx = ax - dx, ady = ay - dy, bdx = bx - dx, bdy = by - dy, cdx = cx - dx, cdy = cy - dy;
    const alift = adx * adx + ady * ady, blift = bdx * bdx + bdy * bdy, clift = cdx * cdx + cdy * cdy;
    const det = alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) + clift * (adx * bdy - bdx * ady);
    return det > 0n ? 1 : (det < 0n ? -1 : 0);
}

/* Sign of the in-circle determinant of a, b, c, d: 1, -1 or 0, exact. */
export function incircle(a, b, c, d) {
    const adx = a[0] - d[0], ady = a[1] - d[1];
    const bdx = b[0] - d[0], bdy = b[1] - d[1];
    const cdx = c[0] - d[0], cdy = c[1] - d[1];
    const bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    const cdxady = cdx * ady, adxcdy = adx * cdy;
    const adxbdy = adx * bdy, bdxady = bdx * ady;
    const alift = adx * adx + ady * ady;
    const blift = bdx * bdx + bdy * bdy;
    const clift = cdx * cdx + cdy * cdy;
    const det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
    const permanent = (Math.abs(bdxcdy) + Math.abs(cdxbdy)) * alift +
        (Math.abs(cdxady) + Math.abs(adxcdy)) * blift + (Math.abs(adxbdy) + Math.abs(bdxady)) * clift;
    if (isFinite(permanent) && permanent >= TINY) {
        const bound = ICC_ERRBOUND_A * permanent;
        if (det > bound) return 1;
        if (-det > bound) return -1;
    }
    return incircleExact(a, b, c, d);
}

function inWindow(v) {
    const m = Math.abs(v);
    return m === 0 || (m >= TWO_M300 && m <= TWO_P300);
}

/* The exact orientation determinant (b - a) x (c - a), rounded to a
 * double after scaling by 2^-shift (shift chosen by the caller). */
function orientValue(a, b, c, shift) {
    const [ax, ay, bx, by, cx, cy] = toIntegers([a[0], a[1], b[0], b[1], c[0], c[1]]);
    const det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    /* the integers carry 2^-emin; undo it and the caller's shift */
    const vals = [a[0], a[1], b[0], b[1], c[0], c[1]].map(split).filter((p) => p[0] !== 0n);
    const emin = vals.length ? Math.min(...vals.map((p) => p[1])) : 0;
    return bigToDouble(det, 2 * emin - shift);
}

/* 2^k as a double built from its bits, for k in [-1074, 1023]. */
function pow2(k) {
    if (k >= -1022) {
        dv.setUint32(0, ((k + 1023) << 20) >>> 0);
        dv.setUint32(4, 0);
    } else {
        const pos = k + 1074; /* the one mantissa bit of a subnormal */
        dv.setUint32(0, pos >= 32 ? (1 << (pos - 32)) >>> 0 : 0);
        dv.setUint32(4, pos < 32 ? (1 << pos) >>> 0 : 0);
    }
    return dv.getFloat64(0);
}

/* v 2^k rounded once, as C's ldexp: scaled exactly while the result
 * stays normal, then by one last factor. */
function ldexp(v, k) {
    if (v === 0 || !isFinite(v)) return v;
    while (k > 1023) {
        v *= pow2(1023);
        k -= 1023;
    }
    if (k >= -1022) return v * pow2(k);
    const E = Math.floor(Math.log2(Math.abs(v))) + 1; /* |v| < 2^E (or equal: one spare bit) */
    const j = Math.min(0, Math.max(k, -1022 - E + 1, -1022));
    v *= pow2(j);
    k -= j;
    return k < -1074 ? v * pow2(-1074) * pow2(Math.max(-1074, k + 1074)) : v * pow2(k);
}

/* v 2^e as a double (rounded; enough for drawing). */
function bigToDouble(v, e) {
    if (v === 0n) return 0;
    const neg = v < 0n;
    if (neg) v = -v;
    const drop = Math.max(0, v.toString(2).length - 60);
    const r = ldexp(Number(v >> BigInt(drop)), e + drop);
    return neg ? -r : r;
}

/* Where the core leaves doubles: differences rescaled by a power of two
 * so the largest is near 1, and the determinant taken exactly; within a
 * few ulps of the core's long double result (not bit for bit), and not
 * finite where a difference overflows. */
function circumcenterWide(a, b, c) {
    const diffs = [b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]];
    const big = Math.max(...diffs.map(Math.abs));
    if (!(big > 0) || !isFinite(big)) return [NaN, NaN];
    const k = Math.round(Math.log2(big));
    const [bx, by, cx, cy] = diffs.map((v) => ldexp(v, -k));
    const d = 2 * orientValue(a, b, c, 2 * k);
    const b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    const ux = (cy * b2 - by * c2) / d, uy = (bx * c2 - cx * b2) / d;
    return [a[0] + ldexp(ux, k) + 0.0, a[1] + ldexp(uy, k) + 0.0];
}

/* The centre of the circle through a, b, c (vor_circumcenter). */
export function circumcenter(a, b, c) {
    const bx = b[0] - a[0], by = b[1] - a[1];
    const cx = c[0] - a[0], cy = c[1] - a[1];
    if (inWindow(bx) && inWindow(by) && inWindow(cx) && inWindow(cy)) {
        const d = 2 * (bx * cy - by * cx);
        if (d !== 0) {
            const b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
            return [a[0] + (cy * b2 - by * c2) / d + 0.0, a[1] + (bx * c2 - cx * b2) / d + 0.0];
        }
    }
    return circumcenterWide(a, b, c);
}

/* Unit direction of the bisector of a and b, a on its left
 * (vor_bisector_dir); [0, 0] when a equals b. */
export function bisectorDir(a, b) {
    let x = -(b[1] - a[1]), y = b[0] - a[0];
    if (!isFinite(x) || !isFinite(y)) {
        x = -(b[1] * 0.5 - a[1] * 0.5);
        y = b[0] * 0.5 - a[0] * 0.5;
    }
    const m = Math.abs(x) > Math.abs(y) ? Math.abs(x) : Math.abs(y);
    if (m === 0) return [0, 0];
    dv.setFloat64(0, m);
    const ex = (dv.getUint32(0) >>> 20) & 0x7ff;
    if (ex >= 1 && ex <= 2044) {
        /* m = f 2^e with f in [1/2, 1): times 2^-e, exact */
        const f = pow2(1022 - ex);
        x *= f;
        y *= f;
    } else {
        /* frexp's exponent, then ldexp's single rounding */
        let e = ex - 1022;
        if (ex === 0) {
            const mant = dv.getUint32(4) + (dv.getUint32(0) & 0xfffff) * 4294967296;
            e = Math.floor(Math.log2(mant)) + 1 - 1074;
            if (Math.pow(2, e - 1 + 1074) > mant) e--; /* log2 rounded up */
            else if (Math.pow(2, e + 1074) <= mant) e++; /* or down */
        }
        x = ldexp(x, -e);
        y = ldexp(y, -e);
    }
    const h = Math.sqrt(x * x + y * y);
    return [x / h + 0.0, y / h + 0.0];
}
