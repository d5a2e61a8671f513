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
    int ended = 0;
    long long at = 8;
    /* Each chunk: 4-byte length, 4-byte type, the data, a 4-byte CRC. */
    while (size > 0 && at + 8 <= size && rc == PLM_OK && !ended) {
        if (fseek(f, (long)at, SEEK_SET) != 0 || fread(head, 1, 8, f) != 8)
            break;
        long long length = big_endian32(head);
        if (length > size - at - 12)
            rc = plm_fail(err, PLM_ERR_PARSE,
                          "%s: corrupt PNG: the chunk at byte %lld declares %lld bytes, the file has %lld left", path,
                          at, length, size - at - 12 > 0 ? size - at - 12 : 0);
        ended = !memcmp(head + 4, "IEND", 4);
        at += 12 + length;
    }
    fclose(f);
    /* A PNG that stops before its IEND chunk makes libpng read past the end,
     * and OpenImageIO's read callback leaks its error text when it does. */
    if (rc == PLM_OK && size > 0 && !ended)
        rc = plm_fail(err, PLM_ERR_PARSE, "%s: truncated PNG: the file ends at byte %lld, before its IEND chunk", path,
                      size);
    return rc;
}

static uint32_t little_endian32(const unsigned char *b)
{
    return (uint32_t)b[3] << 24 | (uint32_t)b[2] << 16 | (uint32_t)b[1] << 8 | (uint32_t)b[0];
}

/* A name as OpenEXR reads it from buf[*at] (n bytes there): up to max + 1
 * characters, fewer when a NUL ends it (the NUL is consumed). A name that
 * does not end within max + 1 characters runs on into the next field, as it
 * does in OpenEXR (found by fuzzing). Returns 0 if buf ran out. */
static int exr_name(const unsigned char *buf, size_t n, size_t *at, size_t max, char *name)
{
    size_t k = 0;
    for (;;) {
        if (*at >= n)
            return 0;
        unsigned char c = buf[(*at)++];
        if (!c)
            break;
        name[k++] = (char)c;
        if (k == max + 1)
            break;
    }
    name[k] = '\0';
    return 1;
}

plm_result plm_image_check_exr_header(const char *path, plm_error *err)
{
    static const unsigned char magic[4] = {0x76, 0x2f, 0x31, 0x01};
    FILE *f = fopen(path, "rb");
    if (!f)
        return PLM_OK; /* the decoder reports the missing file */
    unsigned char buf[2 * 256 + 8];
    long long size = -1;
    uint32_t flags = 0;
    if (fread(buf, 1, 8, f) == 8 && !memcmp(buf, magic, 4) && fseek(f, 0, SEEK_END) == 0) {
        size = ftell(f);
        flags = little_endian32(buf + 4);
    }
    size_t max = flags & 0x400 ? 255 : 31;    /* long names allowed */
    int multipart = (flags & 0x1000) != 0, in_header = 0;
    plm_result rc = PLM_OK;
    /* Attributes: name, type, a 4-byte size, the value; an empty name ends a
     * header (a multi-part file's headers end with an empty one). */
    for (long long at = 8; size > 0 && at < size && rc == PLM_OK;) {
        size_t n, pos = 0;
        char name[257], type[257];
        if (fseek(f, (long)at, SEEK_SET) != 0 || (n = fread(buf, 1, sizeof buf, f)) == 0)
            break;
        if (!exr_name(buf, n, &pos, max, name))
            break; /* cut short: the decoder says so */
        if (!name[0]) {
            if (!multipart || !in_header)
                break;
            in_header = 0;
            at += 1;
            continue;
        }
        if (!exr_name(buf, n, &pos, max, type) || pos + 4 > n)
            break;
        long long length = (int32_t)little_endian32(buf + pos), left = size - at - (long long)pos - 4;
        if (length < 0 || length > left)
            rc = plm_fail(err, PLM_ERR_PARSE,
                          "%s: corrupt EXR: the attribute \"%s\" at byte %lld declares %lld bytes, the file has %lld "
                          "left", path, name, at, length, left);
        in_header = 1;
        at += (long long)pos + 4 + length;
    }
    fclose(f);
    return rc;
}
