/* plumage batch: runs a manifest's jobs as child processes of this same
 * binary (`plumage batch MANIFEST --job N`), so one failing or crashing job
 * never takes the others down, then gathers their summaries. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli/batch.h"
#include "common/clock.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "cli/outputs.h"
#include "common/fileio.h"
#include "common/progress.h"

static volatile sig_atomic_t stop_batch;

static void on_stop(int sig)
{
    (void)sig;
    stop_batch = 1;
}

typedef struct runner {
    const plm_batch *b;
    char self[PLM_PATH_MAX]; /* this executable */
    int threads;
    int *todo, n_todo, next;
    pid_t *pids;
    int *running; /* job index per slot, -1 = free */
    int slots, n_running, finished, failed;
    plm_progress progress;
} runner;

/* "dir/" + "x" with a length check. */
static int job_file(const runner *r, int job, const char *file, char *out)
{
    if (plm_batch_job_path(r->b, job, file, out, PLM_PATH_MAX))
        return 1;
    fprintf(stderr, "error: %s: the output path is too long\n", r->b->out);
    return 0;
}

/* Starts `plumage batch MANIFEST -o OUT --job N` with its output in the job's
 * .log.running; it dies with this process (even on SIGKILL). */
static int spawn(runner *r, int slot, int job)
{
    char dir[PLM_PATH_MAX], log[PLM_PATH_MAX], index[16], threads[16];
    plm_error err;
    if (!job_file(r, job, "", dir) || !job_file(r, job, ".log.running", log))
        return 0;
    if (plm_make_dirs(dir, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 0;
    }
    snprintf(index, sizeof index, "%d", job);
    snprintf(threads, sizeof threads, "%d", r->threads);
    char *argv[] = {"plumage", "batch", (char *)r->b->manifest_path, "-o", (char *)r->b->out, "--job", index,
                    "--threads", threads, "--quiet", NULL};
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid < 0) {
        fprintf(stderr, "error: cannot start job %s: %s\n", r->b->m.jobs[job].name, strerror(errno));
        return 0;
    }
    if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (getppid() != parent)
            _exit(137);
        int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd < 0 || dup2(fd, 1) < 0 || dup2(fd, 2) < 0)
            _exit(126);
        close(fd);
        execv(r->self, argv);
        _exit(127);
    }
    r->pids[slot] = pid;
    r->running[slot] = job;
    ++r->n_running;
    return 1;
}

/* One overall bar: jobs finished and failures, the time left estimated from the jobs finished. */
static void draw_progress(runner *r, int quiet, int last)
{
    if (quiet)
        return;
    char detail[64];
    snprintf(detail, sizeof detail, "%d/%d jobs, %d failed", r->finished, r->n_todo, r->failed);
    (last ? plm_progress_finish : plm_progress_update)(&r->progress, r->n_todo ? (double)r->finished / r->n_todo : 1.0,
                                                       detail);
}

/* A child ended: its log goes into place; a failure is reported at once. */
static void reap(runner *r, int slot, int status, int quiet)
{
    int job = r->running[slot];
    char log[PLM_PATH_MAX], final_log[PLM_PATH_MAX];
    if (job_file(r, job, ".log.running", log) && job_file(r, job, "log.txt", final_log))
        rename(log, final_log);
    r->running[slot] = -1;
    --r->n_running;
    ++r->finished;
    int ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    if (!ok) {
        ++r->failed;
        plm_job_status st;
        plm_batch_job_status(r->b, job, &st);
        char why[64];
        if (WIFSIGNALED(status))
            snprintf(why, sizeof why, "killed by signal %d", WTERMSIG(status));
        else
            snprintf(why, sizeof why, "exit %d", WEXITSTATUS(status));
        fprintf(stderr, "%sjob %s failed (%s): %s\n", !quiet && r->progress.tty ? "\n" : "", r->b->m.jobs[job].name,
                why, st.message[0] ? st.message : "see its log.txt");
    }
    draw_progress(r, quiet, 0);
}

static int run_local(const plm_batch *b, int parallel, int threads, int quiet)
{
    runner r;
    memset(&r, 0, sizeof r);
    r.b = b;
    if (!plm_batch_self_path(r.self, sizeof r.self))
        return 1;
    r.todo = malloc(sizeof *r.todo * (size_t)b->m.n_jobs);
    if (!r.todo) {
        fprintf(stderr, "error: out of memory\n");
        return 1;
    }
    for (int j = 0; j < b->m.n_jobs; ++j) {
        plm_job_status st;
        plm_batch_job_status(b, j, &st);
        if (st.state != PLM_JOB_DONE && st.state != PLM_JOB_RUNNING) /* running: by another batch, here */
            r.todo[r.n_todo++] = j;
    }
    /* Whole jobs in parallel first (no synchronisation inside a job), then the spare cores as threads. */
    long cores = plm_cores();
    r.slots = parallel ? parallel : (int)(cores < r.n_todo ? cores : (r.n_todo ? r.n_todo : 1));
    r.threads = threads ? threads : (int)(cores / r.slots > 1 ? cores / r.slots : 1);
    r.pids = calloc((size_t)r.slots, sizeof *r.pids);
    r.running = malloc(sizeof *r.running * (size_t)r.slots);
    if (!r.pids || !r.running) {
        fprintf(stderr, "error: out of memory\n");
        free(r.todo);
        free(r.pids);
        free(r.running);
        return 1;
    }
    for (int s = 0; s < r.slots; ++s)
        r.running[s] = -1;
    if (!quiet)
        fprintf(stderr, "batch: %d jobs, %d already done; %d to run, %d at a time with %d thread%s each -> %s\n",
                b->m.n_jobs, b->m.n_jobs - r.n_todo, r.n_todo, r.slots, r.threads, r.threads > 1 ? "s" : "", b->out);
    struct sigaction sa, old_int, old_term;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop;
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
    plm_progress_start(&r.progress, "batch");
    double last_draw = 0.0;
    int spawn_failed = 0, forwarded = 0;
    for (;;) {
        for (int s = 0; s < r.slots && !stop_batch && !spawn_failed && r.next < r.n_todo; ++s)
            if (r.running[s] < 0 && !spawn(&r, s, r.todo[r.next++]))
                spawn_failed = 1;
        if (r.n_running == 0)
            break;
        if (stop_batch && !forwarded) { /* the jobs stop their renders and record why */
            for (int s = 0; s < r.slots; ++s)
                if (r.running[s] >= 0)
                    kill(r.pids[s], SIGTERM);
            forwarded = 1;
        }
        int status;
        pid_t pid = waitpid(-1, &status, WNOHANG);
        if (pid > 0) {
            for (int s = 0; s < r.slots; ++s)
                if (r.running[s] >= 0 && r.pids[s] == pid)
                    reap(&r, s, status, quiet);
        } else {
            struct timespec nap = {0, 20000000}; /* 20 ms: a finished job waits at most that for its successor */
            nanosleep(&nap, NULL);
            if (r.progress.tty && plm_seconds() - last_draw > 0.25) { /* the time left goes down */
                draw_progress(&r, quiet, 0);
                last_draw = plm_seconds();
            }
        }
    }
    sigaction(SIGINT, &old_int, NULL);
    sigaction(SIGTERM, &old_term, NULL);
    draw_progress(&r, quiet, 1);
    int not_done = plm_batch_gather(b, 0, quiet); /* the reasons were printed as the jobs ended */
    free(r.todo);
    free(r.pids);
    free(r.running);
    if (stop_batch)
        return 130;
    return not_done || spawn_failed ? 1 : 0;
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
        "sweep.json, renders a scene at two fields of view and three light strengths (6 jobs):\n"
        "  {\"scene\": \"../presets/scenes/vane_quad.json\", \"spp\": 16, \"resolution\": [192, 256],\n"
        "   \"sweep\": {\"camera.fov\": [25, 40], \"lights.1.irradiance\": [[1, 1, 1], [2, 2, 2], [4, 4, 4]]}}\n"
        "The scene is read from the manifest's folder; keys are --set paths (see plumage render --help); instead\n"
        "of \"sweep\", \"jobs\": [{\"name\": \"wide\", \"set\": {\"camera.fov\": 60}}, ...] lists jobs one by one.\n"
        "The output folder is the manifest's name in the working directory (sweep/), created if missing."};
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
            exit_status = plm_batch_run_job(&b, job, threads, quiet);
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
        exit_status = run_local(&b, parallel, threads, quiet);
    }
    plm_manifest_free(&b.m);
    return exit_status;
}
