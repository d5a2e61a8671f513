/* Scene files: JSON read and validated field by field into a plain
 * plm_scene (render/scene.h) that the renderer takes as it is. Species named
 * in a scene become generated feathers (scene/feathers.h); docs/scene-format.md
 * documents every field, its range and default.
 *
 * Three entry points read the same format: a file, a text buffer (for
 * fuzzing, or a scene built in memory) and an already parsed JSON tree (for
 * overrides applied before loading). `name` is shown in error messages and
 * relative paths inside the scene resolve against its directory (a name
 * without '/' resolves them against the working directory). On failure the
 * scene is freed and err names the file, the field path and the allowed
 * values. */
#ifndef PLUMAGE_SCENE_SCENE_FILE_H
#define PLUMAGE_SCENE_SCENE_FILE_H

#include <stddef.h>

#include <cjson/cJSON.h>

#include "common/error.h"
#include "common/json.h"
#include "render/scene.h"

plm_result plm_scene_load(const char *path, plm_scene *scene, plm_error *err);
/* The same, with "path.to.field=value" assignments (common/json_set.h)
 * applied to the top file's JSON before it is read. */
plm_result plm_scene_load_with(const char *path, const char *const *sets, int n_sets, plm_scene *scene,
                               plm_error *err);
/* What plm_scene_load_ex does besides loading. */
typedef struct plm_scene_load_options {
    const char *const *sets; /* "path.to.field=value" assignments, as plm_scene_load_with */
    int n_sets;
    /* If not NULL: the resolved scene, one JSON tree that loads alone into the
     * same scene: the top file after its assignments, with every included
     * file merged in, in reading order, and every file path made absolute.
     * The caller deletes it. */
    cJSON **resolved;
    /* If not NULL: every generated feather's files (plm_feather_write: meshes,
     * textures, feather.json) are written into a folder of its own under this
     * one, named after the feather (plm_feather_cache). */
    const char *asset_dir;
} plm_scene_load_options;

plm_result plm_scene_load_ex(const char *path, const plm_scene_load_options *options, plm_scene *scene,
                             plm_error *err);
plm_result plm_scene_load_buffer(const char *text, size_t length, const char *name, plm_scene *scene,
                                 plm_error *err);
plm_result plm_scene_load_json(const cJSON *root, const char *name, plm_scene *scene, plm_error *err);

/* A feather material's optics (its fields other than type and texture; also
 * a species' "optics" block) into m: type feather, parameters allocated.
 * extra lists the keys obj may have beyond the feather block's table
 * (plm_feather_material_param_block): "barb", "barbule", "masking", ...
 * Absent fields take the documented defaults, so an empty or absent block is
 * a valid default feather. */
plm_result plm_feather_optics_read(const plm_json_reader *r, const cJSON *obj, const char *path,
                                   const char *const *extra, plm_material *m);

/* The fiber of a feather's fluff (render/scene.h's fiber material) from a
 * species' optics block obj at path: the barb's fiber made circular (its
 * medulla scaled across with it, so it stays inside), taking the barb's
 * estimator; an optics "fluff" fiber block (docs/fiber.md's fields and
 * pigments) sets any of it. */
plm_result plm_fluff_optics_read(const plm_json_reader *r, const cJSON *obj, const char *path,
                                 const struct plm_feather_params *feather, plm_fiber_material *out);

/* A file path field (required or not; absent -> ""), resolved against the
 * directory of the file r reads. out holds PLM_PATH_MAX characters. */
plm_result plm_scene_read_path(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                               int required, char *out);
/* The same for a string item (an array element); key may be NULL. When r
 * records paths, the item is rewritten with the absolute path. */
plm_result plm_scene_read_path_item(const plm_json_reader *r, const cJSON *item, const char *path, const char *key,
                                    char *out);

#endif
