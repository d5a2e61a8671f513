/* Species presets: read, validated, then a small feather generated from
 * them as a scene does (its optics block included), since a preset that
 * validates must also generate without harm. */
#include "render/scene.h"
#include "tests/fuzz/fuzz_input.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_input(data, size, "species.json");
    plm_scene scene;
    plm_scene_init(&scene);
    plm_error err = {{0}};
    /* Level 1 and a 32x32 texture keep an iteration in milliseconds. */
    plm_result rc = plm_scene_add_species_feather(&scene, "f", path, 1, 32, &err);
    fuzz_check_failure(rc, &err);
    plm_scene_free(&scene);
    return 0;
}
