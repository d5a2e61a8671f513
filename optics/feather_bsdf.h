/* The feather BSDF (paper Eq. 4): at a vane point, the barb BCSDF in the
 * barb frame and the barbule BCSDFs in the proximal and distal barbule
 * frames, each over the h-interval the masking leaves visible from wo and
 * weighted by the masking's projected widths, plus the delta transmission w_t.
 *
 * With the fiber foreshortening G = cos(theta_i) of each fiber and the
 * |wi.n|^-1 of Eq. 4, the cosine-weighted BSDF is
 *   f_s |wi.n| = sum_k w_k(wo) S_k(wi) cos(theta_i,k)        (k = barb, proximal, distal)
 * where S_k is plm_fiber_eval in fiber k's frame; the barb's term is a sum
 * over the h-ranges the masking leaves visible, each weighted by its rate. The renderer takes w_t as
 * fractional visibility (render/material.h) and the rest divided by (1 - w_t).
 * Sampling chooses component k by the light it sends back, w_k times its
 * fiber's energy for wo, and evaluates only fiber k at the sampled direction
 * (plm_feather_sample). */
#ifndef PLUMAGE_OPTICS_FEATHER_BSDF_H
#define PLUMAGE_OPTICS_FEATHER_BSDF_H

#include "common/rng.h"
#include "common/vec.h"
#include "optics/fiber.h"
#include "optics/fiber_bcsdf.h"
#include "optics/fiber_table_set.h"
#include "optics/masking.h"

/* The fiber BCSDF estimator of a feather (docs/fiber.md). */
typedef enum plm_bcsdf_kind {
    PLM_BCSDF_TABULATED = 0,  /* the h-integral from a table: no sparkle (the default) */
    PLM_BCSDF_STOCHASTIC = 1  /* one traced lobe set per shading point (the paper's estimator) */
} plm_bcsdf_kind;

/* A feather material's optics as a scene describes them. */
typedef struct plm_feather_params {
    plm_fiber_params barb;    /* in the barb frame: axis t, e2 = b, e3 = n */
    plm_fiber_params barbule; /* in each barbule set's frame: axis, e2 = r1, e3 = r2 (docs/masking.md) */
    plm_masking_params masking;
    plm_bcsdf_kind bcsdf;
} plm_feather_params;

/* Barb: the fiber defaults with the paper's Fig. 7 absorption (0.133, 1.967, 2.1)
 * and a concentric white medulla of radius 0.6; barbule: the fiber defaults
 * (no medulla) with the same absorption; masking: its defaults. */
void plm_feather_params_default(plm_feather_params *p);
plm_result plm_feather_params_validate(const plm_feather_params *p, plm_error *err);

/* What shading derives from a feather's parameters, kept apart from them so
 * that a description stays one: the masking's view-independent part (frames,
 * trigonometry) and the fiber tables. Whoever renders owns it (the render
 * world: render/material.h); the parameters must outlive it. */
typedef struct plm_feather_model {
    const plm_feather_params *params;
    plm_masking_model masking;
    /* Tables of the barb and the barbule fiber, from a table set that
     * outlives the model; NULL until plm_feather_model_build_tables (the
     * stochastic estimator serves until then). */
    const plm_fiber_table *table[2];
} plm_feather_model;

/* Prepares the masking of p, without tables. */
void plm_feather_model_init(plm_feather_model *m, const plm_feather_params *p);
/* Gets the fiber tables from set if the estimator is tabulated (a no-op if they are there). */
plm_result plm_feather_model_build_tables(plm_feather_model *m, plm_fiber_table_set *set, plm_error *err);

/* The barb frame (docs/masking.md) at a vane point, as a frame with x = b, y = n,
 * z = t: t = the texture's direction (cos a dP/du + sin a dP/dv) projected
 * into the plane of the shading normal n, b = n x t or its opposite, whichever
 * points to the tip (b . dP/dv > 0). Returns 0 if the tangents are degenerate. */
int plm_feather_barb_frame(vec3 n, vec3 dpdu, vec3 dpdv, vec2 direction_uv, frame *out);

/* Components: the barb over its first visible h-range, the proximal and
 * the distal barbules, then the barb over each further range. */
enum { PLM_FEATHER_BARB = 0, PLM_FEATHER_PROXIMAL = 1, PLM_FEATHER_DISTAL = 2 };
#define PLM_FEATHER_COMPONENTS (PLM_MASKING_MAX_BARB_RANGES + 2)

/* The BSDF prepared for one view direction wo: the masking, the fiber
 * frames in world space and a prepared BCSDF per component. */
typedef struct plm_feather_bsdf {
    const plm_feather_model *model;
    int count;                 /* components: 3 + the barb's visible ranges beyond the first */
    frame fiber_frame[PLM_FEATHER_COMPONENTS]; /* x = e2, y = e3, z = fiber axis, in world space; set where
                                                  weight > 0 */
    const plm_fiber_params *fiber[PLM_FEATHER_COMPONENTS];
    double weight[PLM_FEATHER_COMPONENTS]; /* w_k / (1 - w_t): the components' share of the light that does not
                                              pass (a barb range's: its rate) */
    double pick[PLM_FEATHER_COMPONENTS];   /* sampling probabilities: weight x energy (bcsdf[k].total), normalised */
    plm_masking masking;       /* for wo, in the barb frame */
    plm_fiber_bcsdf bcsdf[PLM_FEATHER_COMPONENTS];
    rgb tint;
} plm_feather_bsdf;

/* The masking seen from w (world space, the barb frame as above) over the
 * part of the barb period a pixel covers (docs/nearfield.md), NULL for the
 * far field. */
void plm_feather_masking(const plm_feather_model *m, const frame *barb, const plm_barb_window *window, vec3 w,
                         plm_masking *out);
/* Prepares for wo (world space) given its masking (plm_feather_masking): a
 * BCSDF per fiber over its visible h-range, and one for the barb over each
 * of its visible ranges, weighted by the range's rate (rng drives only the
 * stochastic estimator's lobe sets). */
void plm_feather_prepare_masked(const plm_feather_model *m, const frame *barb, vec3 wo, const plm_masking *masking,
                                rgb tint, plm_rng *rng, plm_feather_bsdf *out);

/* f_s |wi.n| / (1 - w_t(wo)), see the top of this file. */
rgb plm_feather_eval(const plm_feather_bsdf *f, vec3 wi);
/* The mixture's density: sum_k pick_k pdf_k(wi). */
double plm_feather_pdf(const plm_feather_bsdf *f, vec3 wi);
/* eval(wi) weighted for a light sample of density light_pdf against BSDF
 * sampling, fiber by fiber: each fiber k is its own sampling technique of
 * density pick_k pdf_k (plm_feather_sample weighs its draws by that), so
 * its term takes the power heuristic of light_pdf against pick_k pdf_k
 * (docs/rendering.md). */
rgb plm_feather_eval_mis(const plm_feather_bsdf *f, vec3 wi, double light_pdf);
/* The component u chooses by pick, and u rescaled to [0, 1) within its
 * share (for its fiber's sampler); -1 if none carries light. */
int plm_feather_pick(const plm_feather_bsdf *f, double u, double *remapped);
/* Chooses a component with u0 (plm_feather_pick), then samples its fiber:
 * wi, as pdf the density of fiber k's technique, pick_k pdf_k(wi) (what MIS
 * weighs the draw by; plm_feather_eval_mis), and as weight an estimate of
 * eval(wi) / plm_feather_pdf(wi) that is unbiased given wi, fiber k's own
 * S_k cos / pdf_k times weight_k / pick_k, so that only fiber k is
 * evaluated (docs/rendering.md). Returns 0 if nothing can be sampled. */
int plm_feather_sample(const plm_feather_bsdf *f, double u0, double u1, double u2, vec3 *wi, double *pdf,
                       rgb *weight);

#endif
