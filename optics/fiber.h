/* The fiber BCSDF of barbs and barbules (paper Sec. 5, Eqs. 1-3).
 *
 * A fiber is an infinite cylinder with an elliptical cortex (semi-axis 1 along
 * e2, `eccentricity` along e3) of refractive index eta and RGB absorption
 * sigma_a, optionally holding a Lambertian medulla: an ellipse of its own,
 * anywhere strictly inside the cortex. Directions are in the fiber frame
 * (x = e2, y = e3, z = fiber axis); theta = asin(w.z), phi = atan2(w.y, w.x).
 *
 * Evaluation follows the paper's stochastic scheme, made exactly
 * self-consistent: per shading query a *lobe set* is traced once from the
 * view direction wo (plm_fiber_prepare), and eval/pdf/sample are then
 * deterministic functions of (set, wi). The expectation over lobe sets of
 * plm_fiber_eval is the BCSDF of Eqs. 1-2 (with D = 1). */
#ifndef PLUMAGE_OPTICS_FIBER_H
#define PLUMAGE_OPTICS_FIBER_H

#include "common/error.h"
#include "common/params.h"
#include "common/rng.h"
#include "common/vec.h"

/* Most lobes plm_fiber_trace supports (the energy tests compare 5 with 1000). */
#define PLM_FIBER_MAX_LOBES 1000
/* Most lobes a lobe set (the rendering path) holds. */
#define PLM_FIBER_SET_MAX_LOBES 32

typedef struct plm_fiber_params { /* zero-init is NOT valid; use plm_fiber_params_default() */
    double eccentricity;          /* cortex semi-axis along e3; the semi-axis along e2 is 1 */
    double eta;                   /* cortex refractive index (the medulla's is the same) */
    rgb sigma_a;                  /* cortex absorption per unit 3D path length (units of the e2 semi-axis) */
    double beta_m, beta_n;        /* longitudinal / azimuthal detector standard deviations, radians */
    double medulla_a, medulla_b;  /* medulla semi-axes along e2, e3; both 0 = no medulla */
    double medulla_ca, medulla_cb; /* medulla centre */
    rgb medulla_reflectance;      /* Lambertian albedo d_m */
    int lobes;                    /* N: lobes traced per path, default 5 */
} plm_fiber_params;

/* Circular clear cortex, eta 1.55 (keratin), beta_m = 0.13 and
 * beta_n = 0.12 rad (paper Fig. 7), no medulla (white if enabled), 5 lobes. */
void plm_fiber_params_default(plm_fiber_params *p);

/* The four fibers of the paper's Fig. 7, by variant: 0
 * circular, 1 elliptical e = 1.6, 2 with a concentric medulla of radius 0.6,
 * 3 with that medulla centred at (-0.1, 0.1); all with sigma_a = (0.133,
 * 1.967, 2.1), eta = 1.53, beta_m = 0.13, beta_n = 0.12, a white medulla. */
#define PLM_FIBER_FIGURE7_VARIANTS 4
void plm_fiber_params_figure7(plm_fiber_params *p, int variant);
extern const char *const plm_fiber_figure7_names[PLM_FIBER_FIGURE7_VARIANTS];

/* Checks every field; the message names the field and its allowed range, or
 * says how the medulla pokes out of the cortex. */
plm_result plm_fiber_params_validate(const plm_fiber_params *p, plm_error *err);

/* The fields of a fiber block in files, with their ranges (common/params.h);
 * validation reads the same table. */
extern const plm_param_block plm_fiber_param_block;

static inline int plm_fiber_has_medulla(const plm_fiber_params *p) { return p->medulla_a > 0.0; }

/* Unpolarised Fresnel reflectance of a dielectric interface for cos_i in
 * [0, 1] and eta = n_t / n_i (below 1 from inside the fiber); 1 under total
 * internal reflection. The tracer uses it at every cortex interaction. */
double plm_fiber_fresnel(double cos_i, double eta);

/* One exit of light from the cortex. */
typedef struct plm_fiber_lobe {
    vec3 dir;       /* exit direction, unit, pointing away from the fiber */
    rgb throughput; /* fraction of the light entering at h that leaves here */
    int medulla;    /* 1 if the path bounced off the medulla before leaving (then dir is random); such
                     * lobes all follow the deterministic ones, which leave at theta = -theta_o */
    int wall_hits;  /* before the medulla: the cortex interactions inside the fiber before this exit (0: the
                     * surface reflection, 1: TT, 2: TRT, ...; total internal reflections count too) */
} plm_fiber_lobe;

/* Traces light arriving from view direction wo (unit, pointing away from the
 * fiber) at entry offset h in [-1, 1] (docs/fiber.md; outside, or NaN, gives no
 * lobes) and fills lobes[0..count)
 * in the order light leaves the cortex (lobe 0 is the surface reflection);
 * returns count <= max_lobes (fewer when light is absorbed, lost along the
 * axis, or exceeds the interaction bound of 16 max_lobes + 64). rng drives
 * the medulla's diffuse bounces and may be NULL without a medulla (then the
 * result is deterministic). If inside is not NULL it receives the throughput
 * still travelling inside the fiber when tracing stopped. */
int plm_fiber_trace_n(const plm_fiber_params *p, vec3 wo, double h, plm_rng *rng, plm_fiber_lobe *lobes,
                      int max_lobes, rgb *inside);
/* plm_fiber_trace_n with max_lobes = p->lobes (lobes must hold that many). */
int plm_fiber_trace(const plm_fiber_params *p, vec3 wo, double h, plm_rng *rng, plm_fiber_lobe *lobes);

/* Where a path first reaches the medulla. Up to there a path is
 * deterministic; what leaves the fiber after it depends only on this point
 * and on how many lobes the path may still store (the medulla table,
 * optics/fiber_medulla_table.h, builds on that). */
typedef struct plm_fiber_medulla_hit {
    double t;       /* the medulla point (ca + a cos t, cb + b sin t) */
    rgb throughput; /* of the light arriving there (before the medulla's albedo) */
    int lobes;      /* lobes stored before (the surface reflection included), < p->lobes */
} plm_fiber_medulla_hit;

/* plm_fiber_trace up to the medulla: fills lobes (p->lobes of room) with the
 * lobes before it and hit; returns 0 if the path stores p->lobes lobes or
 * dies first, or the fiber has no medulla. */
int plm_fiber_trace_to_medulla(const plm_fiber_params *p, vec3 wo, double h, plm_fiber_lobe *lobes,
                               plm_fiber_medulla_hit *hit);
/* Unit light leaving medulla point t in the diffuse direction of (u1, u2)
 * in [0, 1)^2 (uniform (u1, u2) give the cosine distribution about the
 * normal), times the medulla's albedo, traced on as plm_fiber_trace does
 * (rng drives later bounces) until max_lobes lobes; returns their count. */
int plm_fiber_trace_from_medulla(const plm_fiber_params *p, double t, double u1, double u2, plm_rng *rng,
                                 plm_fiber_lobe *lobes, int max_lobes);

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
