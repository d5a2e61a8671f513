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

#endif
