/* The grid both parts of the tabulated fiber BCSDF are laid on and read
 * through (optics/fiber_table.h, optics/fiber_medulla_table.h): the
 * symmetries, the |theta_o|, phi_o and h nodes, a view in the tables' terms,
 * the rows and weighted terms a query combines, the energy scale, the
 * samplers' search, and the builds' thread pool (docs/fiber.md). */
#ifndef PLUMAGE_OPTICS_FIBER_GRID_H
#define PLUMAGE_OPTICS_FIBER_GRID_H

#include <stddef.h>

#include "common/vec.h"
#include "optics/fiber_trace.h"

/* Which mirror symmetries of the cross-section the table exploits. */
enum {
    PLM_FIBER_TABLE_ROTATIONAL = 0, /* circular cortex, no or a centred circular medulla: one phi_o node */
    PLM_FIBER_TABLE_MIRROR_XY = 1,  /* phi_o in [0, pi/2] */
    PLM_FIBER_TABLE_MIRROR_X = 2,   /* medulla off the e3 axis only along e3 (x -> -x): phi_o in [-pi/2, pi/2] */
    PLM_FIBER_TABLE_MIRROR_Y = 3,   /* y -> -y: phi_o in [0, pi] */
    PLM_FIBER_TABLE_NONE = 4        /* phi_o all around */
};

/* h cell bounds
 * uniform in asin(h) (malloc'ed, NULL when out of memory) and the number of
 * h samples per cell the builds take (the same h in both parts where the
 * medulla's rows run over h, so their energies add up); phi_o of the first
 * node and the step between nodes for a symmetry; the two phi_o nodes
 * around a folded phi_o and the fraction between them; and the wrapped
 * Gaussian G_N's mass in each of `bins` bins over [-pi, pi) times A, added
 * to cell (RGB per bin). */
double *plm_fiber_h_nodes(int cells);
/* The |theta_o| nodes of docs/fiber.md (denser toward grazing): u(theta), the
 * inverse Bravais index; the node coordinate (0 .. nodes - 1) of theta given
 * with its sine and cosine, u_last = u(theta_max); node k's theta. */
/* theta_o nodes are uniform in the mean of theta_o / theta_max and of
 * (u_first - u) / (u_first - u_last), where u = cos(theta_o) / sqrt(eta^2 -
 * sin^2(theta_o)) is the inverse of the Bravais index that bends azimuths
 * inside the fiber. Lobes move about evenly with u, which near grazing, where
 * the index grows without bound, changes much faster than theta_o; the
 * theta_o half keeps the nodes dense enough at moderate angles, where the
 * Fresnel energies still change (docs/fiber.md). */
static inline double plm_fiber_inverse_index(double eta, double sin_theta, double cos_theta)
{
    return cos_theta / sqrt(eta * eta - sin_theta * sin_theta);
}
double plm_fiber_theta_u(double eta, double theta);
double plm_fiber_theta_coordinate(double eta, double u_last, double theta_max, int nodes, double theta,
                                  double sin_theta, double cos_theta);
double plm_fiber_node_theta(double eta, double u_last, double theta_max, int nodes, int k);
int plm_fiber_h_sub_samples(double beta_n, int cells); /* per cell, midpoint rule in asin(h) */
void plm_fiber_phi_nodes(int symmetry, int phi_nodes, double *phi_lo, double *phi_step);
void plm_fiber_phi_weights(int symmetry, int phi_nodes, double phi_lo, double phi_step, double phi, int ip[2],
                           double *frac);
void plm_fiber_gn_deposit(double *cell, int bins, double beta, rgb A, double delta);
/* A prepare's steps shared by both parts: wo and the h-interval in the
 * tables' terms (0 at the poles or for an empty interval); the rows and
 * coefficients (at most 4) whose combination of cumulative rows is the mean
 * over the view's interval; the four nodes (|theta_o| node it, phi_o node
 * ip: index it phi_nodes + ip) around the view and their bilinear weights,
 * given |theta_o|'s node coordinate ft and the folded phi_o; and the
 * weighted rows (terms, at most 16) whose sum is the interval's mean
 * between those nodes: node c's row rows->row[r] with weight w[c]
 * rows->coef[r], the nodes node_floats and the rows row_floats apart in
 * data, node by node (node_end, if not NULL: where each node's terms end).
 * Returns the number of terms. */
typedef struct plm_fiber_view {
    double theta_o, phi_o;       /* wo's angles */
    double sin_theta, cos_theta; /* of |theta_o| */
    double phi;                  /* phi_o folded into the symmetry's range */
    int flip;                    /* the mirrored view: relative azimuths and h change sign */
    double hmin, hmax;           /* the interval in the folded view, within [-1, 1] ... */
    double asin_hmin, asin_hmax; /* ... and their asin (h cells are uniform in it) */
} plm_fiber_view;
int plm_fiber_view_of(int symmetry, vec3 wo, double hmin, double hmax, plm_fiber_view *v);
typedef struct plm_fiber_h_rows {
    int row[4];
    double coef[4];
    int n;
} plm_fiber_h_rows;
/* An h-interval narrower than this counts as a point (the density at its
 * h): the mean over an interval divides by its width, 0 / 0 at a point and
 * mostly rounding near one. */
#define PLM_FIBER_POINT_WIDTH 1e-9
/* The cell of h (given with its asin, as cells are uniform in it) and h's
 * fraction across it. */
static inline int plm_fiber_h_cell(const double *h_node, int cells, double h, double asin_h, double *frac)
{
    int j = (int)floor((asin_h + 0.5 * PLM_PI) / PLM_PI * cells);
    j = j < 0 ? 0 : j >= cells ? cells - 1 : j;
    double lo = h_node[j], hi = h_node[j + 1];
    *frac = plm_clamp((h - lo) / (hi - lo), 0.0, 1.0);
    return j;
}
/* Adds coef to row j of l (a new row if l has none). */
static inline void plm_fiber_rows_add(plm_fiber_h_rows *l, int j, double coef)
{
    for (int r = 0; r < l->n; ++r)
        if (l->row[r] == j) {
            l->coef[r] += coef;
            return;
        }
    l->row[l->n] = j;
    l->coef[l->n++] = coef;
}
void plm_fiber_interval_rows(const double *h_node, int cells, const plm_fiber_view *v, plm_fiber_h_rows *rows);
/* The interval's energy at one |theta_o| node, blended between its two
 * phi_o nodes (fraction fp) from their cell bounds' energies b0 and b1:
 * the rows' combination of them. */
static inline double plm_fiber_rows_energy(const float *b0, const float *b1, double fp, const plm_fiber_h_rows *rows)
{
    const float *b[2] = {b0, b1};
    double e = 0.0;
    for (int j = 0; j < 2; ++j) {
        double wj = j ? fp : 1.0 - fp;
        if (!(wj > 0.0))
            continue;
        for (int r = 0; r < rows->n; ++r)
            e += wj * rows->coef[r] * b[j][rows->row[r]];
    }
    return e;
}
/* The blend's energy scale of tables without lobe records (docs/fiber.md):
 * the first of the three |theta_o| nodes through which the interval's
 * energy is interpolated at node coordinate ft (-1: fewer than three
 * nodes), and the scale from their energies e[0..2] (mean of RGB): the
 * quadratic through them in cos(|theta_o|) at cos_theta (not past the last
 * node) over the linear blend of the two nodes around ft, 1 if that is 0. */
int plm_fiber_energy_first(int theta_nodes, double ft);
double plm_fiber_energy_scale(const double *node_cos, int theta_nodes, double ft, double cos_theta, const double e[3]);
void plm_fiber_corners(int symmetry, int theta_nodes, int phi_nodes, double phi_lo, double phi_step, double ft,
                       double phi, int nodes[4], double w[4]);
int plm_fiber_terms(const float *data, size_t node_floats, size_t row_floats, const int nodes[4], const double w[4],
                    const plm_fiber_h_rows *rows, const float **term, double *coef, int *node_end);
/* The column to probe next when searching a cumulative row for the columns
 * lo < hi around goal (their values x0 <= goal < x1): the first three probes
 * where the row, taken as linear between them, reaches goal (a row is
 * smooth over a few columns, so two or three probes tend to do), then
 * bisection (in case it is not). Both parts' samplers search this way. */
static inline int plm_fiber_search_probe(int probe, int lo, int hi, double x0, double x1, double goal)
{
    int mid = probe < 3 ? lo + (int)((goal - x0) / (x1 - x0) * (hi - lo) + 0.5) : (lo + hi) / 2;
    return mid <= lo ? lo + 1 : mid >= hi ? hi - 1 : mid;
}
/* Runs work(ctx, item, scratch, lobes) for items 0..items-1 on `threads`
 * threads (0: all cores), each thread with scratch_bytes of scratch and room
 * for `lobes` lobes, showing "what" and the progress on stderr (unless
 * quiet) once `started` (plm_seconds, common/clock.h) is a second ago; returns 0 when
 * out of memory. */
typedef void (*plm_fiber_work)(void *ctx, int item, double *scratch, plm_fiber_lobe *lobes);
int plm_fiber_parallel(plm_fiber_work work, void *ctx, int items, size_t scratch_bytes, int lobes, int threads,
                       int quiet, const char *what, double started);

#endif
