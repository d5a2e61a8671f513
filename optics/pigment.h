/* Pigment absorption from concentrations: a fiber block may give its cortex
 * absorption as `"pigments": {"eumelanin": 1, "yellow": 3, ...}` instead of
 * an RGB sigma_a. Each pigment adds its concentration times its RGB
 * absorption per unit fiber radius (the units of sigma_a, docs/fiber.md):
 * eumelanin and pheomelanin with published coefficients, carotenoid-like
 * yellow and red pigments and clear keratin with estimates; docs/species.md
 * ("Pigments") gives the values and their sources. */
#ifndef PLUMAGE_OPTICS_PIGMENT_H
#define PLUMAGE_OPTICS_PIGMENT_H

#include "common/params.h"
#include "common/vec.h"

typedef struct plm_pigments { /* concentrations; all 0 = a clear fiber */
    double eumelanin, pheomelanin, yellow, red, keratin;
} plm_pigments;

/* The fields of a "pigments" block, with their ranges. */
extern const plm_param_block plm_pigments_param_block;

/* sigma_a = sum over pigments of concentration x coefficient. */
rgb plm_pigments_sigma_a(const plm_pigments *c);

#endif
