#include "batch/manifest.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/fileio.h"
#include "common/json.h"

uint64_t plm_fnv1a64(const void *data, size_t len, uint64_t h)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < len; ++i) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

/* What the manifest and each job may say; a job's own values win. */
typedef struct job_fields {
    const char *scene;
    const cJSON *set;
    int spp, width, height;
    long long seed;
    int assets;
} job_fields;

static char *dup_string(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

/* dir(base)/rel unless rel is absolute or base has no folder. */
static char *resolve(const char *base, const char *rel)
{
    const char *slash = strrchr(base, '/');
    if (rel[0] == '/' || !slash)
        return dup_string(rel);
    size_t n = (size_t)(slash - base) + strlen(rel) + 2;
    char *out = malloc(n);
    if (out)
        snprintf(out, n, "%.*s/%s", (int)(slash - base), base, rel);
    return out;
}

static plm_result read_path_field(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                                  const char **out)
{
    const char *def = *out;
    plm_result rc = plm_json_string(r, obj, path, key, def, out);
    if (rc == PLM_OK && *out && !(*out)[0])
        return plm_json_fail(r, path, key, "expected a non-empty file path");
    return rc;
}

/* "set": {"camera.fov": 30, ...}: each key a dotted path, each value any JSON. */
static plm_result check_set(const plm_json_reader *r, const cJSON *set, const char *path)
{
    if (!set)
        return PLM_OK;
    if (!cJSON_IsObject(set))
        return plm_json_fail(r, path, "set", "expected an object of \"path.to.field\": value");
    for (const cJSON *e = set->child; e; e = e->next)
        if (!e->string[0] || strchr(e->string, '=') || e->string[0] == '.' || strstr(e->string, ".."))
            return plm_json_fail(r, path, "set", "\"%s\" is not a dotted path such as camera.fov", e->string);
    return PLM_OK;
}

/* Fields shared by the manifest's top level and each job, over `f` (the defaults). */
static plm_result read_job_fields(const plm_json_reader *r, const cJSON *obj, const char *path, job_fields *f)
{
    plm_result rc = read_path_field(r, obj, path, "scene", &f->scene);
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "spp", f->spp, 1, 1 << 24, &f->spp);
    int seed = (int)f->seed;
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "seed", seed, -1, 2147483647, &seed);
    f->seed = seed;
    if (rc == PLM_OK)
        rc = plm_json_bool(r, obj, path, "assets", f->assets, &f->assets);
    const cJSON *res = cJSON_GetObjectItemCaseSensitive(obj, "resolution");
    if (rc == PLM_OK && res) {
        const cJSON *w = cJSON_GetArrayItem(res, 0), *h = cJSON_GetArrayItem(res, 1);
        /* The range first: converting a double beyond int's range to int is undefined (found by fuzz_batch). */
        if (!cJSON_IsArray(res) || cJSON_GetArraySize(res) != 2 || !cJSON_IsNumber(w) || !cJSON_IsNumber(h) ||
            !(w->valuedouble >= 1 && w->valuedouble <= 16384 && h->valuedouble >= 1 && h->valuedouble <= 16384) ||
            w->valuedouble != (int)w->valuedouble || h->valuedouble != (int)h->valuedouble)
            return plm_json_fail(r, path, "resolution", "expected [width, height], whole numbers in [1, 16384]");
        f->width = (int)w->valuedouble;
        f->height = (int)h->valuedouble;
    }
    if (rc == PLM_OK)
        rc = check_set(r, cJSON_GetObjectItemCaseSensitive(obj, "set"), path);
    return rc;
}

/* "path=value" with the value as compact JSON. */
static char *assignment(const char *path, const cJSON *value)
{
    char *v = cJSON_PrintUnformatted(value);
    if (!v)
        return NULL;
    size_t n = strlen(path) + strlen(v) + 2;
    char *s = malloc(n);
    if (s)
        snprintf(s, n, "%s=%s", path, v);
    free(v);
    return s;
}

static int append_set(plm_batch_job *job, char *s)
{
    char **bigger = s ? realloc(job->sets, sizeof *bigger * (size_t)(job->n_sets + 1)) : NULL;
    if (!bigger) {
        free(s);
        return 0;
    }
    job->sets = bigger;
    job->sets[job->n_sets++] = s;
    return 1;
}

static int append_sets(plm_batch_job *job, const cJSON *set)
{
    for (const cJSON *e = set ? set->child : NULL; e; e = e->next)
        if (!append_set(job, assignment(e->string, e)))
            return 0;
    return 1;
}

static void job_free(plm_batch_job *job)
{
    for (int i = 0; i < job->n_sets; ++i)
        free(job->sets[i]);
    free(job->sets);
    free(job->scene);
    free(job->label);
}

void plm_manifest_free(plm_manifest *m)
{
    for (int i = 0; i < m->n_jobs; ++i)
        job_free(&m->jobs[i]);
    free(m->jobs);
    free(m->output);
    memset(m, 0, sizeof *m);
}

static uint64_t job_key(const plm_batch_job *job)
{
    char nums[128];
    snprintf(nums, sizeof nums, "%d %d %d %lld %d", job->spp, job->width, job->height, job->seed, job->assets);
    uint64_t h = plm_fnv1a64(job->scene, strlen(job->scene) + 1, PLM_FNV_OFFSET);
    for (int i = 0; i < job->n_sets; ++i)
        h = plm_fnv1a64(job->sets[i], strlen(job->sets[i]) + 1, h);
    return plm_fnv1a64(nums, strlen(nums), h);
}

/* Fills job `index` from its fields (the scene must exist). */
static plm_result make_job(const plm_json_reader *r, const char *where, const job_fields *f, const cJSON *top_set,
                           int index, int digits, const char *name, plm_batch_job *job)
{
    if (!f->scene)
        return plm_json_fail(r, where, "scene", "required (a scene file, here or at the top level)");
    job->scene = resolve(r->file, f->scene);
    if (!job->scene)
        return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
    if (access(job->scene, R_OK) != 0)
        return plm_json_fail(r, where, "scene", "%s: cannot read: %s", job->scene, strerror(errno));
    job->spp = f->spp;
    job->width = f->width;
    job->height = f->height;
    job->seed = f->seed;
    job->assets = f->assets;
    if (snprintf(job->name, sizeof job->name, "%0*d%s%s", digits, index, name ? "-" : "", name ? name : "") >=
        (int)sizeof job->name)
        return plm_json_fail(r, where, "name", "too long");
    if (!append_sets(job, top_set) || !append_sets(job, f->set))
        return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
    return PLM_OK;
}

static int digits_for(int n)
{
    int d = 4;
    for (int v = 10000; v <= n - 1; v *= 10)
        ++d;
    return d;
}

static plm_result read_jobs(const plm_json_reader *r, const cJSON *jobs, const job_fields *top, const cJSON *top_set,
                            plm_manifest *m)
{
    static const char *const keys[] = {"name", "scene", "set", "spp", "resolution", "seed", "assets", NULL};
    int n = cJSON_GetArraySize(jobs);
    if (!cJSON_IsArray(jobs) || n == 0)
        return plm_json_fail(r, "jobs", NULL, "expected a non-empty array of jobs");
    if (n > PLM_BATCH_MAX_JOBS)
        return plm_json_fail(r, "jobs", NULL, "%d jobs, at most %d", n, PLM_BATCH_MAX_JOBS);
    m->jobs = calloc((size_t)n, sizeof *m->jobs);
    if (!m->jobs)
        return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
    int i = 0;
    for (const cJSON *e = jobs->child; e; e = e->next, ++i) {
        char where[32];
        snprintf(where, sizeof where, "jobs[%d]", i);
        m->n_jobs = i + 1;
        job_fields f = *top;
        f.set = cJSON_GetObjectItemCaseSensitive(e, "set");
        const char *name = NULL;
        plm_result rc = plm_json_check_object(r, e, where, keys);
        if (rc == PLM_OK)
            rc = read_job_fields(r, e, where, &f);
        if (rc == PLM_OK)
            rc = plm_json_string(r, e, where, "name", NULL, &name);
        if (rc == PLM_OK && name &&
            (!name[0] || strlen(name) > 64 || strspn(name, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                           "0123456789._-") != strlen(name) || name[0] == '.'))
            rc = plm_json_fail(r, where, "name", "\"%s\": 1 to 64 letters, digits, '.', '_' or '-' (a folder name)",
                               name);
        if (rc == PLM_OK)
            rc = make_job(r, where, &f, top_set, i, digits_for(n), name, &m->jobs[i]);
        if (rc == PLM_OK)
            m->jobs[i].label = dup_string(name ? name : m->jobs[i].name);
        if (rc == PLM_OK && !m->jobs[i].label)
            rc = plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
        if (rc != PLM_OK)
            return rc;
    }
    return PLM_OK;
}

/* The label of a sweep job: one "key=value" line per key with more than one
 * value, by its whole path (a last segment alone can mean two things, as
 * barb.eccentricity and masking.barb_eccentricity once did). */
static char *sweep_label(const cJSON *sweep, const int *choice)
{
    char buf[1024] = "";
    int k = 0;
    for (const cJSON *e = sweep->child; e; e = e->next, ++k) {
        if (cJSON_GetArraySize(e) < 2)
            continue;
        const cJSON *v = cJSON_GetArrayItem(e, choice[k]);
        char *text = cJSON_IsString(v) ? dup_string(v->valuestring) : cJSON_PrintUnformatted(v);
        snprintf(buf + strlen(buf), sizeof buf - strlen(buf), "%s%s=%s", buf[0] ? "\n" : "",
                 e->string, text ? text : "?");
        free(text);
    }
    return dup_string(buf);
}

static plm_result read_sweep(const plm_json_reader *r, const cJSON *sweep, const job_fields *top,
                             const cJSON *top_set, plm_manifest *m)
{
    if (!cJSON_IsObject(sweep) || !sweep->child)
        return plm_json_fail(r, "sweep", NULL, "expected a non-empty object of \"path.to.field\": [values...]");
    long long total = 1;
    for (const cJSON *e = sweep->child; e; e = e->next) {
        int n = cJSON_GetArraySize(e);
        if (!cJSON_IsArray(e) || n == 0)
            return plm_json_fail(r, "sweep", e->string, "expected a non-empty array of values");
        if (m->n_keys == PLM_BATCH_MAX_SWEEP_KEYS)
            return plm_json_fail(r, "sweep", NULL, "at most %d parameters", PLM_BATCH_MAX_SWEEP_KEYS);
        m->key_counts[m->n_keys++] = n;
        total *= n;
        if (total > PLM_BATCH_MAX_JOBS)
            return plm_json_fail(r, "sweep", NULL, "more than %d jobs in the product", PLM_BATCH_MAX_JOBS);
    }
    plm_result rc = check_set(r, sweep, "");
    if (rc != PLM_OK)
        return plm_json_fail(r, "sweep", NULL, "keys must be dotted paths such as camera.fov");
    m->jobs = calloc((size_t)total, sizeof *m->jobs);
    if (!m->jobs)
        return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
    for (int i = 0; i < (int)total; ++i) {
        int choice[PLM_BATCH_MAX_SWEEP_KEYS], rest = i;
        for (int k = m->n_keys - 1; k >= 0; --k) {
            choice[k] = rest % m->key_counts[k];
            rest /= m->key_counts[k];
        }
        m->n_jobs = i + 1;
        plm_batch_job *job = &m->jobs[i];
        rc = make_job(r, "", top, top_set, i, digits_for((int)total), NULL, job);
        int k = 0;
        for (const cJSON *e = sweep->child; rc == PLM_OK && e; e = e->next, ++k)
            if (!append_set(job, assignment(e->string, cJSON_GetArrayItem(e, choice[k]))))
                rc = plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
        if (rc == PLM_OK && !(job->label = sweep_label(sweep, choice)))
            rc = plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
        if (rc != PLM_OK)
            return rc;
    }
    return PLM_OK;
}

plm_result plm_manifest_parse(const char *text, size_t len, const char *path, plm_manifest *m, plm_error *err)
{
    static const char *const keys[] = {"scene", "output", "spp", "resolution", "seed", "assets", "set", "jobs", "sweep",
                                       NULL};
    memset(m, 0, sizeof *m);
    cJSON *root;
    plm_result rc = plm_json_parse(text, len, path, &root, err);
    if (rc != PLM_OK)
        return rc;
    plm_json_reader r = {path, err, 0};
    job_fields top = {NULL, NULL, 0, 0, 0, -1, 1};
    const char *output = NULL;
    const cJSON *jobs = cJSON_GetObjectItemCaseSensitive(root, "jobs");
    const cJSON *sweep = cJSON_GetObjectItemCaseSensitive(root, "sweep");
    const cJSON *top_set = cJSON_GetObjectItemCaseSensitive(root, "set");
    rc = plm_json_check_object(&r, root, "", keys);
    if (rc == PLM_OK)
        rc = read_job_fields(&r, root, "", &top);
    if (rc == PLM_OK)
        rc = read_path_field(&r, root, "", "output", &output);
    if (rc == PLM_OK && !jobs == !sweep)
        rc = plm_json_fail(&r, "", NULL, "give either \"jobs\" (a list) or \"sweep\" (parameter values), not %s",
                           jobs ? "both" : "neither");
    if (rc == PLM_OK)
        rc = jobs ? read_jobs(&r, jobs, &top, top_set, m) : read_sweep(&r, sweep, &top, top_set, m);
    if (rc == PLM_OK && !(m->output = dup_string(output ? output : "")))
        rc = plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory");
    for (int i = 0; rc == PLM_OK && i < m->n_jobs; ++i)
        m->jobs[i].key = job_key(&m->jobs[i]);
    cJSON_Delete(root);
    if (rc != PLM_OK)
        plm_manifest_free(m);
    return rc;
}

plm_result plm_manifest_load(const char *path, plm_manifest *m, plm_error *err)
{
    char *text;
    memset(m, 0, sizeof *m);
    plm_result rc = plm_read_text_file(path, &text, err);
    if (rc != PLM_OK)
        return rc;
    rc = plm_manifest_parse(text, strlen(text), path, m, err);
    free(text);
    return rc;
}
