// OpenImageIO adapter behind common/image_io.h, built as the module that
// image_module.c opens on first use (see common/image_module.h).
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <unistd.h>

extern "C" {
#include "common/fileio.h"
#include "common/image_module.h"
}

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

static plm_result oiio_write(const char *path, int width, int height, int channels, plm_pixel_type type,
                             const void *data, plm_error *err)
{
    if (width <= 0 || height <= 0 || channels <= 0)
        return plm_fail(err, PLM_ERR_INVALID, "%s: invalid image size %dx%dx%d", path, width, height, channels);
    char temp[4096];
    plm_temp_path_for(path, temp, sizeof temp);
    auto out = ImageOutput::create(path);
    if (!out)
        return plm_fail(err, PLM_ERR_IO, "%s: no image writer for this file type (use .exr, .png, .hdr, .tif)", path);
    ImageSpec spec(width, height, channels, oiio_type(type));
    // OpenImageIO stamps EXR headers with the current time unless told not to;
    // an empty DateTime keeps the same pixels byte-identical across runs.
    spec.attribute("DateTime", "");
    if (!out->open(temp, spec)) {
        std::string msg = out->geterror();
        return plm_fail(err, PLM_ERR_IO, "%s: cannot write: %s", path, msg.c_str());
    }
    bool ok = out->write_image(oiio_type(type), data);
    ok = out->close() && ok;
    if (!ok) {
        std::string msg = out->geterror();
        std::remove(temp);
        return plm_fail(err, PLM_ERR_IO, "%s: write failed: %s", path, msg.c_str());
    }
    if (std::rename(temp, path) != 0) {
        std::remove(temp);
        return plm_fail(err, PLM_ERR_IO, "%s: cannot rename into place", path);
    }
    return PLM_OK;
}

static plm_result oiio_read(const char *path, int *width, int *height, int *channels, float **pixels, plm_error *err)
{
    *pixels = nullptr;
    auto in = ImageInput::open(path);
    if (!in) {
        std::string msg = OIIO::geterror();
        return plm_fail(err, PLM_ERR_IO, "%s: cannot read image: %s", path, msg.c_str());
    }
    const ImageSpec &spec = in->spec();
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

static plm_result oiio_draw_text(plm_image *img, int x, int y, int size_px, const char *text, const float color[3],
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

extern "C" __attribute__((visibility("default"))) const plm_image_module plm_image_module_table = {
    sizeof(plm_image_module), oiio_write, oiio_read, oiio_draw_text};
