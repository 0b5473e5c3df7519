/* sites.c -- validation and exact de-duplication of the input points.
 *
 * vor_sites_new() makes one pass over the input: it rejects the first
 * non-finite coordinate, and looks every point up in an open-addressing hash
 * table keyed on the bit patterns of its coordinates (-0.0 is first made
 * +0.0, so that the points that compare equal are exactly the points with
 * equal bits). A point seen before maps to the earlier site; a new point
 * becomes the next site. Sites therefore come in order of first occurrence,
 * and input_of is strictly increasing.
 *
 * Table: a power of two of 64-bit slots, at least twice the number of
 * points (load <= 1/2), linear probing. A slot holds 32 bits of the key's
 * hash (a tag) and the site index plus one (0 = empty), so a probe touches
 * the site's coordinates only when the tags agree, which for distinct
 * points happens with probability 2^-32 per probe. The hash mixes both
 * coordinates' bits through multiplications and xor-shifts, so grids and
 * other regular inputs (whose low mantissa bits are all zero) spread as
 * well as random ones.
 *
 * Cost: expected O(n) time. For 10^6 points the table (16 MiB) exceeds the
 * caches, so points go through in blocks of 32 whose slots are prefetched
 * before they are probed: the misses overlap, and 10^6 points take about
 * 20 ms, a third of it the kernel's zeroing of fresh pages.
 * Memory: the output arrays (24 bytes per input point before the site
 * arrays are trimmed to the number of sites) plus the table, 16 to 32 bytes
 * per point, freed before returning.
 */
#include <stdlib.h>
#include <string.h>

#include "internal.h"

/* Bits of a coordinate with -0.0 folded into +0.0. */
static inline uint64_t coord_bits(double v) {
    uint64_t u;
    if (v == 0)
        v = 0.0;
    memcpy(&u, &v, sizeof u);
    return u;
}

static inline int bits_finite(uint64_t u) {
    return (u & 0x7ff0000000000000u) != 0x7ff0000000000000u;
}

/* 64-bit hash of a point's two coordinate patterns. */
static inline uint64_t point_hash(uint64_t x, uint64_t y) {
    uint64_t h = x * 0x9e3779b97f4a7c15u;
    h ^= (y + 0x632be59bd9b4e019u) * 0xc2b2ae3d27d4eb4fu;
    h ^= h >> 32;
    h *= 0xd6e8feb86659fd93u;
    h ^= h >> 32;
    return h;
}

void vor_sites_free(vor_sites *s) {
    if (!s)
        return;
    free(s->xy);
    free(s->input_of);
    free(s->site_of);
    free(s);
}

/* Shrinks an array to its final size if realloc agrees; keeps it as it is
 * otherwise (the larger block is still valid). */
static void *trim(void *p, size_t bytes) {
    if (bytes == 0)
        return p;
    void *q = realloc(p, bytes);
    return q ? q : p;
}

vor_status vor_sites_new(const double *xy, size_t n, vor_sites **out,
                         size_t *bad_index) {
    if (!out)
        return VOR_EINVAL;
    *out = NULL;
    if (n > VOR_MAX_POINTS)
        return VOR_ETOOMANY;
    if (n > 0 && !xy)
        return VOR_EINVAL;

    vor_sites *s = calloc(1, sizeof *s);
    if (!s)
        return VOR_ENOMEM;
    s->n_input = n;
    if (n == 0) {
        *out = s;
        return VOR_OK;
    }

    size_t cap = 1;
    int shift = 64;
    while (cap < 2 * n) {
        cap <<= 1;
        shift--;
    }
    uint64_t *table = vor__calloc_large(cap, sizeof *table);
    s->xy = vor__alloc_large(2 * n, sizeof *s->xy);
    s->input_of = vor__alloc_large(n, sizeof *s->input_of);
    s->site_of = vor__alloc_large(n, sizeof *s->site_of);
    if (!table || !s->xy || !s->input_of || !s->site_of) {
        free(table);
        vor_sites_free(s);
        return VOR_ENOMEM;
    }

    /* Points go through in blocks: first every hash of the block is
     * computed and its slot prefetched, then the lookups run, so that the
     * cache misses of a block overlap instead of following each other. */
    enum { BLOCK = 32 };
    uint64_t hashes[BLOCK];
    const uint64_t mask = cap - 1;
    double *sxy = s->xy;
    uint32_t m = 0; /* sites so far */
    for (size_t i0 = 0; i0 < n; i0 += BLOCK) {
        size_t len = n - i0 < BLOCK ? n - i0 : BLOCK;
        for (size_t j = 0; j < len; j++) {
            size_t i = i0 + j;
            uint64_t bx = coord_bits(xy[2 * i]), by = coord_bits(xy[2 * i + 1]);
            if (!bits_finite(bx) || !bits_finite(by)) {
                if (bad_index)
                    *bad_index = i;
                free(table);
                vor_sites_free(s);
                return VOR_ENONFINITE;
            }
            hashes[j] = point_hash(bx, by);
            __builtin_prefetch(&table[hashes[j] >> shift]);
        }
        for (size_t j = 0; j < len; j++) {
            size_t i = i0 + j;
            uint64_t h = hashes[j];
            /* slot from the high bits, tag from the low 32: independent,
             * since the table has at most 2^31 slots */
            uint64_t tag = h << 32;
            uint64_t slot = h >> shift;
            uint32_t site;
            for (;;) {
                uint64_t e = table[slot];
                if (e == 0) {
                    site = m++;
                    table[slot] = tag | (uint64_t)(site + 1);
                    sxy[2 * site] = xy[2 * i] == 0 ? 0.0 : xy[2 * i];
                    sxy[2 * site + 1] =
                        xy[2 * i + 1] == 0 ? 0.0 : xy[2 * i + 1];
                    s->input_of[site] = (uint32_t)i;
                    break;
                }
                if ((e & 0xffffffff00000000u) == tag) {
                    uint32_t k = (uint32_t)e - 1;
                    if (sxy[2 * k] == xy[2 * i] &&
                        sxy[2 * k + 1] == xy[2 * i + 1]) {
                        site = k;
                        break;
                    }
                }
                slot = (slot + 1) & mask;
            }
            s->site_of[i] = site;
        }
    }
    free(table);

    s->n = m;
    s->xy = trim(s->xy, 2 * (size_t)m * sizeof *s->xy);
    s->input_of = trim(s->input_of, (size_t)m * sizeof *s->input_of);
    *out = s;
    return VOR_OK;
}
