/* Long validations of the fiber BCSDF (ctest label "slow"): sampling against
 * pdf over many random fibers, the white furnace as a Monte Carlo estimate
 * averaged over lobe sets, and 5 against 1000 lobes over the paper's Fig. 10
 * range of eccentricities and medulla sizes. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>

#include "optics/fiber.h"
#include "tests/fiber_stats.h"

/* A random valid fiber: eccentricity, index, roughness, and (half the time)
 * an off-centre elliptical medulla. */
static plm_fiber_params random_fiber(plm_rng *rng)
{
    for (;;) {
        plm_fiber_params p;
        plm_fiber_params_figure7(&p, 1);
        p.eccentricity = 0.3 + 3.0 * plm_rng_uniform(rng);
        p.eta = 1.2 + 0.6 * plm_rng_uniform(rng);
        p.sigma_a = rgb_make(2.0 * plm_rng_uniform(rng), 0.5 * plm_rng_uniform(rng), 0.0);
        p.beta_m = plm_radians(2.0 + 40.0 * plm_rng_uniform(rng));
        p.beta_n = plm_radians(2.0 + 60.0 * plm_rng_uniform(rng));
        if (plm_rng_uniform(rng) < 0.5) {
            p.medulla_a = 0.1 + 0.6 * plm_rng_uniform(rng);
            p.medulla_b = p.eccentricity * (0.1 + 0.6 * plm_rng_uniform(rng));
            p.medulla_ca = 0.4 * (plm_rng_uniform(rng) - 0.5);
            p.medulla_cb = 0.4 * p.eccentricity * (plm_rng_uniform(rng) - 0.5);
            p.medulla_reflectance = rgb_make(plm_rng_uniform(rng), 0.7, 1.0);
        }
        if (plm_fiber_params_validate(&p, NULL) == PLM_OK)
            return p;
    }
}

static vec3 random_direction(plm_rng *rng)
{
    return plm_fiber_direction(asin(2.0 * plm_rng_uniform(rng) - 1.0), PLM_TWO_PI * plm_rng_uniform(rng));
}

static void sampling_matches_pdf_for_random_fibers(void **state)
{
    (void)state;
    enum { N_TESTS = 40 };
    const double threshold = chi_square_sidak(0.01, N_TESTS);
    plm_rng rng;
    plm_rng_seed(&rng, 1234, 0);
    int failures = 0;
    for (int t = 0; t < N_TESTS; ++t) {
        plm_fiber_params p = random_fiber(&rng);
        plm_fiber_lobe_set set;
        do
            plm_fiber_prepare(&p, random_direction(&rng), -1.0, 1.0, &rng, &set);
        while (!(set.total > 0.0));
        plm_fiber_bcsdf b = bcsdf_of_set(&p, &set);
        double pv = bcsdf_chi_square(&b, &rng, 1000000);
        fprintf(stderr, "chi-square %2d: e %.2f beta %.1f/%.1f deg, %d lobes: p-value %.4f\n", t, p.eccentricity,
                plm_degrees(p.beta_m), plm_degrees(p.beta_n), set.count, pv);
        failures += !(pv > threshold);
    }
    assert_int_equal(failures, 0);
}

/* Without absorption, the mean over lobe sets of a uniform-sphere Monte Carlo
 * estimate of the integral of eval cos equals the mean lobe energy within
 * four standard errors. */
static void monte_carlo_white_furnace(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 4321, 0);
    for (int t = 0; t < 12; ++t) {
        plm_fiber_params p = random_fiber(&rng);
        p.sigma_a = rgb_gray(0.0);
        p.medulla_reflectance = rgb_gray(1.0);
        vec3 wo = random_direction(&rng);
        const int n_sets = 20000, per_set = 64;
        double sum = 0.0, sum2 = 0.0, energy = 0.0;
        for (int s = 0; s < n_sets; ++s) {
            plm_fiber_lobe_set set;
            plm_fiber_prepare(&p, wo, -1.0, 1.0, &rng, &set);
            for (int k = 0; k < set.count; ++k)
                energy += set.throughput[k].r / n_sets;
            for (int j = 0; j < per_set; ++j) {
                vec3 wi = random_direction(&rng);
                double est = plm_fiber_eval(&p, &set, wi).r * sqrt(wi.x * wi.x + wi.y * wi.y) * 4.0 * PLM_PI;
                sum += est;
                sum2 += est * est;
            }
        }
        double n = (double)n_sets * per_set, mean = sum / n, se = sqrt((sum2 / n - mean * mean) / n);
        fprintf(stderr, "furnace %2d: e %.2f beta %.1f/%.1f deg: integral %.4f +- %.4f, lobe energy %.4f\n", t,
                p.eccentricity, plm_degrees(p.beta_m), plm_degrees(p.beta_n), mean, se, energy);
        assert_true(fabs(mean - energy) < 4.0 * se);
        assert_true(energy > 0.9 && energy <= 1.0 + 1e-12);
    }
}

/* The paper's Fig. 13 claim over its Fig. 10 ranges (e_b 1 to 1.8, medulla
 * radius up to 0.8, white medulla, no absorption): 5 lobes are within 1% of
 * 1000 in mean energy. */
static void five_lobes_suffice_over_figure10_ranges(void **state)
{
    (void)state;
    static plm_fiber_lobe lobes[PLM_FIBER_MAX_LOBES];
    for (int e = 0; e < 5; ++e)
        for (int m = 0; m < 5; ++m) {
            plm_fiber_params p;
            plm_fiber_params_figure7(&p, 1);
            p.sigma_a = rgb_gray(0.0);
            p.eccentricity = 1.0 + 0.2 * e;
            p.medulla_a = p.medulla_b = 0.2 * m;
            assert_int_equal(plm_fiber_params_validate(&p, NULL), PLM_OK);
            double sum5 = 0.0, sum1000 = 0.0;
            const int n = 20000;
            for (int i = 0; i < n; ++i) {
                for (int run = 0; run < 2; ++run) {
                    plm_rng rng;
                    plm_rng_seed(&rng, 6, (uint64_t)i);
                    vec3 wo = random_direction(&rng);
                    double h = 2.0 * plm_rng_uniform(&rng) - 1.0;
                    int count = plm_fiber_trace_n(&p, wo, h, &rng, lobes, run ? 1000 : 5, NULL);
                    double total = 0.0;
                    for (int k = 0; k < count; ++k)
                        total += lobes[k].throughput.r;
                    *(run ? &sum1000 : &sum5) += total / n;
                }
            }
            fprintf(stderr, "e %.1f medulla %.1f: mean energy 5 lobes %.5f, 1000 lobes %.5f\n", p.eccentricity,
                    p.medulla_a, sum5, sum1000);
            assert_true((sum1000 - sum5) / sum1000 < 0.01);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sampling_matches_pdf_for_random_fibers),
        cmocka_unit_test(monte_carlo_white_furnace),
        cmocka_unit_test(five_lobes_suffice_over_figure10_ranges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
