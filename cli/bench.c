/* plumage bench <what>: prints performance figures for one part of plumage. */
#include "cli/bench.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli/commands.h"
#include "cli/options.h"

double plm_bench_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double plm_bench_ns_per_call(void (*body)(void *ctx, long calls), void *ctx, long calls, int runs)
{
    double times[64];
    if (runs > 64)
        runs = 64;
    body(ctx, calls / 10 + 1); /* warm caches and branch predictors */
    for (int r = 0; r < runs; ++r) {
        double t0 = plm_bench_seconds();
        body(ctx, calls);
        times[r] = (plm_bench_seconds() - t0) * 1e9 / (double)calls;
    }
    qsort(times, (size_t)runs, sizeof times[0], compare_doubles);
    return runs % 2 ? times[runs / 2] : 0.5 * (times[runs / 2 - 1] + times[runs / 2]);
}

static const plm_subcommand benches[] = {
    {"masking", bench_masking, "ns per masking call as the renderer makes it, and the feather BSDF's prepare"},
    {"generate", bench_generate, "one flight feather in memory: meshes + 1024x1024 textures, ms and peak memory"},
    {"render", bench_render, "path tracer: samples/s/thread and peak memory, one feather and 2,500 instanced"},
    {"scene", bench_scene, "scene files and pelts of 100 to 100,000 feathers: load, samples/s/thread, peak memory"},
    {"fiber", bench_fiber, "fiber BCSDF: single-thread ns per prepare+eval and prepare+sample, Fig. 7 fibers"},
    {NULL, NULL, NULL}, /* sentinel: benchmarks are added here as the parts land */
};

int cmd_bench(int argc, char **argv)
{
    return plm_dispatch("plumage bench <what> [options]", "benchmark", benches, argc, argv);
}
