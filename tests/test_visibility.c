/* The ID pass (render/visibility.h) on quads whose projections are known
 * exactly: a camera 10 units above the z = 0 plane whose image spans
 * [-1, 1]^2 there, 200 x 200 pixels of 0.01 each. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "assert_double.h"
#include "render/scene_build.h"
#include "render/visibility.h"

/* A quad of size (w, h) whose object space runs from y = 0 (a feather's
 * base) to y = h, placed with its centre at (x, y, z). */
static void add_quad(plm_scene *s, const char *name, double w, double h, vec3 centre, int feather, plm_part part)
{
    plm_error err = {{0}};
    plm_mesh quad;
    assert_int_equal(plm_shape_quad(w, h, 0.0, 1, &quad, &err), PLM_OK);
    for (int i = 0; i < quad.vertex_count; ++i)
        quad.positions[3 * i + 1] += (float)(0.5 * h);
    plm_material m = plm_diffuse_material(name, rgb_gray(0.5), 0.0);
    plm_instance in = {.mesh = plm_scene_add_mesh(s, name, &quad), .material = plm_scene_add_material(s, &m),
                       .xform = plm_xform_translate(v3(centre.x, centre.y - 0.5 * h, centre.z)),
                       .tint = rgb_gray(1.0), .feather = feather, .part = part};
    assert_true(plm_scene_add_instance(s, &in) >= 0);
}

/* Feather 1: a unit vane at z = 0; feather 2: its right half's double just in
 * front of it; feather 3: a vane crossing the image's right edge; the body a
 * 2 x 2 quad behind them all. */
static void build(plm_scene *s, plm_world *w)
{
    plm_error err = {{0}};
    plm_scene_init(s);
    s->camera.position = v3(0.0, 0.0, 10.0);
    s->camera.look_at = v3(0.0, 0.0, 0.0);
    s->camera.up = v3(0.0, 1.0, 0.0);
    s->camera.fov = 2.0 * plm_degrees(atan(0.1));
    s->camera.given = 1;
    s->film.width = s->film.height = 200;
    int one = plm_scene_new_feather(s), two = plm_scene_new_feather(s), three = plm_scene_new_feather(s);
    add_quad(s, "one", 1.0, 1.0, v3(0.0, 0.0, 0.0), one, PLM_PART_VANE);
    add_quad(s, "two", 0.5, 1.0, v3(0.25, 0.0, 0.01), two, PLM_PART_VANE);
    add_quad(s, "three", 0.4, 0.2, v3(1.0, 0.7, 0.0), three, PLM_PART_RACHIS);
    add_quad(s, "body", 2.0, 2.0, v3(0.0, 0.0, -0.01), 0, PLM_PART_BODY);
    assert_int_equal(plm_world_build(s, w, &err), PLM_OK);
}

/* Projected areas, visible areas, the proximal half and the body, counted
 * pixel by pixel: every count is exact (no pixel centre lies within 0.5% of
 * a pixel of an edge). */
static void counts_are_the_projected_areas(void **state)
{
    (void)state;
    plm_scene s;
    plm_world w;
    build(&s, &w);
    plm_visibility v;
    plm_error err = {{0}};
    assert_int_equal(plm_visibility_trace(&w, &w.camera, &v, &err), PLM_OK);
    assert_int_equal(v.feather_count, 3);
    assert_int_equal(v.rays, 40000);
    assert_int_equal(v.hits, 40000);
    assert_int_equal(v.feathers[1].crossed, 10000);
    assert_int_equal(v.feathers[1].seen, 5000);
    assert_int_equal(v.feathers[2].crossed, 5000);
    assert_int_equal(v.feathers[2].seen, 5000);
    /* The left half of feather 1 shows: half its rows below v = 0.5. */
    assert_int_equal(v.feathers[1].seen_proximal, 2500);
    assert_double_near(v.feathers[1].v_min, 0.005, 1e-4);
    assert_int_equal(v.feathers[1].on_border, 0);
    assert_int_equal(v.feathers[3].on_border, 1);
    /* Feather 3 spans x 0.8..1.2, y 0.6..0.8: 20 x 20 pixels on screen. */
    assert_int_equal(v.feathers[3].crossed, 400);
    assert_int_equal(v.part_hits[PLM_PART_RACHIS], 400);
    assert_int_equal(v.part_hits[PLM_PART_VANE], 10000);
    assert_int_equal(v.part_hits[PLM_PART_BODY], 40000 - 10400);
    assert_int_equal(v.deepest, 3);
    /* Pixel (149, 100), x = 0.495, y = -0.005: ends on feather 2 half way along it. */
    size_t p = (size_t)100 * 200 + 149;
    assert_int_equal(v.feather[p], 2);
    assert_int_equal(v.part[p], PLM_PART_VANE);
    assert_double_near(v.v[p], 0.495, 1e-4);
    plm_visibility_summary sum;
    assert_int_equal(plm_visibility_summarise(&v, 1, &sum, &err), PLM_OK);
    assert_int_equal(sum.feathers, 2); /* feather 3 is partly off-screen */
    assert_double_near(sum.median, 0.5, 1e-12);
    assert_double_near(sum.max, 1.0, 1e-12);
    assert_int_equal(sum.proximal_feathers, 2);
    assert_int_equal(sum.proximal_rays, 2500 + 2500);
    assert_double_near(sum.body, 29600.0 / 40000.0, 1e-12);
    plm_visibility_free(&v);
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* A camera from any direction frames the whole world: from 26 directions
 * spread over the sphere, every feather's rays stay off the border. */
static void cameras_around_frame_the_world(void **state)
{
    (void)state;
    vec3 mean = v3(0.0, 0.0, 0.0);
    for (int i = 0; i < 26; ++i) {
        vec3 d = plm_visibility_direction(i, 26);
        assert_double_near(v3_length(d), 1.0, 1e-12);
        mean = v3_add(mean, v3_scale(d, 1.0 / 26));
    }
    assert_true(v3_length(mean) < 0.05);
    plm_scene s;
    plm_world w;
    build(&s, &w);
    plm_error err = {{0}};
    for (int i = 0; i < 26; i += 5) {
        plm_camera c = plm_visibility_camera(&w, plm_visibility_direction(i, 26), 64, 48, 40.0);
        plm_visibility v;
        assert_int_equal(plm_visibility_trace(&w, &c, &v, &err), PLM_OK);
        long long border = 0;
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 64; ++x)
                border += (x == 0 || y == 0 || x == 63 || y == 47) && v.instance[y * 64 + x] >= 0;
        assert_int_equal(border, 0);
        assert_true(v.hits > 0);
        plm_visibility_free(&v);
    }
    plm_world_free(&w);
    plm_scene_free(&s);
}

/* Crossing pairs: feathers 1 and 2 of build() lie one over the other 0.01
 * apart (one order only); a third vane tilted 10 degrees about x through
 * feather 1's centre passes through it (both orders, on either side of
 * y = 0) and through feather 2 as well, which lies over the centre line too.
 * With a tolerance above the tilted vane's largest height difference from
 * them (0.5 sin 10 + 0.01 = 0.097), no pair counts. */
static void crossing_pairs_are_found_by_rays(void **state)
{
    (void)state;
    plm_scene s;
    plm_world w;
    plm_error err = {{0}};
    build(&s, &w);
    plm_crossing_grid g = {v3(-0.5, -0.5, 1.0), v3(1, 0, 0), v3(0, 1, 0), v3(0, 0, -1), 50, 50, 0.001};
    plm_crossings c;
    assert_int_equal(plm_visibility_crossings(&w, &g, &c, &err), PLM_OK);
    assert_int_equal(c.rays, 2500);
    assert_int_equal(c.ordered, 1);
    assert_int_equal(c.pairs, 0);
    plm_world_free(&w);

    plm_mesh quad;
    assert_int_equal(plm_shape_quad(0.8, 1.0, 0.0, 1, &quad, &err), PLM_OK);
    plm_material m = plm_diffuse_material("tilted", rgb_gray(0.5), 0.0);
    plm_instance in = {.mesh = plm_scene_add_mesh(&s, "tilted", &quad), .material = plm_scene_add_material(&s, &m),
                       .xform = plm_xform_rotate(v3(1, 0, 0), plm_radians(10.0)), .tint = rgb_gray(1.0),
                       .feather = plm_scene_new_feather(&s), .part = PLM_PART_VANE};
    assert_true(plm_scene_add_instance(&s, &in) >= 0);
    assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
    assert_int_equal(plm_visibility_crossings(&w, &g, &c, &err), PLM_OK);
    assert_int_equal(c.pairs, 2);
    assert_int_equal(c.ordered, 5); /* 1 over 2, and the tilted vane both ways with each */
    g.tolerance = 0.1;
    assert_int_equal(plm_visibility_crossings(&w, &g, &c, &err), PLM_OK);
    assert_int_equal(c.pairs, 0);
    plm_world_free(&w);
    plm_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(counts_are_the_projected_areas),
        cmocka_unit_test(cameras_around_frame_the_world),
        cmocka_unit_test(crossing_pairs_are_found_by_rays),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
