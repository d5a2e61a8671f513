/* What the layouts share (private to generate/): the prototypes and their
 * extents, per-feather variation and the instance matrix. The pelt and the
 * ball (layout.c) and the wing (wing.c) build on these. */
#ifndef PLUMAGE_GENERATE_LAYOUT_PARTS_H
#define PLUMAGE_GENERATE_LAYOUT_PARTS_H

#include "common/rng.h"
#include "generate/layout.h"

/* Random streams: one per purpose, so that changing one draw does not shift another. */
enum { PLM_LAYOUT_STREAM_PLACE = 1, PLM_LAYOUT_STREAM_FEATHER = 2, PLM_LAYOUT_STREAM_VARIANT = 3 };

/* What placement needs to know of a prototype: its meshes (feather frame,
 * mm) and its size. The meshes are the level-1 limit surfaces: their
 * vertices lie on the same surfaces as any finer level's. */
typedef struct plm_layout_extent {
    plm_mesh mesh[2];  /* vane, rachis */
    double (*hull)[3]; /* convex hull of the vertices' (y, z): all a tilt about x can bring lowest;
                          third, the squared distance from the origin of a vertex there */
    int hull_count;
    double w_min;      /* the smallest squared distance of any vertex from the origin */
    double length, rachis_radius;
    /* The vane as a height map over the feather frame's (x, y): the highest z
     * of the vane above each cell's centre, -INFINITY where there is none.
     * Feathers settle on the ones beneath them by it (generate/pelt.c). */
    float *top;
    int nx, ny;
    double x0, y0, dx, dy;
    vec3 centre;       /* the vane's bounding sphere */
    double radius;
} plm_layout_extent;

/* The vane's height at feather-frame (x, y); -INFINITY off the vane. */
double plm_layout_height(const plm_layout_extent *e, double x, double y);

void plm_layout_extents_free(plm_layout_extent *e, int n);

/* The prototypes: `variants` per species into out->prototypes, and their
 * extents (freed with plm_layout_extents_free). */
plm_result plm_layout_make_prototypes(const plm_species *const *species, int species_count, int variants, uint64_t seed,
                                      plm_layout *out, plm_layout_extent **extents, plm_error *err);

/* The ranges of per-feather variation, defaults filled in. */
typedef struct plm_layout_ranges {
    double scale, yaw, lift, tint;
} plm_layout_ranges;

plm_layout_ranges plm_layout_ranges_of(const plm_layout_variation *v);

/* Draws a feather's variation (scale, yaw, lift, tint) from its own stream. */
void plm_layout_draw_variation(plm_rng *rng, const plm_layout_ranges *v, plm_layout_instance *in);

/* The instance matrix for a feather frame (X, T, Z) at `origin`, `scale` layout units per mm. */
void plm_layout_set_matrix(plm_layout_instance *in, vec3 x, vec3 t, vec3 z, vec3 origin, double scale);

/* A feather-frame point p taken into layout space by the instance's matrix. */
vec3 plm_layout_apply(const plm_layout_instance *in, const float *p);

#endif
