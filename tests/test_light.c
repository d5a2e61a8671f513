/* Environment maps and the sky as lights: their sampling against their
 * densities (chi-square), the integral of their radiance by importance
 * sampling against quadrature, a white furnace inside a constant map, light
 * and BSDF sampling agreeing under a map with one bright texel, the camera
 * switch, and next-event estimation's choice among lights. */
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

#include "render/render.h"
#include "render/scene_build.h"
#include "tests/chi_square.h"
#include "test_render_stats.h"

/* A w x h lat-long map of grey `base` with texel (bx, by) at `bright`; rows
 * of a zero band hold 0 (bilinear radiance still reaches into them). */
static plm_light grey_map(int w, int h, double base, int bx, int by, double bright, int zero_row)
{
    plm_light l = plm_light_default(PLM_LIGHT_ENV_MAP);
    l.image.width = w, l.image.height = h, l.image.channels = 3;
    l.image.pixels = malloc(sizeof(float) * 3 * (size_t)w * h);
    assert_non_null(l.image.pixels);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                l.image.pixels[3 * (y * w + x) + c] =
                    (float)(x == bx && y == by ? bright * (1.0 + 0.2 * c) : (y == zero_row ? 0.0 : base));
    return l;
}

/* A sky light with a visible sun. */
static plm_light test_sky(double elevation_deg, double azimuth_deg, double sun_size_deg)
{
    plm_light l = plm_light_default(PLM_LIGHT_SKY);
    l.sky.sun_elevation = plm_radians(elevation_deg);
    l.sky.sun_azimuth = plm_radians(azimuth_deg);
    l.sky.sun_size = plm_radians(sun_size_deg);
    return l;
}

/* The direction of lat-long (u, v) in the light's frame. */
static vec3 direction_at(const plm_render_light *rl, double u, double v)
{
    return plm_envmap_direction(&rl->axes, v2(u, v));
}

/* Chi-square of light samples against the light's own density, on a G x G/2
 * grid in the light's lat-long (u, v): each cell's expected count is N
 * times the integral of plm_light_pdf over it (midpoint rule on S x S
 * sub-cells: exact for a grid density whose cells the grid refines, within
 * a fraction of a standard error at the edge of a sun's disk). */
static void assert_samples_follow_pdf(const plm_render_light *rl, const char *what)
{
    enum { G = 64, S = 24, N = 400000 };
    static double observed[G * G / 2], expected[G * G / 2];
    memset(observed, 0, sizeof observed);
    for (int cy = 0; cy < G / 2; ++cy)
        for (int cx = 0; cx < G; ++cx) {
            double sum = 0.0;
            for (int sy = 0; sy < S; ++sy)
                for (int sx = 0; sx < S; ++sx) {
                    double u = (cx + (sx + 0.5) / S) / G, v = (cy + (sy + 0.5) / S) / (G / 2);
                    double solid = (PLM_TWO_PI / (G * S)) * (PLM_PI / (G / 2 * S)) * sin(PLM_PI * v);
                    sum += plm_light_pdf(rl, v3(0, 0, 0), direction_at(rl, u, v)) * solid;
                }
            expected[cy * G + cx] = N * sum;
        }
    plm_rng rng;
    plm_rng_seed(&rng, 17, 1);
    for (int i = 0; i < N; ++i) {
        plm_light_sample ls;
        assert_true(plm_light_sample_from(rl, v3(0, 0, 0), plm_rng_uniform(&rng), plm_rng_uniform(&rng), &ls));
        assert_double_near(plm_light_pdf(rl, v3(0, 0, 0), ls.wi), ls.pdf, 1e-6 * ls.pdf);
        vec2 uv = plm_envmap_uv(&rl->axes, ls.wi);
        int cx = (int)(uv.x * G), cy = (int)(uv.y * G / 2);
        observed[(cy < G / 2 ? cy : G / 2 - 1) * G + (cx < G ? cx : G - 1)] += 1.0;
    }
    double pv = chi_square_test(observed, expected, G * G / 2);
    fprintf(stderr, "%s: chi-square p-value %.4f\n", what, pv);
    if (!(pv > 0.01))
        fail_msg("%s: light samples do not follow plm_light_pdf (p %.5f)", what, pv);
}

/* Whether d lies in the sky's sun disk (never for other lights). */
static int in_sun(const plm_render_light *rl, vec3 d)
{
    return rl->desc->type == PLM_LIGHT_SKY && rl->sun_pick > 0.0 &&
           v3_dot(frame_to_local(&rl->axes, d), rl->sky.sun) >= rl->sky.cos_sun_radius;
}

/* The integral of the light's luminance over the sphere by importance
 * sampling against quadrature (midpoint on a fine lat-long grid), within 4
 * standard errors, and the density's integral against 1, by uniform
 * directions. A sun's disk is too small for either grid or uniform
 * directions: they leave it out and add its irradiance and its share of the
 * density (sun_pick; the grid's share inside it is below 1e-4). */
static void assert_integral_and_unit_density(const plm_render_light *rl, const char *what)
{
    enum { GU = 1024, GV = 512, N = 200000 };
    int sun = rl->desc->type == PLM_LIGHT_SKY && rl->sun_pick > 0.0;
    double quadrature = sun ? rgb_luminance(rgb_mul(rl->scale, rl->sky.sun_irradiance)) : 0.0;
    for (int y = 0; y < GV; ++y)
        for (int x = 0; x < GU; ++x) {
            double v = (y + 0.5) / GV, solid = (PLM_TWO_PI / GU) * (PLM_PI / GV) * sin(PLM_PI * v);
            vec3 d = direction_at(rl, (x + 0.5) / GU, v);
            if (!in_sun(rl, d))
                quadrature += rgb_luminance(plm_light_environment(rl, d, NULL)) * solid;
        }
    plm_rng rng;
    plm_rng_seed(&rng, 23, 1);
    double sum = 0.0, sum2 = 0.0, density = 0.0, density2 = 0.0;
    for (int i = 0; i < N; ++i) {
        plm_light_sample ls;
        assert_true(plm_light_sample_from(rl, v3(0, 0, 0), plm_rng_uniform(&rng), plm_rng_uniform(&rng), &ls));
        double f = rgb_luminance(ls.radiance) / ls.pdf;
        sum += f, sum2 += f * f;
        vec3 u = plm_sample_uniform_sphere(plm_rng_uniform(&rng), plm_rng_uniform(&rng));
        double p = in_sun(rl, u) ? 0.0 : plm_light_pdf(rl, v3(0, 0, 0), u) * 4.0 * PLM_PI;
        density += p, density2 += p * p;
    }
    estimate is = iid_estimate(sum, sum2, N), unit = iid_estimate(density, density2, N);
    double sun_share = sun ? rl->sun_pick : 0.0;
    fprintf(stderr, "%s: integral %.6g +- %.2g by sampling, %.6g by quadrature; density integral %.4f +- %.4f "
            "besides the sun's %.4f\n", what, is.mean, is.se, quadrature, unit.mean, unit.se, sun_share);
    assert_agree(is, (estimate){quadrature, 0.0}, 4.0);
    assert_agree(unit, (estimate){1.0 - sun_share, 0.0}, 4.0);
}

/* Sampling an environment map: samples follow its density, even with a
 * texel 10^4 times the rest and a row of zeros; the density covers the
 * bilinear radiance (the importance-sampled integral is right). */
static void environment_map_sampling(void **state)
{
    (void)state;
    plm_light map = grey_map(8, 4, 0.1, 5, 1, 1000.0, 3);
    map.rotation = 0.4;
    map.up = v3_normalize(v3(0.2, 1.0, 0.3));
    plm_render_light rl;
    plm_error err;
    assert_int_equal(plm_render_light_init(&map, &rl, &err), PLM_OK);
    assert_samples_follow_pdf(&rl, "8x4 map, one bright texel");
    assert_integral_and_unit_density(&rl, "8x4 map, one bright texel");
    /* No direction whose radiance is not zero has density zero (else light sampling would miss it). */
    for (int y = 0; y < 200; ++y)
        for (int x = 0; x < 400; ++x) {
            vec3 d = direction_at(&rl, (x + 0.5) / 400, (y + 0.5) / 200);
            double pdf;
            rgb le = plm_light_environment(&rl, d, &pdf);
            assert_true(pdf > 0.0 || rgb_is_black(le));
        }
    plm_render_light_free(&rl);
    free(map.image.pixels);
}

/* Sampling the sky: a mixture of its grid and its sun's disk, whose radiance
 * is 10^5 times the sky's; with a small sun the disk holds the cells'
 * share too narrowly for a chi-square, so that one uses a large sun. */
static void sky_sampling(void **state)
{
    (void)state;
    plm_light sky = test_sky(35.0, 120.0, 12.0);
    sky.up = v3_normalize(v3(0.0, 0.3, 1.0));
    plm_render_light rl;
    plm_error err;
    assert_int_equal(plm_render_light_init(&sky, &rl, &err), PLM_OK);
    assert_true(rl.sun_pick > 0.2 && rl.sun_pick < 0.99);
    assert_samples_follow_pdf(&rl, "sky, 12 degree sun");
    plm_render_light_free(&rl);

    /* The real sun. */
    sky = test_sky(35.0, 120.0, 0.53);
    assert_int_equal(plm_render_light_init(&sky, &rl, &err), PLM_OK);
    assert_integral_and_unit_density(&rl, "sky and sun");
    plm_render_light_free(&rl);
    sky.sky.sun = 0;
    assert_int_equal(plm_render_light_init(&sky, &rl, &err), PLM_OK);
    assert_double_near(rl.sun_pick, 0.0, 0.0);
    assert_integral_and_unit_density(&rl, "sky without its sun");
    plm_render_light_free(&rl);
}

/* White furnace inside a constant environment map (the map's own code
 * path: bilinear lookups, the grid density, MIS): a white, partly
 * transmissive, strongly curled surface has the map's radiance everywhere. */
static void white_furnace_in_a_constant_map(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    plm_mesh m;
    plm_error err;
    assert_int_equal(plm_shape_quad(2.0 * PLM_PI * 0.9, 6.0, 1.0, 64, &m, &err), PLM_OK);
    plm_material white = plm_diffuse_material("white", rgb_gray(1.0), 0.2);
    assert_true(plm_scene_add_object(&s, plm_scene_add_mesh(&s, "cup", &m), plm_scene_add_material(&s, &white),
                                     plm_xform_identity()) >= 0);
    plm_light map = grey_map(16, 8, 0.7, -1, -1, 0.0, -1);
    map.rotation = 1.0;
    assert_true(plm_scene_add_light(&s, &map) >= 0);
    s.camera = (plm_camera_desc){v3(0.0, 0.3, -4.0), v3(0, 0, -1), v3(0, 1, 0), 12, 0, 0, 1};
    s.film.width = s.film.height = 32;
    plm_world w;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    estimate e = film_mean(&w, PLM_ESTIMATOR_MIS, 256, 20000, 5);
    fprintf(stderr, "furnace in a constant map of 0.7: %.5f +- %.5f\n", e.mean, e.se);
    assert_agree(e, (estimate){0.7, 0.0}, 4.0);
    assert_true(fabs(e.mean / 0.7 - 1.0) < 0.01);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* A diffuse floor and ball under a map with one bright texel: MIS, light
 * sampling alone and BSDF sampling alone estimate the same image. */
static void light_and_bsdf_sampling_agree_under_a_bright_texel(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    plm_mesh floor, ball;
    plm_error err;
    assert_int_equal(plm_shape_quad(20, 20, 0, 1, &floor, &err), PLM_OK);
    assert_int_equal(plm_shape_sphere(0.5, 32, &ball, &err), PLM_OK);
    plm_material grey = plm_diffuse_material("grey", rgb_make(0.6, 0.5, 0.4), 0.0);
    int mg = plm_scene_add_material(&s, &grey);
    assert_true(plm_scene_add_object(&s, plm_scene_add_mesh(&s, "floor", &floor), mg, plm_xform_floor(0)) >= 0);
    assert_true(plm_scene_add_object(&s, plm_scene_add_mesh(&s, "ball", &ball), mg,
                                     plm_xform_translate(v3(0, 0.5, 0))) >= 0);
    /* A texel 150 times the rest, 0 to 45 degrees up: most of the light. */
    plm_light map = grey_map(8, 4, 0.2, 2, 1, 30.0, 3);
    assert_true(plm_scene_add_light(&s, &map) >= 0);
    s.camera = (plm_camera_desc){v3(0, 1.5, 3.0), v3(0, 0.3, 0), v3(0, 1, 0), 50, 0, 0, 1};
    s.film.width = 32, s.film.height = 24;
    plm_world w;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    estimate mis = assert_estimators_agree(&w, 4, 20000, 31, "one bright texel");
    assert_true(mis.se < 0.02 * mis.mean);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* visible = false: camera rays see black where the sky was, while the
 * floor it lights is as bright as with the sky in view. */
static void a_hidden_sky_still_lights(void **state)
{
    (void)state;
    estimate sky[2], floor[2];
    for (int visible = 0; visible < 2; ++visible) {
        plm_scene s;
        plm_scene_init(&s);
        plm_mesh floor_mesh;
        plm_error err;
        assert_int_equal(plm_shape_quad(200, 200, 0, 1, &floor_mesh, &err), PLM_OK);
        plm_material grey = plm_diffuse_material("grey", rgb_gray(0.5), 0.0);
        assert_true(plm_scene_add_object(&s, plm_scene_add_mesh(&s, "floor", &floor_mesh),
                                         plm_scene_add_material(&s, &grey), plm_xform_floor(0)) >= 0);
        plm_light l = test_sky(40.0, 30.0, 0.53);
        l.visible = visible;
        assert_true(plm_scene_add_light(&s, &l) >= 0);
        /* Looking at the horizon: the upper half of the film is sky. */
        s.camera = (plm_camera_desc){v3(0, 1, 0), v3(0, 1, -10), v3(0, 1, 0), 30, 0, 0, 1};
        s.film.width = s.film.height = 16;
        plm_world w;
        assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
        sky[visible] = film_region_mean(&w, PLM_ESTIMATOR_MIS, 4, 4000, 3, 0.0, 0.0, 1.0, 0.4);
        floor[visible] = film_region_mean(&w, PLM_ESTIMATOR_MIS, 4, 4000, 4, 0.0, 0.6, 1.0, 1.0);
        plm_world_free(&w);
        plm_scene_free(&s);
    }
    assert_double_near(sky[0].mean, 0.0, 0.0);
    assert_true(sky[1].mean > 0.01);
    assert_agree(floor[0], floor[1], 4.0);
}

/* The shadow catcher: camera rays that reach the ground see the background
 * times the share of the light that reaches it. Under a constant sky L and
 * a sun E straight overhead, a ground point 1 below the centre of a ball of
 * radius r loses the sun and the sky's cap of sin^2 = r^2: the share kept is
 * 1 - (pi L r^2 + E) / (pi L + E); away from the ball every sample is the
 * background itself. */
static void the_ground_catches_shadows(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    plm_mesh ball;
    plm_error err;
    assert_int_equal(plm_shape_sphere(0.3, 128, &ball, &err), PLM_OK);
    plm_material grey = plm_diffuse_material("grey", rgb_gray(0.5), 0.0);
    assert_true(plm_scene_add_object(&s, plm_scene_add_mesh(&s, "ball", &ball), plm_scene_add_material(&s, &grey),
                                     plm_xform_translate(v3(0, 1, 0))) >= 0);
    plm_light sky = plm_constant_sky(rgb_gray(0.5)), sun = plm_light_default(PLM_LIGHT_DISTANT);
    sky.ground = 1;
    sun.irradiance = rgb_gray(2.0);
    assert_true(plm_scene_add_light(&s, &sky) >= 0 && plm_scene_add_light(&s, &sun) >= 0);
    plm_world w;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    assert_true(w.ground.enabled);
    double sum = 0.0, sum2 = 0.0;
    enum { N = 40000 };
    for (int i = 0; i < N; ++i) {
        plm_rng rng;
        plm_rng_seed(&rng, 77, (uint64_t)i);
        long long rays = 0;
        /* From beside the ball down to the point under it, and 100 away (where the ball is 3e-5 sr). */
        double v = rgb_mean(plm_path_radiance(&w, v3(2, 1, 0), v3_normalize(v3(-2, -1, 0)), 4, PLM_ESTIMATOR_MIS,
                                              NULL, &rng, &rays));
        sum += v, sum2 += v * v;
        rgb far = plm_path_radiance(&w, v3(99, 1, 0), v3_normalize(v3(1, -1, 0)), 4, PLM_ESTIMATOR_MIS, NULL, &rng,
                                    &rays);
        assert_double_near(far.g, 0.5, 1e-12);
    }
    double l = 0.5, e = 2.0, want = l * (1.0 - (PLM_PI * l * 0.09 + e) / (PLM_PI * l + e));
    estimate under = iid_estimate(sum, sum2, N);
    fprintf(stderr, "ground under the ball: %.5f +- %.5f, expected %.5f\n", under.mean, under.se, want);
    assert_agree(under, (estimate){want, 0.002 * want}, 4.0);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* Next-event estimation picks lights in proportion to the light each
 * brings: a dim constant sky (pi L) and a distant light (its irradiance). */
static void lights_are_picked_by_the_light_they_bring(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    plm_light sky = plm_constant_sky(rgb_gray(0.02)), sun = plm_light_default(PLM_LIGHT_DISTANT);
    sun.irradiance = rgb_gray(8.0);
    assert_true(plm_scene_add_light(&s, &sky) >= 0 && plm_scene_add_light(&s, &sun) >= 0);
    plm_world w;
    plm_error err;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    double sky_power = PLM_PI * 0.02;
    assert_double_near(plm_world_light_pick(&w, 0), sky_power / (sky_power + 8.0), 1e-12);
    assert_double_near(plm_world_light_pick(&w, 1), 8.0 / (sky_power + 8.0), 1e-12);
    assert_int_equal(plm_world_pick_light(&w, 0.0), 0);
    assert_int_equal(plm_world_pick_light(&w, 0.5), 1);
    plm_world_free(&w);
    plm_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(environment_map_sampling),
        cmocka_unit_test(sky_sampling),
        cmocka_unit_test(white_furnace_in_a_constant_map),
        cmocka_unit_test(light_and_bsdf_sampling_agree_under_a_bright_texel),
        cmocka_unit_test(a_hidden_sky_still_lights),
        cmocka_unit_test(the_ground_catches_shadows),
        cmocka_unit_test(lights_are_picked_by_the_light_they_bring),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
