/* From a film's linear radiance to the picture a person looks at: white
 * balance, exposure and a view transform, then 8-bit sRGB. The EXR keeps the
 * linear radiance; only the PNG goes through this (docs/rendering.md).
 *
 *  - "filmic" (the default): plumage's AgX-style view. Colours are first
 *    pulled 20% toward the grey of their luminance (the inset), each
 *    channel is encoded as log2 of its ratio to mid grey over 16.5 stops
 *    (10 below 0.18, 6.5 above) and passed through a sigmoid that keeps mid
 *    grey where the sRGB curve puts it (0.18 -> 0.461) with the same
 *    contrast there, lifts the darkest stops out of black with a soft toe
 *    and rolls highlights off to reach white only 6.5 stops above grey;
 *    then colours are pushed 10% back out. Bright colours so go to white
 *    through their own hue instead of clipping channel by channel into the
 *    primaries, and a highlight 2 stops above another stays brighter.
 *  - "standard": scale and clamp to [0, 1], the sRGB curve: values as they
 *    are, everything above 1 flat white. */
#ifndef PLUMAGE_RENDER_FILM_H
#define PLUMAGE_RENDER_FILM_H

#include <stddef.h>
#include <stdint.h>

#include "common/vec.h"

typedef enum plm_view { PLM_VIEW_FILMIC = 0, PLM_VIEW_STANDARD = 1 } plm_view;

/* Names of the views, as in scene files and options ("filmic", "standard"). */
extern const char *const plm_view_names[];

typedef struct plm_picture {
    plm_view view;
    double exposure;      /* stops: radiance times 2^exposure */
    double white_balance; /* kelvin: a blackbody of this temperature shows as the display's white; 0 = none */
} plm_picture;

/* What the picture does to one linear colour, in [0, 1] display-encoded (sRGB) values. */
typedef struct plm_picture_map {
    plm_view view;
    double m[3][3]; /* white balance times 2^exposure, on linear sRGB */
} plm_picture_map;
void plm_picture_map_init(const plm_picture *p, plm_picture_map *map);
rgb plm_picture_apply(const plm_picture_map *map, rgb linear);

/* width * height linear RGB pixels to 8-bit sRGB (non-finite values as black). */
void plm_picture_to_srgb8(const plm_picture *p, const float *rgb, size_t pixels, uint8_t *out);

#endif
