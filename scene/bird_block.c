/* Bird objects in scene files: {"bird": FILE, ...} builds the bird preset's
 * skin, bill and eyes (generate/bird.h) and lays each tract's feathers with
 * the pelt layout on its own part of the skin. docs/birds.md. */
#include "scene/bird_block.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/rng.h"
#include "generate/bird.h"
#include "generate/layout.h"
#include "scene/layout_block.h"
#include "scene/readers.h"

#define CM2_PER_M2 1e4
#define MM 0.001

typedef struct bird_options {
    int feathers;     /* lay the tracts' feathers */
    double perch_radius, perch_length; /* mm; 0: no perch and no feet */
    rgb bark;
    int level;        /* the body's subdivision */
    int feather_level, texture_size;
} bird_options;

static plm_result no_memory(const plm_json_reader *r) { return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory"); }

static vec3 vertex(const float *a, uint32_t i) { return v3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); }

static void put3(float *a, uint32_t i, vec3 v)
{
    a[3 * i] = (float)v.x, a[3 * i + 1] = (float)v.y, a[3 * i + 2] = (float)v.z;
}

/* Which triangles a part of the skin takes: those of one tract (k), the feathered ones or the bare ones. */
typedef enum skin_part { SKIN_TRACT, SKIN_FEATHERED, SKIN_BARE } skin_part;

static int takes(skin_part part, int k, int tract)
{
    return part == SKIN_TRACT ? tract == k : part == SKIN_FEATHERED ? tract >= 0 : tract < 0;
}

/* The skin's triangles of a part as a mesh of their own, the flow turned by `flow`. */
static plm_result tract_mesh(const plm_bird_body *b, skin_part part, int tract, double flow, plm_mesh *out,
                             double *area)
{
    const plm_mesh *skin = &b->skin;
    memset(out, 0, sizeof *out);
    *area = 0.0;
    int32_t *map = malloc(sizeof(int32_t) * (size_t)skin->vertex_count);
    out->positions = malloc(sizeof(float) * 3 * (size_t)skin->vertex_count);
    out->normals = malloc(sizeof(float) * 3 * (size_t)skin->vertex_count);
    out->tangents = malloc(sizeof(float) * 3 * (size_t)skin->vertex_count);
    out->indices = malloc(sizeof(uint32_t) * 3 * (size_t)skin->triangle_count);
    if (!map || !out->positions || !out->normals || !out->tangents || !out->indices) {
        free(map);
        plm_mesh_free(out);
        return PLM_ERR_NO_MEMORY;
    }
    memset(map, 0xff, sizeof(int32_t) * (size_t)skin->vertex_count);
    double c = cos(flow), s = sin(flow);
    for (int t = 0; t < skin->triangle_count; ++t) {
        if (!takes(part, tract, b->tract[t]))
            continue;
        const uint32_t *v = skin->indices + 3 * t;
        for (int k = 0; k < 3; ++k) {
            if (map[v[k]] < 0) {
                uint32_t n = (uint32_t)out->vertex_count++;
                map[v[k]] = (int32_t)n;
                put3(out->positions, n, vertex(skin->positions, v[k]));
                put3(out->normals, n, vertex(skin->normals, v[k]));
                put3(out->tangents, n, v3_add(v3_scale(vertex(skin->tangents, v[k]), c),
                                              v3_scale(vertex(b->ventral, v[k]), s)));
            }
            out->indices[3 * out->triangle_count + k] = (uint32_t)map[v[k]];
        }
        vec3 p0 = vertex(skin->positions, v[0]), p1 = vertex(skin->positions, v[1]), p2 = vertex(skin->positions, v[2]);
        *area += 0.5 * v3_length(v3_cross(v3_sub(p1, p0), v3_sub(p2, p0)));
        out->triangle_count++;
    }
    free(map);
    return PLM_OK;
}

/* Whether a feather scaled by s about its root keeps its vane (taken as a
 * quarter of its length each side of the rachis) off an eye. */
static int clear_of_eye(vec3 root, vec3 v, double s, vec3 eye, double radius)
{
    for (int k = 0; k <= 16; ++k) {
        vec3 p = v3_madd(root, v, s * k / 16.0);
        if (v3_length(v3_sub(p, eye)) < 1.1 * radius + 0.25 * s * v3_length(v))
            return 0;
    }
    return 1;
}

/* Feathers reaching over an eye end before it: each is shrunk about its
 * root (bisection on its scale) until it clears both eyes. */
static void clear_eyes(const plm_bird_body *b, plm_layout *l)
{
    for (int i = 0; i < l->instance_count; ++i) {
        plm_layout_instance *in = &l->instances[i];
        double length = l->prototypes[in->prototype].shape.length;
        vec3 root = v3(in->m[0][3], in->m[1][3], in->m[2][3]);
        vec3 v = v3_scale(v3(in->m[0][1], in->m[1][1], in->m[2][1]), length);
        int clear = clear_of_eye(root, v, 1.0, b->eye[0], b->eye_radius);
        if (clear && clear_of_eye(root, v, 1.0, b->eye[1], b->eye_radius))
            continue;
        double lo = 0.0, hi = 1.0;
        for (int k = 0; k < 12; ++k) {
            double mid = 0.5 * (lo + hi);
            if (clear_of_eye(root, v, mid, b->eye[0], b->eye_radius) &&
                clear_of_eye(root, v, mid, b->eye[1], b->eye_radius))
                lo = mid;
            else
                hi = mid;
        }
        double s = fmax(lo, 0.05); /* a stub where even the root is at the eye */
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
                in->m[r][c] *= s;
        in->scale *= s;
    }
}

/* One tract's feathers: a pelt on its part of the skin. */
static plm_result lay_tract(const plm_json_reader *r, const char *path, const plm_bird *bird, const plm_bird_body *b,
                            int k, const bird_options *o, const plm_xform *xform, plm_scene *scene,
                            plm_feather_cache *cache, int *ordinal)
{
    const plm_bird_tract *t = &bird->tracts[k];
    char tpath[300];
    snprintf(tpath, sizeof tpath, "%s (%s: tracts[%d] \"%s\")", path, bird->name, k, t->name);
    plm_mesh m;
    double area;
    if (tract_mesh(b, SKIN_TRACT, k, t->flow, &m, &area) != PLM_OK)
        return no_memory(r);
    if (m.triangle_count == 0) {
        plm_mesh_free(&m);
        return PLM_OK; /* covered over entirely by later tracts */
    }
    plm_species species;
    plm_result rc = plm_species_load(t->species, &species, r->err);
    if (rc != PLM_OK) {
        plm_error_prefix(r->err, "%s: %s: ", r->file, tpath);
        plm_mesh_free(&m);
        return rc;
    }
    plm_layout_species sp = {&species, 1.0};
    plm_pelt_params p = {0};
    p.surface.kind = PLM_SURFACE_MESH;
    p.surface.mesh = &m;
    p.count = (int)fmax(1.0, round(t->density * area * CM2_PER_M2));
    p.axis = b->axis;
    p.feather_length = fmax(t->size[0], t->size[1]) * MM;
    p.head_size = fmin(t->size[0], t->size[1]) / fmax(t->size[0], t->size[1]);
    p.edge_size = 1.0; /* a tract's edge meets its neighbour's feathers: no gap */
    p.elevation = t->elevation;
    p.seed = plm_hash64(bird->seed, (uint64_t)k, 0xb17du);
    plm_layout layout = {0};
    rc = plm_layout_pelt(&p, &sp, 1, &layout, r->err);
    if (rc != PLM_OK)
        plm_error_prefix(r->err, "%s: %s: ", r->file, tpath);
    else
        clear_eyes(b, &layout);
    const char *files[1] = {t->species};
    if (rc == PLM_OK)
        rc = plm_layout_block_place(r, tpath, &layout, files, o->feather_level, o->texture_size, p.seed,
                                    (*ordinal)++, xform, scene, cache);
    plm_layout_free(&layout);
    plm_species_free(&species);
    plm_mesh_free(&m);
    return rc;
}

/* Loads n species files into sp (freed by the caller with free_species). */
static plm_result load_species(const plm_json_reader *r, const char *path, const char *const *files, int n,
                               plm_species *sp)
{
    for (int k = 0; k < n; ++k) {
        plm_result rc = plm_species_load(files[k], &sp[k], r->err);
        if (rc != PLM_OK) {
            plm_error_prefix(r->err, "%s: %s: ", r->file, path);
            for (int j = 0; j < k; ++j)
                plm_species_free(&sp[j]);
            return rc;
        }
    }
    return PLM_OK;
}

static void free_species(plm_species *sp, int n)
{
    for (int k = 0; k < n; ++k)
        plm_species_free(&sp[k]);
}

/* Both wings, folded along the flanks: one layout, placed at each shoulder
 * (the left one mirrored), lifted off the skin by the body feathers' depth. */
static plm_result lay_wings(const plm_json_reader *r, const char *path, const plm_bird *bird, const plm_bird_body *b,
                            const bird_options *o, const plm_xform *xform, plm_scene *scene,
                            plm_feather_cache *cache, int *ordinal)
{
    const plm_bird_wings *w = &bird->wings;
    char wpath[300];
    snprintf(wpath, sizeof wpath, "%s (%s: wings)", path, bird->name);
    const char *files[PLM_WING_ROWS];
    for (int k = 0; k < PLM_WING_ROWS; ++k) { /* a row left out takes its fallback's (always an earlier row) */
        int fallback = plm_wing_row_fallback(k);
        files[k] = w->rows[k][0] ? w->rows[k] : fallback >= 0 ? files[fallback] : w->rows[PLM_WING_SECONDARY];
    }
    plm_species sp[PLM_WING_ROWS];
    plm_result rc = load_species(r, wpath, files, PLM_WING_ROWS, sp);
    if (rc != PLM_OK)
        return rc;
    const plm_species *rows[PLM_WING_ROWS];
    for (int k = 0; k < PLM_WING_ROWS; ++k)
        rows[k] = &sp[k];
    plm_wing_params p = {0};
    p.span = w->span * MM;
    p.chord = w->chord * MM;
    p.fold = w->fold;
    p.primaries = w->primaries;
    p.secondaries = w->secondaries;
    p.tertials = w->tertials;
    p.seed = plm_hash64(bird->seed, 0x3179u, 0);
    plm_layout layout = {0};
    if ((rc = plm_layout_wing(&p, rows, &layout, r->err)) != PLM_OK)
        plm_error_prefix(r->err, "%s: %s: ", r->file, wpath);
    for (int side = 0; rc == PLM_OK && side < 2; ++side) {
        double m[3][4];
        plm_bird_wing_frame(b, side, 0.1 * bird->m.head_width * MM, m);
        plm_xform at, x;
        plm_xform_from_matrix(m, &at);
        x = plm_xform_compose(xform, &at);
        /* One ordinal for both sides: the same feathers, generated once. */
        rc = plm_layout_block_place(r, wpath, &layout, files, o->feather_level, o->texture_size, p.seed, *ordinal,
                                    &x, scene, cache);
    }
    (*ordinal)++;
    plm_layout_free(&layout);
    free_species(sp, PLM_WING_ROWS);
    return rc;
}

/* The tail's fan of rectrices with their coverts. */
static plm_result lay_tail(const plm_json_reader *r, const char *path, const plm_bird *bird, const plm_bird_body *b,
                           const bird_options *o, const plm_xform *xform, plm_scene *scene,
                           plm_feather_cache *cache, int *ordinal)
{
    char tpath[300];
    snprintf(tpath, sizeof tpath, "%s (%s: tail)", path, bird->name);
    const char *files[2] = {bird->tail.rectrix, bird->tail.covert};
    plm_species sp[2];
    plm_result rc = load_species(r, tpath, files, 2, sp);
    if (rc != PLM_OK)
        return rc;
    plm_layout layout = {0};
    if ((rc = plm_bird_tail_layout(bird, b, &sp[0], &sp[1], &layout, r->err)) != PLM_OK)
        plm_error_prefix(r->err, "%s: %s: ", r->file, tpath);
    if (rc == PLM_OK)
        rc = plm_layout_block_place(r, tpath, &layout, files, o->feather_level, o->texture_size,
                                    plm_hash64(bird->seed, 0x7a11u, 0), (*ordinal)++, xform, scene, cache);
    plm_layout_free(&layout);
    free_species(sp, 2);
    return rc;
}

/* A named material of the object's (prefix.name). */
static int add_material(plm_scene *scene, const char *prefix, const char *name, const plm_bird_surface *s)
{
    plm_material m = {0};
    snprintf(m.name, sizeof m.name, "%.100s.%s", prefix, name);
    m.type = PLM_MATERIAL_COAT;
    m.reflectance = s->colour;
    m.roughness = s->roughness;
    m.ior = 1.5;
    return plm_scene_add_material(scene, &m);
}

static plm_result add_mesh_instance(const plm_json_reader *r, plm_scene *scene, const char *prefix, const char *name,
                                    plm_mesh *mesh, int material, const plm_xform *xform, plm_part part)
{
    char full[PLM_NAME_MAX];
    snprintf(full, sizeof full, "%.100s.%s", prefix, name);
    int index = plm_scene_add_mesh(scene, full, mesh);
    if (index < 0) {
        plm_mesh_free(mesh);
        return no_memory(r);
    }
    plm_instance in = {index, material, *xform, rgb_gray(1.0), 0, part};
    return material < 0 || plm_scene_add_instance(scene, &in) < 0 ? no_memory(r) : PLM_OK;
}

/* An eye: an eyeball in the iris colour with a black pupil bulging from it where it looks. */
static plm_result add_eye(const plm_json_reader *r, plm_scene *scene, const char *prefix, const plm_bird_body *b,
                          int side, int iris, int pupil, const plm_xform *xform)
{
    plm_mesh ball = {0}, dot = {0};
    double radius = b->eye_radius;
    plm_result rc = plm_shape_sphere(radius, 24, &ball, r->err);
    if (rc == PLM_OK)
        rc = plm_shape_sphere(0.5 * radius, 16, &dot, r->err);
    if (rc != PLM_OK) {
        plm_mesh_free(&ball);
        return rc;
    }
    plm_xform at = plm_xform_translate(b->eye[side]);
    plm_xform x = plm_xform_compose(xform, &at);
    plm_xform at_pupil = plm_xform_translate(v3_madd(b->eye[side], b->eye_normal[side], 0.58 * radius));
    plm_xform xp = plm_xform_compose(xform, &at_pupil);
    rc = add_mesh_instance(r, scene, prefix, side ? "eye.right" : "eye.left", &ball, iris, &x, PLM_PART_OTHER);
    if (rc == PLM_OK)
        rc = add_mesh_instance(r, scene, prefix, side ? "pupil.right" : "pupil.left", &dot, pupil, &xp,
                               PLM_PART_OTHER);
    else
        plm_mesh_free(&dot);
    return rc;
}

/* The branch and the feet gripping it. */
static plm_result add_perch(const plm_json_reader *r, const char *path, const plm_bird *bird, const bird_options *o,
                            const plm_xform *xform, plm_scene *scene)
{
    plm_mesh branch, feet;
    plm_result rc = plm_bird_perch(bird, o->perch_radius, o->perch_length, &branch, &feet, r->err);
    if (rc != PLM_OK)
        return rc;
    plm_material bark = {0};
    snprintf(bark.name, sizeof bark.name, "%.100s.perch", path);
    bark.type = PLM_MATERIAL_DIFFUSE;
    bark.reflectance = o->bark;
    int b = plm_scene_add_material(scene, &bark), f = add_material(scene, path, "feet", &bird->feet);
    rc = add_mesh_instance(r, scene, path, "perch", &branch, b, xform, PLM_PART_OTHER);
    if (rc == PLM_OK)
        rc = add_mesh_instance(r, scene, path, "feet", &feet, f, xform, PLM_PART_OTHER);
    else
        plm_mesh_free(&feet);
    return rc;
}

static plm_result read_options(const plm_json_reader *r, const cJSON *obj, const char *path, bird_options *o)
{
    static const char *const keys[] = {"bird", "transform", "feathers", "level", "feather_level", "texture_size",
                                       "perch", NULL};
    static const char *const perch_keys[] = {"radius", "length", "colour", NULL};
    plm_result rc = plm_json_check_object(r, obj, path, keys);
    const cJSON *perch = cJSON_GetObjectItemCaseSensitive(obj, "perch");
    char ppath[300];
    snprintf(ppath, sizeof ppath, "%s.perch", path);
    if (rc == PLM_OK && perch) {
        rc = plm_json_check_object(r, perch, ppath, perch_keys);
        if (rc == PLM_OK)
            rc = plm_json_number(r, perch, ppath, "radius", 12.0, 1.0, 1000.0, &o->perch_radius);
        if (rc == PLM_OK)
            rc = plm_json_number(r, perch, ppath, "length", 300.0, 10.0, 10000.0, &o->perch_length);
        if (rc == PLM_OK)
            rc = plm_json_rgb(r, perch, ppath, "colour", rgb_make(0.22, 0.16, 0.11), 0.0, 1.0, &o->bark);
    }
    if (rc == PLM_OK)
        rc = plm_json_bool(r, obj, path, "feathers", 1, &o->feathers);
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "level", 4, 1, 6, &o->level);
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "feather_level", 2, 1, 6, &o->feather_level);
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "texture_size", 512, 16, 8192, &o->texture_size);
    return rc;
}

static plm_result build(const plm_json_reader *r, const char *path, const plm_bird *bird, plm_bird_body *b,
                        const bird_options *o, const plm_xform *xform, plm_scene *scene, plm_feather_cache *cache,
                        int *ordinal)
{
    plm_result rc = PLM_OK;
    for (int k = 0; rc == PLM_OK && o->feathers && k < bird->tract_count; ++k)
        rc = lay_tract(r, path, bird, b, k, o, xform, scene, cache, ordinal);
    if (rc == PLM_OK && o->feathers && bird->wings.present)
        rc = lay_wings(r, path, bird, b, o, xform, scene, cache, ordinal);
    if (rc == PLM_OK && o->feathers && bird->tail.present)
        rc = lay_tail(r, path, bird, b, o, xform, scene, cache, ordinal);
    if (rc != PLM_OK)
        return rc;
    static const plm_bird_surface pupil = {{0.01, 0.01, 0.01}, 0.03};
    int skin = add_material(scene, path, "skin", &bird->skin);
    int upper = add_material(scene, path, "bill.upper", &bird->bill);
    int lower = add_material(scene, path, "bill.lower", &bird->lower_bill);
    int iris = add_material(scene, path, "iris", &bird->iris);
    int dark = add_material(scene, path, "pupil", &pupil);
    if (skin < 0 || upper < 0 || lower < 0 || iris < 0 || dark < 0)
        return no_memory(r);
    /* The feathered skin is the ID pass's body; the bare eye rings belong to the eyes. */
    plm_mesh feathered, bare;
    double area;
    if (tract_mesh(b, SKIN_FEATHERED, 0, 0.0, &feathered, &area) != PLM_OK)
        return no_memory(r);
    if (tract_mesh(b, SKIN_BARE, 0, 0.0, &bare, &area) != PLM_OK) {
        plm_mesh_free(&feathered);
        return no_memory(r);
    }
    rc = add_mesh_instance(r, scene, path, "skin", &feathered, skin, xform, PLM_PART_BODY);
    if (rc == PLM_OK && bare.triangle_count > 0)
        rc = add_mesh_instance(r, scene, path, "eye_rings", &bare, skin, xform, PLM_PART_OTHER);
    else
        plm_mesh_free(&bare);
    if (rc == PLM_OK)
        rc = add_mesh_instance(r, scene, path, "bill.upper", &b->upper_bill, upper, xform, PLM_PART_OTHER);
    if (rc == PLM_OK)
        rc = add_mesh_instance(r, scene, path, "bill.lower", &b->lower_bill, lower, xform, PLM_PART_OTHER);
    for (int side = 0; rc == PLM_OK && side < 2; ++side)
        rc = add_eye(r, scene, path, b, side, iris, dark, xform);
    if (rc == PLM_OK && o->perch_radius > 0.0)
        rc = add_perch(r, path, bird, o, xform, scene);
    return rc;
}

plm_result plm_bird_block_read(const plm_json_reader *r, const cJSON *obj, const char *path, const plm_xform *xform,
                               plm_scene *scene, plm_feather_cache *cache, int *ordinal)
{
    bird_options o = {0};
    char file[PLM_PATH_MAX];
    plm_result rc = read_options(r, obj, path, &o);
    if (rc == PLM_OK)
        rc = plm_scene_read_path(r, obj, path, "bird", 1, file);
    if (rc != PLM_OK)
        return rc;
    plm_bird *bird = malloc(sizeof *bird);
    if (!bird)
        return no_memory(r);
    plm_bird_body body;
    rc = plm_bird_load(file, bird, r->err);
    if (rc == PLM_OK && (rc = plm_bird_build(bird, o.level, &body, r->err)) != PLM_OK)
        plm_error_prefix(r->err, "%s: ", file);
    if (rc == PLM_OK) {
        rc = build(r, path, bird, &body, &o, xform, scene, cache, ordinal);
        plm_bird_body_free(&body);
    }
    free(bird);
    return rc;
}
