/* Feathers generated from species presets for a scene, each distinct one
 * once. A request names a species file, the subdivision level, the texture
 * size and a variant (a seed: different variants are different feathers of
 * the same species); the cache adds the feather's meshes and materials to the
 * scene the first time and hands back the same indices every later time, so
 * a scene's memory grows with the number of distinct feathers, not with the
 * number of instances. */
#ifndef PLUMAGE_SCENE_FEATHERS_H
#define PLUMAGE_SCENE_FEATHERS_H

#include <stdint.h>

#include <cjson/cJSON.h>

#include "common/error.h"
#include "generate/species.h"
#include "render/scene.h"

/* What placing one feather adds: the vane with the feather material, the
 * rachis tube with a diffuse material in the rachis colour and, where the
 * species has any, the fluff's curves with a fiber material. */
#define PLM_FEATHER_PARTS_MAX 3
typedef struct plm_feather_parts {
    int count; /* 2 or 3 for a generated feather; 1 for a plain mesh */
    int mesh[PLM_FEATHER_PARTS_MAX], material[PLM_FEATHER_PARTS_MAX];
    plm_part part[PLM_FEATHER_PARTS_MAX]; /* for the ID pass: vane, rachis, fluff, or the plain mesh's part */
    double length; /* the feather's extent along its rachis (+y), mm */
} plm_feather_parts;

/* The feather is the species' own, or its seeded variant (variant, seed) as
 * plm_species_variant (generate/layout.h) makes it, or, when shape is given,
 * that shape and pigment (a layout's prototype; then (variant, seed) must
 * identify it among the requests of one cache). */
typedef struct plm_feather_request {
    const char *species; /* a species preset file, or the file holding inline_species */
    int level;           /* subdivision level 1..6; 0 = the default */
    int texture_size;    /* 16..8192; 0 = 1024 */
    int variant;         /* 0 = the species as written */
    uint64_t seed;
    const plm_shape *shape;     /* NULL, or the shape to generate */
    const plm_pigment *pigment; /* with shape */
    const cJSON *inline_species; /* NULL, or the species object itself (a scene's inline species) */
    const char *inline_path;     /* with inline_species: its field path in `species`, e.g. "feathers.f.species" */
} plm_feather_request;

typedef struct plm_feather_cache_entry plm_feather_cache_entry;

typedef struct plm_feather_cache {
    plm_feather_cache_entry *entries;
    int count, capacity;
    /* NULL, or where each feather's files go as it is generated
     * (plm_feather_write): into asset_dir/<NN>-<name>, NN its place in the
     * cache and the name's characters outside [A-Za-z0-9._-] replaced by '_'. */
    const char *asset_dir;
} plm_feather_cache;

/* The parts of the requested feather, generated into scene on the first
 * request. `name` names the new meshes and materials (NAME.vane,
 * NAME.rachis, NAME.fluff, NAME, NAME.rachis, NAME.fluff; at most 100 characters) and is unused on a
 * cache hit. Errors from the species name its file. */
plm_result plm_feather_cache_get(plm_feather_cache *cache, plm_scene *scene, const char *name,
                                 const plm_feather_request *request, plm_feather_parts *out, plm_error *err);

void plm_feather_cache_free(plm_feather_cache *cache);

/* A species file's optics block as every scene reads it (checked against the
 * feather, fiber and masking tables; an absent block is every default): a
 * copy of the block for feather.json's feather material (the caller deletes
 * it), and the rachis colour it gives the rachis mesh (rachis_reflectance or
 * its default). `plumage generate` writes feather.json from these, so a
 * feather's rachis is the same colour however it reaches the renderer. */
plm_result plm_species_optics_load(const char *species, cJSON **optics, rgb *rachis, plm_error *err);

#endif
