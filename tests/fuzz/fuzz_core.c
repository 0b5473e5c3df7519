/* fuzz_core.c -- libFuzzer target: the three algorithms agree on any input.
 *
 * The fuzzer's bytes become up to 96 points. The first byte picks how:
 * coordinates from a tiny integer range (so duplicates, collinear runs and
 * cocircular quadruples are common), 16-bit integers, integers scaled by a
 * huge or tiny power of ten, or raw doubles (non-finite ones must be refused
 * with VOR_ENONFINITE, nothing else). Every algorithm must return VOR_OK, pass
 * vor_check and give the bit-identical diagram; the clip of a box around the
 * sites must succeed. The same points filled into a vor_sites by hand,
 * repeats and all, must be refused or give that diagram (by_hand). Any
 * violation aborts, which libFuzzer reports with the input that caused
 * it. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../core/vor.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void fail(const char *what, const char *detail) {
    fprintf(stderr, "fuzz_core: %s: %s\n", what, detail);
    abort();
}

static size_t make_points(const uint8_t *data, size_t size, double *xy) {
    if (size == 0) return 0;
    unsigned mode = data[0] % 5;
    data++;
    size--;
    size_t n = 0;
    switch (mode) {
    case 0: /* 0..7: degeneracies everywhere */
    case 1: /* 0..15 scaled to 1e9 + k/8: exact, far from the origin */
        for (; n < 96 && 2 * n + 1 < size; n++) {
            double x = data[2 * n] % (mode ? 16 : 8);
            double y = data[2 * n + 1] % (mode ? 16 : 8);
            xy[2 * n] = mode ? 1e9 + x / 8 : x;
            xy[2 * n + 1] = y;
        }
        break;
    case 2: /* 16-bit integers */
        for (; n < 96 && 4 * n + 3 < size; n++) {
            xy[2 * n] = (int16_t)(data[4 * n] | data[4 * n + 1] << 8);
            xy[2 * n + 1] = (int16_t)(data[4 * n + 2] | data[4 * n + 3] << 8);
        }
        break;
    case 3: { /* small integers times 1e300 or 1e-300 */
        double scale = size && data[0] & 1 ? 1e300 : 1e-300;
        for (; n < 96 && 2 * n + 2 < size; n++) {
            xy[2 * n] = (double)(data[2 * n + 1] % 8) * scale;
            xy[2 * n + 1] = (double)(data[2 * n + 2] % 8) * scale;
        }
        break;
    }
    default: /* raw doubles */
        for (; n < 96 && 16 * n + 15 < size; n++) {
            memcpy(&xy[2 * n], data + 16 * n, 16);
        }
        break;
    }
    return n;
}

/* The raw points as a vor_sites filled by hand, repeats and non-finite
 * values kept (vor_compute's contract asks for neither): every algorithm
 * answers VOR_ENONFINITE if a coordinate is not finite, else VOR_EINVAL
 * if a point repeats, else the diagram it gives through vor_sites_new
 * (bit for bit where no coordinate is -0.0, which vor_sites_new stores
 * as 0.0), and never a diagram with an error. */
static void by_hand(const double *xy, size_t n, vor_status made,
                    const vor_sites *sites, vor_diagram *const *d) {
    uint32_t ident[96];
    int minus_zero = 0;
    for (size_t i = 0; i < n; i++) ident[i] = (uint32_t)i;
    for (size_t i = 0; i < 2 * n; i++)
        minus_zero |= xy[i] == 0 && signbit(xy[i]);
    vor_sites hand = {n, n, (double *)xy, ident, ident};
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        vor_diagram *h = NULL;
        vor_status st = vor_compute(&hand, (vor_algorithm)a, &h);
        vor_status want = made == VOR_ENONFINITE ? VOR_ENONFINITE
                          : sites->n < n         ? VOR_EINVAL
                                                 : VOR_OK;
        if (st != want) fail("by hand", vor_status_message(st));
        if (st != VOR_OK) {
            if (h != NULL) fail("by hand", "a diagram with an error");
            continue;
        }
        if (!minus_zero && !vor_diagram_equal(h, d[a]))
            fail("by hand", "differs from the diagram of vor_sites_new");
        vor_diagram_free(h);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    double xy[2 * 96];
    size_t n = make_points(data, size, xy);
    vor_sites *sites = NULL;
    size_t bad = 0;
    vor_status st = vor_sites_new(xy, n, &sites, &bad);
    if (st == VOR_ENONFINITE) {
        if (bad >= n || (isfinite(xy[2 * bad]) && isfinite(xy[2 * bad + 1])))
            fail("sites", "wrong index for a non-finite coordinate");
        by_hand(xy, n, st, NULL, NULL);
        return 0;
    }
    if (st != VOR_OK) fail("sites", vor_status_message(st));

    vor_diagram *d[VOR_ALGORITHM_COUNT] = {0};
    char msg[256];
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) {
        st = vor_compute(sites, (vor_algorithm)a, &d[a]);
        if (st != VOR_OK) fail(vor_algorithm_name(a), vor_status_message(st));
        if (vor_check(d[a], sites, msg, sizeof msg) != 0)
            fail(vor_algorithm_name(a), msg);
        if (a > 0 && !vor_diagram_equal(d[0], d[a]))
            fail(vor_algorithm_name(a), "differs from fortune");
    }
    by_hand(xy, n, st, sites, d);

    if (sites->n > 0) {
        double box[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY};
        for (size_t i = 0; i < sites->n; i++) {
            box[0] = fmin(box[0], sites->xy[2 * i]);
            box[1] = fmin(box[1], sites->xy[2 * i + 1]);
            box[2] = fmax(box[2], sites->xy[2 * i]);
            box[3] = fmax(box[3], sites->xy[2 * i + 1]);
        }
        double w = box[2] - box[0], h = box[3] - box[1];
        double pad = fmax(fmax(w, h), fmax(fabs(box[0]), fabs(box[1])) * 0x1p-40);
        if (!(pad > 0) || !isfinite(pad)) pad = 1.0;
        box[0] -= pad;
        box[1] -= pad;
        box[2] += pad;
        box[3] += pad;
        if (isfinite(box[0]) && isfinite(box[1]) && isfinite(box[2]) &&
            isfinite(box[3]) && box[0] < box[2] && box[1] < box[3]) {
            vor_clipped *c = NULL;
            st = vor_clip(d[0], sites, box, &c);
            if (st != VOR_OK) fail("clip", vor_status_message(st));
            vor_clipped_free(c);
        }
    }
    for (int a = 0; a < VOR_ALGORITHM_COUNT; a++) vor_diagram_free(d[a]);
    vor_sites_free(sites);
    return 0;
}
