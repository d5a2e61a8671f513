/* Sampling building blocks shared by the BCSDFs, the BSDFs and the lights. */
#ifndef PLUMAGE_COMMON_SAMPLING_H
#define PLUMAGE_COMMON_SAMPLING_H

#include <stdint.h>

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
 * The caller owns cdf (n + 1 doubles) and guide (n ints). */
typedef struct plm_distribution1d {
    const double *cdf; /* cdf[0] = 0, cdf[n] = 1 */
    const int *guide;  /* guide[i]: the bin u = i / n falls in, where sampling starts its search */
    int n;
    double total;      /* sum of the weights; 0 means nothing can be sampled */
} plm_distribution1d;

/* Fills cdf and guide from weights; returns the distribution (total 0 if all weights are 0). */
plm_distribution1d plm_distribution1d_build(const double *weights, int n, double *cdf, int *guide);
/* Picks a bin with probability weight/total; *remapped is u rescaled to [0,1)
 * within the bin so it can be reused. */
int plm_distribution1d_sample(const plm_distribution1d *d, double u, double *remapped);
static inline double plm_distribution1d_pmf(const plm_distribution1d *d, int i)
{
    return d->cdf[i + 1] - d->cdf[i];
}

/* Stratified random numbers for the samples of one pixel (docs/rendering.md).
 * Each dimension pair takes its points from a (0,2)-sequence in base 2 (the
 * radical inverse and Sobol's second dimension): any power-of-two run of it
 * puts one point in each cell of every grid of that many equal cells. Per
 * pixel and pair the sample index is shuffled (a bijection of [0, count))
 * and the points are XOR-scrambled by random bits, so each sample on its own
 * is uniform in every pair and the pairs are independent (the estimate stays
 * unbiased), while the count samples of a pixel together are its first
 * count points: spread evenly over each pair's square. */
typedef struct plm_sampler {
    uint64_t key;   /* the pixel's (and the render's seed): scrambles and shuffles */
    uint32_t index; /* this sample, in [0, count) */
    uint32_t count; /* samples per pixel */
} plm_sampler;

/* Pair `dim` of the sample, in [0, 1)^2. */
vec2 plm_sampler_2d(const plm_sampler *s, uint32_t dim);

#endif
