/* Evaluation and sampling of the fiber BCSDF from a traced lobe set
 * (paper Eqs. 1 and 2 with D = 1).
 *
 * Each lobe k is an impulse of throughput A_k in direction (Theta_k, Phi_k),
 * blurred by the detectors: G_M, a Gaussian in theta of std-dev beta_m
 * truncated and normalised to [-pi/2, pi/2], and G_N, a Gaussian in phi of
 * std-dev beta_n wrapped onto the circle. Both are proper densities in
 * (theta, phi), so with the solid-angle measure cos(theta) dtheta dphi,
 *   eval(wi) cos(theta_i) = sum_k A_k G_M G_N / cos(theta_i)
 * integrates to sum_k A_k over the sphere, and sampling G_M and G_N exactly
 * gives pdf = sum_k P_k G_M G_N / cos(theta_i). */
#include "optics/fiber.h"

#include <float.h>

#define SQRT2 1.41421356237309504880
#define SQRT_2PI 2.50662827463100050242
#define HALF_PI (0.5 * PLM_PI)

/* c[0] + c[1] t + ... + c[n - 1] t^(n - 1), by Horner's rule. */
static double polynomial(const double *c, int n, double t)
{
    double p = c[n - 1];
    for (int i = n - 2; i >= 0; --i)
        p = p * t + c[i];
    return p;
}

/* c[0] + c[1] t + ... + c[n - 1] t^(n - 1) (n <= 32) by Estrin's scheme:
 * pairs c[i] + c[i + 1] t, then pairs of those with t^2, with t^4, ...: the
 * additions of a level do not wait on each other, so the chain is log2(n)
 * steps long instead of Horner's n. */
static double polynomial_estrin(const double *c, int n, double t)
{
    double v[16];
    int m = 0;
    for (int i = 0; i < n; i += 2)
        v[m++] = i + 1 < n ? c[i] + c[i + 1] * t : c[i];
    for (double p = t * t; m > 1; p *= p) {
        int k = 0;
        for (int i = 0; i < m; i += 2)
            v[k++] = i + 1 < m ? v[i] + v[i + 1] * p : v[i];
        m = k;
    }
    return v[0];
}

/* erfinv(y) / y for w = -log(1 - y^2) < 5 (|y| < 0.9966, where G_M's and
 * G_N's samplers land but for 0.34% of u), as a polynomial of degree 22 in
 * s = (w - 2.5) / 2.5: the Chebyshev interpolant on [-1, 1], off by less
 * than 2e-18 (computed for plumage at 60 digits, then rounded to doubles).
 * Its two leading terms by Horner's rule, which keeps their rounding small,
 * the rest by Estrin's scheme. erfinv(y) is then within 3 ulp (the
 * rounding of w, of the sum and of the product by y). */
static double erfinv_centre(double s)
{
    static const double c[23] = {
        1.501409351110792, 0.6166006918604175, -0.02610823577739765, -0.019573561059547377, 0.008525400950939892,
        -0.0004878983983252155, -0.0008341356436926482, 0.0002921906851342163, 2.0472417839420812e-05,
        -4.1432071450377935e-05, 8.652721877484876e-06, 2.851652817060834e-06, -1.853870554105327e-06,
        1.3583392473566449e-07, 1.9953933232996815e-07, -7.08985061397636e-08, -6.70810932648382e-09,
        1.1040417909061025e-08, -1.9880707100189075e-09, -9.760204713196851e-10, 4.4650677608736676e-10,
        3.867417238765463e-11, -3.9169363297916484e-11};
    return c[0] + s * (c[1] + s * polynomial_estrin(c + 2, 21, s));
}

/* A first guess at erfinv(y) where w = -log(1 - y^2) >= 5 (|y| from 0.9966
 * to 1 - DBL_EPSILON, w up to 36), relative error below 3.2e-8:
 * erfinv(y) / y as a polynomial of degree 12 in t = sqrt(w) - 4.125, which
 * interpolates it at the Chebyshev nodes of its t interval (coefficients
 * computed for plumage at 50 digits, then rounded to doubles). */
static double erfinv_tail_guess(double y, double w)
{
    static const double tail[13] = {3.9659885118570983,     1.0097691324581133,     0.0009621238629170097,
                                    -0.0007192407034188612, 0.0002574516084964363,  -9.835366838846713e-05,
                                    3.605000759870352e-05,  -4.739202267111365e-06, 8.495969002055456e-06,
                                    -1.222834500151884e-05, 3.560271971162274e-06,  9.712200729772167e-07,
                                    -4.249644392272747e-07};
    return y * polynomial(tail, 13, sqrt(w) - 4.125);
}

/* Inverse error function. Where w = -log(1 - y^2) < 5 the polynomial of
 * erfinv_centre, within 3 ulp; in the tails, and everywhere if polish is
 * set, a guess polished by one Halley step on erf, or on erfc near +-1
 * where 1 - |y| is exact (cubic convergence: from 3.2e-8 to below rounding;
 * within 2 ulp of erfinv over [-1 + DBL_EPSILON, 1 - DBL_EPSILON],
 * test_fiber_bcsdf). The step's erf and exp cost G_M's sampler, which
 * rounds theta to a few ulp anyway, as much as the rest of it, so it goes
 * without in the centre (docs/fiber.md). With f = erf(x) - y,
 * f' = 2/sqrt(pi) e^(-x^2) and f'' = -2x f', Halley's step is
 * f / (f' + x f). */
static double erfinv(double y, int polish)
{
    double w = -log((1.0 - y) * (1.0 + y));
    double x = w < 5.0 ? y * erfinv_centre((w - 2.5) * 0.4) : erfinv_tail_guess(y, w);
    if (w < 5.0 && !polish)
        return x;
    const double two_over_sqrt_pi = 1.12837916709551257390;
    double slope = two_over_sqrt_pi * exp(-x * x);
    if (!(slope > 0.0))
        return x;
    double sign = y < 0.0 ? -1.0 : 1.0;
    double residual = fabs(y) > 0.5 ? sign * ((1.0 - fabs(y)) - erfc(sign * x)) : erf(x) - y;
    return x - residual / (slope + x * residual);
}

/* erf(x) for x >= 0, skipping the call where it is 1 to double precision. */
static double erf_positive(double x) { return x > 6.0 ? 1.0 : erf(x); }

/* G_M about Theta prepared (fiber.h), given s = sqrt(2) beta, inv_s = 1 / s
 * and unit = 1 / (sqrt(2 pi) beta): erf at the standard scores of -pi/2 and
 * pi/2, and from them 1 / (sqrt(2 pi) beta Z) with Z = (erf_hi - erf_lo) / 2
 * the mass inside (no division when Z is 1 to double precision, as for
 * most lobes). */
static void gm_detector(double Theta, double s, double inv_s, double unit, plm_fiber_gm_detector *g)
{
    g->theta = Theta;
    g->s = s;
    g->erf_lo = -erf_positive((HALF_PI + Theta) * inv_s);
    g->erf_hi = erf_positive((HALF_PI - Theta) * inv_s);
    double z = 0.5 * (g->erf_hi - g->erf_lo);
    g->scale = z == 1.0 ? unit : unit / z;
}

/* Wraps an angle difference of two angles in [-pi, pi] into [-pi, pi]. */
static double wrap_pi(double d) { return d > PLM_PI ? d - PLM_TWO_PI : d < -PLM_PI ? d + PLM_TWO_PI : d; }

/* Terms of a Gaussian further than this many std-devs (e^-50 relative) are
 * skipped, in both detectors alike, so most lobes cost no exponential. */
#define GAUSSIAN_CUTOFF 10.0

/* e^(-dt^2 / (2 beta_m^2)), zero beyond the cutoff. */
static double gm_unnormalised(double dt, double beta, double inv2b2)
{
    return fabs(dt) < GAUSSIAN_CUTOFF * beta ? exp(-dt * dt * inv2b2) : 0.0;
}

/* sqrt(2 pi) beta G_N(dphi): the wrapped Gaussian on the circle, dphi in [-pi, pi]. */
static double gn_unnormalised(double dphi, double beta)
{
    double sum = 0.0, cutoff = GAUSSIAN_CUTOFF * beta, inv2b2 = 0.5 / (beta * beta);
    int wraps = 1 + (int)(cutoff / PLM_TWO_PI);
    for (int k = -wraps; k <= wraps; ++k) {
        double d = dphi + PLM_TWO_PI * k;
        if (fabs(d) < cutoff)
            sum += exp(-d * d * inv2b2);
    }
    return sum;
}

/* A uniform in [0, 1) to (-1, 1) for erfinv, never reaching the poles. */
static double to_open_symmetric(double u)
{
    double y = 2.0 * u - 1.0;
    return plm_clamp(y, -1.0 + DBL_EPSILON, 1.0 - DBL_EPSILON);
}

void plm_fiber_prepare(const plm_fiber_params *p, vec3 wo, double hmin, double hmax, plm_rng *rng,
                       plm_fiber_lobe_set *set)
{
    set->count = 0;
    set->total = 0.0;
    set->cdf[0] = 0.0;
    set->h = hmin + (hmax - hmin) * plm_rng_uniform(rng);
    if (p->lobes > PLM_FIBER_SET_MAX_LOBES)
        return;
    plm_fiber_lobe lobes[PLM_FIBER_SET_MAX_LOBES];
    int n = plm_fiber_trace(p, wo, set->h, rng, lobes);
    double s = SQRT2 * p->beta_m, inv_s = 1.0 / s, unit = 1.0 / (SQRT_2PI * p->beta_m);
    for (int i = 0; i < n; ++i) {
        double w = rgb_mean(lobes[i].throughput);
        if (!(w > 0.0))
            continue; /* black lobes add nothing to eval, pdf or sample */
        int k = set->count++;
        set->theta[k] = plm_safe_asin(lobes[i].dir.z);
        set->phi[k] = atan2(lobes[i].dir.y, lobes[i].dir.x);
        plm_fiber_gm_detector g;
        gm_detector(set->theta[k], s, inv_s, unit, &g);
        set->gm_scale[k] = g.scale;
        set->throughput[k] = lobes[i].throughput;
        set->cdf[k + 1] = set->cdf[k] + w;
    }
    set->total = set->cdf[set->count];
}

void plm_fiber_gm_detector_about(double beta_m, double Theta, plm_fiber_gm_detector *g)
{
    double s = SQRT2 * beta_m;
    gm_detector(Theta, s, 1.0 / s, 1.0 / (SQRT_2PI * beta_m), g);
}

double plm_fiber_gm(double beta_m, double scale, double dtheta)
{
    return scale * gm_unnormalised(dtheta, beta_m, 0.5 / (beta_m * beta_m));
}

double plm_fiber_sample_gm(const plm_fiber_gm_detector *g, double u)
{
    double y = plm_clamp(g->erf_lo + u * (g->erf_hi - g->erf_lo), -1.0 + DBL_EPSILON, 1.0 - DBL_EPSILON);
    return plm_clamp(g->theta + g->s * erfinv(y, 0), -HALF_PI, HALF_PI);
}

double plm_fiber_normal_quantile(double u) { return SQRT2 * erfinv(to_open_symmetric(u), 1); }

/* sum_k A_k G_M G_N and sum_k mean(A_k) G_M G_N at (theta, phi). */
static void detector_sums_at(const plm_fiber_params *p, const plm_fiber_lobe_set *set, double theta, double phi,
                             rgb *f_sum, double *p_sum)
{
    *f_sum = rgb_gray(0.0);
    *p_sum = 0.0;
    double inv2bm2 = 0.5 / (p->beta_m * p->beta_m), inv2bn2 = 0.5 / (p->beta_n * p->beta_n);
    double gn_scale = 1.0 / (SQRT_2PI * p->beta_n);
    /* With beta_n < pi / cutoff only the unwrapped term of G_N can matter, and
     * one exponential serves both detectors. */
    int single_wrap = GAUSSIAN_CUTOFF * p->beta_n <= PLM_PI;
    double cut_m = GAUSSIAN_CUTOFF * p->beta_m, cut_n = GAUSSIAN_CUTOFF * p->beta_n;
    for (int k = 0; k < set->count; ++k) {
        double dt = theta - set->theta[k], dp = wrap_pi(phi - set->phi[k]), d;
        if (single_wrap)
            d = fabs(dt) < cut_m && fabs(dp) < cut_n ? exp(-dt * dt * inv2bm2 - dp * dp * inv2bn2) : 0.0;
        else
            d = gm_unnormalised(dt, p->beta_m, inv2bm2) * gn_unnormalised(dp, p->beta_n);
        d *= set->gm_scale[k] * gn_scale;
        *f_sum = rgb_add(*f_sum, rgb_scale(set->throughput[k], d));
        *p_sum += (set->cdf[k + 1] - set->cdf[k]) * d;
    }
}

/* The sums at wi, and cos(theta_i); returns 0 at the poles, where both
 * densities' 1/cos(theta) has no meaning. */
static int detector_sums(const plm_fiber_params *p, const plm_fiber_lobe_set *set, vec3 wi, rgb *f_sum,
                         double *p_sum, double *cos_theta)
{
    double ct = sqrt(wi.x * wi.x + wi.y * wi.y);
    *cos_theta = ct;
    if (!(ct > 1e-12)) {
        *f_sum = rgb_gray(0.0);
        *p_sum = 0.0;
        return 0;
    }
    /* asin is cheaper than atan2 and as accurate away from the poles. */
    double theta = fabs(wi.z) < 0.9 ? asin(wi.z) : atan2(wi.z, ct);
    detector_sums_at(p, set, theta, atan2(wi.y, wi.x), f_sum, p_sum);
    return 1;
}

double plm_fiber_lobe_gm(const plm_fiber_params *p, const plm_fiber_lobe_set *set, int k, double theta)
{
    return set->gm_scale[k] * gm_unnormalised(theta - set->theta[k], p->beta_m, 0.5 / (p->beta_m * p->beta_m));
}

double plm_fiber_lobe_gn(const plm_fiber_params *p, const plm_fiber_lobe_set *set, int k, double phi)
{
    return gn_unnormalised(wrap_pi(remainder(phi, PLM_TWO_PI) - set->phi[k]), p->beta_n) / (SQRT_2PI * p->beta_n);
}

rgb plm_fiber_eval(const plm_fiber_params *p, const plm_fiber_lobe_set *set, vec3 wi)
{
    rgb f;
    double unused, ct;
    if (!detector_sums(p, set, wi, &f, &unused, &ct))
        return rgb_gray(0.0);
    return rgb_scale(f, 1.0 / (ct * ct));
}

double plm_fiber_pdf(const plm_fiber_params *p, const plm_fiber_lobe_set *set, vec3 wi)
{
    rgb unused;
    double s, ct;
    if (!(set->total > 0.0) || !detector_sums(p, set, wi, &unused, &s, &ct))
        return 0.0;
    return s / (set->total * ct);
}

int plm_fiber_sample(const plm_fiber_params *p, const plm_fiber_lobe_set *set, double u0, double u1, double u2,
                     plm_fiber_sample_rec *rec)
{
    if (!(set->total > 0.0))
        return 0;
    double target = u0 * set->total;
    int k = 0;
    while (k + 1 < set->count && set->cdf[k + 1] <= target)
        ++k;
    plm_fiber_gm_detector g;
    plm_fiber_gm_detector_about(p->beta_m, set->theta[k], &g);
    double theta = plm_fiber_sample_gm(&g, u1);
    double phi = remainder(set->phi[k] + p->beta_n * plm_fiber_normal_quantile(u2), PLM_TWO_PI);
    /* remainder(): the sampled offset may wrap several times when beta_n is large. */
    vec3 wi = plm_fiber_direction(theta, phi);
    double ct = sqrt(wi.x * wi.x + wi.y * wi.y), s; /* as eval and pdf compute it from wi */
    rgb f;
    if (!(ct > 1e-12))
        return 0;
    detector_sums_at(p, set, theta, phi, &f, &s); /* the angles eval would recover from wi, to rounding */
    if (!(s > 0.0))
        return 0;
    rec->wi = wi;
    rec->pdf = s / (set->total * ct);
    rec->weight = rgb_scale(f, set->total / s); /* eval cos / pdf, without forming the 1/cos factors */
    rec->lobe = k;
    return 1;
}
