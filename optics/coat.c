/* The coat BSDF (optics/coat.h). Local frame: z the normal, wo above. */
#include "optics/coat.h"

#include <math.h>
#include <string.h>

#include "common/sampling.h"

_Static_assert(sizeof(plm_coat) <= PLM_BSDF_STATE_BYTES, "plm_bsdf.state must hold a coat");

double plm_fresnel_dielectric(double cos_i, double eta)
{
    cos_i = plm_clamp(cos_i, 0.0, 1.0);
    double sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin_t2 >= 1.0)
        return 1.0;
    double cos_t = sqrt(1.0 - sin_t2);
    double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t), rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

static const plm_coat *state(const plm_bsdf *b) { return (const plm_coat *)b->state; }

static double ggx_d(double cos_h, double a)
{
    double a2 = a * a, c2 = cos_h * cos_h, t = c2 * (a2 - 1.0) + 1.0;
    return a2 / (PLM_PI * t * t);
}

/* Smith's Lambda for GGX at a direction with cosine c to the normal. */
static double ggx_lambda(double c, double a)
{
    double t2 = (1.0 - c * c) / (c * c);
    return 0.5 * (sqrt(1.0 + a * a * t2) - 1.0);
}

/* The probability of drawing the coat's lobe rather than the base's. */
static double spec_pick(const plm_coat *c, double cos_o)
{
    double f = plm_fresnel_dielectric(cos_o, c->eta), base = (1.0 - f) * rgb_mean(c->albedo);
    return plm_clamp(f / (f + base + 1e-12), 0.1, 0.9);
}

/* The two lobes' cosine-weighted values and densities at wi (local). */
static void lobes(const plm_coat *c, vec3 o, vec3 i, double *spec, double *spec_pdf, double *base, double *base_pdf)
{
    *spec = *spec_pdf = *base = *base_pdf = 0.0;
    if (i.z <= 0.0 || o.z <= 0.0)
        return;
    vec3 h = v3_add(o, i);
    double len = v3_length(h);
    if (len > 0.0) {
        h = v3_scale(h, 1.0 / len);
        double d = ggx_d(h.z, c->alpha), oh = v3_dot(o, h);
        double lo = ggx_lambda(o.z, c->alpha), li = ggx_lambda(i.z, c->alpha);
        *spec = d * plm_fresnel_dielectric(oh, c->eta) / (4.0 * o.z * (1.0 + lo + li));
        *spec_pdf = d / (4.0 * o.z * (1.0 + lo)); /* visible normals: G1(o) D / (4 cos_o) */
    }
    double t = (1.0 - plm_fresnel_dielectric(o.z, c->eta)) * (1.0 - plm_fresnel_dielectric(i.z, c->eta));
    *base = t * i.z * PLM_INV_PI;
    *base_pdf = i.z * PLM_INV_PI;
}

static rgb coat_eval(const plm_bsdf *b, vec3 wi)
{
    double s, sp, d, dp;
    lobes(state(b), frame_to_local(&b->shading, b->wo), frame_to_local(&b->shading, wi), &s, &sp, &d, &dp);
    return rgb_add(rgb_gray(s), rgb_scale(state(b)->albedo, d));
}

static double coat_pdf(const plm_bsdf *b, vec3 wi)
{
    vec3 o = frame_to_local(&b->shading, b->wo);
    double s, sp, d, dp, p = spec_pick(state(b), o.z);
    lobes(state(b), o, frame_to_local(&b->shading, wi), &s, &sp, &d, &dp);
    return p * sp + (1.0 - p) * dp;
}

static rgb coat_eval_mis(const plm_bsdf *b, vec3 wi, double light_pdf)
{
    return rgb_scale(coat_eval(b, wi), plm_power_heuristic(light_pdf, coat_pdf(b, wi)));
}

/* A GGX normal visible from o (Heitz 2018), for u1, u2 in [0, 1). */
static vec3 sample_visible_normal(vec3 o, double a, double u1, double u2)
{
    vec3 vh = v3_normalize(v3(a * o.x, a * o.y, o.z));
    double lensq = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = lensq > 0.0 ? v3_scale(v3(-vh.y, vh.x, 0.0), 1.0 / sqrt(lensq)) : v3(1, 0, 0), t2 = v3_cross(vh, t1);
    double r = sqrt(u1), phi = PLM_TWO_PI * u2, p1 = r * cos(phi), p2 = r * sin(phi), s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * sqrt(fmax(0.0, 1.0 - p1 * p1)) + s * p2;
    vec3 nh = v3_add(v3_add(v3_scale(t1, p1), v3_scale(t2, p2)),
                     v3_scale(vh, sqrt(fmax(0.0, 1.0 - p1 * p1 - p2 * p2))));
    return v3_normalize(v3(a * nh.x, a * nh.y, fmax(1e-9, nh.z)));
}

static int coat_sample(const plm_bsdf *b, double u0, double u1, double u2, plm_bsdf_sample_rec *s)
{
    const plm_coat *c = state(b);
    vec3 o = frame_to_local(&b->shading, b->wo), i;
    if (o.z <= 0.0)
        return 0;
    if (u0 < spec_pick(c, o.z)) {
        vec3 h = sample_visible_normal(o, c->alpha, u1, u2);
        i = v3_sub(v3_scale(h, 2.0 * v3_dot(o, h)), o);
    } else {
        i = plm_sample_cosine_hemisphere(u1, u2);
    }
    if (i.z <= 0.0)
        return 0;
    s->wi = frame_to_world(&b->shading, i);
    s->pdf = coat_pdf(b, s->wi);
    if (!(s->pdf > 0.0))
        return 0;
    s->weight = rgb_scale(coat_eval(b, s->wi), 1.0 / s->pdf);
    return 1;
}

static const plm_bsdf_ops coat_ops = {coat_eval, coat_pdf, coat_eval_mis, coat_sample};

void plm_coat_bsdf(const plm_coat *coat, vec3 n, vec3 wo, plm_bsdf *out)
{
    out->ops = &coat_ops;
    out->wo = wo;
    out->shading = frame_from_z(n);
    out->albedo = coat->albedo;
    memcpy(out->state, coat, sizeof *coat);
}
