/* The fiber tracer against closed forms, and its energy bookkeeping. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>

#include "render/fiber.h"

/* Unpolarised Fresnel reflectance written out from the textbook amplitudes,
 * independently of the tracer's (eta = n_t / n_i). */
static double fresnel_reference(double cos_i, double eta)
{
    double sin_t = sqrt(1.0 - cos_i * cos_i) / eta;
    if (sin_t >= 1.0)
        return 1.0;
    double cos_t = sqrt(1.0 - sin_t * sin_t);
    double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    double rp = (cos_t - eta * cos_i) / (cos_t + eta * cos_i);
    return 0.5 * (rs * rs + rp * rp);
}

static double angle_difference(double a, double b) { return remainder(a - b, PLM_TWO_PI); }

static void assert_near(double got, double want, double tol, const char *what, int lobe)
{
    if (!(fabs(got - want) <= tol)) {
        fprintf(stderr, "%s of lobe %d: got %.9f, want %.9f\n", what, lobe, got, want);
        fail();
    }
}

/* A smooth circular fiber without medulla has the classic lobes (Marschner et
 * al. 2003; d'Eon et al. 2011): p internal paths leave at azimuth
 * 2p gamma_t - 2 gamma_o + p pi from the view azimuth, at theta = -theta_o,
 * with A_0 = f, A_p = (1 - f)^2 T^p f^(p-1), T = exp(-sigma_a 2 cos gamma_t / cos theta_t). */
static void circular_fiber_matches_closed_form(void **state)
{
    (void)state;
    plm_fiber_params p;
    plm_fiber_params_default(&p);
    p.eta = 1.53;
    p.sigma_a = rgb_make(0.133, 1.967, 2.1);
    p.lobes = 6;
    const double thetas[] = {0.0, 30.0, -45.0, 70.0}, phis[] = {0.0, 50.0, -120.0, 180.0};
    const double hs[] = {-0.95, -0.5, 0.0, 0.3, 0.8, 0.99};
    int checked = 0;
    for (int it = 0; it < 4; ++it)
        for (int ip = 0; ip < 4; ++ip)
            for (int ih = 0; ih < 6; ++ih) {
                double theta_o = plm_radians(thetas[it]), phi_o = plm_radians(phis[ip]), h = hs[ih];
                vec3 wo = plm_fiber_direction(theta_o, phi_o);
                plm_fiber_lobe lobes[6];
                int n = plm_fiber_trace(&p, wo, h, NULL, lobes);
                assert_int_equal(n, 6);
                double gamma_o = asin(h);
                double sin_theta_t = sin(theta_o) / p.eta, cos_theta_t = sqrt(1.0 - sin_theta_t * sin_theta_t);
                double eta_perp = sqrt(p.eta * p.eta - plm_sqr(sin(theta_o))) / cos(theta_o); /* Bravais */
                double gamma_t = asin(h / eta_perp);
                double f = fresnel_reference(cos(theta_o) * cos(gamma_o), p.eta);
                double sa[3] = {p.sigma_a.r, p.sigma_a.g, p.sigma_a.b};
                for (int k = 0; k < n; ++k) {
                    double phi_want = phi_o + 2.0 * k * gamma_t - 2.0 * gamma_o + k * PLM_PI;
                    double theta_got = asin(lobes[k].dir.z), phi_got = atan2(lobes[k].dir.y, lobes[k].dir.x);
                    assert_near(v3_length(lobes[k].dir), 1.0, 1e-12, "direction length", k);
                    assert_near(theta_got, -theta_o, 1e-4, "theta", k);
                    assert_near(angle_difference(phi_got, phi_want), 0.0, 1e-4, "phi", k);
                    double got[3] = {lobes[k].throughput.r, lobes[k].throughput.g, lobes[k].throughput.b};
                    for (int c = 0; c < 3; ++c) {
                        double T = exp(-sa[c] * 2.0 * cos(gamma_t) / cos_theta_t);
                        double want = k == 0 ? f : plm_sqr(1.0 - f) * pow(T, k) * pow(f, k - 1);
                        assert_near(got[c], want, 1e-4 * fmax(want, 1e-3), "throughput", k);
                    }
                    ++checked;
                }
            }
    assert_int_equal(checked, 4 * 4 * 6 * 6);
}

/* On an elliptical fiber seen along an axis, the centre ray (h = 0) meets the
 * vertex head-on: it reflects straight back and crosses the full axis (2 or 2e)
 * to leave straight through, longitudinally refracted by Snell's law. */
static void elliptical_fiber_vertex_rays(void **state)
{
    (void)state;
    plm_fiber_params p;
    plm_fiber_params_default(&p);
    p.eccentricity = 1.6;
    p.eta = 1.53;
    p.sigma_a = rgb_gray(0.7);
    p.lobes = 2;
    for (int axis = 0; axis < 2; ++axis) {
        double theta_o = plm_radians(35.0), phi_o = axis ? 0.5 * PLM_PI : 0.0, chord = axis ? 2.0 * 1.6 : 2.0;
        vec3 wo = plm_fiber_direction(theta_o, phi_o);
        plm_fiber_lobe lobes[2];
        assert_int_equal(plm_fiber_trace(&p, wo, 0.0, NULL, lobes), 2);
        double f = fresnel_reference(cos(theta_o), p.eta);
        double cos_theta_t = sqrt(1.0 - plm_sqr(sin(theta_o) / p.eta));
        assert_near(angle_difference(atan2(lobes[0].dir.y, lobes[0].dir.x), phi_o), 0.0, 1e-9, "R phi", axis);
        assert_near(angle_difference(atan2(lobes[1].dir.y, lobes[1].dir.x), phi_o + PLM_PI), 0.0, 1e-9,
                    "TT phi", axis);
        assert_near(lobes[0].throughput.r, f, 1e-12, "R throughput", axis);
        assert_near(lobes[1].throughput.g, plm_sqr(1.0 - f) * exp(-0.7 * chord / cos_theta_t), 1e-12,
                    "TT throughput", axis);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(circular_fiber_matches_closed_form),
        cmocka_unit_test(elliptical_fiber_vertex_rays),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
