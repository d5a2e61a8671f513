/* The image size limit (common/image_io.h), shared by plumage_common and
 * the OpenImageIO module, which checks a file's header before allocating. */
#include "common/image_io.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

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

static uint32_t big_endian32(const unsigned char *b)
{
    return (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | (uint32_t)b[3];
}

plm_result plm_image_check_png_chunks(const char *path, plm_error *err)
{
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    FILE *f = fopen(path, "rb");
    if (!f)
        return PLM_OK; /* the decoder reports the missing file */
    unsigned char head[8];
    long long size = -1;
    if (fread(head, 1, 8, f) == 8 && !memcmp(head, signature, 8) && fseek(f, 0, SEEK_END) == 0)
        size = ftell(f);
    plm_result rc = PLM_OK;
    /* Each chunk: 4-byte length, 4-byte type, the data, a 4-byte CRC. */
    for (long long at = 8; size > 0 && at + 8 <= size && rc == PLM_OK;) {
        if (fseek(f, (long)at, SEEK_SET) != 0 || fread(head, 1, 8, f) != 8)
            break;
        long long length = big_endian32(head);
        if (length > size - at - 12)
            rc = plm_fail(err, PLM_ERR_PARSE,
                          "%s: corrupt PNG: the chunk at byte %lld declares %lld bytes, the file has %lld left", path,
                          at, length, size - at - 12 > 0 ? size - at - 12 : 0);
        else if (!memcmp(head + 4, "IEND", 4))
            break;
        at += 12 + length;
    }
    fclose(f);
    return rc;
}
