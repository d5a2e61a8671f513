/* File helpers shared by the cmocka tests: species presets from the source
 * tree and whole files read back for byte comparisons. Include after
 * <cmocka.h>; the test must be compiled with PLUMAGE_SOURCE_DIR (CMake does). */
#ifndef PLUMAGE_TESTS_TEST_FILES_H
#define PLUMAGE_TESTS_TEST_FILES_H

#include <stdio.h>
#include <stdlib.h>

#include "generate/species.h"

/* presets/species/<name>.json, which must load. */
static inline plm_species load_preset(const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/presets/species/%s.json", PLUMAGE_SOURCE_DIR, name);
    plm_species sp;
    plm_error err = {{0}};
    plm_result rc = plm_species_load(path, &sp, &err);
    if (rc != PLM_OK)
        fprintf(stderr, "%s\n", err.message);
    assert_int_equal(rc, PLM_OK);
    return sp;
}

/* The whole of a file that must exist and not be empty (malloc'd; *size set). */
static inline unsigned char *read_whole_file(const char *path, long *size)
{
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    fseek(fp, 0, SEEK_END);
    *size = ftell(fp);
    rewind(fp);
    assert_true(*size > 0);
    unsigned char *bytes = malloc((size_t)*size);
    assert_non_null(bytes);
    assert_int_equal(fread(bytes, 1, (size_t)*size, fp), (size_t)*size);
    fclose(fp);
    return bytes;
}

#endif
