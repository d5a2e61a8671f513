/* The BSDF interface (pbrt-style, small): what the path tracer asks of a
 * surface's scattering, and what a material hands it. A plm_bsdf is
 * prepared once for the view direction wo (a feather traces its fiber lobe
 * sets then); eval, pdf and sample are then deterministic functions of wi.
 * The renderer's materials fill one in at each hit. */
#ifndef PLUMAGE_OPTICS_BSDF_H
#define PLUMAGE_OPTICS_BSDF_H

#include "common/vec.h"

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

#define PLM_BSDF_STATE_BYTES 51200

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

#endif
