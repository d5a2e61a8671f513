/* The fiber BCSDF as the feather BSDF calls it: one interface over both
 * estimators (docs/fiber.md). With a table (optics/fiber_table.h) its two
 * parts, the one without the medulla and the medulla's
 * (optics/fiber_medulla_table.h), mixed by energy; without, the stochastic
 * lobe set of optics/fiber.h. */
#ifndef PLUMAGE_OPTICS_FIBER_BCSDF_H
#define PLUMAGE_OPTICS_FIBER_BCSDF_H

#include "optics/fiber.h"
#include "optics/fiber_medulla_table.h"
#include "optics/fiber_table.h"

/* The fiber BCSDF prepared for one view direction wo and h-interval, by
 * either estimator: with a table, its two parts (deterministic: rng is not
 * used); without (NULL), the stochastic lobe set of fiber.h. Sampling mixes
 * the two parts by energy; pdf is the mixture's density. */
typedef struct plm_fiber_bcsdf {
    const plm_fiber_params *params;
    plm_fiber_table_query tab;   /* tab.table NULL: stochastic */
    plm_fiber_medulla_query med; /* tabulated: the medulla's part */
    plm_fiber_lobe_set set;      /* stochastic: every lobe */
    double pick_table;           /* probability that sampling uses the part without the medulla */
    double total;              /* > 0 iff something can be sampled */
} plm_fiber_bcsdf;

void plm_fiber_bcsdf_prepare(const plm_fiber_params *p, const plm_fiber_table *table, vec3 wo, double hmin,
                             double hmax, plm_rng *rng, plm_fiber_bcsdf *out);
/* As plm_fiber_eval: eval(wi) cos(theta_i) integrates to the energy over the sphere. */
rgb plm_fiber_bcsdf_eval(const plm_fiber_bcsdf *b, vec3 wi);
double plm_fiber_bcsdf_pdf(const plm_fiber_bcsdf *b, vec3 wi);
/* Both at once: one table lookup serves the two. */
rgb plm_fiber_bcsdf_eval_pdf(const plm_fiber_bcsdf *b, vec3 wi, double *pdf);
int plm_fiber_bcsdf_sample(const plm_fiber_bcsdf *b, double u0, double u1, double u2, plm_fiber_sample_rec *rec);
/* The same direction alone, for callers that evaluate it themselves (the
 * feather BSDF evaluates every fiber at it): skips the lookup of its weight. */
int plm_fiber_bcsdf_sample_direction(const plm_fiber_bcsdf *b, double u0, double u1, double u2, vec3 *wi);

#endif
