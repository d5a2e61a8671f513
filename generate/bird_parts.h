/* What the bird's files share (private to generate/). */
#ifndef PLUMAGE_GENERATE_BIRD_PARTS_H
#define PLUMAGE_GENERATE_BIRD_PARTS_H

#include "generate/bird.h"

/* Skin within this many eye radii of an eye's centre is left bare: the eye ring. */
#define PLM_BIRD_EYE_RING 1.5

static inline vec3 plm_mesh_vertex(const float *a, int i)
{
    return v3(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
}

/* The bill at the front ring of the body: its centre, the direction toward
 * the tail and the dorsal direction there, in mm; `scale` takes mm to the
 * bird's units. Fills out->upper_bill and out->lower_bill. */
plm_result plm_bird_bill(const plm_bird *bird, vec3 base, vec3 back, vec3 dorsal, double scale, plm_bird_body *out,
                         plm_error *err);

#endif
