#include "render/film_stats.h"

#include <math.h>

static double luminance(const float *p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

static int clamp_index(int i, int n) { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

/* Median of nine by partial insertion sort: the fifth smallest. */
static double median9(double v[9])
{
    for (int i = 1; i < 9; ++i)
        for (int j = i; j > 0 && v[j - 1] > v[j]; --j) {
            double t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
    return v[4];
}

long long plm_count_fireflies(const float *rgb, int width, int height, int channels, double ratio)
{
    long long count = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double v[9];
            int k = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    size_t i = (size_t)clamp_index(y + dy, height) * width + clamp_index(x + dx, width);
                    v[k++] = luminance(rgb + i * channels);
                }
            double centre = v[4];
            if (!isfinite(centre) || centre > ratio * median9(v))
                ++count;
        }
    return count;
}

double plm_mean_luminance(const float *rgb, size_t pixels, int channels)
{
    double sum = 0.0;
    for (size_t i = 0; i < pixels; ++i)
        sum += luminance(rgb + i * channels);
    return pixels ? sum / pixels : 0.0;
}

plm_mean_comparison plm_compare_means(const float *rgb, const float *reference, size_t pixels, int channels)
{
    plm_mean_comparison c = {plm_mean_luminance(rgb, pixels, channels),
                             plm_mean_luminance(reference, pixels, channels), 0.0, 0.0};
    double squares = 0.0;
    for (size_t i = 0; i < pixels; ++i) {
        double d = luminance(rgb + i * channels) - luminance(reference + i * channels);
        squares += d * d;
    }
    c.difference = c.mean - c.reference_mean;
    c.standard_error = pixels ? sqrt(squares) / pixels : 0.0;
    return c;
}
