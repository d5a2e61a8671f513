/* The image size limit (common/image_io.h), shared by plumage_common and
 * the OpenImageIO module, which checks a file's header before allocating. */
#include "common/image_io.h"

plm_result plm_image_check_size(const char *what, long long width, long long height, long long channels,
                                plm_error *err)
{
    if (width < 1 || height < 1 || channels < 1)
        return plm_fail(err, PLM_ERR_INVALID, "%s: %lldx%lld pixels with %lld channels is an empty image", what, width,
                        height, channels);
    if (width > PLM_IMAGE_SIDE_MAX || height > PLM_IMAGE_SIDE_MAX || channels > PLM_IMAGE_CHANNELS_MAX ||
        width * height > PLM_IMAGE_VALUES_MAX / channels)
        return plm_fail(err, PLM_ERR_INVALID,
                        "%s: %lldx%lld pixels with %lld channels is over the image limit (at most %d pixels a side, "
                        "%d channels, %lld values in all)",
                        what, width, height, channels, PLM_IMAGE_SIDE_MAX, PLM_IMAGE_CHANNELS_MAX,
                        PLM_IMAGE_VALUES_MAX);
    return PLM_OK;
}
