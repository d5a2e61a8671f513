/* Scenes built in code, as the tests and `plumage bench render` build them:
 * small constructors for the plain structs of render/scene.h, a ground
 * plane, and feathers lying like tiles on it. One copy serves the unit
 * tests, the slow validations and the benchmarks, so a benchmark measures
 * the scene a test validates. */
#ifndef PLUMAGE_RENDER_SCENE_BUILD_H
#define PLUMAGE_RENDER_SCENE_BUILD_H

#include <stdint.h>

#include "render/scene.h"

/* A diffuse material; transmission is the fraction passing straight through. */
plm_material plm_diffuse_material(const char *name, rgb reflectance, double transmission);
/* Uniform radiance from every direction. */
plm_light plm_constant_sky(rgb radiance);
/* A one-sided parallelogram emitting radiance toward edge_u x edge_v. */
plm_light plm_quad_light(vec3 corner, vec3 edge_u, vec3 edge_v, rgb radiance);

/* Adds an instance of mesh with material (tint 1). Returns its index, or -1
 * when out of memory. */
int plm_scene_add_object(plm_scene *scene, int mesh, int material, plm_xform xform);

/* The transform that lays a quad of plm_shape_quad (the xy plane, normal +z)
 * flat at height y, facing +y. */
plm_xform plm_xform_floor(double y);

/* A size x size diffuse quad in the plane y = 0 facing +y, named "ground".
 * Returns the instance index, or -1 with err set. */
int plm_scene_add_ground(plm_scene *scene, double size, rgb reflectance, plm_error *err);

/* One feather to place: its parts (e.g. vane and rachis) and the scale that
 * makes it about one unit long along +y, the rachis direction. */
typedef struct plm_tile_feather {
    int count;
    int mesh[2], material[2];
    double scale;
} plm_tile_feather;

/* count feathers on a square grid of the given spacing centred on the origin
 * over the ground y = 0, lying almost flat (tilted 0.25-0.35 rad up from it),
 * pointing along -z give or take 0.2 rad, 0.05-0.15 units above the ground so
 * that neighbours overlap like tiles, each tinted a little: all drawn from
 * seed. Returns 0 when out of memory. */
int plm_scene_add_feather_tiles(plm_scene *scene, const plm_tile_feather *feather, int count, double spacing,
                                uint64_t seed);

#endif
