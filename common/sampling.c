#include "common/sampling.h"

#include "common/rng.h"

/* plm_sincos rather than the C library's: the trace-only pass takes one of
 * these for every camera sample. */
vec3 plm_sample_cosine_hemisphere(double u1, double u2)
{
    double r = sqrt(u1), s, c;
    plm_sincos(PLM_TWO_PI * u2, &s, &c);
    return v3(r * c, r * s, plm_safe_sqrt(1.0 - u1));
}

vec3 plm_sample_uniform_sphere(double u1, double u2)
{
    double z = 1.0 - 2.0 * u1, r = plm_safe_sqrt(1.0 - z * z), phi = PLM_TWO_PI * u2;
    return v3(r * cos(phi), r * sin(phi), z);
}

/* The last of cdf[lo .. n - 1] at most u, walking from bin lo (u in [0, 1)). */
static int bin_from(const double *cdf, int n, int lo, double u)
{
    while (lo > 0 && cdf[lo] > u)
        --lo;
    while (lo + 1 < n && cdf[lo + 1] <= u)
        ++lo;
    return lo;
}

plm_distribution1d plm_distribution1d_build(const double *weights, int n, double *cdf, int *guide)
{
    plm_distribution1d d = {cdf, guide, n, 0.0};
    cdf[0] = 0.0;
    for (int i = 0; i < n; ++i)
        cdf[i + 1] = cdf[i] + weights[i];
    d.total = cdf[n];
    for (int i = 1; i <= n; ++i)
        cdf[i] = d.total > 0.0 ? cdf[i] / d.total : (double)i / n;
    cdf[n] = 1.0;
    for (int i = 0; i < n; ++i)
        guide[i] = bin_from(cdf, n, i > 0 ? guide[i - 1] : 0, (double)i / n);
    return d;
}

int plm_distribution1d_sample(const plm_distribution1d *d, double u, double *remapped)
{
    /* The bin whose cdf entry is the last at most u (zero-weight bins have
     * the next one's entry, so they are never chosen): from the guide's bin
     * for u's 1/n-th of [0, 1), a walk of about as many bins as that stretch
     * of the CDF holds (a sky's rises at the sun), instead of a binary search. */
    int g = u > 0.0 ? (int)(u * d->n) : 0;
    int lo = bin_from(d->cdf, d->n, d->guide[g < d->n ? g : d->n - 1], u);
    double width = d->cdf[lo + 1] - d->cdf[lo];
    if (remapped) {
        double t = width > 0.0 ? (u - d->cdf[lo]) / width : 0.0;
        *remapped = t < 0.0 ? 0.0 : (t >= 1.0 ? 0x1.fffffffffffffp-1 : t);
    }
    return lo;
}

/* ---- the stratified sampler ---------------------------------------------- */

static uint32_t reverse_bits(uint32_t x)
{
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    return ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
}

/* Sobol's second dimension as 32 bits: index bit k adds column k of its
 * generator matrix (the binary Pascal triangle); the first dimension, the
 * radical inverse, is the bit reversal. */
static uint32_t sobol_second(uint32_t i)
{
    uint32_t x = 0;
    for (uint32_t column = 1u << 31; i; i >>= 1, column ^= column >> 1)
        if (i & 1u)
            x ^= column;
    return x;
}

/* A bijection of [0, n) chosen by key: xor, odd multiply and xor-shift, each
 * invertible on the bits of the next power of two, repeated on values that
 * land outside [0, n) (cycle walking) until one lands inside. */
static uint32_t shuffle(uint32_t i, uint32_t n, uint64_t key)
{
    if (n < 2 || i >= n)
        return i;
    uint32_t mask = n - 1;
    int bits = 0;
    for (uint32_t m = mask; m; m >>= 1)
        ++bits;
    mask = bits >= 32 ? 0xffffffffu : (1u << bits) - 1u;
    uint32_t a = (uint32_t)key, b = (uint32_t)(key >> 32) | 1u;
    do {
        i = ((i ^ a) * b) & mask;
        i ^= i >> (bits / 2 + 1);
        i = (i * 0x2c1b3c6du + (a >> 16)) & mask; /* 0x2c1b3c6d is odd */
    } while (i >= n);
    return i;
}

vec2 plm_sampler_2d(const plm_sampler *s, uint32_t dim)
{
    /* plm_hash64(key, dim, 1) and (key, dim, 2), their first two words folded in once. */
    uint64_t h = plm_hash64_step(plm_hash64_step(0, s->key), dim);
    uint64_t scramble = plm_hash64_step(h, 1), order = plm_hash64_step(h, 2);
    uint32_t i = shuffle(s->index, s->count, order);
    uint32_t x = reverse_bits(i) ^ (uint32_t)scramble, y = sobol_second(i) ^ (uint32_t)(scramble >> 32);
    return v2(x * 0x1p-32, y * 0x1p-32);
}
