/* test_bowyer_watson.c -- the Bowyer-Watson Delaunay mesh: every standard point set,
 * degenerate starts (a long collinear prefix in insertion order), sites on
 * hull edges and on the lines through them, sites on interior edges, the
 * degenerate sets in many insertion orders, and the diagram built from the
 * mesh. Each mesh passes vor__mesh_check and, up to 2000 sites, a
 * brute-force empty-circle oracle (tests/core/mesh_oracle.h). */
#include "mesh_oracle.h"

static const mo_algorithm algorithm = {
    "bowyer-watson",
    vor__bowyer_watson_mesh,
    vor__bowyer_watson_mesh_ordered,
    vor__bowyer_watson,
};

int main(void) { return mo_main(&algorithm, "core/bowyer_watson"); }
