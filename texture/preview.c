#include "texture/preview.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "texture/texture.h"

static const float background_rgb[3] = {0.03f, 0.03f, 0.035f};

static void fill(float *rgb, int w, int h, const float *c)
{
    for (int i = 0; i < w * h; ++i)
        memcpy(rgb + 3 * i, c, 3 * sizeof(float));
}

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

/* A hue wheel (HSV with full saturation) for the barb angle. */
static void hue(double angle, float *c)
{
    double h = fmod(angle / PLM_TWO_PI + 1.0, 1.0) * 6.0;
    static const double offsets[3] = {5.0, 3.0, 1.0};
    for (int k = 0; k < 3; ++k) {
        double q = fmod(offsets[k] + h, 6.0);
        c[k] = (float)(0.85 - 0.7 * fmax(0.0, fmin(q, fmin(4.0 - q, 1.0))));
    }
}

void plm_preview_texture(const plm_feather *f, double barb_step, int w, int h, float *rgb)
{
    const plm_outline *o = &f->outline;
    fill(rgb, w, h, background_rgb);
    /* Fit the flat texture rectangle (2U x Lv mm) into the tile. */
    double scale = fmin(w / (2.0 * o->half_extent), h / o->vane_length) * 0.95;
    double ox = 0.5 * (w - scale * 2.0 * o->half_extent), oy = 0.5 * (h - scale * o->vane_length);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            double u = (i + 0.5 - ox) / (scale * 2.0 * o->half_extent), v = 1.0 - (j + 0.5 - oy) / (scale * o->vane_length);
            if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0)
                continue;
            const float *t = texel(&f->texture, v2(u, v));
            float *c = rgb + 3 * ((size_t)j * w + i);
            plm_flat_region r = plm_texture_region_of(t[2]);
            if (r == PLM_FLAT_RACHIS)
                c[0] = c[1] = c[2] = 0.9f;
            else if (r == PLM_FLAT_VANE)
                hue(atan2(2.0 * t[1] - 1.0, 2.0 * t[0] - 1.0), c);
        }
    enum { MAX_POINTS = 4096 };
    vec2 *pts = malloc(sizeof *pts * MAX_POINTS);
    if (!pts)
        return;
    double step = 0.5 / (scale * fmax(2.0 * o->half_extent, o->vane_length)); /* half a tile pixel */
    for (int side = 0; side < 2; ++side)
        for (double y = o->vane_base; barb_step > 0.0 && y < o->rachis_end; y += barb_step) {
            int n = plm_preview_trace_barb(f, side, y, step, pts, MAX_POINTS);
            for (int k = 0; k < n; ++k) {
                int i = (int)(ox + pts[k].x * scale * 2.0 * o->half_extent);
                int j = (int)(oy + (1.0 - pts[k].y) * scale * o->vane_length);
                if (i >= 0 && i < w && j >= 0 && j < h)
                    memset(rgb + 3 * ((size_t)j * w + i), 0, 3 * sizeof(float));
            }
        }
    free(pts);
}

typedef struct view {
    vec3 right, up, toward; /* camera axes; toward points at the viewer */
    double scale, ox, oy;
} view;

static vec3 vertex(const plm_mesh *m, int i)
{
    return v3(m->positions[3 * i], m->positions[3 * i + 1], m->positions[3 * i + 2]);
}

/* Screen x, y and depth (larger = nearer). */
static vec3 project(const view *vw, vec3 p)
{
    return v3(vw->ox + vw->scale * v3_dot(p, vw->right), vw->oy - vw->scale * v3_dot(p, vw->up), v3_dot(p, vw->toward));
}

static void raster_mesh(const plm_feather *f, const plm_mesh *m, int is_vane, const view *vw, int w, int h,
                        float *depth, float *rgb)
{
    const vec3 light = v3_normalize(v3(0.4, 0.7, 0.6));
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *idx = m->indices + 3 * t;
        vec3 s[3];
        for (int k = 0; k < 3; ++k)
            s[k] = project(vw, vertex(m, (int)idx[k]));
        double area = (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y);
        if (fabs(area) < 1e-12)
            continue;
        int x0 = (int)fmax(0, floor(fmin(s[0].x, fmin(s[1].x, s[2].x))));
        int x1 = (int)fmin(w - 1, ceil(fmax(s[0].x, fmax(s[1].x, s[2].x))));
        int y0 = (int)fmax(0, floor(fmin(s[0].y, fmin(s[1].y, s[2].y))));
        int y1 = (int)fmin(h - 1, ceil(fmax(s[0].y, fmax(s[1].y, s[2].y))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                double px = x + 0.5, py = y + 0.5, b[3];
                for (int k = 0; k < 3; ++k) {
                    const vec3 *a = &s[(k + 1) % 3], *c = &s[(k + 2) % 3];
                    b[k] = ((c->x - a->x) * (py - a->y) - (px - a->x) * (c->y - a->y)) / area;
                }
                if (b[0] < 0.0 || b[1] < 0.0 || b[2] < 0.0)
                    continue;
                double z = b[0] * s[0].z + b[1] * s[1].z + b[2] * s[2].z;
                size_t pix = (size_t)y * w + x;
                if (z <= depth[pix])
                    continue;
                vec3 n = v3(0, 0, 0);
                vec2 uv = v2(0, 0);
                for (int k = 0; k < 3; ++k) {
                    const float *nk = m->normals + 3 * idx[k];
                    n = v3_add(n, v3_scale(v3(nk[0], nk[1], nk[2]), b[k]));
                    if (is_vane)
                        uv = v2_add(uv, v2_scale(v2(m->uvs[2 * idx[k]], m->uvs[2 * idx[k] + 1]), b[k]));
                }
                float base[3] = {0.85f, 0.8f, 0.7f};
                if (is_vane) {
                    const float *tx = texel(&f->texture, uv);
                    plm_flat_region r = plm_texture_region_of(tx[2]);
                    if (r == PLM_FLAT_BACKGROUND)
                        continue;
                    if (r == PLM_FLAT_VANE) /* colour by barb angle, softened */
                        hue(atan2(2.0 * tx[1] - 1.0, 2.0 * tx[0] - 1.0), base);
                }
                double shade = 0.25 + 0.75 * fabs(v3_dot(v3_normalize(n), light)); /* two-sided */
                depth[pix] = (float)z;
                for (int k = 0; k < 3; ++k)
                    rgb[3 * pix + k] = (float)(base[k] * shade);
            }
    }
}

void plm_preview_shape(const plm_feather *f, double yaw, double pitch, int w, int h, float *rgb)
{
    fill(rgb, w, h, background_rgb);
    float *depth = malloc(sizeof(float) * (size_t)w * h);
    if (!depth)
        return;
    for (int i = 0; i < w * h; ++i)
        depth[i] = -FLT_MAX;
    double cy = cos(plm_radians(yaw)), sy = sin(plm_radians(yaw));
    double cp = cos(plm_radians(pitch)), sp = sin(plm_radians(pitch));
    view vw;
    vw.right = v3(cy, 0, -sy);
    vw.toward = v3_add(v3_scale(v3(sy, 0, cy), cp), v3(0, sp, 0));
    vw.up = v3_cross(vw.toward, vw.right);
    /* Fit the projected bounds of both meshes into the tile. */
    double lo[2] = {DBL_MAX, DBL_MAX}, hi[2] = {-DBL_MAX, -DBL_MAX};
    const plm_mesh *meshes[2] = {&f->vane, &f->rachis};
    for (int m = 0; m < 2; ++m)
        for (int i = 0; i < meshes[m]->vertex_count; ++i) {
            vec3 p = vertex(meshes[m], i);
            double a = v3_dot(p, vw.right), b = v3_dot(p, vw.up);
            lo[0] = fmin(lo[0], a), hi[0] = fmax(hi[0], a), lo[1] = fmin(lo[1], b), hi[1] = fmax(hi[1], b);
        }
    vw.scale = 0.95 * fmin(w / (hi[0] - lo[0]), h / (hi[1] - lo[1]));
    vw.ox = 0.5 * w - vw.scale * 0.5 * (lo[0] + hi[0]);
    vw.oy = 0.5 * h + vw.scale * 0.5 * (lo[1] + hi[1]);
    raster_mesh(f, &f->vane, 1, &vw, w, h, depth, rgb);
    raster_mesh(f, &f->rachis, 0, &vw, w, h, depth, rgb);
    free(depth);
}
