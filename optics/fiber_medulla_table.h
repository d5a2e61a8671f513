/* The medulla's part of the tabulated fiber BCSDF: the mean over h in
 * [h-, h+] and over the medulla's diffuse bounces of the lobes that met the
 * medulla, tabulated in expectation, so the tabulated estimator is
 * deterministic (docs/fiber.md, "The medulla's part").
 *
 * A path is deterministic until it first reaches the medulla; what leaves
 * after that depends only on the point it reached and on how many lobes it
 * may still store. The build tabulates that emission once per fiber (many
 * quasi-random diffuse directions per medulla point). The part is symmetric
 * in theta_i (a diffuse bounce forgets the sign of the longitudinal
 * direction), and independent of the sign of theta_o. Two layouts:
 *
 * - Rotationally symmetric fibers (one view node): per |theta_o| node, the
 *   emission of the points the deterministic paths reach is deposited into
 *   a table over (s, |theta_i|, phi_i - phi_o), cumulative in s = h / h_reach
 *   and in phi_i.
 * - Every other fiber (factored): the two factors are kept apart. Per view
 *   node (|theta_o|, phi_o) the light reaching each medulla point,
 *   cumulative over h cells, and the traced h samples themselves (for the
 *   interval's partial cells); per medulla point its emission over
 *   (|theta_i|, phi_i) in the fiber's frame (folded by the mirrors with wo),
 *   shared by all views. A query blends the light over the view nodes and
 *   the interval into one weight per point; eval is the points' emission
 *   weighted by it. */
#ifndef PLUMAGE_OPTICS_FIBER_MEDULLA_TABLE_H
#define PLUMAGE_OPTICS_FIBER_MEDULLA_TABLE_H

#include <stddef.h>

#include "optics/fiber.h"
#include "optics/fiber_grid.h"

/* Default resolution aims at this many bytes (within the fiber table's budget). */
#define PLM_FIBER_MEDULLA_BUDGET ((size_t)10 << 20)

/* Resolution of the medulla table; 0 = the defaults of docs/fiber.md. */
typedef struct plm_fiber_medulla_resolution {
    int theta_nodes, phi_nodes; /* view nodes over |theta_o| and phi_o (in the symmetry's range) */
    int h_cells;                /* uniform in asin(h), or asin(s) (below) */
    int theta_bins, phi_bins;   /* |theta_i| over [0, pi/2], phi_i over [-pi, pi) */
    int directions;             /* quasi-random diffuse directions per medulla point */
    /* Factored tables only: medulla points (a multiple of 8, at most
     * PLM_FIBER_MEDULLA_POINTS) and traced h samples kept per h cell. */
    int points, records;
} plm_fiber_medulla_resolution;

#define PLM_FIBER_MEDULLA_POINTS 96

typedef struct plm_fiber_medulla_table {
    plm_fiber_medulla_resolution res; /* theta_nodes 0: no medulla, no table */
    int symmetry;                     /* the fiber table's (optics/fiber_table.h) */
    int factored;                     /* 1: the factored layout (every fiber but a rotationally symmetric one) */
    double theta_max, eta, u_last; /* theta_o nodes as the other part's (optics/fiber_table.h) */
    double phi_lo, phi_step;
    /* Rotationally symmetric: the medulla's radius r. Paths meet the medulla
     * only for |h| below h_reach (plm_fiber_medulla_reach), so rows run over
     * s = h / h_reach, which puts the part's edge on a cell bound at every
     * view (docs/fiber.md). 0: rows over h itself. */
    double radius;
    double *h_node; /* h_cells + 1 cell bounds (over s or h) */
    double *node_cos; /* cos(|theta_o|) of each |theta_o| node (factored tables scale their blend by the
                       * interval's energy interpolated in it, as the other part does; docs/fiber.md) */
    float *bound_energy; /* factored tables: per node and h cell bound, the energy (mean of RGB) its light row
                          * gives the points (plm_fiber_medulla_bound_energies) */
    /* What eval interpolates between bin centres: 1, each bin's mass per unit
     * theta_i (bands narrower than beta_m); 0, its density per solid angle
     * (docs/fiber.md). band_scale: per |theta_i| band, what turns its mass
     * into the quantity interpolated, times the band's width: 1, or its
     * width over the integral of cos(theta) across it. */
    int per_theta;
    double *band_scale;
    /* Rotationally symmetric: per node, rows 0..h_cells, each: bands
     * 0..theta_bins-1 of columns 0..phi_bins, then each band's total, RGB.
     * Factored: the points' emission, their sampling tables, then per node
     * the light's cumulative rows and the h samples (fiber_medulla_table.c).
     * Points into the fiber table's data. */
    float *data;
    size_t floats;
} plm_fiber_medulla_table;


/* The resolution for p (theta_nodes 0 without a medulla) and its size in
 * floats, given the fiber table's symmetry; r overrides the defaults. */
void plm_fiber_medulla_layout(const plm_fiber_params *p, int symmetry, const plm_fiber_medulla_resolution *r,
                              plm_fiber_medulla_table *m);
/* A factored table's bound_energy, from its data (once built or read). */
void plm_fiber_medulla_bound_energies(plm_fiber_medulla_table *m);
/* The h cell bounds and the bands' scales (data is the caller's). */
plm_result plm_fiber_medulla_alloc(plm_fiber_medulla_table *m, plm_error *err);
void plm_fiber_medulla_release(plm_fiber_medulla_table *m);
/* Fills m->data (deterministically) on `threads` threads (0: all cores),
 * showing progress on stderr as plm_fiber_parallel does unless quiet. */
plm_result plm_fiber_medulla_build(const plm_fiber_params *p, plm_fiber_medulla_table *m, int threads, int quiet,
                                   double started, plm_error *err);

/* The largest |h| whose paths meet the medulla, seen from |theta_o| of
 * sine sin_theta and cosine cos_theta: min(1, r eta'), eta' the Bravais
 * index sqrt(eta^2 - sin^2) / cos, for a rotationally symmetric table (a
 * path refracted at offset h runs at distance |h| / eta' from the axis, and
 * reflections keep that distance); 1 for any other. */
double plm_fiber_medulla_reach(const plm_fiber_medulla_table *m, double sin_theta, double cos_theta);

/* A prepared query: the weighted rows (terms) of the four view nodes around
 * wo whose sum is the mean over [h-, h+] between the nodes, as the other
 * part's (optics/fiber_table.h), and the part's energy. */
#define PLM_FIBER_MEDULLA_TERMS 16 /* four nodes, four rows each */
typedef struct plm_fiber_medulla_query {
    const plm_fiber_medulla_table *table; /* NULL: no medulla part */
    const float *term[PLM_FIBER_MEDULLA_TERMS];
    double coef[PLM_FIBER_MEDULLA_TERMS]; /* a node's bilinear weight times the row's h weight */
    int terms, flip;
    int node_end[4];    /* node c's terms end here, the next node's begin (sampling reads one node's) */
    double node_sum[4]; /* node c's energy, the sum of RGB, at least 0 */
    double sum;         /* the part's energy: the nodes' sum ... */
    double total;       /* ... and its mean of RGB */
    double phi_o;  /* of wo */
    double band_width, bin_width; /* of a |theta_i| band and a phi_i bin */
    double origin; /* the columns' azimuth is the relative azimuth delta (below) plus this */
    /* Factored tables: the light reaching each medulla point, its mean over
     * the interval blended over the view nodes (RGB, w[channel][point]);
     * wbar, its mean over RGB (at least 0), by which sampling and pdf weight
     * the points' emission (mean of RGB); norm, the sum over the points of
     * wbar times the point's emitted energy. */
    float w[3][PLM_FIBER_MEDULLA_POINTS], wbar[PLM_FIBER_MEDULLA_POINTS];
    double norm;
} plm_fiber_medulla_query;

/* v: wo and the interval as both parts see them (optics/fiber_table.h). */
void plm_fiber_medulla_prepare(const plm_fiber_medulla_table *m, const plm_fiber_view *v,
                               plm_fiber_medulla_query *q);
/* At wi given by its angles in the table's orientation (theta_i, delta =
 * phi_i - phi_o, mirrored when the view is, cos(theta_i)): eval into *f (if
 * not NULL), the bins' densities per solid angle interpolated bilinearly
 * between bin centres, over cos(theta_i); and the sampler's
 * piecewise-constant solid-angle density into *pdf (if not NULL; one of
 * the two is asked for). */
void plm_fiber_medulla_lookup(const plm_fiber_medulla_query *q, const double angles[3], rgb *f, double *pdf);
/* A view node by its energy and a |theta_i| band by its mass in that node
 * (u0), the sign of theta_i and the position in the band (u1), a phi_i bin
 * by the band's cumulative row (u2), uniform within the bin: the direction
 * into wi, its angles (as the lookup takes them) into angles. Returns 0 if
 * there is nothing to sample. */
int plm_fiber_medulla_sample(const plm_fiber_medulla_query *q, double u0, double u1, double u2, double angles[3],
                             vec3 *wi);

#endif
