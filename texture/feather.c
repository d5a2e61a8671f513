#include "texture/feather.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "common/fileio.h"
#include "generate/fluff.h"
#include "generate/geometry.h"
#include "texture/texture.h"

plm_result plm_feather_generate(const plm_species *species, const plm_feather_options *options, plm_feather *out,
                                plm_error *err)
{
    memset(out, 0, sizeof *out);
    plm_feather_options opt = options ? *options : (plm_feather_options){0};
    int level = opt.level ? opt.level : PLM_FEATHER_DEFAULT_LEVEL;
    int tw = opt.texture_width ? opt.texture_width : PLM_TEXTURE_DEFAULT_SIZE;
    int th = opt.texture_height ? opt.texture_height : PLM_TEXTURE_DEFAULT_SIZE;
    if (level < 1 || level > 6)
        return plm_fail(err, PLM_ERR_INVALID, "subdivision level %d is out of range [1, 6]", level);
    plm_result rc = plm_species_validate(species, species->name, err);
    if (rc == PLM_OK)
        rc = plm_outline_init(&out->outline, &species->shape, species->name, err);
    if (rc == PLM_OK && !opt.no_meshes)
        rc = plm_vane_mesh(&out->outline, level, &out->vane, err);
    /* The tube is thin: one level less gives it as many segments per mm as the vane. */
    if (rc == PLM_OK && !opt.no_meshes)
        rc = plm_rachis_mesh(&out->outline, level > 1 ? level - 1 : 1, &out->rachis, err);
    if (rc == PLM_OK && !opt.no_meshes)
        rc = plm_fluff_curves(&out->outline, &out->fluff, err);
    if (rc == PLM_OK && !opt.no_textures)
        rc = plm_texture_author(&out->outline, &species->pigment, tw, th, &out->texture, &out->barb,
                                opt.no_pigment ? NULL : &out->pigment, err);
    if (rc != PLM_OK)
        plm_feather_free(out);
    return rc;
}

void plm_feather_free(plm_feather *f)
{
    plm_mesh_free(&f->vane);
    plm_mesh_free(&f->rachis);
    plm_curves_free(&f->fluff);
    plm_texture_image_free(&f->texture);
    plm_texture_image_free(&f->barb);
    plm_texture_image_free(&f->pigment);
}

static plm_result join_path(char *buf, size_t n, const char *dir, const char *name, plm_error *err)
{
    if ((size_t)snprintf(buf, n, "%s/%s", dir, name) >= n)
        return plm_fail(err, PLM_ERR_INVALID, "%s: path is too long", dir);
    return PLM_OK;
}

static plm_result write_image_pair(const char *dir, const char *stem, const plm_image *img,
                                   const plm_feather_files *files, plm_error *err)
{
    char path[4096], name[64];
    plm_result rc = PLM_OK;
    if (!img->pixels)
        return PLM_OK;
    if (!files->no_exr) {
        snprintf(name, sizeof name, "%s.exr", stem);
        rc = join_path(path, sizeof path, dir, name, err);
        if (rc == PLM_OK)
            rc = plm_texture_write(path, img, err);
    }
    if (rc == PLM_OK && !files->no_png) {
        snprintf(name, sizeof name, "%s.png", stem);
        rc = join_path(path, sizeof path, dir, name, err);
        if (rc == PLM_OK)
            rc = plm_texture_write(path, img, err);
    }
    return rc;
}

plm_result plm_feather_write_textures(const plm_feather *f, const char *dir, const plm_feather_files *files,
                                      plm_error *err)
{
    plm_feather_files def = {0};
    if (!files)
        files = &def;
    plm_image texture = {0};
    plm_result rc = plm_make_dirs(dir, err);
    if (rc == PLM_OK && f->texture.pixels)
        rc = plm_texture_with_barb(&f->texture, &f->barb, &texture, err);
    if (rc == PLM_OK)
        rc = write_image_pair(dir, "texture", &texture, files, err);
    plm_texture_image_free(&texture);
    if (rc == PLM_OK)
        rc = write_image_pair(dir, "pigment", &f->pigment, files, err);
    return rc;
}

static void mesh_bounds(const plm_mesh *m, vec3 *lo, vec3 *hi)
{
    for (int i = 0; i < m->vertex_count; ++i) {
        const float *p = m->positions + 3 * i;
        *lo = v3(fmin(lo->x, p[0]), fmin(lo->y, p[1]), fmin(lo->z, p[2]));
        *hi = v3(fmax(hi->x, p[0]), fmax(hi->y, p[1]), fmax(hi->z, p[2]));
    }
}

static cJSON *vec3_json(vec3 v)
{
    double a[3] = {v.x, v.y, v.z};
    return cJSON_CreateDoubleArray(a, 3);
}

/* A scene for `plumage render`: the two meshes, a feather material on the
 * vane (with the pigment image, which colours it as in a scene that generates it), a diffuse rachis in the species' rachis colour, a camera looking at the dorsal side from +z and
 * framing the whole feather, and a sky with a sun. */
static cJSON *scene_json(const plm_feather *f, const cJSON *optics, rgb rachis_rgb, const char *texture_file,
                         const char *pigment_file)
{
    vec3 lo = v3(1e30, 1e30, 1e30), hi = v3(-1e30, -1e30, -1e30);
    mesh_bounds(&f->vane, &lo, &hi);
    mesh_bounds(&f->rachis, &lo, &hi);
    vec3 centre = v3_scale(v3_add(lo, hi), 0.5);
    const int width = 384, height = 768;
    const double fov = 30.0;
    /* Fit the taller of the feather's height and its width (scaled to the film's aspect). */
    double half = 0.5 * fmax(hi.y - lo.y, (hi.x - lo.x) * height / width);
    double distance = 1.1 * half / tan(plm_radians(0.5 * fov)) + (hi.z - centre.z);
    cJSON *root = cJSON_CreateObject();
    cJSON *camera = cJSON_AddObjectToObject(root, "camera");
    cJSON_AddItemToObject(camera, "position", vec3_json(v3_add(centre, v3(0, 0, distance))));
    cJSON_AddItemToObject(camera, "look_at", vec3_json(centre));
    cJSON_AddItemToObject(camera, "up", vec3_json(v3(0, 1, 0)));
    cJSON_AddNumberToObject(camera, "fov", fov);
    cJSON *film = cJSON_AddObjectToObject(root, "film");
    cJSON_AddNumberToObject(film, "width", width);
    cJSON_AddNumberToObject(film, "height", height);
    cJSON_AddNumberToObject(film, "spp", 64);
    cJSON *lights = cJSON_AddArrayToObject(root, "lights");
    cJSON *sky = cJSON_CreateObject(), *sun = cJSON_CreateObject();
    cJSON_AddStringToObject(sky, "type", "environment");
    cJSON_AddItemToObject(sky, "radiance", vec3_json(v3(0.5, 0.55, 0.6)));
    cJSON_AddStringToObject(sun, "type", "distant");
    cJSON_AddItemToObject(sun, "direction", vec3_json(v3(0.3, 0.5, 1.0)));
    cJSON_AddItemToObject(sun, "irradiance", vec3_json(v3(3.0, 3.0, 3.0)));
    cJSON_AddItemToArray(lights, sky);
    cJSON_AddItemToArray(lights, sun);
    cJSON *meshes = cJSON_AddObjectToObject(root, "meshes");
    cJSON_AddStringToObject(cJSON_AddObjectToObject(meshes, "vane"), "file", "vane.ply");
    cJSON_AddStringToObject(cJSON_AddObjectToObject(meshes, "rachis"), "file", "rachis.ply");
    cJSON *materials = cJSON_AddObjectToObject(root, "materials");
    /* The species' optics block belongs to the renderer: its fields go into
     * the feather material as they are. */
    cJSON *feather = optics ? cJSON_Duplicate(optics, 1) : cJSON_CreateObject();
    cJSON_DeleteItemFromObjectCaseSensitive(feather, "type");
    cJSON_DeleteItemFromObjectCaseSensitive(feather, "texture");
    cJSON_AddStringToObject(feather, "type", "feather");
    cJSON_AddStringToObject(feather, "texture", texture_file);
    if (pigment_file)
        cJSON_AddStringToObject(feather, "pigment", pigment_file);
    cJSON_AddItemToObject(materials, "feather", feather);
    cJSON *rachis = cJSON_AddObjectToObject(materials, "rachis");
    cJSON_AddStringToObject(rachis, "type", "diffuse");
    cJSON_AddItemToObject(rachis, "reflectance", vec3_json(v3(rachis_rgb.r, rachis_rgb.g, rachis_rgb.b)));
    cJSON *objects = cJSON_AddArrayToObject(root, "objects");
    const char *pairs[2][2] = {{"vane", "feather"}, {"rachis", "rachis"}};
    for (int i = 0; i < 2; ++i) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "mesh", pairs[i][0]);
        cJSON_AddStringToObject(o, "material", pairs[i][1]);
        cJSON_AddItemToArray(objects, o);
    }
    return root;
}

static plm_result write_text(const char *path, const char *text, plm_error *err)
{
    plm_atomic_file af;
    plm_result rc = plm_atomic_open(&af, path, err);
    if (rc != PLM_OK)
        return rc;
    fputs(text, af.fp);
    fputc('\n', af.fp);
    return plm_atomic_commit(&af, err);
}

plm_result plm_feather_write(const plm_feather *f, const cJSON *optics, rgb rachis, const char *dir,
                             const plm_feather_files *files, plm_error *err)
{
    plm_feather_files def = {0};
    if (!files)
        files = &def;
    char path[4096];
    static const char *const names[2][2] = {{"vane.ply", "vane.obj"}, {"rachis.ply", "rachis.obj"}};
    const plm_mesh *meshes[2] = {&f->vane, &f->rachis};
    plm_result rc = plm_make_dirs(dir, err);
    for (int m = 0; m < 2 && rc == PLM_OK; ++m)
        for (int k = 0; k <= files->obj && rc == PLM_OK; ++k) {
            rc = join_path(path, sizeof path, dir, names[m][k], err);
            if (rc == PLM_OK)
                rc = plm_mesh_write(path, meshes[m], err);
        }
    if (rc == PLM_OK)
        rc = plm_feather_write_textures(f, dir, files, err);
    if (rc != PLM_OK || !f->texture.pixels)
        return rc;
    const char *ext = files->no_exr ? "png" : "exr";
    char texture[16], pigment[16];
    snprintf(texture, sizeof texture, "texture.%s", ext);
    snprintf(pigment, sizeof pigment, "pigment.%s", ext);
    cJSON *scene = scene_json(f, optics, rachis, texture, f->pigment.pixels ? pigment : NULL);
    char *text = scene ? cJSON_Print(scene) : NULL;
    cJSON_Delete(scene);
    if (!text)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory writing feather.json");
    rc = join_path(path, sizeof path, dir, "feather.json", err);
    if (rc == PLM_OK)
        rc = write_text(path, text, err);
    cJSON_free(text);
    return rc;
}
