/* plumage bench generate: milliseconds and memory to build feathers in
 * memory, single thread: one species in detail (meshes at the default level,
 * the textures, the fluff, each alone), then every preset with its fluff;
 * and the single-feather scene rendered with and without its fluff. */
#include <dirent.h>
#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/bench.h"
#include "common/clock.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "common/memory.h"
#include "generate/fluff.h"
#include "render/render.h"
#include "scene/scene_file.h"
#include "texture/feather.h"

static double median(double *v, int n)
{
    for (int i = 1; i < n; ++i) /* insertion sort: a handful of values */
        for (int j = i; j > 0 && v[j] < v[j - 1]; --j) {
            double t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* What one generation measured: median wall and thread-CPU milliseconds,
 * the feather's arrays (meshes, textures, fluff) and the resident memory
 * the generation added at its peak, in MiB. */
typedef struct generation {
    double ms[2];
    double arrays_mib, fluff_kib, peak_mib;
    int curves, points;
} generation;

static double mesh_bytes(const plm_mesh *m)
{
    int floats = 3 + 3 * (m->normals != NULL) + 2 * (m->uvs != NULL) + 3 * (m->tangents != NULL);
    return 4.0 * ((double)floats * m->vertex_count + 3.0 * m->triangle_count);
}

static double image_bytes(const plm_image *i) { return i->pixels ? 4.0 * i->width * i->height * i->channels : 0.0; }

static int time_generation(const plm_species *sp, const plm_feather_options *fo, int runs, generation *g)
{
    double wall[64] = {0}, cpu[64] = {0};
    for (int r = 0; r < runs; ++r) {
        plm_feather f;
        plm_error err;
        malloc_trim(0);
        double start = plm_memory_resident_mib();
        plm_memory_reset_peak();
        double t0 = plm_seconds(), c0 = plm_thread_seconds();
        if (plm_feather_generate(sp, fo, &f, &err) != PLM_OK) {
            fprintf(stderr, "error: %s\n", err.message);
            return 0;
        }
        wall[r] = 1e3 * (plm_seconds() - t0);
        cpu[r] = 1e3 * (plm_thread_seconds() - c0);
        g->peak_mib = plm_memory_peak_mib() - start;
        double bytes = mesh_bytes(&f.vane) + mesh_bytes(&f.rachis) + image_bytes(&f.texture) + image_bytes(&f.barb) +
                       image_bytes(&f.pigment) + (double)plm_curves_bytes(&f.fluff);
        g->arrays_mib = bytes / (1024.0 * 1024.0);
        g->fluff_kib = (double)plm_curves_bytes(&f.fluff) / 1024.0;
        g->curves = f.fluff.curve_count;
        g->points = f.fluff.point_count;
        plm_feather_free(&f);
    }
    g->ms[0] = median(wall, runs);
    g->ms[1] = median(cpu, runs);
    return 1;
}

/* Median thread-CPU milliseconds of the fluff alone (its outline prepared once). */
static double time_fluff(const plm_species *sp, int runs)
{
    plm_outline o;
    double cpu[64] = {0};
    if (plm_outline_init(&o, &sp->shape, sp->name, NULL) != PLM_OK)
        return NAN;
    for (int r = 0; r < runs; ++r) {
        plm_curves c;
        double c0 = plm_thread_seconds();
        plm_result rc = plm_fluff_curves(&o, &c, NULL);
        cpu[r] = 1e3 * (plm_thread_seconds() - c0);
        plm_curves_free(&c);
        if (rc != PLM_OK)
            return NAN;
    }
    return median(cpu, runs);
}

/* One species in detail: everything, without the pigment image, meshes
 * (with the fluff) alone, textures alone, the fluff alone. */
static int detail(const char *species, const plm_feather_options *all, int runs)
{
    plm_species sp;
    plm_error err;
    if (plm_species_load(species, &sp, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 0;
    }
    plm_feather_options parts[4] = {*all, *all, *all, *all};
    parts[1].no_pigment = 1;  /* the feather texture is what the renderer needs */
    parts[2].no_textures = 1; /* meshes and fluff alone */
    parts[3].no_meshes = 1;   /* textures alone */
    static const char *const names[4] = {"generate", "generate_no_pigment", "meshes", "textures"};
    generation g[4];
    int ok = time_generation(&sp, all, 1, &g[0]); /* warm-up */
    for (int k = 0; k < 4 && ok; ++k)
        ok = time_generation(&sp, &parts[k], runs, &g[k]);
    double fluff = ok ? time_fluff(&sp, runs) : NAN;
    plm_species_free(&sp);
    if (!ok)
        return 0;
    printf("species %s, level %d, textures %dx%d, median of %d runs, 1 thread (wall and thread CPU)\n", species,
           all->level, all->texture_width, all->texture_height, runs);
    for (int k = 0; k < 4; ++k)
        printf("%s_ms %.2f cpu_ms %.2f\n", names[k], g[k].ms[0], g[k].ms[1]);
    printf("fluff_cpu_ms %.2f curves %d points %d fluff_kib %.1f\n", fluff, g[0].curves, g[0].points, g[0].fluff_kib);
    return 1;
}

static int by_name(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* Every species preset (*.json in dir, by name) with its fluff. */
static int every_preset(const char *dir, const plm_feather_options *all, int runs)
{
    DIR *d = opendir(dir);
    if (!d) {
        fprintf(stderr, "error: %s: cannot read the folder\n", dir);
        return 0;
    }
    char *names[256];
    int n = 0;
    for (struct dirent *e = readdir(d); e && n < 256; e = readdir(d)) {
        size_t len = strlen(e->d_name);
        if (len > 5 && strcmp(e->d_name + len - 5, ".json") == 0)
            names[n++] = strdup(e->d_name);
    }
    closedir(d);
    qsort(names, (size_t)n, sizeof *names, by_name);
    printf("\n%-22s %9s %9s %9s %7s %8s %9s %10s %9s\n", "preset", "gen_ms", "cpu_ms", "fluff_ms", "curves", "points",
           "fluff_kib", "arrays_mib", "peak_mib");
    int ok = 1;
    for (int i = 0; i < n; ++i) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        plm_species sp;
        plm_error err;
        generation g;
        if (ok && plm_species_load(path, &sp, &err) != PLM_OK) {
            fprintf(stderr, "error: %s\n", err.message);
            ok = 0;
        }
        if (ok && (ok = time_generation(&sp, all, runs, &g)))
            printf("%-22.*s %9.2f %9.2f %9.3f %7d %8d %9.1f %10.2f %9.1f\n", (int)strlen(names[i]) - 5, names[i],
                   g.ms[0], g.ms[1], time_fluff(&sp, runs), g.curves, g.points, g.fluff_kib, g.arrays_mib, g.peak_mib);
        if (ok)
            plm_species_free(&sp);
        free(names[i]);
    }
    return ok;
}

static int count_fluff(const plm_scene *s)
{
    int n = 0;
    for (int i = 0; i < s->instance_count; ++i)
        n += s->instances[i].part == PLM_PART_FLUFF;
    return n;
}

/* The scene rendered without its fluff's instances, then with them (the
 * fluff's table is built for the second alone): samples per second per
 * thread and the peak resident memory of each render (world and film). */
static int render_both(const char *file, int spp, int threads, int width)
{
    plm_scene scene;
    plm_error err;
    if (plm_scene_load(file, &scene, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 0;
    }
    if (width > 0) {
        scene.film.height = (int)fmax(1.0, round((double)scene.film.height * width / scene.film.width));
        scene.film.width = width;
    }
    printf("\nscene %s, %dx%d, %d spp, %d threads\n", file, scene.film.width, scene.film.height, spp, threads);
    int all = scene.instance_count, ok = 1;
    plm_instance *instances = malloc(sizeof *instances * (size_t)(all + 1));
    if (!instances) {
        plm_scene_free(&scene);
        return 0;
    }
    memcpy(instances, scene.instances, sizeof *instances * (size_t)all);
    double rate[2] = {0.0, 0.0};
    for (int k = 0; k < 2 && ok; ++k) {
        scene.instance_count = 0; /* without the fluff's instances, then all of them */
        for (int i = 0; i < all; ++i)
            if (k == 1 || instances[i].part != PLM_PART_FLUFF)
                scene.instances[scene.instance_count++] = instances[i];
        malloc_trim(0);
        plm_memory_reset_peak();
        plm_render_options o = {.threads = threads, .spp = spp};
        plm_film film;
        if (!(ok = plm_render(&scene, &o, &film, &err) == PLM_OK)) {
            fprintf(stderr, "error: %s\n", err.message);
            break;
        }
        rate[k] = film.sample_count / film.seconds / film.threads;
        printf("%s instances %d fluff_instances %d seconds %.2f samples_per_s_thread %.0f peak_mib %.1f\n",
               k ? "with_fluff" : "without_fluff", scene.instance_count, count_fluff(&scene), film.seconds, rate[k],
               plm_memory_peak_mib());
        plm_film_free(&film);
    }
    if (ok)
        printf("with_over_without_speed %.3f\n", rate[1] / rate[0]);
    free(instances);
    plm_scene_free(&scene);
    return ok;
}

int bench_generate(int argc, char **argv)
{
    double start_mib = plm_memory_resident_mib();
    const char *species = "presets/species/remex_pigeon.json", *presets = "presets/species";
    const char *scene = "presets/scenes/single_feather.json";
    int runs = 7, size = 1024, level = PLM_FEATHER_DEFAULT_LEVEL, spp = 16, threads = 2, width = 0;
    int no_presets = 0, no_render = 0;
    plm_option opts[] = {
        {"--species", PLM_OPT_STRING, &species, 0, 0, 0, NULL, "FILE",
         "species timed in detail (default presets/species/remex_pigeon.json, from the repository root)", 0},
        {"--presets", PLM_OPT_STRING, &presets, 0, 0, 0, NULL, "DIR",
         "folder of species presets timed with their fluff (default presets/species)", 0},
        {"--runs", PLM_OPT_INT, &runs, 0, 1, 64, NULL, "N", "timed runs; the median is reported (default 7)", 0},
        {"--texture-size", PLM_OPT_INT, &size, 0, 8, 16384, NULL, "N", "texture width and height (default 1024)", 0},
        {"--level", PLM_OPT_INT, &level, 0, 1, 6, NULL, "N", "subdivision level (default 3)", 0},
        {"--scene", PLM_OPT_STRING, &scene, 0, 0, 0, NULL, "FILE",
         "scene rendered with and without its fluff (default presets/scenes/single_feather.json)", 0},
        {"--spp", PLM_OPT_INT, &spp, 0, 1, 65536, NULL, "N", "samples per pixel of those renders (default 16)", 0},
        {"--threads", PLM_OPT_INT, &threads, 0, 1, 1024, NULL, "N", "render threads (default 2)", 0},
        {"--width", PLM_OPT_INT, &width, 0, 8, 16384, NULL, "N", "render width, height to the scene's aspect "
         "(default the scene's)", 0},
        {"--no-presets", PLM_OPT_FLAG, &no_presets, 0, 0, 0, NULL, NULL, "skip the presets", 0},
        {"--no-render", PLM_OPT_FLAG, &no_render, 0, 0, 0, NULL, NULL, "skip the renders", 0},
    };
    const plm_command_help help = {
        "plumage bench generate [options]",
        "Times plm_feather_generate in memory (no files), single thread: for one species its meshes at the\n"
        "default subdivision level with the fluff plus the feather and pigment textures; also without the\n"
        "pigment image, meshes and fluff alone, textures alone, the fluff alone. Then every species preset\n"
        "with its fluff: milliseconds, the fluff's curves, points and KiB, the feather's arrays and the\n"
        "resident memory its generation added at its peak. Then renders the single-feather scene with and\n"
        "without its fluff: samples per second per thread and peak resident memory of each (peaks are\n"
        "measured from a reset before each step). Ends with what the process held at the start."};
    int rc = plm_parse_options(&help, argc, argv, 1, opts, (int)(sizeof opts / sizeof opts[0]), NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    plm_feather_options all = {.level = level, .texture_width = size, .texture_height = size};
    int ok = detail(species, &all, runs);
    if (ok && !no_presets)
        ok = every_preset(presets, &all, runs);
    if (ok && !no_render)
        ok = render_both(scene, spp, threads, width);
    if (!ok)
        return 1;
    printf("\nstart_mib %.1f\n", start_mib);
    return 0;
}
