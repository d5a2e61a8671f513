/* plumage bench generate: milliseconds and peak memory to build one feather
 * in memory (meshes at the default level plus the textures), single thread. */
#include <stdio.h>
#include <stdlib.h>

#include "cli/bench.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "texture/feather.h"

/* Median milliseconds of `runs` generations with the given options. */
static int time_generation(const plm_species *sp, const plm_feather_options *fo, int runs, double *ms)
{
    double times[64];
    for (int r = 0; r < runs; ++r) {
        plm_feather f;
        plm_error err;
        double t0 = plm_bench_seconds();
        if (plm_feather_generate(sp, fo, &f, &err) != PLM_OK) {
            fprintf(stderr, "error: %s\n", err.message);
            return 0;
        }
        times[r] = 1e3 * (plm_bench_seconds() - t0);
        plm_feather_free(&f);
    }
    for (int i = 1; i < runs; ++i) /* insertion sort: a handful of values */
        for (int j = i; j > 0 && times[j] < times[j - 1]; --j) {
            double t = times[j];
            times[j] = times[j - 1];
            times[j - 1] = t;
        }
    *ms = runs % 2 ? times[runs / 2] : 0.5 * (times[runs / 2 - 1] + times[runs / 2]);
    return 1;
}

int bench_generate(int argc, char **argv)
{
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
        "Times plm_feather_generate in memory (no files): meshes at the default subdivision level plus the "
        "feather and pigment textures, single thread; also meshes alone and textures alone. Prints the median "
        "milliseconds and the process's peak resident memory."};
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
    plm_feather_options meshes = all, textures = all;
    meshes.no_textures = 1;
    textures.no_meshes = 1;
    double ms_all, ms_meshes, ms_textures;
    int ok = time_generation(&sp, &all, 1, &ms_all) && /* warm-up */
             time_generation(&sp, &all, runs, &ms_all) && time_generation(&sp, &meshes, runs, &ms_meshes) &&
             time_generation(&sp, &textures, runs, &ms_textures);
    plm_species_free(&sp);
    if (!ok)
        return 1;
    printf("species %s, level %d, textures %dx%d (feather + pigment), median of %d runs, 1 thread\n", species, level,
           size, size, runs);
    printf("generate_ms %.2f\nmeshes_ms %.2f\ntextures_ms %.2f\npeak_mib %.1f\n", ms_all, ms_meshes, ms_textures,
           plm_bench_peak_mib());
    return 0;
}
