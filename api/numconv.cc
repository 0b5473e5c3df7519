// numconv.cc -- the C interface of numconv.h over fast_float and dragonbox.
//
// Parsing: our own scan checks the grammar (JSON's, or the looser one of
// text bodies) and finds the end of the number; fast_float then converts
// exactly that span, correctly rounded to nearest whatever the current
// rounding mode. fast_float 3.9 returns infinity on overflow without an
// error code, so an infinite result of a digit string means overflow.
//
// Formatting: dragonbox gives the shortest correctly rounded decimal
// significand and exponent; we lay the digits out in plain or exponent
// notation two digits at a time. Everything is noexcept and allocation-free.
#include <cmath>
#include <cstring>

#include <fast_float/fast_float.h>
#include <dragonbox/dragonbox.h>

#include "numconv.h"

namespace {

inline bool is_digit(char c) { return c >= '0' && c <= '9'; }

// The first byte at or after p that is not a decimal digit (end if none).
// Eight bytes at a time where eight remain: a byte b is a digit when both
// its high nibble and that of b + 6 are 3. Adding 6 to every byte can
// carry out of a byte >= 0xfa, a non-digit, into the bytes above it
// (later in memory), and so can only turn later bytes into non-digits:
// the first non-digit is still found exactly. Numbers in coordinates are
// mostly long fractions, which this reads in two or three steps instead
// of seventeen.
inline const char *skip_digits(const char *p, const char *end) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    const uint64_t hi = 0xf0f0f0f0f0f0f0f0u, threes = 0x3333333333333333u;
    const uint64_t sixes = 0x0606060606060606u;
    while (end - p >= 8) {
        uint64_t x;
        std::memcpy(&x, p, 8);
        uint64_t bad = ((x & hi) | (((x + sixes) & hi) >> 4)) ^ threes;
        if (bad != 0) return p + (__builtin_ctzll(bad) >> 3);
        p += 8;
    }
#endif
    while (p < end && is_digit(*p)) p++;
    return p;
}

// Case-insensitive match of the lower-case word w at [p, end).
bool match_word(const char *p, const char *end, const char *w) {
    size_t n = std::strlen(w);
    if ((size_t)(end - p) < n) return false;
    for (size_t i = 0; i < n; i++) {
        char c = p[i];
        if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
        if (c != w[i]) return false;
    }
    return true;
}

// Converts the digit span [s, e) already checked by a grammar scan.
api_num convert(const char *s, const char *e, double *out) {
    double v = 0;
    fast_float::from_chars_result r = fast_float::from_chars(s, e, v);
    if (r.ec != std::errc() || r.ptr != e) return API_NUM_SYNTAX;
    if (std::isinf(v)) return API_NUM_OVERFLOW;
    *out = v;
    return API_NUM_OK;
}

const char digit_pairs[201] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

const uint64_t pow10_table[20] = {
    1u, 10u, 100u, 1000u, 10000u, 100000u, 1000000u, 10000000u, 100000000u,
    1000000000u, 10000000000u, 100000000000u, 1000000000000u,
    10000000000000u, 100000000000000u, 1000000000000000u,
    10000000000000000u, 100000000000000000u, 1000000000000000000u,
    10000000000000000000u};

// Number of decimal digits of v (1 for 0): log10 from the bit length
// (1233/4096 ~ log10 2), corrected by one comparison.
inline int count_digits(uint64_t v) {
    int bits = 64 - __builtin_clzll(v | 1);
    int k = (bits * 1233) >> 12;
    return k + (v >= pow10_table[k]);
}

// Writes exactly n digits of v (with leading zeros; v < 10^n, n <= 10) at
// o, two at a time, in 32-bit arithmetic.
__attribute__((always_inline)) inline void put_fixed32(uint32_t v, int n, char *o) {
    char *p = o + n;
    while (p - o >= 2) {
        uint32_t r = v % 100;
        v /= 100;
        p -= 2;
        std::memcpy(p, digit_pairs + 2 * r, 2);
    }
    if (p > o) *--p = (char)('0' + v % 10);
}

// Exactly eight digits of v < 10^8, without a loop.
__attribute__((always_inline)) inline void put8(uint32_t v, char *o) {
    uint32_t a = v / 10000, b = v % 10000;
    std::memcpy(o, digit_pairs + 2 * (a / 100), 2);
    std::memcpy(o + 2, digit_pairs + 2 * (a % 100), 2);
    std::memcpy(o + 4, digit_pairs + 2 * (b / 100), 2);
    std::memcpy(o + 6, digit_pairs + 2 * (b % 100), 2);
}

// Writes exactly n digits of v (with leading zeros; v < 10^n, n <= 19)
// at o: eight digits at a time from the right (one 64-bit division each,
// then 32-bit arithmetic), the rest two at a time.
__attribute__((always_inline)) inline void put_fixed(uint64_t v, int n, char *o) {
    while (n >= 8) {
        uint64_t q = v / 100000000;
        put8((uint32_t)(v - q * 100000000), o + n - 8);
        v = q;
        n -= 8;
    }
    put_fixed32((uint32_t)v, n, o);
}

}  // namespace

extern "C" api_num api_num_parse_json(const char *s, const char *end,
                                      double *out, const char **stop) {
    const char *p = s;
    *stop = s;
    if (p < end && *p == '-') p++;
    if (p >= end) return API_NUM_SYNTAX;
    if (*p == '0') {
        p++;
    } else if (*p >= '1' && *p <= '9') {
        p = skip_digits(p + 1, end);
    } else {
        return API_NUM_SYNTAX;
    }
    if (p < end && *p == '.') {
        const char *q = p + 1;
        if (q >= end || !is_digit(*q)) { *stop = p; return API_NUM_SYNTAX; }
        p = skip_digits(q + 1, end);
    }
    if (p < end && (*p == 'e' || *p == 'E')) {
        const char *q = p + 1;
        if (q < end && (*q == '+' || *q == '-')) q++;
        if (q >= end || !is_digit(*q)) { *stop = p; return API_NUM_SYNTAX; }
        p = skip_digits(q + 1, end);
    }
    *stop = p;
    return convert(s, p, out);
}

extern "C" api_num api_num_parse_text(const char *s, const char *end,
                                      double *out, const char **stop) {
    const char *p = s;
    bool neg = false;
    *stop = s;
    if (p < end && (*p == '+' || *p == '-')) { neg = *p == '-'; p++; }
    const char *digits = p;  // fast_float refuses a leading '+'
    if (p < end && (*p == 'i' || *p == 'I' || *p == 'n' || *p == 'N')) {
        if (match_word(p, end, "infinity")) {
            p += 8;
            *out = neg ? -HUGE_VAL : HUGE_VAL;
        } else if (match_word(p, end, "inf")) {
            p += 3;
            *out = neg ? -HUGE_VAL : HUGE_VAL;
        } else if (match_word(p, end, "nan")) {
            p += 3;
            *out = NAN;
        } else {
            return API_NUM_SYNTAX;
        }
        *stop = p;
        return API_NUM_NONFINITE;
    }
    size_t n_digits = 0;
    while (p < end && is_digit(*p)) { p++; n_digits++; }
    if (p < end && *p == '.') {
        p++;
        while (p < end && is_digit(*p)) { p++; n_digits++; }
    }
    if (n_digits == 0) return API_NUM_SYNTAX;
    if (p < end && (*p == 'e' || *p == 'E')) {
        const char *q = p + 1;
        if (q < end && (*q == '+' || *q == '-')) q++;
        if (q < end && is_digit(*q)) {
            while (++q < end && is_digit(*q)) {}
            p = q;
        }
        // else: "1e" or "1e+" -- the number ends before the 'e', and the
        // caller sees an unexpected 'e'.
    }
    *stop = p;
    api_num r = convert(digits, p, out);
    if (r == API_NUM_OK && neg) *out = -*out;
    return r;
}

extern "C" size_t api_num_format(double v, char *buf) {
    if (!std::isfinite(v)) return 0;
    char *o = buf;
    if (std::signbit(v)) *o++ = '-';
    if (v == 0) {
        *o++ = '0';
        return (size_t)(o - buf);
    }
    auto r = jkj::dragonbox::to_decimal(v, jkj::dragonbox::policy::sign::ignore,
                                        jkj::dragonbox::policy::trailing_zero::remove);
    uint64_t sig = r.significand;
    int k = count_digits(sig);
    int pos = k + r.exponent;  // value = 0.d1d2...dk * 10^pos
    // The digits are written one byte to the right of where they start,
    // so that a decimal point can be made by moving the digits before it
    // one byte left (at most 17 bytes, no division).
    if (pos > 0 && pos <= 17) {
        if (pos >= k) {  // integer: digits then zeros
            put_fixed(sig, k, o);
            o += k;
            std::memset(o, '0', (size_t)(pos - k));
            o += pos - k;
        } else {  // digits on both sides of the point
            put_fixed(sig, k, o + 1);
            for (int i = 0; i < pos; i++) o[i] = o[i + 1];
            o[pos] = '.';
            o += k + 1;
        }
    } else if (pos <= 0 && pos > -6) {
        *o++ = '0';
        *o++ = '.';
        for (int i = 0; i < -pos; i++) *o++ = '0';
        put_fixed(sig, k, o);
        o += k;
    } else {
        put_fixed(sig, k, o + 1);
        o[0] = o[1];
        if (k > 1) {
            o[1] = '.';
            o += k + 1;
        } else {
            o += 1;
        }
        *o++ = 'e';
        int e = pos - 1;
        if (e < 0) { *o++ = '-'; e = -e; }
        int ne = e >= 100 ? 3 : e >= 10 ? 2 : 1;
        put_fixed((uint64_t)e, ne, o);
        o += ne;
    }
    return (size_t)(o - buf);
}
