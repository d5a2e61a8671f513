/* Quick pictures of a generated feather for contact sheets (no path
 * tracing): a shaded view of the meshes with the texture's outline cut out,
 * and the texture itself with barbs traced through its direction field. */
#ifndef PLUMAGE_TEXTURE_PREVIEW_H
#define PLUMAGE_TEXTURE_PREVIEW_H

#include "texture/feather.h"

/* Orthographic view of vane and rachis, turned `yaw` degrees about the rachis
 * axis and tilted `pitch` degrees toward the viewer, fitted to a w x h tile.
 * Vane texels marked background are left out. rgb is w * h * 3, linear. */
void plm_preview_shape(const plm_feather *f, double yaw, double pitch, int w, int h, float *rgb);

/* The feather texture over the flat outline at its true aspect: vane hue
 * shows the barb angle, the rachis is white, background dark; every
 * `barb_step` mm along the rachis a barb is traced through the stored
 * directions (second-order Runge-Kutta) and drawn in black. */
void plm_preview_texture(const plm_feather *f, double barb_step, int w, int h, float *rgb);

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
