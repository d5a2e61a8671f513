/* Near-field shading (docs/nearfield.md): the masking of a window of the
 * barb period, its mean over positions against the far field, closed forms
 * at the normal view, the barb coordinate read from the feather texture, the
 * pixel footprint and the window it gives. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "common/image_io.h"
#include "common/rng.h"
#include "optics/masking.h"
#include "optics/nearfield.h"

#include "masking_random.h"

/* The paper's Fig. 9 sets (e_bb 1, delta_bb 1, phi_bb 45 degrees). */
static plm_masking_params figure9(int set)
{
    plm_masking_params p;
    plm_masking_params_default(&p);
    p.barb_eccentricity = set == 1 ? 3.0 : 1.0;
    p.barbule_length = set == 1 ? 1.0 : 3.0;
    p.barbule_inclination = set == 1 ? 0.0 : plm_radians(45.0);
    return p;
}

/* Views up to 80 degrees from either side's normal. */
static vec3 random_view(plm_rng *rng)
{
    double ct = uniform(rng, cos(plm_radians(80.0)), 1.0), phi = uniform(rng, 0.0, PLM_TWO_PI);
    double st = sqrt(1.0 - ct * ct), side = plm_rng_uniform(rng) < 0.5 ? -1.0 : 1.0;
    return v3(st * cos(phi), side * ct, st * sin(phi));
}

/* One ray's answer: a window of 1e-9 of a period around x. */
static void point_masking(const plm_masking_model *m, vec3 wo, double x, plm_masking *out)
{
    plm_barb_window w = {x - 5e-10, x + 5e-10};
    plm_masking_eval_window(m, wo, &w, out);
}

static void check_window_invariants(const plm_masking *m)
{
    double w[4] = {m->w_barb, m->w_proximal, m->w_distal, m->w_transmission};
    double sum = 0.0;
    for (int i = 0; i < 4; ++i) {
        assert_true(isfinite(w[i]) && w[i] >= 0.0);
        sum += w[i];
    }
    assert_double_near(sum, 1.0, 1e-12);
    assert_true(m->barb_range_count >= 0 && m->barb_range_count <= PLM_MASKING_MAX_BARB_RANGES);
    double rates = 0.0;
    for (int i = 0; i < m->barb_range_count; ++i) {
        assert_true(-1.0 <= m->barb[i].hmin && m->barb[i].hmin <= m->barb[i].hmax && m->barb[i].hmax <= 1.0);
        rates += m->barb[i].rate;
    }
    assert_double_near(rates, m->w_barb, 1e-12);
}

/* The far field's barb h-distribution: the rate of h <= h_cut. */
static double far_barb_cdf(const plm_masking *m, double h_cut)
{
    double sum = 0.0;
    for (int i = 0; i < m->barb_range_count; ++i) {
        const plm_h_range *g = &m->barb[i];
        sum += g->rate * plm_clamp((h_cut - g->hmin) / fmax(g->hmax - g->hmin, 1e-300), 0.0, 1.0);
    }
    return sum;
}

#define CUTS 9

/* Over n random positions within a period, the mean of one ray's answer
 * (weights, and the barb's h-distribution as its CDF at CUTS points) equals
 * the far field to Monte Carlo error (5 sigma from the samples' own
 * variance); the barbule sets' h-intervals are the far field's. */
static void check_random_positions(const plm_masking_params *p, vec3 wo, int n, plm_rng *rng)
{
    plm_masking_model model;
    plm_masking_prepare(p, &model);
    plm_masking far;
    plm_masking_eval_window(&model, wo, NULL, &far);
    double sum[4 + CUTS] = {0}, sum2[4 + CUTS] = {0};
    for (int i = 0; i < n; ++i) {
        plm_masking m;
        point_masking(&model, wo, plm_rng_uniform(rng), &m);
        check_window_invariants(&m);
        assert_double_near(m.proximal.hmin, far.proximal.hmin, 1e-15);
        assert_double_near(m.distal.hmax, far.distal.hmax, 1e-15);
        double v[4 + CUTS] = {m.w_barb, m.w_proximal, m.w_distal, m.w_transmission};
        for (int c = 0; c < CUTS; ++c)
            for (int k = 0; k < m.barb_range_count; ++k)
                v[4 + c] += 0.5 * (m.barb[k].hmin + m.barb[k].hmax) <= -0.8 + 0.2 * c ? m.barb[k].rate : 0.0;
        for (int k = 0; k < 4 + CUTS; ++k) {
            sum[k] += v[k];
            sum2[k] += v[k] * v[k];
        }
    }
    double expected[4 + CUTS] = {far.w_barb, far.w_proximal, far.w_distal, far.w_transmission};
    for (int c = 0; c < CUTS; ++c)
        expected[4 + c] = far_barb_cdf(&far, -0.8 + 0.2 * c);
    for (int k = 0; k < 4 + CUTS; ++k) {
        double mean = sum[k] / n, var = fmax(sum2[k] / n - mean * mean, 0.0);
        /* A floor for classes narrower than the samples can see. */
        assert_double_near(mean, expected[k], 5.0 * sqrt(var / n) + 2.0 / n);
    }
}

static void random_positions_average_to_the_far_field(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 11, 0);
    for (int set = 1; set <= 2; ++set) {
        plm_masking_params p = figure9(set);
        for (int v = 0; v < 24; ++v)
            check_random_positions(&p, random_view(&rng), 4000, &rng);
    }
    for (int k = 0; k < 40; ++k) {
        plm_masking_params p = random_params(&rng);
        check_random_positions(&p, random_view(&rng), 2000, &rng);
    }
}

/* Evenly spaced positions integrate the piecewise-constant classes with an
 * error of at most (classes + 1) / n: a deterministic check of the same
 * identity, and of the barb h-ranges' rates cut to a window. */
static void stratified_positions_average_to_the_far_field(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 12, 0);
    const int n = 20000;
    for (int k = 0; k < 30; ++k) {
        plm_masking_params p = k < 2 ? figure9(k + 1) : random_params(&rng);
        plm_masking_model model;
        plm_masking_prepare(&p, &model);
        vec3 wo = random_view(&rng);
        plm_masking far;
        plm_masking_eval_window(&model, wo, NULL, &far);
        double w[4] = {0}, cdf = 0.0;
        for (int i = 0; i < n; ++i) {
            plm_masking m;
            point_masking(&model, wo, (i + 0.5) / n, &m);
            w[0] += m.w_barb, w[1] += m.w_proximal, w[2] += m.w_distal, w[3] += m.w_transmission;
            for (int r = 0; r < m.barb_range_count; ++r)
                cdf += m.barb[r].hmax <= 0.1 ? m.barb[r].rate : 0.0;
        }
        double far_w[4] = {far.w_barb, far.w_proximal, far.w_distal, far.w_transmission};
        for (int c = 0; c < 4; ++c)
            assert_double_near(w[c] / n, far_w[c], 7.0 / n);
        assert_double_near(cdf / n, far_barb_cdf(&far, 0.1), 7.0 / n);
    }
}

/* Windows of any width average to the far field too (the filter keeps the
 * mean), a window of a whole period is the far field, and a window just
 * short of it is close to it: the transition is continuous. */
static void windows_filter_without_changing_the_mean(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 13, 0);
    const int n = 4000;
    for (int k = 0; k < 20; ++k) {
        plm_masking_params p = k < 2 ? figure9(k + 1) : random_params(&rng);
        plm_masking_model model;
        plm_masking_prepare(&p, &model);
        vec3 wo = random_view(&rng);
        plm_masking far, m;
        plm_masking_eval_window(&model, wo, NULL, &far);
        double width = uniform(&rng, 0.05, 0.95), mean_barb = 0.0, mean_t = 0.0;
        for (int i = 0; i < n; ++i) {
            double x = (i + 0.5) / n;
            plm_masking_eval_window(&model, wo, &(plm_barb_window){x - 0.5 * width, x + 0.5 * width}, &m);
            check_window_invariants(&m);
            mean_barb += m.w_barb / n;
            mean_t += m.w_transmission / n;
        }
        assert_double_near(mean_barb, far.w_barb, 14.0 / n);
        assert_double_near(mean_t, far.w_transmission, 14.0 / n);
        double x = plm_rng_uniform(&rng);
        plm_masking_eval_window(&model, wo, &(plm_barb_window){x - 0.5, x + 0.5}, &m);
        assert_double_near(m.w_barb, far.w_barb, 0.0);
        assert_double_near(m.w_transmission, far.w_transmission, 0.0);
        plm_masking_eval_window(&model, wo, &(plm_barb_window){x - 0.4995, x + 0.4995}, &m);
        assert_double_near(m.w_barb, far.w_barb, 2e-3);
        assert_double_near(m.w_transmission, far.w_transmission, 2e-3);
    }
}

/* Seen along the normal with flat rows (theta_bb = 0), from either side, a
 * ray at x meets the barb where |x| < w = 1 / (2 (1 + l_bb)), at h = +-x / w
 * (h runs along (d_y, -d_x)); elsewhere a barbule row (distal for x > 0)
 * that lets delta / (1 + delta) through. */
static void normal_view_closed_form(void **state)
{
    (void)state;
    plm_masking_params p;
    plm_masking_params_default(&p);
    p.barbule_length = 2.0;
    p.barbule_separation = 0.5;
    plm_masking_model model;
    plm_masking_prepare(&p, &model);
    double w = 1.0 / 6.0, t = 0.5 / 1.5;
    const double xs[] = {0.0, 0.1, -0.15, 0.3, -0.3, 0.45, 0.7};
    for (size_t k = 0; k < 2 * sizeof xs / sizeof xs[0]; ++k) {
        size_t i = k / 2;
        double side = k % 2 ? -1.0 : 1.0;
        plm_masking m;
        point_masking(&model, v3(0, side, 0), xs[i], &m);
        double x = xs[i] - floor(xs[i] + 0.5); /* within the period around barb 0 */
        if (fabs(x) < w) {
            assert_double_near(m.w_barb, 1.0, 1e-12);
            assert_int_equal(m.barb_range_count, 1);
            assert_double_near(0.5 * (m.barb[0].hmin + m.barb[0].hmax), side * x / w, 1e-6);
        } else {
            assert_double_near(m.w_barb, 0.0, 1e-12);
            assert_double_near(x > 0 ? m.w_distal : m.w_proximal, 1.0 - t, 1e-12);
            assert_double_near(m.w_transmission, t, 1e-12);
        }
    }
}

/* The coordinate read from a texture whose stored fraction is a linear
 * function a x + b y of the texel position (x right, y down): bilinear with
 * unwrapping gives the linear function back, its gradient in uv units, and
 * a texture without the channel has no coordinate. */
static void texture_coordinate_is_unwrapped(void **state)
{
    (void)state;
    const int width = 16, height = 12;
    const double a = 0.31, b = -0.17;
    float *px = malloc(sizeof(float) * 3 * width * height), *barb = malloc(sizeof(float) * width * height);
    assert_non_null(px);
    assert_non_null(barb);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            float *t = px + 3 * (y * width + x);
            t[PLM_FTEX_COS] = plm_ftex_encode_component(1.0);
            t[PLM_FTEX_SIN] = plm_ftex_encode_component(0.0);
            t[PLM_FTEX_REGION] = plm_ftex_encode_region(PLM_REGION_VANE);
            barb[y * width + x] = plm_ftex_encode_barb(a * x + b * y + 0.05);
        }
    plm_feather_texture tex;
    plm_error err = {{0}};
    assert_int_equal(plm_feather_texture_from_pixels(width, height, px, &tex, &err), PLM_OK);
    plm_barb_sample s;
    assert_int_equal(plm_feather_texture_barb(&tex, v2(0.5, 0.5), &s), 0);
    tex.barb = barb;
    plm_rng rng;
    plm_rng_seed(&rng, 14, 0);
    for (int i = 0; i < 200; ++i) {
        /* Inside the texel centres, where bilinear filtering has four texels. */
        double x = uniform(&rng, 0.0, width - 1.0), y = uniform(&rng, 0.0, height - 1.0);
        vec2 uv = v2((x + 0.5) / width, 1.0 - (y + 0.5) / height);
        assert_int_equal(plm_feather_texture_barb(&tex, uv, &s), 1);
        double expected = a * x + b * y + 0.05, d = s.coordinate - expected;
        assert_double_near(d - floor(d + 0.5), 0.0, 1e-5);
        assert_double_near(s.gradient.x, a * width, 1e-4);
        assert_double_near(s.gradient.y, -b * height, 1e-4);
        assert_double_near(s.texel_step, fabs(a), 1e-5);
    }
    /* At uv (1/2, 1/2), texel (7.5, 5.5): coordinate 1.44, so x = 0.94, the same phase as -0.06. With
     * dP/du, dP/dv the unit axes, a cone of 1e-4 covers 5.4e-4 of a period, but texels 0.31 of a
     * period apart widen the window to (0.31 - 0.3) / 0.15; no cone is the far field. */
    vec3 n = v3(0, 0, 1), d = v3(0, 0, -1);
    plm_texel_site site;
    plm_feather_texture_site(&tex, v2(0.5, 0.5), &site);
    plm_barb_window w = plm_nearfield_at(&tex, &site, v3(1, 0, 0), v3(0, 1, 0), n, d, 1e-4);
    assert_double_near(0.5 * (w.x0 + w.x1), -0.06, 1e-5);
    assert_double_near(w.x1 - w.x0, 0.01 / 0.15, 1e-6); /* the texels are floats */
    w = plm_nearfield_at(&tex, &site, v3(1, 0, 0), v3(0, 1, 0), n, d, 0.0);
    assert_true(w.x1 - w.x0 >= 1.0);
    plm_feather_texture_free(&tex);
}

/* A 4-channel EXR's fourth channel reaches the texture as its coordinate. */
static void texture_file_keeps_the_coordinate(void **state)
{
    (void)state;
    const int width = 8, height = 4;
    float px[4 * 8 * 4];
    for (int i = 0; i < width * height; ++i) {
        px[4 * i + PLM_FTEX_COS] = plm_ftex_encode_component(0.0);
        px[4 * i + PLM_FTEX_SIN] = plm_ftex_encode_component(1.0);
        px[4 * i + PLM_FTEX_REGION] = plm_ftex_encode_region(PLM_REGION_VANE);
        px[4 * i + PLM_FTEX_BARB] = plm_ftex_encode_barb(0.125 * (i % width));
    }
    char dir[] = "/tmp/plm_nearfield_XXXXXX", path[64];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/t.exr", dir);
    plm_error err = {{0}};
    assert_int_equal(plm_image_write(path, width, height, 4, PLM_PIXEL_FLOAT, px, &err), PLM_OK);
    plm_feather_texture tex;
    assert_int_equal(plm_feather_texture_read(path, &tex, &err), PLM_OK);
    remove(path);
    rmdir(dir);
    assert_non_null(tex.barb);
    for (int i = 0; i < width * height; ++i)
        assert_double_near(tex.barb[i], px[4 * i + PLM_FTEX_BARB], 0.0);
    assert_int_equal(plm_feather_texture_region(&tex, v2(0.3, 0.3)), PLM_REGION_VANE);
    plm_feather_texture_free(&tex);
}

/* The footprint: at normal incidence the cone's width times the gradient;
 * tilted by theta toward the gradient, stretched by 1 / cos theta; tilted
 * across it, not at all. The world gradient from a uv gradient on a
 * sheared parameterisation. */
static void footprint_and_gradient(void **state)
{
    (void)state;
    vec3 n = v3(0, 0, 1), g = v3(4, 0, 0);
    assert_double_near(plm_nearfield_footprint(g, v3(0, 0, -1), n, 0.01), 0.04, 1e-12);
    double th = plm_radians(60.0);
    assert_double_near(plm_nearfield_footprint(g, v3(sin(th), 0, -cos(th)), n, 0.01), 0.08, 1e-12);
    assert_double_near(plm_nearfield_footprint(g, v3(0, sin(th), -cos(th)), n, 0.01), 0.04, 1e-12);
    /* c = 3 u + 5 v with P = u dpdu + v dpdv: grad c . dpdu = 3, grad c . dpdv = 5. */
    vec3 dpdu = v3(2, 0, 0), dpdv = v3(1, 3, 0);
    vec3 gw = plm_nearfield_gradient(v2(3, 5), dpdu, dpdv);
    assert_double_near(v3_dot(gw, dpdu), 3.0, 1e-12);
    assert_double_near(v3_dot(gw, dpdv), 5.0, 1e-12);
    assert_double_near(gw.z, 0.0, 1e-12);
}

/* The window: centred on coordinate - 1/2 within the period, as wide as the
 * footprint; a period or more, or texels half a period apart, is the far field. */
static void window_from_footprint(void **state)
{
    (void)state;
    plm_barb_window w = plm_nearfield_window(3.75, 0.2, 0.1);
    assert_double_near(0.5 * (w.x0 + w.x1), 0.25, 1e-12);
    assert_double_near(w.x1 - w.x0, 0.2, 1e-12);
    w = plm_nearfield_window(-2.5, 0.0, 0.1);
    assert_double_near(0.5 * (w.x0 + w.x1), 0.0, 1e-12);
    assert_true(w.x1 > w.x0 && w.x1 - w.x0 < 1e-8);
    w = plm_nearfield_window(0.3, 1.0, 0.1);
    assert_true(w.x1 - w.x0 >= 1.0);
    w = plm_nearfield_window(0.3, 0.01, 0.45);
    assert_true(w.x1 - w.x0 >= 1.0);
    w = plm_nearfield_window(0.3, 0.01, 0.375); /* halfway up the texel ramp */
    assert_double_near(w.x1 - w.x0, 0.5, 1e-12);
    w = plm_nearfield_window(0.3, NAN, 0.1);
    assert_true(w.x1 - w.x0 >= 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(random_positions_average_to_the_far_field),
        cmocka_unit_test(stratified_positions_average_to_the_far_field),
        cmocka_unit_test(windows_filter_without_changing_the_mean),
        cmocka_unit_test(normal_view_closed_form),
        cmocka_unit_test(texture_coordinate_is_unwrapped),
        cmocka_unit_test(texture_file_keeps_the_coordinate),
        cmocka_unit_test(footprint_and_gradient),
        cmocka_unit_test(window_from_footprint),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
