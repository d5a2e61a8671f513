/* Helpers shared by the feather BSDF tests (test_feather_bsdf.c,
 * slow_render.c): a feather material on a plane, the Monte Carlo integral
 * of eval, and the chi-square test (chi_square.h) of sample against pdf. */
#ifndef PLUMAGE_TESTS_FEATHER_BSDF_STATS_H
#define PLUMAGE_TESTS_FEATHER_BSDF_STATS_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/material.h"
#include "optics/feather_bsdf.h"
#include "common/sampling.h"
#include "tests/assert_double.h"
#include "tests/chi_square.h"

/* A feather material whose texture is vane everywhere with barbs at angle a (uv space). */
static inline plm_material feather_material(const plm_feather_params *p, double a)
{
    plm_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "feather");
    m.type = PLM_MATERIAL_FEATHER;
    m.reflectance = rgb_gray(0.8);
    m.feather = malloc(sizeof *m.feather);
    *m.feather = *p;
    float *px = malloc(sizeof(float) * 4 * 4 * 3);
    for (int i = 0; i < 16; ++i)
        px[3 * i] = (float)((cos(a) + 1) / 2), px[3 * i + 1] = (float)((sin(a) + 1) / 2), px[3 * i + 2] = 1.0f;
    plm_error err;
    assert_int_equal(plm_feather_texture_from_pixels(4, 4, px, &m.texture, &err), PLM_OK);
    return m;
}

static inline void free_material(plm_material *m)
{
    plm_feather_texture_free(&m->texture);
    free(m->feather);
}

/* A hit on the plane z = 0 with u along x, v along y (toward the tip), normal +z,
 * with what rendering derives from m prepared into *prepared (no tables: add
 * them from a table set with plm_material_prepare_tables). */
static inline plm_hit plane_hit(const plm_material *m, plm_prepared_material *prepared)
{
    plm_material_prepare(m, prepared);
    plm_hit h;
    memset(&h, 0, sizeof h);
    h.ng = h.n = v3(0, 0, 1);
    h.dpdu = v3(1, 0, 0);
    h.dpdv = v3(0, 1, 0);
    h.uv = v2(0.5, 0.5);
    h.tint = rgb_gray(1.0);
    h.material = m;
    h.prepared = prepared;
    plm_material_surface(&h);
    return h;
}

/* Uniform-sphere Monte Carlo of the integral of eval, with its standard error. */
static inline void integrate_eval(const plm_bsdf *b, plm_rng *rng, int n, double *mean, double *se)
{
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        vec3 wi = plm_sample_uniform_sphere(plm_rng_uniform(rng), plm_rng_uniform(rng));
        double v = rgb_mean(plm_bsdf_eval(b, wi)) * 4.0 * PLM_PI;
        sum += v;
        sum2 += v * v;
    }
    *mean = sum / n;
    *se = sqrt(fmax(sum2 / n - *mean * *mean, 0.0) / n);
}

/* White furnace of one prepared BSDF at a hit: the integral of eval (f|cos|
 * divided by 1 - w_t) over the sphere, by n uniform samples, must equal the
 * weighted lobe energy of its lobe sets within z_max standard errors.
 * Returns the albedo (1 - w_t) x lobe energy + w_t, which is at most 1. */
static inline double furnace_albedo(const plm_hit *hit, vec3 wo, plm_rng *rng, int n, double z_max, const char *label)
{
    plm_bsdf b;
    plm_material_bsdf(hit, wo, rng, &b);
    const plm_feather_bsdf *f = (const plm_feather_bsdf *)b.state;
    double lobe_energy = 0.0;
    for (int k = 0; k < f->count; ++k)
        lobe_energy += f->weight[k] * f->bcsdf[k].total; /* the mean over RGB of each fiber's lobe energy */
    double integral, se;
    integrate_eval(&b, rng, n, &integral, &se);
    double wt = plm_material_transmission(hit, wo), albedo = (1.0 - wt) * lobe_energy + wt;
    fprintf(stderr, "%s: integral %.4f +- %.4f, lobe energy %.4f, w_t %.3f, albedo %.4f\n", label, integral, se,
            lobe_energy, wt, albedo);
    if (fabs(integral - lobe_energy) > z_max * se + 1e-3)
        fail_msg("%s: integral of f|cos| %.4f +- %.4f, lobe energy %.4f", label, integral, se, lobe_energy);
    assert_double_near(wt, f->masking.w_transmission, 1e-15);
    assert_true(albedo <= 1.0 + 1e-9);
    return albedo;
}

enum { THETA_BINS = 60, PHI_BINS = 120 };

/* Cell of the (theta, phi) grid of frame f holding w (theta = asin(w.z), phi = atan2(w.y, w.x)). */
static int grid_cell(const frame *f, vec3 w)
{
    vec3 l = frame_to_local(f, w);
    return chi_square_cell(asin(plm_clamp(l.z, -1, 1)), atan2(l.y, l.x), THETA_BINS, PHI_BINS);
}

/* A sample drawn with u0 first: its pdf is the chosen fiber's technique's,
 * pick_k pdf_k (what MIS weighs it by), plm_bsdf_pdf the pick-weighted
 * mixture of the three fibers' pdfs, and its weight the chosen fiber's own
 * S_k cos / pdf_k times weight_k / pick_k (its mean is tested by the
 * feather's weight test). */
static void check_sample(const plm_bsdf *b, double u0, const plm_bsdf_sample_rec *rec)
{
    const plm_feather_bsdf *fb = (const plm_feather_bsdf *)b->state;
    double pdf = plm_bsdf_pdf(b, rec->wi), mix = 0.0, unused;
    for (int k = 0; k < fb->count; ++k)
        if (fb->pick[k] > 0.0)
            mix += fb->pick[k] * plm_fiber_bcsdf_pdf(&fb->bcsdf[k], frame_to_local(&fb->fiber_frame[k], rec->wi));
    assert_double_near(mix, pdf, 1e-12 * pdf);
    int k = plm_feather_pick(fb, u0, &unused);
    vec3 l = frame_to_local(&fb->fiber_frame[k], rec->wi);
    double pk, own = plm_fiber_bcsdf_eval_pdf(&fb->bcsdf[k], l, &pk).r * sqrt(l.x * l.x + l.y * l.y) / pk *
                     fb->weight[k] / fb->pick[k];
    assert_double_near(rec->pdf, fb->pick[k] * pk, 1e-12 * rec->pdf);
    assert_double_near(rec->weight.r, own, 1e-9 * own + 1e-300);
}

/* The pdf's integral over cell (it, ip) of frame f's (theta, phi) grid by an
 * n x n midpoint rule (pbrt-v4's test uses 8 x 8). A cell whose largest
 * midpoint value exceeds four times their mean holds a peak, which 8 x 8
 * points miss: an elliptical fiber's caustic reaches a pdf of 1,600 in one
 * 3-degree cell of slow_render's config 26, where 449 samples fell, 512 x 512
 * points expect 439 and 8 x 8 expected 184. Such a cell is integrated again on
 * a three times finer grid, up to 72 x 72. */
static double cell_probability(const plm_bsdf *b, const frame *f, int it, int ip, int n)
{
    const double dt = PLM_PI / THETA_BINS, df = PLM_TWO_PI / PHI_BINS;
    double sum = 0.0, peak = 0.0;
    for (int a = 0; a < n; ++a)
        for (int c = 0; c < n; ++c) {
            double theta = -0.5 * PLM_PI + (it + (a + 0.5) / n) * dt, phi = -PLM_PI + (ip + (c + 0.5) / n) * df;
            double p = plm_bsdf_pdf(b, frame_to_world(f, v3(cos(theta) * cos(phi), cos(theta) * sin(phi), sin(theta))));
            sum += p * cos(theta);
            peak = fmax(peak, p * cos(theta));
        }
    double probability = sum * dt * df / ((double)n * n);
    if (peak <= 4.0 * sum / ((double)n * n) || n >= 72)
        return probability;
    return cell_probability(b, f, it, ip, 3 * n);
}

/* Histogram of plm_bsdf_sample over a (theta, phi) grid of the barb frame
 * against the pdf integrated over each cell (cell_probability), each sample
 * checked on its own (check_sample). Returns the p-value of Pearson's
 * chi-square. */
static inline double chi_square(const plm_bsdf *b, plm_rng *rng, int n)
{
    static double observed[THETA_BINS * PHI_BINS], expected[THETA_BINS * PHI_BINS];
    memset(observed, 0, sizeof observed);
    const plm_feather_bsdf *fb = (const plm_feather_bsdf *)b->state;
    const frame f = fb->fiber_frame[PLM_FEATHER_BARB];
    for (int s = 0; s < n; ++s) {
        plm_bsdf_sample_rec rec;
        double u0 = plm_rng_uniform(rng), u1 = plm_rng_uniform(rng), u2 = plm_rng_uniform(rng);
        if (!plm_bsdf_sample(b, u0, u1, u2, &rec))
            continue;
        check_sample(b, u0, &rec);
        observed[grid_cell(&f, rec.wi)] += 1.0;
    }
    for (int it = 0; it < THETA_BINS; ++it)
        for (int ip = 0; ip < PHI_BINS; ++ip)
            expected[it * PHI_BINS + ip] = n * cell_probability(b, &f, it, ip, 8);
    double total = 0.0;
    for (int i = 0; i < THETA_BINS * PHI_BINS; ++i)
        total += expected[i];
    assert_double_near(total / n, 1.0, 0.01); /* the pdf integrates to 1 */
    return chi_square_test(observed, expected, THETA_BINS * PHI_BINS);
}

#endif
