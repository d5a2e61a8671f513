/* The shared base: random numbers, sampling helpers, JSON validation, safe files. */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "common/fileio.h"
#include "common/image_io.h"
#include "common/json.h"
#include "common/memory.h"
#include "common/params.h"
#include "common/rng.h"
#include "common/sampling.h"

/* The distance from y to the next double away from zero. */
static double ulp(double y) { return nextafter(fabs(y), INFINITY) - fabs(y); }

/* plm_sincos against the C library's sin and cos: within 2 ulp at random
 * angles over several turns, on both sides of the quadrants' edges, near
 * 0 and where it hands over to the library; exact at 0. */
static void sincos_matches_the_library(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 11, 0);
    double s, c, worst = 0.0;
    plm_sincos(0.0, &s, &c);
    assert_true(s == 0.0 && c == 1.0);
    for (int i = 0; i < 400000; ++i) {
        double x;
        if (i < 100000)
            x = 40.0 * plm_rng_uniform(&rng) - 20.0;
        else if (i < 200000) /* next to a multiple of pi/4, where the quadrant or the remainder's sign turns */
            x = (double)((i % 160) - 80) * (PLM_PI / 4.0) * (1.0 + 1e-12 * (plm_rng_uniform(&rng) - 0.5));
        else if (i < 300000) /* small: the polynomials' leading terms */
            x = ldexp(plm_rng_uniform(&rng) - 0.5, -(i % 60));
        else /* large, up to where the library takes over and past it */
            x = ldexp(1.0 + plm_rng_uniform(&rng), 10 + i % 10) * (i % 2 ? 1.0 : -1.0);
        plm_sincos(x, &s, &c);
        double es = fabs(s - sin(x)) / ulp(sin(x)), ec = fabs(c - cos(x)) / ulp(cos(x));
        worst = fmax(worst, fmax(es, ec));
        if (es > 2.0 || ec > 2.0)
            fail_msg("sincos(%.17g): %.17g %.17g, library %.17g %.17g", x, s, c, sin(x), cos(x));
    }
    print_message("sincos: worst %.2f ulp\n", worst);
}

/* ulp distance from the C library's value, checked against a bound; the
 * worst so far in *worst. Both NaN counts as no distance. */
static double ulp_off(double got, double want, double bound, double *worst, const char *what, double a, double b)
{
    if (isnan(want) && isnan(got))
        return 0.0;
    double e = fabs(got - want) / ulp(want);
    if (!(e <= bound))
        fail_msg("%s(%.17g, %.17g): %.17g, library %.17g (%.2f ulp)", what, a, b, got, want, e);
    *worst = fmax(*worst, e);
    return e;
}

/* A uniform double in [lo, hi). */
static double uniform_in(plm_rng *rng, double lo, double hi) { return lo + (hi - lo) * plm_rng_uniform(rng); }

/* plm_atan2 against the C library's atan2: within 1 ulp at 4 million
 * deterministic random points, a million each: over all octants at radii
 * from 2^-40 to 2^40; on both sides of the octants' edges (|y| = |x|, x = 0,
 * y = 0) and of plm_atan_octant's reduction bounds (|y| / |x| or
 * |x| / |y| = 0.16, 0.3697, 0.7222) in every octant; ratios down to 2^-1074
 * (results down to the subnormals); and magnitudes up to and past where it
 * hands over to the library (2^-1000, 2^1000). Zeros, infinities and NaN as
 * the library, signs of zero included. */
static void atan2_matches_the_library(void **state)
{
    (void)state;
    const double zero[2] = {0.0, -0.0}, side[4] = {1.0, -1.0, 0x1p-1030, 0x1p1020};
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            double z = zero[i], x = j ? -side[0] : side[0];
            assert_true(plm_atan2(z, x) == atan2(z, x) && signbit(plm_atan2(z, x)) == signbit(z));
            assert_true(plm_atan2(x, z) == atan2(x, z)); /* +-pi/2 */
            assert_true(plm_atan2(z, zero[j]) == atan2(z, zero[j]) &&
                        signbit(plm_atan2(z, zero[j])) == signbit(atan2(z, zero[j])));
        }
    assert_true(plm_atan2(0.0, 3.0) == 0.0 && !signbit(plm_atan2(0.0, 3.0)));
    assert_true(plm_atan2(1.0, 1.0) == atan2(1.0, 1.0) && plm_atan2(-2.0, -2.0) == atan2(-2.0, -2.0));
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double y = side[i], x = side[j];
            assert_true(plm_atan2(y * INFINITY, x) == atan2(y * INFINITY, x));
            assert_true(plm_atan2(y, x * INFINITY) == atan2(y, x * INFINITY));
            assert_true(plm_atan2(y * INFINITY, x * INFINITY) == atan2(y * INFINITY, x * INFINITY));
        }
    assert_true(isnan(plm_atan2(NAN, 1.0)) && isnan(plm_atan2(1.0, NAN)) && isnan(plm_atan2(NAN, NAN)));

    plm_rng rng;
    plm_rng_seed(&rng, 12, 0);
    const double bound[4] = {0.16, 0.3697, 0.7222, 1.0};
    double worst = 0.0;
    for (int i = 0; i < 4000000; ++i) {
        double y, x;
        if (i < 1000000) { /* any angle at radii 2^-40..2^40 */
            double a = uniform_in(&rng, -PLM_PI, PLM_PI), r = ldexp(1.0 + plm_rng_uniform(&rng), (i % 81) - 40);
            y = r * sin(a);
            x = r * cos(a);
        } else if (i < 2000000) { /* a ratio next to a reduction bound or 1, either way round, either sign */
            double t = bound[i % 4] * (1.0 + ldexp(uniform_in(&rng, -1.0, 1.0), -(i % 50) - 3));
            double big = uniform_in(&rng, 0.5, 2.0);
            y = big * t;
            x = big;
            if (i & 4) {
                x = y;
                y = big;
            }
            x = (i & 8) ? -x : x;
            y = (i & 16) ? -y : y;
        } else if (i < 3000000) { /* small ratios, down to subnormal results; either axis */
            double big = uniform_in(&rng, 1.0, 2.0) * ((i & 1) ? 1.0 : -1.0);
            double small = ldexp(uniform_in(&rng, 1.0, 2.0), -(i % 1100)) * ((i & 2) ? 1.0 : -1.0);
            y = (i & 4) ? big : small;
            x = (i & 4) ? small : big;
        } else { /* large and small magnitudes, across where the library takes over */
            double a = uniform_in(&rng, -PLM_PI, PLM_PI);
            int e = (i & 1) ? 980 + (i % 60) : -1040 + (i % 60);
            y = ldexp(sin(a), e);
            x = ldexp(cos(a), e);
        }
        ulp_off(plm_atan2(y, x), atan2(y, x), 1.0, &worst, "atan2", y, x);
    }
    print_message("atan2: worst %.2f ulp\n", worst);
}

/* Test point i of asin's and acos's domain, a million of each kind: i / 10^6
 * = 0 uniform over [-1, 1]; 1 next to one of the nine edges (relative
 * offsets from 2^-2 down to 2^-51); 2 |x| from 1 down to 2^-1074; 3 1 - |x|
 * from 2^-1 down to 2^-53. Odd i are negated. */
static double inverse_sine_point(plm_rng *rng, int i, const double edge[9])
{
    double x;
    switch (i / 1000000) {
    case 0:
        x = uniform_in(rng, -1.0, 1.0);
        break;
    case 1:
        x = fmin(edge[i % 9] * (1.0 + ldexp(uniform_in(rng, -1.0, 1.0), -(i % 50) - 2)), 1.0);
        break;
    case 2:
        x = ldexp(uniform_in(rng, 1.0, 2.0), -(i % 1080));
        break;
    default:
        x = 1.0 - ldexp(uniform_in(rng, 1.0, 2.0), -(i % 53) - 1);
    }
    return (i & 1) ? -x : x;
}

/* plm_asin against the C library's asin: within 2 ulp at 3 million
 * deterministic random points, a million each: over [-1, 1]; next to 1/2
 * (where it turns to asin(x) = pi/2 - 2 asin(sqrt((1 - x) / 2))), +-1 and
 * the sines of 1, 1/2, ..., 1/64 (results just under a power of two, where an
 * ulp is smallest against the error); and |x| down to 2^-1074.
 * asin(+-1) = +-pi/2 and asin(+-0) = +-0 exactly; NaN stays NaN. */
static void asin_matches_the_library(void **state)
{
    (void)state;
    assert_true(plm_asin(1.0) == PLM_PI / 2.0 && plm_asin(-1.0) == -PLM_PI / 2.0 && plm_asin(1.0) == asin(1.0));
    assert_true(plm_asin(0.0) == 0.0 && !signbit(plm_asin(0.0)) && signbit(plm_asin(-0.0)));
    assert_true(plm_asin(0.5) == asin(0.5) && plm_asin(-0.5) == asin(-0.5));
    assert_true(isnan(plm_asin(NAN)));

    plm_rng rng;
    plm_rng_seed(&rng, 13, 0);
    double edge[9] = {0.5, 1.0};
    for (int k = 0; k < 7; ++k)
        edge[2 + k] = sin(ldexp(1.0, -k));
    double worst = 0.0;
    for (int i = 0; i < 3000000; ++i) {
        double x = inverse_sine_point(&rng, i, edge);
        ulp_off(plm_asin(x), asin(x), 2.0, &worst, "asin", x, 0.0);
    }
    print_message("asin: worst %.2f ulp\n", worst);
}

/* plm_acos against the C library's acos: within 2 ulp at 4 million
 * deterministic random points, a million each: over [-1, 1]; next to +-1/2
 * (where it turns from pi/2 - asin(x) to 2 asin(sqrt((1 - |x|) / 2)) or
 * pi less that), +-1 and the cosines of 2, 1, 1/2, ..., 1/32 (results
 * just under a power of two, where an ulp is smallest against the error);
 * |x| down to 2^-1074; and 1 - |x| from 2^-1 down to 2^-53 (results down
 * to 2^-26 and up to pi). acos(1) = 0 and acos(-1) = pi exactly; NaN for
 * NaN and outside [-1, 1]. */
static void acos_matches_the_library(void **state)
{
    (void)state;
    assert_true(plm_acos(1.0) == 0.0 && plm_acos(-1.0) == PLM_PI && plm_acos(-1.0) == acos(-1.0));
    assert_true(plm_acos(0.0) == acos(0.0) && plm_acos(-0.0) == acos(-0.0));
    assert_true(plm_acos(0.5) == acos(0.5) && plm_acos(-0.5) == acos(-0.5));
    assert_true(isnan(plm_acos(NAN)) && isnan(plm_acos(1.5)) && isnan(plm_acos(-1.0 - 0x1p-52)));

    plm_rng rng;
    plm_rng_seed(&rng, 14, 0);
    double edge[9] = {0.5, 1.0};
    for (int k = 0; k < 7; ++k)
        edge[2 + k] = cos(ldexp(1.0, 1 - k));
    double worst = 0.0;
    for (int i = 0; i < 4000000; ++i) {
        double x = inverse_sine_point(&rng, i, edge);
        ulp_off(plm_acos(x), acos(x), 2.0, &worst, "acos", x, 0.0);
    }
    print_message("acos: worst %.2f ulp\n", worst);
}

static void rng_is_reproducible_and_uniform(void **state)
{
    (void)state;
    plm_rng a, b, c;
    plm_rng_seed(&a, 42, 7);
    plm_rng_seed(&b, 42, 7);
    plm_rng_seed(&c, 42, 8);
    int same_stream_differs = 0;
    for (int i = 0; i < 1000; ++i) {
        uint32_t x = plm_rng_u32(&a);
        assert_int_equal(x, plm_rng_u32(&b));
        same_stream_differs += x != plm_rng_u32(&c);
    }
    assert_true(same_stream_differs > 990);
    /* Mean and variance of U(0,1): 1/2 and 1/12, to 5 sigma for 1e6 samples. */
    double sum = 0, sum2 = 0;
    int n = 1000000;
    for (int i = 0; i < n; ++i) {
        double u = plm_rng_uniform(&a);
        assert_true(u >= 0.0 && u < 1.0);
        sum += u;
        sum2 += u * u;
    }
    double mean = sum / n, var = sum2 / n - mean * mean;
    assert_true(fabs(mean - 0.5) < 5.0 * sqrt(1.0 / 12.0 / n));
    assert_true(fabs(var - 1.0 / 12.0) < 1e-3);
}

/* The bin sampling picks is the last whose cdf entry is at most u, however
 * far the guide's start is from it: random weights with runs of zeros and a
 * spike (a sky's sun), u at random, on cdf entries and on the guide's i / n. */
static void distribution_finds_the_last_entry_at_most_u(void **state)
{
    (void)state;
    enum { N = 37 };
    plm_rng rng;
    plm_rng_seed(&rng, 3, 3);
    for (int t = 0; t < 200; ++t) {
        double w[N], cdf[N + 1];
        int guide[N];
        for (int i = 0; i < N; ++i)
            w[i] = plm_rng_uniform(&rng) < 0.4 ? 0.0 : plm_rng_uniform(&rng);
        w[(int)(plm_rng_uniform(&rng) * N)] += 1000.0 * (t % 2);
        plm_distribution1d d = plm_distribution1d_build(w, N, cdf, guide);
        for (int k = 0; k < 300; ++k) {
            double u = k < 100 ? plm_rng_uniform(&rng) : k < 100 + N ? cdf[k - 100] : (double)(k % N) / N;
            if (!(u < 1.0))
                continue; /* a cdf entry of 1 before trailing zero weights: u is in [0, 1) */
            int last = 0;
            for (int i = 1; i < N; ++i)
                if (cdf[i] <= u)
                    last = i;
            double r;
            assert_int_equal(plm_distribution1d_sample(&d, u, &r), last);
            assert_true(d.total == 0.0 || w[last] > 0.0);
        }
    }
}

static void distribution_matches_weights(void **state)
{
    (void)state;
    double w[5] = {1.0, 0.0, 3.0, 0.0, 4.0}, cdf[6];
    int guide[5];
    plm_distribution1d d = plm_distribution1d_build(w, 5, cdf, guide);
    assert_double_near(d.total, 8.0, 1e-12);
    int counts[5] = {0};
    plm_rng rng;
    plm_rng_seed(&rng, 1, 1);
    int n = 800000;
    for (int i = 0; i < n; ++i) {
        double r;
        int k = plm_distribution1d_sample(&d, plm_rng_uniform(&rng), &r);
        assert_true(r >= 0.0 && r < 1.0);
        counts[k]++;
    }
    assert_int_equal(counts[1], 0);
    assert_int_equal(counts[3], 0);
    for (int k = 0; k < 5; ++k) {
        double p = w[k] / 8.0;
        assert_double_near(plm_distribution1d_pmf(&d, k), p, 1e-12);
        assert_true(fabs(counts[k] - n * p) <= 5.0 * sqrt(n * p * (1 - p)) + 1e-9);
    }
}

static void cosine_hemisphere_has_expected_moments(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 3, 0);
    /* E[cos] = 2/3 under the pdf cos/pi. */
    double sum = 0;
    int n = 400000;
    for (int i = 0; i < n; ++i) {
        vec3 w = plm_sample_cosine_hemisphere(plm_rng_uniform(&rng), plm_rng_uniform(&rng));
        assert_double_near(v3_length(w), 1.0, 1e-9);
        assert_true(w.z >= 0.0);
        sum += w.z;
    }
    assert_double_near(sum / n, 2.0 / 3.0, 3e-3);
}

static const char *write_temp(const char *name, const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "/tmp/plumage-test-%ld-%s", (long)getpid(), name);
    FILE *fp = fopen(path, "w");
    fputs(text, fp);
    fclose(fp);
    return path;
}

static void json_errors_name_file_field_and_range(void **state)
{
    (void)state;
    plm_error err = {{0}};
    cJSON *root = NULL;
    const char *bad = write_temp("bad.json", "{\n  \"a\": 1,\n  \"b\": [1, 2\n}\n");
    assert_int_equal(plm_json_load(bad, &root, &err), PLM_ERR_PARSE);
    assert_non_null(strstr(err.message, bad));
    remove(bad);

    const char *good = write_temp("good.json", "{\"camera\": {\"fov\": 200, \"extra\": true}}");
    assert_int_equal(plm_json_load(good, &root, &err), PLM_OK);
    plm_json_reader r = {"scene.json", &err, 0};
    const cJSON *camera = cJSON_GetObjectItem(root, "camera");
    double fov;
    assert_int_equal(plm_json_number(&r, camera, "camera", "fov", 40, 1, 179, &fov), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "scene.json: camera.fov: 200 is out of range [1, 179]"));
    const char *allowed[] = {"fov", NULL};
    assert_int_equal(plm_json_check_object(&r, camera, "camera", allowed), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "camera.extra: unknown field"));
    double missing;
    assert_int_equal(plm_json_number(&r, camera, "camera", "near", 0.5, 0, 1, &missing), PLM_OK);
    assert_double_near(missing, 0.5, 0.0);
    cJSON_Delete(root);
    remove(good);

    /* An enum names its choices whether the value is an unknown string or not a string at all. */
    const char *const sides[] = {"left", "right", NULL};
    cJSON *split = cJSON_Parse("{\"side\": \"up\", \"other\": 2}");
    int side = -1;
    assert_int_equal(plm_json_enum(&r, split, "split", "side", sides, 0, &side), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "scene.json: split.side: \"up\" is not one of \"left\", \"right\""));
    assert_int_equal(plm_json_enum(&r, split, "split", "other", sides, 0, &side), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "scene.json: split.other: expected one of \"left\", \"right\""));
    assert_int_equal(plm_json_enum(&r, split, "split", "absent", sides, 0, &side), PLM_OK);
    assert_int_equal(side, 0);
    cJSON_SetValuestring(cJSON_GetObjectItem(split, "side"), "right");
    assert_int_equal(plm_json_enum(&r, split, "split", "side", sides, 0, &side), PLM_OK);
    assert_int_equal(side, 1);
    cJSON_Delete(split);
}

static void atomic_file_leaves_nothing_on_abort(void **state)
{
    (void)state;
    char path[256];
    snprintf(path, sizeof path, "/tmp/plumage-test-%ld-atomic.txt", (long)getpid());
    remove(path);
    plm_atomic_file f;
    plm_error err;
    assert_int_equal(plm_atomic_open(&f, path, &err), PLM_OK);
    fputs("partial", f.fp);
    plm_atomic_abort(&f);
    assert_int_equal(access(path, F_OK), -1);
    assert_int_equal(access(f.temp_path, F_OK), -1);
    assert_int_equal(plm_atomic_open(&f, path, &err), PLM_OK);
    fputs("whole", f.fp);
    assert_int_equal(plm_atomic_commit(&f, &err), PLM_OK);
    char *text;
    assert_int_equal(plm_read_text_file(path, &text, &err), PLM_OK);
    assert_string_equal(text, "whole");
    free(text);
    remove(path);
}

static void image_round_trips_through_exr_and_png16(void **state)
{
    (void)state;
    float px[2 * 3 * 3];
    uint16_t px16[2 * 3 * 3];
    for (int i = 0; i < 18; ++i) {
        px[i] = 0.1f * (float)i - 0.3f;
        px16[i] = (uint16_t)(i * 3000);
    }
    char exr[256], png[256];
    snprintf(exr, sizeof exr, "/tmp/plumage-test-%ld.exr", (long)getpid());
    snprintf(png, sizeof png, "/tmp/plumage-test-%ld.png", (long)getpid());
    plm_error err;
    assert_int_equal(plm_image_write(exr, 3, 2, 3, PLM_PIXEL_FLOAT, px, &err), PLM_OK);
    assert_int_equal(plm_image_write(png, 3, 2, 3, PLM_PIXEL_UINT16, px16, &err), PLM_OK);
    int w, h, c;
    float *back;
    assert_int_equal(plm_image_read(exr, &w, &h, &c, &back, &err), PLM_OK);
    assert_int_equal(w, 3);
    assert_int_equal(h, 2);
    assert_int_equal(c, 3);
    for (int i = 0; i < 18; ++i)
        assert_double_near(back[i], px[i], 1e-6);
    free(back);
    assert_int_equal(plm_image_read(png, &w, &h, &c, &back, &err), PLM_OK);
    assert_int_equal(w, 3);
    assert_int_equal(h, 2);
    assert_int_equal(c, 3);
    for (int i = 0; i < 18; ++i)
        assert_double_near(back[i], px16[i] / 65535.0, 1e-6);
    free(back);
    remove(exr);
    remove(png);
    assert_int_equal(plm_image_read("/nonexistent/x.exr", &w, &h, &c, &back, &err), PLM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent/x.exr"));
}

/* A PNG chunk that declares more bytes than the file holds is refused before
 * libpng sees it (libpng would allocate the declared length first). */
static void png_chunk_longer_than_the_file_is_refused(void **state)
{
    (void)state;
    uint16_t px16[2 * 3 * 3] = {0};
    char png[256];
    snprintf(png, sizeof png, "/tmp/plumage-test-chunk-%ld.png", (long)getpid());
    plm_error err;
    assert_int_equal(plm_image_write(png, 3, 2, 3, PLM_PIXEL_UINT16, px16, &err), PLM_OK);
    assert_int_equal(plm_image_check_png_chunks(png, &err), PLM_OK);
    /* The chunk after IHDR (8-byte signature, then 12 + 13 bytes) claims 1.8 GB. */
    FILE *f = fopen(png, "r+b");
    assert_non_null(f);
    const unsigned char huge[4] = {0x6d, 0x00, 0x00, 0x14};
    assert_int_equal(fseek(f, 33, SEEK_SET), 0);
    assert_int_equal(fwrite(huge, 1, 4, f), 4);
    fclose(f);
    int w, h, c;
    float *back = NULL;
    assert_int_equal(plm_image_read(png, &w, &h, &c, &back, &err), PLM_ERR_PARSE);
    assert_null(back);
    assert_non_null(strstr(err.message, "corrupt PNG: the chunk at byte 33 declares 1828716564 bytes"));
    /* Cut after the signature and one byte: no chunk is whole, and there is no IEND. */
    assert_int_equal(truncate(png, 9), 0);
    assert_int_equal(plm_image_read(png, &w, &h, &c, &back, &err), PLM_ERR_PARSE);
    assert_null(back);
    assert_non_null(strstr(err.message, "truncated PNG: the file ends at byte 9, before its IEND chunk"));
    remove(png);
}

/* The same for an EXR attribute's declared size: OpenEXR allocates it first. */
static void exr_attribute_longer_than_the_file_is_refused(void **state)
{
    (void)state;
    float px[2 * 3 * 3] = {0};
    char exr[256];
    snprintf(exr, sizeof exr, "/tmp/plumage-test-attr-%ld.exr", (long)getpid());
    plm_error err;
    assert_int_equal(plm_image_write(exr, 3, 2, 3, PLM_PIXEL_FLOAT, px, &err), PLM_OK);
    assert_int_equal(plm_image_check_exr_header(exr, &err), PLM_OK);
    /* The first attribute (after the 8-byte magic and version): its name, its type, then its size. */
    unsigned char head[80];
    FILE *f = fopen(exr, "r+b");
    assert_non_null(f);
    assert_int_equal(fread(head, 1, sizeof head, f), sizeof head);
    size_t name = strlen((const char *)head + 8), type = strlen((const char *)head + 9 + name);
    long at = (long)(8 + name + 1 + type + 1);
    const unsigned char huge[4] = {0x00, 0x84, 0xd7, 0x17}; /* 400,000,000 little-endian */
    assert_int_equal(fseek(f, at, SEEK_SET), 0);
    assert_int_equal(fwrite(huge, 1, 4, f), 4);
    fclose(f);
    int w, h, c;
    float *back = NULL;
    assert_int_equal(plm_image_read(exr, &w, &h, &c, &back, &err), PLM_ERR_PARSE);
    assert_null(back);
    char expect[160];
    snprintf(expect, sizeof expect, "corrupt EXR: the attribute \"%s\" at byte 8 declares 400000000 bytes",
             (const char *)head + 8);
    assert_non_null(strstr(err.message, expect));
    remove(exr);
}

/* Text lands right of and above its baseline origin, in the asked colour,
 * and nowhere else; with alpha, the text is composited over the image. */
static void text_is_drawn_at_its_baseline(void **state)
{
    (void)state;
    for (int channels = 3; channels <= 4; ++channels) {
        enum { W = 96, H = 40 };
        float px[W * H * 4] = {0};
        plm_image img = {W, H, channels, px};
        const float red[3] = {1.0f, 0.0f, 0.0f};
        plm_error err = {{0}};
        assert_int_equal(plm_image_draw_text(&img, 20, 30, 20, "Hx", red, &err), PLM_OK);
        int inked = 0, stray = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const float *p = px + (y * W + x) * channels;
                int ink = p[0] > 0.0f;
                /* "Hx" has no descender: ink only between the cap height
                 * (about 0.73 em above the baseline) and the baseline. */
                int inside = x >= 20 && x < 20 + 2 * 20 && y >= 30 - 17 && y <= 30;
                inked += ink && inside && p[0] > 0.99f;
                stray += ink && !inside;
                assert_double_near(p[1], 0.0, 0.0);
                if (channels == 4) /* text composited over clear black: alpha = coverage = red */
                    assert_double_near(p[3], p[0], 1e-6);
            }
        assert_true(inked > 40);
        assert_int_equal(stray, 0);
    }
    float px[4 * 4 * 2] = {0};
    plm_image two = {4, 4, 2, px};
    const float white[3] = {1, 1, 1};
    plm_error err = {{0}};
    assert_int_equal(plm_image_draw_text(&two, 0, 3, 8, "a", white, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "3 or 4 channels"));
}

/* A parameter table reads angles in degrees into radians, keeps absent
 * fields, refuses unknown keys (but the extra ones) and out-of-range values
 * naming the field and range, and checks structs against the same ranges. */
typedef struct table_target {
    double length, angle;
    int count;
    uint64_t seed;
    vec3 axis;
} table_target;

static void parameter_tables_read_check_and_print(void **state)
{
    (void)state;
    static const plm_param params[] = {
        {"length", PLM_PARAM_NUMBER, offsetof(table_target, length), 0.5, 2.0, "mm", "how long", 0},
        {"angle", PLM_PARAM_ANGLE, offsetof(table_target, angle), 0.0, 90.0, "degrees", "how steep", 0},
        {"count", PLM_PARAM_INT, offsetof(table_target, count), 1, 10, "", "how many", 0},
        {"seed", PLM_PARAM_SEED, offsetof(table_target, seed), 0, 100, "", "which", 0},
        {"axis", PLM_PARAM_VEC3, offsetof(table_target, axis), -1.0, 1.0, "", "where to", 0},
    };
    const plm_param_block block = {"test", "a test block", params, 5};
    static const char *const extra[] = {"note", NULL};
    plm_error err = {{0}};
    plm_json_reader r = {"t.json", &err, 0};
    table_target t = {1.0, 0.0, 3, 7, {0, 0, 1}};
    cJSON *obj = cJSON_Parse("{\"angle\": 30, \"count\": 4, \"seed\": 9, \"note\": \"read elsewhere\"}");
    assert_int_equal(plm_params_read(&r, obj, "block", &block, extra, &t), PLM_OK);
    assert_double_near(t.angle, 30.0 * PLM_PI / 180.0, 1e-15);
    assert_double_near(t.length, 1.0, 0.0); /* absent: kept */
    assert_int_equal(t.count, 4);
    assert_int_equal((int)t.seed, 9);
    assert_int_equal(plm_params_check(&block, &t, &err), PLM_OK);
    cJSON_Delete(obj);
    obj = cJSON_Parse("{\"note\": 1, \"colour\": 2}");
    assert_int_equal(plm_params_read(&r, obj, "block", &block, extra, &t), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "block.colour"));
    cJSON_Delete(obj);
    obj = cJSON_Parse("{\"length\": 3}");
    assert_int_equal(plm_params_read(&r, obj, "block", &block, NULL, &t), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "t.json: block.length"));
    assert_non_null(strstr(err.message, "[0.5, 2]"));
    cJSON_Delete(obj);
    t.angle = 100.0 * PLM_PI / 180.0;
    assert_int_equal(plm_params_check(&block, &t, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "test parameter angle = 100 degrees is out of range [0, 90]"));
    t.angle = 0.0;
    t.axis.y = NAN;
    assert_int_equal(plm_params_check(&block, &t, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "axis"));
    /* The markdown table: a header, a rule and one row per field, defaults from the struct given. */
    t.axis.y = 0.0;
    char buf[4096] = {0};
    FILE *fp = fmemopen(buf, sizeof buf - 1, "w");
    const void *defaults[1] = {&t};
    const char *labels[1] = {""};
    plm_params_print(fp, &block, 1, labels, defaults, 1);
    fclose(fp);
    int rows = 0;
    for (const char *p = buf; (p = strchr(p, '\n')); ++p)
        ++rows;
    assert_int_equal(rows, 2 + 5);
    assert_non_null(strstr(buf, "| `length` | number | 1 | 0.5 | 2 | mm | how long |"));
}

/* Touching 64 MiB (mapped directly, so no allocator keeps it afterwards)
 * raises the resident and peak figures by about that; once it is unmapped
 * and the peak reset, the peak is back near the resident memory. */
static void memory_figures_follow_what_is_touched(void **state)
{
    (void)state;
    const size_t size = 64u << 20;
    double resident0 = plm_memory_resident_mib();
    assert_true(resident0 > 0.0);
    assert_true(plm_memory_peak_mib() >= resident0);
    unsigned char *block = mmap(NULL, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    assert_true(block != MAP_FAILED);
    memset(block, 1, size);
    assert_true(plm_memory_resident_mib() >= resident0 + 60.0);
    double peak = plm_memory_peak_mib();
    assert_true(peak >= resident0 + 60.0);
    munmap(block, size);
    if (!plm_memory_reset_peak())
        skip(); /* no /proc/self/clear_refs here */
    assert_true(plm_memory_peak_mib() <= peak - 48.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sincos_matches_the_library),
        cmocka_unit_test(atan2_matches_the_library),
        cmocka_unit_test(asin_matches_the_library),
        cmocka_unit_test(acos_matches_the_library),
        cmocka_unit_test(rng_is_reproducible_and_uniform),
        cmocka_unit_test(distribution_finds_the_last_entry_at_most_u),
        cmocka_unit_test(distribution_matches_weights),
        cmocka_unit_test(cosine_hemisphere_has_expected_moments),
        cmocka_unit_test(json_errors_name_file_field_and_range),
        cmocka_unit_test(atomic_file_leaves_nothing_on_abort),
        cmocka_unit_test(image_round_trips_through_exr_and_png16),
        cmocka_unit_test(png_chunk_longer_than_the_file_is_refused),
        cmocka_unit_test(exr_attribute_longer_than_the_file_is_refused),
        cmocka_unit_test(text_is_drawn_at_its_baseline),
        cmocka_unit_test(parameter_tables_read_check_and_print),
        cmocka_unit_test(memory_figures_follow_what_is_touched),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
