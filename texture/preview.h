/* Quick pictures of a generated feather's textures (no path tracing): the
 * barb coordinate up close, and barbs traced through the direction field. */
#ifndef PLUMAGE_TEXTURE_PREVIEW_H
#define PLUMAGE_TEXTURE_PREVIEW_H

#include "texture/feather.h"

/* A close-up of the barb coordinate (docs/generating.md): a square of `span`
 * mm of the flat feather centred on `centre` (flat mm), each pixel the
 * nearest texel's fractional part as grey (0 black to 1 white) on the vane,
 * the rachis pale blue, background dark. Barbs show as stripes, one ramp per
 * barb, at the species' angle. */
void plm_preview_barb_coordinate(const plm_feather *f, vec2 centre, double span, int w, int h, float *rgb);

/* Traces the barb leaving the rachis edge at flat height y on one side
 * through the feather texture's directions (midpoint steps of `step` in uv
 * units), writing up to max_points uv points; returns how many. */
int plm_preview_trace_barb(const plm_feather *f, int side, double y, double step, vec2 *points, int max_points);

#endif
