/* White balance, exposure and the view transforms of render/film.h. */
#include "render/film.h"

#include <math.h>

#include "common/image_io.h"
#include "render/colour.h"

const char *const plm_view_names[] = {"filmic", "standard", NULL};

/* The filmic view's constants (render/film.h). */
#define GREY 0.18
#define EV_BELOW 10.0 /* stops below grey that the log encoding holds */
#define EV_ABOVE 6.5  /* stops above grey: white */
#define INSET 0.15
#define OUTSET 0.15
#define TOE_POWER 1.5
#define SHOULDER_POWER 1.5
#define NEUTRAL_KELVIN 6504.0 /* the white balance that changes nothing */

static double srgb_decode(double v) { return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4); }

static double luminance(rgb c) { return rgb_luminance(c); }

/* Bradford's cone-like responses from XYZ. */
static const double bradford[3][3] = {
    {0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}};

static void mat_mul(const double a[3][3], const double b[3][3], double out[3][3])
{
    double r[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            out[i][j] = r[i][j];
}

static void mat_inverse(const double a[3][3], double out[3][3])
{
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            out[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
        }
}

/* A white of chromaticity (x, y) and luminance 1, as Bradford responses. */
static void white_response(double x, double y, double out[3])
{
    double xyz[3] = {x / y, 1.0, (1.0 - x - y) / y};
    for (int i = 0; i < 3; ++i)
        out[i] = bradford[i][0] * xyz[0] + bradford[i][1] * xyz[1] + bradford[i][2] * xyz[2];
}

/* Linear sRGB -> linear sRGB: the von Kries adaptation in Bradford's space
 * that takes a blackbody of kelvin to one of NEUTRAL_KELVIN. */
static void white_balance(double kelvin, double m[3][3])
{
    double xs, ys, xt, yt, src[3], dst[3];
    plm_blackbody_chromaticity(kelvin, &xs, &ys);
    plm_blackbody_chromaticity(NEUTRAL_KELVIN, &xt, &yt);
    white_response(xs, ys, src);
    white_response(xt, yt, dst);
    double to_xyz[3][3], from_xyz[3][3], inv_bradford[3][3], scale[3][3] = {{0}};
    for (int j = 0; j < 3; ++j) {
        double xyz[3];
        rgb e = rgb_make(j == 0, j == 1, j == 2);
        plm_srgb_to_xyz(e, xyz);
        for (int i = 0; i < 3; ++i)
            to_xyz[i][j] = xyz[i];
        scale[j][j] = dst[j] / src[j];
    }
    mat_inverse(to_xyz, from_xyz);
    mat_inverse(bradford, inv_bradford);
    mat_mul(bradford, to_xyz, m);
    mat_mul(scale, m, m);
    mat_mul(inv_bradford, m, m);
    mat_mul(from_xyz, m, m);
}

void plm_picture_map_init(const plm_picture *p, plm_picture_map *map)
{
    map->view = p->view;
    double gain = exp2(p->exposure);
    if (p->white_balance > 0.0 && p->white_balance != NEUTRAL_KELVIN) {
        white_balance(p->white_balance, map->m);
    } else {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                map->m[i][j] = i == j;
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            map->m[i][j] *= gain;
}

/* s t / (1 + (s t / a)^p)^(1/p): rises with slope s from 0 toward a; the
 * asymptote a for which it reaches `height` at t = span. */
static double soft_limit(double s, double t, double a, double p) { return s * t / pow(1.0 + pow(s * t / a, p), 1.0 / p); }
static double limit_for(double s, double span, double height, double p)
{
    return s * span / pow(pow(s * span / height, p) - 1.0, 1.0 / p);
}

/* The sigmoid from the log encoding x in [0, 1] to a display value in [0,
 * 1]: through (grey's x, sRGB(0.18)) with the sRGB curve's slope per stop
 * there, to 0 at x = 0 and 1 at x = 1. */
static double filmic_curve(double x)
{
    const double range = EV_BELOW + EV_ABOVE, px = EV_BELOW / range, py = plm_srgb_encode(GREY);
    /* d sRGB / d log2(x) at grey, per unit of the encoding. */
    const double slope = 1.055 / 2.4 * log(2.0) * pow(GREY, 1.0 / 2.4) * range;
    double t = x - px;
    if (t >= 0.0)
        return py + soft_limit(slope, t, limit_for(slope, 1.0 - px, 1.0 - py, SHOULDER_POWER), SHOULDER_POWER);
    return py - soft_limit(slope, -t, limit_for(slope, px, py, TOE_POWER), TOE_POWER);
}

/* A colour pulled toward (amount > 0) or pushed away from (< 0) the grey of its luminance. */
static rgb toward_grey(rgb c, double amount)
{
    return rgb_add(rgb_scale(c, 1.0 - amount), rgb_gray(amount * luminance(c)));
}

static double filmic_channel(double v)
{
    double e = (log2(fmax(v, 1e-12) / GREY) + EV_BELOW) / (EV_BELOW + EV_ABOVE);
    return srgb_decode(filmic_curve(plm_clamp(e, 0.0, 1.0)));
}

rgb plm_picture_apply(const plm_picture_map *map, rgb c)
{
    const double(*m)[3] = map->m;
    rgb v = rgb_make(m[0][0] * c.r + m[0][1] * c.g + m[0][2] * c.b, m[1][0] * c.r + m[1][1] * c.g + m[1][2] * c.b,
                     m[2][0] * c.r + m[2][1] * c.g + m[2][2] * c.b);
    if (map->view == PLM_VIEW_FILMIC) {
        v = toward_grey(rgb_make(plm_positive(v.r), plm_positive(v.g), plm_positive(v.b)), INSET);
        v = rgb_make(filmic_channel(v.r), filmic_channel(v.g), filmic_channel(v.b));
        v = toward_grey(v, -OUTSET / (1.0 - OUTSET)); /* the inverse of a pull of OUTSET */
    }
    return rgb_make(plm_srgb_encode(plm_clamp(v.r, 0.0, 1.0)), plm_srgb_encode(plm_clamp(v.g, 0.0, 1.0)),
                    plm_srgb_encode(plm_clamp(v.b, 0.0, 1.0)));
}

void plm_picture_to_srgb8(const plm_picture *p, const float *rgb_pixels, size_t pixels, uint8_t *out)
{
    plm_picture_map map;
    plm_picture_map_init(p, &map);
    for (size_t i = 0; i < pixels; ++i) {
        const float *q = rgb_pixels + 3 * i;
        rgb c = rgb_make(q[0], q[1], q[2]);
        rgb d = rgb_is_finite(c) ? plm_picture_apply(&map, c) : rgb_gray(0.0);
        out[3 * i] = (uint8_t)lrint(255.0 * d.r);
        out[3 * i + 1] = (uint8_t)lrint(255.0 * d.g);
        out[3 * i + 2] = (uint8_t)lrint(255.0 * d.b);
    }
}
