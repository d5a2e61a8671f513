/* Layout blocks in scene files: an object {"layout": {...}, "transform": ...}
 * places a whole plumage (generate/layout.h) with feathers generated once per
 * prototype. docs/scene-format.md documents the fields; the tables below are
 * what the reader, `plumage params` and the docs read. */
#ifndef PLUMAGE_SCENE_LAYOUT_BLOCK_H
#define PLUMAGE_SCENE_LAYOUT_BLOCK_H

#include <cjson/cJSON.h>

#include "common/json.h"
#include "common/params.h"
#include "generate/layout.h"
#include "render/scene.h"
#include "scene/feathers.h"

extern const plm_param_block plm_pelt_param_block;      /* plm_pelt_params */
extern const plm_param_block plm_ball_param_block;      /* plm_ball_params */
extern const plm_param_block plm_wing_param_block;      /* plm_wing_params */
extern const plm_param_block plm_variation_param_block; /* plm_layout_variation */

/* Reads the layout object at path, runs the layout and adds its feathers to
 * scene, each instance placed by xform after the layout's own matrix.
 * ordinal tells the scene's layouts apart (their prototypes are not shared). */
plm_result plm_layout_block_read(const plm_json_reader *r, const cJSON *obj, const char *path, const plm_xform *xform,
                                 plm_scene *scene, plm_feather_cache *cache, int ordinal);

/* Generates each prototype of a layout once (prototype k of species i from
 * species_files[i], named "layout<ordinal>.<k>") and adds every instance to
 * scene, placed by xform after the layout's own matrix. */
plm_result plm_layout_block_place(const plm_json_reader *r, const char *path, const plm_layout *layout,
                                  const char *const *species_files, int level, int texture_size, uint64_t seed,
                                  int ordinal, const plm_xform *xform, plm_scene *scene, plm_feather_cache *cache);

#endif
