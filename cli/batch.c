/* plumage batch: the command over the batch library (batch/batch.h): its
 * options, the manifest and output folder opened, and the job callback that
 * renders one job as plumage render does. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "batch/batch.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "cli/outputs.h"
#include "cli/render_job.h"

/* The job callback: the job rendered as plumage render renders a scene. */
static int render_job(plm_batch_render *r, void *ctx)
{
    (void)ctx;
    const plm_batch_job *bj = r->job;
    plm_render_job rj;
    memset(&rj, 0, sizeof rj);
    rj.scene = bj->scene;
    rj.sets = (const char *const *)bj->sets;
    rj.n_sets = bj->n_sets;
    rj.spp = bj->spp;
    rj.width = bj->width;
    rj.height = bj->height;
    rj.seed = bj->seed;
    rj.max_depth = -1;
    rj.threads = r->threads;
    rj.progress = r->progress;
    rj.cancel = r->cancel;
    rj.discard_interrupted = 1;
    snprintf(rj.png, sizeof rj.png, "%s", r->png);
    snprintf(rj.exr, sizeof rj.exr, "%s", r->exr);
    rj.resolved = r->resolved;
    rj.asset_dir = r->asset_dir;
    int status = plm_render_job_run(&rj);
    r->width = rj.out_width, r->height = rj.out_height, r->spp = rj.out_spp, r->seed = rj.out_seed;
    r->threads_used = rj.used_threads, r->samples = rj.samples, r->nonfinite = rj.nonfinite;
    r->load_seconds = rj.load_seconds, r->render_seconds = rj.render_seconds, r->write_seconds = rj.write_seconds;
    r->interrupted = rj.interrupted;
    snprintf(r->error, sizeof r->error, "%s", rj.error);
    return status;
}

static void print_jobs(const plm_batch *b)
{
    for (int j = 0; j < b->m.n_jobs; ++j) {
        const plm_batch_job *job = &b->m.jobs[j];
        plm_job_status st;
        plm_batch_job_status(b, j, &st);
        printf("%s  [%s]  %s", job->name, plm_job_state_names[st.state], job->scene);
        if (job->spp)
            printf("  spp=%d", job->spp);
        if (job->width)
            printf("  resolution=%dx%d", job->width, job->height);
        if (job->seed >= 0)
            printf("  seed=%lld", job->seed);
        for (int i = 0; i < job->n_sets; ++i)
            printf("  %s", job->sets[i]);
        printf("\n");
    }
}

/* Absolute manifest and output paths: jobs and scheduler tasks may run from
 * another folder. `create`: make the output folder (not for a dry run). */
static int open_batch(plm_batch *b, const char *manifest, const char *output, int create)
{
    plm_error err = {{0}};
    memset(b, 0, sizeof *b);
    if (!realpath(manifest, b->manifest_path)) {
        fprintf(stderr, "error: %s: cannot open: %s\n", manifest, strerror(errno));
        return 0;
    }
    if (plm_manifest_load(b->manifest_path, &b->m, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 0;
    }
    char dir[PLM_PATH_MAX];
    if (output && output[0])
        snprintf(dir, sizeof dir, "%s", output);
    else if (b->m.output[0])
        snprintf(dir, sizeof dir, "%s", b->m.output);
    else { /* "path/name.json" -> "name" in the working directory */
        const char *base = strrchr(manifest, '/');
        base = base ? base + 1 : manifest;
        const char *dot = strrchr(base, '.');
        snprintf(dir, sizeof dir, "%.*s", dot && dot != base ? (int)(dot - base) : (int)strlen(base), base);
    }
    char cwd[PLM_PATH_MAX] = "";
    if ((dir[0] != '/' && !getcwd(cwd, sizeof cwd)) ||
        snprintf(b->out, sizeof b->out, "%s%s%s", cwd, cwd[0] ? "/" : "", dir) >= (int)sizeof b->out) {
        fprintf(stderr, "error: %s: cannot make the output folder's path absolute\n", dir);
        plm_manifest_free(&b->m);
        return 0;
    }
    plm_outputs outputs = {0};
    const char *option = output && output[0] ? "-o" : (b->m.output[0] ? "output" : "output folder");
    if (create && !plm_outputs_folder(&outputs, option, dir)) {
        plm_manifest_free(&b->m);
        return 0;
    }
    return 1;
}

int cmd_batch(int argc, char **argv)
{
    const char *output = NULL, *partition = NULL, *time_limit = NULL, *mem = NULL;
    int job = -1, dry_run = 0, status = 0, gather = 0, parallel = 0, threads = 0, quiet = 0, slurm = 0;
    int slurm_print = 0, cpus = 1;
    plm_opt_list sbatch_args = {{0}, 0};
    plm_option opts[] = {
        {"-o", PLM_OPT_STRING, &output, 0, 0, 0, NULL, "DIR",
         "output folder (default: the manifest's \"output\", else the manifest's name in the working directory)", 0},
        {"--dry-run", PLM_OPT_FLAG, &dry_run, 0, 0, 0, NULL, NULL, "list the jobs and their state, run nothing", 0},
        {"--job", PLM_OPT_INT, &job, 0, 0, PLM_BATCH_MAX_JOBS - 1, NULL, "N",
         "run job N alone in this process (0-based; skipped if already done)", 0},
        {"--status", PLM_OPT_FLAG, &status, 0, 0, 0, NULL, NULL,
         "report each job as done, running, failed, killed or missing, from the output folder "
         "alone (exit 1 unless all are done)",
         0},
        {"--gather", PLM_OPT_FLAG, &gather, 0, 0, 0, NULL, NULL,
         "write report.json and a sweep's contact sheet from the jobs' folders (what a Slurm batch ends with)", 0},
        {"--parallel", PLM_OPT_INT, &parallel, 0, 1, 1024, NULL, "N", "jobs at once (default: one per core)", 0},
        {"--threads", PLM_OPT_INT, &threads, 0, 1, 1024, NULL, "N",
         "render threads per job (default: the cores left over by --parallel; with --job: all cores)", 0},
        {"--quiet", PLM_OPT_FLAG, &quiet, 0, 0, 0, NULL, NULL, "no progress bar", 0},
        {"--slurm", PLM_OPT_FLAG, &slurm, 0, 0, 0, NULL, NULL,
         "submit the jobs not yet done as a Slurm job array, then a gather step (see docs/batch.md)", 0},
        {"--slurm-print", PLM_OPT_FLAG, &slurm_print, 0, 0, 0, NULL, NULL,
         "write the Slurm scripts into OUT/slurm/ and print them, without submitting", 0},
        {"--partition", PLM_OPT_STRING, &partition, 0, 0, 0, NULL, "NAME", "Slurm partition (default: the cluster's)",
         0},
        {"--time", PLM_OPT_STRING, &time_limit, 0, 0, 0, NULL, "LIMIT", "Slurm time limit per task, e.g. 30:00", 0},
        {"--cpus-per-task", PLM_OPT_INT, &cpus, 0, 1, 1024, NULL, "N",
         "Slurm CPUs per task, also its render threads (default 1)", 0},
        {"--mem", PLM_OPT_STRING, &mem, 0, 0, 0, NULL, "SIZE", "Slurm memory per task, e.g. 2G", 0},
        {"--sbatch", PLM_OPT_LIST, &sbatch_args, 0, 0, 0, NULL, "OPTION",
         "any other sbatch option, passed through (repeatable), e.g. --sbatch=--account=lab", 0},
    };
    const plm_command_help help = {
        "plumage batch MANIFEST.json [options]",
        "Runs a manifest's jobs (a list, or a sweep over parameter values; see docs/batch.md), several at once,\n"
        "each as its own process writing image.png, image.exr and summary.json into OUT/<job>/. Jobs already done\n"
        "are skipped, so an interrupted batch resumes where it stopped. A failing job does not stop the others;\n"
        "the batch then exits 1 and lists the failures. A sweep also gets OUT/contact_sheet.png, labelled with\n"
        "the parameter values (each key's whole path); every batch gets OUT/report.json. A minimal manifest,\n"
        "saved as out/sweep.json in the source tree, renders a scene at two fields of view and three light\n"
        "strengths (6 jobs):\n"
        "  {\"scene\": \"../presets/scenes/vane_quad.json\", \"spp\": 16, \"resolution\": [192, 256],\n"
        "   \"sweep\": {\"camera.fov\": [25, 40], \"lights.1.irradiance\": [[1, 1, 1], [2, 2, 2], [4, 4, 4]]}}\n"
        "The scene path is relative to the manifest's folder (out/, hence ../presets/); keys are --set paths (see\n"
        "plumage render --help); instead of \"sweep\", \"jobs\": [{\"name\": \"wide\", \"set\": {\"camera.fov\": 60}},\n"
        "...] lists jobs one by one. The output folder is -o DIR, else the manifest's name in the working\n"
        "directory (sweep/), created if missing:\n"
        "  plumage batch out/sweep.json -o out/sweep     # out/sweep/0000/image.png ... out/sweep/contact_sheet.png"};
    const char *positional[1];
    int n_pos = 0;
    int rc = plm_parse_options(&help, argc, argv, 1, opts, (int)(sizeof opts / sizeof opts[0]), positional, 1, &n_pos);
    if (rc)
        return rc == 1 ? 0 : 2;
    if (n_pos != 1) {
        fprintf(stderr, "error: plumage batch needs exactly one manifest file (see --help)\n");
        return 2;
    }
    if (dry_run + status + gather + (job >= 0) + (slurm || slurm_print) > 1) {
        fprintf(stderr, "error: --dry-run, --status, --gather, --job and --slurm exclude each other\n");
        return 2;
    }
    plm_batch b;
    if (!open_batch(&b, positional[0], output, !dry_run && !status))
        return 1;
    int exit_status = 0;
    if (job >= b.m.n_jobs) {
        fprintf(stderr, "error: --job: %d is out of range [0, %d] for %s\n", job, b.m.n_jobs - 1, positional[0]);
        exit_status = 2;
    } else if (job >= 0) {
        plm_job_status st;
        plm_batch_job_status(&b, job, &st);
        if (st.state == PLM_JOB_DONE || st.state == PLM_JOB_RUNNING)
            fprintf(stderr, "job %s is already %s (%s/%s/)\n", b.m.jobs[job].name, plm_job_state_names[st.state],
                    b.out, b.m.jobs[job].name);
        else
            exit_status = plm_batch_run_job(&b, job, threads, quiet, render_job, NULL);
    } else if (dry_run) {
        print_jobs(&b);
    } else if (status) {
        exit_status = plm_batch_print_status(&b) ? 1 : 0;
    } else if (gather) {
        exit_status = plm_batch_gather(&b, 1, quiet) ? 1 : 0;
    } else if (slurm || slurm_print) {
        plm_slurm_options so = {partition, time_limit, mem, cpus, sbatch_args.items, sbatch_args.count, slurm_print};
        exit_status = plm_batch_slurm(&b, &so);
    } else {
        exit_status = plm_batch_run_local(&b, parallel, threads, quiet);
    }
    plm_manifest_free(&b.m);
    return exit_status;
}
