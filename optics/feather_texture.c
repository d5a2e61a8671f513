#include "optics/feather_texture.h"

#include <math.h>
#include <stdlib.h>

#include "common/image_io.h"

plm_result plm_feather_texture_from_pixels(int width, int height, float *pixels, plm_feather_texture *out,
                                           plm_error *err)
{
    out->width = width;
    out->height = height;
    out->pixels = pixels;
    out->barb = NULL;
    out->region = malloc((size_t)width * (size_t)height);
    if (!out->region) {
        free(pixels);
        out->pixels = NULL;
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a %dx%d feather texture", width, height);
    }
    for (long i = 0; i < (long)width * height; ++i)
        out->region[i] = (unsigned char)plm_ftex_decode_region(pixels[PLM_FTEX_CHANNELS * i + PLM_FTEX_REGION]);
    return PLM_OK;
}

plm_result plm_feather_texture_read(const char *path, plm_feather_texture *out, plm_error *err)
{
    int w, h, c;
    float *pixels;
    plm_result rc = plm_image_read(path, &w, &h, &c, &pixels, err);
    if (rc != PLM_OK)
        return rc;
    if (c < 3) {
        free(pixels);
        return plm_fail(err, PLM_ERR_INVALID,
                        "%s: a feather texture needs 3 channels (cos, sin, region), this image has %d", path, c);
    }
    float *barb = NULL;
    if (plm_ftex_has_barb(c) && !(barb = malloc(sizeof *barb * (size_t)w * (size_t)h))) {
        free(pixels);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory for a %dx%d barb coordinate", path, w, h);
    }
    if (c > 3) { /* the first three channels, and the coordinate apart */
        for (long i = 0; i < (long)w * h; ++i) {
            if (barb)
                barb[i] = pixels[(long)c * i + PLM_FTEX_BARB];
            for (int k = 0; k < 3; ++k)
                pixels[3 * i + k] = pixels[(long)c * i + k];
        }
    }
    rc = plm_feather_texture_from_pixels(w, h, pixels, out, err);
    if (rc == PLM_OK)
        out->barb = barb;
    else
        free(barb);
    return rc;
}

void plm_feather_texture_free(plm_feather_texture *t)
{
    free(t->pixels);
    free(t->region);
    free(t->barb);
    t->pixels = NULL;
    t->region = NULL;
    t->barb = NULL;
}

/* Continuous texel coordinates of uv: texel centres sit at integers. */
static void texel_coords(const plm_feather_texture *t, vec2 uv, double *x, double *y)
{
    *x = plm_clamp(uv.x, 0.0, 1.0) * t->width - 0.5;
    *y = (1.0 - plm_clamp(uv.y, 0.0, 1.0)) * t->height - 0.5;
}

/* Nearest integer of a texel coordinate, which is at least -0.5 (uv is clamped). */
static long nearest(double x) { return (long)(x + 0.5); }

static long texel_index(const plm_feather_texture *t, long x, long y)
{
    x = x < 0 ? 0 : (x >= t->width ? t->width - 1 : x);
    y = y < 0 ? 0 : (y >= t->height ? t->height - 1 : y);
    return y * t->width + x;
}

void plm_feather_texture_site(const plm_feather_texture *t, vec2 uv, plm_texel_site *out)
{
    texel_coords(t, uv, &out->x, &out->y);
    long x = nearest(out->x), y = nearest(out->y); /* >= 0: uv is clamped */
    out->cx = x >= t->width ? t->width - 1 : x;
    out->cy = y >= t->height ? t->height - 1 : y;
    out->centre = out->cy * t->width + out->cx;
}

long plm_texel_nearest(int width, int height, vec2 uv)
{
    plm_feather_texture t = {width, height, NULL, NULL, NULL};
    plm_texel_site site;
    plm_feather_texture_site(&t, uv, &site);
    return site.centre;
}

plm_region plm_feather_texture_region(const plm_feather_texture *t, vec2 uv)
{
    plm_texel_site site;
    plm_feather_texture_site(t, uv, &site);
    return plm_feather_texture_region_at(t, &site);
}

/* The (unnormalised) direction stored in texel i. */
static vec2 texel_direction(const plm_feather_texture *t, long i)
{
    const float *px = t->pixels + PLM_FTEX_CHANNELS * i;
    return v2(plm_ftex_decode_component(px[PLM_FTEX_COS]), plm_ftex_decode_component(px[PLM_FTEX_SIN]));
}

vec2 plm_feather_texture_direction(const plm_feather_texture *t, vec2 uv)
{
    plm_texel_site site;
    plm_feather_texture_site(t, uv, &site);
    return plm_feather_texture_direction_at(t, &site);
}

vec2 plm_feather_texture_direction_at(const plm_feather_texture *t, const plm_texel_site *site)
{
    double x = site->x, y = site->y;
    long centre = site->centre;
    long x0 = (long)floor(x), y0 = (long)floor(y);
    double fx = x - x0, fy = y - y0;
    vec2 sum = v2(0.0, 0.0);
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            long i = texel_index(t, x0 + dx, y0 + dy);
            if (t->region[i] != t->region[centre])
                continue;
            double w = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy);
            sum = v2_add(sum, v2_scale(texel_direction(t, i), w));
        }
    double len = v2_length(sum);
    if (len > 1e-6)
        return v2_scale(sum, 1.0 / len);
    /* Opposite directions cancelled (a texture error) or a zero texel: use the nearest alone. */
    vec2 d = texel_direction(t, centre);
    len = v2_length(d);
    return len > 1e-6 ? v2_scale(d, 1.0 / len) : v2(0.0, 1.0);
}

/* Texel (x, y)'s coordinate unwrapped to within half a period of ref, and
 * whether it lies in the region. */
static int barb_texel(const plm_feather_texture *t, long x, long y, unsigned char region, double ref, double *c)
{
    if (x < 0 || y < 0 || x >= t->width || y >= t->height)
        return 0;
    long i = y * t->width + x;
    *c = plm_ftex_barb_unwrap(t->barb[i], ref);
    return t->region[i] == region;
}

/* The coordinate's change per texel along (sx, sy) at texel (x, y): central
 * where both neighbours share its region, one-sided where one does. */
static double barb_difference(const plm_feather_texture *t, long x, long y, int sx, int sy, double ref)
{
    unsigned char region = t->region[y * t->width + x];
    double plus, minus;
    int has_plus = barb_texel(t, x + sx, y + sy, region, ref, &plus);
    int has_minus = barb_texel(t, x - sx, y - sy, region, ref, &minus);
    if (has_plus && has_minus)
        return 0.5 * (plus - minus);
    return has_plus ? plus - ref : (has_minus ? ref - minus : 0.0);
}

int plm_feather_texture_barb(const plm_feather_texture *t, vec2 uv, plm_barb_sample *out)
{
    plm_texel_site site;
    plm_feather_texture_site(t, uv, &site);
    return plm_feather_texture_barb_at(t, &site, out);
}

int plm_feather_texture_barb_at(const plm_feather_texture *t, const plm_texel_site *site, plm_barb_sample *out)
{
    if (!t->barb)
        return 0;
    double x = site->x, y = site->y;
    long centre = site->centre, cx = site->cx, cy = site->cy;
    double ref = t->barb[centre];
    long x0 = (long)floor(x), y0 = (long)floor(y);
    double fx = x - x0, fy = y - y0, sum = 0.0, weight = 0.0;
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            double c, w = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy);
            if (barb_texel(t, x0 + dx, y0 + dy, t->region[centre], ref, &c)) {
                sum += w * c;
                weight += w;
            }
        }
    out->coordinate = weight > 0.0 ? sum / weight : ref;
    double gx = barb_difference(t, cx, cy, 1, 0, ref), gy = barb_difference(t, cx, cy, 0, 1, ref);
    out->texel_step = fmax(fabs(gx), fabs(gy));
    /* x grows with u, y against v (top row first). */
    out->gradient = v2(gx * t->width, -gy * t->height);
    return 1;
}
