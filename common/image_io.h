/* Image files through OpenImageIO (adapter in image_io.cpp, loaded on first
 * use by image_module.c), plus the
 * conversions every stage needs. Pixels are row-major, top row first,
 * channels interleaved. Writes are atomic (temporary file, then rename). */
#ifndef PLUMAGE_COMMON_IMAGE_IO_H
#define PLUMAGE_COMMON_IMAGE_IO_H

#include <stddef.h>
#include <stdint.h>
#include "common/error.h"

/* An image in memory: float channels, row-major, top row first. */
typedef struct plm_image {
    int width, height, channels;
    float *pixels; /* width * height * channels, malloc'd */
} plm_image;

/* The largest image plumage reads, makes or renders: at most 16384 pixels a
 * side, 64 channels and 2^28 values in all (1 GiB of floats: 8192 x 8192
 * RGBA, or 9459 x 9459 RGB). Larger requests are refused before anything is
 * allocated (docs/robustness.md). */
#define PLM_IMAGE_SIDE_MAX 16384
#define PLM_IMAGE_CHANNELS_MAX 64
#define PLM_IMAGE_VALUES_MAX ((long long)1 << 28)

/* PLM_OK if a width x height image of that many channels is within the
 * limits above; else PLM_ERR_INVALID with a message naming `what` and the limit. */
plm_result plm_image_check_size(const char *what, long long width, long long height, long long channels,
                                plm_error *err);

/* PLM_OK unless path is a PNG file one of whose chunks declares more bytes
 * than the file holds: libpng allocates a chunk's declared length before it
 * reads it, so such a file would ask for gigabytes (found by fuzzing). Files
 * that are not PNG, and PNG files cut short at a chunk boundary, pass here
 * and are left to the decoder. */
plm_result plm_image_check_png_chunks(const char *path, plm_error *err);

/* The same for an EXR file's header: OpenEXR allocates an attribute's
 * declared size before reading it (a 1 kB file declaring a 400 MB string
 * took 400 MB; found by fuzzing). */
plm_result plm_image_check_exr_header(const char *path, plm_error *err);

typedef enum plm_pixel_type {
    PLM_PIXEL_FLOAT = 0,  /* 32-bit float (EXR, HDR, TIFF) */
    PLM_PIXEL_UINT8 = 1,  /* PNG, JPEG */
    PLM_PIXEL_UINT16 = 2  /* 16-bit PNG, TIFF */
} plm_pixel_type;

/* The format follows path's extension; data's element type is `type`. */
plm_result plm_image_write(const char *path, int width, int height, int channels, plm_pixel_type type,
                           const void *data, plm_error *err);

/* The same image as the bytes of a PNG file, in memory (type UINT8 or
 * UINT16; a fourth channel is written as it is, unassociated alpha);
 * *bytes is malloc'd (caller frees). For formats that embed images (glTF). */
plm_result plm_image_encode_png(int width, int height, int channels, plm_pixel_type type, const void *data,
                                unsigned char **bytes, size_t *size, plm_error *err);

/* Reads a file as float with the reader of the format its extension names
 * (EXR, PNG, HDR, TIFF, JPEG...); *pixels is malloc'd (caller frees). */
plm_result plm_image_read(const char *path, int *width, int *height, int *channels, float **pixels,
                          plm_error *err);

/* The reads and writes above load the image library (OpenImageIO, a module:
 * see common/image_module.h) on first use. What that cost: the resident
 * memory its loading added and the process's peak resident memory just
 * before, in MiB; both 0 while it is not loaded. */
void plm_image_library_memory(double *added_mib, double *peak_before_mib);

/* Linear float RGB -> 8-bit sRGB PNG, after scaling by 2^exposure and a
 * clamp (the simplest tone map: the values are shown as they are). Non-finite
 * values are written as black. */
plm_result plm_image_write_srgb_png(const char *path, int width, int height, const float *rgb, double exposure,
                                    plm_error *err);

/* Draws text into img (float, 3 or 4 channels) in the colour `color` (RGB;
 * with a fourth channel the text is composited over as alpha). (x, y) is the left end of
 * the baseline in pixels; size_px the font size in pixels. The font is
 * DejaVu Sans from Debian's fonts-dejavu-core (PLM_IMAGE_FONT); a missing
 * font is an error, never a silent fallback. Keep text to ASCII: OpenImageIO
 * 2.4 draws other UTF-8 characters (degree sign, Greek) as wrong glyphs. */
#define PLM_IMAGE_FONT "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
plm_result plm_image_draw_text(plm_image *img, int x, int y, int size_px, const char *text, const float color[3],
                               plm_error *err);

/* sRGB transfer function of a linear value in [0, 1]. */
double plm_srgb_encode(double linear);

#endif
