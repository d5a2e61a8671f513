/* The coat BSDF (optics/coat.h): Fresnel's known values, the white furnace
 * between its bounds, the sampler's weights against quadrature of eval, its
 * directions against its pdf (chi-square), and reciprocity. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "common/rng.h"
#include "optics/coat.h"
#include "tests/chi_square.h"

static plm_bsdf bsdf; /* 50 KiB: not on the stack */

static vec3 from_angles(double theta, double phi)
{
    return v3(sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
}

static void prepare(double albedo, double alpha, double theta_o)
{
    plm_coat c = {rgb_gray(albedo), alpha, 1.5};
    plm_coat_bsdf(&c, v3(0, 0, 1), from_angles(theta_o, 0.3), &bsdf);
}

/* Normal incidence on glass reflects ((n - 1) / (n + 1))^2; grazing reflects all. */
static void fresnel_known_values(void **state)
{
    (void)state;
    assert_double_near(plm_fresnel_dielectric(1.0, 1.5), 0.04, 1e-15);
    assert_double_near(plm_fresnel_dielectric(0.0, 1.5), 1.0, 1e-15);
    assert_double_near(plm_fresnel_dielectric(1.0, 1.33), pow(0.33 / 2.33, 2.0), 1e-15);
}

/* The cosine-weighted hemispherical mean of F (midpoint rule, 10^5 steps). */
static double fresnel_mean(double eta)
{
    const int n = 100000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        double mu = (i + 0.5) / n;
        sum += plm_fresnel_dielectric(mu, eta) * mu;
    }
    return 2.0 * sum / n;
}

/* The albedo by the sampler's weights: mean and standard error. */
static void sampled_albedo(int n, uint64_t seed, double *mean, double *se)
{
    plm_rng rng;
    plm_rng_seed(&rng, seed, 3);
    double s = 0.0, s2 = 0.0;
    for (int i = 0; i < n; ++i) {
        plm_bsdf_sample_rec r;
        double u0 = plm_rng_uniform(&rng), u1 = plm_rng_uniform(&rng), u2 = plm_rng_uniform(&rng);
        double w = plm_bsdf_sample(&bsdf, u0, u1, u2, &r) ? r.weight.g : 0.0;
        s += w, s2 += w * w;
    }
    *mean = s / n;
    *se = sqrt(fmax(0.0, s2 / n - *mean * *mean) / n);
}

/* White furnace: with a white base the coat neither makes light nor loses
 * more than the coat's Fresnel reflection can explain. The base alone
 * returns (1 - F(cos_o)) (1 - mean F), so that is a lower bound; 1 the upper. */
static void white_furnace_between_bounds(void **state)
{
    (void)state;
    const double alphas[] = {0.05, 0.3, 0.8}, thetas[] = {0.0, 30.0, 60.0, 80.0};
    double fbar = fresnel_mean(1.5);
    for (int a = 0; a < 3; ++a)
        for (int t = 0; t < 4; ++t) {
            double theta = plm_radians(thetas[t]), mean, se;
            prepare(1.0, alphas[a], theta);
            sampled_albedo(200000, 11 + (uint64_t)(4 * a + t), &mean, &se);
            double lower = (1.0 - plm_fresnel_dielectric(cos(theta), 1.5)) * (1.0 - fbar);
            fprintf(stderr, "alpha %.2f theta %2.0f: albedo %.4f +- %.4f (lower bound %.4f)\n", alphas[a],
                    thetas[t], mean, se, lower);
            assert_true(mean <= 1.0 + 4.0 * se);
            assert_true(mean >= lower - 4.0 * se);
        }
}

/* A smooth coat over black at normal incidence reflects F(1) = 0.04: GGX at
 * alpha 0.05 loses under 1% to masking and sees F within 1% of F(1), so
 * within 5% of 0.04. */
static void smooth_coat_reflects_fresnel(void **state)
{
    (void)state;
    double mean, se;
    prepare(0.0, 0.05, 0.0);
    sampled_albedo(200000, 5, &mean, &se);
    assert_double_near(mean, 0.04, 0.002);
}

/* The sampler's weights and quadrature of eval (uniform directions) estimate
 * one integral: they agree within 4 combined standard errors. */
static void weights_agree_with_eval(void **state)
{
    (void)state;
    const double alphas[] = {0.1, 0.5};
    for (int a = 0; a < 2; ++a) {
        prepare(0.7, alphas[a], plm_radians(50.0));
        double mean, se;
        sampled_albedo(200000, 21 + (uint64_t)a, &mean, &se);
        plm_rng rng;
        plm_rng_seed(&rng, 31 + (uint64_t)a, 3);
        const int n = 400000;
        double s = 0.0, s2 = 0.0;
        for (int i = 0; i < n; ++i) {
            double z = plm_rng_uniform(&rng), phi = PLM_TWO_PI * plm_rng_uniform(&rng);
            double v = PLM_TWO_PI * plm_bsdf_eval(&bsdf, from_angles(acos(z), phi)).g;
            s += v, s2 += v * v;
        }
        double q = s / n, qse = sqrt(fmax(0.0, s2 / n - q * q) / n);
        fprintf(stderr, "alpha %.1f: sampled %.4f +- %.4f, quadrature %.4f +- %.4f\n", alphas[a], mean, se, q, qse);
        assert_true(fabs(mean - q) <= 4.0 * sqrt(se * se + qse * qse));
    }
}

/* Sampled directions follow pdf (chi-square over theta x phi cells, pdf
 * integrated by 8 x 8 midpoints per cell); each sample's pdf and weight
 * match pdf() and eval() / pdf(). */
static void samples_follow_pdf(void **state)
{
    (void)state;
    enum { T = 32, P = 64, S = 8, N = 300000 };
    static double observed[T * P], expected[T * P];
    const double alphas[] = {0.05, 0.3};
    for (int a = 0; a < 2; ++a) {
        prepare(0.5, alphas[a], plm_radians(40.0));
        memset(observed, 0, sizeof observed);
        for (int ct = 0; ct < T; ++ct)
            for (int cp = 0; cp < P; ++cp) {
                double sum = 0.0;
                for (int st = 0; st < S; ++st)
                    for (int sp = 0; sp < S; ++sp) {
                        double th = (ct + (st + 0.5) / S) / T * 0.5 * PLM_PI;
                        double ph = (cp + (sp + 0.5) / S) / P * PLM_TWO_PI - PLM_PI;
                        double solid = sin(th) * (0.5 * PLM_PI / (T * S)) * (PLM_TWO_PI / (P * S));
                        sum += plm_bsdf_pdf(&bsdf, from_angles(th, ph)) * solid;
                    }
                expected[ct * P + cp] = N * sum;
            }
        plm_rng rng;
        plm_rng_seed(&rng, 41 + (uint64_t)a, 3);
        for (int i = 0; i < N; ++i) {
            plm_bsdf_sample_rec r;
            double u0 = plm_rng_uniform(&rng), u1 = plm_rng_uniform(&rng), u2 = plm_rng_uniform(&rng);
            if (!plm_bsdf_sample(&bsdf, u0, u1, u2, &r))
                continue;
            double pdf = plm_bsdf_pdf(&bsdf, r.wi);
            assert_double_near(r.pdf, pdf, 1e-9 * pdf);
            assert_double_near(r.weight.r, plm_bsdf_eval(&bsdf, r.wi).r / pdf, 1e-9 * r.weight.r + 1e-15);
            double th = acos(plm_clamp(r.wi.z, -1.0, 1.0)), ph = atan2(r.wi.y, r.wi.x);
            int ct = (int)(th / (0.5 * PLM_PI) * T), cp = (int)((ph + PLM_PI) / PLM_TWO_PI * P);
            observed[(ct < T ? ct : T - 1) * P + (cp < P ? cp : P - 1)] += 1.0;
        }
        double pv = chi_square_test(observed, expected, T * P);
        fprintf(stderr, "alpha %.2f: chi-square p-value %.4f\n", alphas[a], pv);
        assert_true(pv > chi_square_sidak(0.01, 2));
    }
}

/* f(o, i) = f(i, o): eval / cos_i is symmetric. */
static void reciprocal(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 51, 3);
    plm_coat c = {rgb_make(0.8, 0.4, 0.1), 0.25, 1.5};
    static plm_bsdf back;
    for (int k = 0; k < 1000; ++k) {
        vec3 o = from_angles(acos(plm_rng_uniform(&rng)), PLM_TWO_PI * plm_rng_uniform(&rng));
        vec3 i = from_angles(acos(plm_rng_uniform(&rng)), PLM_TWO_PI * plm_rng_uniform(&rng));
        if (o.z < 1e-3 || i.z < 1e-3)
            continue;
        plm_coat_bsdf(&c, v3(0, 0, 1), o, &bsdf);
        plm_coat_bsdf(&c, v3(0, 0, 1), i, &back);
        rgb a = plm_bsdf_eval(&bsdf, i), b = plm_bsdf_eval(&back, o);
        assert_double_near(a.r / i.z, b.r / o.z, 1e-9 * (a.r / i.z));
        assert_double_near(a.b / i.z, b.b / o.z, 1e-9 * (a.b / i.z));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fresnel_known_values),   cmocka_unit_test(white_furnace_between_bounds),
        cmocka_unit_test(smooth_coat_reflects_fresnel), cmocka_unit_test(weights_agree_with_eval),
        cmocka_unit_test(samples_follow_pdf),     cmocka_unit_test(reciprocal),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
