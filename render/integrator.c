#include "render/integrator.h"

#include "common/sampling.h"

typedef enum segment_end { END_ESCAPED, END_LIGHT, END_SURFACE } segment_end;

typedef struct segment {
    double t;     /* END_SURFACE, END_LIGHT: the ray parameter of the end */
    plm_hit hit;  /* END_SURFACE */
    int light;    /* END_LIGHT: index of the area light */
    rgb emitted;  /* END_LIGHT */
} segment;

/* The numbers of one depth beyond the sampler's pairs: the passing of the
 * ray that leaves it (a seed hashed per surface plus a shift: the sampler
 * keeps the seed for all of a pixel's samples and stratifies the shift) and
 * the third BSDF number at the vertex that ray finds. Drawn on first need:
 * a ray that escapes meets no surface and needs none. */
typedef struct depth_numbers {
    const plm_sampler *sampler;
    plm_rng *rng;
    int depth, drawn;
    uint64_t seed;
    vec2 more;
} depth_numbers;

static void draw_numbers(depth_numbers *n)
{
    if (n->drawn)
        return;
    if (n->sampler) {
        n->seed = plm_hash64(n->sampler->key, (uint64_t)n->depth, 3);
        n->more = plm_sampler_2d(n->sampler, PLM_SAMPLE_DIM(PLM_SAMPLE_MORE, n->depth));
    } else {
        n->seed = ((uint64_t)plm_rng_u32(n->rng) << 32) | plm_rng_u32(n->rng);
        n->more = v2(0.0, plm_rng_uniform(n->rng));
    }
    n->drawn = 1;
}

/* plm_passing's draw. */
static void draw_passing(void *arg, uint64_t *seed, double *shift)
{
    depth_numbers *n = arg;
    draw_numbers(n);
    *seed = n->seed;
    *shift = n->more.x;
}

/* Follows o + t d until it scatters off a surface, hits an area light or
 * escapes; surfaces it meets are passed with their transmission probability,
 * decided by the depth's numbers. */
static segment_end trace_segment(const plm_world *w, vec3 o, vec3 d, double spread, depth_numbers *numbers,
                                 segment *seg, long long *rays)
{
    double t_surface = INFINITY, t;
    ++*rays;
    plm_passing passing = {0, 0.0, draw_passing, numbers};
    int surface = plm_world_intersect_passing(w, o, d, INFINITY, &passing, spread, &t_surface, &seg->hit);
    int light = -1;
    for (int i = 0; i < w->light_count; ++i) {
        rgb le;
        if (plm_light_intersect(&w->lights[i], o, d, t_surface, &t, &le)) {
            t_surface = t;
            light = i;
            seg->emitted = le;
        }
    }
    seg->t = t_surface;
    if (light >= 0) {
        seg->light = light;
        return END_LIGHT;
    }
    return surface ? END_SURFACE : END_ESCAPED;
}

double plm_shadow_transmittance(const plm_world *w, vec3 o, vec3 d, double dist, long long *rays)
{
    double tmax = dist < INFINITY ? dist * (1.0 - 1e-6) - w->epsilon : INFINITY;
    if (!(tmax > 0.0))
        return 1.0;
    ++*rays;
    return plm_world_transmittance(w, o, d, tmax);
}

/* Radiance an escaped or light-hitting ray brings back, MIS-weighted
 * against light sampling from the previous vertex when that could have found
 * it; known_pdf, if not NULL, is the light's density of d (plm_light_pdf). */
static rgb emission_weight(const plm_world *w, int light, rgb le, vec3 prev_p, vec3 d, double prev_pdf,
                           int counted_fully, plm_estimator est, const double *known_pdf)
{
    if (counted_fully || est == PLM_ESTIMATOR_BSDF)
        return le;
    if (est == PLM_ESTIMATOR_NEE)
        return rgb_gray(0.0);
    double light_pdf = (known_pdf ? *known_pdf : plm_light_pdf(&w->lights[light], prev_p, d)) *
                       plm_world_light_pick(w, light);
    return rgb_scale(le, plm_power_heuristic(prev_pdf, light_pdf));
}

/* Two uniforms: the sampler's pair dim, or rng's. */
static vec2 sample_2d(const plm_sampler *sampler, uint32_t dim, plm_rng *rng)
{
    if (sampler)
        return plm_sampler_2d(sampler, dim);
    double u1 = plm_rng_uniform(rng);
    return v2(u1, plm_rng_uniform(rng));
}

/* Next-event estimation: one light chosen by the light it brings
 * (plm_world_pick_light), one sample of it (u). */
static rgb direct_light(const plm_world *w, const plm_hit *hit, const plm_bsdf *bsdf, vec2 u, plm_rng *rng,
                        plm_estimator est, long long *rays)
{
    int li = plm_world_pick_light(w, plm_rng_uniform(rng));
    plm_light_sample ls;
    if (!plm_light_sample_from(&w->lights[li], hit->p, u.x, u.y, &ls) || rgb_is_black(ls.radiance))
        return rgb_gray(0.0);
    /* The shadow ray before the BSDF: a feather's eval costs more than the
     * ray, and in a pelt nearly half the light samples are hidden. */
    vec3 o = plm_world_offset(w, hit, ls.wi);
    /* Area lights stop every ray: one in front of the sampled light hides it, as it does for bounce rays. */
    for (int i = 0; i < w->light_count; ++i) {
        double t;
        rgb le;
        if (i != li && plm_light_intersect(&w->lights[i], o, ls.wi, ls.dist, &t, &le))
            return rgb_gray(0.0);
    }
    double visible = plm_shadow_transmittance(w, o, ls.wi, ls.dist, rays);
    if (visible <= 0.0)
        return rgb_gray(0.0);
    /* MIS weighs against the BSDF's sampling, technique by technique (optics/bsdf.h). */
    int weighted = !ls.is_delta && est != PLM_ESTIMATOR_NEE;
    double light_pdf = plm_world_light_pick(w, li) * ls.pdf;
    if (!(light_pdf > 0.0))
        return rgb_gray(0.0);
    rgb f = weighted ? plm_bsdf_eval_mis(bsdf, ls.wi, light_pdf) : plm_bsdf_eval(bsdf, ls.wi);
    if (rgb_is_black(f))
        return rgb_gray(0.0);
    return rgb_scale(rgb_mul(f, ls.radiance), visible / light_pdf);
}

/* Where the ray o + t d, t in (0, tmax), meets the ground from above. */
static int ground_hit(const plm_ground *g, vec3 o, vec3 d, double tmax, double *t)
{
    double above = v3_dot(o, g->normal) - g->height, down = -v3_dot(d, g->normal);
    if (!g->enabled || !(above > 0.0 && down > 0.0))
        return 0;
    *t = above / down;
    return *t < tmax;
}

/* A camera ray that reaches the ground (the shadow catcher) before anything
 * else: the background it would have seen along d, times the share of the
 * lights' irradiance that the scene leaves the ground at p. One light sample
 * (u) estimates the share the scene takes away, the sample's irradiance
 * times its blocked fraction over the unobstructed irradiance: unbiased,
 * and without noise where nothing is in the way (a single sample can take
 * away more than all, a pixel's mean cannot). Area lights are not part of it. */
static rgb catch_shadow(const plm_world *w, vec3 p, vec3 d, vec2 u, plm_rng *rng, long long *rays)
{
    rgb background = rgb_gray(0.0);
    for (int i = 0; i < w->light_count; ++i)
        if (plm_light_is_infinite(&w->lights[i]) && w->lights[i].desc->visible)
            background = rgb_add(background, plm_light_environment(&w->lights[i], d, NULL));
    int li = plm_world_pick_light(w, plm_rng_uniform(rng));
    const plm_render_light *l = &w->lights[li];
    vec3 n = w->ground.normal;
    plm_light_sample ls;
    if (rgb_is_black(background) || !(plm_light_is_infinite(l) || l->desc->type == PLM_LIGHT_DISTANT) ||
        !plm_light_sample_from(l, p, u.x, u.y, &ls) || !(v3_dot(ls.wi, n) > 0.0))
        return background;
    double pdf = plm_world_light_pick(w, li) * ls.pdf;
    if (!(pdf > 0.0))
        return background;
    double blocked = 1.0 - plm_shadow_transmittance(w, v3_madd(p, n, w->epsilon), ls.wi, ls.dist, rays);
    rgb e = rgb_scale(ls.radiance, v3_dot(ls.wi, n) * blocked / pdf), e0 = w->ground.irradiance;
    rgb kept = rgb_make(e0.r > 0.0 ? 1.0 - e.r / e0.r : 1.0, e0.g > 0.0 ? 1.0 - e.g / e0.g : 1.0,
                        e0.b > 0.0 ? 1.0 - e.b / e0.b : 1.0);
    return rgb_mul(background, kept);
}

rgb plm_path_radiance(const plm_world *w, vec3 o, vec3 d, int max_depth, plm_estimator est,
                      const plm_sampler *sampler, plm_rng *rng, long long *rays)
{
    rgb radiance = rgb_gray(0.0), beta = rgb_gray(1.0);
    vec3 prev_p = o;
    double prev_pdf = 0.0;
    segment seg;
    plm_bsdf bsdf;
    for (int depth = 0;; ++depth) {
        depth_numbers numbers = {sampler, rng, depth, 0, 0, {0.0, 0.0}};
        /* Camera rays carry the pixel cone (near-field shading); after a scattering event it is lost. */
        segment_end end =
            trace_segment(w, o, d, depth == 0 ? w->camera.pixel_spread : 0.0, &numbers, &seg, rays);
        double t_ground;
        if (depth == 0 && ground_hit(&w->ground, o, d, end == END_ESCAPED ? INFINITY : seg.t, &t_ground)) {
            vec2 u = sample_2d(sampler, PLM_SAMPLE_DIM(PLM_SAMPLE_LIGHT, 0), rng);
            radiance = catch_shadow(w, v3_madd(o, d, t_ground), d, u, rng, rays);
            break;
        }
        if (end == END_LIGHT) {
            rgb le = emission_weight(w, seg.light, seg.emitted, prev_p, d, prev_pdf, depth == 0, est, NULL);
            radiance = rgb_add(radiance, rgb_mul(beta, le));
            break;
        }
        if (end == END_ESCAPED) {
            for (int i = 0; i < w->light_count; ++i)
                /* Camera rays (passing vanes or not) do not see a light hidden from the camera. */
                if (plm_light_is_infinite(&w->lights[i]) && (depth > 0 || w->lights[i].desc->visible)) {
                    /* The radiance's lookup gives the density MIS needs, when it does;
                     * otherwise none is passed on, so a weighting that needs one looks it up. */
                    double pdf, *known = depth > 0 && est == PLM_ESTIMATOR_MIS ? &pdf : NULL;
                    rgb le = plm_light_environment(&w->lights[i], d, known);
                    le = emission_weight(w, i, le, prev_p, d, prev_pdf, depth == 0, est, known);
                    radiance = rgb_add(radiance, rgb_mul(beta, le));
                }
            break;
        }
        if (depth >= max_depth)
            break;
        /* Drawn before rng serves the vertex, so its sequence does not depend on the ray's passing. */
        draw_numbers(&numbers);
        vec3 wo = v3_neg(d);
        plm_material_bsdf(&seg.hit, wo, rng, &bsdf);
        if (est != PLM_ESTIMATOR_BSDF && w->light_count > 0) {
            vec2 u = sample_2d(sampler, PLM_SAMPLE_DIM(PLM_SAMPLE_LIGHT, depth), rng);
            radiance = rgb_add(radiance, rgb_mul(beta, direct_light(w, &seg.hit, &bsdf, u, rng, est, rays)));
        }
        /* The pair drives the choices that shape the lobe most (the feather's
         * component and a fiber's azimuth bin or lobe, then theta_i). */
        vec2 u = sample_2d(sampler, PLM_SAMPLE_DIM(PLM_SAMPLE_BSDF, depth), rng);
        plm_bsdf_sample_rec s;
        if (!plm_bsdf_sample(&bsdf, u.x, u.y, numbers.more.y, &s))
            break;
        beta = rgb_mul(beta, s.weight);
        if (rgb_is_black(beta)) /* nothing more can arrive (and 0 x an infinite sky would be NaN) */
            break;
        prev_pdf = s.pdf;
        prev_p = seg.hit.p;
        d = s.wi;
        o = plm_world_offset(w, &seg.hit, d);
        /* Russian roulette once paths have a few bounces; unbiased by the 1/(1-q) reweighting. */
        if (depth >= 3) {
            double q = fmax(0.05, 1.0 - rgb_max(beta));
            if (plm_rng_uniform(rng) < q)
                break;
            beta = rgb_scale(beta, 1.0 / (1.0 - q));
        }
    }
    return radiance;
}

int plm_path_trace_only(const plm_world *w, vec3 o, vec3 d, int max_depth, plm_rng *rng)
{
    int rays = 0;
    double t;
    plm_hit hit;
    for (int depth = 0; depth <= max_depth; ++depth) {
        ++rays;
        if (!plm_world_intersect(w, o, d, INFINITY, &t, &hit))
            break;
        vec3 n = v3_dot(d, hit.ng) < 0.0 ? hit.ng : v3_neg(hit.ng);
        frame f = frame_from_z(n);
        d = frame_to_world(&f, plm_sample_cosine_hemisphere(plm_rng_uniform(rng), plm_rng_uniform(rng)));
        o = plm_world_offset(w, &hit, d);
    }
    return rays;
}
