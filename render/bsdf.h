/* The material interface of the path tracer (pbrt-style, small).
 *
 * At a surface hit the renderer asks the material two things:
 *  - plm_material_transmission(hit, w): the probability that a ray arriving
 *    from direction w (unit, pointing back toward where the ray came from)
 *    passes straight through. This is the delta transmission of the feather
 *    (paper Eq. 4, w_t) handled as fractional visibility (docs/rendering.md): camera
 *    and bounce rays continue straight with this probability, shadow rays
 *    are attenuated by it.
 *  - plm_material_bsdf(hit, wo, rng): the BSDF of the other branch, the
 *    light that does not pass: f_s without its delta term, divided by
 *    (1 - w_t(wo)), so it conserves energy on its own.
 * A plm_bsdf is prepared once for the view direction wo (a feather traces
 * its fiber lobe sets here, with rng); eval, pdf and sample are then
 * deterministic functions of wi. */
#ifndef PLUMAGE_RENDER_BSDF_H
#define PLUMAGE_RENDER_BSDF_H

#include "common/rng.h"
#include "common/vec.h"
#include "render/masking.h"
#include "render/scene.h"

/* What a material needs to know about the surface at a hit, in world space. */
typedef struct plm_hit {
    vec3 p;          /* position */
    vec3 ng;         /* geometric normal, unit, on the mesh's front (counter-clockwise) side */
    vec3 n;          /* shading normal, unit, same side as ng: the feather's dorsal side */
    vec3 dpdu, dpdv; /* surface derivatives; for vanes dP/dv points to the feather's tip */
    vec2 uv;
    rgb tint;        /* per-instance colour variation */
    const plm_material *material;
    /* The pixel cone that found the hit: its width at p (world units; 0 for
     * none: after a scattering event, in shadow queries, with
     * film.far_field) and the ray direction. */
    double cone_width;
    vec3 ray_dir;
    /* Set by plm_material_surface: whether the hit lies on a feather's vane,
     * and there the barb frame (x = b, y = n, z = t; docs/masking.md). */
    int on_vane;
    frame barb;
    /* On a vane, the part of the barb period the pixel covers (a whole
     * period: the far field; docs/nearfield.md). */
    plm_barb_window window;
    /* Set by plm_material_transmission_keep: the feather's masking for the
     * view direction masking_w, which the BSDF reuses when wo is the same. */
    int has_masking;
    vec3 masking_w;
    plm_masking masking;
} plm_hit;

typedef struct plm_bsdf_sample_rec {
    vec3 wi;    /* unit, pointing away from the surface */
    double pdf; /* solid-angle density, > 0, of the technique that drew wi (MIS weighs by it, see eval_mis) */
    rgb weight; /* an estimate of eval(wi) / pdf(wi), unbiased given wi */
} plm_bsdf_sample_rec;

struct plm_bsdf;
typedef struct plm_bsdf_ops {
    /* f(wo, wi) |cos theta_i|: the cosine is included so a BSDF may cancel it (Eq. 4). */
    rgb (*eval)(const struct plm_bsdf *b, vec3 wi);
    double (*pdf)(const struct plm_bsdf *b, vec3 wi);
    /* eval(wi) weighted for a light sample of density light_pdf at wi by the
     * power heuristic against the BSDF's sampling. A BSDF that samples a
     * mixture by drawing one term weighs each term against that term's own
     * technique (density: the term's pick times its pdf, which sample then
     * returns as pdf): its other terms need no lookup at a sampled direction. */
    rgb (*eval_mis)(const struct plm_bsdf *b, vec3 wi, double light_pdf);
    /* Returns 0 when no direction could be sampled. */
    int (*sample)(const struct plm_bsdf *b, double u0, double u1, double u2, plm_bsdf_sample_rec *s);
} plm_bsdf_ops;

#define PLM_BSDF_STATE_BYTES 20480

typedef struct plm_bsdf {
    const plm_bsdf_ops *ops;
    vec3 wo;
    frame shading;  /* z = shading normal turned toward wo */
    rgb albedo;     /* diffuse */
    /* Room for a material's prepared state (the feather's masking and lobe sets). */
    _Alignas(16) unsigned char state[PLM_BSDF_STATE_BYTES];
} plm_bsdf;

static inline rgb plm_bsdf_eval(const plm_bsdf *b, vec3 wi) { return b->ops->eval(b, wi); }
static inline double plm_bsdf_pdf(const plm_bsdf *b, vec3 wi) { return b->ops->pdf(b, wi); }
static inline rgb plm_bsdf_eval_mis(const plm_bsdf *b, vec3 wi, double light_pdf)
{
    return b->ops->eval_mis(b, wi, light_pdf);
}
static inline int plm_bsdf_sample(const plm_bsdf *b, double u0, double u1, double u2, plm_bsdf_sample_rec *s)
{
    return b->ops->sample(b, u0, u1, u2, s);
}

/* Completes a hit whose geometric fields are set: the material's surface
 * data (the texture lookups), done once per hit. In two steps for the
 * Embree filters, which decide a candidate's passing from the first and
 * finish only the hit they keep: _at sets what the transmission needs
 * (site: where uv falls in the material's texture, NULL: looked up), _finish
 * the rest (the pigment's tint). */
void plm_material_surface(plm_hit *hit);
void plm_material_surface_at(plm_hit *hit, const plm_texel_site *site);
void plm_material_surface_finish(plm_hit *hit);
double plm_material_transmission(const plm_hit *hit, vec3 w);
/* The same, keeping what it computed in the hit for plm_material_bsdf with wo = w
 * (a ray's closest hit was seen by the filters that decided its passing). */
double plm_material_transmission_keep(plm_hit *hit, vec3 w);
void plm_material_bsdf(const plm_hit *hit, vec3 wo, plm_rng *rng, plm_bsdf *out);

/* Lambertian reflection on the side of wo (two-sided), albedo in [0, 1]. */
void plm_diffuse_bsdf(const plm_hit *hit, vec3 wo, rgb albedo, plm_bsdf *out);

#endif
