/* Feather textures authored from the flat outline (generate/outline.h).
 *
 * The feather texture is ONE 3-channel image (the renderer's contract, see
 * render/feather_texture.h):
 *   ch0 = (cos a + 1) / 2, ch1 = (sin a + 1) / 2   barb direction (cos a, sin a) in uv space,
 *                                                  pointing away from the rachis, normalised in uv units
 *   ch2 = region: 0 background, 0.5 rachis, 1 vane
 * so the 3D barb tangent is normalize(cos a dP/du + sin a dP/dv). Texel
 * (0, 0) is the top-left corner at uv = (0, 1): u runs left to right, v from
 * the bottom row (the vane's base) to the top row (the tip). Every texel
 * carries a unit direction; outside the outline (never rendered) it is the
 * straight barb at the row's rachis angle.
 *
 * The optional pigment image has 3 channels in [0, 1]:
 *   ch0 = bands (1 inside a dark bar; bars follow the barbs),
 *   ch1 = tip weight (1 at the tip, falling to 0 over pigment.tip_length),
 *   ch2 = per-barb variation (a value per barb, scaled by pigment.barb_jitter);
 * all 0 outside the vane. */
#ifndef PLUMAGE_TEXTURE_TEXTURE_H
#define PLUMAGE_TEXTURE_TEXTURE_H

#include "common/image_io.h"
#include "generate/outline.h"

#define PLM_TEXTURE_DEFAULT_SIZE 1024

/* Allocates and fills `feather` (and `pigment` if not NULL) at width x height. */
plm_result plm_texture_author(const plm_outline *o, const plm_pigment *pg, int width, int height,
                              plm_image *feather, plm_image *pigment, plm_error *err);

/* Writes an image as EXR (float) or 16-bit PNG, chosen by the extension. */
plm_result plm_texture_write(const char *path, const plm_image *img, plm_error *err);

/* The region value a texel's third channel encodes (0, 0.5, 1) as plm_flat_region. */
plm_flat_region plm_texture_region_of(float channel2);

/* Frees the pixels and zeroes the struct. */
void plm_texture_image_free(plm_image *img);

#endif
