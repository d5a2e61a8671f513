/* Near-field windows from the barb coordinate and the pixel footprint; see
 * nearfield.h and docs/nearfield.md. */
#include "optics/nearfield.h"

#include <math.h>

/* Texels further apart than this in phase start to widen the window; at
 * TEXEL_FAR (short of the half period where unwrapping fails) it is a whole
 * period. */
#define TEXEL_NEAR 0.3
#define TEXEL_FAR 0.45

vec3 plm_nearfield_gradient(vec2 g, vec3 dpdu, vec3 dpdv)
{
    /* grad c = g_u grad u + g_v grad v, with grad u and grad v the dual basis
     * of (dP/du, dP/dv) in the tangent plane (the inverse Gram matrix). */
    double a = v3_dot(dpdu, dpdu), b = v3_dot(dpdu, dpdv), c = v3_dot(dpdv, dpdv);
    double det = a * c - b * b;
    if (!(det > 1e-30))
        return v3(0.0, 0.0, 0.0);
    double ku = (g.x * c - g.y * b) / det, kv = (g.y * a - g.x * b) / det;
    return v3_add(v3_scale(dpdu, ku), v3_scale(dpdv, kv));
}

double plm_nearfield_footprint(vec3 gradient, vec3 d, vec3 n, double width)
{
    /* The ellipse has semi-axes width / 2 across the ray's projection e onto
     * the plane and width / (2 |cos|) along it; its extent along the
     * gradient is width sqrt(g_perp^2 + (g.e / cos)^2). */
    double cos_t = fmax(fabs(v3_dot(d, n)), 1e-3);
    vec3 e = v3_sub(d, v3_scale(n, v3_dot(d, n)));
    double le = v3_length(e), g2 = v3_dot(gradient, gradient);
    double along = le > 1e-12 ? v3_dot(gradient, e) / le : 0.0;
    double perp2 = fmax(g2 - along * along, 0.0);
    return width * sqrt(perp2 + plm_sqr(along / cos_t));
}

plm_barb_window plm_nearfield_window(double coordinate, double footprint, double texel_step)
{
    double limit = plm_clamp((texel_step - TEXEL_NEAR) / (TEXEL_FAR - TEXEL_NEAR), 0.0, 1.0);
    double width = fmax(footprint, limit);
    if (!(footprint < 1.0) || !(width < 1.0)) /* also NaN */
        return plm_nearfield_far();
    /* Only the position within the period matters; keep x near [-1/2, 1/2). */
    double x = coordinate - 0.5;
    x -= floor(x + 0.5);
    /* A window never narrower than 1e-9 of a period: one ray's answer. */
    double half = 0.5 * fmax(width, 1e-9);
    return (plm_barb_window){x - half, x + half};
}

plm_barb_window plm_nearfield_at(const plm_feather_texture *t, const plm_texel_site *site, vec3 dpdu, vec3 dpdv,
                                 vec3 n, vec3 d, double width)
{
    plm_barb_sample s;
    if (!(width > 0.0 && width < INFINITY) || !plm_feather_texture_barb_at(t, site, &s))
        return plm_nearfield_far();
    vec3 g = plm_nearfield_gradient(s.gradient, dpdu, dpdv);
    if (!(v3_dot(g, g) > 0.0)) /* no barbs to resolve */
        return plm_nearfield_far();
    return plm_nearfield_window(s.coordinate, plm_nearfield_footprint(g, d, n, width), s.texel_step);
}
