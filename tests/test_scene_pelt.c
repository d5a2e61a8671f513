/* A pelt as the renderer sees it (scene file -> world): only the tips show,
 * feathers lie on the body, none passes through another. Each tolerance
 * below was fixed before measuring; the figures measured are printed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "assert_double.h"
#include "render/visibility.h"
#include "scene/scene_file.h"

enum { FEATHERS = 600 };
static const double WIDTH = 0.3, HEIGHT = 0.2;

/* The default pelt (overlap 2/3, elevation 8 degrees) of covert_parrot on a
 * 0.3 x 0.2 plane with skin under it, seen from 45 degrees above the tail. */
static void load(plm_scene *s, plm_world *w)
{
    char text[2048];
    snprintf(text, sizeof text,
             "{\"camera\": {\"position\": [0, -0.12, 0.12], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1], \"fov\": 24},"
             " \"film\": {\"width\": 240, \"height\": 160},"
             " \"materials\": {\"skin\": {\"reflectance\": [0.25, 0.2, 0.17]}},"
             " \"objects\": [{\"layout\": {\"type\": \"pelt\", \"species\": [\"%s/presets/species/covert_parrot.json\"],"
             " \"surface\": {\"shape\": \"plane\", \"size\": [%g, %g]}, \"surface_material\": \"skin\","
             " \"count\": %d, \"seed\": 26, \"level\": 1, \"texture_size\": 128}}]}",
             PLUMAGE_SOURCE_DIR, WIDTH, HEIGHT, FEATHERS);
    plm_error err = {{0}};
    assert_int_equal(plm_scene_load_buffer(text, strlen(text), "pelt", s, &err), PLM_OK);
    assert_int_equal(s->feather_count, FEATHERS);
    assert_int_equal(plm_world_build(s, w, &err), PLM_OK);
}

/* The instance of a feather's given part. */
static const plm_instance *part_of(const plm_scene *s, int feather, plm_part part)
{
    for (int i = 0; i < s->instance_count; ++i)
        if (s->instances[i].feather == feather && s->instances[i].part == part)
            return &s->instances[i];
    return NULL;
}

/* The length of a placed feather: its rachis mesh's extent along +y, scaled. */
static double length_of(const plm_scene *s, const plm_instance *rachis, vec3 *tip)
{
    const plm_mesh *m = &s->meshes[rachis->mesh].mesh;
    int top = 0;
    for (int i = 1; i < m->vertex_count; ++i)
        if (m->positions[3 * i + 1] > m->positions[3 * top + 1])
            top = i;
    const float *p = m->positions + 3 * top;
    *tip = plm_xform_point(rachis->xform.m, v3(p[0], p[1], p[2]));
    vec3 base = plm_xform_point(rachis->xform.m, v3(0, 0, 0));
    return v3_length(v3_sub(*tip, base));
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Only the tips show: the median visible fraction of the feathers wholly in
 * the picture (which lies inside the pelt) at most 0.40. How many show some
 * of their proximal half is printed: the aim is none, not met yet (between
 * two rounded tips the crescent a feather shows reaches below its middle;
 * docs/layouts.md). */
static void only_the_tips_show(void **state)
{
    (void)state;
    plm_scene s;
    plm_world w;
    load(&s, &w);
    plm_visibility vis;
    plm_visibility_summary sum;
    plm_error err = {{0}};
    assert_int_equal(plm_visibility_trace(&w, &w.camera, &vis, &err), PLM_OK);
    assert_int_equal(plm_visibility_summarise(&vis, 20, &sum, &err), PLM_OK);
    printf("feathers measured %d, visible fraction median %.3f p90 %.3f, proximal half seen on %d feathers "
           "(%lld rays), body %.4f\n", sum.feathers, sum.median, sum.p90, sum.proximal_feathers, sum.proximal_rays,
           sum.body);
    assert_true(sum.feathers >= 30);
    assert_true(sum.median <= 0.40);
    plm_visibility_free(&vis);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* Feathers lie on the body: the gap under each tip (straight down to the next
 * surface that is not the feather itself) below 10% of the feather's length,
 * and the rachis leaving the skin at a shallow angle (median at most 15
 * degrees, none above 30). Feathers within a length of the plane's edge are
 * left out: nothing lies under their tips but the skin's edge. */
static void feathers_lie_on_the_body(void **state)
{
    (void)state;
    plm_scene s;
    plm_world w;
    load(&s, &w);
    double *gap = malloc(sizeof(double) * FEATHERS), *angle = malloc(sizeof(double) * FEATHERS);
    int n = 0;
    for (int f = 1; f <= FEATHERS; ++f) {
        const plm_instance *rachis = part_of(&s, f, PLM_PART_RACHIS);
        assert_non_null(rachis);
        vec3 tip;
        double length = length_of(&s, rachis, &tip);
        if (fabs(tip.x) > 0.5 * WIDTH - length || fabs(tip.y) > 0.5 * HEIGHT - length)
            continue;
        vec3 down = v3(0, 0, -1), axis = plm_xform_vector(rachis->xform.m, v3(0, 1, 0));
        double t = 0.0, tnear = 0.0;
        int instance;
        while (plm_world_first_hit(&w, tip, down, tnear, INFINITY, &instance, &t) &&
               s.instances[instance].feather == f)
            tnear = t + w.epsilon;
        gap[n] = t / length;
        angle[n++] = plm_degrees(asin(axis.z / v3_length(axis)));
    }
    qsort(gap, (size_t)n, sizeof *gap, compare_double);
    qsort(angle, (size_t)n, sizeof *angle, compare_double);
    printf("%d inner feathers: gap under the tip / length median %.4f max %.4f; rachis angle median %.1f max %.1f "
           "degrees\n", n, gap[n / 2], gap[n - 1], angle[n / 2], angle[n - 1]);
    assert_true(n >= 100);
    assert_true(gap[n - 1] < 0.10);
    assert_true(angle[n / 2] <= 15.0 && angle[n - 1] <= 30.0);
    free(gap);
    free(angle);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* No feather passes through another: vertical rays every 0.5 mm over the
 * whole plane (down to the skin), surfaces closer than 0.1% of the largest
 * feather's length along a ray counting as touching. Zero pairs. */
static void no_feather_passes_through_another(void **state)
{
    (void)state;
    plm_scene s;
    plm_world w;
    load(&s, &w);
    double longest = 0.0;
    for (int f = 1; f <= FEATHERS; ++f) {
        vec3 tip;
        longest = fmax(longest, length_of(&s, part_of(&s, f, PLM_PART_RACHIS), &tip));
    }
    plm_crossing_grid g = {v3(-0.5 * WIDTH, -0.5 * HEIGHT, 1.0), v3(WIDTH, 0, 0), v3(0, HEIGHT, 0), v3(0, 0, -1),
                           (int)(WIDTH / 0.0005), (int)(HEIGHT / 0.0005), 0.001 * longest};
    plm_crossings c;
    plm_error err = {{0}};
    assert_int_equal(plm_visibility_crossings(&w, &g, &c, &err), PLM_OK);
    printf("%lld rays, %lld ordered pairs, %d pairs passing through each other (e.g. %d and %d)\n", c.rays,
           c.ordered, c.pairs, c.example[0], c.example[1]);
    assert_true(c.ordered > FEATHERS); /* the rays do see feathers overlap */
    assert_int_equal(c.pairs, 0);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* "shape": "mesh": the example body read from its PLY with its tangents as the flow; a mesh file
 * without tangents cannot ask for them. */
static void pelt_on_a_mesh_file(void **state)
{
    (void)state;
    char text[2048];
    const char *fmt = "{\"materials\": {\"skin\": {\"reflectance\": [0.25, 0.2, 0.17]}},"
                      " \"objects\": [{\"layout\": {\"type\": \"pelt\","
                      " \"species\": [\"%s/presets/species/covert_parrot.json\"],"
                      " \"surface\": {\"shape\": \"mesh\", \"file\": \"%s\"%s}, \"surface_material\": \"skin\","
                      " \"count\": 100, \"level\": 1, \"texture_size\": 32}}]}";
    snprintf(text, sizeof text, fmt, PLUMAGE_SOURCE_DIR, PLUMAGE_SOURCE_DIR "/presets/meshes/body.ply", "");
    plm_scene s;
    plm_error err = {{0}};
    assert_int_equal(plm_scene_load_buffer(text, strlen(text), "mesh", &s, &err), PLM_OK);
    assert_int_equal(s.feather_count, 100);
    int body = 0;
    for (int i = 0; i < s.instance_count; ++i)
        if (s.instances[i].part == PLM_PART_BODY) {
            const plm_mesh *m = &s.meshes[s.instances[i].mesh].mesh;
            assert_non_null(m->tangents);
            assert_non_null(m->density);
            body++;
        }
    assert_int_equal(body, 1);
    /* Every calamus base on the body: within its 0.2 length and 0.09 width. */
    for (int f = 1; f <= 100; ++f) {
        vec3 base = plm_xform_point(part_of(&s, f, PLM_PART_RACHIS)->xform.m, v3(0, 0, 0));
        assert_true(fabs(base.y) <= 0.1 + 1e-3 && fabs(base.x) <= 0.045 + 1e-3);
    }
    plm_scene_free(&s);
    FILE *obj = fopen("flat.obj", "w");
    assert_non_null(obj);
    fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", obj);
    fclose(obj);
    snprintf(text, sizeof text, fmt, PLUMAGE_SOURCE_DIR, "flat.obj", ", \"flow\": \"tangents\"");
    assert_int_not_equal(plm_scene_load_buffer(text, strlen(text), "mesh", &s, &err), PLM_OK);
    printf("%s\n", err.message);
    assert_non_null(strstr(err.message, "surface.flow"));
    remove("flat.obj");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(only_the_tips_show),
        cmocka_unit_test(feathers_lie_on_the_body),
        cmocka_unit_test(no_feather_passes_through_another),
        cmocka_unit_test(pelt_on_a_mesh_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
