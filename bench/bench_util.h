/* bench_util.h -- the few helpers every benchmark driver shares, C and C++.
 *
 * A clock (CLOCK_MONOTONIC in nanoseconds), the kernel's CPU time, medians,
 * the peak-memory probe and the exchange files that let every peer run on the very same points:
 *
 *   points file:    little-endian float64 pairs x0 y0 x1 y1 ..., no header;
 *                   n = size / 16. A driver's --points may name several,
 *                   comma-separated, of the same n: run r computes file
 *                   r mod count (bu_split_paths).
 *   triangles file: uint32 triples of point indices (counter-clockwise
 *                   expected), no header; n_tri = size / 12.
 *
 * Peak memory: Linux keeps the high-water mark of the resident set (VmHWM in
 * /proc/self/status); writing "5" to /proc/self/clear_refs resets it to the
 * current resident set. A driver resets it once the input is ready, runs the
 * computation once, and reports VmHWM minus the resident set at the reset:
 * the memory the computation itself needed at its peak, output included.
 * Where the reset is refused, the probe reports -1 and the tables say "-".
 *
 * Everything is static so that each driver is one translation unit; the
 * header compiles as C11 and as C++17 (casts on malloc, no designated
 * initialisers). Results are printed by the drivers as one line
 * "RESULT key=value ..." that bench/run parses.
 */
#ifndef VOR_BENCH_UTIL_H
#define VOR_BENCH_UTIL_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

/* Monotonic time in nanoseconds. */
static inline uint64_t bu_now_ns(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

/* CPU time the kernel has spent on behalf of this process so far, in ms
 * (getrusage), -1 if unknown. A computation's share of it is mostly the
 * page faults of its first touch of fresh memory: the kernel zeroes each
 * page, and on a virtual machine whose host has taken the memory back, the
 * host backs it again first. Reported beside a wall time so that a growth
 * in one can be told from a growth in the other. */
static inline double bu_sys_ms(void) {
    struct rusage u;
    if (getrusage(RUSAGE_SELF, &u) != 0)
        return -1.0;
    return (double)u.ru_stime.tv_sec * 1e3 + (double)u.ru_stime.tv_usec / 1e3;
}

static inline int bu_cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of v[0..n-1] (sorts v in place); 0 for n == 0. */
static inline double bu_median(double *v, size_t n) {
    if (n == 0)
        return 0.0;
    qsort(v, n, sizeof *v, bu_cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* A field of /proc/self/status in KiB ("VmHWM", "VmRSS"), -1 if unknown. */
static inline long bu_status_kib(const char *field) {
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    size_t len = strlen(field);
    long v = -1;
    if (!f)
        return -1;
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, field, len) == 0 && line[len] == ':') {
            v = strtol(line + len + 1, NULL, 10);
            break;
        }
    }
    fclose(f);
    return v;
}

/* Resets the resident-set high-water mark; returns the mark (KiB) it was
 * reset to, or -1 if the kernel refused. */
static inline long bu_peak_reset(void) {
    FILE *f = fopen("/proc/self/clear_refs", "w");
    if (!f)
        return -1;
    int ok = fputs("5", f) >= 0;
    if (fclose(f) != 0 || !ok)
        return -1;
    long hwm = bu_status_kib("VmHWM"), rss = bu_status_kib("VmRSS");
    /* The reset worked only if the mark is now about the resident set. The
     * kernel batches its per-thread resident counters (64 pages each), so
     * the two can differ by a little either way. */
    if (hwm < 0 || rss < 0 || hwm > rss + 1024)
        return -1;
    return hwm;
}

/* Bytes of peak growth since bu_peak_reset() returned base_kib, or -1. */
static inline double bu_peak_bytes(long base_kib) {
    long hwm = bu_status_kib("VmHWM");
    if (base_kib < 0 || hwm < 0)
        return -1.0;
    return (double)(hwm - base_kib) * 1024.0;
}

/* Reads a whole file; *len receives its size. NULL on failure (message on
 * stderr: drivers are programs, not libraries). */
static inline void *bu_read_file(const char *path, size_t *len) {
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    long size;
    if (!f) {
        perror(path);
        return NULL;
    }
    if (fseek(f, 0, SEEK_END) != 0 || (size = ftell(f)) < 0 ||
        fseek(f, 0, SEEK_SET) != 0) {
        perror(path);
        fclose(f);
        return NULL;
    }
    buf = (char *)malloc((size_t)size + 1);
    if (!buf || fread(buf, 1, (size_t)size, f) != (size_t)size) {
        fprintf(stderr, "%s: cannot read\n", path);
        free(buf);
        fclose(f);
        return NULL;
    }
    fclose(f);
    buf[size] = '\0';
    *len = (size_t)size;
    return buf;
}

/* Points file -> new array of 2 * *n doubles. */
static inline double *bu_read_points(const char *path, size_t *n) {
    size_t len = 0;
    double *xy = (double *)bu_read_file(path, &len);
    if (xy && len % 16 != 0) {
        fprintf(stderr, "%s: size %zu is not a multiple of 16\n", path, len);
        free(xy);
        return NULL;
    }
    *n = len / 16;
    return xy;
}

/* Splits a comma-separated list of points files in place: *list's commas
 * become NULs and paths[0 .. count) point into it. Returns the count (at
 * most max). The drivers take such a list so that consecutive runs compute
 * different inputs of one size: one input repeated lets the branch
 * predictors learn it, which below about a thousand points is worth up to a
 * factor of two (bench_algo warmth). Run r computes input r mod count. */
static inline int bu_split_paths(char *list, char **paths, int max) {
    int count = 0;
    while (list && *list && count < max) {
        paths[count++] = list;
        char *comma = strchr(list, ',');
        if (!comma)
            break;
        *comma = '\0';
        list = comma + 1;
    }
    return count;
}

/* Writes len bytes to path; 0 on success. */
static inline int bu_write_file(const char *path, const void *data, size_t len) {
    FILE *f = fopen(path, "wb");
    if (!f) {
        perror(path);
        return -1;
    }
    size_t w = len ? fwrite(data, 1, len, f) : 0;
    if (fclose(f) != 0 || w != len) {
        fprintf(stderr, "%s: cannot write\n", path);
        return -1;
    }
    return 0;
}

/* Number of timed runs for a computation of about est_ns nanoseconds: enough
 * to fill budget_ns, at least min_runs, at most max_runs. */
static inline int bu_runs_for(double est_ns, double budget_ns, int min_runs,
                              int max_runs) {
    double r = est_ns > 0 ? budget_ns / est_ns : max_runs;
    if (r < min_runs)
        r = min_runs;
    if (r > max_runs)
        r = max_runs;
    return (int)r;
}

#endif /* VOR_BENCH_UTIL_H */
