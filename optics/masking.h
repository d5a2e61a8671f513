/* Analytic masking of barbs and barbules (paper Sec. 6.1, Figs. 5 and 6;
 * the geometry, frames and conventions are in docs/masking.md).
 *
 * For a view direction, the masking says which fraction of the vane's
 * projected width belongs to the barb, the proximal barbules, the distal
 * barbules and the gaps (w_barb + w_proximal + w_distal + w_transmission = 1),
 * and which part of each fiber's width (its h-interval) is seen.
 *
 * It works at two scales, each a 2D cross-section:
 * - barbule level: a row of barbule ellipses (period 1, semi-axes
 *   a = 1 / (2 (1 + delta_bb)) along r1 and e_bb * a along r2); either
 *   neighbours overlap in projection (no transmittance, part of the width
 *   hidden) or the gap shows (transmittance = projected gap / period);
 * - barb level: barbs are ellipses with period 1 along b, barbule rows are
 *   segments of length l_bb barb half-widths leaving each barb's side at the
 *   height of its centre and rising at theta_bb (falling if negative) to a
 *   ridge (valley) shared with the neighbour; a row lets a ray through with
 *   its set's barbule-level transmittance (independent layers multiply).
 * Both levels see one 3D arrangement: each row lies in a plane through the
 * barb axis t tilted about t by theta_bb, its barbules at phi_bb to t within
 * that plane (plm_masking_barbule_frames).
 * Directions are in the barb frame (x, y, z) = (w.b, w.n, w.t): n the
 * dorsal normal, t the barb axis away from the rachis, b toward the tip. */
#ifndef PLUMAGE_OPTICS_MASKING_H
#define PLUMAGE_OPTICS_MASKING_H

#include "common/error.h"
#include "common/params.h"
#include "common/vec.h"

/* The authors' parameter names; angles in radians here (degrees in files and
 * on the command line). */
typedef struct plm_masking_params {
    double barb_eccentricity;    /* e_b: barb extent along n / extent along b, (0, 20] */
    double barbule_eccentricity; /* e_bb: the same in a barbule's row frame, (0, 20] */
    double barbule_length;       /* l_bb: in barb half-widths, (0, 100] */
    double barbule_separation;   /* delta_bb: gap / barbule width, [0, 100] */
    double barbule_rotation;     /* phi_bb: angle between a barbule and the barb axis, (0, 90) degrees */
    double barbule_inclination;  /* theta_bb: tilt of the rows about t, toward n if > 0, (-90, 90) degrees */
} plm_masking_params;

/* Defaults: e_b 1, e_bb 1, l_bb 1, delta_bb 1, phi_bb 45 deg, theta_bb 0. */
void plm_masking_params_default(plm_masking_params *p);
/* PLM_ERR_INVALID with a message naming the field and its range (in degrees
 * for the angles) if any field is out of range or not finite. */
plm_result plm_masking_params_validate(const plm_masking_params *p, plm_error *err);
/* The fields of a masking block in files, with their ranges (common/params.h);
 * validation reads the same table. */
extern const plm_param_block plm_masking_param_block;

/* A visible interval of a fiber's h (from -1 to 1 across its silhouette,
 * increasing along (d_y, -d_x) for the view d in its cross-section) and the fraction of the
 * vane's projected width that sees the fiber through it. */
typedef struct plm_h_range {
    double hmin, hmax, rate;
} plm_h_range;

/* Each barb range comes from one class of view rays with the same barbule
 * layers in front; there are at most five classes per period, and a window
 * shorter than a period (plm_masking_eval_window) may cut one class twice. */
#define PLM_MASKING_MAX_BARB_RANGES 6

typedef struct plm_masking {
    double w_barb, w_proximal, w_distal, w_transmission; /* sum to 1, all >= 0 */
    plm_h_range proximal, distal; /* visible h-interval of each barbule set; rate = its weight */
    int barb_range_count;
    plm_h_range barb[PLM_MASKING_MAX_BARB_RANGES]; /* ordered by h, disjoint; rates sum to w_barb */
} plm_masking;

/* Full masking for a view direction wo in the barb frame (need not be
 * normalised). Constant time, no allocation. */
void plm_masking_eval(const plm_masking_params *p, vec3 wo_barb_frame, plm_masking *out);

/* The view-independent work (frames, trigonometry) done once per parameter
 * set, for callers that evaluate many directions (a BSDF, through
 * plm_masking_eval_window below). */
typedef struct plm_barb_geometry {
    double w, hb, yc;      /* barb semi-axes along b and n; ridge height (cell 0's ridge is (1/2, yc)) */
    double inv_w2, inv_hb2; /* 1 / w^2, 1 / hb^2 */
} plm_barb_geometry;
typedef struct plm_barbule_frame {
    vec3 axis, e2, e3;
} plm_barbule_frame;
typedef struct plm_masking_model {
    plm_masking_params params; /* what it was prepared from */
    plm_barbule_frame proximal, distal;
    plm_barb_geometry barb;
} plm_masking_model;
void plm_masking_prepare(const plm_masking_params *p, plm_masking_model *model);

/* Near field (docs/nearfield.md): where rays enter the vane's mid-plane,
 * across the barb period, as x in barb periods along b (barb j centred at
 * x = j, its cell [j - w, j + 1 - w)); the window [x0, x1] is the part of the
 * period a pixel covers. */
typedef struct plm_barb_window {
    double x0, x1;
} plm_barb_window;

/* The masking of the rays entering over the window, as fractions of it: the
 * same classes, weights and h-ranges as the far field, cut to the window. A
 * window of a period or more (or NULL) is the far field exactly, so averaged
 * over positions the near field equals the far field; a narrow window is one
 * ray's answer: the barb at (nearly) one h, a barbule layer with its
 * statistical transmittance, or the gap. */
void plm_masking_eval_window(const plm_masking_model *model, vec3 wo_barb_frame, const plm_barb_window *window,
                             plm_masking *out);

/* ---- the two levels on their own (used by the full masking, the probe and tests) ---- */

typedef struct plm_barbule_masking {
    double transmittance; /* fraction of a barbule row's projected period that is gap */
    double hmin, hmax;    /* visible h-interval of one barbule */
} plm_barbule_masking;

/* d = (w.r1, w.r2), the view direction in a barbule row's cross-section (need
 * not be normalised; a zero vector is treated as the row normal). */
void plm_masking_barbule(double barbule_eccentricity, double barbule_separation, vec2 d, plm_barbule_masking *out);

typedef struct plm_barb_masking {
    double w_barb, w_proximal, w_distal, w_transmission;
    int barb_range_count;
    plm_h_range barb[PLM_MASKING_MAX_BARB_RANGES];
} plm_barb_masking;

/* d = (w.b, w.n), the view direction in the barb cross-section (need not be
 * normalised; a zero vector is treated as the normal). t_proximal and
 * t_distal are the barbule-level transmittances of the two sets, in [0, 1]. */
void plm_masking_barb(double barb_eccentricity, double barbule_length, double barbule_inclination,
                      double t_proximal, double t_distal, vec2 d, plm_barb_masking *out);

/* The fiber frame of one barbule set in the barb frame: its axis, e2 = r1
 * (across the barbules, within their row), e3 = r2 (the row's dorsal normal).
 * With p = (+-cos theta_bb, sin theta_bb, 0) across the distal (+) or
 * proximal (-) row: axis = sin phi_bb p + cos phi_bb t, r2 is the unit normal
 * of the row plane with r2 . n > 0, and r1 = r2 x axis. */
void plm_masking_barbule_frames(const plm_masking_params *p, plm_barbule_frame *proximal,
                                plm_barbule_frame *distal);

#endif
