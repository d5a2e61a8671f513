/* Shared by test_fiber_table.c and slow_fiber_table.c: a feather sheet under
 * a sky and a low sun, seen at an angle, rendered with the tabulated and the
 * stochastic fiber estimator; the mean of each image quadrant with its
 * standard error (independent paths, test_render_stats.h). barb_eccentricity
 * 1 is the default feather (a circular barb with a concentric medulla);
 * otherwise its barb's cortex is that ellipse, as most species presets have
 * it (the tables' least accurate case per query, docs/fiber.md). Include
 * after cmocka.h. */
#ifndef PLUMAGE_TESTS_FIBER_TABLE_RENDER_H
#define PLUMAGE_TESTS_FIBER_TABLE_RENDER_H

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "optics/feather_bsdf.h"
#include "render/render.h"
#include "render/scene_build.h"
#include "test_render_stats.h"

enum { SHEET_QUADS = 4 };

/* The sheet with its barb's eccentricity, rendered with one estimator. */
static inline void feather_sheet_scene(double barb_eccentricity, plm_bcsdf_kind kind, plm_scene *s)
{
    plm_scene_init(s);
    plm_mesh mesh;
    plm_error err;
    assert_int_equal(plm_shape_quad(2.0, 2.0, 1.0, 16, &mesh, &err), PLM_OK);
    plm_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "vane");
    m.type = PLM_MATERIAL_FEATHER;
    m.reflectance = rgb_gray(0.7);
    m.feather = malloc(sizeof *m.feather);
    assert_non_null(m.feather);
    plm_feather_params_default(m.feather);
    m.feather->barb.eccentricity = m.feather->masking.barb_eccentricity = barb_eccentricity;
    m.feather->bcsdf = kind;
    float *px = malloc(sizeof(float) * 3 * 4); /* the texture takes it */
    assert_non_null(px);
    for (int i = 0; i < 4; ++i) /* all vane, barbs at 60 degrees */
        px[3 * i] = (float)((sin(plm_radians(60.0)) + 1) / 2), px[3 * i + 1] = (float)((cos(plm_radians(60.0)) + 1) / 2),
        px[3 * i + 2] = 1.0f;
    assert_int_equal(plm_feather_texture_from_pixels(2, 2, px, &m.texture, &err), PLM_OK);
    plm_instance in = {.mesh = plm_scene_add_mesh(s, "vane", &mesh), .material = plm_scene_add_material(s, &m),
                       .xform = plm_xform_identity(), .tint = rgb_gray(1.0)};
    assert_true(plm_scene_add_instance(s, &in) >= 0);
    plm_light sky = plm_light_default(PLM_LIGHT_CONSTANT_ENV), sun = plm_light_default(PLM_LIGHT_DISTANT);
    sky.radiance = rgb_make(0.3, 0.4, 0.6);
    plm_scene_add_light(s, &sky);
    sun.direction = v3_normalize(v3(-0.6, 0.3, 0.75));
    sun.irradiance = rgb_gray(3.0);
    plm_scene_add_light(s, &sun);
    s->camera = (plm_camera_desc){v3(0.8, -1.2, 1.6), v3(0, 0, 0), v3(0, 0, 1), 40, 0, 0, 1};
    s->film.width = s->film.height = 24;
}

typedef struct sheet_job {
    const plm_world *world;
    long paths;
    uint64_t seed;
    int quadrant;
    estimate result;
} sheet_job;

static void *sheet_quadrant(void *arg)
{
    sheet_job *j = arg;
    double x0 = 0.5 * (j->quadrant % 2), y0 = 0.5 * (j->quadrant / 2);
    j->result = film_region_mean(j->world, PLM_ESTIMATOR_MIS, 6, j->paths, j->seed, x0, y0, x0 + 0.5, y0 + 0.5);
    return NULL;
}

/* e[k][q]: quadrant q's mean with estimator k (0 tabulated, 1 stochastic)
 * from paths[k] independent paths, seeded seed + 10 k + q; the eight
 * estimates run on `threads` threads (the figures do not depend on it). */
static inline void sheet_estimator_quadrants(double barb_eccentricity, const long paths[2], uint64_t seed,
                                             int threads, estimate e[2][SHEET_QUADS])
{
    plm_scene s[2];
    plm_world w[2];
    sheet_job jobs[2 * SHEET_QUADS];
    for (int k = 0; k < 2; ++k) {
        feather_sheet_scene(barb_eccentricity, k ? PLM_BCSDF_STOCHASTIC : PLM_BCSDF_TABULATED, &s[k]);
        plm_error err;
        assert_int_equal(plm_world_build(&s[k], &w[k], &err), PLM_OK);
        for (int q = 0; q < SHEET_QUADS; ++q)
            jobs[k * SHEET_QUADS + q] = (sheet_job){&w[k], paths[k], seed + 10 * (uint64_t)k + (uint64_t)q, q, {0, 0}};
    }
    for (int first = 0; first < 2 * SHEET_QUADS; first += threads) {
        pthread_t tid[2 * SHEET_QUADS];
        int n = first + threads <= 2 * SHEET_QUADS ? threads : 2 * SHEET_QUADS - first;
        for (int i = 1; i < n; ++i)
            assert_int_equal(pthread_create(&tid[i], NULL, sheet_quadrant, &jobs[first + i]), 0);
        sheet_quadrant(&jobs[first]);
        for (int i = 1; i < n; ++i)
            pthread_join(tid[i], NULL);
    }
    for (int k = 0; k < 2; ++k) {
        for (int q = 0; q < SHEET_QUADS; ++q) {
            e[k][q] = jobs[k * SHEET_QUADS + q].result;
            fprintf(stderr, "%s, quadrant %d: mean %.5f +- %.5f\n", k ? "stochastic" : "tabulated", q, e[k][q].mean,
                    e[k][q].se);
        }
        plm_world_free(&w[k]);
        plm_scene_free(&s[k]);
    }
}

/* The whole image's mean from its quadrants' (equal areas). */
static inline estimate sheet_whole(const estimate e[SHEET_QUADS])
{
    estimate whole = {0.0, 0.0};
    for (int q = 0; q < SHEET_QUADS; ++q) {
        whole.mean += e[q].mean / SHEET_QUADS;
        whole.se += plm_sqr(e[q].se / SHEET_QUADS);
    }
    whole.se = sqrt(whole.se);
    return whole;
}

#endif
