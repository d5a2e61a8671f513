/* Batches of render jobs run, resumed, reported and submitted to Slurm: the
 * local runner, single jobs, the status and report, the Slurm scripts. The
 * library renders nothing itself: a job's render is the command's, behind a
 * job callback (plm_batch_render_fn). Every job owns a folder
 * under the output folder; what is in it says how far the job got:
 *   summary.json  written last, atomically: the job is done (if its key and
 *                 output hashes still match)
 *   failed.json   the job ran and failed (the message, the exit status)
 *   started.json  the job started and has not finished: running (if its
 *                 process is alive on this host) or killed
 * docs/batch.md describes the layout. */
#ifndef PLUMAGE_BATCH_BATCH_H
#define PLUMAGE_BATCH_BATCH_H

#include <signal.h>
#include <stddef.h>

#include "batch/manifest.h"
#include "common/fileio.h"

typedef struct plm_batch {
    char manifest_path[PLM_PATH_MAX]; /* absolute: tasks may run elsewhere */
    char out[PLM_PATH_MAX - 256];     /* absolute output folder (room for job and file names) */
    plm_manifest m;
} plm_batch;

typedef enum plm_job_state {
    PLM_JOB_MISSING = 0, /* never started, or its summary is for other inputs */
    PLM_JOB_KILLED,      /* started, never finished */
    PLM_JOB_FAILED,
    PLM_JOB_RUNNING,     /* started, its process alive on this host */
    PLM_JOB_DONE,
    PLM_JOB_STATES
} plm_job_state;

extern const char *const plm_job_state_names[]; /* "missing", "killed", "failed", "running", "done" */

typedef struct plm_job_status {
    plm_job_state state;
    char runner[64];    /* "local" or "slurm <job>_<task>", from the newest record */
    char message[512];  /* failed: why; killed, running: when and where it started */
    double seconds;     /* done: total time */
} plm_job_status;

/* A job's folder: out/<job name>/<file> (file may be ""); 0 if it does not fit. */
int plm_batch_job_path(const plm_batch *b, int job, const char *file, char *out, size_t size);

/* Reads the job's folder (see above). */
void plm_batch_job_status(const plm_batch *b, int job, plm_job_status *st);

/* One job's render as plm_batch_run_job asks the command for it, and the
 * figures the job's summary records, which the render reports back. */
typedef struct plm_batch_render {
    const plm_batch_job *job;      /* the scene, its overrides, spp, size and seed (0, -1: the scene's) */
    int threads, progress;         /* threads 0: all cores */
    volatile sig_atomic_t *cancel; /* set by SIGTERM or SIGINT: stop, and write no image */
    const char *png, *exr, *resolved; /* the images and the resolved scene, in the job's folder */
    const char *asset_dir;         /* the generated feathers' files go here; NULL: none */
    /* reported back */
    int width, height, spp, threads_used, interrupted;
    unsigned long long seed;
    long long samples, nonfinite;
    double load_seconds, render_seconds, write_seconds;
    char error[1024]; /* why it failed */
} plm_batch_render;

/* The command's renderer: renders r->job into r's outputs and fills in the
 * figures. Returns the exit status: 0, 1 on an error (r->error says why),
 * 130 if r->cancel stopped it. */
typedef int (*plm_batch_render_fn)(plm_batch_render *r, void *ctx);

/* Runs one job in this process (`--job N`) through render(r, ctx): the job's
 * folder is cleaned of temporaries and stale records, the images and summary
 * written. Returns the exit status; SIGTERM or SIGINT stop the render and
 * fail the job. */
int plm_batch_run_job(const plm_batch *b, int job, int threads, int quiet, plm_batch_render_fn render, void *ctx);

/* Runs the jobs not done, `parallel` at once (0: one per core) with `threads`
 * each (0: the cores left over), each as a child process of this executable,
 * `SELF batch MANIFEST -o OUT --job N --threads T --quiet`, which the command
 * must answer with plm_batch_run_job; then gathers (plm_batch_gather).
 * SIGINT or SIGTERM stop the jobs. Returns the exit status (130: stopped). */
int plm_batch_run_local(const plm_batch *b, int parallel, int threads, int quiet);

/* Reads every job's state; writes report.json and, for a sweep, the labelled
 * contact sheet. Prints each job not done with its reason (`explain`), or
 * just their names. Returns the number of jobs not done. */
int plm_batch_gather(const plm_batch *b, int explain, int quiet);

/* Prints every job's state (from the output folder alone); returns the number not done. */
int plm_batch_print_status(const plm_batch *b);

typedef struct plm_slurm_options {
    const char *partition, *time, *mem;
    int cpus_per_task;
    const char *const *sbatch_args; /* passed through verbatim, one #SBATCH line each */
    int n_sbatch_args;
    int print_only;
} plm_slurm_options;

/* Writes the array and gather scripts for the jobs not done and submits
 * them (or prints them). Returns the exit status. */
int plm_batch_slurm(const plm_batch *b, const plm_slurm_options *opt);

/* The running executable's absolute path (children and tasks run the same binary). */
int plm_batch_self_path(char *out, size_t size);

/* Writes a JSON document atomically. */
int plm_batch_write_json(const char *path, const void *cjson_doc);

#endif
