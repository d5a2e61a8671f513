/* plumage batch --slurm: the jobs not yet done as one Slurm job array (each
 * task is `plumage batch MANIFEST --job $SLURM_ARRAY_TASK_ID`), and a gather
 * step that runs after the array however its tasks end (afterany). The job
 * folders are the only state, so a resubmission runs just what is missing.
 * docs/batch.md describes the cluster set-up this assumes. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "batch/batch.h"
#include "common/progress.h"
#include "common/fileio.h"

/* 'text' for the shell, with embedded quotes escaped. */
static void put_quoted(FILE *fp, const char *text)
{
    fputc('\'', fp);
    for (const char *p = text; *p; ++p)
        if (*p == '\'')
            fputs("'\\''", fp);
        else
            fputc(*p, fp);
    fputc('\'', fp);
}

/* A job to submit: neither done nor running right now on this host. */
static int wanted(const plm_batch *b, int j)
{
    plm_job_status st;
    plm_batch_job_status(b, j, &st);
    return st.state != PLM_JOB_DONE && st.state != PLM_JOB_RUNNING;
}

/* The indices of the jobs to submit as Slurm ranges: "0-3,7,9-12". Returns their number. */
static int array_spec(const plm_batch *b, char *out, size_t size)
{
    int n = 0;
    size_t len = 0;
    out[0] = '\0';
    for (int j = 0; j < b->m.n_jobs;) {
        if (!wanted(b, j)) {
            ++j;
            continue;
        }
        int k = j + 1;
        while (k < b->m.n_jobs && wanted(b, k))
            ++k;
        int w = k - 1 > j ? snprintf(out + len, size - len, "%s%d-%d", n ? "," : "", j, k - 1)
                          : snprintf(out + len, size - len, "%s%d", n ? "," : "", j);
        if (w < 0 || (size_t)w >= size - len)
            return -1;
        len += (size_t)w;
        n += k - j;
        j = k;
    }
    return n;
}

static void put_header(FILE *fp, const plm_slurm_options *opt, const char *name, int cpus, const char *log)
{
    fprintf(fp, "#!/bin/bash\n#SBATCH --job-name=%s\n#SBATCH --cpus-per-task=%d\n#SBATCH --output=%s\n", name, cpus,
            log);
    if (opt->partition)
        fprintf(fp, "#SBATCH --partition=%s\n", opt->partition);
    if (opt->time)
        fprintf(fp, "#SBATCH --time=%s\n", opt->time);
    for (int i = 0; i < opt->n_sbatch_args; ++i)
        fprintf(fp, "#SBATCH %s\n", opt->sbatch_args[i]);
}

/* The plumage command a script runs, up to its mode arguments. */
static void put_command(FILE *fp, const char *self, const plm_batch *b)
{
    fputs("exec ", fp);
    put_quoted(fp, self);
    fputs(" batch ", fp);
    put_quoted(fp, b->manifest_path);
    fputs(" -o ", fp);
    put_quoted(fp, b->out);
}

static int write_script(const char *path, const char *self, const plm_batch *b, const plm_slurm_options *opt,
                        const char *array)
{
    plm_atomic_file f;
    plm_error err;
    char log[PLM_PATH_MAX];
    if (plm_atomic_open(&f, path, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 0;
    }
    if (array) {
        snprintf(log, sizeof log, "%s/slurm/logs/%%A_%%a.log", b->out);
        put_header(f.fp, opt, "plumage-batch", opt->cpus_per_task, log);
        fprintf(f.fp, "#SBATCH --array=%s\n", array);
        if (opt->mem)
            fprintf(f.fp, "#SBATCH --mem=%s\n", opt->mem);
        fputs("# One job of the manifest; its folder records how it ended.\n", f.fp);
        put_command(f.fp, self, b);
        fprintf(f.fp, " --job \"$SLURM_ARRAY_TASK_ID\" --threads \"${SLURM_CPUS_PER_TASK:-%d}\" --quiet\n",
                opt->cpus_per_task);
    } else {
        snprintf(log, sizeof log, "%s/slurm/logs/gather_%%j.log", b->out);
        put_header(f.fp, opt, "plumage-gather", 1, log);
        fputs("# After the array, however its tasks ended: report.json and the contact sheet.\n", f.fp);
        put_command(f.fp, self, b);
        fputs(" --gather\n", f.fp);
    }
    if (plm_atomic_commit(&f, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 0;
    }
    return 1;
}

/* Runs sbatch with argv and returns the job id it prints (--parsable: "id[;cluster]"), or -1. */
static long submit(char *const argv[])
{
    int fds[2];
    if (pipe(fds) != 0)
        return -1;
    pid_t pid = fork();
    if (pid == 0) {
        dup2(fds[1], 1);
        close(fds[0]);
        close(fds[1]);
        execvp(argv[0], argv);
        fprintf(stderr, "error: cannot run %s: %s\n", argv[0], strerror(errno));
        _exit(127);
    }
    close(fds[1]);
    char buf[256] = "";
    size_t len = 0;
    ssize_t n;
    while (pid > 0 && len < sizeof buf - 1 && (n = read(fds[0], buf + len, sizeof buf - 1 - len)) > 0)
        len += (size_t)n;
    buf[len] = '\0';
    close(fds[0]);
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return -1;
    char *end;
    long id = strtol(buf, &end, 10);
    return end != buf && id > 0 ? id : -1;
}

static void print_file(const char *path)
{
    char *text;
    if (plm_read_text_file(path, &text, NULL) == PLM_OK) {
        printf("# %s\n%s\n", path, text);
        free(text);
    }
}

int plm_batch_slurm(const plm_batch *b, const plm_slurm_options *opt)
{
    char self[PLM_PATH_MAX], dir[PLM_PATH_MAX], array_path[PLM_PATH_MAX], gather_path[PLM_PATH_MAX];
    char array[8192];
    plm_error err;
    if (!plm_batch_self_path(self, sizeof self))
        return 1;
    int n = array_spec(b, array, sizeof array);
    if (n < 0) {
        fprintf(stderr, "error: too many separate ranges of jobs to submit in one array\n");
        return 1;
    }
    snprintf(dir, sizeof dir, "%s/slurm/logs", b->out);
    snprintf(array_path, sizeof array_path, "%s/slurm/array.sbatch", b->out);
    snprintf(gather_path, sizeof gather_path, "%s/slurm/gather.sbatch", b->out);
    if (plm_make_dirs(dir, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 1;
    }
    if ((n > 0 && !write_script(array_path, self, b, opt, array)) || !write_script(gather_path, self, b, opt, NULL))
        return 1;
    if (opt->print_only) {
        if (n > 0)
            print_file(array_path);
        print_file(gather_path);
        printf("# submit with:\n%s%s\nsbatch --dependency=afterany:<array job id> %s\n", n ? "sbatch " : "",
               n ? array_path : "# (every job is done: no array)", gather_path);
        fflush(stdout);
        plm_print_wrote((const char *const[]){n > 0 ? array_path : NULL, gather_path}, 2);
        return 0;
    }
    long array_id = 0;
    if (n > 0) {
        char *argv[] = {"sbatch", "--parsable", array_path, NULL};
        if ((array_id = submit(argv)) < 0) {
            fprintf(stderr, "error: sbatch %s failed (is Slurm reachable from here?)\n", array_path);
            return 1;
        }
    }
    char dependency[64];
    snprintf(dependency, sizeof dependency, "--dependency=afterany:%ld", array_id);
    char *gather_argv[] = {"sbatch", "--parsable", n > 0 ? dependency : "--quiet", gather_path, NULL};
    long gather_id = submit(gather_argv);
    if (gather_id < 0) {
        fprintf(stderr, "error: sbatch %s failed%s\n", gather_path,
                n > 0 ? " (the array was submitted: its tasks run; gather later with --gather)" : "");
        return 1;
    }
    if (n > 0)
        printf("submitted job array %ld (%d of %d jobs: %s) and gather job %ld after it\n", array_id, n, b->m.n_jobs,
               array, gather_id);
    else
        printf("every job is done; submitted gather job %ld\n", gather_id);
    printf("follow with: plumage batch %s -o %s --status\n", b->manifest_path, b->out);
    fflush(stdout);
    plm_print_wrote((const char *const[]){n > 0 ? array_path : NULL, gather_path}, 2);
    return 0;
}
