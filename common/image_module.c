/* image_io.h's file functions, forwarded to the OpenImageIO module opened on
 * first use (see image_module.h for why it is a module). */
#include <pthread.h>

#include "common/image_module.h"
#include "common/memory.h"
#include "common/module.h"

/* The module is opened once per process and stays open: the table and the
 * load error are process-wide by nature, so they live here, set once under
 * pthread_once (render threads and tests may reach an image call together). */
static pthread_once_t module_once = PTHREAD_ONCE_INIT;
static const plm_image_module *module_table;
static char module_message[sizeof ((plm_error *)0)->message];
static double module_added_mib, module_peak_before_mib; /* see plm_image_library_memory */

/* Opens the module (common/module.h) and notes what loading it cost. */
static void load_module(void)
{
    static const plm_module_spec spec = {"image library", PLM_IMAGE_MODULE_FILE, PLM_IMAGE_MODULE_ENV,
                                         PLUMAGE_MODULE_BUILD_PATH, PLM_IMAGE_MODULE_SYMBOL,
                                         sizeof(plm_image_module)};
    double resident_before = plm_memory_resident_mib();
    module_peak_before_mib = plm_memory_peak_mib();
    module_table = plm_module_open(&spec, module_message, sizeof module_message);
    if (module_table)
        module_added_mib = plm_memory_resident_mib() - resident_before;
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
