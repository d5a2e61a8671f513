/* plumage bench <what>: prints performance figures for one part of plumage. */
#include "cli/bench.h"
#include "common/clock.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli/commands.h"
#include "cli/options.h"

int plm_bench_in_child(int (*measure)(void *ctx, void *figures), void *ctx, void *figures, size_t size)
{
    int fd[2];
    if (pipe(fd) != 0)
        return 0;
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        int ok = measure(ctx, figures);
        ssize_t n = write(fd[1], figures, size);
        _exit(n == (ssize_t)size && ok ? 0 : 1);
    }
    close(fd[1]);
    ssize_t n = pid > 0 ? read(fd[0], figures, size) : -1;
    close(fd[0]);
    int status = 1;
    if (pid > 0)
        waitpid(pid, &status, 0);
    return n == (ssize_t)size && WIFEXITED(status) && WEXITSTATUS(status) == 0;
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
        double t0 = plm_seconds();
        body(ctx, calls);
        times[r] = (plm_seconds() - t0) * 1e9 / (double)calls;
    }
    qsort(times, (size_t)runs, sizeof times[0], compare_doubles);
    return runs % 2 ? times[runs / 2] : 0.5 * (times[runs / 2 - 1] + times[runs / 2]);
}

static const plm_subcommand benches[] = {
    {"masking", bench_masking, "ns per masking call as the renderer makes it, and the feather BSDF's prepare"},
    {"generate", bench_generate, "one flight feather in memory: meshes + 1024x1024 textures, ms and peak memory"},
    {"render", bench_render, "path tracer: samples/s/thread and peak memory, one feather and 2,500 instanced"},
    {"scene", bench_scene, "scene files and pelts of 100 to 100,000 feathers: load, samples/s/thread, peak memory"},
    {"export", bench_export, "glTF export of pelt_2500, the wing and the parrot, with and without fluff"},
    {"fiber", bench_fiber, "fiber BCSDF: single-thread ns per prepare+eval and prepare+sample, Fig. 7 fibers"},
    {NULL, NULL, NULL}, /* sentinel: benchmarks are added here as the parts land */
};

int cmd_bench(int argc, char **argv)
{
    return plm_dispatch("plumage bench <what> [options]", "benchmark", benches, argc, argv);
}
