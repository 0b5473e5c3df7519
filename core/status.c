/* status.c -- names, messages and HTTP statuses of vor_status, and the
 * algorithm names. Generated from the tables in vor.h, so a status or an
 * algorithm is declared in exactly one place. Cannot fail. */
#include <string.h>

#include "vor.h"

static const struct {
    const char *name;
    int http;
    const char *message;
} status_info[] = {
#define VOR__INFO(name, http, msg) {#name, http, msg},
    VOR_STATUS_TABLE(VOR__INFO)
#undef VOR__INFO
};

static const char *const algorithm_names[VOR_ALGORITHM_COUNT] = {
    [VOR_FORTUNE] = "fortune",
    [VOR_BOWYER_WATSON] = "bowyer-watson",
    [VOR_FLIP] = "flip",
};

const char *vor_status_message(vor_status s) {
    return (unsigned)s < VOR_STATUS_COUNT ? status_info[s].message
                                          : "unknown status";
}

const char *vor_status_name(vor_status s) {
    return (unsigned)s < VOR_STATUS_COUNT ? status_info[s].name : "VOR_EUNKNOWN";
}

int vor_status_http(vor_status s) {
    return (unsigned)s < VOR_STATUS_COUNT ? status_info[s].http : 500;
}

const char *vor_algorithm_name(vor_algorithm a) {
    return (unsigned)a < VOR_ALGORITHM_COUNT ? algorithm_names[a] : "unknown";
}

vor_status vor_algorithm_parse(const char *name, vor_algorithm *out) {
    if (name == NULL) return VOR_EALGORITHM;
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        if (strcmp(name, algorithm_names[a]) == 0) {
            *out = (vor_algorithm)a;
            return VOR_OK;
        }
    }
    return VOR_EALGORITHM;
}
