/* Opening adapter modules (module.h). */
#include "common/module.h"

#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The folder holding the running executable, without a trailing slash. */
static int executable_dir(char *out, size_t size)
{
    ssize_t n = readlink("/proc/self/exe", out, size - 1);
    if (n <= 0)
        return 0;
    out[n] = '\0';
    char *slash = strrchr(out, '/');
    if (!slash)
        return 0;
    *slash = '\0';
    return 1;
}

enum { MAX_PATHS = 3, PATH_SIZE = 4096 };

/* The candidate paths in order; returns how many. */
static int candidates(const plm_module_spec *s, char paths[MAX_PATHS][PATH_SIZE])
{
    int count = 0;
    const char *override = getenv(s->env);
    if (override && override[0]) {
        snprintf(paths[count++], PATH_SIZE, "%s", override);
        return count;
    }
    char dir[PATH_SIZE];
    if (executable_dir(dir, sizeof dir)) {
        if (snprintf(paths[count], PATH_SIZE, "%s/%s", dir, s->file) < PATH_SIZE)
            ++count;
        if (snprintf(paths[count], PATH_SIZE, "%s/%s/%s", dir, PLUMAGE_MODULE_RELDIR, s->file) < PATH_SIZE)
            ++count;
    }
    snprintf(paths[count++], PATH_SIZE, "%s", s->build_path);
    return count;
}

const void *plm_module_open(const plm_module_spec *s, char *message, size_t size)
{
    char paths[MAX_PATHS][PATH_SIZE];
    int count = candidates(s, paths);
    for (int i = 0; i < count; ++i) {
        if (access(paths[i], F_OK) != 0)
            continue;
        void *handle = dlopen(paths[i], RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            snprintf(message, size, "%s module %s cannot be loaded: %s", s->what, paths[i], dlerror());
            return NULL;
        }
        const unsigned *table = dlsym(handle, s->symbol);
        if (!table || *table != s->size) {
            dlclose(handle);
            snprintf(message, size, "%s module %s is not from this build of plumage (rebuild or reinstall it)",
                     s->what, paths[i]);
            return NULL;
        }
        return table;
    }
    char tried[MAX_PATHS * PATH_SIZE];
    size_t used = 0;
    for (int i = 0; i < count && used < sizeof tried; ++i) {
        int n = snprintf(tried + used, sizeof tried - used, "%s%s", i ? ", " : "", paths[i]);
        used += n > 0 ? (size_t)n : 0;
    }
    const char *override = getenv(s->env);
    if (override && override[0])
        snprintf(message, size, "%s module not found: looked for %s (from %s)", s->what, tried, s->env);
    else
        snprintf(message, size, "%s module not found: looked for %s; reinstall plumage or set %s to the module's path",
                 s->what, tried, s->env);
    return NULL;
}
