/* The local runner: a manifest's jobs as child processes of this same
 * executable (SELF batch MANIFEST -o OUT --job N, which the command answers
 * with plm_batch_run_job), several at once, so one failing or crashing job
 * never takes the others down; then their summaries gathered. */
#define _XOPEN_SOURCE 700 /* sigaction, nanosleep */
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

#include "batch/batch.h"
#include "common/clock.h"
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

int plm_batch_run_local(const plm_batch *b, int parallel, int threads, int quiet)
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

