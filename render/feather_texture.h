/* The feather texture: one 3-channel image that the generator writes and the
 * renderer reads (a fixed contract):
 *   ch0 = (cos a + 1) / 2, ch1 = (sin a + 1) / 2, ch2 = region
 * where (cos a, sin a) is the barb direction in UV space (pointing away from
 * the rachis) and region is 0 background, 0.5 rachis, 1 vane. Texel (0, 0) is
 * the image's top-left corner and sits at uv = (0, 1): u runs left to right,
 * v from the bottom row (v = 0, the feather's base) to the top row. */
#ifndef PLUMAGE_RENDER_FEATHER_TEXTURE_H
#define PLUMAGE_RENDER_FEATHER_TEXTURE_H

#include "common/error.h"
#include "common/vec.h"

typedef enum plm_region {
    PLM_REGION_BACKGROUND = 0, /* not part of the feather: rays pass as if nothing were there */
    PLM_REGION_RACHIS = 1,     /* the shaft: a diffuse surface */
    PLM_REGION_VANE = 2        /* barbs and barbules: the feather BSDF */
} plm_region;

typedef struct plm_feather_texture {
    int width, height;
    float *pixels;       /* width * height * 3, top row first */
    unsigned char *region; /* width * height plm_region values, decoded once */
} plm_feather_texture;

/* Reads any image OpenImageIO can read with at least 3 channels. */
plm_result plm_feather_texture_read(const char *path, plm_feather_texture *out, plm_error *err);
/* Takes ownership of pixels (malloc'd, 3 channels). */
plm_result plm_feather_texture_from_pixels(int width, int height, float *pixels, plm_feather_texture *out,
                                           plm_error *err);
void plm_feather_texture_free(plm_feather_texture *t);

/* Region of the texel nearest to uv (no filtering: regions never blend). */
plm_region plm_feather_texture_region(const plm_feather_texture *t, vec2 uv);

/* Barb direction (cos a, sin a) at uv, unit length: bilinear among the four
 * nearest texels that share the region of the nearest one, renormalised, so
 * it never blends across a region boundary; decoding to vectors before
 * averaging means there is no angle wrap-around. */
vec2 plm_feather_texture_direction(const plm_feather_texture *t, vec2 uv);

#endif
