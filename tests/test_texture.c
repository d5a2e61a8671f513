/* Feather textures (texture/): barb angles, integral curves, the region mask
 * against the outline, splits, the plumulaceous base and the rachis, file
 * round trips and reproducibility. Expected values come from the species
 * parameters, not from the code under test. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"
#include "test_files.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/feather_texture_contract.h"
#include "texture/feather.h"
#include "texture/preview.h"
#include "texture/texture.h"

static plm_feather textures_of(const plm_species *sp, int size)
{
    plm_feather f;
    plm_feather_options opt = {.texture_width = size, .texture_height = size, .no_meshes = 1};
    plm_error err = {{0}};
    plm_result rc = plm_feather_generate(sp, &opt, &f, &err);
    if (rc != PLM_OK)
        fprintf(stderr, "%s\n", err.message);
    assert_int_equal(rc, PLM_OK);
    return f;
}

static const float *texel_at(const plm_image *t, int i, int j)
{
    return t->pixels + 3 * ((size_t)j * t->width + i);
}

/* Flat coordinates of texel centres and back. */
static double texel_x(const plm_feather *f, int i)
{
    return plm_outline_flat(&f->outline, (i + 0.5) / f->texture.width, 0.5).x;
}
static double row_y(const plm_feather *f, int j)
{
    return plm_outline_flat(&f->outline, 0.5, 1.0 - (j + 0.5) / f->texture.height).y;
}
static int row_of(const plm_feather *f, double y)
{
    vec2 uv = plm_outline_uv(&f->outline, 0.0, y);
    return (int)floor((1.0 - uv.y) * f->texture.height);
}
static int column_of(const plm_feather *f, double x)
{
    return (int)floor(plm_outline_uv(&f->outline, x, 0.0).x * f->texture.width);
}
static plm_flat_region region_at(const plm_feather *f, double x, double y)
{
    return plm_texture_region_of(texel_at(&f->texture, column_of(f, x), row_of(f, y))[2]);
}

/* The barb's angle to the rachis (degrees) stored at a texel, back in flat mm. */
static double barb_angle_at(const plm_feather *f, int i, int j)
{
    const float *p = texel_at(&f->texture, i, j);
    double dx = (2.0 * p[0] - 1.0) * 2.0 * f->outline.half_extent, dy = (2.0 * p[1] - 1.0) * f->outline.vane_length;
    return plm_degrees(atan2(fabs(dx), dy));
}

/* Next to the rachis the stored angle is the parameterised one, per side,
 * interpolated from base to tip; directions point away from the rachis. */
static void barb_angle_at_the_rachis_is_the_parameter(void **state)
{
    (void)state;
    plm_species sp = load_preset("remex_pigeon");
    plm_feather f = textures_of(&sp, 1024);
    const plm_shape *sh = &sp.shape;
    double lv = sh->length - sh->calamus_length;
    for (int k = 1; k <= 8; ++k) {
        double t = 0.1 * k;
        int j = row_of(&f, sh->calamus_length + t * lv);
        double y = row_y(&f, j), tr = (y - sh->calamus_length) / lv;
        /* Rachis half-width from the parameters: base + (tip - base) s^taper. */
        double r = 0.5 * (sh->rachis_base_width +
                          (sh->rachis_tip_width - sh->rachis_base_width) * pow(y / sh->length, sh->rachis_taper));
        for (int side = 0; side < 2; ++side) {
            double sign = side ? 1.0 : -1.0, texel_w = 2.0 * f.outline.half_extent / f.texture.width;
            int i = column_of(&f, sign * (r + 0.5 * texel_w));
            if (fabs(texel_x(&f, i)) <= r)
                i += side ? 1 : -1;
            assert_int_equal(plm_texture_region_of(texel_at(&f.texture, i, j)[2]), PLM_FLAT_VANE);
            double expect = plm_degrees(sh->barb_angle_base[side] +
                                        (sh->barb_angle_tip[side] - sh->barb_angle_base[side]) * tr);
            assert_double_near(barb_angle_at(&f, i, j), expect, 0.5);
            const float *p = texel_at(&f.texture, i, j);
            assert_true((2.0 * p[0] - 1.0) * sign > 0.0); /* away from the rachis */
        }
    }
    plm_feather_free(&f);
    plm_species_free(&sp);
}

/* With constant barb angle and rachis width the barb turns linearly: half
 * way from the rachis to the widest point it has turned curvature / 2. */
static void barbs_curve_toward_the_tip_by_the_curvature(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    plm_shape *sh = &sp.shape;
    sh->barb_angle_base[0] = sh->barb_angle_tip[0] = sh->barb_angle_base[1] = sh->barb_angle_tip[1] =
        plm_radians(50.0);
    sh->barb_curvature = plm_radians(20.0);
    sh->rachis_tip_width = sh->rachis_base_width;
    sh->split_count = 0;
    plm_feather f = textures_of(&sp, 1024);
    double r = 0.5 * sh->rachis_base_width;
    for (int side = 0; side < 2; ++side) {
        double w = f.outline.widest[side];
        for (double q = 0.25; q < 0.8; q += 0.25) {
            double a = r + q * (w - r), y = sh->calamus_length + 0.7 * (sh->length - sh->calamus_length);
            int i = column_of(&f, side ? a : -a), j = row_of(&f, y);
            double a_texel = fabs(texel_x(&f, i));
            double expect = 50.0 - 20.0 * (a_texel - r) / (w - r);
            assert_double_near(barb_angle_at(&f, i, j), expect, 0.05);
        }
    }
    plm_feather_free(&f);
    plm_species_free(&sp);
}

/* Barbs traced through the stored directions stay on one barb: the point
 * where each meets the rachis centre line (the stream function psi) drifts
 * by less than one texel along the whole barb. */
static void stored_directions_are_tangents_of_the_barbs(void **state)
{
    (void)state;
    plm_species sp = load_preset("remex_pigeon");
    sp.shape.barb_end_jitter = sp.shape.barb_fray = sp.shape.split_frequency = 0.0; /* barbs to the outline */
    plm_feather f = textures_of(&sp, 1024);
    const plm_outline *o = &f.outline;
    enum { MAX = 20000 };
    vec2 *pts = malloc(sizeof *pts * MAX);
    double texel_h = o->vane_length / f.texture.height, step = 0.25 / f.texture.width;
    for (int side = 0; side < 2; ++side)
        for (int k = 2; k <= 8; k += 2) {
            double y = o->vane_base + 0.1 * k * o->vane_length;
            int n = plm_preview_trace_barb(&f, side, y, step, pts, MAX);
            vec2 p0 = plm_outline_flat(o, pts[0].x, pts[0].y), pn = plm_outline_flat(o, pts[n - 1].x, pts[n - 1].y);
            /* The traced barb crosses most of the vane. */
            assert_true(fabs(pn.x) > 0.8 * plm_outline_width(o, side, (pn.y - o->vane_base) / o->vane_length));
            double psi0 = plm_outline_sample(o, p0.x, p0.y).barb_origin, drift = 0.0;
            for (int i = 0; i < n; ++i) {
                vec2 p = plm_outline_flat(o, pts[i].x, pts[i].y);
                plm_flat_sample fs = plm_outline_sample(o, p.x, p.y);
                if (fs.region != PLM_FLAT_BACKGROUND) /* the last step may end just past the edge */
                    drift = fmax(drift, fabs(fs.barb_origin - psi0));
            }
            assert_true(drift < texel_h);
        }
    free(pts);
    plm_feather_free(&f);
    plm_species_free(&sp);
}

/* Outermost vane texel of a row on one side, as a width in mm. */
static double mask_width(const plm_feather *f, int j, int side)
{
    double texel_w = 2.0 * f->outline.half_extent / f->texture.width, width = 0.0;
    for (int i = 0; i < f->texture.width; ++i) {
        double x = texel_x(f, i);
        if ((x > 0.0) == side && plm_texture_region_of(texel_at(&f->texture, i, j)[2]) == PLM_FLAT_VANE)
            width = fmax(width, fabs(x) + 0.5 * texel_w);
    }
    return width;
}

/* The mask's widths at the width profile's control points are the outline's
 * (the parameters, narrowed by any emargination): no wider, and where every
 * barb reaches the outline within the barbs' tapered tips of it; with ragged
 * barb ends within the end jitter and the taper. */
static void mask_widths_are_the_parameters(void **state)
{
    (void)state;
    static const char *const names[3] = {"remex_pigeon", "rectrix_notched", "covert_parrot"};
    for (int s = 0; s < 3; ++s)
        for (int ragged = 0; ragged < 2; ++ragged) {
            plm_species sp = load_preset(names[s]);
            sp.shape.split_frequency = 0.0;
            if (!ragged)
                sp.shape.barb_end_jitter = sp.shape.barb_fray = 0.0;
            plm_feather f = textures_of(&sp, 1024);
            const plm_shape *sh = &sp.shape;
            double lv = sh->length - sh->calamus_length, texel_w = 2.0 * f.outline.half_extent / f.texture.width;
            double taper = PLM_BARB_TAPER * f.outline.spacing + texel_w;
            double ends = sh->barb_end_jitter * f.outline.spacing + taper;
            for (int side = 0; side < 2; ++side) {
                const plm_width_profile *w = &sh->width[side];
                for (int k = 0; k < w->count; ++k) {
                    if (w->t[k] <= sh->plumulaceous + 0.1 || w->t[k] >= 1.0 - sh->tip_length)
                        continue; /* the fluffy base and the closing tip are not the profile */
                    int j = row_of(&f, sh->calamus_length + w->t[k] * lv);
                    double width = plm_outline_width(&f.outline, side, (row_y(&f, j) - sh->calamus_length) / lv);
                    double mask = mask_width(&f, j, side);
                    /* The barbs' fine tapered tips may fall between texel centres. */
                    assert_true(mask <= width + texel_w && mask >= width - (ragged ? ends : taper));
                }
            }
            plm_feather_free(&f);
            plm_species_free(&sp);
        }
}

/* A notched tip: near the tip the vane is gone at the rachis but present
 * half way out; rounded and pointed tips close at the rachis. */
static void notched_tip_is_cut_at_the_rachis(void **state)
{
    (void)state;
    plm_species sp = load_preset("rectrix_notched");
    plm_feather f = textures_of(&sp, 512);
    const plm_outline *o = &f.outline;
    double y = o->vane_base + (1.0 - 0.3 * sp.shape.tip_length) * o->vane_length;
    for (int side = 0; side < 2; ++side) {
        double s = side ? 1.0 : -1.0, w = sp.shape.width[side].width[sp.shape.width[side].count - 1];
        assert_int_equal(region_at(&f, s * 0.05 * w, y), PLM_FLAT_BACKGROUND);
        assert_int_equal(region_at(&f, s * 0.5 * w, y), PLM_FLAT_VANE);
    }
    plm_feather_free(&f);
    plm_species_free(&sp);
}

/* y on the barb leaving the centre line at psi, at distance a: bisection on
 * the stream function (psi grows with y along a column). */
static double y_on_barb(const plm_outline *o, double a, double psi)
{
    double lo = 0.0, hi = o->shape.length + 2.0 * o->half_extent;
    for (int it = 0; it < 100; ++it) {
        double mid = 0.5 * (lo + hi);
        if (plm_outline_sample(o, a, mid).barb_origin < psi)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* A split is a gap between barbs: background along the split's barb beyond
 * 1 - depth of the width, vane beside it and inside the depth; barbs leaving
 * the rachis in the plumulaceous base are not vane. */
static void splits_and_the_fluffy_base(void **state)
{
    (void)state;
    cJSON *root = cJSON_Parse("{\"shape\": {\"length\": 100, \"calamus_length\": 10, \"plumulaceous\": 0.2,"
                              "\"splits\": {\"gap\": 1.5, \"list\": [{\"position\": 0.55, \"depth\": 0.5, "
                              "\"side\": \"right\"}]}}}");
    plm_species sp;
    assert_int_equal(plm_species_parse(root, "t.json", &sp, NULL), PLM_OK);
    cJSON_Delete(root);
    plm_feather f = textures_of(&sp, 1024);
    const plm_outline *o = &f.outline;
    double psi = o->vane_base + 0.55 * o->vane_length;
    double w = plm_outline_width(o, 1, 0.6);
    /* At 80% of the width the gap is 1.5 * (0.8 - 0.5) / 0.5 = 0.9 mm wide in psi. */
    double a = 0.8 * w;
    assert_int_equal(region_at(&f, a, y_on_barb(o, a, psi)), PLM_FLAT_BACKGROUND);
    assert_int_equal(region_at(&f, a, y_on_barb(o, a, psi - 0.8)), PLM_FLAT_VANE);
    assert_int_equal(region_at(&f, a, y_on_barb(o, a, psi + 0.8)), PLM_FLAT_VANE);
    /* Inside the depth, and on the other side, the split's barb is vane. */
    assert_int_equal(region_at(&f, 0.3 * w, y_on_barb(o, 0.3 * w, psi)), PLM_FLAT_VANE);
    assert_int_equal(region_at(&f, -a, y_on_barb(o, -a, psi)), PLM_FLAT_VANE);
    /* Fluffy base: barbs from the first 20% of the vane are fibers
     * (generate/fluff.h), not vane: background up to the rachis, vane above. */
    for (int side = 0; side < 2; ++side) {
        double sign = side ? 1.0 : -1.0, x = sign * 0.3 * plm_outline_width(o, side, 0.3);
        int vane = 0, n = 400;
        for (int k = 0; k < n; ++k) {
            double psi_k = o->vane_base + 0.2 * o->vane_length * (k + 0.5) / n;
            vane += region_at(&f, x, y_on_barb(o, x, psi_k)) == PLM_FLAT_VANE;
        }
        assert_true(vane <= 4); /* texel rounding at the base's end */
        assert_int_equal(region_at(&f, x, y_on_barb(o, x, o->vane_base + 0.23 * o->vane_length)), PLM_FLAT_VANE);
        assert_int_equal(region_at(&f, 0.0, o->vane_base + 0.1 * o->vane_length), PLM_FLAT_RACHIS);
    }
    plm_feather_free(&f);
    plm_species_free(&sp);
}

/* The rachis texels of a row span the rachis width from the parameters. */
static void rachis_region_has_the_rachis_width(void **state)
{
    (void)state;
    plm_species sp = load_preset("remex_pigeon");
    plm_feather f = textures_of(&sp, 1024);
    const plm_shape *sh = &sp.shape;
    double texel_w = 2.0 * f.outline.half_extent / f.texture.width;
    for (int j = 0; j < f.texture.height; j += 37) {
        double y = row_y(&f, j);
        double expect = sh->rachis_base_width +
                        (sh->rachis_tip_width - sh->rachis_base_width) * pow(y / sh->length, sh->rachis_taper);
        int count = 0;
        for (int i = 0; i < f.texture.width; ++i)
            count += plm_texture_region_of(texel_at(&f.texture, i, j)[2]) == PLM_FLAT_RACHIS;
        assert_true(fabs(count * texel_w - expect) <= texel_w + 1e-9);
    }
    plm_feather_free(&f);
    plm_species_free(&sp);
}

/* Point-in-triangle in the plane (either winding). */
static int inside(double px, double py, const float *a, const float *b, const float *c)
{
    double d0 = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
    double d1 = (c[0] - b[0]) * (py - b[1]) - (c[1] - b[1]) * (px - b[0]);
    double d2 = (a[0] - c[0]) * (py - c[1]) - (a[1] - c[1]) * (px - c[0]);
    return (d0 >= 0 && d1 >= 0 && d2 >= 0) || (d0 <= 0 && d1 <= 0 && d2 <= 0);
}

/* The smooth vane surface covers every vane texel: laid flat (no bend,
 * twist or curl), each vane texel centre falls inside some triangle. */
static void the_vane_mesh_covers_every_vane_texel(void **state)
{
    (void)state;
    static const char *const names[4] = {"remex_pigeon", "covert_parrot", "rectrix_notched", "hackle_pointed"};
    for (int s = 0; s < 4; ++s) {
        plm_species sp = load_preset(names[s]);
        sp.shape.bend_in_plane = sp.shape.bend_out_of_plane = sp.shape.twist = sp.shape.curl = 0.0;
        plm_feather f;
        plm_feather_options opt = {.texture_width = 256, .texture_height = 256};
        assert_int_equal(plm_feather_generate(&sp, &opt, &f, NULL), PLM_OK);
        int w = f.texture.width, h = f.texture.height;
        unsigned char *covered = calloc((size_t)w * h, 1);
        const plm_mesh *m = &f.vane;
        for (int t = 0; t < m->triangle_count; ++t) {
            const float *v[3];
            double lo[2] = {1e30, 1e30}, hi[2] = {-1e30, -1e30};
            for (int k = 0; k < 3; ++k) {
                v[k] = m->positions + 3 * m->indices[3 * t + k];
                for (int c = 0; c < 2; ++c)
                    lo[c] = fmin(lo[c], v[k][c]), hi[c] = fmax(hi[c], v[k][c]);
            }
            for (int i = (int)fmax(0, column_of(&f, lo[0])); i <= column_of(&f, hi[0]) && i < w; ++i)
                for (int j = (int)fmax(0, row_of(&f, hi[1])); j <= row_of(&f, lo[1]) && j < h; ++j)
                    if (inside(texel_x(&f, i), row_y(&f, j), v[0], v[1], v[2]))
                        covered[(size_t)j * w + i] = 1;
        }
        int lost = 0;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i)
                lost += plm_texture_region_of(texel_at(&f.texture, i, j)[2]) == PLM_FLAT_VANE &&
                        !covered[(size_t)j * w + i];
        assert_int_equal(lost, 0);
        free(covered);
        plm_feather_free(&f);
        plm_species_free(&sp);
    }
}


/* The barb coordinate at uv as the contract says to filter it: the four
 * nearest texels unwrapped along rows and columns (never diagonally, where a
 * step can pass half a period), then bilinear. */
static double barb_coordinate_at(const plm_image *b, vec2 uv)
{
    double x = uv.x * b->width - 0.5, y = (1.0 - uv.y) * b->height - 0.5;
    int i0 = (int)floor(x), j0 = (int)floor(y);
    double fx = x - i0, fy = y - j0, c[2][2];
    for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di) {
            int i = (int)plm_clamp(i0 + di, 0, b->width - 1), j = (int)plm_clamp(j0 + dj, 0, b->height - 1);
            float value = b->pixels[(size_t)j * b->width + i];
            c[dj][di] = di ? plm_ftex_barb_unwrap(value, c[dj][0]) : (dj ? plm_ftex_barb_unwrap(value, c[0][0]) : value);
        }
    return (1.0 - fy) * ((1.0 - fx) * c[0][0] + fx * c[0][1]) + fy * ((1.0 - fx) * c[1][0] + fx * c[1][1]);
}

/* Whether the four texels bilinear filtering at uv reads are all vane. */
static int among_vane_texels(const plm_feather *f, vec2 uv)
{
    double x = uv.x * f->texture.width - 0.5, y = (1.0 - uv.y) * f->texture.height - 0.5;
    int i0 = (int)floor(x), j0 = (int)floor(y), all = 1;
    for (int k = 0; k < 4; ++k) {
        int i = (int)plm_clamp(i0 + (k & 1), 0, f->texture.width - 1), j = (int)plm_clamp(j0 + (k >> 1), 0, f->texture.height - 1);
        all = all && plm_texture_region_of(texel_at(&f->texture, i, j)[2]) == PLM_FLAT_VANE;
    }
    return all;
}

/* The largest change of the coordinate between two vane texels next to each
 * other in a row or a column on one side of the feather (past the rachis's
 * end the two vanes meet, and their barbs are unrelated): under half a
 * period, unwrapping recovers it. */
static double barb_coordinate_step_max(const plm_feather *f)
{
    const plm_image *b = &f->barb;
    double worst = 0.0;
    for (int j = 0; j + 1 < b->height; ++j)
        for (int i = 0; i + 1 < b->width; ++i) {
            if (plm_texture_region_of(texel_at(&f->texture, i, j)[2]) != PLM_FLAT_VANE)
                continue;
            float w = b->pixels[(size_t)j * b->width + i];
            for (int k = 0; k < 2; ++k) {
                int ni = i + !k, nj = j + k;
                if (plm_texture_region_of(texel_at(&f->texture, ni, nj)[2]) == PLM_FLAT_VANE &&
                    (texel_x(f, i) > 0.0) == (texel_x(f, ni) > 0.0))
                    worst = fmax(worst, fabs(plm_ftex_barb_unwrap(b->pixels[(size_t)nj * b->width + ni], w) - w));
            }
        }
    return worst;
}

/* The sizes at which the tests below read each preset: the pigeon remex's
 * outer vane near the tip has barbs so flat to the rachis that 1024 columns
 * give more than half a period per texel there (docs/generating.md). */
static const struct {
    const char *name;
    int size;
} barb_presets[3] = {{"remex_pigeon", 2048}, {"covert_parrot", 1024}, {"hackle_pointed", 1024}};

/* Barbs traced through the stored directions keep one barb coordinate. The
 * trace stays within a texel height of its barb
 * (stored_directions_are_tangents_of_the_barbs), which allows a drift of
 * that times the density; where the texture resolves the phase it is far
 * less, and both the drift and the coordinate read at each point against the
 * generator's stream function stay under 1/50 of a period. */
static void barb_coordinate_is_constant_along_traced_barbs(void **state)
{
    (void)state;
    enum { MAX = 40000 };
    vec2 *pts = malloc(sizeof *pts * MAX);
    for (int s = 0; s < 3; ++s) {
        plm_species sp = load_preset(barb_presets[s].name);
        plm_feather f = textures_of(&sp, barb_presets[s].size);
        const plm_outline *o = &f.outline;
        assert_int_equal(f.barb.channels, 1);
        double barbs_per_mm = sp.shape.barb_density / 10.0, texel_h = o->vane_length / f.texture.height;
        double step = 0.25 / f.texture.width, drift = 0.0, misread = 0.0;
        for (int side = 0; side < 2; ++side)
            for (int k = 1; k <= 9; ++k) {
                if (0.1 * k < sp.shape.plumulaceous + 0.05)
                    continue; /* the fluffy base's down strands are too short to trace */
                double y = o->vane_base + (0.1 * k + 0.013 * side) * o->vane_length;
                int n = plm_preview_trace_barb(&f, side, y, step, pts, MAX);
                assert_true(n > 10);
                double start = barb_coordinate_at(&f.barb, pts[0]), previous = start;
                for (int i = 1; i < n; ++i) {
                    if (!among_vane_texels(&f, pts[i]))
                        continue; /* the outline's edge: the contract blends only within a region */
                    double w = barb_coordinate_at(&f.barb, pts[i]);
                    vec2 p = plm_outline_flat(o, pts[i].x, pts[i].y);
                    double exact = (plm_outline_sample(o, p.x, p.y).barb_origin - o->vane_base) * barbs_per_mm;
                    misread = fmax(misread, fabs(plm_ftex_barb_unwrap(plm_ftex_encode_barb(w), exact) - exact));
                    previous = plm_ftex_barb_unwrap(plm_ftex_encode_barb(w), previous);
                    drift = fmax(drift, fabs(previous - start));
                }
            }
        printf("%s at %d: coordinate drift along traced barbs %.4f of a period (a texel: %.4f), read error %.4f\n",
               barb_presets[s].name, barb_presets[s].size, drift, texel_h * barbs_per_mm, misread);
        assert_true(drift < fmin(0.02, texel_h * barbs_per_mm));
        assert_true(misread < 0.02);
        plm_feather_free(&f);
        plm_species_free(&sp);
    }
    free(pts);
}

/* Along the vane just outside the rachis the coordinate wraps once per barb:
 * the count between two heights is the species' density times the distance,
 * less the change of the barbs' rise over the distance a from the centre line
 * (a cot theta near the rachis, theta the barb angle parameter). Every step
 * between neighbouring vane texels stays under half a period, so no wrap is
 * missed: the texture resolves the phase. */
static void barb_coordinate_period_is_the_barb_density(void **state)
{
    (void)state;
    for (int s = 0; s < 3; ++s) {
        const char *name = barb_presets[s].name;
        plm_species sp = load_preset(name);
        plm_feather f = textures_of(&sp, barb_presets[s].size);
        const plm_outline *o = &f.outline;
        double barbs_per_mm = sp.shape.barb_density / 10.0, texel_w = 2.0 * o->half_extent / f.texture.width;
        double step_max = barb_coordinate_step_max(&f);
        printf("%s: largest step between neighbouring texels %.3f of a period\n", name, step_max);
        assert_true(step_max < 0.5);
        double t0 = fmax(0.2, sp.shape.plumulaceous + 0.1); /* above the fluffy base */
        int j0 = row_of(&f, o->vane_base + 0.8 * o->vane_length), j1 = row_of(&f, o->vane_base + t0 * o->vane_length);
        double y0 = row_y(&f, j1), y1 = row_y(&f, j0);
        for (int side = 0; side < 2; ++side) {
            /* One column, a texel and a half off the rachis where it is widest (the rachis tapers). */
            double a = plm_outline_rachis_radius(o, y0) + 1.5 * texel_w;
            int i = column_of(&f, side ? a : -a), wraps = 0;
            a = fabs(texel_x(&f, i));
            double previous = -1.0;
            for (int j = j1; j >= j0; --j) { /* base to tip: the coordinate rises */
                assert_int_equal(plm_texture_region_of(texel_at(&f.texture, i, j)[2]), PLM_FLAT_VANE);
                float w = f.barb.pixels[(size_t)j * f.barb.width + i];
                if (previous >= 0.0) {
                    assert_true(plm_ftex_barb_unwrap(w, previous) > previous);
                    wraps += w < previous;
                }
                previous = w;
            }
            double cot0 = 1.0 / tan(plm_outline_barb_angle(o, side, y0));
            double cot1 = 1.0 / tan(plm_outline_barb_angle(o, side, y1));
            double expected = barbs_per_mm * ((y1 - y0) - a * (cot1 - cot0));
            printf("%s side %d: %d wraps over %.1f mm, density x distance %.1f, with the rise %.1f\n", name,
                   side, wraps, y1 - y0, barbs_per_mm * (y1 - y0), expected);
            /* The ends sit anywhere within their periods. */
            assert_true(fabs(wraps - expected) <= 1.0);
        }
        plm_feather_free(&f);
        plm_species_free(&sp);
    }
}

static double smooth01(double e0, double e1, double x)
{
    double t = fmin(1.0, fmax(0.0, (x - e0) / (e1 - e0)));
    return t * t * (3.0 - 2.0 * t);
}

/* Pooled correlation of a barb's variation with that of the barb k further
 * along, over the series of (seeds x sides) collected below. */
#define SERIES_MAX 64
#define BARBS_MAX 512
typedef struct barb_series {
    int count, length[SERIES_MAX];
    double value[SERIES_MAX][BARBS_MAX];
} barb_series;

static double lag_correlation(const barb_series *b, int k)
{
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    int n = 0;
    for (int s = 0; s < b->count; ++s)
        for (int j = 0; j + k < b->length[s]; ++j) {
            double x = b->value[s][j], y = b->value[s][j + k];
            if (x < 0.0 || y < 0.0)
                continue; /* a barb no texel sampled */
            sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y, ++n;
        }
    double cov = sxy / n - sx * sy / ((double)n * n);
    return cov / sqrt((sxx / n - sx * sx / ((double)n * n)) * (syy / n - sy * sy / ((double)n * n)));
}

/* The pigment image's downy base and per-barb variation, against the
 * species' values: the base channel is 1 over the barbs leaving the rachis in
 * the downy base, 0 past base_length beyond it, a smoothstep between (so the
 * colour boundary follows the barbs); the barb channel is one value per barb
 * (every texel of a barb the same, so it reads as barbs, not grain) in
 * [0, barb_jitter]; across barbs, half of it is shared by groups of about
 * barb_clump barbs: neighbours correlate (expected r = 0.38 for 4 barbs;
 * asserted above 0.25) and barbs two groups apart do not (|r| < 0.1; the
 * standard error over these 20 seeds is about 0.015). With barb_clump 1,
 * neighbours are independent too. */
static void pigment_base_and_barb_variation(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    sp.pigment.base_length = 0.2;
    sp.pigment.barb_jitter = 0.4;
    for (int clump = 4; clump >= 1; clump -= 3) {
        sp.pigment.barb_clump = clump;
        static barb_series series;
        memset(&series, 0, sizeof series);
        for (int seed = 1; seed <= 20; ++seed) {
            sp.pigment.seed = (uint64_t)seed;
            plm_feather f = textures_of(&sp, 384);
            const plm_outline *o = &f.outline;
            double down = sp.shape.plumulaceous, *value[2];
            for (int side = 0; side < 2; ++side) {
                value[side] = series.value[series.count + side];
                series.length[series.count + side] = BARBS_MAX;
                for (int j = 0; j < BARBS_MAX; ++j)
                    value[side][j] = -1.0;
            }
            for (int j = 0; j < f.pigment.height; ++j)
                for (int i = 0; i < f.pigment.width; ++i) {
                    vec2 p = plm_outline_flat(o, (i + 0.5) / f.pigment.width, 1.0 - (j + 0.5) / f.pigment.height);
                    plm_flat_sample s = plm_outline_sample(o, p.x, p.y);
                    const float *px = f.pigment.pixels + PLM_PIGMENT_CHANNELS * ((size_t)j * f.pigment.width + i);
                    if (s.region != PLM_FLAT_VANE) {
                        assert_double_near(px[PLM_PIGMENT_BASE] + px[PLM_PIGMENT_BARB], 0.0, 0.0);
                        continue;
                    }
                    double t = (s.barb_origin - o->vane_base) / o->vane_length;
                    double base = t <= down ? 1.0 : 1.0 - smooth01(down, down + 0.2, t);
                    assert_double_near(px[PLM_PIGMENT_BASE], base, 1e-6);
                    int barb = (int)floor((s.barb_origin - o->vane_base) / o->spacing);
                    assert_true(barb >= 0 && barb < BARBS_MAX);
                    double *v = &value[p.x >= 0.0][barb];
                    assert_true(px[PLM_PIGMENT_BARB] >= 0.0f && px[PLM_PIGMENT_BARB] <= 0.4f);
                    if (*v < 0.0)
                        *v = px[PLM_PIGMENT_BARB];
                    assert_double_near(px[PLM_PIGMENT_BARB], *v, 0.0); /* one value along the whole barb */
                }
            series.count += 2;
            plm_feather_free(&f);
        }
        double r1 = lag_correlation(&series, 1), far = 0.0;
        for (int k = 2 * clump; k <= 2 * clump + 4; ++k)
            far = fmax(far, fabs(lag_correlation(&series, k)));
        fprintf(stderr, "barb_clump %d: neighbouring barbs r = %.3f, %d-%d apart |r| <= %.3f\n", clump, r1,
                2 * clump, 2 * clump + 4, far);
        if (clump > 1)
            assert_true(r1 > 0.25);
        else
            assert_true(fabs(r1) < 0.1);
        assert_true(far < 0.1);
    }
    plm_species_free(&sp);
}

static void files_round_trip_and_runs_repeat(void **state)
{
    (void)state;
    plm_species sp = load_preset("hackle_pointed");
    plm_feather f = textures_of(&sp, 256), g = textures_of(&sp, 256);
    size_t n = (size_t)256 * 256 * 3;
    assert_memory_equal(f.texture.pixels, g.texture.pixels, n * sizeof(float));
    assert_int_equal(f.pigment.channels, PLM_PIGMENT_CHANNELS);
    assert_memory_equal(f.pigment.pixels, g.pigment.pixels, (size_t)256 * 256 * PLM_PIGMENT_CHANNELS * sizeof(float));
    for (size_t i = 0; i < n; ++i)
        assert_true(isfinite(f.texture.pixels[i]) && f.texture.pixels[i] >= 0.0f && f.texture.pixels[i] <= 1.0f);
    const char *files[2] = {"texture_rt.exr", "texture_rt.png"};
    for (int k = 0; k < 2; ++k) {
        plm_image back;
        assert_int_equal(plm_texture_write(files[k], &f.texture, NULL), PLM_OK);
        assert_int_equal(plm_image_read(files[k], &back.width, &back.height, &back.channels, &back.pixels, NULL),
                         PLM_OK);
        assert_int_equal(back.width, 256);
        assert_int_equal(back.height, 256);
        assert_int_equal(back.channels, 3);
        assert_false(plm_ftex_has_barb(back.channels)); /* a texture from before the coordinate */
        for (size_t i = 0; i < n; ++i)
            assert_double_near(back.pixels[i], f.texture.pixels[i], k ? 0.5 / 65535.0 + 1e-7 : 0.0);
        plm_texture_image_free(&back);
        remove(files[k]);
    }
    /* The files plumage writes carry the barb coordinate as a fourth channel:
     * exact in EXR, to 16-bit rounding in PNG (where 1 is the phase 0). */
    assert_memory_equal(f.barb.pixels, g.barb.pixels, (size_t)256 * 256 * sizeof(float));
    assert_int_equal(plm_feather_write_textures(&f, "texture_rt_dir", NULL, NULL), PLM_OK);
    const char *written[2] = {"texture_rt_dir/texture.exr", "texture_rt_dir/texture.png"};
    for (int k = 0; k < 2; ++k) {
        plm_image back;
        assert_int_equal(plm_image_read(written[k], &back.width, &back.height, &back.channels, &back.pixels, NULL),
                         PLM_OK);
        assert_int_equal(back.channels, PLM_FTEX_CHANNELS_WITH_BARB);
        assert_true(plm_ftex_has_barb(back.channels));
        double tol = k ? 0.5 / 65535.0 + 1e-7 : 0.0;
        for (size_t i = 0; i < (size_t)256 * 256; ++i) {
            const float *px = back.pixels + PLM_FTEX_CHANNELS_WITH_BARB * i;
            for (int c = 0; c < PLM_FTEX_CHANNELS; ++c)
                assert_double_near(px[c], f.texture.pixels[PLM_FTEX_CHANNELS * i + c], tol);
            double stored = f.barb.pixels[i];
            assert_double_near(plm_ftex_barb_unwrap(px[PLM_FTEX_BARB], stored), stored, tol);
        }
        plm_texture_image_free(&back);
    }
    for (int k = 0; k < 2; ++k)
        remove(written[k]);
    remove("texture_rt_dir/pigment.exr");
    remove("texture_rt_dir/pigment.png");
    remove("texture_rt_dir");
    plm_error err = {{0}};
    assert_int_equal(plm_texture_write("texture_rt.jpg", &f.texture, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, ".exr or .png"));
    plm_feather_free(&f);
    plm_feather_free(&g);
    plm_species_free(&sp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(barb_angle_at_the_rachis_is_the_parameter),
        cmocka_unit_test(barbs_curve_toward_the_tip_by_the_curvature),
        cmocka_unit_test(stored_directions_are_tangents_of_the_barbs),
        cmocka_unit_test(mask_widths_are_the_parameters),
        cmocka_unit_test(notched_tip_is_cut_at_the_rachis),
        cmocka_unit_test(splits_and_the_fluffy_base),
        cmocka_unit_test(rachis_region_has_the_rachis_width),
        cmocka_unit_test(the_vane_mesh_covers_every_vane_texel),
        cmocka_unit_test(barb_coordinate_is_constant_along_traced_barbs),
        cmocka_unit_test(barb_coordinate_period_is_the_barb_density),
        cmocka_unit_test(pigment_base_and_barb_variation),
        cmocka_unit_test(files_round_trip_and_runs_repeat),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
