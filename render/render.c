/* Film, tiles, threads, passes, progress and output. */
#include "render/render.h"
#include "common/clock.h"
#include "common/threads.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/image_io.h"
#include "common/progress.h"

#define TILE 16
#define MAX_PASS_SAMPLES 16
#define MAX_PASSES 128

typedef struct job {
    const plm_world *world;
    const plm_render_options *opt;
    plm_film *film;
    double *sum;               /* width * height * 3 running sums */
    int spp, max_depth;
    uint64_t seed;
    double filter_radius; /* pixels; 0: box */
    int tiles_x, tile_count;
    int pass_count;
    int pass_start[MAX_PASSES + 1];        /* first sample index of each pass; pass_start[pass_count] = spp */
    atomic_int next_tile[MAX_PASSES];  /* per pass */
    atomic_llong samples_done;
    atomic_llong rays;
    atomic_llong nonfinite;
    atomic_int stop;           /* set once a cancel was seen: no new tiles */
    atomic_int finished_threads;
    pthread_barrier_t barrier;  /* between passes, for the threads that did start */
    pthread_mutex_t gate_lock;  /* workers wait here until the barrier knows how many they are */
    pthread_cond_t gate;
    int gate_open;
} job;

/* Passes of 1, 1, 2, 4, 8, ... samples per pixel up to a cap: an early full
 * image, then steady work per pass, and never more than MAX_PASSES passes. */
static void plan_passes(job *j)
{
    int cap = j->spp / (MAX_PASSES - 16) > MAX_PASS_SAMPLES ? j->spp / (MAX_PASSES - 16) : MAX_PASS_SAMPLES;
    int n = 0, s = 0, size = 1;
    j->pass_start[0] = 0;
    while (s < j->spp) {
        int step = n == MAX_PASSES - 1 || size > j->spp - s ? j->spp - s : size;
        s += step;
        j->pass_start[++n] = s;
        if (n >= 2)
            size = 2 * size > cap ? cap : 2 * size;
    }
    j->pass_count = n;
}

/* Where within (or around) its pixel a sample lands, from a stratified
 * uniform u: the pixel's square (a box filter), or a tent of the given
 * radius about its centre by inverting the tent's distribution, so samples
 * stay stratified and each keeps weight 1 (filter importance sampling). A box
 * lets through the harmonics of detail a few pixels apart, such as barbs,
 * which fold back as moire; a tent of radius 1 takes them down 5-10 times. */
static double filter_offset(double u, double radius)
{
    if (radius <= 0.0)
        return u;
    double x = u < 0.5 ? sqrt(2.0 * u) - 1.0 : 1.0 - sqrt(2.0 * (1.0 - u));
    return 0.5 + radius * x;
}

static void render_tile(job *j, int tile, int s0, int s1)
{
    const plm_world *w = j->world;
    int width = j->film->width, height = j->film->height;
    int x0 = (tile % j->tiles_x) * TILE, y0 = (tile / j->tiles_x) * TILE;
    long long rays = 0, bad = 0;
    for (int y = y0; y < y0 + TILE && y < height; ++y)
        for (int x = x0; x < x0 + TILE && x < width; ++x) {
            long pixel = (long)y * width + x;
            double *acc = j->sum + 3 * pixel;
            /* The pixel's samples share a sampler key (their stratification), each has a stream of its own. */
            plm_sampler sampler = {plm_hash64(j->seed, (uint64_t)pixel, UINT64_MAX), 0, (uint32_t)j->spp};
            for (int s = s0; s < s1; ++s) {
                plm_rng rng;
                plm_rng_seed(&rng, plm_hash64(j->seed, (uint64_t)pixel, (uint64_t)s), 0);
                sampler.index = (uint32_t)s;
                /* A pinhole camera has no use for the lens pair. */
                vec2 film = plm_sampler_2d(&sampler, PLM_SAMPLE_PIXEL);
                vec2 lens = w->camera.lens_radius > 0.0 ? plm_sampler_2d(&sampler, PLM_SAMPLE_LENS) : v2(0.0, 0.0);
                vec3 o, d;
                plm_camera_ray(&w->camera, x + filter_offset(film.x, j->filter_radius),
                               y + filter_offset(film.y, j->filter_radius), lens.x, lens.y, &o, &d);
                if (j->opt->trace_only) {
                    rays += plm_path_trace_only(w, o, d, j->max_depth, &rng);
                    continue;
                }
                rgb l = plm_path_radiance(w, o, d, j->max_depth, j->opt->estimator, &sampler, &rng, &rays);
                if (!rgb_is_finite(l)) {
                    ++bad;
                    continue;
                }
                acc[0] += l.r, acc[1] += l.g, acc[2] += l.b;
            }
            j->film->samples[pixel] += s1 - s0;
        }
    long long pixels = (long long)(x0 + TILE < width ? TILE : width - x0) * (y0 + TILE < height ? TILE : height - y0);
    atomic_fetch_add(&j->samples_done, pixels * (s1 - s0));
    atomic_fetch_add(&j->rays, rays);
    atomic_fetch_add(&j->nonfinite, bad);
}

static void *worker(void *arg)
{
    job *j = arg;
    pthread_mutex_lock(&j->gate_lock);
    while (!j->gate_open)
        pthread_cond_wait(&j->gate, &j->gate_lock);
    pthread_mutex_unlock(&j->gate_lock);
    for (int p = 0; p < j->pass_count; ++p) {
        for (;;) {
            if (j->opt->cancel && *j->opt->cancel)
                atomic_store(&j->stop, 1);
            if (atomic_load(&j->stop))
                break;
            int tile = atomic_fetch_add(&j->next_tile[p], 1);
            if (tile >= j->tile_count)
                break;
            render_tile(j, tile, j->pass_start[p], j->pass_start[p + 1]);
        }
        /* Passes in order: a pixel's samples are then always summed in index order. */
        pthread_barrier_wait(&j->barrier);
        if (atomic_load(&j->stop))
            break;
    }
    atomic_fetch_add(&j->finished_threads, 1);
    return NULL;
}

static void draw_progress(job *j, plm_progress *progress, double elapsed, int final)
{
    long long total = (long long)j->film->width * j->film->height * j->spp;
    long long done = atomic_load(&j->samples_done);
    double fraction = total ? (double)done / total : 1.0, rate = elapsed > 0 ? done / elapsed : 0.0;
    char detail[48];
    snprintf(detail, sizeof detail, "%.3g samples/s", rate);
    (final ? plm_progress_finish : plm_progress_update)(progress, fraction, detail);
}

plm_result plm_render_world(const plm_world *world, const plm_render_options *opt, plm_film *film,
                            plm_error *err)
{
    const plm_film_desc *fd = &world->scene->film;
    memset(film, 0, sizeof *film);
    /* The film is an image like any other: refused before allocating if over the limit. */
    plm_result rc = plm_image_check_size("film.width x film.height", fd->width, fd->height, 3, err);
    if (rc != PLM_OK)
        return rc;
    film->width = fd->width;
    film->height = fd->height;
    size_t pixels = (size_t)film->width * film->height;
    job *j = calloc(1, sizeof *j);
    film->rgb = calloc(pixels * 3, sizeof *film->rgb);
    film->samples = calloc(pixels, sizeof *film->samples);
    if (j)
        j->sum = calloc(pixels * 3, sizeof *j->sum);
    if (!j || !j->sum || !film->rgb || !film->samples) {
        if (j)
            free(j->sum);
        free(j);
        plm_film_free(film);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a %dx%d film", film->width, film->height);
    }
    j->world = world;
    j->opt = opt;
    j->film = film;
    j->spp = opt->spp > 0 ? opt->spp : fd->spp;
    j->max_depth = opt->max_depth > 0 ? opt->max_depth : (opt->max_depth < 0 ? 0 : fd->max_depth);
    j->seed = opt->seed > 0 ? (uint64_t)opt->seed : (opt->seed < 0 ? 0 : fd->seed);
    j->filter_radius = fd->filter_radius;
    j->tiles_x = (film->width + TILE - 1) / TILE;
    j->tile_count = j->tiles_x * ((film->height + TILE - 1) / TILE);
    plan_passes(j);
    pthread_mutex_init(&j->gate_lock, NULL);
    pthread_cond_init(&j->gate, NULL);

    /* Start the threads, then size the barrier to those that did start and open the gate. */
    double t0 = plm_seconds(), last_draw = t0;
    plm_progress progress;
    if (opt->progress)
        plm_progress_start(&progress, "render");
    plm_threads threads;
    int started = plm_threads_start(&threads, opt->threads, worker, j); /* 0: one per core */
    film->threads = started > 0 ? started : 1;
    pthread_barrier_init(&j->barrier, NULL, (unsigned)film->threads);
    pthread_mutex_lock(&j->gate_lock);
    j->gate_open = 1;
    pthread_cond_broadcast(&j->gate);
    pthread_mutex_unlock(&j->gate_lock);
    if (started == 0) /* no thread at all: render on this one */
        worker(j);
    while (atomic_load(&j->finished_threads) < film->threads) {
        struct timespec nap = {0, 50 * 1000 * 1000};
        nanosleep(&nap, NULL);
        double t = plm_seconds();
        if (opt->progress && t - last_draw >= 0.25) {
            draw_progress(j, &progress, t - t0, 0);
            last_draw = t;
        }
    }
    plm_threads_join(&threads);
    film->seconds = plm_seconds() - t0;
    if (opt->progress)
        draw_progress(j, &progress, film->seconds, 1);
    pthread_barrier_destroy(&j->barrier);
    pthread_cond_destroy(&j->gate);
    pthread_mutex_destroy(&j->gate_lock);

    for (size_t p = 0; p < pixels; ++p)
        for (int c = 0; c < 3; ++c)
            film->rgb[3 * p + c] = film->samples[p] ? (float)(j->sum[3 * p + c] / film->samples[p]) : 0.0f;
    film->sample_count = atomic_load(&j->samples_done);
    film->ray_count = atomic_load(&j->rays);
    film->nonfinite = atomic_load(&j->nonfinite);
    film->interrupted = film->sample_count < (long long)pixels * j->spp;
    free(j->sum);
    free(j);
    return PLM_OK;
}

plm_result plm_render(const plm_scene *scene, const plm_render_options *opt, plm_film *film, plm_error *err)
{
    plm_world world;
    plm_result rc = plm_world_build(scene, &world, err);
    if (rc != PLM_OK)
        return rc;
    rc = plm_render_world(&world, opt, film, err);
    if (rc == PLM_OK && (rc = plm_embree_check(&world.embree, "tracing rays", err)) != PLM_OK)
        plm_film_free(film);
    plm_world_free(&world);
    return rc;
}

void plm_film_free(plm_film *film)
{
    free(film->rgb);
    free(film->samples);
    film->rgb = NULL;
    film->samples = NULL;
}

plm_picture plm_picture_of(const plm_film_desc *f)
{
    plm_picture p = {(plm_view)f->view, f->exposure, f->white_balance};
    return p;
}

plm_result plm_film_write(const plm_film *film, const char *exr_path, const char *png_path,
                          const plm_picture *picture, plm_error *err)
{
    plm_result rc = PLM_OK;
    if (exr_path && exr_path[0])
        rc = plm_image_write(exr_path, film->width, film->height, 3, PLM_PIXEL_FLOAT, film->rgb, err);
    if (rc != PLM_OK || !png_path || !png_path[0])
        return rc;
    size_t pixels = (size_t)film->width * film->height;
    uint8_t *bytes = malloc(3 * pixels);
    if (!bytes)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory", png_path);
    plm_picture_to_srgb8(picture, film->rgb, pixels, bytes);
    rc = plm_image_write(png_path, film->width, film->height, 3, PLM_PIXEL_UINT8, bytes, err);
    free(bytes);
    return rc;
}
