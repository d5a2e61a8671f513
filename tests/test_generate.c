/* The generator (generate/): species presets and their validation, the
 * OpenSubdiv limit surfaces, and the meshes' topology, orientation, size and
 * reproducibility. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"
#include "test_files.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/json.h"
#include "common/rng.h"
#include "generate/geometry.h"
#include "generate/subdiv.h"
#include "texture/feather.h"

static const char *const presets[] = {"remex_pigeon", "covert_parrot", "rectrix_notched", "hackle_pointed"};
#define PRESET_COUNT 4

/* The meshes (no textures) of a species. */
static plm_feather meshes_of(const plm_species *sp)
{
    plm_feather f;
    plm_feather_options opt = {.no_textures = 1};
    assert_int_equal(plm_feather_generate(sp, &opt, &f, NULL), PLM_OK);
    return f;
}

/* Parses JSON text as a species; returns the result and leaves the message. */
static plm_result parse_text(const char *text, plm_error *err)
{
    cJSON *root = cJSON_Parse(text);
    assert_non_null(root);
    plm_species sp;
    plm_result rc = plm_species_parse(root, "test.json", &sp, err);
    if (rc == PLM_OK)
        plm_species_free(&sp);
    cJSON_Delete(root);
    return rc;
}

static void expect_error(const char *text, const char *field)
{
    plm_error err = {{0}};
    assert_int_equal(parse_text(text, &err), PLM_ERR_INVALID);
    if (!strstr(err.message, field))
        fprintf(stderr, "message \"%s\" does not name %s\n", err.message, field);
    assert_non_null(strstr(err.message, field));
    assert_non_null(strstr(err.message, "test.json"));
}

static void species_errors_name_the_field(void **state)
{
    (void)state;
    plm_error err = {{0}};
    assert_int_equal(parse_text("{}", &err), PLM_OK);
    expect_error("{\"shape\": {\"vane\": {\"left\": {\"width\": [[0, 5], [0.5, -2], [1, 3]]}}}}",
                 "shape.vane.left.width[1]");
    expect_error("{\"shape\": {\"rachis\": {\"base_width\": 1, \"tip_width\": 2}}}", "shape.rachis.tip_width");
    expect_error("{\"shape\": {\"rachis\": {\"base_width\": -1}}}", "shape.rachis.base_width");
    expect_error("{\"shape\": {\"splits\": {\"list\": [{\"position\": 1.2, \"depth\": 0.3}]}}}",
                 "shape.splits.list[0].position");
    expect_error("{\"shape\": {\"splits\": {\"list\": [{\"position\": 0.6, \"depth\": 1.5}]}}}",
                 "shape.splits.list[0].depth");
    expect_error("{\"shape\": {\"plumulaceous\": 0.5, \"splits\": {\"list\": [{\"position\": 0.4}]}}}",
                 "shape.splits.list[0].position");
    expect_error("{\"shape\": {\"vane\": {\"right\": {\"width\": [[0, 5], [0.7, 5], [0.6, 3]]}}}}",
                 "shape.vane.right.width[2]");
    expect_error("{\"shape\": {\"vane\": {\"tip\": {\"shape\": \"oval\"}}}}", "shape.vane.tip.shape");
    expect_error("{\"shape\": {\"barbs\": {\"angle_base\": 30, \"angle_tip\": 30, \"curvature\": 40}}}",
                 "shape.barbs.curvature");
    expect_error("{\"shape\": {\"lenght\": 30}}", "shape.lenght");
    expect_error("{\"shape\": {\"length\": 30, \"calamus_length\": 29}}", "shape.calamus_length");
    /* Vanes no wider than the rachis leave nothing to render. */
    expect_error("{\"shape\": {\"rachis\": {\"base_width\": 5}, \"vane\": {\"left\": {\"width\": [[0, 2], [1, 2]]}}}}",
                 "shape.vane.left.width");
}

/* The generator leaves the optics block to the renderer: any object passes, a non-object does not. */
static void presets_load_and_leave_optics_alone(void **state)
{
    (void)state;
    for (int i = 0; i < PRESET_COUNT; ++i) {
        plm_species sp = load_preset(presets[i]);
        assert_string_equal(sp.name, presets[i]);
        plm_species_free(&sp);
    }
    plm_error err = {{0}};
    plm_species sp;
    cJSON *root = cJSON_Parse("{\"optics\": {\"anything\": [1, 2], \"the renderer\": \"owns\"}}");
    assert_int_equal(plm_species_parse(root, "t.json", &sp, &err), PLM_OK);
    plm_species_free(&sp);
    cJSON_Delete(root);
    root = cJSON_Parse("{\"optics\": 3}");
    assert_int_equal(plm_species_parse(root, "t.json", &sp, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "optics"));
    cJSON_Delete(root);
}

/* The species presets' folder, and the next preset's name in it (the file name less ".json"). */
static DIR *open_presets(char dir[1024])
{
    snprintf(dir, 1024, "%s/presets/species", PLUMAGE_SOURCE_DIR);
    DIR *d = opendir(dir);
    assert_non_null(d);
    return d;
}

static int next_preset(DIR *d, char stem[256])
{
    for (struct dirent *e; (e = readdir(d));) {
        size_t n = strlen(e->d_name);
        if (n >= 6 && strcmp(e->d_name + n - 5, ".json") == 0) {
            snprintf(stem, 256, "%.*s", (int)(n - 5), e->d_name);
            return 1;
        }
    }
    return 0;
}

/* Every preset in presets/species loads, is named after its file, says where
 * its values come from, and reads as a feather: a short bare calamus (at most
 * 15% of the length) and a vane (down strands included) starting right there. */
static void every_preset_loads_with_a_source(void **state)
{
    (void)state;
    char dir[1024], stem[256];
    DIR *d = open_presets(dir);
    int count = 0;
    while (next_preset(d, stem)) {
        char path[2048];
        snprintf(path, sizeof path, "%s/%s.json", dir, stem);
        plm_species sp;
        plm_error err = {{0}};
        if (plm_species_load(path, &sp, &err) != PLM_OK)
            fail_msg("%s", err.message);
        assert_string_equal(sp.name, stem);
        cJSON *root = NULL;
        assert_int_equal(plm_json_load(path, &root, NULL), PLM_OK);
        const cJSON *source = cJSON_GetObjectItemCaseSensitive(root, "source");
        const cJSON *description = cJSON_GetObjectItemCaseSensitive(root, "description");
        assert_true(cJSON_IsString(source) && strlen(source->valuestring) > 40);
        assert_true(cJSON_IsString(description) && strlen(description->valuestring) > 20);
        assert_true(cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(root, "optics")));
        cJSON_Delete(root);
        const plm_shape *sh = &sp.shape;
        assert_true(sh->calamus_length <= 0.15 * sh->length);
        plm_outline o;
        assert_int_equal(plm_outline_init(&o, sh, path, NULL), PLM_OK);
        double first = INFINITY;
        for (int j = 0; j <= 400 && !isfinite(first); ++j) {
            double y = sh->length * j / 400.0;
            for (int i = -100; i <= 100; ++i)
                if (plm_outline_sample(&o, o.half_extent * i / 100.0, y).region == PLM_FLAT_VANE) {
                    first = y;
                    break;
                }
        }
        /* The downy base is fibers (generate/fluff.h): the vane starts where it ends. */
        assert_true(first <= sh->calamus_length + sh->plumulaceous * (sh->length - sh->calamus_length) +
                                 0.03 * sh->length);
        plm_species_free(&sp);
        count++;
    }
    closedir(d);
    assert_true(count >= 12);
}

/* Edge bookkeeping: directed edges must be unique (consistent winding) and
 * each undirected edge used once (boundary) or twice (interior). */
typedef struct edge_stats {
    int edges, boundary_edges, non_manifold, inconsistent, boundary_vertices_bad;
} edge_stats;

static int compare_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static edge_stats count_edges(const plm_mesh *m)
{
    size_t n = 3 * (size_t)m->triangle_count;
    uint64_t *directed = malloc(n * sizeof *directed), *undirected = malloc(n * sizeof *undirected);
    int *boundary_degree = calloc((size_t)m->vertex_count, sizeof(int));
    for (int t = 0; t < m->triangle_count; ++t)
        for (int k = 0; k < 3; ++k) {
            uint64_t a = m->indices[3 * t + k], b = m->indices[3 * t + (k + 1) % 3];
            directed[3 * t + k] = a << 32 | b;
            undirected[3 * t + k] = a < b ? a << 32 | b : b << 32 | a;
        }
    qsort(directed, n, sizeof *directed, compare_u64);
    qsort(undirected, n, sizeof *undirected, compare_u64);
    edge_stats s = {0};
    for (size_t i = 1; i < n; ++i)
        s.inconsistent += directed[i] == directed[i - 1];
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j < n && undirected[j] == undirected[i])
            ++j;
        s.edges++;
        if (j - i == 1) {
            s.boundary_edges++;
            boundary_degree[undirected[i] >> 32]++;
            boundary_degree[undirected[i] & 0xffffffffu]++;
        } else if (j - i > 2) {
            s.non_manifold++;
        }
        i = j;
    }
    for (int v = 0; v < m->vertex_count; ++v)
        s.boundary_vertices_bad += boundary_degree[v] != 0 && boundary_degree[v] != 2;
    free(directed);
    free(undirected);
    free(boundary_degree);
    return s;
}

/* Manifold with consistent winding and the Euler characteristic of a disk
 * (1: one boundary loop) or a sphere (2: closed). */
static void check_topology(const plm_mesh *m, int euler)
{
    edge_stats s = count_edges(m);
    assert_int_equal(s.non_manifold, 0);
    assert_int_equal(s.inconsistent, 0);
    assert_int_equal(s.boundary_vertices_bad, 0);
    assert_int_equal(m->vertex_count - s.edges + m->triangle_count, euler);
    if (euler == 2)
        assert_int_equal(s.boundary_edges, 0);
}

static vec3 pos(const plm_mesh *m, uint32_t i)
{
    return v3(m->positions[3 * i], m->positions[3 * i + 1], m->positions[3 * i + 2]);
}

static vec3 nrm(const plm_mesh *m, uint32_t i)
{
    return v3(m->normals[3 * i], m->normals[3 * i + 1], m->normals[3 * i + 2]);
}

/* No degenerate triangles (area against the longest edge squared), and the
 * limit normals at the three vertices lie within max_angle degrees of the
 * flat triangle's normal (the limit derivatives belong to this surface, and
 * nothing is flipped). */
static void check_triangles(const plm_mesh *m, double max_angle)
{
    int degenerate = 0, flipped = 0;
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * t;
        vec3 a = pos(m, i[0]), b = pos(m, i[1]), c = pos(m, i[2]);
        vec3 cr = v3_cross(v3_sub(b, a), v3_sub(c, a));
        double longest = fmax(v3_length(v3_sub(b, a)), fmax(v3_length(v3_sub(c, b)), v3_length(v3_sub(a, c))));
        degenerate += !(0.5 * v3_length(cr) > 1e-4 * longest * longest);
        for (int k = 0; k < 3; ++k)
            flipped += !(v3_dot(v3_normalize(cr), nrm(m, i[k])) > cos(plm_radians(max_angle)));
    }
    for (int v = 0; v < m->vertex_count; ++v)
        assert_double_near(v3_length(nrm(m, (uint32_t)v)), 1.0, 1e-5);
    assert_int_equal(degenerate, 0);
    assert_int_equal(flipped, 0);
}

static void vanes_are_clean_open_disks(void **state)
{
    (void)state;
    for (int p = 0; p < PRESET_COUNT; ++p) {
        plm_species sp = load_preset(presets[p]);
        plm_feather f = meshes_of(&sp);
        const plm_mesh *m = &f.vane;
        check_topology(m, 1);
        check_triangles(m, 15.0);
        for (int v = 0; v < m->vertex_count; ++v) {
            for (int k = 0; k < 2; ++k)
                assert_true(m->uvs[2 * v + k] >= 0.0f && m->uvs[2 * v + k] <= 1.0f);
            vec3 t = v3(m->tangents[3 * v], m->tangents[3 * v + 1], m->tangents[3 * v + 2]);
            assert_double_near(v3_length(t), 1.0, 1e-5);
            assert_true(fabs(v3_dot(t, nrm(m, (uint32_t)v))) < 1e-4);
        }
        plm_feather_free(&f);
        plm_species_free(&sp);
    }
}

/* Signed volume by the divergence theorem: positive for outward normals. */
static double signed_volume(const plm_mesh *m)
{
    double v = 0.0;
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * t;
        v += v3_dot(pos(m, i[0]), v3_cross(pos(m, i[1]), pos(m, i[2]))) / 6.0;
    }
    return v;
}

static void rachis_is_a_closed_outward_tube(void **state)
{
    (void)state;
    for (int p = 0; p < PRESET_COUNT; ++p) {
        plm_species sp = load_preset(presets[p]);
        plm_feather f = meshes_of(&sp);
        const plm_mesh *m = &f.rachis;
        check_topology(m, 2);
        /* The domed ends turn 90 degrees within a few triangles of the (one
         * level coarser) tube: there only "not flipped" is asked. */
        check_triangles(m, 89.0);
        /* The tube's volume is that of the tapering circular section, up to
         * the smoothing of an 8-point ring and the rounded caps. */
        const plm_outline *o = &f.outline;
        double expect = 0.0;
        for (int i = 0; i < 2000; ++i) {
            double r = plm_outline_rachis_radius(o, (i + 0.5) / 2000 * o->rachis_end);
            expect += PLM_PI * r * r * o->rachis_end / 2000;
        }
        double vol = signed_volume(m);
        assert_true(vol > 0.0);
        assert_true(fabs(vol / expect - 1.0) < 0.03);
        plm_feather_free(&f);
        plm_species_free(&sp);
    }
}

/* Straight feather: the tube spans exactly the length, the vane reaches the
 * tip, and every row of the vane mesh covers the outline's width. */
static void length_and_widths_match_the_parameters(void **state)
{
    (void)state;
    plm_species sp = load_preset("remex_pigeon");
    sp.shape.bend_in_plane = sp.shape.bend_out_of_plane = sp.shape.twist = 0.0;
    sp.shape.curl = 0.0;
    plm_feather f = meshes_of(&sp);
    double lo = 1e9, hi = -1e9, vlo = 1e9, vhi = -1e9;
    for (int v = 0; v < f.rachis.vertex_count; ++v) {
        lo = fmin(lo, f.rachis.positions[3 * v + 1]);
        hi = fmax(hi, f.rachis.positions[3 * v + 1]);
    }
    for (int v = 0; v < f.vane.vertex_count; ++v) {
        vlo = fmin(vlo, f.vane.positions[3 * v + 1]);
        vhi = fmax(vhi, f.vane.positions[3 * v + 1]);
    }
    /* The domed ends of the smooth tube overshoot the end points slightly
     * (0.1% measured); the issue asks for 1%, this asks for 0.3%. */
    assert_double_near(lo, 0.0, 3e-3 * sp.shape.length);
    assert_double_near(hi, sp.shape.length, 3e-3 * sp.shape.length);
    assert_double_near(hi - lo, sp.shape.length, 3e-3 * sp.shape.length);
    assert_double_near(vlo, sp.shape.calamus_length, 1e-4 * sp.shape.length);
    assert_double_near(vhi, sp.shape.length, 1e-4 * sp.shape.length);
    /* Mesh extent per side at the width profile's control points (away from
     * the tip): at least the parameter, at most 1% (plus a row's change) more;
     * the outline's width there is the parameter narrowed by any emargination. */
    const plm_outline *o = &f.outline;
    for (int side = 0; side < 2; ++side) {
        const plm_width_profile *w = &sp.shape.width[side];
        for (int k = 1; k + 1 < w->count; ++k) {
            double y = o->vane_base + w->t[k] * o->vane_length, extent = 0.0;
            for (int v = 0; v < f.vane.vertex_count; ++v) {
                double x = f.vane.positions[3 * v] * (side ? 1.0 : -1.0);
                if (fabs(f.vane.positions[3 * v + 1] - y) < 0.01 * o->vane_length)
                    extent = fmax(extent, x);
            }
            double width = plm_outline_width(o, side, w->t[k]);
            assert_true(width <= w->width[k] && width >= (1.0 - sp.shape.emargination[side].depth) * w->width[k]);
            assert_true(extent >= w->width[k] * 0.999); /* the mesh leaves emarginations to the texture */
            assert_true(extent <= plm_outline_mesh_extent(o, side, w->t[k]) * 1.01);
            assert_true(plm_outline_mesh_extent(o, side, w->t[k]) <= w->width[k] * 1.05);
        }
    }
    plm_feather_free(&f);
    plm_species_free(&sp);
}

/* The centre line is a helix of exact arc length, turning by the bends. */
static void bends_turn_the_rachis_by_their_angles(void **state)
{
    (void)state;
    plm_species sp = load_preset("remex_pigeon");
    plm_shape *sh = &sp.shape;
    sh->bend_in_plane = plm_radians(30.0);
    sh->bend_out_of_plane = sh->twist = 0.0;
    plm_outline o;
    assert_int_equal(plm_outline_init(&o, sh, "t", NULL), PLM_OK);
    double arc = 0.0;
    int n = 4000;
    for (int i = 0; i < n; ++i)
        arc += v3_length(v3_sub(plm_rachis_frame_at(&o, sh->length * (i + 1) / n).c,
                                plm_rachis_frame_at(&o, sh->length * i / n).c));
    assert_double_near(arc, sh->length, 1e-6 * sh->length);
    plm_rachis_frame tip = plm_rachis_frame_at(&o, sh->length);
    assert_double_near(plm_degrees(atan2(tip.t.x, tip.t.y)), 30.0, 1e-9); /* toward +x */
    assert_true(tip.c.x > 0.0);
    sh->bend_in_plane = 0.0;
    sh->bend_out_of_plane = plm_radians(20.0);
    assert_int_equal(plm_outline_init(&o, sh, "t", NULL), PLM_OK);
    tip = plm_rachis_frame_at(&o, sh->length);
    assert_double_near(plm_degrees(atan2(-tip.t.z, tip.t.y)), 20.0, 1e-9); /* ventral */
    /* Frames stay orthonormal and right-handed. */
    sh->bend_in_plane = plm_radians(10.0);
    sh->twist = plm_radians(25.0);
    assert_int_equal(plm_outline_init(&o, sh, "t", NULL), PLM_OK);
    plm_rachis_frame fr = plm_rachis_frame_at(&o, 0.7 * sh->length);
    assert_double_near(v3_dot(fr.x, fr.t), 0.0, 1e-12);
    assert_double_near(v3_dot(v3_cross(fr.x, fr.t), fr.z), 1.0, 1e-12);
    plm_species_free(&sp);
}

/* The rachis as the species' values make it, computed here from them alone:
 * its tangent turns at a constant rate omega (bend out of the plane about -x,
 * twist about y, bend in the plane about -z, each per mm), so frame vectors
 * at arc length y are the base frame's rotated about omega by |omega| y. */
static vec3 species_rotate(const plm_shape *sh, vec3 v, double y)
{
    vec3 w = v3_scale(v3(-sh->bend_out_of_plane, sh->twist, -sh->bend_in_plane), 1.0 / sh->length);
    double a = v3_length(w) * y;
    if (a < 1e-15)
        return v;
    vec3 k = v3_normalize(w);
    return v3_add(v3_add(v3_scale(v, cos(a)), v3_scale(v3_cross(k, v), sin(a))),
                  v3_scale(k, v3_dot(k, v) * (1.0 - cos(a))));
}

/* The centre line at y: the tangent integrated by Simpson's rule. */
static vec3 species_centre(const plm_shape *sh, double y)
{
    enum { N = 400 };
    vec3 c = v3(0, 0, 0);
    for (int i = 0; i <= N; ++i) {
        double weight = i == 0 || i == N ? 1.0 : (i % 2 ? 4.0 : 2.0);
        c = v3_add(c, v3_scale(species_rotate(sh, v3(0, 1, 0), y * i / N), weight * y / (3.0 * N)));
    }
    return c;
}

/* Measured on the generated vane mesh of every preset, against the species'
 * own values: the rachis's direction (the mesh's midline, u = 1/2, whose
 * secants over 10% of the vane give the tangent at their middle) at a fifth
 * and at nine tenths of the vane, within 0.3 degrees; and the cupping, the
 * parabola fitted across the vane in the rachis's frame between 30% and 70%
 * of the vane, whose depth at the widest point must be tan(curl) W / 2
 * within 4% (0.02 mm where flat). Bend and cup are what keep a feather lying
 * on a table from reading as a flat cut-out. */
static void every_preset_bends_and_cups_by_its_values(void **state)
{
    (void)state;
    char dir[1024], stem[256];
    DIR *d = open_presets(dir);
    int count = 0;
    while (next_preset(d, stem)) {
        plm_species sp = load_preset(stem);
        const plm_shape *sh = &sp.shape;
        plm_feather f = meshes_of(&sp);
        const plm_mesh *m = &f.vane;
        double y0 = f.outline.vane_base, lv = f.outline.vane_length;
        for (int k = 0; k < 2; ++k) {
            double from = k ? 0.85 : 0.15, to = k ? 0.95 : 0.25; /* v range of the secant */
            vec3 lo = v3(0, 0, 0), hi = v3(0, 0, 0);
            double vlo = 2.0, vhi = -1.0;
            for (int i = 0; i < m->vertex_count; ++i) {
                double u = m->uvs[2 * i], v = m->uvs[2 * i + 1];
                vec3 p = v3(m->positions[3 * i], m->positions[3 * i + 1], m->positions[3 * i + 2]);
                if (fabs(u - 0.5) > 1e-4 || v < from || v > to)
                    continue;
                if (v < vlo)
                    vlo = v, lo = p;
                if (v > vhi)
                    vhi = v, hi = p;
            }
            assert_true(vhi - vlo > 0.05);
            vec3 measured = v3_normalize(v3_sub(hi, lo));
            vec3 expected = species_rotate(sh, v3(0, 1, 0), y0 + 0.5 * (vlo + vhi) * lv);
            double angle = plm_degrees(acos(fmin(1.0, v3_dot(measured, expected))));
            if (angle > 0.3)
                fail_msg("%s: rachis direction at v = %.2f off by %.3f degrees", stem, 0.5 * (vlo + vhi), angle);
        }
        for (int side = 0; side < 2; ++side) {
            double xz2 = 0.0, x4 = 0.0;
            for (int i = 0; i < m->vertex_count; ++i) {
                double u = m->uvs[2 * i], v = m->uvs[2 * i + 1];
                if (v < 0.3 || v > 0.7 || (u > 0.5) != side || fabs(u - 0.5) < 1e-3)
                    continue;
                double y = y0 + v * lv;
                vec3 p = v3_sub(v3(m->positions[3 * i], m->positions[3 * i + 1], m->positions[3 * i + 2]),
                                species_centre(sh, y));
                double x = v3_dot(p, species_rotate(sh, v3(1, 0, 0), y));
                double depth = -v3_dot(p, species_rotate(sh, v3(0, 0, 1), y)); /* > 0 ventral */
                xz2 += depth * x * x;
                x4 += x * x * x * x;
            }
            double widest = f.outline.widest[side];
            double measured = xz2 / x4 * widest * widest, expected = 0.5 * tan(sh->curl) * widest;
            if (fabs(measured - expected) > fmax(0.04 * fabs(expected), 0.02))
                fail_msg("%s: cup depth at the widest point of side %d %.3f mm, species %.3f mm", stem, side,
                         measured, expected);
        }
        plm_feather_free(&f);
        plm_species_free(&sp);
        count++;
    }
    closedir(d);
    assert_true(count >= 12);
}

/* The fitted cage's limit passes through the targets: the refined mesh's
 * first vertices descend from the cage vertices and sit on them. */
static void limit_surface_interpolates_the_cage(void **state)
{
    (void)state;
    /* A bumpy 5x5-vertex sheet. */
    double values[25 * 3];
    int quads[16 * 4], *q = quads;
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) {
            double *v = values + 3 * (j * 5 + i);
            v[0] = i, v[1] = j, v[2] = sin(1.3 * i) * cos(0.7 * j);
        }
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            int a = j * 5 + i;
            *q++ = a, *q++ = a + 1, *q++ = a + 6, *q++ = a + 5;
        }
    double targets[25 * 3];
    memcpy(targets, values, sizeof values);
    plm_subdiv_cage cage = {25, 16, quads, 3};
    double residual = 1.0;
    assert_int_equal(plm_subdiv_fit(&cage, values, 60, &residual, NULL), PLM_OK);
    assert_true(residual < 1e-9);
    plm_subdiv_limit l;
    assert_int_equal(plm_subdiv_refine(&cage, values, 3, &l, NULL), PLM_OK);
    assert_int_equal(l.quad_count, 16 * 64);
    for (int i = 0; i < 25 * 3; ++i)
        assert_double_near(l.value[i], targets[i], 1e-8);
    plm_subdiv_limit_free(&l);
    plm_error err = {{0}};
    assert_int_equal(plm_subdiv_refine(&cage, values, 7, &l, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "level"));
}

/* Random valid species across the allowed ranges: every one that passes
 * validation gives clean meshes and finite textures. */
static void random_species_give_clean_feathers(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 2024, 5);
    int generated = 0;
    for (int n = 0; n < 16; ++n) {
#define U(lo, hi) ((lo) + ((hi) - (lo)) * plm_rng_uniform(&rng))
        plm_species sp;
        plm_species_default(&sp);
        plm_shape *sh = &sp.shape;
        sh->length = U(5.0, 400.0);
        sh->calamus_length = U(0.0, 0.3) * sh->length;
        sh->plumulaceous = U(0.0, 0.5);
        sh->rachis_base_width = U(0.005, 0.03) * sh->length;
        sh->rachis_tip_width = U(0.1, 1.0) * sh->rachis_base_width;
        sh->rachis_taper = U(0.2, 5.0);
        sh->bend_in_plane = plm_radians(U(-90.0, 90.0));
        sh->bend_out_of_plane = plm_radians(U(-90.0, 90.0));
        sh->twist = plm_radians(U(-180.0, 180.0));
        sh->curl = plm_radians(U(-60.0, 60.0));
        sh->tip_shape = (plm_tip_shape)(plm_rng_u32(&rng) % 5);
        sh->tip_length = U(0.01, 0.9);
        for (int side = 0; side < 2; ++side) {
            plm_width_profile *w = &sh->width[side];
            w->count = 4;
            for (int k = 0; k < 4; ++k) {
                w->t[k] = k / 3.0;
                w->width[k] = U(0.03, 0.25) * sh->length;
            }
            sh->barb_angle_base[side] = plm_radians(U(15.0, 85.0));
            sh->barb_angle_tip[side] = plm_radians(U(15.0, 85.0));
        }
        sh->barb_curvature = plm_radians(U(-20.0, 12.0));
        sh->barb_end_jitter = U(0.0, 20.0);
        sh->barb_fray = U(0.0, 50.0);
        plm_emargination *e = &sh->emargination[n % 2];
        e->position = U(0.0, 1.0);
        e->depth = U(0.0, 0.9);
        e->length = U(0.01, 0.5);
        sh->seed = plm_rng_u32(&rng) >> 1;
        sh->split_frequency = n % 2 ? U(0.0, 16.0) : 0.0; /* drawn splits, or a list */
        sh->split_count = n % 2 ? 0 : (int)(plm_rng_u32(&rng) % 8);
        for (int i = 0; i < sh->split_count; ++i) {
            sh->splits[i].position = U(sh->plumulaceous + 0.01, 0.99);
            sh->splits[i].depth = U(0.05, 1.0);
            sh->splits[i].side = (int)(plm_rng_u32(&rng) % 2);
        }
#undef U
        if (plm_species_validate(&sp, "random", NULL) != PLM_OK)
            continue; /* e.g. barbs that would fold: refused with a message, tested above */
        plm_feather f;
        plm_feather_options opt = {.level = 2, .texture_width = 64, .texture_height = 64};
        assert_int_equal(plm_feather_generate(&sp, &opt, &f, NULL), PLM_OK);
        const plm_mesh *meshes[2] = {&f.vane, &f.rachis};
        for (int m = 0; m < 2; ++m) {
            check_topology(meshes[m], m ? 2 : 1);
            check_triangles(meshes[m], 89.0);
        }
        for (size_t i = 0; i < (size_t)64 * 64 * 3; ++i)
            assert_true(isfinite(f.texture.pixels[i]) && isfinite(f.pigment.pixels[i]));
        plm_feather_free(&f);
        ++generated;
    }
    assert_true(generated >= 8);
}

static void same_species_same_bytes(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    const char *names[2] = {"gen_same_a.ply", "gen_same_b.ply"};
    unsigned char *bytes[2];
    long size[2];
    for (int k = 0; k < 2; ++k) {
        plm_feather f = meshes_of(&sp);
        assert_int_equal(plm_mesh_write(names[k], &f.vane, NULL), PLM_OK);
        plm_feather_free(&f);
        bytes[k] = read_whole_file(names[k], &size[k]);
        remove(names[k]);
    }
    assert_int_equal(size[0], size[1]);
    assert_memory_equal(bytes[0], bytes[1], (size_t)size[0]);
    free(bytes[0]);
    free(bytes[1]);
    plm_species_free(&sp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(species_errors_name_the_field),
        cmocka_unit_test(presets_load_and_leave_optics_alone),
        cmocka_unit_test(every_preset_loads_with_a_source),
        cmocka_unit_test(vanes_are_clean_open_disks),
        cmocka_unit_test(rachis_is_a_closed_outward_tube),
        cmocka_unit_test(length_and_widths_match_the_parameters),
        cmocka_unit_test(bends_turn_the_rachis_by_their_angles),
        cmocka_unit_test(every_preset_bends_and_cups_by_its_values),
        cmocka_unit_test(limit_surface_interpolates_the_cage),
        cmocka_unit_test(random_species_give_clean_feathers),
        cmocka_unit_test(same_species_same_bytes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
