/* Brute-force reference for the masking: explicit 3D barbs and barbules,
 * parallel rays from the view direction, counting what each ray hits first.
 *
 * It shares nothing with the analytic masking (masking.c) but the parameter
 * struct, the result struct and vector maths: the geometry is built here from
 * the parameters' definitions (docs/masking.md) and traced with Embree.
 *
 * The scene, in the barb frame (x = b, y = n, z = t), is periodic in x (one
 * period holds `barbs` barbs, period 1 each) and in z (`length`):
 * - barb j: an elliptic cylinder along z through (j, 0), semi-axes w along b
 *   and e_b w along n, with w = 1 / (2 (1 + l_bb cos theta_bb)) as in the
 *   paper's cross-section (barb width plus two barbule spans is one period);
 * - two rows of barbules per barb, each in the plane through the barb's side
 *   line (j +- w, 0, z) that contains t and rises at theta_bb across the barb
 *   (falls, if negative); within it each barbule is an elliptic cylinder at
 *   phi_bb from t, leaning toward the barb's tip, with cross-section
 *   semi-axes a along r1 (in the row, across the barbules) and e_bb a along
 *   r2 (the row's normal). Barbules are rooted one every `pitch / sin phi_bb`
 *   along t (so neighbours are `pitch` apart across the row), with
 *   a = pitch / (2 (1 + delta_bb)), each row of each barb at its own random
 *   phase along t; each barbule is cut by the plane x = j +- 1/2 where the
 *   distal row of barb j meets the proximal row of barb j + 1.
 * A ray that leaves through the bottom (top, for views from below) of the
 * scene is transmitted. */
#ifndef PLUMAGE_RENDER_MASKING_REFERENCE_H
#define PLUMAGE_RENDER_MASKING_REFERENCE_H

#include <stdint.h>

#include "common/error.h"
#include "optics/masking.h"

typedef struct plm_masking_reference_options {
    int barbs;            /* barbs per period of the scene along b (default 16) */
    double pitch;         /* barbule period across a row, in barb periods (default 0.005) */
    double length;        /* scene period along t, in barb periods (default 2) */
    uint64_t layout_seed; /* phases of the barbule sets (default 1) */
} plm_masking_reference_options;

void plm_masking_reference_options_default(plm_masking_reference_options *o);

typedef struct plm_masking_reference plm_masking_reference;

/* Builds the scene; options may be NULL for the defaults. The rotation must
 * be at least 1 degree (barbules along the barb never reach the ridge). */
plm_result plm_masking_reference_create(const plm_masking_params *p, const plm_masking_reference_options *options,
                                        plm_masking_reference **out, plm_error *err);
void plm_masking_reference_destroy(plm_masking_reference *ref);

/* Casts `samples` parallel rays (a jittered grid over one period of the
 * scene) from direction wo (toward the viewer, barb frame, need not be
 * normalised) and fills out with the fractions that hit the barb, the
 * proximal and distal barbules first or pass through. The h-intervals
 * (h as in masking.h) span the hits on each kind less 1% of them at each end (rays
 * slipping past the cut ends of barbule rows would stretch them; each end is
 * good to about 0.02), and the barb has one range [hmin, hmax] holding w_barb;
 * a kind never hit gets [0, 0].
 * Fails for views within 1e-6 of the vane plane, which never leave it. */
plm_result plm_masking_reference_eval(const plm_masking_reference *ref, vec3 wo, unsigned samples, uint64_t seed,
                                      plm_masking *out, plm_error *err);

#endif
