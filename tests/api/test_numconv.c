/* test_numconv.c -- the number shim (api/numconv.h) against glibc.
 *
 * Parsing is checked bit for bit against strtod (round to nearest) on
 * millions of strings: random doubles printed with %.17g, random short and
 * long decimals, random exponents, and hand-picked extremes (subnormals,
 * DBL_MAX and the overflow boundary, -0). Formatting is checked by reading
 * every output back with strtod (identical bits) and, on a sample, by
 * comparing its number of significant digits with the shortest %.*e that
 * reads back. The grammar checks (what JSON and text bodies accept) are
 * tested case by case. VOR_TEST_SCALE=k multiplies the random counts. */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../../api/numconv.h"

static const uint64_t SEED = 0x5eed0001u;
static uint64_t rng_state;

static uint64_t rnd(void) {
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

static long scale(void) {
    const char *s = getenv("VOR_TEST_SCALE");
    long k = s ? strtol(s, NULL, 10) : 1;
    return k > 0 ? k : 1;
}

static uint64_t bits(double v) {
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    return u;
}

static double random_finite_double(void) {
    for (;;) {
        uint64_t u = rnd();
        double v;
        memcpy(&v, &u, sizeof v);
        if (isfinite(v)) return v;
    }
}

/* Parses s with the JSON grammar and with strtod; they must agree exactly
 * (an infinite strtod result must be reported as overflow). Returns 1 if
 * the string was consumed whole by both. */
static void check_parse_json(const char *s) {
    size_t len = strlen(s);
    double got = 0;
    const char *stop;
    api_num r = api_num_parse_json(s, s + len, &got, &stop);
    errno = 0;
    char *end;
    double want = strtod(s, &end);
    if (r == API_NUM_SYNTAX || stop != s + len) {
        fail_msg("\"%s\": not accepted whole (status %d, stopped at %td)", s,
                 (int)r, stop - s);
    }
    if (isinf(want)) {
        if (r != API_NUM_OVERFLOW) fail_msg("\"%s\": overflow not reported", s);
        return;
    }
    if (r != API_NUM_OK) fail_msg("\"%s\": status %d", s, (int)r);
    if (bits(got) != bits(want)) {
        fail_msg("\"%s\": got %a, strtod %a", s, got, want);
    }
}

static void check_parse_text(const char *s) {
    size_t len = strlen(s);
    double got = 0;
    const char *stop;
    api_num r = api_num_parse_text(s, s + len, &got, &stop);
    double want = strtod(s, NULL);
    if (stop != s + len) fail_msg("\"%s\": text grammar stopped early", s);
    if (isinf(want) && r == API_NUM_OVERFLOW) return;
    if (r != API_NUM_OK || bits(got) != bits(want)) {
        fail_msg("\"%s\": text got %a (status %d), strtod %a", s, got, (int)r,
                 want);
    }
}

static void test_parse_extremes(void **state) {
    (void)state;
    static const char *const cases[] = {
        "0", "-0", "0.0", "-0.0", "0e0", "0E+5", "0e-999999", "-0e999999",
        "1", "-1", "9007199254740993", "9007199254740992", "123456789012345678901234567890",
        "0.1", "0.3", "2.5e-1", "1e308", "-1e308", "1.7976931348623157e308",
        "1.7976931348623158e308", "1.79769313486231580793e308",
        "1.797693134862315807937e308", "1.7976931348623159e308", "1e309",
        "-1e309", "1e99999999999999999999", "2e-308", "2.2250738585072014e-308",
        "2.2250738585072011e-308", "4.9406564584124654e-324", "5e-324",
        "2.4703282292062328e-324", "2.4703282292062327e-324", "3e-324",
        "1e-324", "1e-400", "-1e-400", "1e-99999999999999999999",
        "0.000000000000000000000000000000000000000000001e45",
        "100000000000000000000000000000000000000000000e-45",
        "7.2057594037927933e16", "9007199254740993.000000000000000000001",
        "4503599627370496.5", "4503599627370497.5", "1e23", "8.98846567431158e307",
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        check_parse_json(cases[i]);
        check_parse_text(cases[i]);
    }
    double v;
    const char *stop;
    const char *s = "-0";
    assert_int_equal(api_num_parse_json(s, s + 2, &v, &stop), API_NUM_OK);
    assert_true(signbit(v));
    s = "1e309";
    assert_int_equal(api_num_parse_json(s, s + 5, &v, &stop), API_NUM_OVERFLOW);
    assert_ptr_equal(stop, s + 5);
}

static void test_parse_random_17g(void **state) {
    (void)state;
    rng_state = SEED;
    long n = 1000000 * scale();
    printf("# seed %#llx, %ld random doubles as %%.17g\n",
           (unsigned long long)SEED, n);
    char buf[64];
    for (long i = 0; i < n; i++) {
        double v = random_finite_double();
        snprintf(buf, sizeof buf, "%.17g", v);
        check_parse_json(buf);
    }
}

/* Random decimals: short ones (what people type), long ones (more digits
 * than a double holds, to reach fast_float's slow path), random exponents
 * over the whole range and beyond. */
static void test_parse_random_decimals(void **state) {
    (void)state;
    rng_state = SEED + 1;
    long n = 1000000 * scale();
    printf("# seed %#llx, %ld random decimals\n",
           (unsigned long long)(SEED + 1), n);
    char buf[1024];
    for (long i = 0; i < n; i++) {
        size_t k = 0;
        uint64_t r = rnd();
        if (r & 1) buf[k++] = '-';
        int long_form = (r >> 1) % 16 == 0;
        int int_digits = 1 + (int)((r >> 5) % (long_form ? 400 : 8));
        int frac_digits = (int)((r >> 14) % (long_form ? 400 : 8));
        uint64_t d = rnd();
        for (int j = 0; j < int_digits; j++) {
            if (j % 16 == 15) d = rnd();
            int c = (int)(d % 10);
            d /= 10;
            if (j == 0 && c == 0 && int_digits > 1) c = 1 + (int)(d % 9);
            buf[k++] = (char)('0' + c);
        }
        if (frac_digits > 0) {
            buf[k++] = '.';
            for (int j = 0; j < frac_digits; j++) {
                if (j % 16 == 0) d = rnd();
                buf[k++] = (char)('0' + d % 10);
                d /= 10;
            }
        }
        if ((r >> 24) % 3 != 0) {
            buf[k++] = (r >> 26) & 1 ? 'e' : 'E';
            int e = (int)((r >> 27) % 700) - 350;
            k += (size_t)snprintf(buf + k, sizeof buf - k, "%s%d",
                                  e >= 0 && ((r >> 40) & 1) ? "+" : "", e);
        }
        buf[k] = 0;
        check_parse_json(buf);
        if (i % 8 == 0) check_parse_text(buf);
    }
}

/* The shortest number of significant digits that round-trips, found with
 * %.*e and strtod. */
static int shortest_digits(double v) {
    char buf[64];
    for (int p = 1; p <= 17; p++) {
        snprintf(buf, sizeof buf, "%.*e", p - 1, v);
        if (strtod(buf, NULL) == v) return p;
    }
    return 17;
}

static int significant_digits(const char *s, size_t len) {
    int n = 0, seen = 0, zeros = 0;
    for (size_t i = 0; i < len && s[i] != 'e'; i++) {
        char c = s[i];
        if (c < '0' || c > '9') continue;
        if (c == '0') {
            if (seen) zeros++;
            continue;
        }
        seen = 1;
        n += zeros + 1;
        zeros = 0;
    }
    return n;
}

static void check_format(double v, int check_shortest) {
    char buf[API_NUM_MAXLEN + 1];
    size_t len = api_num_format(v, buf);
    assert_true(len > 0 && len <= API_NUM_MAXLEN);
    buf[len] = 0;
    char *end;
    double back = strtod(buf, &end);
    if (*end != 0 || bits(back) != bits(v)) {
        fail_msg("%a formatted as \"%s\" reads back as %a", v, buf, back);
    }
    /* JSON grammar: the JSON parser must accept the whole output. */
    const char *stop;
    double again;
    if (api_num_parse_json(buf, buf + len, &again, &stop) != API_NUM_OK ||
        stop != buf + len || bits(again) != bits(v)) {
        fail_msg("\"%s\" is not a JSON number that reads back", buf);
    }
    if (check_shortest && v != 0) {
        int want = shortest_digits(v), got = significant_digits(buf, len);
        if (got != want) {
            fail_msg("%a: \"%s\" has %d significant digits, shortest is %d",
                     v, buf, got, want);
        }
    }
}

static void test_format_cases(void **state) {
    (void)state;
    static const struct {
        double v;
        const char *s;
    } cases[] = {
        {0.0, "0"}, {-0.0, "-0"}, {1.0, "1"}, {-3.0, "-3"}, {0.25, "0.25"},
        {1500.0, "1500"}, {0.1, "0.1"}, {1e-6, "0.000001"}, {1.5e-6, "0.0000015"},
        {1e-7, "1e-7"}, {1e16, "10000000000000000"}, {1e17, "1e17"},
        {123456789012345680.0, "1.2345678901234568e17"}, {1e300, "1e300"},
        {DBL_MAX, "1.7976931348623157e308"}, {5e-324, "5e-324"},
        {-2.2250738585072014e-308, "-2.2250738585072014e-308"},
        {0.30000000000000004, "0.30000000000000004"}, {800.5, "800.5"},
        {12345678901234567.0, "12345678901234568"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char buf[API_NUM_MAXLEN + 1];
        size_t len = api_num_format(cases[i].v, buf);
        buf[len] = 0;
        assert_string_equal(buf, cases[i].s);
        check_format(cases[i].v, 1);
    }
    char buf[API_NUM_MAXLEN];
    assert_int_equal(api_num_format(NAN, buf), 0);
    assert_int_equal(api_num_format(-INFINITY, buf), 0);
}

static void test_format_random(void **state) {
    (void)state;
    rng_state = SEED + 2;
    long n = 2000000 * scale();
    printf("# seed %#llx, %ld random doubles formatted and read back, "
           "1 in 40 checked for shortness\n",
           (unsigned long long)(SEED + 2), n);
    for (long i = 0; i < n; i++) {
        double v;
        uint64_t r = rnd();
        switch (r % 4) {
        case 0: v = random_finite_double(); break;
        case 1: v = (double)(rnd() >> 11) * 0x1p-53; break;         /* [0,1) */
        case 2: v = (double)(int64_t)(rnd() % 2000001) - 1e6; break;  /* ints */
        default: {                                  /* subnormals and tiny */
            uint64_t u = rnd() >> (12 + r % 40);
            memcpy(&v, &u, sizeof v);
            break;
        }
        }
        check_format(v, i % 40 == 0);
    }
}

static void test_json_grammar(void **state) {
    (void)state;
    static const struct {
        const char *s;
        api_num status;
        int stop; /* bytes consumed */
    } cases[] = {
        {"01", API_NUM_OK, 1},     {"1.", API_NUM_SYNTAX, 1},
        {".5", API_NUM_SYNTAX, 0}, {"+1", API_NUM_SYNTAX, 0},
        {"-", API_NUM_SYNTAX, 0},  {"1e", API_NUM_SYNTAX, 1},
        {"1e+", API_NUM_SYNTAX, 1}, {"NaN", API_NUM_SYNTAX, 0},
        {"Infinity", API_NUM_SYNTAX, 0}, {"-Infinity", API_NUM_SYNTAX, 0},
        {"", API_NUM_SYNTAX, 0},   {"12,", API_NUM_OK, 2},
        {"1.5]", API_NUM_OK, 3},   {"-0.0e-0 ", API_NUM_OK, 7},
        {"0x10", API_NUM_OK, 1},   {"1e5x", API_NUM_OK, 3},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *s = cases[i].s;
        double v;
        const char *stop;
        api_num r = api_num_parse_json(s, s + strlen(s), &v, &stop);
        if (r != cases[i].status || stop - s != cases[i].stop) {
            fail_msg("\"%s\": status %d stop %td, expected %d %d", s, (int)r,
                     stop - s, (int)cases[i].status, cases[i].stop);
        }
    }
    /* Never reads past end: a number cut by the end pointer. */
    const char *s = "12345";
    double v;
    const char *stop;
    assert_int_equal(api_num_parse_json(s, s + 2, &v, &stop), API_NUM_OK);
    assert_true(v == 12.0);
}

/* Where the JSON grammar stops after a run of k digits followed by byte
 * c (or by the end of the input, c < 0), in the integer part, the
 * fraction and the exponent: digits are read several at a time, and the
 * first byte that is not a digit, at any offset, must end the number. The
 * input sits at the very end of an allocation of its own size, so a read
 * past end is an error under AddressSanitizer. */
static void test_json_digit_runs(void **state) {
    (void)state;
    static const char *const prefix[] = {"7", "0.", "1e", "-3.25E-"};
    for (size_t f = 0; f < sizeof prefix / sizeof prefix[0]; f++) {
        size_t pl = strlen(prefix[f]);
        for (size_t k = 0; k <= 40; k++) {
            for (int c = -1; c < 256; c++) {
                if (c == '.' || c == 'e' || c == 'E') continue; /* go on */
                size_t len = pl + k + (c >= 0);
                char *b = malloc(len);
                assert_non_null(b);
                memcpy(b, prefix[f], pl);
                for (size_t i = 0; i < k; i++) b[pl + i] = (char)('0' + (i * 7 + k) % 10);
                if (c >= 0) b[pl + k] = (char)c;
                /* the oracle: a byte loop over the same span */
                size_t want = pl;
                while (want < len && b[want] >= '0' && b[want] <= '9') want++;
                double v;
                const char *stop;
                api_num r = api_num_parse_json(b, b + len, &v, &stop);
                int ok = want > pl || f == 0; /* "7" is a number alone */
                /* a refused number stops at its last '.', 'e' or 'E' */
                size_t bad = pl - 1;
                while (bad > 0 && strchr(".eE", b[bad]) == NULL) bad--;
                size_t got = (size_t)(stop - b);
                free(b);
                /* exponents of many digits overflow: read, not refused */
                if (got != (ok ? want : bad) || (r != API_NUM_SYNTAX) != ok) {
                    fail_msg("prefix \"%s\", %zu digits, then byte %d: status "
                             "%d, stop %zu (expected %zu)", prefix[f], k, c,
                             (int)r, got, ok ? want : bad);
                }
            }
        }
    }
}

static void test_text_grammar(void **state) {
    (void)state;
    static const struct {
        const char *s;
        api_num status;
        int stop;
        double v;
    } cases[] = {
        {"+1", API_NUM_OK, 2, 1.0},    {".5", API_NUM_OK, 2, 0.5},
        {"5.", API_NUM_OK, 2, 5.0},    {"-.5e1", API_NUM_OK, 5, -5.0},
        {"007", API_NUM_OK, 3, 7.0},   {"1e", API_NUM_OK, 1, 1.0},
        {"1e+x", API_NUM_OK, 1, 1.0},  {"inf", API_NUM_NONFINITE, 3, INFINITY},
        {"-Infinity", API_NUM_NONFINITE, 9, -INFINITY},
        {"NaN", API_NUM_NONFINITE, 3, 0}, {"nano", API_NUM_NONFINITE, 3, 0},
        {".", API_NUM_SYNTAX, 0, 0},   {"+", API_NUM_SYNTAX, 0, 0},
        {"abc", API_NUM_SYNTAX, 0, 0}, {"1e999", API_NUM_OVERFLOW, 5, 0},
        {"-0", API_NUM_OK, 2, -0.0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *s = cases[i].s;
        double v = 0;
        const char *stop;
        api_num r = api_num_parse_text(s, s + strlen(s), &v, &stop);
        if (r != cases[i].status || stop - s != cases[i].stop) {
            fail_msg("\"%s\": status %d stop %td, expected %d %d", s, (int)r,
                     stop - s, (int)cases[i].status, cases[i].stop);
        }
        if (r == API_NUM_OK || (r == API_NUM_NONFINITE && isinf(cases[i].v))) {
            assert_true(bits(v) == bits(cases[i].v));
        }
        if (r == API_NUM_NONFINITE && !isinf(cases[i].v)) assert_true(isnan(v));
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_extremes),
        cmocka_unit_test(test_json_grammar),
        cmocka_unit_test(test_json_digit_runs),
        cmocka_unit_test(test_text_grammar),
        cmocka_unit_test(test_format_cases),
        cmocka_unit_test(test_parse_random_17g),
        cmocka_unit_test(test_parse_random_decimals),
        cmocka_unit_test(test_format_random),
    };
    return cmocka_run_group_tests_name("api/numconv", tests, NULL, NULL);
}
