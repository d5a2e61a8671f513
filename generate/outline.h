/* The flat feather: the species' shape laid out in the vane plane before any
 * bending, the common ground of the meshes and the textures.
 *
 * Flat coordinates (x, y) are millimetres: y along the rachis from the base
 * of the calamus, x across (right vane x > 0). The vanes' texture space is
 *     u = 1/2 + x / (2 U),   v = (y - y0) / Lv
 * with y0 the vane's base (the calamus length), Lv the vaned length and U the
 * half-width the vane mesh covers, so one image holds both vanes and the
 * rachis between them, v running base (0) to tip (1).
 *
 * Barbs are the level curves of the stream function
 *     psi(x, y) = y - F(|x|, y),
 * F(a, y) being the rise of a barb between the rachis centre line and the
 * distance a from it. psi is the y at which the barb through (x, y) meets the
 * centre line, so every barb is an exact integral curve of the direction
 * field (1 - F_y, F_a) (the gradient of psi turned by 90 degrees). Along a
 * barb the angle to the rachis is theta(y) at the rachis edge and turns
 * linearly by the barb curvature out to the widest point of the vane:
 *     phi(a) = theta - kappa (a - r) / (W - r),   F = r cot(theta) + (D/kappa) ln(sin theta / sin phi)
 * with r the rachis half-width, W the vane's widest point and D = W - r. */
#ifndef PLUMAGE_GENERATE_OUTLINE_H
#define PLUMAGE_GENERATE_OUTLINE_H

#include "common/vec.h"
#include "generate/species.h"

/* The vane cage's quads across (both vanes) and along; the mesh extent
 * below allows for the smoothing of one row. */
#define PLM_VANE_COLUMNS 8
#define PLM_VANE_ROWS 24

/* Barb spacings over which a barb narrows to its tip at its end. */
#define PLM_BARB_TAPER 1.5

typedef enum plm_flat_region {
    PLM_FLAT_BACKGROUND = 0,
    PLM_FLAT_RACHIS = 1,
    PLM_FLAT_VANE = 2
} plm_flat_region;

typedef struct plm_outline {
    plm_shape shape;       /* the species' shape, with this feather's drawn splits added to its list */
    double vane_base;      /* y0: where the vanes start (mm) */
    double vane_length;    /* Lv (mm) */
    double rachis_end;     /* y where the rachis ends (the notch bottom for notched tips) */
    double widest[2];      /* W per side (mm) */
    double half_extent;    /* U: the vane mesh spans |x| <= U (mm) */
    double spacing;        /* mm between neighbouring barbs along the rachis */
    double fray_length;    /* mm below the tip over which barbs part */
    double slope[2][PLM_WIDTH_POINTS_MAX]; /* monotone cubic tangents of each width profile */
} plm_outline;

/* A point's classification and barb direction in flat coordinates. Inside
 * the outline (vane, rachis, and the fluffy base and split gaps between
 * them) both are exact; outside it, where nothing is rendered, they are
 * those of a straight barb at the row's rachis angle. */
typedef struct plm_flat_sample {
    plm_flat_region region;
    vec2 barb;          /* unit barb direction (pointing away from the rachis) in flat x, y */
    double barb_origin; /* psi: y where this barb meets the rachis centre line */
} plm_flat_sample;

/* Prepares the flat model; fails (naming the fields) if barbs would fold back on
 * themselves, which the single-field checks cannot see. */
plm_result plm_outline_init(plm_outline *o, const plm_shape *shape, const char *file, plm_error *err);

/* Rachis half-width (mm) at y; 0 past the rachis end. */
double plm_outline_rachis_radius(const plm_outline *o, double y);
/* Barb angle to the rachis at the rachis edge, for a side's barbs there at y (radians). */
double plm_outline_barb_angle(const plm_outline *o, int side, double y);
/* Vane width (mm from the centre line) of one side at vane position t, tip shape included. */
double plm_outline_width(const plm_outline *o, int side, double t);
/* Half-width the mesh covers at t: a little more than the outline, so that
 * the smooth surface always contains it; the texture cuts the exact outline. */
double plm_outline_mesh_extent(const plm_outline *o, int side, double t);

/* Everything the texture needs at one flat point. */
plm_flat_sample plm_outline_sample(const plm_outline *o, double x, double y);

/* The same, split so that what depends only on y is computed once per row
 * of texels; here `barb` has the right direction but not unit length (the
 * texture rescales it to uv units and normalises once). */
typedef struct plm_outline_row {
    double y, t;               /* flat height and vane position */
    double cover, inset_scale; /* the fray: share of its spacing a barb covers; how much its end jitter grows */
    double r, dr;              /* rachis half-width and its slope */
    double width[2], notch[2]; /* outer and (notched tips) inner vane edge per side */
    double theta[2], dtheta[2], sin_t[2], cot_t[2], log_sin_t[2], inv_sin2_t[2]; /* barb angle at the rachis */
    double span[2], inv_span[2], span_per_kappa[2], kappa_dr[2]; /* rachis edge to widest point, per side */
} plm_outline_row;
void plm_outline_row_at(const plm_outline *o, double y, plm_outline_row *row);
plm_flat_sample plm_outline_sample_row(const plm_outline *o, const plm_outline_row *row, double x);

/* Texture space <-> flat coordinates. */
vec2 plm_outline_uv(const plm_outline *o, double x, double y);
vec2 plm_outline_flat(const plm_outline *o, double u, double v);

#endif
