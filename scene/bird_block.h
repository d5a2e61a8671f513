/* Bird objects in scene files: {"bird": FILE, "transform": ..., "feathers",
 * "level", "feather_level", "texture_size"} places the bird preset FILE
 * (generate/bird.h): its skin, bill and eyes, and each feather tract laid by
 * the pelt layout on its part of the skin. docs/birds.md documents it. */
#ifndef PLUMAGE_SCENE_BIRD_BLOCK_H
#define PLUMAGE_SCENE_BIRD_BLOCK_H

#include <cjson/cJSON.h>

#include "common/json.h"
#include "render/scene.h"
#include "scene/feathers.h"

/* Reads the bird object at path and adds it to scene, placed by xform.
 * *ordinal counts the scene's layouts (each tract is one) and is advanced. */
plm_result plm_bird_block_read(const plm_json_reader *r, const cJSON *obj, const char *path, const plm_xform *xform,
                               plm_scene *scene, plm_feather_cache *cache, int *ordinal);

#endif
