/* Shared by the tabulated fiber BCSDF tests (test_fiber_table.c,
 * slow_fiber_table.c): a first-principles reference of the part of the BCSDF
 * the table holds, and its relative L2 error over random queries. Include
 * after cmocka.h. */
#ifndef PLUMAGE_TESTS_FIBER_TABLE_STATS_H
#define PLUMAGE_TESTS_FIBER_TABLE_STATS_H

#include <stdio.h>
#include <stdlib.h>

#include "optics/fiber_bcsdf.h"

/* The longitudinal detector: a Gaussian of std-dev beta about Theta,
 * normalised on [-pi/2, pi/2], written out independently of fiber.c. */
static double reference_gm(double beta, double Theta, double theta)
{
    double s = sqrt(2.0) * beta;
    double z = 0.5 * (erf((0.5 * PLM_PI - Theta) / s) + erf((0.5 * PLM_PI + Theta) / s));
    return exp(-0.5 * plm_sqr((theta - Theta) / beta)) / (sqrt(2.0 * PLM_PI) * beta * z);
}

/* The azimuthal detector: a Gaussian wrapped onto the circle, `wraps` turns
 * either side of dphi. */
static double reference_gn(double beta, double dphi, int wraps)
{
    double sum = 0.0;
    for (int k = -wraps; k <= wraps; ++k)
        sum += exp(-0.5 * plm_sqr((dphi + PLM_TWO_PI * k) / beta));
    return sum / (sqrt(2.0 * PLM_PI) * beta);
}

/* The mean over h in [hmin, hmax] (strata midpoints) of eval(wi) from the
 * lobes that never meet the medulla: sum_k A_k G_M G_N / cos^2(theta_i). */
static rgb reference_eval(const plm_fiber_params *p, vec3 wo, double hmin, double hmax, vec3 wi, int strata)
{
    plm_fiber_lobe *lobes = malloc(sizeof *lobes * (size_t)p->lobes);
    plm_rng rng;
    plm_rng_seed(&rng, 5, 5);
    double ct = sqrt(wi.x * wi.x + wi.y * wi.y), theta = atan2(wi.z, ct), phi = atan2(wi.y, wi.x);
    rgb sum = rgb_gray(0.0);
    for (int s = 0; s < strata; ++s) {
        double h = hmin + (hmax - hmin) * (s + 0.5) / strata;
        int n = plm_fiber_trace(p, wo, h, &rng, lobes);
        for (int k = 0; k < n && !lobes[k].medulla; ++k) {
            double Theta = asin(lobes[k].dir.z), Phi = atan2(lobes[k].dir.y, lobes[k].dir.x);
            double d = reference_gm(p->beta_m, Theta, theta) * reference_gn(p->beta_n, phi - Phi, 6);
            sum = rgb_add(sum, rgb_scale(lobes[k].throughput, d));
        }
    }
    free(lobes);
    return rgb_scale(sum, 1.0 / (strata * ct * ct));
}

/* The table's part of eval without the medulla's. */
static rgb table_part_eval(const plm_fiber_table *t, vec3 wo, double hmin, double hmax, vec3 wi)
{
    plm_fiber_bcsdf b;
    plm_fiber_bcsdf_prepare(&t->params, t, wo, hmin, hmax, NULL, &b);
    b.med.table = NULL;
    b.med.total = 0.0;
    return plm_fiber_bcsdf_eval(&b, wi);
}

static vec3 random_sphere(plm_rng *rng)
{
    return plm_fiber_direction(asin(2.0 * plm_rng_uniform(rng) - 1.0), PLM_TWO_PI * plm_rng_uniform(rng));
}

/* The radical inverse of i in base b: i's digits mirrored about the point. */
static double radical_inverse(unsigned i, unsigned b)
{
    double x = 0.0, scale = 1.0 / b;
    for (; i > 0; i /= b, scale /= b)
        x += (i % b) * scale;
    return x;
}

/* Point s of the Halton sequence in bases 2, 3 and 5, shifted modulo 1. */
static void shifted_halton(int s, const double shift[3], double u[3])
{
    static const unsigned base[3] = {2, 3, 5};
    for (int d = 0; d < 3; ++d) {
        u[d] = radical_inverse((unsigned)s, base[d]) + shift[d];
        u[d] -= floor(u[d]);
    }
}

/* Adds eval(wi[i]) / paths of a lobe of weight A leaving in direction dir
 * to x[3 i .. 3 i + 2] for every wi (G_N's wraps beyond one turn dropped:
 * below e^-100 for beta_n < 0.6 rad). */
static void add_lobe_eval(const plm_fiber_params *p, rgb A, vec3 dir, const vec3 *wi, int n, int paths, double *x)
{
    double Theta = asin(dir.z), Phi = atan2(dir.y, dir.x);
    for (int i = 0; i < n; ++i) {
        double ct = sqrt(wi[i].x * wi[i].x + wi[i].y * wi[i].y), theta = atan2(wi[i].z, ct);
        if (fabs(theta - Theta) > 12.0 * p->beta_m)
            continue; /* below e^-72 */
        double dphi = remainder(atan2(wi[i].y, wi[i].x) - Phi, PLM_TWO_PI);
        double d = reference_gm(p->beta_m, Theta, theta) * reference_gn(p->beta_n, dphi, 1) / (ct * ct);
        x[3 * i] += A.r * d / paths;
        x[3 * i + 1] += A.g * d / paths;
        x[3 * i + 2] += A.b * d / paths;
    }
}

/* One shift's estimate of eval at every wi into x (RGB per wi): the mean
 * over `per` paths whose h and first diffuse direction are the shifted
 * Halton points 0..per-1. */
static void medulla_shift_estimate(const plm_fiber_params *p, vec3 wo, double hmin, double hmax, const vec3 *wi,
                                   int n, int per, const double shift[3], plm_rng *rng, plm_fiber_lobe *lobes,
                                   double *x)
{
    for (int i = 0; i < 3 * n; ++i)
        x[i] = 0.0;
    for (int s = 0; s < per; ++s) {
        double u[3];
        shifted_halton(s, shift, u);
        plm_fiber_medulla_hit hit;
        if (!plm_fiber_trace_to_medulla(p, wo, hmin + (hmax - hmin) * u[0], lobes, &hit))
            continue;
        int m = plm_fiber_trace_from_medulla(p, hit.t, u[1], u[2], rng, lobes, p->lobes - hit.lobes);
        for (int k = 0; k < m; ++k)
            add_lobe_eval(p, rgb_mul(hit.throughput, lobes[k].throughput), lobes[k].dir, wi, n, per, x);
    }
}

/* The converged stochastic mean of the medulla's part, written apart from
 * the table: the stochastic estimator's paths (plm_fiber_trace_to_medulla,
 * then plm_fiber_trace_from_medulla with the lobes left, which
 * test_fiber_table checks against plm_fiber_trace), `sets` of them (a
 * positive multiple of SHIFTS), each's lobes evaluated at every wi[i] with
 * the detectors above. The entry offset h and the first diffuse direction
 * come from a randomised quasi-Monte Carlo set: the Halton points in bases
 * 2, 3 and 5, shifted modulo 1 by a random vector, SHIFTS times (later
 * bounces are random). A wi sees light from few directions only, so random
 * sets leave it noisy; the points spread evenly over (h, direction) cut
 * that noise several times at the same cost. mean[i] is the mean over the
 * shifts, var[i] the variance of that mean (unbiased, from the shifts'
 * spread). */
static void reference_medulla(const plm_fiber_params *p, vec3 wo, double hmin, double hmax, const vec3 *wi, int n,
                              int sets, plm_rng *rng, rgb *mean, rgb *var)
{
    enum { SHIFTS = 16 };
    assert_true(sets >= SHIFTS && sets % SHIFTS == 0);
    plm_fiber_lobe *lobes = malloc(sizeof *lobes * (size_t)p->lobes);
    double *sum = calloc(6 * (size_t)n, sizeof(double)), *x = malloc(3 * sizeof(double) * (size_t)n);
    for (int r = 0; r < SHIFTS; ++r) {
        double shift[3] = {plm_rng_uniform(rng), plm_rng_uniform(rng), plm_rng_uniform(rng)};
        medulla_shift_estimate(p, wo, hmin, hmax, wi, n, sets / SHIFTS, shift, rng, lobes, x);
        for (int i = 0; i < 3 * n; ++i) {
            sum[2 * i] += x[i];
            sum[2 * i + 1] += x[i] * x[i];
        }
    }
    for (int i = 0; i < n; ++i) {
        double m[3], v[3];
        for (int c = 0; c < 3; ++c) {
            m[c] = sum[2 * (3 * i + c)] / SHIFTS;
            v[c] = fmax(0.0, sum[2 * (3 * i + c) + 1] / SHIFTS - m[c] * m[c]) / (SHIFTS - 1);
        }
        mean[i] = rgb_make(m[0], m[1], m[2]);
        var[i] = rgb_make(v[0], v[1], v[2]);
    }
    free(lobes);
    free(sum);
    free(x);
}

/* The table's medulla part alone. */
static rgb table_medulla_eval(const plm_fiber_table *t, vec3 wo, double hmin, double hmax, vec3 wi)
{
    plm_fiber_bcsdf b;
    plm_fiber_bcsdf_prepare(&t->params, t, wo, hmin, hmax, NULL, &b);
    b.tab.total = 0.0;
    return plm_fiber_bcsdf_eval(&b, wi);
}

/* The table's whole BCSDF, both parts. */
static rgb table_whole_eval(const plm_fiber_table *t, vec3 wo, double hmin, double hmax, vec3 wi)
{
    plm_fiber_bcsdf b;
    plm_fiber_bcsdf_prepare(&t->params, t, wo, hmin, hmax, NULL, &b);
    return plm_fiber_bcsdf_eval(&b, wi);
}

/* Accumulates a relative L2 difference per channel (RGB) with a noisy
 * reference (see medulla_error) and, at the end, finishes it. */
typedef struct noisy_l2 {
    double num[3], den[3], var[3];
} noisy_l2;

static void noisy_l2_add(noisy_l2 *l, rgb a, rgb m, rgb var)
{
    double av[3] = {a.r, a.g, a.b}, mv[3] = {m.r, m.g, m.b}, vv[3] = {var.r, var.g, var.b};
    for (int c = 0; c < 3; ++c) {
        l->num[c] += plm_sqr(av[c] - mv[c]);
        l->den[c] += plm_sqr(mv[c]);
        l->var[c] += vv[c];
    }
}

static void noisy_l2_finish(const noisy_l2 *l, double err[3], double noise[3])
{
    for (int c = 0; c < 3; ++c) {
        double signal = l->den[c] - l->var[c];
        err[c] = signal > 0.0 ? sqrt(fmax(0.0, l->num[c] - l->var[c]) / signal) : 0.0;
        if (noise)
            noise[c] = signal > 0.0 ? sqrt(l->var[c] / signal) : 0.0;
    }
}

/* Relative L2 difference per channel of the table's medulla part against
 * reference_medulla over `views` random (wo, h-interval) with `n` uniform wi
 * each, the reference's own noise taken out: err^2 = (sum (a - m)^2 - sum
 * var) / (sum m^2 - sum var), as E[(a - m)^2] = (a - mean)^2 + var. noise
 * receives sqrt(sum var / (sum m^2 - sum var)), the reference's relative
 * noise, which the estimate of err is only good to a fraction of. Compared
 * is eval cos(theta_i), what a renderer integrates: the medulla part is
 * spread over all theta_i, and eval's 1 / cos^2(theta_i) would give the few
 * wi nearest the fiber's axis most of the L2 norm (its square is not even
 * integrable there). If whole is not NULL it receives the same difference
 * for the whole BCSDF at the same queries: the table's two parts together
 * against reference_eval (2000 strata) plus reference_medulla, the
 * estimator's requirement as stated (the part without the medulla's
 * reference is exact, so the noise is the medulla reference's). The
 * draws from rng are the same either way. */
static inline void medulla_error(const plm_fiber_table *t, plm_rng *rng, int views, int n, int sets, double err[3],
                                 double noise[3], double whole[3])
{
    noisy_l2 part = {.num = {0}}, all = {.num = {0}};
    vec3 *wi = malloc(sizeof *wi * (size_t)n);
    rgb *mean = malloc(sizeof *mean * (size_t)n), *var = malloc(sizeof *var * (size_t)n);
    for (int q = 0; q < views; ++q) {
        vec3 wo = random_sphere(rng);
        double h0 = 2.0 * plm_rng_uniform(rng) - 1.0, h1 = 2.0 * plm_rng_uniform(rng) - 1.0;
        double hmin = fmin(h0, h1), hmax = fmax(h0, h1);
        for (int i = 0; i < n; ++i)
            wi[i] = random_sphere(rng);
        reference_medulla(&t->params, wo, hmin, hmax, wi, n, sets, rng, mean, var);
        for (int i = 0; i < n; ++i) {
            double cw = sqrt(wi[i].x * wi[i].x + wi[i].y * wi[i].y);
            mean[i] = rgb_scale(mean[i], cw);
            var[i] = rgb_scale(var[i], cw * cw);
            noisy_l2_add(&part, rgb_scale(table_medulla_eval(t, wo, hmin, hmax, wi[i]), cw), mean[i], var[i]);
            if (whole) {
                rgb ref = rgb_add(mean[i], rgb_scale(reference_eval(&t->params, wo, hmin, hmax, wi[i], 2000), cw));
                noisy_l2_add(&all, rgb_scale(table_whole_eval(t, wo, hmin, hmax, wi[i]), cw), ref, var[i]);
            }
        }
    }
    noisy_l2_finish(&part, err, noise);
    if (whole)
        noisy_l2_finish(&all, whole, NULL);
    free(wi);
    free(mean);
    free(var);
}

/* slow_fiber_table's random fiber: circular (with a centred circular
 * medulla or none) or elliptical, the rest drawn from rng. Returns 0 if the
 * draw is not a valid fiber (then draw again); name (size bytes) receives
 * its name. */
static inline int random_table_fiber(plm_rng *rng, int circular, int index, plm_fiber_params *p, char *name, size_t size)
{
    plm_fiber_params_default(p);
    p->eta = 1.3 + 0.4 * plm_rng_uniform(rng);
    p->sigma_a = rgb_make(3.0 * plm_rng_uniform(rng), plm_rng_uniform(rng), 0.1 * plm_rng_uniform(rng));
    p->beta_m = plm_radians(3.0 + 20.0 * plm_rng_uniform(rng));
    p->beta_n = plm_radians(4.0 + 20.0 * plm_rng_uniform(rng));
    p->eccentricity = circular ? 1.0 : 1.1 + 0.8 * plm_rng_uniform(rng);
    if (plm_rng_uniform(rng) < 0.5) {
        p->medulla_a = p->medulla_b = 0.2 + 0.5 * plm_rng_uniform(rng);
        p->medulla_reflectance = rgb_gray(plm_rng_uniform(rng));
    }
    snprintf(name, size, "random %d (e %.2f, bn %.1f deg)", index, p->eccentricity, plm_degrees(p->beta_n));
    return plm_fiber_params_validate(p, NULL) == PLM_OK;
}

/* One query of table_error: wo uniform on the sphere, an h-interval with
 * uniform ends, and wi either uniform on the sphere (uniform_wi) or at the
 * lobes: theta_i = -theta_o plus a normal offset of beta_m, phi_i uniform
 * (where the table's values matter most). Tests that compare other
 * estimators on table_error's queries draw them here. */
typedef struct stats_query {
    vec3 wo, wi;
    double hmin, hmax;
} stats_query;

static stats_query error_query(const plm_fiber_params *p, plm_rng *rng, int uniform_wi)
{
    stats_query q;
    q.wo = random_sphere(rng);
    double h0 = 2.0 * plm_rng_uniform(rng) - 1.0, h1 = 2.0 * plm_rng_uniform(rng) - 1.0;
    q.hmin = fmin(h0, h1);
    q.hmax = fmax(h0, h1);
    if (uniform_wi) {
        q.wi = random_sphere(rng);
    } else {
        double u1 = fmax(plm_rng_uniform(rng), 1e-12), u2 = plm_rng_uniform(rng);
        double g = sqrt(-2.0 * log(u1)) * cos(PLM_TWO_PI * u2); /* Box-Muller */
        double theta = plm_clamp(-asin(q.wo.z) + p->beta_m * g, -1.55, 1.55);
        q.wi = plm_fiber_direction(theta, PLM_TWO_PI * plm_rng_uniform(rng));
    }
    return q;
}

/* Relative L2 difference per channel, sqrt(sum (table - ref)^2 / sum ref^2),
 * over n random queries (error_query). */
static inline void table_error(const plm_fiber_table *t, plm_rng *rng, int n, int uniform_wi, int strata, double err[3])
{
    const plm_fiber_params *p = &t->params;
    double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i) {
        stats_query q = error_query(p, rng, uniform_wi);
        rgb a = table_part_eval(t, q.wo, q.hmin, q.hmax, q.wi);
        rgb b = reference_eval(p, q.wo, q.hmin, q.hmax, q.wi, strata);
        double av[3] = {a.r, a.g, a.b}, bv[3] = {b.r, b.g, b.b};
        for (int c = 0; c < 3; ++c) {
            num[c] += plm_sqr(av[c] - bv[c]);
            den[c] += plm_sqr(bv[c]);
        }
    }
    for (int c = 0; c < 3; ++c)
        err[c] = den[c] > 0.0 ? sqrt(num[c] / den[c]) : 0.0;
}

#endif
