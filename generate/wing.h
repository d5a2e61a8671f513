/* The wing layout: a parametric right wing of flight feathers and coverts,
 * spread or folded, as a layout (generate/layout.h): prototypes per row and
 * one instance per feather with its row and dorsal order. See
 * docs/layouts.md for the frame, the parameters and the rows. */
#ifndef PLUMAGE_GENERATE_WING_H
#define PLUMAGE_GENERATE_WING_H

#include "generate/layout.h"

/* The rows of a wing, each its own species. */
typedef enum plm_wing_row {
    PLM_WING_PRIMARY = 0,
    PLM_WING_SECONDARY,
    PLM_WING_TERTIAL,
    PLM_WING_GREATER_COVERT,
    PLM_WING_MEDIAN_COVERT,
    PLM_WING_LESSER_COVERT,
    PLM_WING_ALULA,
    PLM_WING_ROWS
} plm_wing_row;

/* The row names used in files and messages ("primary", ...). */
extern const char *const plm_wing_row_names[PLM_WING_ROWS];

/* A right wing: the shoulder at the origin, span along +x, the leading edge
 * toward +y, dorsal +z. */
typedef struct plm_wing_params {
    double span;      /* shoulder to the tip of the longest primary, layout units [1] */
    double chord;     /* length of the secondaries, layout units [0.3 span] */
    double sweep;     /* radians the hand and its primaries sweep back (0 = straight) */
    double fold;      /* 0 = spread .. 1 = folded against the body */
    int primaries;    /* [10], at most 12 */
    int secondaries;  /* [12], at most 24 */
    int tertials;     /* [3], at most 6 */
    int variants;     /* distinct prototypes per row [3] */
    plm_layout_variation variation;
    uint64_t seed;
} plm_wing_params;

/* rows[PLM_WING_ROWS]: the species of each row; NULL rows take the secondary's
 * (the primary and secondary rows are required). */
plm_result plm_layout_wing(const plm_wing_params *p, const plm_species *const *rows, plm_layout *out,
                           plm_error *err);

#endif
