/* config.c -- parsing and validating voronoid's settings.
 *
 * One table lists every setting: flag, environment variable, kind of value,
 * bounds, help text and where it lands in srv_config. Parsing is two passes
 * over that table: the environment first, then argv, so a flag overrides a
 * variable. Each value is checked against its kind and bounds as it is read;
 * the first bad one stops parsing with a message that names it. The cost is
 * O(argc * settings), nothing is allocated, nothing is printed.
 */
#include "config.h"

#include <arpa/inet.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef enum opt_kind {
    OPT_ADDR,    /* numeric IPv4 / IPv6 address -> char[64] */
    OPT_INT,     /* decimal integer in [min, max] -> int */
    OPT_UINT,    /* decimal integer in [min, max] -> unsigned */
    OPT_SIZE,    /* integer with optional K, M, G suffix (powers of 1024) */
    OPT_COUNT,   /* integer in [min, max] -> size_t */
    OPT_SECONDS, /* decimal number of seconds in [min, max] -> double */
    OPT_DIR      /* an existing directory -> char[4096] */
} opt_kind;

typedef struct opt_def {
    const char *flag; /* without the leading "--" */
    const char *env;
    opt_kind kind;
    double min, max;
    size_t offset;
    const char *arg;  /* placeholder in the help text */
    const char *help;
} opt_def;

#define OFF(field) offsetof(srv_config, field)

static const opt_def opts[] = {
    {"bind", "VORONOID_BIND", OPT_ADDR, 0, 0, OFF(bind), "ADDR",
     "address to listen on, IPv4 or IPv6 (default 127.0.0.1)"},
    {"port", "VORONOID_PORT", OPT_INT, 0, 65535, OFF(port), "N",
     "TCP port, 0 = any free port (default 8080)"},
    {"workers", "VORONOID_WORKERS", OPT_INT, 1, 256, OFF(workers), "N",
     "compute threads (default: number of CPUs)"},
    {"queue", "VORONOID_QUEUE", OPT_INT, 1, 100000, OFF(queue), "N",
     "requests waiting for a worker before 503 (default 64)"},
    {"inline-points", "VORONOID_INLINE_POINTS", OPT_COUNT, 0, 100000,
     OFF(inline_points), "N", "requests of at most N points are computed on "
     "the connection's thread, without the queue; 0 = never (default 128)"},
    {"max-body", "VORONOID_MAX_BODY", OPT_SIZE, 1024, 4.0 * 1024 * 1024 * 1024,
     OFF(max_body), "BYTES", "largest request body, K/M/G suffix allowed "
     "(default 64M)"},
    {"max-points", "VORONOID_MAX_POINTS", OPT_COUNT, 1, 1073741824.0,
     OFF(max_points), "N", "most points in one request (default 1000000)"},
    {"timeout", "VORONOID_TIMEOUT", OPT_SECONDS, 0.001, 86400, OFF(timeout),
     "SECONDS", "deadline from a complete request to its answer, else 504 "
     "(default 60)"},
    {"grace", "VORONOID_GRACE", OPT_SECONDS, 0, 3600, OFF(grace), "SECONDS",
     "on SIGTERM/SIGINT, time to finish in-flight requests (default 10)"},
    {"http-threads", "VORONOID_HTTP_THREADS", OPT_INT, 1, 64,
     OFF(http_threads), "N",
     "connection-handling threads (default: number of CPUs)"},
    {"connection-timeout", "VORONOID_CONNECTION_TIMEOUT", OPT_UINT, 1, 3600,
     OFF(connection_timeout), "SECONDS",
     "close a connection idle or stalled this long (default 30)"},
    {"max-connections", "VORONOID_MAX_CONNECTIONS", OPT_UINT, 1, 100000,
     OFF(max_connections), "N", "open connections at most (default 1024)"},
    {"max-connections-per-ip", "VORONOID_MAX_CONNECTIONS_PER_IP", OPT_UINT,
     0, 100000, OFF(max_connections_per_ip), "N",
     "open connections from one client address at most; 0 = no limit "
     "(default 128)"},
    {"header-timeout", "VORONOID_HEADER_TIMEOUT", OPT_SECONDS, 0.1, 3600,
     OFF(header_timeout), "SECONDS", "time a client has to send a request's "
     "line and headers, else 408 and close (default 10)"},
    {"min-upload-rate", "VORONOID_MIN_UPLOAD_RATE", OPT_SIZE, 0,
     1024.0 * 1024 * 1024, OFF(min_upload_rate), "BYTES", "bytes per second "
     "a body must average once --header-timeout has passed since its "
     "headers, else 408 and close; 0 = no minimum (default 1K)"},
    {"send-timeout", "VORONOID_SEND_TIMEOUT", OPT_SECONDS, 1, 3600,
     OFF(send_timeout), "SECONDS", "drop a connection whose client reads "
     "nothing of its answer this long, freeing the answer (default 10)"},
    {"drain", "VORONOID_DRAIN", OPT_SECONDS, 0, 3600, OFF(drain), "SECONDS",
     "on SIGTERM/SIGINT, keep accepting (with Connection: close) this long "
     "while /readyz says 503, then stop listening (default 5)"},
    {"answer-memory", "VORONOID_ANSWER_MEMORY", OPT_SIZE, 16.0 * 1024 * 1024,
     1024.0 * 1024 * 1024 * 1024, OFF(answer_memory), "BYTES",
     "memory for requests being computed and answers being sent, across "
     "all connections; past it, large requests get 503 (default: a "
     "quarter of the machine's memory, at most 1G)"},
    {"web-dir", "VORONOID_WEB_DIR", OPT_DIR, 0, 0, OFF(web_dir), "DIR",
     "serve the page from this directory instead of the built-in copy"},
};

#define N_OPTS (sizeof opts / sizeof opts[0])

size_t srv_config_answer_memory_for(unsigned long long ram) {
    const unsigned long long lo = 64ull << 20, hi = 1ull << 30;
    unsigned long long v = ram / 4;
    if (ram == 0 || v > hi) v = hi;
    if (v < lo) v = lo;
    return (size_t)v;
}

static unsigned long long machine_memory(void) {
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || size <= 0) return 0;
    return (unsigned long long)pages * (unsigned long long)size;
}

void srv_config_defaults(srv_config *out, int cpus) {
    if (cpus < 1) cpus = 1;
    if (cpus > 64) cpus = 64;
    memset(out, 0, sizeof *out);
    strcpy(out->bind, "127.0.0.1");
    out->port = 8080;
    out->http_threads = cpus;
    out->workers = cpus;
    out->queue = 64;
    out->inline_points = 128;
    out->max_body = (size_t)64 << 20;
    out->max_points = 1000000;
    out->timeout = 60;
    out->grace = 10;
    out->connection_timeout = 30;
    out->max_connections = 1024;
    out->max_connections_per_ip = 128;
    out->header_timeout = 10;
    out->min_upload_rate = 1024;
    out->send_timeout = 10;
    out->drain = 5;
    out->answer_memory = srv_config_answer_memory_for(machine_memory());
}

static void errf(char *err, size_t size, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static void errf(char *err, size_t size, const char *fmt, ...) {
    va_list ap;
    if (err == NULL || size == 0) return;
    va_start(ap, fmt);
    vsnprintf(err, size, fmt, ap);
    va_end(ap);
}

/* Parses a whole decimal integer (no sign for unsigned use, no spaces).
 * 0 on success. */
static int parse_integer(const char *s, long long *out) {
    char *end;
    if (*s == '\0' || *s == ' ' || *s == '\t' || *s == '+') return -1;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (errno != 0 || *end != '\0') return -1;
    *out = v;
    return 0;
}

/* A size as the help shows it: 0, 1K, 64M, 4G, 1024G. */
static const char *size_text(char *buf, size_t size, double v) {
    static const char units[] = "GMK";
    for (int i = 0; i < 3; i++) {
        double unit = (double)(1ull << (10 * (3 - i)));
        if (v >= unit && fmod(v, unit) == 0) {
            snprintf(buf, size, "%.0f%c", v / unit, units[i]);
            return buf;
        }
    }
    snprintf(buf, size, "%.0f", v);
    return buf;
}

/* Applies one value of setting o from source (a flag "--x" or a variable
 * name, for the message). 0 on success, -1 with err set. */
static int apply(const opt_def *o, const char *source, const char *value,
                 srv_config *c, char *err, size_t err_size) {
    char *field = (char *)c + o->offset;
    long long iv;
    switch (o->kind) {
    case OPT_ADDR: {
        unsigned char tmp[16];
        if (strlen(value) >= 64 || (inet_pton(AF_INET, value, tmp) != 1 &&
                                    inet_pton(AF_INET6, value, tmp) != 1)) {
            errf(err, err_size, "invalid value for %s: '%s' (expected a "
                 "numeric IPv4 or IPv6 address such as 127.0.0.1 or ::1)",
                 source, value);
            return -1;
        }
        strcpy(field, value);
        return 0;
    }
    case OPT_INT:
    case OPT_UINT:
    case OPT_COUNT:
        if (parse_integer(value, &iv) != 0 || (double)iv < o->min ||
            (double)iv > o->max) {
            errf(err, err_size, "invalid value for %s: '%s' (expected an "
                 "integer from %.0f to %.0f)", source, value, o->min, o->max);
            return -1;
        }
        if (o->kind == OPT_INT) *(int *)field = (int)iv;
        else if (o->kind == OPT_UINT) *(unsigned *)field = (unsigned)iv;
        else *(size_t *)field = (size_t)iv;
        return 0;
    case OPT_SIZE: {
        char num[32];
        size_t len = strlen(value);
        unsigned shift = 0;
        if (len > 0 && len < sizeof num) {
            memcpy(num, value, len + 1);
            switch (num[len - 1]) {
            case 'k': case 'K': shift = 10; break;
            case 'm': case 'M': shift = 20; break;
            case 'g': case 'G': shift = 30; break;
            default: break;
            }
            if (shift) num[len - 1] = '\0';
        }
        if (len == 0 || len >= sizeof num || parse_integer(num, &iv) != 0 ||
            iv < 0 || iv > (LLONG_MAX >> 30) ||
            (double)(iv << shift) < o->min ||
            (double)(iv << shift) > o->max) {
            char lo[16], hi[16];
            errf(err, err_size, "invalid value for %s: '%s' (expected a size "
                 "in bytes from %s to %s, with an optional K, M or G suffix)",
                 source, value, size_text(lo, sizeof lo, o->min),
                 size_text(hi, sizeof hi, o->max));
            return -1;
        }
        *(size_t *)field = (size_t)(iv << shift);
        return 0;
    }
    case OPT_SECONDS: {
        char *end;
        double v;
        errno = 0;
        v = (*value == '\0' || *value == ' ') ? NAN : strtod(value, &end);
        if (isnan(v) || errno != 0 || *end != '\0' || v < o->min ||
            v > o->max) {
            errf(err, err_size, "invalid value for %s: '%s' (expected a "
                 "number of seconds from %g to %g)", source, value, o->min,
                 o->max);
            return -1;
        }
        *(double *)field = v;
        return 0;
    }
    case OPT_DIR: {
        struct stat st;
        if (*value == '\0' || strlen(value) >= 4096 ||
            stat(value, &st) != 0 || !S_ISDIR(st.st_mode)) {
            errf(err, err_size, "invalid value for %s: '%s' (expected an "
                 "existing directory)", source, value);
            return -1;
        }
        strcpy(field, value);
        return 0;
    }
    }
    return -1;
}

static const opt_def *find_flag(const char *name, size_t len) {
    for (size_t i = 0; i < N_OPTS; i++)
        if (strlen(opts[i].flag) == len && memcmp(opts[i].flag, name, len) == 0)
            return &opts[i];
    return NULL;
}

srv_config_result srv_config_parse(int argc, char *const *argv,
                                   srv_getenv_fn env, int cpus,
                                   srv_config *out, char *err,
                                   size_t err_size) {
    srv_config_defaults(out, cpus);
    if (err != NULL && err_size > 0) err[0] = '\0';

    if (env != NULL) {
        for (size_t i = 0; i < N_OPTS; i++) {
            const char *v = env(opts[i].env);
            if (v != NULL && apply(&opts[i], opts[i].env, v, out, err,
                                   err_size) != 0)
                return SRV_CONFIG_ERROR;
        }
    }

    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
            return SRV_CONFIG_HELP;
        if (strncmp(a, "--", 2) != 0 || a[2] == '\0') {
            errf(err, err_size, "unexpected argument '%s' (flags start with "
                 "--; see --help)", a);
            return SRV_CONFIG_ERROR;
        }
        const char *name = a + 2;
        const char *eq = strchr(name, '=');
        size_t name_len = eq ? (size_t)(eq - name) : strlen(name);
        const opt_def *o = find_flag(name, name_len);
        if (o == NULL) {
            errf(err, err_size, "unknown flag '--%.*s' (see --help)",
                 (int)(name_len > 64 ? 64 : name_len), name);
            return SRV_CONFIG_ERROR;
        }
        char source[48];
        snprintf(source, sizeof source, "--%s", o->flag);
        const char *value;
        if (eq != NULL) {
            value = eq + 1;
        } else if (i + 1 < argc) {
            value = argv[++i];
        } else {
            errf(err, err_size, "missing value for %s (expected %s)", source,
                 o->arg);
            return SRV_CONFIG_ERROR;
        }
        if (apply(o, source, value, out, err, err_size) != 0)
            return SRV_CONFIG_ERROR;
    }
    return SRV_CONFIG_OK;
}

void srv_config_usage(FILE *f) {
    fputs("usage: voronoid [--flag VALUE]...\n"
          "\n"
          "The voronoid HTTP service: Voronoi diagrams and Delaunay "
          "triangulations\nwith Fortune's sweep, Bowyer-Watson and Lawson "
          "flipping.\n"
          "Each flag can also be set by the environment variable shown; a "
          "flag wins.\n\n", f);
    for (size_t i = 0; i < N_OPTS; i++) {
        char left[64];
        snprintf(left, sizeof left, "--%s %s", opts[i].flag, opts[i].arg);
        fprintf(f, "  %-30s %s\n  %-30s   [%s]\n", left, opts[i].help, "",
                opts[i].env);
    }
    fputs("  --help                         this text\n"
          "\n"
          "Endpoints: POST /voronoi, POST /compare, GET / (the page),\n"
          "GET /openapi.yaml, GET /healthz, GET /readyz, GET /metrics.\n"
          "SIGTERM or SIGINT: /readyz turns 503; keep accepting for "
          "--drain seconds\n(answers say Connection: close), stop listening, "
          "finish in-flight requests\nwithin --grace seconds, exit 0. A "
          "second signal cuts both short.\n", f);
}

void srv_config_print(const srv_config *c, FILE *f) {
    fprintf(f,
            "voronoid: config bind=%s port=%d http-threads=%d workers=%d "
            "queue=%d inline-points=%zu max-body=%zu max-points=%zu "
            "timeout=%gs grace=%gs connection-timeout=%us "
            "max-connections=%u max-connections-per-ip=%u "
            "header-timeout=%gs min-upload-rate=%zu send-timeout=%gs "
            "drain=%gs answer-memory=%zu web-dir=%s\n",
            c->bind, c->port, c->http_threads, c->workers, c->queue,
            c->inline_points, c->max_body, c->max_points, c->timeout, c->grace,
            c->connection_timeout, c->max_connections,
            c->max_connections_per_ip, c->header_timeout, c->min_upload_rate,
            c->send_timeout, c->drain, c->answer_memory,
            c->web_dir[0] ? c->web_dir : "(built in)");
}
