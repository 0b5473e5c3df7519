/* fmt.h -- the few numbers voronoid writes on every request (access-log
 * fields, Server-Timing durations, request ids), without printf.
 *
 * glibc's printf costs about a microsecond for one "%.3f"; a request
 * writes about a dozen such numbers, which was a visible share of a tiny
 * request's cost. These write the same text as the printf formats named
 * below, for every value. Each writes into out (room for the size stated)
 * and returns the number of characters written; no NUL is added.
 */
#ifndef VOR_SRV_FMT_H
#define VOR_SRV_FMT_H

#include <stddef.h>
#include <stdint.h>

/* Longest text of srv_fmt_ms3 (a double of any magnitude in "%.3f"). */
#define SRV_FMT_MS3_MAX 320

/* v as "%.3f" would write it (rounded exactly, as printf does): "4.210".
 * out has room for SRV_FMT_MS3_MAX characters. */
size_t srv_fmt_ms3(char *out, double v);

/* v in decimal, as "%llu": out has room for 20 characters. */
size_t srv_fmt_u64(char *out, uint64_t v);

/* v as "%016llx": exactly 16 lowercase hex digits. */
size_t srv_fmt_hex64(char *out, uint64_t v);

#endif /* VOR_SRV_FMT_H */
