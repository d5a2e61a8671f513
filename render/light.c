#include "render/light.h"

#include <stdlib.h>
#include <string.h>

/* ---------- frames and lat-long conventions ---------- */

/* v turned by the least rotation that takes +y to up (Rodrigues' formula);
 * up = -y turns half a turn about +x. */
static vec3 turn_from_y(vec3 up, vec3 v)
{
    vec3 axis = v3(up.z, 0.0, -up.x); /* +y x up */
    double s = v3_length(axis), c = up.y;
    if (s < 1e-12)
        return c > 0.0 ? v : v3(v.x, -v.y, -v.z);
    axis = v3_scale(axis, 1.0 / s);
    return v3_add(v3_add(v3_scale(v, c), v3_scale(v3_cross(axis, v), s)), v3_scale(axis, v3_dot(axis, v) * (1.0 - c)));
}

frame plm_light_axes(vec3 up, double rotation)
{
    double s = sin(rotation), c = cos(rotation);
    frame f = {turn_from_y(up, v3(c, 0.0, s)), up, turn_from_y(up, v3(-s, 0.0, c))};
    return f;
}

/* plm_atan2 and plm_acos (via plm_safe_acos) rather than the C library's:
 * this runs for every escaping ray and every light sample's density. */
vec2 plm_envmap_uv(const frame *axes, vec3 d)
{
    vec3 l = frame_to_local(axes, d);
    double u = plm_atan2(l.x, -l.z) / PLM_TWO_PI + 0.5;
    u -= floor(u);
    return v2(u, plm_safe_acos(l.y) / PLM_PI);
}

/* The direction of uv and its sin(theta), which a density over the sphere divides by. */
static vec3 envmap_direction(const frame *axes, vec2 uv, double *sin_theta)
{
    double cos_theta, sin_phi, cos_phi;
    plm_sincos(PLM_PI * uv.y, sin_theta, &cos_theta);
    plm_sincos(PLM_TWO_PI * (uv.x - 0.5), &sin_phi, &cos_phi);
    return frame_to_world(axes, v3(*sin_theta * sin_phi, cos_theta, -*sin_theta * cos_phi));
}

vec3 plm_envmap_direction(const frame *axes, vec2 uv)
{
    double sin_theta;
    return envmap_direction(axes, uv, &sin_theta);
}

/* ---------- the grid density ---------- */

/* Builds the density from per-cell luminance (width * height, row 0 at the
 * zenith), weighting each row by its solid angle's sin(theta). */
static plm_result envmap_build(const double *luminance, int w, int h, plm_envmap *env, plm_error *err)
{
    env->width = w;
    env->height = h;
    env->marginal_cdf = malloc(sizeof(double) * (size_t)(h + 1));
    env->conditional_cdf = malloc(sizeof(double) * (size_t)h * (size_t)(w + 1));
    env->conditional = malloc(sizeof *env->conditional * (size_t)h);
    env->marginal_guide = malloc(sizeof(int) * (size_t)h);
    env->conditional_guide = malloc(sizeof(int) * (size_t)h * (size_t)w);
    double *weights = malloc(sizeof(double) * (size_t)w);
    double *row_totals = malloc(sizeof(double) * (size_t)h);
    if (!env->marginal_cdf || !env->conditional_cdf || !env->conditional || !env->marginal_guide ||
        !env->conditional_guide || !weights || !row_totals) {
        free(weights);
        free(row_totals);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a %dx%d environment map", w, h);
    }
    for (int y = 0; y < h; ++y) {
        double sin_theta = sin(PLM_PI * (y + 0.5) / h); /* solid angle of the row's cells */
        for (int x = 0; x < w; ++x)
            weights[x] = luminance[(size_t)y * w + x] * sin_theta;
        env->conditional[y] = plm_distribution1d_build(weights, w, env->conditional_cdf + (size_t)y * (w + 1),
                                                       env->conditional_guide + (size_t)y * w);
        row_totals[y] = env->conditional[y].total;
    }
    env->marginal = plm_distribution1d_build(row_totals, h, env->marginal_cdf, env->marginal_guide);
    /* Each cell spans 2 pi / w by pi / h in (phi, theta). */
    env->integral = env->marginal.total * 2.0 * PLM_PI * PLM_PI / ((double)w * h);
    free(weights);
    free(row_totals);
    return PLM_OK;
}

/* Cell holding uv. */
static void envmap_cell(const plm_envmap *env, vec2 uv, int *x, int *y)
{
    *x = (int)(uv.x * env->width);
    *y = (int)(uv.y * env->height);
    *x = *x < 0 ? 0 : (*x >= env->width ? env->width - 1 : *x);
    *y = *y < 0 ? 0 : (*y >= env->height ? env->height - 1 : *y);
}

/* Density over the sphere of cell (x, y) at sin(theta): p(u, v) / (2 pi^2 sin theta),
 * p(u, v) = pmf(cell) * width * height. */
static double envmap_cell_pdf(const plm_envmap *env, int x, int y, double sin_theta)
{
    if (env->marginal.total <= 0.0 || sin_theta <= 0.0)
        return 0.0;
    double p = plm_distribution1d_pmf(&env->marginal, y) * plm_distribution1d_pmf(&env->conditional[y], x) *
               (double)env->width * env->height;
    return p / (2.0 * PLM_PI * PLM_PI * sin_theta);
}

static double envmap_pdf(const plm_envmap *env, vec2 uv)
{
    int x, y;
    envmap_cell(env, uv, &x, &y);
    return envmap_cell_pdf(env, x, y, sin(PLM_PI * uv.y));
}

/* A direction drawn from the density (0 if it is empty), with its pdf. */
static int envmap_sample(const plm_envmap *env, const frame *axes, double u1, double u2, vec3 *wi, double *pdf)
{
    if (env->marginal.total <= 0.0)
        return 0;
    double ru, rv;
    int y = plm_distribution1d_sample(&env->marginal, u1, &rv);
    int x = plm_distribution1d_sample(&env->conditional[y], u2, &ru);
    double sin_theta;
    *wi = envmap_direction(axes, v2((x + ru) / env->width, (y + rv) / env->height), &sin_theta);
    *pdf = envmap_cell_pdf(env, x, y, sin_theta);
    return *pdf > 0.0;
}

/* ---------- radiance of the infinite lights ---------- */

/* A texel's RGB, negative and non-finite values (which some HDR files hold) as 0. */
static rgb texel_rgb(const plm_image *im, int x, int y)
{
    const float *p = im->pixels + ((size_t)y * im->width + x) * im->channels;
    rgb c = rgb_make(p[0], p[1], p[2]);
    if (!rgb_is_finite(c))
        return rgb_gray(0.0);
    return rgb_make(plm_positive(c.r), plm_positive(c.g), plm_positive(c.b));
}

/* Bilinear between texel centres, wrapping around in u, held at the poles. */
static rgb image_bilinear(const plm_image *im, vec2 uv)
{
    double fx = uv.x * im->width - 0.5, fy = uv.y * im->height - 0.5;
    int x0 = (int)floor(fx), y0 = (int)floor(fy);
    double tx = fx - x0, ty = fy - y0;
    int xs[2] = {(x0 % im->width + im->width) % im->width, ((x0 + 1) % im->width + im->width) % im->width};
    int ys[2] = {y0 < 0 ? 0 : (y0 >= im->height ? im->height - 1 : y0),
                 y0 + 1 >= im->height ? im->height - 1 : (y0 + 1 < 0 ? 0 : y0 + 1)};
    rgb top = rgb_add(rgb_scale(texel_rgb(im, xs[0], ys[0]), 1.0 - tx), rgb_scale(texel_rgb(im, xs[1], ys[0]), tx));
    rgb bottom = rgb_add(rgb_scale(texel_rgb(im, xs[0], ys[1]), 1.0 - tx), rgb_scale(texel_rgb(im, xs[1], ys[1]), tx));
    return rgb_add(rgb_scale(top, 1.0 - ty), rgb_scale(bottom, ty));
}

/* A map's density: each texel's luminance smoothed by (1 6 1) / 8 both ways,
 * the mean of the bilinear radiance over the texel, so the density is not 0
 * wherever the radiance is not. */
static plm_result image_envmap(const plm_image *im, plm_envmap *env, plm_error *err)
{
    int w = im->width, h = im->height;
    double *lum = malloc(sizeof(double) * (size_t)w * h), *rows = malloc(sizeof(double) * (size_t)w * h);
    if (!lum || !rows) {
        free(lum);
        free(rows);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a %dx%d environment map", w, h);
    }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            lum[(size_t)y * w + x] = rgb_luminance(texel_rgb(im, x, y));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double *r = lum + (size_t)y * w;
            rows[(size_t)y * w + x] = (r[(x + w - 1) % w] + 6.0 * r[x] + r[(x + 1) % w]) / 8.0;
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int up = y > 0 ? y - 1 : 0, down = y + 1 < h ? y + 1 : h - 1;
            lum[(size_t)y * w + x] =
                (rows[(size_t)up * w + x] + 6.0 * rows[(size_t)y * w + x] + rows[(size_t)down * w + x]) / 8.0;
        }
    free(rows);
    plm_result rc = envmap_build(lum, w, h, env, err);
    free(lum);
    return rc;
}

/* The sky's density over a grid of its luminance at cell centres (its sun
 * is sampled apart); rows below the horizon hold the ground's. */
static plm_result sky_envmap(const plm_sky_model *sky, plm_envmap *env, plm_error *err)
{
    enum { W = 128, H = 64 }; /* H even: the horizon falls between rows */
    double *lum = malloc(sizeof(double) * W * H);
    if (!lum)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for the sky");
    frame identity = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            lum[y * W + x] = rgb_luminance(
                plm_sky_radiance(sky, plm_envmap_direction(&identity, v2((x + 0.5) / W, (y + 0.5) / H))));
    plm_result rc = envmap_build(lum, W, H, env, err);
    free(lum);
    return rc;
}

/* The sun's cone of directions about its centre c (unit, world). */
static double sun_cone_pdf(const plm_render_light *l) { return 1.0 / (PLM_TWO_PI * (1.0 - l->sky.cos_sun_radius)); }

/* Radiance along d of the sky (sun included), and its mixture density if pdf is not NULL. */
static rgb sky_lookup(const plm_render_light *l, vec3 d, double *pdf)
{
    vec3 local = frame_to_local(&l->axes, d);
    rgb le = plm_sky_radiance(&l->sky, local);
    int in_sun = l->sun_pick > 0.0 && v3_dot(local, l->sky.sun) >= l->sky.cos_sun_radius;
    if (in_sun)
        le = rgb_add(le, l->sky.sun_radiance);
    if (pdf)
        *pdf = (1.0 - l->sun_pick) * envmap_pdf(&l->env, plm_envmap_uv(&l->axes, d)) +
               (in_sun ? l->sun_pick * sun_cone_pdf(l) : 0.0);
    return rgb_mul(l->scale, le);
}

rgb plm_light_environment(const plm_render_light *l, vec3 d, double *pdf)
{
    const plm_light *desc = l->desc;
    if (desc->type == PLM_LIGHT_CONSTANT_ENV) {
        if (pdf)
            *pdf = 1.0 / (4.0 * PLM_PI);
        return l->scale;
    }
    if (desc->type == PLM_LIGHT_SKY)
        return sky_lookup(l, d, pdf);
    /* One direction -> (u, v) for the radiance and the density: its atan2
     * and acos are most of a lookup. */
    vec2 uv = plm_envmap_uv(&l->axes, d);
    if (pdf)
        *pdf = envmap_pdf(&l->env, uv);
    return rgb_mul(l->scale, image_bilinear(&desc->image, uv));
}

/* ---------- setting up ---------- */

/* Luminance of a sky of radiance 1 per cd/m^2: 1.2 x 2^15 cd/m^2 saturates a
 * camera at EV 15 (ISO 12232's saturation-based exposure), so exposure 0 is
 * the sunny-16 rule's. */
#define PLM_SKY_UNIT_CD (1.2 * 32768.0)

plm_result plm_render_light_init(const plm_light *desc, plm_render_light *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    out->desc = desc;
    out->scale = rgb_scale(desc->radiance, desc->intensity);
    out->axes = plm_light_axes(desc->up, desc->type == PLM_LIGHT_ENV_MAP ? desc->rotation : 0.0);
    plm_result rc = PLM_OK;
    switch (desc->type) {
    case PLM_LIGHT_QUAD: {
        vec3 c = v3_cross(desc->edge_u, desc->edge_v);
        out->area = v3_length(c);
        out->normal = v3_scale(c, 1.0 / out->area);
        break;
    }
    case PLM_LIGHT_ENV_MAP:
        rc = image_envmap(&desc->image, &out->env, err);
        break;
    case PLM_LIGHT_SKY: {
        out->scale = rgb_gray(desc->intensity / PLM_SKY_UNIT_CD);
        plm_sky_model_init(&desc->sky, &out->sky);
        rc = sky_envmap(&out->sky, &out->env, err);
        /* Sun and sky sampled in proportion to the light each brings. */
        double sun = rgb_luminance(out->sky.sun_irradiance), dome = out->env.integral / 4.0;
        out->sun_pick = sun > 0.0 ? sun / (sun + dome) : 0.0;
        break;
    }
    default:
        break;
    }
    return rc;
}

void plm_render_light_free(plm_render_light *l)
{
    free(l->env.marginal_cdf);
    free(l->env.conditional_cdf);
    free(l->env.conditional);
    free(l->env.marginal_guide);
    free(l->env.conditional_guide);
    memset(l, 0, sizeof *l);
}

double plm_light_power(const plm_render_light *l, vec3 centre)
{
    const plm_light *desc = l->desc;
    switch (desc->type) {
    case PLM_LIGHT_CONSTANT_ENV:
        return PLM_PI * rgb_luminance(l->scale);
    case PLM_LIGHT_ENV_MAP:
        return rgb_luminance(l->scale) * l->env.integral / 4.0;
    case PLM_LIGHT_SKY:
        return rgb_luminance(l->scale) * (l->env.integral / 4.0 + rgb_luminance(l->sky.sun_irradiance));
    case PLM_LIGHT_DISTANT:
        return rgb_luminance(desc->irradiance);
    case PLM_LIGHT_SPHERE: {
        double d2 = v3_dot(v3_sub(desc->center, centre), v3_sub(desc->center, centre)), r2 = desc->radius * desc->radius;
        double solid = d2 <= r2 ? 4.0 * PLM_PI : PLM_TWO_PI * (1.0 - sqrt(1.0 - r2 / d2));
        return rgb_luminance(desc->radiance) * solid;
    }
    case PLM_LIGHT_QUAD: {
        vec3 mid = v3_add(desc->corner, v3_scale(v3_add(desc->edge_u, desc->edge_v), 0.5));
        double d2 = v3_dot(v3_sub(mid, centre), v3_sub(mid, centre));
        double solid = fmin(PLM_TWO_PI, l->area / fmax(d2, 1e-12));
        return rgb_luminance(desc->radiance) * solid * (desc->two_sided ? 2.0 : 1.0);
    }
    }
    return 0.0;
}

/* Sum over a w x h lat-long grid in the light's frame of radiance(cell
 * centre) times its solid angle and its cosine to n. */
static rgb grid_irradiance(const plm_render_light *l, vec3 n, int w, int h, rgb (*radiance)(const plm_render_light *,
                                                                                              int, int, vec3))
{
    rgb sum = rgb_gray(0.0);
    for (int y = 0; y < h; ++y) {
        double v = (y + 0.5) / h, solid = (PLM_TWO_PI / w) * (cos(PLM_PI * y / h) - cos(PLM_PI * (y + 1) / h));
        for (int x = 0; x < w; ++x) {
            vec3 d = plm_envmap_direction(&l->axes, v2((x + 0.5) / w, v));
            double c = v3_dot(d, n);
            if (c > 0.0)
                sum = rgb_add(sum, rgb_scale(radiance(l, x, y, d), c * solid));
        }
    }
    return sum;
}

static rgb texel_radiance(const plm_render_light *l, int x, int y, vec3 d)
{
    (void)d;
    return rgb_mul(l->scale, texel_rgb(&l->desc->image, x, y));
}

static rgb dome_radiance(const plm_render_light *l, int x, int y, vec3 d)
{
    (void)x, (void)y;
    return rgb_mul(l->scale, plm_sky_radiance(&l->sky, frame_to_local(&l->axes, d)));
}

rgb plm_light_irradiance(const plm_render_light *l, vec3 n)
{
    const plm_light *desc = l->desc;
    switch (desc->type) {
    case PLM_LIGHT_CONSTANT_ENV:
        return rgb_scale(l->scale, PLM_PI);
    case PLM_LIGHT_ENV_MAP:
        return grid_irradiance(l, n, desc->image.width, desc->image.height, texel_radiance);
    case PLM_LIGHT_SKY: {
        rgb dome = grid_irradiance(l, n, 512, 256, dome_radiance);
        double c = v3_dot(frame_to_world(&l->axes, l->sky.sun), n);
        return rgb_add(dome, rgb_scale(rgb_mul(l->scale, l->sky.sun_irradiance), fmax(c, 0.0)));
    }
    case PLM_LIGHT_DISTANT:
        return rgb_scale(desc->irradiance, fmax(v3_dot(desc->direction, n), 0.0));
    default:
        return rgb_gray(0.0);
    }
}

/* ---------- sampling ---------- */

/* Cone of directions subtended by a sphere seen from outside (pbrt's uniform cone). */
static int sphere_sample(const plm_light *l, vec3 p, double u1, double u2, plm_light_sample *s)
{
    vec3 to_center = v3_sub(l->center, p);
    double d2 = v3_dot(to_center, to_center), r2 = l->radius * l->radius;
    if (d2 <= r2)
        return 0; /* inside the light: not supported as a receiver position */
    double cos_max = sqrt(1.0 - r2 / d2);
    double cos_t = 1.0 - u1 * (1.0 - cos_max), sin_t = plm_safe_sqrt(1.0 - cos_t * cos_t);
    double phi = PLM_TWO_PI * u2, d = sqrt(d2);
    frame f = frame_from_z(v3_scale(to_center, 1.0 / d));
    s->wi = frame_to_world(&f, v3(sin_t * cos(phi), sin_t * sin(phi), cos_t));
    /* Distance to the near intersection of the sampled direction with the sphere. */
    double b = d * cos_t;
    s->dist = b - plm_safe_sqrt(r2 - (d2 - b * b));
    s->radiance = l->radiance;
    s->pdf = 1.0 / (PLM_TWO_PI * (1.0 - cos_max));
    return 1;
}

/* A direction uniform in the cone of half-angle acos(cos_max) about axis (unit). */
static vec3 cone_direction(vec3 axis, double cos_max, double u1, double u2)
{
    double cos_t = 1.0 - u1 * (1.0 - cos_max), sin_t = plm_safe_sqrt(1.0 - cos_t * cos_t), sp, cp;
    plm_sincos(PLM_TWO_PI * u2, &sp, &cp);
    frame f = frame_from_z(axis);
    return frame_to_world(&f, v3(sin_t * cp, sin_t * sp, cos_t));
}

/* The sky: the sun's cone with probability sun_pick (u1 reused within it), else the grid. */
static int sky_sample(const plm_render_light *l, double u1, double u2, plm_light_sample *s)
{
    if (u1 < l->sun_pick) {
        vec3 sun = frame_to_world(&l->axes, l->sky.sun);
        s->wi = cone_direction(sun, l->sky.cos_sun_radius, u1 / l->sun_pick, u2);
    } else {
        double pdf;
        if (!envmap_sample(&l->env, &l->axes, (u1 - l->sun_pick) / (1.0 - l->sun_pick), u2, &s->wi, &pdf))
            return 0;
    }
    s->radiance = sky_lookup(l, s->wi, &s->pdf);
    return s->pdf > 0.0;
}

int plm_light_sample_from(const plm_render_light *l, vec3 p, double u1, double u2, plm_light_sample *s)
{
    const plm_light *desc = l->desc;
    s->is_delta = 0;
    s->dist = INFINITY;
    switch (desc->type) {
    case PLM_LIGHT_CONSTANT_ENV:
        s->wi = plm_sample_uniform_sphere(u1, u2);
        s->radiance = l->scale;
        s->pdf = 1.0 / (4.0 * PLM_PI);
        return 1;
    case PLM_LIGHT_ENV_MAP:
        if (!envmap_sample(&l->env, &l->axes, u1, u2, &s->wi, &s->pdf))
            return 0;
        s->radiance = rgb_mul(l->scale, image_bilinear(&desc->image, plm_envmap_uv(&l->axes, s->wi)));
        return 1;
    case PLM_LIGHT_SKY:
        return sky_sample(l, u1, u2, s);
    case PLM_LIGHT_DISTANT:
        s->wi = desc->direction;
        s->radiance = desc->irradiance;
        s->pdf = 1.0;
        s->is_delta = 1;
        return 1;
    case PLM_LIGHT_SPHERE:
        return sphere_sample(desc, p, u1, u2, s);
    case PLM_LIGHT_QUAD: {
        vec3 q = v3_add(desc->corner, v3_add(v3_scale(desc->edge_u, u1), v3_scale(desc->edge_v, u2)));
        vec3 to = v3_sub(q, p);
        double d2 = v3_dot(to, to), d = sqrt(d2);
        if (d <= 0.0)
            return 0;
        s->wi = v3_scale(to, 1.0 / d);
        double cos_l = -v3_dot(s->wi, l->normal);
        if (desc->two_sided)
            cos_l = fabs(cos_l);
        if (cos_l <= 0.0)
            return 0;
        s->dist = d;
        s->radiance = desc->radiance;
        s->pdf = d2 / (cos_l * l->area);
        return 1;
    }
    }
    return 0;
}

static int quad_hit(const plm_render_light *l, vec3 o, vec3 d, double tmax, double *t)
{
    const plm_light *desc = l->desc;
    double denom = v3_dot(d, l->normal);
    if (denom == 0.0 || (!desc->two_sided && denom > 0.0))
        return 0;
    double th = v3_dot(v3_sub(desc->corner, o), l->normal) / denom;
    if (!(th > 0.0 && th < tmax))
        return 0;
    vec3 q = v3_sub(v3_madd(o, d, th), desc->corner);
    /* Coordinates of q along the (not necessarily orthogonal) edges. */
    double uu = v3_dot(desc->edge_u, desc->edge_u), uv = v3_dot(desc->edge_u, desc->edge_v);
    double vv = v3_dot(desc->edge_v, desc->edge_v), qu = v3_dot(q, desc->edge_u), qv = v3_dot(q, desc->edge_v);
    double det = uu * vv - uv * uv, a = (qu * vv - qv * uv) / det, b = (qv * uu - qu * uv) / det;
    if (a < 0.0 || a > 1.0 || b < 0.0 || b > 1.0)
        return 0;
    *t = th;
    return 1;
}

static int sphere_hit(const plm_light *l, vec3 o, vec3 d, double tmax, double *t)
{
    vec3 oc = v3_sub(o, l->center);
    double b = v3_dot(oc, d), c = v3_dot(oc, oc) - l->radius * l->radius, disc = b * b - c;
    if (disc < 0.0 || c <= 0.0)
        return 0;
    double th = -b - sqrt(disc);
    if (!(th > 0.0 && th < tmax))
        return 0;
    *t = th;
    return 1;
}

int plm_light_intersect(const plm_render_light *l, vec3 o, vec3 d, double tmax, double *t, rgb *radiance)
{
    const plm_light *desc = l->desc;
    int hit = desc->type == PLM_LIGHT_SPHERE ? sphere_hit(desc, o, d, tmax, t)
              : desc->type == PLM_LIGHT_QUAD ? quad_hit(l, o, d, tmax, t)
                                             : 0;
    if (hit)
        *radiance = desc->radiance;
    return hit;
}

double plm_light_pdf(const plm_render_light *l, vec3 p, vec3 wi)
{
    const plm_light *desc = l->desc;
    double t;
    switch (desc->type) {
    case PLM_LIGHT_CONSTANT_ENV:
    case PLM_LIGHT_ENV_MAP:
    case PLM_LIGHT_SKY: {
        double pdf;
        plm_light_environment(l, wi, &pdf);
        return pdf;
    }
    case PLM_LIGHT_DISTANT:
        return 0.0;
    case PLM_LIGHT_SPHERE: {
        vec3 to_center = v3_sub(desc->center, p);
        double d2 = v3_dot(to_center, to_center), r2 = desc->radius * desc->radius;
        if (d2 <= r2 || !sphere_hit(desc, p, wi, INFINITY, &t))
            return 0.0;
        return 1.0 / (PLM_TWO_PI * (1.0 - sqrt(1.0 - r2 / d2)));
    }
    case PLM_LIGHT_QUAD:
        if (!quad_hit(l, p, wi, INFINITY, &t))
            return 0.0;
        return t * t / (fabs(v3_dot(wi, l->normal)) * l->area);
    }
    return 0.0;
}
