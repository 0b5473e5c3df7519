/* harness.h -- what the integration tests share: starting and stopping a
 * real voronoid, HTTP requests through libcurl (one at a time or many at
 * once with the multi interface), raw sockets for requests no HTTP client
 * would send, and saving responses for the OpenAPI check.
 *
 * The daemon is the binary named by $VOR_DAEMON, started on 127.0.0.1
 * port 0 with its stderr (start-up line and access log) in a file of a
 * temporary directory; the port is read from the "listening on" line.
 * $VOR_TSAN=1 (ThreadSanitizer builds) asks the tests for smaller sizes.
 * Responses are saved as JSON files under $VOR_RESPONSES, or else
 * <directory of $VOR_DAEMON>/responses.
 *
 * Everything is static (each test binary includes this once); waits have
 * generous hang guards and no test asserts on elapsed time.
 */
#ifndef VOR_TESTS_INTEGRATION_HARNESS_H
#define VOR_TESTS_INTEGRATION_HARNESS_H

#include <arpa/inet.h>
#include <ctype.h>
#include <curl/curl.h>
#include <errno.h>
#include <fcntl.h>
#include <jansson.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define IT_UNUSED __attribute__((unused))

/* ---- the daemon ---------------------------------------------------------- */

typedef struct it_daemon {
    pid_t pid;
    int port;
    char dir[64];
    char log[128];
} it_daemon;

IT_UNUSED static int it_tsan(void) {
    const char *t = getenv("VOR_TSAN");
    return t != NULL && strcmp(t, "1") == 0;
}

IT_UNUSED static double it_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec / 1e9;
}

IT_UNUSED static void it_sleep(double s) {
    struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    nanosleep(&ts, NULL);
}

/* Reads a whole file into a new NUL-terminated buffer (NULL if absent). */
IT_UNUSED static char *it_read_file(const char *path, size_t *len) {
    FILE *f = fopen(path, "rb");
    if (f == NULL) return NULL;
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap);
    for (;;) {
        if (n + 4096 > cap) buf = realloc(buf, cap *= 2);
        size_t got = fread(buf + n, 1, 4096, f);
        n += got;
        if (got == 0) break;
    }
    fclose(f);
    buf[n] = '\0';
    if (len) *len = n;
    return buf;
}

/* Daemons still running when the test binary exits (a failed assertion
 * jumps past the cleanup) are killed, so none is left behind. */
static pid_t it__pids[16];

static void it__kill_leftovers(void) {
    for (int i = 0; i < 16; i++)
        if (it__pids[i] > 0) {
            kill(it__pids[i], SIGKILL);
            waitpid(it__pids[i], NULL, 0);
            it__pids[i] = 0;
        }
}

static void it__track(pid_t pid, int add) {
    static int registered;
    if (!registered) {
        atexit(it__kill_leftovers);
        registered = 1;
    }
    for (int i = 0; i < 16; i++) {
        if (add && it__pids[i] == 0) {
            it__pids[i] = pid;
            return;
        }
        if (!add && it__pids[i] == pid) {
            it__pids[i] = 0;
            return;
        }
    }
}

/* Starts $VOR_DAEMON --bind 127.0.0.1 --port 0 with the extra flags
 * (NULL-terminated, may be NULL), and --drain 0 unless they name a drain
 * period. Returns 0 once it is listening. */
IT_UNUSED static int it_start(it_daemon *d, const char *const *extra) {
    const char *bin = getenv("VOR_DAEMON");
    memset(d, 0, sizeof *d);
    if (bin == NULL || access(bin, X_OK) != 0) {
        fprintf(stderr, "VOR_DAEMON is not set to an executable\n");
        return -1;
    }
    strcpy(d->dir, "/tmp/voronoid-it-XXXXXX");
    if (mkdtemp(d->dir) == NULL) return -1;
    snprintf(d->log, sizeof d->log, "%s/daemon.log", d->dir);

    const char *argv[64];
    int argc = 0;
    argv[argc++] = bin;
    argv[argc++] = "--bind";
    argv[argc++] = "127.0.0.1";
    argv[argc++] = "--port";
    argv[argc++] = "0";
    int drain_given = 0;
    for (int i = 0; extra && extra[i] && argc < 60; i++) {
        argv[argc++] = extra[i];
        if (strncmp(extra[i], "--drain", 7) == 0) drain_given = 1;
    }
    if (!drain_given) { /* tests stop daemons often: no drain period */
        argv[argc++] = "--drain";
        argv[argc++] = "0";
    }
    argv[argc] = NULL;

    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        int fd = open(d->log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
            close(fd);
        }
        execv(bin, (char *const *)argv);
        _exit(127);
    }
    d->pid = pid;
    it__track(pid, 1);
    double until = it_now() + (it_tsan() ? 120 : 60);
    while (it_now() < until) {
        char *log = it_read_file(d->log, NULL);
        const char *p = log ? strstr(log, "listening on http://127.0.0.1:") : NULL;
        if (p != NULL) {
            d->port = atoi(p + strlen("listening on http://127.0.0.1:"));
            free(log);
            return d->port > 0 ? 0 : -1;
        }
        free(log);
        int status;
        if (waitpid(pid, &status, WNOHANG) == pid) {
            fprintf(stderr, "voronoid exited before listening\n");
            it__track(pid, 0);
            d->pid = 0;
            return -1;
        }
        it_sleep(0.02);
    }
    return -1;
}

/* Exit status of the daemon after signal sig (0 = none, just wait), or
 * -1 if it did not exit within the hang guard (it is then killed). */
IT_UNUSED static int it_stop(it_daemon *d, int sig) {
    if (d->pid <= 0) return -1;
    if (sig) kill(d->pid, sig);
    double until = it_now() + (it_tsan() ? 120 : 60);
    int status = 0;
    while (waitpid(d->pid, &status, WNOHANG) == 0) {
        if (it_now() > until) {
            kill(d->pid, SIGKILL);
            waitpid(d->pid, &status, 0);
            it__track(d->pid, 0);
            d->pid = 0;
            return -1;
        }
        it_sleep(0.01);
    }
    it__track(d->pid, 0);
    d->pid = 0;
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    return 128 + WTERMSIG(status);
}

/* Stops the daemon if running and removes its directory. On a failing
 * exit status the log is printed to help the reader. */
IT_UNUSED static int it_cleanup(it_daemon *d) {
    int rc = 0;
    if (d->pid > 0) rc = it_stop(d, SIGTERM);
    if (rc != 0) {
        char *log = it_read_file(d->log, NULL);
        if (log) {
            size_t n = strlen(log);
            fprintf(stderr, "---- daemon log (exit %d), last part:\n%s\n", rc,
                    n > 6000 ? log + n - 6000 : log);
            free(log);
        }
    }
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", d->dir);
    if (d->dir[0] && system(cmd) != 0) rc = rc ? rc : -1;
    return rc;
}

/* The group fixture of most test files: libcurl set up and one daemon
 * started with args (NULL-terminated, or NULL), which it_group_stop stops
 * with SIGTERM; the group fails unless the daemon exited 0. */
IT_UNUSED static int it_group_start(it_daemon *d, const char *const *args) {
    curl_global_init(CURL_GLOBAL_ALL);
    return it_start(d, args);
}

IT_UNUSED static int it_group_stop(it_daemon *d) {
    int rc = it_stop(d, SIGTERM);
    if (rc != 0) fprintf(stderr, "daemon exit status %d\n", rc);
    d->pid = 0;
    it_cleanup(d);
    curl_global_cleanup();
    return rc == 0 ? 0 : -1;
}

IT_UNUSED static char *it_log(const it_daemon *d) { return it_read_file(d->log, NULL); }

/* Whether the log comes to hold `text`: the daemon buffers access lines
 * for a few milliseconds, so a line may follow its answer a little later.
 * Waits up to a minute (a hang guard, not a timing requirement). */
IT_UNUSED static int it_log_has(const it_daemon *d, const char *text) {
    for (int i = 0; i < 6000; i++) {
        char *log = it_log(d);
        int found = log != NULL && strstr(log, text) != NULL;
        free(log);
        if (found) return 1;
        it_sleep(0.01);
    }
    return 0;
}

/* The line of the log that holds `text`, once it is there (waited for as
 * it_log_has does): a copy without its newline, to free; NULL if it never
 * came. */
IT_UNUSED static char *it_log_line(const it_daemon *d, const char *text) {
    for (int i = 0; i < 6000; i++) {
        char *log = it_log(d);
        const char *hit = log != NULL ? strstr(log, text) : NULL;
        if (hit != NULL) {
            const char *start = hit, *end = strchr(hit, '\n');
            while (start > log && start[-1] != '\n') start--;
            size_t len = end != NULL ? (size_t)(end - start) : strlen(start);
            char *line = malloc(len + 1);
            if (line != NULL) {
                memcpy(line, start, len);
                line[len] = '\0';
            }
            free(log);
            return line;
        }
        free(log);
        it_sleep(0.01);
    }
    return NULL;
}

/* ---- HTTP through libcurl ----------------------------------------------- */

typedef struct it_req {
    const char *method;        /* default: GET, or POST when body != NULL */
    const char *path;          /* with query string */
    const char *headers[12];   /* "Name: value", NULL-terminated */
    const void *body;
    size_t len;
    int gzip;                  /* send Accept-Encoding: gzip, decode */
    int chunked;               /* send the body chunked */
} it_req;

typedef struct it_resp {
    long status;
    char *body;
    size_t len;
    char *head;     /* raw header block(s) */
    size_t hlen;
    int curl_rc;
    char err[CURL_ERROR_SIZE];
} it_resp;

typedef struct it_grow {
    char **p;
    size_t *n;
    size_t cap;
} it_grow;

static size_t it__sink(char *data, size_t sz, size_t nm, void *ud) {
    it_grow *g = ud;
    size_t n = sz * nm;
    if (*g->n + n + 1 > g->cap) {
        size_t cap = g->cap ? g->cap : 4096;
        while (cap < *g->n + n + 1) cap *= 2;
        *g->p = realloc(*g->p, cap);
        g->cap = cap;
    }
    memcpy(*g->p + *g->n, data, n);
    *g->n += n;
    (*g->p)[*g->n] = '\0';
    return n;
}

typedef struct it_easy {
    CURL *h;
    struct curl_slist *hdrs;
    it_grow body, head;
    it_resp *resp;
    const char *up;   /* chunked upload: what is left to send */
    size_t up_left;
} it_easy;

/* Hands a chunked upload to libcurl in pieces of at most 16 KiB. */
static size_t it__source(char *buf, size_t sz, size_t nm, void *ud) {
    it_easy *e = ud;
    size_t n = sz * nm;
    if (n > 16384) n = 16384;
    if (n > e->up_left) n = e->up_left;
    memcpy(buf, e->up, n);
    e->up += n;
    e->up_left -= n;
    return n;
}

static void it__prepare(it_easy *e, const it_daemon *d, const it_req *q,
                        it_resp *r) {
    memset(r, 0, sizeof *r);
    memset(e, 0, sizeof *e);
    e->resp = r;
    e->h = curl_easy_init();
    char url[2048];
    snprintf(url, sizeof url, "http://127.0.0.1:%d%s", d->port, q->path);
    curl_easy_setopt(e->h, CURLOPT_URL, url);
    const char *method = q->method ? q->method : (q->body ? "POST" : "GET");
    if (strcmp(method, "HEAD") == 0) {
        curl_easy_setopt(e->h, CURLOPT_NOBODY, 1L);
    } else if (q->body != NULL || strcmp(method, "POST") == 0) {
        curl_easy_setopt(e->h, CURLOPT_POST, 1L);
        if (q->chunked) {
            e->up = q->body;
            e->up_left = q->len;
            curl_easy_setopt(e->h, CURLOPT_READFUNCTION, it__source);
            curl_easy_setopt(e->h, CURLOPT_READDATA, e);
        } else {
            curl_easy_setopt(e->h, CURLOPT_POSTFIELDS, q->body ? q->body : "");
            curl_easy_setopt(e->h, CURLOPT_POSTFIELDSIZE_LARGE,
                             (curl_off_t)q->len);
        }
        if (strcmp(method, "POST") != 0)
            curl_easy_setopt(e->h, CURLOPT_CUSTOMREQUEST, method);
    } else if (strcmp(method, "GET") != 0) {
        curl_easy_setopt(e->h, CURLOPT_CUSTOMREQUEST, method);
    }
    for (int i = 0; i < 12 && q->headers[i]; i++)
        e->hdrs = curl_slist_append(e->hdrs, q->headers[i]);
    if (q->chunked) e->hdrs = curl_slist_append(e->hdrs, "Transfer-Encoding: chunked");
    e->hdrs = curl_slist_append(e->hdrs, "Expect:");
    curl_easy_setopt(e->h, CURLOPT_HTTPHEADER, e->hdrs);
    if (q->gzip) curl_easy_setopt(e->h, CURLOPT_ACCEPT_ENCODING, "gzip");
    e->body.p = &r->body;
    e->body.n = &r->len;
    e->head.p = &r->head;
    e->head.n = &r->hlen;
    curl_easy_setopt(e->h, CURLOPT_WRITEFUNCTION, it__sink);
    curl_easy_setopt(e->h, CURLOPT_WRITEDATA, &e->body);
    curl_easy_setopt(e->h, CURLOPT_HEADERFUNCTION, it__sink);
    curl_easy_setopt(e->h, CURLOPT_HEADERDATA, &e->head);
    curl_easy_setopt(e->h, CURLOPT_ERRORBUFFER, r->err);
    curl_easy_setopt(e->h, CURLOPT_TIMEOUT, it_tsan() ? 300L : 120L);
    curl_easy_setopt(e->h, CURLOPT_NOSIGNAL, 1L);
}

static void it__finish(it_easy *e, CURLcode rc) {
    e->resp->curl_rc = (int)rc;
    curl_easy_getinfo(e->h, CURLINFO_RESPONSE_CODE, &e->resp->status);
    if (e->resp->body == NULL) {
        e->resp->body = calloc(1, 1);
    }
    if (e->resp->head == NULL) e->resp->head = calloc(1, 1);
    curl_slist_free_all(e->hdrs);
    curl_easy_cleanup(e->h);
}

/* One request. r must be freed with it_free. */
IT_UNUSED static void it_http(const it_daemon *d, const it_req *q, it_resp *r) {
    it_easy e;
    it__prepare(&e, d, q, r);
    CURLcode rc = curl_easy_perform(e.h);
    it__finish(&e, rc);
}

/* n requests at once, each on its own connection. */
IT_UNUSED static void it_parallel(const it_daemon *d, const it_req *q,
                                  it_resp *r, size_t n) {
    CURLM *m = curl_multi_init();
    it_easy *e = calloc(n, sizeof *e);
    curl_multi_setopt(m, CURLMOPT_MAX_TOTAL_CONNECTIONS, (long)n);
    for (size_t i = 0; i < n; i++) {
        it__prepare(&e[i], d, &q[i], &r[i]);
        curl_easy_setopt(e[i].h, CURLOPT_PRIVATE, &e[i]);
        curl_easy_setopt(e[i].h, CURLOPT_FRESH_CONNECT, 1L);
        curl_multi_add_handle(m, e[i].h);
    }
    int running = 1;
    while (running) {
        curl_multi_perform(m, &running);
        CURLMsg *msg;
        int left;
        while ((msg = curl_multi_info_read(m, &left)) != NULL) {
            if (msg->msg != CURLMSG_DONE) continue;
            it_easy *x;
            curl_easy_getinfo(msg->easy_handle, CURLINFO_PRIVATE, (char **)&x);
            curl_multi_remove_handle(m, x->h);
            it__finish(x, msg->data.result);
        }
        if (running) curl_multi_poll(m, NULL, 0, 100, NULL);
    }
    curl_multi_cleanup(m);
    free(e);
}

IT_UNUSED static void it_free(it_resp *r) {
    free(r->body);
    free(r->head);
    memset(r, 0, sizeof *r);
}

/* Value of the last response header `name` (case-insensitive) copied into
 * buf, or NULL. */
IT_UNUSED static const char *it_header(const it_resp *r, const char *name,
                                       char *buf, size_t size) {
    const char *found = NULL;
    size_t n = strlen(name);
    for (const char *p = r->head; p && *p;) {
        const char *eol = strstr(p, "\r\n");
        if (eol == NULL) break;
        if ((size_t)(eol - p) > n && strncasecmp(p, name, n) == 0 && p[n] == ':') {
            const char *v = p + n + 1;
            while (*v == ' ') v++;
            size_t k = (size_t)(eol - v);
            if (k >= size) k = size - 1;
            memcpy(buf, v, k);
            buf[k] = '\0';
            found = buf;
        }
        if (strncmp(p, "HTTP/", 5) == 0) found = NULL; /* a new block */
        p = eol + 2;
    }
    return found;
}

/* The body parsed as JSON (NULL and a message if it is not). */
IT_UNUSED static json_t *it_json(const it_resp *r) {
    json_error_t err;
    json_t *j = json_loadb(r->body, r->len, 0, &err);
    if (j == NULL)
        fprintf(stderr, "not JSON (%s): %.300s\n", err.text, r->body);
    return j;
}

/* ---- metrics --------------------------------------------------------------- */

/* Value of the sample line `series value` in a Prometheus text (the whole
 * line must start with series), or -1 when there is none. */
IT_UNUSED static double it_metric(const char *text, const char *series) {
    size_t n = strlen(series);
    for (const char *p = text; p && *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : NULL)
        if (strncmp(p, series, n) == 0 && p[n] == ' ') return atof(p + n + 1);
    return -1;
}

/* GET /metrics and one sample from it (-1 when absent or on failure). */
IT_UNUSED static double it_get_metric(const it_daemon *d, const char *series) {
    it_req q = {.path = "/metrics"};
    it_resp r;
    it_http(d, &q, &r);
    double v = r.status == 200 ? it_metric(r.body, series) : -1;
    it_free(&r);
    return v;
}

/* ---- slow requests --------------------------------------------------------- */

/* Body of a request for the diagram of n generated points whose answer is
 * only the timings (slow to compute, small to send). */
IT_UNUSED static void it_slow_body(char *buf, size_t size, size_t n) {
    snprintf(buf, size,
             "{\"generate\": {\"distribution\": \"uniform\", \"n\": %zu, "
             "\"seed\": 1}, \"format\": \"timings\"}", n);
}

/* Finds a number of points whose request keeps a worker busy for at least
 * min_s seconds on this machine and build (doubling from 25000, at most
 * max_n). This sizes the tests' slow requests; nothing is asserted on the
 * times themselves. */
IT_UNUSED static size_t it_calibrate(const it_daemon *d, double min_s,
                                     size_t max_n) {
    size_t n = 25000;
    for (;;) {
        char body[256];
        it_slow_body(body, sizeof body, n);
        it_req q = {.path = "/voronoi", .body = body, .len = strlen(body)};
        it_resp r;
        double t0 = it_now();
        it_http(d, &q, &r);
        double dt = it_now() - t0;
        long status = r.status;
        it_free(&r);
        if (status != 200 || dt >= min_s || n * 2 > max_n) {
            printf("slow requests: %zu points (%.3f s here)\n", n, dt);
            return n;
        }
        n *= dt < min_s / 4 ? 4 : 2;
        if (n > max_n) n = max_n;
    }
}

/* ---- saving responses for tests/openapi ---------------------------------- */

IT_UNUSED static const char *it_responses_dir(char *buf, size_t size) {
    const char *env = getenv("VOR_RESPONSES");
    if (env && *env) {
        snprintf(buf, size, "%s", env);
    } else {
        const char *bin = getenv("VOR_DAEMON");
        if (bin == NULL) return NULL;
        snprintf(buf, size, "%s", bin);
        char *slash = strrchr(buf, '/');
        if (slash) *slash = '\0';
        else snprintf(buf, size, ".");
        size_t k = strlen(buf);
        snprintf(buf + k, size - k, "/responses");
    }
    mkdir(buf, 0755);
    return buf;
}

/* Saves request line, status, headers and body as <dir>/<name>.json. */
IT_UNUSED static void it_save(const char *name, const it_req *q,
                              const it_resp *r) {
    char dir[1024], path[1200], hbuf[512];
    if (r->status == 0) return; /* no answer: nothing to hold to the contract */
    if (it_responses_dir(dir, sizeof dir) == NULL) return;
    json_t *o = json_object();
    const char *method = q->method ? q->method : (q->body ? "POST" : "GET");
    char p[1024];
    snprintf(p, sizeof p, "%s", q->path);
    char *qm = strchr(p, '?');
    if (qm) *qm = '\0';
    json_object_set_new(o, "method", json_string(method));
    json_object_set_new(o, "path", json_string(p));
    json_object_set_new(o, "status", json_integer(r->status));
    const char *ct = it_header(r, "Content-Type", hbuf, sizeof hbuf);
    json_object_set_new(o, "content_type", json_string(ct ? ct : ""));
    json_t *h = json_object();
    for (const char *s = r->head; s && *s;) {
        const char *eol = strstr(s, "\r\n");
        if (eol == NULL) break;
        const char *colon = memchr(s, ':', (size_t)(eol - s));
        if (colon && strncmp(s, "HTTP/", 5) != 0) {
            char key[128], val[512];
            size_t kn = (size_t)(colon - s);
            if (kn >= sizeof key) kn = sizeof key - 1;
            for (size_t i = 0; i < kn; i++) key[i] = (char)tolower((unsigned char)s[i]);
            key[kn] = '\0';
            const char *v = colon + 1;
            while (*v == ' ') v++;
            size_t vn = (size_t)(eol - v);
            if (vn >= sizeof val) vn = sizeof val - 1;
            memcpy(val, v, vn);
            val[vn] = '\0';
            json_object_set_new(h, key, json_string(val));
        }
        s = eol + 2;
    }
    json_object_set_new(o, "headers", h);
    json_t *body = json_stringn(r->body, r->len);
    if (body != NULL) {
        json_object_set_new(o, "body", body);
    } else {
        /* Not UTF-8 (binary): hex is enough for the check. */
        size_t n = r->len > 4096 ? 4096 : r->len;
        char *hex = malloc(2 * n + 1);
        for (size_t i = 0; i < n; i++)
            sprintf(hex + 2 * i, "%02x", (unsigned char)r->body[i]);
        hex[2 * n] = '\0';
        json_object_set_new(o, "body_hex", json_string(hex));
        free(hex);
    }
    snprintf(path, sizeof path, "%s/%s.json", dir, name);
    json_dump_file(o, path, JSON_INDENT(1));
    json_decref(o);
}

/* ---- raw sockets --------------------------------------------------------- */

IT_UNUSED static int it_connect(int port) {
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) return -1;
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_port = htons((uint16_t)port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

/* Case-insensitive strstr (ASCII). */
IT_UNUSED static const char *strcasestr_like(const char *hay, const char *needle) {
    size_t n = strlen(needle);
    for (; *hay; hay++)
        if (strncasecmp(hay, needle, n) == 0) return hay;
    return NULL;
}

IT_UNUSED static int it_send_all(int fd, const void *data, size_t n) {
    const char *p = data;
    while (n > 0) {
        ssize_t w = send(fd, p, n, MSG_NOSIGNAL);
        if (w <= 0) return -1;
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

/* Reads until the peer closes, `timeout_s` passes without data, or cap
 * bytes arrived. Returns bytes read; *closed tells whether the peer closed
 * (or reset) the connection. */
IT_UNUSED static size_t it_recv_until(int fd, char *buf, size_t cap,
                                      double timeout_s, int *closed) {
    size_t n = 0;
    if (closed) *closed = 0;
    while (n + 1 < cap) {
        struct pollfd p = {fd, POLLIN, 0};
        int rc = poll(&p, 1, (int)(timeout_s * 1000));
        if (rc <= 0) break;
        ssize_t got = recv(fd, buf + n, cap - 1 - n, 0);
        if (got <= 0) {
            if (closed) *closed = 1;
            break;
        }
        n += (size_t)got;
    }
    buf[n] = '\0';
    return n;
}

/* Reads one HTTP response: until its headers and Content-Length bytes of
 * body are in, the peer closes, or timeout_s passes without data. Returns
 * bytes read; *closed as for it_recv_until. */
IT_UNUSED static size_t it_recv_response(int fd, char *buf, size_t cap,
                                         double timeout_s, int *closed) {
    size_t n = 0;
    if (closed) *closed = 0;
    while (n + 1 < cap) {
        buf[n] = '\0';
        const char *end = strstr(buf, "\r\n\r\n");
        if (end != NULL) {
            const char *cl = strcasestr_like(buf, "\r\nContent-Length:");
            size_t want = cl ? (size_t)atol(cl + 17) : 0;
            if (n >= (size_t)(end + 4 - buf) + want) break;
        }
        struct pollfd p = {fd, POLLIN, 0};
        int rc = poll(&p, 1, (int)(timeout_s * 1000));
        if (rc <= 0) break;
        ssize_t got = recv(fd, buf + n, cap - 1 - n, 0);
        if (got <= 0) {
            if (closed) *closed = 1;
            break;
        }
        n += (size_t)got;
    }
    buf[n] = '\0';
    return n;
}

/* Status code of the first HTTP response in buf, 0 if none. */
IT_UNUSED static int it_raw_status(const char *buf) {
    if (strncmp(buf, "HTTP/1.", 7) != 0) return 0;
    return atoi(buf + 9);
}

#endif /* VOR_TESTS_INTEGRATION_HARNESS_H */
