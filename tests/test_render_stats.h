/* Statistics shared by the renderer tests (test_render.c, test_feather_bsdf.c):
 * image means from independent samples, with honest standard errors, a
 * z-test between two estimates and the three estimators' agreement. */
#ifndef PLUMAGE_TESTS_RENDER_STATS_H
#define PLUMAGE_TESTS_RENDER_STATS_H

#include <stdio.h>

#include "render/render.h"

typedef struct estimate { double mean, se; } estimate;

/* The channel mean of one path through film position (x, y) (fractions of
 * the film) and the pinhole; it must be finite. */
static inline double film_sample(const plm_world *w, plm_estimator est, int max_depth, double x, double y,
                                 const plm_sampler *sampler, plm_rng *rng)
{
    vec3 o, d;
    plm_camera_ray(&w->camera, x * w->camera.width, y * w->camera.height, 0.5, 0.5, &o, &d);
    long long rays = 0;
    rgb l = plm_path_radiance(w, o, d, max_depth, est, sampler, rng, &rays);
    assert_true(rgb_is_finite(l));
    return rgb_mean(l);
}

/* The mean of n iid values from their sum and sum of squares, with its standard error. */
static inline estimate iid_estimate(double sum, double sum2, long n)
{
    estimate e;
    e.mean = sum / n;
    e.se = sqrt(fmax(sum2 / n - e.mean * e.mean, 0.0) / n);
    return e;
}

/* Mean radiance (channel mean) over the film rectangle [x0, x1) x [y0, y1)
 * (fractions of the film): n independent samples, each from a uniformly
 * random position in it through the pinhole, so the standard error is that
 * of iid samples. Every sample must be finite. */
static inline estimate film_region_mean(const plm_world *w, plm_estimator est, int max_depth, long n, uint64_t seed,
                                        double x0, double y0, double x1, double y1)
{
    double sum = 0.0, sum2 = 0.0;
    for (long i = 0; i < n; ++i) {
        plm_rng rng;
        plm_rng_seed(&rng, plm_hash64(seed, (uint64_t)i, 99), 3);
        double x = x0 + (x1 - x0) * plm_rng_uniform(&rng), y = y0 + (y1 - y0) * plm_rng_uniform(&rng);
        double v = film_sample(w, est, max_depth, x, y, NULL, &rng);
        sum += v;
        sum2 += v * v;
    }
    return iid_estimate(sum, sum2, n);
}

/* The same mean over the whole film from `keys` independent runs of the
 * stratified sampler (common/sampling.h) as the renderer uses it, each
 * averaging spp samples whose film position (uniform over the film, as if it
 * were one pixel), light and BSDF samples are stratified; the standard error
 * is that of the runs' means, which are iid. */
static inline estimate film_mean_stratified(const plm_world *w, plm_estimator est, int max_depth, long keys,
                                            int spp, uint64_t seed)
{
    double sum = 0.0, sum2 = 0.0;
    for (long k = 0; k < keys; ++k) {
        plm_sampler sampler = {plm_hash64(seed, (uint64_t)k, 7), 0, (uint32_t)spp};
        double run = 0.0;
        for (int i = 0; i < spp; ++i) {
            plm_rng rng;
            plm_rng_seed(&rng, plm_hash64(seed, (uint64_t)k, 100 + (uint64_t)i), 3);
            sampler.index = (uint32_t)i;
            vec2 film = plm_sampler_2d(&sampler, PLM_SAMPLE_PIXEL);
            run += film_sample(w, est, max_depth, film.x, film.y, &sampler, &rng) / spp;
        }
        sum += run;
        sum2 += run * run;
    }
    return iid_estimate(sum, sum2, keys);
}

/* The whole film. */
static inline estimate film_mean(const plm_world *w, plm_estimator est, int max_depth, long n, uint64_t seed)
{
    return film_region_mean(w, est, max_depth, n, seed, 0.0, 0.0, 1.0, 1.0);
}

/* How many combined standard errors apart two independent estimates are. */
static inline double z_score(estimate a, estimate b)
{
    return fabs(a.mean - b.mean) / sqrt(a.se * a.se + b.se * b.se + 1e-30);
}

static void assert_agree(estimate a, estimate b, double z_max)
{
    double z = z_score(a, b);
    if (z > z_max)
        fail_msg("estimates disagree: %.6f +- %.6f vs %.6f +- %.6f (z = %.2f)", a.mean, a.se, b.mean, b.se, z);
}

/* The film's mean by MIS, by light sampling alone and by BSDF sampling alone
 * (n, n and 2n paths; seeds seed, seed + 1, seed + 2) agree within 4.5
 * standard errors pairwise: the three converge to the same image whatever
 * weights MIS gives. Returns the MIS estimate. */
static inline estimate assert_estimators_agree(const plm_world *w, int max_depth, long n, uint64_t seed, const char *what)
{
    estimate mis = film_mean(w, PLM_ESTIMATOR_MIS, max_depth, n, seed);
    estimate nee = film_mean(w, PLM_ESTIMATOR_NEE, max_depth, n, seed + 1);
    estimate bsdf = film_mean(w, PLM_ESTIMATOR_BSDF, max_depth, 2 * n, seed + 2);
    fprintf(stderr, "%s: MIS %.5f +- %.5f, NEE %.5f +- %.5f, BSDF %.5f +- %.5f\n", what, mis.mean, mis.se, nee.mean,
            nee.se, bsdf.mean, bsdf.se);
    assert_agree(mis, nee, 4.5);
    assert_agree(mis, bsdf, 4.5);
    assert_agree(nee, bsdf, 4.5);
    return mis;
}

#endif
