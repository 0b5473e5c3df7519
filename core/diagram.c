/* diagram.c -- the canonical Voronoi diagram (placeholder, being written).
 *
 * Every entry point returns VOR_EUNAVAILABLE until the builder lands; the
 * free and compare functions are already real. */
#include <stdlib.h>
#include <string.h>

#include "internal.h"

vor_status vor__diagram_build(const vor_sites *s, size_t n_vertices,
                              uint32_t *edges, int32_t *ends, size_t n_edges,
                              vor_diagram **out) {
    (void)s; (void)n_vertices; (void)n_edges;
    free(edges);
    free(ends);
    if (out) *out = NULL;
    return VOR_EUNAVAILABLE;
}

vor_status vor__mesh_to_diagram(const vor_sites *s, vor__mesh *m,
                                vor_diagram **out) {
    (void)s;
    if (m) {
        free(m->tri);
        free(m->adj);
        memset(m, 0, sizeof *m);
    }
    if (out) *out = NULL;
    return VOR_EUNAVAILABLE;
}

int vor__all_collinear(const vor_sites *s) {
    (void)s;
    return 0;
}

vor_status vor__diagram_degenerate(const vor_sites *s, vor_diagram **out) {
    (void)s;
    if (out) *out = NULL;
    return VOR_EUNAVAILABLE;
}

vor_status vor_diagram_triangles(const vor_diagram *d, const vor_sites *sites,
                                 uint32_t **out, size_t *n_tri) {
    (void)d; (void)sites;
    if (out) *out = NULL;
    if (n_tri) *n_tri = 0;
    return VOR_EUNAVAILABLE;
}

int vor_diagram_equal(const vor_diagram *p, const vor_diagram *q) {
    return p == q;
}

void vor_diagram_free(vor_diagram *d) {
    if (!d) return;
    free(d->vertex_xy);
    free(d->vertex_sites);
    free(d->edge_sites);
    free(d->edge_ends);
    free(d->ray_edge);
    free(d->ray_dir);
    free(d->cell_start);
    free(d->cell_edges);
    free(d->cell_bounded);
    free(d);
}
