/* plumage's renderer: a scene in, a film of mean radiance out.
 *
 *   plm_scene scene;  plm_scene_load("scene.json", &scene, &err);   // scene/scene_file.h
 *   plm_render_options opt = {0};            // zero = the scene's settings, all cores
 *   plm_film film;    plm_render(&scene, &opt, &film, &err);
 *   plm_picture pic = plm_picture_of(&scene.film);
 *   plm_film_write(&film, "out.exr", "out.png", &pic, &err);
 *
 * Pixels are split into 16x16 tiles shared by the threads; samples are taken
 * in passes (1, 1, 2, 4, 8, 16, 16, ... per pixel). Each pixel sample draws
 * its random numbers from (seed, pixel, sample index) alone and a pixel's
 * samples are summed in index order, so the image is bit-identical at any
 * thread count. */
#ifndef PLUMAGE_RENDER_RENDER_H
#define PLUMAGE_RENDER_RENDER_H

#include <signal.h>

#include "render/film.h"
#include "render/integrator.h"
#include "render/scene.h"
#include "render/world.h"

typedef struct plm_render_options {
    int threads;       /* 0 = all cores */
    int spp;           /* 0 = the scene's film.spp */
    int max_depth;     /* 0 = the scene's film.max_depth; use -1 to ask for 0 bounces */
    long long seed;    /* 0 = the scene's film.seed; use -1 to ask for seed 0 */
    plm_estimator estimator;
    int progress;      /* draw a progress bar on stderr */
    int trace_only;    /* benchmark: trace the rays, shade nothing (the film stays black) */
    volatile sig_atomic_t *cancel; /* when it becomes non-zero: finish the tiles in flight and stop */
} plm_render_options;

typedef struct plm_film {
    int width, height;
    float *rgb;               /* width * height * 3: mean radiance over the samples taken */
    int *samples;             /* per pixel: samples taken (all spp unless interrupted) */
    long long sample_count;   /* pixel samples taken in all */
    long long ray_count;      /* rays cast (surface and shadow queries) */
    long long nonfinite;      /* samples that were NaN or infinite: counted, then dropped (taken as 0) */
    int interrupted;          /* stopped by *cancel before all samples were taken */
    double seconds;           /* wall clock of the sampling (not the scene build) */
    int threads;
} plm_film;

/* Builds the world and renders it. */
plm_result plm_render(const plm_scene *scene, const plm_render_options *opt, plm_film *film, plm_error *err);
/* Renders an already built world (the benchmark separates build from sampling). */
plm_result plm_render_world(const plm_world *world, const plm_render_options *opt, plm_film *film,
                            plm_error *err);
void plm_film_free(plm_film *film);

/* The picture a scene's film block asks for (view, exposure, white balance). */
plm_picture plm_picture_of(const plm_film_desc *f);
/* Writes the linear EXR and/or the sRGB PNG through `picture` (NULL or "" = skip), each atomically. */
plm_result plm_film_write(const plm_film *film, const char *exr_path, const char *png_path,
                          const plm_picture *picture, plm_error *err);

#endif
