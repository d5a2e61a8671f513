/* What makes a pelt read as plumage rather than scales, measured on the
 * layout: roots without a lattice (a Fourier transform of the root
 * positions), sizes shrinking toward the head and the edges, and neighbours
 * that never repeat one another. Each tolerance was written down before the
 * measurement; the figures printed are in docs/layouts.md. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"
#include "layout_helpers.h"
#include "test_files.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/rng.h"
#include "generate/layout.h"

static plm_layout unit_pelt(const plm_species *sp, int count, uint64_t seed)
{
    plm_layout_species list[1] = {{sp, 1.0}};
    plm_pelt_params p = {0};
    p.surface.kind = PLM_SURFACE_PLANE;
    p.count = count;
    p.seed = seed;
    plm_layout l;
    plm_error err = {{0}};
    plm_result rc = plm_layout_pelt(&p, list, 1, &l, &err);
    if (rc != PLM_OK)
        fprintf(stderr, "%s\n", err.message);
    assert_int_equal(rc, PLM_OK);
    return l;
}

static double sq(double x) { return x * x; }

/* ---- No lattice ---- */

/* The periodogram S(k) = |sum_j w_j exp(-2 pi i k . x_j)|^2 / sum_j w_j^2 of
 * points in the unit square at integer k with |k_x|, |k_y| <= K, and its
 * largest value over the mean of S in the same ring |k| (rings one unit
 * wide), for |k| >= k_min: near 1 for any structure without a lattice,
 * whatever its radial profile (blue noise has a ring, white noise none); a
 * lattice puts a sum of n phases that agree into single k, which stand far
 * above their ring. The weights w (a Hann window, sin^2(pi x) sin^2(pi y))
 * fade the points out toward the square's edges: cut off sharply, the edges
 * and the density gradient between them leak along the axes (|k| 12-30). */
static double periodogram_peak(const double (*x)[2], int n, int K, double k_min)
{
    int side = 2 * K + 1, rings = (int)ceil(K * sqrt(2.0)) + 2;
    double *re = calloc((size_t)side * side, sizeof *re), *im = calloc((size_t)side * side, sizeof *im);
    double *ring_sum = calloc((size_t)rings, sizeof *ring_sum);
    int *ring_count = calloc((size_t)rings, sizeof *ring_count);
    double(*px)[2] = malloc(sizeof *px * (size_t)side);
    double weights = 0.0;
    for (int j = 0; j < n; ++j) {
        double w = sq(sin(PLM_PI * x[j][0]) * sin(PLM_PI * x[j][1]));
        weights += w * w;
        /* w exp(-2 pi i k x) for every k_x by powers of one phase. */
        double cx = cos(-PLM_TWO_PI * x[j][0]), sx = sin(-PLM_TWO_PI * x[j][0]);
        double cy = cos(-PLM_TWO_PI * x[j][1]), sy = sin(-PLM_TWO_PI * x[j][1]);
        px[K][0] = w, px[K][1] = 0.0;
        for (int k = 1; k <= K; ++k) {
            px[K + k][0] = px[K + k - 1][0] * cx - px[K + k - 1][1] * sx;
            px[K + k][1] = px[K + k - 1][0] * sx + px[K + k - 1][1] * cx;
            px[K - k][0] = px[K + k][0], px[K - k][1] = -px[K + k][1];
        }
        double yr = cos(PLM_TWO_PI * K * x[j][1]), yi = sin(PLM_TWO_PI * K * x[j][1]); /* ky = -K */
        for (int b = 0; b < side; ++b) {
            for (int a = 0; a < side; ++a) {
                re[b * side + a] += px[a][0] * yr - px[a][1] * yi;
                im[b * side + a] += px[a][0] * yi + px[a][1] * yr;
            }
            double t = yr * cy - yi * sy;
            yi = yr * sy + yi * cy;
            yr = t;
        }
    }
    for (int b = 0; b < side; ++b)
        for (int a = 0; a < side; ++a) {
            double k = hypot(a - K, b - K);
            double S = (sq(re[b * side + a]) + sq(im[b * side + a])) / weights;
            re[b * side + a] = S;
            ring_sum[(int)k] += S;
            ring_count[(int)k]++;
        }
    double peak = 0.0;
    for (int b = 0; b < side; ++b)
        for (int a = 0; a < side; ++a) {
            double k = hypot(a - K, b - K);
            if (k >= k_min && k <= K)
                peak = fmax(peak, re[b * side + a] / (ring_sum[(int)k] / ring_count[(int)k]));
        }
    free(re), free(im), free(ring_sum), free(ring_count), free(px);
    return peak;
}

/* Roots of 2,500 feathers over the unit square against the same count on a
 * jittered square lattice. Tolerance: no k where the periodogram exceeds 20
 * times its ring's mean (for a structure without a lattice S / mean is
 * about exponentially distributed: over the ~20,000 k tested the largest is
 * near 10, and 20 is exceeded with probability about 4e-5), from |k| = 12
 * (below it the density gradient and the square's edges make the spectrum).
 * The lattice must exceed it, or the test could not fail. */
static void roots_have_no_lattice(void **state)
{
    (void)state;
    enum { N = 2500, K = 75 };
    plm_species sp = load_preset("covert_parrot");
    plm_layout l = unit_pelt(&sp, N, 9);
    double(*x)[2] = malloc(sizeof *x * N);
    for (int i = 0; i < N; ++i)
        x[i][0] = l.instances[i].m[0][3] + 0.5, x[i][1] = l.instances[i].m[1][3] + 0.5;
    double roots = periodogram_peak((const double(*)[2])x, N, K, 12.0);
    plm_rng rng;
    plm_rng_seed(&rng, 3, 1);
    for (int i = 0; i < N; ++i) /* a 50 x 50 lattice, each point jittered by a tenth of the spacing */
        x[i][0] = (i % 50 + 0.5 + 0.1 * (plm_rng_uniform(&rng) - 0.5)) / 50,
        x[i][1] = (i / 50 + 0.5 + 0.1 * (plm_rng_uniform(&rng) - 0.5)) / 50;
    double lattice = periodogram_peak((const double(*)[2])x, N, K, 12.0);
    printf("periodogram peak over its ring's mean: pelt roots %.1f, jittered lattice %.1f\n", roots, lattice);
    assert_true(roots < 20.0);
    assert_true(lattice > 20.0);
    free(x);
    plm_layout_free(&l);
    plm_species_free(&sp);
}

/* ---- Sizes along the flow and toward the edges ---- */

/* The default flow runs toward -y: the head is the +y edge. Away from the
 * edges (|x|, |y| < 0.4), the quarter toward the head against the quarter
 * toward the tail: sizes 0.67 against 0.93 of the largest by the field (a
 * ratio of 0.72; tolerance 0.62-0.82), and so about (0.93 / 0.67)^2 = 1.9
 * times the feathers per area (tolerance 1.5-2.5). Within 0.02 of the side
 * edges feathers are at most 0.75 of the size of those between |x| 0.2 and
 * 0.4 at the same height (the field: 0.6-0.7 of it at the edge). */
static void sizes_shrink_toward_head_and_edges(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    plm_layout l = unit_pelt(&sp, 2500, 4);
    double size[4] = {0.0};
    int n[4] = {0};
    for (int i = 0; i < l.instance_count; ++i) {
        const plm_layout_instance *in = &l.instances[i];
        double x = in->m[0][3], y = in->m[1][3];
        int band = fabs(x) < 0.4 && y > 0.25 && y < 0.4 ? 0 : fabs(x) < 0.4 && y < -0.25 && y > -0.4 ? 1 : -1;
        if (fabs(y) < 0.3 && fabs(x) > 0.48)
            band = 2;
        else if (fabs(y) < 0.3 && fabs(x) > 0.2 && fabs(x) < 0.4)
            band = 3;
        if (band >= 0)
            size[band] += in->scale, n[band]++;
    }
    double head = size[0] / n[0], tail = size[1] / n[1], edge = size[2] / n[2], inside = size[3] / n[3];
    printf("mean size: head quarter %.3f, tail quarter %.3f (ratio %.3f; feathers %d and %d, ratio %.2f); "
           "edges %.3f, inside %.3f (ratio %.3f)\n", head, tail, head / tail, n[0], n[1], (double)n[0] / n[1], edge,
           inside, edge / inside);
    assert_true(head / tail > 0.62 && head / tail < 0.82);
    assert_true((double)n[0] / n[1] > 1.5 && (double)n[0] / n[1] < 2.5);
    assert_true(edge / inside < 0.75);
    plm_layout_free(&l);
    plm_species_free(&sp);
}

/* ---- Neighbours never identical ---- */

/* The 6 nearest roots of root i (brute force: the test's pelts are small). */
static void nearest(const plm_layout *l, int i, int *out)
{
    double best[6];
    for (int k = 0; k < 6; ++k)
        best[k] = INFINITY, out[k] = -1;
    for (int j = 0; j < l->instance_count; ++j) {
        if (j == i)
            continue;
        double d = sq(l->instances[j].m[0][3] - l->instances[i].m[0][3]) +
                   sq(l->instances[j].m[1][3] - l->instances[i].m[1][3]);
        for (int k = 0; k < 6; ++k)
            if (d < best[k]) {
                for (int m = 5; m > k; --m)
                    best[m] = best[m - 1], out[m] = out[m - 1];
                best[k] = d, out[k] = j;
                break;
            }
    }
}

/* A feather's length in layout units: its scale over the prototype's. */
static double length_of(const plm_layout *l, int i)
{
    const plm_layout_instance *in = &l->instances[i];
    return v3_length(column(in, 1)) * l->prototypes[in->prototype].shape.length;
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Tolerances: the coefficient of variation of the lengths of a feather and
 * its six nearest neighbours has a median in [5%, 15%] over the feathers
 * away from the edges; the yaws' standard deviation is 2-5 degrees; lift and
 * tint vary (standard deviations above 0.1 degree and 0.01); no feather has
 * a neighbour with the same prototype, length, yaw and tint. */
static void neighbours_never_repeat(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    plm_layout l = unit_pelt(&sp, 1200, 6);
    double *cv = malloc(sizeof *cv * (size_t)l.instance_count);
    int m = 0, same = 0;
    double yaw[2] = {0.0}, lift[2] = {0.0}, tint[2] = {0.0};
    for (int i = 0; i < l.instance_count; ++i) {
        const plm_layout_instance *in = &l.instances[i];
        int nb[6];
        nearest(&l, i, nb);
        for (int k = 0; k < 6; ++k) {
            const plm_layout_instance *o = &l.instances[nb[k]];
            same += o->prototype == in->prototype && length_of(&l, nb[k]) == length_of(&l, i) && o->yaw == in->yaw &&
                    o->tint.r == in->tint.r && o->tint.g == in->tint.g && o->tint.b == in->tint.b;
        }
        yaw[0] += in->yaw, yaw[1] += in->yaw * in->yaw;
        lift[0] += in->lift, lift[1] += in->lift * in->lift;
        tint[0] += in->tint.g, tint[1] += in->tint.g * in->tint.g;
        if (fabs(in->m[0][3]) > 0.4 || fabs(in->m[1][3]) > 0.4)
            continue;
        double s = length_of(&l, i), s2 = s * s;
        for (int k = 0; k < 6; ++k)
            s += length_of(&l, nb[k]), s2 += sq(length_of(&l, nb[k]));
        double mean = s / 7;
        cv[m++] = sqrt(fmax(s2 / 7 - mean * mean, 0.0) * 7 / 6) / mean;
    }
    qsort(cv, (size_t)m, sizeof *cv, compare_double);
    int n = l.instance_count;
    double sd_yaw = plm_degrees(sqrt(yaw[1] / n - sq(yaw[0] / n))), sd_lift = plm_degrees(sqrt(lift[1] / n - sq(lift[0] / n)));
    double sd_tint = sqrt(tint[1] / n - sq(tint[0] / n));
    printf("neighbourhood length CV median %.3f (%d feathers); yaw sd %.2f deg, lift sd %.2f deg, tint sd %.3f; "
           "identical neighbours %d\n", cv[m / 2], m, sd_yaw, sd_lift, sd_tint, same);
    assert_true(cv[m / 2] >= 0.05 && cv[m / 2] <= 0.15);
    assert_true(sd_yaw >= 2.0 && sd_yaw <= 5.0);
    assert_true(sd_lift > 0.1);
    assert_true(sd_tint > 0.01);
    assert_int_equal(same, 0);
    free(cv);
    plm_layout_free(&l);
    plm_species_free(&sp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(roots_have_no_lattice),
        cmocka_unit_test(sizes_shrink_toward_head_and_edges),
        cmocka_unit_test(neighbours_never_repeat),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
