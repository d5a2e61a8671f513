/* Shared by the tabulated fiber BCSDF tests (test_fiber_table.c,
 * slow_fiber_table.c): a first-principles reference of the part of the BCSDF
 * the table holds, and its relative L2 error over random queries. Include
 * after cmocka.h. */
#ifndef PLUMAGE_TESTS_FIBER_TABLE_STATS_H
#define PLUMAGE_TESTS_FIBER_TABLE_STATS_H

#include <stdio.h>
#include <stdlib.h>

#include "render/fiber_table.h"

/* The longitudinal detector: a Gaussian of std-dev beta about Theta,
 * normalised on [-pi/2, pi/2], written out independently of fiber.c. */
static double reference_gm(double beta, double Theta, double theta)
{
    double s = sqrt(2.0) * beta;
    double z = 0.5 * (erf((0.5 * PLM_PI - Theta) / s) + erf((0.5 * PLM_PI + Theta) / s));
    return exp(-0.5 * plm_sqr((theta - Theta) / beta)) / (sqrt(2.0 * PLM_PI) * beta * z);
}

/* The azimuthal detector: a Gaussian wrapped onto the circle. */
static double reference_gn(double beta, double dphi)
{
    double sum = 0.0;
    for (int k = -6; k <= 6; ++k)
        sum += exp(-0.5 * plm_sqr((dphi + PLM_TWO_PI * k) / beta));
    return sum / (sqrt(2.0 * PLM_PI) * beta);
}

/* The mean over h in [hmin, hmax] (strata midpoints) of eval(wi) from the
 * lobes that never meet the medulla: sum_k A_k G_M G_N / cos^2(theta_i). */
static rgb reference_eval(const plm_fiber_params *p, vec3 wo, double hmin, double hmax, vec3 wi, int strata)
{
    plm_fiber_lobe *lobes = malloc(sizeof *lobes * (size_t)p->lobes);
    plm_rng rng;
    plm_rng_seed(&rng, 5, 5);
    double ct = sqrt(wi.x * wi.x + wi.y * wi.y), theta = atan2(wi.z, ct), phi = atan2(wi.y, wi.x);
    rgb sum = rgb_gray(0.0);
    for (int s = 0; s < strata; ++s) {
        double h = hmin + (hmax - hmin) * (s + 0.5) / strata;
        int n = plm_fiber_trace(p, wo, h, &rng, lobes);
        for (int k = 0; k < n && !lobes[k].medulla; ++k) {
            double Theta = asin(lobes[k].dir.z), Phi = atan2(lobes[k].dir.y, lobes[k].dir.x);
            double d = reference_gm(p->beta_m, Theta, theta) * reference_gn(p->beta_n, phi - Phi);
            sum = rgb_add(sum, rgb_scale(lobes[k].throughput, d));
        }
    }
    free(lobes);
    return rgb_scale(sum, 1.0 / (strata * ct * ct));
}

/* The table's part of eval alone: a prepared BCSDF without its medulla sample. */
static rgb table_part_eval(const plm_fiber_table *t, vec3 wo, double hmin, double hmax, vec3 wi)
{
    plm_fiber_bcsdf b;
    plm_rng rng;
    plm_rng_seed(&rng, 1, 1);
    plm_fiber_bcsdf_prepare(&t->params, t, wo, hmin, hmax, &rng, &b);
    b.set.count = 0;
    return plm_fiber_bcsdf_eval(&b, wi);
}

static vec3 random_sphere(plm_rng *rng)
{
    return plm_fiber_direction(asin(2.0 * plm_rng_uniform(rng) - 1.0), PLM_TWO_PI * plm_rng_uniform(rng));
}

/* Relative L2 difference per channel, sqrt(sum (table - ref)^2 / sum ref^2),
 * over n random queries: wo uniform on the sphere, an h-interval with
 * uniform ends, and wi either uniform on the sphere (uniform_wi) or at the
 * lobes: theta_i = -theta_o plus a normal offset of beta_m, phi_i uniform
 * (where the table's values matter most). */
static void table_error(const plm_fiber_table *t, plm_rng *rng, int n, int uniform_wi, int strata, double err[3])
{
    const plm_fiber_params *p = &t->params;
    double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
    for (int q = 0; q < n; ++q) {
        vec3 wo = random_sphere(rng);
        double h0 = 2.0 * plm_rng_uniform(rng) - 1.0, h1 = 2.0 * plm_rng_uniform(rng) - 1.0;
        double hmin = fmin(h0, h1), hmax = fmax(h0, h1);
        vec3 wi;
        if (uniform_wi) {
            wi = random_sphere(rng);
        } else {
            double u1 = fmax(plm_rng_uniform(rng), 1e-12), u2 = plm_rng_uniform(rng);
            double g = sqrt(-2.0 * log(u1)) * cos(PLM_TWO_PI * u2); /* Box-Muller */
            double theta = plm_clamp(-asin(wo.z) + p->beta_m * g, -1.55, 1.55);
            wi = plm_fiber_direction(theta, PLM_TWO_PI * plm_rng_uniform(rng));
        }
        rgb a = table_part_eval(t, wo, hmin, hmax, wi), b = reference_eval(p, wo, hmin, hmax, wi, strata);
        double av[3] = {a.r, a.g, a.b}, bv[3] = {b.r, b.g, b.b};
        for (int c = 0; c < 3; ++c) {
            num[c] += plm_sqr(av[c] - bv[c]);
            den[c] += plm_sqr(bv[c]);
        }
    }
    for (int c = 0; c < 3; ++c)
        err[c] = den[c] > 0.0 ? sqrt(num[c] / den[c]) : 0.0;
}

#endif
