/* Lights prepared for rendering: sampling toward a point (next-event
 * estimation), the density of that sampling for a given direction (multiple
 * importance sampling) and the radiance a ray finds when it hits or escapes
 * to a light. Area lights are analytic shapes outside the Embree scene; every
 * ray stops at them (the integrator tests them beside each Embree query), so
 * a light hides what lies behind it, other lights included. */
#ifndef PLUMAGE_RENDER_LIGHT_H
#define PLUMAGE_RENDER_LIGHT_H

#include "common/error.h"
#include "common/vec.h"
#include "common/sampling.h"
#include "render/scene.h"

/* An environment map's importance sampling: a 2D piecewise-constant density
 * over the lat-long image proportional to luminance * sin(theta). */
typedef struct plm_envmap {
    const plm_image *image;
    double *marginal_cdf;            /* height + 1 */
    double *conditional_cdf;         /* height * (width + 1) */
    int *marginal_guide;             /* height */
    int *conditional_guide;          /* height * width */
    plm_distribution1d marginal;     /* over rows */
    plm_distribution1d *conditional; /* one per row, over columns */
} plm_envmap;

typedef struct plm_render_light {
    const plm_light *desc;
    plm_envmap env;         /* env map only */
    vec3 normal;            /* quad: unit edge_u x edge_v */
    double area;            /* quad */
} plm_render_light;

typedef struct plm_light_sample {
    vec3 wi;       /* unit, from the point toward the light */
    double dist;   /* distance to the sampled point; INFINITY for env and distant lights */
    rgb radiance;  /* arriving along -wi (irradiance for the distant light) */
    double pdf;    /* solid angle; for the distant light 1 (a delta) */
    int is_delta;
} plm_light_sample;

plm_result plm_render_light_init(const plm_light *desc, plm_render_light *out, plm_error *err);
void plm_render_light_free(plm_render_light *l);

/* Samples a direction from p toward the light. Returns 0 if the light is not visible from p. */
int plm_light_sample_from(const plm_render_light *l, vec3 p, double u1, double u2, plm_light_sample *s);
/* Solid-angle density of plm_light_sample_from for the direction wi from p (0 for delta lights). */
double plm_light_pdf(const plm_render_light *l, vec3 p, vec3 wi);

/* Radiance toward -d of an infinite light (constant or env map) seen along d,
 * and if pdf is not NULL plm_light_pdf of d from the same lookup. */
rgb plm_light_environment(const plm_render_light *l, vec3 d, double *pdf);
static inline int plm_light_is_infinite(const plm_render_light *l)
{
    return l->desc->type == PLM_LIGHT_CONSTANT_ENV || l->desc->type == PLM_LIGHT_ENV_MAP;
}
/* An area light hit by the ray o + t d with t in (0, tmax): returns 1 and
 * sets *t and the radiance leaving the light toward -d. */
int plm_light_intersect(const plm_render_light *l, vec3 o, vec3 d, double tmax, double *t, rgb *radiance);

/* Env map lookup conventions: direction <-> (u, v) in [0,1]^2, v = 0 is +y (the top row). */
vec2 plm_envmap_uv(double rotation, vec3 d);
vec3 plm_envmap_direction(double rotation, vec2 uv);

#endif
