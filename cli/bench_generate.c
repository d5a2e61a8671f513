/* plumage bench generate: milliseconds and peak memory to build one feather
 * in memory (meshes at the default level plus the textures), single thread. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "cli/bench.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "common/memory.h"
#include "texture/feather.h"

/* CPU seconds of this thread: on a shared machine, less disturbed by other
 * processes than the wall clock. */
static double thread_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

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

/* Median wall and thread-CPU milliseconds of `runs` generations. */
static int time_generation(const plm_species *sp, const plm_feather_options *fo, int runs, double ms[2])
{
    double wall[64], cpu[64];
    for (int r = 0; r < runs; ++r) {
        plm_feather f;
        plm_error err;
        double t0 = plm_bench_seconds(), c0 = thread_seconds();
        if (plm_feather_generate(sp, fo, &f, &err) != PLM_OK) {
            fprintf(stderr, "error: %s\n", err.message);
            return 0;
        }
        wall[r] = 1e3 * (plm_bench_seconds() - t0);
        cpu[r] = 1e3 * (thread_seconds() - c0);
        plm_feather_free(&f);
    }
    ms[0] = median(wall, runs);
    ms[1] = median(cpu, runs);
    return 1;
}

int bench_generate(int argc, char **argv)
{
    double start_mib = plm_memory_resident_mib();
    const char *species = "presets/species/remex_pigeon.json";
    int runs = 7, size = 1024, level = PLM_FEATHER_DEFAULT_LEVEL;
    plm_option opts[] = {
        {"--species", PLM_OPT_STRING, &species, 0, 0, 0, NULL, "FILE",
         "species preset (default presets/species/remex_pigeon.json, from the repository root)", 0},
        {"--runs", PLM_OPT_INT, &runs, 0, 1, 64, NULL, "N", "timed runs; the median is reported (default 7)", 0},
        {"--texture-size", PLM_OPT_INT, &size, 0, 8, 16384, NULL, "N", "texture width and height (default 1024)", 0},
        {"--level", PLM_OPT_INT, &level, 0, 1, 6, NULL, "N", "subdivision level (default 3)", 0},
    };
    const plm_command_help help = {
        "plumage bench generate [options]",
        "Times plm_feather_generate in memory (no files): meshes at the default subdivision level plus the\n"
        "feather and pigment textures, single thread; also without the pigment image, meshes alone and\n"
        "textures alone. Prints median wall and thread-CPU milliseconds, the process's peak resident memory\n"
        "and what it held at the start."};
    int rc = plm_parse_options(&help, argc, argv, 1, opts, (int)(sizeof opts / sizeof opts[0]), NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    plm_species sp;
    plm_error err;
    if (plm_species_load(species, &sp, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 1;
    }
    plm_feather_options all = {.level = level, .texture_width = size, .texture_height = size};
    plm_feather_options parts[4] = {all, all, all, all};
    parts[1].no_pigment = 1;  /* the feather texture is what the renderer needs */
    parts[2].no_textures = 1; /* meshes alone */
    parts[3].no_meshes = 1;   /* textures alone */
    static const char *const names[4] = {"generate", "generate_no_pigment", "meshes", "textures"};
    double ms[4][2];
    int ok = time_generation(&sp, &all, 1, ms[0]); /* warm-up */
    for (int k = 0; k < 4 && ok; ++k)
        ok = time_generation(&sp, &parts[k], runs, ms[k]);
    plm_species_free(&sp);
    if (!ok)
        return 1;
    printf("species %s, level %d, textures %dx%d, median of %d runs, 1 thread (wall and thread CPU)\n", species,
           level, size, size, runs);
    for (int k = 0; k < 4; ++k)
        printf("%s_ms %.2f cpu_ms %.2f\n", names[k], ms[k][0], ms[k][1]);
    printf("peak_mib %.1f start_mib %.1f\n", plm_memory_peak_mib(), start_mib);
    return 0;
}
