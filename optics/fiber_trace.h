/* The fiber tracer: exact geometric optics of light entering a fiber
 * (optics/fiber_params.h) from a view direction at an entry offset h, and
 * the lobes it leaves in (paper Sec. 5.2, Eq. 3). Directions are in the
 * fiber frame (x = e2, y = e3, z = fiber axis). The BCSDF
 * (optics/fiber.h) and the tables (optics/fiber_table.h) build on it. */
#ifndef PLUMAGE_OPTICS_FIBER_TRACE_H
#define PLUMAGE_OPTICS_FIBER_TRACE_H

#include "common/rng.h"
#include "common/vec.h"
#include "optics/fiber_params.h"

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

#endif
