/* Analytic barb and barbule masking: closed forms, invariants, symmetry,
 * continuity and robustness (the comparison with explicit 3D geometry is in
 * test_masking_reference.c and slow_masking.c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/rng.h"
#include "optics/masking.h"

#include "masking_random.h"

static vec3 random_direction(plm_rng *rng)
{
    double z = uniform(rng, -1.0, 1.0), phi = uniform(rng, 0.0, PLM_TWO_PI), r = sqrt(1.0 - z * z);
    return v3(r * cos(phi), z, r * sin(phi)); /* uniform over the sphere; y is the normal */
}

/* Every invariant a masking result must satisfy, whatever the input. */
static void check_invariants(const plm_masking *m)
{
    double w[4] = {m->w_barb, m->w_proximal, m->w_distal, m->w_transmission};
    double sum = 0.0;
    for (int i = 0; i < 4; ++i) {
        assert_true(isfinite(w[i]));
        assert_true(w[i] >= 0.0);
        sum += w[i];
    }
    assert_true(fabs(sum - 1.0) < 1e-12);
    const plm_h_range *sets[2] = {&m->proximal, &m->distal};
    for (int i = 0; i < 2; ++i) {
        assert_true(isfinite(sets[i]->hmin) && isfinite(sets[i]->hmax));
        assert_true(-1.0 <= sets[i]->hmin && sets[i]->hmin <= sets[i]->hmax && sets[i]->hmax <= 1.0);
    }
    assert_true(m->barb_range_count >= 0 && m->barb_range_count <= PLM_MASKING_MAX_BARB_RANGES);
    double rates = 0.0, previous = -1.0;
    for (int i = 0; i < m->barb_range_count; ++i) {
        const plm_h_range *g = &m->barb[i];
        assert_true(isfinite(g->hmin) && isfinite(g->hmax) && isfinite(g->rate));
        assert_true(previous - 1e-12 <= g->hmin && g->hmin < g->hmax && g->hmax <= 1.0);
        assert_true(g->rate > 0.0);
        /* The rate per unit h never exceeds an unobstructed barb's. */
        previous = g->hmax;
        rates += g->rate;
    }
    assert_true(fabs(rates - m->w_barb) < 1e-12);
}

/* Normal view, theta_bb = 0: barbs cover 2w of the unit period with
 * w = 1 / (2 (1 + l_bb)), the flat barbules the rest, and a barbule row seen
 * along its normal lets through delta / (1 + delta). */
static void normal_view_has_closed_form_weights(void **state)
{
    (void)state;
    const double cases[][4] = {{1, 1, 1, 1}, {3, 1, 1, 1}, {1, 2.5, 3, 0.3}, {6, 0.5, 0.2, 3}, {2, 1, 4, 0}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        plm_masking_params p;
        plm_masking_params_default(&p);
        p.barb_eccentricity = cases[k][0];
        p.barbule_eccentricity = cases[k][1];
        p.barbule_length = cases[k][2];
        p.barbule_separation = cases[k][3];
        plm_masking m;
        plm_masking_eval(&p, v3(0.0, 2.0, 0.0), &m);
        double w = 0.5 / (1.0 + p.barbule_length), t = p.barbule_separation / (1.0 + p.barbule_separation);
        assert_double_near(m.w_barb, 2.0 * w, 1e-12);
        assert_double_near(m.w_proximal, (0.5 - w) * (1.0 - t), 1e-12);
        assert_double_near(m.w_distal, (0.5 - w) * (1.0 - t), 1e-12);
        assert_double_near(m.w_transmission, (1.0 - 2.0 * w) * t, 1e-12);
        assert_int_equal(m.barb_range_count, 1);
        assert_double_near(m.barb[0].hmin, -1.0, 1e-12);
        assert_double_near(m.barb[0].hmax, 1.0, 1e-12);
        assert_double_near(m.proximal.hmin, -1.0, 1e-12);
        assert_double_near(m.distal.hmax, 1.0, 1e-12);
        check_invariants(&m);
    }
}

/* Barbule row at view angle alpha from its normal: period cos(alpha),
 * barbule width 2a sqrt(cos^2 + e^2 sin^2), a = 1 / (2 (1 + delta)). */
static void barbule_level_has_closed_form(void **state)
{
    (void)state;
    const double e = 1.7, delta = 0.6, a = 0.5 / (1.0 + delta);
    for (int i = -89; i <= 89; ++i) {
        double alpha = plm_radians(i);
        double period = cos(alpha), width = 2.0 * a * sqrt(plm_sqr(cos(alpha)) + plm_sqr(e * sin(alpha)));
        plm_barbule_masking m;
        plm_masking_barbule(e, delta, v2(3.0 * sin(alpha), 3.0 * cos(alpha)), &m);
        if (period > width) {
            assert_double_near(m.transmittance, 1.0 - width / period, 1e-12);
            assert_double_near(m.hmin, -1.0, 1e-15);
            assert_double_near(m.hmax, 1.0, 1e-15);
        } else {
            assert_double_near(m.transmittance, 0.0, 0.0);
            assert_double_near(m.hmax - m.hmin, 2.0 * period / width, 1e-12);
            /* The neighbour on the d_x side hides the high-h side when d_x d_y > 0. */
            if (i > 0)
                assert_double_near(m.hmin, -1.0, 0.0);
            else
                assert_double_near(m.hmax, 1.0, 0.0);
        }
        /* From below the row looks the same with h mirrored. */
        plm_barbule_masking below;
        plm_masking_barbule(e, delta, v2(sin(alpha), -cos(alpha)), &below);
        assert_double_near(below.transmittance, m.transmittance, 1e-12);
        assert_double_near(below.hmin, -m.hmax, 1e-12);
    }
}

static void touching_barbules_transmit_nothing(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 11, 0);
    for (int i = 0; i < 20000; ++i) {
        plm_masking_params p = random_params(&rng);
        p.barbule_separation = 0.0;
        vec3 wo = random_direction(&rng);
        plm_barbule_masking b;
        plm_masking_barbule(p.barbule_eccentricity, 0.0, v2(wo.x, wo.y), &b);
        assert_double_near(b.transmittance, 0.0, 0.0);
        plm_masking m;
        plm_masking_eval(&p, wo, &m);
        assert_double_near(m.w_transmission, 0.0, 0.0);
        check_invariants(&m);
    }
}

/* r is m seen in a mirror: the same weights (the barbule sets exchanged if
 * `swapped`), every h-interval mirrored (h -> -h) and the barb's in reverse order. */
static void assert_mirror_image(const plm_masking *m, const plm_masking *r, int swapped)
{
    const plm_h_range *mp = swapped ? &m->distal : &m->proximal, *md = swapped ? &m->proximal : &m->distal;
    assert_double_near(r->w_barb, m->w_barb, 1e-9);
    assert_double_near(r->w_proximal, swapped ? m->w_distal : m->w_proximal, 1e-9);
    assert_double_near(r->w_distal, swapped ? m->w_proximal : m->w_distal, 1e-9);
    assert_double_near(r->w_transmission, m->w_transmission, 1e-9);
    assert_double_near(r->proximal.hmin, -mp->hmax, 1e-9);
    assert_double_near(r->proximal.hmax, -mp->hmin, 1e-9);
    assert_double_near(r->distal.hmin, -md->hmax, 1e-9);
    assert_double_near(r->distal.hmax, -md->hmin, 1e-9);
    assert_int_equal(r->barb_range_count, m->barb_range_count);
    for (int k = 0; k < m->barb_range_count; ++k) {
        const plm_h_range *a = &m->barb[k], *b = &r->barb[m->barb_range_count - 1 - k];
        assert_double_near(b->hmin, -a->hmax, 1e-9);
        assert_double_near(b->rate, a->rate, 1e-9);
    }
}

/* Mirroring the view across the barb plane (b -> -b) swaps the proximal and
 * distal sets; mirroring it across the vane plane (n -> -n) together with
 * the rows (theta_bb -> -theta_bb) keeps them. */
static void mirror_symmetries(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 12, 0);
    for (int i = 0; i < 20000; ++i) {
        plm_masking_params p = random_params(&rng), q = p;
        q.barbule_inclination = -p.barbule_inclination;
        vec3 wo = random_direction(&rng);
        plm_masking m, across_barb, across_vane;
        plm_masking_eval(&p, wo, &m);
        plm_masking_eval(&p, v3(-wo.x, wo.y, wo.z), &across_barb);
        plm_masking_eval(&q, v3(wo.x, -wo.y, wo.z), &across_vane);
        assert_mirror_image(&m, &across_barb, 1);
        assert_mirror_image(&m, &across_vane, 0);
    }
}

/* The full masking is the barb level fed with the two barbule levels, each
 * seeing the view in its own row frame, written out here from the geometry
 * (docs/masking.md): a test of the wiring. */
static void full_masking_composes_the_levels_through_the_row_frames(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 18, 0);
    for (int i = 0; i < 20000; ++i) {
        plm_masking_params p = random_params(&rng);
        vec3 wo = random_direction(&rng);
        double sp = sin(p.barbule_rotation), cp = cos(p.barbule_rotation);
        double st = sin(p.barbule_inclination), ct = cos(p.barbule_inclination);
        /* r1 and r2 of the proximal and distal rows */
        vec3 r1[2] = {v3(cp * ct, -cp * st, sp), v3(cp * ct, cp * st, -sp)};
        vec3 r2[2] = {v3(st, ct, 0.0), v3(-st, ct, 0.0)};
        plm_barbule_masking bb[2];
        for (int k = 0; k < 2; ++k)
            plm_masking_barbule(p.barbule_eccentricity, p.barbule_separation,
                                v2(v3_dot(wo, r1[k]), v3_dot(wo, r2[k])), &bb[k]);
        plm_barb_masking b;
        plm_masking_barb(p.barb_eccentricity, p.barbule_length, p.barbule_inclination, bb[0].transmittance,
                         bb[1].transmittance, v2(wo.x, wo.y), &b);
        plm_masking m;
        plm_masking_eval(&p, wo, &m);
        assert_double_near(m.w_barb, b.w_barb, 1e-9);
        assert_double_near(m.w_proximal, b.w_proximal, 1e-9);
        assert_double_near(m.w_distal, b.w_distal, 1e-9);
        assert_double_near(m.w_transmission, b.w_transmission, 1e-9);
        assert_double_near(m.proximal.hmin, bb[0].hmin, 1e-9);
        assert_double_near(m.proximal.hmax, bb[0].hmax, 1e-9);
        assert_double_near(m.distal.hmin, bb[1].hmin, 1e-9);
        assert_double_near(m.distal.hmax, bb[1].hmax, 1e-9);
        assert_int_equal(m.barb_range_count, b.barb_range_count);
        for (int k = 0; k < b.barb_range_count; ++k) {
            assert_double_near(m.barb[k].hmin, b.barb[k].hmin, 1e-9);
            assert_double_near(m.barb[k].hmax, b.barb[k].hmax, 1e-9);
            assert_double_near(m.barb[k].rate, b.barb[k].rate, 1e-9);
        }
    }
}

/* Random parameters and views, including degenerate ones (along the barb,
 * along a barbule, in the vane plane, NaN): always a valid result. */
static void random_and_degenerate_views_give_valid_results(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 13, 0);
    for (int i = 0; i < 100000; ++i) {
        plm_masking_params p = random_params(&rng);
        assert_int_equal(plm_masking_params_validate(&p, NULL), PLM_OK);
        plm_barbule_frame fp, fd;
        plm_masking_barbule_frames(&p, &fp, &fd);
        vec3 special[6] = {v3(0, 0, 1), fp.axis, fd.axis, v3(1, 0, 0), v3(NAN, 1, 0), v3(0, 0, 0)};
        vec3 wo = i % 10 == 0 ? special[(i / 10) % 6] : random_direction(&rng);
        plm_masking m;
        plm_masking_eval(&p, wo, &m);
        check_invariants(&m);
    }
}

/* The barbule frames describe rows rooted along the barb: orthonormal and
 * right-handed (r1 = r2 x axis), r2 normal to t (the row plane contains the
 * barb axis), the axis at phi_bb from t, and the row, seen along t in the barb
 * cross-section, leaving the barb's side at theta_bb toward n. */
static void barbule_frames_are_rows_rooted_along_the_barb(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 14, 0);
    for (int i = 0; i < 1000; ++i) {
        plm_masking_params p = random_params(&rng);
        plm_barbule_frame f[2];
        plm_masking_barbule_frames(&p, &f[0], &f[1]);
        for (int k = 0; k < 2; ++k) {
            double side = k == 1 ? 1.0 : -1.0; /* distal leaves toward +b, proximal toward -b */
            assert_double_near(v3_length(f[k].axis), 1.0, 1e-12);
            assert_double_near(v3_length(f[k].e3), 1.0, 1e-12);
            assert_double_near(v3_dot(f[k].axis, f[k].e3), 0.0, 1e-12);
            vec3 r1 = v3_cross(f[k].e3, f[k].axis);
            assert_double_near(v3_length(v3_sub(r1, f[k].e2)), 0.0, 1e-12);
            assert_double_near(f[k].e3.z, 0.0, 1e-15);
            assert_true(f[k].e3.y > 0.0);
            assert_double_near(f[k].axis.z, cos(p.barbule_rotation), 1e-12);
            assert_double_near(atan2(f[k].axis.y, side * f[k].axis.x), p.barbule_inclination, 1e-12);
        }
    }
}

static vec3 sweep_view(int sweep_polar, double fixed, int upper, double t)
{
    double polar = sweep_polar ? t : fixed, azimuth = sweep_polar ? fixed : t;
    return v3(sin(polar) * cos(azimuth), upper ? cos(polar) : -cos(polar), sin(polar) * sin(azimuth));
}

static double weight_change(const plm_masking *a, const plm_masking *b)
{
    return fmax(fmax(fabs(a->w_barb - b->w_barb), fabs(a->w_proximal - b->w_proximal)),
                fmax(fabs(a->w_distal - b->w_distal), fabs(a->w_transmission - b->w_transmission)));
}

/* The largest change of any weight between neighbouring views along a
 * sweep of the polar angle from the normal (0 to 87 degrees, fixed azimuth)
 * or of the azimuth (fixed polar angle), on one side, 0.05 degrees apart.
 * Where a step changes a weight by more than `bound`, that step is looked at
 * again 100 times finer: a steep but continuous change shrinks there, a jump
 * does not. */
static double largest_weight_step(const plm_masking_params *p, int sweep_polar, double fixed, int upper, double bound)
{
    const double step = plm_radians(0.05), end = sweep_polar ? plm_radians(87.0) : PLM_TWO_PI;
    plm_masking prev = {0};
    double worst = 0.0;
    for (double t = 0.0; t < end; t += step) {
        plm_masking m;
        plm_masking_eval(p, sweep_view(sweep_polar, fixed, upper, t), &m);
        double change = t > 0.0 ? weight_change(&m, &prev) : 0.0;
        if (change > bound) {
            change = 0.0;
            plm_masking a = prev;
            for (int i = 1; i <= 100; ++i) {
                plm_masking b;
                plm_masking_eval(p, sweep_view(sweep_polar, fixed, upper, t - step + step * i / 100.0), &b);
                change = fmax(change, weight_change(&a, &b));
                a = b;
            }
        }
        worst = fmax(worst, change);
        prev = m;
    }
    return worst;
}

/* Along fine sweeps of the view the weights move by a small amount per step
 * (a steep change, such as a barbule row turning opaque, is followed finer).
 * The one visibility event where they jump is crossing the vane plane
 * (y = 0: the view changes side), so the sweeps stay off it; grazing a
 * barbule row's plane only flips that set's h-interval, not the weights. */
static void weights_are_continuous_along_view_sweeps(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 15, 0);
    for (int sweep = 0; sweep < 60; ++sweep) {
        plm_masking_params p = random_params(&rng);
        int sweep_polar = sweep % 2, upper = (sweep / 2) % 2;
        double fixed = sweep_polar ? uniform(&rng, 0.0, PLM_TWO_PI) : uniform(&rng, 0.01, plm_radians(85.0));
        double worst = largest_weight_step(&p, sweep_polar, fixed, upper, 0.02);
        if (worst > 0.02)
            fprintf(stderr, "sweep %d: largest step %g (e_b %g e_bb %g l %g d %g phi %g theta %g fixed %g)\n", sweep,
                    worst, p.barb_eccentricity, p.barbule_eccentricity, p.barbule_length, p.barbule_separation,
                    plm_degrees(p.barbule_rotation), plm_degrees(p.barbule_inclination), plm_degrees(fixed));
        assert_true(worst <= 0.02);
    }
}

/* The barb level by plain 2D ray casting, for comparison: N rays spread
 * evenly over one projected period, each intersected with every barb and
 * barbule segment it can reach (no visibility classes), front to back, each
 * segment passing T of what reaches it. */
typedef struct crossing {
    double depth;
    int kind; /* 0 barb, 1 proximal, 2 distal */
    int cell; /* which barb */
} crossing;

static int by_depth_descending(const void *a, const void *b)
{
    double x = ((const crossing *)a)->depth, y = ((const crossing *)b)->depth;
    return (x < y) - (x > y);
}

#define H_BINS 20

static void cast_barb_level(double e_b, double l, double theta, double tp, double td, vec2 d, int n, double w_out[4],
                            double h_bins[H_BINS])
{
    double w = 0.5 / (1.0 + l * cos(theta)), hb = w * e_b, yc = l * w * sin(theta);
    d = v2_normalize(d);
    vec2 u = v2(d.y, -d.x);
    double ylo = fmin(-hb, yc), yhi = fmax(hb, yc);
    double half_width = sqrt(plm_sqr(w * d.y) + plm_sqr(hb * d.x));
    for (int k = 0; k < 4; ++k)
        w_out[k] = 0.0;
    for (int k = 0; k < H_BINS; ++k)
        h_bins[k] = 0.0;
    for (int i = 0; i < n; ++i) {
        double s = (i + 0.5) / n * fabs(d.y);
        /* the ray s u + t d within the band of geometry */
        double t0 = (ylo + s * d.x) / d.y, t1 = (yhi + s * d.x) / d.y;
        double xa = s * d.y + t0 * d.x, xb = s * d.y + t1 * d.x;
        int j0 = (int)floor(fmin(xa, xb)) - 1, j1 = (int)floor(fmax(xa, xb)) + 1;
        crossing c[1024];
        int m = 0;
        for (int j = j0; j <= j1 && m < 1020; ++j) {
            /* barb j: |((s u + t d) - (j, 0)) / (w, hb)| = 1 */
            double ox = s * u.x - j, oy = s * u.y;
            double qa = plm_sqr(d.x / w) + plm_sqr(d.y / hb);
            double qb = 2.0 * (ox * d.x / (w * w) + oy * d.y / (hb * hb));
            double qc = plm_sqr(ox / w) + plm_sqr(oy / hb) - 1.0;
            double disc = qb * qb - 4.0 * qa * qc;
            if (disc > 0.0)
                c[m++] = (crossing){(-qb + sqrt(disc)) / (2.0 * qa), 0, j};
            vec2 ridge = v2(j + 0.5, yc), roots[2] = {v2(j + 1.0 - w, 0.0), v2(j + w, 0.0)};
            for (int k = 0; k < 2; ++k) {
                /* solve origin + t d = root + f (ridge - root) */
                vec2 e = v2_sub(ridge, roots[k]), o = v2_sub(v2_scale(u, s), roots[k]);
                double den = v2_cross(d, e);
                if (fabs(den) < 1e-300)
                    continue;
                double f = v2_cross(d, o) / den, t = v2_cross(e, o) / den;
                if (f > 0.0 && f < 1.0)
                    c[m++] = (crossing){t, 1 + k, j};
            }
        }
        qsort(c, (size_t)m, sizeof c[0], by_depth_descending);
        double thr = 1.0;
        int ended = 0;
        for (int k = 0; k < m && !ended; ++k) {
            if (c[k].kind == 0) {
                double h = (s - c[k].cell * u.x) / half_width; /* (j, 0) . u = j d_y */
                int bin = (int)((h + 1.0) * 0.5 * H_BINS);
                h_bins[bin < 0 ? 0 : bin >= H_BINS ? H_BINS - 1 : bin] += thr / n;
                w_out[0] += thr;
                ended = 1;
                continue;
            }
            double t = c[k].kind == 1 ? tp : td;
            w_out[c[k].kind] += thr * (1.0 - t);
            thr *= t;
        }
        if (!ended)
            w_out[3] += thr;
    }
    for (int k = 0; k < 4; ++k)
        w_out[k] /= n;
}

/* The visibility classes against plain ray casting over random geometry and
 * views (both sides, grazing to 3 degrees from the vane plane). */
static void barb_level_matches_plain_ray_casting(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 16, 0);
    const int n = 4000;
    for (int i = 0; i < 400; ++i) {
        double e_b = uniform(&rng, 0.2, 6.0), l = uniform(&rng, 0.1, 6.0);
        double theta = plm_radians(uniform(&rng, -85.0, 85.0));
        double tp = uniform(&rng, 0.0, 1.0), td = uniform(&rng, 0.0, 1.0);
        double elevation = plm_radians(uniform(&rng, 3.0, 90.0)), side = plm_rng_uniform(&rng) < 0.5 ? -1.0 : 1.0;
        double sign = plm_rng_uniform(&rng) < 0.5 ? -1.0 : 1.0;
        vec2 d = v2(sign * cos(elevation), side * sin(elevation));
        plm_barb_masking m;
        plm_masking_barb(e_b, l, theta, tp, td, d, &m);
        double cast[4], cast_h[H_BINS];
        cast_barb_level(e_b, l, theta, tp, td, d, n, cast, cast_h);
        double got[4] = {m.w_barb, m.w_proximal, m.w_distal, m.w_transmission};
        /* n evenly spread rays miss each of at most 5 class boundaries by half a ray */
        for (int k = 0; k < 4; ++k)
            assert_double_near(got[k], cast[k], 5.0 / n);
        /* the barb's h-ranges put the same rate in each h bin as the rays do */
        double got_h[H_BINS] = {0};
        for (int r = 0; r < m.barb_range_count; ++r) {
            const plm_h_range *g = &m.barb[r];
            double density = g->rate / (g->hmax - g->hmin);
            for (int b = 0; b < H_BINS; ++b) {
                double lo = -1.0 + 2.0 * b / H_BINS, hi = lo + 2.0 / H_BINS;
                got_h[b] += density * fmax(0.0, fmin(hi, g->hmax) - fmax(lo, g->hmin));
            }
        }
        for (int b = 0; b < H_BINS; ++b)
            assert_double_near(got_h[b], cast_h[b], 5.0 / n);
    }
}

/* Out-of-range values are named with the field and its range; the angles'
 * ranges are open (degrees in the message). */
static void validation_names_the_field_and_range(void **state)
{
    (void)state;
    struct {
        size_t offset;
        double value;
        const char *name, *range;
    } bad[] = {
        {offsetof(plm_masking_params, barb_eccentricity), 0.0, "barb_eccentricity", "(0, 20]"},
        {offsetof(plm_masking_params, barb_eccentricity), -1.0, "barb_eccentricity", "(0, 20]"},
        {offsetof(plm_masking_params, barbule_eccentricity), 0.0, "barbule_eccentricity", "(0, 20]"},
        {offsetof(plm_masking_params, barbule_length), 0.0, "barbule_length", "(0, 100]"},
        {offsetof(plm_masking_params, barbule_length), -2.0, "barbule_length", "(0, 100]"},
        {offsetof(plm_masking_params, barbule_separation), -0.1, "barbule_separation", "[0, 100]"},
        {offsetof(plm_masking_params, barbule_rotation), plm_radians(91.0), "barbule_rotation", "(0, 90)"},
        {offsetof(plm_masking_params, barbule_rotation), plm_radians(90.0), "barbule_rotation", "(0, 90)"},
        {offsetof(plm_masking_params, barbule_rotation), 0.0, "barbule_rotation", "(0, 90)"},
        {offsetof(plm_masking_params, barbule_inclination), plm_radians(90.0), "barbule_inclination", "(-90, 90)"},
        {offsetof(plm_masking_params, barbule_inclination), plm_radians(-90.0), "barbule_inclination", "(-90, 90)"},
        {offsetof(plm_masking_params, barbule_inclination), plm_radians(-120.0), "barbule_inclination", "(-90, 90)"},
        {offsetof(plm_masking_params, barbule_separation), NAN, "barbule_separation", "[0, 100]"},
        {offsetof(plm_masking_params, barb_eccentricity), INFINITY, "barb_eccentricity", "(0, 20]"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        plm_masking_params p;
        plm_masking_params_default(&p);
        assert_int_equal(plm_masking_params_validate(&p, NULL), PLM_OK);
        *(double *)((char *)&p + bad[i].offset) = bad[i].value;
        plm_error err;
        err.message[0] = '\0';
        assert_int_equal(plm_masking_params_validate(&p, &err), PLM_ERR_INVALID);
        assert_non_null(strstr(err.message, bad[i].name));
        assert_non_null(strstr(err.message, bad[i].range));
    }
    /* just inside the open ranges */
    plm_masking_params p;
    plm_masking_params_default(&p);
    p.barbule_inclination = plm_radians(-89.9);
    p.barbule_rotation = plm_radians(89.9);
    assert_int_equal(plm_masking_params_validate(&p, NULL), PLM_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(normal_view_has_closed_form_weights),
        cmocka_unit_test(barbule_level_has_closed_form),
        cmocka_unit_test(touching_barbules_transmit_nothing),
        cmocka_unit_test(mirror_symmetries),
        cmocka_unit_test(full_masking_composes_the_levels_through_the_row_frames),
        cmocka_unit_test(random_and_degenerate_views_give_valid_results),
        cmocka_unit_test(barbule_frames_are_rows_rooted_along_the_barb),
        cmocka_unit_test(weights_are_continuous_along_view_sweeps),
        cmocka_unit_test(barb_level_matches_plain_ray_casting),
        cmocka_unit_test(validation_names_the_field_and_range),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
