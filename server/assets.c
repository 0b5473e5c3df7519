/* assets.c -- lookup of the page's files and openapi.yaml.
 *
 * Representation: an array parallel to srv_embedded_assets holding each
 * file's gzip copy (level 9, kept only when it saves at least 10%) and its
 * ETag (64-bit FNV-1a of the content), made once in srv_assets_new. Lookup
 * is a linear scan of a handful of names. In --web-dir mode a page file is
 * read from disk per request: only paths made of [A-Za-z0-9._-] segments
 * that do not start with '.' are looked up, so nothing outside the
 * directory can be named.
 */
#include "assets.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "gzip.h"

typedef struct cached {
    unsigned char *gz;
    size_t gz_len;
    char etag[24];
} cached;

struct srv_assets {
    char web_dir[4096];
    cached *c; /* srv_embedded_count entries */
};

static void make_etag(const unsigned char *d, size_t n, char *out) {
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; i++) {
        h ^= d[i];
        h *= 1099511628211ull;
    }
    snprintf(out, 24, "\"%016llx\"", (unsigned long long)h);
}

static void compress_into(const unsigned char *d, size_t n, int level,
                          unsigned char **gz, size_t *gz_len) {
    char *z;
    size_t zn;
    *gz = NULL;
    *gz_len = 0;
    if (n < SRV_GZIP_MIN || srv_gzip(d, n, level, &z, &zn) != 0) return;
    if (zn > n - n / 10) {
        free(z);
        return;
    }
    *gz = (unsigned char *)z;
    *gz_len = zn;
}

srv_assets *srv_assets_new(const char *web_dir) {
    srv_assets *a = calloc(1, sizeof *a);
    if (a == NULL) return NULL;
    if (web_dir != NULL) snprintf(a->web_dir, sizeof a->web_dir, "%s", web_dir);
    a->c = calloc(srv_embedded_count + 1, sizeof *a->c);
    if (a->c == NULL) {
        free(a);
        return NULL;
    }
    for (size_t i = 0; i < srv_embedded_count; i++) {
        const srv_embedded *e = &srv_embedded_assets[i];
        make_etag(e->data, e->len, a->c[i].etag);
        compress_into(e->data, e->len, 9, &a->c[i].gz, &a->c[i].gz_len);
    }
    return a;
}

void srv_assets_free(srv_assets *a) {
    if (a == NULL) return;
    for (size_t i = 0; i < srv_embedded_count; i++) free(a->c[i].gz);
    free(a->c);
    free(a);
}

static const char *canonical(const char *path) {
    return strcmp(path, "/") == 0 ? "/index.html" : path;
}

static long find_embedded(const char *path) {
    for (size_t i = 0; i < srv_embedded_count; i++)
        if (strcmp(srv_embedded_assets[i].path, path) == 0) return (long)i;
    return -1;
}

/* Whether a path may be looked up under --web-dir. */
static int safe_path(const char *p) {
    if (p[0] != '/' || strlen(p) > 200) return 0;
    const char *s = p + 1;
    if (*s == '\0') return 0;
    while (*s) {
        if (*s == '.' || *s == '/') return 0; /* ".x", "..", "//" */
        while (*s && *s != '/') {
            char c = *s++;
            if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                  (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-'))
                return 0;
        }
        if (*s == '/') s++;
        if (*s == '\0' && s[-1] == '/') return 0;
    }
    return 1;
}

static const char *mime_of(const char *path) {
    static const struct {
        const char *ext, *mime;
    } map[] = {
        {".html", "text/html; charset=utf-8"},
        {".js", "text/javascript; charset=utf-8"},
        {".mjs", "text/javascript; charset=utf-8"},
        {".css", "text/css; charset=utf-8"},
        {".svg", "image/svg+xml"},
        {".json", "application/json"},
        {".yaml", "application/yaml"},
        {".png", "image/png"},
        {".ico", "image/x-icon"},
        {".txt", "text/plain; charset=utf-8"},
        {".csv", "text/csv; charset=utf-8"},
        {".woff2", "font/woff2"},
    };
    const char *dot = strrchr(path, '.');
    if (dot != NULL)
        for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
            if (strcmp(dot, map[i].ext) == 0) return map[i].mime;
    return "application/octet-stream";
}

static int from_disk(const srv_assets *a, const char *path) {
    return a->web_dir[0] != '\0' && strcmp(path, "/openapi.yaml") != 0;
}

int srv_assets_has(const srv_assets *a, const char *path) {
    path = canonical(path);
    if (from_disk(a, path)) {
        char full[4400];
        struct stat st;
        if (!safe_path(path)) return 0;
        snprintf(full, sizeof full, "%s%s", a->web_dir, path);
        return stat(full, &st) == 0 && S_ISREG(st.st_mode);
    }
    return find_embedded(path) >= 0;
}

int srv_assets_get(const srv_assets *a, const char *path, srv_asset *out) {
    memset(out, 0, sizeof *out);
    path = canonical(path);
    if (!from_disk(a, path)) {
        long i = find_embedded(path);
        if (i < 0) return -1;
        const srv_embedded *e = &srv_embedded_assets[i];
        out->mime = e->mime;
        out->data = e->data;
        out->len = e->len;
        out->gz = a->c[i].gz;
        out->gz_len = a->c[i].gz_len;
        memcpy(out->etag, a->c[i].etag, sizeof out->etag);
        return 0;
    }
    if (!safe_path(path)) return -1;
    char full[4400];
    snprintf(full, sizeof full, "%s%s", a->web_dir, path);
    FILE *f = fopen(full, "rb");
    if (f == NULL) return -1;
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode) ||
        st.st_size > (1 << 28)) {
        fclose(f);
        return -1;
    }
    size_t n = (size_t)st.st_size;
    /* One block: the struct's owned pointer is the content. */
    unsigned char *d = malloc(n + 1);
    if (d == NULL) {
        fclose(f);
        return -2;
    }
    size_t got = fread(d, 1, n, f);
    fclose(f);
    if (got != n) {
        free(d);
        return -2;
    }
    out->mime = mime_of(path);
    out->data = d;
    out->len = n;
    out->owned = d;
    make_etag(d, n, out->etag);
    return 0;
}

void srv_asset_release(srv_asset *asset) {
    if (asset == NULL) return;
    free(asset->owned);
    asset->owned = NULL;
}
