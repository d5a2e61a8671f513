/* Statistics shared by the renderer tests (test_render.c, test_feather_bsdf.c):
 * image means from independent samples, with honest standard errors, and a
 * z-test between two estimates. */
#ifndef PLUMAGE_TESTS_RENDER_STATS_H
#define PLUMAGE_TESTS_RENDER_STATS_H

#include "render/render.h"

typedef struct estimate { double mean, se; } estimate;

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
        double x = (x0 + (x1 - x0) * plm_rng_uniform(&rng)) * w->camera.width;
        double y = (y0 + (y1 - y0) * plm_rng_uniform(&rng)) * w->camera.height;
        vec3 o, d;
        plm_camera_ray(&w->camera, x, y, 0.5, 0.5, &o, &d);
        long long rays = 0;
        rgb l = plm_path_radiance(w, o, d, max_depth, est, &rng, &rays);
        assert_true(rgb_is_finite(l));
        double v = rgb_mean(l);
        sum += v;
        sum2 += v * v;
    }
    estimate e;
    e.mean = sum / n;
    e.se = sqrt(fmax(sum2 / n - e.mean * e.mean, 0.0) / n);
    return e;
}

/* The whole film. */
static inline estimate film_mean(const plm_world *w, plm_estimator est, int max_depth, long n, uint64_t seed)
{
    return film_region_mean(w, est, max_depth, n, seed, 0.0, 0.0, 1.0, 1.0);
}

static void assert_agree(estimate a, estimate b, double z_max)
{
    double z = fabs(a.mean - b.mean) / sqrt(a.se * a.se + b.se * b.se + 1e-30);
    if (z > z_max)
        fail_msg("estimates disagree: %.6f +- %.6f vs %.6f +- %.6f (z = %.2f)", a.mean, a.se, b.mean, b.se, z);
}

#endif
