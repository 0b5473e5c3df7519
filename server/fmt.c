/* fmt.c -- printf-free formatting of durations, counts and ids.
 *
 * srv_fmt_ms3 takes the fast way for the values requests produce
 * (0 <= v < 2^30 / 1000, i.e. under 12 days in milliseconds): f = v * 1000
 * is then below 2^30, so f carries the exact product to within 2^-23, and
 * the thousandths are f rounded to the nearest integer -- unless f's
 * fraction lies within 1e-6 of one half, where that error could decide the
 * rounding: those, negative (-0 too), huge and non-finite values go to
 * snprintf.
 * Output is therefore exactly snprintf's "%.3f" for every value. O(digits).
 */
#include "fmt.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

size_t srv_fmt_u64(char *out, uint64_t v) {
    char tmp[20];
    size_t n = 0;
    do {
        tmp[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v != 0);
    for (size_t i = 0; i < n; i++) out[i] = tmp[n - 1 - i];
    return n;
}

size_t srv_fmt_hex64(char *out, uint64_t v) {
    static const char digits[] = "0123456789abcdef";
    for (int i = 15; i >= 0; i--) {
        out[i] = digits[v & 15];
        v >>= 4;
    }
    return 16;
}

size_t srv_fmt_ms3(char *out, double v) {
    if (v >= 0 && !signbit(v) && v < (double)(1u << 30) / 1000) {
        double f = v * 1000;
        uint64_t t = (uint64_t)f;
        double frac = f - (double)t; /* exact: f < 2^30 */
        if (frac > 0.5 + 1e-6 || frac < 0.5 - 1e-6) {
            if (frac > 0.5) t++;
            size_t n = srv_fmt_u64(out, t / 1000);
            unsigned r = (unsigned)(t % 1000);
            out[n++] = '.';
            out[n++] = (char)('0' + r / 100);
            out[n++] = (char)('0' + r / 10 % 10);
            out[n++] = (char)('0' + r % 10);
            return n;
        }
    }
    char tmp[SRV_FMT_MS3_MAX + 1];
    int k = snprintf(tmp, sizeof tmp, "%.3f", v);
    if (k < 0) k = 0;
    if ((size_t)k > SRV_FMT_MS3_MAX) k = SRV_FMT_MS3_MAX;
    memcpy(out, tmp, (size_t)k);
    return (size_t)k;
}
