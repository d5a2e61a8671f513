/* Long validations of the feather BSDF and the renderer (label slow):
 * chi-square of sample against pdf and the white furnace over random
 * feathers and views (both sides of the vane), and the three estimators
 * agreeing on a pelt of instanced, partly transparent feathers. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include "render/render.h"
#include "render/scene_build.h"
#include "test_feather_bsdf_stats.h"
#include "test_render_stats.h"

enum { CONFIGS = 40 };

static double uniform(plm_rng *rng, double lo, double hi) { return lo + (hi - lo) * plm_rng_uniform(rng); }

/* A random feather over the paper's explored ranges; clear = no absorption, white medulla. */
static plm_feather_params random_params(plm_rng *rng, int clear)
{
    for (;;) {
        plm_feather_params p;
        plm_feather_params_default(&p);
        p.masking.barb_eccentricity = uniform(rng, 1.0, 3.0);
        p.masking.barbule_eccentricity = uniform(rng, 1.0, 3.0);
        p.masking.barbule_length = uniform(rng, 1.0, 4.0);
        p.masking.barbule_separation = uniform(rng, 0.1, 3.0);
        p.masking.barbule_inclination = plm_radians(uniform(rng, -60.0, 60.0));
        p.masking.barbule_rotation = plm_radians(uniform(rng, 30.0, 60.0));
        plm_fiber_params *f[2] = {&p.barb, &p.barbule};
        for (int k = 0; k < 2; ++k) {
            f[k]->eccentricity = uniform(rng, 1.0, 2.0);
            f[k]->beta_m = uniform(rng, 0.1, 0.4);
            f[k]->beta_n = uniform(rng, 0.1, 0.4);
            f[k]->sigma_a = clear ? rgb_gray(0.0) : rgb_make(uniform(rng, 0, 2), uniform(rng, 0, 2), uniform(rng, 0, 2));
        }
        double r = uniform(rng, 0.0, 0.6);
        p.barb.medulla_a = p.barb.medulla_b = r;
        p.barb.medulla_ca = uniform(rng, -0.2, 0.2);
        p.barb.medulla_cb = uniform(rng, -0.2, 0.2);
        p.barb.medulla_reflectance = clear ? rgb_gray(1.0) : rgb_make(uniform(rng, 0, 1), uniform(rng, 0, 1), 1.0);
        if (r == 0.0)
            p.barb.medulla_ca = p.barb.medulla_cb = 0.0;
        plm_error err;
        if (plm_feather_params_validate(&p, &err) == PLM_OK)
            return p;
    }
}

/* A random feather material on the plane and a view from anywhere (either side). */
static plm_material random_case(plm_rng *rng, int clear, vec3 *wo)
{
    plm_feather_params p = random_params(rng, clear);
    plm_material m = feather_material(&p, uniform(rng, 0.3, 2.8));
    *wo = plm_sample_uniform_sphere(plm_rng_uniform(rng), plm_rng_uniform(rng));
    return m;
}

static void sampling_matches_pdf_over_random_feathers(void **state)
{
    (void)state;
    const double threshold = chi_square_sidak(0.01, CONFIGS);
    plm_rng rng;
    plm_rng_seed(&rng, 2024, 1);
    for (int c = 0; c < CONFIGS; ++c) {
        vec3 wo;
        plm_material m = random_case(&rng, 0, &wo);
        plm_prepared_material prepared;
        plm_hit hit = plane_hit(&m, &prepared);
        plm_bsdf b;
        plm_material_bsdf(&hit, wo, &rng, &b);
        const plm_feather_bsdf *f = (const plm_feather_bsdf *)b.state;
        if (f->pick[0] + f->pick[1] + f->pick[2] > 0.0) {
            double pv = chi_square(&b, &rng, 300000);
            fprintf(stderr, "config %2d: view (%.2f, %.2f, %.2f), w_t %.3f, p-value %.4f\n", c, wo.x, wo.y, wo.z,
                    f->masking.w_transmission, pv);
            if (!(pv > threshold))
                fail_msg("config %d: p-value %.6f below %.6f", c, pv, threshold);
        }
        free_material(&m);
    }
}

static void white_furnace_over_random_feathers(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 77, 2);
    double albedo_sum = 0.0;
    for (int c = 0; c < CONFIGS; ++c) {
        vec3 wo;
        plm_material m = random_case(&rng, 1, &wo);
        plm_prepared_material prepared;
        plm_hit hit = plane_hit(&m, &prepared);
        char label[32];
        snprintf(label, sizeof label, "config %d", c);
        albedo_sum += furnace_albedo(&hit, wo, &rng, 1000000, 4.5, label);
        free_material(&m);
    }
    assert_true(albedo_sum / CONFIGS > 0.95);
}

/* 100 feathers (vane quads with a feather texture whose corners are cut
 * away) lying like tiles over a floor, as `plumage bench render` lays its
 * pelt, under a sky and a quad light. */
static void estimators_agree_on_a_pelt(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    plm_rng rng;
    plm_rng_seed(&rng, 9, 9);
    plm_feather_params p = random_params(&rng, 0);
    plm_material m = feather_material(&p, 1.0);
    for (int y = 0; y < 4; ++y) /* cut the corners away: background texels */
        for (int x = 0; x < 4; ++x)
            if ((x == 0 || x == 3) && (y == 0 || y == 3))
                m.texture.region[y * 4 + x] = PLM_REGION_BACKGROUND;
    plm_mesh quad;
    plm_error err;
    assert_int_equal(plm_shape_quad(0.5, 1.0, 1.0, 16, &quad, &err), PLM_OK);
    plm_tile_feather vane = {1, {plm_scene_add_mesh(&s, "vane", &quad)}, {plm_scene_add_material(&s, &m)}, 1.0};
    assert_true(plm_scene_add_ground(&s, 20.0, rgb_gray(0.4), &err) >= 0);
    assert_true(plm_scene_add_feather_tiles(&s, &vane, 100, 0.3, 9));
    plm_light lights[2] = {plm_quad_light(v3(-1, 3, -1), v3(2, 0, 0), v3(0, 0, 2), rgb_gray(3.0)),
                           plm_constant_sky(rgb_make(0.3, 0.4, 0.5))};
    for (int i = 0; i < 2; ++i)
        assert_true(plm_scene_add_light(&s, &lights[i]) >= 0);
    s.camera = (plm_camera_desc){v3(0, 2.5, 3.5), v3(0, 0, 0), v3(0, 1, 0), 45, 0, 0, 1};
    s.film.width = 64, s.film.height = 48;
    plm_world w;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    assert_estimators_agree(&w, 8, 300000, 1, "pelt");
    plm_world_free(&w);
    plm_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sampling_matches_pdf_over_random_feathers),
        cmocka_unit_test(white_furnace_over_random_feathers),
        cmocka_unit_test(estimators_agree_on_a_pelt),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
