/* numconv.h -- exact, fast conversions between decimal text and doubles.
 *
 * A thin C interface over two header-only C++ libraries: fast_float (text ->
 * double, correctly rounded to nearest exactly like glibc's strtod, about
 * 0.06 us a number) and dragonbox (double -> the shortest decimal that reads
 * back to the same double, about 0.05 us). Implemented in numconv.cc; the
 * grammar checks are ours, the libraries only convert digits.
 *
 * None of these functions allocates, reads past `end`, or depends on the
 * locale or the floating-point rounding mode. */
#ifndef VOR_API_NUMCONV_H
#define VOR_API_NUMCONV_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum api_num {
    API_NUM_OK = 0,     /* a finite number was read */
    API_NUM_SYNTAX,     /* no number of the expected grammar starts here */
    API_NUM_OVERFLOW,   /* well-formed, but its magnitude exceeds DBL_MAX */
    API_NUM_NONFINITE   /* an inf/infinity/nan word (text grammar only) */
} api_num;

/* Reads one number of JSON's grammar (-?(0|[1-9][0-9]*)(.[0-9]+)?
 * ([eE][+-]?[0-9]+)?) starting at s, never reading at or beyond end.
 * *stop is set to the first byte after the longest grammatical prefix (s if
 * there is none). On API_NUM_OK *out is the correctly rounded value (an
 * underflow gives the nearest subnormal or a signed zero, as strtod does);
 * otherwise *out is unspecified. The caller decides whether the byte at
 * *stop may follow a number. */
api_num api_num_parse_json(const char *s, const char *end, double *out,
                           const char **stop);

/* Like api_num_parse_json, for text bodies: also accepts a leading '+',
 * a missing integer or fraction part (".5", "5."), leading zeros, and the
 * words inf, infinity and nan in any case (API_NUM_NONFINITE, *out set). */
api_num api_num_parse_text(const char *s, const char *end, double *out,
                           const char **stop);

/* Longest output of api_num_format, without a terminator. */
#define API_NUM_MAXLEN 26

/* Writes the shortest decimal that strtod reads back as exactly v (fewest
 * significant digits; among equally short ones the closest to v) into buf,
 * which must have room for API_NUM_MAXLEN bytes; returns the length. No
 * terminator is written. The form is JSON's: plain notation ("0.25",
 * "-3", "1500") when the decimal point falls within 17 digits of the first
 * digit and not more than 5 zeros after the point, exponent notation
 * ("1e-7", "1.25e300", no '+') otherwise, so integers in
 * plain notation stay below 10^17 and fit a 64-bit integer. -0.0 gives
 * "-0". v must be finite (non-finite values give 0 and write nothing). */
size_t api_num_format(double v, char *buf);

#ifdef __cplusplus
}
#endif

#endif /* VOR_API_NUMCONV_H */
