#include "generate/outline.h"

#include <math.h>
#include <string.h>

#include "common/json.h"
#include "common/rng.h"

/* Tangents of a monotone piecewise cubic through the profile's points
 * (Fritsch & Butland 1984): no overshoot, so widths stay >= 0 and the widest
 * control point is the widest point of the curve. */
static void monotone_slopes(const plm_width_profile *w, double *m)
{
    int n = w->count;
    double d[PLM_WIDTH_POINTS_MAX], h[PLM_WIDTH_POINTS_MAX];
    for (int k = 0; k + 1 < n; ++k) {
        h[k] = w->t[k + 1] - w->t[k];
        d[k] = (w->width[k + 1] - w->width[k]) / h[k];
    }
    m[0] = d[0];
    m[n - 1] = d[n - 2];
    for (int k = 1; k + 1 < n; ++k)
        m[k] = d[k - 1] * d[k] <= 0.0 ? 0.0
                                      : 3.0 * (h[k - 1] + h[k]) /
                                            ((2.0 * h[k] + h[k - 1]) / d[k - 1] + (h[k] + 2.0 * h[k - 1]) / d[k]);
    /* End slopes are one-sided; limit them so the end intervals stay monotone. */
    if (m[0] * d[0] < 0.0 || fabs(m[0]) > 3.0 * fabs(d[0]))
        m[0] = 0.0;
    if (m[n - 1] * d[n - 2] < 0.0 || fabs(m[n - 1]) > 3.0 * fabs(d[n - 2]))
        m[n - 1] = 0.0;
}

static double profile(const plm_width_profile *w, const double *m, double t)
{
    int k = 0;
    while (k + 2 < w->count && t > w->t[k + 1])
        ++k;
    double h = w->t[k + 1] - w->t[k];
    double s = plm_clamp((t - w->t[k]) / h, 0.0, 1.0), s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * w->width[k] + (s3 - 2 * s2 + s) * h * m[k] + (-2 * s3 + 3 * s2) * w->width[k + 1] +
           (s3 - s2) * h * m[k + 1];
}

/* Position within the tip region: 0 where the tip starts closing, 1 at the tip. */
static double tip_tau(const plm_outline *o, double t)
{
    double start = 1.0 - o->shape.tip_length;
    return t <= start ? 0.0 : plm_clamp((t - start) / o->shape.tip_length, 0.0, 1.0);
}

/* 1 - depth over the emargination's length, smoothly: the vane's width
 * beyond an emargination (outer primaries) is a fraction of the profile. */
static double emargination(const plm_emargination *e, double t)
{
    if (e->depth <= 0.0)
        return 1.0;
    double s = plm_clamp((t - e->position) / e->length + 0.5, 0.0, 1.0);
    return 1.0 - e->depth * s * s * (3.0 - 2.0 * s);
}

/* The profile with its emargination, before the tip closes it. */
static double open_width(const plm_outline *o, int side, double t)
{
    return profile(&o->shape.width[side], o->slope[side], t) * emargination(&o->shape.emargination[side], t);
}

/* (1 - tau^p)^(1/p): p = 2 an ellipse, larger p squarer corners. */
static double superellipse(double tau, double p)
{
    return pow(fmax(0.0, 1.0 - pow(tau, p)), 1.0 / p);
}

/* The width with the tip's closing, of the profile with its emargination
 * or (for the mesh, which must stay smooth) without. */
static double closed_width(const plm_outline *o, int side, double t, int emarginated)
{
    if (t < 0.0 || t > 1.0)
        return 0.0;
    double w = emarginated ? open_width(o, side, t) : profile(&o->shape.width[side], o->slope[side], t);
    double tau = tip_tau(o, t);
    double round = sqrt(fmax(0.0, 1.0 - tau * tau));
    switch (o->shape.tip_shape) {
    case PLM_TIP_POINTED: return w * (1.0 - tau);
    case PLM_TIP_NOTCHED: return 0.5 * w * (1.0 + round); /* the outer edge of the lobe */
    case PLM_TIP_TRUNCATE: return w * superellipse(tau, 3.0);
    case PLM_TIP_SQUARE: return w * superellipse(tau, 8.0);
    default: return w * round;
    }
}

double plm_outline_width(const plm_outline *o, int side, double t) { return closed_width(o, side, t, 1); }

/* Notched tips: the inner edge of a side's lobe (0 elsewhere). */
static double notch_inner_width(const plm_outline *o, int side, double t)
{
    if (o->shape.tip_shape != PLM_TIP_NOTCHED)
        return 0.0;
    double tau = tip_tau(o, t);
    return 0.5 * open_width(o, side, t) * (1.0 - sqrt(fmax(0.0, 1.0 - tau * tau)));
}

double plm_outline_rachis_radius(const plm_outline *o, double y)
{
    if (y < 0.0 || y > o->rachis_end)
        return 0.0;
    const plm_shape *sh = &o->shape;
    double s = y / o->rachis_end;
    return 0.5 * (sh->rachis_base_width + (sh->rachis_tip_width - sh->rachis_base_width) * pow(s, sh->rachis_taper));
}

/* d r / d y */
static double rachis_radius_slope(const plm_outline *o, double y)
{
    if (y <= 0.0 || y > o->rachis_end)
        return 0.0;
    const plm_shape *sh = &o->shape;
    double s = y / o->rachis_end;
    return 0.5 * (sh->rachis_tip_width - sh->rachis_base_width) * sh->rachis_taper *
           pow(s, sh->rachis_taper - 1.0) / o->rachis_end;
}

double plm_outline_barb_angle(const plm_outline *o, int side, double y)
{
    const plm_shape *sh = &o->shape;
    return sh->barb_angle_base[side] +
           (sh->barb_angle_tip[side] - sh->barb_angle_base[side]) * (y - o->vane_base) / o->vane_length;
}

void plm_outline_row_at(const plm_outline *o, double y, plm_outline_row *row)
{
    const plm_shape *sh = &o->shape;
    row->y = y;
    row->t = (y - o->vane_base) / o->vane_length;
    row->r = plm_outline_rachis_radius(o, y);
    row->dr = rachis_radius_slope(o, y);
    /* The fray: over its length below the tip, barbs part (each covers less
     * of its spacing) and end more raggedly, the more the nearer the tip. */
    double z = o->fray_length > 0.0 ? plm_clamp((o->shape.length - y) / o->fray_length, 0.0, 1.0) : 1.0;
    row->cover = 0.4 + 0.6 * z;
    row->inset_scale = 3.0 - 2.0 * z;
    for (int side = 0; side < 2; ++side) {
        double theta = plm_outline_barb_angle(o, side, y);
        row->theta[side] = theta;
        row->dtheta[side] = (sh->barb_angle_tip[side] - sh->barb_angle_base[side]) / o->vane_length;
        row->sin_t[side] = sin(theta);
        row->cot_t[side] = cos(theta) / row->sin_t[side];
        row->log_sin_t[side] = log(row->sin_t[side]);
        row->inv_sin2_t[side] = 1.0 / (row->sin_t[side] * row->sin_t[side]);
        row->span[side] = o->widest[side] - row->r;
        row->inv_span[side] = 1.0 / row->span[side];
        row->span_per_kappa[side] = fabs(sh->barb_curvature) < 1e-9 ? 0.0 : row->span[side] / sh->barb_curvature;
        row->kappa_dr[side] = sh->barb_curvature * row->dr * row->inv_span[side] * row->inv_span[side];
        row->width[side] = plm_outline_width(o, side, row->t);
        row->notch[side] = notch_inner_width(o, side, row->t);
    }
}

/* F(a, y) of the header with its partial derivatives. */
typedef struct barb_rise {
    double f, fa, fy;
} barb_rise;

static barb_rise rise(const plm_outline *o, const plm_outline_row *row, int side, double a)
{
    double dtheta = row->dtheta[side], r = row->r, cot_t = row->cot_t[side];
    double kappa = o->shape.barb_curvature;
    barb_rise b;
    if (a <= r || fabs(kappa) < 1e-9) { /* a straight barb */
        b.f = a * cot_t;
        b.fa = cot_t;
        b.fy = -a * dtheta * row->inv_sin2_t[side];
        return b;
    }
    double span = row->span[side];
    /* Beyond the widest point (outside the vane) the barb keeps its last angle. */
    double d = fmin(a - r, span), beyond = a - r - d;
    /* Single precision for the two transcendental calls (the texel loop's
     * cost): relative error 1e-7, far below a texel. */
    double phi = row->theta[side] - kappa * d * row->inv_span[side], sin_p = sinf((float)phi);
    double inv_sin_p = 1.0 / sin_p;
    double cot_p = copysign(sqrt(fmax(0.0, 1.0 - sin_p * sin_p)), 0.5 * PLM_PI - phi) * inv_sin_p;
    double log_ratio = row->log_sin_t[side] - logf((float)sin_p);
    double dphi = dtheta + row->kappa_dr[side] * (span - d);
    b.f = r * cot_t + row->span_per_kappa[side] * log_ratio + beyond * cot_p;
    b.fa = cot_p;
    b.fy = row->dr * cot_t - r * dtheta * row->inv_sin2_t[side] - row->dr / kappa * log_ratio +
           row->span_per_kappa[side] * (cot_t * dtheta - cot_p * dphi) - beyond * dphi * inv_sin_p * inv_sin_p;
    return b;
}

static int in_split_gap(const plm_outline *o, int side, double xi, double psi)
{
    const plm_shape *sh = &o->shape;
    for (int i = 0; i < sh->split_count; ++i) {
        const plm_split *s = &sh->splits[i];
        double inner = 1.0 - s->depth;
        if (s->side != side || xi <= inner)
            continue;
        double half_gap = 0.5 * sh->split_gap * (xi - inner) / s->depth;
        if (fabs(psi - (o->vane_base + s->position * o->vane_length)) < half_gap)
            return 1;
    }
    return 0;
}

/* Uniform in [0, 1): the feather's own draw for one barb of one side. */
static double barb_draw(const plm_outline *o, int64_t barb, int side, uint64_t salt)
{
    return (double)(plm_hash64(o->shape.seed ^ salt, (uint64_t)barb, (uint64_t)side) >> 11) * 0x1p-53;
}

/* Value noise over barbs, smooth across groups of `size` barbs, in [0, 1). */
static double barb_noise(const plm_outline *o, int64_t barb, int side, double size, uint64_t salt)
{
    double g = barb / size, g0 = floor(g), f = g - g0;
    f = f * f * (3.0 - 2.0 * f);
    return (1.0 - f) * barb_draw(o, (int64_t)g0, side, salt) + f * barb_draw(o, (int64_t)g0 + 1, side, salt);
}

/* How far short of the outline a barb ends, as a fraction of the species'
 * end jitter: half its own draw, half shared with its neighbours (smooth
 * noise over groups of four barbs), so the edge is ragged barb by barb and
 * in short stretches, as a worn vane is. Stretches matter where barbs lie
 * nearly along the edge (a primary's outer vane): there a single short barb
 * hides behind its longer outer neighbours. */
static double barb_shortfall(const plm_outline *o, int64_t barb, int side)
{
    return 0.5 * barb_draw(o, barb, side, 0xed9eu) + 0.5 * barb_noise(o, barb, side, 4.0, 0x9a0bu);
}

/* Whether a pennaceous point at distance a from the centre line, on the barb
 * leaving the rachis at psi, lies beyond its barb's end or, in the fray,
 * between two parted barbs. Barb j spans coordinates [j, j + 1) with its
 * centre at j + 1/2 (the texture's barb coordinate); over its last
 * PLM_BARB_TAPER spacings it narrows to a fine tip, as barbs do, and in the
 * fray each barb keeps its own share of the row's cover. */
static int past_barb(const plm_outline *o, const plm_outline_row *row, int side, double a, double psi)
{
    /* On a narrow vane (a primary's outer vane, a tip) barbs are short: their
     * ends vary by at most a third of the vane's width, and so does the taper. */
    double w = row->width[side], room = w - fmax(row->r, row->notch[side]);
    double jitter = fmin(o->shape.barb_end_jitter * o->spacing * row->inset_scale, room / 3.0);
    double taper = fmin(PLM_BARB_TAPER * o->spacing, room / 3.0);
    if (a < w - jitter - taper && row->cover >= 1.0)
        return 0;
    double c = (psi - o->vane_base) / o->spacing, j = floor(c);
    double left = w - jitter * barb_shortfall(o, (int64_t)j, side) - a; /* to the barb's end */
    if (left <= 0.0)
        return 1;
    double cover = row->cover >= 1.0 ? 1.0 : fmin(1.0, row->cover * (0.7 + 0.6 * barb_draw(o, (int64_t)j, side, 0xf4a7u)));
    double half = 0.5 * cover * fmin(1.0, 0.15 + 0.85 * left / taper);
    return fabs(c - j - 0.5) > half;
}

plm_flat_sample plm_outline_sample_row(const plm_outline *o, const plm_outline_row *row, double x)
{
    int side = x >= 0.0;
    double a = fabs(x), y = row->y, t = row->t, w = row->width[side];
    plm_flat_sample s;
    if (!(t >= 0.0 && t <= 1.0 && a <= w && a >= row->notch[side]) && a > row->r) {
        /* Outside the outline nothing is rendered: the straight barb at the
         * rachis angle is enough, and saves the transcendental calls. */
        s.region = PLM_FLAT_BACKGROUND;
        s.barb = v2(side ? row->sin_t[side] : -row->sin_t[side], row->sin_t[side] * row->cot_t[side]);
        s.barb_origin = y - a * row->cot_t[side];
        return s;
    }
    barb_rise b = rise(o, row, side, a);
    double along = 1.0 - b.fy;
    s.barb = v2(side ? along : -along, b.fa); /* normalised by the caller */
    s.barb_origin = y - b.f;
    if (y >= 0.0 && y <= o->rachis_end && a <= row->r)
        s.region = PLM_FLAT_RACHIS;
    else if (s.barb_origin >= o->vane_base + o->shape.plumulaceous * o->vane_length)
        s.region = (o->shape.split_count > 0 && in_split_gap(o, side, a / w, s.barb_origin)) ||
                           past_barb(o, row, side, a, s.barb_origin)
                       ? PLM_FLAT_BACKGROUND
                       : PLM_FLAT_VANE;
    else /* the downy base: its barbs are fibers (generate/fluff.h), not vane */
        s.region = PLM_FLAT_BACKGROUND;
    return s;
}

plm_flat_sample plm_outline_sample(const plm_outline *o, double x, double y)
{
    plm_outline_row row;
    plm_outline_row_at(o, y, &row);
    plm_flat_sample s = plm_outline_sample_row(o, &row, x);
    s.barb = v2_normalize(s.barb);
    return s;
}

double plm_outline_mesh_extent(const plm_outline *o, int side, double t)
{
    /* The widest outline within one cage row either side, so the smooth limit
     * surface (which rounds the cage) still covers every vane texel; the
     * emarginations' steps are left to the texture, as a step in the cage
     * would fold the smooth surface. */
    const double window = 1.0 / PLM_VANE_ROWS;
    double w = 0.0;
    for (int k = -8; k <= 8; ++k)
        w = fmax(w, closed_width(o, side, plm_clamp(t + window * k / 8.0, 0.0, 1.0), 0));
    double y = o->vane_base + t * o->vane_length;
    double floor_width = fmax(1.5 * plm_outline_rachis_radius(o, y), 0.03 * o->widest[side]);
    return fmax(1.01 * w, floor_width);
}

vec2 plm_outline_uv(const plm_outline *o, double x, double y)
{
    return v2(0.5 + x / (2.0 * o->half_extent), (y - o->vane_base) / o->vane_length);
}

vec2 plm_outline_flat(const plm_outline *o, double u, double v)
{
    return v2((u - 0.5) * 2.0 * o->half_extent, o->vane_base + v * o->vane_length);
}

/* A Poisson count of mean m (at most 16: inversion is short and exact enough). */
static int poisson(plm_rng *rng, double m)
{
    double p = exp(-m), cdf = p, u = plm_rng_uniform(rng);
    int n = 0;
    while (u > cdf && n < 4 * PLM_SPLITS_MAX) {
        ++n;
        p *= m / n;
        cdf += p;
    }
    return n;
}

/* This feather's splits: a Poisson number per vane at the species'
 * frequency, at uniform positions and depths in the species' ranges (kept in
 * the pennaceous vane), appended to the listed ones. */
static void draw_splits(plm_shape *sh)
{
    if (!(sh->split_frequency > 0.0))
        return;
    plm_rng rng;
    plm_rng_seed(&rng, sh->seed, 0x5711u);
    double lo = fmax(sh->split_positions[0], sh->plumulaceous + 0.01);
    double hi = fmax(lo, fmin(sh->split_positions[1], 0.99));
    for (int side = 0; side < 2; ++side) {
        int n = poisson(&rng, sh->split_frequency);
        for (int i = 0; i < n; ++i) {
            double position = lo + (hi - lo) * plm_rng_uniform(&rng);
            double depth = sh->split_depths[0] + (sh->split_depths[1] - sh->split_depths[0]) * plm_rng_uniform(&rng);
            if (sh->split_count < PLM_SPLITS_MAX)
                sh->splits[sh->split_count++] = (plm_split){position, depth, side};
        }
    }
}

plm_result plm_outline_init(plm_outline *o, const plm_shape *shape, const char *file, plm_error *err)
{
    memset(o, 0, sizeof *o);
    o->shape = *shape;
    draw_splits(&o->shape);
    o->spacing = 10.0 / shape->barb_density; /* density is per cm */
    o->fray_length = shape->barb_fray * o->spacing;
    o->vane_base = shape->calamus_length;
    o->vane_length = shape->length - shape->calamus_length;
    o->rachis_end = shape->tip_shape == PLM_TIP_NOTCHED ? shape->length - shape->tip_length * o->vane_length
                                                        : shape->length;
    for (int side = 0; side < 2; ++side) {
        monotone_slopes(&shape->width[side], o->slope[side]);
        for (int i = 0; i < shape->width[side].count; ++i)
            o->widest[side] = fmax(o->widest[side], shape->width[side].width[i]);
    }
    double extent = 0.0;
    for (int side = 0; side < 2; ++side)
        for (int i = 0; i <= 512; ++i)
            extent = fmax(extent, plm_outline_mesh_extent(o, side, i / 512.0));
    o->half_extent = 1.01 * extent;
    /* Barbs must keep moving away from the rachis (1 - F_y > 0), or the
     * level curves of psi would fold over. */
    for (int side = 0; side < 2; ++side)
        for (int i = 0; i <= 64; ++i) {
            plm_outline_row row;
            plm_outline_row_at(o, o->vane_base + i / 64.0 * o->vane_length, &row);
            for (int j = 1; j <= 32; ++j) {
                if (1.0 - rise(o, &row, side, o->widest[side] * j / 32.0).fy < 0.2) {
                    plm_json_reader r = {file ? file : "(species)", err, 0};
                    return plm_json_fail(&r, "shape.barbs", "angle_tip",
                                         "barb angles change too fast along the rachis for vanes this wide (barbs "
                                         "would cross); bring angle_base and angle_tip closer or the feather longer");
                }
            }
        }
    return PLM_OK;
}
