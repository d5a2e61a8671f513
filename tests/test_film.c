/* The film's picture and measures: the standard view is the clamp, the
 * filmic view keeps mid grey and rolls highlights off to white through their
 * hue, exposure and white balance do what they say; fireflies counted
 * against their 3x3 neighbourhood, and the means of an image and a
 * reference compared with the standard error the pixels give. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <math.h>
#include <stdlib.h>

#include "common/image_io.h"
#include "common/rng.h"
#include "render/colour.h"
#include "render/film.h"
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

static rgb show(plm_view view, double exposure, double kelvin, rgb c)
{
    plm_picture p = {view, exposure, kelvin};
    plm_picture_map map;
    plm_picture_map_init(&p, &map);
    return plm_picture_apply(&map, c);
}

/* The standard view is today's clamp: scale, clamp to [0, 1], sRGB. */
static void standard_view_is_the_clamp(void **state)
{
    (void)state;
    const double v[] = {0.0, 0.01, 0.18, 0.5, 0.99, 1.0, 3.0};
    for (int i = 0; i < 7; ++i) {
        rgb d = show(PLM_VIEW_STANDARD, 1.0, 6504.0, rgb_make(v[i], v[i] / 2, v[i] / 4));
        assert_double_near(d.r, plm_srgb_encode(fmin(2.0 * v[i], 1.0)), 1e-12);
        assert_double_near(d.b, plm_srgb_encode(fmin(0.5 * v[i], 1.0)), 1e-12);
    }
}

/* Filmic: black stays black, mid grey shows as the sRGB curve shows it,
 * greys rise monotonically and stay apart up to 6.5 stops above grey, where
 * they reach white; exposure is a factor of 2 per stop. */
static void filmic_view_keeps_grey_and_separates_highlights(void **state)
{
    (void)state;
    assert_double_near(show(PLM_VIEW_FILMIC, 0.0, 6504.0, rgb_gray(0.0)).g, 0.0, 1e-12);
    assert_double_near(show(PLM_VIEW_FILMIC, 0.0, 6504.0, rgb_gray(0.18)).g, plm_srgb_encode(0.18), 1e-9);
    double last = 0.0;
    for (double v = 0.001; v < 0.18 * pow(2.0, 6.5) * 0.999; v *= 1.1) {
        double d = show(PLM_VIEW_FILMIC, 0.0, 6504.0, rgb_gray(v)).g;
        assert_true(d > last && d < 1.0);
        last = d;
    }
    assert_double_near(show(PLM_VIEW_FILMIC, 0.0, 6504.0, rgb_gray(0.18 * pow(2.0, 6.5))).g, 1.0, 1e-9);
    assert_double_near(show(PLM_VIEW_FILMIC, 0.0, 6504.0, rgb_gray(100.0)).r, 1.0, 1e-12);
    /* Highlights the clamp makes equal white stay apart: 2 and 4 differ by more than 5 of 255 steps. */
    double two = show(PLM_VIEW_FILMIC, 0.0, 6504.0, rgb_gray(2.0)).g, four = show(PLM_VIEW_FILMIC, 0.0, 6504.0, rgb_gray(4.0)).g;
    assert_true(four - two > 5.0 / 255.0);
    /* The toe keeps the darkest stops apart from black: 0.01 within 20% of the sRGB curve's value. */
    assert_true(fabs(show(PLM_VIEW_FILMIC, 0.0, 6504.0, rgb_gray(0.01)).g / plm_srgb_encode(0.01) - 1.0) < 0.2);
    rgb a = show(PLM_VIEW_FILMIC, 1.0, 6504.0, rgb_make(0.3, 0.2, 0.05)), b = show(PLM_VIEW_FILMIC, 0.0, 6504.0, rgb_make(0.6, 0.4, 0.1));
    assert_double_near(a.r, b.r, 1e-12);
    assert_double_near(a.b, b.b, 1e-12);
}

/* A saturated green made ever brighter than grey keeps its hue's order
 * (green first), loses purity steadily and ends white, where the clamp
 * holds it at a flat primary-like green far above 1. */
static void filmic_view_takes_bright_colours_to_white(void **state)
{
    (void)state;
    double last_purity = 1.0;
    for (double k = 1.0; k <= 512.0; k *= 2.0) {
        rgb d = show(PLM_VIEW_FILMIC, 0.0, 6504.0, rgb_make(0.03 * k, 0.4 * k, 0.08 * k));
        double purity = (d.g - fmin(d.r, d.b)) / d.g;
        assert_true(d.g >= d.b && d.b >= d.r);
        assert_true(purity <= last_purity + 1e-12);
        last_purity = purity;
    }
    assert_true(last_purity < 0.01);
    rgb clamp = show(PLM_VIEW_STANDARD, 0.0, 6504.0, rgb_make(0.03 * 8, 0.4 * 8, 0.08 * 8));
    assert_true((clamp.g - clamp.r) / clamp.g > 0.4);
}

/* White balance: 6504 K changes nothing; at T the colour of a blackbody of
 * T shows as a blackbody of 6504 K does (neutral), and 3200 K makes a grey
 * bluer. */
static void white_balance_neutralises_its_temperature(void **state)
{
    (void)state;
    plm_picture none = {PLM_VIEW_STANDARD, 0.0, 6504.0};
    plm_picture_map map;
    plm_picture_map_init(&none, &map);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            assert_double_near(map.m[i][j], i == j, 0.0);
    const double kelvins[] = {2000.0, 3200.0, 5000.0, 9000.0};
    double x, y;
    plm_blackbody_chromaticity(6504.0, &x, &y);
    rgb neutral = plm_xyz_to_srgb(x / y, 1.0, (1.0 - x - y) / y);
    for (int k = 0; k < 4; ++k) {
        plm_blackbody_chromaticity(kelvins[k], &x, &y);
        rgb light = plm_xyz_to_srgb(x / y, 1.0, (1.0 - x - y) / y);
        plm_picture p = {PLM_VIEW_STANDARD, 0.0, kelvins[k]};
        plm_picture_map_init(&p, &map);
        rgb c = rgb_make(map.m[0][0] * light.r + map.m[0][1] * light.g + map.m[0][2] * light.b,
                         map.m[1][0] * light.r + map.m[1][1] * light.g + map.m[1][2] * light.b,
                         map.m[2][0] * light.r + map.m[2][1] * light.g + map.m[2][2] * light.b);
        /* (the two sRGB <-> XYZ matrices are inverses to about 1e-7) */
        assert_double_near(c.r / c.g, neutral.r / neutral.g, 1e-5);
        assert_double_near(c.b / c.g, neutral.b / neutral.g, 1e-5);
    }
    rgb grey = show(PLM_VIEW_STANDARD, 0.0, 3200.0, rgb_gray(0.2));
    assert_true(grey.b > grey.g && grey.g > grey.r);
    /* Blackbody chromaticities on the Planckian locus (CIE 15: 2856 K, illuminant A, is (0.4476, 0.4074)). */
    plm_blackbody_chromaticity(2856.0, &x, &y);
    assert_double_near(x, 0.4476, 0.002);
    assert_double_near(y, 0.4074, 0.002);
}

/* Non-finite pixels become black bytes. */
static void nonfinite_pixels_are_black(void **state)
{
    (void)state;
    float px[6] = {NAN, 0.5f, 0.5f, 0.18f, 0.18f, 0.18f};
    uint8_t out[6];
    plm_picture p = {PLM_VIEW_FILMIC, 0.0, 6504.0};
    plm_picture_to_srgb8(&p, px, 2, out);
    assert_int_equal(out[0] + out[1] + out[2], 0);
    assert_int_equal(out[3], (int)lrint(255.0 * plm_srgb_encode(0.18)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(standard_view_is_the_clamp),
        cmocka_unit_test(filmic_view_keeps_grey_and_separates_highlights),
        cmocka_unit_test(filmic_view_takes_bright_colours_to_white),
        cmocka_unit_test(white_balance_neutralises_its_temperature),
        cmocka_unit_test(nonfinite_pixels_are_black),
        cmocka_unit_test(fireflies_are_isolated_bright_pixels),
        cmocka_unit_test(means_agree_within_their_noise),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
