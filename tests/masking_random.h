/* Random masking parameters over the whole valid range, shared by the
 * masking and near-field tests. */
#ifndef PLUMAGE_TESTS_MASKING_RANDOM_H
#define PLUMAGE_TESTS_MASKING_RANDOM_H

#include "common/rng.h"
#include "optics/masking.h"

static inline double uniform(plm_rng *rng, double lo, double hi) { return lo + (hi - lo) * plm_rng_uniform(rng); }

static inline plm_masking_params random_params(plm_rng *rng)
{
    plm_masking_params p;
    p.barb_eccentricity = uniform(rng, 0.2, 6.0);
    p.barbule_eccentricity = uniform(rng, 0.2, 4.0);
    p.barbule_length = uniform(rng, 0.1, 6.0);
    p.barbule_separation = plm_rng_uniform(rng) < 0.1 ? 0.0 : uniform(rng, 0.0, 4.0);
    p.barbule_rotation = plm_radians(uniform(rng, 0.01, 89.99));
    p.barbule_inclination = plm_radians(uniform(rng, -80.0, 80.0));
    return p;
}

#endif
