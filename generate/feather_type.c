/* The defaults a species' `type` gives: one row per kind of feather.
 *
 * The numbers are judgements from photographs of real feathers and the
 * proportions in docs/species.md (flight feathers' vane asymmetry after
 * Speakman & Thomson and Feo et al.; emarginated outer primaries; body
 * feathers bent and cupped more than flight feathers), not measurements.
 * Lengths, widths and rachis widths are at the type's own length: a species
 * that sets another length and no widths gets them scaled (species.c). */
#include <string.h>

#include "common/vec.h"
#include "generate/species.h"

const char *const plm_feather_type_names[PLM_TYPE_COUNT + 1] = {
    "contour", "covert", "primary", "secondary", "tertial", "rectrix", "hackle", NULL};

#define WIDTH_POINTS 5

typedef struct type_row {
    double length, calamus, plumulaceous;
    double rachis_base, rachis_tip, taper;
    double bend_out, bend_in, twist, curl; /* degrees */
    int points;
    double width[2][WIDTH_POINTS][2]; /* per side, [t, mm] */
    plm_emargination emargination[2];
    plm_tip_shape tip;
    double tip_length;
    double angle_base[2], angle_tip[2], curvature, density; /* degrees, per cm */
    double end_jitter, fray;                                /* barb spacings */
    double split_frequency;                                 /* per vane */
} type_row;

/* Left is the leading (outer, narrow) vane of flight feathers. */
static const type_row rows[PLM_TYPE_COUNT] = {
    [PLM_TYPE_CONTOUR] = {60, 4, 0.3, 1.0, 0.15, 1.0, 18, 5, 0, 15, 5,
                          {{{0, 5}, {0.25, 9}, {0.6, 11}, {0.85, 10.5}, {1, 8.5}},
                           {{0, 5}, {0.25, 9}, {0.6, 11}, {0.85, 10.5}, {1, 8.5}}},
                          {{0}, {0}}, PLM_TIP_ROUNDED, 0.35, {55, 55}, {40, 40}, 8, 30, 3.5, 5, 2.0},
    [PLM_TYPE_COVERT] = {45, 3, 0.15, 0.8, 0.15, 1.0, 14, 3, 0, 12, 5,
                         {{{0, 5}, {0.2, 8}, {0.55, 10}, {0.85, 10}, {1, 9}},
                          {{0, 5}, {0.2, 8}, {0.55, 10}, {0.85, 10}, {1, 9}}},
                         {{0}, {0}}, PLM_TIP_TRUNCATE, 0.3, {55, 55}, {45, 45}, 8, 30, 3.5, 5, 2.0},
    [PLM_TYPE_PRIMARY] = {180, 22, 0.05, 3.0, 0.4, 0.8, 8, 6, 6, 4, 4,
                          {{{0, 4}, {0.25, 7}, {0.55, 6.5}, {1, 4.5}}, {{0, 10}, {0.3, 19}, {0.75, 18}, {1, 13}}},
                          {{0.62, 0.45, 0.08}, {0.58, 0.25, 0.06}}, PLM_TIP_ROUNDED, 0.14, {25, 45}, {18, 35}, 12,
                          24, 4.0, 4, 0.4},
    [PLM_TYPE_SECONDARY] = {140, 18, 0.06, 2.6, 0.4, 0.8, 6, 2, 3, 4, 3,
                            {{{0, 5}, {0.3, 8}, {1, 7.5}}, {{0, 9}, {0.3, 14}, {1, 13.5}}},
                            {{0}, {0}}, PLM_TIP_TRUNCATE, 0.1, {32, 45}, {26, 38}, 10, 24, 3.5, 4, 0.5},
    [PLM_TYPE_TERTIAL] = {110, 12, 0.08, 2.0, 0.3, 0.9, 8, 0, 2, 6, 3,
                          {{{0, 6}, {0.3, 10}, {1, 9}}, {{0, 8}, {0.3, 13}, {1, 12}}},
                          {{0}, {0}}, PLM_TIP_ROUNDED, 0.2, {40, 48}, {32, 38}, 10, 24, 3.5, 4, 0.8},
    [PLM_TYPE_RECTRIX] = {150, 15, 0.06, 2.4, 0.4, 0.9, 4, 0, 0, 3, 3,
                          {{{0, 6}, {0.3, 10}, {1, 10}}, {{0, 7}, {0.3, 11.5}, {1, 11.5}}},
                          {{0}, {0}}, PLM_TIP_SQUARE, 0.08, {38, 45}, {30, 38}, 8, 24, 3.5, 4, 0.6},
    [PLM_TYPE_HACKLE] = {90, 5, 0.35, 0.9, 0.12, 1.0, 15, 0, 0, 6, 4,
                         {{{0, 3.5}, {0.3, 4.5}, {0.6, 4.5}, {1, 3.5}}, {{0, 3.5}, {0.3, 4.5}, {0.6, 4.5}, {1, 3.5}}},
                         {{0}, {0}}, PLM_TIP_POINTED, 0.45, {40, 40}, {30, 30}, 5, 28, 3.5, 6, 2.5},
};

/* The fluffy base: body feathers (contour, hackle) have long, curly down
 * barbs and an afterfeather; coverts shorter down and none; flight feathers
 * a short, sparse downy base. Barb thickness is not scaled with the length:
 * down barbs are about 20-40 um thick on small and large birds alike. */
typedef struct fluff_row {
    double density, length, curl, thickness, barbules; /* per cm, vane widths, degrees, mm, per mm */
    int afterfeather;
    double afterfeather_size;
} fluff_row;

static const fluff_row fluff_rows[PLM_TYPE_COUNT] = {
    [PLM_TYPE_CONTOUR] = {30, 1.1, 150, 0.025, 20, 1, 0.22},
    [PLM_TYPE_COVERT] = {30, 0.9, 110, 0.025, 20, 0, 0.15},
    [PLM_TYPE_PRIMARY] = {20, 0.5, 60, 0.04, 4, 0, 0.1},
    [PLM_TYPE_SECONDARY] = {20, 0.5, 60, 0.04, 4, 0, 0.1},
    [PLM_TYPE_TERTIAL] = {22, 0.6, 80, 0.035, 5, 0, 0.1},
    [PLM_TYPE_RECTRIX] = {20, 0.5, 60, 0.04, 4, 0, 0.1},
    [PLM_TYPE_HACKLE] = {28, 1.2, 150, 0.025, 16, 1, 0.18},
};

static void fluff_default(plm_shape *sh, plm_feather_type type)
{
    const fluff_row *f = &fluff_rows[type];
    sh->fluff_density = f->density;
    sh->fluff_length = f->length;
    sh->fluff_curl = plm_radians(f->curl);
    sh->fluff_thickness = f->thickness;
    sh->fluff_barbules = f->barbules;
    sh->afterfeather = f->afterfeather;
    sh->afterfeather_size = f->afterfeather_size;
}

void plm_species_default_of_type(plm_species *s, plm_feather_type type)
{
    const type_row *r = &rows[type];
    memset(s, 0, sizeof *s);
    strcpy(s->name, "default");
    s->type = type;
    plm_shape *sh = &s->shape;
    sh->length = r->length;
    sh->calamus_length = r->calamus;
    sh->plumulaceous = r->plumulaceous;
    sh->rachis_base_width = r->rachis_base;
    sh->rachis_tip_width = r->rachis_tip;
    sh->rachis_taper = r->taper;
    sh->bend_out_of_plane = plm_radians(r->bend_out);
    sh->bend_in_plane = plm_radians(r->bend_in);
    sh->twist = plm_radians(r->twist);
    sh->curl = plm_radians(r->curl);
    for (int side = 0; side < 2; ++side) {
        plm_width_profile *w = &sh->width[side];
        w->count = r->points;
        for (int k = 0; k < r->points; ++k) {
            w->t[k] = r->width[side][k][0];
            w->width[k] = r->width[side][k][1];
        }
        sh->emargination[side] = r->emargination[side];
        if (sh->emargination[side].length == 0.0)
            sh->emargination[side] = (plm_emargination){0.6, 0.0, 0.06};
        sh->barb_angle_base[side] = plm_radians(r->angle_base[side]);
        sh->barb_angle_tip[side] = plm_radians(r->angle_tip[side]);
    }
    sh->tip_shape = r->tip;
    sh->tip_length = r->tip_length;
    sh->barb_curvature = plm_radians(r->curvature);
    sh->barb_density = r->density;
    sh->barb_end_jitter = r->end_jitter;
    sh->barb_fray = r->fray;
    sh->split_frequency = r->split_frequency;
    sh->split_positions[0] = 0.3;
    sh->split_positions[1] = 0.95;
    sh->split_depths[0] = 0.2;
    sh->split_depths[1] = 0.6;
    sh->split_gap = 0.6;
    sh->seed = 1;
    fluff_default(sh, type);
    s->pigment.band_width = 0.5;
    s->pigment.tip_length = 0.15;
    s->pigment.base_length = 0.15;
    s->pigment.barb_jitter = 0.3;
    s->pigment.barb_clump = 4.0;
}

void plm_species_default(plm_species *s)
{
    plm_species_default_of_type(s, PLM_TYPE_CONTOUR);
}
