/* Image files through OpenImageIO (adapter in image_io.cpp), plus the
 * conversions every stage needs. Pixels are row-major, top row first,
 * channels interleaved. Writes are atomic (temporary file, then rename). */
#ifndef PLUMAGE_COMMON_IMAGE_IO_H
#define PLUMAGE_COMMON_IMAGE_IO_H

#include <stdint.h>
#include "common/error.h"

/* An image in memory: float channels, row-major, top row first. */
typedef struct plm_image {
    int width, height, channels;
    float *pixels; /* width * height * channels, malloc'd */
} plm_image;

typedef enum plm_pixel_type {
    PLM_PIXEL_FLOAT = 0,  /* 32-bit float (EXR, HDR, TIFF) */
    PLM_PIXEL_UINT8 = 1,  /* PNG, JPEG */
    PLM_PIXEL_UINT16 = 2  /* 16-bit PNG, TIFF */
} plm_pixel_type;

/* The format follows path's extension; data's element type is `type`. */
plm_result plm_image_write(const char *path, int width, int height, int channels, plm_pixel_type type,
                           const void *data, plm_error *err);

/* Reads any supported file as float; *pixels is malloc'd (caller frees). */
plm_result plm_image_read(const char *path, int *width, int *height, int *channels, float **pixels,
                          plm_error *err);

/* Linear float RGB -> 8-bit sRGB PNG, after scaling by 2^exposure and a
 * clamp (the simplest tone map: the values are shown as they are). Non-finite
 * values are written as black. */
plm_result plm_image_write_srgb_png(const char *path, int width, int height, const float *rgb, double exposure,
                                    plm_error *err);

/* Draws text into img (float, 3 or 4 channels) in the colour `color` (RGB;
 * with a fourth channel the text is composited over as alpha). (x, y) is the left end of
 * the baseline in pixels; size_px the font size in pixels. The font is
 * DejaVu Sans from Debian's fonts-dejavu-core (PLM_IMAGE_FONT); a missing
 * font is an error, never a silent fallback. */
#define PLM_IMAGE_FONT "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
plm_result plm_image_draw_text(plm_image *img, int x, int y, int size_px, const char *text, const float color[3],
                               plm_error *err);

/* sRGB transfer function of a linear value in [0, 1]. */
double plm_srgb_encode(double linear);

#endif
