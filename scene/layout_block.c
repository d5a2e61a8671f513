#include "scene/layout_block.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/rng.h"
#include "generate/layout.h"
#include "generate/wing.h"
#include "scene/readers.h"

#define MAX_LAYOUT_SPECIES 16
#define BIG 1e9

static const plm_param variation_params[] = {
    {"scale", PLM_PARAM_NUMBER, offsetof(plm_layout_variation, scale), 0.0, 0.9, "",
     "size factor drawn in [1 - scale, 1 + scale]; 0 = 0.15 in a pelt, else 0.1", 0},
    {"yaw", PLM_PARAM_ANGLE, offsetof(plm_layout_variation, yaw), 0.0, 90.0, "degrees",
     "turn about the surface normal drawn in [-yaw, yaw]; 0 = 6", 0},
    {"lift", PLM_PARAM_ANGLE, offsetof(plm_layout_variation, lift), 0.0, 45.0, "degrees",
     "extra elevation drawn in [0, lift]; 0 = 3", 0},
    {"tint", PLM_PARAM_NUMBER, offsetof(plm_layout_variation, tint), 0.0, 1.0, "",
     "colour factor per channel in [1 - tint, 1]; 0 = 0.1", 0},
    {"none", PLM_PARAM_BOOL, offsetof(plm_layout_variation, none), 0, 1, "", "no variation at all", 0},
};
const plm_param_block plm_variation_param_block = {
    "variation", "per-feather variation of a layout", variation_params,
    PLM_PARAM_COUNT(variation_params)};

static const plm_param pelt_params[] = {
    {"count", PLM_PARAM_INT, offsetof(plm_pelt_params, count), 0, 1e6, "", "feathers; 0 = density x area", 0},
    {"density", PLM_PARAM_NUMBER, offsetof(plm_pelt_params, density), 0.0, 1e7, "per square unit",
     "feathers per unit area when count is 0; 0 = 100 over the whole surface", 0},
    {"axis", PLM_PARAM_VEC3, offsetof(plm_pelt_params, axis), -BIG, BIG, "",
     "flow: feathers point along this axis projected on the surface; [0, 0, 0] = [0, -1, 0]", 0},
    {"overlap", PLM_PARAM_NUMBER, offsetof(plm_pelt_params, overlap), 0.0, 0.95, "",
     "fraction of a feather's length covered by the ones behind it; 0 = 2/3", 0},
    {"feather_length", PLM_PARAM_NUMBER, offsetof(plm_pelt_params, feather_length), 0.0, BIG, "layout units",
     "length of a feather of scale 1; 0 = spacing / (1 - overlap)", 0},
    {"elevation", PLM_PARAM_ANGLE, offsetof(plm_pelt_params, elevation), 0.0, 80.0, "degrees",
     "angle between a feather's base and the surface; 0 = 8", 0},
    {"head_size", PLM_PARAM_NUMBER, offsetof(plm_pelt_params, head_size), 0.0, 1.0, "",
     "size of the feathers at the head end of the flow relative to the largest; 0 = 0.6", 0},
    {"edge_size", PLM_PARAM_NUMBER, offsetof(plm_pelt_params, edge_size), 0.0, 1.0, "",
     "size of the feathers at the surface's edges relative to the largest; 0 = 0.6", 0},
    {"edge_width", PLM_PARAM_NUMBER, offsetof(plm_pelt_params, edge_width), 0.0, BIG, "layout units",
     "how far from an edge feathers shrink; 0 = a feather's length", 0},
    {"variants", PLM_PARAM_INT, offsetof(plm_pelt_params, variants), 0, 64, "",
     "distinct feathers generated per species; 0 = 4", 0},
    {"seed", PLM_PARAM_SEED, offsetof(plm_pelt_params, seed), 0, 2147483647, "", "placement and variation", 0},
};
const plm_param_block plm_pelt_param_block = {
    "pelt", "feathers over a surface (layout type \"pelt\"); also surface, species, variation", pelt_params,
    PLM_PARAM_COUNT(pelt_params)};

static const plm_param ball_params[] = {
    {"count", PLM_PARAM_INT, offsetof(plm_ball_params, count), 0, 1e6, "", "feathers; 0 = 496", 0},
    {"radius", PLM_PARAM_NUMBER, offsetof(plm_ball_params, radius), 0.0, BIG, "layout units",
     "radius of the core sphere; 0 = 1", 0},
    {"feather_length", PLM_PARAM_NUMBER, offsetof(plm_ball_params, feather_length), 0.0, BIG, "layout units",
     "length of a feather of scale 1; 0 = 2 radius", 0},
    {"spread", PLM_PARAM_ANGLE, offsetof(plm_ball_params, spread), 0.0, 90.0, "degrees",
     "feathers lean up to this far from the radial direction; 0 = 10", 0},
    {"variants", PLM_PARAM_INT, offsetof(plm_ball_params, variants), 0, 64, "",
     "distinct feathers generated per species; 0 = 4", 0},
    {"seed", PLM_PARAM_SEED, offsetof(plm_ball_params, seed), 0, 2147483647, "", "placement and variation", 0},
};
const plm_param_block plm_ball_param_block = {
    "ball", "feathers radiating from a sphere (layout type \"ball\"); also species, variation", ball_params,
    PLM_PARAM_COUNT(ball_params)};

static const plm_param wing_params[] = {
    {"span", PLM_PARAM_NUMBER, offsetof(plm_wing_params, span), 0.0, BIG, "layout units",
     "shoulder to the tip of the longest primary; 0 = 1", 0},
    {"chord", PLM_PARAM_NUMBER, offsetof(plm_wing_params, chord), 0.0, BIG, "layout units",
     "length of the secondaries; 0 = 0.3 span", 0},
    {"sweep", PLM_PARAM_ANGLE, offsetof(plm_wing_params, sweep), -60.0, 60.0, "degrees",
     "how far the hand and its primaries sweep back", 0},
    {"fold", PLM_PARAM_NUMBER, offsetof(plm_wing_params, fold), 0.0, 1.0, "", "0 = spread .. 1 = folded", 0},
    {"primaries", PLM_PARAM_INT, offsetof(plm_wing_params, primaries), 0, 12, "", "0 = 10", 0},
    {"secondaries", PLM_PARAM_INT, offsetof(plm_wing_params, secondaries), 0, 24, "", "0 = 12", 0},
    {"tertials", PLM_PARAM_INT, offsetof(plm_wing_params, tertials), 0, 6, "", "0 = 3", 0},
    {"speculum", PLM_PARAM_INT, offsetof(plm_wing_params, speculum), 0, 24, "",
     "outer secondaries taking the speculum row's species, at most secondaries", 0},
    {"variants", PLM_PARAM_INT, offsetof(plm_wing_params, variants), 0, 64, "",
     "distinct feathers generated per row; 0 = 3", 0},
    {"seed", PLM_PARAM_SEED, offsetof(plm_wing_params, seed), 0, 2147483647, "", "variation", 0},
};
const plm_param_block plm_wing_param_block = {
    "wing",
    "a right wing (layout type \"wing\"): shoulder at the origin, span along +x, leading edge toward +y, its top "
    "(dorsal) side toward +z; also rows, variation",
    wing_params,
    PLM_PARAM_COUNT(wing_params)};

/* The species a layout uses, loaded, with their files (for the feather cache). */
typedef struct species_list {
    int count;
    char file[MAX_LAYOUT_SPECIES][PLM_PATH_MAX];
    plm_species species[MAX_LAYOUT_SPECIES];
    plm_layout_species weighted[MAX_LAYOUT_SPECIES];
} species_list;

/* "species": ["file", {"file": ..., "weight": ...}, ...] */
static plm_result read_species(const plm_json_reader *r, const cJSON *obj, const char *path, species_list *out)
{
    static const char *const keys[] = {"file", "weight", NULL};
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(obj, "species");
    int n = cJSON_GetArraySize(list);
    if (!cJSON_IsArray(list) || n < 1 || n > MAX_LAYOUT_SPECIES)
        return plm_json_fail(r, path, "species", "required: an array of 1 to %d species files or "
                             "{\"file\", \"weight\"} objects", MAX_LAYOUT_SPECIES);
    char epath[300];
    int i = 0;
    for (const cJSON *e = list->child; e; e = e->next, ++i) {
        snprintf(epath, sizeof epath, "%s.species[%d]", path, i);
        double weight = 1.0;
        plm_result rc = PLM_OK;
        if (cJSON_IsString(e)) {
            rc = plm_scene_read_path_item(r, e, epath, NULL, out->file[i]);
        } else {
            rc = plm_json_check_object(r, e, epath, keys);
            if (rc == PLM_OK)
                rc = plm_scene_read_path(r, e, epath, "file", 1, out->file[i]);
            if (rc == PLM_OK)
                rc = plm_json_number(r, e, epath, "weight", 1.0, 1e-6, 1e6, &weight);
        }
        if (rc == PLM_OK && (rc = plm_species_load(out->file[i], &out->species[i], r->err)) != PLM_OK)
            plm_error_prefix(r->err, "%s: %s: ", r->file, epath);
        if (rc != PLM_OK)
            return rc;
        out->weighted[i] = (plm_layout_species){&out->species[i], weight};
        out->count = i + 1;
    }
    return PLM_OK;
}

/* "rows": {"primary": file, "secondary": file, ...}: one species per wing row,
 * indexed by plm_wing_row; rows left out take their fallback's. */
static plm_result read_rows(const plm_json_reader *r, const cJSON *obj, const char *path, species_list *out)
{
    const cJSON *rows = cJSON_GetObjectItemCaseSensitive(obj, "rows");
    char rpath[300];
    snprintf(rpath, sizeof rpath, "%s.rows", path);
    if (!cJSON_IsObject(rows))
        return plm_json_fail(r, path, "rows", "required: {\"primary\": file, \"secondary\": file, ...}");
    const char *keys[PLM_WING_ROWS + 1] = {NULL};
    for (int row = 0; row < PLM_WING_ROWS; ++row)
        keys[row] = plm_wing_row_names[row];
    plm_result rc = plm_json_check_object(r, rows, rpath, keys);
    for (int row = 0; rc == PLM_OK && row < PLM_WING_ROWS; ++row) {
        int required = row == PLM_WING_PRIMARY || row == PLM_WING_SECONDARY;
        rc = plm_scene_read_path(r, rows, rpath, plm_wing_row_names[row], required, out->file[row]);
    }
    for (int row = 0; rc == PLM_OK && row < PLM_WING_ROWS; ++row) {
        if (!out->file[row][0])
            snprintf(out->file[row], PLM_PATH_MAX, "%s", out->file[plm_wing_row_fallback(row)]);
        if ((rc = plm_species_load(out->file[row], &out->species[row], r->err)) != PLM_OK)
            plm_error_prefix(r->err, "%s: %s.%s: ", r->file, rpath, plm_wing_row_names[row]);
        else
            out->count = row + 1;
    }
    return rc;
}

/* {"shape": "mesh", "file": PLY or OBJ, "flow": "tangents" or "axis"}: the
 * mesh read and added to the scene under the layout's name. Its vertex
 * tangents are the flow unless "flow" is "axis" (the pelt's axis projected
 * onto the surface); the default is the tangents when the file has them. */
static plm_result read_surface_file(const plm_json_reader *r, const cJSON *surface, const char *spath,
                                    const char *path, plm_scene *scene, int *mesh_index)
{
    static const char *const keys[] = {"shape", "file", "flow", NULL};
    static const char *const flows[] = {"tangents", "axis", NULL};
    char file[PLM_PATH_MAX];
    plm_mesh m = {0};
    int flow = 0;
    plm_result rc = plm_json_check_object(r, surface, spath, keys);
    if (rc == PLM_OK)
        rc = plm_scene_read_path(r, surface, spath, "file", 1, file);
    if (rc == PLM_OK && (rc = plm_mesh_read(file, &m, r->err)) != PLM_OK)
        plm_error_prefix(r->err, "%s: %s.file: ", r->file, spath);
    if (rc == PLM_OK)
        rc = plm_json_enum(r, surface, spath, "flow", flows, m.tangents ? 0 : 1, &flow);
    if (rc == PLM_OK && flow == 0 && !m.tangents)
        rc = plm_json_fail(r, spath, "flow", "\"tangents\" needs vertex tangents (PLY tx ty tz) in %s", file);
    if (rc == PLM_OK && flow == 1) {
        free(m.tangents);
        m.tangents = NULL;
    }
    char name[PLM_NAME_MAX];
    snprintf(name, sizeof name, "%.100s.surface", path);
    if (rc == PLM_OK && (*mesh_index = plm_scene_add_mesh(scene, name, &m)) < 0)
        rc = plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
    if (rc != PLM_OK)
        plm_mesh_free(&m);
    return rc;
}

/* "surface": {"shape": "plane", "size": [w, h]}, {"shape": "sphere", "radius": r},
 * {"shape": "mesh", "file": FILE, ...} or {"mesh": NAME} (a mesh of the scene's "meshes"). */
static plm_result read_surface(const plm_json_reader *r, const cJSON *obj, const char *path, plm_scene *scene,
                               plm_surface *s, int *mesh_index)
{
    static const char *const shapes[] = {"plane", "sphere", "mesh", NULL};
    static const char *const plane_keys[] = {"shape", "size", NULL};
    static const char *const sphere_keys[] = {"shape", "radius", NULL};
    static const char *const mesh_keys[] = {"mesh", NULL};
    char spath[300];
    snprintf(spath, sizeof spath, "%s.surface", path);
    const cJSON *surface = cJSON_GetObjectItemCaseSensitive(obj, "surface");
    *mesh_index = -1;
    if (!cJSON_IsObject(surface))
        return plm_json_fail(r, path, "surface", "required: {\"shape\": \"plane\", \"sphere\" or \"mesh\"} or "
                             "{\"mesh\": NAME}");
    const char *mesh = NULL;
    plm_result rc = plm_json_string(r, surface, spath, "mesh", NULL, &mesh);
    if (rc == PLM_OK && mesh) {
        rc = plm_json_check_object(r, surface, spath, mesh_keys);
        *mesh_index = plm_scene_find_mesh(scene, mesh);
        if (rc == PLM_OK && *mesh_index < 0)
            return plm_json_fail(r, spath, "mesh", "\"%s\" is not defined in \"meshes\"", mesh);
        s->kind = PLM_SURFACE_MESH;
        return rc;
    }
    int shape = 0;
    if (rc == PLM_OK)
        rc = plm_json_enum(r, surface, spath, "shape", shapes, 0, &shape);
    if (rc == PLM_OK && shape == 2) {
        s->kind = PLM_SURFACE_MESH;
        return read_surface_file(r, surface, spath, path, scene, mesh_index);
    }
    if (rc == PLM_OK)
        rc = plm_json_check_object(r, surface, spath, shape == 0 ? plane_keys : sphere_keys);
    if (rc != PLM_OK)
        return rc;
    if (shape == 1) {
        s->kind = PLM_SURFACE_SPHERE;
        return plm_json_number(r, surface, spath, "radius", 1.0, 1e-6, BIG, &s->radius);
    }
    s->kind = PLM_SURFACE_PLANE;
    s->width = s->height = 1.0;
    const cJSON *size = cJSON_GetObjectItemCaseSensitive(surface, "size");
    if (!size)
        return PLM_OK;
    if (!cJSON_IsArray(size) || cJSON_GetArraySize(size) != 2 || !cJSON_IsNumber(size->child) ||
        !cJSON_IsNumber(size->child->next) || !(size->child->valuedouble > 0.0 && size->child->valuedouble <= BIG) ||
        !(size->child->next->valuedouble > 0.0 && size->child->next->valuedouble <= BIG))
        return plm_json_fail(r, spath, "size", "expected [width, height], each in (0, 1e9]");
    s->width = size->child->valuedouble;
    s->height = size->child->next->valuedouble;
    return PLM_OK;
}

/* The layout's surface (pelt), core (ball) or skin (wing) as a scene object, when a material is named for it. */
static plm_result add_base(const plm_json_reader *r, const cJSON *obj, const char *path, const plm_surface *s,
                           const plm_wing_params *wing, int mesh_index, const plm_xform *xform, plm_scene *scene)
{
    const char *name = NULL;
    plm_result rc = plm_json_string(r, obj, path, "surface_material", NULL, &name);
    if (rc != PLM_OK || !name)
        return rc;
    int material = plm_scene_find_material(scene, name);
    if (material < 0)
        return plm_json_fail(r, path, "surface_material", "\"%s\" is not defined in \"materials\"", name);
    if (mesh_index < 0) {
        plm_mesh m = {0};
        char mesh_name[PLM_NAME_MAX];
        snprintf(mesh_name, sizeof mesh_name, "%.100s.surface", path);
        rc = wing                            ? plm_wing_skin(wing, &m, r->err)
             : s->kind == PLM_SURFACE_PLANE ? plm_shape_quad(s->width, s->height, 0.0, 1, &m, r->err)
                                            : plm_shape_sphere(s->radius, 64, &m, r->err);
        if (rc != PLM_OK)
            return rc;
        if ((mesh_index = plm_scene_add_mesh(scene, mesh_name, &m)) < 0) {
            plm_mesh_free(&m);
            return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
        }
    }
    plm_instance in = {mesh_index, material, *xform, rgb_gray(1.0), 0, PLM_PART_BODY};
    return plm_scene_add_instance(scene, &in) < 0 ? plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory") : PLM_OK;
}

plm_result plm_layout_block_place(const plm_json_reader *r, const char *path, const plm_layout *layout,
                                  const char *const *species_files, int level, int texture_size, uint64_t seed,
                                  int ordinal, const plm_xform *xform, plm_scene *scene, plm_feather_cache *cache)
{
    plm_feather_parts *parts = calloc((size_t)layout->prototype_count, sizeof *parts);
    if (!parts && layout->prototype_count)
        return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
    plm_result rc = PLM_OK;
    /* Only the prototypes some instance shows (a wing's speculum row may have none). */
    for (int i = 0; parts && i < layout->instance_count; ++i)
        parts[layout->instances[i].prototype].count = 1;
    for (int k = 0; rc == PLM_OK && k < layout->prototype_count; ++k) {
        const plm_layout_prototype *pr = &layout->prototypes[k];
        if (!parts[k].count)
            continue;
        char name[PLM_NAME_MAX];
        snprintf(name, sizeof name, "layout%d.%d", ordinal, k);
        plm_feather_request q = {species_files[pr->species], level, texture_size, k + 1,
                                 plm_hash64(seed, (uint64_t)ordinal, 0x1a70u), &pr->shape, &pr->pigment, NULL, NULL};
        if ((rc = plm_feather_cache_get(cache, scene, name, &q, &parts[k], r->err)) != PLM_OK)
            plm_error_prefix(r->err, "%s: %s: ", r->file, path);
    }
    for (int i = 0; rc == PLM_OK && i < layout->instance_count; ++i) {
        const plm_layout_instance *li = &layout->instances[i];
        plm_xform local;
        if (!plm_xform_from_matrix(li->m, &local))
            continue; /* a degenerate placement has nothing to show */
        plm_xform x = plm_xform_compose(xform, &local);
        const plm_feather_parts *p = &parts[li->prototype];
        int feather = plm_scene_new_feather(scene);
        for (int k = 0; rc == PLM_OK && k < p->count; ++k) {
            plm_instance in = {p->mesh[k], p->material[k], x, li->tint, feather, p->part[k]};
            if (plm_scene_add_instance(scene, &in) < 0)
                rc = plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
        }
    }
    free(parts);
    return rc;
}

plm_result plm_layout_block_read(const plm_json_reader *r, const cJSON *obj, const char *path, const plm_xform *xform,
                                 plm_scene *scene, plm_feather_cache *cache, int ordinal)
{
    static const char *const types[] = {"pelt", "ball", "wing", NULL};
    static const char *const wing_extra[] = {"type", "rows", "surface_material", "variation", "level",
                                             "texture_size", NULL};
    static const char *const pelt_extra[] = {"type", "species", "surface", "surface_material", "variation",
                                             "level", "texture_size", NULL};
    static const char *const ball_extra[] = {"type", "species", "surface_material", "variation", "level",
                                             "texture_size", NULL};
    if (!cJSON_IsObject(obj))
        return plm_json_fail(r, path, NULL, "expected an object with \"type\": \"pelt\", \"ball\" or \"wing\"");
    int type = 0, level = 2, texture_size = 512;
    plm_result rc = plm_json_enum(r, obj, path, "type", types, 0, &type);
    plm_pelt_params pelt = {0};
    plm_ball_params ball = {0};
    plm_wing_params wing = {0};
    plm_layout_variation *variation = type == 0 ? &pelt.variation : type == 1 ? &ball.variation : &wing.variation;
    char vpath[300];
    snprintf(vpath, sizeof vpath, "%s.variation", path);
    if (rc == PLM_OK)
        rc = type == 0   ? plm_params_read(r, obj, path, &plm_pelt_param_block, pelt_extra, &pelt)
             : type == 1 ? plm_params_read(r, obj, path, &plm_ball_param_block, ball_extra, &ball)
                         : plm_params_read(r, obj, path, &plm_wing_param_block, wing_extra, &wing);
    const cJSON *var = cJSON_GetObjectItemCaseSensitive(obj, "variation");
    if (rc == PLM_OK && var)
        rc = plm_params_read(r, var, vpath, &plm_variation_param_block, NULL, variation);
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "level", level, 1, 6, &level);
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "texture_size", texture_size, 16, 8192, &texture_size);
    int mesh_index = -1;
    if (rc == PLM_OK && type == 0)
        rc = read_surface(r, obj, path, scene, &pelt.surface, &mesh_index);
    if (rc != PLM_OK)
        return rc;
    if (mesh_index >= 0)
        pelt.surface.mesh = &scene->meshes[mesh_index].mesh; /* used before any mesh is added */
    species_list *sl = calloc(1, sizeof *sl);
    if (!sl)
        return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
    plm_layout layout = {0};
    rc = type == 2 ? read_rows(r, obj, path, sl) : read_species(r, obj, path, sl);
    if (rc == PLM_OK) {
        const plm_species *rows[PLM_WING_ROWS];
        for (int row = 0; row < PLM_WING_ROWS && type == 2; ++row)
            rows[row] = &sl->species[row];
        rc = type == 0   ? plm_layout_pelt(&pelt, sl->weighted, sl->count, &layout, r->err)
             : type == 1 ? plm_layout_ball(&ball, sl->weighted, sl->count, &layout, r->err)
                         : plm_layout_wing(&wing, rows, &layout, r->err);
        if (rc != PLM_OK)
            plm_error_prefix(r->err, "%s: %s: ", r->file, path);
    }
    uint64_t seed = type == 0 ? pelt.seed : type == 1 ? ball.seed : wing.seed;
    const char *files[MAX_LAYOUT_SPECIES];
    for (int i = 0; i < sl->count; ++i)
        files[i] = sl->file[i];
    if (rc == PLM_OK)
        rc = plm_layout_block_place(r, path, &layout, files, level, texture_size, seed, ordinal, xform, scene, cache);
    plm_surface core = {PLM_SURFACE_SPHERE, 0.0, 0.0, ball.radius > 0.0 ? ball.radius : 1.0, NULL};
    if (rc == PLM_OK)
        rc = add_base(r, obj, path, type == 0 ? &pelt.surface : &core, type == 2 ? &wing : NULL, mesh_index, xform,
                      scene);
    plm_layout_free(&layout);
    for (int i = 0; i < sl->count; ++i)
        plm_species_free(&sl->species[i]);
    free(sl);
    return rc;
}
