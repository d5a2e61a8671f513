/* Feather textures authored from the flat outline (generate/outline.h).
 *
 * The feather texture and the optional pigment image follow the contract in
 * common/feather_texture_contract.h (channels, region codes, texel layout).
 * The barb direction is normalised in uv units, so the 3D barb tangent is
 * normalize(cos a dP/du + sin a dP/dv). Every texel carries a unit
 * direction; outside the outline (never rendered) it is the straight barb at
 * the row's rachis angle. */
#ifndef PLUMAGE_TEXTURE_TEXTURE_H
#define PLUMAGE_TEXTURE_TEXTURE_H

#include "common/image_io.h"
#include "generate/outline.h"

#define PLM_TEXTURE_DEFAULT_SIZE 1024

/* Allocates and fills `feather` (the contract's first 3 channels), `barb`
 * (1 channel: the barb coordinate's fraction, PLM_FTEX_BARB) and `pigment`
 * (if not NULL) at width x height. */
plm_result plm_texture_author(const plm_outline *o, const plm_pigment *pg, int width, int height,
                              plm_image *feather, plm_image *barb, plm_image *pigment, plm_error *err);

/* The feather texture as files store it: feather's 3 channels and barb's one
 * interleaved into PLM_FTEX_CHANNELS_WITH_BARB channels (allocated in out). */
plm_result plm_texture_with_barb(const plm_image *feather, const plm_image *barb, plm_image *out, plm_error *err);

/* Writes an image as EXR (float) or 16-bit PNG, chosen by the extension. */
plm_result plm_texture_write(const char *path, const plm_image *img, plm_error *err);

/* The region value a texel's third channel encodes (0, 0.5, 1) as plm_flat_region. */
plm_flat_region plm_texture_region_of(float channel2);

/* Frees the pixels and zeroes the struct. */
void plm_texture_image_free(plm_image *img);

#endif
