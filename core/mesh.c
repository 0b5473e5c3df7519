/* mesh.c -- the Delaunay mesh shared by Bowyer-Watson and flipping
 * (placeholder: the real construction helpers and checker follow). */
#include <stdio.h>
#include <stdlib.h>

#include "internal.h"

void vor__mesh_clear(vor__mesh *m) {
    if (!m)
        return;
    free(m->tri);
    free(m->adj);
    m->tri = NULL;
    m->adj = NULL;
    m->n_tri = 0;
    m->cap_tri = 0;
}

int vor__mesh_check(const vor__mesh *m, const vor_sites *s, char *msg,
                    size_t msg_size) {
    (void)m;
    (void)s;
    if (msg && msg_size)
        snprintf(msg, msg_size, "mesh checker not available yet");
    return 1;
}
