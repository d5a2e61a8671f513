/* Safe file output: everything plumage writes goes to a temporary file in the
 * destination's directory and is renamed over the destination only when
 * complete, so a failed or interrupted run never leaves a partial file. */
#ifndef PLUMAGE_COMMON_FILEIO_H
#define PLUMAGE_COMMON_FILEIO_H

#include <stdio.h>
#include "common/error.h"

/* The longest path plumage takes, with its terminating zero. */
#define PLM_PATH_MAX 4096

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

/* Every writer (plm_atomic_file, images, meshes) goes through these three:
 * it writes into target, then commits, or discards on any failure. target is
 * a temporary beside path, renamed over it when complete; but when path is
 * an existing device or pipe (/dev/null, /dev/full, a FIFO), which a rename
 * would replace, target is path itself and a failure is reported as it is. */
void plm_output_target(const char *path, char *target, size_t target_size);
plm_result plm_output_commit(const char *path, const char *target, plm_error *err);
void plm_output_discard(const char *path, const char *target);

/* Writes size bytes to path through a plm_atomic_file. */
plm_result plm_write_file(const char *path, const void *data, size_t size, plm_error *err);

/* Creates a directory and its parents if missing. */
plm_result plm_make_dirs(const char *path, plm_error *err);
/* The same, noting in first_created (size bytes) the outermost directory it
 * created ("" if it created none): removing that and the ones below it undoes it. */
plm_result plm_make_dirs_noting(const char *path, char *first_created, size_t size, plm_error *err);

/* Reads a whole regular file of at most max_size bytes into a malloc'd
 * buffer with a NUL after the last byte (*size excludes it). Devices, pipes
 * and larger files are refused before anything is allocated. */
plm_result plm_read_file(const char *path, size_t max_size, char **out, size_t *size, plm_error *err);

/* The largest text file (scene, species) plumage reads: 256 MiB. */
#define PLM_TEXT_FILE_MAX ((size_t)256 << 20)

/* plm_read_file for text files (at most PLM_TEXT_FILE_MAX). */
plm_result plm_read_text_file(const char *path, char **out, plm_error *err);

/* Lower-cased extension of path without the dot ("" if none). */
const char *plm_path_extension(const char *path, char *buf, size_t buf_size);

#endif
