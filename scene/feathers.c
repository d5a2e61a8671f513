#include "scene/feathers.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/json.h"
#include "generate/layout.h"
#include "optics/feather_bsdf.h"
#include "scene/readers.h"
#include "texture/feather.h"
#include "texture/texture.h"

#define FEATHER_NAME_MAX 100 /* leaves room for ".rachis" in a PLM_NAME_MAX name */

struct plm_feather_cache_entry {
    char species[PLM_PATH_MAX];
    char inline_path[PLM_SPECIES_PATH_MAX]; /* "" for a species file */
    int level, texture_size, variant, given_shape;
    uint64_t seed;
    plm_feather_parts parts;
    cJSON *optics; /* the species' optics block, to share parameters between equal ones */
};

static void normalise(plm_feather_request *q)
{
    if (q->level <= 0)
        q->level = PLM_FEATHER_DEFAULT_LEVEL;
    if (q->texture_size <= 0)
        q->texture_size = PLM_TEXTURE_DEFAULT_SIZE;
}

static const plm_feather_cache_entry *find(const plm_feather_cache *c, const plm_feather_request *q)
{
    for (int i = 0; i < c->count; ++i) {
        const plm_feather_cache_entry *e = &c->entries[i];
        if (e->level == q->level && e->texture_size == q->texture_size && e->variant == q->variant &&
            e->seed == q->seed && e->given_shape == (q->shape != NULL) && strcmp(e->species, q->species) == 0 &&
            strcmp(e->inline_path, q->inline_species ? q->inline_path : "") == 0)
            return e;
    }
    return NULL;
}

/* A species' optics block (root's; absent: an empty one, which means every
 * default) into the feather material and the fluff's fiber, and a copy of
 * the block. `at` is the species' field path in `file` ("" for a species file). */
static plm_result read_optics(const char *file, const char *at, cJSON *root, plm_material *feather,
                              plm_fiber_material *fluff, cJSON **optics_out, plm_error *err)
{
    static const char *const optics_keys[] = {"barb", "barbule", "masking", "fluff", NULL};
    const cJSON *optics = cJSON_GetObjectItemCaseSensitive(root, "optics");
    if (!optics)
        optics = cJSON_AddObjectToObject(root, "optics");
    plm_json_reader r = {file, err, 0};
    char path[PLM_SPECIES_PATH_MAX];
    snprintf(path, sizeof path, "%s%soptics", at, at[0] ? "." : "");
    plm_result rc = optics ? plm_feather_optics_read(&r, optics, path, optics_keys, feather)
                           : plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory");
    if (rc == PLM_OK && (rc = plm_fluff_optics_read(&r, optics, path, feather->feather, fluff)) != PLM_OK) {
        free(feather->feather);
        feather->feather = NULL;
    }
    if (rc == PLM_OK && !(*optics_out = cJSON_Duplicate(optics, 1))) {
        free(feather->feather);
        feather->feather = NULL;
        rc = plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory");
    }
    return rc;
}

/* The species parsed twice over: its shape and pigment by generate/, its
 * optics block (which generate/ does not keep) into the feather material.
 * A species file, or one inline in another file (then messages give its path there). */
static plm_result read_species(const plm_feather_request *q, plm_species *species, plm_material *feather,
                               plm_fiber_material *fluff, cJSON **optics_out, plm_error *err)
{
    cJSON *root = NULL;
    const char *at = q->inline_species ? q->inline_path : "";
    plm_result rc = q->inline_species ? ((root = cJSON_Duplicate(q->inline_species, 1))
                                             ? PLM_OK
                                             : plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory"))
                                      : plm_json_load(q->species, &root, err);
    if (rc != PLM_OK)
        return rc;
    rc = plm_species_parse_at(root, q->species, at, species, err);
    if (rc == PLM_OK && (rc = read_optics(q->species, at, root, feather, fluff, optics_out, err)) != PLM_OK)
        plm_species_free(species);
    cJSON_Delete(root);
    return rc;
}

plm_result plm_species_optics_load(const char *species, cJSON **optics, rgb *rachis, plm_error *err)
{
    cJSON *root = NULL;
    plm_material feather;
    plm_fiber_material fluff;
    memset(&feather, 0, sizeof feather);
    *optics = NULL;
    plm_result rc = plm_json_load(species, &root, err);
    if (rc == PLM_OK && (rc = read_optics(species, "", root, &feather, &fluff, optics, err)) == PLM_OK) {
        *rachis = feather.reflectance;
        free(feather.feather);
    }
    cJSON_Delete(root);
    return rc;
}

static double extent_y(const plm_mesh *m)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int v = 0; v < m->vertex_count; ++v)
        lo = fmin(lo, m->positions[3 * v + 1]), hi = fmax(hi, m->positions[3 * v + 1]);
    return hi > lo ? hi - lo : 0.0;
}

/* An earlier feather's parts read from the same optics block, or NULL. */
static const plm_feather_parts *same_optics(const plm_feather_cache *c, const cJSON *optics)
{
    for (int i = 0; i < c->count; ++i)
        if (cJSON_Compare(c->entries[i].optics, optics, 1))
            return &c->entries[i].parts;
    return NULL;
}

/* The fluff's curves and fiber material (its parameters shared with an
 * earlier feather of the same optics), if the feather has any. Takes the
 * curves; frees the parameters it does not hand to the scene. */
static plm_result add_fluff(plm_scene *scene, const char *name, plm_curves *curves,
                            const plm_fiber_material *fiber, plm_fiber_material *shared, plm_feather_parts *out,
                            plm_error *err)
{
    if (curves->curve_count == 0)
        return PLM_OK;
    plm_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%.100s.fluff", name);
    m.type = PLM_MATERIAL_FIBER;
    m.shares_fiber = shared != NULL;
    m.fiber = shared ? shared : malloc(sizeof *m.fiber);
    if (!m.fiber)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory");
    if (!shared)
        *m.fiber = *fiber;
    int k = out->count;
    out->part[k] = PLM_PART_FLUFF;
    if ((out->mesh[k] = plm_scene_add_curves(scene, m.name, curves)) < 0 ||
        (out->material[k] = plm_scene_add_material(scene, &m)) < 0) {
        if (!shared)
            free(m.fiber);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory");
    }
    out->count++;
    return PLM_OK;
}

/* The feather's files in its own folder of the cache's asset folder. */
static plm_result write_assets(const plm_feather_cache *cache, const char *name, const plm_feather *f,
                               const cJSON *optics, rgb rachis, plm_error *err)
{
    char dir[PLM_PATH_MAX];
    int n = snprintf(dir, sizeof dir, "%s/%02d-%s", cache->asset_dir, cache->count, name);
    if (n >= (int)sizeof dir)
        return plm_fail(err, PLM_ERR_INVALID, "%s: the asset folder's path is too long", cache->asset_dir);
    for (char *c = dir + n - strlen(name); *c; ++c)
        if (!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-", *c))
            *c = '_';
    return plm_feather_write(f, optics, rachis, dir, NULL, err);
}

/* Generates the feather and adds its two meshes and two materials. */
static plm_result generate(const plm_feather_cache *cache, plm_scene *scene, const char *name,
                           const plm_feather_request *q, plm_feather_parts *out, cJSON **optics, plm_error *err)
{
    char vane_name[PLM_NAME_MAX], rachis_name[PLM_NAME_MAX];
    if (strlen(name) > FEATHER_NAME_MAX)
        return plm_fail(err, PLM_ERR_INVALID, "feather name \"%.40s...\": names are limited to %d characters", name,
                        FEATHER_NAME_MAX);
    snprintf(vane_name, sizeof vane_name, "%.100s.vane", name);
    snprintf(rachis_name, sizeof rachis_name, "%.100s.rachis", name);
    if (plm_scene_find_mesh(scene, vane_name) >= 0 || plm_scene_find_material(scene, name) >= 0)
        return plm_fail(err, PLM_ERR_INVALID, "feather \"%s\" is already defined (names must be unique)", name);
    plm_species species;
    plm_material feather, rachis;
    plm_fiber_material fluff;
    memset(&feather, 0, sizeof feather);
    memset(&rachis, 0, sizeof rachis);
    plm_result rc = read_species(q, &species, &feather, &fluff, optics, err);
    if (rc != PLM_OK)
        return rc;
    /* Variants (and species) that differ in shape and pigment but not in
     * optics share one set of feather and fluff parameters, and so their fiber tables. */
    const plm_feather_parts *shared = same_optics(cache, *optics);
    plm_fiber_material *shared_fluff = NULL;
    if (shared) {
        free(feather.feather);
        feather.feather = scene->materials[shared->material[0]].feather;
        feather.shares_feather = 1;
        for (int k = 0; k < shared->count; ++k)
            if (shared->part[k] == PLM_PART_FLUFF)
                shared_fluff = scene->materials[shared->material[k]].fiber;
    }
    /* A variant is another individual of the species: its own random choices. */
    plm_shape shape;
    plm_pigment pigment;
    plm_species_variant(&species, q->variant, q->seed, &shape, &pigment);
    species.shape = q->shape ? *q->shape : shape;
    species.pigment = q->shape ? *q->pigment : pigment;
    snprintf(feather.name, sizeof feather.name, "%.100s", name);
    snprintf(rachis.name, sizeof rachis.name, "%.100s.rachis", name);
    rachis.reflectance = feather.reflectance;
    plm_feather f;
    memset(&f, 0, sizeof f);
    /* The pigment image only when the species has pigment variation to show. */
    const plm_pigment *pg = &species.pigment;
    int has_pigment = pg->band_count > 0 || pg->tip_length > 0.0 || pg->barb_jitter > 0.0 || pg->base_length > 0.0 ||
                      species.shape.plumulaceous > 0.0;
    plm_feather_options options = {q->level, q->texture_size, q->texture_size, 0, 0, !has_pigment};
    rc = plm_feather_generate(&species, &options, &f, err);
    if (rc == PLM_OK && cache->asset_dir)
        rc = write_assets(cache, name, &f, *optics, rachis.reflectance, err);
    if (rc == PLM_OK) {
        rc = plm_feather_texture_from_pixels(f.texture.width, f.texture.height, f.texture.pixels, &feather.texture,
                                             err);
        f.texture.pixels = NULL; /* owned by the material now */
        if (rc == PLM_OK) { /* the barb coordinate too (docs/nearfield.md) */
            feather.texture.barb = f.barb.pixels;
            f.barb.pixels = NULL;
        }
        feather.pigment = f.pigment;
        memset(&f.pigment, 0, sizeof f.pigment);
    }
    /* The scene takes each part as it is added (meshes are zeroed in f); the
     * feather material goes last so that it is ours to free until then. */
    int taken = 0;
    if (rc == PLM_OK) {
        out->count = 2;
        out->part[0] = PLM_PART_VANE;
        out->part[1] = PLM_PART_RACHIS;
        out->length = extent_y(&f.vane);
        taken = (out->mesh[0] = plm_scene_add_mesh(scene, vane_name, &f.vane)) >= 0 &&
                (out->mesh[1] = plm_scene_add_mesh(scene, rachis_name, &f.rachis)) >= 0 &&
                (out->material[1] = plm_scene_add_material(scene, &rachis)) >= 0 &&
                (rc = add_fluff(scene, name, &f.fluff, &fluff, shared_fluff, out, err)) == PLM_OK &&
                (out->material[0] = plm_scene_add_material(scene, &feather)) >= 0;
        if (!taken && rc == PLM_OK)
            rc = plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory");
    }
    if (!taken) {
        plm_feather_texture_free(&feather.texture);
        if (!feather.shares_feather)
            free(feather.feather);
        free(feather.pigment.pixels);
    }
    plm_feather_free(&f);
    plm_species_free(&species);
    return rc;
}

plm_result plm_feather_cache_get(plm_feather_cache *cache, plm_scene *scene, const char *name,
                                 const plm_feather_request *request, plm_feather_parts *out, plm_error *err)
{
    plm_feather_request q = *request;
    normalise(&q);
    if (strlen(q.species) >= PLM_PATH_MAX)
        return plm_fail(err, PLM_ERR_INVALID, "species path is longer than %d characters", PLM_PATH_MAX - 1);
    if (q.inline_species && strlen(q.inline_path) >= PLM_SPECIES_PATH_MAX)
        return plm_fail(err, PLM_ERR_INVALID, "field path %.40s... is longer than %d characters", q.inline_path,
                        PLM_SPECIES_PATH_MAX - 1);
    const plm_feather_cache_entry *hit = find(cache, &q);
    if (hit) {
        *out = hit->parts;
        return PLM_OK;
    }
    if (cache->count == cache->capacity) {
        int cap = cache->capacity ? 2 * cache->capacity : 8;
        plm_feather_cache_entry *e = realloc(cache->entries, (size_t)cap * sizeof *e);
        if (!e)
            return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory");
        cache->entries = e;
        cache->capacity = cap;
    }
    memset(out, 0, sizeof *out);
    cJSON *optics = NULL;
    plm_result rc = generate(cache, scene, name, &q, out, &optics, err);
    if (rc != PLM_OK) {
        cJSON_Delete(optics);
        return rc;
    }
    plm_feather_cache_entry *e = &cache->entries[cache->count++];
    snprintf(e->species, sizeof e->species, "%s", q.species);
    snprintf(e->inline_path, sizeof e->inline_path, "%s", q.inline_species ? q.inline_path : "");
    e->level = q.level;
    e->texture_size = q.texture_size;
    e->variant = q.variant;
    e->seed = q.seed;
    e->given_shape = q.shape != NULL;
    e->optics = optics;
    e->parts = *out;
    return PLM_OK;
}

void plm_feather_cache_free(plm_feather_cache *cache)
{
    for (int i = 0; i < cache->count; ++i)
        cJSON_Delete(cache->entries[i].optics);
    free(cache->entries);
    memset(cache, 0, sizeof *cache);
}
