/* Scene files: the JSON reader with everything it reaches (includes, meshes,
 * textures and species named by relative paths resolve in the harness's
 * empty directory), read from the memory buffer. */
#include "scene/scene_file.h"
#include "tests/fuzz/fuzz_input.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    plm_scene scene;
    plm_error err = {{0}};
    plm_result rc = plm_scene_load_buffer((const char *)data, size, fuzz_input_path("scene.json"), &scene, &err);
    fuzz_check_failure(rc, &err);
    if (rc == PLM_OK)
        plm_scene_free(&scene);
    return 0;
}
