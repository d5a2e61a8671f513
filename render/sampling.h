/* Sampling building blocks shared by the BCSDFs, the BSDFs and the lights. */
#ifndef PLUMAGE_RENDER_SAMPLING_H
#define PLUMAGE_RENDER_SAMPLING_H

#include "common/vec.h"

/* Cosine-weighted direction about +z from two uniforms; pdf = cos(theta)/pi. */
vec3 plm_sample_cosine_hemisphere(double u1, double u2);
/* Uniform direction on the unit sphere; pdf = 1/(4 pi). */
vec3 plm_sample_uniform_sphere(double u1, double u2);

/* Power heuristic (beta = 2) for multiple importance sampling. */
static inline double plm_power_heuristic(double pdf_a, double pdf_b)
{
    double a = pdf_a * pdf_a, b = pdf_b * pdf_b;
    return a + b > 0.0 ? a / (a + b) : 0.0;
}

/* A piecewise-constant 1D distribution over n bins from non-negative weights.
 * The caller owns cdf (n + 1 doubles). */
typedef struct plm_distribution1d {
    const double *cdf; /* cdf[0] = 0, cdf[n] = 1 */
    int n;
    double total;      /* sum of the weights; 0 means nothing can be sampled */
} plm_distribution1d;

/* Fills cdf from weights; returns the distribution (total 0 if all weights are 0). */
plm_distribution1d plm_distribution1d_build(const double *weights, int n, double *cdf);
/* Picks a bin with probability weight/total; *remapped is u rescaled to [0,1)
 * within the bin so it can be reused. */
int plm_distribution1d_sample(const plm_distribution1d *d, double u, double *remapped);
static inline double plm_distribution1d_pmf(const plm_distribution1d *d, int i)
{
    return d->cdf[i + 1] - d->cdf[i];
}

#endif
