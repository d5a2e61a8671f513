/* Adapters built as modules: shared objects that plumage opens with dlopen()
 * the first time it needs them, so that commands which never touch their
 * library neither load it nor pay for it at start-up (docs/benchmarks.md,
 * "Start-up and baseline memory"). Each module exports one symbol: a table
 * of function pointers whose first member is its own size, so that a module
 * from another build is refused. OpenImageIO (common/image_module.h) and
 * Assimp (export/asset_module.c) are modules. */
#ifndef PLUMAGE_COMMON_MODULE_H
#define PLUMAGE_COMMON_MODULE_H

#include <stddef.h>

typedef struct plm_module_spec {
    const char *what;       /* in messages: "image library" */
    const char *file;       /* the module's file name: "plumage_image_oiio.so" */
    const char *env;        /* the environment variable naming its full path, overriding the search */
    const char *build_path; /* where the build tree holds it */
    const char *symbol;     /* its table's symbol */
    unsigned size;          /* the table's size as this build knows it */
} plm_module_spec;

/* The module's table, opened from the first of these that exists: $env
 * alone if set; otherwise next to the executable, the install layout's
 * <bin>/PLUMAGE_MODULE_RELDIR, and last the build tree. A path that exists
 * but does not load is an error in itself. NULL on failure, with a message
 * naming the module, the paths tried and what to do in message. The module
 * stays open for the process's life. Not thread-safe: callers load once
 * (pthread_once). */
const void *plm_module_open(const plm_module_spec *spec, char *message, size_t size);

#endif
