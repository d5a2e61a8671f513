/* The contract between the image loader (image_module.c, in plumage_common)
 * and the OpenImageIO adapter (image_io.cpp), which is built as a separate
 * module and opened with dlopen() the first time an image is read or written.
 * Debian's OpenImageIO pulls in about 260 shared libraries; keeping it out of
 * the executable lets commands that touch no image start in milliseconds
 * (see docs/benchmarks.md). Callers use common/image_io.h, never this file. */
#ifndef PLUMAGE_COMMON_IMAGE_MODULE_H
#define PLUMAGE_COMMON_IMAGE_MODULE_H

#include "common/image_io.h"

/* One entry per function of image_io.h that needs OpenImageIO. */
typedef struct plm_image_module {
    unsigned size; /* sizeof(plm_image_module) as the module was built: a stale module is refused */
    plm_result (*write)(const char *path, int width, int height, int channels, plm_pixel_type type,
                        const void *data, plm_error *err);
    plm_result (*read)(const char *path, int *width, int *height, int *channels, float **pixels, plm_error *err);
    plm_result (*encode_png)(int width, int height, int channels, plm_pixel_type type, const void *data,
                             unsigned char **bytes, size_t *size, plm_error *err);
    plm_result (*draw_text)(plm_image *img, int x, int y, int size_px, const char *text, const float color[3],
                            plm_error *err);
} plm_image_module;

/* The one symbol the module exports: a `const plm_image_module`. */
#define PLM_IMAGE_MODULE_SYMBOL "plm_image_module_table"
/* The module's file name; where it is looked for is described in image_module.c. */
#define PLM_IMAGE_MODULE_FILE "plumage_image_oiio.so"
/* Environment variable naming the module's full path, overriding the search. */
#define PLM_IMAGE_MODULE_ENV "PLUMAGE_IMAGE_MODULE"

#endif
