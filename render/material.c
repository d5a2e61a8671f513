/* Materials behind the plm_bsdf interface: the diffuse BSDF here, the feather
 * (optics/feather_bsdf.c) dispatched to by type. */
#include "render/material.h"
#include "optics/coat.h"
#include "optics/feather_bsdf.h"
#include "optics/nearfield.h"
#include "common/sampling.h"

#include <string.h>

_Static_assert(sizeof(plm_feather_bsdf) <= PLM_BSDF_STATE_BYTES, "plm_bsdf.state must hold a feather BSDF");

static double diffuse_pdf(const plm_bsdf *b, vec3 wi)
{
    double c = v3_dot(wi, b->shading.z);
    return c > 0.0 ? c * PLM_INV_PI : 0.0;
}

/* The cosine-weighted f is the albedo times the density. */
static rgb diffuse_eval(const plm_bsdf *b, vec3 wi) { return rgb_scale(b->albedo, diffuse_pdf(b, wi)); }

static rgb diffuse_eval_mis(const plm_bsdf *b, vec3 wi, double light_pdf)
{
    double p = diffuse_pdf(b, wi);
    return rgb_scale(b->albedo, p * plm_power_heuristic(light_pdf, p));
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

static const plm_bsdf_ops diffuse_ops = {diffuse_eval, diffuse_pdf, diffuse_eval_mis, diffuse_sample};

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

static const plm_feather_bsdf *feather_state(const plm_bsdf *b) { return (const plm_feather_bsdf *)b->state; }
static rgb feather_eval(const plm_bsdf *b, vec3 wi) { return plm_feather_eval(feather_state(b), wi); }
static double feather_pdf(const plm_bsdf *b, vec3 wi) { return plm_feather_pdf(feather_state(b), wi); }
static rgb feather_eval_mis(const plm_bsdf *b, vec3 wi, double light_pdf)
{
    return plm_feather_eval_mis(feather_state(b), wi, light_pdf);
}
static int feather_sample(const plm_bsdf *b, double u0, double u1, double u2, plm_bsdf_sample_rec *s)
{
    return plm_feather_sample(feather_state(b), u0, u1, u2, &s->wi, &s->pdf, &s->weight);
}

static const plm_bsdf_ops feather_ops = {feather_eval, feather_pdf, feather_eval_mis, feather_sample};

/* A fiber (curves): the fiber BCSDF in the frame of the curve's axis,
 * integrated over the whole fiber width (h in [-1, 1]): the far field of a
 * fiber thinner than a pixel. eval is S cos(theta_i), theta_i from the
 * plane across the axis, as for a feather's barbs (optics/feather_bsdf.h). */
typedef struct fiber_state {
    frame axis; /* z = the curve's unit tangent */
    plm_fiber_bcsdf bcsdf;
    rgb tint;
} fiber_state;
_Static_assert(sizeof(fiber_state) <= PLM_BSDF_STATE_BYTES, "plm_bsdf.state must hold a fiber BSDF");

static const fiber_state *fiber_of(const plm_bsdf *b) { return (const fiber_state *)b->state; }
static double across_axis(vec3 local) { return sqrt(local.x * local.x + local.y * local.y); }

static rgb fiber_eval_pdf(const plm_bsdf *b, vec3 wi, double *pdf)
{
    const fiber_state *f = fiber_of(b);
    vec3 local = frame_to_local(&f->axis, wi);
    rgb s = plm_fiber_bcsdf_eval_pdf(&f->bcsdf, local, pdf);
    return rgb_mul(rgb_scale(s, across_axis(local)), f->tint);
}

static rgb fiber_eval(const plm_bsdf *b, vec3 wi)
{
    double pdf;
    return fiber_eval_pdf(b, wi, &pdf);
}

static double fiber_pdf(const plm_bsdf *b, vec3 wi)
{
    return plm_fiber_bcsdf_pdf(&fiber_of(b)->bcsdf, frame_to_local(&fiber_of(b)->axis, wi));
}

static rgb fiber_eval_mis(const plm_bsdf *b, vec3 wi, double light_pdf)
{
    double pdf;
    rgb f = fiber_eval_pdf(b, wi, &pdf);
    return rgb_scale(f, plm_power_heuristic(light_pdf, pdf));
}

static int fiber_sample(const plm_bsdf *b, double u0, double u1, double u2, plm_bsdf_sample_rec *s)
{
    const fiber_state *f = fiber_of(b);
    vec3 local;
    if (!plm_fiber_bcsdf_sample_direction(&f->bcsdf, u0, u1, u2, &local))
        return 0;
    s->wi = frame_to_world(&f->axis, local);
    rgb e = fiber_eval_pdf(b, s->wi, &s->pdf);
    if (!(s->pdf > 0.0))
        return 0;
    s->weight = rgb_scale(e, 1.0 / s->pdf);
    return 1;
}

static const plm_bsdf_ops fiber_ops = {fiber_eval, fiber_pdf, fiber_eval_mis, fiber_sample};

static void fiber_bsdf(const plm_hit *hit, vec3 wo, plm_rng *rng, plm_bsdf *out)
{
    const plm_fiber_material *m = hit->material->fiber;
    fiber_state *f = (fiber_state *)out->state;
    f->axis = frame_from_z(hit->dpdu);
    f->tint = hit->tint;
    plm_fiber_bcsdf_prepare(&m->fiber, hit->prepared->fiber_table, frame_to_local(&f->axis, wo), -1.0, 1.0, rng,
                            &f->bcsdf);
    out->ops = &fiber_ops;
}

void plm_material_prepare(const plm_material *m, plm_prepared_material *out)
{
    memset(out, 0, sizeof *out);
    if (m->feather)
        plm_feather_model_init(&out->feather, m->feather);
}

plm_result plm_material_prepare_tables(const plm_material *m, plm_fiber_table_set *set, plm_prepared_material *p,
                                       plm_error *err)
{
    if (m->feather)
        return plm_feather_model_build_tables(&p->feather, set, err);
    if (m->fiber && !m->fiber->stochastic && !p->fiber_table)
        return plm_fiber_table_set_get(set, &m->fiber->fiber, &p->fiber_table, err);
    return PLM_OK;
}

/* (1 - w) white + w c */
static rgb mix_from_white(rgb c, double w) { return rgb_add(rgb_gray(1.0), rgb_scale(rgb_sub(c, rgb_gray(1.0)), w)); }

/* Nearest texel: bands and barbs have sharp edges. */
rgb plm_material_pigment(const plm_material *m, vec2 uv)
{
    const plm_image *p = &m->pigment;
    if (!p->pixels)
        return rgb_gray(1.0);
    const float *px = p->pixels + (size_t)p->channels * (size_t)plm_texel_nearest(p->width, p->height, uv);
    double band = px[PLM_PIGMENT_BANDS], tip = px[PLM_PIGMENT_TIP], barb = px[PLM_PIGMENT_BARB];
    double base = p->channels > PLM_PIGMENT_BASE ? px[PLM_PIGMENT_BASE] : 0.0;
    rgb f = rgb_mul(mix_from_white(m->band_tint, band), mix_from_white(m->tip_tint, tip));
    f = rgb_mul(f, mix_from_white(m->base_tint, base));
    return rgb_scale(f, plm_clamp(1.0 - barb, 0.0, 1.0));
}

void plm_material_surface_at(plm_hit *hit, const plm_texel_site *site)
{
    /* The texture says where the vane is; background texels never get here
     * (the Embree filters drop them). */
    const plm_material *m = hit->material;
    hit->on_vane = 0;
    hit->has_masking = 0;
    if (m->type != PLM_MATERIAL_FEATHER)
        return;
    plm_texel_site own;
    if (!site) {
        plm_feather_texture_site(&m->texture, hit->uv, &own);
        site = &own;
    }
    if (plm_feather_texture_region_at(&m->texture, site) != PLM_REGION_VANE)
        return;
    vec2 dir = plm_feather_texture_direction_at(&m->texture, site);
    hit->on_vane = plm_feather_barb_frame(hit->n, hit->dpdu, hit->dpdv, dir, &hit->barb);
    hit->window = plm_nearfield_at(&m->texture, site, hit->dpdu, hit->dpdv, hit->n, hit->ray_dir, hit->cone_width);
}

void plm_material_surface_finish(plm_hit *hit)
{
    const plm_material *m = hit->material;
    if (hit->on_vane && m->pigment.pixels)
        hit->tint = rgb_mul(hit->tint, plm_material_pigment(m, hit->uv));
}

void plm_material_surface(plm_hit *hit)
{
    plm_material_surface_at(hit, NULL);
    plm_material_surface_finish(hit);
}

double plm_material_transmission(const plm_hit *hit, vec3 w)
{
    const plm_material *m = hit->material;
    if (m->type == PLM_MATERIAL_DIFFUSE)
        return m->transmission;
    if (!hit->on_vane)
        return 0.0;
    plm_masking masking;
    plm_feather_masking(&hit->prepared->feather, &hit->barb, &hit->window, w, &masking);
    return masking.w_transmission;
}

double plm_material_transmission_keep(plm_hit *hit, vec3 w)
{
    const plm_material *m = hit->material;
    if (m->type != PLM_MATERIAL_FEATHER || !hit->on_vane)
        return plm_material_transmission(hit, w);
    plm_feather_masking(&hit->prepared->feather, &hit->barb, &hit->window, w, &hit->masking);
    hit->has_masking = 1;
    hit->masking_w = w;
    return hit->masking.w_transmission;
}

void plm_material_bsdf(const plm_hit *hit, vec3 wo, plm_rng *rng, plm_bsdf *out)
{
    const plm_material *m = hit->material;
    if (m->type == PLM_MATERIAL_COAT) {
        plm_coat coat = {rgb_mul(m->reflectance, hit->tint), m->roughness, m->ior};
        plm_coat_bsdf(&coat, v3_dot(wo, hit->ng) >= 0.0 ? hit->n : v3_neg(hit->n), wo, out);
        return;
    }
    /* Diffuse materials, and a feather's rachis: the material's reflectance. */
    plm_diffuse_bsdf(hit, wo, rgb_mul(m->reflectance, hit->tint), out);
    if (m->type == PLM_MATERIAL_FIBER)
        fiber_bsdf(hit, wo, rng, out);
    if (hit->on_vane) {
        int known = hit->has_masking && hit->masking_w.x == wo.x && hit->masking_w.y == wo.y &&
                    hit->masking_w.z == wo.z;
        plm_masking own; /* over the hit's window (docs/nearfield.md) */
        if (!known)
            plm_feather_masking(&hit->prepared->feather, &hit->barb, &hit->window, wo, &own);
        plm_feather_prepare_masked(&hit->prepared->feather, &hit->barb, wo, known ? &hit->masking : &own, hit->tint,
                                   rng, (plm_feather_bsdf *)out->state);
        out->ops = &feather_ops;
    }
}
