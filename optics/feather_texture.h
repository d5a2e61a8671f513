/* The feather texture as the renderer reads it: the image the generator
 * writes (its encoding is common/feather_texture_contract.h), with the
 * regions decoded once. */
#ifndef PLUMAGE_OPTICS_FEATHER_TEXTURE_H
#define PLUMAGE_OPTICS_FEATHER_TEXTURE_H

#include "common/error.h"
#include "common/feather_texture_contract.h"
#include "common/vec.h"

typedef struct plm_feather_texture {
    int width, height;
    float *pixels;       /* width * height * 3, top row first */
    unsigned char *region; /* width * height plm_region values, decoded once */
    float *barb;         /* width * height barb coordinate fractions (PLM_FTEX_BARB), or NULL: none */
} plm_feather_texture;

/* Reads any image OpenImageIO can read with at least 3 channels; a fourth is
 * the barb coordinate. */
plm_result plm_feather_texture_read(const char *path, plm_feather_texture *out, plm_error *err);
/* Takes ownership of pixels (malloc'd, 3 channels); no barb coordinate
 * (assign a malloc'd one to out->barb, which the texture then owns). */
plm_result plm_feather_texture_from_pixels(int width, int height, float *pixels, plm_feather_texture *out,
                                           plm_error *err);
void plm_feather_texture_free(plm_feather_texture *t);

/* The texel nearest to uv in an image of this size laid out as the contract
 * says (top row first, uv = (0, 1) at the top-left corner); its index. */
long plm_texel_nearest(int width, int height, vec2 uv);

/* Where uv falls among the texels, which the lookups at one point share:
 * continuous texel coordinates (texel centres at integers) and the nearest
 * texel, (cx, cy) and its index. */
typedef struct plm_texel_site {
    double x, y;
    long cx, cy, centre;
} plm_texel_site;
void plm_feather_texture_site(const plm_feather_texture *t, vec2 uv, plm_texel_site *out);

/* Region of the texel nearest to uv (no filtering: regions never blend). */
plm_region plm_feather_texture_region(const plm_feather_texture *t, vec2 uv);
static inline plm_region plm_feather_texture_region_at(const plm_feather_texture *t, const plm_texel_site *s)
{
    return (plm_region)t->region[s->centre];
}

/* Barb direction (cos a, sin a) at uv, unit length: bilinear among the four
 * nearest texels that share the region of the nearest one, renormalised, so
 * it never blends across a region boundary; decoding to vectors before
 * averaging means there is no angle wrap-around. */
vec2 plm_feather_texture_direction(const plm_feather_texture *t, vec2 uv);
vec2 plm_feather_texture_direction_at(const plm_feather_texture *t, const plm_texel_site *site);

/* The barb coordinate near uv (docs/nearfield.md). */
typedef struct plm_barb_sample {
    double coordinate; /* barb periods; its fraction is the position across the period */
    vec2 gradient;     /* d coordinate / d(u, v), periods per uv unit */
    double texel_step; /* the larger change between neighbouring texels, in periods */
} plm_barb_sample;

/* Bilinear among the four nearest texels that share the nearest one's
 * region, each unwrapped to within half a period of the nearest texel's
 * value (plm_ftex_barb_unwrap), so the phase never breaks at a barb
 * boundary; the gradient by differences between the nearest texel's
 * neighbours of its region. Returns 0 if the texture has no coordinate. */
int plm_feather_texture_barb(const plm_feather_texture *t, vec2 uv, plm_barb_sample *out);
int plm_feather_texture_barb_at(const plm_feather_texture *t, const plm_texel_site *site, plm_barb_sample *out);

#endif
