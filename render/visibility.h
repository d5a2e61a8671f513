/* The ID pass: for every camera ray, which placed feather, which part of it
 * (vane, rachis, fluffy base, body, other; render/scene.h's plm_part) and
 * where along the feather the ray ends, and which feathers it crossed on
 * its way. From it, what plumage is judged by: the fraction of each
 * feather's projected area that the camera sees, where on the feather the
 * seen part lies, and how many rays end on bare skin.
 *
 *   plm_world w;        plm_world_build(&scene, &w, &err);
 *   plm_visibility vis; plm_visibility_trace(&w, &w.camera, &vis, &err);
 *   vis.feathers[id].seen / (double)vis.feathers[id].crossed   // visible fraction of feather id
 *   plm_visibility_free(&vis);
 *
 * One ray through each pixel centre (a pinhole at the camera's position). A
 * feather's projected area is counted in rays: those that cross it anywhere,
 * whatever lies in front (the ray is followed through every surface, the
 * masks' background texels removed as in rendering); its visible area is the
 * rays that end on it. docs/layouts.md gives the figures measured with it. */
#ifndef PLUMAGE_RENDER_VISIBILITY_H
#define PLUMAGE_RENDER_VISIBILITY_H

#include "render/world.h"

/* The most surfaces one ray is followed through; deeper ones are not counted. */
#define PLM_VISIBILITY_MAX_LAYERS 256

typedef struct plm_feather_view {
    int crossed;       /* rays crossing the feather anywhere: its projected area, in rays */
    int seen;          /* rays ending on it */
    int seen_proximal; /* of those, rays ending on its proximal half (v < 0.5) */
    int on_border;     /* crossed by a ray through the image's outermost pixels: partly off-screen */
    float v_min;       /* the lowest v at which a ray ends on it; 2 if none does */
} plm_feather_view;

typedef struct plm_visibility {
    int width, height;
    /* Per pixel, rows from the top: */
    int *instance;       /* the scene instance the ray ends on; -1: it escapes */
    int *feather;        /* that instance's feather (1..feather_count); 0: none */
    unsigned char *part; /* its plm_part (PLM_PART_OTHER where the ray escapes) */
    float *v;            /* where along the feather it ends: the hit's coordinate along the instance's
                            object +y over the feather's extent there (its parts' largest), 0 at the
                            calamus base, 1 at the tip (feather frame, generate/species.h); -1 where
                            the ray escapes */
    int feather_count;          /* the scene's */
    plm_feather_view *feathers; /* indexed by feather id, 1..feather_count (entry 0 unused) */
    long long rays, hits;       /* hits: rays that end on a surface */
    long long part_hits[PLM_PART_COUNT];
    long long crossings;        /* surfaces crossed by all rays together */
    int deepest;                /* most surfaces one ray crossed */
} plm_visibility;

/* Traces the ID pass through the camera (any plm_camera: the world's own,
 * or one from plm_camera_from_desc). */
plm_result plm_visibility_trace(const plm_world *w, const plm_camera *camera, plm_visibility *out, plm_error *err);
void plm_visibility_free(plm_visibility *v);

/* Over the feathers entirely on screen (not on the border) whose projected
 * area is at least min_rays rays: */
typedef struct plm_visibility_summary {
    int feathers;
    double median, p90, max;   /* of the visible fraction seen / crossed */
    int proximal_feathers;     /* feathers of which some ray sees the proximal half */
    long long proximal_rays;   /* rays that do, over the rays ending on those feathers (seen_rays) */
    long long seen_rays;
    double body;               /* rays ending on the body over the rays that end on anything (all feathers) */
} plm_visibility_summary;

plm_result plm_visibility_summarise(const plm_visibility *v, int min_rays, plm_visibility_summary *s,
                                    plm_error *err);

/* Vanes that pass through one another, found by rays: a grid of nu x nv
 * parallel rays along `dir`, starting at origin + (i + 0.5)/nu u + (j + 0.5)/nv v,
 * each followed through every surface until it meets the body. Two feathers'
 * vanes pass through each other when some ray crosses the first before the
 * second and another the second before the first, each time more than
 * `tolerance` apart along the ray (closer, they touch: a feather resting on
 * another). For sheets that each lie over the grid's plane once, as a
 * pelt's feathers do seen along the surface normal, this is exact up to the
 * grid's spacing. */
typedef struct plm_crossing_grid {
    vec3 origin, u, v, dir;
    int nu, nv;
    double tolerance;
} plm_crossing_grid;

typedef struct plm_crossings {
    long long rays, ordered; /* rays traced; feather pairs seen in some order (each order once) */
    int pairs;               /* feather pairs seen in both orders: passing through each other */
    int example[2];          /* one such pair's feather ids (0 0 if none) */
} plm_crossings;

plm_result plm_visibility_crossings(const plm_world *w, const plm_crossing_grid *g, plm_crossings *out,
                                    plm_error *err);

/* n directions spread evenly over the sphere (a Fibonacci spiral), unit vectors. */
vec3 plm_visibility_direction(int i, int n);

/* A pinhole camera of vertical field of view fov (degrees) framing the whole
 * world from direction `from` (a unit vector from the world's centre toward
 * the eye), for a width x height film. */
plm_camera plm_visibility_camera(const plm_world *w, vec3 from, int width, int height, double fov);

#endif
