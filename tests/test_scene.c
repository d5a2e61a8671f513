/* Scene files: fields and defaults, includes with relative paths, instances
 * and transforms, and errors that name the file, the field path and the
 * allowed values. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/fileio.h"
#include "common/image_io.h"
#include "generate/species.h"
#include "optics/feather_bsdf.h"
#include "render/scene.h"
#include "scene/scene_file.h"

static char dir[256];

static void write_file(const char *name, const char *text)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/plumage_test_scene_XXXXXX");
    if (!mkdtemp(dir))
        return -1;
    char sub[512];
    snprintf(sub, sizeof sub, "%s/feather", dir);
    plm_error err;
    if (plm_make_dirs(sub, &err) != PLM_OK)
        return -1;
    /* A 4x2 feather texture: left column background, the rest vane. */
    float px[4 * 2 * 3];
    for (int i = 0; i < 8; ++i)
        px[3 * i] = 1.0f, px[3 * i + 1] = 0.5f, px[3 * i + 2] = i % 4 == 0 ? 0.0f : 1.0f;
    char tex[600];
    snprintf(tex, sizeof tex, "%s/texture.exr", sub);
    return plm_image_write(tex, 4, 2, 3, PLM_PIXEL_FLOAT, px, &err) == PLM_OK ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static plm_result load(const char *name, plm_scene *s, plm_error *err)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return plm_scene_load(path, s, err);
}

static void defaults_when_fields_are_absent(void **state)
{
    (void)state;
    write_file("empty.json", "{}");
    plm_scene s;
    plm_error err;
    assert_int_equal(load("empty.json", &s, &err), PLM_OK);
    assert_int_equal(s.film.width, 512);
    assert_int_equal(s.film.height, 512);
    assert_int_equal(s.film.spp, 64);
    assert_int_equal(s.film.max_depth, 16);
    assert_int_equal((int)s.film.seed, 1);
    assert_int_equal(s.film.fiber_table_mib, 32);
    assert_false(s.camera.given);
    assert_double_near(s.camera.fov, 40.0, 0);
    assert_string_equal(s.film.png, "");
    assert_int_equal(s.instance_count, 0);
    plm_scene_free(&s);
}

/* The generator's feather.json works alone and through an include; paths
 * resolve against the file that names them. */
static void includes_resolve_relative_paths(void **state)
{
    (void)state;
    write_file("feather/feather.json",
               "{\"meshes\": {\"vane\": {\"shape\": \"quad\", \"size\": [0.2, 1]}},\n"
               " \"materials\": {\"vane\": {\"type\": \"diffuse\", \"mask\": \"texture.exr\"}},\n"
               " \"objects\": [{\"mesh\": \"vane\", \"material\": \"vane\"}]}");
    write_file("top.json",
               "{\"include\": \"feather/feather.json\",\n"
               " \"camera\": {\"position\": [0, 0, 3], \"fov\": 30},\n"
               " \"film\": {\"width\": 64, \"height\": 32, \"spp\": 4, \"png\": \"out.png\"},\n"
               " \"lights\": [{\"type\": \"environment\", \"radiance\": [1, 2, 3]},\n"
               "            {\"type\": \"distant\", \"direction\": [0, 2, 0], \"irradiance\": [3, 3, 3]},\n"
               "            {\"type\": \"sky\", \"sun_elevation\": 30, \"sun_azimuth\": 120, \"turbidity\": 3,\n"
               "             \"up\": [0, 0, 2], \"visible\": false, \"intensity\": 0.5, \"ground\": true}],\n"
               " \"objects\": [{\"mesh\": \"vane\", \"material\": \"vane\", \"tint\": [0.5, 0.5, 0.5],\n"
               "   \"tint_jitter\": 0.4, \"seed\": 3,\n"
               "   \"transform\": {\"translate\": [0, 0, 1]},\n"
               "   \"instances\": [{\"transform\": {\"scale\": 2, \"rotate\": [0, 0, 90]}}, {}, {}]}]}");
    plm_scene s;
    plm_error err;
    assert_int_equal(load("feather/feather.json", &s, &err), PLM_OK);
    assert_int_equal(s.instance_count, 1);
    assert_int_equal(s.materials[0].texture.width, 4);
    plm_scene_free(&s);

    if (load("top.json", &s, &err) != PLM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(s.mesh_count, 1);
    assert_int_equal(s.instance_count, 4);
    assert_int_equal(s.light_count, 3);
    assert_int_equal(s.lights[0].type, PLM_LIGHT_CONSTANT_ENV);
    assert_double_near(s.lights[0].intensity, 1.0, 0.0);
    assert_true(s.lights[0].visible && !s.lights[0].ground);
    assert_double_near(s.lights[1].direction.y, 1.0, 1e-12);
    const plm_light *sky = &s.lights[2];
    assert_int_equal(sky->type, PLM_LIGHT_SKY);
    assert_double_near(sky->sky.sun_azimuth, plm_radians(120.0), 1e-12);
    assert_double_near(sky->sky.sun_size, plm_radians(0.53), 1e-12);
    assert_double_near(sky->up.z, 1.0, 1e-12);
    assert_double_near(sky->intensity, 0.5, 0.0);
    assert_true(!sky->visible && sky->ground && sky->sky.sun);
    assert_true(s.camera.given);
    assert_double_near(s.camera.fov, 30.0, 0);
    assert_int_equal(s.film.width, 64);
    assert_string_equal(s.film.png, "out.png");
    assert_int_equal(s.materials[0].texture.region[0], PLM_REGION_BACKGROUND);
    assert_int_equal(s.materials[0].texture.region[1], PLM_REGION_VANE);
    /* Instance 1: scale 2, rotate 90 about z, then the object's translate: (1,0,0) -> (0,2,1). */
    vec3 p = plm_xform_point(s.instances[1].xform.m, v3(1, 0, 0));
    assert_double_near(p.x, 0.0, 1e-12);
    assert_double_near(p.y, 2.0, 1e-12);
    assert_double_near(p.z, 1.0, 1e-12);
    vec3 q = plm_xform_point(s.instances[1].xform.inv, p);
    assert_double_near(q.x, 1.0, 1e-12);
    /* Tints vary per instance but never brighten and never leave [tint (1 - jitter), tint]. */
    for (int i = 1; i < 4; ++i) {
        rgb t = s.instances[i].tint;
        assert_true(t.r <= 0.5 && t.r >= 0.3 && t.g <= 0.5 && t.g >= 0.3 && t.b <= 0.5 && t.b >= 0.3);
    }
    assert_true(s.instances[1].tint.r != s.instances[2].tint.r);
    plm_scene_free(&s);
}

/* A feather material: every field read, degrees converted, defaults kept where absent. */
static void feather_material_fields(void **state)
{
    (void)state;
    write_file("feather/material.json",
               "{\"materials\": {\"f\": {\"type\": \"feather\", \"texture\": \"texture.exr\",\n"
               "  \"rachis_reflectance\": [0.2, 0.3, 0.4],\n"
               "  \"barb\": {\"eccentricity\": 1.6, \"eta\": 1.53, \"sigma_a\": [1, 2, 3], \"beta_m\": 10,\n"
               "           \"beta_n\": 20, \"medulla_axes\": [0.5, 0.4], \"medulla_centre\": [-0.1, 0.1],\n"
               "           \"medulla_reflectance\": [0.1, 0.2, 0.9], \"lobes\": 7},\n"
               "  \"barbule\": {\"eccentricity\": 2},\n"
               "  \"masking\": {\"barb_eccentricity\": 1.6, \"barbule_length\": 2,\n"
               "              \"barbule_separation\": 0.3, \"barbule_rotation\": 40, \"barbule_inclination\": -30}}}}");
    plm_scene s;
    plm_error err;
    if (load("feather/material.json", &s, &err) != PLM_OK)
        fail_msg("%s", err.message);
    const plm_material *m = &s.materials[0];
    assert_int_equal(m->type, PLM_MATERIAL_FEATHER);
    assert_double_near(m->reflectance.b, 0.4, 0);
    const plm_feather_params *p = m->feather;
    assert_double_near(p->barb.eccentricity, 1.6, 0);
    assert_double_near(p->barb.sigma_a.g, 2.0, 0);
    assert_double_near(p->barb.beta_m, plm_radians(10.0), 1e-15);
    assert_double_near(p->barb.beta_n, plm_radians(20.0), 1e-15);
    assert_double_near(p->barb.medulla_b, 0.4, 0);
    assert_double_near(p->barb.medulla_ca, -0.1, 0);
    assert_int_equal(p->barb.lobes, 7);
    assert_double_near(p->barbule.eccentricity, 2.0, 0);
    assert_double_near(p->masking.barb_eccentricity, 1.6, 0);
    assert_double_near(p->masking.barbule_eccentricity, 2.0, 0); /* the barbule fiber's: one cross-section */
    plm_feather_params def;
    plm_feather_params_default(&def);
    assert_double_near(p->barbule.eta, def.barbule.eta, 0);
    assert_double_near(p->masking.barbule_rotation, plm_radians(40.0), 1e-15);
    assert_double_near(p->masking.barbule_inclination, plm_radians(-30.0), 1e-15);
    assert_double_near(p->masking.barbule_separation, 0.3, 0);
    assert_int_equal(m->texture.width, 4);
    plm_scene_free(&s);
}

/* A barb's or barbule's cross-section is one ellipse: the fiber's eccentricity
 * and the masking's barb_eccentricity / barbule_eccentricity are one number.
 * Either may be given and the other takes it; both must agree; each must fit
 * the other's range; a medulla must still fit the cortex it gives. */
static void eccentricity_is_one_value(void **state)
{
    (void)state;
    write_file("feather/ecc_masking.json",
               "{\"materials\": {\"f\": {\"type\": \"feather\", \"texture\": \"texture.exr\",\n"
               "  \"masking\": {\"barb_eccentricity\": 2.5, \"barbule_eccentricity\": 1.2}}}}");
    plm_scene s;
    plm_error err;
    if (load("feather/ecc_masking.json", &s, &err) != PLM_OK)
        fail_msg("%s", err.message);
    const plm_feather_params *p = s.materials[0].feather;
    assert_double_near(p->barb.eccentricity, 2.5, 0);
    assert_double_near(p->barbule.eccentricity, 1.2, 0);
    assert_double_near(p->masking.barb_eccentricity, 2.5, 0);
    plm_scene_free(&s);
    const struct { const char *json; const char *const *words; } bad[] = {
        {"\"barb\": {\"eccentricity\": 1.6}, \"masking\": {\"barb_eccentricity\": 3}",
         (const char *const[]){"materials.f.masking.barb_eccentricity", "3", "barb.eccentricity is 1.6", "give one",
                               NULL}},
        {"\"barbule\": {\"eccentricity\": 30}",
         (const char *const[]){"materials.f.barbule", "30", "over 20", "masking.barbule_eccentricity", NULL}},
        {"\"masking\": {\"barb_eccentricity\": 0.005}",
         (const char *const[]){"materials.f.masking.barb_eccentricity", "under 0.01", NULL}},
        {"\"barb\": {\"medulla_axes\": [0.5, 0.9]}, \"masking\": {\"barb_eccentricity\": 0.8}",
         (const char *const[]){"materials.f.barb", "from masking.barb_eccentricity", NULL}},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        char json[512];
        snprintf(json, sizeof json, "{\"materials\": {\"f\": {\"type\": \"feather\", \"texture\": \"texture.exr\", %s}}}",
                 bad[i].json);
        write_file("feather/ecc_bad.json", json);
        assert_int_equal(load("feather/ecc_bad.json", &s, &err), PLM_ERR_INVALID);
        for (const char *const *w = bad[i].words; *w; ++w)
            if (!strstr(err.message, *w))
                fail_msg("case %zu: \"%s\" not in: %s", i, *w, err.message);
    }
}

/* A fiber's pigments become its sigma_a: concentrations times the published
 * melanin coefficients (Chiang et al. 2016: eumelanin (0.419, 0.697, 1.37),
 * pheomelanin (0.187, 0.4, 1.05) per unit radius), summed. */
static void fiber_pigments_give_sigma_a(void **state)
{
    (void)state;
    write_file("feather/pigments.json",
               "{\"materials\": {\"f\": {\"type\": \"feather\", \"texture\": \"texture.exr\",\n"
               "  \"barb\": {\"pigments\": {\"eumelanin\": 2, \"pheomelanin\": 0.5}},\n"
               "  \"barbule\": {\"pigments\": {}}}}}");
    plm_scene s;
    plm_error err;
    if (load("feather/pigments.json", &s, &err) != PLM_OK)
        fail_msg("%s", err.message);
    const plm_feather_params *p = s.materials[0].feather;
    assert_double_near(p->barb.sigma_a.r, 2 * 0.419 + 0.5 * 0.187, 1e-15);
    assert_double_near(p->barb.sigma_a.g, 2 * 0.697 + 0.5 * 0.4, 1e-15);
    assert_double_near(p->barb.sigma_a.b, 2 * 1.37 + 0.5 * 1.05, 1e-15);
    assert_double_near(p->barbule.sigma_a.g, 0.0, 0); /* no pigment: a clear fiber */
    plm_scene_free(&s);
}

/* Each bad file must fail with a message holding every listed fragment. */
static void expect_error(const char *text, const char *const *fragments)
{
    write_file("bad.json", text);
    plm_scene s;
    plm_error err = {{0}};
    assert_int_not_equal(load("bad.json", &s, &err), PLM_OK);
    for (const char *const *f = fragments; *f; ++f)
        if (!strstr(err.message, *f))
            fail_msg("message \"%s\" lacks \"%s\"", err.message, *f);
}

static void errors_name_file_field_and_allowed_values(void **state)
{
    (void)state;
    expect_error("{\"camera\": {\"fov\": 200}}", (const char *const[]){"bad.json", "camera.fov", "[0.01, 179]", NULL});
    expect_error("{\"materials\": {\"f\": {\"type\": \"feather\", \"texture\": \"feather/texture.exr\", "
                 "\"barb\": {\"sigma_a\": [1, 1, 1], \"pigments\": {\"eumelanin\": 1}}}}}",
                 (const char *const[]){"bad.json", "materials.f.barb.pigments", "sigma_a or pigments", NULL});
    expect_error("{\"materials\": {\"f\": {\"type\": \"feather\", \"texture\": \"feather/texture.exr\", "
                 "\"barb\": {\"pigments\": {\"eumelanin\": -1}}}}}",
                 (const char *const[]){"bad.json", "materials.f.barb.pigments.eumelanin", "[0, 100]", NULL});
    expect_error("{\"camera\": {\"fob\": 20}}",
                 (const char *const[]){"bad.json", "camera.fob", "unknown field", "position", NULL});
    expect_error("{\"film\": {\"spp\": \"many\"}}", (const char *const[]){"film.spp", "number", NULL});
    expect_error("{\"film\": {\"width\": 0}}", (const char *const[]){"film.width", "[1, 16384]", NULL});
    expect_error("{\"film\": {\"spp\": 1.5}}", (const char *const[]){"film.spp", "whole number", NULL});
    expect_error("{\"film\": {\"fiber_table_mib\": 4}}",
                 (const char *const[]){"bad.json", "film.fiber_table_mib", "[8, 4096]", NULL});
    expect_error("{\"lights\": [{\"type\": \"laser\"}]}",
                 (const char *const[]){"lights[0].type", "\"environment\"", "\"quad\"", NULL});
    expect_error("{\"lights\": [{\"radiance\": [1, 1, 1]}]}", (const char *const[]){"lights[0].type", "required", NULL});
    expect_error("{\"lights\": [{\"type\": \"sphere\", \"radius\": -1}]}", (const char *const[]){"lights[0].radius", NULL});
    expect_error("{\"lights\": [{\"type\": \"sky\", \"turbidity\": 20}]}",
                 (const char *const[]){"bad.json", "lights[0].turbidity", "[1.7, 10]", NULL});
    expect_error("{\"lights\": [{\"type\": \"sky\", \"map\": \"sky.exr\"}]}",
                 (const char *const[]){"bad.json", "lights[0]", "map", NULL});
    expect_error("{\"lights\": [{\"type\": \"environment\", \"up\": [0, 0, 0]}]}",
                 (const char *const[]){"bad.json", "lights[0].up", "non-zero", NULL});
    expect_error("{\"lights\": [{\"type\": \"environment\", \"map\": \"nowhere.exr\"}]}",
                 (const char *const[]){"bad.json", "lights[0].map", "nowhere.exr", NULL});
    expect_error("{\"meshes\": {\"m\": {\"file\": \"missing.ply\"}}}",
                 (const char *const[]){"meshes.m.file", "missing.ply", NULL});
    expect_error("{\"meshes\": {\"m\": {\"shape\": \"torus\"}}}", (const char *const[]){"meshes.m.shape", "\"sphere\"", NULL});
    expect_error("{\"meshes\": {\"m\": {\"shape\": \"quad\", \"size\": [1]}}}", (const char *const[]){"meshes.m.size", NULL});
    expect_error("{\"materials\": {\"a\": {\"reflectance\": [2, 0, 0]}}}",
                 (const char *const[]){"materials.a.reflectance", "[0, 1]", NULL});
    expect_error("{\"materials\": {\"a\": {\"mask\": \"none.exr\"}}}", (const char *const[]){"materials.a.mask", "none.exr", NULL});
    expect_error("{\"objects\": [{\"mesh\": \"nothing\", \"material\": \"x\"}]}",
                 (const char *const[]){"objects[0].mesh", "\"nothing\" is not defined", NULL});
    expect_error("{\"meshes\": {\"q\": {\"shape\": \"quad\"}}, \"materials\": {\"d\": {}},"
                 " \"objects\": [{\"mesh\": \"q\", \"material\": \"d\", \"instances\": [{\"transform\": {\"scale\": 0}}]}]}",
                 (const char *const[]){"objects[0].instances[0].scale", "non-zero", NULL});
    expect_error("{\"include\": \"feather/feather.json\", \"meshes\": {\"vane\": {\"shape\": \"quad\"}}}",
                 (const char *const[]){"meshes.vane", "already defined", NULL});
    expect_error("{\"include\": \"nonexistent.json\"}", (const char *const[]){"nonexistent.json", NULL});
    expect_error("{\"film\": {\"width\": 10,}", (const char *const[]){"bad.json:1:", "malformed JSON", NULL});
    expect_error("{\"cameras\": {}}", (const char *const[]){"cameras", "unknown field", "include", NULL});
    expect_error("{\"camera\": {\"position\": [0, 0, 0], \"look_at\": [0, 0, 0]}}",
                 (const char *const[]){"camera.look_at", "must differ", NULL});
    expect_error("{\"materials\": {\"f\": {\"type\": \"feather\"}}}", (const char *const[]){"materials.f.texture", "required", NULL});
    expect_error("{\"materials\": {\"f\": {\"type\": \"feather\", \"texture\": \"feather/texture.exr\","
                 " \"barb\": {\"medulla_axes\": [0.9, 0.9], \"medulla_centre\": [0.5, 0]}}}}",
                 (const char *const[]){"bad.json", "materials.f.barb", "pokes out", NULL});
    expect_error("{\"materials\": {\"f\": {\"type\": \"feather\", \"barbule\": {\"lobes\": 40}}}}",
                 (const char *const[]){"materials.f.barbule.lobes", "[1, 32]", NULL});
    expect_error("{\"materials\": {\"f\": {\"type\": \"feather\", \"masking\": {\"barbule_rotation\": 100}}}}",
                 (const char *const[]){"materials.f.masking.barbule_rotation", "[0, 90]", NULL});
    expect_error("{\"materials\": {\"f\": {\"type\": \"feather\", \"masking\": {\"barbule_inclination\": 90}}}}",
                 (const char *const[]){"materials.f.masking", "barbule_inclination", "(-90, 90)", NULL});
    expect_error("{\"materials\": {\"f\": {\"type\": \"feather\", \"barb\": {\"beta\": 3}}}}",
                 (const char *const[]){"materials.f.barb.beta", "unknown field", "beta_m", NULL});
    expect_error("{\"materials\": {\"f\": {\"type\": \"feather\", \"reflectance\": [1, 1, 1]}}}",
                 (const char *const[]){"materials.f.reflectance", "unknown field", "rachis_reflectance", NULL});
    write_file("cycle.json", "{\"include\": \"cycle.json\"}");
    expect_error("{\"include\": \"cycle.json\"}", (const char *const[]){"cycle", "nested", NULL});
}

/* A scene from a buffer reads like the same text from a file; text after
 * the value is refused, and the buffer need not end in a NUL. */
static void buffer_reads_like_a_file(void **state)
{
    (void)state;
    const char *text = "{\"film\": {\"width\": 33, \"height\": 17},"
                       " \"meshes\": {\"q\": {\"shape\": \"quad\"}}, \"materials\": {\"d\": {}},"
                       " \"objects\": [{\"mesh\": \"q\", \"material\": \"d\"}]}  ";
    write_file("buffer.json", text);
    plm_scene a, b;
    plm_error err = {{0}};
    assert_int_equal(load("buffer.json", &a, &err), PLM_OK);
    char *copy = malloc(strlen(text));
    memcpy(copy, text, strlen(text)); /* no terminating NUL */
    assert_int_equal(plm_scene_load_buffer(copy, strlen(text), "mem", &b, &err), PLM_OK);
    assert_int_equal(a.film.width, b.film.width);
    assert_int_equal(a.film.height, 17);
    assert_int_equal(a.instance_count, b.instance_count);
    assert_int_equal(a.mesh_count, b.mesh_count);
    assert_int_equal(a.meshes[0].mesh.triangle_count, b.meshes[0].mesh.triangle_count);
    plm_scene_free(&a);
    plm_scene_free(&b);
    free(copy);
    const char *garbage = "{\"film\": {}} x";
    assert_int_not_equal(plm_scene_load_buffer(garbage, strlen(garbage), "mem", &b, &err), PLM_OK);
    assert_non_null(strstr(err.message, "mem:1:"));
    assert_int_not_equal(plm_scene_load_buffer(garbage, 5, "cut", &b, &err), PLM_OK);
    assert_non_null(strstr(err.message, "cut"));
}

/* Feathers of one species, level, texture size and variant are generated
 * once, however many names ask for them; another variant is another feather. */
static void species_feathers_are_generated_once(void **state)
{
    (void)state;
    char text[2048];
    snprintf(text, sizeof text,
             "{\"feathers\": {"
             "\"a\": {\"species\": \"%s/presets/species/covert_parrot.json\", \"level\": 1, \"texture_size\": 32},"
             "\"b\": {\"species\": \"%s/presets/species/covert_parrot.json\", \"level\": 1, \"texture_size\": 32},"
             "\"c\": {\"species\": \"%s/presets/species/covert_parrot.json\", \"level\": 1, \"texture_size\": 32,"
             " \"variant\": 3}},"
             " \"objects\": [{\"feather\": \"a\"}, {\"feather\": \"b\"}, {\"feather\": \"c\"}]}",
             PLUMAGE_SOURCE_DIR, PLUMAGE_SOURCE_DIR, PLUMAGE_SOURCE_DIR);
    plm_scene s;
    plm_error err = {{0}};
    assert_int_equal(plm_scene_load_buffer(text, strlen(text), "mem", &s, &err), PLM_OK);
    assert_int_equal(s.mesh_count, 6);     /* vane, rachis and fluff of a (= b) and of c */
    assert_int_equal(s.material_count, 6); /* feather, rachis and fluff materials of each */
    assert_int_equal(s.instance_count, 9);
    assert_int_equal(s.instances[0].mesh, s.instances[3].mesh);
    assert_int_equal(s.instances[1].material, s.instances[4].material);
    assert_int_not_equal(s.instances[0].mesh, s.instances[6].mesh);
    assert_int_equal(plm_scene_find_mesh(&s, "a.vane"), s.instances[0].mesh);
    assert_int_equal(plm_scene_find_mesh(&s, "a.fluff"), s.instances[2].mesh);
    assert_int_equal(s.materials[s.instances[0].material].type, PLM_MATERIAL_FEATHER);
    /* The variant has its own texture and fluff but shares the species' optics (and fiber tables). */
    const plm_material *ma = &s.materials[s.instances[0].material], *mc = &s.materials[s.instances[6].material];
    assert_ptr_equal(ma->feather, mc->feather);
    assert_true(mc->shares_feather && !ma->shares_feather);
    assert_ptr_not_equal(ma->texture.pixels, mc->texture.pixels);
    const plm_material *fa = &s.materials[s.instances[2].material], *fc = &s.materials[s.instances[8].material];
    assert_int_equal(fa->type, PLM_MATERIAL_FIBER);
    assert_ptr_equal(fa->fiber, fc->fiber);
    assert_true(fc->shares_fiber && !fa->shares_fiber);
    assert_int_not_equal(s.instances[2].mesh, s.instances[8].mesh);
    plm_scene_free(&s);
    /* A species file's errors name the scene field that named it. */
    snprintf(text, sizeof text, "{\"feathers\": {\"x\": {\"species\": \"%s/no_such_species.json\"}}}", dir);
    assert_int_not_equal(plm_scene_load_buffer(text, strlen(text), "mem", &s, &err), PLM_OK);
    assert_non_null(strstr(err.message, "feathers.x.species"));
    assert_non_null(strstr(err.message, "no_such_species.json"));
}

/* A species field has one range wherever it enters: a species file, a
 * species written inline in a scene, or --set on that inline species. The
 * range expected is the table's own (plm_shape_param_block's length). */
static void species_fields_have_one_range_everywhere(void **state)
{
    (void)state;
    const plm_param *length = &plm_shape_param_block.params[0];
    assert_string_equal(length->name, "length");
    char range[64], text[512], path[512];
    snprintf(range, sizeof range, "[%.10g, %.10g]", length->min, length->max);
    write_file("long.json", "{\"shape\": {\"length\": 5000}}");
    expect_error("{\"feathers\": {\"f\": {\"species\": \"long.json\"}}}",
                 (const char *const[]){"long.json", "shape.length", "5000", range, NULL});
    expect_error("{\"feathers\": {\"f\": {\"species\": {\"shape\": {\"length\": 5000}}}}}",
                 (const char *const[]){"bad.json", "feathers.f.species.shape.length", "5000", range, NULL});
    expect_error("{\"feathers\": {\"f\": {\"species\": 42}}}",
                 (const char *const[]){"bad.json", "feathers.f.species", "a string) or the species itself", NULL});
    /* The inline species' optics are read like a file's, with their path. */
    expect_error("{\"feathers\": {\"f\": {\"species\": {\"optics\": {\"barb\": {\"eta\": 9}}}}}}",
                 (const char *const[]){"bad.json", "feathers.f.species.optics.barb.eta", NULL});
    /* A valid inline species is generated, and --set reaches into it. */
    snprintf(text, sizeof text, "{\"feathers\": {\"f\": {\"species\": {\"shape\": {\"length\": 30}}, \"level\": 1, "
                                "\"texture_size\": 32}}, \"objects\": [{\"feather\": \"f\"}]}");
    write_file("inline.json", text);
    snprintf(path, sizeof path, "%s/inline.json", dir);
    plm_scene s;
    plm_error err = {{0}};
    assert_int_equal(plm_scene_load(path, &s, &err), PLM_OK);
    assert_int_equal(s.instance_count, 3); /* vane, rachis, fluff */
    plm_scene_free(&s);
    const char *set[] = {"feathers.f.species.shape.length=5000"};
    assert_int_not_equal(plm_scene_load_with(path, set, 1, &s, &err), PLM_OK);
    assert_non_null(strstr(err.message, "inline.json"));
    assert_non_null(strstr(err.message, "feathers.f.species.shape.length"));
    assert_non_null(strstr(err.message, range));
}

/* A pelt block places count feathers (vane, rachis and fluff each) from a few
 * prototypes generated once, plus its surface; the same seed gives the same
 * scene, another seed another; a species without optics takes the defaults. */
static void layout_blocks_place_generated_prototypes(void **state)
{
    (void)state;
    write_file("bare.json", "{\"name\": \"bare\", \"shape\": {\"length\": 40}, \"pigment\": {\"bands\": 3}}");
    const char *fmt = "{\"materials\": {\"skin\": {}}, \"objects\": [{\"layout\": {\"type\": \"pelt\","
                      " \"species\": [\"bare.json\", {\"file\": \"bare.json\", \"weight\": 2}], \"count\": 30,"
                      " \"variants\": 2, \"seed\": %d, \"level\": 1, \"texture_size\": 32,"
                      " \"surface\": {\"shape\": \"plane\", \"size\": [0.4, 0.3]}, \"surface_material\": \"skin\"},"
                      " \"transform\": {\"translate\": [1, 2, 3]}}]}";
    plm_scene s[3];
    plm_error err = {{0}};
    for (int k = 0; k < 3; ++k) {
        char text[1024], name[32];
        snprintf(text, sizeof text, fmt, k == 2 ? 8 : 7);
        snprintf(name, sizeof name, "pelt%d.json", k);
        write_file(name, text);
        if (load(name, &s[k], &err) != PLM_OK)
            fail_msg("%s", err.message);
    }
    /* 2 species entries x 2 variants = 4 prototypes: 12 feather meshes (vane, rachis, fluff) and the surface. */
    assert_int_equal(s[0].mesh_count, 13);
    assert_int_equal(s[0].instance_count, 3 * 30 + 1);
    int pigmented = 0;
    for (int m = 0; m < s[0].material_count; ++m) {
        const plm_material *mat = &s[0].materials[m];
        if (mat->type != PLM_MATERIAL_FEATHER)
            continue;
        /* No optics block: the documented defaults. */
        plm_feather_params def;
        plm_feather_params_default(&def);
        assert_double_near(mat->feather->barb.eta, def.barb.eta, 0.0);
        assert_double_near(mat->reflectance.g, 0.75, 0.0);
        pigmented += mat->pigment.pixels != NULL && mat->pigment.channels == PLM_PIGMENT_CHANNELS;
    }
    assert_int_equal(pigmented, 4);
    int same = 1, differs = 0;
    for (int i = 0; i < s[0].instance_count; ++i)
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) {
                same &= s[0].instances[i].xform.m[r][c] == s[1].instances[i].xform.m[r][c];
                differs |= s[0].instances[i].xform.m[r][c] != s[2].instances[i].xform.m[r][c];
            }
    assert_true(same);
    assert_true(differs);
    /* The object's transform moves the whole pelt: the surface sits at its translation. */
    const plm_instance *surface = &s[0].instances[s[0].instance_count - 1];
    assert_double_near(surface->xform.m[0][3], 1.0, 1e-12);
    assert_double_near(surface->xform.m[2][3], 3.0, 1e-12);
    for (int k = 0; k < 3; ++k)
        plm_scene_free(&s[k]);
    expect_error("{\"objects\": [{\"layout\": {\"type\": \"pelt\", \"species\": [\"bare.json\"], \"count\": -1,"
                 " \"surface\": {\"shape\": \"plane\"}}}]}",
                 (const char *const[]){"bad.json", "objects[0].layout.count", "[0, 1000000]", NULL});
    expect_error("{\"objects\": [{\"layout\": {\"type\": \"pelt\", \"species\": [\"bare.json\"]}}]}",
                 (const char *const[]){"objects[0].layout.surface", "required", NULL});
    expect_error("{\"objects\": [{\"layout\": {\"type\": \"ball\", \"species\": [\"bare.json\"],"
                 " \"variation\": {\"yaw\": 100}}}]}",
                 (const char *const[]){"objects[0].layout.variation.yaw", "[0, 90]", NULL});
    expect_error("{\"objects\": [{\"layout\": {\"type\": \"ball\", \"species\": [\"missing.json\"]}}]}",
                 (const char *const[]){"objects[0].layout.species[0]", "missing.json", NULL});
    expect_error("{\"objects\": [{\"layout\": {\"type\": \"wing\"}}]}",
                 (const char *const[]){"objects[0].layout.rows", "required", NULL});
    expect_error("{\"objects\": [{\"layout\": {\"type\": \"wing\", \"rows\": {\"secondary\": \"bare.json\"}}}]}",
                 (const char *const[]){"objects[0].layout.rows.primary", "required", NULL});
    expect_error("{\"objects\": [{\"layout\": {\"type\": \"wing\", \"rows\": {\"primary\": \"bare.json\","
                 " \"secondary\": \"bare.json\", \"tail\": \"bare.json\"}}}]}",
                 (const char *const[]){"objects[0].layout.rows.tail", "unknown field", "alula", NULL});
    expect_error("{\"objects\": [{\"layout\": {\"type\": \"fan\"}}]}",
                 (const char *const[]){"objects[0].layout.type", "\"wing\"", NULL});
    /* A wing: every row's feathers placed, the rows left out taking the secondary's species. */
    write_file("wing.json", "{\"objects\": [{\"layout\": {\"type\": \"wing\", \"rows\": {\"primary\": \"bare.json\","
                            " \"secondary\": \"bare.json\"}, \"primaries\": 9, \"variants\": 1, \"level\": 1,"
                            " \"texture_size\": 16}}]}");
    plm_scene w;
    if (load("wing.json", &w, &err) != PLM_OK)
        fail_msg("%s", err.message);
    assert_true(w.instance_count > 3 * (9 + 12 + 3));
    assert_int_equal(w.instance_count % 3, 0);
    /* One prototype per row (vane, rachis, fluff); none of the speculum's, which no secondary takes here. */
    assert_int_equal(w.mesh_count, 3 * 10);
    plm_scene_free(&w);
    expect_error("{\"objects\": [{\"layout\": {\"type\": \"ball\", \"species\": [\"bare.json\"], \"colour\": 1}}]}",
                 (const char *const[]){"objects[0].layout.colour", "unknown field", NULL});
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(defaults_when_fields_are_absent),
        cmocka_unit_test(includes_resolve_relative_paths),
        cmocka_unit_test(feather_material_fields),
        cmocka_unit_test(fiber_pigments_give_sigma_a),
        cmocka_unit_test(eccentricity_is_one_value),
        cmocka_unit_test(errors_name_file_field_and_allowed_values),
        cmocka_unit_test(buffer_reads_like_a_file),
        cmocka_unit_test(species_feathers_are_generated_once),
        cmocka_unit_test(species_fields_have_one_range_everywhere),
        cmocka_unit_test(layout_blocks_place_generated_prototypes),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
