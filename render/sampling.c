#include "render/sampling.h"

vec3 plm_sample_cosine_hemisphere(double u1, double u2)
{
    double r = sqrt(u1), phi = PLM_TWO_PI * u2;
    return v3(r * cos(phi), r * sin(phi), plm_safe_sqrt(1.0 - u1));
}

vec3 plm_sample_uniform_sphere(double u1, double u2)
{
    double z = 1.0 - 2.0 * u1, r = plm_safe_sqrt(1.0 - z * z), phi = PLM_TWO_PI * u2;
    return v3(r * cos(phi), r * sin(phi), z);
}

plm_distribution1d plm_distribution1d_build(const double *weights, int n, double *cdf)
{
    plm_distribution1d d = {cdf, n, 0.0};
    cdf[0] = 0.0;
    for (int i = 0; i < n; ++i)
        cdf[i + 1] = cdf[i] + weights[i];
    d.total = cdf[n];
    for (int i = 1; i <= n; ++i)
        cdf[i] = d.total > 0.0 ? cdf[i] / d.total : (double)i / n;
    cdf[n] = 1.0;
    return d;
}

int plm_distribution1d_sample(const plm_distribution1d *d, double u, double *remapped)
{
    /* Binary search for the last cdf entry <= u, skipping zero-weight bins. */
    int lo = 0, hi = d->n;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (d->cdf[mid] <= u)
            lo = mid;
        else
            hi = mid;
    }
    while (lo + 1 < d->n && d->cdf[lo + 1] == d->cdf[lo] && d->cdf[lo + 1] <= u)
        ++lo;
    double width = d->cdf[lo + 1] - d->cdf[lo];
    if (remapped) {
        double t = width > 0.0 ? (u - d->cdf[lo]) / width : 0.0;
        *remapped = t < 0.0 ? 0.0 : (t >= 1.0 ? 0x1.fffffffffffffp-1 : t);
    }
    return lo;
}
