#include "optics/feather_bsdf.h"

#include "common/sampling.h"

#include <assert.h>
#include <string.h>

void plm_feather_params_default(plm_feather_params *p)
{
    plm_fiber_params_default(&p->barb);
    plm_fiber_params_default(&p->barbule);
    p->barb.sigma_a = p->barbule.sigma_a = rgb_make(0.133, 1.967, 2.1); /* paper Fig. 7 */
    p->barb.medulla_a = p->barb.medulla_b = 0.6;
    plm_masking_params_default(&p->masking);
    p->bcsdf = PLM_BCSDF_TABULATED;
}

void plm_feather_model_init(plm_feather_model *m, const plm_feather_params *p)
{
    m->params = p;
    plm_masking_prepare(&p->masking, &m->masking);
    m->table[0] = m->table[1] = NULL;
}

plm_result plm_feather_model_build_tables(plm_feather_model *m, plm_fiber_table_set *set, plm_error *err)
{
    const plm_fiber_params *fiber[2] = {&m->params->barb, &m->params->barbule};
    for (int k = 0; k < 2 && m->params->bcsdf == PLM_BCSDF_TABULATED; ++k) {
        plm_result rc = m->table[k] ? PLM_OK : plm_fiber_table_set_get(set, fiber[k], &m->table[k], err);
        if (rc != PLM_OK)
            return rc;
    }
    return PLM_OK;
}

plm_result plm_feather_params_validate(const plm_feather_params *p, plm_error *err)
{
    plm_result rc = plm_fiber_params_validate(&p->barb, err);
    if (rc != PLM_OK) {
        plm_error_prefix(err, "barb: ");
        return rc;
    }
    rc = plm_fiber_params_validate(&p->barbule, err);
    if (rc != PLM_OK) {
        plm_error_prefix(err, "barbule: ");
        return rc;
    }
    if (p->barb.lobes > PLM_FIBER_SET_MAX_LOBES || p->barbule.lobes > PLM_FIBER_SET_MAX_LOBES)
        return plm_fail(err, PLM_ERR_INVALID, "lobes: at most %d when rendering", PLM_FIBER_SET_MAX_LOBES);
    rc = plm_masking_params_validate(&p->masking, err);
    if (rc != PLM_OK)
        plm_error_prefix(err, "masking: ");
    return rc;
}

int plm_feather_barb_frame(vec3 n, vec3 dpdu, vec3 dpdv, vec2 direction_uv, frame *out)
{
    vec3 t = v3_add(v3_scale(dpdu, direction_uv.x), v3_scale(dpdv, direction_uv.y));
    t = v3_sub(t, v3_scale(n, v3_dot(t, n)));
    double len = v3_length(t);
    if (!(len > 1e-12))
        return 0;
    t = v3_scale(t, 1.0 / len);
    vec3 b = v3_cross(n, t);
    /* The distal side faces the tip. A barb exactly along dP/dv leaves the
     * side undefined; then dP/du breaks the tie consistently. */
    double side = v3_dot(b, dpdv);
    if (side < 0.0 || (side == 0.0 && v3_dot(b, dpdu) < 0.0))
        b = v3_neg(b);
    out->x = b;
    out->y = n;
    out->z = t;
    return 1;
}

void plm_feather_masking(const plm_feather_model *m, const frame *barb, const plm_barb_window *window, vec3 w,
                         plm_masking *out)
{
    /* The prepared masking must be of the parameters as they are now: a stale
     * one would mask with other parameters than the scene's. */
    assert(memcmp(&m->params->masking, &m->masking.params, sizeof m->masking.params) == 0);
    plm_masking_eval_window(&m->masking, frame_to_local(barb, w), window, out);
}

/* Component index of the barb's visible range i. */
static int barb_component(int i) { return i == 0 ? PLM_FEATHER_BARB : PLM_FEATHER_DISTAL + i; }

void plm_feather_prepare_masked(const plm_feather_model *model, const frame *barb, vec3 wo,
                                const plm_masking *masking, rgb tint, plm_rng *rng, plm_feather_bsdf *out)
{
    const plm_feather_params *p = model->params;
    out->model = model;
    out->tint = tint;
    plm_masking *m = &out->masking;
    *m = *masking;
    double opaque = 1.0 - m->w_transmission;
    double scale = opaque > 1e-12 ? 1.0 / opaque : 0.0;
    /* The barb is seen through up to six h-ranges of different rates, each a
     * component of its own. (Choosing one range by its rate, a one-sample
     * estimate of their sum, let the rare sliver at a barb's edge, whose
     * grazing reflection of a light behind the feather is a hundred times
     * the rest's, make the back-lit goose's fireflies.) */
    plm_h_range whole = {-1.0, 1.0, m->w_barb};
    int ranges = m->barb_range_count > 0 ? m->barb_range_count : 1;
    const plm_h_range *range[PLM_FEATHER_COMPONENTS];
    out->count = ranges + 2;
    for (int i = 0; i < ranges; ++i) {
        int k = barb_component(i);
        range[k] = m->barb_range_count > 0 ? &m->barb[i] : &whole;
        out->fiber[k] = &p->barb;
        out->fiber_frame[k] = *barb; /* x = b = e2, y = n = e3, z = t = axis */
        out->weight[k] = range[k]->rate * scale;
    }
    range[PLM_FEATHER_PROXIMAL] = &m->proximal;
    range[PLM_FEATHER_DISTAL] = &m->distal;
    out->weight[PLM_FEATHER_PROXIMAL] = m->w_proximal * scale;
    out->weight[PLM_FEATHER_DISTAL] = m->w_distal * scale;
    /* A barbule frame serves only a set with weight (eval and sampling skip
     * the others), and most views see one barbule set or none. */
    const plm_barbule_frame *bb[2] = {&model->masking.proximal, &model->masking.distal};
    for (int j = 0; j < 2; ++j) {
        int k = PLM_FEATHER_PROXIMAL + j;
        out->fiber[k] = &p->barbule;
        if (!(out->weight[k] > 0.0))
            continue;
        frame *f = &out->fiber_frame[k];
        f->x = frame_to_world(barb, bb[j]->e2);
        f->y = frame_to_world(barb, bb[j]->e3);
        f->z = frame_to_world(barb, bb[j]->axis);
    }
    for (int k = 0; k < out->count; ++k) {
        out->bcsdf[k].total = 0.0;
        const plm_fiber_table *table = model->table[out->fiber[k] == &p->barb ? 0 : 1];
        if (out->weight[k] > 0.0)
            plm_fiber_bcsdf_prepare(out->fiber[k], p->bcsdf == PLM_BCSDF_TABULATED ? table : NULL,
                                    frame_to_local(&out->fiber_frame[k], wo), range[k]->hmin, range[k]->hmax, rng,
                                    &out->bcsdf[k]);
    }
    /* Sampling chooses a component by the light it sends back, its weight
     * times its fiber's energy for wo: the sampled direction's weight, fiber
     * k's own, then varies little with the choice (plm_feather_sample). */
    double total = 0.0;
    for (int k = 0; k < out->count; ++k)
        total += out->pick[k] = out->bcsdf[k].total > 0.0 ? out->weight[k] * out->bcsdf[k].total : 0.0;
    for (int k = 0; k < out->count; ++k)
        out->pick[k] = total > 0.0 ? out->pick[k] / total : 0.0;
}

/* cos(theta) of a fiber-frame direction: the length of its component across
 * the axis (as the fiber samplers compute it; accurate near the axis). */
static double fiber_cos_theta(vec3 local) { return sqrt(local.x * local.x + local.y * local.y); }

/* Fiber k's term of eval at the world direction wi, w_k S_k cos(theta_i)
 * (without the tint), and, if q is not NULL, the density with which
 * sampling draws wi through fiber k, pick_k pdf_k, from the same lookups. */
static rgb fiber_term(const plm_feather_bsdf *f, int k, vec3 wi, double *q)
{
    vec3 local = frame_to_local(&f->fiber_frame[k], wi);
    double pk = 0.0;
    rgb s = q ? plm_fiber_bcsdf_eval_pdf(&f->bcsdf[k], local, &pk) : plm_fiber_bcsdf_eval(&f->bcsdf[k], local);
    if (q)
        *q = f->pick[k] * pk;
    return rgb_scale(s, f->weight[k] * fiber_cos_theta(local));
}

/* The components sampling can pick are exactly those that carry light
 * (pick[k] > 0 iff weight[k] > 0 and the fiber has energy for wo): eval,
 * eval_mis and pdf sum those. */
rgb plm_feather_eval(const plm_feather_bsdf *f, vec3 wi)
{
    rgb sum = rgb_gray(0.0);
    for (int k = 0; k < f->count; ++k)
        if (f->pick[k] > 0.0)
            sum = rgb_add(sum, fiber_term(f, k, wi, NULL));
    return rgb_mul(sum, f->tint);
}

rgb plm_feather_eval_mis(const plm_feather_bsdf *f, vec3 wi, double light_pdf)
{
    rgb sum = rgb_gray(0.0);
    for (int k = 0; k < f->count; ++k) {
        if (!(f->pick[k] > 0.0))
            continue;
        double qk;
        rgb term = fiber_term(f, k, wi, &qk);
        sum = rgb_add(sum, rgb_scale(term, plm_power_heuristic(light_pdf, qk)));
    }
    return rgb_mul(sum, f->tint);
}

double plm_feather_pdf(const plm_feather_bsdf *f, vec3 wi)
{
    double pdf = 0.0;
    for (int k = 0; k < f->count; ++k)
        if (f->pick[k] > 0.0)
            pdf += f->pick[k] * plm_fiber_bcsdf_pdf(&f->bcsdf[k], frame_to_local(&f->fiber_frame[k], wi));
    return pdf;
}

int plm_feather_pick(const plm_feather_bsdf *f, double u, double *remapped)
{
    const double *w = f->pick;
    int k = 0;
    while (k < f->count - 1 && (u >= w[k] || w[k] == 0.0)) {
        u -= w[k];
        ++k;
    }
    if (w[k] <= 0.0)
        return -1;
    *remapped = plm_clamp(u / w[k], 0.0, 0x1.fffffffffffffp-1);
    return k;
}

int plm_feather_sample(const plm_feather_bsdf *f, double u0, double u1, double u2, vec3 *wi, double *pdf,
                       rgb *weight)
{
    double remapped;
    int k = plm_feather_pick(f, u0, &remapped);
    vec3 local;
    if (k < 0 || !plm_fiber_bcsdf_sample_direction(&f->bcsdf[k], remapped, u1, u2, &local))
        return 0;
    /* Fiber k's term and density at the world direction, as eval gives them
     * (the trip to world space and back moves the fiber's direction by
     * rounding, enough to change the density in the last digits). */
    *wi = frame_to_world(&f->fiber_frame[k], local);
    double q;
    rgb term = fiber_term(f, k, *wi, &q);
    if (!(q > 0.0))
        return 0;
    /* eval(wi) / pdf(wi) estimated by fiber k alone: its term over
     * pick_k pdf_k. Given wi, fiber k was the choice with probability
     * pick_k pdf_k / pdf, so the estimate's mean is eval / pdf; the other
     * fibers are not evaluated. MIS weighs the draw as fiber k's own
     * technique, whose density is pick_k pdf_k (plm_feather_eval_mis). */
    *pdf = q;
    *weight = rgb_mul(rgb_scale(term, 1.0 / q), f->tint);
    return 1;
}
