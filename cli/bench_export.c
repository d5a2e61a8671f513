/* plumage bench export: glTF export of scene files (by default the
 * 2,500-feather pelt, the default wing and the parrot), each with its fluff
 * as lines and with --no-fluff, each in a child process of its own: load
 * seconds, the export's bake and write seconds, the file's size, its nodes,
 * meshes and line segments, and peak resident memory after the load and
 * during the export alone. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli/bench.h"
#include "common/clock.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "common/memory.h"
#include "export/gltf.h"
#include "scene/scene_file.h"

typedef struct figures {
    int ok, instances;
    plm_gltf_report report;
    double load, export_seconds, file_mib, load_peak_mib, export_peak_mib;
} figures;

/* Loads and exports path to out; fills f. Runs in the child. */
static void measure(const char *path, const char *out, const plm_gltf_options *o, figures *f)
{
    plm_scene scene;
    plm_error err = {{0}};
    double t0 = plm_seconds();
    if (plm_scene_load(path, &scene, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return;
    }
    double t1 = plm_seconds();
    f->load_peak_mib = plm_memory_peak_mib();
    /* The export's own peak, if the system can restart the count (else the process's). */
    int own = plm_memory_reset_peak();
    plm_result rc = plm_gltf_export(&scene, out, o, &f->report, &err);
    double t2 = plm_seconds();
    f->export_peak_mib = own ? plm_memory_peak_mib() : 0.0;
    f->instances = scene.instance_count;
    plm_scene_free(&scene);
    if (rc != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return;
    }
    struct stat st;
    f->file_mib = stat(out, &st) == 0 ? (double)st.st_size / (1 << 20) : 0.0;
    f->load = t1 - t0;
    f->export_seconds = t2 - t1;
    f->ok = 1;
}

typedef struct export_job {
    const char *path, *out;
    const plm_gltf_options *o;
} export_job;

static int measure_job(void *ctx, void *figs)
{
    const export_job *j = ctx;
    figures *f = figs;
    measure(j->path, j->out, j->o, f);
    return f->ok;
}

static int run_isolated(const char *path, const char *out, const plm_gltf_options *o)
{
    figures f = {0};
    export_job job = {path, out, o};
    const char *slash = strrchr(path, '/');
    if (!plm_bench_in_child(measure_job, &job, &f, sizeof f) || !f.ok) {
        printf("%-24s failed\n", slash ? slash + 1 : path);
        return 1;
    }
    const plm_gltf_report *r = &f.report;
    char segments[32] = "off";
    if (!o->no_fluff)
        snprintf(segments, sizeof segments, "%ld", r->segments);
    printf("%-24s %9d %6d %6d %9s %7.2f %7.2f %7.2f %8.2f %10.3f %9.1f %9.1f\n", slash ? slash + 1 : path,
           f.instances, r->nodes, r->meshes, segments, f.load, r->bake_seconds, r->write_seconds, f.export_seconds,
           f.file_mib, f.load_peak_mib, f.export_peak_mib);
    return 0;
}

/* The temporary folder and the files in it (no subfolders). */
static void remove_folder(const char *dir)
{
    DIR *d = opendir(dir);
    for (struct dirent *e = d ? readdir(d) : NULL; e; e = readdir(d)) {
        char path[4400];
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0 &&
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name) < (int)sizeof path)
            remove(path);
    }
    if (d)
        closedir(d);
    if (rmdir(dir) != 0)
        fprintf(stderr, "warning: could not remove %s\n", dir);
}

int bench_export(int argc, char **argv)
{
    int gltf = 0;
    plm_gltf_options o = {0};
    plm_option opts[] = {
        {"--gltf", PLM_OPT_FLAG, &gltf, 0, 0, 0, NULL, NULL, "write .gltf (with .bin and PNG files) instead of .glb", 0},
        {"--bake-views", PLM_OPT_INT, &o.bake.views, 0, 2, 256, NULL, "N", "as plumage export (default 24)", 0},
        {"--bake-samples", PLM_OPT_INT, &o.bake.samples, 0, 1, 1 << 16, NULL, "N", "as plumage export (default 64)", 0},
    };
    plm_command_help help = {
        "plumage bench export [SCENE.json...] [options]",
        "Exports each scene (default: presets/scenes/pelt_2500.json, the default wing,\n"
        "presets/scenes/default.json, and the parrot, presets/scenes/amazon_parrot.json) as glTF into a\n"
        "temporary folder, with its fluff as lines and then with --no-fluff, each in a process of its own, and\n"
        "prints: load seconds (generation and layout), the export's bake and write seconds and their total,\n"
        "the file's size in MiB (.gltf: the JSON alone), its nodes, meshes and line segments (off: --no-fluff)\n"
        "and the peak resident memory after the load and during the export alone (docs/benchmarks.md)."};
    const char *scenes[64];
    int n = 0;
    int rc = plm_parse_options(&help, argc, argv, 1, opts, (int)(sizeof opts / sizeof opts[0]), scenes, 64, &n);
    if (rc)
        return rc == 1 ? 0 : 2;
    static const char *const defaults[] = {"presets/scenes/pelt_2500.json", "presets/scenes/default.json",
                                           "presets/scenes/amazon_parrot.json"};
    if (n == 0)
        for (; n < 3; ++n)
            scenes[n] = defaults[n];
    const char *tmp = getenv("TMPDIR");
    char dir[4096];
    snprintf(dir, sizeof dir, "%s/plumage-bench-export-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
    if (!mkdtemp(dir)) {
        fprintf(stderr, "error: cannot make a temporary folder %s\n", dir);
        return 1;
    }
    printf("%-24s %9s %6s %6s %9s %7s %7s %7s %8s %10s %9s %9s\n", "scene", "instances", "nodes", "meshes",
           "segments", "load_s", "bake_s", "write_s", "export_s", "file_mib", "load_mib", "exp_mib");
    int failed = 0;
    for (int i = 0; i < 2 * n; ++i) {
        char out[4200];
        snprintf(out, sizeof out, "%s/%d.%s", dir, i, gltf ? "gltf" : "glb");
        o.no_fluff = i % 2;
        failed |= run_isolated(scenes[i / 2], out, &o);
    }
    remove_folder(dir);
    return failed;
}
