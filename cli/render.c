/* plumage render: a scene file in, a linear EXR and a tone-mapped PNG out. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/bench.h"
#include "common/clock.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "cli/outputs.h"
#include "cli/render_job.h"
#include "cli/turntable.h"
#include "common/fileio.h"
#include "common/image_io.h"
#include "common/memory.h"
#include "scene/scene_file.h"

static volatile sig_atomic_t interrupted;

static void on_sigint(int sig)
{
    (void)sig;
    interrupted = 1;
}

/* "dir/name.json" -> "name" + ext, in the working directory. */
static void default_output(const char *scene_path, const char *ext, char *out, size_t size)
{
    const char *base = strrchr(scene_path, '/');
    base = base ? base + 1 : scene_path;
    const char *dot = strrchr(base, '.');
    int len = dot ? (int)(dot - base) : (int)strlen(base);
    snprintf(out, size, "%.*s%s", len, base, ext);
}

/* Outputs: the job's own if it names any; else the scene's film.png/exr; with
 * neither, both named after the scene. */
static void choose_outputs(plm_render_job *job, const plm_film_desc *fd)
{
    if (job->png[0] || job->exr[0])
        return;
    snprintf(job->png, sizeof job->png, "%s", fd->png);
    snprintf(job->exr, sizeof job->exr, "%s", fd->exr);
    if (!job->png[0] && !job->exr[0]) {
        default_output(job->scene, ".png", job->png, sizeof job->png);
        default_output(job->scene, ".exr", job->exr, sizeof job->exr);
    }
}

static int job_failed(plm_render_job *job, const plm_error *err)
{
    snprintf(job->error, sizeof job->error, "%s", err->message);
    fprintf(stderr, "error: %s\n", err->message);
    return 1;
}

/* The job's peak and its parts. The scene's own peak is the larger of the
 * peak before the image library was loaded and the peak after it less the
 * library; a library loaded before the job is part of what the job found. */
static void job_memory(plm_render_job *job, int library_loaded_before)
{
    double added, peak_before;
    plm_image_library_memory(&added, &peak_before);
    if (library_loaded_before)
        added = peak_before = 0.0;
    job->peak_mib = plm_memory_peak_mib();
    job->image_library_mib = added;
    job->scene_mib = fmax(peak_before, job->peak_mib - added) - job->before_mib;
}

/* The resolved scene as rendered: its film says what the job's options
 * changed, and names no output files (re-rendering it must not write over
 * the files it was rendered to; give -o). */
static plm_result write_resolved(const plm_render_job *job, const plm_scene *scene, cJSON *resolved, plm_error *err)
{
    cJSON *film = cJSON_GetObjectItemCaseSensitive(resolved, "film");
    if (!film)
        film = cJSON_AddObjectToObject(resolved, "film");
    const char *const keys[] = {"width", "height", "spp",           "seed", "max_depth", "exposure",
                                "view",  "white_balance", "png", "exr",  NULL};
    for (int k = 0; film && keys[k]; ++k)
        cJSON_DeleteItemFromObjectCaseSensitive(film, keys[k]);
    const plm_film_desc *f = &scene->film;
    int ok = film && cJSON_AddNumberToObject(film, "width", job->width > 0 ? job->width : f->width) &&
             cJSON_AddNumberToObject(film, "height", job->width > 0 ? job->height : f->height) &&
             cJSON_AddNumberToObject(film, "spp", job->spp > 0 ? job->spp : f->spp) &&
             cJSON_AddNumberToObject(film, "seed", job->seed >= 0 ? (double)job->seed : (double)f->seed) &&
             cJSON_AddNumberToObject(film, "max_depth", job->max_depth >= 0 ? job->max_depth : f->max_depth) &&
             cJSON_AddNumberToObject(film, "exposure", job->exposure_given ? job->exposure : f->exposure) &&
             cJSON_AddStringToObject(film, "view", plm_view_names[job->view > 0 ? job->view - 1 : f->view]) &&
             cJSON_AddNumberToObject(film, "white_balance", job->white_balance > 0 ? job->white_balance : f->white_balance);
    char *text = ok ? cJSON_Print(resolved) : NULL;
    if (!text)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory writing %s", job->resolved);
    plm_result rc = plm_write_file(job->resolved, text, strlen(text), err);
    cJSON_free(text);
    return rc;
}

/* A turntable wrote its frames as it went: the job's outputs become the
 * first and last frame and the MP4, as the summary line names them. */
static void describe_sequence(plm_render_job *job, int interrupted, const char *mp4)
{
    const char *named = job->png[0] ? job->png : job->exr;
    char first[PLM_PATH_MAX], last[PLM_PATH_MAX];
    plm_turntable_frame_path(named, 0, job->turntable, first, sizeof first);
    plm_turntable_frame_path(named, job->turntable - 1, job->turntable, last, sizeof last);
    int n = snprintf(job->png, sizeof job->png, "%s%s%s", first, interrupted ? "" : " ... ", interrupted ? "" : last);
    if (n >= (int)sizeof job->png) /* too long to name both: the first will do */
        snprintf(job->png, sizeof job->png, "%s", first);
    snprintf(job->exr, sizeof job->exr, "%s", mp4);
}

int plm_render_job_run(plm_render_job *job)
{
    plm_error err = {{0}};
    plm_scene scene;
    /* Memory: the peak of this job alone, told apart from what the process held before and from the
     * image library, which is loaded when the first image is read or written. */
    plm_memory_reset_peak();
    job->before_mib = plm_memory_resident_mib();
    double library_before, unused;
    plm_image_library_memory(&library_before, &unused);
    double t0 = plm_seconds();
    cJSON *resolved = NULL;
    plm_scene_load_options lo = {job->sets, job->n_sets, job->resolved ? &resolved : NULL, job->asset_dir};
    if (plm_scene_load_ex(job->scene, &lo, &scene, &err) != PLM_OK)
        return job_failed(job, &err);
    plm_result written = resolved ? write_resolved(job, &scene, resolved, &err) : PLM_OK;
    cJSON_Delete(resolved);
    if (written != PLM_OK) {
        plm_scene_free(&scene);
        return job_failed(job, &err);
    }
    if (job->width > 0) {
        scene.film.width = job->width;
        scene.film.height = job->height;
    }
    choose_outputs(job, &scene.film);
    /* The film may name the outputs: checked here, before the render (`plumage render` checked -o and --exr
     * before the scene was read). */
    plm_outputs outputs = {0};
    if ((job->png[0] && !plm_outputs_file(&outputs, "film.png", job->png)) ||
        (job->exr[0] && !plm_outputs_file(&outputs, "film.exr", job->exr))) {
        plm_outputs_undo(&outputs);
        plm_scene_free(&scene);
        snprintf(job->error, sizeof job->error, "cannot write the outputs (see above)");
        return 1;
    }
    plm_render_options ro = {0};
    ro.threads = job->threads;
    ro.spp = job->spp;
    ro.max_depth = job->max_depth < 0 ? 0 : (job->max_depth == 0 ? -1 : job->max_depth);
    ro.seed = job->seed < 0 ? 0 : (job->seed == 0 ? -1 : job->seed);
    ro.estimator = (plm_estimator)job->estimator;
    ro.progress = job->progress;
    ro.cancel = job->cancel;
    plm_picture picture = plm_picture_of(&scene.film);
    if (job->exposure_given)
        picture.exposure = job->exposure;
    if (job->view > 0)
        picture.view = (plm_view)(job->view - 1);
    if (job->white_balance > 0.0)
        picture.white_balance = job->white_balance;
    plm_film film;
    double t1 = plm_seconds();
    char mp4[PLM_PATH_MAX] = "";
    plm_turntable turntable = {job->turntable, job->png, job->exr, 0.0};
    plm_result rendered = job->turntable > 0
                              ? plm_turntable_render(&scene, &ro, &picture, &turntable, &film, mp4, sizeof mp4, &err)
                              : plm_render(&scene, &ro, &film, &err);
    if (rendered != PLM_OK) {
        plm_outputs_undo(&outputs);
        plm_scene_free(&scene);
        return job_failed(job, &err);
    }
    double t2 = plm_seconds();
    int status = 0;
    if (job->turntable > 0)
        describe_sequence(job, film.interrupted, mp4);
    else if (film.interrupted && job->discard_interrupted)
        job->png[0] = job->exr[0] = '\0';
    else if (plm_film_write(&film, job->exr, job->png, &picture, &err) != PLM_OK)
        status = job_failed(job, &err);
    job->load_seconds = t1 - t0;
    job->render_seconds = t2 - t1;
    job->write_seconds = plm_seconds() - t2;
    job->out_width = film.width;
    job->out_height = film.height;
    job->out_spp = job->spp > 0 ? job->spp : scene.film.spp;
    job->out_seed = job->seed >= 0 ? (unsigned long long)job->seed : (unsigned long long)scene.film.seed;
    job->samples = film.sample_count;
    job->nonfinite = film.nonfinite;
    job->interrupted = film.interrupted;
    job->used_threads = film.threads;
    fprintf(stderr, "%s%dx%d, %lld samples in %.2f s on %d threads (%.0f samples/s/thread)\n",
            film.interrupted ? "interrupted: " : "", film.width, film.height, film.sample_count, film.seconds,
            film.threads, film.seconds > 0 ? film.sample_count / film.seconds / film.threads : 0.0);
    if (film.nonfinite)
        fprintf(stderr, "warning: %lld non-finite samples were dropped (counted as black)\n", film.nonfinite);
    else
        fprintf(stderr, "non-finite samples: 0\n");
    job_memory(job, library_before > 0.0);
    fprintf(stderr, "memory: peak %.1f MiB: %.1f at the start, %.1f the image library, %.1f the scene and its "
            "render\n", job->peak_mib, job->before_mib, job->image_library_mib, job->scene_mib);
    if (status) {
        fprintf(stderr, "not written: %s %s\n", job->png, job->exr);
        plm_outputs_undo(&outputs);
    } else if (job->png[0] || job->exr[0]) {
        plm_print_wrote((const char *const[]){job->png, job->exr}, 2);
    }
    plm_film_free(&film);
    plm_scene_free(&scene);
    return status ? status : (job->interrupted ? 130 : 0);
}

int cmd_render(int argc, char **argv)
{
    static const char *const estimators[] = {"mis", "nee", "bsdf", NULL};
    int spp = 0, threads = 0, seed = -1, max_depth = -1, quiet = 0, estimator = 0, view = 0, turntable = 0;
    double exposure = 0.0, white_balance = 0.0;
    const char *png = NULL, *exr = NULL, *resolution = NULL;
    plm_opt_list sets = {{0}, 0};
    plm_option opts[] = {
        {"--spp", PLM_OPT_INT, &spp, 0, 1, 1 << 24, NULL, "N", "samples per pixel (default: the scene's film.spp)", 0},
        {"--resolution", PLM_OPT_STRING, &resolution, 0, 0, 0, NULL, "WxH",
         "image size, each side in [1, 16384] (default: the scene's film.width x film.height)", 0},
        {"--set", PLM_OPT_LIST, &sets, 0, 0, 0, NULL, "PATH=VALUE",
         "change a field of the scene file before it is read, e.g. camera.fov=30 or lights.0.radiance=[1,1,1] "
         "(repeatable; see docs/batch.md)", 0},
        {"--threads", PLM_OPT_INT, &threads, 0, 1, 1024, NULL, "N", "render threads (default: all cores)", 0},
        {"--seed", PLM_OPT_INT, &seed, 0, 0, 2147483647, NULL, "N", "random seed (default: the scene's film.seed)", 0},
        {"--max-depth", PLM_OPT_INT, &max_depth, 0, 0, 1024, NULL, "N",
         "most scattering events per path (default: the scene's film.max_depth)", 0},
        {"-o", PLM_OPT_STRING, &png, 0, 0, 0, NULL, "FILE.png",
         "tone-mapped PNG output (default: film.png, else <scene name>.png); with -o, EXR only if --exr", 0},
        {"--exr", PLM_OPT_STRING, &exr, 0, 0, 0, NULL, "FILE.exr",
         "linear EXR output (default: film.exr, else <scene name>.exr)", 0},
        {"--exposure", PLM_OPT_DOUBLE, &exposure, 0, -30, 30, NULL, "STOPS", "PNG exposure (default: film.exposure)", 0},
        {"--view", PLM_OPT_CHOICE, &view, 0, 0, 0, plm_view_names, "NAME",
         "PNG view transform: filmic or standard, a clamp (default: film.view)", 0},
        {"--white-balance", PLM_OPT_DOUBLE, &white_balance, 0, 1500, 25000, NULL, "KELVIN",
         "PNG: light of a blackbody this hot shows as white (default: film.white_balance)", 0},
        {"--estimator", PLM_OPT_CHOICE, &estimator, 0, 0, 0, estimators, "NAME",
         "mis (default), nee (light sampling only) or bsdf (BSDF sampling only): for validation", 0},
        {"--turntable", PLM_OPT_INT, &turntable, 0, 1, PLM_TURNTABLE_MAX, NULL, "N",
         "N frames with the camera orbiting the subject, numbered after -o (frame.png -> frame_000.png ...), "
         "and an MP4 beside them where ffmpeg is installed", 0},
        {"--quiet", PLM_OPT_FLAG, &quiet, 0, 0, 0, NULL, NULL, "no progress bar", 0},
    };
    const int n_opts = (int)(sizeof opts / sizeof opts[0]);
    plm_command_help help = {
        "plumage render SCENE.json [options]",
        "Renders a scene file (fields: docs/scene-format.md) with a path tracer: next-event estimation,\n"
        "multiple importance sampling, Russian roulette, feathers' delta transmission as fractional visibility.\n"
        "Writes a linear EXR and a tone-mapped sRGB PNG, atomically. Ctrl-C stops early and writes the image\n"
        "rendered so far; the same scene, seed and spp give the same image at any thread count.\n"
        "--set PATH=VALUE changes the scene file before it is read. PATH is the fields' names joined by dots, a\n"
        "number picking an array element from 0; VALUE is JSON, or else a string. A path value (a species, a mesh,\n"
        "a texture) is read from the scene file's folder, as if written in the file:\n"
        "  plumage render presets/scenes/pelt_82.json --set camera.fov=30 --set 'lights.1.irradiance=[4,4,4]'\n"
        "  plumage render presets/scenes/pelt_82.json --set objects.0.layout.species.0=../species/remex_pigeon.json\n"
        "(the first object's layout's first species; ../species/ from presets/scenes/). Output folders are created\n"
        "if missing and checked before any work; the last line names the files written."};
    const char *positional[1];
    int n_positional = 0;
    int rc = plm_parse_options(&help, argc, argv, 1, opts, n_opts, positional, 1, &n_positional);
    if (rc)
        return rc == 1 ? 0 : 2;
    if (n_positional != 1) {
        fprintf(stderr, "error: plumage render needs exactly one scene file (see --help)\n");
        return 2;
    }
    plm_render_job job;
    memset(&job, 0, sizeof job);
    if (resolution && !plm_parse_resolution(resolution, &job.width, &job.height)) {
        fprintf(stderr, "error: --resolution: '%s' must be WxH, each a whole number in [1, 16384]\n", resolution);
        return 2;
    }
    job.scene = positional[0];
    job.sets = sets.items;
    job.n_sets = sets.count;
    job.spp = spp;
    job.threads = threads;
    job.max_depth = max_depth;
    job.seed = seed;
    job.estimator = estimator;
    job.progress = !quiet;
    job.turntable = turntable;
    job.exposure_given = opts[8].seen;
    job.exposure = exposure;
    job.view = opts[9].seen ? view + 1 : 0;
    job.white_balance = white_balance;
    /* -o/--exr replace the scene's outputs: with -o alone, no EXR. */
    if (png || exr) {
        snprintf(job.png, sizeof job.png, "%s", png ? png : "");
        snprintf(job.exr, sizeof job.exr, "%s", exr ? exr : "");
    }
    plm_outputs outputs = {0}; /* given ones: checked before the scene is read */
    if ((png && !plm_outputs_file(&outputs, "-o", png)) || (exr && !plm_outputs_file(&outputs, "--exr", exr))) {
        plm_outputs_undo(&outputs);
        return 1;
    }
    job.cancel = &interrupted;
    struct sigaction sa, old;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigint;
    sa.sa_flags = SA_RESETHAND; /* a second Ctrl-C kills at once */
    sigaction(SIGINT, &sa, &old);
    int status = plm_render_job_run(&job);
    sigaction(SIGINT, &old, NULL);
    if (status == 1)
        plm_outputs_undo(&outputs);
    return status;
}
