/* The scene reader's lowest layer (scene/readers.c): paths and optics, read
 * alike by scene files, their feathers, layouts and birds. */
#ifndef PLUMAGE_SCENE_READERS_H
#define PLUMAGE_SCENE_READERS_H

#include "common/json.h"
#include "render/scene.h"

/* dir(base)/rel unless rel is absolute or base has no directory; out holds PLM_PATH_MAX characters. */
void plm_scene_resolve_path(const char *base, const char *rel, char *out);

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
