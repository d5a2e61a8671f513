/* Species presets: read, validated, then a small feather generated from
 * them as a scene does (its optics block included), since a preset that
 * validates must also generate without harm. */
#include "scene/feathers.h"
#include "tests/fuzz/fuzz_input.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_input(data, size, "species.json");
    plm_scene scene;
    plm_scene_init(&scene);
    plm_feather_cache cache = {0};
    /* Level 1 and a 32x32 texture keep an iteration in milliseconds. */
    plm_feather_request request = {.species = path, .level = 1, .texture_size = 32};
    plm_feather_parts parts;
    plm_error err = {{0}};
    plm_result rc = plm_feather_cache_get(&cache, &scene, "f", &request, &parts, &err);
    fuzz_check_failure(rc, &err);
    plm_feather_cache_free(&cache);
    plm_scene_free(&scene);
    return 0;
}
