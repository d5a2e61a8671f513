/* Catmull-Clark limit surfaces through OpenSubdiv (adapter: subdiv.cpp).
 *
 * A cage is an all-quad control mesh carrying `width` doubles per vertex
 * (position and any other primvar, e.g. uv). Refinement gives a denser quad
 * mesh whose vertices are projected onto the limit surface, with the exact
 * first derivatives there, so normals and tangents are smooth. */
#ifndef PLUMAGE_GENERATE_SUBDIV_H
#define PLUMAGE_GENERATE_SUBDIV_H

#include "common/error.h"

#define PLM_SUBDIV_MAX_WIDTH 8

typedef struct plm_subdiv_cage {
    int vertex_count;
    int quad_count;
    const int *quads; /* 4 vertex indices per quad, counter-clockwise seen from the front */
    int width;        /* doubles per vertex, at most PLM_SUBDIV_MAX_WIDTH */
} plm_subdiv_cage;

typedef struct plm_subdiv_limit {
    int vertex_count, quad_count, width;
    double *value; /* width per vertex: the limit surface */
    double *d1;    /* width per vertex: derivative along one local direction */
    double *d2;    /* width per vertex: along a second, counter-clockwise from d1 */
    int *quads;    /* 4 per quad, same orientation as the cage */
} plm_subdiv_limit;

/* Replaces the targets in `values` (width per cage vertex) by control values
 * whose limit surface passes through the targets at the cage vertices
 * (iterated correction; the residual shrinks geometrically). Returns the
 * largest remaining residual in *residual if not NULL. */
plm_result plm_subdiv_fit(const plm_subdiv_cage *cage, double *values, int iterations, double *residual,
                          plm_error *err);

/* Refines `level` times (1..6) and evaluates the limit at every refined vertex. */
plm_result plm_subdiv_refine(const plm_subdiv_cage *cage, const double *values, int level,
                             plm_subdiv_limit *out, plm_error *err);

void plm_subdiv_limit_free(plm_subdiv_limit *l);

#endif
