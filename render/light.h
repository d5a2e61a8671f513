/* Lights prepared for rendering: sampling toward a point (next-event
 * estimation), the density of that sampling for a given direction (multiple
 * importance sampling) and the radiance a ray finds when it hits or escapes
 * to a light. Area lights are analytic shapes outside the Embree scene; every
 * ray stops at them (the integrator tests them beside each Embree query), so
 * a light hides what lies behind it, other lights included.
 *
 * Environment maps and the sky are infinite lights in a frame of their own
 * (y their zenith, -z the map's centre column or north). A map's radiance is
 * bilinear between texel centres; both are importance sampled by a 2D
 * piecewise-constant density over a lat-long grid proportional to luminance
 * times sin(theta) (a map's texels, smoothed so that the density covers
 * everywhere the bilinear radiance is not zero); the sky adds its sun's disk,
 * sampled uniformly in its cone, as a second technique of the same light. */
#ifndef PLUMAGE_RENDER_LIGHT_H
#define PLUMAGE_RENDER_LIGHT_H

#include "common/error.h"
#include "common/vec.h"
#include "common/sampling.h"
#include "render/scene.h"
#include "render/sky.h"

/* A 2D piecewise-constant density over a width x height lat-long grid. */
typedef struct plm_envmap {
    int width, height;
    double *marginal_cdf;            /* height + 1 */
    double *conditional_cdf;         /* height * (width + 1) */
    int *marginal_guide;             /* height */
    int *conditional_guide;          /* height * width */
    plm_distribution1d marginal;     /* over rows */
    plm_distribution1d *conditional; /* one per row, over columns */
    double integral;                 /* of the weights' luminance over the sphere (before sin(theta)) */
} plm_envmap;

typedef struct plm_render_light {
    const plm_light *desc;
    rgb scale;              /* env map, sky: radiance (filter) times intensity; sky: per cd/m^2 */
    frame axes;             /* env map, sky: the light's frame (x east, y zenith, z south) in world space */
    plm_envmap env;         /* env map, sky: the grid density */
    plm_sky_model sky;      /* sky */
    double sun_pick;        /* sky: probability that a sample is drawn from the sun's disk */
    vec3 normal;            /* quad: unit edge_u x edge_v */
    double area;            /* quad */
    double power;           /* what light selection weighs it by (plm_light_power) */
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

/* Radiance toward -d of an infinite light (constant, env map or sky) seen
 * along d, and if pdf is not NULL plm_light_pdf of d from the same lookup. */
rgb plm_light_environment(const plm_render_light *l, vec3 d, double *pdf);
static inline int plm_light_is_infinite(const plm_render_light *l)
{
    plm_light_type t = l->desc->type;
    return t == PLM_LIGHT_CONSTANT_ENV || t == PLM_LIGHT_ENV_MAP || t == PLM_LIGHT_SKY;
}
/* An area light hit by the ray o + t d with t in (0, tmax): returns 1 and
 * sets *t and the radiance leaving the light toward -d. */
int plm_light_intersect(const plm_render_light *l, vec3 o, vec3 d, double tmax, double *t, rgb *radiance);

/* How much light it brings a scene whose bounds' centre is `centre`, in
 * luminance, for choosing among lights (only the ratios matter): the
 * irradiance it gives a surface facing it, for an infinite light its
 * radiance over the sphere over 4 (pi L for a constant sky); an area light's
 * radiance times the solid angle it fills seen from the centre. */
double plm_light_power(const plm_render_light *l, vec3 centre);

/* The irradiance (RGB) an infinite or distant light gives a plane facing n
 * (unit) with nothing in the way: a map's texels and the sky's grid summed
 * with their solid angles and cosines, the sky's sun and a distant light in
 * closed form; 0 for area lights. */
rgb plm_light_irradiance(const plm_render_light *l, vec3 n);

/* Lat-long conventions in a light's frame: direction <-> (u, v) in [0,1]^2,
 * v = 0 toward the zenith (the top row), u = 0.5 toward -z (north). */
vec2 plm_envmap_uv(const frame *axes, vec3 d);
vec3 plm_envmap_direction(const frame *axes, vec2 uv);
/* The frame whose zenith is up (unit) and whose north is -z turned by the
 * least rotation that takes +y to up, then by `rotation` about up. */
frame plm_light_axes(vec3 up, double rotation);

#endif
