#include <math.h>
#include <stdlib.h>

#include "common/image_io.h"

double plm_srgb_encode(double v)
{
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

plm_result plm_image_write_srgb_png(const char *path, int width, int height, const float *rgb, double exposure,
                                    plm_error *err)
{
    size_t n = (size_t)width * height * 3;
    uint8_t *bytes = malloc(n);
    if (!bytes)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory", path);
    double scale = exp2(exposure);
    for (size_t i = 0; i < n; ++i) {
        double v = isfinite(rgb[i]) ? rgb[i] * scale : 0.0;
        v = v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
        bytes[i] = (uint8_t)lrint(255.0 * plm_srgb_encode(v));
    }
    plm_result rc = plm_image_write(path, width, height, 3, PLM_PIXEL_UINT8, bytes, err);
    free(bytes);
    return rc;
}
