/* Bird presets and the body built from them: the Amazon preset reads, bad
 * presets fail naming the field, the skin is closed and outward, every
 * triangle but the eye rings belongs to a tract, the landmarks sit where a
 * bird has them, and the build is deterministic. */
#define _GNU_SOURCE
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

#include "generate/bird.h"
#include "generate/species.h"

#define AMAZON PLUMAGE_SOURCE_DIR "/presets/birds/amazon_parrot.json"

static plm_bird bird;

static void amazon_reads(void **state)
{
    (void)state;
    plm_error err = {{0}};
    assert_int_equal(plm_bird_load(AMAZON, &bird, &err), PLM_OK);
    assert_double_near(bird.m.total_length, 370.0, 0.0);
    assert_int_equal(bird.bill_family, PLM_BILL_HOOKED);
    assert_int_equal(bird.tracts[0].pteryla, PLM_PTERYLA_CAPITAL);
    assert_double_near(bird.p.posture, plm_radians(55.0), 1e-12);
    int named[PLM_PTERYLAE] = {0};
    for (int k = 0; k < bird.tract_count; ++k)
        named[bird.tracts[k].pteryla] = 1;
    for (int p = 0; p < PLM_PTERYLAE; ++p)
        assert_true(named[p]);
}

/* A preset with `field` replaced: the error names `expected`. */
static void assert_bad(const char *json, const char *expected)
{
    char path[] = "/tmp/plumage_bird_XXXXXX.json";
    int fd = mkstemps(path, 5);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    fputs(json, f);
    fclose(f);
    plm_error err = {{0}};
    assert_int_not_equal(plm_bird_load(path, &bird, &err), PLM_OK);
    remove(path);
    if (!strstr(err.message, expected))
        fail_msg("message \"%s\" does not name \"%s\"", err.message, expected);
}

#define MEASURES "\"measurements\": {\"total_length\": 370, \"wing_chord\": 205, \"tail_length\": 115, " \
                 "\"bill_length\": 32, \"bill_depth\": 29, \"head_width\": 36, \"tarsus\": %s}"
#define TRACT "{\"name\": \"capital\", \"species\": \"x.json\", \"density\": 5, \"size\": [8, 12]}"

static void bad_presets_name_the_field(void **state)
{
    (void)state;
    char json[1024];
    snprintf(json, sizeof json, "{" MEASURES ", \"bill\": {}, \"tracts\": [" TRACT "]}", "-24");
    assert_bad(json, "measurements.tarsus: -24 is out of range");
    snprintf(json, sizeof json, "{" MEASURES ", \"bill\": {}, \"tracts\": [" TRACT "], \"crest\": 2}", "24");
    assert_bad(json, ": crest: unknown field");
    snprintf(json, sizeof json, "{" MEASURES ", \"bill\": {}, \"tracts\": [{\"name\": \"capital\", "
             "\"density\": 5, \"size\": [8, 12]}]}", "24");
    assert_bad(json, "tracts[0].species: required");
    snprintf(json, sizeof json, "{" MEASURES ", \"bill\": {}, \"tracts\": [{\"name\": \"crown\", "
             "\"species\": \"x.json\", \"density\": 5, \"size\": [8, 12]}]}", "24");
    assert_bad(json, "tracts[0].pteryla: required");
    snprintf(json, sizeof json, "{" MEASURES ", \"bill\": {}, \"tracts\": [{\"name\": \"capital\", \"pteryla\": "
             "\"alar\", \"species\": \"x.json\", \"density\": 5, \"size\": [8, 12]}]}", "24");
    assert_bad(json, "tracts[0].pteryla");
    snprintf(json, sizeof json, "{" MEASURES ", \"bill\": {}, \"tracts\": [{\"name\": \"capital\", "
             "\"species\": \"x.json\", \"density\": 5, \"size\": [8, 12], \"s\": [0.5, 0.2]}]}", "24");
    assert_bad(json, "tracts[0].s");
}

static vec3 vtx(const float *a, uint32_t i) { return v3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); }

static double signed_volume(const plm_mesh *m)
{
    double v = 0.0;
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * t;
        v += v3_dot(vtx(m->positions, i[0]), v3_cross(vtx(m->positions, i[1]), vtx(m->positions, i[2]))) / 6.0;
    }
    return v;
}

/* The skin is closed and wound outward, its normals agree with its faces,
 * only the eye rings are bare, and the parts sit where a bird has them. */
static void body_is_a_closed_dressed_skin(void **state)
{
    (void)state;
    plm_error err = {{0}};
    assert_int_equal(plm_bird_load(AMAZON, &bird, &err), PLM_OK);
    plm_bird_body b;
    assert_int_equal(plm_bird_build(&bird, 3, &b, &err), PLM_OK);
    const plm_mesh *m = &b.skin;
    assert_true(signed_volume(m) > 0.0);
    assert_true(signed_volume(&b.upper_bill) > 0.0 && signed_volume(&b.lower_bill) > 0.0);
    int against = 0, bare = 0;
    double area = 0.0, bare_area = 0.0;
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * t;
        vec3 face = v3_cross(v3_sub(vtx(m->positions, i[1]), vtx(m->positions, i[0])),
                             v3_sub(vtx(m->positions, i[2]), vtx(m->positions, i[0])));
        for (int k = 0; k < 3; ++k)
            against += v3_dot(face, vtx(m->normals, i[k])) < 0.0;
        area += 0.5 * v3_length(face);
        if (b.tract[t] < 0) {
            ++bare;
            bare_area += 0.5 * v3_length(face);
            vec3 c = vtx(m->positions, i[0]);
            double d = fmin(v3_length(v3_sub(c, b.eye[0])), v3_length(v3_sub(c, b.eye[1])));
            assert_true(d < 2.0 * b.eye_radius); /* bare only at the eye rings */
        }
    }
    fprintf(stderr, "skin %d triangles, %.1f cm^2; normals against their face %d; bare %d (%.2f cm^2)\n",
            m->triangle_count, area * 1e4, against, bare, bare_area * 1e4);
    assert_int_equal(against, 0);
    assert_true(bare > 0 && bare_area < 0.02 * area);
    /* Eyes left and right of the head, above the bill; shoulders apart; the tail's base behind and below. */
    assert_true(b.eye[0].y > 0.0 && b.eye[1].y < 0.0);
    assert_double_near(b.eye[0].y, -b.eye[1].y, 1e-9);
    assert_true(b.shoulder[0].y > 0.0 && b.shoulder[1].y < 0.0);
    assert_true(b.tail_base.x < b.eye[0].x && b.tail_base.z < b.eye[0].z);
    double bill_tip = -INFINITY;
    for (int i = 0; i < b.upper_bill.vertex_count; ++i)
        bill_tip = fmax(bill_tip, b.upper_bill.positions[3 * i]);
    assert_true(bill_tip > b.eye[0].x + 0.5 * bird.m.bill_length * 1e-3);
    plm_bird_body_free(&b);
}

static void build_is_deterministic(void **state)
{
    (void)state;
    plm_error err = {{0}};
    assert_int_equal(plm_bird_load(AMAZON, &bird, &err), PLM_OK);
    plm_bird_body a, b;
    assert_int_equal(plm_bird_build(&bird, 2, &a, &err), PLM_OK);
    assert_int_equal(plm_bird_build(&bird, 2, &b, &err), PLM_OK);
    assert_int_equal(a.skin.vertex_count, b.skin.vertex_count);
    assert_memory_equal(a.skin.positions, b.skin.positions, sizeof(float) * 3 * (size_t)a.skin.vertex_count);
    assert_memory_equal(a.tract, b.tract, sizeof(int) * (size_t)a.skin.triangle_count);
    plm_bird_body_free(&a);
    plm_bird_body_free(&b);
}

/* The tail: a fan of rectrices, the central ones longest and on top, with
 * coverts over their bases; the wings' frames mirror each other. */
static void tail_fans_and_wings_mirror(void **state)
{
    (void)state;
    plm_error err = {{0}};
    assert_int_equal(plm_bird_load(AMAZON, &bird, &err), PLM_OK);
    assert_true(bird.tail.present && bird.wings.present);
    plm_bird_body b;
    assert_int_equal(plm_bird_build(&bird, 2, &b, &err), PLM_OK);
    plm_species rectrix, covert;
    assert_int_equal(plm_species_load(bird.tail.rectrix, &rectrix, &err), PLM_OK);
    assert_int_equal(plm_species_load(bird.tail.covert, &covert, &err), PLM_OK);
    plm_layout l;
    assert_int_equal(plm_bird_tail_layout(&bird, &b, &rectrix, &covert, &l, &err), PLM_OK);
    int n = bird.tail.count;
    assert_int_equal(l.instance_count, 3 * n);
    double longest = 0.0, outer = 0.0;
    for (int i = 0; i < n; ++i) {
        const plm_layout_instance *in = &l.instances[i];
        vec3 root = v3(in->m[0][3], in->m[1][3], in->m[2][3]);
        assert_true(v3_length(v3_sub(root, b.tail_base)) < 0.01); /* rooted within 1 cm of the tail's base */
        double len = v3_length(v3(in->m[0][1], in->m[1][1], in->m[2][1])) * rectrix.shape.length;
        if (i == n / 2)
            longest = len;
        if (i == 0)
            outer = len;
        /* a rectrix points back along the tail */
        assert_true(v3_dot(v3(in->m[0][1], in->m[1][1], in->m[2][1]), b.tail_direction) > 0.0);
    }
    fprintf(stderr, "tail: central rectrix %.1f mm, outer %.1f mm\n", longest * 1e3, outer * 1e3);
    assert_double_near(longest, bird.m.tail_length * 1e-3, 0.12 * bird.m.tail_length * 1e-3);
    assert_true(outer < longest);
    double left[3][4], right[3][4];
    plm_bird_wing_frame(&b, 0, 0.003, left);
    plm_bird_wing_frame(&b, 1, 0.003, right);
    for (int c = 0; c < 4; ++c) {
        assert_double_near(left[0][c], right[0][c], 1e-12);
        assert_double_near(left[1][c], -right[1][c], 1e-12);
        assert_double_near(left[2][c], right[2][c], 1e-12);
    }
    assert_true(right[1][3] < 0.0 && left[1][3] > 0.0); /* each wing outside its flank */
    plm_layout_free(&l);
    plm_species_free(&rectrix);
    plm_species_free(&covert);
    plm_bird_body_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(amazon_reads),
        cmocka_unit_test(bad_presets_name_the_field),
        cmocka_unit_test(body_is_a_closed_dressed_skin),
        cmocka_unit_test(build_is_deterministic),
        cmocka_unit_test(tail_fans_and_wings_mirror),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
