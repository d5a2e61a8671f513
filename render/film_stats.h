/* Measures of a rendered image's noise, from its linear pixels: isolated
 * bright pixels (fireflies) and the image's mean against a reference's.
 * `plumage fireflies` prints them; docs/rendering.md says how they are read. */
#ifndef PLUMAGE_RENDER_FILM_STATS_H
#define PLUMAGE_RENDER_FILM_STATS_H

#include <stddef.h>

/* Pixels whose luminance is more than `ratio` times the median luminance of
 * their 3x3 neighbourhood (themselves included; the image's edge rows and
 * columns repeated beyond it). rgb: width * height * channels floats, the
 * first three channels RGB. A non-finite pixel counts as a firefly. */
long long plm_count_fireflies(const float *rgb, int width, int height, int channels, double ratio);

/* The mean luminance of an image and its difference from a reference of the
 * same size, with the standard error of that difference estimated from the
 * pixels (independent per pixel, as the renderer's samples are):
 * sqrt(sum (a - b)^2) / n. */
typedef struct plm_mean_comparison {
    double mean, reference_mean;
    double difference, standard_error;
} plm_mean_comparison;

double plm_mean_luminance(const float *rgb, size_t pixels, int channels);
plm_mean_comparison plm_compare_means(const float *rgb, const float *reference, size_t pixels, int channels);

#endif
