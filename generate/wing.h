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
    PLM_WING_PRIMARY_COVERT,  /* the greater coverts of the primaries */
    PLM_WING_MARGINAL_COVERT, /* over the leading edge */
    PLM_WING_UNDER_COVERT,    /* the ventral side's coverts */
    PLM_WING_SPECULUM,        /* not a row: the species of the outer `speculum` secondaries, whose row is
                                 PLM_WING_SECONDARY */
    PLM_WING_ROWS
} plm_wing_row;

/* The row names used in files and messages ("primary", ...). */
extern const char *const plm_wing_row_names[PLM_WING_ROWS];

/* The row whose species a row without one takes (primary covert: greater
 * covert; marginal: lesser; under-wing: median; the others: secondary),
 * always a smaller index; -1 for the two required rows. */
int plm_wing_row_fallback(int row);

/* A right wing in its own space: the shoulder at the origin, span along +x,
 * the leading edge toward +y, dorsal +z; `frame` takes it where it goes. */
typedef struct plm_wing_params {
    double span;      /* shoulder to the tip of the longest primary, layout units [1] */
    double chord;     /* length of the secondaries, layout units [0.3 span] */
    double sweep;     /* radians the hand and its primaries sweep back (0 = straight) */
    double fold;      /* 0 = spread .. 1 = folded against the body */
    int primaries;    /* [10], at most 12 */
    int secondaries;  /* [12], at most 24 */
    int tertials;     /* [3], at most 6 */
    int speculum;     /* how many outer secondaries take the PLM_WING_SPECULUM species [0] */
    int variants;     /* distinct prototypes per row [3] */
    /* The shoulder frame: wing space -> layout space, rows of [linear | translation]. The
     * linear part must be orthonormal; a reflection (determinant -1) makes the left wing, its
     * instances' matrices then mirror the feathers. All zeros = the identity. */
    double frame[3][4];
    plm_layout_variation variation;
    uint64_t seed;
} plm_wing_params;

/* rows[PLM_WING_ROWS]: the species of each row; NULL rows take their
 * fallback's (plm_wing_row_fallback; the primary and secondary rows are
 * required). Instances come in dorsal order (`order` = index): the under-wing
 * coverts first, the most ventral lowest, then the flight feathers and the
 * dorsal coverts. */
plm_result plm_layout_wing(const plm_wing_params *p, const plm_species *const *rows, plm_layout *out,
                           plm_error *err);

/* The wing's skin in layout space: a strip from the bones (where the flight
 * feathers root) forward to under the leading edge's coverts, dorsal normals
 * (+z in wing space). Every covert roots on it and covers it: seen from
 * above or below, skin that shows is a gap in the plumage. */
plm_result plm_wing_skin(const plm_wing_params *p, plm_mesh *out, plm_error *err);

#endif
