/* routes.h -- voronoid's route table: which handler answers a method and
 * path, and what Allow says when the method does not fit.
 *
 * The table is static and small (a dozen paths), so matching is a linear
 * scan of exact paths; "/problems/" matches every path under it (the
 * problem type documents, RFC 9457 type URIs); static assets under the
 * page (/app.js, /style.css, ...) match a catch-all "asset" route for GET
 * and HEAD when the asset store has the file. Handlers themselves live in server.c; this module
 * only names them, so it can be tested without a socket.
 */
#ifndef VOR_SRV_ROUTES_H
#define VOR_SRV_ROUTES_H

#include <stddef.h>

/* Routes, in the order /metrics lists them. SRV_ROUTE_OTHER counts
 * requests that matched nothing (404). */
#define SRV_ROUTE_TABLE(X)                                         \
    X(SRV_ROUTE_VORONOI, "/voronoi", SRV_M_POST)                   \
    X(SRV_ROUTE_COMPARE, "/compare", SRV_M_POST)                   \
    X(SRV_ROUTE_PAGE, "/", SRV_M_GET | SRV_M_HEAD)                 \
    X(SRV_ROUTE_OPENAPI, "/openapi.yaml", SRV_M_GET | SRV_M_HEAD)  \
    X(SRV_ROUTE_HEALTHZ, "/healthz", SRV_M_GET | SRV_M_HEAD)       \
    X(SRV_ROUTE_READYZ, "/readyz", SRV_M_GET | SRV_M_HEAD)         \
    X(SRV_ROUTE_METRICS, "/metrics", SRV_M_GET | SRV_M_HEAD)       \
    X(SRV_ROUTE_PROBLEM, "/problems/", SRV_M_GET | SRV_M_HEAD)     \
    X(SRV_ROUTE_ASSET, "asset", SRV_M_GET | SRV_M_HEAD)            \
    X(SRV_ROUTE_OTHER, "other", 0)

/* Methods as bits. OPTIONS is allowed on every route that exists. */
enum {
    SRV_M_GET = 1u << 0,
    SRV_M_HEAD = 1u << 1,
    SRV_M_POST = 1u << 2,
    SRV_M_OPTIONS = 1u << 3,
    SRV_M_OTHER = 1u << 4 /* PUT, DELETE, PATCH, anything else */
};

typedef enum srv_route {
#define SRV__ROUTE_ENUM(id, path, methods) id,
    SRV_ROUTE_TABLE(SRV__ROUTE_ENUM)
#undef SRV__ROUTE_ENUM
    SRV_ROUTE_COUNT
} srv_route;

typedef enum srv_match {
    SRV_MATCH_OK,
    SRV_MATCH_NOT_FOUND,  /* 404 */
    SRV_MATCH_METHOD      /* 405: allow holds the Allow header */
} srv_match;

/* Method name -> SRV_M_* bit (SRV_M_OTHER for anything unknown). */
unsigned srv_method_bit(const char *method);

/* Name used in /metrics and the access log ("/voronoi", "other"...). */
const char *srv_route_name(srv_route r);

/* Allowed methods of a route, OPTIONS included, as an Allow header value
 * ("POST, OPTIONS") written into allow (allow_size >= 32 is enough). */
void srv_route_allow(srv_route r, char *allow, size_t allow_size);

/* Finds the route for method and path. has_asset(path, ctx) tells whether
 * the asset store has a file for a path not in the table (NULL: none).
 * *route is set for SRV_MATCH_OK and SRV_MATCH_METHOD (and is
 * SRV_ROUTE_OTHER for NOT_FOUND). allow gets the Allow value for
 * SRV_MATCH_METHOD and SRV_MATCH_OK. Cannot fail. */
srv_match srv_route_match(const char *method, const char *path,
                          int (*has_asset)(const char *path, void *ctx),
                          void *ctx, srv_route *route, char *allow,
                          size_t allow_size);

#endif /* VOR_SRV_ROUTES_H */
