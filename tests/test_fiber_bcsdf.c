/* The fiber BCSDF's evaluation from lobe sets: white furnace, sampling
 * against pdf (chi-square), sample weights, reproducibility, and a sweep for
 * non-finite output. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <stdio.h>
#include <stdlib.h>

#include "optics/fiber.h"
#include "tests/assert_double.h"
#include "tests/fiber_stats.h"

/* A Fig. 7 fiber, checked valid. */
static plm_fiber_params figure7(int variant)
{
    plm_fiber_params p;
    plm_fiber_params_figure7(&p, variant);
    assert_int_equal(plm_fiber_params_validate(&p, NULL), PLM_OK);
    return p;
}

static double set_energy(const plm_fiber_lobe_set *set, int channel)
{
    double s = 0.0;
    for (int k = 0; k < set->count; ++k)
        s += channel == 0 ? set->throughput[k].r : channel == 1 ? set->throughput[k].g : set->throughput[k].b;
    return s;
}

/* With sigma_a = 0 the integral of eval cos over the sphere is the lobe
 * energy of the set (1 minus what stayed inside), for any roughness,
 * eccentricity and direction; and the pdf integrates to 1. */
static void white_furnace(void **state)
{
    (void)state;
    const double betas[] = {0.05, 0.13, 0.4, 1.2};
    const double eccentricities[] = {1.0, 1.6, 3.0};
    const double thetas[] = {10.0, -80.0};
    plm_rng rng;
    plm_rng_seed(&rng, 21, 0);
    for (int b = 0; b < 4; ++b)
        for (int e = 0; e < 3; ++e)
            for (int t = 0; t < 2; ++t) {
                plm_fiber_params p = figure7(e == 1 ? 3 : 0);
                p.sigma_a = rgb_gray(0.0);
                p.eccentricity = eccentricities[e];
                p.beta_m = betas[b];
                p.beta_n = betas[(b + t) % 4];
                vec3 wo = plm_fiber_direction(plm_radians(thetas[t]), plm_radians(30.0 * t));
                plm_fiber_lobe_set set;
                plm_fiber_prepare(&p, wo, -1.0, 1.0, &rng, &set);
                double energy = set_energy(&set, 0);
                assert_true(energy > 0.5 && energy <= 1.0 + 1e-12);
                plm_fiber_bcsdf b = bcsdf_of_set(&p, &set);
                double integral = integrate_bcsdf(&b, 0, -0.5 * PLM_PI, 0.5 * PLM_PI, -PLM_PI, PLM_PI, 240, 480);
                double pdf_integral =
                    integrate_bcsdf(&b, 3, -0.5 * PLM_PI, 0.5 * PLM_PI, -PLM_PI, PLM_PI, 240, 480);
                if (fabs(integral - energy) > 1e-3 * energy || fabs(pdf_integral - 1.0) > 1e-3) {
                    fprintf(stderr, "beta %g/%g e %g theta %g: integral %.6f energy %.6f pdf %.6f\n", p.beta_m,
                            p.beta_n, p.eccentricity, thetas[t], integral, energy, pdf_integral);
                    fail();
                }
            }
}

/* The four Fig. 7 fibers at their incidence, and two rough, very elliptical
 * ones at other directions (slow_fiber.c runs many more). */
static void sampling_matches_pdf(void **state)
{
    (void)state;
    enum { N_TESTS = 6 };
    const double threshold = chi_square_sidak(0.01, N_TESTS);
    plm_rng rng;
    plm_rng_seed(&rng, 77, 0);
    for (int t = 0; t < N_TESTS; ++t) {
        plm_fiber_params p = figure7(t % 4);
        if (t >= 4) { /* rough and very elliptical */
            p.beta_m = 0.6;
            p.beta_n = 0.9;
            p.eccentricity = 3.0;
        }
        vec3 wo = plm_fiber_direction(plm_radians(t == 5 ? -75.0 : 45.0), plm_radians(20.0 * t));
        plm_fiber_lobe_set set;
        plm_fiber_prepare(&p, wo, -1.0, 1.0, &rng, &set);
        plm_fiber_bcsdf b = bcsdf_of_set(&p, &set);
        double pv = bcsdf_chi_square(&b, &rng, 400000);
        fprintf(stderr, "chi-square test %d: %d lobes, p-value %.4f (threshold %.5f)\n", t, set.count, pv,
                threshold);
        assert_true(pv > threshold);
    }
}

/* The same seed traces the same lobe sets (h and every lobe), and eval and
 * pdf are functions of the set: equal where they are not zero (at a lobe's
 * own direction). Another seed traces other sets, so the agreement is not
 * that of a tracer that ignores its random numbers. */
static void lobe_sets_are_reproducible(void **state)
{
    (void)state;
    plm_fiber_params p = figure7(3);
    vec3 wo = plm_fiber_direction(0.3, 1.0);
    plm_fiber_lobe_set a, b, c;
    plm_rng ra, rb, rc;
    plm_rng_seed(&ra, 4, 2);
    plm_rng_seed(&rb, 4, 2);
    plm_rng_seed(&rc, 5, 2);
    int differ = 0;
    for (int i = 0; i < 100; ++i) {
        plm_fiber_prepare(&p, wo, -0.5, 0.7, &ra, &a);
        plm_fiber_prepare(&p, wo, -0.5, 0.7, &rb, &b);
        plm_fiber_prepare(&p, wo, -0.5, 0.7, &rc, &c);
        assert_true(a.h >= -0.5 && a.h <= 0.7);
        assert_true(a.h == b.h);
        assert_true(a.count > 0);
        assert_int_equal(a.count, b.count);
        for (int k = 0; k < a.count; ++k) {
            assert_true(a.theta[k] == b.theta[k] && a.phi[k] == b.phi[k]);
            assert_memory_equal(&a.throughput[k], &b.throughput[k], sizeof a.throughput[k]);
        }
        vec3 wi = plm_fiber_direction(a.theta[0], a.phi[0]);
        rgb fa = plm_fiber_eval(&p, &a, wi), fb = plm_fiber_eval(&p, &b, wi);
        assert_true(fa.g > 0.0);
        assert_true(fa.r == fb.r && fa.g == fb.g && fa.b == fb.b);
        assert_true(plm_fiber_pdf(&p, &a, wi) == plm_fiber_pdf(&p, &b, wi));
        differ += a.h != c.h;
    }
    assert_true(differ > 90);
}

/* Random valid parameters, directions (poles and grazing included), entry
 * ranges and sample numbers (0 and 1 - eps included): nothing non-finite or
 * negative comes out. */
static void no_non_finite_output(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 99, 0);
    int queries = 0;
    const double edge_u[] = {0.0, 0x1.fffffffffffffp-1, 0.5};
    {   /* non-finite inputs give empty or zero results, never NaN */
        plm_fiber_params p = figure7(3);
        plm_fiber_lobe_set set;
        plm_fiber_prepare(&p, plm_fiber_direction(0.3, 0.2), NAN, 1.0, &rng, &set);
        assert_int_equal(set.count, 0);
        plm_fiber_prepare(&p, v3(NAN, 0.0, 0.0), -1.0, 1.0, &rng, &set);
        assert_int_equal(set.count, 0);
        plm_fiber_prepare(&p, plm_fiber_direction(0.3, 0.2), -1.0, 1.0, &rng, &set);
        rgb f = plm_fiber_eval(&p, &set, v3(NAN, 0.0, 1.0));
        assert_true(rgb_is_black(f) && plm_fiber_pdf(&p, &set, v3(0.0, NAN, 0.0)) == 0.0);
        plm_fiber_sample_rec rec;
        assert_int_equal(plm_fiber_sample(&p, &set, NAN, 0.5, 0.5, &rec) && !isfinite(rec.pdf), 0);
    }
    while (queries < 20000) {
        plm_fiber_params p;
        plm_fiber_params_default(&p);
        p.eccentricity = 0.05 + 8.0 * plm_rng_uniform(&rng);
        p.eta = 1.0 + 2.0 * plm_rng_uniform(&rng);
        p.sigma_a = rgb_make(40.0 * plm_rng_uniform(&rng), plm_rng_uniform(&rng), 0.0);
        p.beta_m = plm_radians(0.5 + 89.5 * plm_rng_uniform(&rng));
        p.beta_n = plm_radians(0.5 + 89.5 * plm_rng_uniform(&rng));
        p.lobes = 1 + (int)(plm_rng_uniform(&rng) * PLM_FIBER_SET_MAX_LOBES);
        if (plm_rng_uniform(&rng) < 0.6) {
            p.medulla_a = 0.01 + 0.9 * plm_rng_uniform(&rng);
            p.medulla_b = 0.01 + 0.9 * p.eccentricity * plm_rng_uniform(&rng);
            p.medulla_ca = plm_rng_uniform(&rng) - 0.5;
            p.medulla_cb = p.eccentricity * (plm_rng_uniform(&rng) - 0.5);
            p.medulla_reflectance = rgb_make(plm_rng_uniform(&rng), 1.0, 0.0);
        }
        if (plm_fiber_params_validate(&p, NULL) != PLM_OK)
            continue;
        for (int q = 0; q < 20; ++q, ++queries) {
            double theta_o = q == 0 ? 0.5 * PLM_PI : q == 1 ? -0.5 * PLM_PI + 1e-9 : asin(2.0 * plm_rng_uniform(&rng) - 1.0);
            vec3 wo = plm_fiber_direction(theta_o, PLM_TWO_PI * plm_rng_uniform(&rng));
            double h0 = q == 2 ? 1.0 : 2.0 * plm_rng_uniform(&rng) - 1.0, h1 = q == 3 ? h0 : 1.0;
            plm_fiber_lobe_set set;
            plm_fiber_prepare(&p, wo, fmin(h0, h1), fmax(h0, h1), &rng, &set);
            for (int k = 0; k < set.count; ++k)
                assert_true(rgb_is_finite(set.throughput[k]) && isfinite(set.theta[k]) && isfinite(set.gm_scale[k]));
            double theta_i = q == 4 ? 0.5 * PLM_PI : asin(2.0 * plm_rng_uniform(&rng) - 1.0);
            vec3 wi = plm_fiber_direction(theta_i, PLM_TWO_PI * plm_rng_uniform(&rng));
            rgb f = plm_fiber_eval(&p, &set, wi);
            double pdf = plm_fiber_pdf(&p, &set, wi);
            assert_true(rgb_is_finite(f) && f.r >= 0.0 && f.g >= 0.0 && f.b >= 0.0);
            assert_true(isfinite(pdf) && pdf >= 0.0);
            plm_fiber_sample_rec rec;
            double u0 = q < 3 ? edge_u[q] : plm_rng_uniform(&rng);
            double u1 = q < 3 ? edge_u[(q + 1) % 3] : plm_rng_uniform(&rng);
            double u2 = q < 3 ? edge_u[(q + 2) % 3] : plm_rng_uniform(&rng);
            if (plm_fiber_sample(&p, &set, u0, u1, u2, &rec)) {
                assert_true(rgb_is_finite(rec.weight) && rec.weight.r >= 0.0);
                assert_true(isfinite(rec.pdf) && rec.pdf > 0.0);
                assert_true(fabs(v3_length(rec.wi) - 1.0) < 1e-9);
            }
        }
    }
}

/* The separable detectors the plots use are the ones eval uses:
 * eval cos^2 = sum_k A_k G_M G_N, at any roughness (wrapped G_N included). */
static void separable_detectors_match_eval(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 8, 0);
    for (int i = 0; i < 2000; ++i) {
        plm_fiber_params p = figure7(i % 4);
        p.beta_n = i % 3 == 0 ? 1.4 : 0.12;
        vec3 wo = plm_fiber_direction(asin(2.0 * plm_rng_uniform(&rng) - 1.0), PLM_TWO_PI * plm_rng_uniform(&rng));
        plm_fiber_lobe_set set;
        plm_fiber_prepare(&p, wo, -1.0, 1.0, &rng, &set);
        double theta = asin(2.0 * plm_rng_uniform(&rng) - 1.0), phi = PLM_TWO_PI * (plm_rng_uniform(&rng) - 0.5);
        rgb sum = rgb_gray(0.0);
        for (int k = 0; k < set.count; ++k)
            sum = rgb_add(sum, rgb_scale(set.throughput[k], plm_fiber_lobe_gm(&p, &set, k, theta) *
                                                                plm_fiber_lobe_gn(&p, &set, k, phi)));
        double c2 = plm_sqr(cos(theta));
        rgb f = plm_fiber_eval(&p, &set, plm_fiber_direction(theta, phi));
        assert_true(fabs(f.g * c2 - sum.g) <= 1e-12 * sum.g + 1e-300);
    }
}

/* pi in long double, for references a few ulp of a double apart. */
static const long double PI_L = 3.14159265358979323846264338327950288L;

/* The standard normal's CDF at x in long double, from the upper tail
 * where x > 0 (1 - CDF) so that no digits cancel: CDF(x) if upper is 0. */
static long double normal_tail(long double x, int upper)
{
    return 0.5L * erfcl((upper ? x : -x) / sqrtl(2.0L));
}

/* The samplers' inverse CDFs are exact to a few ulp: the standard normal's
 * quantile (G_N's sampler and the moving lobes') against its root in long
 * double, found by Newton steps on erfcl from the same u (the u the sampler
 * sees: 2u - 1 rounded as it rounds it); G_M's sampler against the CDF of the
 * truncated Gaussian in long double, for narrow and wide detectors about
 * several Theta. u covers [0, 1) evenly and both tails down to 1e-16. */
static void samplers_invert_their_cdfs(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 5, 0);
    double worst = 0.0;
    for (int i = 0; i < 200000; ++i) {
        double r = plm_rng_uniform(&rng), u = i % 3 == 0 ? r : pow(10.0, -16.0 * r);
        u = i % 3 == 2 ? 1.0 - u : u;
        double y = plm_clamp(2.0 * u - 1.0, -1.0 + DBL_EPSILON, 1.0 - DBL_EPSILON);
        int upper = y > 0.0;
        long double goal = upper ? 0.5L * (1.0L - y) : 0.5L * (1.0L + y); /* the tail the sampler aims at */
        double x = plm_fiber_normal_quantile(u);
        long double root = x;
        for (int k = 0; k < 3; ++k) /* the density at the root: exp(-x^2/2) / sqrt(2 pi) */
            root -= (upper ? -1.0L : 1.0L) * (normal_tail(root, upper) - goal) /
                    (expl(-0.5L * root * root) / sqrtl(2.0L * PI_L));
        double ulp = nextafter(fabs((double)root), INFINITY) - fabs((double)root);
        worst = fmax(worst, (double)(fabsl(x - root) / ulp));
    }
    fprintf(stderr, "normal quantile: within %.2f ulp of its root\n", worst);
    assert_true(worst <= 3.0);
    const double betas[] = {0.02, 0.13, 1.2}, thetas[] = {0.0, -0.7, 1.45};
    for (int b = 0; b < 3; ++b)
        for (int t = 0; t < 3; ++t) {
            plm_fiber_gm_detector g;
            plm_fiber_gm_detector_about(betas[b], thetas[t], &g);
            long double s = sqrtl(2.0L) * betas[b], lo = erfl((-0.5L * PI_L - thetas[t]) / s);
            long double hi = erfl((0.5L * PI_L - thetas[t]) / s);
            for (int i = 0; i < 2000; ++i) {
                double u = (i + plm_rng_uniform(&rng)) / 2000.0;
                double theta = plm_fiber_sample_gm(&g, u);
                long double cdf = (erfl((theta - thetas[t]) / s) - lo) / (hi - lo);
                /* u maps to erf's range to a few ulp of 1, and theta, Theta plus the
                 * scaled quantile, rounds to a few of its ulp: times the density */
                double big = fmax(fabs(theta), fabs(thetas[t])), ulp = nextafter(big, INFINITY) - big;
                double density =
                    (double)(2.0L / ((hi - lo) * s * sqrtl(PI_L)) * expl(-plm_sqr((theta - thetas[t]) / (double)s)));
                assert_double_near((double)cdf, u, 4.0 * DBL_EPSILON + 4.0 * ulp * density);
            }
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(white_furnace),
        cmocka_unit_test(sampling_matches_pdf),
        cmocka_unit_test(lobe_sets_are_reproducible),
        cmocka_unit_test(separable_detectors_match_eval),
        cmocka_unit_test(no_non_finite_output),
        cmocka_unit_test(samplers_invert_their_cdfs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
