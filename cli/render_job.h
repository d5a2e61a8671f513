/* One render from a scene file to images, as `plumage render` and every
 * `plumage batch` job do it: the scene read with its overrides, rendered,
 * written atomically, and the figures a summary needs handed back. */
#ifndef PLUMAGE_CLI_RENDER_JOB_H
#define PLUMAGE_CLI_RENDER_JOB_H

#include <signal.h>

#include "render/render.h"

typedef struct plm_render_job {
    /* inputs: zero means "as the scene says" */
    const char *scene;
    const char *const *sets; /* "path=value" overrides (common/json_set.h) */
    int n_sets;
    int spp, width, height, threads, max_depth; /* max_depth: -1 = the scene's */
    long long seed;                             /* -1 = the scene's film.seed */
    int estimator;
    int progress;
    int exposure_given;
    double exposure;
    int view;             /* 0 = the scene's film.view, else a plm_view + 1 */
    double white_balance; /* 0 = the scene's film.white_balance */
    char png[PLM_PATH_MAX], exr[PLM_PATH_MAX]; /* both "": the scene's film.png/exr (see plm_render_job_run) */
    int turntable;        /* > 0: that many frames around the subject, numbered after png/exr (cli/turntable.h) */
    volatile sig_atomic_t *cancel;
    int discard_interrupted; /* batch jobs: a cancelled render writes no image */
    const char *resolved;    /* if set: the resolved scene is written here (docs/batch.md) */
    const char *asset_dir;   /* if set: each generated feather's files go into a folder here */
    /* outputs */
    int out_width, out_height, out_spp;
    unsigned long long out_seed;
    long long samples, nonfinite;
    int interrupted, used_threads;
    double load_seconds;   /* reading the scene, generating its feathers */
    double render_seconds; /* building the world and sampling */
    double write_seconds;
    char error[1024]; /* the message of a failure ("" on success) */
    double peak_mib;  /* peak resident memory during the job (the process's if it cannot be reset per job) */
    double before_mib, image_library_mib, scene_mib; /* held at the start, added by loading the image
                                                        library, the scene and its render at their peak */
} plm_render_job;

/* Runs the job; messages go to stderr. Returns the exit status: 0, 1 on
 * an error, 130 if *cancel stopped the render (the image so far is written). */
int plm_render_job_run(plm_render_job *job);

#endif
