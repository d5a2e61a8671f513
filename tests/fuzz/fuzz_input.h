/* What every harness shares. libFuzzer hands a harness bytes in memory; the
 * scene reader takes them as they are, the others take a path (OpenImageIO
 * opens files itself), so there the bytes go to a file of the harness's name
 * in a private directory made once per process and removed at exit. A failed
 * read must explain itself: an empty message is reported as a crash. */
#ifndef PLUMAGE_TESTS_FUZZ_INPUT_H
#define PLUMAGE_TESTS_FUZZ_INPUT_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/error.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char fuzz_dir[256], fuzz_path[512];

static void fuzz_cleanup(void)
{
    remove(fuzz_path);
    rmdir(fuzz_dir);
}

/* <private dir>/name: where a harness's input lives, so that relative paths
 * an input names resolve in an empty directory. */
static const char *fuzz_input_path(const char *name)
{
    if (!fuzz_dir[0]) {
        const char *tmp = getenv("TMPDIR");
        snprintf(fuzz_dir, sizeof fuzz_dir, "%s/plumage-fuzz-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
        if (!mkdtemp(fuzz_dir)) {
            perror("fuzz: mkdtemp");
            abort();
        }
        snprintf(fuzz_path, sizeof fuzz_path, "%s/%s", fuzz_dir, name);
        atexit(fuzz_cleanup);
    }
    return fuzz_path;
}

/* Writes data to fuzz_input_path(name) and returns that path. */
static const char *fuzz_write_input(const uint8_t *data, size_t size, const char *name)
{
    fuzz_input_path(name);
    FILE *fp = fopen(fuzz_path, "wb");
    if (!fp || fwrite(data, 1, size, fp) != size || fclose(fp) != 0) {
        perror("fuzz: writing the input");
        abort();
    }
    return fuzz_path;
}

/* Aborts (a finding) when a reader failed without saying why. */
static void fuzz_check_failure(plm_result rc, const plm_error *err)
{
    if (rc != PLM_OK && !err->message[0]) {
        fprintf(stderr, "fuzz: %s with no message\n", plm_result_name(rc));
        abort();
    }
}

#endif
