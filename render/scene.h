/* A scene as plain data: camera, film, lights, meshes, materials and
 * instances: all the renderer needs, nothing about where it came from. Scene
 * files are read into it by scene/scene_file.h (docs/scene-format.md
 * documents every field and default); code builds it with the
 * plm_scene_add_* functions. The scene owns everything it points to. */
#ifndef PLUMAGE_RENDER_SCENE_H
#define PLUMAGE_RENDER_SCENE_H

#include <stdint.h>

#include "common/curves.h"
#include "common/error.h"
#include "common/fileio.h"
#include "common/image_io.h"
#include "common/mesh.h"
#include "common/params.h"
#include "common/vec.h"
#include "optics/feather_texture.h"
#include "optics/fiber_params.h"
#include "render/transform.h"

#define PLM_NAME_MAX 128

typedef struct plm_camera_desc {
    vec3 position, look_at, up;
    double fov;            /* vertical field of view, degrees */
    double aperture;       /* thin-lens radius in scene units; 0 = pinhole */
    double focus_distance; /* 0 = the distance from position to look_at */
    int given;             /* 0: frame the scene's bounds automatically */
} plm_camera_desc;

typedef struct plm_film_desc {
    int width, height, spp, max_depth;
    uint64_t seed;
    double exposure;     /* PNG only: scale by 2^exposure before the view transform */
    int view;            /* PNG only: a plm_view (render/film.h) */
    double white_balance; /* PNG only: kelvin shown as white (render/film.h) */
    int far_field;       /* 1: feathers only in the far field, even where barbs are resolved (docs/nearfield.md) */
    double filter_radius; /* pixels: 0 each pixel averages its own area (a box), > 0 a tent this wide each way */
    int fiber_table_mib; /* memory of each tabulated fiber BCSDF's table (docs/fiber.md) */
    char exr[PLM_PATH_MAX]; /* "" = not written */
    char png[PLM_PATH_MAX];
} plm_film_desc;

typedef enum plm_light_type {
    PLM_LIGHT_CONSTANT_ENV, /* uniform radiance from every direction */
    PLM_LIGHT_ENV_MAP,      /* lat-long image, its top row toward `up` */
    PLM_LIGHT_DISTANT,      /* a sun: irradiance from one direction */
    PLM_LIGHT_SPHERE,       /* uniformly emitting sphere */
    PLM_LIGHT_QUAD,         /* uniformly emitting parallelogram */
    PLM_LIGHT_SKY           /* analytic clear sky and sun disk (render/sky.h) */
} plm_light_type;

/* A clear sky and its sun (Preetham, Shirley and Smits 1999; render/sky.h). */
typedef struct plm_sky_params {
    double sun_elevation; /* radians above the horizon */
    double sun_azimuth;   /* radians from north (-z when up is +y) toward east (+x) */
    double turbidity;     /* haze: 2 very clear, 3 clear, 6 hazy */
    double sun_size;      /* angular diameter of the sun's disk, radians; its irradiance does not change with it */
    int sun;              /* 0: the sky without the sun's disk */
    rgb ground_albedo;    /* below the horizon: a diffuse ground lit by this sky and sun */
    double latitude, longitude; /* radians, north and east positive: with a scene's "time", where the sun is seen */
} plm_sky_params;

typedef struct plm_light {
    plm_light_type type;
    rgb radiance;          /* constant env, sphere, quad; env map: colour filter over the image */
    double intensity;      /* environment and sky: multiplies their radiance */
    int visible;           /* environment and sky: camera rays see them (0: they see black there) */
    vec3 up;               /* environment and sky: unit zenith (the map's top row) */
    double rotation;       /* env map: radians about up */
    int ground;            /* environment and sky: a shadow catcher at ground_height (docs/rendering.md) */
    double ground_height;  /* along up */
    plm_image image;       /* env map (RGB) */
    plm_sky_params sky;    /* sky */
    rgb irradiance;        /* distant: on a surface facing the light */
    vec3 direction;        /* distant: unit vector toward the light */
    vec3 center;           /* sphere */
    double radius;
    vec3 corner, edge_u, edge_v; /* quad: emits toward edge_u x edge_v (both sides if two_sided) */
    int two_sided;
} plm_light;

/* A light of the type with every documented default (docs/scene-format.md). */
plm_light plm_light_default(plm_light_type type);

typedef enum plm_material_type {
    PLM_MATERIAL_DIFFUSE = 0,
    PLM_MATERIAL_FEATHER = 1,
    PLM_MATERIAL_COAT = 2, /* a glossy dielectric coat over a diffuse base (optics/coat.h) */
    PLM_MATERIAL_FIBER = 3 /* curves: a fiber BCSDF across each curve (a feather's fluff) */
} plm_material_type;

struct plm_feather_params; /* optics/feather_bsdf.h */

/* A fiber material's fiber (its table is the render world's: render/material.h). */
typedef struct plm_fiber_material {
    plm_fiber_params fiber;
    int stochastic; /* 1: the stochastic estimator instead of the table (docs/fiber.md) */
} plm_fiber_material;

typedef struct plm_material {
    char name[PLM_NAME_MAX];
    plm_material_type type;
    rgb reflectance;     /* diffuse albedo; for a feather, the rachis colour */
    double transmission; /* diffuse: fraction of light passing straight through (a perforated sheet) */
    double roughness;    /* coat: GGX alpha of the coat, reflectance its base's albedo */
    double ior;          /* coat: the coat's index of refraction */
    plm_feather_texture texture;             /* feather only */
    struct plm_feather_params *feather;      /* feather only, malloc'd */
    int shares_feather; /* feather belongs to an earlier material: feathers of one species share their
                           optics and so their fiber tables (tens of MB each; the render world's) */
    plm_fiber_material *fiber; /* fiber only, malloc'd */
    int shares_fiber;          /* fiber belongs to an earlier material, as shares_feather */
    /* Feather only: the generator's pigment image (channels in
     * common/feather_texture_contract.h; no pixels = none) and the colours
     * it mixes in: a texel's scattered colour is multiplied by
     * mix(1, band_tint, bands) * mix(1, tip_tint, tip) * mix(1, base_tint, base) * (1 - barb). */
    plm_image pigment;
    rgb band_tint, tip_tint, base_tint;
} plm_material;

/* A triangle mesh, or curves (then mesh is empty): a feather's fluff. */
typedef struct plm_scene_mesh {
    char name[PLM_NAME_MAX];
    plm_mesh mesh;
    plm_curves curves;
} plm_scene_mesh;

/* What part of a bird an instance is, for the ID pass (render/visibility.h):
 * a feather's vane, rachis or fluffy base, the body (bare skin) or anything else. */
typedef enum plm_part {
    PLM_PART_OTHER = 0,
    PLM_PART_VANE,
    PLM_PART_RACHIS,
    PLM_PART_FLUFF,
    PLM_PART_BODY,
    PLM_PART_COUNT
} plm_part;

/* "other", "vane", "rachis", "fluff", "body": in files and reports. */
extern const char *const plm_part_names[PLM_PART_COUNT + 1]; /* NULL-terminated */

typedef struct plm_instance {
    int mesh, material; /* indices into the scene's arrays */
    plm_xform xform;    /* object to world */
    rgb tint;           /* multiplies the material's scattered colour */
    int feather;        /* the placed feather it is part of, 1..scene feather_count; 0: none */
    plm_part part;
} plm_instance;

typedef struct plm_scene {
    plm_camera_desc camera;
    plm_film_desc film;
    plm_light *lights;
    int light_count, light_capacity;
    plm_scene_mesh *meshes;
    int mesh_count, mesh_capacity;
    plm_material *materials;
    int material_count, material_capacity;
    plm_instance *instances;
    int instance_count, instance_capacity;
    int feather_count; /* feathers placed: instances' feather ids run from 1 to it (plm_scene_new_feather) */
} plm_scene;

/* The camera, film and feather-material blocks' fields and ranges
 * (common/params.h); the feather block's offsets are into plm_material. */
extern const plm_param_block plm_camera_param_block;
extern const plm_param_block plm_film_param_block;
extern const plm_param_block plm_feather_material_param_block;
/* The lights' blocks by their "type" in a scene file; offsets into plm_light.
 * "environment" serves the constant sky and the env map (its "map" field is
 * read by the scene reader). */
extern const plm_param_block plm_environment_light_param_block;
extern const plm_param_block plm_sky_light_param_block;
extern const plm_param_block plm_distant_light_param_block;
extern const plm_param_block plm_sphere_light_param_block;
extern const plm_param_block plm_quad_light_param_block;

/* The feather material's defaults for the fields of that block. */
void plm_feather_material_default(plm_material *m);

/* Empty scene with the documented camera and film defaults. */
void plm_scene_init(plm_scene *scene);
void plm_scene_free(plm_scene *scene);

/* Builders; each returns the new element's index, or -1 when out of memory.
 * add_mesh takes ownership of mesh's arrays; add_material of the texture
 * and feather parameters. */
int plm_scene_add_mesh(plm_scene *scene, const char *name, plm_mesh *mesh);
/* Curves as a mesh of the scene (instanced like one); takes ownership of the arrays. */
int plm_scene_add_curves(plm_scene *scene, const char *name, plm_curves *curves);
int plm_scene_add_material(plm_scene *scene, const plm_material *material);
int plm_scene_add_light(plm_scene *scene, const plm_light *light);
int plm_scene_add_instance(plm_scene *scene, const plm_instance *instance);
/* A new feather's id (1, 2, ...) for the instances that make it up. */
int plm_scene_new_feather(plm_scene *scene);
int plm_scene_find_mesh(const plm_scene *scene, const char *name);
int plm_scene_find_material(const plm_scene *scene, const char *name);

/* Built-in shapes. A quad of size (w, h) in the xy plane centred at the origin,
 * normal +z, u along +x and v along +y; `curl` bends it into a cylinder about
 * the y axis with that curvature (1/radius, 0 = flat), keeping its width. */
plm_result plm_shape_quad(double width, double height, double curl, int segments, plm_mesh *out, plm_error *err);
/* A UV sphere centred at the origin; v runs from the south pole (0) to the north pole (1, +y). */
plm_result plm_shape_sphere(double radius, int rings, plm_mesh *out, plm_error *err);

#endif
