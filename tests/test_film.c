/* The film's measures and picture: fireflies counted against their 3x3
 * neighbourhood, and the means of an image and a reference compared with
 * the standard error the pixels give. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <math.h>
#include <stdlib.h>

#include "common/rng.h"
#include "render/film_stats.h"

/* A 20 x 10 grey image with bright pixels: lone ones inside, on an edge
 * and in a corner (the edge repeated beyond the image: a corner pixel is 4
 * of its 9) count; of a 3 x 3 bright block only the corners count (4 of
 * their 9 are bright, 6 of an edge pixel's); a non-finite pixel counts. */
static void fireflies_are_isolated_bright_pixels(void **state)
{
    (void)state;
    enum { W = 20, H = 10 };
    float img[W * H * 3];
    for (int i = 0; i < W * H * 3; ++i)
        img[i] = 0.2f;
    const int lone[][2] = {{3, 3}, {10, 5}, {19, 5}, {0, 9}};
    for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 3; ++c)
            img[3 * (lone[k][1] * W + lone[k][0]) + c] = 5.0f;
    for (int y = 5; y < 8; ++y)
        for (int x = 14; x < 17; ++x)
            img[3 * (y * W + x) + 1] = 9.0f; /* green only: luminance 6.5 */
    assert_int_equal(plm_count_fireflies(img, W, H, 3, 5.0), 4 + 4);
    /* The lone pixels are 25 times the grey, the block's 32.6 times. */
    assert_int_equal(plm_count_fireflies(img, W, H, 3, 25.0), 4);
    assert_int_equal(plm_count_fireflies(img, W, H, 3, 24.9), 8);
    assert_int_equal(plm_count_fireflies(img, W, H, 3, 33.0), 0);
    img[3 * (1 * W + 1)] = NAN;
    assert_int_equal(plm_count_fireflies(img, W, H, 3, 33.0), 1);
}

/* Two noisy images of the same mean agree (|z| small); one 2% brighter is
 * many standard errors off. The standard error is the spread of the
 * pixels' differences over sqrt(n), computed here independently. */
static void means_agree_within_their_noise(void **state)
{
    (void)state;
    enum { N = 20000 };
    float *a = malloc(sizeof(float) * 3 * N), *b = malloc(sizeof(float) * 3 * N), *c = malloc(sizeof(float) * 3 * N);
    assert_true(a && b && c);
    plm_rng rng;
    plm_rng_seed(&rng, 8, 8);
    double sq = 0.0;
    for (int i = 0; i < N; ++i) {
        double x = 1.0 + 0.3 * (plm_rng_uniform(&rng) - 0.5), y = 1.0 + 0.3 * (plm_rng_uniform(&rng) - 0.5);
        for (int k = 0; k < 3; ++k)
            a[3 * i + k] = (float)x, b[3 * i + k] = (float)y, c[3 * i + k] = (float)(1.02 * x);
        sq += (x - y) * (x - y);
    }
    plm_mean_comparison same = plm_compare_means(a, b, N, 3);
    assert_double_near(same.standard_error, sqrt(sq) / N, 1e-6 * sqrt(sq) / N);
    assert_true(fabs(same.difference / same.standard_error) < 4.0);
    plm_mean_comparison brighter = plm_compare_means(c, b, N, 3);
    assert_true(brighter.difference / brighter.standard_error > 10.0);
    assert_double_near(plm_mean_luminance(a, N, 3), same.mean, 0.0);
    free(a), free(b), free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fireflies_are_isolated_bright_pixels),
        cmocka_unit_test(means_agree_within_their_noise),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
