#include "render/scene_build.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "common/rng.h"

plm_material plm_diffuse_material(const char *name, rgb reflectance, double transmission)
{
    plm_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    m.type = PLM_MATERIAL_DIFFUSE;
    m.reflectance = reflectance;
    m.transmission = transmission;
    return m;
}

plm_light plm_constant_sky(rgb radiance)
{
    plm_light l = plm_light_default(PLM_LIGHT_CONSTANT_ENV);
    l.radiance = radiance;
    return l;
}

plm_light plm_quad_light(vec3 corner, vec3 edge_u, vec3 edge_v, rgb radiance)
{
    plm_light l = plm_light_default(PLM_LIGHT_QUAD);
    l.corner = corner;
    l.edge_u = edge_u;
    l.edge_v = edge_v;
    l.radiance = radiance;
    return l;
}

int plm_scene_add_object(plm_scene *scene, int mesh, int material, plm_xform xform)
{
    plm_instance in = {.mesh = mesh, .material = material, .xform = xform, .tint = rgb_gray(1.0)};
    return plm_scene_add_instance(scene, &in);
}

plm_xform plm_xform_floor(double y)
{
    plm_xform r = plm_xform_rotate(v3(1, 0, 0), -PLM_PI / 2), t = plm_xform_translate(v3(0, y, 0));
    return plm_xform_compose(&t, &r);
}

int plm_scene_add_ground(plm_scene *scene, double size, rgb reflectance, plm_error *err)
{
    plm_mesh quad;
    if (plm_shape_quad(size, size, 0.0, 1, &quad, err) != PLM_OK)
        return -1;
    int mesh = plm_scene_add_mesh(scene, "ground", &quad);
    plm_material grey = plm_diffuse_material("ground", reflectance, 0.0);
    int material = mesh < 0 ? -1 : plm_scene_add_material(scene, &grey);
    int i = material < 0 ? -1 : plm_scene_add_object(scene, mesh, material, plm_xform_floor(0.0));
    if (i < 0)
        plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory building the ground");
    return i;
}

int plm_scene_add_feather_tiles(plm_scene *scene, const plm_tile_feather *feather, int count, double spacing,
                                uint64_t seed)
{
    plm_rng rng;
    plm_rng_seed(&rng, seed, 1);
    int side = (int)ceil(sqrt((double)count));
    plm_xform scale = plm_xform_scale(v3(feather->scale, feather->scale, feather->scale));
    for (int i = 0; i < count; ++i) {
        double gx = (i % side + 0.5 - 0.5 * side) * spacing, gz = (i / side + 0.5 - 0.5 * side) * spacing;
        plm_xform lay = plm_xform_rotate(v3(1, 0, 0), -PLM_PI / 2 + 0.25 + 0.1 * plm_rng_uniform(&rng));
        plm_xform turn = plm_xform_rotate(v3(0, 1, 0), PLM_PI + 0.4 * (plm_rng_uniform(&rng) - 0.5));
        plm_xform at = plm_xform_translate(v3(gx, 0.05 + 0.1 * plm_rng_uniform(&rng), gz));
        plm_xform x = plm_xform_compose(&turn, &lay);
        x = plm_xform_compose(&at, &x);
        x = plm_xform_compose(&x, &scale);
        double t = 0.7 + 0.3 * plm_rng_uniform(&rng);
        for (int k = 0; k < feather->count; ++k) {
            plm_instance in = {.mesh = feather->mesh[k], .material = feather->material[k], .xform = x,
                               .tint = rgb_make(t, t * 0.9, 0.8)};
            if (plm_scene_add_instance(scene, &in) < 0)
                return 0;
        }
    }
    return 1;
}
