/* Scene files: JSON validated field by field (unknown fields are errors),
 * includes merged, relative paths resolved against the file that names them.
 * docs/scene-format.md documents every field. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene/scene_file.h"

#include "common/feather_texture_contract.h"
#include "common/json_set.h"
#include "common/rng.h"
#include "optics/feather_bsdf.h"
#include "render/film.h"
#include "render/sky.h"
#include "scene/bird_block.h"
#include "scene/feathers.h"
#include "scene/layout_block.h"
#include "scene/readers.h"
#include "texture/feather.h"
#include "texture/texture.h"

#define MAX_INCLUDE_DEPTH 8
#define BIG 1e9 /* bound for coordinates and distances */

/* A name in a scene's "feathers" block and what it places. */
typedef struct named_feather {
    char name[PLM_NAME_MAX];
    plm_feather_parts parts;
} named_feather;

typedef struct loader {
    plm_scene *scene;
    plm_error *err;
    int camera_set, film_set; /* by a file nearer the top: includes do not override them */
    plm_feather_cache cache;
    named_feather *feathers;
    int feather_count, feather_capacity;
    int layout_count;
    int record; /* build the resolved scene (plm_scene_load_ex) */
} loader;

static plm_result load_file(loader *ld, const char *path, int depth, cJSON *parent_includes);

static plm_result read_camera(const plm_json_reader *r, const cJSON *obj, plm_camera_desc *c)
{
    plm_result rc = plm_params_read(r, obj, "camera", &plm_camera_param_block, NULL, c);
    if (rc != PLM_OK)
        return rc;
    vec3 view = v3_sub(c->look_at, c->position);
    if (v3_length(view) < 1e-9)
        return plm_json_fail(r, "camera", "look_at", "must differ from camera.position");
    if (v3_length(v3_cross(view, c->up)) < 1e-9 * v3_length(view) * v3_length(c->up) || v3_length(c->up) == 0.0)
        return plm_json_fail(r, "camera", "up", "must be a non-zero vector not parallel to the view direction");
    c->given = 1;
    return PLM_OK;
}

static plm_result read_film(const plm_json_reader *r, const cJSON *obj, plm_film_desc *f)
{
    static const char *const extra[] = {"view", "exr", "png", NULL};
    plm_result rc = plm_params_read(r, obj, "film", &plm_film_param_block, extra, f);
    if (rc == PLM_OK)
        rc = plm_json_enum(r, obj, "film", "view", plm_view_names, f->view, &f->view);
    /* Outputs are relative to the working directory, not to the scene file:
     * rendering a preset must not write into the preset folder. */
    const char *exr = NULL, *png = NULL;
    if (rc == PLM_OK)
        rc = plm_json_string(r, obj, "film", "exr", NULL, &exr);
    if (rc == PLM_OK)
        rc = plm_json_string(r, obj, "film", "png", NULL, &png);
    if (rc != PLM_OK)
        return rc;
    if (exr)
        snprintf(f->exr, sizeof f->exr, "%s", exr);
    if (png)
        snprintf(f->png, sizeof f->png, "%s", png);
    return PLM_OK;
}

/* The environment's "map": a lat-long image of at least RGB. */
static plm_result read_environment_map(const plm_json_reader *r, const cJSON *obj, const char *path, plm_light *l)
{
    char file[PLM_PATH_MAX];
    plm_result rc = plm_scene_read_path(r, obj, path, "map", 0, file);
    if (rc != PLM_OK || !file[0])
        return rc;
    l->type = PLM_LIGHT_ENV_MAP;
    plm_image *im = &l->image;
    rc = plm_image_read(file, &im->width, &im->height, &im->channels, &im->pixels, r->err);
    if (rc != PLM_OK) {
        plm_error_prefix(r->err, "%s: %s.map: ", r->file, path);
        return rc;
    }
    if (im->channels < 3) {
        free(im->pixels);
        im->pixels = NULL;
        return plm_json_fail(r, path, "map", "%s has %d channels, an environment map needs RGB", file, im->channels);
    }
    return PLM_OK;
}

/* A sky's sun from a place and a time: "time" with latitude and longitude
 * instead of sun_elevation and sun_azimuth. */
static plm_result read_sun_time(const plm_json_reader *r, const cJSON *obj, const char *path, plm_light *l)
{
    const char *time = NULL;
    plm_result rc = plm_json_string(r, obj, path, "time", NULL, &time);
    int has_place = cJSON_HasObjectItem(obj, "latitude") || cJSON_HasObjectItem(obj, "longitude");
    if (rc != PLM_OK || (!time && !has_place))
        return rc;
    if (!time)
        return plm_json_fail(r, path, cJSON_HasObjectItem(obj, "latitude") ? "latitude" : "longitude",
                             "places the sun only with \"time\" (e.g. \"2026-06-21T09:30+02:00\")");
    if (!cJSON_HasObjectItem(obj, "latitude") || !cJSON_HasObjectItem(obj, "longitude"))
        return plm_json_fail(r, path, "time", "needs both latitude and longitude, in degrees");
    if (cJSON_HasObjectItem(obj, "sun_elevation") || cJSON_HasObjectItem(obj, "sun_azimuth"))
        return plm_json_fail(r, path, "time", "places the sun itself: give it or sun_elevation and sun_azimuth, "
                                              "not both");
    double julian_day, elevation, azimuth;
    if (!plm_julian_day_parse(time, &julian_day))
        return plm_json_fail(r, path, "time",
                             "\"%s\" is not an ISO 8601 local date and time with its offset from UT, such as "
                             "\"2026-06-21T09:30+02:00\" or \"2026-06-21T07:30Z\"",
                             time);
    plm_sun_position(l->sky.latitude, l->sky.longitude, julian_day, &elevation, &azimuth);
    if (elevation < 0.0)
        return plm_json_fail(r, path, "time", "the sun is %.1f degrees below the horizon there at %s; the sky model "
                                              "needs it above (0 to 90 degrees)",
                             -plm_degrees(elevation), time);
    l->sky.sun_elevation = elevation;
    l->sky.sun_azimuth = azimuth;
    return PLM_OK;
}

static plm_result read_light(const plm_json_reader *r, const cJSON *obj, const char *path, plm_light *l)
{
    static const char *const types[] = {"environment", "sky", "distant", "sphere", "quad", NULL};
    static const plm_light_type light_types[] = {PLM_LIGHT_CONSTANT_ENV, PLM_LIGHT_SKY, PLM_LIGHT_DISTANT,
                                                 PLM_LIGHT_SPHERE, PLM_LIGHT_QUAD};
    const plm_param_block *blocks[] = {&plm_environment_light_param_block, &plm_sky_light_param_block,
                                       &plm_distant_light_param_block, &plm_sphere_light_param_block,
                                       &plm_quad_light_param_block};
    static const char *const map_extra[] = {"type", "map", NULL}, *const sky_extra[] = {"type", "time", NULL},
                             *const type_extra[] = {"type", NULL};
    int type = -1;
    *l = plm_light_default(PLM_LIGHT_CONSTANT_ENV); /* the caller frees l->image whatever the result */
    if (!cJSON_IsObject(obj))
        return plm_json_fail(r, path, NULL, "expected an object");
    if (!cJSON_GetObjectItemCaseSensitive(obj, "type"))
        return plm_json_fail(r, path, "type",
                             "required: one of \"environment\", \"sky\", \"distant\", \"sphere\", \"quad\"");
    plm_result rc = plm_json_enum(r, obj, path, "type", types, 0, &type);
    if (rc != PLM_OK)
        return rc;
    *l = plm_light_default(light_types[type]);
    /* Only the environment has a "map", only the sky a "time". */
    rc = plm_params_read(r, obj, path, blocks[type], type == 0 ? map_extra : type == 1 ? sky_extra : type_extra, l);
    if (rc == PLM_OK && type == 1)
        rc = read_sun_time(r, obj, path, l);
    if (rc != PLM_OK)
        return rc;
    if (v3_length(l->up) == 0.0)
        return plm_json_fail(r, path, "up", "must be a non-zero vector (the zenith)");
    l->up = v3_normalize(l->up);
    if (l->type == PLM_LIGHT_DISTANT) {
        if (v3_length(l->direction) == 0.0)
            return plm_json_fail(r, path, "direction", "must be a non-zero vector (pointing toward the light)");
        l->direction = v3_normalize(l->direction);
    }
    if (l->type == PLM_LIGHT_QUAD && v3_length(v3_cross(l->edge_u, l->edge_v)) < 1e-12)
        return plm_json_fail(r, path, "edge_v", "edge_u and edge_v must span a non-zero area");
    return type == 0 ? read_environment_map(r, obj, path, l) : PLM_OK;
}

static plm_result read_mesh(const plm_json_reader *r, const cJSON *obj, const char *path, plm_mesh *m)
{
    static const char *const shapes[] = {"quad", "sphere", NULL};
    static const char *const file_keys[] = {"file", NULL};
    static const char *const quad_keys[] = {"shape", "size", "curl", "segments", NULL};
    static const char *const sphere_keys[] = {"shape", "radius", "rings", NULL};
    if (!cJSON_IsObject(obj))
        return plm_json_fail(r, path, NULL, "expected an object with \"file\" or \"shape\"");
    if (cJSON_GetObjectItemCaseSensitive(obj, "file")) {
        char file[PLM_PATH_MAX];
        plm_result rc = plm_json_check_object(r, obj, path, file_keys);
        if (rc == PLM_OK)
            rc = plm_scene_read_path(r, obj, path, "file", 1, file);
        if (rc == PLM_OK && (rc = plm_mesh_read(file, m, r->err)) != PLM_OK)
            plm_error_prefix(r->err, "%s: %s.file: ", r->file, path);
        return rc;
    }
    if (!cJSON_GetObjectItemCaseSensitive(obj, "shape"))
        return plm_json_fail(r, path, NULL, "needs \"file\" (PLY or OBJ) or \"shape\" (\"quad\" or \"sphere\")");
    int shape = 0;
    plm_result rc = plm_json_enum(r, obj, path, "shape", shapes, 0, &shape);
    if (rc == PLM_OK)
        rc = plm_json_check_object(r, obj, path, shape == 0 ? quad_keys : sphere_keys);
    if (rc != PLM_OK)
        return rc;
    if (shape == 0) {
        double size[2] = {1.0, 1.0}, curl = 0.0;
        int segments = 32;
        const cJSON *s = cJSON_GetObjectItemCaseSensitive(obj, "size");
        if (s) {
            if (!cJSON_IsArray(s) || cJSON_GetArraySize(s) != 2 || !cJSON_IsNumber(cJSON_GetArrayItem(s, 0)) ||
                !cJSON_IsNumber(cJSON_GetArrayItem(s, 1)))
                return plm_json_fail(r, path, "size", "expected [width, height], each in (0, 1e9]");
            size[0] = cJSON_GetArrayItem(s, 0)->valuedouble;
            size[1] = cJSON_GetArrayItem(s, 1)->valuedouble;
            if (!(size[0] > 0.0 && size[0] <= BIG && size[1] > 0.0 && size[1] <= BIG))
                return plm_json_fail(r, path, "size", "expected [width, height], each in (0, 1e9]");
        }
        rc = plm_json_number(r, obj, path, "curl", 0.0, -BIG, BIG, &curl);
        if (rc == PLM_OK)
            rc = plm_json_int(r, obj, path, "segments", segments, 1, 4096, &segments);
        if (rc == PLM_OK && fabs(curl) * size[0] > PLM_TWO_PI)
            return plm_json_fail(r, path, "curl", "|curl| * width must be at most 2 pi (one full turn)");
        return rc == PLM_OK ? plm_shape_quad(size[0], size[1], curl, segments, m, r->err) : rc;
    }
    double radius;
    int rings;
    rc = plm_json_number(r, obj, path, "radius", 1.0, 1e-9, BIG, &radius);
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "rings", 64, 3, 4096, &rings);
    return rc == PLM_OK ? plm_shape_sphere(radius, rings, m, r->err) : rc;
}

/* A feather's "pigment": the generator's pigment image (pigment.exr), so that a feather read from its
 * files is coloured as the same feather generated in memory. Its channels are weights in [0, 1]
 * (common/feather_texture_contract.h); a 3-channel image has no downy base. */
static plm_result read_pigment_image(const plm_json_reader *r, const cJSON *obj, const char *path, plm_material *m)
{
    char file[PLM_PATH_MAX];
    plm_result rc = plm_scene_read_path(r, obj, path, "pigment", 0, file);
    if (rc != PLM_OK || !file[0])
        return rc;
    plm_image *im = &m->pigment;
    if ((rc = plm_image_read(file, &im->width, &im->height, &im->channels, &im->pixels, r->err)) != PLM_OK) {
        plm_error_prefix(r->err, "%s: %s.pigment: ", r->file, path);
        return rc;
    }
    size_t n = (size_t)im->width * (size_t)im->height * (size_t)im->channels, i = 0;
    if (im->channels >= 3 && im->channels <= PLM_PIGMENT_CHANNELS)
        while (i < n && im->pixels[i] >= 0.0f && im->pixels[i] <= 1.0f)
            ++i;
    else
        rc = plm_json_fail(r, path, "pigment", "%s has %d channels; a pigment image has 3 or 4", file, im->channels);
    if (rc == PLM_OK && i < n)
        rc = plm_json_fail(r, path, "pigment", "%s: value %g at pixel %zu, channel %zu is not a weight in [0, 1]",
                           file, im->pixels[i], i / (size_t)im->channels, i % (size_t)im->channels);
    if (rc != PLM_OK) {
        free(im->pixels);
        im->pixels = NULL;
    }
    return rc;
}

static plm_result read_feather(const plm_json_reader *r, const cJSON *obj, const char *path, plm_material *m)
{
    static const char *const extra[] = {"type", "texture", "pigment", "barb", "barbule", "masking", "bcsdf", NULL};
    static const char *const bcsdfs[] = {"tabulated", "stochastic", NULL}; /* in plm_bcsdf_kind's order */
    int bcsdf = PLM_BCSDF_TABULATED;
    plm_result rc = plm_feather_optics_read(r, obj, path, extra, m);
    if (rc == PLM_OK && (rc = plm_json_enum(r, obj, path, "bcsdf", bcsdfs, bcsdf, &bcsdf)) == PLM_OK)
        m->feather->bcsdf = (plm_bcsdf_kind)bcsdf;
    char texture[PLM_PATH_MAX];
    if (rc == PLM_OK)
        rc = plm_scene_read_path(r, obj, path, "texture", 1, texture);
    if (rc == PLM_OK && (rc = plm_feather_texture_read(texture, &m->texture, r->err)) != PLM_OK)
        plm_error_prefix(r->err, "%s: %s.texture: ", r->file, path);
    return rc == PLM_OK ? read_pigment_image(r, obj, path, m) : rc;
}

/* {"type": "coat", "reflectance": base albedo, "roughness": GGX alpha, "ior"} */
static plm_result read_coat(const plm_json_reader *r, const cJSON *obj, const char *path, plm_material *m)
{
    static const char *const keys[] = {"type", "reflectance", "roughness", "ior", NULL};
    m->type = PLM_MATERIAL_COAT;
    plm_result rc = plm_json_check_object(r, obj, path, keys);
    if (rc == PLM_OK)
        rc = plm_json_rgb(r, obj, path, "reflectance", rgb_gray(0.5), 0.0, 1.0, &m->reflectance);
    if (rc == PLM_OK)
        rc = plm_json_number(r, obj, path, "roughness", 0.2, 0.01, 1.0, &m->roughness);
    if (rc == PLM_OK)
        rc = plm_json_number(r, obj, path, "ior", 1.5, 1.01, 3.0, &m->ior);
    return rc;
}

static plm_result read_material(const plm_json_reader *r, const cJSON *obj, const char *path, plm_material *m)
{
    static const char *const types[] = {"diffuse", "feather", "coat", NULL};
    static const char *const diffuse_keys[] = {"type", "reflectance", "transmission", "mask", NULL};
    int type = 0;
    if (!cJSON_IsObject(obj))
        return plm_json_fail(r, path, NULL, "expected an object");
    plm_result rc = plm_json_enum(r, obj, path, "type", types, 0, &type);
    if (rc != PLM_OK)
        return rc;
    if (type == 1)
        return read_feather(r, obj, path, m);
    if (type == 2)
        return read_coat(r, obj, path, m);
    rc = plm_json_check_object(r, obj, path, diffuse_keys);
    if (rc == PLM_OK)
        rc = plm_json_rgb(r, obj, path, "reflectance", rgb_gray(0.5), 0.0, 1.0, &m->reflectance);
    if (rc == PLM_OK)
        rc = plm_json_number(r, obj, path, "transmission", 0.0, 0.0, 1.0, &m->transmission);
    char mask[PLM_PATH_MAX];
    if (rc == PLM_OK)
        rc = plm_scene_read_path(r, obj, path, "mask", 0, mask);
    if (rc == PLM_OK && mask[0] && (rc = plm_feather_texture_read(mask, &m->texture, r->err)) != PLM_OK)
        plm_error_prefix(r->err, "%s: %s.mask: ", r->file, path);
    m->type = PLM_MATERIAL_DIFFUSE;
    return rc;
}

/* {"translate", "rotate" (degrees about x, then y, then z), "scale"} or {"matrix": 12 or 16 numbers, row-major}. */
static plm_result read_transform(const plm_json_reader *r, const cJSON *obj, const char *path, plm_xform *out)
{
    static const char *const keys[] = {"translate", "rotate", "scale", "matrix", NULL};
    *out = plm_xform_identity();
    if (!obj)
        return PLM_OK;
    plm_result rc = plm_json_check_object(r, obj, path, keys);
    if (rc != PLM_OK)
        return rc;
    const cJSON *mat = cJSON_GetObjectItemCaseSensitive(obj, "matrix");
    if (mat) {
        int n = cJSON_GetArraySize(mat);
        if (obj->child->next || !cJSON_IsArray(mat) || (n != 12 && n != 16))
            return plm_json_fail(r, path, "matrix", "expected 12 or 16 numbers (row-major), and no other field");
        double m[3][4];
        for (int i = 0; i < 12; ++i) {
            const cJSON *e = cJSON_GetArrayItem(mat, i);
            if (!cJSON_IsNumber(e) || !(fabs(e->valuedouble) <= BIG))
                return plm_json_fail(r, path, "matrix", "element %d must be a number in [-1e9, 1e9]", i);
            m[i / 4][i % 4] = e->valuedouble;
        }
        if (!plm_xform_from_matrix(m, out))
            return plm_json_fail(r, path, "matrix", "is singular");
        return PLM_OK;
    }
    vec3 t, rot, s = v3(1.0, 1.0, 1.0);
    rc = plm_json_vec3(r, obj, path, "translate", v3(0.0, 0.0, 0.0), -BIG, BIG, &t);
    if (rc == PLM_OK)
        rc = plm_json_vec3(r, obj, path, "rotate", v3(0.0, 0.0, 0.0), -36000.0, 36000.0, &rot);
    const cJSON *sc = cJSON_GetObjectItemCaseSensitive(obj, "scale");
    if (rc == PLM_OK && cJSON_IsNumber(sc))
        s = v3(sc->valuedouble, sc->valuedouble, sc->valuedouble);
    else if (rc == PLM_OK)
        rc = plm_json_vec3(r, obj, path, "scale", s, -BIG, BIG, &s);
    if (rc != PLM_OK)
        return rc;
    if (!(fabs(s.x) >= 1e-12 && fabs(s.y) >= 1e-12 && fabs(s.z) >= 1e-12 && fabs(s.x) <= BIG))
        return plm_json_fail(r, path, "scale", "must be a non-zero number or 3 non-zero numbers in [-1e9, 1e9]");
    plm_xform x = plm_xform_scale(s), step;
    step = plm_xform_rotate(v3(1, 0, 0), plm_radians(rot.x)), x = plm_xform_compose(&step, &x);
    step = plm_xform_rotate(v3(0, 1, 0), plm_radians(rot.y)), x = plm_xform_compose(&step, &x);
    step = plm_xform_rotate(v3(0, 0, 1), plm_radians(rot.z)), x = plm_xform_compose(&step, &x);
    step = plm_xform_translate(t);
    *out = plm_xform_compose(&step, &x);
    return PLM_OK;
}

static plm_result read_name_ref(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                                int index, const char *kind)
{
    const char *name = NULL;
    plm_result rc = plm_json_string(r, obj, path, key, NULL, &name);
    if (rc != PLM_OK)
        return rc;
    if (!name)
        return plm_json_fail(r, path, key, "required: the name of one of the scene's %s", kind);
    if (index < 0)
        return plm_json_fail(r, path, key, "\"%s\" is not defined in \"%s\"", name, kind);
    return PLM_OK;
}

/* Per-instance colour variation: each channel of the tint scaled by a factor
 * in [1 - jitter, 1], drawn from (seed, instance index), so it never brightens. */
static rgb jitter_tint(rgb tint, double jitter, int seed, int index)
{
    plm_rng rng;
    plm_rng_seed(&rng, plm_hash64((uint64_t)seed, (uint64_t)index, 0x7115), 1);
    double a = plm_rng_uniform(&rng), b = plm_rng_uniform(&rng), c = plm_rng_uniform(&rng);
    return rgb_make(tint.r * (1.0 - jitter * a), tint.g * (1.0 - jitter * b), tint.b * (1.0 - jitter * c));
}

static const named_feather *find_feather(const loader *ld, const char *name)
{
    for (int i = 0; i < ld->feather_count; ++i)
        if (strcmp(ld->feathers[i].name, name) == 0)
            return &ld->feathers[i];
    return NULL;
}

/* What an object places: a mesh with a material, or both parts of a
 * generated feather (its vane with the feather material, its rachis tube). */
static plm_result read_parts(const loader *ld, const plm_json_reader *r, const cJSON *obj, const char *path,
                             plm_feather_parts *parts)
{
    const plm_scene *scene = ld->scene;
    const char *feather = NULL, *mesh_name = NULL, *material_name = NULL;
    plm_result rc = plm_json_string(r, obj, path, "feather", NULL, &feather);
    if (rc == PLM_OK)
        rc = plm_json_string(r, obj, path, "mesh", NULL, &mesh_name);
    if (rc == PLM_OK)
        rc = plm_json_string(r, obj, path, "material", NULL, &material_name);
    if (rc != PLM_OK)
        return rc;
    if (feather) {
        if (mesh_name || material_name)
            return plm_json_fail(r, path, "feather", "give either \"feather\" or \"mesh\" and \"material\"");
        if (cJSON_GetObjectItemCaseSensitive(obj, "part"))
            return plm_json_fail(r, path, "part", "a feather's parts are known: \"part\" is for a mesh");
        const named_feather *f = find_feather(ld, feather);
        if (!f)
            return plm_json_fail(r, path, "feather", "\"%s\" is not defined in \"feathers\"", feather);
        *parts = f->parts;
        return PLM_OK;
    }
    parts->count = 1;
    parts->mesh[0] = mesh_name ? plm_scene_find_mesh(scene, mesh_name) : -1;
    parts->material[0] = material_name ? plm_scene_find_material(scene, material_name) : -1;
    int part = PLM_PART_OTHER;
    rc = read_name_ref(r, obj, path, "mesh", parts->mesh[0], "meshes");
    if (rc == PLM_OK)
        rc = read_name_ref(r, obj, path, "material", parts->material[0], "materials");
    if (rc == PLM_OK)
        rc = plm_json_enum(r, obj, path, "part", plm_part_names, PLM_PART_OTHER, &part);
    parts->part[0] = (plm_part)part;
    return rc;
}

/* Each placement of a feather's parts (or of a mesh that is one) is a feather of its own. */
static plm_result add_parts(const plm_json_reader *r, plm_scene *scene, const plm_feather_parts *parts,
                            const plm_xform *xform, rgb tint)
{
    int feather = 0;
    for (int k = 0; k < parts->count; ++k)
        if (!feather && (parts->part[k] == PLM_PART_VANE || parts->part[k] == PLM_PART_RACHIS ||
                         parts->part[k] == PLM_PART_FLUFF))
            feather = plm_scene_new_feather(scene);
    for (int k = 0; k < parts->count; ++k) {
        plm_instance in = {parts->mesh[k], parts->material[k], *xform, tint, feather, parts->part[k]};
        if (plm_scene_add_instance(scene, &in) < 0)
            return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
    }
    return PLM_OK;
}

/* {"layout": {...}, "transform": ...}: a whole plumage (scene/layout_block.h). */
static plm_result read_layout_object(loader *ld, const plm_json_reader *r, const cJSON *obj, const char *path)
{
    static const char *const keys[] = {"layout", "transform", NULL};
    plm_xform xform;
    char lpath[300];
    snprintf(lpath, sizeof lpath, "%s.layout", path);
    plm_result rc = plm_json_check_object(r, obj, path, keys);
    if (rc == PLM_OK)
        rc = read_transform(r, cJSON_GetObjectItemCaseSensitive(obj, "transform"), path, &xform);
    if (rc == PLM_OK)
        rc = plm_layout_block_read(r, cJSON_GetObjectItemCaseSensitive(obj, "layout"), lpath, &xform, ld->scene,
                                   &ld->cache, ld->layout_count++);
    return rc;
}

/* {"bird": FILE, "transform": ..., ...}: a whole bird (scene/bird_block.h). */
static plm_result read_bird_object(loader *ld, const plm_json_reader *r, const cJSON *obj, const char *path)
{
    plm_xform xform;
    plm_result rc = read_transform(r, cJSON_GetObjectItemCaseSensitive(obj, "transform"), path, &xform);
    if (rc == PLM_OK)
        rc = plm_bird_block_read(r, obj, path, &xform, ld->scene, &ld->cache, &ld->layout_count);
    return rc;
}

static plm_result read_object(loader *ld, const plm_json_reader *r, const cJSON *obj, const char *path)
{
    if (cJSON_IsObject(obj) && cJSON_GetObjectItemCaseSensitive(obj, "layout"))
        return read_layout_object(ld, r, obj, path);
    if (cJSON_IsObject(obj) && cJSON_GetObjectItemCaseSensitive(obj, "bird"))
        return read_bird_object(ld, r, obj, path);
    plm_scene *scene = ld->scene;
    static const char *const keys[] = {"mesh", "material", "feather", "layout", "transform", "tint", "instances",
                                       "tint_jitter", "seed", "part", NULL};
    static const char *const instance_keys[] = {"transform", "tint", NULL};
    plm_feather_parts parts = {0};
    plm_xform xform;
    rgb tint;
    plm_result rc = plm_json_check_object(r, obj, path, keys);
    if (rc == PLM_OK)
        rc = read_parts(ld, r, obj, path, &parts);
    if (rc == PLM_OK)
        rc = read_transform(r, cJSON_GetObjectItemCaseSensitive(obj, "transform"), path, &xform);
    double jitter = 0.0;
    int seed = 0;
    if (rc == PLM_OK)
        rc = plm_json_rgb(r, obj, path, "tint", rgb_gray(1.0), 0.0, 1.0, &tint);
    if (rc == PLM_OK)
        rc = plm_json_number(r, obj, path, "tint_jitter", 0.0, 0.0, 1.0, &jitter);
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "seed", 0, 0, 2147483647, &seed);
    if (rc != PLM_OK)
        return rc;
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(obj, "instances");
    if (!list)
        return add_parts(r, scene, &parts, &xform, jitter_tint(tint, jitter, seed, 0));
    if (!cJSON_IsArray(list))
        return plm_json_fail(r, path, "instances", "expected an array of {\"transform\", \"tint\"} objects");
    int index = 0;
    for (const cJSON *e = list->child; e; e = e->next, ++index) {
        char epath[256];
        snprintf(epath, sizeof epath, "%s.instances[%d]", path, index);
        plm_xform local;
        rgb inst_tint;
        rc = plm_json_check_object(r, e, epath, instance_keys);
        if (rc == PLM_OK)
            rc = read_transform(r, cJSON_GetObjectItemCaseSensitive(e, "transform"), epath, &local);
        if (rc == PLM_OK)
            rc = plm_json_rgb(r, e, epath, "tint", tint, 0.0, 1.0, &inst_tint);
        if (rc != PLM_OK)
            return rc;
        plm_xform x = plm_xform_compose(&xform, &local);
        if ((rc = add_parts(r, scene, &parts, &x, jitter_tint(inst_tint, jitter, seed, index))) != PLM_OK)
            return rc;
    }
    return PLM_OK;
}

static plm_result check_new_name(const plm_json_reader *r, const char *path, const char *name, int existing)
{
    if (strlen(name) >= PLM_NAME_MAX)
        return plm_json_fail(r, path, name, "names are limited to %d characters", PLM_NAME_MAX - 1);
    if (existing >= 0)
        return plm_json_fail(r, path, name, "is already defined (names must be unique across included files)");
    return PLM_OK;
}

static plm_result read_meshes(const plm_json_reader *r, const cJSON *obj, plm_scene *scene)
{
    if (!cJSON_IsObject(obj))
        return plm_json_fail(r, "meshes", NULL, "expected an object of name: mesh");
    for (const cJSON *e = obj->child; e; e = e->next) {
        char path[256];
        snprintf(path, sizeof path, "meshes.%s", e->string);
        plm_mesh mesh = {0};
        plm_result rc = check_new_name(r, "meshes", e->string, plm_scene_find_mesh(scene, e->string));
        if (rc == PLM_OK)
            rc = read_mesh(r, e, path, &mesh);
        if (rc != PLM_OK)
            return rc;
        if (mesh.triangle_count == 0 || !mesh.positions || !mesh.indices) {
            plm_mesh_free(&mesh);
            return plm_json_fail(r, path, NULL, "has no triangles");
        }
        if (plm_scene_add_mesh(scene, e->string, &mesh) < 0) {
            plm_mesh_free(&mesh);
            return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
        }
    }
    return PLM_OK;
}

static plm_result read_materials(const plm_json_reader *r, const cJSON *obj, plm_scene *scene)
{
    if (!cJSON_IsObject(obj))
        return plm_json_fail(r, "materials", NULL, "expected an object of name: material");
    for (const cJSON *e = obj->child; e; e = e->next) {
        char path[256];
        snprintf(path, sizeof path, "materials.%s", e->string);
        plm_material m;
        memset(&m, 0, sizeof m);
        snprintf(m.name, sizeof m.name, "%s", e->string);
        plm_result rc = check_new_name(r, "materials", e->string, plm_scene_find_material(scene, e->string));
        if (rc == PLM_OK)
            rc = read_material(r, e, path, &m);
        if (rc == PLM_OK && plm_scene_add_material(scene, &m) < 0)
            rc = plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
        if (rc != PLM_OK) {
            plm_feather_texture_free(&m.texture);
            free(m.feather);
            return rc;
        }
    }
    return PLM_OK;
}

static plm_result add_named_feather(loader *ld, const char *name, const plm_feather_parts *parts)
{
    if (ld->feather_count == ld->feather_capacity) {
        int cap = ld->feather_capacity ? 2 * ld->feather_capacity : 8;
        named_feather *f = realloc(ld->feathers, (size_t)cap * sizeof *f);
        if (!f)
            return plm_fail(ld->err, PLM_ERR_NO_MEMORY, "out of memory");
        ld->feathers = f;
        ld->feather_capacity = cap;
    }
    named_feather *f = &ld->feathers[ld->feather_count++];
    snprintf(f->name, sizeof f->name, "%s", name);
    f->parts = *parts;
    return PLM_OK;
}

/* {"species": file or the species itself, "level", "texture_size", "variant"}:
 * generated once per distinct (species, level, texture size, variant), however many names ask. */
static plm_result read_species_feather(loader *ld, const plm_json_reader *r, const cJSON *obj, const char *path,
                                      const char *name)
{
    static const char *const keys[] = {"species", "level", "texture_size", "variant", NULL};
    char species_file[PLM_PATH_MAX], inline_path[PLM_SPECIES_PATH_MAX];
    plm_feather_request q = {species_file, PLM_FEATHER_DEFAULT_LEVEL, PLM_TEXTURE_DEFAULT_SIZE, 0, 0, NULL, NULL,
                             NULL, inline_path};
    const cJSON *inline_species = cJSON_GetObjectItemCaseSensitive(obj, "species");
    plm_result rc = plm_json_check_object(r, obj, path, keys);
    if (rc == PLM_OK && cJSON_IsObject(inline_species)) {
        /* The species written out here: its messages name this file and path. */
        q.inline_species = inline_species;
        snprintf(species_file, sizeof species_file, "%s", r->file);
        if (snprintf(inline_path, sizeof inline_path, "%s.species", path) >= (int)sizeof inline_path)
            rc = plm_json_fail(r, path, "species", "nested too deep to be named in messages");
    } else if (rc == PLM_OK && inline_species && !cJSON_IsString(inline_species)) {
        rc = plm_json_fail(r, path, "species", "expected a species file (a string) or the species itself (an object)");
    } else if (rc == PLM_OK) {
        rc = plm_scene_read_path(r, obj, path, "species", 1, species_file);
    }
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "level", q.level, 1, 6, &q.level);
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "texture_size", q.texture_size, 16, 8192, &q.texture_size);
    if (rc == PLM_OK)
        rc = plm_json_int(r, obj, path, "variant", 0, 0, 2147483647, &q.variant);
    if (rc != PLM_OK)
        return rc;
    plm_feather_parts parts;
    /* Whatever fails (reading, optics, generation) comes from the species named here. */
    if ((rc = plm_feather_cache_get(&ld->cache, ld->scene, name, &q, &parts, r->err)) != PLM_OK) {
        if (!q.inline_species)
            plm_error_prefix(r->err, "%s: %s.species: ", r->file, path);
        return rc;
    }
    return add_named_feather(ld, name, &parts);
}

static plm_result read_feathers(loader *ld, const plm_json_reader *r, const cJSON *obj)
{
    if (!cJSON_IsObject(obj))
        return plm_json_fail(r, "feathers", NULL, "expected an object of name: {\"species\": file}");
    for (const cJSON *e = obj->child; e; e = e->next) {
        char path[256];
        snprintf(path, sizeof path, "feathers.%s", e->string);
        plm_result rc = check_new_name(r, "feathers", e->string, find_feather(ld, e->string) ? 0 : -1);
        if (rc == PLM_OK)
            rc = read_species_feather(ld, r, e, path, e->string);
        if (rc != PLM_OK)
            return rc;
    }
    return PLM_OK;
}

/* includes: where the included files' resolved trees are merged (NULL unless recording). */
static plm_result read_includes(loader *ld, const plm_json_reader *r, const cJSON *inc, int depth, cJSON *includes)
{
    if (cJSON_IsString(inc)) {
        char file[PLM_PATH_MAX];
        plm_scene_resolve_path(r->file, inc->valuestring, file);
        return load_file(ld, file, depth + 1, includes);
    }
    if (!cJSON_IsArray(inc))
        return plm_json_fail(r, "include", NULL, "expected a file path or an array of file paths");
    int i = 0;
    for (const cJSON *e = inc->child; e; e = e->next, ++i) {
        if (!cJSON_IsString(e))
            return plm_json_fail(r, "include", NULL, "element %d must be a file path", i);
        char file[PLM_PATH_MAX];
        plm_scene_resolve_path(r->file, e->valuestring, file);
        plm_result rc = load_file(ld, file, depth + 1, includes);
        if (rc != PLM_OK)
            return rc;
    }
    return PLM_OK;
}

static plm_result read_scene(loader *ld, const plm_json_reader *r, const cJSON *root, int depth, cJSON *includes)
{
    static const char *const keys[] = {"include", "camera", "film", "lights", "meshes", "materials", "feathers",
                                       "objects", NULL};
    plm_scene *scene = ld->scene;
    plm_result rc = plm_json_check_object(r, root, "", keys);
    /* The including file's camera and film win over an included file's. */
    const cJSON *camera = cJSON_GetObjectItemCaseSensitive(root, "camera");
    const cJSON *film = cJSON_GetObjectItemCaseSensitive(root, "film");
    int take_camera = camera && !ld->camera_set, take_film = film && !ld->film_set;
    ld->camera_set |= camera != NULL;
    ld->film_set |= film != NULL;
    if (rc == PLM_OK && take_camera)
        rc = read_camera(r, camera, &scene->camera);
    if (rc == PLM_OK && take_film)
        rc = read_film(r, film, &scene->film);
    const cJSON *inc = cJSON_GetObjectItemCaseSensitive(root, "include");
    if (rc == PLM_OK && inc)
        rc = read_includes(ld, r, inc, depth, includes);
    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
    if (rc == PLM_OK && lights && !cJSON_IsArray(lights))
        rc = plm_json_fail(r, "lights", NULL, "expected an array of lights");
    int i = 0;
    for (const cJSON *e = lights ? lights->child : NULL; rc == PLM_OK && e; e = e->next, ++i) {
        char path[64];
        snprintf(path, sizeof path, "lights[%d]", i);
        plm_light light;
        rc = read_light(r, e, path, &light);
        if (rc == PLM_OK && plm_scene_add_light(scene, &light) < 0) {
            free(light.image.pixels);
            rc = plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
        }
    }
    const cJSON *meshes = cJSON_GetObjectItemCaseSensitive(root, "meshes");
    if (rc == PLM_OK && meshes)
        rc = read_meshes(r, meshes, scene);
    const cJSON *materials = cJSON_GetObjectItemCaseSensitive(root, "materials");
    if (rc == PLM_OK && materials)
        rc = read_materials(r, materials, scene);
    const cJSON *feathers = cJSON_GetObjectItemCaseSensitive(root, "feathers");
    if (rc == PLM_OK && feathers)
        rc = read_feathers(ld, r, feathers);
    const cJSON *objects = cJSON_GetObjectItemCaseSensitive(root, "objects");
    if (rc == PLM_OK && objects && !cJSON_IsArray(objects))
        rc = plm_json_fail(r, "objects", NULL, "expected an array of objects");
    i = 0;
    for (const cJSON *e = objects ? objects->child : NULL; rc == PLM_OK && e; e = e->next, ++i) {
        char path[64];
        snprintf(path, sizeof path, "objects[%d]", i);
        rc = read_object(ld, r, e, path);
    }
    return rc;
}

/* The resolved scene: `from` (a file's tree, or its includes' merged trees)
 * moved into `into` as the loader reads them. Lists and named blocks keep
 * the reading order (included files first); of camera and film the first
 * read wins, which is the including file's (from_wins) or the earlier include's. */
static plm_result merge_scene(cJSON *into, cJSON *from, int from_wins, plm_error *err)
{
    static const char *const keys[] = {"camera", "film", "lights", "meshes", "materials", "feathers", "objects"};
    int ok = 1;
    cJSON_DeleteItemFromObjectCaseSensitive(from, "include");
    for (int k = 0; k < 7; ++k) {
        cJSON *item = cJSON_DetachItemFromObjectCaseSensitive(from, keys[k]);
        cJSON *dst = cJSON_GetObjectItemCaseSensitive(into, keys[k]);
        if (!item)
            continue;
        if (!dst || (k < 2 && from_wins)) {
            cJSON_DeleteItemFromObjectCaseSensitive(into, keys[k]);
            ok &= cJSON_AddItemToObject(into, keys[k], item);
            continue;
        }
        while (k >= 2 && item->child) {
            cJSON *e = cJSON_DetachItemViaPointer(item, item->child);
            ok &= cJSON_IsArray(dst) ? cJSON_AddItemToArray(dst, e) : cJSON_AddItemToObject(dst, e->string, e);
        }
        cJSON_Delete(item);
    }
    return ok ? PLM_OK : plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for the resolved scene");
}

/* Reads a file's tree; when recording, its resolved tree (with its own
 * includes') goes into parent_includes. */
static plm_result read_recorded(loader *ld, const plm_json_reader *r, cJSON *root, int depth, cJSON *parent_includes)
{
    cJSON *includes = ld->record ? cJSON_CreateObject() : NULL;
    if (ld->record && !includes)
        return plm_fail(ld->err, PLM_ERR_NO_MEMORY, "out of memory");
    plm_result rc = read_scene(ld, r, root, depth, includes);
    if (rc == PLM_OK && ld->record)
        rc = merge_scene(includes, root, 1, ld->err);
    if (rc == PLM_OK && ld->record)
        rc = merge_scene(parent_includes, includes, 0, ld->err);
    cJSON_Delete(includes);
    return rc;
}

static plm_result load_file(loader *ld, const char *path, int depth, cJSON *parent_includes)
{
    if (depth > MAX_INCLUDE_DEPTH)
        return plm_fail(ld->err, PLM_ERR_INVALID, "%s: include: nested more than %d deep (an include cycle?)",
                        path, MAX_INCLUDE_DEPTH);
    cJSON *root;
    plm_result rc = plm_json_load(path, &root, ld->err);
    if (rc != PLM_OK)
        return rc;
    plm_json_reader r = {path, ld->err, ld->record};
    rc = read_recorded(ld, &r, root, depth, parent_includes);
    cJSON_Delete(root);
    return rc;
}

static void loader_free(loader *ld)
{
    plm_feather_cache_free(&ld->cache);
    free(ld->feathers);
}

/* Reads the top-level tree with a fresh loader; the scene is freed on failure. */
static plm_result load_root(const cJSON *root, const char *name, plm_scene *scene, plm_error *err)
{
    loader ld = {scene, err, 0, 0, {0}, NULL, 0, 0, 0, 0};
    plm_json_reader r = {name, err, 0};
    plm_result rc = read_scene(&ld, &r, root, 0, NULL);
    loader_free(&ld);
    if (rc != PLM_OK)
        plm_scene_free(scene);
    return rc;
}

plm_result plm_scene_load_json(const cJSON *root, const char *name, plm_scene *scene, plm_error *err)
{
    plm_scene_init(scene);
    return load_root(root, name, scene, err);
}

plm_result plm_scene_load_buffer(const char *text, size_t length, const char *name, plm_scene *scene,
                                 plm_error *err)
{
    plm_scene_init(scene);
    cJSON *root;
    plm_result rc = plm_json_parse(text, length, name, &root, err);
    if (rc != PLM_OK)
        return rc;
    rc = load_root(root, name, scene, err);
    cJSON_Delete(root);
    return rc;
}

plm_result plm_scene_load_ex(const char *path, const plm_scene_load_options *o, plm_scene *scene, plm_error *err)
{
    plm_scene_init(scene);
    if (o->resolved)
        *o->resolved = NULL;
    cJSON *root, *resolved = o->resolved ? cJSON_CreateObject() : NULL;
    plm_result rc = plm_json_load(path, &root, err);
    for (int i = 0; rc == PLM_OK && i < o->n_sets; ++i)
        if ((rc = plm_json_set_assignment(root, o->sets[i], err)) != PLM_OK)
            plm_error_prefix(err, "%s: --set ", path);
    if (rc == PLM_OK && o->resolved && !resolved)
        rc = plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory");
    if (rc == PLM_OK) {
        loader ld = {scene, err, 0, 0, {0}, NULL, 0, 0, 0, o->resolved != NULL};
        ld.cache.asset_dir = o->asset_dir;
        plm_json_reader r = {path, err, ld.record};
        rc = read_recorded(&ld, &r, root, 0, resolved);
        loader_free(&ld);
        if (rc != PLM_OK)
            plm_scene_free(scene);
    }
    cJSON_Delete(root);
    if (rc == PLM_OK && o->resolved)
        *o->resolved = resolved;
    else
        cJSON_Delete(resolved);
    return rc;
}

plm_result plm_scene_load_with(const char *path, const char *const *sets, int n_sets, plm_scene *scene,
                               plm_error *err)
{
    plm_scene_load_options o = {sets, n_sets, NULL, NULL};
    return plm_scene_load_ex(path, &o, scene, err);
}

plm_result plm_scene_load(const char *path, plm_scene *scene, plm_error *err)
{
    return plm_scene_load_with(path, NULL, 0, scene, err);
}
