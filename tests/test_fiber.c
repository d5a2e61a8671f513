/* The fiber tracer against closed forms, and its energy bookkeeping. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "optics/fiber.h"

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

/* The tracer's Fresnel term: the textbook amplitudes from either side,
 * reciprocity (the same reflectance from outside at theta_i and from inside at
 * the refracted theta_t), and total internal reflection beyond the critical
 * angle, approached continuously. */
static void fresnel_both_ways_with_total_internal_reflection(void **state)
{
    (void)state;
    const double eta = 1.53, critical_sin = 1.0 / eta;
    for (int i = 0; i <= 1000; ++i) {
        double cos_i = i / 1000.0, sin_i = sqrt(1.0 - cos_i * cos_i);
        assert_near(plm_fiber_fresnel(cos_i, eta), fresnel_reference(cos_i, eta), 1e-14, "outside", i);
        double sin_t = sin_i / eta, cos_t = sqrt(1.0 - sin_t * sin_t);
        assert_near(plm_fiber_fresnel(cos_t, 1.0 / eta), plm_fiber_fresnel(cos_i, eta), 1e-12, "reciprocity", i);
        if (sin_i > critical_sin)
            assert_true(plm_fiber_fresnel(cos_i, 1.0 / eta) == 1.0);
        else
            assert_near(plm_fiber_fresnel(cos_i, 1.0 / eta), fresnel_reference(cos_i, 1.0 / eta), 1e-10, "inside", i);
    }
    double cos_critical = sqrt(1.0 - critical_sin * critical_sin);
    assert_true(plm_fiber_fresnel(cos_critical + 1e-9, 1.0 / eta) > 0.999);
}

/* A Fig. 7 fiber's cross-section, clear, with the given
 * eccentricity and medulla reflectance. */
static plm_fiber_params fiber_variant(int variant, double eccentricity, rgb medulla_reflectance)
{
    plm_fiber_params p;
    plm_fiber_params_figure7(&p, variant);
    p.sigma_a = rgb_gray(0.0);
    p.eccentricity = eccentricity;
    p.medulla_reflectance = medulla_reflectance;
    assert_int_equal(plm_fiber_params_validate(&p, NULL), PLM_OK);
    return p;
}

/* A random view direction (uniform on the sphere) and entry offset. */
static void random_query(plm_rng *rng, vec3 *wo, double *h)
{
    double z = 2.0 * plm_rng_uniform(rng) - 1.0, phi = PLM_TWO_PI * plm_rng_uniform(rng);
    *wo = plm_fiber_direction(asin(z), phi);
    *h = 2.0 * plm_rng_uniform(rng) - 1.0;
}

/* Traces query i of a reproducible random sequence: the same (seed, i) gives
 * the same direction, offset and medulla bounces whatever the fiber's
 * absorption, medulla albedo or lobe count. */
static int trace_query(const plm_fiber_params *p, uint64_t seed, int i, plm_fiber_lobe *lobes, int max_lobes)
{
    plm_rng rng;
    plm_rng_seed(&rng, seed, (uint64_t)i);
    vec3 wo;
    double h;
    random_query(&rng, &wo, &h);
    return plm_fiber_trace_n(p, wo, h, &rng, lobes, max_lobes, NULL);
}

static double lobe_sum(const plm_fiber_lobe *lobes, int n, int channel)
{
    double s = 0.0;
    for (int k = 0; k < n; ++k)
        s += channel == 0 ? lobes[k].throughput.r : channel == 1 ? lobes[k].throughput.g : lobes[k].throughput.b;
    return s;
}

/* Finite, in [0, 1], unit directions; lobes after the first are never black
 * without absorption (a total internal reflection stores nothing), unless the
 * path's weight has underflowed after hundreds of lobes. */
static void assert_valid_lobes(const plm_fiber_lobe *lobes, int n)
{
    for (int k = 0; k < n; ++k) {
        rgb t = lobes[k].throughput;
        assert_true(rgb_is_finite(t));
        assert_true(t.r >= 0.0 && t.g >= 0.0 && t.b >= 0.0 && rgb_max(t) <= 1.0);
        assert_true(k == 0 || t.r > 0.0 || lobes[k - 1].throughput.r < 1e-300);
        assert_true(fabs(v3_length(lobes[k].dir) - 1.0) < 1e-9);
    }
}

/* Without absorption nothing is lost: the lobes and what is still inside
 * after the last one add up to 1 exactly, for any number of lobes. */
static void energy_is_conserved_without_absorption(void **state)
{
    (void)state;
    static plm_fiber_lobe lobes[PLM_FIBER_MAX_LOBES];
    const int counts[] = {1, 2, 5, 40};
    for (int variant = 0; variant < 4; ++variant) {
        plm_fiber_params p = fiber_variant(variant, variant == 0 ? 1.0 : 1.6, rgb_gray(1.0));
        plm_rng rng;
        plm_rng_seed(&rng, 11, (uint64_t)variant);
        for (int i = 0; i < 4000; ++i) {
            vec3 wo;
            double h;
            random_query(&rng, &wo, &h);
            rgb inside;
            int n = plm_fiber_trace_n(&p, wo, h, &rng, lobes, counts[i % 4], &inside);
            assert_true(n >= 1 && n <= counts[i % 4]);
            assert_valid_lobes(lobes, n);
            assert_true(rgb_is_finite(inside) && inside.r >= 0.0 && inside.r <= 1.0);
            double total = lobe_sum(lobes, n, 0) + inside.r;
            if (fabs(total - 1.0) > 1e-9) {
                fprintf(stderr, "variant %d query %d: lobes + inside = %.15f\n", variant, i, total);
                fail();
            }
        }
    }
}

/* h = +-1 are the silhouettes (docs/fiber.md): light grazes the cortex there and
 * is reflected whole, whatever the eccentricity. */
static void silhouettes_are_grazing(void **state)
{
    (void)state;
    const double eccentricities[] = {0.3, 1.0, 1.6, 4.0};
    for (int e = 0; e < 4; ++e) {
        plm_fiber_params p = fiber_variant(1, eccentricities[e], rgb_gray(1.0));
        for (int j = 0; j < 24; ++j) {
            vec3 wo = plm_fiber_direction(plm_radians(-60.0 + 5.0 * j), plm_radians(15.0 * j));
            for (int side = -1; side <= 1; side += 2) {
                plm_fiber_lobe lobes[5];
                assert_true(plm_fiber_trace(&p, wo, side, NULL, lobes) >= 1);
                assert_true(lobes[0].throughput.r > 1.0 - 1e-5);
            }
        }
    }
}

/* Mean lobe energy over random (direction, h) with and without absorption-free
 * white off-centre medulla: five lobes hold >= 97% and are within 1% of 1000
 * lobes (the paper's Fig. 13). The same random numbers drive both counts, so
 * the first five lobes are the same paths. */
static void five_lobes_hold_the_energy(void **state)
{
    (void)state;
    static plm_fiber_lobe lobes[PLM_FIBER_MAX_LOBES];
    const int variants[] = {1, 3};
    for (int v = 0; v < 2; ++v) {
        plm_fiber_params p = fiber_variant(variants[v], 1.6, rgb_gray(1.0));
        double sum5 = 0.0, sum1000 = 0.0;
        const int n_queries = 8000;
        for (int i = 0; i < n_queries; ++i) {
            double e[2];
            for (int run = 0; run < 2; ++run) {
                int n = trace_query(&p, 5, i, lobes, run ? 1000 : 5);
                assert_valid_lobes(lobes, n);
                e[run] = lobe_sum(lobes, n, 0);
            }
            assert_true(e[0] <= e[1] + 1e-12 && e[1] <= 1.0 + 1e-12);
            sum5 += e[0];
            sum1000 += e[1];
        }
        double mean5 = sum5 / n_queries, mean1000 = sum1000 / n_queries;
        fprintf(stderr, "variant %d: mean energy 5 lobes %.5f, 1000 lobes %.5f\n", variants[v], mean5, mean1000);
        assert_true(mean5 >= 0.97);
        assert_true((mean1000 - mean5) / mean1000 < 0.01);
    }
}

/* Paths do not depend on sigma_a, so with the same random numbers every
 * query's energy falls as absorption grows, and the mean falls strictly. */
static void absorption_only_darkens(void **state)
{
    (void)state;
    const double scales[] = {0.0, 0.05, 0.2, 0.5, 1.0, 3.0, 10.0};
    const rgb base = {0.133, 1.967, 2.1};
    plm_fiber_params p = fiber_variant(3, 1.6, rgb_gray(0.8));
    double previous_mean[3] = {INFINITY, INFINITY, INFINITY};
    double previous[500][3];
    for (int s = 0; s < 7; ++s) {
        p.sigma_a = rgb_scale(base, scales[s]);
        double mean[3] = {0, 0, 0};
        for (int i = 0; i < 500; ++i) {
            plm_fiber_lobe lobes[5];
            int n = trace_query(&p, 9, i, lobes, 5);
            for (int c = 0; c < 3; ++c) {
                double e = lobe_sum(lobes, n, c);
                if (s > 0)
                    assert_true(e <= previous[i][c] + 1e-15);
                previous[i][c] = e;
                mean[c] += e / 500;
            }
        }
        for (int c = 0; c < 3; ++c) {
            assert_true(mean[c] < previous_mean[c]);
            previous_mean[c] = mean[c];
        }
    }
}

/* A black medulla only removes light: each path is the medulla-free path up
 * to where it meets the medulla, and stops there; a white medulla only adds. */
static void black_medulla_only_removes_energy(void **state)
{
    (void)state;
    plm_fiber_params none = fiber_variant(1, 1.6, rgb_gray(0.0));
    plm_fiber_params black = fiber_variant(3, 1.6, rgb_gray(0.0));
    plm_fiber_params white = fiber_variant(3, 1.6, rgb_gray(1.0));
    none.sigma_a = black.sigma_a = white.sigma_a = rgb_make(0.133, 1.967, 2.1);
    int shortened = 0;
    for (int i = 0; i < 4000; ++i) {
        plm_fiber_lobe lobes_none[5], lobes_black[5], lobes_white[5];
        int n[3];
        const plm_fiber_params *ps[3] = {&none, &black, &white};
        plm_fiber_lobe *out[3] = {lobes_none, lobes_black, lobes_white};
        for (int k = 0; k < 3; ++k)
            n[k] = trace_query(ps[k], 3, i, out[k], 5);
        assert_true(n[1] <= n[0]);
        for (int k = 0; k < n[1]; ++k) {
            assert_true(v3_length(v3_sub(lobes_black[k].dir, lobes_none[k].dir)) < 1e-12);
            assert_true(rgb_is_black(rgb_sub(lobes_black[k].throughput, lobes_none[k].throughput)));
            assert_true(rgb_is_black(rgb_sub(lobes_black[k].throughput, lobes_white[k].throughput)));
        }
        for (int c = 0; c < 3; ++c) {
            assert_true(lobe_sum(lobes_black, n[1], c) <= lobe_sum(lobes_none, n[0], c));
            assert_true(lobe_sum(lobes_black, n[1], c) <= lobe_sum(lobes_white, n[2], c));
        }
        shortened += n[1] < n[0];
    }
    assert_true(shortened > 400); /* the medulla is hit often enough for the test to mean something */
}

/* Head-on (theta = 0, h = 0) light reaches a concentric medulla of radius
 * 0.6 after a 0.4 segment and, after the bounce, needs at least 0.4 more to
 * leave: lobe 1 is attenuated over at least 0.8, and over less if the segment
 * ending on the medulla were not attenuated. */
static void segments_to_the_medulla_are_attenuated(void **state)
{
    (void)state;
    plm_fiber_params clear = fiber_variant(2, 1.0, rgb_gray(1.0));
    plm_fiber_params absorbing = clear;
    absorbing.sigma_a = rgb_gray(0.5);
    double shortest = INFINITY;
    for (int i = 0; i < 2000; ++i) {
        plm_fiber_lobe a[2], b[2];
        plm_rng ra, rb;
        plm_rng_seed(&ra, 17, (uint64_t)i);
        plm_rng_seed(&rb, 17, (uint64_t)i);
        vec3 wo = v3(1.0, 0.0, 0.0);
        assert_int_equal(plm_fiber_trace_n(&clear, wo, 0.0, &ra, a, 2, NULL), 2);
        assert_int_equal(plm_fiber_trace_n(&absorbing, wo, 0.0, &rb, b, 2, NULL), 2);
        double length = -log(b[1].throughput.r / a[1].throughput.r) / 0.5;
        shortest = fmin(shortest, length);
    }
    assert_true(shortest >= 0.8 - 1e-9);
    assert_true(shortest < 0.85); /* nearly radial bounces occur */
}

/* Every field is range-checked with its name in the message, and the medulla
 * must lie strictly inside the cortex, decided to about 1e-9. */
static void validation_names_field_and_range(void **state)
{
    (void)state;
    struct { const char *field; double bad; } cases[] = {
        {"eccentricity", 0.0}, {"eta", 0.9}, {"beta_m", 0.0}, {"beta_n", 2.0}, {"medulla_a", -0.1}, {"medulla_centre", NAN},
    };
    for (int i = 0; i < 6; ++i) {
        plm_fiber_params p;
        plm_fiber_params_default(&p);
        double *fields[6] = {&p.eccentricity, &p.eta, &p.beta_m, &p.beta_n, &p.medulla_a, &p.medulla_cb};
        *fields[i] = cases[i].bad;
        plm_error err;
        assert_int_equal(plm_fiber_params_validate(&p, &err), PLM_ERR_INVALID);
        assert_non_null(strstr(err.message, cases[i].field));
        assert_non_null(strstr(err.message, "range"));
    }
    plm_fiber_params p;
    plm_fiber_params_default(&p);
    p.sigma_a.g = -1.0;
    plm_error err;
    assert_int_equal(plm_fiber_params_validate(&p, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "sigma_a"));
    p.sigma_a.g = 0.0;
    p.lobes = 1001;
    assert_int_equal(plm_fiber_params_validate(&p, &err), PLM_ERR_INVALID);
    p.lobes = 5;
    const double eps = 1e-6;
    struct { double e, a, b, ca, cb; int inside; } medullas[] = {
        {1.0, 0.5, 0.5, 0.5 - eps, 0.0, 1},  {1.0, 0.5, 0.5, 0.5 + eps, 0.0, 0},
        {1.6, 0.3, 0.3, 0.0, 1.3 - eps, 1},  {1.6, 0.3, 0.3, 0.0, 1.3 + eps, 0},
        {1.6, 0.6, 0.6, -0.1, 0.1, 1},       {0.5, 0.3, 0.5 - eps, 0.0, 0.0, 1},
        {0.5, 0.3, 0.5 + eps, 0.0, 0.0, 0},  {1.0, 0.5, 0.0, 0.0, 0.0, 0},
    };
    for (int i = 0; i < 8; ++i) {
        p.eccentricity = medullas[i].e;
        p.medulla_a = medullas[i].a;
        p.medulla_b = medullas[i].b;
        p.medulla_ca = medullas[i].ca;
        p.medulla_cb = medullas[i].cb;
        plm_result r = plm_fiber_params_validate(&p, &err);
        assert_int_equal(r, medullas[i].inside ? PLM_OK : PLM_ERR_INVALID);
        if (r != PLM_OK)
            assert_non_null(strstr(err.message, "medulla"));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(circular_fiber_matches_closed_form),
        cmocka_unit_test(elliptical_fiber_vertex_rays),
        cmocka_unit_test(fresnel_both_ways_with_total_internal_reflection),
        cmocka_unit_test(energy_is_conserved_without_absorption),
        cmocka_unit_test(silhouettes_are_grazing),
        cmocka_unit_test(five_lobes_hold_the_energy),
        cmocka_unit_test(absorption_only_darkens),
        cmocka_unit_test(black_medulla_only_removes_energy),
        cmocka_unit_test(segments_to_the_medulla_are_attenuated),
        cmocka_unit_test(validation_names_field_and_range),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
