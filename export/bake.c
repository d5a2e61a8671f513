/* The far-field albedo by Monte Carlo over the renderer's BSDF (bake.h). */
#include "export/bake.h"

#include <math.h>
#include <stdlib.h>

#include "common/sampling.h"
#include "render/material.h"

/* The centre of the vane texel nearest the texture's centre; 0 if none. */
static int vane_uv(const plm_feather_texture *t, vec2 *uv)
{
    long best = -1;
    double best_d = INFINITY;
    for (int y = 0; y < t->height; ++y)
        for (int x = 0; x < t->width; ++x) {
            long i = (long)y * t->width + x;
            double dx = x + 0.5 - 0.5 * t->width, dy = y + 0.5 - 0.5 * t->height, d = dx * dx + dy * dy;
            if (t->region[i] == PLM_REGION_VANE && d < best_d)
                best = i, best_d = d;
        }
    if (best < 0)
        return 0;
    *uv = v2(((double)(best % t->width) + 0.5) / t->width, 1.0 - ((double)(best / t->width) + 0.5) / t->height);
    return 1;
}

/* A far-field hit on the plane z = 0 at a vane texel, without the pigment
 * (the caller scales by it texel by texel) and with a white tint. */
static plm_result plane_hit(const plm_material *m, const plm_prepared_material *p, plm_material *plain, plm_hit *h,
                            plm_error *err)
{
    *plain = *m;
    plain->pigment.pixels = NULL;
    *h = (plm_hit){0};
    h->ng = h->n = v3(0, 0, 1);
    h->dpdu = v3(1, 0, 0); /* on a fiber: its axis */
    h->dpdv = v3(0, 1, 0);
    h->tint = rgb_gray(1.0);
    h->material = plain;
    h->prepared = p;
    h->uv = v2(0.5, 0.5);
    if (m->type == PLM_MATERIAL_FEATHER && !vane_uv(&m->texture, &h->uv))
        return plm_fail(err, PLM_ERR_INVALID, "material %s: its feather texture has no vane texel", m->name);
    plm_material_surface(h);
    return PLM_OK;
}

typedef struct furnace {
    plm_material plain;
    plm_hit hit;
    plm_bsdf *bsdf; /* 50 KiB: on the heap */
} furnace;

static plm_result furnace_open(furnace *f, const plm_material *m, const plm_prepared_material *p, plm_error *err)
{
    f->bsdf = malloc(sizeof *f->bsdf);
    if (!f->bsdf)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "material %s: out of memory", m->name);
    plm_result rc = plane_hit(m, p, &f->plain, &f->hit, err);
    if (rc != PLM_OK)
        free(f->bsdf);
    return rc;
}

/* w_t(wo) and the mean of n BSDF sample weights, an unbiased estimate of A(wo)
 * (sample weights estimate f |cos| / pdf over the whole sphere). */
static double furnace_view(furnace *f, vec3 wo, int n, plm_rng *rng, rgb *albedo)
{
    double wt = plm_material_transmission(&f->hit, wo);
    plm_material_bsdf(&f->hit, wo, rng, f->bsdf);
    rgb sum = rgb_gray(0.0);
    for (int i = 0; i < n; ++i) {
        plm_bsdf_sample_rec s;
        double u0 = plm_rng_uniform(rng), u1 = plm_rng_uniform(rng), u2 = plm_rng_uniform(rng);
        if (plm_bsdf_sample(f->bsdf, u0, u1, u2, &s) && isfinite(rgb_mean(s.weight)))
            sum = rgb_add(sum, s.weight);
    }
    *albedo = rgb_scale(sum, 1.0 / n);
    return wt;
}

plm_result plm_bake_view_at(const plm_material *m, const plm_prepared_material *p, vec3 wo, int samples,
                            uint64_t seed, plm_bake_view *out, plm_error *err)
{
    furnace f;
    plm_result rc = furnace_open(&f, m, p, err);
    if (rc != PLM_OK)
        return rc;
    plm_rng rng;
    plm_rng_seed(&rng, seed, 1);
    /* Batches of 64 samples, each with its own prepared BSDF, give the standard error. */
    int batches = samples > 64 ? samples / 64 : 1, per = samples / batches;
    double wt_sum = 0.0, l_sum = 0.0, l_sum2 = 0.0;
    rgb a_sum = rgb_gray(0.0);
    for (int b = 0; b < batches; ++b) {
        rgb a;
        double wt = furnace_view(&f, wo, per, &rng, &a), l = wt + (1.0 - wt) * rgb_mean(a);
        wt_sum += wt, a_sum = rgb_add(a_sum, a), l_sum += l, l_sum2 += l * l;
    }
    free(f.bsdf);
    out->transmission = wt_sum / batches;
    out->albedo = rgb_scale(a_sum, 1.0 / batches);
    out->radiance = rgb_add(rgb_gray(out->transmission), rgb_scale(out->albedo, 1.0 - out->transmission));
    double mean = l_sum / batches;
    out->radiance_se = batches > 1 ? sqrt(fmax(l_sum2 / batches - mean * mean, 0.0) / (batches - 1)) : INFINITY;
    return PLM_OK;
}

/* View i of k x k stratified ones and its weight: for a surface cosine-distributed
 * over the dorsal hemisphere (weight 1); for a fiber uniform over the sphere,
 * weighted by the width it shows (|wo x axis|), as a tuft of fibers lying every
 * which way shows them at a distance. */
static vec3 bake_view(const plm_material *m, int i, int k, plm_rng *rng, double *weight)
{
    double u1 = (i % k + plm_rng_uniform(rng)) / k, u2 = (i / k + plm_rng_uniform(rng)) / k;
    *weight = 1.0;
    if (m->type != PLM_MATERIAL_FIBER)
        return plm_sample_cosine_hemisphere(u1, u2);
    vec3 wo = plm_sample_uniform_sphere(u1, u2);
    *weight = sqrt(wo.y * wo.y + wo.z * wo.z); /* the fiber's axis is dpdu = +x (plane_hit) */
    return wo;
}

plm_result plm_bake_albedo_of(const plm_material *m, const plm_prepared_material *p, const plm_bake_options *o,
                              plm_bake_albedo *out, plm_error *err)
{
    if (m->type != PLM_MATERIAL_FEATHER && m->type != PLM_MATERIAL_FIBER) {
        *out = (plm_bake_albedo){m->reflectance, 1.0 - m->transmission, 0.0};
        return PLM_OK;
    }
    int k = o->views > 0 ? o->views : 24, n = o->samples > 0 ? o->samples : 64;
    furnace f;
    plm_result rc = furnace_open(&f, m, p, err);
    if (rc != PLM_OK)
        return rc;
    plm_rng rng;
    plm_rng_seed(&rng, o->seed, 2);
    /* Weighted sums over the views (a fiber passes nothing straight through: w_t = 0). */
    double w_sum = 0.0, wt_sum = 0.0, s_sum = 0.0, s_sum2 = 0.0;
    rgb scattered = rgb_gray(0.0);
    for (int i = 0; i < k * k; ++i) {
        double w;
        vec3 wo = bake_view(m, i, k, &rng, &w);
        rgb a;
        double wt = furnace_view(&f, wo, n, &rng, &a), s = (1.0 - wt) * rgb_mean(a);
        w_sum += w, wt_sum += w * wt;
        scattered = rgb_add(scattered, rgb_scale(a, w * (1.0 - wt)));
        s_sum += w * s, s_sum2 += w * s * s;
    }
    free(f.bsdf);
    double alpha = 1.0 - wt_sum / w_sum;
    if (!(alpha > 0.0))
        return plm_fail(err, PLM_ERR_INVALID, "material %s: lets all light through (alpha 0); nothing to bake",
                        m->name);
    out->alpha = alpha;
    out->colour = rgb_scale(scattered, 1.0 / (w_sum * alpha));
    /* Across views, treating the strata as independent draws: an upper bound. */
    double views = (double)(k * k), mean = s_sum / w_sum;
    out->colour_se = sqrt(fmax(s_sum2 / w_sum - mean * mean, 0.0) / (views - 1.0)) / alpha;
    return PLM_OK;
}
