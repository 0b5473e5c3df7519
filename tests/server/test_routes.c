/* test_routes.c -- the route table: exact paths, the asset catch-all,
 * 404 and 405 with the Allow list, OPTIONS on every existing path and
 * on "*", the server as a whole. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "../../server/routes.h"

static int fake_assets(const char *path, void *ctx) {
    (void)ctx;
    return strcmp(path, "/app.js") == 0 || strcmp(path, "/style.css") == 0;
}

static srv_match m(const char *method, const char *path, srv_route *r,
                   char *allow) {
    return srv_route_match(method, path, fake_assets, NULL, r, allow, 48);
}

static void test_exact_routes(void **state) {
    (void)state;
    static const struct {
        const char *method, *path;
        srv_route route;
    } ok[] = {
        {"POST", "/voronoi", SRV_ROUTE_VORONOI},
        {"POST", "/compare", SRV_ROUTE_COMPARE},
        {"GET", "/", SRV_ROUTE_PAGE},
        {"HEAD", "/", SRV_ROUTE_PAGE},
        {"GET", "/openapi.yaml", SRV_ROUTE_OPENAPI},
        {"GET", "/healthz", SRV_ROUTE_HEALTHZ},
        {"HEAD", "/healthz", SRV_ROUTE_HEALTHZ},
        {"GET", "/readyz", SRV_ROUTE_READYZ},
        {"GET", "/metrics", SRV_ROUTE_METRICS},
        {"GET", "/app.js", SRV_ROUTE_ASSET},
        {"HEAD", "/style.css", SRV_ROUTE_ASSET},
        {"OPTIONS", "/voronoi", SRV_ROUTE_VORONOI},
        {"OPTIONS", "/", SRV_ROUTE_PAGE},
        {"GET", "/problems/too-large", SRV_ROUTE_PROBLEM},
        {"HEAD", "/problems/anything", SRV_ROUTE_PROBLEM},
    };
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        srv_route r;
        char allow[48];
        srv_match got = m(ok[i].method, ok[i].path, &r, allow);
        if (got != SRV_MATCH_OK || r != ok[i].route)
            fail_msg("%s %s: match %d route %d", ok[i].method, ok[i].path,
                     (int)got, (int)r);
    }
}

static void test_not_found(void **state) {
    (void)state;
    const char *paths[] = {"/voronoi/", "/Voronoi", "/nope", "", "/app.jsx",
                           "/../etc/passwd", "/healthz?x", "//", "/problems/",
                           "/problems", NULL};
    for (int i = 0; paths[i]; i++) {
        srv_route r = SRV_ROUTE_VORONOI;
        char allow[48];
        assert_int_equal(m("GET", paths[i], &r, allow), SRV_MATCH_NOT_FOUND);
        assert_int_equal(r, SRV_ROUTE_OTHER);
    }
    srv_route r;
    char allow[48];
    assert_int_equal(srv_route_match("GET", NULL, NULL, NULL, &r, allow, 48),
                     SRV_MATCH_NOT_FOUND);
    /* Without an asset store nothing else exists. */
    assert_int_equal(srv_route_match("GET", "/app.js", NULL, NULL, &r, allow,
                                     48),
                     SRV_MATCH_NOT_FOUND);
}

static void test_method_not_allowed_lists_allow(void **state) {
    (void)state;
    static const struct {
        const char *method, *path, *allow;
    } bad[] = {
        {"GET", "/voronoi", "POST, OPTIONS"},
        {"HEAD", "/compare", "POST, OPTIONS"},
        {"PUT", "/voronoi", "POST, OPTIONS"},
        {"DELETE", "/", "GET, HEAD, OPTIONS"},
        {"POST", "/metrics", "GET, HEAD, OPTIONS"},
        {"PATCH", "/app.js", "GET, HEAD, OPTIONS"},
        {"BREW", "/healthz", "GET, HEAD, OPTIONS"},
        {"POST", "/problems/invalid", "GET, HEAD, OPTIONS"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        srv_route r;
        char allow[48];
        assert_int_equal(m(bad[i].method, bad[i].path, &r, allow),
                         SRV_MATCH_METHOD);
        assert_string_equal(allow, bad[i].allow);
    }
}

/* "OPTIONS *" asks about the server: every method some path takes. "*"
 * is no path for any other method. */
static void test_options_asterisk(void **state) {
    (void)state;
    srv_route r = SRV_ROUTE_VORONOI;
    char allow[48];
    assert_int_equal(m("OPTIONS", "*", &r, allow), SRV_MATCH_OK);
    assert_int_equal(r, SRV_ROUTE_OTHER);
    assert_string_equal(allow, "GET, HEAD, POST, OPTIONS");
    const char *others[] = {"GET", "HEAD", "POST", "PUT", NULL};
    for (int i = 0; others[i]; i++)
        if (m(others[i], "*", &r, allow) != SRV_MATCH_NOT_FOUND)
            fail_msg("%s *: not a 404", others[i]);
    assert_int_equal(m("OPTIONS", "*x", &r, allow), SRV_MATCH_NOT_FOUND);
}

static void test_names_and_methods(void **state) {
    (void)state;
    assert_string_equal(srv_route_name(SRV_ROUTE_VORONOI), "/voronoi");
    assert_string_equal(srv_route_name(SRV_ROUTE_OTHER), "other");
    assert_string_equal(srv_route_name((srv_route)99), "other");
    assert_int_equal(srv_method_bit("GET"), SRV_M_GET);
    assert_int_equal(srv_method_bit("get"), SRV_M_OTHER); /* case matters */
    assert_int_equal(srv_method_bit(NULL), SRV_M_OTHER);
    char small[8];
    srv_route_allow(SRV_ROUTE_PAGE, small, sizeof small); /* truncates safely */
    assert_true(strlen(small) < sizeof small);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exact_routes),
        cmocka_unit_test(test_not_found),
        cmocka_unit_test(test_method_not_allowed_lists_allow),
        cmocka_unit_test(test_options_asterisk),
        cmocka_unit_test(test_names_and_methods),
    };
    return cmocka_run_group_tests_name("server/routes", tests, NULL, NULL);
}
