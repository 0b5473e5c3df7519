/* voronoi.c -- the command line: Voronoi diagrams of files and pipes with
 * the service's own codec, no server needed.
 *
 * Everything about points and results goes through api/ (the same parser,
 * options, computation and writers as POST /voronoi and /compare); this file
 * only reads the input, maps flags to api_request_option and reports
 * problems as "voronoi: FILE: line N: ..." on stderr. Exit status: 0 done,
 * 1 the input or the computation failed, 2 the command line is wrong. The
 * whole input is read into memory (the parser needs it in one piece).
 */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "../api/api.h"

static const char usage_text[] =
    "usage: voronoi [options] [FILE | -]\n"
    "\n"
    "Computes the Voronoi diagram of the points in FILE (or standard input)\n"
    "and writes it to standard output.\n"
    "\n"
    "Input:\n"
    "  FILE                 points as JSON ({\"points\": [[x,y],...], ...} or a\n"
    "                       bare [[x,y],...]), text (one \"x,y\" or \"x y\" per\n"
    "                       line; '#' comments, blank lines and a header line\n"
    "                       are skipped) or binary (little-endian float64 x,y\n"
    "                       pairs). The kind comes from --input, else from the\n"
    "                       extension (.json; .csv .txt .tsv; .bin), else it is\n"
    "                       guessed: JSON if it starts with '{' or '[', text\n"
    "                       otherwise. '-' or no FILE reads standard input.\n"
    "  -i, --input KIND     json, csv (or text), binary\n"
    "  -g, --generate DIST:N[:SEED]\n"
    "                       generate N points instead of reading any; SEED\n"
    "                       (default 1) makes the set reproducible. DIST is\n"
    "                         uniform    the unit square\n"
    "                         gaussian   standard normal x and y\n"
    "                         pixels     integer pixels of an 800x600 window,\n"
    "                                    with duplicates (alias: random)\n"
    "                         grid       ceil(sqrt N) square of integers\n"
    "                         circle     N points on the unit circle\n"
    "                         clustered  gaussian clusters in the unit square\n"
    "                         lognormal  exp(2 N(0,1)) in x and y (heavy tails)\n"
    "                         outlier    N-1 points in a 0.1 x 0.1 square\n"
    "                                    around (8.5, 47.3), one at (0, 0)\n"
    "                         decades    |x|, |y| log-uniform in [1e-6, 1e6],\n"
    "                                    random signs (twelve decades)\n"
    "\n"
    "Computation:\n"
    "  -a, --algorithm NAME fortune (default), bowyer-watson or flip\n"
    "  -b, --bounds XMIN,YMIN,XMAX,YMAX\n"
    "                       clip the diagram to this box (adds \"clipped\" to\n"
    "                       the JSON unless --include says otherwise)\n"
    "  -c, --compare        run all three algorithms and write a JSON table of\n"
    "                       their timings and operation counts, and whether\n"
    "                       their diagrams are identical (\"agree\")\n"
    "  -r, --repeat N       with --compare: run each algorithm N times (1 to\n"
    "                       50) in rotating order on the same sites and give\n"
    "                       the median, min and max of every phase; default 5\n"
    "                       up to 20,000 sites, 3 up to 200,000, else 1\n"
    "      --trace          add the algorithm's steps to the JSON result\n"
    "                       (\"trace\": {\"steps\": [...]}; at most 2000 points)\n"
    "\n"
    "Output:\n"
    "  -f, --format FMT     json (default), geojson (cells as polygons, clipped\n"
    "                       to the bounds or to the sites' bounding box grown\n"
    "                       by 10%), svg (a picture), binary (little-endian\n"
    "                       arrays, layout in openapi.yaml), timings (only\n"
    "                       the timings in milliseconds, labelled with the\n"
    "                       algorithm, n_input and n_sites)\n"
    "      --include PARTS  comma-separated parts of the JSON result: vertices,\n"
    "                       edges, cells (the default three), triangles, sites,\n"
    "                       clipped, counts (the algorithm's operation counts;\n"
    "                       also with --format timings)\n"
    "  -h, --help           show this text\n"
    "\n"
    "Indices in the output are input indices (positions in the input; a\n"
    "repeated point is represented by its first occurrence).\n"
    "\n"
    "Exit status: 0 success, 1 invalid input or failed computation (the\n"
    "message names the line or the JSON pointer of the offending value),\n"
    "2 invalid command line.\n"
    "\n"
    "Examples:\n"
    "  voronoi points.csv > diagram.json\n"
    "  voronoi --generate uniform:100000:7 --format timings\n"
    "  voronoi --compare --generate lognormal:100000\n"
    "  voronoi --bounds 0,0,800,600 --format svg points.txt > picture.svg\n"
    "  voronoi --compare --repeat 9 --generate gaussian:50000\n"
    "  curl -s example.org/points.json | voronoi --compare -\n";

static void usage_error(const char *fmt, const char *arg) {
    fputs("voronoi: ", stderr);
    fprintf(stderr, fmt, arg);
    fputs("\ntry 'voronoi --help'\n", stderr);
    exit(2);
}

/* Reads all of f into a new buffer; NULL on error (errno set). */
static char *read_all(FILE *f, size_t *len) {
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    if (buf == NULL) return NULL;
    for (;;) {
        if (n == cap) {
            char *b = cap < SIZE_MAX / 2 ? realloc(buf, cap * 2) : NULL;
            if (b == NULL) {
                free(buf);
                errno = ENOMEM;
                return NULL;
            }
            buf = b;
            cap *= 2;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0) {
            if (ferror(f)) {
                int e = errno;
                free(buf);
                errno = e ? e : EIO;
                return NULL;
            }
            break;
        }
    }
    *len = n;
    return buf;
}

/* Input kind from a name given to --input. */
static int input_from_name(const char *s, api_input *out) {
    if (strcmp(s, "json") == 0) *out = API_IN_JSON;
    else if (strcmp(s, "csv") == 0 || strcmp(s, "text") == 0 || strcmp(s, "txt") == 0)
        *out = API_IN_TEXT;
    else if (strcmp(s, "binary") == 0 || strcmp(s, "bin") == 0) *out = API_IN_BINARY;
    else return -1;
    return 0;
}

static api_input input_from_extension(const char *path) {
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    if (dot == NULL || (slash && dot < slash)) return API_IN_AUTO;
    if (strcasecmp(dot, ".json") == 0) return API_IN_JSON;
    if (strcasecmp(dot, ".csv") == 0 || strcasecmp(dot, ".txt") == 0 ||
        strcasecmp(dot, ".tsv") == 0) {
        return API_IN_TEXT;
    }
    if (strcasecmp(dot, ".bin") == 0) return API_IN_BINARY;
    return API_IN_AUTO;
}

/* Reports a problem about the input (exit 1). */
static void fail(const char *source, const api_problem *p) {
    fprintf(stderr, "voronoi: %s: %s", source, p->detail);
    if (p->pointer[0]) fprintf(stderr, " (at %s)", p->pointer);
    fprintf(stderr, " [%d %s]\n", api_code_http(p->code), api_code_slug(p->code));
    exit(1);
}

/* Parses "DIST:N[:SEED]" for --generate. */
static void parse_generate(const char *arg, char *dist, size_t dist_size,
                           size_t *n, uint64_t *seed) {
    const char *c1 = strchr(arg, ':');
    if (c1 == NULL || (size_t)(c1 - arg) >= dist_size || c1 == arg) {
        usage_error("--generate wants DIST:N[:SEED], got \"%s\"", arg);
    }
    memcpy(dist, arg, (size_t)(c1 - arg));
    dist[c1 - arg] = 0;
    char *end;
    errno = 0;
    double dn = strtod(c1 + 1, &end);
    if (end == c1 + 1 || (*end != 0 && *end != ':') || errno || dn < 0 ||
        dn != (double)(size_t)dn) {
        usage_error("--generate: N must be a non-negative integer, got \"%s\"", arg);
    }
    *n = (size_t)dn;
    *seed = 1;
    if (*end == ':') {
        const char *s = end + 1;
        errno = 0;
        unsigned long long v = strtoull(s, &end, 10);
        if (end == s || *end != 0 || errno || *s == '-') {
            usage_error("--generate: SEED must be a non-negative integer, got \"%s\"",
                        arg);
        }
        *seed = (uint64_t)v;
    }
}

static void write_out(const api_buf *b) {
    if (b->len > 0 && fwrite(b->data, 1, b->len, stdout) != b->len) {
        fprintf(stderr, "voronoi: writing the output: %s\n", strerror(errno));
        exit(1);
    }
    if (fflush(stdout) != 0) {
        fprintf(stderr, "voronoi: writing the output: %s\n", strerror(errno));
        exit(1);
    }
}

int main(int argc, char **argv) {
    static const struct option longopts[] = {
        {"algorithm", required_argument, NULL, 'a'},
        {"bounds", required_argument, NULL, 'b'},
        {"compare", no_argument, NULL, 'c'},
        {"format", required_argument, NULL, 'f'},
        {"generate", required_argument, NULL, 'g'},
        {"help", no_argument, NULL, 'h'},
        {"include", required_argument, NULL, 'I'},
        {"input", required_argument, NULL, 'i'},
        {"repeat", required_argument, NULL, 'r'},
        {"trace", no_argument, NULL, 'T'},
        {NULL, 0, NULL, 0},
    };
    api_request r;
    api_problem p;
    api_request_init(&r);
    /* Option flags are checked at once (on r, so a usage error exits 2)
     * and applied again after the body is parsed, so that the command line
     * wins over options found in a JSON body. */
    struct {
        const char *key, *value;
    } given[16];
    int n_given = 0;
    int compare = 0, have_input_kind = 0, repeat_given = 0;
    api_input kind = API_IN_AUTO;
    const char *generate = NULL;
    int opt;
    opterr = 0;
    while ((opt = getopt_long(argc, argv, ":a:b:cf:g:hi:r:", longopts, NULL)) != -1) {
        const char *key = NULL, *value = optarg;
        switch (opt) {
        case 'a': key = "algorithm"; break;
        case 'b': key = "bounds"; break;
        case 'f': key = "format"; break;
        case 'I': key = "include"; break;
        case 'r': key = "repeat"; repeat_given = 1; break;
        case 'T': key = "trace"; value = "true"; break;
        case 'c': compare = 1; break;
        case 'g': generate = optarg; break;
        case 'i':
            if (input_from_name(optarg, &kind) != 0) {
                usage_error("--input must be json, csv or binary, got \"%s\"", optarg);
            }
            have_input_kind = 1;
            break;
        case 'h': fputs(usage_text, stdout); return 0;
        case ':': usage_error("option %s needs a value", argv[optind - 1]); break;
        default: usage_error("unknown option %s", argv[optind - 1]); break;
        }
        if (key) {
            if (api_request_option(&r, key, value, &p) != API_OK) {
                usage_error("%s", p.detail);
            }
            if (n_given == (int)(sizeof given / sizeof given[0])) {
                usage_error("%s", "too many options");
            }
            given[n_given].key = key;
            given[n_given++].value = value;
        }
    }
    if (argc - optind > 1) usage_error("one input at most, got also \"%s\"", argv[optind + 1]);
    const char *path = optind < argc ? argv[optind] : NULL;
    if (generate && path) usage_error("--generate and an input file (%s) exclude each other", path);

    const char *source = "standard input";
    api_timings t = {0};
    if (generate) {
        char dist[64];
        size_t n;
        uint64_t seed;
        parse_generate(generate, dist, sizeof dist, &n, &seed);
        source = "--generate";
        double t0 = api_clock_ms();
        api_code c = api_generate(dist, n, seed, &r.xy, &p);
        if (c == API_INVALID) usage_error("--generate: %s", p.detail);
        if (c != API_OK) fail(source, &p);
        r.n = n;
        r.generated = 1;
        t.parse_ms = api_clock_ms() - t0;
    } else {
        FILE *f = stdin;
        if (path && strcmp(path, "-") != 0) {
            source = path;
            f = fopen(path, "rb");
            if (f == NULL) {
                fprintf(stderr, "voronoi: %s: %s\n", path, strerror(errno));
                return 1;
            }
            if (!have_input_kind) kind = input_from_extension(path);
        }
        size_t len;
        char *body = read_all(f, &len);
        if (body == NULL) {
            fprintf(stderr, "voronoi: %s: %s\n", source, strerror(errno));
            return 1;
        }
        if (f != stdin) fclose(f);
        double t0 = api_clock_ms();
        api_code c = api_parse_body(&r, kind, body, len, NULL, &p);
        t.parse_ms = api_clock_ms() - t0;
        free(body);
        if (c != API_OK) fail(source, &p);
        for (int i = 0; i < n_given; i++) {
            api_request_option(&r, given[i].key, given[i].value, &p);
        }
    }
    if (compare && r.format != API_FMT_JSON) {
        usage_error("%s", "--compare writes JSON; the format does not apply");
    }
    if (!compare && repeat_given) {
        usage_error("%s", "--repeat applies to --compare only");
    }

    api_buf out;
    api_buf_init(&out);
    if (compare) {
        api_compare cmp;
        api_compare_init(&cmp);
        cmp.t.parse_ms = t.parse_ms;
        if (api_compare_run(&r, &cmp, &p) != API_OK) fail(source, &p);
        if (api_write_compare(&r, &cmp, &out, &p) != API_OK) fail(source, &p);
        api_compare_clear(&cmp);
    } else {
        api_result res;
        api_result_init(&res);
        res.t.parse_ms = t.parse_ms;
        if (api_compute(&r, &res, &p) != API_OK) fail(source, &p);
        if (api_write_result(&r, &res, &res.t, &out, &p) != API_OK) fail(source, &p);
        api_result_clear(&res);
    }
    write_out(&out);
    api_buf_clear(&out);
    api_request_clear(&r);
    return 0;
}
