/* The feather BSDF (paper Eq. 4) on its own and in the renderer: the barb
 * frame, a white furnace of its albedo, chi-square of sample against pdf,
 * sample weights (the chosen fiber's, unbiased for the mixture's),
 * transmission as fractional visibility (transparent shadows against
 * stochastic passing) and a furnace scene. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "optics/feather_bsdf.h"
#include "render/render.h"
#include "render/scene_build.h"
#include "test_feather_bsdf_stats.h"
#include "test_render_stats.h"

/* A clear feather (no absorption) with a white medulla in its barbs. */
static plm_feather_params clear_params(int variant)
{
    plm_feather_params p;
    plm_feather_params_default(&p);
    p.barb.sigma_a = p.barbule.sigma_a = rgb_gray(0.0);
    p.barb.medulla_reflectance = rgb_gray(1.0);
    if (variant == 1) {
        p.barb.eccentricity = 1.6;
        p.masking.barb_eccentricity = 3.0;
        p.masking.barbule_separation = 0.3;
    } else if (variant == 2) {
        p.masking.barbule_length = 3.0;
        p.masking.barbule_inclination = plm_radians(45.0);
        p.barbule.eccentricity = 2.0;
        p.barb.medulla_ca = -0.1, p.barb.medulla_cb = 0.1;
        p.barb.beta_m = p.barbule.beta_m = 0.3;
    }
    plm_error err;
    assert_int_equal(plm_feather_params_validate(&p, &err), PLM_OK);
    return p;
}

static void barb_frame_follows_texture_and_tip(void **state)
{
    (void)state;
    for (int side = 0; side < 2; ++side) {
        double a = side ? plm_radians(135.0) : plm_radians(45.0); /* right and left vanes */
        frame f;
        assert_true(plm_feather_barb_frame(v3(0, 0, 1), v3(2, 0, 0), v3(0, 1, 0), v2(cos(a), sin(a)), &f));
        /* t follows the uv direction through the Jacobian: dP/du is twice as long as dP/dv. */
        vec3 t = v3_normalize(v3(2 * cos(a), sin(a), 0));
        assert_double_near(v3_dot(f.z, t), 1.0, 1e-12);
        assert_double_near(v3_dot(f.x, f.z), 0.0, 1e-12);
        assert_double_near(v3_length(f.x), 1.0, 1e-12);
        assert_true(v3_dot(f.x, v3(0, 1, 0)) > 0.0); /* distal side toward the tip */
        assert_double_near(f.y.z, 1.0, 0);
    }
    /* Degenerate tangents are refused. */
    frame f;
    assert_false(plm_feather_barb_frame(v3(0, 0, 1), v3(0, 0, 0), v3(0, 0, 0), v2(1, 0), &f));
}

static void set_texel(float *px, int i, double angle, float region)
{
    px[3 * i] = (float)((cos(angle) + 1) / 2), px[3 * i + 1] = (float)((sin(angle) + 1) / 2), px[3 * i + 2] = region;
}

/* The texture contract: region by nearest texel (v = 0 is the bottom row),
 * directions filtered only among texels of the same region, and averaged as
 * vectors so angles near +-180 degrees do not wrap to 0. */
/* A texture file with the barb coordinate as a fourth channel (what plumage
 * writes now) reads as the same three channels: in PNG the fourth is stored
 * as RGBA's alpha and must not scale the others (even where it is 0). */
static void four_channel_textures_read_as_three(void **state)
{
    (void)state;
    const float texels[2][PLM_FTEX_CHANNELS_WITH_BARB] = {{0.2f, 0.9f, 1.0f, 0.0f}, {0.7f, 0.4f, 0.5f, 0.03f}};
    const char *files[2] = {"ftex4_rt.exr", "ftex4_rt.png"};
    for (int k = 0; k < 2; ++k) {
        plm_error err;
        if (k == 0)
            assert_int_equal(plm_image_write(files[k], 2, 1, 4, PLM_PIXEL_FLOAT, texels, &err), PLM_OK);
        else {
            uint16_t words[8];
            for (int c = 0; c < 8; ++c)
                words[c] = (uint16_t)lrint(65535.0 * texels[c / 4][c % 4]);
            assert_int_equal(plm_image_write(files[k], 2, 1, 4, PLM_PIXEL_UINT16, words, &err), PLM_OK);
        }
        plm_feather_texture t;
        assert_int_equal(plm_feather_texture_read(files[k], &t, &err), PLM_OK);
        for (int i = 0; i < 2; ++i)
            for (int c = 0; c < PLM_FTEX_CHANNELS; ++c)
                assert_double_near(t.pixels[PLM_FTEX_CHANNELS * i + c], texels[i][c], 0.5 / 65535.0 + 1e-7);
        assert_int_equal(plm_feather_texture_region(&t, v2(0.25, 0.5)), PLM_REGION_VANE);
        assert_int_equal(plm_feather_texture_region(&t, v2(0.75, 0.5)), PLM_REGION_RACHIS);
        plm_feather_texture_free(&t);
        remove(files[k]);
    }
}

static void texture_lookups_keep_regions_and_angles(void **state)
{
    (void)state;
    float *px = malloc(sizeof(float) * 4 * 2 * 3);
    /* top row: vane at 179 deg, vane at -179 deg, rachis at 90 deg, background at 0 deg */
    set_texel(px, 0, plm_radians(179.0), 1.0f), set_texel(px, 1, plm_radians(-179.0), 1.0f);
    set_texel(px, 2, plm_radians(90.0), 0.5f), set_texel(px, 3, 0.0, 0.0f);
    for (int i = 4; i < 8; ++i) /* bottom row: vane at 10 deg */
        set_texel(px, i, plm_radians(10.0), 1.0f);
    plm_feather_texture t;
    plm_error err;
    assert_int_equal(plm_feather_texture_from_pixels(4, 2, px, &t, &err), PLM_OK);
    assert_int_equal(plm_feather_texture_region(&t, v2(0.1, 0.9)), PLM_REGION_VANE);
    assert_int_equal(plm_feather_texture_region(&t, v2(0.6, 0.9)), PLM_REGION_RACHIS);
    assert_int_equal(plm_feather_texture_region(&t, v2(0.9, 0.9)), PLM_REGION_BACKGROUND);
    assert_int_equal(plm_feather_texture_region(&t, v2(0.9, 0.1)), PLM_REGION_VANE);
    /* Between the 179 and -179 degree texels: 180 degrees, not 0. */
    vec2 d = plm_feather_texture_direction(&t, v2(0.25, 0.75));
    assert_double_near(d.x, -1.0, 1e-4);
    assert_double_near(v2_length(d), 1.0, 1e-12);
    /* A vane point next to the rachis: bilinear weights (0.35, 0.15 | 0.35, 0.15)
     * over texels (-179, rachis | 10, 10); the rachis's 90 degrees never enters. */
    d = plm_feather_texture_direction(&t, v2(0.45, 0.5));
    vec2 mean = v2_normalize(v2_add(v2_scale(v2(cos(plm_radians(-179.0)), sin(plm_radians(-179.0))), 0.35),
                                    v2_scale(v2(cos(plm_radians(10.0)), sin(plm_radians(10.0))), 0.5)));
    assert_double_near(d.x, mean.x, 1e-4);
    assert_double_near(d.y, mean.y, 1e-4);
    /* On the rachis texel: its own direction, whatever its vane neighbours say. */
    d = plm_feather_texture_direction(&t, v2(0.62, 0.8));
    assert_double_near(atan2(d.y, d.x), PLM_PI / 2, 1e-3);
    plm_feather_texture_free(&t);
}

/* The pigment image multiplies the colour a vane texel scatters:
 * mix(1, band_tint, bands) * mix(1, tip_tint, tip) * mix(1, base_tint, base)
 * * (1 - barb), texel by texel (nearest), on top of the instance's tint;
 * rachis texels keep theirs. An image of 3 channels (before the downy base
 * had its own) reads as base 0. */
static void pigment_tints_vane_texels(void **state)
{
    (void)state;
    plm_error err;
    float *px = malloc(sizeof(float) * 2 * 1 * 3);
    set_texel(px, 0, plm_radians(90.0), 1.0f), set_texel(px, 1, plm_radians(90.0), 0.5f); /* vane | rachis */
    plm_material m;
    memset(&m, 0, sizeof m);
    m.type = PLM_MATERIAL_FEATHER;
    plm_feather_material_default(&m);
    m.band_tint = rgb_make(0.5, 0.25, 1.0);
    m.tip_tint = rgb_make(0.2, 0.2, 0.2);
    m.base_tint = rgb_make(1.0, 0.4, 0.6);
    assert_int_equal(plm_feather_texture_from_pixels(2, 1, px, &m.texture, &err), PLM_OK);
    static float pigment[2 * 4] = {1.0f, 0.5f, 0.1f, 0.5f, 1.0f, 1.0f, 0.0f, 1.0f}; /* bands, tip, barb, base */
    static float old_pigment[2 * 3] = {1.0f, 0.5f, 0.1f, 1.0f, 1.0f, 0.0f};         /* bands, tip, barb */
    for (int channels = 3; channels <= 4; ++channels) {
        m.pigment = (plm_image){2, 1, channels, channels == 4 ? pigment : old_pigment};
        plm_hit hit;
        memset(&hit, 0, sizeof hit);
        hit.material = &m;
        hit.n = v3(0, 0, 1), hit.ng = hit.n, hit.dpdu = v3(1, 0, 0), hit.dpdv = v3(0, 1, 0);
        hit.tint = rgb_make(0.8, 0.8, 0.8);
        hit.uv = v2(0.25, 0.5);
        plm_material_surface(&hit);
        assert_true(hit.on_vane);
        /* bands 1: band_tint; tip 0.5: halfway to 0.2 = 0.6; barb 0.1: 0.9; times the instance's 0.8;
         * base 0.5 (4 channels): halfway to base_tint. */
        rgb base = channels == 4 ? rgb_make(1.0, 0.7, 0.8) : rgb_gray(1.0);
        assert_double_near(hit.tint.r, 0.8 * 0.5 * 0.6 * 0.9 * base.r, 1e-6);
        assert_double_near(hit.tint.g, 0.8 * 0.25 * 0.6 * 0.9 * base.g, 1e-6);
        assert_double_near(hit.tint.b, 0.8 * 1.0 * 0.6 * 0.9 * base.b, 1e-6);
        hit.tint = rgb_make(0.8, 0.8, 0.8);
        hit.uv = v2(0.75, 0.5);
        plm_material_surface(&hit);
        assert_false(hit.on_vane);
        assert_double_near(hit.tint.r, 0.8, 0.0);
    }
    plm_feather_texture_free(&m.texture);
}

/* White furnace: without absorption the albedo, the integral of f |cos| plus
 * w_t, is 1 minus what the fiber lobes lose (light still inside after N
 * lobes). For each prepared BSDF, the integral of eval equals the weighted
 * lobe energy of its lobe sets; over many views the albedo is close to 1. */
static void white_furnace_of_the_bsdf(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 5, 5);
    double albedo_sum = 0.0;
    int cases = 0;
    for (int variant = 0; variant < 3; ++variant) {
        plm_feather_params p = clear_params(variant);
        plm_material m = feather_material(&p, plm_radians(60.0));
        plm_prepared_material prepared;
        plm_hit hit = plane_hit(&m, &prepared);
        const double views[][3] = {{0.1, 0.2, 1.0}, {0.7, -0.3, 0.4}, {-0.5, 0.6, 0.3}, {0.3, 0.2, -0.8}};
        for (int v = 0; v < 4; ++v) {
            char label[64];
            snprintf(label, sizeof label, "variant %d view %d", variant, v);
            vec3 wo = v3_normalize(v3(views[v][0], views[v][1], views[v][2]));
            albedo_sum += furnace_albedo(&hit, wo, &rng, 400000, 4.0, label);
            ++cases;
        }
        free_material(&m);
    }
    /* Five lobes keep >= 97% of the energy on average (the fiber's own test); the masking loses nothing. */
    assert_true(albedo_sum / cases > 0.95);
}

static void sampling_matches_pdf(void **state)
{
    (void)state;
    enum { N_TESTS = 4 };
    const double threshold = chi_square_sidak(0.01, N_TESTS);
    plm_rng rng;
    plm_rng_seed(&rng, 8, 8);
    for (int t = 0; t < N_TESTS; ++t) {
        plm_feather_params p;
        plm_feather_params_default(&p);
        p.barb.beta_m = p.barb.beta_n = p.barbule.beta_m = p.barbule.beta_n = t < 2 ? 0.25 : 0.12;
        if (t % 2)
            p.masking.barbule_inclination = plm_radians(30.0), p.masking.barbule_separation = 0.2;
        plm_material m = feather_material(&p, plm_radians(50.0 + 20.0 * t));
        plm_prepared_material prepared;
        plm_hit hit = plane_hit(&m, &prepared);
        vec3 wo = v3_normalize(t == 3 ? v3(0.4, 0.3, -0.6) : v3(0.3 * t, 0.5, 0.8));
        plm_bsdf b;
        plm_material_bsdf(&hit, wo, &rng, &b);
        double pv = chi_square(&b, &rng, 300000);
        if (!(pv > threshold))
            fail_msg("chi-square test %d: p-value %.5f below %.5f", t, pv, threshold);
        free_material(&m);
    }
}

/* The same test with the fiber tables (docs/fiber.md) at the views of the
 * two vertices of the paths that make bench render's close-up fireflies
 * (docs/rendering.md): the parrot's barb (elliptical, a large blue-green
 * medulla) seen from above, and the underside of a curled vane seen at
 * grazing, 1 degree off its plane, from two sides. Small tables: the test
 * is of sampling against pdf, not of the tables' accuracy. */
static void tabulated_sampling_matches_pdf_at_grazing_views(void **state)
{
    (void)state;
    enum { N_TESTS = 3 };
    const double threshold = chi_square_sidak(0.01, N_TESTS);
    const double views[N_TESTS][3] = {{0.3, 0.2, 0.93}, {0.8, 0.6, -0.02}, {-0.6, 0.8, -0.02}};
    plm_feather_params p;
    plm_feather_params_default(&p);
    p.barb.eccentricity = p.masking.barb_eccentricity = 1.4;
    p.barb.medulla_a = p.barb.medulla_b = 0.8;
    p.barb.medulla_reflectance = rgb_make(0.03, 0.75, 0.45);
    plm_fiber_table_options o = {0};
    o.no_cache = o.quiet = 1;
    o.theta_nodes = 7, o.phi_nodes = 6, o.h_cells = 16, o.phi_bins = 96;
    o.medulla = (plm_fiber_medulla_resolution){4, 3, 12, 9, 36, 512, 16, 8};
    plm_error err;
    plm_material m = feather_material(&p, plm_radians(50.0));
    plm_prepared_material prepared;
    plm_hit hit = plane_hit(&m, &prepared);
    plm_fiber_table_set tables;
    plm_fiber_table_set_init(&tables, &o);
    if (plm_material_prepare_tables(&m, &tables, &prepared, &err) != PLM_OK)
        fail_msg("%s", err.message);
    plm_rng rng;
    plm_rng_seed(&rng, 8, 9);
    for (int t = 0; t < N_TESTS; ++t) {
        plm_bsdf b;
        plm_material_bsdf(&hit, v3_normalize(v3(views[t][0], views[t][1], views[t][2])), &rng, &b);
        double pv = chi_square(&b, &rng, 300000);
        fprintf(stderr, "tabulated feather, view %d: chi-square p-value %.4f\n", t, pv);
        if (!(pv > threshold))
            fail_msg("chi-square test %d: p-value %.5f below %.5f", t, pv, threshold);
    }
    plm_fiber_table_set_free(&tables);
    free_material(&m);
}

/* The same seed prepares the same BSDF: eval, pdf and samples agree exactly
 * wherever the BSDF is not zero (at directions it samples). Another seed
 * prepares another one (the lobe sets are random), so the agreement is not
 * that of a BSDF that ignores its random numbers. */
static void prepared_bsdf_is_reproducible_by_seed(void **state)
{
    (void)state;
    plm_feather_params p;
    plm_feather_params_default(&p);
    plm_material m = feather_material(&p, 1.0);
    plm_prepared_material prepared;
    plm_hit hit = plane_hit(&m, &prepared);
    plm_rng a, b, c, u;
    plm_rng_seed(&a, 1, 2);
    plm_rng_seed(&b, 1, 2);
    plm_rng_seed(&c, 3, 2);
    plm_rng_seed(&u, 4, 4);
    plm_bsdf x, y, z;
    vec3 wo = v3_normalize(v3(0.2, 0.1, 1.0));
    plm_material_bsdf(&hit, wo, &a, &x);
    plm_material_bsdf(&hit, wo, &b, &y);
    plm_material_bsdf(&hit, wo, &c, &z);
    int sampled = 0, differ = 0;
    for (int i = 0; i < 64; ++i) {
        double u0 = plm_rng_uniform(&u), u1 = plm_rng_uniform(&u), u2 = plm_rng_uniform(&u);
        plm_bsdf_sample_rec sx, sy;
        int ok = plm_bsdf_sample(&x, u0, u1, u2, &sx);
        assert_int_equal(ok, plm_bsdf_sample(&y, u0, u1, u2, &sy));
        if (!ok)
            continue;
        ++sampled;
        assert_memory_equal(&sx, &sy, sizeof sx);
        rgb fx = plm_bsdf_eval(&x, sx.wi), fy = plm_bsdf_eval(&y, sx.wi), fz = plm_bsdf_eval(&z, sx.wi);
        assert_true(fx.r > 0.0 && fx.g > 0.0 && fx.b > 0.0);
        assert_true(fx.r == fy.r && fx.g == fy.g && fx.b == fy.b);
        assert_true(plm_bsdf_pdf(&x, sx.wi) == plm_bsdf_pdf(&y, sx.wi));
        differ += fx.r != fz.r || plm_bsdf_pdf(&x, sx.wi) != plm_bsdf_pdf(&z, sx.wi);
    }
    assert_true(sampled > 32);
    assert_true(differ > sampled / 2);
    free_material(&m);
}

/* Over one side of the normal n (0: upper, 1: lower), from N samples: the
 * mean sampled weight (est), the same samples weighted as if pick were
 * uniform over the fibers that carry light (wrong) and the integral of eval
 * by uniform Monte Carlo (ref). */
static void weights_on_side(const plm_bsdf *b, vec3 n, int side, plm_rng *rng, estimate *est, estimate *wrong,
                            estimate *ref)
{
    enum { N = 200000 };
    const plm_feather_bsdf *f = (const plm_feather_bsdf *)b->state;
    double carrying = (f->pick[0] > 0.0) + (f->pick[1] > 0.0) + (f->pick[2] > 0.0);
    double sum = 0.0, sum2 = 0.0, bad = 0.0, bad2 = 0.0, integral = 0.0, integral2 = 0.0;
    for (int i = 0; i < N; ++i) {
        double u0 = plm_rng_uniform(rng), u1 = plm_rng_uniform(rng), u2 = plm_rng_uniform(rng), r;
        plm_bsdf_sample_rec rec;
        if (plm_bsdf_sample(b, u0, u1, u2, &rec) && (v3_dot(rec.wi, n) > 0.0) == (side == 0)) {
            double v = rgb_mean(rec.weight), x = v * f->pick[plm_feather_pick(f, u0, &r)] * carrying;
            sum += v, sum2 += v * v, bad += x, bad2 += x * x;
        }
        vec3 w = plm_sample_uniform_sphere(plm_rng_uniform(rng), plm_rng_uniform(rng));
        double e = (v3_dot(w, n) > 0.0) == (side == 0) ? rgb_mean(plm_bsdf_eval(b, w)) * 4.0 * PLM_PI : 0.0;
        integral += e, integral2 += e * e;
    }
    *est = iid_estimate(sum, sum2, N);
    *wrong = iid_estimate(bad, bad2, N);
    *ref = iid_estimate(integral, integral2, N);
}

/* A sampled direction's weight is fiber k's own S_k cos / pdf_k times
 * weight_k / pick_k, an estimate of eval / pdf that is unbiased given wi:
 * so the mean weight over each hemisphere of the barb frame's normal must be
 * the integral of eval over it (uniform Monte Carlo), z-tests at 4.2
 * standard errors (8 tests, false alarm 2e-4 in all). Stochastic and
 * tabulated fibers (small tables), two views and barbule layouts each. The
 * test can fail: the same samples weighted as if pick were uniform over the
 * fibers (a wrong pick_k in the weight) are rejected in every case. */
static void sampled_weights_estimate_the_mixture(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 41, 7);
    int wrong_caught = 0;
    for (int t = 0; t < 4; ++t) {
        plm_feather_params p;
        plm_feather_params_default(&p);
        if (t % 2)
            p.masking.barbule_inclination = plm_radians(30.0), p.masking.barbule_separation = 0.4;
        plm_fiber_table_options o = {0};
        o.no_cache = o.quiet = 1;
        o.theta_nodes = 5, o.phi_nodes = 4, o.h_cells = 8, o.phi_bins = 64;
        o.medulla = (plm_fiber_medulla_resolution){4, 3, 12, 9, 36, 512, 16, 8};
        plm_error err;
        if (t < 2)
            p.bcsdf = PLM_BCSDF_STOCHASTIC;
        plm_material m = feather_material(&p, plm_radians(40.0 + 25.0 * t));
        plm_prepared_material prepared;
        plm_hit hit = plane_hit(&m, &prepared);
        plm_fiber_table_set tables;
        plm_fiber_table_set_init(&tables, &o);
        if (plm_material_prepare_tables(&m, &tables, &prepared, &err) != PLM_OK)
            fail_msg("%s", err.message);
        plm_bsdf b;
        plm_material_bsdf(&hit, v3_normalize(t % 2 ? v3(-0.4, 0.3, 0.7) : v3(0.3, -0.5, 0.6)), &rng, &b);
        for (int side = 0; side < 2; ++side) {
            estimate est, bad, ref;
            weights_on_side(&b, hit.n, side, &rng, &est, &bad, &ref);
            double z = z_score(est, ref), zw = z_score(bad, ref);
            fprintf(stderr, "case %d, %s side: mean weight %.5f +- %.5f, integral of eval %.5f +- %.5f (z %.2f); "
                            "uniform pick %.5f (z %.1f)\n",
                    t, side ? "lower" : "upper", est.mean, est.se, ref.mean, ref.se, z, bad.mean, zw);
            if (z > 4.2)
                fail_msg("case %d side %d: mean weight %.5f +- %.5f, integral %.5f +- %.5f", t, side, est.mean, est.se,
                         ref.mean, ref.se);
            wrong_caught += side == 0 && zw > 4.2;
        }
        plm_fiber_table_set_free(&tables);
        free_material(&m);
    }
    assert_int_equal(wrong_caught, 4);
}

/* ---------- the feather in scenes ---------- */

/* The BSDF's masking and barbule fiber frames are the masking model's, in
 * world space through the barb frame: each barbule axis lies in its row's
 * plane through t, tilted about t by theta_bb (also for falling rows). */
static void barbule_fibers_lie_in_the_tilted_rows(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 21, 0);
    int checked[2] = {0, 0};
    for (int i = 0; i < 200; ++i) {
        plm_feather_params p;
        plm_feather_params_default(&p);
        p.masking.barbule_inclination = plm_radians(-80.0 + 160.0 * plm_rng_uniform(&rng));
        p.masking.barbule_rotation = plm_radians(5.0 + 80.0 * plm_rng_uniform(&rng));
        p.masking.barbule_length = 0.5 + 3.0 * plm_rng_uniform(&rng);
        plm_feather_model model;
        plm_feather_model_init(&model, &p);
        frame barb;
        barb.y = v3_normalize(v3(plm_rng_uniform(&rng) - 0.5, 1.0, plm_rng_uniform(&rng) - 0.5));
        barb.z = v3_normalize(v3_cross(barb.y, v3(1.0, 0.2, -0.3)));
        barb.x = v3_cross(barb.y, barb.z);
        vec3 wo = v3_normalize(v3(plm_rng_uniform(&rng) - 0.5, plm_rng_uniform(&rng) - 0.3, plm_rng_uniform(&rng) - 0.5));
        plm_masking feather, m;
        plm_feather_masking(&model, &barb, NULL, wo, &feather);
        plm_feather_bsdf f;
        plm_feather_prepare_masked(&model, &barb, wo, &feather, rgb_gray(1.0), &rng, &f);
        plm_masking_eval(&p.masking, frame_to_local(&barb, wo), &m);
        assert_double_near(f.masking.w_barb, m.w_barb, 1e-12);
        assert_double_near(f.masking.w_distal, m.w_distal, 1e-12);
        assert_double_near(f.masking.w_transmission, m.w_transmission, 1e-12);
        double st = sin(p.masking.barbule_inclination), ct = cos(p.masking.barbule_inclination);
        for (int k = 0; k < 2; ++k) {
            int set = k == 0 ? PLM_FEATHER_PROXIMAL : PLM_FEATHER_DISTAL;
            if (!(f.weight[set] > 0.0))
                continue; /* a set the view does not see has no frame */
            checked[k]++;
            const frame *fb = &f.fiber_frame[set];
            double side = k == 0 ? -1.0 : 1.0;
            vec3 across = v3_add(v3_scale(barb.x, side * ct), v3_scale(barb.y, st)); /* rises at theta across b */
            vec3 row_normal = v3_cross(barb.z, across);
            assert_double_near(v3_dot(fb->z, row_normal), 0.0, 1e-12); /* the axis lies in the row */
            assert_double_near(v3_dot(fb->x, row_normal), 0.0, 1e-12); /* so does r1 */
            assert_double_near(v3_dot(fb->z, barb.z), cos(p.masking.barbule_rotation), 1e-12);
            assert_true(v3_dot(fb->z, across) > 0.0);
            assert_true(v3_dot(fb->y, barb.y) > 0.0); /* r2 on the dorsal side */
        }
    }
    assert_true(checked[0] >= 50 && checked[1] >= 50);
}

static void add_feather_sheet(plm_scene *s, const plm_feather_params *p, double curl, plm_xform x)
{
    plm_mesh mesh;
    plm_error err;
    assert_int_equal(plm_shape_quad(2.0, 2.0, curl, 32, &mesh, &err), PLM_OK);
    int mi = plm_scene_add_mesh(s, "vane", &mesh);
    plm_material m = feather_material(p, plm_radians(60.0));
    assert_true(plm_scene_add_object(s, mi, plm_scene_add_material(s, &m), x) >= 0);
}

/* Feathers (curled, seen from both sides) in a uniform white sky: radiance 1
 * up to the fiber lobes' loss, a few percent at most. */
static void furnace_scene(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    plm_feather_params p = clear_params(0);
    add_feather_sheet(&s, &p, 1.2, plm_xform_identity());
    plm_light sky = plm_constant_sky(rgb_gray(1.0));
    assert_true(plm_scene_add_light(&s, &sky) >= 0);
    s.camera = (plm_camera_desc){v3(0.4, 0.3, 2.5), v3(0, 0, -0.3), v3(0, 1, 0), 30, 0, 0, 1};
    s.film.width = s.film.height = 32;
    plm_world w;
    plm_error err;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    estimate e = film_mean(&w, PLM_ESTIMATOR_MIS, 64, 20000, 3);
    if (!(e.mean < 1.0 + 4.0 * e.se && e.mean > 0.96))
        fail_msg("furnace: %.4f +- %.4f", e.mean, e.se);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* A feather sheet between a floor and a quad light: light sampling attenuates
 * shadow rays by w_t of their direction, BSDF sampling passes the sheet with
 * that probability; both must give the same image (from below the sheet). */
static void feather_shadows_agree_with_stochastic_passing(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    plm_feather_params p;
    plm_feather_params_default(&p);
    p.masking.barbule_separation = 2.0;
    plm_xform lift = plm_xform_translate(v3(0, 0, 0.6)), tilt = plm_xform_rotate(v3(1, 0, 0), 0.3);
    plm_xform x = plm_xform_compose(&lift, &tilt);
    add_feather_sheet(&s, &p, 0.0, x);
    plm_mesh floor;
    plm_error err;
    assert_int_equal(plm_shape_quad(6, 6, 0, 1, &floor, &err), PLM_OK);
    plm_material grey = plm_diffuse_material("grey", rgb_gray(0.5), 0.0);
    assert_true(plm_scene_add_object(&s, plm_scene_add_mesh(&s, "floor", &floor), plm_scene_add_material(&s, &grey),
                                     plm_xform_identity()) >= 0);
    plm_light q = plm_quad_light(v3(-0.5, -0.5, 1.5), v3(0, 1, 0), v3(1, 0, 0), rgb_gray(5.0));
    assert_true(plm_scene_add_light(&s, &q) >= 0);
    s.camera = (plm_camera_desc){v3(0.0, -1.2, 0.35), v3(0, 0, 0), v3(0, 0, 1), 50, 0, 0, 1};
    s.film.width = s.film.height = 24;
    plm_world w;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    estimate nee = film_mean(&w, PLM_ESTIMATOR_NEE, 4, 20000, 31);
    estimate bsdf = film_mean(&w, PLM_ESTIMATOR_BSDF, 4, 60000, 32);
    assert_agree(nee, bsdf, 4.5);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* MIS weighs each fiber's term of a light sample against that fiber's own
 * sampling technique (pick_k pdf_k, the pdf plm_bsdf_sample returns): a
 * feather sheet seen from above under a quad light as wide as the sheet
 * (light samples of low density, so both techniques carry weight), with
 * barbules dense enough that barb and barbules share most views, must look
 * the same with MIS as with light sampling alone and BSDF sampling alone.
 * The test can fail: weighing the light samples by the mixture's pdf
 * instead, as before the BSDF's samples took their own fiber's, left 4%
 * too little light (6 standard errors). */
static void mis_weighs_each_fiber_against_the_light(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    plm_feather_params p;
    plm_feather_params_default(&p);
    p.masking.barbule_separation = 0.3;
    p.barb.beta_m = p.barbule.beta_m = 0.2;
    add_feather_sheet(&s, &p, 0.6, plm_xform_identity());
    plm_light q = plm_quad_light(v3(-1.5, -1.5, 1.0), v3(0, 3.0, 0), v3(3.0, 0, 0), rgb_gray(1.0));
    assert_true(plm_scene_add_light(&s, &q) >= 0);
    s.camera = (plm_camera_desc){v3(0.3, -1.0, 1.4), v3(0, 0, 0), v3(0, 0, 1), 40, 0, 0, 1};
    s.film.width = s.film.height = 24;
    plm_world w;
    plm_error err;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    assert_estimators_agree(&w, 2, 40000, 51, "feather under a wide quad light");
    plm_world_free(&w);
    plm_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(barb_frame_follows_texture_and_tip),
        cmocka_unit_test(texture_lookups_keep_regions_and_angles),
        cmocka_unit_test(four_channel_textures_read_as_three),
        cmocka_unit_test(pigment_tints_vane_texels),
        cmocka_unit_test(white_furnace_of_the_bsdf),
        cmocka_unit_test(sampling_matches_pdf),
        cmocka_unit_test(tabulated_sampling_matches_pdf_at_grazing_views),
        cmocka_unit_test(prepared_bsdf_is_reproducible_by_seed),
        cmocka_unit_test(sampled_weights_estimate_the_mixture),
        cmocka_unit_test(barbule_fibers_lie_in_the_tilted_rows),
        cmocka_unit_test(furnace_scene),
        cmocka_unit_test(feather_shadows_agree_with_stochastic_passing),
        cmocka_unit_test(mis_weighs_each_fiber_against_the_light),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
