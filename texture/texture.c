#include "texture/texture.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/feather_texture_contract.h"
#include "common/fileio.h"
#include "common/rng.h"

/* The generator's flat regions are the contract's region codes. */
_Static_assert(PLM_FLAT_BACKGROUND == (int)PLM_REGION_BACKGROUND && PLM_FLAT_RACHIS == (int)PLM_REGION_RACHIS &&
                   PLM_FLAT_VANE == (int)PLM_REGION_VANE,
               "generate/outline.h regions must match common/feather_texture_contract.h");

static double smoothstep(double e0, double e1, double x)
{
    double t = plm_clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

/* 1 over the first `width` of each band period, 0 elsewhere, with soft edges. */
static double band_value(double phase, double width)
{
    const double soft = 0.03; /* a few texels of anti-aliasing at typical sizes */
    phase -= floor(phase);
    return smoothstep(-soft, soft, phase) * (1.0 - smoothstep(width - soft, width + soft, phase)) +
           smoothstep(1.0 - soft, 1.0 + soft, phase);
}

/* The last barb's variation value: neighbouring texels mostly share a barb. */
typedef struct barb_cache {
    int64_t barb;
    int side;
    float value;
} barb_cache;

/* A uniform draw in [0, 1) per (seed, index, side). */
static double draw(uint64_t seed, int64_t index, int side)
{
    return (double)(plm_hash64(seed, (uint64_t)index, (uint64_t)side) >> 11) * (1.0 / 9007199254740992.0);
}

/* A barb's variation in [0, 1]: half its own draw, half a value that wanders
 * smoothly across the barbs (draws every `clump` barbs, joined by a
 * smoothstep), so that neighbouring barbs come in lighter and darker groups
 * as real barbs do, rather than as per-barb grain. */
static double barb_variation(const plm_pigment *pg, int64_t barb, int side)
{
    double clump = fmax(pg->barb_clump, 1.0);
    if (clump <= 1.0)
        return draw(pg->seed, barb, side);
    double x = (double)barb / clump, k = floor(x), f = x - k;
    int64_t knot = (int64_t)k;
    double a = draw(pg->seed ^ 0xc1u, knot, side), b = draw(pg->seed ^ 0xc1u, knot + 1, side);
    return 0.5 * draw(pg->seed, barb, side) + 0.5 * (a + (b - a) * f * f * (3.0 - 2.0 * f));
}

static void pigment_texel(const plm_outline *o, const plm_pigment *pg, const plm_flat_sample *s, int side,
                          barb_cache *cache, float *out)
{
    out[PLM_PIGMENT_BANDS] = out[PLM_PIGMENT_TIP] = out[PLM_PIGMENT_BARB] = out[PLM_PIGMENT_BASE] = 0.0f;
    if (s->region != PLM_FLAT_VANE)
        return;
    double t_origin = (s->barb_origin - o->vane_base) / o->vane_length;
    if (pg->band_count > 0)
        out[PLM_PIGMENT_BANDS] = (float)band_value(t_origin * pg->band_count, pg->band_width);
    if (pg->tip_length > 0.0)
        out[PLM_PIGMENT_TIP] = (float)smoothstep(1.0 - pg->tip_length, 1.0, t_origin);
    /* The downy base's colour over the barbs leaving the rachis there, fading
     * along the barbs' origins (so the boundary follows the barbs) beyond it. */
    double down = o->shape.plumulaceous;
    out[PLM_PIGMENT_BASE] = (float)(t_origin <= down ? 1.0
                                    : pg->base_length > 0.0 ? 1.0 - smoothstep(down, down + pg->base_length, t_origin)
                                                            : 0.0);
    /* One value per barb: barbs are barb_density per cm along the rachis. */
    int64_t barb = (int64_t)floor((s->barb_origin - o->vane_base) * o->shape.barb_density / 10.0);
    if (barb != cache->barb || side != cache->side) {
        cache->barb = barb;
        cache->side = side;
        cache->value = (float)(pg->barb_jitter * barb_variation(pg, barb, side));
    }
    out[PLM_PIGMENT_BARB] = cache->value;
}

static plm_result alloc_image(plm_image *img, int width, int height, int channels, plm_error *err)
{
    img->width = width;
    img->height = height;
    img->channels = channels;
    img->pixels = malloc(sizeof(float) * (size_t)channels * (size_t)width * (size_t)height);
    if (!img->pixels)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a %dx%d texture", width, height);
    return PLM_OK;
}

plm_result plm_texture_author(const plm_outline *o, const plm_pigment *pg, int width, int height,
                              plm_image *feather, plm_image *barb, plm_image *pigment, plm_error *err)
{
    memset(feather, 0, sizeof *feather);
    memset(barb, 0, sizeof *barb);
    if (pigment)
        memset(pigment, 0, sizeof *pigment);
    if (width < 8 || height < 8 || width > 16384 || height > 16384)
        return plm_fail(err, PLM_ERR_INVALID, "texture size %dx%d is out of range [8, 16384]", width, height);
    plm_result rc = alloc_image(feather, width, height, 3, err);
    if (rc == PLM_OK)
        rc = alloc_image(barb, width, height, 1, err);
    if (rc == PLM_OK && pigment)
        rc = alloc_image(pigment, width, height, PLM_PIGMENT_CHANNELS, err);
    if (rc != PLM_OK) {
        plm_texture_image_free(feather);
        plm_texture_image_free(barb);
        return rc;
    }
    /* psi in mm times barbs per mm along the rachis: one period per barb. */
    double barbs_per_mm = o->shape.barb_density / 10.0;
    /* A flat direction (dx, dy) in mm becomes (dx / 2U, dy / Lv) in uv units. */
    double su = 1.0 / (2.0 * o->half_extent), sv = 1.0 / o->vane_length;
    barb_cache cache = {INT64_MIN, -1, 0.0f};
    for (int j = 0; j < height; ++j) {
        double v = 1.0 - (j + 0.5) / height;
        plm_outline_row row;
        plm_outline_row_at(o, plm_outline_flat(o, 0.5, v).y, &row);
        for (int i = 0; i < width; ++i) {
            vec2 p = plm_outline_flat(o, (i + 0.5) / width, v);
            plm_flat_sample s = plm_outline_sample_row(o, &row, p.x);
            /* Single precision: the texel stores floats anyway. */
            float dx = (float)(s.barb.x * su), dy = (float)(s.barb.y * sv);
            float inv = 1.0f / sqrtf(dx * dx + dy * dy);
            vec2 d = v2(dx * inv, dy * inv);
            if (!isfinite(d.x) || !isfinite(d.y)) {
                plm_texture_image_free(feather);
                plm_texture_image_free(barb);
                if (pigment)
                    plm_texture_image_free(pigment);
                return plm_fail(err, PLM_ERR_INTERNAL, "texture: non-finite barb direction at texel (%d, %d)", i,
                                j);
            }
            float *px = feather->pixels + 3 * ((size_t)j * width + i);
            px[PLM_FTEX_COS] = plm_ftex_encode_component(d.x);
            px[PLM_FTEX_SIN] = plm_ftex_encode_component(d.y);
            px[PLM_FTEX_REGION] = plm_ftex_encode_region((plm_region)s.region);
            barb->pixels[(size_t)j * width + i] = plm_ftex_encode_barb((s.barb_origin - o->vane_base) * barbs_per_mm);
            if (pigment)
                pigment_texel(o, pg, &s, p.x >= 0.0, &cache, pigment->pixels + PLM_PIGMENT_CHANNELS * ((size_t)j * width + i));
        }
    }
    return PLM_OK;
}

plm_result plm_texture_write(const char *path, const plm_image *img, plm_error *err)
{
    char ext[16];
    plm_path_extension(path, ext, sizeof ext);
    if (strcmp(ext, "exr") == 0)
        return plm_image_write(path, img->width, img->height, img->channels, PLM_PIXEL_FLOAT, img->pixels, err);
    if (strcmp(ext, "png") != 0)
        return plm_fail(err, PLM_ERR_INVALID, "%s: textures are written as .exr or .png", path);
    size_t n = (size_t)img->width * img->height * img->channels;
    uint16_t *words = malloc(n * sizeof *words);
    if (!words)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory", path);
    for (size_t i = 0; i < n; ++i)
        words[i] = (uint16_t)lrint(65535.0 * plm_clamp(img->pixels[i], 0.0, 1.0));
    plm_result rc = plm_image_write(path, img->width, img->height, img->channels, PLM_PIXEL_UINT16, words, err);
    free(words);
    return rc;
}

plm_result plm_texture_with_barb(const plm_image *feather, const plm_image *barb, plm_image *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    if (alloc_image(out, feather->width, feather->height, PLM_FTEX_CHANNELS_WITH_BARB, err) != PLM_OK)
        return PLM_ERR_NO_MEMORY;
    for (size_t i = 0; i < (size_t)feather->width * feather->height; ++i) {
        memcpy(out->pixels + PLM_FTEX_CHANNELS_WITH_BARB * i, feather->pixels + PLM_FTEX_CHANNELS * i,
               PLM_FTEX_CHANNELS * sizeof(float));
        out->pixels[PLM_FTEX_CHANNELS_WITH_BARB * i + PLM_FTEX_BARB] = barb->pixels[i];
    }
    return PLM_OK;
}

plm_flat_region plm_texture_region_of(float channel2)
{
    return (plm_flat_region)plm_ftex_decode_region(channel2);
}

void plm_texture_image_free(plm_image *img)
{
    free(img->pixels);
    memset(img, 0, sizeof *img);
}
