/* bench_algo.c -- the driver that times libvor's algorithms and checks
 * triangulations, ours and the peers', with exact predicates.
 *
 * Subcommands (bench/run calls them; every one prints what it measured):
 *
 *   table   for each distribution, each n and each algorithm, one child
 *           process: generate the points, prepare the sites (vor_sites_new,
 *           outside the timer), then time vor_compute -- the full canonical
 *           diagram -- on as many inputs of that size as fit in a time
 *           budget (5 to 1001 runs, a new input each) and report the median
 *           and the first run apart; at the sizes named by --mem-ns the
 *           first run also measures peak memory (bench_util.h). Prints one
 *           table per distribution and writes every case to --csv.
 *   points  writes a generated set as a points file, so that every peer
 *           reads the very same doubles: a distribution (--dist) or a
 *           shape (--shape, bench_shapes.h).
 *   shapes  lists the shapes' names, one a line.
 *   json    writes a generated set as a POST /voronoi JSON body.
 *   ours    times one algorithm on a points file like the peers are timed,
 *           optionally writing the dual triangles for `check`.
 *   warmth  the same computation timed three ways, to tell the machine's
 *           state from the algorithm's cost: cold (each run in a fresh
 *           process on points it has never seen: cold caches, untrained
 *           branch predictors, fresh heap pages), warm on the same points
 *           (one process repeating one input, as `table` does) and warm on
 *           varied points (one process, a new input of the same size each
 *           run). Medians of --runs runs each.
 *   check   verifies a triangulation of a points file exactly: indices in
 *           range, every triangle strictly counter-clockwise, every edge in
 *           at most two triangles and in opposite directions, every interior
 *           edge locally Delaunay (vor_incircle), every distinct point used
 *           (duplicates are one site, named by any of their indices), and
 *           the triangle count equal to 2n - 2 - h, with n the distinct
 *           points and h those on the convex hull's boundary from an
 *           independent monotone chain. Also
 *           counts Voronoi vertices (triangles merged across cocircular
 *           edges) to compare with our diagram.
 *
 * Distributions: every one the service generates (uniform, gaussian,
 * pixels alias random, grid, circle, clustered, lognormal, outlier,
 * decades; api/distribution.h through tests/support/testsets.h), the same
 * points as `voronoi --generate DIST:N:SEED`, and unit-circle (cos, sin of
 * 2 pi k/n, the same as circle).
 *
 * Each table case runs in its own process so that one case's heap does not
 * skew the next one's time or memory, and so that a crash or an overlong
 * run (SIGALRM after --limit-s) costs one row, not the run. A case whose
 * time, predicted from the algorithm's previous size, would exceed
 * --limit-s, or the table's --total-s, is skipped and says so.
 */
#include <errno.h>
#include <signal.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../core/internal.h"
#include "../core/vor.h"
#include "../api/codec.h"
#include "../tests/support/testsets.h"
#include "bench_shapes.h"
#include "bench_util.h"

#define MAX_LIST 32

static void usage(void) {
    fputs(
        "usage: bench_algo table [--algos a,b] [--dists d,e] [--ns 10,100]\n"
        "                        [--mem-ns 100000] [--check-max N] [--seed S]\n"
        "                        [--budget-ms 300] [--limit-s 240]\n"
        "                        [--total-s 0] --csv FILE\n"
        "       bench_algo points --dist D --n N [--seed S] --out FILE\n"
        "       bench_algo points --shape S --n N [--seed S] --out FILE\n"
        "       bench_algo shapes\n"
        "       bench_algo json   --dist D --n N [--seed S] [--algo A] --out FILE\n"
        "       bench_algo ours   --algo A --points FILE [--runs R]\n"
        "                         [--budget-ms B] [--tris FILE] [--clip 1]\n"
        "                         (R runs, fewer if they overrun B; --clip 1\n"
        "                         also times vor_clip of the diagram to the\n"
        "                         GeoJSON answers' default box, R runs)\n"
        "       bench_algo check  --points FILE --tris FILE\n"
        "       bench_algo warmth [--algos a,b] --dist D --ns 500,1000\n"
        "                         [--runs R] [--seed S] --csv FILE\n"
        "distributions: uniform gaussian pixels (random) grid circle clustered\n"
        "               lognormal outlier decades unit-circle\n",
        stderr);
}

/* ---- options -------------------------------------------------------------- */

typedef struct opts {
    const char *algos, *dists, *ns, *mem_ns, *csv, *out, *points, *tris;
    const char *dist, *shape, *algo;
    size_t n, check_max;
    uint64_t seed;
    double budget_ms;
    int budget_set; /* --budget-ms was given */
    int runs, limit_s, total_s;
    int clip; /* ours: also time vor_clip (--clip 1) */
} opts;

static int parse_opts(int argc, char **argv, opts *o) {
    memset(o, 0, sizeof *o);
    o->algos = "fortune,bowyer-watson,flip";
    o->dists = "uniform,gaussian,random";
    o->ns = "10,100,1000";
    o->mem_ns = "";
    o->algo = "bowyer-watson";
    o->seed = 1;
    o->budget_ms = 300; /* table: per case; ours: for all runs, if given */
    o->runs = 3;
    o->limit_s = 240;
    o->check_max = 100000;
    for (int i = 2; i < argc; i++) {
        const char *k = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v) {
            fprintf(stderr, "%s needs a value\n", k);
            return -1;
        }
        i++;
        if (!strcmp(k, "--algos")) o->algos = v;
        else if (!strcmp(k, "--dists")) o->dists = v;
        else if (!strcmp(k, "--ns")) o->ns = v;
        else if (!strcmp(k, "--mem-ns")) o->mem_ns = v;
        else if (!strcmp(k, "--csv")) o->csv = v;
        else if (!strcmp(k, "--out")) o->out = v;
        else if (!strcmp(k, "--points")) o->points = v;
        else if (!strcmp(k, "--tris")) o->tris = v;
        else if (!strcmp(k, "--dist")) o->dist = v;
        else if (!strcmp(k, "--shape")) o->shape = v;
        else if (!strcmp(k, "--algo")) o->algo = v;
        else if (!strcmp(k, "--n")) o->n = strtoull(v, NULL, 10);
        else if (!strcmp(k, "--check-max")) o->check_max = strtoull(v, NULL, 10);
        else if (!strcmp(k, "--seed")) o->seed = strtoull(v, NULL, 10);
        else if (!strcmp(k, "--budget-ms")) {
            o->budget_ms = strtod(v, NULL);
            o->budget_set = 1;
        }
        else if (!strcmp(k, "--runs")) o->runs = atoi(v);
        else if (!strcmp(k, "--limit-s")) o->limit_s = atoi(v);
        else if (!strcmp(k, "--total-s")) o->total_s = atoi(v);
        else if (!strcmp(k, "--clip")) o->clip = atoi(v);
        else {
            fprintf(stderr, "unknown option %s\n", k);
            return -1;
        }
    }
    return 0;
}

/* Splits a comma-separated list in place (s is copied first); returns the
 * count, at most MAX_LIST. */
static size_t split(const char *s, char *buf, size_t bufsize,
                    const char **items) {
    size_t n = 0;
    snprintf(buf, bufsize, "%s", s);
    for (char *tok = strtok(buf, ","); tok && n < MAX_LIST;
         tok = strtok(NULL, ","))
        items[n++] = tok;
    return n;
}

/* ---- points ----------------------------------------------------------------- */

/* New array of 2n doubles for a named distribution, NULL if unknown or out of
 * memory: the service's distributions (api/distribution.h, the very points
 * `voronoi --generate DIST:N:SEED` makes) and unit-circle. */
static double *generate(const char *dist, size_t n, uint64_t seed) {
    if (!strcmp(dist, "unit-circle"))
        return vt_unit_circle(n);
    double *xy = vt_distribution(dist, n, seed);
    if (!xy)
        fprintf(stderr, "unknown distribution %s (or out of memory)\n", dist);
    return xy;
}

/* ---- one timed case ---------------------------------------------------------- */

typedef struct result {
    int status;        /* vor_status of the last compute */
    int check_ok;      /* 1 valid, 0 invalid, -1 not checked */
    int runs;
    size_t n, distinct, vertices, edges, triangles;
    double median_ms, min_ms, first_ms, peak_bytes;
    double first_sys_ms; /* the kernel's CPU time in the first run, or -1 */
    vor_counts counts; /* of the first run */
    char msg[160];
} result;

/* Times vor_compute on prepared sites: one run first (with the peak-memory
 * probe when measure_mem), then as many as fit in budget_ms (at least
 * min_runs in all, at most max_runs). The first run, the process's first
 * touch of its heap and of the algorithm's code, is reported apart
 * (first_ms); with three runs or more the median leaves it out. Keeps the
 * last diagram in *keep when keep != NULL. */
static void time_compute(const vor_sites *sites, vor_algorithm algo,
                         int measure_mem, double budget_ms, int min_runs,
                         int max_runs, result *r, vor_diagram **keep) {
    double *ms = malloc(sizeof *ms * (size_t)(max_runs > 0 ? max_runs : 1));
    vor_diagram *d = NULL;
    long base = -1;
    if (!ms) {
        r->status = VOR_ENOMEM;
        return;
    }
    r->peak_bytes = -1;
    if (measure_mem)
        base = bu_peak_reset();
    /* the counts cost the same whether read or not (vor_compute_ex) */
    vor_options opt = {.counts = &r->counts};
    double s0 = bu_sys_ms();
    uint64_t t0 = bu_now_ns();
    vor_status st = vor_compute_ex(sites, algo, &opt, &d);
    uint64_t t1 = bu_now_ns();
    double s1 = bu_sys_ms();
    r->first_sys_ms = s0 >= 0 && s1 >= 0 ? s1 - s0 : -1.0;
    if (measure_mem && st == VOR_OK)
        r->peak_bytes = bu_peak_bytes(base);
    ms[0] = (double)(t1 - t0) / 1e6;
    int runs = 1;
    int want = bu_runs_for((double)(t1 - t0), budget_ms * 1e6, min_runs,
                           max_runs);
    while (st == VOR_OK && runs < want) {
        vor_diagram_free(d);
        d = NULL;
        t0 = bu_now_ns();
        st = vor_compute(sites, algo, &d);
        t1 = bu_now_ns();
        ms[runs++] = (double)(t1 - t0) / 1e6;
    }
    r->status = st;
    r->runs = runs;
    r->first_ms = ms[0];
    r->min_ms = ms[0];
    for (int i = 1; i < runs; i++)
        if (ms[i] < r->min_ms)
            r->min_ms = ms[i];
    r->median_ms = runs >= 3 ? bu_median(ms + 1, (size_t)runs - 1)
                             : bu_median(ms, (size_t)runs);
    if (d) {
        r->vertices = d->n_vertices;
        r->edges = d->n_edges;
    }
    if (keep)
        *keep = d;
    else
        vor_diagram_free(d);
    free(ms);
}

/* Prepared sites of dist for (n, seed); NULL on failure. */
static vor_sites *sites_for(const char *dist, size_t n, uint64_t seed) {
    double *xy = generate(dist, n, seed);
    vor_sites *s = NULL;
    if (xy && vor_sites_new(xy, n, &s, NULL) != VOR_OK)
        s = NULL;
    free(xy);
    return s;
}

/* The child's work for one table case; fills *r.
 *
 * Every run computes a new input of the distribution and size (seeds seed,
 * seed + 1, ...), prepared outside the timer just before it: one input
 * repeated lets the branch predictors learn it, which at small n is worth a
 * factor of two (bench_algo warmth shows it), and no user repeats an input.
 * grid and circle have no seed and repeat theirs. The first run, the
 * process's first (fresh heap pages, cold code), is reported apart as
 * first_ms, and its diagram is the one counted and checked (every algorithm
 * sees the same first input); the median is over the other runs, as many
 * as fit in the budget: a cap that changed with n (it once dropped from
 * 1001 to 51 runs above n = 1000) would change how warm the median is at
 * that n, not the algorithm. */
static void table_case(const opts *o, const char *dist, vor_algorithm algo,
                       size_t n, int measure_mem, result *r) {
    memset(r, 0, sizeof *r);
    r->n = n;
    r->check_ok = -1;
    r->peak_bytes = -1;
    vor_sites *first = sites_for(dist, n, o->seed);
    if (!first) {
        r->status = VOR_ENOMEM;
        return;
    }
    r->distinct = first->n;
    vor_diagram *d = NULL;
    long base = measure_mem ? bu_peak_reset() : -1;
    uint64_t t0 = bu_now_ns();
    vor_status st = vor_compute(first, algo, &d);
    uint64_t t1 = bu_now_ns();
    if (measure_mem && st == VOR_OK)
        r->peak_bytes = bu_peak_bytes(base);
    r->first_ms = r->min_ms = r->median_ms = (double)(t1 - t0) / 1e6;
    int want = bu_runs_for((double)(t1 - t0), o->budget_ms * 1e6, 5, 1001);
    double *ms = malloc(sizeof *ms * (size_t)want);
    int runs = 0;
    if (!ms)
        st = VOR_ENOMEM;
    while (st == VOR_OK && 1 + runs < want) {
        vor_sites *s = sites_for(dist, n, o->seed + 1 + (uint64_t)runs);
        vor_diagram *e = NULL;
        if (!s) {
            st = VOR_ENOMEM;
            break;
        }
        t0 = bu_now_ns();
        st = vor_compute(s, algo, &e);
        t1 = bu_now_ns();
        ms[runs++] = (double)(t1 - t0) / 1e6;
        if (ms[runs - 1] < r->min_ms)
            r->min_ms = ms[runs - 1];
        vor_diagram_free(e);
        vor_sites_free(s);
    }
    r->status = st;
    r->runs = 1 + runs;
    if (runs > 0)
        r->median_ms = bu_median(ms, (size_t)runs);
    if (d) {
        r->vertices = d->n_vertices;
        r->edges = d->n_edges;
        if (n <= o->check_max)
            r->check_ok = vor_check(d, first, r->msg, sizeof r->msg) == 0;
    }
    free(ms);
    vor_diagram_free(d);
    vor_sites_free(first);
}

static const char *status_text(const result *r) {
    if (r->status >= 0 && r->status < VOR_STATUS_COUNT)
        return r->status == VOR_OK ? "ok" : vor_status_name(r->status);
    return r->msg;
}

/* Runs fn(arg, out) in a child process that an alarm ends after limit_s
 * seconds; the child sends the size bytes of *out back through a pipe.
 * Returns 0 when they arrived, -1 otherwise with the reason (a crash, the
 * timeout, no result) in msg. */
static int in_child(void (*fn)(const void *arg, void *out), const void *arg,
                    void *out, size_t size, int limit_s, char *msg,
                    size_t msg_size) {
    int fd[2];
    fflush(NULL);
    if (pipe(fd) != 0) {
        snprintf(msg, msg_size, "pipe: %s", strerror(errno));
        return -1;
    }
    pid_t pid = fork();
    if (pid < 0) {
        snprintf(msg, msg_size, "fork: %s", strerror(errno));
        close(fd[0]);
        close(fd[1]);
        return -1;
    }
    if (pid == 0) {
        close(fd[0]);
        alarm((unsigned)limit_s);
        fn(arg, out);
        size_t done = 0;
        while (done < size) {
            ssize_t w = write(fd[1], (const char *)out + done, size - done);
            if (w < 0 && errno == EINTR)
                continue;
            if (w <= 0)
                _exit(1);
            done += (size_t)w;
        }
        _exit(0);
    }
    close(fd[1]);
    size_t have = 0;
    while (have < size) {
        ssize_t k = read(fd[0], (char *)out + have, size - have);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            break;
        have += (size_t)k;
    }
    close(fd[0]);
    int ws = 0;
    while (waitpid(pid, &ws, 0) < 0 && errno == EINTR)
        ;
    if (have == size)
        return 0;
    if (WIFSIGNALED(ws) && WTERMSIG(ws) == SIGALRM)
        snprintf(msg, msg_size, "timeout>%ds", limit_s);
    else if (WIFSIGNALED(ws))
        snprintf(msg, msg_size, "crash(signal %d)", WTERMSIG(ws));
    else
        snprintf(msg, msg_size, "no-result(exit %d)",
                 WIFEXITED(ws) ? WEXITSTATUS(ws) : -1);
    return -1;
}

typedef struct case_arg {
    const opts *o;
    const char *dist;
    vor_algorithm algo;
    size_t n;
    int measure_mem;
} case_arg;

static void table_child(const void *arg, void *out) {
    const case_arg *a = (const case_arg *)arg;
    table_case(a->o, a->dist, a->algo, a->n, a->measure_mem, (result *)out);
}

/* Runs table_case in a child with an alarm; a crash, a timeout or a broken
 * pipe is reported in r (status -1, msg says what). */
static void run_case(const opts *o, const char *dist, vor_algorithm algo,
                     size_t n, int measure_mem, result *r) {
    case_arg a = {o, dist, algo, n, measure_mem};
    char msg[sizeof r->msg];
    if (in_child(table_child, &a, r, sizeof *r, o->limit_s, msg, sizeof msg)) {
        memset(r, 0, sizeof *r);
        r->n = n;
        r->check_ok = -1;
        r->peak_bytes = -1;
        r->status = -1;
        snprintf(r->msg, sizeof r->msg, "%s", msg);
    }
}

static int in_list(size_t n, const size_t *v, size_t k) {
    for (size_t i = 0; i < k; i++)
        if (v[i] == n)
            return 1;
    return 0;
}

static void fmt_ms(char *buf, size_t size, double ms) {
    if (ms >= 100)
        snprintf(buf, size, "%.0f", ms);
    else if (ms >= 1)
        snprintf(buf, size, "%.2f", ms);
    else
        snprintf(buf, size, "%.4f", ms);
}

static int cmd_table(const opts *o) {
    char abuf[512], dbuf[512], nbuf[512], mbuf[512];
    const char *an[MAX_LIST], *dn[MAX_LIST], *ns[MAX_LIST], *ms[MAX_LIST];
    size_t na = split(o->algos, abuf, sizeof abuf, an);
    size_t nd = split(o->dists, dbuf, sizeof dbuf, dn);
    size_t nn = split(o->ns, nbuf, sizeof nbuf, ns);
    size_t nm = split(o->mem_ns, mbuf, sizeof mbuf, ms);
    vor_algorithm algo[MAX_LIST];
    size_t nval[MAX_LIST], mem[MAX_LIST];
    int bad = 0;
    for (size_t i = 0; i < na; i++)
        if (vor_algorithm_parse(an[i], &algo[i]) != VOR_OK) {
            fprintf(stderr, "unknown algorithm %s\n", an[i]);
            return 2;
        }
    for (size_t i = 0; i < nn; i++)
        nval[i] = strtoull(ns[i], NULL, 10);
    for (size_t i = 0; i < nm; i++)
        mem[i] = strtoull(ms[i], NULL, 10);
    FILE *csv = o->csv ? fopen(o->csv, "w") : NULL;
    if (o->csv && !csv) {
        perror(o->csv);
        return 2;
    }
    if (csv)
        fprintf(csv, "algorithm,distribution,n,distinct,runs,median_ms,min_ms,"
                     "ns_per_point,peak_bytes_per_point,vertices,edges,check,"
                     "status,first_ms\n");
    printf("Timed: vor_compute only (full canonical diagram), sites prepared "
           "outside the timer;\neach run on a new input of the same size "
           "(seeds S, S+1, ...; grid and circle\nrepeat theirs); ms = median "
           "of the runs after the first; ns/pt = that median / n\ninput "
           "points; 1st = the first run's ns/pt (fresh heap, cold code); "
           "B/pt = peak\nmemory of one vor_compute per input point (VmHWM "
           "growth, child process per case).\nseed S = %llu\n",
           (unsigned long long)o->seed);
    uint64_t t_start = bu_now_ns();
    for (size_t di = 0; di < nd; di++) {
        /* Whether an algorithm has given up on this distribution (a larger
         * n after a timeout or crash would only waste the budget). */
        int gave_up[MAX_LIST] = {0};
        /* Last successful case per algorithm, to predict the next one. */
        size_t prev_n[MAX_LIST] = {0};
        double prev_ms[MAX_LIST] = {0};
        printf("\n== %s\n%9s", dn[di], "n");
        for (size_t ai = 0; ai < na; ai++)
            printf(" | %-33s", an[ai]);
        printf("\n%9s", "");
        for (size_t ai = 0; ai < na; ai++)
            printf(" | %9s %6s %5s %4s %4s", "ms", "ns/pt", "1st", "B/pt",
                   "runs");
        printf("\n");
        for (size_t ni = 0; ni < nn; ni++) {
            size_t n = nval[ni];
            size_t counts[MAX_LIST][2];
            int have_counts = 0, differ = 0;
            printf("%9zu", n);
            fflush(stdout);
            for (size_t ai = 0; ai < na; ai++) {
                result r;
                /* A case needs at least 3 runs; predict one from the last
                 * size, growing a little faster than linearly. */
                double predicted_s =
                    prev_n[ai] ? prev_ms[ai] / 1e3 * ((double)n / prev_n[ai]) *
                                     1.3
                               : 0.0;
                double elapsed = (double)(bu_now_ns() - t_start) / 1e9;
                const char *skip =
                    gave_up[ai] ? "skipped (smaller n failed)"
                    : 3 * predicted_s > o->limit_s
                        ? "skipped (over --limit-s)"
                    : o->total_s > 0 && elapsed + 3 * predicted_s > o->total_s
                        ? "skipped (over --total-s)"
                        : NULL;
                if (skip) {
                    memset(&r, 0, sizeof r);
                    r.n = n;
                    r.status = -1;
                    r.check_ok = -1;
                    r.peak_bytes = -1;
                    snprintf(r.msg, sizeof r.msg, "%s", skip);
                } else {
                    run_case(o, dn[di], algo[ai], n, in_list(n, mem, nm), &r);
                }
                if (r.status == VOR_OK) {
                    prev_n[ai] = n;
                    prev_ms[ai] = r.median_ms;
                }
                if (r.status != VOR_OK) {
                    printf(" | %-33.33s", status_text(&r));
                    if (r.status < 0)
                        gave_up[ai] = 1;
                } else {
                    char t[32], b[16] = "-";
                    fmt_ms(t, sizeof t, r.median_ms);
                    if (r.peak_bytes >= 0)
                        snprintf(b, sizeof b, "%.0f",
                                 r.peak_bytes / (double)n);
                    printf(" | %9s %6.0f %5.0f %4s %4d%s", t,
                           r.median_ms * 1e6 / (double)n,
                           r.first_ms * 1e6 / (double)n, b, r.runs,
                           r.check_ok == 0 ? "!" : "");
                    counts[ai][0] = r.vertices;
                    counts[ai][1] = r.edges;
                    if (have_counts && (counts[ai][0] != counts[0][0] ||
                                        counts[ai][1] != counts[0][1]))
                        differ = 1;
                    if (ai == 0)
                        have_counts = 1;
                }
                fflush(stdout);
                if (r.check_ok == 0) {
                    fprintf(stderr, "%s %s n=%zu: vor_check: %s\n", an[ai],
                            dn[di], n, r.msg);
                    bad = 1;
                }
                if (csv) {
                    fprintf(csv, "%s,%s,%zu,%zu,%d,%.6f,%.6f,%.2f,", an[ai],
                            dn[di], n, r.distinct, r.runs, r.median_ms,
                            r.min_ms,
                            r.status == VOR_OK ? r.median_ms * 1e6 / (double)n
                                               : 0.0);
                    if (r.peak_bytes >= 0)
                        fprintf(csv, "%.1f", r.peak_bytes / (double)n);
                    fprintf(csv, ",%zu,%zu,%s,%s,%.6f\n", r.vertices, r.edges,
                            r.check_ok < 0   ? "-"
                            : r.check_ok > 0 ? "ok"
                                             : "FAILED",
                            status_text(&r), r.first_ms);
                    fflush(csv);
                }
            }
            printf("%s\n", differ ? "  <- algorithms' counts differ" : "");
            if (differ)
                bad = 1;
        }
    }
    if (csv && fclose(csv) != 0) {
        perror(o->csv);
        return 2;
    }
    printf("\n('!' after runs: vor_check rejected the diagram; checked up to "
           "n = %zu)\n",
           o->check_max);
    return bad;
}

/* ---- points, json ------------------------------------------------------------ */

static int cmd_points(const opts *o, int json) {
    if (!o->dist == !o->shape || !o->out || o->n == 0) {
        usage();
        return 2;
    }
    double *xy;
    if (o->shape) {
        xy = bs_shape(o->shape, o->n, o->seed);
        if (!xy)
            fprintf(stderr, "unknown shape %s (or out of memory)\n", o->shape);
    } else {
        xy = generate(o->dist, o->n, o->seed);
    }
    if (!xy)
        return 2;
    int rc;
    if (!json) {
        rc = bu_write_file(o->out, xy, o->n * 16);
    } else {
        FILE *f = fopen(o->out, "w");
        rc = -1;
        if (f) {
            fprintf(f, "{\"algorithm\":\"%s\",\"points\":[", o->algo);
            for (size_t i = 0; i < o->n; i++)
                fprintf(f, "%s[%.17g,%.17g]", i ? "," : "", xy[2 * i],
                        xy[2 * i + 1]);
            fputs("]}\n", f);
            rc = fclose(f) == 0 ? 0 : -1;
        }
        if (rc)
            perror(o->out);
    }
    free(xy);
    return rc ? 2 : 0;
}

/* ---- ours --------------------------------------------------------------------- */

/* --clip 1: vor_clip of diagram d to the box GeoJSON answers are clipped
 * to when no bounds are given (api__default_box), runs times; prints
 * clip_ms (median) and clip_min_ms. */
static vor_status time_clip(const vor_diagram *d, const vor_sites *s,
                            int runs) {
    double box[4];
    api__default_box(s, box);
    double ms[64];
    if (runs < 1) runs = 1;
    if (runs > 64) runs = 64;
    for (int k = 0; k < runs; k++) {
        vor_clipped *c = NULL;
        uint64_t t0 = bu_now_ns();
        vor_status st = vor_clip(d, s, box, &c);
        ms[k] = (double)(bu_now_ns() - t0) / 1e6;
        vor_clipped_free(c);
        if (st != VOR_OK) return st;
    }
    double least = ms[0];
    for (int k = 1; k < runs; k++) least = ms[k] < least ? ms[k] : least;
    printf(" clip_ms=%.3f clip_min_ms=%.3f", bu_median(ms, (size_t)runs),
           least);
    return VOR_OK;
}

static int cmd_ours(const opts *o) {
    vor_algorithm algo;
    size_t n = 0;
    if (!o->points || vor_algorithm_parse(o->algo, &algo) != VOR_OK) {
        usage();
        return 2;
    }
    double *xy = bu_read_points(o->points, &n);
    if (!xy)
        return 2;
    vor_sites *sites = NULL;
    vor_status st = vor_sites_new(xy, n, &sites, NULL);
    free(xy);
    if (st != VOR_OK) {
        printf("RESULT name=%s n=%zu status=%s\n", o->algo, n,
               vor_status_name(st));
        return 1;
    }
    result r;
    vor_diagram *d = NULL;
    memset(&r, 0, sizeof r);
    /* --runs runs, as peer_cgal makes them; fewer when they would not fit
     * in --budget-ms, if given (a slow algorithm then gets one run). Its
     * default, the table's, cut --runs 5 to one run at 10^6 sites. */
    time_compute(sites, algo, 1, o->budget_set ? o->budget_ms : INFINITY, 1,
                 o->runs, &r, &d);
    if (r.status != VOR_OK) {
        printf("RESULT name=%s n=%zu status=%s\n", o->algo, n,
               vor_status_name(r.status));
        vor_sites_free(sites);
        return 1;
    }
    uint32_t *tri = NULL;
    size_t nt = 0;
    st = vor_diagram_triangles(d, sites, &tri, &nt);
    /* the file names input points, as the peers' do: a site is its first
     * occurrence */
    for (size_t i = 0; st == VOR_OK && i < 3 * nt; i++)
        tri[i] = sites->input_of[tri[i]];
    if (st == VOR_OK && o->tris && bu_write_file(o->tris, tri, nt * 12) != 0)
        st = VOR_EINVAL;
    printf("RESULT name=%s n=%zu ms=%.3f min_ms=%.3f runs=%d peak_bpp=%.1f "
           "sys_ms=%.1f vertices=%zu triangles=%zu sites=%zu",
           o->algo, n, r.median_ms, r.min_ms, r.runs,
           r.peak_bytes >= 0 ? r.peak_bytes / (double)n : -1.0,
           r.first_sys_ms, r.vertices, nt, sites->n);
    if (st == VOR_OK && o->clip) st = time_clip(d, sites, o->runs);
    /* the operation counts of the first run, those of this algorithm */
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++)
        if (vor_count_algorithms(i) & (1u << algo))
            printf(" c_%s=%llu", vor_count_name(i),
                   (unsigned long long)vor_count_value(&r.counts, i));
    printf(" status=%s\n", st == VOR_OK ? "ok" : vor_status_name(st));
    free(tri);
    vor_diagram_free(d);
    vor_sites_free(sites);
    return st == VOR_OK ? 0 : 1;
}

/* ---- check ---------------------------------------------------------------------- */

static const double *g_xy; /* for the qsort comparators below */

static int cmp_lex(const void *a, const void *b) {
    const double *p = g_xy + 2 * *(const uint32_t *)a;
    const double *q = g_xy + 2 * *(const uint32_t *)b;
    if (p[0] != q[0])
        return p[0] < q[0] ? -1 : 1;
    return (p[1] > q[1]) - (p[1] < q[1]);
}

static const uint64_t *g_key; /* half-edge keys, for cmp_by_key */

static int cmp_by_key(const void *a, const void *b) {
    uint64_t x = g_key[*(const uint32_t *)a], y = g_key[*(const uint32_t *)b];
    return (x > y) - (x < y);
}

/* Number of points on the boundary of the convex hull of the distinct
 * points (vertices and points inside hull edges), by Andrew's monotone
 * chain that pops only on strict right turns; -1 on allocation failure.
 * canon[i] receives the smallest index of the points equal to point i,
 * and *distinct their number: duplicates are one site, whichever index
 * a triangulation names it by. */
static long hull_boundary(const double *xy, size_t n, uint32_t *canon,
                          size_t *distinct) {
    uint32_t *idx = malloc(sizeof *idx * (n ? n : 1)),
             *h = malloc(sizeof *h * 2 * (n ? n : 1));
    long count = -1;
    if (!idx || !h)
        goto out;
    for (size_t i = 0; i < n; i++)
        idx[i] = (uint32_t)i;
    g_xy = xy;
    qsort(idx, n, sizeof *idx, cmp_lex);
    size_t m = 0; /* distinct points, each its smallest index, in idx[0..m) */
    for (size_t i = 0, j; i < n; i = j) {
        uint32_t least = idx[i];
        for (j = i + 1; j < n && cmp_lex(&idx[i], &idx[j]) == 0; j++)
            least = idx[j] < least ? idx[j] : least;
        for (size_t k = i; k < j; k++)
            canon[idx[k]] = least;
        idx[m++] = least;
    }
    *distinct = m;
    size_t k = 0;
    for (size_t i = 0; i < m; i++) { /* lower chain */
        while (k >= 2 && vor_orient2d(xy + 2 * h[k - 2], xy + 2 * h[k - 1],
                                      xy + 2 * idx[i]) < 0)
            k--;
        h[k++] = idx[i];
    }
    size_t lower = k;
    for (size_t i = m - 1; m > 1 && i-- > 0;) { /* upper chain */
        while (k >= lower + 1 &&
               vor_orient2d(xy + 2 * h[k - 2], xy + 2 * h[k - 1],
                            xy + 2 * idx[i]) < 0)
            k--;
        h[k++] = idx[i];
    }
    count = k ? (long)k - 1 : 0; /* the first point closes the chain */
out:
    free(idx);
    free(h);
    return count;
}

static uint32_t uf_find(uint32_t *p, uint32_t x) {
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

/* Index in by_key (half-edge ids sorted by key) of the first half-edge with
 * the given key, or m if there is none. */
static size_t find_key(const uint64_t *key, const uint32_t *by_key, size_t m,
                       uint64_t k) {
    size_t lo = 0, hi = m;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (key[by_key[mid]] < k)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < m && key[by_key[lo]] == k ? lo : m;
}

static int cmd_check(const opts *o) {
    size_t n = 0, len = 0;
    if (!o->points || !o->tris) {
        usage();
        return 2;
    }
    double *xy = bu_read_points(o->points, &n);
    uint32_t *t = xy ? bu_read_file(o->tris, &len) : NULL;
    if (!xy || !t || len % 12 != 0) {
        if (t)
            fprintf(stderr, "%s: size is not a multiple of 12\n", o->tris);
        free(xy);
        free(t);
        return 2;
    }
    size_t nt = len / 12, m = 3 * nt, bad_index = 0, bad_orient = 0,
           bad_edges = 0, bad_delaunay = 0, unused = 0, vertices = 0,
           boundary = 0;
    /* Half-edge e = 3i + k goes from t[e] to t[3i + (k+1)%3]; its key packs
     * (from, to) so that sorting ids by key lets the twin (to, from) be found
     * by binary search. */
    uint64_t *key = malloc(sizeof *key * (m ? m : 1));
    uint32_t *by_key = malloc(sizeof *by_key * (m ? m : 1));
    uint32_t *uf = malloc(sizeof *uf * (nt ? nt : 1));
    uint8_t *used = calloc(n ? n : 1, 1);
    uint32_t *canon = malloc(sizeof *canon * (n ? n : 1));
    size_t distinct = 0;
    long h = canon ? hull_boundary(xy, n, canon, &distinct) : -1;
    if (!key || !by_key || !uf || !used || h == -1) {
        fputs("check: out of memory\n", stderr);
        return 2;
    }
    for (size_t i = 0; i < nt; i++) {
        uint32_t *v = t + 3 * i;
        uf[i] = (uint32_t)i;
        if (v[0] >= n || v[1] >= n || v[2] >= n) {
            bad_index++;
            v[0] = v[1] = v[2] = 0;
        } else {
            for (int k = 0; k < 3; k++) /* one name per site */
                v[k] = canon[v[k]];
            if (vor_orient2d(xy + 2 * v[0], xy + 2 * v[1], xy + 2 * v[2]) <= 0)
                bad_orient++;
        }
        for (int k = 0; k < 3; k++) {
            used[v[k]] = 1;
            key[3 * i + k] = (uint64_t)v[k] << 32 | v[(k + 1) % 3];
            by_key[3 * i + k] = (uint32_t)(3 * i + k);
        }
    }
    g_key = key;
    qsort(by_key, m, sizeof *by_key, cmp_by_key);
    for (size_t i = 1; i < m; i++)
        if (key[by_key[i]] == key[by_key[i - 1]])
            bad_edges++; /* the same directed edge in two triangles */
    for (size_t e = 0; e < m; e++) {
        uint32_t from = (uint32_t)(key[e] >> 32), to = (uint32_t)key[e];
        size_t j = find_key(key, by_key, m, (uint64_t)to << 32 | from);
        if (j == m) {
            boundary++;
            continue;
        }
        size_t f = by_key[j];
        if (f < e)
            continue; /* each interior edge once */
        uint32_t c = t[3 * (e / 3) + (e % 3 + 2) % 3]; /* apex of e */
        uint32_t d = t[3 * (f / 3) + (f % 3 + 2) % 3]; /* apex across */
        int s = vor_incircle(xy + 2 * from, xy + 2 * to, xy + 2 * c,
                             xy + 2 * d);
        if (s > 0) {
            bad_delaunay++;
        } else if (s == 0) { /* same circumcircle: one Voronoi vertex */
            uint32_t x = uf_find(uf, (uint32_t)(e / 3)),
                     y = uf_find(uf, (uint32_t)(f / 3));
            if (x != y)
                uf[x] = y;
        }
    }
    for (size_t i = 0; i < n; i++)
        unused += canon[i] == i && !used[i];
    for (size_t i = 0; i < nt; i++)
        vertices += uf_find(uf, (uint32_t)i) == i;
    long expected = h >= 0 ? 2 * (long)distinct - 2 - h : -1;
    int ok = bad_index == 0 && bad_orient == 0 && bad_edges == 0 &&
             bad_delaunay == 0 && unused == 0 && h >= 0 &&
             (long)nt == expected && (long)boundary == h;
    printf("RESULT check=%s n=%zu distinct=%zu triangles=%zu expected=%ld "
           "hull=%ld boundary_edges=%zu bad_index=%zu bad_orient=%zu "
           "bad_edges=%zu bad_delaunay=%zu unused=%zu voronoi_vertices=%zu\n",
           ok ? "ok" : "WRONG", n, distinct, nt, expected, h, boundary, bad_index,
           bad_orient, bad_edges, bad_delaunay, unused, vertices);
    free(xy);
    free(t);
    free(key);
    free(by_key);
    free(uf);
    free(used);
    free(canon);
    return ok ? 0 : 1;
}

/* ---- warmth ------------------------------------------------------------------ */

typedef struct warm_arg {
    const char *dist;
    vor_algorithm algo;
    size_t n;
    uint64_t seed;
    int runs;
    int varied; /* warm runs: a new input each run (1) or the same one (0) */
} warm_arg;

typedef struct warm_out {
    int status; /* vor_status, or -1 when the points could not be made */
    double ms;  /* cold: the one run; warm: the median of runs 2 .. runs+1 */
} warm_out;

/* One computation in a process that has done nothing else yet. */
static void cold_child(const void *arg, void *out) {
    const warm_arg *a = (const warm_arg *)arg;
    warm_out *w = (warm_out *)out;
    vor_sites *s = sites_for(a->dist, a->n, a->seed);
    vor_diagram *d = NULL;
    w->status = -1;
    w->ms = 0;
    if (!s)
        return;
    uint64_t t0 = bu_now_ns();
    w->status = vor_compute(s, a->algo, &d);
    w->ms = (double)(bu_now_ns() - t0) / 1e6;
    vor_diagram_free(d);
    vor_sites_free(s);
}

/* runs + 1 computations in one process, on one input or on runs + 1
 * inputs prepared beforehand; the first run is left out of the median. */
static void warm_child(const void *arg, void *out) {
    const warm_arg *a = (const warm_arg *)arg;
    warm_out *w = (warm_out *)out;
    int k = a->varied ? a->runs + 1 : 1;
    vor_sites **s = calloc((size_t)k, sizeof *s);
    double *ms = malloc(sizeof *ms * (size_t)(a->runs + 1));
    w->status = -1;
    w->ms = 0;
    for (int i = 0; s && i < k; i++)
        if (!(s[i] = sites_for(a->dist, a->n, a->seed + (uint64_t)i)))
            return;
    if (!s || !ms)
        return;
    w->status = VOR_OK;
    for (int r = 0; r <= a->runs && w->status == VOR_OK; r++) {
        vor_diagram *d = NULL;
        uint64_t t0 = bu_now_ns();
        w->status = vor_compute(s[a->varied ? r : 0], a->algo, &d);
        ms[r] = (double)(bu_now_ns() - t0) / 1e6;
        vor_diagram_free(d);
    }
    w->ms = bu_median(ms + 1, (size_t)a->runs);
    for (int i = 0; i < k; i++)
        vor_sites_free(s[i]);
    free(s);
    free(ms);
}

/* Cold, warm on the same input, warm on varied inputs: median ms of runs
 * each, for every n and algorithm; a table and --csv rows. */
static int cmd_warmth(const opts *o) {
    char abuf[512], nbuf[512];
    const char *an[MAX_LIST], *ns[MAX_LIST];
    size_t na = split(o->algos, abuf, sizeof abuf, an);
    size_t nn = split(o->ns, nbuf, sizeof nbuf, ns);
    static const char *const mode[3] = {"cold", "warm-same", "warm-varied"};
    const char *dist = o->dist ? o->dist : "uniform";
    int runs = o->runs > 0 ? o->runs : 3;
    FILE *csv = o->csv ? fopen(o->csv, "w") : NULL;
    if (o->csv && !csv) {
        perror(o->csv);
        return 2;
    }
    if (csv)
        fprintf(csv, "algorithm,distribution,n,mode,runs,median_ms,"
                     "ns_per_point,status\n");
    printf("%s, median of %d runs per mode; ns per input point\n", dist, runs);
    printf("%9s", "n");
    for (size_t ai = 0; ai < na; ai++)
        printf(" | %-29s", an[ai]);
    printf("\n%9s", "");
    for (size_t ai = 0; ai < na; ai++)
        printf(" | %9s %9s %9s", mode[0], "w-same", "w-varied");
    printf("\n");
    int bad = 0;
    for (size_t ni = 0; ni < nn; ni++) {
        size_t n = strtoull(ns[ni], NULL, 10);
        printf("%9zu", n);
        for (size_t ai = 0; ai < na; ai++) {
            vor_algorithm algo;
            if (vor_algorithm_parse(an[ai], &algo) != VOR_OK) {
                fprintf(stderr, "unknown algorithm %s\n", an[ai]);
                return 2;
            }
            printf(" |");
            for (int m = 0; m < 3; m++) {
                warm_arg a = {dist, algo, n, o->seed, runs, m == 2};
                warm_out w = {-1, 0};
                char msg[96] = "";
                double med = 0;
                int ok = 1;
                if (m == 0) { /* one process per run, a new seed each */
                    double *v = malloc(sizeof *v * (size_t)runs);
                    for (int r = 0; v && r < runs && ok; r++) {
                        a.seed = o->seed + (uint64_t)r;
                        ok = in_child(cold_child, &a, &w, sizeof w, o->limit_s,
                                      msg, sizeof msg) == 0 &&
                             w.status == VOR_OK;
                        if (ok)
                            v[r] = w.ms;
                    }
                    ok = ok && v;
                    if (ok)
                        med = bu_median(v, (size_t)runs);
                    free(v);
                } else {
                    ok = in_child(warm_child, &a, &w, sizeof w, o->limit_s,
                                  msg, sizeof msg) == 0 &&
                         w.status == VOR_OK;
                    med = w.ms;
                }
                if (ok)
                    printf(" %9.0f", med * 1e6 / (double)n);
                else
                    printf(" %9s", "failed");
                bad |= !ok;
                if (csv)
                    fprintf(csv, "%s,%s,%zu,%s,%d,%.6f,%.2f,%s\n", an[ai], dist,
                            n, mode[m], runs, ok ? med : 0.0,
                            ok ? med * 1e6 / (double)n : 0.0,
                            ok ? "ok" : msg[0] ? msg : "failed");
                fflush(stdout);
            }
        }
        printf("\n");
    }
    if (csv && fclose(csv) != 0) {
        perror(o->csv);
        return 2;
    }
    return bad;
}

/* Caps this process's address space (and so its children's) at
 * BENCH_MEM_LIMIT_GB GiB, 8 by default: an algorithm that runs away with
 * memory then fails one case with VOR_ENOMEM or a crash instead of driving
 * the machine into swap or the OOM killer. 0 disables the cap. */
static void limit_memory(void) {
    const char *env = getenv("BENCH_MEM_LIMIT_GB");
    double gb = env ? strtod(env, NULL) : 8.0;
    if (gb > 0) {
        struct rlimit rl;
        rl.rlim_cur = rl.rlim_max = (rlim_t)(gb * 1073741824.0);
        setrlimit(RLIMIT_AS, &rl);
    }
}

int main(int argc, char **argv) {
    opts o;
    limit_memory();
    if (argc < 2 || parse_opts(argc, argv, &o) != 0) {
        usage();
        return 2;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "table"))
        return cmd_table(&o);
    if (!strcmp(cmd, "points"))
        return cmd_points(&o, 0);
    if (!strcmp(cmd, "json"))
        return cmd_points(&o, 1);
    if (!strcmp(cmd, "shapes")) {
        for (size_t i = 0; i < sizeof bs_shapes / sizeof bs_shapes[0]; i++)
            puts(bs_shapes[i].name);
        return 0;
    }
    if (!strcmp(cmd, "ours"))
        return cmd_ours(&o);
    if (!strcmp(cmd, "check"))
        return cmd_check(&o);
    if (!strcmp(cmd, "warmth"))
        return cmd_warmth(&o);
    usage();
    return 2;
}
