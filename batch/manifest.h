/* Batch manifests: a list of render jobs, or a sweep (the cartesian product
 * of parameter values), each job a scene file plus overrides. docs/batch.md
 * documents the format. The reader parses from a buffer so that it can be
 * fuzzed; every error names the manifest and the field. */
#ifndef PLUMAGE_BATCH_MANIFEST_H
#define PLUMAGE_BATCH_MANIFEST_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"

#define PLM_BATCH_MAX_JOBS 100000
#define PLM_BATCH_MAX_SWEEP_KEYS 8

typedef struct plm_batch_job {
    char name[96];   /* its folder under the output folder: "0003" or "0003-<name>" */
    char *scene;     /* resolved against the manifest's folder */
    char **sets;     /* "path=JSON value": the manifest's "set" first, then the job's own */
    int n_sets;
    int spp;         /* 0 = the scene's film.spp */
    int width, height; /* 0 = the scene's film size */
    long long seed;  /* -1 = the scene's film.seed */
    int assets;      /* write the generated feathers' meshes and textures (default 1) */
    char *label;     /* sweep: one "key=value" line per parameter that varies (the key's last
                        segment unless two keys share it); jobs: the name */
    uint64_t key;    /* hash of everything above but the name: a summary for other inputs is stale */
} plm_batch_job;

typedef struct plm_manifest {
    char *output;    /* output folder, relative to the working directory like a scene's
                        film.png ("" = not given) */
    plm_batch_job *jobs;
    int n_jobs;
    /* A sweep's shape, for the contact sheet: jobs are in row-major order of
     * the keys as written (the last key varies fastest). 0 keys: a job list. */
    int n_keys;
    int key_counts[PLM_BATCH_MAX_SWEEP_KEYS];
} plm_manifest;

/* Parses manifest text (len bytes, need not be NUL-terminated). `path` names
 * the manifest in messages and is the base of relative paths; scene files
 * must exist. On failure *m is left empty. */
plm_result plm_manifest_parse(const char *text, size_t len, const char *path, plm_manifest *m, plm_error *err);
plm_result plm_manifest_load(const char *path, plm_manifest *m, plm_error *err);
void plm_manifest_free(plm_manifest *m);

/* 64-bit FNV-1a, continued from h (start with PLM_FNV_OFFSET): job keys and output hashes. */
#define PLM_FNV_OFFSET 0xcbf29ce484222325ull
uint64_t plm_fnv1a64(const void *data, size_t len, uint64_t h);

#endif
