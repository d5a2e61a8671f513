/* A feather's fluff in a scene (generate/fluff.h, render/world.c): placed
 * with the feather as curves with a fiber material; rendered with and
 * without it, finite and deterministic images that differ; the ID pass
 * reports the fluff; the fiber BSDF's samples weigh what eval and pdf say
 * and return no more light than arrives. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/render.h"
#include "render/visibility.h"
#include "scene/scene_file.h"

/* A small contour feather (20 mm, an afterfeather by its type) seen from
 * 30 mm in front of its downy base, with `fluff` as its shape.fluff block. */
static void load(const char *fluff, plm_scene *scene)
{
    char text[2048];
    snprintf(text, sizeof text,
             "{\"film\": {\"width\": 40, \"height\": 40, \"spp\": 4, \"max_depth\": 6},"
             " \"camera\": {\"position\": [0, 4, -30], \"look_at\": [0, 4, 0], \"up\": [0, 1, 0], \"fov\": 30},"
             " \"lights\": [{\"type\": \"environment\", \"radiance\": [0.2, 0.2, 0.2]},"
             "  {\"type\": \"distant\", \"direction\": [0.3, 0.5, -1.0], \"irradiance\": [3, 3, 3]}],"
             " \"feathers\": {\"f\": {\"level\": 1, \"texture_size\": 64, \"species\": {\"type\": \"contour\","
             "  \"shape\": {\"length\": 20, \"plumulaceous\": 0.3, \"fluff\": %s}}}},"
             " \"objects\": [{\"feather\": \"f\"}]}",
             fluff);
    plm_error err = {{0}};
    plm_result rc = plm_scene_load_buffer(text, strlen(text), "fluff.json", scene, &err);
    if (rc != PLM_OK)
        fprintf(stderr, "%s\n", err.message);
    assert_int_equal(rc, PLM_OK);
}

static int fluff_instances(const plm_scene *s)
{
    int n = 0;
    for (int i = 0; i < s->instance_count; ++i)
        if (s->instances[i].part == PLM_PART_FLUFF) {
            assert_true(s->meshes[s->instances[i].mesh].curves.curve_count > 0);
            assert_int_equal(s->materials[s->instances[i].material].type, PLM_MATERIAL_FIBER);
            n++;
        }
    return n;
}

static plm_film render(const plm_scene *s)
{
    plm_render_options o = {.threads = 1};
    plm_film film;
    plm_error err = {{0}};
    assert_int_equal(plm_render(s, &o, &film, &err), PLM_OK);
    assert_int_equal(film.nonfinite, 0);
    for (int i = 0; i < 3 * film.width * film.height; ++i)
        assert_true(isfinite(film.rgb[i]) && film.rgb[i] >= 0.0f);
    return film;
}

static long long fluff_hits(const plm_scene *s)
{
    plm_world w;
    plm_visibility v;
    assert_int_equal(plm_world_build(s, &w, NULL), PLM_OK);
    assert_int_equal(plm_visibility_trace(&w, &w.camera, &v, NULL), PLM_OK);
    long long n = v.part_hits[PLM_PART_FLUFF];
    /* Where along the feather: the fluff lies on its lower part (v over the whole feather, not the fluff's extent). */
    for (int i = 0; i < v.width * v.height; ++i)
        if (v.part[i] == PLM_PART_FLUFF)
            assert_true(v.v[i] >= 0.0f && v.v[i] < 0.75f);
    plm_visibility_free(&v);
    plm_world_free(&w);
    return n;
}

static void with_and_without_fluff(void **state)
{
    (void)state;
    plm_scene with, without;
    load("{}", &with);
    load("{\"density\": 0}", &without);
    assert_int_equal(fluff_instances(&with), 1);
    assert_int_equal(fluff_instances(&without), 0);
    plm_film a = render(&with), b = render(&with), c = render(&without);
    size_t n = 3 * (size_t)a.width * (size_t)a.height;
    assert_memory_equal(a.rgb, b.rgb, n * sizeof(float)); /* deterministic */
    double differ = 0.0;
    for (size_t i = 0; i < n; ++i)
        differ += fabs(a.rgb[i] - c.rgb[i]);
    printf("mean |with - without| per channel %.4g\n", differ / n);
    assert_true(differ > 0.0);
    long long hits = fluff_hits(&with);
    printf("fluff ends %lld of %d camera rays\n", hits, a.width * a.height);
    assert_true(hits > 0);
    assert_int_equal(fluff_hits(&without), 0);
    plm_film_free(&a);
    plm_film_free(&b);
    plm_film_free(&c);
    plm_scene_free(&with);
    plm_scene_free(&without);
}

/* Shoot at the middle of the first down barb: the hit is a fiber's (this
 * barb's or one in front), whose samples weigh eval / pdf, and whose mean
 * weight, the light it scatters of what arrives, is at most one. */
static void fiber_bsdf_samples(void **state)
{
    (void)state;
    plm_scene s;
    load("{}", &s);
    plm_world w;
    assert_int_equal(plm_world_build(&s, &w, NULL), PLM_OK);
    const plm_curves *c = NULL;
    for (int i = 0; i < s.instance_count; ++i)
        if (s.instances[i].part == PLM_PART_FLUFF)
            c = &s.meshes[s.instances[i].mesh].curves;
    assert_non_null(c);
    const float *mid = c->points + 4 * (size_t)(c->first[0] + (c->first[1] - c->first[0]) / 2);
    vec3 o = v3(0.0, 4.0, -30.0), target = v3(mid[0], mid[1], mid[2]);
    vec3 d = v3_normalize(v3_sub(target, o));
    double t;
    plm_hit hit;
    assert_true(plm_world_intersect(&w, o, d, INFINITY, &t, &hit));
    assert_int_equal(hit.material->type, PLM_MATERIAL_FIBER);
    assert_true(hit.fiber_radius > 0.0);
    /* Rays leave it beyond its surface. */
    vec3 out = plm_world_offset(&w, &hit, d);
    assert_true(v3_length(v3_sub(out, hit.fiber_axis_point)) > hit.fiber_radius);
    plm_rng rng;
    plm_rng_seed(&rng, 7, 1);
    plm_bsdf bsdf;
    plm_material_bsdf(&hit, v3_neg(d), &rng, &bsdf);
    rgb sum = rgb_gray(0.0);
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        plm_bsdf_sample_rec r;
        if (!plm_bsdf_sample(&bsdf, plm_rng_uniform(&rng), plm_rng_uniform(&rng), plm_rng_uniform(&rng), &r))
            continue;
        if (i < 200) {
            rgb e = plm_bsdf_eval(&bsdf, r.wi);
            double p = plm_bsdf_pdf(&bsdf, r.wi);
            assert_double_near(p, r.pdf, 1e-9 * p);
            assert_double_near(r.weight.g, e.g / p, 1e-9 * fmax(1.0, e.g / p));
        }
        sum = rgb_add(sum, r.weight);
    }
    sum = rgb_scale(sum, 1.0 / n);
    printf("fiber albedo (mean sample weight) %.4f %.4f %.4f\n", sum.r, sum.g, sum.b);
    assert_true(rgb_max(sum) <= 1.02 && rgb_max(sum) > 0.0); /* at most what arrives, within the MC error */
    plm_world_free(&w);
    plm_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(with_and_without_fluff),
        cmocka_unit_test(fiber_bsdf_samples),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
