/* Near-field shading of a vane (docs/nearfield.md): where a pixel is smaller
 * than a barb period, the feather texture's barb coordinate says where within
 * the period a ray enters the vane, and the masking of the rays entering over
 * the part of the period the pixel covers (plm_masking_eval_window) replaces
 * the far-field masking. The window is the pixel's footprint across the
 * barbs, so it grows continuously into a whole period, which is the far
 * field exactly: zooming never pops, and the mean over a period is the far
 * field at every scale. */
#ifndef PLUMAGE_OPTICS_NEARFIELD_H
#define PLUMAGE_OPTICS_NEARFIELD_H

#include "common/vec.h"
#include "optics/feather_texture.h"
#include "optics/masking.h"

/* The far field as a window: a whole period. */
static inline plm_barb_window plm_nearfield_far(void) { return (plm_barb_window){0.0, 1.0}; }

/* The coordinate's gradient on the surface in world units (periods per unit
 * length) from its uv gradient and the surface's dP/du, dP/dv. */
vec3 plm_nearfield_gradient(vec2 gradient_uv, vec3 dpdu, vec3 dpdv);

/* A pixel cone of `width` (world units, across the ray) meeting the surface
 * of normal n along direction d cuts an ellipse from its tangent plane; the
 * coordinate's range over that ellipse, in periods. */
double plm_nearfield_footprint(vec3 gradient, vec3 d, vec3 n, double width);

/* The window a pixel covers around a coordinate (barb j centred at
 * coordinate j + 1/2, so the pigment's per-barb value covers a barb and its
 * own barbules): as wide as the footprint, or as the texture's limit where
 * neighbouring texels lie so far apart in phase (texel_step periods) that
 * unwrapping them becomes unreliable; at a period or more, the far field. */
plm_barb_window plm_nearfield_window(double coordinate, double footprint, double texel_step);

/* All of the above at a vane point: the texture's coordinate where the
 * point's uv falls (site), the cone of `width` arriving along d; the far
 * field when the texture has no coordinate or there is no cone (width 0, or
 * not finite). */
plm_barb_window plm_nearfield_at(const plm_feather_texture *t, const plm_texel_site *site, vec3 dpdu, vec3 dpdv,
                                 vec3 n, vec3 d, double width);

#endif
