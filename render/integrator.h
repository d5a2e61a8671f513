/* Unidirectional path tracing with next-event estimation, multiple
 * importance sampling (power heuristic) and Russian roulette. Delta
 * transmission is fractional visibility (docs/rendering.md): a ray that meets a
 * surface passes straight on with the material's plm_material_transmission,
 * and shadow rays are attenuated by the same probability. */
#ifndef PLUMAGE_RENDER_INTEGRATOR_H
#define PLUMAGE_RENDER_INTEGRATOR_H

#include "common/rng.h"
#include "common/sampling.h"
#include "render/world.h"

typedef enum plm_estimator {
    PLM_ESTIMATOR_MIS = 0,  /* light and BSDF sampling combined (the default) */
    PLM_ESTIMATOR_NEE = 1,  /* light sampling only (delta lights and smooth BSDFs only) */
    PLM_ESTIMATOR_BSDF = 2  /* BSDF sampling only: emission found by bounce rays (misses delta lights) */
} plm_estimator;

/* The sampler's dimension pairs (common/sampling.h): the camera's, then
 * three per path vertex: its light sample, its BSDF sample's first two
 * numbers, and the passing of the ray that reached it with the BSDF
 * sample's third number. */
enum { PLM_SAMPLE_PIXEL = 0, PLM_SAMPLE_LENS = 1, PLM_SAMPLE_LIGHT = 2, PLM_SAMPLE_BSDF = 3, PLM_SAMPLE_MORE = 4 };
#define PLM_SAMPLE_DIM(what, depth) ((uint32_t)(what) + 3u * (uint32_t)(depth))

/* Radiance arriving at o from direction -d along the ray o + t d.
 * max_depth is the most scattering events a path may have (0: emitters seen
 * directly). The light and BSDF samples and the passing of vanes come from
 * sampler (stratified over a pixel's samples) if it is not NULL, all other
 * random numbers from rng.
 * Adds the number of rays cast (surface and shadow queries) to *rays. */
rgb plm_path_radiance(const plm_world *w, vec3 o, vec3 d, int max_depth, plm_estimator estimator,
                      const plm_sampler *sampler, plm_rng *rng, long long *rays);

/* Rays with no shading at all (cosine bounces off every hit up to
 * max_depth, no lights, no materials, no transmission): the cost of ray
 * traversal alone, for the per-ray shading overhead of `plumage bench
 * render`. Returns the ray count. */
int plm_path_trace_only(const plm_world *w, vec3 o, vec3 d, int max_depth, plm_rng *rng);

/* Fraction of light travelling from p (a surface point, ray already
 * offset) along d that reaches distance dist: 0 behind an opaque surface,
 * the product of the transmissions of the surfaces crossed otherwise.
 * Adds the queries it made to *rays. */
double plm_shadow_transmittance(const plm_world *w, vec3 o, vec3 d, double dist, long long *rays);

#endif
