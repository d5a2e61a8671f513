/* The path tracer against answers known in advance: analytic scenes, a
 * furnace, estimators that must agree, transparent shadows, the mask
 * filters, light sampling densities, and bit-identical images at any thread
 * count. Statistical checks use a z-test on independent samples. */
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
#include "common/sampling.h"
#include "render/scene_build.h"
#include "tests/chi_square.h"
#include "test_render_stats.h"

/* ---------- scene building ---------- */

static int add_quad_mesh(plm_scene *s, const char *name, double w, double h, double curl)
{
    plm_mesh m;
    plm_error err;
    assert_int_equal(plm_shape_quad(w, h, curl, 64, &m, &err), PLM_OK);
    return plm_scene_add_mesh(s, name, &m);
}

static int add_sphere_mesh(plm_scene *s, const char *name, double r)
{
    plm_mesh m;
    plm_error err;
    assert_int_equal(plm_shape_sphere(r, 48, &m, &err), PLM_OK);
    return plm_scene_add_mesh(s, name, &m);
}

static int add_diffuse(plm_scene *s, const char *name, rgb reflectance, double transmission)
{
    plm_material m = plm_diffuse_material(name, reflectance, transmission);
    return plm_scene_add_material(s, &m);
}

static void add_object(plm_scene *s, int mesh, int material, plm_xform x)
{
    assert_true(plm_scene_add_object(s, mesh, material, x) >= 0);
}

static void add_light(plm_scene *s, plm_light l) { assert_true(plm_scene_add_light(s, &l) >= 0); }

static plm_light constant_env(double radiance) { return plm_constant_sky(rgb_gray(radiance)); }

static void look(plm_scene *s, vec3 from, vec3 at, vec3 up, double fov, int width, int height, int spp)
{
    s->camera.position = from;
    s->camera.look_at = at;
    s->camera.up = up;
    s->camera.fov = fov;
    s->camera.given = 1;
    s->film.width = width;
    s->film.height = height;
    s->film.spp = spp;
}

static double film_channel_mean(const plm_film *f, int c)
{
    double sum = 0.0;
    for (int i = 0; i < f->width * f->height; ++i)
        sum += f->rgb[3 * i + c];
    return sum / (f->width * f->height);
}

/* ---------- tests ---------- */

/* A diffuse plane under a constant environment L reflects albedo * L (it
 * sees only the sky's upper half: E = pi L, and (albedo / pi) E). */
static void diffuse_plane_under_constant_sky(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    rgb albedo = rgb_make(0.8, 0.5, 0.2);
    add_object(&s, add_quad_mesh(&s, "floor", 200, 200, 0), add_diffuse(&s, "d", albedo, 0.0), plm_xform_floor(0));
    add_light(&s, constant_env(1.5));
    look(&s, v3(0, 3, 0), v3(0, 0, 0), v3(0, 0, -1), 30, 24, 24, 32);
    plm_world w;
    plm_error err;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    estimate e = film_mean(&w, PLM_ESTIMATOR_MIS, 4, 40000, 1);
    estimate expected = {rgb_mean(albedo) * 1.5, 0.0};
    assert_agree(e, expected, 4.0);
    assert_true(fabs(e.mean / expected.mean - 1.0) < 0.01);

    plm_render_options opt = {0};
    plm_film film;
    assert_int_equal(plm_render_world(&w, &opt, &film, &err), PLM_OK);
    assert_int_equal(film.nonfinite, 0);
    assert_false(film.interrupted);
    double want[3] = {albedo.r * 1.5, albedo.g * 1.5, albedo.b * 1.5};
    for (int c = 0; c < 3; ++c)
        assert_true(fabs(film_channel_mean(&film, c) / want[c] - 1.0) < 0.02);
    plm_film_free(&film);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* The pixel filter, from first principles: a black half-plane whose edge
 * falls on a pixel boundary, against a sky of radiance 1. A box filter (the
 * default) gives columns of exactly 0 and 1; a tent of radius 1 pixel
 * reaches half a pixel across the edge from the two columns beside it, so
 * each takes (1 - 1/2)^2 / 2 = 1/8 of the other side's radiance (0.125 and
 * 0.875), and every column further away stays pure. Stratified samples
 * through the tent's inverse distribution: within 0.01 at 256 spp. */
static void pixel_filter_box_and_tent(void **state)
{
    (void)state;
    for (int tent = 0; tent < 2; ++tent) {
        plm_scene s;
        plm_scene_init(&s);
        plm_xform left = plm_xform_translate(v3(-10.0, 0.0, 0.0));
        add_object(&s, add_quad_mesh(&s, "half", 20, 20, 0), add_diffuse(&s, "black", rgb_gray(0.0), 0.0), left);
        add_light(&s, constant_env(1.0));
        look(&s, v3(0, 0, 3), v3(0, 0, 0), v3(0, 1, 0), 30, 16, 4, 256);
        s.film.filter_radius = tent ? 1.0 : 0.0;
        plm_world w;
        plm_error err;
        assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
        plm_render_options opt = {0};
        plm_film film;
        assert_int_equal(plm_render_world(&w, &opt, &film, &err), PLM_OK);
        int dark_first = film.rgb[0] < 0.5; /* which side of the image the half-plane is on */
        for (int x = 0; x < 16; ++x) {
            double expected = (x < 8) == dark_first ? 0.0 : 1.0;
            if (tent && (x == 7 || x == 8))
                expected = expected == 0.0 ? 0.125 : 0.875;
            for (int y = 0; y < 4; ++y)
                assert_double_near(film.rgb[3 * (y * 16 + x) + 1], expected, tent ? 0.01 : 1e-12);
        }
        plm_film_free(&film);
        plm_world_free(&w);
        plm_scene_free(&s);
    }
}

/* Under a distant light of irradiance E at 60 degrees from the normal, every
 * sample is exact: albedo / pi * E cos(60). */
static void diffuse_plane_under_distant_light(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    rgb albedo = rgb_make(0.5, 0.25, 0.75);
    add_object(&s, add_quad_mesh(&s, "floor", 200, 200, 0), add_diffuse(&s, "d", albedo, 0.0), plm_xform_floor(0));
    plm_light sun = plm_light_default(PLM_LIGHT_DISTANT);
    sun.direction = v3(sin(PLM_PI / 3), cos(PLM_PI / 3), 0.0);
    sun.irradiance = rgb_make(2.0, 3.0, 1.0);
    add_light(&s, sun);
    look(&s, v3(0, 3, 0), v3(0, 0, 0), v3(0, 0, -1), 30, 16, 16, 4);
    plm_render_options opt = {0};
    plm_film film;
    plm_error err;
    assert_int_equal(plm_render(&s, &opt, &film, &err), PLM_OK);
    double want[3] = {albedo.r / PLM_PI * 2.0 * 0.5, albedo.g / PLM_PI * 3.0 * 0.5, albedo.b / PLM_PI * 1.0 * 0.5};
    for (int i = 0; i < 16 * 16; ++i)
        for (int c = 0; c < 3; ++c)
            assert_double_near(film.rgb[3 * i + c], want[c], 1e-5 * want[c]);
    assert_int_equal(film.nonfinite, 0);
    plm_film_free(&film);
    plm_scene_free(&s);
}

/* A small lat-long map with a bright patch, for the environment-map tests. */
static plm_light test_env_map(void)
{
    plm_light l = plm_light_default(PLM_LIGHT_ENV_MAP);
    l.rotation = 0.3;
    plm_image *im = &l.image;
    im->width = 32, im->height = 16, im->channels = 3;
    im->pixels = malloc(sizeof(float) * 32 * 16 * 3);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) {
            float *p = im->pixels + 3 * (y * 32 + x);
            int sun = x >= 20 && x < 23 && y >= 3 && y < 5;
            p[0] = sun ? 40.0f : 0.2f + 0.02f * x;
            p[1] = sun ? 30.0f : 0.3f;
            p[2] = sun ? 20.0f : 0.5f - 0.02f * y;
        }
    return l;
}

/* A diffuse floor with a ball, lit by a quad light, a sphere light and an
 * environment map: a scene on which every estimator must agree. */
static void lit_room(plm_scene *s, double sheet_transmission)
{
    plm_scene_init(s);
    add_object(s, add_quad_mesh(s, "floor", 20, 20, 0), add_diffuse(s, "grey", rgb_make(0.6, 0.5, 0.4), 0.0),
               plm_xform_floor(0));
    plm_xform ball = plm_xform_translate(v3(0.3, 0.5, 0.0));
    add_object(s, add_sphere_mesh(s, "ball", 0.5), add_diffuse(s, "red", rgb_make(0.7, 0.2, 0.2), 0.0), ball);
    if (sheet_transmission > 0.0) /* a perforated sheet over everything */
        add_object(s, add_quad_mesh(s, "sheet", 4, 4, 0),
                   add_diffuse(s, "sheet", rgb_gray(0.3), sheet_transmission), plm_xform_floor(1.5));
    /* edge_u x edge_v points down */
    add_light(s, plm_quad_light(v3(-0.6, 2.5, -0.6), v3(1.2, 0, 0), v3(0, 0, 1.2), rgb_make(4, 4, 3)));
    plm_light sp = plm_light_default(PLM_LIGHT_SPHERE);
    sp.center = v3(-2, 1.2, 1);
    sp.radius = 0.4;
    sp.radiance = rgb_make(2, 3, 4);
    add_light(s, sp);
    add_light(s, test_env_map());
    look(s, v3(0, 1.0, 3.0), v3(0, 0.3, 0), v3(0, 1, 0), 50, 32, 24, 8);
}

static void estimators_agree(void **state)
{
    (void)state;
    plm_scene s;
    lit_room(&s, 0.0);
    plm_world w;
    plm_error err;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    estimate mis = assert_estimators_agree(&w, 6, 30000, 11, "lit room");
    assert_true(mis.se < 0.02 * mis.mean);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* Under a perforated sheet, light sampling sees the sheet as a transparent
 * shadow (attenuated by its transmission) while BSDF sampling passes it
 * stochastically; both estimate the same image. */
static void transparent_shadows_agree_with_stochastic_passing(void **state)
{
    (void)state;
    plm_scene s;
    lit_room(&s, 0.6);
    look(&s, v3(0, 1.0, 3.0), v3(0, 0.3, 0), v3(0, 1, 0), 50, 32, 24, 8);
    plm_world w;
    plm_error err;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    assert_true(w.transmissive);
    estimate nee = film_mean(&w, PLM_ESTIMATOR_NEE, 6, 30000, 21);
    estimate bsdf = film_mean(&w, PLM_ESTIMATOR_BSDF, 6, 60000, 22);
    estimate mis = film_mean(&w, PLM_ESTIMATOR_MIS, 6, 30000, 23);
    assert_agree(nee, bsdf, 4.5);
    assert_agree(mis, bsdf, 4.5);
    /* Direct attenuation is exactly the transmission for one sheet. */
    double o = 0.0;
    assert_true(plm_world_intersect(&w, v3(0, 3, 0), v3(0, -1, 0), INFINITY, &o, &(plm_hit){0}));
    assert_double_near(plm_shadow_transmittance(&w, v3(0.1, 1.0, 0.1), v3(0, 1, 0), INFINITY, &(long long){0}), 0.6, 1e-12);
    assert_double_near(plm_shadow_transmittance(&w, v3(0.3, 0.1, 0.0), v3(0, 1, 0), INFINITY, &(long long){0}), 0.0, 0.0);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* A plm_passing draw that counts its calls and gives its seed and shift. */
typedef struct counted_numbers {
    int draws;
    uint64_t seed;
    double shift;
} counted_numbers;

static void draw_counted(void *arg, uint64_t *seed, double *shift)
{
    counted_numbers *c = arg;
    ++c->draws;
    *seed = c->seed;
    *shift = c->shift;
}

/* Shadow rays through a stack of partly transmissive sheets, instanced and
 * not, masked and not: the product of their transmissions, up to the first
 * opaque one; the order the filter meets them in does not matter. */
static void transmittance_through_stacked_sheets(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    int mesh = add_quad_mesh(&s, "sheet", 2, 2, 0);
    const double tr[4] = {0.9, 0.5, 0.7, 0.0};
    for (int i = 0; i < 4; ++i) {
        char name[16];
        snprintf(name, sizeof name, "m%d", i);
        add_object(&s, mesh, add_diffuse(&s, name, rgb_gray(0.5), tr[i]), plm_xform_translate(v3(0, 0, -i)));
    }
    plm_world w;
    plm_error err;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    assert_int_equal(w.prototype_count, 2); /* transmissive and opaque sheets need different filters */
    long long rays = 0;
    assert_double_near(plm_shadow_transmittance(&w, v3(0.1, 0.2, 1), v3(0, 0, -1), 1.5, &rays), 0.9, 1e-15);
    assert_double_near(plm_shadow_transmittance(&w, v3(0.1, 0.2, 1), v3(0, 0, -1), 3.5, &rays),
                       0.9 * 0.5 * 0.7, 1e-15);
    assert_double_near(plm_shadow_transmittance(&w, v3(0.1, 0.2, 1), v3(0, 0, -1), INFINITY, &rays), 0.0, 0.0);
    assert_double_near(plm_shadow_transmittance(&w, v3(0.1, 0.2, -2.5), v3(0, 0, 1), INFINITY, &rays), 0.7 * 0.5 * 0.9,
                       1e-15);
    /* Passing rays stop at sheet i with probability (1 - tr_i) times the
     * product of the transmissions before it, also when a pixel's seed is
     * kept and its samples' shifts are stratified (as the sampler does): the
     * decisions at the sheets stay independent. */
    enum { PIXELS = 4000, SHIFTS = 16 };
    double observed[4] = {0}, expected[4], reach = PIXELS * SHIFTS;
    for (int i = 0; i < 4; ++i) {
        expected[i] = reach * (1.0 - tr[i]);
        reach *= tr[i];
    }
    for (int p = 0; p < PIXELS; ++p)
        for (int k = 0; k < SHIFTS; ++k) {
            double t = 0.0;
            plm_hit hit;
            plm_passing numbers = {plm_hash64(41, (uint64_t)p, 0), (k + 0.5) / SHIFTS, NULL, NULL};
            assert_true(plm_world_intersect_passing(&w, v3(0.1, 0.2, 1), v3(0, 0, -1), INFINITY, &numbers, 0.0, &t,
                                                    &hit));
            observed[(int)lround(t) - 1] += 1.0;
        }
    double pv = chi_square_test(observed, expected, 4);
    if (!(pv > 0.01))
        fail_msg("passing: stopped at the sheets %.0f %.0f %.0f %.0f times, expected %.0f %.0f %.0f %.0f (p %.5f)",
                 observed[0], observed[1], observed[2], observed[3], expected[0], expected[1], expected[2],
                 expected[3], pv);
    /* Numbers drawn on demand: never for a ray that meets no sheet, once for
     * one that passes some, which then stops where the same numbers given up
     * front stop it. */
    for (int k = 0; k < SHIFTS; ++k) {
        counted_numbers c = {0, plm_hash64(41, 7, 0), (k + 0.5) / SHIFTS};
        double t_drawn = 0.0, t_given = 0.0;
        plm_passing drawn = {0, 0.0, draw_counted, &c}, given = {c.seed, c.shift, NULL, NULL};
        plm_hit hit;
        assert_false(plm_world_intersect_passing(&w, v3(0.1, 0.2, 1), v3(0, 0, 1), INFINITY, &drawn, 0.0, &t_drawn,
                                                 &hit));
        assert_int_equal(c.draws, 0);
        assert_true(plm_world_intersect_passing(&w, v3(0.1, 0.2, 1), v3(0, 0, -1), INFINITY, &drawn, 0.0, &t_drawn,
                                                &hit));
        assert_int_equal(c.draws, 1);
        assert_true(plm_world_intersect_passing(&w, v3(0.1, 0.2, 1), v3(0, 0, -1), INFINITY, &given, 0.0, &t_given,
                                                &hit));
        assert_double_near(t_drawn, t_given, 0.0);
    }
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* White furnace: a white, partly transmissive, strongly curled surface in a
 * uniform environment of radiance 1 has radiance 1 everywhere, at every
 * number of interreflections (roulette and MIS must stay unbiased). */
static void white_furnace(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    /* 90% of a cylinder of radius 1 about (0, y, -1), its slit facing -z; the camera looks in through the slit. */
    int mesh = add_quad_mesh(&s, "cup", 2.0 * PLM_PI * 0.9, 6.0, 1.0);
    add_object(&s, mesh, add_diffuse(&s, "white", rgb_gray(1.0), 0.2), plm_xform_identity());
    add_light(&s, constant_env(1.0));
    look(&s, v3(0.0, 0.3, -4.0), v3(0, 0, -1), v3(0, 1, 0), 12, 32, 32, 8);
    plm_world w;
    plm_error err;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    estimate e = film_mean(&w, PLM_ESTIMATOR_MIS, 256, 30000, 5);
    assert_agree(e, (estimate){1.0, 0.0}, 4.0);
    assert_true(fabs(e.mean - 1.0) < 0.01);
    plm_world_free(&w);
    plm_scene_free(&s);
}


/* ---------- the stratified sampler ---------- */

/* 64 samples of a pixel fill every grid of 64 equal cells of each pair (a
 * (0,6,2)-net: 1x64, 2x32, ... 64x1), whatever the key, and so do the first
 * 32 of 45 (the shuffle is a bijection of [0, 45), so indices 0..31 are
 * among them), with at most two per cell. */
static void sampler_fills_every_elementary_grid(void **state)
{
    (void)state;
    const uint32_t counts[2] = {64, 45};
    for (int c = 0; c < 2; ++c)
        for (uint64_t key = 1; key <= 20; ++key)
            for (uint32_t dim = 0; dim < 6; ++dim) {
                plm_sampler s = {plm_hash64(key, 5, 5), 0, counts[c]};
                vec2 p[64];
                for (s.index = 0; s.index < s.count; ++s.index) {
                    p[s.index] = plm_sampler_2d(&s, dim);
                    assert_true(p[s.index].x >= 0.0 && p[s.index].x < 1.0 && p[s.index].y >= 0.0 && p[s.index].y < 1.0);
                }
                int log_cells = counts[c] == 64 ? 6 : 5;
                for (int a = 0; a <= log_cells; ++a) {
                    int nx = 1 << a, ny = 1 << (log_cells - a), cell[64] = {0};
                    for (uint32_t i = 0; i < s.count; ++i)
                        cell[(int)(p[i].x * nx) * ny + (int)(p[i].y * ny)]++;
                    for (int k = 0; k < nx * ny; ++k)
                        if (cell[k] < 1 || cell[k] > (counts[c] == 64 ? 1 : 2))
                            fail_msg("count %u key %llu dim %u grid %dx%d: cell %d holds %d", counts[c],
                                     (unsigned long long)key, dim, nx, ny, k, cell[k]);
                }
            }
}

/* Each sample on its own is uniform in a pair and independent of another
 * pair (what keeps a render unbiased; a pixel's samples are not independent
 * of each other, which is the point): over many pixel keys, chi-square of one
 * sample's pair on a 16 x 16 grid and of the first coordinates of two pairs. */
static void sampler_samples_are_uniform_and_independent(void **state)
{
    (void)state;
    enum { N = 60000, G = 16, TESTS = 2 };
    static double observed[TESTS][G * G], expected[G * G];
    for (int i = 0; i < G * G; ++i)
        expected[i] = (double)N / (G * G);
    for (uint64_t key = 0; key < N; ++key) {
        plm_sampler s = {plm_hash64(key, 9, 9), 13, 48};
        vec2 a = plm_sampler_2d(&s, 3), b = plm_sampler_2d(&s, 4);
        observed[0][(int)(a.x * G) * G + (int)(a.y * G)] += 1.0;
        observed[1][(int)(a.x * G) * G + (int)(b.x * G)] += 1.0;
    }
    const double threshold = chi_square_sidak(0.01, TESTS);
    for (int t = 0; t < TESTS; ++t) {
        double pv = chi_square_test(observed[t], expected, G * G);
        if (!(pv > threshold))
            fail_msg("chi-square test %d: p-value %.5f below %.5f", t, pv, threshold);
    }
}

/* The renderer's stratified samples estimate the same image as independent
 * ones (under two perforated sheets: passing, where one ray's decisions at
 * the two must stay independent, transparent shadows, MIS) and with less
 * variance per sample. */
static void stratified_sampler_agrees_with_independent_samples(void **state)
{
    (void)state;
    plm_scene s;
    lit_room(&s, 0.6);
    add_object(&s, add_quad_mesh(&s, "sheet 2", 4, 4, 0), add_diffuse(&s, "sheet 2", rgb_gray(0.3), 0.5),
               plm_xform_floor(1.2));
    look(&s, v3(0, 2.5, 2.5), v3(0, 0.3, 0), v3(0, 1, 0), 50, 32, 24, 8); /* from above the sheets */
    plm_world w;
    plm_error err;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    enum { KEYS = 1500, SPP = 16 };
    estimate indep = film_mean(&w, PLM_ESTIMATOR_MIS, 6, KEYS * SPP, 31);
    estimate strat = film_mean_stratified(&w, PLM_ESTIMATOR_MIS, 6, KEYS, SPP, 32);
    assert_agree(indep, strat, 4.5);
    /* Variance of a mean of SPP samples: stratified over independent. */
    double ratio = strat.se * strat.se / (indep.se * indep.se * SPP);
    fprintf(stderr, "stratified %.5f +- %.5f, independent %.5f +- %.5f, variance ratio %.3f\n", strat.mean, strat.se,
            indep.mean, indep.se, ratio);
    assert_true(ratio < 0.7);
    plm_world_free(&w);
    plm_scene_free(&s);
}

static void render_threads(const plm_scene *s, int threads, uint64_t seed, plm_film *film)
{
    plm_render_options opt = {0};
    opt.threads = threads;
    opt.seed = (long long)seed;
    plm_error err;
    assert_int_equal(plm_render(s, &opt, film, &err), PLM_OK);
    assert_int_equal(film->nonfinite, 0);
}

static void bit_identical_at_any_thread_count(void **state)
{
    (void)state;
    plm_scene s;
    lit_room(&s, 0.5);
    look(&s, v3(0, 1.0, 3.0), v3(0, 0.3, 0), v3(0, 1, 0), 50, 37, 29, 5); /* odd sizes: partial tiles */
    plm_film a, b, c, d;
    render_threads(&s, 1, 7, &a);
    render_threads(&s, 2, 7, &b);
    render_threads(&s, 3, 7, &c);
    render_threads(&s, 2, 8, &d);
    size_t bytes = sizeof(float) * 3 * 37 * 29;
    assert_memory_equal(a.rgb, b.rgb, bytes);
    assert_memory_equal(a.rgb, c.rgb, bytes);
    assert_memory_not_equal(a.rgb, d.rgb, bytes);
    for (int i = 0; i < 37 * 29; ++i)
        assert_int_equal(a.samples[i], 5);
    plm_film_free(&a), plm_film_free(&b), plm_film_free(&c), plm_film_free(&d);
    plm_scene_free(&s);
}

/* Non-finite samples are counted and dropped, never written: a sky of
 * infinite radiance seen by half the image, a finite one lighting the rest. */
static void nonfinite_samples_are_counted_and_dropped(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    add_light(&s, constant_env(INFINITY));
    add_object(&s, add_quad_mesh(&s, "wall", 100, 100, 0), add_diffuse(&s, "black", rgb_gray(0.0), 0.0),
               plm_xform_translate(v3(50, 0, 0))); /* covers the right half of the view */
    look(&s, v3(0, 0, 5), v3(0, 0, 0), v3(0, 1, 0), 40, 16, 16, 2);
    plm_render_options opt = {0};
    plm_film f;
    plm_error err;
    assert_int_equal(plm_render(&s, &opt, &f, &err), PLM_OK);
    assert_true(f.nonfinite > 0 && f.nonfinite < f.sample_count);
    for (int i = 0; i < 16 * 16 * 3; ++i)
        assert_true(isfinite(f.rgb[i]));
    plm_film_free(&f);
    plm_scene_free(&s);
}

/* A cancelled render stops early, normalises by the samples it took and never leaves NaN. */
static void cancelled_render_keeps_what_it_took(void **state)
{
    (void)state;
    plm_scene s;
    lit_room(&s, 0.0);
    volatile sig_atomic_t cancel = 1;
    plm_render_options opt = {0};
    opt.cancel = &cancel;
    opt.spp = 64;
    plm_film f;
    plm_error err;
    assert_int_equal(plm_render(&s, &opt, &f, &err), PLM_OK);
    assert_true(f.interrupted);
    for (int i = 0; i < f.width * f.height * 3; ++i)
        assert_true(isfinite(f.rgb[i]) && f.rgb[i] >= 0.0f);
    plm_film_free(&f);
    plm_scene_free(&s);
}

/* Background texels are not there: rays pass through them (intersection
 * filter) and so do shadow rays (occlusion filter), through two instances. */
static void mask_filters_remove_background(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    int mesh = add_quad_mesh(&s, "vane", 1, 1, 0);
    plm_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "masked");
    m.reflectance = rgb_gray(0.5);
    float *px = malloc(sizeof(float) * 8 * 8 * 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            px[3 * (y * 8 + x)] = 1.0f, px[3 * (y * 8 + x) + 1] = 0.5f;
            px[3 * (y * 8 + x) + 2] = x < 4 ? 0.0f : (y < 2 ? 0.5f : 1.0f); /* left half background */
        }
    plm_error err;
    assert_int_equal(plm_feather_texture_from_pixels(8, 8, px, &m.texture, &err), PLM_OK);
    int mat = plm_scene_add_material(&s, &m);
    add_object(&s, mesh, mat, plm_xform_identity());
    add_object(&s, mesh, mat, plm_xform_translate(v3(0, 0, -2)));
    plm_world w;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    assert_int_equal(w.prototype_count, 1);
    double t;
    plm_hit hit;
    assert_false(plm_world_intersect(&w, v3(-0.25, 0, 1), v3(0, 0, -1), INFINITY, &t, &hit));
    assert_double_near(plm_world_transmittance(&w, v3(-0.25, 0, 1), v3(0, 0, -1), 10.0), 1.0, 0.0);
    assert_true(plm_world_intersect(&w, v3(0.25, 0, 1), v3(0, 0, -1), INFINITY, &t, &hit));
    assert_double_near(t, 1.0, 1e-5);
    assert_double_near(hit.uv.x, 0.75, 1e-5);
    assert_double_near(hit.uv.y, 0.5, 1e-5);
    assert_double_near(plm_world_transmittance(&w, v3(0.25, 0, 1), v3(0, 0, -1), 10.0), 0.0, 0.0);
    /* Behind the first instance, the second one is hit on its vane half. */
    assert_true(plm_world_intersect(&w, v3(0.25, 0, -1), v3(0, 0, -1), INFINITY, &t, &hit));
    assert_double_near(hit.p.z, -2.0, 1e-5);
    assert_double_near(hit.dpdu.x, 1.0, 1e-6);
    assert_double_near(hit.dpdv.y, 1.0, 1e-6);
    plm_world_free(&w);

    /* A curled vane (triangles all on background are left out of the BVH) and
     * a texture that is background everywhere (no triangle at all). */
    int curled = add_quad_mesh(&s, "curled", 1, 1, 0.5);
    plm_instance in = {.mesh = curled, .material = mat, .xform = plm_xform_translate(v3(0, 0, 5)),
                       .tint = rgb_gray(1.0)};
    plm_scene_add_instance(&s, &in);
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "nothing");
    px = calloc(4 * 4 * 3, sizeof(float));
    assert_int_equal(plm_feather_texture_from_pixels(4, 4, px, &m.texture, &err), PLM_OK);
    in.material = plm_scene_add_material(&s, &m);
    in.xform = plm_xform_translate(v3(0, 0, 8));
    plm_scene_add_instance(&s, &in);
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    assert_int_equal(w.prototype_count, 3);
    for (double x = -0.45; x < 0.5; x += 0.1) {
        int hits = plm_world_intersect(&w, v3(x, 0.1, 10), v3(0, 0, -1), 5.5, &t, &hit);
        assert_int_equal(hits, x > 0.0);
        if (hits)
            assert_true(hit.uv.x > 0.5 && hit.p.z < 5.0 + 1e-9);
    }
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* Light sampling densities: E[1/pdf] over light samples is the solid angle
 * the light covers (closed form for a square seen on its axis), and
 * plm_light_pdf agrees with the density the sample reported (environment
 * maps and the sky: test_light). */
static void light_sampling_densities(void **state)
{
    (void)state;
    plm_light q = plm_quad_light(v3(-1, -1, 2), v3(0, 2, 0), v3(2, 0, 0), rgb_gray(1.0)); /* faces -z, toward the origin */
    plm_render_light rl;
    plm_error err;
    assert_int_equal(plm_render_light_init(&q, &rl, &err), PLM_OK);
    plm_rng rng;
    plm_rng_seed(&rng, 3, 3);
    double sum = 0.0;
    int n = 200000;
    for (int i = 0; i < n; ++i) {
        plm_light_sample ls;
        assert_true(plm_light_sample_from(&rl, v3(0, 0, 0), plm_rng_uniform(&rng), plm_rng_uniform(&rng), &ls));
        sum += 1.0 / ls.pdf;
        assert_double_near(plm_light_pdf(&rl, v3(0, 0, 0), ls.wi), ls.pdf, 1e-9 * ls.pdf);
    }
    double a = 2.0, b = 2.0, d = 2.0, omega = 4.0 * atan(a * b / (2.0 * d * sqrt(4.0 * d * d + a * a + b * b)));
    assert_true(fabs(sum / n / omega - 1.0) < 0.005);
    plm_render_light_free(&rl);

}

/* An area light hides what lies behind it from every ray: a dark quad
 * light over a floor shades it from the sky for light sampling exactly as
 * for BSDF sampling (bounce rays stop at the light). */
static void lights_hide_what_lies_behind_them(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    add_object(&s, add_quad_mesh(&s, "floor", 50, 50, 0), add_diffuse(&s, "d", rgb_gray(0.8), 0.0), plm_xform_floor(0));
    add_light(&s, constant_env(1.0));
    /* faces down, radiance 0: a dark ceiling */
    add_light(&s, plm_quad_light(v3(-2, 0.6, -2), v3(4, 0, 0), v3(0, 0, 4), rgb_gray(0.0)));
    look(&s, v3(0, 0.5, 0.5), v3(0, 0, 0), v3(0, 1, 0), 40, 16, 16, 1);
    plm_world w;
    plm_error err;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    estimate nee = film_mean(&w, PLM_ESTIMATOR_NEE, 3, 20000, 41);
    estimate bsdf = film_mean(&w, PLM_ESTIMATOR_BSDF, 3, 20000, 42);
    assert_agree(nee, bsdf, 4.5);
    assert_true(nee.mean < 0.5 * 0.8); /* the ceiling hides most of the sky */
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* Thin lens: every lens sample through a film point meets the same point on
 * the plane in focus; the pinhole's ray goes through it too. Env map
 * conventions: uv and direction are inverse maps, the centre looks along -z
 * and v = 0 is +y. */
static void camera_lens_and_envmap_conventions(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    look(&s, v3(1, 2, 5), v3(0, 0, 0), v3(0, 1, 0), 35, 64, 48, 1);
    s.camera.aperture = 0.2;
    s.camera.focus_distance = 4.0;
    add_object(&s, add_quad_mesh(&s, "q", 1, 1, 0), add_diffuse(&s, "d", rgb_gray(0.5), 0.0), plm_xform_identity());
    plm_world w;
    plm_error err;
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    vec3 o0, d0;
    plm_camera_ray(&w.camera, 20.5, 30.25, 0.0, 0.0, &o0, &d0); /* lens centre */
    vec3 focus = v3_madd(o0, d0, 4.0 / v3_dot(d0, w.camera.forward));
    for (int i = 0; i < 8; ++i) {
        vec3 o, d;
        plm_camera_ray(&w.camera, 20.5, 30.25, 0.1 + 0.1 * i, 0.13 * i, &o, &d);
        assert_true(v3_length(v3_sub(o, s.camera.position)) <= 0.2 + 1e-12);
        vec3 p = v3_madd(o, d, v3_dot(v3_sub(focus, o), w.camera.forward) / v3_dot(d, w.camera.forward));
        assert_true(v3_length(v3_sub(p, focus)) < 1e-9);
    }
    plm_world_free(&w);
    plm_scene_free(&s);

    /* Lat-long conventions: the top row toward up, the centre column north
     * (-z with up +y; +y with up +z, the least turn from +y), rotation from
     * north toward east; uv -> direction -> uv is the identity. */
    frame axes[3] = {plm_light_axes(v3(0, 1, 0), 0.0), plm_light_axes(v3(0, 1, 0), PLM_PI / 2),
                     plm_light_axes(v3(0, 0, 1), 0.0)};
    const vec3 north[3] = {v3(0, 0, -1), v3(1, 0, 0), v3(0, 1, 0)};
    for (int a = 0; a < 3; ++a) {
        vec3 centre = plm_envmap_direction(&axes[a], v2(0.5, 0.5)), top = plm_envmap_direction(&axes[a], v2(0.3, 0.0));
        assert_double_near(v3_dot(centre, north[a]), 1.0, 1e-12);
        assert_double_near(v3_dot(top, axes[a].y), 1.0, 1e-12);
        assert_double_near(v3_dot(v3_cross(axes[a].x, axes[a].y), axes[a].z), 1.0, 1e-12); /* right-handed */
        for (int i = 0; i < 20; ++i) {
            vec2 uv = v2(0.05 + 0.045 * i, 0.03 + 0.047 * i);
            vec2 back = plm_envmap_uv(&axes[a], plm_envmap_direction(&axes[a], uv));
            assert_double_near(back.x, uv.x, 1e-12);
            assert_double_near(back.y, uv.y, 1e-12);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(diffuse_plane_under_constant_sky),
        cmocka_unit_test(pixel_filter_box_and_tent),
        cmocka_unit_test(diffuse_plane_under_distant_light),
        cmocka_unit_test(estimators_agree),
        cmocka_unit_test(transparent_shadows_agree_with_stochastic_passing),
        cmocka_unit_test(white_furnace),
        cmocka_unit_test(transmittance_through_stacked_sheets),
        cmocka_unit_test(bit_identical_at_any_thread_count),
        cmocka_unit_test(sampler_fills_every_elementary_grid),
        cmocka_unit_test(sampler_samples_are_uniform_and_independent),
        cmocka_unit_test(stratified_sampler_agrees_with_independent_samples),
        cmocka_unit_test(cancelled_render_keeps_what_it_took),
        cmocka_unit_test(nonfinite_samples_are_counted_and_dropped),
        cmocka_unit_test(mask_filters_remove_background),
        cmocka_unit_test(light_sampling_densities),
        cmocka_unit_test(camera_lens_and_envmap_conventions),
        cmocka_unit_test(lights_hide_what_lies_behind_them),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
