/* The feather-texture contract: the one place that says how a feather
 * texture (and its pigment image) encodes what the generator knows. texture/
 * writes it, optics/ reads it; neither knows the other.
 *
 * Feather texture, 3 float channels, top row first:
 *   PLM_FTEX_COS, PLM_FTEX_SIN  (cos a + 1) / 2 and (sin a + 1) / 2, where
 *                               (cos a, sin a) is the unit barb direction in
 *                               uv units, pointing away from the rachis
 *   PLM_FTEX_REGION             region code / 2: 0 background, 0.5 rachis, 1 vane
 *                               (decoded with thresholds halfway between codes)
 * and, in files written since the barb coordinate was added, a fourth:
 *   PLM_FTEX_BARB               the barb coordinate's fractional part, in [0, 1]
 *                               (1 is the same phase as 0): the stream function
 *                               psi (where a texel's barb meets the rachis
 *                               centre line, mm) times the barb density (barbs
 *                               per mm along the rachis), so it is constant along
 *                               a barb and rises by 1 from one barb to the next.
 *                               Only the fraction is stored (EXR and 16-bit PNG
 *                               alike: 1/65535 of a period is far below a texel).
 *                               It jumps from 1 to 0 at every barb boundary, so
 *                               never filter it as it is: take the nearest texel,
 *                               or unwrap the neighbours to the nearest texel's
 *                               value (plm_ftex_barb_unwrap) before blending.
 *                               Images with 3 channels have no coordinate
 *                               (plm_ftex_has_barb); their other channels read as
 *                               before. See docs/generating.md.
 * Texel (0, 0) is the top-left corner and sits at uv = (0, 1): u runs left to
 * right, v from the bottom row (the feather's base, v = 0) to the top row.
 *
 * Pigment image, 4 float channels in [0, 1], 0 outside the vane:
 *   PLM_PIGMENT_BANDS  1 inside a dark bar (bars follow the barbs)
 *   PLM_PIGMENT_TIP    1 at the tip, falling to 0 over the species' tip length
 *   PLM_PIGMENT_BARB   a value per barb, at most the species' barb jitter
 *   PLM_PIGMENT_BASE   1 over the downy base, falling to 0 over the species' base length
 *                      (images with 3 channels have none: read as 0)
 * Same texel layout as the feather texture. */
#ifndef PLUMAGE_COMMON_FEATHER_TEXTURE_CONTRACT_H
#define PLUMAGE_COMMON_FEATHER_TEXTURE_CONTRACT_H

#include <math.h>

#define PLM_FTEX_CHANNELS 3
#define PLM_FTEX_COS 0
#define PLM_FTEX_SIN 1
#define PLM_FTEX_REGION 2
#define PLM_FTEX_BARB 3 /* optional: PLM_FTEX_CHANNELS_WITH_BARB channels */
#define PLM_FTEX_CHANNELS_WITH_BARB 4

#define PLM_PIGMENT_CHANNELS 4
#define PLM_PIGMENT_BANDS 0
#define PLM_PIGMENT_TIP 1
#define PLM_PIGMENT_BARB 2
#define PLM_PIGMENT_BASE 3

typedef enum plm_region {
    PLM_REGION_BACKGROUND = 0, /* not part of the feather: rays pass as if nothing were there */
    PLM_REGION_RACHIS = 1,     /* the shaft: a diffuse surface */
    PLM_REGION_VANE = 2        /* barbs and barbules: the feather BSDF */
} plm_region;

static inline float plm_ftex_encode_region(plm_region r) { return 0.5f * (float)r; }

/* Halfway between the codes, so filtering or 16-bit rounding never changes a region. */
static inline plm_region plm_ftex_decode_region(float value)
{
    return value < 0.25f ? PLM_REGION_BACKGROUND : (value < 0.75f ? PLM_REGION_RACHIS : PLM_REGION_VANE);
}

/* A direction component in [-1, 1] to a channel value in [0, 1], and back. */
static inline float plm_ftex_encode_component(double c) { return (float)(0.5 * (c + 1.0)); }
static inline double plm_ftex_decode_component(float v) { return 2.0 * (double)v - 1.0; }

/* Whether an image with this many channels carries the barb coordinate. */
static inline int plm_ftex_has_barb(int channels) { return channels > PLM_FTEX_BARB; }

/* The barb coordinate (psi times the barb density) to its stored fraction. */
static inline float plm_ftex_encode_barb(double coordinate) { return (float)(coordinate - floor(coordinate)); }

/* The stored fraction shifted by whole periods to lie within half a period of
 * reference (e.g. the nearest texel's value): neighbours unwrapped this way
 * can be blended without mixing the end of one barb with the start of the next. */
static inline double plm_ftex_barb_unwrap(float value, double reference)
{
    return (double)value + floor(reference - (double)value + 0.5);
}

#endif
