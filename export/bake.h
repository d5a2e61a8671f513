/* The far-field colour of plumage's materials for tools that know only a
 * base colour and an alpha: what a surface looks like under uniform white
 * light (a white furnace), measured with the renderer's own BSDF
 * (render/material.h).
 *
 * Under radiance 1 from every direction a surface seen from wo sends back
 *   L(wo) = w_t(wo) + (1 - w_t(wo)) A(wo),
 * w_t the light passing straight through and A the directional albedo of
 * the rest (the BSDF integrated over the whole sphere of wi, front and back).
 * A viewer that blends a base colour C with alpha a over a white background
 * shows a C + (1 - a). Averaged over views (cosine-weighted over the dorsal
 * hemisphere, +n), a = 1 - <w_t> and C = <(1 - w_t) A> / a make the two
 * equal: the colour matches plumage's render at a distance, where the barbs
 * are not resolved. The average over views is over all azimuths, so it does
 * not depend on which way the barbs run: one value per feather optics, which
 * the pigment image and the instances' tints then scale texel by texel
 * (docs/assets.md).
 *
 * A fiber (a feather's fluff, drawn as lines) is baked the same way with
 * its fiber BCSDF across a fiber along +x: w_t = 0, and the views are
 * uniform over the sphere weighted by the width the fiber shows from each,
 * |wo x axis|, the mix a tuft of fibers lying every which way sends back. */
#ifndef PLUMAGE_EXPORT_BAKE_H
#define PLUMAGE_EXPORT_BAKE_H

#include <stdint.h>

#include "common/error.h"
#include "common/vec.h"
#include "render/material.h"
#include "render/scene.h"

/* The furnace seen from one direction. */
typedef struct plm_bake_view {
    double transmission; /* w_t(wo) */
    rgb albedo;          /* A(wo) */
    rgb radiance;        /* L(wo) */
    double radiance_se;  /* standard error of L's channel mean */
} plm_bake_view;

typedef struct plm_bake_albedo {
    rgb colour;       /* C: the base colour, linear */
    double alpha;     /* a */
    double colour_se; /* standard error of C's channel mean */
} plm_bake_albedo;

/* How finely: views x views stratified directions, samples BSDF samples at each. */
typedef struct plm_bake_options {
    int views;    /* 0 = 24 */
    int samples;  /* 0 = 64 */
    uint64_t seed;
} plm_bake_options;

/* L(wo) of the material on a plane with normal +z (u along +x, v along +y)
 * at a vane texel of its texture; a diffuse material is the same everywhere.
 * wo unit. p is what m derives (plm_material_prepare): a feather material's
 * fiber tables are used if built (plm_material_prepare_tables), else its
 * stochastic estimator. */
plm_result plm_bake_view_at(const plm_material *m, const plm_prepared_material *p, vec3 wo, int samples,
                            uint64_t seed, plm_bake_view *out, plm_error *err);

/* C and a as above (a fiber: a = 1), with p as for plm_bake_view_at: a fiber
 * material's table is used if built, else its stochastic estimator. For a diffuse or coat material: its
 * reflectance and 1 - its transmission. */
plm_result plm_bake_albedo_of(const plm_material *m, const plm_prepared_material *p, const plm_bake_options *o,
                              plm_bake_albedo *out, plm_error *err);

#endif
