/* One batch job in this process, and what a job's folder says about it. */
#define _XOPEN_SOURCE 700 /* nftw */
#include <dirent.h>
#include <errno.h>
#include <ftw.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "batch/batch.h"
#include "common/clock.h"
#include "common/fileio.h"
#include "common/json.h"

const char *const plm_job_state_names[] = {"missing", "killed", "failed", "running", "done"};

/* The images every job writes, and the resolved scene, in its folder; with
 * assets, the generated feathers' files in folders under ASSETS. */
static const char *const outputs[] = {"image.png", "image.exr", "scene.json"};
#define N_OUTPUTS 3
#define ASSETS "assets"

int plm_batch_job_path(const plm_batch *b, int job, const char *file, char *out, size_t size)
{
    const char *name = b->m.jobs[job].name;
    size_t n = strlen(b->out), k = strlen(name), f = strlen(file);
    if (n + k + f + 3 > size) {
        out[0] = '\0';
        return 0;
    }
    memcpy(out, b->out, n);
    out[n] = '/';
    memcpy(out + n + 1, name, k + 1);
    if (f) {
        out[n + 1 + k] = '/';
        memcpy(out + n + k + 2, file, f + 1);
    }
    return 1;
}

int plm_batch_self_path(char *out, size_t size)
{
    ssize_t n = readlink("/proc/self/exe", out, size - 1);
    if (n <= 0 || (size_t)n >= size - 1) {
        fprintf(stderr, "error: cannot find the plumage executable (/proc/self/exe)\n");
        return 0;
    }
    out[n] = '\0';
    return 1;
}

int plm_batch_write_json(const char *path, const void *cjson_doc)
{
    plm_error err;
    plm_atomic_file f;
    char *text = cJSON_Print(cjson_doc);
    if (!text || plm_atomic_open(&f, path, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", text ? err.message : "out of memory");
        free(text);
        return 0;
    }
    fprintf(f.fp, "%s\n", text);
    free(text);
    if (plm_atomic_commit(&f, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 0;
    }
    return 1;
}

/* Size and FNV-1a hash of a file as "bytes" and "fnv1a64"; 0 if unreadable. */
static int hash_file(const char *path, long long *bytes, char hex[17])
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return 0;
    unsigned char buf[1 << 16];
    uint64_t h = PLM_FNV_OFFSET;
    size_t n;
    *bytes = 0;
    while ((n = fread(buf, 1, sizeof buf, fp)) > 0) {
        h = plm_fnv1a64(buf, n, h);
        *bytes += (long long)n;
    }
    int ok = !ferror(fp);
    fclose(fp);
    snprintf(hex, 17, "%016llx", (unsigned long long)h);
    return ok;
}

static void key_hex(const plm_batch_job *job, char hex[17])
{
    snprintf(hex, 17, "%016llx", (unsigned long long)job->key);
}

/* Where this process runs: "local", or "slurm <array job>_<task>". */
static void runner_name(char *out, size_t size)
{
    const char *job = getenv("SLURM_ARRAY_JOB_ID"), *task = getenv("SLURM_ARRAY_TASK_ID");
    const char *plain = getenv("SLURM_JOB_ID");
    if (job && task)
        snprintf(out, size, "slurm %s_%s", job, task);
    else if (plain)
        snprintf(out, size, "slurm %s", plain);
    else
        snprintf(out, size, "local");
}

static void utc_now(char *out, size_t size)
{
    time_t t = time(NULL);
    struct tm tm;
    gmtime_r(&t, &tm);
    strftime(out, size, "%Y-%m-%dT%H:%M:%SZ", &tm);
}

/* The fields every record of a job carries: which job, where, when. */
static cJSON *record(const plm_batch *b, int job, const char *state)
{
    char runner[64], host[256] = "", when[32];
    runner_name(runner, sizeof runner);
    gethostname(host, sizeof host - 1);
    utc_now(when, sizeof when);
    cJSON *doc = cJSON_CreateObject();
    cJSON_AddStringToObject(doc, "state", state);
    cJSON_AddNumberToObject(doc, "job", job);
    cJSON_AddStringToObject(doc, "name", b->m.jobs[job].name);
    cJSON_AddStringToObject(doc, "runner", runner);
    cJSON_AddStringToObject(doc, "host", host);
    cJSON_AddNumberToObject(doc, "pid", (double)getpid());
    cJSON_AddStringToObject(doc, "time", when);
    return doc;
}

static const char *string_field(const cJSON *doc, const char *key)
{
    const cJSON *s = cJSON_GetObjectItemCaseSensitive(doc, key);
    return cJSON_IsString(s) ? s->valuestring : "";
}

/* Loads out/<job>/<file> if it is a JSON object for this job. */
static cJSON *load_record(const plm_batch *b, int job, const char *file)
{
    char path[PLM_PATH_MAX];
    plm_batch_job_path(b, job, file, path, sizeof path);
    if (access(path, F_OK) != 0)
        return NULL;
    cJSON *doc = NULL;
    if (plm_json_load(path, &doc, NULL) != PLM_OK || !cJSON_IsObject(doc) ||
        strcmp(string_field(doc, "name"), b->m.jobs[job].name) != 0) {
        cJSON_Delete(doc);
        return NULL;
    }
    return doc;
}

/* A summary counts if it is for these inputs and every output still has its recorded hash. */
static int summary_is_complete(const plm_batch *b, int job, const cJSON *summary)
{
    char key[17];
    key_hex(&b->m.jobs[job], key);
    if (strcmp(string_field(summary, "state"), "done") != 0 || strcmp(string_field(summary, "key"), key) != 0)
        return 0;
    const cJSON *files = cJSON_GetObjectItemCaseSensitive(summary, "outputs");
    if (!cJSON_IsObject(files) || !files->child)
        return 0;
    for (const cJSON *f = files->child; f; f = f->next) {
        char path[PLM_PATH_MAX], hex[17];
        long long bytes;
        plm_batch_job_path(b, job, f->string, path, sizeof path);
        const cJSON *size = cJSON_GetObjectItemCaseSensitive(f, "bytes");
        if (!hash_file(path, &bytes, hex) || !cJSON_IsNumber(size) || size->valuedouble != (double)bytes ||
            strcmp(string_field(f, "fnv1a64"), hex) != 0)
            return 0;
    }
    return 1;
}

/* Whether a started job's process is alive: only knowable on its own host. */
static int still_running(const cJSON *started)
{
    char host[256] = "";
    const cJSON *pid = cJSON_GetObjectItemCaseSensitive(started, "pid");
    gethostname(host, sizeof host - 1);
    if (!cJSON_IsNumber(pid) || pid->valuedouble <= 1 || (pid_t)pid->valuedouble == getpid() ||
        strcmp(string_field(started, "host"), host) != 0)
        return 0;
    return kill((pid_t)pid->valuedouble, 0) == 0 || errno == EPERM;
}

void plm_batch_job_status(const plm_batch *b, int job, plm_job_status *st)
{
    memset(st, 0, sizeof *st);
    static const char *const files[] = {"summary.json", "failed.json", "started.json"};
    static const plm_job_state states[] = {PLM_JOB_DONE, PLM_JOB_FAILED, PLM_JOB_KILLED};
    for (int i = 0; i < 3 && st->state == PLM_JOB_MISSING; ++i) {
        cJSON *doc = load_record(b, job, files[i]);
        if (!doc || (i == 0 && !summary_is_complete(b, job, doc))) {
            cJSON_Delete(doc);
            continue;
        }
        st->state = states[i];
        snprintf(st->runner, sizeof st->runner, "%s", string_field(doc, "runner"));
        if (i == 0) {
            const cJSON *sec = cJSON_GetObjectItemCaseSensitive(doc, "seconds");
            const cJSON *s = cJSON_GetObjectItemCaseSensitive(sec, "total");
            st->seconds = cJSON_IsNumber(s) ? s->valuedouble : 0.0;
        } else if (i == 1) {
            snprintf(st->message, sizeof st->message, "%s", string_field(doc, "error"));
        } else {
            int alive = still_running(doc);
            st->state = alive ? PLM_JOB_RUNNING : PLM_JOB_KILLED;
            snprintf(st->message, sizeof st->message, "started %s on %s%s", string_field(doc, "time"),
                     string_field(doc, "host"), alive ? "" : ", never finished");
        }
        cJSON_Delete(doc);
    }
}

static int remove_entry(const char *path, const struct stat *st, int type, struct FTW *ftw)
{
    (void)st, (void)type, (void)ftw;
    remove(path);
    return 0;
}

/* Removes what an earlier, killed run of the job may have left: temporary
 * files (".name.tmpPID-N.ext", see common/fileio.h), the old records and
 * the old assets (another run's feathers, or a killed run's temporaries). */
static void clean_job_folder(const plm_batch *b, int job)
{
    char dir[PLM_PATH_MAX], path[PLM_PATH_MAX];
    plm_batch_job_path(b, job, "", dir, sizeof dir);
    DIR *d = opendir(dir);
    for (struct dirent *e = d ? readdir(d) : NULL; e; e = readdir(d))
        if (e->d_name[0] == '.' && strstr(e->d_name, ".tmp") &&
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name) < (int)sizeof path)
            remove(path);
    if (d)
        closedir(d);
    static const char *const records[] = {"summary.json", "failed.json", "started.json"};
    for (int i = 0; i < 3; ++i) {
        plm_batch_job_path(b, job, records[i], path, sizeof path);
        remove(path);
    }
    plm_batch_job_path(b, job, ASSETS, path, sizeof path);
    nftw(path, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

static volatile sig_atomic_t stop_job;

static void on_stop(int sig)
{
    stop_job = sig;
}

static cJSON *string_array(char *const *items, int n)
{
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; i < n; ++i)
        cJSON_AddItemToArray(a, cJSON_CreateString(items[i]));
    return a;
}

static int finish_failed(const plm_batch *b, int job, const char *message, int status)
{
    char path[PLM_PATH_MAX];
    cJSON *doc = record(b, job, "failed");
    cJSON_AddStringToObject(doc, "error", message);
    cJSON_AddNumberToObject(doc, "exit", status);
    plm_batch_job_path(b, job, "failed.json", path, sizeof path);
    plm_batch_write_json(path, doc);
    cJSON_Delete(doc);
    fprintf(stderr, "job %s failed: %s\n", b->m.jobs[job].name, message);
    return status;
}

/* The file out/<job>/<file> as "file": {"bytes", "fnv1a64"}; 0 if unreadable. */
static int add_output(const plm_batch *b, int job, const char *file, cJSON *files)
{
    char path[PLM_PATH_MAX], hex[17];
    long long bytes;
    plm_batch_job_path(b, job, file, path, sizeof path);
    if (!hash_file(path, &bytes, hex))
        return 0;
    cJSON *f = cJSON_AddObjectToObject(files, file);
    return f && cJSON_AddNumberToObject(f, "bytes", (double)bytes) && cJSON_AddStringToObject(f, "fnv1a64", hex);
}

/* Every file under out/<job>/<folder>, by name, as add_output. */
static int add_outputs_under(const plm_batch *b, int job, const char *folder, cJSON *files)
{
    char dir[PLM_PATH_MAX], sub[PLM_PATH_MAX];
    struct dirent **list = NULL; /* scandir leaves it unset when it fails (no folder: a scene without feathers) */
    plm_batch_job_path(b, job, folder, dir, sizeof dir);
    int n = scandir(dir, &list, NULL, alphasort), ok = n >= 0 || errno == ENOENT;
    for (int i = 0; i < n; ++i) {
        const struct dirent *e = list[i];
        char path[PLM_PATH_MAX];
        struct stat st;
        if (ok && e->d_name[0] != '.' &&
            (ok = snprintf(sub, sizeof sub, "%s/%s", folder, e->d_name) < (int)sizeof sub &&
                  plm_batch_job_path(b, job, sub, path, sizeof path) && lstat(path, &st) == 0))
            ok = S_ISDIR(st.st_mode) ? add_outputs_under(b, job, sub, files) : add_output(b, job, sub, files);
        free(list[i]);
    }
    free(list);
    return ok;
}

static cJSON *summary_document(const plm_batch *b, int job, const plm_batch_render *rj, double total)
{
    const plm_batch_job *bj = &b->m.jobs[job];
    char key[17];
    key_hex(bj, key);
    cJSON *doc = record(b, job, "done");
    cJSON_AddStringToObject(doc, "key", key);
    cJSON_AddStringToObject(doc, "scene", bj->scene);
    cJSON_AddItemToObject(doc, "set", string_array(bj->sets, bj->n_sets));
    cJSON_AddStringToObject(doc, "label", bj->label);
    cJSON_AddNumberToObject(doc, "width", rj->width);
    cJSON_AddNumberToObject(doc, "height", rj->height);
    cJSON_AddNumberToObject(doc, "spp", rj->spp);
    cJSON_AddNumberToObject(doc, "seed", (double)rj->seed);
    cJSON_AddNumberToObject(doc, "threads", rj->threads_used);
    cJSON_AddNumberToObject(doc, "samples", (double)rj->samples);
    cJSON_AddNumberToObject(doc, "nonfinite_samples", (double)rj->nonfinite);
    cJSON *sec = cJSON_AddObjectToObject(doc, "seconds");
    cJSON_AddNumberToObject(sec, "load", rj->load_seconds);
    cJSON_AddNumberToObject(sec, "render", rj->render_seconds);
    cJSON_AddNumberToObject(sec, "write", rj->write_seconds);
    cJSON_AddNumberToObject(sec, "total", total);
    cJSON_AddBoolToObject(doc, "assets", bj->assets);
    cJSON *files = cJSON_AddObjectToObject(doc, "outputs");
    int ok = 1;
    for (int i = 0; ok && i < N_OUTPUTS; ++i)
        ok = add_output(b, job, outputs[i], files);
    if (ok && bj->assets)
        ok = add_outputs_under(b, job, ASSETS, files);
    if (!ok) {
        cJSON_Delete(doc);
        return NULL;
    }
    return doc;
}

int plm_batch_run_job(const plm_batch *b, int job, int threads, int quiet, plm_batch_render_fn render, void *ctx)
{
    const plm_batch_job *bj = &b->m.jobs[job];
    char dir[PLM_PATH_MAX], path[PLM_PATH_MAX];
    plm_error err;
    plm_batch_job_path(b, job, "", dir, sizeof dir);
    if (plm_make_dirs(dir, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 1;
    }
    clean_job_folder(b, job);
    double t0 = plm_seconds();
    cJSON *started = record(b, job, "started");
    plm_batch_job_path(b, job, "started.json", path, sizeof path);
    int ok = plm_batch_write_json(path, started);
    cJSON_Delete(started);
    if (!ok)
        return 1;

    plm_batch_render rj;
    memset(&rj, 0, sizeof rj);
    rj.job = bj;
    rj.threads = threads;
    rj.progress = !quiet;
    rj.cancel = &stop_job;
    char png[PLM_PATH_MAX], exr[PLM_PATH_MAX], resolved[PLM_PATH_MAX], assets[PLM_PATH_MAX];
    plm_batch_job_path(b, job, outputs[0], png, sizeof png);
    plm_batch_job_path(b, job, outputs[1], exr, sizeof exr);
    plm_batch_job_path(b, job, outputs[2], resolved, sizeof resolved);
    plm_batch_job_path(b, job, ASSETS, assets, sizeof assets);
    rj.png = png;
    rj.exr = exr;
    rj.resolved = resolved;
    rj.asset_dir = bj->assets ? assets : NULL;
    /* A scheduler stops a task with SIGTERM (time limit, scancel): the render
     * ends at the next tile and the job records that it failed. */
    struct sigaction sa, old_term, old_int;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop;
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGTERM, &sa, &old_term);
    sigaction(SIGINT, &sa, &old_int);
    int status = render(&rj, ctx);
    sigaction(SIGTERM, &old_term, NULL);
    sigaction(SIGINT, &old_int, NULL);
    if (status != 0)
        return finish_failed(b, job,
                             !rj.interrupted        ? rj.error
                             : stop_job == SIGTERM ? "stopped by SIGTERM (scancel, a time limit or kill)"
                                                   : "stopped by SIGINT (Ctrl-C)",
                             status);
    double total = plm_seconds() - t0;
    cJSON *summary = summary_document(b, job, &rj, total);
    if (!summary)
        return finish_failed(b, job, "an output could not be read back for its hash", 1);
    plm_batch_job_path(b, job, "summary.json", path, sizeof path);
    ok = plm_batch_write_json(path, summary);
    cJSON_Delete(summary);
    return ok ? 0 : finish_failed(b, job, "summary.json could not be written", 1);
}
