/* routes.c -- matching a method and path against the route table.
 *
 * Exact paths first, then the /problems/ prefix, then the asset catch-all
 * (any path the asset store knows, for GET and HEAD). A path that exists with another method gives
 * 405 and the Allow list; OPTIONS is allowed wherever the path exists
 * (CORS preflight), and on "*", the server as a whole (RFC 9110, 9.3.7),
 * whose Allow lists every method some path takes. Linear in the number
 * of routes; no allocation.
 */
#include "routes.h"

#include <string.h>

static const struct {
    const char *path;
    unsigned methods;
} table[SRV_ROUTE_COUNT] = {
#define SRV__ROUTE_INFO(id, path, methods) [id] = {path, methods},
    SRV_ROUTE_TABLE(SRV__ROUTE_INFO)
#undef SRV__ROUTE_INFO
};

unsigned srv_method_bit(const char *m) {
    if (m == NULL) return SRV_M_OTHER;
    if (strcmp(m, "GET") == 0) return SRV_M_GET;
    if (strcmp(m, "HEAD") == 0) return SRV_M_HEAD;
    if (strcmp(m, "POST") == 0) return SRV_M_POST;
    if (strcmp(m, "OPTIONS") == 0) return SRV_M_OPTIONS;
    return SRV_M_OTHER;
}

const char *srv_route_name(srv_route r) {
    return (unsigned)r < SRV_ROUTE_COUNT ? table[r].path : "other";
}

/* The Allow list of the methods in m, OPTIONS always last. */
static void copy_allow(char *allow, size_t allow_size, unsigned m) {
    static const struct {
        unsigned bit;
        const char *name;
    } names[] = {{SRV_M_GET, "GET"}, {SRV_M_HEAD, "HEAD"},
                 {SRV_M_POST, "POST"}};
    /* Plain copies, not snprintf: this runs for every request. The whole
     * list is at most "GET, HEAD, POST, OPTIONS"; a buffer too small for
     * it gets as much as fits, terminated, as snprintf would give. */
    char list[32];
    size_t len = 0;
    if (allow_size == 0) return;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        if (m & names[i].bit) {
            size_t k = strlen(names[i].name);
            memcpy(list + len, names[i].name, k);
            memcpy(list + len + k, ", ", 2);
            len += k + 2;
        }
    }
    memcpy(list + len, "OPTIONS", sizeof "OPTIONS");
    len += sizeof "OPTIONS" - 1;
    if (len >= allow_size) len = allow_size - 1;
    memcpy(allow, list, len);
    allow[len] = '\0';
}

void srv_route_allow(srv_route r, char *allow, size_t allow_size) {
    copy_allow(allow, allow_size,
               (unsigned)r < SRV_ROUTE_COUNT ? table[r].methods : 0);
}

srv_match srv_route_match(const char *method, const char *path,
                          int (*has_asset)(const char *path, void *ctx),
                          void *ctx, srv_route *route, char *allow,
                          size_t allow_size) {
    unsigned bit = srv_method_bit(method);
    srv_route found = SRV_ROUTE_OTHER;
    if (allow_size > 0) allow[0] = '\0';
    if (bit == SRV_M_OPTIONS && path != NULL && strcmp(path, "*") == 0) {
        *route = SRV_ROUTE_OTHER;
        copy_allow(allow, allow_size, SRV_M_GET | SRV_M_HEAD | SRV_M_POST);
        return SRV_MATCH_OK;
    }
    for (int r = 0; r < SRV_ROUTE_COUNT; r++) {
        if (r == SRV_ROUTE_ASSET || r == SRV_ROUTE_OTHER) continue;
        if (path != NULL && strcmp(path, table[r].path) == 0) {
            found = (srv_route)r;
            break;
        }
    }
    /* /problems/<type>: the handler knows the types (404 for others). */
    if (found == SRV_ROUTE_PROBLEM ||
        (path != NULL && strncmp(path, "/problems/", 10) == 0 && path[10]))
        found = path[10] ? SRV_ROUTE_PROBLEM : SRV_ROUTE_OTHER;
    if (found == SRV_ROUTE_OTHER && path != NULL && path[0] == '/' &&
        has_asset != NULL && has_asset(path, ctx))
        found = SRV_ROUTE_ASSET;
    *route = found;
    if (found == SRV_ROUTE_OTHER) return SRV_MATCH_NOT_FOUND;
    srv_route_allow(found, allow, allow_size);
    if (bit == SRV_M_OPTIONS || (table[found].methods & bit))
        return SRV_MATCH_OK;
    return SRV_MATCH_METHOD;
}
