#include "texture/preview.h"

#include <math.h>
#include <string.h>

#include "texture/texture.h"

static const float background_rgb[3] = {0.03f, 0.03f, 0.035f};

static const float *texel(const plm_image *t, vec2 uv)
{
    int i = (int)plm_clamp(floor(uv.x * t->width), 0, t->width - 1);
    int j = (int)plm_clamp(floor((1.0 - uv.y) * t->height), 0, t->height - 1);
    return t->pixels + 3 * ((size_t)j * t->width + i);
}

/* Barb direction at uv as the renderer reads it: bilinear among the four
 * nearest texels that share the nearest texel's region. */
static vec2 direction(const plm_image *t, vec2 uv)
{
    double fx = uv.x * t->width - 0.5, fy = (1.0 - uv.y) * t->height - 0.5;
    int i0 = (int)floor(fx), j0 = (int)floor(fy);
    double ax = fx - i0, ay = fy - j0;
    plm_flat_region region = plm_texture_region_of(texel(t, uv)[2]);
    vec2 d = v2(0, 0);
    for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di) {
            int i = (int)plm_clamp(i0 + di, 0, t->width - 1), j = (int)plm_clamp(j0 + dj, 0, t->height - 1);
            const float *p = t->pixels + 3 * ((size_t)j * t->width + i);
            if (plm_texture_region_of(p[2]) != region)
                continue;
            double wgt = (di ? ax : 1.0 - ax) * (dj ? ay : 1.0 - ay);
            d = v2_add(d, v2_scale(v2(2.0 * p[0] - 1.0, 2.0 * p[1] - 1.0), wgt));
        }
    return v2_normalize(d);
}

int plm_preview_trace_barb(const plm_feather *f, int side, double y, double step, vec2 *points, int max_points)
{
    const plm_outline *o = &f->outline;
    double x = (side ? 1.0 : -1.0) * (plm_outline_rachis_radius(o, y) + 1e-3);
    vec2 p = plm_outline_uv(o, x, y);
    int n = 0;
    while (n < max_points && p.x >= 0.0 && p.x <= 1.0 && p.y >= 0.0 && p.y <= 1.0) {
        points[n++] = p;
        vec2 mid = v2_add(p, v2_scale(direction(&f->texture, p), 0.5 * step));
        p = v2_add(p, v2_scale(direction(&f->texture, mid), step));
        if (plm_texture_region_of(texel(&f->texture, p)[2]) == PLM_FLAT_BACKGROUND)
            break;
    }
    return n;
}

void plm_preview_barb_coordinate(const plm_feather *f, vec2 centre, double span, int w, int h, float *rgb)
{
    static const float rachis_rgb[3] = {0.55f, 0.65f, 0.8f};
    const plm_image *b = &f->barb;
    double mm_per_pixel = span / fmax(w, h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            double x = centre.x + (i + 0.5 - 0.5 * w) * mm_per_pixel, y = centre.y - (j + 0.5 - 0.5 * h) * mm_per_pixel;
            vec2 uv = plm_outline_uv(&f->outline, x, y);
            float *c = rgb + 3 * ((size_t)j * w + i);
            plm_flat_region r = uv.x < 0.0 || uv.x > 1.0 || uv.y < 0.0 || uv.y > 1.0
                                    ? PLM_FLAT_BACKGROUND
                                    : plm_texture_region_of(texel(&f->texture, uv)[2]);
            if (r == PLM_FLAT_VANE) {
                /* The nearest texel, as the contract asks: the value jumps at every barb. */
                int ti = (int)plm_clamp(floor(uv.x * b->width), 0, b->width - 1);
                int tj = (int)plm_clamp(floor((1.0 - uv.y) * b->height), 0, b->height - 1);
                c[0] = c[1] = c[2] = b->pixels[(size_t)tj * b->width + ti];
            } else
                memcpy(c, r == PLM_FLAT_RACHIS ? rachis_rgb : background_rgb, 3 * sizeof(float));
        }
}
