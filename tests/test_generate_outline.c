/* Outlines that read as feathers (generate/outline.h, generate/feather_type.c):
 * vane asymmetry and tips by feather type, the ragged edge of barb ends, the
 * frayed tip, splits drawn per feather, and the errors of their fields. The
 * figures asked for are measured on the outline itself, every preset. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"
#include "test_files.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "generate/outline.h"

enum { PRESETS_MAX = 64 };

/* Every preset in presets/species, loaded (returns how many). */
static int load_all(plm_species *out, char (*names)[64])
{
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/presets/species", PLUMAGE_SOURCE_DIR);
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d)) && n < PRESETS_MAX;) {
        size_t len = strlen(e->d_name);
        if (len < 6 || strcmp(e->d_name + len - 5, ".json"))
            continue;
        snprintf(names[n], 64, "%.*s", (int)(len - 5), e->d_name);
        out[n] = load_preset(names[n]);
        ++n;
    }
    closedir(d);
    assert_true(n >= 12);
    return n;
}

static plm_species parse(const char *text)
{
    cJSON *root = cJSON_Parse(text);
    assert_non_null(root);
    plm_species sp;
    plm_error err = {{0}};
    plm_result rc = plm_species_parse(root, "t.json", &sp, &err);
    if (rc != PLM_OK)
        fprintf(stderr, "%s\n", err.message);
    assert_int_equal(rc, PLM_OK);
    cJSON_Delete(root);
    return sp;
}

static void expect_error(const char *text, const char *field)
{
    cJSON *root = cJSON_Parse(text);
    assert_non_null(root);
    plm_species sp;
    plm_error err = {{0}};
    assert_int_equal(plm_species_parse(root, "t.json", &sp, &err), PLM_ERR_INVALID);
    cJSON_Delete(root);
    if (!strstr(err.message, field) || !strstr(err.message, "t.json"))
        fail_msg("message \"%s\" does not name t.json and %s", err.message, field);
}

/* Leading (left) to trailing (right) vane width at 25% of the length from
 * the tip, the larger over the smaller for feathers that are not flight feathers. */
static double asymmetry(const plm_species *sp)
{
    plm_outline o;
    assert_int_equal(plm_outline_init(&o, &sp->shape, sp->name, NULL), PLM_OK);
    double t = (0.75 * sp->shape.length - o.vane_base) / o.vane_length;
    double l = plm_outline_width(&o, 0, t), r = plm_outline_width(&o, 1, t);
    return fmax(l, r) / fmin(l, r);
}

/* Flight feathers are asymmetric as their type says (an outer primary at
 * least 3:1, a secondary 1.5-2:1 after Speakman & Thomson's and Feo et al.'s
 * figures), the narrow vane leading (left); contour feathers and coverts are
 * nearly symmetric. Every preset, and every type's own defaults. */
static void vane_asymmetry_follows_the_type(void **state)
{
    (void)state;
    static plm_species sp[PRESETS_MAX + PLM_TYPE_COUNT];
    static char names[PRESETS_MAX + PLM_TYPE_COUNT][64];
    int n = load_all(sp, names);
    for (int k = 0; k < PLM_TYPE_COUNT; ++k, ++n) {
        plm_species_default_of_type(&sp[n], (plm_feather_type)k);
        snprintf(names[n], 64, "type %s", plm_feather_type_names[k]);
    }
    static const double lo[PLM_TYPE_COUNT] = {1, 1, 3.0, 1.5, 1.05, 1, 1};
    static const double hi[PLM_TYPE_COUNT] = {1.25, 1.25, 6.0, 2.1, 1.6, 1.35, 1.25};
    for (int i = 0; i < n; ++i) {
        double a = asymmetry(&sp[i]);
        plm_feather_type type = sp[i].type;
        printf("%-22s %-9s %.2f:1\n", names[i], plm_feather_type_names[type], a);
        if (!(a >= lo[type] && a <= hi[type]))
            fail_msg("%s: vane asymmetry %.2f:1 outside [%g, %g] for a %s", names[i], a, lo[type], hi[type],
                     plm_feather_type_names[type]);
        if (type == PLM_TYPE_PRIMARY || type == PLM_TYPE_SECONDARY)
            assert_true(sp[i].shape.width[0].width[1] < sp[i].shape.width[1].width[1]); /* leading vane narrow */
    }
}

/* Tips close as their shape's formula says, half way into the tip:
 * rounded sqrt(1 - tau^2), truncate (1 - tau^3)^(1/3), square (1 - tau^8)^(1/8),
 * pointed 1 - tau; an emargination narrows the vane by its depth beyond it. */
static void tips_and_emarginations_have_their_shapes(void **state)
{
    (void)state;
    plm_species sp = parse("{\"shape\": {\"vane\": {\"left\": {\"width\": [[0, 8], [1, 8]]}, "
                           "\"right\": {\"width\": [[0, 8], [1, 8]], \"emargination\": {\"position\": 0.4, "
                           "\"depth\": 0.3, \"length\": 0.1}}, \"tip\": {\"length\": 0.2}}}}");
    static const plm_tip_shape shapes[4] = {PLM_TIP_ROUNDED, PLM_TIP_TRUNCATE, PLM_TIP_SQUARE, PLM_TIP_POINTED};
    const double tau = 0.5;
    const double expect[4] = {sqrt(1 - tau * tau), cbrt(1 - tau * tau * tau), pow(1 - pow(tau, 8), 0.125), 1 - tau};
    for (int k = 0; k < 4; ++k) {
        sp.shape.tip_shape = shapes[k];
        plm_outline o;
        assert_int_equal(plm_outline_init(&o, &sp.shape, "t", NULL), PLM_OK);
        assert_double_near(plm_outline_width(&o, 0, 1.0 - 0.2 * (1.0 - tau)), 8.0 * expect[k], 1e-9);
        assert_double_near(plm_outline_width(&o, 1, 0.3), 8.0, 1e-9);
        assert_double_near(plm_outline_width(&o, 1, 0.4), 8.0 * (1.0 - 0.5 * 0.3), 1e-9);
        assert_double_near(plm_outline_width(&o, 1, 0.5), 8.0 * 0.7, 1e-9);
    }
    plm_species_free(&sp);
}

/* A type gives its defaults, scaled to the species' length where the file
 * gives no sizes; fields the file gives win. */
static void types_give_defaults_scaled_to_the_length(void **state)
{
    (void)state;
    plm_species primary = parse("{\"type\": \"primary\"}"), half = parse("{\"type\": \"primary\", \"shape\": "
                                                                         "{\"length\": 90}}");
    assert_int_equal(primary.type, PLM_TYPE_PRIMARY);
    assert_true(primary.shape.emargination[0].depth > 0.0);
    assert_true(primary.shape.bend_in_plane > 0.0); /* backward, toward the trailing vane */
    assert_double_near(half.shape.width[1].width[1], 0.5 * primary.shape.width[1].width[1], 1e-12);
    assert_double_near(half.shape.calamus_length, 0.5 * primary.shape.calamus_length, 1e-12);
    assert_double_near(half.shape.rachis_base_width, 0.5 * primary.shape.rachis_base_width, 1e-12);
    plm_species own = parse("{\"type\": \"hackle\", \"shape\": {\"length\": 45, \"calamus_length\": 7, "
                            "\"vane\": {\"tip\": {\"shape\": \"rounded\"}}}}");
    assert_double_near(own.shape.calamus_length, 7.0, 0.0);
    assert_int_equal(own.shape.tip_shape, PLM_TIP_ROUNDED);
    plm_species contour = parse("{}");
    assert_int_equal(contour.type, PLM_TYPE_CONTOUR);
    plm_species_free(&primary);
    plm_species_free(&half);
    plm_species_free(&own);
    plm_species_free(&contour);
}

/* A preset's outline with no splits (the edge away from splits); returns its shape. */
static plm_shape outline_without_splits(const plm_species *sp, plm_outline *o)
{
    plm_shape sh = sp->shape;
    sh.split_frequency = 0.0;
    sh.split_count = 0;
    assert_int_equal(plm_outline_init(o, &sh, sp->name, NULL), PLM_OK);
    return sh;
}

/* Outermost vane point of a row on one side at or inside a (mm); -1 if none
 * within `depth` mm of it. */
static double row_edge(const plm_outline *o, const plm_outline_row *row, int side, double a, double depth, double step)
{
    for (double x = a; x > a - depth && x > row->r; x -= step)
        if (plm_outline_sample_row(o, row, side ? x : -x).region == PLM_FLAT_VANE)
            return x;
    return -1.0;
}

/* Share of [from, to] (mm from the centre line) of a row that is vane. */
static double row_cover(const plm_outline *o, const plm_outline_row *row, int side, double from, double to, int n)
{
    int vane = 0;
    for (int i = 0; i < n; ++i) {
        double x = from + (to - from) * (i + 0.5) / n;
        vane += plm_outline_sample_row(o, row, side ? x : -x).region == PLM_FLAT_VANE;
    }
    return (double)vane / n;
}

/* The edge is made of barb ends: away from splits, the downy base and the
 * tip, the vane's edge deviates from its own smoothed course (a moving
 * average over twenty barb spacings) by at least a third of a barb spacing,
 * RMS, measured across the edge; every preset, both vanes. A smooth outline
 * would give under a tenth. */
static void edges_are_ragged_by_a_third_of_a_barb_spacing(void **state)
{
    (void)state;
    static plm_species sp[PRESETS_MAX];
    static char names[PRESETS_MAX][64];
    int n = load_all(sp, names);
    enum { ROWS_MAX = 8192 };
    static double inset[ROWS_MAX], slope[ROWS_MAX];
    int failures = 0;
    for (int i = 0; i < n; ++i) {
        plm_outline o;
        const plm_shape sh = outline_without_splits(&sp[i], &o);
        double s = o.spacing, dy = 0.125 * s;
        double t0 = sh.plumulaceous, t1 = 1.0 - (o.fray_length + 4.0 * s) / o.vane_length;
        for (int side = 0; side < 2; ++side) {
            int rows = 0, missing = 0;
            for (double y = o.vane_base + t0 * o.vane_length; y < o.vane_base + t1 * o.vane_length && rows < ROWS_MAX;
                 y += dy) {
                plm_outline_row row;
                plm_outline_row_at(&o, y, &row);
                double w = row.width[side];
                double pennaceous = o.vane_base + sh.plumulaceous * o.vane_length + s;
                if (plm_outline_sample_row(&o, &row, side ? w : -w).barb_origin < pennaceous)
                    continue; /* the edge's barbs here come from the downy base */
                double e = row_edge(&o, &row, side, w, (sh.barb_end_jitter + 3.0) * s, s / 64.0);
                if (e < 0.0) {
                    ++missing;
                    continue;
                }
                double t = row.t, h = 1e-4;
                slope[rows] = (plm_outline_width(&o, side, t + h) - plm_outline_width(&o, side, t - h)) /
                              (2.0 * h * o.vane_length);
                if (fabs(slope[rows]) > 2.0)
                    continue; /* the closing tip, nearly across the rows */
                inset[rows++] = w - e;
            }
            if (!(rows > 64 && missing < rows / 20)) {
                printf("%s: %d rows with an edge, %d without\n", names[i], rows, missing);
                ++failures;
                continue;
            }
            int half = (int)lrint(10.0 * s / dy);
            double sum = 0.0;
            int count = 0;
            for (int k = half; k + half < rows; ++k) {
                double mean = 0.0;
                for (int m = -half; m <= half; ++m)
                    mean += inset[k + m];
                mean /= 2 * half + 1;
                double across = (inset[k] - mean) / sqrt(1.0 + slope[k] * slope[k]);
                sum += across * across;
                ++count;
            }
            double rms = sqrt(sum / count) / s;
            printf("%-22s %s vane: edge %.2f barb spacings RMS from its smoothed course%s\n", names[i],
                   side ? "right" : "left ", rms, rms >= 1.0 / 3.0 ? "" : ": under 1/3");
            failures += !(rms >= 1.0 / 3.0);
        }
        plm_species_free(&sp[i]);
    }
    assert_int_equal(failures, 0);
}

/* The tip frays: in each of the rows over the last three barb spacings below
 * the tip the barbs part, leaving at most 90% of the row between the rachis
 * and the vane's edge covered, while below the fray the vane inside its
 * ragged edge is closed (at least 99%). Every preset, both vanes. */
static void tips_fray_over_three_barb_spacings(void **state)
{
    (void)state;
    static plm_species sp[PRESETS_MAX];
    static char names[PRESETS_MAX][64];
    int n = load_all(sp, names);
    for (int i = 0; i < n; ++i) {
        plm_outline o;
        const plm_shape sh = outline_without_splits(&sp[i], &o);
        double s = o.spacing;
        for (int side = 0; side < 2; ++side) {
            double worst_fray = 0.0;
            for (int k = 1; k <= 12; ++k) {
                plm_outline_row row;
                plm_outline_row_at(&o, sh.length - 3.0 * s * k / 12.0, &row);
                double r = fmax(row.r, row.notch[side]), w = row.width[side];
                if (w <= r + 0.02 * s)
                    continue; /* a pointed tip's last rows: nothing but rachis */
                worst_fray = fmax(worst_fray, row_cover(&o, &row, side, r, w, 2000));
            }
            plm_outline_row row;
            plm_outline_row_at(&o, sh.length - o.fray_length - 3.0 * s, &row);
            double from = fmax(row.r, row.notch[side]), room = row.width[side] - from;
            double inner = row.width[side] - fmin((sh.barb_end_jitter + PLM_BARB_TAPER) * s, room * 2.0 / 3.0);
            double closed = row_cover(&o, &row, side, from, inner - 0.02 * room, 2000);
            printf("%-22s %s vane: tip rows at most %.0f%% covered, %.0f%% below the fray\n", names[i],
                   side ? "right" : "left ", 100.0 * worst_fray, 100.0 * closed);
            if (!(worst_fray <= 0.9) || !(closed >= 0.99))
                fail_msg("%s: tip rows up to %.2f covered, below the fray %.3f", names[i], worst_fray, closed);
        }
        plm_species_free(&sp[i]);
    }
}

/* Ragged by default: over 100 feathers (seeds) of every contour and covert
 * preset, at least half have a split on each vane. */
static void contour_feathers_split_by_default(void **state)
{
    (void)state;
    static plm_species sp[PRESETS_MAX];
    static char names[PRESETS_MAX][64];
    int n = load_all(sp, names), tested = 0;
    for (int i = 0; i < n; ++i) {
        if (sp[i].type != PLM_TYPE_CONTOUR && sp[i].type != PLM_TYPE_COVERT)
            continue;
        int both = 0, total = 0;
        for (uint64_t seed = 1; seed <= 100; ++seed) {
            plm_shape sh = sp[i].shape;
            sh.seed = seed;
            plm_outline o;
            assert_int_equal(plm_outline_init(&o, &sh, names[i], NULL), PLM_OK);
            int per_side[2] = {0, 0};
            for (int k = 0; k < o.shape.split_count; ++k) {
                const plm_split *s = &o.shape.splits[k];
                assert_true(s->position > sh.plumulaceous && s->position < 1.0);
                assert_true(s->depth > 0.0 && s->depth <= 1.0);
                per_side[s->side]++;
            }
            both += per_side[0] >= 1 && per_side[1] >= 1;
            total += o.shape.split_count;
        }
        printf("%-22s %d of 100 feathers split on both vanes, %.2f splits per vane\n", names[i], both, total / 200.0);
        if (both < 50)
            fail_msg("%s: only %d of 100 feathers have a split on each vane", names[i], both);
        ++tested;
    }
    assert_true(tested >= 8);
    /* The same seed gives the same splits; another seed others. */
    plm_outline a, b;
    plm_shape sh = sp[0].shape;
    sh.split_frequency = 4.0;
    assert_int_equal(plm_outline_init(&a, &sh, "t", NULL), PLM_OK);
    assert_int_equal(plm_outline_init(&b, &sh, "t", NULL), PLM_OK);
    assert_memory_equal(a.shape.splits, b.shape.splits, sizeof a.shape.splits);
    sh.seed += 1;
    assert_int_equal(plm_outline_init(&b, &sh, "t", NULL), PLM_OK);
    assert_true(a.shape.split_count != b.shape.split_count || a.shape.splits[0].position != b.shape.splits[0].position);
    for (int i = 0; i < n; ++i)
        plm_species_free(&sp[i]);
}

static void new_fields_refuse_bad_values(void **state)
{
    (void)state;
    expect_error("{\"shape\": {\"splits\": {\"frequency\": -1}}}", "shape.splits.frequency");
    expect_error("{\"shape\": {\"splits\": {\"frequency\": 17}}}", "shape.splits.frequency");
    expect_error("{\"shape\": {\"splits\": {\"count\": 2}}}", "shape.splits.count");
    expect_error("{\"shape\": {\"splits\": {\"seed\": 2}}}", "shape.splits.seed");
    expect_error("{\"shape\": {\"splits\": {\"frequency\": 1, \"list\": [{\"position\": 0.5}]}}}",
                 "shape.splits.frequency");
    expect_error("{\"shape\": {\"splits\": {\"positions\": [0.9, 0.5]}}}", "shape.splits.positions");
    expect_error("{\"shape\": {\"plumulaceous\": 0.6, \"splits\": {\"positions\": [0.2, 0.5]}}}",
                 "shape.splits.positions");
    expect_error("{\"type\": \"leaf\"}", "type");
    expect_error("{\"shape\": {\"barbs\": {\"end_jitter\": -1}}}", "shape.barbs.end_jitter");
    expect_error("{\"shape\": {\"barbs\": {\"fray\": 51}}}", "shape.barbs.fray");
    expect_error("{\"shape\": {\"seed\": -3}}", "shape.seed");
    expect_error("{\"shape\": {\"vane\": {\"right\": {\"emargination\": {\"depth\": 1.5}}}}}",
                 "shape.vane.right.emargination.depth");
    expect_error("{\"shape\": {\"vane\": {\"left\": {\"emargination\": {\"length\": 0}}}}}",
                 "shape.vane.left.emargination.length");
    expect_error("{\"shape\": {\"vane\": {\"tip\": {\"shape\": \"oval\"}}}}", "shape.vane.tip.shape");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(vane_asymmetry_follows_the_type),
        cmocka_unit_test(tips_and_emarginations_have_their_shapes),
        cmocka_unit_test(types_give_defaults_scaled_to_the_length),
        cmocka_unit_test(edges_are_ragged_by_a_third_of_a_barb_spacing),
        cmocka_unit_test(tips_fray_over_three_barb_spacings),
        cmocka_unit_test(contour_feathers_split_by_default),
        cmocka_unit_test(new_fields_refuse_bad_values),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
