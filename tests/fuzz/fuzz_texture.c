/* Feather textures as EXR or PNG (FUZZ_FILE_NAME's extension), of any size
 * and channel count: a texture that reads must answer every lookup with a
 * region and a unit direction. */
#include <math.h>

#include "optics/feather_texture.h"
#include "tests/fuzz/fuzz_input.h"

static void check_lookups(const plm_feather_texture *t)
{
    /* Corners, the centre and points outside [0, 1] (uvs are clamped). */
    static const double uv[][2] = {{0, 0}, {1, 1}, {0, 1}, {1, 0}, {0.5, 0.5}, {-3, 0.25}, {0.7, 42}};
    for (size_t i = 0; i < sizeof uv / sizeof uv[0]; ++i) {
        vec2 p = {uv[i][0], uv[i][1]};
        plm_region r = plm_feather_texture_region(t, p);
        vec2 d = plm_feather_texture_direction(t, p);
        if (r > PLM_REGION_VANE || !(fabs(d.x * d.x + d.y * d.y - 1.0) < 1e-6))
            abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_input(data, size, FUZZ_FILE_NAME);
    plm_feather_texture tex = {0};
    plm_error err = {{0}};
    plm_result rc = plm_feather_texture_read(path, &tex, &err);
    fuzz_check_failure(rc, &err);
    if (rc == PLM_OK) {
        check_lookups(&tex);
        plm_feather_texture_free(&tex);
    }
    return 0;
}
