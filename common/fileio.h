/* Safe file output: everything plumage writes goes to a temporary file in the
 * destination's directory and is renamed over the destination only when
 * complete, so a failed or interrupted run never leaves a partial file. */
#ifndef PLUMAGE_COMMON_FILEIO_H
#define PLUMAGE_COMMON_FILEIO_H

#include <stdio.h>
#include "common/error.h"

typedef struct plm_atomic_file {
    FILE *fp;             /* write here */
    char path[4096];      /* final destination */
    char temp_path[4096]; /* where the data goes until commit */
} plm_atomic_file;

/* Opens a temporary file next to path. */
plm_result plm_atomic_open(plm_atomic_file *f, const char *path, plm_error *err);
/* Closes and renames onto the destination; removes the temporary on failure. */
plm_result plm_atomic_commit(plm_atomic_file *f, plm_error *err);
/* Closes and removes the temporary; the destination is untouched. */
void plm_atomic_abort(plm_atomic_file *f);

/* A temporary name beside path that keeps its extension (image writers choose
 * the format by extension): "dir/name.png" -> "dir/.name.tmp<pid>-<n>.png". */
void plm_temp_path_for(const char *path, char *out, size_t out_size);

/* Creates a directory and its parents if missing. */
plm_result plm_make_dirs(const char *path, plm_error *err);

/* Reads a whole file into a NUL-terminated malloc'd buffer. */
plm_result plm_read_text_file(const char *path, char **out, plm_error *err);

/* Lower-cased extension of path without the dot ("" if none). */
const char *plm_path_extension(const char *path, char *buf, size_t buf_size);

#endif
