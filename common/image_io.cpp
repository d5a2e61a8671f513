// OpenImageIO adapter behind common/image_io.h, built as the module that
// image_module.c opens on first use (see common/image_module.h).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <unistd.h>
#include <vector>

extern "C" {
#include "common/fileio.h"
#include "common/image_module.h"
}
#include "common/adapter_guard.hpp"

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

static TypeDesc oiio_type(plm_pixel_type t)
{
    switch (t) {
    case PLM_PIXEL_UINT8: return TypeDesc::UINT8;
    case PLM_PIXEL_UINT16: return TypeDesc::UINT16;
    default: return TypeDesc::FLOAT;
    }
}

static plm_result image_write(const char *path, int width, int height, int channels, plm_pixel_type type,
                              const void *data, plm_error *err)
{
    if (width <= 0 || height <= 0 || channels <= 0)
        return plm_fail(err, PLM_ERR_INVALID, "%s: invalid image size %dx%dx%d", path, width, height, channels);
    auto out = ImageOutput::create(path);
    if (!out)
        return plm_fail(err, PLM_ERR_IO, "%s: no image writer for this file type (use .exr, .png, .hdr, .tif)", path);
    ImageSpec spec(width, height, channels, oiio_type(type));
    // OpenImageIO stamps EXR headers with the current time unless told not to;
    // an empty DateTime keeps the same pixels byte-identical across runs.
    spec.attribute("DateTime", "");
    // Every image plumage writes is data (a fourth channel is no alpha to
    // premultiply by, e.g. the feather texture's barb coordinate): write and
    // read it as it is, never associated (docs/generating.md).
    spec.attribute("oiio:UnassociatedAlpha", 1);
    // OpenImageIO does not notice a failed write (a full disk), so formats that
    // can are encoded in memory and written by plm_write_file, which does.
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    bool in_memory = out->supports("ioproxy") && out->set_ioproxy(&proxy);
    char temp[4096];
    plm_output_target(path, temp, sizeof temp);
    if (!out->open(in_memory ? path : temp, spec)) {
        std::string msg = out->geterror();
        if (!in_memory)
            plm_output_discard(path, temp);
        return plm_fail(err, PLM_ERR_IO, "%s: cannot write: %s", path, msg.c_str());
    }
    bool ok = out->write_image(oiio_type(type), data);
    ok = out->close() && ok;
    if (!ok) {
        std::string msg = out->geterror();
        if (!in_memory)
            plm_output_discard(path, temp);
        return plm_fail(err, PLM_ERR_IO, "%s: write failed: %s", path, msg.c_str());
    }
    return in_memory ? plm_write_file(path, bytes.data(), bytes.size(), err) : plm_output_commit(path, temp, err);
}

static plm_result encode_png(int width, int height, int channels, plm_pixel_type type, const void *data,
                             unsigned char **bytes, size_t *size, plm_error *err)
{
    if (width <= 0 || height <= 0 || channels <= 0 || channels > 4 || type == PLM_PIXEL_FLOAT)
        return plm_fail(err, PLM_ERR_INVALID, "PNG in memory: invalid image %dx%dx%d of %s", width, height, channels,
                        type == PLM_PIXEL_FLOAT ? "floats (PNG holds 8 or 16 bits)" : "integers");
    auto out = ImageOutput::create("png");
    std::vector<unsigned char> buf;
    OIIO::Filesystem::IOVecOutput proxy(buf);
    if (!out || !out->set_ioproxy(&proxy))
        return plm_fail(err, PLM_ERR_INTERNAL, "PNG in memory: OpenImageIO's PNG writer cannot write to memory");
    ImageSpec spec(width, height, channels, oiio_type(type));
    spec.attribute("oiio:UnassociatedAlpha", 1); // as image_write: the values as they are
    bool ok = out->open("memory.png", spec) && out->write_image(oiio_type(type), data);
    ok = out->close() && ok;
    if (!ok) {
        std::string msg = out->geterror();
        return plm_fail(err, PLM_ERR_INTERNAL, "PNG in memory: %s", msg.c_str());
    }
    *bytes = (unsigned char *)std::malloc(buf.size() ? buf.size() : 1);
    if (!*bytes)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "PNG in memory: out of memory");
    std::memcpy(*bytes, buf.data(), buf.size());
    *size = buf.size();
    return PLM_OK;
}

static plm_result image_read(const char *path, int *width, int *height, int *channels, float **pixels,
                             plm_error *err)
{
    *pixels = nullptr;
    if (plm_result rc = plm_image_check_png_chunks(path, err); rc != PLM_OK)
        return rc;
    if (plm_result rc = plm_image_check_exr_header(path, err); rc != PLM_OK)
        return rc;
    // Only the reader of the format the extension names: a file is never
    // offered to every other format's decoder (docs/robustness.md).
    auto in = ImageInput::create(path);
    ImageSpec spec, config;
    config.attribute("oiio:UnassociatedAlpha", 1); // as written: see image_write
    if (!in || !in->open(path, spec, config)) {
        std::string msg = in ? in->geterror() : OIIO::geterror();
        return plm_fail(err, PLM_ERR_IO, "%s: cannot read image: %s", path, msg.c_str());
    }
    plm_result rc = plm_image_check_size(path, spec.width, spec.height, spec.nchannels, err);
    if (rc == PLM_OK && spec.depth > 1)
        rc = plm_fail(err, PLM_ERR_INVALID, "%s: a volume (%d deep) is not an image", path, spec.depth);
    if (rc != PLM_OK)
        return rc;
    size_t count = (size_t)spec.width * spec.height * spec.nchannels;
    float *buf = (float *)std::malloc(count * sizeof(float));
    if (!buf)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory", path);
    if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, buf)) {
        std::string msg = in->geterror();
        std::free(buf);
        return plm_fail(err, PLM_ERR_PARSE, "%s: cannot decode image: %s", path, msg.c_str());
    }
    *width = spec.width;
    *height = spec.height;
    *channels = spec.nchannels;
    *pixels = buf;
    return PLM_OK;
}

static plm_result draw_text(plm_image *img, int x, int y, int size_px, const char *text, const float color[3],
                            plm_error *err)
{
    if (!img || !img->pixels || img->width <= 0 || img->height <= 0 || (img->channels != 3 && img->channels != 4))
        return plm_fail(err, PLM_ERR_INVALID, "draw text: the image must be float with 3 or 4 channels");
    if (size_px <= 0 || !text || !color)
        return plm_fail(err, PLM_ERR_INVALID, "draw text: size_px must be > 0 (got %d) and text and colour given",
                        size_px);
    // OpenImageIO would substitute another font for a missing one; say so instead.
    if (access(PLM_IMAGE_FONT, R_OK) != 0)
        return plm_fail(err, PLM_ERR_IO, "draw text: font %s not found (install fonts-dejavu-core)", PLM_IMAGE_FONT);
    ImageSpec spec(img->width, img->height, img->channels, TypeDesc::FLOAT);
    OIIO::ImageBuf buf(spec, img->pixels); // wraps the caller's pixels, no copy
    float rgba[4] = {color[0], color[1], color[2], 1.0f};
    if (!OIIO::ImageBufAlgo::render_text(buf, x, y, text, size_px, PLM_IMAGE_FONT,
                                         OIIO::cspan<float>(rgba, img->channels))) {
        std::string msg = buf.geterror();
        return plm_fail(err, PLM_ERR_INTERNAL, "draw text: %s", msg.c_str());
    }
    return PLM_OK;
}

// The module's entry points let no exception out (common/adapter_guard.hpp).
static plm_result oiio_write(const char *path, int width, int height, int channels, plm_pixel_type type,
                             const void *data, plm_error *err)
{
    return plm_guard(err, path, [&] { return image_write(path, width, height, channels, type, data, err); });
}

static plm_result oiio_read(const char *path, int *width, int *height, int *channels, float **pixels, plm_error *err)
{
    *pixels = nullptr;
    return plm_guard(err, path, [&] { return image_read(path, width, height, channels, pixels, err); });
}

static plm_result oiio_encode_png(int width, int height, int channels, plm_pixel_type type, const void *data,
                                  unsigned char **bytes, size_t *size, plm_error *err)
{
    return plm_guard(err, "PNG in memory", [&] { return encode_png(width, height, channels, type, data, bytes, size, err); });
}

static plm_result oiio_draw_text(plm_image *img, int x, int y, int size_px, const char *text, const float color[3],
                                 plm_error *err)
{
    return plm_guard(err, "draw text", [&] { return draw_text(img, x, y, size_px, text, color, err); });
}

extern "C" __attribute__((visibility("default"))) const plm_image_module plm_image_module_table = {
    sizeof(plm_image_module), oiio_write, oiio_read, oiio_encode_png, oiio_draw_text};
