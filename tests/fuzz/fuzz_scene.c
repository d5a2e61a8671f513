/* Scene files: the JSON reader with everything it reaches (includes, meshes,
 * textures, species named by relative paths land in the harness's directory). */
#include "render/scene.h"
#include "tests/fuzz/fuzz_input.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_input(data, size, "scene.json");
    plm_scene scene;
    plm_error err = {{0}};
    plm_result rc = plm_scene_load(path, &scene, &err);
    fuzz_check_failure(rc, &err);
    if (rc == PLM_OK)
        plm_scene_free(&scene);
    return 0;
}
