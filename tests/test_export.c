/* glTF export (export/): the bake against first principles and the
 * renderer's own furnace, and round trips of a small pelt and the default
 * wing read back through Assimp and compared with the scene's instances. */
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
#include <sys/stat.h>
#include <unistd.h>

#include "export/asset.h"
#include "export/gltf.h"
#include "render/render.h"
#include "render/scene_build.h"
#include "scene/scene_file.h"
#include "test_feather_bsdf_stats.h"
#include "test_render_stats.h"

/* A diffuse material bakes to exactly what it is: its reflectance as colour,
 * 1 - transmission as alpha; the furnace radiance t + (1 - t) rho. */
static void diffuse_bakes_to_its_reflectance(void **state)
{
    (void)state;
    plm_material m = plm_diffuse_material("grey", rgb_make(0.3, 0.5, 0.7), 0.2);
    plm_bake_albedo al;
    plm_error err;
    assert_int_equal(plm_bake_albedo_of(&m, &(plm_bake_options){0}, &al, &err), PLM_OK);
    assert_double_near(al.colour.r, 0.3, 0.0);
    assert_double_near(al.colour.b, 0.7, 0.0);
    assert_double_near(al.alpha, 0.8, 1e-15);
    plm_bake_view v;
    assert_int_equal(plm_bake_view_at(&m, v3_normalize(v3(0.3, 0.1, 0.9)), 256, 1, &v, &err), PLM_OK);
    assert_double_near(v.radiance.g, 0.2 + 0.8 * 0.5, 1e-12);
}

/* A feather that absorbs nothing (clear fibers, white medulla) sends all the
 * light back in the furnace but for what the fiber lobes lose (at most a
 * few percent; test_feather_bsdf's furnace): a C + (1 - a) is 1 within
 * that, and a is the masking's 1 - <w_t>, strictly between 0 and 1. */
static void clear_feather_bakes_to_white(void **state)
{
    (void)state;
    plm_feather_params p;
    plm_feather_params_default(&p);
    p.barb.sigma_a = p.barbule.sigma_a = rgb_gray(0.0);
    p.barb.medulla_reflectance = rgb_gray(1.0);
    p.bcsdf = PLM_BCSDF_STOCHASTIC;
    plm_material m = feather_material(&p, plm_radians(60.0));
    plm_bake_albedo al;
    plm_error err;
    assert_int_equal(plm_bake_albedo_of(&m, &(plm_bake_options){16, 64, 3}, &al, &err), PLM_OK);
    double furnace = al.alpha * rgb_mean(al.colour) + (1.0 - al.alpha);
    fprintf(stderr, "clear feather: colour %.4f %.4f %.4f (se %.4f), alpha %.4f, furnace %.4f\n", al.colour.r,
            al.colour.g, al.colour.b, al.colour_se, al.alpha, furnace);
    assert_true(al.alpha > 0.0 && al.alpha < 1.0);
    assert_true(furnace > 0.95 && furnace < 1.0 + 4.0 * al.colour_se);
    free_material(&m);
}

/* The bake's L(wo) against the renderer's image of the same material on a
 * quad that fills the view, under a white sky of radiance 1 (far field, the
 * fiber tables as rendering uses them): agree within 4 standard errors. */
static void bake_agrees_with_the_renderers_furnace(void **state)
{
    (void)state;
    const vec3 views[2] = {{0.0, 0.0, 1.0}, {0.0, -0.5, 0.866}};
    for (int k = 0; k < 2; ++k) {
        plm_scene s;
        plm_scene_init(&s);
        plm_feather_params p;
        plm_feather_params_default(&p);
        plm_mesh quad;
        plm_error err;
        assert_int_equal(plm_shape_quad(40.0, 40.0, 0.0, 1, &quad, &err), PLM_OK);
        plm_material fm = feather_material(&p, plm_radians(60.0));
        int mat = plm_scene_add_material(&s, &fm);
        assert_true(plm_scene_add_object(&s, plm_scene_add_mesh(&s, "quad", &quad), mat, plm_xform_identity()) >= 0);
        plm_light sky = plm_constant_sky(rgb_gray(1.0));
        assert_true(plm_scene_add_light(&s, &sky) >= 0);
        vec3 wo = v3_normalize(views[k]);
        /* A narrow view from 10 units away: wo varies by under 0.1 degrees. */
        s.camera = (plm_camera_desc){v3_scale(wo, 10.0), v3(0, 0, 0), v3(0, 1, 0), 0.1, 0, 0, 1};
        s.film.width = s.film.height = 8;
        s.film.far_field = 1;
        plm_world w;
        assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
        estimate render = film_mean(&w, PLM_ESTIMATOR_MIS, 4, 20000, 11 + k);
        plm_bake_view v;
        assert_int_equal(plm_bake_view_at(&s.materials[mat], wo, 64 * 256, 5 + k, &v, &err), PLM_OK);
        estimate bake = {rgb_mean(v.radiance), v.radiance_se};
        fprintf(stderr, "furnace from (%.2f %.2f %.2f): render %.4f +- %.4f, bake %.4f +- %.4f (w_t %.3f)\n", wo.x,
                wo.y, wo.z, render.mean, render.se, bake.mean, bake.se, v.transmission);
        assert_agree(render, bake, 4.0);
        plm_world_free(&w);
        plm_scene_free(&s);
    }
}

/* --- round trips ------------------------------------------------------ */

/* Curves (a feather's fluff) are not exported (export/gltf.c). */
static int exported(const plm_scene *s, int i) { return s->meshes[s->instances[i].mesh].curves.curve_count == 0; }

static int distinct_pairs(const plm_scene *s)
{
    int n = 0;
    for (int i = 0; i < s->instance_count; ++i) {
        if (!exported(s, i))
            continue;
        int seen = 0;
        for (int j = 0; j < i && !seen; ++j)
            seen = s->instances[j].mesh == s->instances[i].mesh && s->instances[j].material == s->instances[i].material;
        n += !seen;
    }
    return n;
}

static const plm_asset_summary_node *find_node(const plm_asset_summary *a, const char *name)
{
    for (int i = 0; i < a->node_count; ++i)
        if (strcmp(a->nodes[i].name, name) == 0)
            return &a->nodes[i];
    return NULL;
}

/* a = b c for 3x4 affine matrices. */
static void compose(const double b[3][4], const double c[3][4], double a[3][4])
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j)
            a[i][j] = b[i][0] * c[0][j] + b[i][1] * c[1][j] + b[i][2] * c[2][j] + (j == 3 ? b[i][3] : 0.0);
}

/* Every instance of s is in the file read back as a: its node (feather_NNNN
 * or MESH_INDEX) under the root with the instance's transform, one of the
 * node's meshes with the instance's vertex and triangle counts and its
 * material's name; feathers of one prototype share their meshes. */
static void check_round_trip(const plm_scene *s, const plm_asset_summary *a, const plm_gltf_report *r)
{
    int feathers = 0, others = 0;
    for (int i = 0; i < s->instance_count; ++i) {
        int first = exported(s, i);
        for (int j = 0; j < i && first && s->instances[i].feather; ++j)
            first = s->instances[j].feather != s->instances[i].feather;
        feathers += s->instances[i].feather && first;
        others += !s->instances[i].feather;
    }
    fprintf(stderr, "  %d instances: %d feathers, %d others, %d (mesh, material) pairs; read back %d nodes, %d meshes, "
            "%d materials, %d textures\n", s->instance_count, feathers, others, distinct_pairs(s), a->node_count,
            a->mesh_count, a->material_count, a->texture_count);
    assert_int_equal(a->node_count, 1 + feathers + others);
    assert_int_equal(r->nodes, a->node_count);
    assert_int_equal(a->mesh_count, distinct_pairs(s));
    double root[3][4];
    plm_gltf_root_matrix(s, root);
    for (int j = 0; j < 12; ++j)
        assert_double_near(a->nodes[0].world[j / 4][j % 4], root[j / 4][j % 4], 1e-7);
    int *mesh_of_pair = malloc(sizeof(int) * (size_t)s->mesh_count * (size_t)s->material_count);
    for (int k = 0; k < s->mesh_count * s->material_count; ++k)
        mesh_of_pair[k] = -1;
    for (int i = 0; i < s->instance_count; ++i) {
        const plm_instance *in = &s->instances[i];
        char name[64];
        if (!exported(s, i))
            continue;
        if (in->feather)
            snprintf(name, sizeof name, "feather_%04d", in->feather);
        else
            snprintf(name, sizeof name, "%.40s_%d", s->meshes[in->mesh].name, i);
        const plm_asset_summary_node *n = find_node(a, name);
        assert_non_null(n);
        assert_int_equal(n->parent, 0);
        double want[3][4];
        compose(root, in->xform.m, want);
        for (int j = 0; j < 12; ++j)
            assert_double_near(n->world[j / 4][j % 4], want[j / 4][j % 4], 1e-6 * (1.0 + fabs(want[j / 4][j % 4])));
        const plm_mesh *m = &s->meshes[in->mesh].mesh;
        int found = -1;
        for (int k = 0; k < n->mesh_count && found < 0; ++k) {
            const plm_asset_summary_mesh *am = &a->meshes[n->mesh[k]];
            if (am->vertex_count == m->vertex_count && am->face_count == m->triangle_count &&
                strcmp(a->materials[am->material].name, s->materials[in->material].name) == 0)
                found = n->mesh[k];
        }
        if (found < 0)
            fail_msg("%s: no mesh of %d vertices, %d triangles, material %s", name, m->vertex_count,
                     m->triangle_count, s->materials[in->material].name);
        int *shared = &mesh_of_pair[in->mesh * s->material_count + in->material];
        if (*shared < 0)
            *shared = found;
        assert_int_equal(found, *shared); /* one mesh per (mesh, material): instances share it */
        const plm_asset_summary_mesh *am = &a->meshes[found];
        assert_int_equal(am->has_uvs, m->uvs != NULL);
        const plm_asset_summary_material *mat = &a->materials[am->material];
        if (s->materials[in->material].type == PLM_MATERIAL_FEATHER)
            assert_true(mat->base_color_textures == 1 && mat->blend);
    }
    free(mesh_of_pair);
}

static void round_trip(const char *preset, const char *const *sets, int n_sets, const char *out)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/presets/scenes/%s", PLUMAGE_SOURCE_DIR, preset);
    plm_scene s;
    plm_error err;
    if (plm_scene_load_with(path, sets, n_sets, &s, &err) != PLM_OK)
        fail_msg("%s", err.message);
    plm_gltf_options o = {.bake = {4, 8, 1}};
    plm_gltf_report r;
    if (plm_gltf_export(&s, out, &o, &r, &err) != PLM_OK)
        fail_msg("%s", err.message);
    plm_asset_summary a;
    if (plm_asset_read_gltf(out, &a, &err) != PLM_OK)
        fail_msg("%s", err.message);
    fprintf(stderr, "%s -> %s\n", preset, out);
    check_round_trip(&s, &a, &r);
    plm_asset_summary_free(&a);
    plm_scene_free(&s);
}

static const char *const small[] = {"objects.0.layout.level=1", "objects.0.layout.texture_size=64"};

static void pelt_round_trip(void **state)
{
    (void)state;
    round_trip("pelt_82.json", small, 2, "export_pelt.glb");
    /* Embedded: every texture is in the file. */
    plm_asset_summary a;
    plm_error err;
    assert_int_equal(plm_asset_read_gltf("export_pelt.glb", &a, &err), PLM_OK);
    assert_true(a.texture_count >= 2);
    for (int i = 0; i < a.material_count; ++i)
        assert_true(!a.materials[i].base_color_textures || a.materials[i].texture_embedded);
    plm_asset_summary_free(&a);
    remove("export_pelt.glb");
}

static void wing_round_trip_as_gltf(void **state)
{
    (void)state;
    mkdir("export_wing", 0755);
    round_trip("default.json", small, 2, "export_wing/wing.gltf");
    struct stat st;
    assert_int_equal(stat("export_wing/wing.bin", &st), 0);
    /* The textures beside it, named after their materials. */
    char cmd[256];
    snprintf(cmd, sizeof cmd, "ls export_wing/wing.*.albedo.png export_wing/wing.*.orientation.png | wc -l");
    FILE *p = popen(cmd, "r");
    int n = 0;
    assert_int_equal(fscanf(p, "%d", &n), 1);
    pclose(p);
    assert_true(n >= 2 && n % 2 == 0);
    assert_int_equal(system("rm -r export_wing"), 0);
}

/* Bad requests fail with the path in the message and leave no file. */
static void refusals_leave_nothing(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    plm_mesh quad;
    plm_error err;
    assert_int_equal(plm_shape_quad(1.0, 1.0, 0.0, 1, &quad, &err), PLM_OK);
    plm_material m = plm_diffuse_material("grey", rgb_gray(0.5), 0.0);
    assert_true(plm_scene_add_object(&s, plm_scene_add_mesh(&s, "quad", &quad), plm_scene_add_material(&s, &m),
                                     plm_xform_identity()) >= 0);
    plm_gltf_options o = {0};
    assert_int_equal(plm_gltf_export(&s, "export_bad.obj", &o, NULL, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "export_bad.obj: unsupported format"));
    assert_int_not_equal(access("export_bad.obj", F_OK), 0);
    assert_int_equal(plm_gltf_export(&s, "no_such_dir/x.glb", &o, NULL, &err), PLM_ERR_IO);
    assert_non_null(strstr(err.message, "no_such_dir/x.glb"));
    /* A scene of one quad exports (one node under the root, opaque grey). */
    assert_int_equal(plm_gltf_export(&s, "export_quad.glb", &o, NULL, &err), PLM_OK);
    plm_asset_summary a;
    assert_int_equal(plm_asset_read_gltf("export_quad.glb", &a, &err), PLM_OK);
    assert_int_equal(a.node_count, 2);
    assert_int_equal(a.mesh_count, 1);
    assert_false(a.materials[0].blend);
    plm_asset_summary_free(&a);
    remove("export_quad.glb");
    /* Not a glTF file: Assimp's reader says so. */
    FILE *fp = fopen("export_junk.glb", "wb");
    fputs("not a glb", fp);
    fclose(fp);
    assert_int_equal(plm_asset_read_gltf("export_junk.glb", &a, &err), PLM_ERR_PARSE);
    remove("export_junk.glb");
    plm_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(diffuse_bakes_to_its_reflectance),
        cmocka_unit_test(clear_feather_bakes_to_white),
        cmocka_unit_test(bake_agrees_with_the_renderers_furnace),
        cmocka_unit_test(pelt_round_trip),
        cmocka_unit_test(wing_round_trip_as_gltf),
        cmocka_unit_test(refusals_leave_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
