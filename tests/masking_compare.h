/* Shared by test_masking_reference.c and slow_masking.c: the analytic masking
 * against the explicit-geometry Monte Carlo reference over grids of views. */
#ifndef PLUMAGE_TESTS_MASKING_COMPARE_H
#define PLUMAGE_TESTS_MASKING_COMPARE_H

#include <math.h>
#include <stdio.h>

#include "render/masking.h"
#include "render/masking_reference.h"

/* The analytic levels composed with the frames of the reference's actual
 * geometry instead of the model's (docs/masking.md). Barbules rooted along the barb (t) with
 * axis a form rows whose normal is along t x a, not r2 = (0, cos, -sin), and
 * in the barb cross-section they rise at atan(sin theta cos phi / sin phi),
 * not theta. The two agree at theta_bb = 0. This composition is not the
 * product's model; it shows that the level computations themselves are exact
 * for the geometry, so that any disagreement of the full model comes from
 * the frames. */
static inline void masking_rooted_frames(const plm_masking_params *p, vec3 wo, plm_masking *out)
{
    double sp = sin(p->barbule_rotation), cp = cos(p->barbule_rotation);
    double st = sin(p->barbule_inclination), ct = cos(p->barbule_inclination);
    vec3 axis[2] = {v3(-sp, st * cp, ct * cp), v3(sp, st * cp, ct * cp)}; /* proximal, distal */
    vec3 normal[2] = {v3_normalize(v3(st * cp, sp, 0.0)), v3_normalize(v3(-st * cp, sp, 0.0))};
    plm_barbule_masking m[2];
    for (int k = 0; k < 2; ++k) {
        vec3 across = v3_cross(normal[k], axis[k]);
        plm_masking_barbule(p->barbule_eccentricity, p->barbule_separation,
                            v2(v3_dot(wo, across), v3_dot(wo, normal[k])), &m[k]);
    }
    double rise = atan2(st * cp, sp);
    double length = p->barbule_length * ct / cos(rise); /* keeps the barb width */
    plm_barb_masking b;
    plm_masking_barb(p->barb_eccentricity, length, rise, m[0].transmittance, m[1].transmittance, v2(wo.x, wo.y), &b);
    out->w_barb = b.w_barb;
    out->w_proximal = b.w_proximal;
    out->w_distal = b.w_distal;
    out->w_transmission = b.w_transmission;
}

static inline void masking_design_frames(const plm_masking_params *p, vec3 wo, plm_masking *out)
{
    plm_masking_eval(p, wo, out);
}

typedef struct masking_agreement {
    double mean[4], max[4]; /* |analytic - reference| of w_barb, w_proximal, w_distal, w_transmission */
    int views;
} masking_agreement;

/* The reference with default options, or NULL after printing why not. */
static inline plm_masking_reference *masking_reference_or_null(const plm_masking_params *p)
{
    plm_masking_reference *ref = NULL;
    plm_error err;
    if (plm_masking_reference_create(p, NULL, &ref, &err) != PLM_OK)
        fprintf(stderr, "%s\n", err.message);
    return ref;
}

typedef void (*masking_model_fn)(const plm_masking_params *, vec3, plm_masking *);

/* Compares n models with one set of reference rays per view, over views on
 * both sides of the vane with polar angle from +-n in [polar_lo, polar_hi]
 * (degrees, grid steps polar_step and azimuth_step). Returns 0 if the
 * reference failed. */
static inline int masking_compare_models(const plm_masking_params *p, const plm_masking_reference *ref,
                                         const masking_model_fn *models, int n, masking_agreement *out,
                                         double polar_lo, double polar_hi, double polar_step, double azimuth_step,
                                         unsigned samples, uint64_t seed)
{
    for (int i = 0; i < n; ++i)
        out[i] = (masking_agreement){{0, 0, 0, 0}, {0, 0, 0, 0}, 0};
    int views = 0;
    for (int side = 0; side < 2; ++side)
        for (double polar = polar_lo; polar <= polar_hi + 1e-9; polar += polar_step)
            for (double azimuth = 0.5 * azimuth_step; azimuth < 360.0; azimuth += azimuth_step) {
                double t = plm_radians(polar), f = plm_radians(azimuth);
                vec3 wo = v3(sin(t) * cos(f), side ? -cos(t) : cos(t), sin(t) * sin(f));
                plm_masking r;
                plm_error err;
                if (plm_masking_reference_eval(ref, wo, samples, seed + (uint64_t)views, &r, &err) != PLM_OK) {
                    fprintf(stderr, "reference failed: %s\n", err.message);
                    return 0;
                }
                ++views;
                for (int i = 0; i < n; ++i) {
                    plm_masking m;
                    models[i](p, wo, &m);
                    double d[4] = {m.w_barb - r.w_barb, m.w_proximal - r.w_proximal, m.w_distal - r.w_distal,
                                   m.w_transmission - r.w_transmission};
                    for (int k = 0; k < 4; ++k) {
                        out[i].mean[k] += fabs(d[k]);
                        out[i].max[k] = fmax(out[i].max[k], fabs(d[k]));
                    }
                    out[i].views++;
                }
            }
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 4; ++k)
            out[i].mean[k] /= out[i].views;
    return 1;
}

static inline void masking_agreement_print(const char *label, const masking_agreement *a)
{
    printf("%-44s views %4d  mean |diff| barb %.4f prox %.4f dist %.4f trans %.4f  max %.3f %.3f %.3f %.3f\n", label,
           a->views, a->mean[0], a->mean[1], a->mean[2], a->mean[3], a->max[0], a->max[1], a->max[2], a->max[3]);
}

static inline double masking_agreement_worst_mean(const masking_agreement *a)
{
    return fmax(fmax(a->mean[0], a->mean[1]), fmax(a->mean[2], a->mean[3]));
}

#endif
