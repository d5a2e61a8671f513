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

#include <cjson/cJSON.h>

#include "common/fileio.h"
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
    plm_prepared_material prepared;
    plm_material_prepare(&m, &prepared);
    assert_int_equal(plm_bake_albedo_of(&m, &prepared, &(plm_bake_options){0}, &al, &err), PLM_OK);
    assert_double_near(al.colour.r, 0.3, 0.0);
    assert_double_near(al.colour.b, 0.7, 0.0);
    assert_double_near(al.alpha, 0.8, 1e-15);
    plm_bake_view v;
    assert_int_equal(plm_bake_view_at(&m, &prepared, v3_normalize(v3(0.3, 0.1, 0.9)), 256, 1, &v, &err), PLM_OK);
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
    plm_prepared_material prepared;
    plm_material_prepare(&m, &prepared);
    plm_bake_albedo al;
    plm_error err;
    assert_int_equal(plm_bake_albedo_of(&m, &prepared, &(plm_bake_options){16, 64, 3}, &al, &err), PLM_OK);
    double furnace = al.alpha * rgb_mean(al.colour) + (1.0 - al.alpha);
    fprintf(stderr, "clear feather: colour %.4f %.4f %.4f (se %.4f), alpha %.4f, furnace %.4f\n", al.colour.r,
            al.colour.g, al.colour.b, al.colour_se, al.alpha, furnace);
    assert_true(al.alpha > 0.0 && al.alpha < 1.0);
    assert_true(furnace > 0.95 && furnace < 1.0 + 4.0 * al.colour_se);
    free_material(&m);
}

/* A fiber material (a feather's fluff) of params p, stochastic estimator. */
static plm_material fiber_material(const plm_fiber_params *p, plm_fiber_material *fm)
{
    plm_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "fluff");
    m.type = PLM_MATERIAL_FIBER;
    *fm = (plm_fiber_material){*p, 1};
    m.fiber = fm;
    return m;
}

/* A clear fiber passes straight through nothing and sends back all the
 * light it meets but for what its traced lobes lose: opaque, colour near
 * white. A fiber absorbing green and blue (the paper's Fig. 7) comes out
 * red, darker than the clear one in every channel. */
static void fibers_bake_to_their_far_field(void **state)
{
    (void)state;
    plm_fiber_params p;
    plm_fiber_params_default(&p);
    p.sigma_a = rgb_gray(0.0);
    plm_fiber_material fm;
    plm_material m = fiber_material(&p, &fm);
    plm_prepared_material prepared; /* no table: the stochastic estimator */
    plm_material_prepare(&m, &prepared);
    plm_bake_albedo clear, red;
    plm_error err;
    assert_int_equal(plm_bake_albedo_of(&m, &prepared, &(plm_bake_options){16, 64, 3}, &clear, &err), PLM_OK);
    plm_fiber_params_figure7(&p, 0);
    m = fiber_material(&p, &fm);
    assert_int_equal(plm_bake_albedo_of(&m, &prepared, &(plm_bake_options){16, 64, 3}, &red, &err), PLM_OK);
    fprintf(stderr, "clear fiber: colour %.4f %.4f %.4f (se %.4f), alpha %.4f; Fig. 7 fiber %.4f %.4f %.4f\n",
            clear.colour.r, clear.colour.g, clear.colour.b, clear.colour_se, clear.alpha, red.colour.r, red.colour.g,
            red.colour.b);
    assert_double_near(clear.alpha, 1.0, 0.0);
    assert_true(rgb_mean(clear.colour) > 0.95 && rgb_mean(clear.colour) < 1.0 + 4.0 * clear.colour_se);
    assert_true(red.colour.r > 2.0 * red.colour.g && red.colour.r > 2.0 * red.colour.b);
    assert_true(red.colour.r < clear.colour.r && red.colour.g < clear.colour.g && red.colour.b < clear.colour.b);
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
        assert_int_equal(plm_bake_view_at(&s.materials[mat], w.prepared_of[mat], wo, 64 * 256, 5 + k, &v, &err),
                         PLM_OK);
        estimate bake = {rgb_mean(v.radiance), v.radiance_se};
        fprintf(stderr, "furnace from (%.2f %.2f %.2f): render %.4f +- %.4f, bake %.4f +- %.4f (w_t %.3f)\n", wo.x,
                wo.y, wo.z, render.mean, render.se, bake.mean, bake.se, v.transmission);
        assert_agree(render, bake, 4.0);
        plm_world_free(&w);
        plm_scene_free(&s);
    }
}

/* --- round trips ------------------------------------------------------ */
/* Read back by Assimp a line mesh is one of line faces (glTF mode 1, or a
 * strip it split): check_primitive_modes reads the modes from the JSON. */

/* Everything is exported but the fluff with no_fluff (export/gltf.c). */
static int exported(const plm_scene *s, const plm_gltf_options *o, int i)
{
    return !(o->no_fluff && s->instances[i].part == PLM_PART_FLUFF);
}

/* The exported instances' distinct (mesh, material) pairs; of them, those
 * of curves and the segments those curves have (points - curves per set). */
typedef struct pairs {
    int all, curves;
    long segments;
} pairs;

static pairs distinct_pairs(const plm_scene *s, const plm_gltf_options *o)
{
    pairs n = {0, 0, 0};
    for (int i = 0; i < s->instance_count; ++i) {
        if (!exported(s, o, i))
            continue;
        int seen = 0;
        for (int j = 0; j < i && !seen; ++j)
            seen = s->instances[j].mesh == s->instances[i].mesh && s->instances[j].material == s->instances[i].material;
        const plm_curves *c = &s->meshes[s->instances[i].mesh].curves;
        n.all += !seen;
        n.curves += !seen && c->curve_count > 0;
        n.segments += seen ? 0 : c->point_count - c->curve_count;
    }
    return n;
}

/* The line meshes read back and their segments. */
static pairs line_meshes(const plm_asset_summary *a)
{
    pairs n = {a->mesh_count, 0, 0};
    for (int i = 0; i < a->mesh_count; ++i)
        if (a->meshes[i].lines)
            n.curves++, n.segments += a->meshes[i].face_count;
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

/* The mesh of node n with the instance's vertex and triangle (or, for
 * curves, line segment) counts and material name; -1 if none. */
static int mesh_of_instance(const plm_scene *s, const plm_instance *in, const plm_asset_summary *a,
                            const plm_asset_summary_node *n)
{
    const plm_scene_mesh *sm = &s->meshes[in->mesh];
    int lines = sm->curves.curve_count > 0;
    int vertices = lines ? sm->curves.point_count : sm->mesh.vertex_count;
    int faces = lines ? sm->curves.point_count - sm->curves.curve_count : sm->mesh.triangle_count;
    for (int k = 0; k < n->mesh_count; ++k) {
        const plm_asset_summary_mesh *am = &a->meshes[n->mesh[k]];
        if (am->lines == lines && am->vertex_count == vertices && am->face_count == faces &&
            strcmp(a->materials[am->material].name, s->materials[in->material].name) == 0)
            return n->mesh[k];
    }
    fail_msg("%s: no %s mesh of %d vertices, %d faces, material %s", n->name, lines ? "line" : "triangle", vertices,
             faces, s->materials[in->material].name);
    return -1;
}

/* Every exported instance of s is in the file read back as a: its node
 * (feather_NNNN or MESH_INDEX) under the root with the instance's
 * transform, one of the node's meshes with the instance's vertex and
 * triangle counts (curves: line segments) and its material's name;
 * feathers of one prototype share their meshes; as many line meshes and
 * segments as the exported curves have. */
static void check_round_trip(const plm_scene *s, const plm_gltf_options *o, const plm_asset_summary *a,
                             const plm_gltf_report *r)
{
    int feathers = 0, others = 0;
    for (int i = 0; i < s->instance_count; ++i) {
        int first = exported(s, o, i);
        for (int j = 0; j < i && first && s->instances[i].feather; ++j)
            first = s->instances[j].feather != s->instances[i].feather;
        feathers += s->instances[i].feather && first;
        others += !s->instances[i].feather && exported(s, o, i);
    }
    pairs want = distinct_pairs(s, o), got = line_meshes(a);
    fprintf(stderr, "  %d instances: %d feathers, %d others, %d (mesh, material) pairs, %d of curves (%ld segments); "
            "read back %d nodes, %d meshes, %d of lines (%ld segments), %d materials, %d textures\n",
            s->instance_count, feathers, others, want.all, want.curves, want.segments, a->node_count, a->mesh_count,
            got.curves, got.segments, a->material_count, a->texture_count);
    assert_int_equal(a->node_count, 1 + feathers + others);
    assert_int_equal(r->nodes, a->node_count);
    assert_int_equal(a->mesh_count, want.all);
    assert_int_equal(got.curves, want.curves);
    assert_int_equal(got.segments, want.segments);
    assert_int_equal(r->line_meshes, want.curves);
    assert_int_equal(r->segments, want.segments);
    assert_int_equal(r->left_out, s->instance_count - r->instances);
    int left_out = 0;
    for (int i = 0; i < s->instance_count; ++i)
        left_out += !exported(s, o, i);
    assert_int_equal(r->left_out, left_out);
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
        if (!exported(s, o, i))
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
        int found = mesh_of_instance(s, in, a, n);
        int *shared = &mesh_of_pair[in->mesh * s->material_count + in->material];
        if (*shared < 0)
            *shared = found;
        assert_int_equal(found, *shared); /* one mesh per (mesh, material): instances share it */
        const plm_asset_summary_mesh *am = &a->meshes[found];
        assert_int_equal(am->has_uvs, s->meshes[in->mesh].mesh.uvs != NULL);
        const plm_asset_summary_material *mat = &a->materials[am->material];
        if (s->materials[in->material].type == PLM_MATERIAL_FEATHER)
            assert_true(mat->base_color_textures == 1 && mat->blend);
    }
    free(mesh_of_pair);
}

static void load_preset(const char *preset, const char *const *sets, int n_sets, plm_scene *s)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/presets/scenes/%s", PLUMAGE_SOURCE_DIR, preset);
    plm_error err;
    if (plm_scene_load_with(path, sets, n_sets, s, &err) != PLM_OK)
        fail_msg("%s", err.message);
}

/* Exports s to out and checks what Assimp reads back; the report. */
static plm_gltf_report round_trip(plm_scene *s, const char *out, int no_fluff)
{
    plm_error err;
    plm_gltf_options o = {.no_fluff = no_fluff, .bake = {4, 8, 1}};
    plm_gltf_report r;
    if (plm_gltf_export(s, out, &o, &r, &err) != PLM_OK)
        fail_msg("%s", err.message);
    plm_asset_summary a;
    if (plm_asset_read_gltf(out, &a, &err) != PLM_OK)
        fail_msg("%s", err.message);
    fprintf(stderr, "-> %s%s\n", out, no_fluff ? " (no fluff)" : "");
    check_round_trip(s, &o, &a, &r);
    plm_asset_summary_free(&a);
    return r;
}

static const char *const small[] = {"objects.0.layout.level=1", "objects.0.layout.texture_size=64"};

/* The pelt with its fluff as lines, and without: no lines, the fluff's
 * instances counted as left out. */
static void pelt_round_trip(void **state)
{
    (void)state;
    plm_scene s;
    load_preset("pelt_82.json", small, 2, &s);
    plm_gltf_report r = round_trip(&s, "export_pelt.glb", 0);
    assert_true(r.line_meshes > 0 && r.left_out == 0); /* the pelt's feathers have fluff */
    r = round_trip(&s, "export_pelt_bare.glb", 1);
    assert_true(r.line_meshes == 0 && r.segments == 0 && r.left_out > 0);
    remove("export_pelt_bare.glb");
    plm_scene_free(&s);
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

/* The .gltf's own JSON, not Assimp's reading of it: every primitive is of
 * triangles (mode 4) or line segments (mode 1, two indices a segment);
 * the mode 1 ones are the scene's distinct curve sets, with their segments. */
static void check_primitive_modes(const char *path, const plm_scene *s)
{
    char *text;
    plm_error err;
    assert_int_equal(plm_read_text_file(path, &text, &err), PLM_OK);
    cJSON *g = cJSON_Parse(text);
    assert_non_null(g);
    const cJSON *accessors = cJSON_GetObjectItem(g, "accessors"), *mesh;
    pairs lines = {0, 0, 0};
    cJSON_ArrayForEach(mesh, cJSON_GetObjectItem(g, "meshes"))
    {
        const cJSON *p;
        cJSON_ArrayForEach(p, cJSON_GetObjectItem(mesh, "primitives"))
        {
            const cJSON *mode = cJSON_GetObjectItem(p, "mode");
            const cJSON *indices = cJSON_GetArrayItem(accessors, cJSON_GetObjectItem(p, "indices")->valueint);
            int m = cJSON_IsNumber(mode) ? mode->valueint : 4, count = cJSON_GetObjectItem(indices, "count")->valueint;
            assert_true(m == 4 || m == 1);
            assert_int_equal(count % (m == 1 ? 2 : 3), 0);
            lines.curves += m == 1;
            lines.segments += m == 1 ? count / 2 : 0;
        }
    }
    pairs want = distinct_pairs(s, &(plm_gltf_options){0});
    fprintf(stderr, "  %s: %d primitives of mode 1, %ld segments by their indices\n", path, lines.curves,
            lines.segments);
    assert_int_equal(lines.curves, want.curves);
    assert_int_equal(lines.segments, want.segments);
    cJSON_Delete(g);
    free(text);
}

static void wing_round_trip_as_gltf(void **state)
{
    (void)state;
    mkdir("export_wing", 0755);
    /* One variant a row: 11 prototypes of 11 species instead of 31, as telling and faster. */
    static const char *const one_variant[] = {"objects.0.layout.level=1", "objects.0.layout.texture_size=64",
                                              "objects.0.layout.variants=1"};
    plm_scene s;
    load_preset("default.json", one_variant, 3, &s);
    round_trip(&s, "export_wing/wing.gltf", 0);
    check_primitive_modes("export_wing/wing.gltf", &s);
    plm_scene_free(&s);
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

/* Transforms within 0.01 of the identity in every element, which Assimp's
 * exporter takes for the identity and drops (export/asset_assimp.cpp
 * writes them back): an offset of 0.0006, a 0.3 degree turn and a 0.5% scale
 * read back as they are, in .glb and .gltf; the identity stays one. */
static void small_transforms_survive(void **state)
{
    (void)state;
    plm_scene s;
    plm_scene_init(&s);
    plm_mesh quad;
    plm_error err;
    assert_int_equal(plm_shape_quad(1.0, 1.0, 0.0, 1, &quad, &err), PLM_OK);
    plm_material m = plm_diffuse_material("grey", rgb_gray(0.5), 0.0);
    int mesh = plm_scene_add_mesh(&s, "quad", &quad), mat = plm_scene_add_material(&s, &m);
    plm_xform small[4] = {plm_xform_identity(), plm_xform_translate(v3(0.0, 0.0, -0.0006)),
                          plm_xform_rotate(v3(0.0, 0.0, 1.0), plm_radians(0.3)),
                          plm_xform_scale(v3(1.005, 1.005, 1.005))};
    for (int i = 0; i < 4; ++i)
        assert_true(plm_scene_add_object(&s, mesh, mat, small[i]) >= 0);
    const char *files[2] = {"export_small.glb", "export_small.gltf"};
    for (int f = 0; f < 2; ++f) {
        plm_gltf_options o = {0};
        plm_gltf_report r;
        assert_int_equal(plm_gltf_export(&s, files[f], &o, &r, &err), PLM_OK);
        plm_asset_summary a;
        assert_int_equal(plm_asset_read_gltf(files[f], &a, &err), PLM_OK);
        check_round_trip(&s, &o, &a, &r);
        plm_asset_summary_free(&a);
        remove(files[f]);
    }
    remove("export_small.bin");
    plm_scene_free(&s);
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
        cmocka_unit_test(fibers_bake_to_their_far_field),
        cmocka_unit_test(bake_agrees_with_the_renderers_furnace),
        cmocka_unit_test(pelt_round_trip),
        cmocka_unit_test(wing_round_trip_as_gltf),
        cmocka_unit_test(small_transforms_survive),
        cmocka_unit_test(refusals_leave_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
