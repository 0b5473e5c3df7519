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

// Writes the decimal digits of v (no leading zeros, v > 0) ending just
// before `end`; returns the number of digits.
int put_digits_backwards(uint64_t v, char *end) {
    char *p = end;
    while (v >= 100) {
        unsigned r = (unsigned)(v % 100);
        v /= 100;
        p -= 2;
        std::memcpy(p, digit_pairs + 2 * r, 2);
    }
    if (v >= 10) {
        p -= 2;
        std::memcpy(p, digit_pairs + 2 * v, 2);
    } else {
        *--p = (char)('0' + v);
    }
    return (int)(end - p);
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
        while (++p < end && is_digit(*p)) {}
    } else {
        return API_NUM_SYNTAX;
    }
    if (p < end && *p == '.') {
        const char *q = p + 1;
        if (q >= end || !is_digit(*q)) { *stop = p; return API_NUM_SYNTAX; }
        while (++q < end && is_digit(*q)) {}
        p = q;
    }
    if (p < end && (*p == 'e' || *p == 'E')) {
        const char *q = p + 1;
        if (q < end && (*q == '+' || *q == '-')) q++;
        if (q >= end || !is_digit(*q)) { *stop = p; return API_NUM_SYNTAX; }
        while (++q < end && is_digit(*q)) {}
        p = q;
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
    char digits[24];
    int k = put_digits_backwards(r.significand, digits + sizeof digits);
    const char *d = digits + sizeof digits - k;
    int pos = k + r.exponent;  // value = 0.d1d2...dk * 10^pos
    if (pos > 0 && pos <= 17) {
        if (pos >= k) {  // integer: digits then zeros
            std::memcpy(o, d, (size_t)k);
            o += k;
            std::memset(o, '0', (size_t)(pos - k));
            o += pos - k;
        } else {
            std::memcpy(o, d, (size_t)pos);
            o += pos;
            *o++ = '.';
            std::memcpy(o, d + pos, (size_t)(k - pos));
            o += k - pos;
        }
    } else if (pos <= 0 && pos > -6) {
        *o++ = '0';
        *o++ = '.';
        std::memset(o, '0', (size_t)-pos);
        o += -pos;
        std::memcpy(o, d, (size_t)k);
        o += k;
    } else {
        *o++ = d[0];
        if (k > 1) {
            *o++ = '.';
            std::memcpy(o, d + 1, (size_t)(k - 1));
            o += k - 1;
        }
        *o++ = 'e';
        int e = pos - 1;
        if (e < 0) { *o++ = '-'; e = -e; }
        char eb[8];
        int ne = put_digits_backwards((uint64_t)e, eb + sizeof eb);
        std::memcpy(o, eb + sizeof eb - ne, (size_t)ne);
        o += ne;
    }
    return (size_t)(o - buf);
}
