/* Materials behind the plm_bsdf interface: the diffuse BSDF here, the feather
 * (render/feather_bsdf.c) dispatched to by type. */
#include "render/bsdf.h"
#include "render/sampling.h"

static rgb diffuse_eval(const plm_bsdf *b, vec3 wi)
{
    double c = v3_dot(wi, b->shading.z);
    return c > 0.0 ? rgb_scale(b->albedo, c * PLM_INV_PI) : rgb_gray(0.0);
}

static double diffuse_pdf(const plm_bsdf *b, vec3 wi)
{
    double c = v3_dot(wi, b->shading.z);
    return c > 0.0 ? c * PLM_INV_PI : 0.0;
}

static int diffuse_sample(const plm_bsdf *b, double u0, double u1, double u2, plm_bsdf_sample_rec *s)
{
    (void)u0;
    vec3 local = plm_sample_cosine_hemisphere(u1, u2);
    if (local.z <= 0.0)
        return 0;
    s->wi = frame_to_world(&b->shading, local);
    s->pdf = local.z * PLM_INV_PI;
    s->weight = b->albedo; /* (albedo/pi) cos / (cos/pi) */
    return 1;
}

static const plm_bsdf_ops diffuse_ops = {diffuse_eval, diffuse_pdf, diffuse_sample};

void plm_diffuse_bsdf(const plm_hit *hit, vec3 wo, rgb albedo, plm_bsdf *out)
{
    /* Two-sided: reflect on the side the light comes from. The shading normal
     * is flipped with the geometric one so both stay on wo's side. */
    vec3 n = v3_dot(wo, hit->ng) >= 0.0 ? hit->n : v3_neg(hit->n);
    out->ops = &diffuse_ops;
    out->wo = wo;
    out->shading = frame_from_z(n);
    out->albedo = albedo;
}

double plm_material_transmission(const plm_hit *hit, vec3 w)
{
    (void)w;
    const plm_material *m = hit->material;
    return m->type == PLM_MATERIAL_DIFFUSE ? m->transmission : 0.0;
}

void plm_material_bsdf(const plm_hit *hit, vec3 wo, plm_rng *rng, plm_bsdf *out)
{
    (void)rng;
    const plm_material *m = hit->material;
    plm_diffuse_bsdf(hit, wo, rgb_mul(m->reflectance, hit->tint), out);
}
