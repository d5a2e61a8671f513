/* Analytic barb and barbule masking (paper Sec. 6.1). See masking.h for the
 * model and docs/masking.md for the geometry. Both levels measure widths along the projection axis
 * u = (d_y, -d_x), perpendicular to the view direction d in the
 * cross-section: a fiber's visible width between two visibility rays is the
 * difference of the rays' coordinates along u (the paper's Eq. 6 for arcs and
 * its cosine analogue for segments give the same numbers), and h is that
 * coordinate scaled to [-1, 1] across the fiber's silhouette. */
#include "optics/masking.h"

#include <math.h>
#include <stddef.h>

void plm_masking_params_default(plm_masking_params *p)
{
    p->barb_eccentricity = 1.0;
    p->barbule_eccentricity = 1.0;
    p->barbule_length = 1.0;
    p->barbule_separation = 1.0;
    p->barbule_rotation = plm_radians(45.0);
    p->barbule_inclination = 0.0;
}

/* Both angles are open intervals (docs/masking.md): at 0 or 90 degrees of
 * rotation, or +-90 of inclination, barbules lie along the barb or stand
 * upright and the rows of neighbouring barbs never meet. */
#define OPEN_MIN PLM_PARAM_OPEN_MIN
#define OPEN_BOTH (PLM_PARAM_OPEN_MIN | PLM_PARAM_OPEN_MAX)
#define FIELD(name, type, member, lo, hi, unit, meaning, open) \
    {name, type, offsetof(plm_masking_params, member), lo, hi, unit, meaning, open}
static const plm_param masking_params[] = {
    FIELD("barb_eccentricity", PLM_PARAM_NUMBER, barb_eccentricity, 0.0, 20.0, "",
          "e_b: a barb's extent along the normal over its extent across the vane", OPEN_MIN),
    FIELD("barbule_eccentricity", PLM_PARAM_NUMBER, barbule_eccentricity, 0.0, 20.0, "",
          "e_bb: the same for a barbule, in its row's frame", OPEN_MIN),
    FIELD("barbule_length", PLM_PARAM_NUMBER, barbule_length, 0.0, 100.0, "barb half-widths",
          "l_bb: barbule length", OPEN_MIN),
    FIELD("barbule_separation", PLM_PARAM_NUMBER, barbule_separation, 0.0, 100.0, "barbule widths",
          "delta_bb: the gap between neighbouring barbules", 0),
    FIELD("barbule_rotation", PLM_PARAM_ANGLE, barbule_rotation, 0.0, 90.0, "degrees",
          "phi_bb: angle between a barbule and the barb axis", OPEN_BOTH),
    FIELD("barbule_inclination", PLM_PARAM_ANGLE, barbule_inclination, -90.0, 90.0, "degrees",
          "theta_bb: tilt of the barbule rows about the barb axis, toward the normal if > 0", OPEN_BOTH),
};
#undef FIELD
#undef OPEN_MIN
#undef OPEN_BOTH
const plm_param_block plm_masking_param_block = {
    "masking", "barb and barbule geometry for masking: see docs/masking.md", masking_params,
    PLM_PARAM_COUNT(masking_params)};

plm_result plm_masking_params_validate(const plm_masking_params *p, plm_error *err)
{
    return plm_params_check(&plm_masking_param_block, p, err);
}

/* The unit view direction in a cross-section; a zero (or non-finite) vector,
 * a view straight along the fiber, has no cross-section direction, and the
 * normal stands in for it. */
static vec2 unit_direction(vec2 d)
{
    double len = v2_length(d);
    if (!(len > 1e-300) || !isfinite(len))
        return v2(0.0, 1.0);
    return v2_scale(d, 1.0 / len);
}

/* ---------------------------------------------------------------- barbule level */

void plm_masking_barbule(double barbule_eccentricity, double barbule_separation, vec2 d, plm_barbule_masking *out)
{
    d = unit_direction(d);
    /* Period 1 along r1: a barbule of width 2a and a gap of delta * 2a. */
    double a = 0.5 / (1.0 + barbule_separation);
    double period = fabs(d.y); /* the row's period seen along u */
    double width = 2.0 * a * sqrt(d.y * d.y + plm_sqr(barbule_eccentricity * d.x));
    if (period > width) { /* the gap shows between neighbours: Fig. 5, 25 degree case */
        out->transmittance = (period - width) / period;
        out->hmin = -1.0;
        out->hmax = 1.0;
        return;
    }
    /* Neighbours overlap (Fig. 5, 70 degree case): the neighbour on the side of
     * d_x is nearer the viewer (for translated ellipses the order along any
     * ray follows the sign of d_x), and it sits period further along u when
     * d_y > 0. It hides all but `period` of the width, leaving the far side. */
    double visible = period > 0.0 ? 2.0 * period / width : 0.0;
    out->transmittance = 0.0;
    if (d.x * d.y > 0.0) {
        out->hmin = -1.0;
        out->hmax = -1.0 + visible;
    } else {
        out->hmin = 1.0 - visible;
        out->hmax = 1.0;
    }
}

/* ---------------------------------------------------------------- barb level */

/* The barb cross-section, period 1 along x = b, y = n. Cell j holds barb j
 * (centre (j, 0), semi-axes w and hb), its distal barbule from (j + w, 0) to
 * the ridge (j + 1/2, yc) and the proximal barbule of barb j + 1 from
 * (j + 1 - w, 0) to the same ridge; cell j spans x in [j - w, j + 1 - w).
 * Period 1 = barb width 2w + two barbule spans l_bb w cos(theta_bb). */
static plm_barb_geometry barb_geometry(double barb_eccentricity, double barbule_length, double barbule_inclination)
{
    plm_barb_geometry g;
    g.w = 0.5 / (1.0 + barbule_length * cos(barbule_inclination));
    g.hb = g.w * barb_eccentricity;
    g.yc = barbule_length * g.w * sin(barbule_inclination);
    g.inv_w2 = 1.0 / (g.w * g.w);
    g.inv_hb2 = 1.0 / (g.hb * g.hb);
    return g;
}

/* A segment of cell 0 seen from the view: its ends' coordinates along u and
 * along d (depth: larger is nearer the viewer). Cell j adds j d_y and j d_x. */
typedef struct view_segment {
    double s0, s1, inv_ds, depth0, ddepth;
} view_segment;

/* Everything about one view that the rays of all classes share. */
typedef struct barb_view {
    double dx, dy, inv_dy;
    double x_in, x_out;    /* a ray enters and leaves the band at x = s / d_y + x_in, + x_out (plus w) */
    double half_width;     /* the barb's projected half-width along u */
    double k1, k2, inv_qa; /* barb entry depth: k1 ds + sqrt(k2 ds^2 + inv_qa) for offset ds */
    view_segment distal, proximal;
    double t_proximal, t_distal;
} barb_view;

static view_segment view_segment_make(vec2 a, vec2 b, double dx, double dy)
{
    view_segment v;
    v.s0 = a.x * dy - a.y * dx;
    v.s1 = b.x * dy - b.y * dx;
    v.inv_ds = v.s1 != v.s0 ? 1.0 / (v.s1 - v.s0) : 0.0;
    v.depth0 = a.x * dx + a.y * dy;
    v.ddepth = (b.x * dx + b.y * dy) - v.depth0;
    return v;
}

enum { HIT_BARB, HIT_PROXIMAL, HIT_DISTAL };

typedef struct hit {
    double depth;
    int kind;
} hit;

/* What one ray class (offset s along u) delivers per unit of its width. */
typedef struct ray_result {
    double barb, proximal, distal, transmission;
    int barb_cell; /* which barb copy the ray ends on, when barb > 0 */
} ray_result;

/* Most cells a ray is followed through before its remaining throughput
 * (at most max(T)^(2 cells) after crossing barbule layers) is settled on the
 * last layer it crossed; only views within a fraction of a degree of the vane
 * plane get that far. */
#define MAX_CELLS 128

/* floor() without SSE4.1 is a libm call; these arguments are small. */
static inline double floor_small(double x)
{
    double i = (double)(long long)x;
    return i > x ? i - 1.0 : i;
}

/* Adds the crossing of a segment by the ray at offset ds from cell j's origin. */
static int segment_hit(const view_segment *g, double ds, double cell_depth, int kind, hit *h)
{
    if (!((ds - g->s0) * (ds - g->s1) < 0.0))
        return 0; /* misses, or the segment lies along the ray */
    h->depth = cell_depth + g->depth0 + (ds - g->s0) * g->inv_ds * g->ddepth;
    h->kind = kind;
    return 1;
}

/* The crossings of cell j by the ray at offset s, nearest to the viewer first. */
static int cell_hits(const barb_view *v, int j, double s, hit hits[3])
{
    double ds = s - (double)j * v->dy, cell_depth = (double)j * v->dx;
    int n = segment_hit(&v->distal, ds, cell_depth, HIT_DISTAL, &hits[0]);
    n += segment_hit(&v->proximal, ds, cell_depth, HIT_PROXIMAL, &hits[n]);
    if (fabs(ds) < v->half_width) {
        /* the barb's entry depth matters only to order it among segments */
        hits[n].depth = n ? cell_depth + v->k1 * ds + plm_safe_sqrt(v->k2 * ds * ds + v->inv_qa) : 0.0;
        hits[n++].kind = HIT_BARB;
    }
    for (int i = 1; i < n; ++i) /* insertion sort, at most three */
        for (int k = i; k > 0 && hits[k].depth > hits[k - 1].depth; --k) {
            hit tmp = hits[k];
            hits[k] = hits[k - 1];
            hits[k - 1] = tmp;
        }
    return n;
}

/* Follows the ray at offset s from the viewer through the periodic scene:
 * each barbule layer it crosses keeps (1 - T) of what reaches it, the first
 * barb keeps the rest, and what leaves the band is transmitted. */
static ray_result trace_ray(const barb_view *v, double s)
{
    ray_result r = {0.0, 0.0, 0.0, 0.0, 0};
    double x = s * v->inv_dy;
    int j = (int)floor_small(x + v->x_in), j_last = (int)floor_small(x + v->x_out);
    int step = j_last >= j ? 1 : -1;
    double throughput = 1.0;
    int last_layer = -1;
    for (int cells = 0; cells < MAX_CELLS; ++cells, j += step) {
        hit hits[3];
        int n = cell_hits(v, j, s, hits);
        for (int i = 0; i < n; ++i) {
            if (hits[i].kind == HIT_BARB) {
                r.barb = throughput;
                r.barb_cell = j;
                return r;
            }
            int proximal = hits[i].kind == HIT_PROXIMAL;
            double t = proximal ? v->t_proximal : v->t_distal;
            *(proximal ? &r.proximal : &r.distal) += throughput * (1.0 - t);
            throughput *= t;
            last_layer = hits[i].kind;
        }
        if (j == j_last) {
            r.transmission = throughput;
            return r;
        }
    }
    /* Cut off near grazing: the ray is still among the barbules. */
    if (last_layer == HIT_PROXIMAL)
        r.proximal += throughput;
    else if (last_layer == HIT_DISTAL)
        r.distal += throughput;
    else
        r.transmission += throughput;
    return r;
}

/* Sorts five values with a fixed network of nine compare-exchanges: no
 * data-dependent branches to mispredict. */
static void sort5(double v[5])
{
    static const int pairs[9][2] = {{0, 1}, {3, 4}, {2, 4}, {2, 3}, {1, 4}, {0, 3}, {0, 2}, {1, 3}, {1, 2}};
    for (int k = 0; k < 9; ++k) {
        double a = v[pairs[k][0]], b = v[pairs[k][1]];
        v[pairs[k][0]] = a < b ? a : b;
        v[pairs[k][1]] = a < b ? b : a;
    }
}

static double wrap(double s, double period, double inv_period) { return s - period * floor_small(s * inv_period); }

/* Orders the ranges by h and joins neighbours that continue each other at
 * the same throughput (one visible stretch of barb split by a class
 * boundary that changes nothing in front of it). */
static void tidy_barb_ranges(plm_barb_masking *out, double thr[])
{
    int n = out->barb_range_count;
    if (n < 2)
        return;
    for (int i = 1; i < n; ++i)
        for (int k = i; k > 0 && out->barb[k].hmin < out->barb[k - 1].hmin; --k) {
            plm_h_range g = out->barb[k];
            double t = thr[k];
            out->barb[k] = out->barb[k - 1];
            thr[k] = thr[k - 1];
            out->barb[k - 1] = g;
            thr[k - 1] = t;
        }
    int m = 0;
    for (int i = 0; i < n; ++i) {
        if (m > 0 && fabs(out->barb[m - 1].hmax - out->barb[i].hmin) < 1e-9 && fabs(thr[m - 1] - thr[i]) < 1e-12) {
            out->barb[m - 1].hmax = out->barb[i].hmax;
            out->barb[m - 1].rate += out->barb[i].rate;
            continue;
        }
        thr[m] = thr[i];
        out->barb[m++] = out->barb[i];
    }
    out->barb_range_count = m;
}

static barb_view barb_view_make(const plm_barb_geometry *g, double t_proximal, double t_distal, vec2 d)
{
    barb_view v;
    d = unit_direction(d);
    /* Views within 1e-7 of the vane plane are taken as that close to it, on
     * their own side: exactly in the plane the projected period vanishes. */
    const double min_dy = 1e-7;
    if (fabs(d.y) < min_dy)
        d = unit_direction(v2(d.x, d.y < 0.0 ? -min_dy : min_dy));
    v.dx = d.x;
    v.dy = d.y;
    v.inv_dy = 1.0 / d.y;
    /* The ray s u + tau d (u = (d_y, -d_x)) is at x = s / d_y + y d_x / d_y
     * when at height y; it enters the band of geometry on the viewer's side. */
    double ylo = g->yc < -g->hb ? g->yc : -g->hb, yhi = g->yc > g->hb ? g->yc : g->hb;
    double y_in = d.y > 0.0 ? yhi : ylo, y_out = d.y > 0.0 ? ylo : yhi;
    v.x_in = y_in * d.x * v.inv_dy + g->w;
    v.x_out = y_out * d.x * v.inv_dy + g->w;
    v.half_width = sqrt(plm_sqr(g->w * d.y) + plm_sqr(g->hb * d.x));
    /* Barb entry: q = ds u + t d on (q_x / w)^2 + (q_y / hb)^2 = 1, with
     * u = (d_y, -d_x); the larger root t is the side facing the viewer. */
    double iw2 = g->inv_w2, ih2 = g->inv_hb2;
    double qa = d.x * d.x * iw2 + d.y * d.y * ih2;
    double qb = 2.0 * (d.y * d.x * iw2 - d.x * d.y * ih2); /* times ds */
    double qc = d.y * d.y * iw2 + d.x * d.x * ih2;          /* times ds^2, minus 1 */
    v.inv_qa = 1.0 / qa;
    v.k1 = -0.5 * qb * v.inv_qa;
    v.k2 = (qb * qb - 4.0 * qa * qc) * 0.25 * v.inv_qa * v.inv_qa;
    vec2 ridge = v2(0.5, g->yc);
    v.distal = view_segment_make(v2(g->w, 0.0), ridge, d.x, d.y);
    v.proximal = view_segment_make(v2(1.0 - g->w, 0.0), ridge, d.x, d.y);
    v.t_proximal = plm_clamp(t_proximal, 0.0, 1.0);
    v.t_distal = plm_clamp(t_distal, 0.0, 1.0);
    return v;
}

/* What the rays entering the vane's mid-plane over a window of the period
 * see (docs/nearfield.md): NULL is a whole period, the far field. The
 * window [sa, sb] along u is cut where a ray grazes a barb's silhouette
 * (its tangent points, Eq. 5) or passes a segment end (the roots and the
 * ridge corner); between those cuts every ray meets the same things in the
 * same order, so one ray per piece decides it. A whole period has five such
 * pieces, a shorter window at most six (a class cut at both ends). */
static void barb_eval(const plm_barb_geometry *g, double t_proximal, double t_distal, vec2 d,
                      const plm_barb_window *window, plm_barb_masking *out)
{
    barb_view v = barb_view_make(g, t_proximal, t_distal, d);
    double period = fabs(v.dy), inv_period = fabs(v.inv_dy);
    double b[5] = {wrap(-v.half_width, period, inv_period), wrap(v.half_width, period, inv_period),
                   wrap(v.distal.s0, period, inv_period), wrap(v.proximal.s0, period, inv_period),
                   wrap(v.distal.s1, period, inv_period)};
    sort5(b);
    double cut[2 + 2 * 5];
    int n = 0, whole = !window || !(window->x1 - window->x0 < 1.0);
    if (whole) {
        for (int i = 0; i < 5; ++i)
            cut[n++] = b[i];
        cut[n++] = b[0] + period;
    } else {
        /* The point (x, 0) of the mid-plane lies on the ray at s = x d_y. */
        double sa = window->x0 * v.dy, sb = window->x1 * v.dy;
        if (sa > sb) {
            double tmp = sa;
            sa = sb;
            sb = tmp;
        }
        double base = period * floor(sa * inv_period);
        cut[n++] = sa;
        for (int k = 0; k < 2; ++k)
            for (int i = 0; i < 5; ++i) {
                double c = base + k * period + b[i];
                if (c > sa && c < sb)
                    cut[n++] = c;
            }
        cut[n++] = sb;
    }
    /* A whole period divides by the period itself, as the far field always has. */
    double inv_width = whole ? inv_period : 1.0 / (cut[n - 1] - cut[0]);

    out->w_barb = out->w_proximal = out->w_distal = out->w_transmission = 0.0;
    out->barb_range_count = 0;
    double thr[PLM_MASKING_MAX_BARB_RANGES];
    double inv_half_width = 1.0 / v.half_width;
    for (int i = 0; i + 1 < n; ++i) {
        double s0 = cut[i], s1 = cut[i + 1];
        double len = (s1 - s0) * inv_width;
        if (!(len > 1e-13))
            continue;
        ray_result r = trace_ray(&v, 0.5 * (s0 + s1));
        out->w_proximal += len * r.proximal;
        out->w_distal += len * r.distal;
        out->w_transmission += len * r.transmission;
        if (r.barb > 0.0) {
            out->w_barb += len * r.barb;
            double centre = (double)r.barb_cell * v.dy; /* (j, 0) . u */
            double h0 = plm_clamp((s0 - centre) * inv_half_width, -1.0, 1.0);
            double h1 = plm_clamp((s1 - centre) * inv_half_width, -1.0, 1.0);
            thr[out->barb_range_count] = r.barb;
            out->barb[out->barb_range_count++] = (plm_h_range){h0, h1, len * r.barb};
        }
    }
    tidy_barb_ranges(out, thr);
}

void plm_masking_barb(double barb_eccentricity, double barbule_length, double barbule_inclination,
                      double t_proximal, double t_distal, vec2 d, plm_barb_masking *out)
{
    plm_barb_geometry g = barb_geometry(barb_eccentricity, barbule_length, barbule_inclination);
    barb_eval(&g, t_proximal, t_distal, d, NULL, out);
}

/* ---------------------------------------------------------------- full masking */

/* A row lies in the plane through t tilted about t by theta_bb; p is the
 * in-plane direction across the row, p = (+-cos theta, sin theta, 0). A
 * barbule's axis makes phi_bb with t in that plane, r1 = r2 x axis runs
 * across the barbules within the row and r2 is the row's dorsal normal
 * (docs/masking.md). The proximal frame is the distal one mirrored across the
 * barb plane (b -> -b) with r1 negated, so that both are right-handed. */
void plm_masking_barbule_frames(const plm_masking_params *p, plm_barbule_frame *proximal, plm_barbule_frame *distal)
{
    double sp = sin(p->barbule_rotation), cp = cos(p->barbule_rotation);
    double st = sin(p->barbule_inclination), ct = cos(p->barbule_inclination);
    distal->axis = v3(sp * ct, sp * st, cp);
    distal->e2 = v3(cp * ct, cp * st, -sp);
    distal->e3 = v3(-st, ct, 0.0);
    proximal->axis = v3(-sp * ct, sp * st, cp);
    proximal->e2 = v3(cp * ct, -cp * st, sp);
    proximal->e3 = v3(st, ct, 0.0);
}

void plm_masking_prepare(const plm_masking_params *p, plm_masking_model *model)
{
    model->params = *p;
    plm_masking_barbule_frames(p, &model->proximal, &model->distal);
    model->barb = barb_geometry(p->barb_eccentricity, p->barbule_length, p->barbule_inclination);
}

void plm_masking_eval_window(const plm_masking_model *model, vec3 wo, const plm_barb_window *window,
                             plm_masking *out)
{
    plm_barbule_masking mp, md;
    double e_bb = model->params.barbule_eccentricity, delta_bb = model->params.barbule_separation;
    plm_masking_barbule(e_bb, delta_bb, v2(v3_dot(wo, model->proximal.e2), v3_dot(wo, model->proximal.e3)), &mp);
    plm_masking_barbule(e_bb, delta_bb, v2(v3_dot(wo, model->distal.e2), v3_dot(wo, model->distal.e3)), &md);
    plm_barb_masking mb;
    barb_eval(&model->barb, mp.transmittance, md.transmittance, v2(wo.x, wo.y), window, &mb);
    out->w_barb = mb.w_barb;
    out->w_proximal = mb.w_proximal;
    out->w_distal = mb.w_distal;
    out->w_transmission = mb.w_transmission;
    out->proximal = (plm_h_range){mp.hmin, mp.hmax, mb.w_proximal};
    out->distal = (plm_h_range){md.hmin, md.hmax, mb.w_distal};
    out->barb_range_count = mb.barb_range_count;
    for (int i = 0; i < mb.barb_range_count; ++i)
        out->barb[i] = mb.barb[i];
}

void plm_masking_eval(const plm_masking_params *p, vec3 wo, plm_masking *out)
{
    plm_masking_model model;
    plm_masking_prepare(p, &model);
    plm_masking_eval_window(&model, wo, NULL, out);
}
