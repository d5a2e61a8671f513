/* A species preset: the biological description of one kind of feather.
 *
 * The `shape` block drives the generator (every field, its unit, range,
 * default and source is listed in docs/species.md); `pigment` drives the
 * optional pigment image. The `optics` block belongs to the renderer: the
 * parser only checks that it is an object, and scene/ reads it from the file
 * (generate/ knows nothing of rendering).
 *
 * The feather lies in its own frame: the rachis runs along +y from the base
 * of the calamus (y = 0) to the tip (y = length), the vanes spread along x
 * (the right vane at +x, the left at -x), and +z is the dorsal side, toward
 * which barbules rise (docs/masking.md). Lengths are millimetres, angles degrees
 * in the file and radians in these structs. */
#ifndef PLUMAGE_GENERATE_SPECIES_H
#define PLUMAGE_GENERATE_SPECIES_H

#include <cjson/cJSON.h>
#include <stdint.h>

#include "common/error.h"
#include "common/params.h"

#define PLM_WIDTH_POINTS_MAX 16
#define PLM_SPLITS_MAX 32
#define PLM_WIDTH_MAX_MM 500.0 /* a vane width control point */
#define PLM_SPECIES_PATH_MAX 256 /* a field path in messages, with an inline species' prefix */

typedef enum plm_tip_shape {
    PLM_TIP_ROUNDED = 0,  /* an elliptical end: width ~ sqrt(1 - tau^2) */
    PLM_TIP_POINTED = 1,  /* a straight taper to the tip */
    PLM_TIP_NOTCHED = 2,  /* each vane rounds off on its own, leaving a notch at the rachis as deep as the tip */
    PLM_TIP_TRUNCATE = 3, /* rounded-truncate: a blunt end, width ~ (1 - tau^3)^(1/3) */
    PLM_TIP_SQUARE = 4    /* nearly square corners: width ~ (1 - tau^8)^(1/8) */
} plm_tip_shape;

/* The kinds of feather a species' `type` stands for: each gives its own
 * defaults (outline, tip, bends, cupping, splits; generate/feather_type.c). */
typedef enum plm_feather_type {
    PLM_TYPE_CONTOUR = 0,   /* a body feather: symmetric, rounded, bent, split, a long downy base */
    PLM_TYPE_COVERT = 1,    /* a wing or body covert: symmetric, rounded-truncate */
    PLM_TYPE_PRIMARY = 2,   /* an outer primary: 1:3.5 vanes, emarginated outer vane, notched inner vane */
    PLM_TYPE_SECONDARY = 3, /* a secondary: 1:1.8 vanes, blunt tip */
    PLM_TYPE_TERTIAL = 4,   /* a tertial: nearly symmetric, rounded */
    PLM_TYPE_RECTRIX = 5,   /* a tail feather: nearly symmetric, square tip */
    PLM_TYPE_HACKLE = 6,    /* a long narrow pointed neck feather */
    PLM_TYPE_COUNT
} plm_feather_type;

/* Width of one vane against position along the vaned part of the rachis:
 * control points (t, width) with t in [0, 1] from the vane's base to the tip,
 * joined by a monotone cubic (smooth, never overshooting below zero). */
typedef struct plm_width_profile {
    int count;
    double t[PLM_WIDTH_POINTS_MAX];
    double width[PLM_WIDTH_POINTS_MAX]; /* mm, from the rachis centre line to the vane edge */
} plm_width_profile;

/* An emargination: the vane narrows by `depth` of its width over `length`
 * around `position` (fractions of the vaned length), as an outer primary's
 * outer vane narrows and its inner vane is notched. depth 0: none. */
typedef struct plm_emargination {
    double position, depth, length;
} plm_emargination;

typedef struct plm_split {
    double position; /* where the split's barb leaves the rachis, fraction of the vaned length */
    double depth;    /* how far the gap reaches in from the edge, fraction of the vane width */
    int side;        /* 0 left, 1 right */
} plm_split;

typedef struct plm_shape {
    double length;         /* mm, calamus base to tip, along the rachis */
    double calamus_length; /* mm, bare base before the vanes start */
    /* rachis */
    double rachis_base_width, rachis_tip_width; /* mm, diameters */
    double rachis_taper;                        /* exponent: width = base + (tip - base) * s^taper */
    double bend_in_plane, bend_out_of_plane;    /* radians the rachis turns between base and tip */
    double twist;                               /* radians the vane plane turns about the rachis */
    /* vanes */
    plm_width_profile width[2]; /* [0] left (-x), [1] right (+x) */
    plm_emargination emargination[2];
    double curl;                /* radians: slope of the vane at its edge; > 0 cups the edges ventrally */
    plm_tip_shape tip_shape;
    double tip_length; /* fraction of the vaned length over which the tip closes */
    /* barbs */
    double barb_angle_base[2], barb_angle_tip[2]; /* per side: radians between barb and rachis (toward the tip) */
    double barb_curvature;                  /* radians the barb turns toward the tip from rachis to edge */
    double barb_density;                    /* barbs per cm along the rachis, per side */
    double barb_end_jitter;                 /* barb spacings: how much shorter than the outline a barb may end */
    double barb_fray;                       /* barb spacings below the tip over which barbs part */
    /* fluffy base: barbs leaving the rachis in the first `plumulaceous` fraction of the vane */
    double plumulaceous;
    /* its down barbs and the afterfeather's, as curves (generate/fluff.h) */
    double fluff_density;     /* down barbs per cm along the rachis, per side; 0: none */
    double fluff_length;      /* a down barb's length over the vane's width where it leaves the rachis */
    double fluff_curl;        /* radians: RMS turn of a down barb's direction between its root and its end */
    double fluff_thickness;   /* mm: a down barb's diameter at its root */
    double fluff_barbules;    /* barbules per mm along a down barb (both sides together) */
    int afterfeather;         /* 1: an afterfeather leaves the rachis's underside where the vanes begin */
    double afterfeather_size; /* its length, fraction of the feather's length */
    /* splits: gaps between barbs, reaching in from the vane edge; listed
     * ones here, drawn ones added per feather by plm_outline_init */
    int split_count;
    plm_split splits[PLM_SPLITS_MAX];
    double split_frequency;    /* mean splits drawn per vane (Poisson), 0 with a list */
    double split_positions[2]; /* [min, max] of drawn positions, fraction of the vaned length */
    double split_depths[2];    /* [min, max] of drawn depths, fraction of the width */
    double split_gap;          /* mm, width of a split at the vane edge */
    /* this feather's own draws (splits, barb ends): feathers of one species differ by it */
    uint64_t seed;
} plm_shape;

/* Pigment variation (the optional second image). */
typedef struct plm_pigment {
    int band_count;      /* dark bars across the vane, following the barbs (0 = none) */
    double band_width;   /* fraction of the band period that is dark */
    double tip_length;   /* fraction of the vaned length coloured as the tip */
    double base_length;  /* fraction of the vaned length past the downy base over which its colour fades */
    double barb_jitter;  /* 0..1: amplitude of per-barb variation */
    double barb_clump;   /* barbs: how many neighbours share half of that variation (1: each its own) */
    uint64_t seed;
} plm_pigment;

typedef struct plm_species {
    char name[128];
    plm_feather_type type;
    plm_shape shape;
    plm_pigment pigment;
} plm_species;

/* One parameter table per block of the species file (common/params.h), the
 * one place their ranges are written; docs/species.md prints them. */
extern const plm_param_block plm_shape_param_block;     /* plm_shape: length, calamus, plumulaceous */
extern const plm_param_block plm_rachis_param_block;    /* plm_shape */
extern const plm_param_block plm_vane_param_block;      /* plm_shape */
extern const plm_param_block plm_vane_tip_param_block;  /* plm_shape */
extern const plm_param_block plm_barbs_param_block;     /* plm_shape */
extern const plm_param_block plm_fluff_param_block;     /* plm_shape */
extern const plm_param_block plm_barb_side_param_block; /* plm_shape, offset by one double for the right side */
extern const plm_param_block plm_splits_param_block;    /* plm_shape */
extern const plm_param_block plm_emargination_param_block[2]; /* plm_emargination, left and right */
extern const plm_param_block plm_split_param_block;     /* plm_split */
extern const plm_param_block plm_pigment_param_block;   /* plm_pigment */

/* The defaults of every field (a generic contour feather). */
void plm_species_default(plm_species *s);
/* The defaults of a type (plm_species_default is the contour's). */
void plm_species_default_of_type(plm_species *s, plm_feather_type type);
/* The type names as the species file spells them, NULL-terminated. */
extern const char *const plm_feather_type_names[PLM_TYPE_COUNT + 1];

/* Parses and validates a preset. Errors name the file and field path. */
plm_result plm_species_load(const char *path, plm_species *out, plm_error *err);
plm_result plm_species_parse(const cJSON *root, const char *file, plm_species *out, plm_error *err);
/* The same for a species inside another file (a scene's inline species):
 * `path` is where it lies, and prefixes every field path in messages. */
plm_result plm_species_parse_at(const cJSON *root, const char *file, const char *path, plm_species *out,
                                plm_error *err);

/* Checks the relations between fields that single ranges cannot express
 * (tip no wider than base, splits inside the vane, barbs that stay barbs). */
plm_result plm_species_validate(const plm_species *s, const char *file, plm_error *err);
plm_result plm_species_validate_at(const plm_species *s, const char *file, const char *path, plm_error *err);

/* Releases what parsing allocated (today nothing) and zeroes the struct. */
void plm_species_free(plm_species *s);

#endif
