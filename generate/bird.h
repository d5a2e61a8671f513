/* A whole bird from a `bird` preset (presets/birds/, docs/birds.md): a few
 * ornithological measurements and proportions give a body cage that
 * OpenSubdiv smooths into the skin; the bill and eyes are swept shapes; the
 * skin is divided into feather tracts (pterylae) in the body's own
 * parameterisation, so a tract follows any proportions.
 *
 *   plm_bird bird;
 *   plm_bird_load("presets/birds/amazon_parrot.json", &bird, &err);
 *   plm_bird_body body;
 *   plm_bird_build(&bird, 3, &body, &err);  // skin, bill, eyes, tract of each triangle
 *   ...
 *   plm_bird_body_free(&body);
 *
 * The body's parameterisation: s runs along the body from the bill's base
 * (0) to the base of the tail (1); `around` is the angle about the body's
 * axis from the dorsal midline (0 degrees) over the flank (90) to the
 * ventral midline (180), the same on both sides. The bird's frame: metres,
 * +x forward (where the bill points), +y the bird's left, +z up; the origin
 * is where the feet grip the perch. */
#ifndef PLUMAGE_GENERATE_BIRD_H
#define PLUMAGE_GENERATE_BIRD_H

#include <stdint.h>

#include "common/error.h"
#include "common/mesh.h"
#include "common/params.h"
#include "common/vec.h"
#include "generate/wing.h"

#define PLM_BIRD_TRACTS_MAX 24
#define PLM_BIRD_NAME_MAX 64
#define PLM_BIRD_PATH_MAX 4096

/* Millimetres, as field guides and handbooks give them. */
typedef struct plm_bird_measurements {
    double total_length; /* bill tip to tail tip, the bird laid flat */
    double wing_chord;   /* the folded wing, wrist to the longest primary's tip */
    double tail_length;  /* base of the central rectrices to their tip */
    double bill_length;  /* exposed culmen (chord) */
    double bill_depth;   /* at the base, both mandibles */
    double head_width;   /* across the skull behind the eyes, skin without feathers */
    double tarsus;       /* tarsometatarsus */
} plm_bird_measurements;

/* Dimensionless shape of the skin body (docs/birds.md). */
typedef struct plm_bird_proportions {
    double neck;        /* neck width over head width */
    double breast;      /* breast width over head width */
    double rump;        /* rump width over breast width */
    double depth;       /* body depth over breast width */
    double neck_length; /* the neck's share of the body's length */
    double posture;     /* radians: the body's axis below the horizontal (perched upright ~ 55 degrees) */
} plm_bird_proportions;

typedef enum plm_bill_family {
    PLM_BILL_HOOKED = 0, /* parrots, raptors */
    PLM_BILL_CONICAL,    /* finches, cardinals */
    PLM_BILL_DAGGER,     /* kingfishers, herons */
    PLM_BILL_FAMILIES
} plm_bill_family;

extern const char *const plm_bill_family_names[PLM_BILL_FAMILIES + 1]; /* NULL-terminated */

/* A glossy coat over a diffuse base (render's "coat" material). */
typedef struct plm_bird_surface {
    rgb colour;       /* the diffuse base's albedo */
    double roughness; /* the coat's GGX alpha */
} plm_bird_surface;

typedef enum plm_pteryla {
    PLM_PTERYLA_CAPITAL = 0, /* the head */
    PLM_PTERYLA_SPINAL,      /* the back, nape to rump */
    PLM_PTERYLA_VENTRAL,     /* throat, breast and belly */
    PLM_PTERYLA_HUMERAL,     /* the shoulder, over the wing's base */
    PLM_PTERYLA_FEMORAL,     /* the thigh and flank */
    PLM_PTERYLA_CAUDAL,      /* around the tail's base: the tail coverts */
    PLM_PTERYLAE
} plm_pteryla;

extern const char *const plm_pteryla_names[PLM_PTERYLAE + 1]; /* NULL-terminated */

/* Where each pteryla lies in (s, around) unless a tract narrows it. */
typedef struct plm_bird_region {
    double s[2];      /* along the body, 0 bill .. 1 tail base */
    double around[2]; /* radians from the dorsal midline, 0 .. pi */
} plm_bird_region;

extern const plm_bird_region plm_pteryla_regions[PLM_PTERYLAE];

/* A feather tract, or a colour patch within one: a species laid over the
 * part of the skin its region covers. Later tracts take the skin of earlier
 * ones where they overlap, so a patch follows the tract it sits in. */
typedef struct plm_bird_tract {
    char name[PLM_BIRD_NAME_MAX];
    plm_pteryla pteryla;
    plm_bird_region region;
    char species[PLM_BIRD_PATH_MAX]; /* species preset, resolved against the bird file */
    double density;                  /* feathers per square centimetre of skin */
    double size[2];                  /* feather length, mm, at the tract's head end and at its tail end */
    double flow;                     /* radians the flow turns from head-to-tail toward the ventral side */
    double elevation;                /* radians between a feather's base and the skin */
} plm_bird_tract;

/* Both wings: the wing layout (generate/wing.h) folded against the body at the shoulders. */
typedef struct plm_bird_wings {
    char rows[PLM_WING_ROWS][PLM_BIRD_PATH_MAX]; /* species per row, resolved; "" = the layout's fallback */
    double span;  /* mm, shoulder to the longest primary's tip spread [1.6 wing chords] */
    double chord; /* mm, the secondaries' length [0.5 wing chords] */
    double fold;  /* 0 spread .. 1 folded [1] */
    int primaries, secondaries, tertials; /* 0 = the layout's defaults */
    int present;
} plm_bird_wings;

/* The tail: a fan of rectrices with upper and under coverts over their bases. */
typedef struct plm_bird_tail {
    char rectrix[PLM_BIRD_PATH_MAX], covert[PLM_BIRD_PATH_MAX];
    int count;            /* rectrices [12] */
    double spread;        /* radians, the fan's half-angle [15 degrees] */
    double covert_length; /* the coverts' length over the tail's [0.5] */
    double rounding;      /* how much shorter the outermost rectrices are, fraction [0.2] */
    int present;
} plm_bird_tail;

typedef struct plm_bird {
    char name[PLM_BIRD_NAME_MAX];
    plm_bird_measurements m;
    plm_bird_proportions p;
    plm_bill_family bill_family;
    plm_bird_surface bill, lower_bill, iris, skin, feet;
    double eye_diameter; /* mm, the visible eyeball */
    plm_bird_tract tracts[PLM_BIRD_TRACTS_MAX];
    int tract_count;
    plm_bird_wings wings;
    plm_bird_tail tail;
    uint64_t seed;
} plm_bird;

extern const plm_param_block plm_bird_measurement_block; /* plm_bird_measurements */
extern const plm_param_block plm_bird_proportion_block;  /* plm_bird_proportions */
extern const plm_param_block plm_bird_tract_block;       /* plm_bird_tract's numbers */

/* Reads and checks a bird preset; every error names the file and field. */
plm_result plm_bird_load(const char *path, plm_bird *out, plm_error *err);

/* The generated bird, in the bird's frame (metres). */
typedef struct plm_bird_body {
    plm_mesh skin;         /* normals; tangents: the flow of each vertex's tract */
    double *s, *around;    /* per skin vertex: the body's parameterisation */
    float *ventral;        /* 3 per skin vertex: unit tangent across the flow toward the ventral midline */
    int *tract;            /* per skin triangle: the tract that owns it, -1 bare (around the eyes) */
    plm_mesh upper_bill, lower_bill;
    vec3 eye[2];           /* eyeball centres, left then right */
    vec3 eye_normal[2];    /* unit, where each eye looks */
    double eye_radius;
    vec3 shoulder[2];      /* where the wings attach, left then right */
    vec3 shoulder_normal[2]; /* unit, the skin's outward normal there */
    vec3 tail_base;        /* the base of the tail, and its direction (unit, backward and down) */
    vec3 tail_direction;
    vec3 tail_dorsal;      /* unit, the tail's dorsal side */
    vec3 axis;             /* unit, head to tail along the body */
} plm_bird_body;

/* level: subdivision of the body cage, 1..6. */
plm_result plm_bird_build(const plm_bird *bird, int level, plm_bird_body *out, plm_error *err);
void plm_bird_body_free(plm_bird_body *body);

/* The tail's rectrices (species 0) and coverts (species 1) as a layout in
 * the bird's frame. */
plm_result plm_bird_tail_layout(const plm_bird *bird, const plm_bird_body *body, const plm_species *rectrix,
                                const plm_species *covert, plm_layout *out, plm_error *err);

/* The frame that takes the wing layout's space (shoulder at the origin,
 * span +x, leading edge +y, dorsal +z) to the bird's at the given side
 * (0 left, a reflection; 1 right), the folded wing lying along the flank. */
void plm_bird_wing_frame(const plm_bird_body *body, int side, double lift, double m[3][4]);

/* A perch under the bird's origin, its top there, along the bird's side
 * axis (y), and the feet gripping it (tarsi and four toes each, two forward
 * and two back): meshes in the bird's frame. */
plm_result plm_bird_perch(const plm_bird *bird, double radius_mm, double length_mm, plm_mesh *branch, plm_mesh *feet,
                          plm_error *err);

/* A closed swept shape: rings of `around` points about a centre line, each
 * ring an ellipse of half-width w (along side) and half-heights up/down
 * (along up); a ring of zero size closes to a point. Normals outward. */
typedef struct plm_sweep_ring {
    vec3 centre, side, up; /* side and up: unit, perpendicular to the centre line */
    double w, up_height, down_height;
} plm_sweep_ring;

plm_result plm_sweep(const plm_sweep_ring *rings, int ring_count, int around, plm_mesh *out, plm_error *err);

#endif
