/* The fiber BCSDF of barbs and barbules (paper Sec. 5, Eqs. 1-3).
 *
 * A fiber (optics/fiber_params.h) is traced by optics/fiber_trace.h.
 * Directions are in the fiber frame (x = e2, y = e3, z = fiber axis);
 * theta = asin(w.z), phi = atan2(w.y, w.x).
 *
 * Evaluation follows the paper's stochastic scheme, made exactly
 * self-consistent: per shading query a *lobe set* is traced once from the
 * view direction wo (plm_fiber_prepare), and eval/pdf/sample are then
 * deterministic functions of (set, wi). The expectation over lobe sets of
 * plm_fiber_eval is the BCSDF of Eqs. 1-2 (with D = 1). */
#ifndef PLUMAGE_OPTICS_FIBER_H
#define PLUMAGE_OPTICS_FIBER_H

#include "common/rng.h"
#include "common/vec.h"
#include "optics/fiber_params.h"
#include "optics/fiber_trace.h"

/* Most lobes a lobe set (the rendering path) holds. */
#define PLM_FIBER_SET_MAX_LOBES 32

/* A traced lobe set: what eval/pdf/sample need, precomputed once. */
typedef struct plm_fiber_lobe_set {
    int count;
    double h;                                     /* the entry offset traced */
    double theta[PLM_FIBER_SET_MAX_LOBES];        /* lobe direction Theta_k */
    double phi[PLM_FIBER_SET_MAX_LOBES];          /* lobe direction Phi_k */
    double gm_scale[PLM_FIBER_SET_MAX_LOBES];     /* 1 / (sqrt(2 pi) beta_m Z_k): G_M's normalisation */
    rgb throughput[PLM_FIBER_SET_MAX_LOBES];      /* A_k */
    double cdf[PLM_FIBER_SET_MAX_LOBES + 1];      /* lobe choice, P_k proportional to mean(A_k) */
    double total;                                 /* sum of mean(A_k); 0 = nothing to sample */
} plm_fiber_lobe_set;

/* Picks h uniformly in [hmin, hmax] within [-1, 1] (a one-sample estimate
 * of Eq. 1's h-integral), traces from wo (unit) and fills set. Requires p->lobes <=
 * PLM_FIBER_SET_MAX_LOBES (otherwise the set is left empty). */
void plm_fiber_prepare(const plm_fiber_params *p, vec3 wo, double hmin, double hmax, plm_rng *rng,
                       plm_fiber_lobe_set *set);

/* The longitudinal detector G_M about Theta, a Gaussian of std-dev beta_m
 * truncated to [-pi/2, pi/2], prepared once per Theta: its normalisation
 * scale = 1 / (sqrt(2 pi) beta_m Z), Z the Gaussian's mass inside
 * [-pi/2, pi/2], and erf at the standard scores of the ends, between which
 * its inverse CDF maps u. Its value is scale * exp(-dtheta^2 / (2 beta_m^2))
 * (0 beyond 10 std-devs); the inverse of its CDF at u in [0, 1) is
 * plm_fiber_sample_gm. Lobes that never meet the medulla all share Theta =
 * -theta_o, which the tabulated BCSDF (optics/fiber_table.h) builds on. */
typedef struct plm_fiber_gm_detector {
    double theta, s; /* Theta and sqrt(2) beta_m */
    double scale, erf_lo, erf_hi;
} plm_fiber_gm_detector;
void plm_fiber_gm_detector_about(double beta_m, double Theta, plm_fiber_gm_detector *g);
double plm_fiber_gm(double beta_m, double scale, double dtheta);
double plm_fiber_sample_gm(const plm_fiber_gm_detector *g, double u);
/* The standard normal's inverse CDF at u in [0, 1), kept finite: G_N's
 * sampler, and the tabulated BCSDF's for its moving lobes. */
double plm_fiber_normal_quantile(double u);

/* S(wo, wi) for a unit wi: eval(wi) cos(theta_i) = sum_k A_k G_M(theta_i - Theta_k) G_N(phi_i - Phi_k) / cos(theta_i),
 * so the integral of eval cos over the sphere is sum_k A_k. G_M is a Gaussian
 * normalised on [-pi/2, pi/2], G_N a wrapped Gaussian normalised on the circle. */
rgb plm_fiber_eval(const plm_fiber_params *p, const plm_fiber_lobe_set *set, vec3 wi);
/* Solid-angle density of plm_fiber_sample: sum_k P_k G_M G_N / cos(theta_i). */
double plm_fiber_pdf(const plm_fiber_params *p, const plm_fiber_lobe_set *set, vec3 wi);

/* The two detectors of lobe k on their own, for plots that exploit their
 * separability: eval(wi) cos^2(theta_i) = sum_k A_k G_M(theta_i) G_N(phi_i). */
double plm_fiber_lobe_gm(const plm_fiber_params *p, const plm_fiber_lobe_set *set, int k, double theta);
double plm_fiber_lobe_gn(const plm_fiber_params *p, const plm_fiber_lobe_set *set, int k, double phi);

typedef struct plm_fiber_sample_rec {
    vec3 wi;
    double pdf;  /* plm_fiber_pdf(wi) */
    rgb weight;  /* eval(wi) cos(theta_i) / pdf */
    int lobe;    /* the lobe chosen */
} plm_fiber_sample_rec;

/* Chooses a lobe with probability P_k, then theta_i and phi_i by inverting
 * G_M's and G_N's CDFs with u1 and u2. Returns 0 (rec untouched) if the set
 * has nothing to sample. */
int plm_fiber_sample(const plm_fiber_params *p, const plm_fiber_lobe_set *set, double u0, double u1, double u2,
                     plm_fiber_sample_rec *rec);

/* Fiber-frame direction from (theta, phi), radians. */
static inline vec3 plm_fiber_direction(double theta, double phi)
{
    double st, ct, sp, cp;
    plm_sincos(theta, &st, &ct);
    plm_sincos(phi, &sp, &cp);
    return v3(ct * cp, ct * sp, st);
}

#endif
