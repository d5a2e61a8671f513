/* A fiber's parameters (docs/fiber.md): an infinite cylinder with an
 * elliptical cortex (semi-axis 1 along e2, `eccentricity` along e3) of
 * refractive index eta and RGB absorption sigma_a, optionally holding a
 * Lambertian medulla: an ellipse of its own, anywhere strictly inside the
 * cortex; the detectors' roughness and the lobes traced per path. */
#ifndef PLUMAGE_OPTICS_FIBER_PARAMS_H
#define PLUMAGE_OPTICS_FIBER_PARAMS_H

#include "common/error.h"
#include "common/params.h"
#include "common/vec.h"

/* Most lobes plm_fiber_trace supports (the energy tests compare 5 with 1000). */
#define PLM_FIBER_MAX_LOBES 1000

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

#endif
