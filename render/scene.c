/* Scene storage, builders and the built-in shapes. */
#include "render/scene.h"
#include "optics/feather_bsdf.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BIG 1e9 /* bound for coordinates and distances */

static const plm_param camera_params[] = {
    {"position", PLM_PARAM_VEC3, offsetof(plm_camera_desc, position), -BIG, BIG, "scene units", "the eye", 0},
    {"look_at", PLM_PARAM_VEC3, offsetof(plm_camera_desc, look_at), -BIG, BIG, "scene units",
     "a point on the view axis; must differ from position", 0},
    {"up", PLM_PARAM_VEC3, offsetof(plm_camera_desc, up), -BIG, BIG, "", "up direction, not along the view axis", 0},
    {"fov", PLM_PARAM_NUMBER, offsetof(plm_camera_desc, fov), 0.01, 179.0, "degrees", "vertical field of view", 0},
    {"aperture", PLM_PARAM_NUMBER, offsetof(plm_camera_desc, aperture), 0.0, BIG, "scene units",
     "thin-lens radius; 0 = pinhole", 0},
    {"focus_distance", PLM_PARAM_NUMBER, offsetof(plm_camera_desc, focus_distance), 0.0, BIG, "scene units",
     "distance to the plane in focus; 0 = the distance to look_at", 0},
};
const plm_param_block plm_camera_param_block = {
    "camera", "the camera; without a camera block the scene's bounds are framed from +z", camera_params,
    PLM_PARAM_COUNT(camera_params)};

static const plm_param film_params[] = {
    {"width", PLM_PARAM_INT, offsetof(plm_film_desc, width), 1, 16384, "pixels", "image width", 0},
    {"height", PLM_PARAM_INT, offsetof(plm_film_desc, height), 1, 16384, "pixels", "image height", 0},
    {"spp", PLM_PARAM_INT, offsetof(plm_film_desc, spp), 1, 1 << 24, "", "samples per pixel", 0},
    {"seed", PLM_PARAM_SEED, offsetof(plm_film_desc, seed), 0, 2147483647, "", "random seed", 0},
    {"max_depth", PLM_PARAM_INT, offsetof(plm_film_desc, max_depth), 0, 1024, "",
     "most scattering events per path", 0},
    {"exposure", PLM_PARAM_NUMBER, offsetof(plm_film_desc, exposure), -30.0, 30.0, "stops",
     "PNG only: scale by 2^exposure before the view transform", 0},
    {"white_balance", PLM_PARAM_NUMBER, offsetof(plm_film_desc, white_balance), 1500.0, 25000.0, "kelvin",
     "PNG only: light of a blackbody this hot shows as white; 6504 changes nothing, lower is bluer", 0},
    {"far_field", PLM_PARAM_BOOL, offsetof(plm_film_desc, far_field), 0, 1, "",
     "shade feathers with the far-field model only, even where a pixel resolves barbs (docs/nearfield.md)", 0},
    {"filter_radius", PLM_PARAM_NUMBER, offsetof(plm_film_desc, filter_radius), 0.0, 4.0, "pixels",
     "0: a pixel averages its own square (a box); > 0: a tent reaching this far, which keeps fine regular "
     "detail such as barbs from beating into moire (1 is a good choice; docs/rendering.md)", 0},
    {"fiber_table_mib", PLM_PARAM_INT, offsetof(plm_film_desc, fiber_table_mib), PLM_FIBER_TABLE_MIB_MIN,
     PLM_FIBER_TABLE_MIB_MAX, "MiB",
     "memory of each fiber table (tabulated BCSDF): more is more accurate for elliptical fibers (docs/fiber.md)", 0},
};
const plm_param_block plm_film_param_block = {
    "film",
    "the image; also \"view\": the PNG's view transform, \"filmic\" (default) or \"standard\" (a clamp; "
    "docs/rendering.md), and \"exr\" and \"png\": output files (working directory)",
    film_params,
    PLM_PARAM_COUNT(film_params)};

static const plm_param feather_material_params[] = {
    {"rachis_reflectance", PLM_PARAM_RGB, offsetof(plm_material, reflectance), 0.0, 1.0, "",
     "diffuse albedo of the rachis (and of rachis texels)", 0},
    {"band_tint", PLM_PARAM_RGB, offsetof(plm_material, band_tint), 0.0, 1.0, "",
     "colour factor inside the species' pigment bands", 0},
    {"tip_tint", PLM_PARAM_RGB, offsetof(plm_material, tip_tint), 0.0, 1.0, "",
     "colour factor at the tip, fading over the species' pigment tip_length", 0},
    {"base_tint", PLM_PARAM_RGB, offsetof(plm_material, base_tint), 0.0, 1.0, "",
     "colour factor over the downy base, fading over the species' pigment base_length (a grey base)", 0},
};
const plm_param_block plm_feather_material_param_block = {
    "feather", "a feather material (a species' optics block); also barb, barbule (fiber) and masking blocks",
    feather_material_params, PLM_PARAM_COUNT(feather_material_params)};

void plm_feather_material_default(plm_material *m)
{
    m->reflectance = rgb_make(0.8, 0.75, 0.65);
    m->band_tint = rgb_make(0.3, 0.28, 0.26);
    m->tip_tint = rgb_gray(1.0);
    m->base_tint = rgb_gray(1.0);
}

void plm_scene_init(plm_scene *scene)
{
    memset(scene, 0, sizeof *scene);
    scene->camera.position = v3(0.0, 0.0, 5.0);
    scene->camera.look_at = v3(0.0, 0.0, 0.0);
    scene->camera.up = v3(0.0, 1.0, 0.0);
    scene->camera.fov = 40.0;
    plm_film_desc *f = &scene->film;
    f->width = 512;
    f->height = 512;
    f->spp = 64;
    f->max_depth = 16;
    f->seed = 1;
    f->white_balance = 6504.0;
    f->fiber_table_mib = PLM_FIBER_TABLE_MIB_DEFAULT;
}

void plm_scene_free(plm_scene *scene)
{
    for (int i = 0; i < scene->light_count; ++i)
        free(scene->lights[i].image.pixels);
    for (int i = 0; i < scene->mesh_count; ++i) {
        plm_mesh_free(&scene->meshes[i].mesh);
        plm_curves_free(&scene->meshes[i].curves);
    }
    for (int i = 0; i < scene->material_count; ++i) {
        if (!scene->materials[i].shares_fiber)
            free(scene->materials[i].fiber);
        plm_feather_texture_free(&scene->materials[i].texture);
        if (!scene->materials[i].shares_feather)
            free(scene->materials[i].feather);
        free(scene->materials[i].pigment.pixels);
    }
    free(scene->lights);
    free(scene->meshes);
    free(scene->materials);
    free(scene->instances);
    plm_scene_init(scene);
}

/* Makes room for one more element in a growable array. */
static int grow(void **items, int *count, int *capacity, size_t size)
{
    if (*count == *capacity) {
        int cap = *capacity ? 2 * *capacity : 8;
        void *p = realloc(*items, (size_t)cap * size);
        if (!p)
            return -1;
        *items = p;
        *capacity = cap;
    }
    return (*count)++;
}

int plm_scene_add_mesh(plm_scene *scene, const char *name, plm_mesh *mesh)
{
    int i = grow((void **)&scene->meshes, &scene->mesh_count, &scene->mesh_capacity, sizeof *scene->meshes);
    if (i < 0)
        return -1;
    snprintf(scene->meshes[i].name, PLM_NAME_MAX, "%s", name);
    scene->meshes[i].mesh = *mesh;
    memset(&scene->meshes[i].curves, 0, sizeof scene->meshes[i].curves);
    memset(mesh, 0, sizeof *mesh);
    return i;
}

int plm_scene_add_curves(plm_scene *scene, const char *name, plm_curves *curves)
{
    plm_mesh none = {0};
    int i = plm_scene_add_mesh(scene, name, &none);
    if (i >= 0) {
        scene->meshes[i].curves = *curves;
        memset(curves, 0, sizeof *curves);
    }
    return i;
}

int plm_scene_add_material(plm_scene *scene, const plm_material *material)
{
    int i = grow((void **)&scene->materials, &scene->material_count, &scene->material_capacity,
                 sizeof *scene->materials);
    if (i >= 0)
        scene->materials[i] = *material;
    return i;
}

int plm_scene_add_light(plm_scene *scene, const plm_light *light)
{
    int i = grow((void **)&scene->lights, &scene->light_count, &scene->light_capacity, sizeof *scene->lights);
    if (i >= 0)
        scene->lights[i] = *light;
    return i;
}

int plm_scene_add_instance(plm_scene *scene, const plm_instance *instance)
{
    int i = grow((void **)&scene->instances, &scene->instance_count, &scene->instance_capacity,
                 sizeof *scene->instances);
    if (i >= 0)
        scene->instances[i] = *instance;
    return i;
}

const char *const plm_part_names[PLM_PART_COUNT + 1] = {"other", "vane", "rachis", "fluff", "body", NULL};

int plm_scene_new_feather(plm_scene *scene) { return ++scene->feather_count; }

int plm_scene_find_mesh(const plm_scene *scene, const char *name)
{
    for (int i = 0; i < scene->mesh_count; ++i)
        if (strcmp(scene->meshes[i].name, name) == 0)
            return i;
    return -1;
}

int plm_scene_find_material(const plm_scene *scene, const char *name)
{
    for (int i = 0; i < scene->material_count; ++i)
        if (strcmp(scene->materials[i].name, name) == 0)
            return i;
    return -1;
}

/* A (nu+1) x (nv+1) vertex grid with all arrays allocated and triangle indices filled. */
static plm_result grid_mesh(int nu, int nv, plm_mesh *m, plm_error *err)
{
    memset(m, 0, sizeof *m);
    m->vertex_count = (nu + 1) * (nv + 1);
    m->triangle_count = 2 * nu * nv;
    m->positions = malloc(sizeof(float) * 3 * (size_t)m->vertex_count);
    m->normals = malloc(sizeof(float) * 3 * (size_t)m->vertex_count);
    m->uvs = malloc(sizeof(float) * 2 * (size_t)m->vertex_count);
    m->indices = malloc(sizeof(uint32_t) * 3 * (size_t)m->triangle_count);
    if (!m->positions || !m->normals || !m->uvs || !m->indices) {
        plm_mesh_free(m);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a %dx%d shape", nu, nv);
    }
    uint32_t *t = m->indices;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            uint32_t a = (uint32_t)(j * (nu + 1) + i), b = a + 1, c = a + (uint32_t)(nu + 1), d = c + 1;
            *t++ = a, *t++ = b, *t++ = d;
            *t++ = a, *t++ = d, *t++ = c;
        }
    return PLM_OK;
}

static void set_vertex(plm_mesh *m, int k, vec3 p, vec3 n, double u, double v)
{
    m->positions[3 * k] = (float)p.x, m->positions[3 * k + 1] = (float)p.y, m->positions[3 * k + 2] = (float)p.z;
    m->normals[3 * k] = (float)n.x, m->normals[3 * k + 1] = (float)n.y, m->normals[3 * k + 2] = (float)n.z;
    m->uvs[2 * k] = (float)u, m->uvs[2 * k + 1] = (float)v;
}

plm_result plm_shape_quad(double width, double height, double curl, int segments, plm_mesh *out, plm_error *err)
{
    int nu = curl != 0.0 ? segments : 1;
    plm_result rc = grid_mesh(nu, 1, out, err);
    if (rc != PLM_OK)
        return rc;
    for (int j = 0; j <= 1; ++j)
        for (int i = 0; i <= nu; ++i) {
            double u = (double)i / nu, s = (u - 0.5) * width; /* arc length from the centre line */
            vec3 p = v3(s, (j - 0.5) * height, 0.0), n = v3(0.0, 0.0, 1.0);
            if (curl != 0.0) { /* wrap onto a cylinder of radius 1/curl whose axis is parallel to y */
                double a = s * curl;
                p = v3(sin(a) / curl, p.y, (cos(a) - 1.0) / curl);
                n = v3(sin(a), 0.0, cos(a));
            }
            set_vertex(out, j * (nu + 1) + i, p, n, u, j);
        }
    return PLM_OK;
}

plm_result plm_shape_sphere(double radius, int rings, plm_mesh *out, plm_error *err)
{
    int nu = 2 * rings, nv = rings;
    plm_result rc = grid_mesh(nu, nv, out, err);
    if (rc != PLM_OK)
        return rc;
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            double u = (double)i / nu, v = (double)j / nv;
            double theta = PLM_PI * (1.0 - v), phi = PLM_TWO_PI * u;
            vec3 n = v3(sin(theta) * sin(phi), cos(theta), sin(theta) * cos(phi));
            set_vertex(out, j * (nu + 1) + i, v3_scale(n, radius), n, u, v);
        }
    return PLM_OK;
}
