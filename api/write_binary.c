/* write_binary.c -- the diagram as application/octet-stream, for programs
 * that want the arrays without parsing text.
 *
 * Layout (all little-endian; documented in openapi.yaml as BinaryDiagram):
 *
 *   header, 48 bytes:
 *     0  char[4] "VORB"          4  u32 version (1)
 *     8  u32 algorithm (0 fortune, 1 bowyer-watson, 2 flip)
 *    12  u32 flags: 1 triangles present, 2 clipped present, 4 bounds given,
 *              8 counts present
 *    16  u32 n_input   20 u32 n_sites   24 u32 n_vertices   28 u32 n_edges
 *    32  u32 n_rays    36 u32 n_triangles (0 without flag 1)
 *    40  u32 n_clip_points (0 without flag 2)
 *    44  u32 n_counts (0 without flag 8)
 *   then these sections, in this order, each padded with zero bytes to a
 *   multiple of 8:
 *     site_input   u32[n_sites]        input index of each site
 *     input_site   u32[n_input]        site of each input point
 *     sites_xy     f64[2 n_sites]
 *     vertices     f64[2 n_vertices]
 *     edges        i32[4 n_edges]      site a, site b (INPUT indices),
 *                                      end0, end1 (vertex index, -1 = none)
 *     ray_edge     u32[n_rays]         the edge of each ray (increasing)
 *     ray_dir      f64[2 n_rays]       its unit direction
 *     cell_start   u32[n_sites + 1]
 *     cell_edges   u32[2 n_edges]      counter-clockwise, per site
 *     cell_bounded u8[n_sites]
 *     (flag 1) triangles u32[3 n_triangles]   input indices
 *     (flag 2) clip_box f64[4]; clip_edges f64[4 n_edges] (x0, y0, x1, y1,
 *              NaN where the edge misses the box); clip_start
 *              u32[n_sites + 1]; clip_xy f64[2 n_clip_points]
 *     timings      f64[7]   queue, parse, prepare, compute, clip,
 *                           serialize, total (ms)
 *     (flag 8) counts u64[n_counts]  the operation counts, every count of
 *                           core/vor.h's table in its order (0 where it
 *                           does not apply to the algorithm)
 *
 * The "include" choice does not apply: every section is always written.
 * O(output); byte order is produced explicitly, so the format is the same
 * on any host. */
#include <math.h>
#include <string.h>

#include "codec.h"

static void le32(api_buf *b, uint32_t v) {
    unsigned char c[4] = {(unsigned char)v, (unsigned char)(v >> 8),
                          (unsigned char)(v >> 16), (unsigned char)(v >> 24)};
    api__put(b, (const char *)c, 4);
}

static void le64(api_buf *b, double d) {
    uint64_t v;
    memcpy(&v, &d, sizeof v);
    unsigned char c[8];
    for (int i = 0; i < 8; i++) c[i] = (unsigned char)(v >> (8 * i));
    api__put(b, (const char *)c, 8);
}

static void le64u(api_buf *b, uint64_t v) {
    unsigned char c[8];
    for (int i = 0; i < 8; i++) c[i] = (unsigned char)(v >> (8 * i));
    api__put(b, (const char *)c, 8);
}

static void pad8(api_buf *b) {
    while (b->len % 8) api__putc(b, 0);
}

/* Sections are written in chunks so each reserve stays small. */
#define CHUNK 4096

static int put_u32s(api_buf *b, const uint32_t *v, size_t n) {
    for (size_t i = 0; i < n; i++) {
        if (i % CHUNK == 0 && api__reserve(b, 4 * CHUNK + 8)) return -1;
        le32(b, v[i]);
    }
    if (api__reserve(b, 8)) return -1;
    pad8(b);
    return 0;
}

static int put_f64s(api_buf *b, const double *v, size_t n) {
    for (size_t i = 0; i < n; i++) {
        if (i % CHUNK == 0 && api__reserve(b, 8 * CHUNK + 8)) return -1;
        le64(b, v[i]);
    }
    return 0;
}

int api__write_binary(const api_request *r, const api_result *res,
                      api_timings *t, double t0, api_buf *out) {
    const vor_sites *s = res->sites;
    const vor_diagram *d = res->diagram;
    const vor_clipped *c = res->clipped;
    int tri = (api__effective_parts(r) & API_PART_TRIANGLES) != 0;
    uint32_t flags = (tri ? 1u : 0u) | (c ? 2u : 0u) | (r->has_bounds ? 4u : 0u) |
                     8u;
    uint32_t n_clip = c ? c->poly_start[s->n] : 0;
    if (out->len % 8 && api__reserve(out, 8)) return -1;
    pad8(out);
    if (api__reserve(out, 64)) return -1;
    api__put(out, "VORB", 4);
    const uint32_t head[] = {1,
                             (uint32_t)res->algorithm,
                             flags,
                             (uint32_t)s->n_input,
                             (uint32_t)s->n,
                             (uint32_t)d->n_vertices,
                             (uint32_t)d->n_edges,
                             (uint32_t)d->n_rays,
                             tri ? (uint32_t)res->n_triangles : 0,
                             n_clip,
                             (uint32_t)VOR_COUNT_FIELDS};
    for (size_t i = 0; i < sizeof head / sizeof head[0]; i++) le32(out, head[i]);

    if (put_u32s(out, s->input_of, s->n)) return -1;
    if (put_u32s(out, s->site_of, s->n_input)) return -1;
    if (put_f64s(out, s->xy, 2 * s->n)) return -1;
    if (put_f64s(out, d->vertex_xy, 2 * d->n_vertices)) return -1;
    for (size_t e = 0; e < d->n_edges; e++) {
        if (e % CHUNK == 0 && api__reserve(out, 16 * CHUNK)) return -1;
        le32(out, api__input_index(s, d->edge_sites[2 * e]));
        le32(out, api__input_index(s, d->edge_sites[2 * e + 1]));
        le32(out, (uint32_t)d->edge_ends[2 * e]);
        le32(out, (uint32_t)d->edge_ends[2 * e + 1]);
    }
    if (put_u32s(out, d->ray_edge, d->n_rays)) return -1;
    if (put_f64s(out, d->ray_dir, 2 * d->n_rays)) return -1;
    if (put_u32s(out, d->cell_start, s->n + 1)) return -1;
    if (put_u32s(out, d->cell_edges, 2 * d->n_edges)) return -1;
    if (api__reserve(out, s->n + 8)) return -1;
    api__put(out, (const char *)d->cell_bounded, s->n);
    pad8(out);
    if (tri) {
        for (size_t k = 0; k < 3 * res->n_triangles; k++) {
            if (k % CHUNK == 0 && api__reserve(out, 4 * CHUNK + 8)) return -1;
            le32(out, api__input_index(s, res->triangles[k]));
        }
        if (api__reserve(out, 8)) return -1;
        pad8(out);
    }
    if (c) {
        if (put_f64s(out, c->box, 4)) return -1;
        for (size_t e = 0; e < d->n_edges; e++) {
            if (e % CHUNK == 0 && api__reserve(out, 32 * CHUNK)) return -1;
            for (int k = 0; k < 4; k++) le64(out, c->seg_in[e] ? c->seg[4 * e + k] : NAN);
        }
        if (put_u32s(out, c->poly_start, s->n + 1)) return -1;
        if (put_f64s(out, c->poly_xy, 2 * (size_t)n_clip)) return -1;
    }
    api__finish_timings(t, t0);
    const double tv[7] = {t->queue_ms,   t->parse_ms,     t->prepare_ms,
                          t->compute_ms, t->clip_ms,      t->serialize_ms,
                          t->total_ms};
    if (put_f64s(out, tv, 7)) return -1;
    if (api__reserve(out, 8 * VOR_COUNT_FIELDS)) return -1;
    for (size_t i = 0; i < VOR_COUNT_FIELDS; i++)
        le64u(out, vor_count_value(&res->counts, i));
    return 0;
}
