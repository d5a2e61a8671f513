/* Shared by test_masking_reference.c and slow_masking.c: the analytic masking
 * against the explicit-geometry Monte Carlo reference over grids of views. */
#ifndef PLUMAGE_TESTS_MASKING_COMPARE_H
#define PLUMAGE_TESTS_MASKING_COMPARE_H

#include <math.h>
#include <stdio.h>

#include "optics/masking.h"
#include "render/masking_reference.h"

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

/* Compares plm_masking_eval with the reference rays over views on both
 * sides of the vane with polar angle from +-n in [polar_lo, polar_hi]
 * (degrees, grid steps polar_step and azimuth_step). Returns 0 if the
 * reference failed. */
static inline int masking_compare(const plm_masking_params *p, const plm_masking_reference *ref,
                                  masking_agreement *out, double polar_lo, double polar_hi, double polar_step,
                                  double azimuth_step, unsigned samples, uint64_t seed)
{
    *out = (masking_agreement){{0, 0, 0, 0}, {0, 0, 0, 0}, 0};
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
                plm_masking m;
                plm_masking_eval(p, wo, &m);
                double d[4] = {m.w_barb - r.w_barb, m.w_proximal - r.w_proximal, m.w_distal - r.w_distal,
                               m.w_transmission - r.w_transmission};
                for (int k = 0; k < 4; ++k) {
                    out->mean[k] += fabs(d[k]);
                    out->max[k] = fmax(out->max[k], fabs(d[k]));
                }
                out->views++;
            }
    for (int k = 0; k < 4; ++k)
        out->mean[k] /= out->views;
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
