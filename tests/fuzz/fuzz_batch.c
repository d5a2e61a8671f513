/* Batch manifests (batch/manifest.h) from the memory buffer. Scenes named
 * "scene.json" resolve to an empty scene file made beside the manifest's
 * name, so that jobs and sweeps are parsed through to the end. */
#include "batch/manifest.h"
#include "tests/fuzz/fuzz_input.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char manifest[600];
    if (!manifest[0]) {
        fuzz_write_input((const uint8_t *)"{}", 2, "scene.json");
        snprintf(manifest, sizeof manifest, "%s/batch.json", fuzz_dir);
    }
    plm_manifest m;
    plm_error err = {{0}};
    plm_result rc = plm_manifest_parse((const char *)data, size, manifest, &m, &err);
    fuzz_check_failure(rc, &err);
    if (rc == PLM_OK)
        plm_manifest_free(&m);
    return 0;
}
