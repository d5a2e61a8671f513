/* Analytic barb and barbule masking (paper Sec. 6.1). See masking.h for the
 * model. Both levels measure widths along the projection axis
 * u = (d_y, -d_x), perpendicular to the view direction d in the
 * cross-section: a fiber's visible width between two visibility rays is the
 * difference of the rays' coordinates along u (the paper's Eq. 6 for arcs and
 * its cosine analogue for segments give the same numbers), and h is that
 * coordinate scaled to [-1, 1] across the fiber's silhouette. */
#include "render/masking.h"

#include <math.h>

/* Parameter ranges, shared by validation and the documentation. */
#define MAX_ECCENTRICITY 20.0
#define MAX_LENGTH 100.0
#define MAX_SEPARATION 100.0
#define MAX_INCLINATION_DEG 89.0
#define MAX_ROTATION_DEG 90.0

void plm_masking_params_default(plm_masking_params *p)
{
    p->barb_eccentricity = 1.0;
    p->barbule_eccentricity = 1.0;
    p->barbule_length = 1.0;
    p->barbule_separation = 1.0;
    p->barbule_rotation = plm_radians(45.0);
    p->barbule_inclination = 0.0;
}

/* lo_open: the lower bound is excluded. */
static plm_result check_range(plm_error *err, const char *name, double v, double lo, double hi, int lo_open,
                              double shown_scale, const char *unit)
{
    int ok = isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
    if (ok)
        return PLM_OK;
    return plm_fail(err, PLM_ERR_INVALID, "masking parameter %s = %g%s is out of range %c%g, %g]%s", name,
                    v * shown_scale, unit, lo_open ? '(' : '[', lo * shown_scale, hi * shown_scale,
                    isfinite(v) ? "" : " (not a finite number)");
}

plm_result plm_masking_params_validate(const plm_masking_params *p, plm_error *err)
{
    const double deg = 180.0 / PLM_PI;
    plm_result r;
    if ((r = check_range(err, "barb_eccentricity", p->barb_eccentricity, 0.0, MAX_ECCENTRICITY, 1, 1.0, "")) ||
        (r = check_range(err, "barbule_eccentricity", p->barbule_eccentricity, 0.0, MAX_ECCENTRICITY, 1, 1.0, "")) ||
        (r = check_range(err, "barbule_length", p->barbule_length, 0.0, MAX_LENGTH, 1, 1.0, "")) ||
        (r = check_range(err, "barbule_separation", p->barbule_separation, 0.0, MAX_SEPARATION, 0, 1.0, "")) ||
        (r = check_range(err, "barbule_rotation", p->barbule_rotation, 0.0, plm_radians(MAX_ROTATION_DEG), 0, deg,
                         " deg")) ||
        (r = check_range(err, "barbule_inclination", p->barbule_inclination, 0.0,
                         plm_radians(MAX_INCLINATION_DEG), 0, deg, " deg")))
        return r;
    return PLM_OK;
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
 * (j + 1 - w, 0) to the same ridge; cell j spans x in [j - w, j + 1 - w). */
typedef struct barb_scene {
    double w, hb, yc;
    double ylo, yhi;    /* the band of y that holds all geometry */
    vec2 d, u;          /* unit view direction and h axis (d_y, -d_x) */
    double half_width;  /* the barb's projected half-width along u */
    double t_proximal, t_distal;
} barb_scene;

enum { HIT_BARB, HIT_PROXIMAL, HIT_DISTAL };

typedef struct hit {
    double depth; /* position along d: larger is nearer the viewer */
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

static int segment_crossing(vec2 a, vec2 b, double s, const barb_scene *sc, double *depth)
{
    double sa = v2_dot(a, sc->u), sb = v2_dot(b, sc->u);
    if (!((s - sa) * (s - sb) < 0.0))
        return 0; /* misses, or the segment lies along the ray */
    double f = (s - sa) / (sb - sa);
    *depth = v2_dot(v2_add(a, v2_scale(v2_sub(b, a), f)), sc->d);
    return 1;
}

/* Nearest-to-viewer intersection depth of the line {s u + tau d} with barb j. */
static int barb_crossing(const barb_scene *sc, int j, double s, double *depth)
{
    double ds = s - (double)j * sc->u.x; /* offset from barb j's centre, (j, 0) . u */
    if (!(fabs(ds) < sc->half_width))
        return 0;
    /* Local point q = ds u + t d on ((q_x / w)^2 + (q_y / hb)^2 = 1). */
    double iw2 = 1.0 / (sc->w * sc->w), ih2 = 1.0 / (sc->hb * sc->hb);
    double qa = sc->d.x * sc->d.x * iw2 + sc->d.y * sc->d.y * ih2;
    double qb = 2.0 * ds * (sc->u.x * sc->d.x * iw2 + sc->u.y * sc->d.y * ih2);
    double qc = ds * ds * (sc->u.x * sc->u.x * iw2 + sc->u.y * sc->u.y * ih2) - 1.0;
    double t = (-qb + plm_safe_sqrt(qb * qb - 4.0 * qa * qc)) / (2.0 * qa);
    *depth = (double)j * sc->d.x + t;
    return 1;
}

/* The crossings of cell j, nearest to the viewer first. */
static int cell_hits(const barb_scene *sc, int j, double s, hit hits[3])
{
    int n = 0;
    double x0 = (double)j;
    vec2 ridge = v2(x0 + 0.5, sc->yc);
    if (barb_crossing(sc, j, s, &hits[n].depth))
        hits[n++].kind = HIT_BARB;
    if (segment_crossing(v2(x0 + sc->w, 0.0), ridge, s, sc, &hits[n].depth))
        hits[n++].kind = HIT_DISTAL;
    if (segment_crossing(v2(x0 + 1.0 - sc->w, 0.0), ridge, s, sc, &hits[n].depth))
        hits[n++].kind = HIT_PROXIMAL;
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
static ray_result trace_ray(const barb_scene *sc, double s)
{
    ray_result r = {0.0, 0.0, 0.0, 0.0, 0};
    /* x and y along the ray: s u + tau d, travelling toward smaller tau. */
    double tau_top = (sc->yhi + s * sc->d.x) / sc->d.y, tau_bottom = (sc->ylo + s * sc->d.x) / sc->d.y;
    double tau_in = fmax(tau_top, tau_bottom), tau_out = fmin(tau_top, tau_bottom);
    double x_in = s * sc->d.y + tau_in * sc->d.x, x_out = s * sc->d.y + tau_out * sc->d.x;
    int j = (int)floor(x_in + sc->w), j_last = (int)floor(x_out + sc->w);
    int step = j_last >= j ? 1 : -1;
    double throughput = 1.0;
    int last_layer = -1;
    for (int cells = 0; cells < MAX_CELLS; ++cells, j += step) {
        hit hits[3];
        int n = cell_hits(sc, j, s, hits);
        for (int i = 0; i < n; ++i) {
            if (hits[i].kind == HIT_BARB) {
                r.barb = throughput;
                r.barb_cell = j;
                return r;
            }
            int proximal = hits[i].kind == HIT_PROXIMAL;
            double t = proximal ? sc->t_proximal : sc->t_distal;
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

static void sort5(double v[5])
{
    for (int i = 1; i < 5; ++i)
        for (int k = i; k > 0 && v[k] < v[k - 1]; --k) {
            double tmp = v[k];
            v[k] = v[k - 1];
            v[k - 1] = tmp;
        }
}

static double wrap(double s, double period)
{
    double r = fmod(s, period);
    return r < 0.0 ? r + period : r;
}

/* Orders the ranges by h and joins neighbours that continue each other at
 * the same throughput (one visible stretch of barb split by a class
 * boundary that changes nothing in front of it). */
static void tidy_barb_ranges(plm_barb_masking *out, double thr[])
{
    int n = out->barb_range_count;
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

void plm_masking_barb(double barb_eccentricity, double barbule_length, double barbule_inclination,
                      double t_proximal, double t_distal, vec2 d, plm_barb_masking *out)
{
    barb_scene sc;
    d = unit_direction(d);
    /* Views within 1e-7 of the vane plane are taken as that close to it, on
     * their own side: exactly in the plane the projected period vanishes. */
    const double min_dy = 1e-7;
    if (fabs(d.y) < min_dy)
        d = unit_direction(v2(d.x, d.y < 0.0 ? -min_dy : min_dy));
    sc.d = d;
    sc.u = v2(d.y, -d.x);
    /* Period 1 = barb width 2w + two barbule spans l w cos(theta). */
    double c = cos(barbule_inclination);
    sc.w = 0.5 / (1.0 + barbule_length * c);
    sc.hb = sc.w * barb_eccentricity;
    sc.yc = barbule_length * sc.w * sin(barbule_inclination);
    sc.ylo = fmin(-sc.hb, sc.yc);
    sc.yhi = fmax(sc.hb, sc.yc);
    sc.half_width = sqrt(plm_sqr(sc.w * d.y) + plm_sqr(sc.hb * d.x));
    sc.t_proximal = plm_clamp(t_proximal, 0.0, 1.0);
    sc.t_distal = plm_clamp(t_distal, 0.0, 1.0);

    /* Visibility changes only where a ray grazes a barb's silhouette (its
     * tangent points, Eq. 5) or passes a segment end (the roots and the ridge
     * corner); between those, every ray of the period meets the same things in
     * the same order, so one ray per class decides the class. */
    double period = fabs(d.y);
    double b[5] = {wrap(-sc.half_width, period), wrap(sc.half_width, period), wrap(sc.w * d.y, period),
                   wrap((1.0 - sc.w) * d.y, period), wrap(0.5 * d.y - sc.yc * d.x, period)};
    sort5(b);

    out->w_barb = out->w_proximal = out->w_distal = out->w_transmission = 0.0;
    out->barb_range_count = 0;
    double thr[PLM_MASKING_MAX_BARB_RANGES];
    for (int i = 0; i < 5; ++i) {
        double s0 = b[i], s1 = i < 4 ? b[i + 1] : b[0] + period;
        double len = (s1 - s0) / period;
        if (!(len > 1e-13))
            continue;
        ray_result r = trace_ray(&sc, 0.5 * (s0 + s1));
        out->w_proximal += len * r.proximal;
        out->w_distal += len * r.distal;
        out->w_transmission += len * r.transmission;
        if (r.barb > 0.0) {
            out->w_barb += len * r.barb;
            double centre = (double)r.barb_cell * d.y; /* (j, 0) . u */
            double h0 = plm_clamp((s0 - centre) / sc.half_width, -1.0, 1.0);
            double h1 = plm_clamp((s1 - centre) / sc.half_width, -1.0, 1.0);
            thr[out->barb_range_count] = r.barb;
            out->barb[out->barb_range_count++] = (plm_h_range){h0, h1, len * r.barb};
        }
    }
    tidy_barb_ranges(out, thr);
}

/* ---------------------------------------------------------------- full masking */

void plm_masking_barbule_frames(const plm_masking_params *p, plm_barbule_frame *proximal, plm_barbule_frame *distal)
{
    double sp = sin(p->barbule_rotation), cp = cos(p->barbule_rotation);
    double st = sin(p->barbule_inclination), ct = cos(p->barbule_inclination);
    vec3 r2 = v3(0.0, ct, -st);
    distal->axis = v3(sp, st * cp, ct * cp);
    distal->e2 = v3(cp, -st * sp, -ct * sp);
    distal->e3 = r2;
    proximal->axis = v3(-sp, st * cp, ct * cp);
    proximal->e2 = v3(cp, st * sp, ct * sp);
    proximal->e3 = r2;
}

void plm_masking_eval(const plm_masking_params *p, vec3 wo, plm_masking *out)
{
    plm_barbule_frame fp, fd;
    plm_masking_barbule_frames(p, &fp, &fd);
    plm_barbule_masking mp, md;
    plm_masking_barbule(p->barbule_eccentricity, p->barbule_separation, v2(v3_dot(wo, fp.e2), v3_dot(wo, fp.e3)),
                        &mp);
    plm_masking_barbule(p->barbule_eccentricity, p->barbule_separation, v2(v3_dot(wo, fd.e2), v3_dot(wo, fd.e3)),
                        &md);
    plm_barb_masking mb;
    plm_masking_barb(p->barb_eccentricity, p->barbule_length, p->barbule_inclination, mp.transmittance,
                     md.transmittance, v2(wo.x, wo.y), &mb);
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
