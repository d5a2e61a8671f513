/* Layouts: where the feathers of a plumage go. A layout turns a few species
 * and its parameters into a list of prototypes (distinct feathers to
 * generate) and a list of instances (a transform, a prototype and the
 * per-feather variation), deterministically from a seed. Layouts know nothing
 * of rendering: whoever renders generates each prototype once
 * (plm_feather_generate) and instances it many times, so memory grows with
 * the number of distinct feathers, not with the number placed.
 *
 *   plm_layout_species sp[1] = {{&covert, 1.0}};
 *   plm_pelt_params p = {0};                      // zero = defaults
 *   p.surface.kind = PLM_SURFACE_PLANE;  p.count = 2500;
 *   plm_layout out;
 *   plm_layout_pelt(&p, sp, 1, &out, &err);       // out.prototypes, out.instances
 *   ...
 *   plm_layout_free(&out);
 *
 * Frames: a prototype lives in the feather frame of generate/species.h
 * (millimetres, rachis along +y from the calamus base at the origin, dorsal
 * +z); an instance's matrix takes it into the layout's space, whose unit is
 * the surface's (pelt), the wing's span unit or the ball's. The wing is
 * generate/wing.h. See docs/layouts.md for the parameters, shingling and the
 * wing's rows. */
#ifndef PLUMAGE_GENERATE_LAYOUT_H
#define PLUMAGE_GENERATE_LAYOUT_H

#include <stdint.h>

#include "common/error.h"
#include "common/mesh.h"
#include "common/vec.h"
#include "generate/species.h"

/* One species a layout may use, with its share of the feathers (pelt and
 * ball mix species by weight; 0 counts as 1). */
typedef struct plm_layout_species {
    const plm_species *species; /* borrowed */
    double weight;
} plm_layout_species;

/* Per-feather variation, each drawn uniformly from the feather's own random
 * stream. Zero fields mean the defaults in brackets; `none` turns all off. */
typedef struct plm_layout_variation {
    double scale; /* size factor in [1 - scale, 1 + scale] [0.1; a pelt's PLM_PELT_SCALE_VARIATION] */
    double yaw;   /* radians about the surface normal in [-yaw, yaw] [6 degrees] */
    double lift;  /* radians of extra elevation in [0, lift] [3 degrees] */
    double tint;  /* colour factor per channel in [1 - tint, 1], mostly shared brightness [0.1] */
    int none;
} plm_layout_variation;

/* A distinct feather to generate: the layout's species `species` with this
 * shape and pigment (a seeded variant of the species' own; optics stay the
 * species'). */
typedef struct plm_layout_prototype {
    int species; /* index into the species the layout was given (wing: a plm_wing_row) */
    int variant;
    plm_shape shape;
    plm_pigment pigment;
} plm_layout_prototype;

typedef struct plm_layout_instance {
    double m[3][4];  /* feather frame (mm) -> layout space: rows of [linear | translation] */
    int prototype;   /* index into the layout's prototypes */
    int row;         /* wing: the plm_wing_row; pelt and ball: -1 */
    int order;       /* stacking order: a larger order lies above a smaller one where they overlap (wing: dorsal
                      * order; pelt and ball: feathers rooted further along the flow lie below, 0 the furthest) */
    double scale;    /* the size factor applied (1 = the nominal size) */
    double yaw;      /* radians, the yaw applied */
    double lift;     /* radians, the elevation above the surface's tangent plane; wing: the pitch it
                        settled at (negative: tip down), see docs/layouts.md */
    rgb tint;        /* multiplies the feather's scattered colour; each channel in (0, 1] */
} plm_layout_instance;

typedef struct plm_layout {
    plm_layout_prototype *prototypes;
    int prototype_count;
    plm_layout_instance *instances;
    int instance_count;
} plm_layout;

void plm_layout_free(plm_layout *layout);

/* ---- Pelt: feathers over a surface ---- */

#define PLM_PELT_SCALE_VARIATION 0.15 /* a pelt's default variation.scale */

typedef enum plm_surface_kind {
    PLM_SURFACE_PLANE = 0,  /* the rectangle |x| <= width/2, |y| <= height/2 in z = 0, normal +z */
    PLM_SURFACE_SPHERE = 1, /* centred at the origin, normal outward */
    PLM_SURFACE_MESH = 2    /* a triangle mesh (e.g. read with plm_mesh_read), normal on the counter-clockwise side */
} plm_surface_kind;

typedef struct plm_surface {
    plm_surface_kind kind;
    double width, height;  /* plane [1, 1] */
    double radius;         /* sphere [1] */
    const plm_mesh *mesh;  /* mesh, borrowed; its vertex tangents, when present, are the flow field */
} plm_surface;

typedef struct plm_pelt_params {
    plm_surface surface;
    int count;             /* feathers; 0 = density x area */
    double density;        /* feathers per square unit when count is 0 [100 / area] */
    vec3 axis;             /* flow: feathers point along this axis projected onto the surface [(0, -1, 0)] */
    double overlap;        /* fraction of each feather's length covered by the feathers behind it [2/3] */
    double feather_length; /* length of a scale-1 feather in layout units [spacing / (1 - overlap)] */
    double elevation;      /* radians between a feather's base and the tangent plane [8 degrees] */
    /* Feathers are smaller toward the head (against the flow) and toward the
     * surface's edges, each relative to the largest (docs/layouts.md): */
    double head_size;      /* the size at the head end of the flow, (0, 1] [0.6] */
    double edge_size;      /* the size at an edge of the surface, (0, 1] [0.6] */
    double edge_width;     /* layout units over which feathers shrink toward an edge [a feather's length] */
    int variants;          /* distinct prototypes per species [4] */
    plm_layout_variation variation;
    uint64_t seed;
} plm_pelt_params;

/* Blue-noise roots over the surface (dart throwing from the seed), each
 * feather along the flow, raised by `elevation` plus its lift, then raised
 * further if any point of the prototype's meshes would go below the surface
 * (exact for plane and sphere, against the root's tangent plane for a mesh);
 * the calamus base sits on the surface, lifted by the rachis radius. */
plm_result plm_layout_pelt(const plm_pelt_params *p, const plm_layout_species *species, int species_count,
                           plm_layout *out, plm_error *err);

/* ---- Feather ball: feathers radiating from a sphere ---- */

typedef struct plm_ball_params {
    int count;             /* [496] */
    double radius;         /* sphere radius [1] */
    double feather_length; /* layout units [2 radius] */
    double spread;         /* radians: feathers lean up to this far from the radial direction [10 degrees] */
    int variants;          /* [4] */
    plm_layout_variation variation;
    uint64_t seed;
} plm_ball_params;

plm_result plm_layout_ball(const plm_ball_params *p, const plm_layout_species *species, int species_count,
                           plm_layout *out, plm_error *err);

/* A seeded variant of a species (widths, bends, barb angles, splits and the
 * pigment seed jittered a little, still valid); variant 0 is the species itself. */
void plm_species_variant(const plm_species *base, int variant, uint64_t seed, plm_shape *shape,
                         plm_pigment *pigment);

#endif
