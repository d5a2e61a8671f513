#include "render/light.h"

#include <stdlib.h>
#include <string.h>

static double texel_luminance(const plm_image *im, int x, int y)
{
    const float *p = im->pixels + ((size_t)y * im->width + x) * im->channels;
    double l = rgb_luminance(rgb_make(p[0], p[1], p[2]));
    return isfinite(l) && l > 0.0 ? l : 0.0;
}

static rgb texel_rgb(const plm_image *im, int x, int y)
{
    const float *p = im->pixels + ((size_t)y * im->width + x) * im->channels;
    rgb c = rgb_make(p[0], p[1], p[2]);
    return rgb_is_finite(c) ? c : rgb_gray(0.0);
}

static plm_result envmap_init(const plm_image *im, plm_envmap *env, plm_error *err)
{
    int w = im->width, h = im->height;
    env->image = im;
    env->marginal_cdf = malloc(sizeof(double) * (size_t)(h + 1));
    env->conditional_cdf = malloc(sizeof(double) * (size_t)h * (size_t)(w + 1));
    env->conditional = malloc(sizeof *env->conditional * (size_t)h);
    env->marginal_guide = malloc(sizeof(int) * (size_t)h);
    env->conditional_guide = malloc(sizeof(int) * (size_t)h * (size_t)w);
    double *weights = malloc(sizeof(double) * (size_t)(w > h ? w : h));
    double *row_totals = malloc(sizeof(double) * (size_t)h);
    if (!env->marginal_cdf || !env->conditional_cdf || !env->conditional || !env->marginal_guide ||
        !env->conditional_guide || !weights || !row_totals) {
        free(weights);
        free(row_totals);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a %dx%d environment map", w, h);
    }
    for (int y = 0; y < h; ++y) {
        double sin_theta = sin(PLM_PI * (y + 0.5) / h); /* solid angle of the row's texels */
        for (int x = 0; x < w; ++x)
            weights[x] = texel_luminance(im, x, y) * sin_theta;
        env->conditional[y] = plm_distribution1d_build(weights, w, env->conditional_cdf + (size_t)y * (w + 1),
                                                       env->conditional_guide + (size_t)y * w);
        row_totals[y] = env->conditional[y].total;
    }
    env->marginal = plm_distribution1d_build(row_totals, h, env->marginal_cdf, env->marginal_guide);
    free(weights);
    free(row_totals);
    return PLM_OK;
}

plm_result plm_render_light_init(const plm_light *desc, plm_render_light *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    out->desc = desc;
    if (desc->type == PLM_LIGHT_QUAD) {
        vec3 c = v3_cross(desc->edge_u, desc->edge_v);
        out->area = v3_length(c);
        out->normal = v3_scale(c, 1.0 / out->area);
    }
    if (desc->type == PLM_LIGHT_ENV_MAP)
        return envmap_init(&desc->image, &out->env, err);
    return PLM_OK;
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

/* plm_atan2 and plm_acos (via plm_safe_acos) rather than the C library's:
 * this runs for every escaping ray and every light sample's density. */
vec2 plm_envmap_uv(double rotation, vec3 d)
{
    double phi = plm_atan2(d.x, -d.z) - rotation;
    double u = phi / PLM_TWO_PI + 0.5;
    u -= floor(u);
    return v2(u, plm_safe_acos(d.y) / PLM_PI);
}

/* The direction of uv and its sin(theta), which a density over the sphere divides by. */
static vec3 envmap_direction(double rotation, vec2 uv, double *sin_theta)
{
    double cos_theta, sin_phi, cos_phi;
    plm_sincos(PLM_PI * uv.y, sin_theta, &cos_theta);
    plm_sincos(PLM_TWO_PI * (uv.x - 0.5) + rotation, &sin_phi, &cos_phi);
    return v3(*sin_theta * sin_phi, cos_theta, -*sin_theta * cos_phi);
}

vec3 plm_envmap_direction(double rotation, vec2 uv)
{
    double sin_theta;
    return envmap_direction(rotation, uv, &sin_theta);
}

/* Texel holding uv: the piecewise-constant lookup that the sampling density matches. */
static void envmap_texel(const plm_image *im, vec2 uv, int *x, int *y)
{
    *x = (int)(uv.x * im->width);
    *y = (int)(uv.y * im->height);
    *x = *x < 0 ? 0 : (*x >= im->width ? im->width - 1 : *x);
    *y = *y < 0 ? 0 : (*y >= im->height ? im->height - 1 : *y);
}

/* Density over the sphere of texel (x, y) at sin(theta): p(u, v) / (2 pi^2 sin theta),
 * p(u, v) = pmf(texel) * width * height. */
static double envmap_texel_pdf(const plm_envmap *env, int x, int y, double sin_theta)
{
    if (env->marginal.total <= 0.0 || sin_theta <= 0.0)
        return 0.0;
    double p = plm_distribution1d_pmf(&env->marginal, y) * plm_distribution1d_pmf(&env->conditional[y], x) *
               (double)env->image->width * env->image->height;
    return p / (2.0 * PLM_PI * PLM_PI * sin_theta);
}

rgb plm_light_environment(const plm_render_light *l, vec3 d, double *pdf)
{
    const plm_light *desc = l->desc;
    if (desc->type == PLM_LIGHT_CONSTANT_ENV) {
        if (pdf)
            *pdf = 1.0 / (4.0 * PLM_PI);
        return desc->radiance;
    }
    /* One direction -> (u, v) for the radiance and the density: its atan2
     * and acos are most of a lookup. sin(theta) as plm_light_sample_from's
     * envmap_direction takes it, so that the two densities agree. */
    vec2 uv = plm_envmap_uv(desc->rotation, d);
    int x, y;
    envmap_texel(&desc->image, uv, &x, &y);
    if (pdf) {
        double sin_theta, cos_theta;
        plm_sincos(PLM_PI * uv.y, &sin_theta, &cos_theta);
        *pdf = envmap_texel_pdf(&l->env, x, y, sin_theta);
    }
    return rgb_mul(desc->radiance, texel_rgb(&desc->image, x, y));
}

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

int plm_light_sample_from(const plm_render_light *l, vec3 p, double u1, double u2, plm_light_sample *s)
{
    const plm_light *desc = l->desc;
    s->is_delta = 0;
    s->dist = INFINITY;
    switch (desc->type) {
    case PLM_LIGHT_CONSTANT_ENV:
        s->wi = plm_sample_uniform_sphere(u1, u2);
        s->radiance = desc->radiance;
        s->pdf = 1.0 / (4.0 * PLM_PI);
        return 1;
    case PLM_LIGHT_ENV_MAP: {
        const plm_envmap *env = &l->env;
        if (env->marginal.total <= 0.0)
            return 0;
        double ru, rv;
        int y = plm_distribution1d_sample(&env->marginal, u1, &rv);
        int x = plm_distribution1d_sample(&env->conditional[y], u2, &ru);
        vec2 uv = v2((x + ru) / env->image->width, (y + rv) / env->image->height);
        double sin_theta;
        s->wi = envmap_direction(desc->rotation, uv, &sin_theta);
        /* The sampled texel's radiance and density, which a lookup of wi finds
         * again but for rounding at the texel's edges. */
        s->radiance = rgb_mul(desc->radiance, texel_rgb(env->image, x, y));
        s->pdf = envmap_texel_pdf(env, x, y, sin_theta);
        return s->pdf > 0.0;
    }
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
        return 1.0 / (4.0 * PLM_PI);
    case PLM_LIGHT_ENV_MAP: {
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
