/* image_io.h's file functions, forwarded to the OpenImageIO module opened on
 * first use (see image_module.h for why it is a module). */
#include <dlfcn.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/image_module.h"
#include "common/memory.h"

/* The module is opened once per process and stays open: the table and the
 * load error are process-wide by nature, so they live here, set once under
 * pthread_once (render threads and tests may reach an image call together). */
static pthread_once_t module_once = PTHREAD_ONCE_INIT;
static const plm_image_module *module_table;
static char module_message[sizeof ((plm_error *)0)->message];
static double module_added_mib, module_peak_before_mib; /* see plm_image_library_memory */

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

static void module_failed(const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    vsnprintf(module_message, sizeof module_message, fmt, args);
    va_end(args);
}

/* Tries the paths in order: $PLUMAGE_IMAGE_MODULE alone if set; otherwise
 * next to the executable, the install layout's <bin>/PLUMAGE_MODULE_RELDIR,
 * and last the build tree where the module was built. A path that exists
 * but does not load is an error in itself (it names the file and why). */
static void load_module(void)
{
    enum { MAX_PATHS = 3, PATH_SIZE = 4096 };
    char paths[MAX_PATHS][PATH_SIZE];
    int count = 0;
    const char *override = getenv(PLM_IMAGE_MODULE_ENV);
    int overridden = override && override[0];
    char dir[PATH_SIZE];
    if (overridden) {
        snprintf(paths[count++], PATH_SIZE, "%s", override);
    } else {
        if (executable_dir(dir, sizeof dir)) {
            if (snprintf(paths[count], PATH_SIZE, "%s/%s", dir, PLM_IMAGE_MODULE_FILE) < PATH_SIZE)
                ++count;
            if (snprintf(paths[count], PATH_SIZE, "%s/%s/%s", dir, PLUMAGE_MODULE_RELDIR, PLM_IMAGE_MODULE_FILE) <
                PATH_SIZE)
                ++count;
        }
        snprintf(paths[count++], PATH_SIZE, "%s", PLUMAGE_MODULE_BUILD_PATH);
    }
    double resident_before = plm_memory_resident_mib();
    module_peak_before_mib = plm_memory_peak_mib();
    for (int i = 0; i < count; ++i) {
        if (access(paths[i], F_OK) != 0)
            continue;
        void *handle = dlopen(paths[i], RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            module_failed("image library module %s cannot be loaded: %s", paths[i], dlerror());
            return;
        }
        const plm_image_module *table = dlsym(handle, PLM_IMAGE_MODULE_SYMBOL);
        if (!table || table->size != sizeof *table) {
            dlclose(handle);
            module_failed("image library module %s is not from this build of plumage (rebuild or reinstall it)",
                          paths[i]);
            return;
        }
        module_table = table;
        module_added_mib = plm_memory_resident_mib() - resident_before;
        return;
    }
    char tried[MAX_PATHS * PATH_SIZE];
    size_t used = 0;
    for (int i = 0; i < count && used < sizeof tried; ++i) {
        int n = snprintf(tried + used, sizeof tried - used, "%s%s", i ? ", " : "", paths[i]);
        used += n > 0 ? (size_t)n : 0;
    }
    module_failed("image library module not found: looked for %s%s", tried,
                  overridden ? " (from " PLM_IMAGE_MODULE_ENV ")"
                             : "; reinstall plumage or set " PLM_IMAGE_MODULE_ENV " to the module's path");
}

/* The module's table, or NULL with the reason in err, prefixed by what the
 * caller was doing (the file it wanted to read or write). */
static const plm_image_module *image_module(const char *what, plm_error *err)
{
    pthread_once(&module_once, load_module);
    if (!module_table)
        plm_fail(err, PLM_ERR_INTERNAL, "%s: %s", what, module_message);
    return module_table;
}

plm_result plm_image_write(const char *path, int width, int height, int channels, plm_pixel_type type,
                           const void *data, plm_error *err)
{
    const plm_image_module *m = image_module(path, err);
    return m ? m->write(path, width, height, channels, type, data, err) : PLM_ERR_INTERNAL;
}

plm_result plm_image_read(const char *path, int *width, int *height, int *channels, float **pixels,
                          plm_error *err)
{
    *pixels = NULL;
    const plm_image_module *m = image_module(path, err);
    return m ? m->read(path, width, height, channels, pixels, err) : PLM_ERR_INTERNAL;
}

plm_result plm_image_encode_png(int width, int height, int channels, plm_pixel_type type, const void *data,
                                unsigned char **bytes, size_t *size, plm_error *err)
{
    *bytes = NULL;
    *size = 0;
    const plm_image_module *m = image_module("PNG in memory", err);
    return m ? m->encode_png(width, height, channels, type, data, bytes, size, err) : PLM_ERR_INTERNAL;
}

plm_result plm_image_draw_text(plm_image *img, int x, int y, int size_px, const char *text, const float color[3],
                               plm_error *err)
{
    const plm_image_module *m = image_module("draw text", err);
    return m ? m->draw_text(img, x, y, size_px, text, color, err) : PLM_ERR_INTERNAL;
}

void plm_image_library_memory(double *added_mib, double *peak_before_mib)
{
    *added_mib = module_table ? module_added_mib : 0.0;
    *peak_before_mib = module_table ? module_peak_before_mib : 0.0;
}
