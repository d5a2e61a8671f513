/* Pearson's chi-square test of a histogram against expected counts, as
 * pbrt-v4 tests its samplers: cells expecting fewer than 5 samples are pooled
 * into one, and the p-value comes from the Wilson-Hilferty cube-root normal
 * approximation (accurate for the hundreds of degrees of freedom such grids
 * have). Header-only, for any test that histograms a sampler. */
#ifndef PLUMAGE_TESTS_CHI_SQUARE_H
#define PLUMAGE_TESTS_CHI_SQUARE_H

#include <math.h>

/* p-value of observed against expected over n cells; 0 when a sample fell
 * where the expected count is exactly 0. */
static double chi_square_test(const double *observed, const double *expected, int n)
{
    double chi2 = 0.0, pooled_expected = 0.0, pooled_observed = 0.0;
    int dof = -1; /* the counts' total is fixed */
    for (int i = 0; i < n; ++i) {
        if (expected[i] == 0.0 && observed[i] > 0.0)
            return 0.0;
        if (expected[i] < 5.0) {
            pooled_expected += expected[i];
            pooled_observed += observed[i];
        } else {
            chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
            ++dof;
        }
    }
    if (pooled_expected > 0.0) {
        chi2 += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) / pooled_expected;
        ++dof;
    }
    if (dof < 1)
        return 1.0;
    double k = dof, z = (cbrt(chi2 / k) - (1.0 - 2.0 / (9.0 * k))) / sqrt(2.0 / (9.0 * k));
    return 0.5 * erfc(z / sqrt(2.0));
}

/* Sidak's per-test threshold on the p-value for `tests` independent tests
 * whose family-wise false-alarm rate is alpha. */
static inline double chi_square_sidak(double alpha, int tests)
{
    return 1.0 - pow(1.0 - alpha, 1.0 / tests);
}

/* The cell of a theta-major grid of nt x np cells over theta in [-pi/2, pi/2]
 * and phi in [-pi, pi] holding the direction (theta, phi); values on or past
 * an edge go to the edge cell. */
static inline int chi_square_cell(double theta, double phi, int nt, int np)
{
    const double pi = 3.14159265358979323846;
    int it = (int)((theta + 0.5 * pi) / pi * nt), ip = (int)((phi + pi) / (2.0 * pi) * np);
    it = it < 0 ? 0 : it >= nt ? nt - 1 : it;
    ip = ip < 0 ? 0 : ip >= np ? np - 1 : ip;
    return it * np + ip;
}

#endif
