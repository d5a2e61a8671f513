/* The scene prepared for rendering: an Embree scene per mesh prototype, a
 * top-level scene of instances, lights with their sampling tables and the
 * camera. Shared read-only by all render threads. */
#ifndef PLUMAGE_RENDER_WORLD_H
#define PLUMAGE_RENDER_WORLD_H

#include <embree3/rtcore.h>

#include "render/material.h"
#include "render/embree.h"
#include "render/light.h"
#include "render/scene.h"

/* A mesh as Embree sees it, with the texture whose background texels its
 * filter functions remove (NULL: nothing is removed), and whether its
 * material lets light through (then transparent shadow queries pass it);
 * or curves, traced as round linear curves (opaque, no filter). */
typedef struct plm_prototype {
    const plm_mesh *mesh;
    const plm_curves *curves; /* NULL: a triangle mesh */
    const plm_feather_texture *mask;
    int transmissive;
    RTCScene rtc;
    unsigned *triangle; /* Embree primitive -> mesh triangle (triangles all on background are left out), or for
                           curves the first point of the segment */
    vec3 lo, hi;        /* the mesh's bounds */
} plm_prototype;

typedef struct plm_camera {
    vec3 position, right, up, forward; /* right and up scaled to the image plane at distance 1 */
    double lens_radius, focus_distance;
    int width, height;
    double pixel_spread; /* a pixel cone's width per unit distance; 0 = no cone (film.far_field) */
} plm_camera;

/* A shadow catcher: the ground plane of an environment or sky light with
 * "ground" (docs/rendering.md). Camera rays that reach it see the
 * background they would have seen, times the fraction of the lights'
 * irradiance the scene leaves the plane there. */
typedef struct plm_ground {
    int enabled;
    vec3 normal;      /* unit, the light's up */
    double height;    /* the plane: p . normal = height */
    rgb irradiance;   /* the infinite and distant lights' on the plane with nothing in the way */
} plm_ground;

typedef struct plm_world {
    const plm_scene *scene;
    plm_embree embree;
    RTCScene top;
    plm_prototype *prototypes;
    int prototype_count;
    int *instance_prototype; /* per scene instance */
    plm_render_light *lights;
    int light_count;
    int infinite_lights;     /* how many of them are environment lights */
    double *light_cdf;       /* light_count + 1: next-event estimation picks light i with probability
                                light_cdf[i + 1] - light_cdf[i], in proportion to plm_light_power */
    plm_ground ground;
    plm_camera camera;
    vec3 bounds_min, bounds_max;
    double epsilon;          /* ray offset, scaled to the scene */
    int transmissive;        /* some material lets light pass straight (shadow rays must look through it) */
    /* Per scene material: what rendering derives from it (render/material.h),
     * empty where the material shares an earlier one's optics; prepared_of
     * points to its own or that earlier one's. */
    plm_prepared_material *prepared;
    const plm_prepared_material **prepared_of;
    plm_fiber_table_set tables; /* their fiber tables, one per distinct fiber */
} plm_world;

/* Builds everything; the scene must outlive the world. */
plm_result plm_world_build(const plm_scene *scene, plm_world *w, plm_error *err);
void plm_world_free(plm_world *w);

/* Closest surface along o + t d, t in (0, tmax). Fills hit (and *t); returns 0 on a miss. */
int plm_world_intersect(const plm_world *w, vec3 o, vec3 d, double tmax, double *t, plm_hit *hit);
/* The numbers that decide a ray's passing (below): seed and shift, or, if
 * draw is set, draw(arg, &seed, &shift) when the first surface that could
 * let the ray through is met: most rays that escape meet none, and for a
 * stratified sampler the numbers cost more than the rest of a miss. */
typedef struct plm_passing {
    uint64_t seed;
    double shift;
    void (*draw)(void *arg, uint64_t *seed, double *shift);
    void *arg;
} plm_passing;

/* Closest surface along the ray that does not let it pass: each surface
 * with a transmission (toward -d) is passed with that probability, decided
 * by the uniform number hashed from (seed, instance, triangle) plus shift,
 * modulo 1 (a stratified shift, the same for all of a ray's surfaces, keeps
 * each surface's number uniform and independent of the others' as long as
 * the hash is random; docs/rendering.md). This is the delta transmission as
 * fractional visibility in one query. spread: the
 * pixel cone's width per unit distance from o (camera rays: the camera's
 * pixel_spread), 0 for none; near-field shading uses it (docs/nearfield.md). */
int plm_world_intersect_passing(const plm_world *w, vec3 o, vec3 d, double tmax, const plm_passing *passing,
                                double spread, double *t, plm_hit *hit);

/* Fraction of light passing the segment o + t d, t in (0, tmax): 0 if an
 * opaque surface is in the way, else the product of the transmissions of
 * the surfaces crossed (each seen from the segment's origin side: toward -d).
 * One occlusion query whose filters collect the crossings; they are
 * multiplied in order of distance, so the result does not depend on the
 * order Embree finds them in. */
double plm_world_transmittance(const plm_world *w, vec3 o, vec3 d, double tmax);

/* The closest surface along o + t d with t in [tnear, tmax), the masks'
 * background texels removed as for every query: its scene instance and t.
 * No shading state is made (the ID pass, render/visibility.h). Returns 0 on a miss. */
int plm_world_first_hit(const plm_world *w, vec3 o, vec3 d, double tnear, double tmax, int *instance, double *t);

/* A camera as the desc says, for a film of width x height (far_field: no pixel cone). */
void plm_camera_from_desc(const plm_camera_desc *d, int width, int height, int far_field, plm_camera *cam);
/* Where a camera of vertical field of view fov (degrees) looking from
 * direction `from` at the centre of the world's bounds sees all of them. */
vec3 plm_world_frame_position(const plm_world *w, vec3 from, double fov);
/* The camera the world was built with, the automatic framing resolved; and
 * a new camera for the same film (a turntable orbits it between renders). */
plm_camera_desc plm_world_camera_desc(const plm_world *w);
void plm_world_set_camera(plm_world *w, const plm_camera_desc *d);

/* Probability that next-event estimation picks light i. */
static inline double plm_world_light_pick(const plm_world *w, int i) { return w->light_cdf[i + 1] - w->light_cdf[i]; }
/* The light a uniform u in [0, 1) picks (one with a non-zero probability when there is one). */
int plm_world_pick_light(const plm_world *w, double u);

/* Camera ray through film position (x, y) in pixels (top-left origin), lens sample (u1, u2). */
void plm_camera_ray(const plm_camera *c, double x, double y, double u1, double u2, vec3 *o, vec3 *d);

/* A ray origin just off the surface at hit, on the side d leaves toward. */
vec3 plm_world_offset(const plm_world *w, const plm_hit *hit, vec3 d);

#endif
