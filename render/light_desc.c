/* Lights as a scene describes them: every type's defaults and the parameter
 * tables the scene reader checks its fields against (docs/scene-format.md). */
#include <stddef.h>
#include <string.h>

#include "render/scene.h"

#define BIG 1e9 /* bound for coordinates, distances and radiance */

plm_light plm_light_default(plm_light_type type)
{
    plm_light l;
    memset(&l, 0, sizeof l);
    l.type = type;
    l.radiance = rgb_gray(1.0);
    l.intensity = 1.0;
    l.visible = 1;
    l.up = v3(0.0, 1.0, 0.0);
    l.sky.sun_elevation = plm_radians(30.0);
    l.sky.turbidity = 3.0;
    l.sky.sun_size = plm_radians(0.53);
    l.sky.sun = 1;
    l.sky.ground_albedo = rgb_gray(0.2);
    l.irradiance = rgb_gray(1.0);
    l.direction = v3(0.0, 1.0, 0.0);
    l.radius = 1.0;
    l.corner = v3(-0.5, 2.0, -0.5);
    l.edge_u = v3(0.0, 0.0, 1.0);
    l.edge_v = v3(1.0, 0.0, 0.0);
    return l;
}

#define INTENSITY                                                                                                  \
    {"intensity", PLM_PARAM_NUMBER, offsetof(plm_light, intensity), 0.0, BIG, "", "multiplies its radiance", 0}
#define UP                                                                                                         \
    {"up", PLM_PARAM_VEC3, offsetof(plm_light, up), -BIG, BIG, "", "the zenith; non-zero", 0}
#define GROUND                                                                                                     \
    {"ground", PLM_PARAM_BOOL, offsetof(plm_light, ground), 0, 1, "",                                            \
     "a ground plane at ground_height that catches the scene's shadows and otherwise shows this light", 0},      \
    {"ground_height", PLM_PARAM_NUMBER, offsetof(plm_light, ground_height), -BIG, BIG, "scene units",           \
     "the ground's height along up", 0}
#define VISIBLE                                                                                                    \
    {"visible", PLM_PARAM_BOOL, offsetof(plm_light, visible), 0, 1, "",                                          \
     "camera rays see it; false: they see black there, while it still lights the scene", 0}

static const plm_param environment_params[] = {
    {"radiance", PLM_PARAM_RGB, offsetof(plm_light, radiance), 0.0, BIG, "",
     "constant sky radiance; with a map, a colour filter over the map", 0},
    INTENSITY,
    {"rotation", PLM_PARAM_ANGLE, offsetof(plm_light, rotation), -360.0, 360.0, "degrees",
     "turns the map about up (positive: from north toward east)", 0},
    UP,
    VISIBLE,
    GROUND,
};
const plm_param_block plm_environment_light_param_block = {
    "environment",
    "light from every direction: constant, or with \"map\" a lat-long image (EXR, HDR; top row toward up, "
    "centre column toward -z)",
    environment_params, PLM_PARAM_COUNT(environment_params)};

static const plm_param sky_params[] = {
    {"sun_elevation", PLM_PARAM_ANGLE, offsetof(plm_light, sky.sun_elevation), 0.0, 90.0, "degrees",
     "the sun's height above the horizon", 0},
    {"sun_azimuth", PLM_PARAM_ANGLE, offsetof(plm_light, sky.sun_azimuth), -360.0, 360.0, "degrees",
     "the sun's bearing from north (-z when up is +y) toward east (+x)", 0},
    {"turbidity", PLM_PARAM_NUMBER, offsetof(plm_light, sky.turbidity), 1.7, 10.0, "",
     "haze: 2 very clear, 3 clear, 6 hazy, 10 the model's limit", 0},
    {"sun", PLM_PARAM_BOOL, offsetof(plm_light, sky.sun), 0, 1, "", "the sun's disk; false: the sky alone", 0},
    {"sun_size", PLM_PARAM_ANGLE, offsetof(plm_light, sky.sun_size), 0.1, 20.0, "degrees",
     "the sun's angular diameter (0.53 real); larger softens shadows, keeping its irradiance", 0},
    {"ground_albedo", PLM_PARAM_RGB, offsetof(plm_light, sky.ground_albedo), 0.0, 1.0, "",
     "below the horizon: a diffuse ground of this albedo lit by the sky and sun", 0},
    {"latitude", PLM_PARAM_ANGLE, offsetof(plm_light, sky.latitude), -90.0, 90.0, "degrees",
     "with time: where the sky is seen from, north positive", 0},
    {"longitude", PLM_PARAM_ANGLE, offsetof(plm_light, sky.longitude), -180.0, 180.0, "degrees",
     "with time: east positive", 0},
    INTENSITY,
    UP,
    VISIBLE,
    GROUND,
};
const plm_param_block plm_sky_light_param_block = {
    "sky", "a clear sky and sun (Preetham et al. 1999); radiance 1 = 39,322 cd/m^2, what saturates a camera at "
           "EV 15 (sunny 16). The sun stands at sun_elevation and sun_azimuth, or where it is seen from latitude "
           "and longitude at \"time\", an ISO 8601 local time with its offset (\"2026-06-21T09:30+02:00\")",
    sky_params, PLM_PARAM_COUNT(sky_params)};

static const plm_param distant_params[] = {
    {"direction", PLM_PARAM_VEC3, offsetof(plm_light, direction), -BIG, BIG, "",
     "toward the light; non-zero (normalised)", 0},
    {"irradiance", PLM_PARAM_RGB, offsetof(plm_light, irradiance), 0.0, BIG, "",
     "on a surface facing the light", 0},
};
const plm_param_block plm_distant_light_param_block = {"distant", "light from one direction, a point-like sun",
                                                       distant_params, PLM_PARAM_COUNT(distant_params)};

static const plm_param sphere_params[] = {
    {"center", PLM_PARAM_VEC3, offsetof(plm_light, center), -BIG, BIG, "scene units", "", 0},
    {"radius", PLM_PARAM_NUMBER, offsetof(plm_light, radius), 1e-6, BIG, "scene units", "", 0},
    {"radiance", PLM_PARAM_RGB, offsetof(plm_light, radiance), 0.0, BIG, "", "leaving its surface", 0},
};
const plm_param_block plm_sphere_light_param_block = {"sphere", "a uniformly emitting sphere", sphere_params,
                                                      PLM_PARAM_COUNT(sphere_params)};

static const plm_param quad_params[] = {
    {"corner", PLM_PARAM_VEC3, offsetof(plm_light, corner), -BIG, BIG, "scene units", "", 0},
    {"edge_u", PLM_PARAM_VEC3, offsetof(plm_light, edge_u), -BIG, BIG, "scene units", "one edge from corner", 0},
    {"edge_v", PLM_PARAM_VEC3, offsetof(plm_light, edge_v), -BIG, BIG, "scene units",
     "the other edge; edge_u x edge_v non-zero", 0},
    {"radiance", PLM_PARAM_RGB, offsetof(plm_light, radiance), 0.0, BIG, "", "emitted toward edge_u x edge_v", 0},
    {"two_sided", PLM_PARAM_BOOL, offsetof(plm_light, two_sided), 0, 1, "", "emits both ways", 0},
};
const plm_param_block plm_quad_light_param_block = {"quad", "a uniformly emitting parallelogram", quad_params,
                                                    PLM_PARAM_COUNT(quad_params)};
