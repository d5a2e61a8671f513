/* The fluffy base as fibers (generate/fluff.h): how many, how long and how
 * much memory per feather; where every curve starts (down barbs on the
 * rachis within the downy base, the afterfeather's shaft on the rachis's
 * underside where the vanes begin, its barbs on that shaft, barbules on
 * their barb), even on a bent rachis; thinning; reproducibility by seed;
 * bad input. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"
#include "test_files.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "generate/fluff.h"
#include "generate/geometry.h"

static const char *const presets[] = {"covert_parrot", "cardinal_red", "remex_pigeon", "hackle_pointed",
                                      "goose_dark"};
#define PRESET_COUNT 5

/* Float positions of millimetre-sized feathers: a few float steps. */
#define POSITION_TOL 2e-4

static vec3 point(const plm_curves *c, int i)
{
    const float *p = c->points + 4 * (size_t)i;
    return v3(p[0], p[1], p[2]);
}

static double radius(const plm_curves *c, int i) { return c->points[4 * (size_t)i + 3]; }

static double curve_length(const plm_curves *c, int k)
{
    double l = 0.0;
    for (int i = c->first[k] + 1; i < c->first[k + 1]; ++i)
        l += v3_length(v3_sub(point(c, i), point(c, i - 1)));
    return l;
}

/* Distance from p to the polyline of curve k, and the curve's radius there. */
static double distance_to_curve(const plm_curves *c, int k, vec3 p, double *r_there)
{
    double best = INFINITY;
    for (int i = c->first[k]; i + 1 < c->first[k + 1]; ++i) {
        vec3 a = point(c, i), d = v3_sub(point(c, i + 1), a);
        double s = plm_clamp(v3_dot(v3_sub(p, a), d) / v3_dot(d, d), 0.0, 1.0);
        double dist = v3_length(v3_sub(p, v3_madd(a, d, s)));
        if (dist < best)
            best = dist, *r_there = radius(c, i) + s * (radius(c, i + 1) - radius(c, i));
    }
    return best;
}

/* The arc length y of the rachis centre line point nearest p: a scan, then
 * a ternary search (the distance is unimodal near the root). */
static double nearest_on_rachis(const plm_outline *o, vec3 p)
{
    double best = 0.0, dmin = INFINITY;
    for (double y = 0.0; y <= o->rachis_end; y += 0.05) {
        double d = v3_length(v3_sub(plm_rachis_frame_at(o, y).c, p));
        if (d < dmin)
            dmin = d, best = y;
    }
    double lo = fmax(0.0, best - 0.05), hi = fmin(o->rachis_end, best + 0.05);
    for (int it = 0; it < 60; ++it) {
        double a = lo + (hi - lo) / 3.0, b = hi - (hi - lo) / 3.0;
        if (v3_length(v3_sub(plm_rachis_frame_at(o, a).c, p)) < v3_length(v3_sub(plm_rachis_frame_at(o, b).c, p)))
            hi = b;
        else
            lo = a;
    }
    return 0.5 * (lo + hi);
}

static void fluff_of(const plm_shape *sh, plm_outline *o, plm_curves *c)
{
    assert_int_equal(plm_outline_init(o, sh, "t", NULL), PLM_OK);
    assert_int_equal(plm_fluff_curves(o, c, NULL), PLM_OK);
}

static int count_kind(const plm_curves *c, plm_fluff_kind kind, int side_sign, const plm_outline *o)
{
    int n = 0;
    for (int k = 0; k < c->curve_count; ++k)
        if (c->tag[k] == kind) {
            if (side_sign == 0)
                n++;
            else {
                vec3 root = point(c, c->first[k]);
                plm_rachis_frame f = plm_rachis_frame_at(o, nearest_on_rachis(o, root));
                n += (v3_dot(v3_sub(root, f.c), f.x) > 0.0) == (side_sign > 0);
            }
        }
    return n;
}

/* Counts from first principles: one down barb per 1/density cm per side over
 * the downy base (the last may fall at its end), the afterfeather's shaft
 * where the species has one, its barbs per 1/density cm per side over 92% of
 * its length; each barb's length is the vane width there times
 * fluff.length, times 0.6-1.0 from the base's start to its end, times a draw
 * in [0.8, 1.2]; its polyline is that long; memory is the arrays' size. */
static void counts_lengths_and_memory(void **state)
{
    (void)state;
    printf("%-16s %6s %6s %6s %8s %8s %9s %10s\n", "preset", "down", "after", "barbul", "curves", "points",
           "fiber_mm", "bytes");
    for (int p = 0; p < PRESET_COUNT; ++p) {
        plm_species sp = load_preset(presets[p]);
        const plm_shape *sh = &sp.shape;
        plm_outline o;
        plm_curves c;
        fluff_of(sh, &o, &c);
        double spacing = 10.0 / sh->fluff_density, down = sh->plumulaceous * o.vane_length;
        double per_side = ceil(fmin(down, o.rachis_end - o.vane_base) / spacing);
        for (int side = -1; side <= 1; side += 2)
            assert_int_equal(count_kind(&c, PLM_FLUFF_DOWN, side, &o), (int)per_side);
        assert_int_equal(count_kind(&c, PLM_FLUFF_HYPORACHIS, 0, &o), sh->afterfeather);
        double after = sh->afterfeather_size * sh->length;
        if (sh->afterfeather)
            assert_int_equal(count_kind(&c, PLM_FLUFF_AFTERFEATHER, 0, &o), 2 * (int)ceil(0.92 * after / spacing));
        double total = 0.0;
        int barbules = count_kind(&c, PLM_FLUFF_BARBULE, 0, &o);
        double barb_length = 0.0;
        for (int k = 0; k < c.curve_count; ++k) {
            double l = curve_length(&c, k);
            total += l;
            if (c.tag[k] == PLM_FLUFF_DOWN || c.tag[k] == PLM_FLUFF_AFTERFEATHER)
                barb_length += l;
            if (c.tag[k] != PLM_FLUFF_DOWN)
                continue;
            vec3 root = point(&c, c.first[k]);
            double y = nearest_on_rachis(&o, root);
            plm_rachis_frame f = plm_rachis_frame_at(&o, y);
            int side = v3_dot(v3_sub(root, f.c), f.x) > 0.0;
            double t = (y - o.vane_base) / o.vane_length, s = (y - o.vane_base) / down;
            double ratio = l / (sh->fluff_length * plm_outline_width(&o, side, t) * (0.6 + 0.4 * s));
            assert_true(ratio >= 0.8 - 1e-3 && ratio <= 1.2 + 1e-3);
        }
        /* Barbules: fluff.barbules per mm of barb, each barb's count rounded by a draw. */
        int barbs = count_kind(&c, PLM_FLUFF_DOWN, 0, &o) + count_kind(&c, PLM_FLUFF_AFTERFEATHER, 0, &o);
        assert_true(fabs(barbules - sh->fluff_barbules * barb_length) <= barbs);
        size_t bytes = 16 * (size_t)c.point_count + 4 * (size_t)(c.curve_count + 1) + (size_t)c.curve_count;
        assert_int_equal(plm_curves_bytes(&c), bytes);
        assert_true(bytes < 2 * 1024 * 1024); /* a feather's fluff stays under 2 MiB (docs/generating.md) */
        printf("%-16s %6d %6d %6d %8d %8d %9.0f %10zu\n", presets[p], count_kind(&c, PLM_FLUFF_DOWN, 0, &o),
               count_kind(&c, PLM_FLUFF_AFTERFEATHER, 0, &o), barbules, c.curve_count, c.point_count, total, bytes);
        plm_curves_free(&c);
        plm_species_free(&sp);
    }
}

/* Every curve starts where it grows from, and thins to a quarter of its
 * root radius; on presets and on a strongly bent and twisted rachis. */
static void check_roots(const plm_shape *sh)
{
    plm_outline o;
    plm_curves c;
    fluff_of(sh, &o, &c);
    assert_true(c.curve_count > 0);
    double base_end = o.vane_base + sh->plumulaceous * o.vane_length;
    int shaft = -1, barb = -1;
    for (int k = 0; k < c.curve_count; ++k) {
        vec3 root = point(&c, c.first[k]);
        int n = c.first[k + 1] - c.first[k];
        assert_int_equal(n, c.tag[k] == PLM_FLUFF_BARBULE ? PLM_FLUFF_BARBULE_POINTS : PLM_FLUFF_BARB_POINTS);
        if (c.tag[k] == PLM_FLUFF_DOWN || c.tag[k] == PLM_FLUFF_HYPORACHIS) {
            double y = nearest_on_rachis(&o, root);
            double dist = v3_length(v3_sub(root, plm_rachis_frame_at(&o, y).c));
            assert_double_near(dist, plm_outline_rachis_radius(&o, y), POSITION_TOL);
            assert_true(y >= o.vane_base - POSITION_TOL && y <= base_end + POSITION_TOL);
            if (c.tag[k] == PLM_FLUFF_HYPORACHIS) { /* on the underside, where the vanes begin */
                assert_double_near(y, o.vane_base, POSITION_TOL);
                assert_true(v3_dot(v3_sub(root, plm_rachis_frame_at(&o, y).c), plm_rachis_frame_at(&o, y).z) < 0.0);
                shaft = k;
            }
        } else if (c.tag[k] == PLM_FLUFF_AFTERFEATHER) {
            double r_there = 0.0;
            assert_true(shaft >= 0);
            /* on its surface (a joint of the polyline may lie a little nearer) */
            double dist = distance_to_curve(&c, shaft, root, &r_there);
            assert_true(dist <= r_there + POSITION_TOL && dist >= 0.95 * r_there - POSITION_TOL);
        } else {
            double r_there = 0.0;
            assert_int_equal(c.tag[k], PLM_FLUFF_BARBULE);
            assert_true(barb >= 0);
            assert_true(distance_to_curve(&c, barb, root, &r_there) < POSITION_TOL);
        }
        if (c.tag[k] == PLM_FLUFF_DOWN || c.tag[k] == PLM_FLUFF_AFTERFEATHER)
            barb = k;
        for (int i = c.first[k] + 1; i < c.first[k + 1]; ++i)
            assert_true(radius(&c, i) < radius(&c, i - 1) && radius(&c, i) > 0.0);
        assert_double_near(radius(&c, c.first[k + 1] - 1), 0.25 * radius(&c, c.first[k]), 1e-6);
    }
    plm_curves_free(&c);
}

static void every_curve_starts_on_its_shaft(void **state)
{
    (void)state;
    for (int p = 0; p < PRESET_COUNT; ++p) {
        plm_species sp = load_preset(presets[p]);
        check_roots(&sp.shape);
        /* The roots follow the generator's rachis, bent and twisted. */
        sp.shape.bend_out_of_plane = plm_radians(40.0);
        sp.shape.bend_in_plane = plm_radians(-15.0);
        sp.shape.twist = plm_radians(30.0);
        sp.shape.plumulaceous = 0.4;
        sp.shape.afterfeather = 1;
        check_roots(&sp.shape);
        plm_species_free(&sp);
    }
}

/* The same seed gives the same fibers; another seed other fibers; no
 * density, or neither a downy base nor an afterfeather, none. Curl 0 leaves
 * barbs straight; the default curl bends them. */
static void seeded_and_switchable(void **state)
{
    (void)state;
    plm_species sp = load_preset("cardinal_red");
    plm_outline o;
    plm_curves a, b;
    fluff_of(&sp.shape, &o, &a);
    fluff_of(&sp.shape, &o, &b);
    assert_int_equal(a.point_count, b.point_count);
    assert_memory_equal(a.points, b.points, 16 * (size_t)a.point_count);
    plm_curves_free(&b);
    sp.shape.seed = 2;
    fluff_of(&sp.shape, &o, &b);
    assert_true(b.point_count != a.point_count ||
                memcmp(a.points, b.points, 16 * (size_t)a.point_count) != 0);
    plm_curves_free(&b);
    /* Chord over length: 1 for straight barbs, well below for curly ones. */
    double chord = 0.0, straight = 0.0;
    int barbs = 0;
    sp.shape.fluff_curl = 0.0;
    fluff_of(&sp.shape, &o, &b);
    for (int k = 0; k < a.curve_count; ++k)
        if (a.tag[k] == PLM_FLUFF_DOWN) {
            chord += v3_length(v3_sub(point(&a, a.first[k + 1] - 1), point(&a, a.first[k]))) / curve_length(&a, k);
            barbs++;
        }
    for (int k = 0; k < b.curve_count; ++k)
        if (b.tag[k] == PLM_FLUFF_DOWN)
            straight += v3_length(v3_sub(point(&b, b.first[k + 1] - 1), point(&b, b.first[k]))) / curve_length(&b, k);
    printf("chord/length: default curl %.3f, curl 0 %.6f (%d barbs)\n", chord / barbs, straight / barbs, barbs);
    assert_double_near(straight / barbs, 1.0, 1e-5);
    assert_true(chord / barbs < 0.9);
    plm_curves_free(&a);
    plm_curves_free(&b);
    sp.shape.fluff_density = 0.0;
    fluff_of(&sp.shape, &o, &a);
    assert_int_equal(a.curve_count, 0);
    sp.shape.fluff_density = 30.0;
    sp.shape.plumulaceous = 0.0;
    sp.shape.afterfeather = 0;
    fluff_of(&sp.shape, &o, &a);
    assert_int_equal(a.curve_count, 0);
    plm_species_free(&sp);
}

static void expect_error(const char *text, const char *field, const char *range)
{
    cJSON *root = cJSON_Parse(text);
    assert_non_null(root);
    plm_species sp;
    plm_error err = {{0}};
    assert_int_equal(plm_species_parse(root, "test.json", &sp, &err), PLM_ERR_INVALID);
    cJSON_Delete(root);
    if (!strstr(err.message, field) || !strstr(err.message, range))
        fprintf(stderr, "message \"%s\" does not name %s and %s\n", err.message, field, range);
    assert_non_null(strstr(err.message, "test.json"));
    assert_non_null(strstr(err.message, field));
    assert_non_null(strstr(err.message, range));
}

static void bad_fluff_is_refused(void **state)
{
    (void)state;
    expect_error("{\"shape\": {\"fluff\": {\"density\": -3}}}", "shape.fluff.density", "200");
    expect_error("{\"shape\": {\"fluff\": {\"density\": 500}}}", "shape.fluff.density", "200");
    expect_error("{\"shape\": {\"fluff\": {\"length\": 0}}}", "shape.fluff.length", "0.1");
    expect_error("{\"shape\": {\"fluff\": {\"curl\": -10}}}", "shape.fluff.curl", "720");
    expect_error("{\"shape\": {\"fluff\": {\"thickness\": -0.01}}}", "shape.fluff.thickness", "0.5");
    expect_error("{\"shape\": {\"fluff\": {\"barbules\": 100}}}", "shape.fluff.barbules", "40");
    expect_error("{\"shape\": {\"fluff\": {\"afterfeather_size\": 1.5}}}", "shape.fluff.afterfeather_size", "0.9");
    expect_error("{\"shape\": {\"fluff\": {\"afterfeather\": 2}}}", "shape.fluff.afterfeather", "true");
    expect_error("{\"shape\": {\"fluff\": {\"fuzz\": 1}}}", "fuzz", "shape.fluff");
    /* A species built in code is checked against the same ranges. */
    plm_species sp;
    plm_species_default(&sp);
    sp.shape.fluff_density = -1.0;
    plm_error err = {{0}};
    assert_int_equal(plm_species_validate(&sp, "code.json", &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "density"));
}

/* Types give their defaults: body feathers an afterfeather, flight feathers none. */
static void type_defaults(void **state)
{
    (void)state;
    plm_species sp;
    plm_species_default_of_type(&sp, PLM_TYPE_CONTOUR);
    assert_int_equal(sp.shape.afterfeather, 1);
    assert_true(sp.shape.fluff_density > 0.0);
    plm_species_default_of_type(&sp, PLM_TYPE_PRIMARY);
    assert_int_equal(sp.shape.afterfeather, 0);
    plm_species_default_of_type(&sp, PLM_TYPE_COVERT);
    assert_int_equal(sp.shape.afterfeather, 0);
    for (int t = 0; t < PLM_TYPE_COUNT; ++t) {
        plm_species_default_of_type(&sp, (plm_feather_type)t);
        assert_int_equal(plm_species_validate(&sp, "type", NULL), PLM_OK);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(counts_lengths_and_memory),
        cmocka_unit_test(every_curve_starts_on_its_shaft),
        cmocka_unit_test(seeded_and_switchable),
        cmocka_unit_test(bad_fluff_is_refused),
        cmocka_unit_test(type_defaults),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
