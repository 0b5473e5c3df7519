/* trace.c -- the tables behind operation counts and traces (vor.h): the
 * names and descriptions of the counts, the names of the step kinds, and
 * the helpers the algorithms use to fill their steps.
 *
 * The counts' table is VOR_COUNTS_TABLE in vor.h; everything here is
 * generated from it, so a count added there is named, described and read
 * by index without another edit. The algorithms count in their own state
 * (core/bowyer_watson.c, flip.c, mesh.c, hilbert.c, fortune.c) and add
 * their counters into the run at the end (internal.h, vor__run). O(1)
 * each, no allocation.
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "internal.h"

static const struct {
    const char *name, *what;
    unsigned algorithms;
    size_t offset;
} counts[] = {
#define VOR__COUNT_ROW(name, algorithms, what)                               \
    {#name, what, algorithms, offsetof(vor_counts, name)},
    VOR_COUNTS_TABLE(VOR__COUNT_ROW)
#undef VOR__COUNT_ROW
};

_Static_assert(sizeof counts / sizeof counts[0] == VOR_COUNT_FIELDS,
               "vor_counts holds exactly the table's counts");

const char *vor_count_name(size_t i) {
    return i < VOR_COUNT_FIELDS ? counts[i].name : NULL;
}

const char *vor_count_what(size_t i) {
    return i < VOR_COUNT_FIELDS ? counts[i].what : NULL;
}

unsigned vor_count_algorithms(size_t i) {
    return i < VOR_COUNT_FIELDS ? counts[i].algorithms : 0;
}

uint64_t vor_count_value(const vor_counts *c, size_t i) {
    if (c == NULL || i >= VOR_COUNT_FIELDS) return 0;
    return *(const uint64_t *)(const void *)((const char *)c + counts[i].offset);
}

void vor__counts_add(vor_counts *to, const vor_counts *from) {
    uint64_t a[VOR_COUNT_FIELDS], b[VOR_COUNT_FIELDS];
    memcpy(a, to, sizeof a);
    memcpy(b, from, sizeof b);
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++) a[i] += b[i];
    memcpy(to, a, sizeof a);
}

const char *vor_step_kind_name(vor_step_kind k) {
    static const char *const names[VOR_STEP_KIND_COUNT] = {
        [VOR_STEP_ORDER] = "order",       [VOR_STEP_BEGIN] = "begin",
        [VOR_STEP_INSERT] = "insert",     [VOR_STEP_FLIP] = "flip",
        [VOR_STEP_SITE] = "site",         [VOR_STEP_CIRCLE] = "circle",
        [VOR_STEP_SCHEDULE] = "schedule", [VOR_STEP_CANCEL] = "cancel",
        [VOR_STEP_END] = "end",
    };
    return (unsigned)k < VOR_STEP_KIND_COUNT ? names[k] : "?";
}

const char *vor_split_name(vor_split s) {
    switch (s) {
    case VOR_SPLIT_TRIANGLE: return "triangle";
    case VOR_SPLIT_EDGE: return "edge";
    case VOR_SPLIT_HULL: return "hull";
    default: return "";
    }
}

void vor__step_init(vor_step *st, vor_step_kind kind) {
    *st = (vor_step){.kind = kind};
    st->site = st->arc = st->at = VOR_INFINITE;
    for (int k = 0; k < 3; k++) st->tri[k] = VOR_INFINITE;
    for (int k = 0; k < 2; k++)
        st->edge[k] = st->added[k] = st->breakpoint[k] = VOR_INFINITE;
}

void vor__trace_end(vor__run *run) {
    if (!run->trace) return;
    vor_step st;
    vor__step_init(&st, VOR_STEP_END);
    st.counts = &run->counts;
    run->trace(run->trace_ctx, &st);
}

void vor__trace_circle(const vor_sites *s, uint32_t a, uint32_t b, uint32_t c,
                       double vertex[2], double *top) {
    uint32_t t;
    if (a > b) { t = a; a = b; b = t; }
    if (b > c) { t = b; b = c; c = t; }
    if (a > b) { t = a; a = b; b = t; }
    const double *pa = s->xy + 2 * (size_t)a;
    vor_circumcenter(pa, s->xy + 2 * (size_t)b, s->xy + 2 * (size_t)c, vertex);
    *top = vertex[1] + hypot(pa[0] - vertex[0], pa[1] - vertex[1]);
}
