/* What every harness shares. libFuzzer hands a harness bytes in memory; the
 * scene reader takes them as they are, the others take a path (OpenImageIO
 * opens files itself), so there the bytes go to a file of the harness's name
 * in a private directory made once per process and removed at exit. A failed
 * read must explain itself: an empty message is reported as a crash. */
#ifndef PLUMAGE_TESTS_FUZZ_INPUT_H
#define PLUMAGE_TESTS_FUZZ_INPUT_H

#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/error.h"
#include "common/image_io.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char fuzz_dir[256], fuzz_path[512];

/* Removes the private directory and whatever the harness left in it. */
static inline void fuzz_cleanup(void)
{
    DIR *d = opendir(fuzz_dir);
    for (struct dirent *e = d ? readdir(d) : NULL; e; e = readdir(d)) {
        char path[800];
        snprintf(path, sizeof path, "%s/%s", fuzz_dir, e->d_name);
        if (e->d_name[0] != '.')
            remove(path);
    }
    if (d)
        closedir(d);
    rmdir(fuzz_dir);
}

/* <private dir>/name: where a harness's input lives, so that relative paths
 * an input names resolve in a directory holding nothing else. */
static inline const char *fuzz_input_path(const char *name)
{
    if (!fuzz_dir[0]) {
        const char *tmp = getenv("TMPDIR");
        snprintf(fuzz_dir, sizeof fuzz_dir, "%s/plumage-fuzz-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
        if (!mkdtemp(fuzz_dir)) {
            perror("fuzz: mkdtemp");
            abort();
        }
        atexit(fuzz_cleanup);
    }
    snprintf(fuzz_path, sizeof fuzz_path, "%s/%s", fuzz_dir, name);
    return fuzz_path;
}

/* Writes data to fuzz_input_path(name) and returns that path. */
static inline const char *fuzz_write_input(const uint8_t *data, size_t size, const char *name)
{
    fuzz_input_path(name);
    FILE *fp = fopen(fuzz_path, "wb");
    if (!fp || fwrite(data, 1, size, fp) != size || fclose(fp) != 0) {
        perror("fuzz: writing the input");
        abort();
    }
    return fuzz_path;
}

/* Loads the image module (OpenImageIO and its ~260 libraries) before the
 * clock starts, by asking for an image that does not exist: a one-off cost
 * that would otherwise be charged to the first input that names an image. */
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    int w, h, c;
    float *pixels;
    plm_error err;
    plm_image_read(fuzz_input_path("preload.png"), &w, &h, &c, &pixels, &err);
    return 0;
}

/* Aborts (a finding) when a reader failed without saying why. */
static inline void fuzz_check_failure(plm_result rc, const plm_error *err)
{
    if (rc != PLM_OK && !err->message[0]) {
        fprintf(stderr, "fuzz: %s with no message\n", plm_result_name(rc));
        abort();
    }
}

#endif
