/* A triangle mesh as plain arrays: what the generator produces and the
 * renderer consumes. Files are written through OpenMesh (adapter:
 * common/mesh_io.cpp) and read by plumage's own readers (common/mesh_read.c).
 * Floats, because Embree takes floats. */
#ifndef PLUMAGE_COMMON_MESH_H
#define PLUMAGE_COMMON_MESH_H

#include <stdint.h>
#include "common/error.h"

typedef struct plm_mesh {
    int vertex_count;
    int triangle_count;
    float *positions;  /* 3 per vertex */
    float *normals;    /* 3 per vertex, or NULL */
    float *uvs;        /* 2 per vertex, or NULL; for vanes v runs from base (0) to tip (1) */
    float *tangents;   /* 3 per vertex: unit dP/du, or NULL (then derived from the uvs) */
    float *density;    /* 1 per vertex, or NULL: a relative feather density for pelts (PLY property "density") */
    uint32_t *indices; /* 3 per triangle, counter-clockwise seen from the normal side */
} plm_mesh;

/* Frees the arrays and zeroes the struct. */
void plm_mesh_free(plm_mesh *mesh);

/* Limits of what plm_mesh_read accepts: files of at most 1 GiB, arrays
 * (floats or indices) of at most 2^30 entries. */
#define PLM_MESH_FILE_MAX ((size_t)1 << 30)
#define PLM_MESH_MAX_ELEMENTS (1 << 30)

/* PLY or OBJ by extension (common/mesh_read.c); writes go through OpenMesh. */
plm_result plm_mesh_read(const char *path, plm_mesh *out, plm_error *err);
plm_result plm_mesh_write(const char *path, const plm_mesh *mesh, plm_error *err);

#endif
