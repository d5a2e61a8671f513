/* The fluffy base of a feather as fibers: the down (plumulaceous) barbs
 * leaving the rachis in the first `plumulaceous` fraction of the vane, and,
 * where the species has one, the afterfeather: a thin shaft (hyporachis)
 * leaving the rachis's underside where the vanes begin, with down barbs of
 * its own. Down barbs do not hook together, so each is a loose curve: it
 * leaves its shaft at the vane's barb angle, curls by a seeded random walk,
 * thins to a quarter of its root diameter at its end and carries short
 * barbules. All drawn from the feather's shape.seed, in the feather frame
 * (generate/species.h), millimetres; docs/generating.md. */
#ifndef PLUMAGE_GENERATE_FLUFF_H
#define PLUMAGE_GENERATE_FLUFF_H

#include "common/curves.h"
#include "generate/outline.h"

/* What each curve is (plm_curves.tag). */
typedef enum plm_fluff_kind {
    PLM_FLUFF_DOWN = 0,        /* a down barb of the vane's base: starts on the rachis */
    PLM_FLUFF_HYPORACHIS = 1,  /* the afterfeather's shaft: starts on the rachis's underside */
    PLM_FLUFF_AFTERFEATHER = 2, /* a down barb of the afterfeather: starts on the hyporachis */
    PLM_FLUFF_BARBULE = 3      /* a barbule: starts on the barb before it */
} plm_fluff_kind;

/* Points per curve of each kind (segments + 1). */
#define PLM_FLUFF_BARB_POINTS 13
#define PLM_FLUFF_BARBULE_POINTS 4

/* The fluff of the feather `o` describes (empty when shape.fluff.density is 0,
 * or there is neither a downy base nor an afterfeather). The rachis is the
 * generator's own (plm_rachis_frame_at), so the roots follow its bend. */
plm_result plm_fluff_curves(const plm_outline *o, plm_curves *out, plm_error *err);

#endif
