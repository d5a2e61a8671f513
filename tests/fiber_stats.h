/* Statistics shared by the fiber BCSDF tests (test_fiber_bcsdf.c, slow_fiber.c,
 * test_fiber_table.c): quadrature of eval and pdf over the sphere, and
 * pbrt-v4's chi-square test of sampling against pdf, for a prepared BCSDF of
 * either estimator (a lobe set is the stochastic one). Include after cmocka.h. */
#ifndef PLUMAGE_TESTS_FIBER_STATS_H
#define PLUMAGE_TESTS_FIBER_STATS_H

#include "optics/fiber_bcsdf.h"
#include "tests/chi_square.h"

/* The stochastic BCSDF of a traced lobe set. */
static inline plm_fiber_bcsdf bcsdf_of_set(const plm_fiber_params *p, const plm_fiber_lobe_set *set)
{
    plm_fiber_bcsdf b;
    b.params = p;
    b.tab.table = NULL;
    b.set = *set;
    b.pick_table = 0.0;
    b.total = set->total;
    return b;
}

/* Midpoint rule over a (theta, phi) rectangle of eval(wi) cos(theta) dw =
 * eval cos^2 dtheta dphi (channel 0..2), or of pdf dw = pdf cos dtheta dphi (channel 3). */
static double integrate_bcsdf(const plm_fiber_bcsdf *b, int channel, double t0, double t1, double f0, double f1,
                              int nt, int nf)
{
    double sum = 0.0, dt = (t1 - t0) / nt, df = (f1 - f0) / nf;
    for (int i = 0; i < nt; ++i) {
        double theta = t0 + (i + 0.5) * dt, c = cos(theta);
        for (int j = 0; j < nf; ++j) {
            vec3 wi = plm_fiber_direction(theta, f0 + (j + 0.5) * df);
            if (channel == 3) {
                sum += plm_fiber_bcsdf_pdf(b, wi) * c;
            } else {
                rgb e = plm_fiber_bcsdf_eval(b, wi);
                sum += (channel == 0 ? e.r : channel == 1 ? e.g : e.b) * c * c;
            }
        }
    }
    return sum * dt * df;
}

enum { THETA_BINS = 80, PHI_BINS = 160 };

/* pbrt-v4's test: histogram plm_fiber_bcsdf_sample over an 80 x 160 grid of
 * (theta, phi), integrate the pdf over each cell, pool cells expecting
 * fewer than 5 samples, and compare with Pearson's chi-square (chi_square.h).
 * Also checks each record against pdf and eval. Returns the p-value. */
static double bcsdf_chi_square(const plm_fiber_bcsdf *b, plm_rng *rng, int n_samples)
{
    static double observed[THETA_BINS * PHI_BINS], expected[THETA_BINS * PHI_BINS];
    for (int i = 0; i < THETA_BINS * PHI_BINS; ++i)
        observed[i] = 0.0;
    const double dt = PLM_PI / THETA_BINS, df = PLM_TWO_PI / PHI_BINS;
    for (int s = 0; s < n_samples; ++s) {
        plm_fiber_sample_rec rec;
        double u0 = plm_rng_uniform(rng), u1 = plm_rng_uniform(rng), u2 = plm_rng_uniform(rng);
        if (!plm_fiber_bcsdf_sample(b, u0, u1, u2, &rec)) {
            assert_true(b->tab.table); /* a table's sampler may find a bin of mass 0 (probability ~1e-7) */
            continue;
        }
        /* The record agrees with pdf and eval. */
        double pdf = plm_fiber_bcsdf_pdf(b, rec.wi);
        rgb f = plm_fiber_bcsdf_eval(b, rec.wi);
        double c = sqrt(rec.wi.x * rec.wi.x + rec.wi.y * rec.wi.y);
        assert_true(fabs(rec.pdf - pdf) <= 1e-12 * pdf);
        assert_true(fabs(rec.weight.g - f.g * c / pdf) <= 1e-9 * (rec.weight.g + 1e-300));
        double theta = asin(plm_clamp(rec.wi.z, -1.0, 1.0)), phi = atan2(rec.wi.y, rec.wi.x);
        observed[chi_square_cell(theta, phi, THETA_BINS, PHI_BINS)] += 1.0;
    }
    for (int it = 0; it < THETA_BINS; ++it)
        for (int ip = 0; ip < PHI_BINS; ++ip) {
            double t0 = -0.5 * PLM_PI + it * dt, f0 = -PLM_PI + ip * df;
            expected[it * PHI_BINS + ip] = n_samples * integrate_bcsdf(b, 3, t0, t0 + dt, f0, f0 + df, 6, 6);
        }
    return chi_square_test(observed, expected, THETA_BINS * PHI_BINS);
}


#endif
