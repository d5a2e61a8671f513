/* plumage bench scene: scene files (by default the paper's Table 2 scenes,
 * the presets), pelts of growing feather counts, and scenes with the near
 * field on and off (docs/nearfield.md), each measured in a child process of
 * its own so that its peak memory is its own: load (generation, layout),
 * world build, samples per second per thread, time per sample and peak
 * resident memory. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli/bench.h"
#include "common/clock.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "cli/outputs.h"
#include "common/memory.h"
#include "render/render.h"
#include "scene/scene_file.h"

typedef struct bench_scene_options {
    int threads, spp;
    double scale; /* of the film resolution */
    const char *images;
    int far_field; /* 0: the scene's film.far_field; 1: near field on; 2: off */
} bench_scene_options;

typedef struct figures {
    int ok, width, height, spp, threads, instances;
    double load, build, seconds, samples_per_thread, us_per_sample, cpu_us_per_sample, peak_mib;
} figures;

/* Loads (file or text), builds, renders; fills f. Runs in the child. */
static void measure(const char *file, const char *text, const char *tag, const bench_scene_options *o, figures *f)
{
    plm_scene scene;
    plm_error err = {{0}};
    double t0 = plm_seconds();
    plm_result rc = text ? plm_scene_load_buffer(text, strlen(text), tag, &scene, &err)
                         : plm_scene_load(file, &scene, &err);
    if (rc != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return;
    }
    scene.film.width = (int)fmax(1.0, round(scene.film.width * o->scale));
    scene.film.height = (int)fmax(1.0, round(scene.film.height * o->scale));
    if (o->far_field)
        scene.film.far_field = o->far_field == 2;
    double t1 = plm_seconds();
    plm_world world;
    if (plm_world_build(&scene, &world, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        plm_scene_free(&scene);
        return;
    }
    double t2 = plm_seconds();
    plm_render_options opt = {0};
    opt.threads = o->threads;
    opt.spp = o->spp;
    plm_film film;
    double cpu0 = plm_cpu_seconds();
    if (plm_render_world(&world, &opt, &film, &err) == PLM_OK) {
        double cpu = plm_cpu_seconds() - cpu0;
        *f = (figures){1, film.width, film.height, o->spp, film.threads, scene.instance_count, t1 - t0, t2 - t1,
                       film.seconds, film.sample_count / film.seconds / film.threads,
                       1e6 * film.seconds * film.threads / (double)film.sample_count,
                       1e6 * cpu / (double)film.sample_count, plm_memory_peak_mib()};
        if (o->images) { /* to look at what was measured */
            char path[4096];
            snprintf(path, sizeof path, "%s_%s.png", o->images, tag);
            plm_picture picture = plm_picture_of(&scene.film);
            if (plm_film_write(&film, NULL, path, &picture, &err) != PLM_OK)
                fprintf(stderr, "error: %s\n", err.message);
            else
                plm_print_wrote((const char *const[]){path}, 1);
        }
        plm_film_free(&film);
    } else
        fprintf(stderr, "error: %s\n", err.message);
    plm_world_free(&world);
    plm_scene_free(&scene);
}

typedef struct scene_job {
    const char *file, *text, *tag;
    const bench_scene_options *o;
} scene_job;

static int measure_job(void *ctx, void *figs)
{
    const scene_job *j = ctx;
    figures *f = figs;
    measure(j->file, j->text, j->tag, j->o, f);
    return f->ok;
}

/* measure() in a child process (plm_bench_in_child), its figures into *out if not NULL. */
static int run_isolated(const char *label, const char *file, const char *text, const char *tag,
                        const bench_scene_options *o, figures *out)
{
    figures f = {0};
    scene_job job = {file, text, tag, o};
    int ok = plm_bench_in_child(measure_job, &job, &f, sizeof f) && f.ok;
    if (out)
        *out = ok ? f : (figures){0};
    if (!ok) {
        printf("%-28s failed\n", label);
        return 1;
    }
    printf("%-28s %4dx%-4d %4d %3d %8d %8.2f %7.2f %8.2f %12.0f %10.2f %10.2f %9.1f\n", label, f.width, f.height,
           f.spp, f.threads, f.instances, f.load, f.build, f.seconds, f.samples_per_thread, f.us_per_sample,
           f.cpu_us_per_sample, f.peak_mib);
    return 0;
}

/* A scene with the near field on, then off (docs/nearfield.md), one after
 * the other, and what the near field costs: CPU time per sample (which
 * other processes on the cores do not inflate) and peak memory. */
static int run_near_far(const char *file, const char *tag, bench_scene_options o)
{
    figures f[2];
    char label[300], name[300];
    for (int k = 0; k < 2; ++k) {
        o.far_field = k + 1;
        snprintf(label, sizeof label, "%.200s %s", tag, k ? "far" : "near");
        snprintf(name, sizeof name, "%.200s_%s", tag, k ? "far" : "near");
        if (run_isolated(label, file, NULL, name, &o, &f[k]) != 0)
            return 1;
    }
    printf("%-28s near field: %+.1f%% CPU time per sample, %+.1f MiB peak memory\n", tag,
           100.0 * (f[0].cpu_us_per_sample / f[1].cpu_us_per_sample - 1.0), f[0].peak_mib - f[1].peak_mib);
    return 0;
}

static void header(void)
{
    printf("%-28s %9s %4s %3s %8s %8s %7s %8s %12s %10s %10s %9s\n", "scene", "film", "spp", "thr", "instances",
           "load_s", "build_s", "render_s", "samples/s/thr", "us/sample", "cpu_us/smp", "peak_mib");
}

/* A pelt of `count` parrot coverts over a plane, seen whole from above. Growing
 * (study i): the plane grows with the count at a fixed density (100 per square
 * unit) and the camera backs away to keep it in frame. Shrinking (ii): a unit
 * plane whose feathers shrink as their number grows. */
static char *pelt_text(const char *species, int count, int growing)
{
    double side = growing ? sqrt(count / 100.0) : 1.0;
    char *text = malloc(4096);
    if (!text)
        return NULL;
    snprintf(text, 4096,
             "{\"camera\": {\"position\": [0, %.6g, %.6g], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0], \"fov\": 40},"
             " \"film\": {\"width\": 256, \"height\": 256, \"spp\": 4, \"max_depth\": 8},"
             " \"lights\": [{\"type\": \"environment\", \"radiance\": [0.4, 0.45, 0.5]},"
             "  {\"type\": \"distant\", \"direction\": [-0.4, 0.5, 1], \"irradiance\": [3, 3, 3]}],"
             " \"materials\": {\"skin\": {\"reflectance\": [0.25, 0.2, 0.17]}},"
             " \"objects\": [{\"layout\": {\"type\": \"pelt\", \"species\": [\"%s\"], \"count\": %d, \"seed\": 1,"
             "  \"surface\": {\"shape\": \"plane\", \"size\": [%.6g, %.6g]}, \"surface_material\": \"skin\","
             "  \"level\": 2, \"texture_size\": 512}}]}",
             -0.15 * side, 1.5 * side, species, count, side, side);
    return text;
}

int bench_scene(int argc, char **argv)
{
    bench_scene_options o = {0, 4, 1.0, NULL, 0};
    int pelts = 0, near_far = 0;
    const char *species = "presets/species/covert_parrot.json";
    plm_option opts[] = {
        {"--threads", PLM_OPT_INT, &o.threads, 0, 1, 1024, NULL, "N", "render threads (default: all cores)", 0},
        {"--spp", PLM_OPT_INT, &o.spp, 0, 1, 65536, NULL, "N", "samples per pixel (default 4)", 0},
        {"--scale", PLM_OPT_DOUBLE, &o.scale, 0, 0.01, 4.0, NULL, "S", "film resolution factor (default 1)", 0},
        {"--pelts", PLM_OPT_FLAG, &pelts, 0, 0, 0, NULL, NULL,
         "instead: pelts of 100, 2,500, 10,000 and 100,000 feathers, (i) growing at a fixed density, "
         "(ii) on one surface with shrinking feathers", 0},
        {"--species", PLM_OPT_STRING, &species, 0, 0, 0, NULL, "FILE",
         "--pelts: the feather (default presets/species/covert_parrot.json)", 0},
        {"--images", PLM_OPT_STRING, &o.images, 0, 0, 0, NULL, "PREFIX", "also write PREFIX_<scene>.png", 0},
        {"--near-far", PLM_OPT_FLAG, &near_far, 0, 0, 0, NULL, NULL,
         "each scene with the near field on and off (film.far_field) and the near field's cost; default scene "
         "presets/scenes/closeup_remex.json (docs/nearfield.md)", 0},
    };
    plm_command_help help = {
        "plumage bench scene [SCENE.json...] [options]",
        "Loads, builds and renders each scene (default: the Table 2 presets in presets/scenes/ at their own "
        "resolution) in a process of its own, and prints load and build seconds, samples per second per "
        "thread, microseconds per sample (wall clock times threads, and CPU time, which other processes on "
        "the same cores do not inflate) and the process's peak resident memory."};
    const char *positional[64];
    int n = 0;
    int rc = plm_parse_options(&help, argc, argv, 1, opts, (int)(sizeof opts / sizeof opts[0]), positional, 64, &n);
    if (rc)
        return rc == 1 ? 0 : 2;
    if (o.images && !plm_images_prefix_ok(o.images))
        return 1;
    int failures = 0;
    header();
    if (pelts) {
        static const int counts[] = {100, 2500, 10000, 100000};
        for (int growing = 1; growing >= 0; --growing)
            for (int i = 0; i < 4; ++i) {
                char label[64], tag[64];
                snprintf(label, sizeof label, "%s pelt %d", growing ? "(i) growing" : "(ii) shrinking", counts[i]);
                snprintf(tag, sizeof tag, "pelt_%s_%d", growing ? "growing" : "shrinking", counts[i]);
                char *text = pelt_text(species, counts[i], growing);
                failures += text ? run_isolated(label, NULL, text, tag, &o, NULL) : 1;
                free(text);
            }
        return failures ? 1 : 0;
    }
    static const char *const table2[] = {"presets/scenes/single_feather.json", "presets/scenes/pelt_2500.json",
                                         "presets/scenes/pelt_82.json", "presets/scenes/ball_496.json"};
    static const char *const closeup[] = {"presets/scenes/closeup_remex.json"};
    const char *const *files = n ? positional : (near_far ? closeup : table2);
    int count = n ? n : (near_far ? 1 : 4);
    for (int i = 0; i < count; ++i) {
        const char *base = strrchr(files[i], '/');
        base = base ? base + 1 : files[i];
        char tag[256];
        snprintf(tag, sizeof tag, "%.*s", (int)(strcspn(base, ".")), base);
        failures += near_far ? run_near_far(files[i], tag, o) : run_isolated(tag, files[i], NULL, tag, &o, NULL);
    }
    return failures ? 1 : 0;
}
