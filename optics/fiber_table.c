/* The tabulated fiber BCSDF: building the table, and eval / pdf / sample from
 * it (docs/fiber.md has the design, its resolution and its error).
 *
 * Notation: Delta = phi_i - phi_o is the azimuth relative to the view, cut
 * into phi_bins bins over [-pi, pi). For a node (theta_o, phi_o) the table
 * holds S(j, c) for rows j = 0..its h cells and columns c = 0..phi_bins, as the
 * mean of RGB, R and G (B = 3 mean - R - G), so that sampling and pdf read one
 * channel:
 *   S(j, c) = integral over h in [h_0, h_j] and Delta below bin c's start of
 *             sum_k A_k(h) G_N(Delta - Delta_k(h)) over the lobes that never
 *             met the medulla,
 * a summed-area table in (h, Delta): the mass of the whole cells an
 * interval covers is a difference of two rows, the bin masses differences
 * of adjacent columns. After the rows, per cell bound h_j and lobe k, the
 * lobe's (Delta_k, A_k RGB) at h_j: within the partial cells at an
 * interval's ends a lobe is taken to move and change linearly in h, and its
 * G_N's mean over the piece is integrated in closed form (moving lobes). */
#include "optics/fiber_table.h"
#include "common/clock.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/vector_clones.h"

#define HALF_PI (0.5 * PLM_PI)

/* ---- layout -------------------------------------------------------------- */

static size_t row_floats(const plm_fiber_table *t) { return 3 * (size_t)(t->phi_bins + 1); }
/* Per node the rows (bounds 0..its h cells), then per bound its lobe
 * records and the flag of the cell above it (bound_records). */
static size_t record_floats(const plm_fiber_table *t) { return t->lobe_slots ? 4 * (size_t)t->lobe_slots + 1 : 0; }
static size_t bound_floats(const plm_fiber_table *t) { return row_floats(t) + record_floats(t); }
/* |theta_o| node it's h cells and their bounds: the last grazing_nodes
 * nodes have grazing_cells (docs/fiber.md). */
static int grazing(const plm_fiber_table *t, int it) { return it >= t->theta_nodes - t->grazing_nodes; }
static int cells_at(const plm_fiber_table *t, int it) { return grazing(t, it) ? t->grazing_cells : t->h_cells; }
static const double *bounds_at(const plm_fiber_table *t, int it)
{
    return grazing(t, it) ? t->h_node_grazing : t->h_node;
}
static size_t node_floats(const plm_fiber_table *t, int it) { return (size_t)(cells_at(t, it) + 1) * bound_floats(t); }
/* Nodes are stored by |theta_o| node, then phi_o node: the floats before
 * |theta_o| node it's first (all of them for it = theta_nodes). */
static size_t level_start(const plm_fiber_table *t, int it)
{
    int coarse = t->theta_nodes - t->grazing_nodes, below = it < coarse ? it : coarse;
    size_t rows = (size_t)below * (t->h_cells + 1) + (size_t)(it - below) * (t->grazing_cells + 1);
    return rows * (size_t)t->phi_nodes * bound_floats(t);
}
static float *node_data(const plm_fiber_table *t, int node)
{
    int it = node / t->phi_nodes;
    return t->data + level_start(t, it) + node_floats(t, it) * (size_t)(node % t->phi_nodes);
}
/* A node's lobe records at cell bound j: (Delta_k, A_k RGB) per slot k
 * (the lobe's wall hits), then cell j's flag (h_j to h_j+1): 1 if its lobes
 * move linearly enough across it to be integrated as moving lobes, else 0. */
static float *bound_records(const plm_fiber_table *t, int node, int j)
{
    int cells = cells_at(t, node / t->phi_nodes);
    return node_data(t, node) + (size_t)(cells + 1) * row_floats(t) + record_floats(t) * (size_t)j;
}
static double bin_width(const plm_fiber_table *t) { return PLM_TWO_PI / t->phi_bins; }

/* The |theta_o| nodes over [0, theta_max], placed by u: all but the limit node. */
static int placed_nodes(const plm_fiber_table *t) { return t->theta_nodes - t->limit_node; }

/* The node coordinate (0 .. theta_nodes - 1) of |theta_o| in [0, pi/2],
 * given with its sine and cosine. A limit node is reached linearly in u
 * from theta_max: the internal lobes' energies fall about in proportion to
 * cos(theta_o), hence to u, toward grazing views (docs/fiber.md). */
static double theta_coordinate(const plm_fiber_table *t, double theta, double sin_theta, double cos_theta)
{
    int placed = placed_nodes(t);
    if (theta < t->theta_max || !t->limit_node)
        return plm_fiber_theta_coordinate(t->params.eta, t->u_last, t->theta_max, placed, theta, sin_theta,
                                          cos_theta);
    double u = plm_fiber_inverse_index(t->params.eta, sin_theta, cos_theta);
    return placed - 1.0 + plm_clamp((t->u_last - u) / (t->u_last - t->u_limit), 0.0, 1.0);
}

static double node_theta(const plm_fiber_table *t, int k)
{
    int placed = placed_nodes(t);
    return k < placed ? plm_fiber_node_theta(t->params.eta, t->u_last, t->theta_max, placed, k)
                      : PLM_FIBER_THETA_LIMIT;
}

/* The bytes a table aims at: o's budget_mib, kept within its range; 0 or
 * less (or no o) the default. */
static size_t budget_bytes(const plm_fiber_table_options *o)
{
    int mib = o ? o->budget_mib : 0;
    if (mib <= 0)
        return PLM_FIBER_TABLE_BUDGET;
    if (mib < PLM_FIBER_TABLE_MIB_MIN)
        mib = PLM_FIBER_TABLE_MIB_MIN;
    if (mib > PLM_FIBER_TABLE_MIB_MAX)
        mib = PLM_FIBER_TABLE_MIB_MAX;
    return (size_t)mib << 20;
}

/* n cells refined by a factor, to the nearest multiple of 8 (so that a budget
 * just above the default keeps the default cells, not fewer phi_o nodes). */
static int refined_cells(int n, double refine) { return (int)lround(n * refine / 8.0) * 8; }

/* Resolution and symmetry for p: the defaults of docs/fiber.md unless o sets them. */
void plm_fiber_table_layout(const plm_fiber_params *p, const plm_fiber_table_options *o, plm_fiber_table *t)
{
    memset(t, 0, sizeof *t);
    t->params = *p;
    int medulla = plm_fiber_has_medulla(p);
    int centred_x = !medulla || p->medulla_ca == 0.0, centred_y = !medulla || p->medulla_cb == 0.0;
    int circular = p->eccentricity == 1.0 && (!medulla || (centred_x && centred_y && p->medulla_a == p->medulla_b));
    t->symmetry = circular                   ? PLM_FIBER_TABLE_ROTATIONAL
                  : centred_x && centred_y ? PLM_FIBER_TABLE_MIRROR_XY
                  : centred_x              ? PLM_FIBER_TABLE_MIRROR_X
                  : centred_y              ? PLM_FIBER_TABLE_MIRROR_Y
                                           : PLM_FIBER_TABLE_NONE;
    /* A rotationally symmetric fiber needs one phi_o node, so it can afford
     * fine h cells and theta_o nodes, and four bins per beta_n, which keep
     * eval's reconstruction between bins well within 0.5% of a lobe's
     * peak. Otherwise the errors of interpolating between phi_o nodes and
     * within h cells are far larger than that of two bins per beta_n, and
     * the memory goes to h cells and phi_o nodes (docs/fiber.md has the
     * errors). */
    int round_fiber = t->symmetry == PLM_FIBER_TABLE_ROTATIONAL;
    plm_fiber_medulla_layout(p, t->symmetry, o ? &o->medulla : NULL, &t->medulla);
    /* The medulla's part first (an override may take all of it: the other part then gets its least). */
    size_t whole = budget_bytes(o);
    size_t medulla_bytes = sizeof(float) * t->medulla.floats;
    size_t budget = medulla_bytes < whole ? whole - medulla_bytes : 0;
    /* Beyond the default budget an elliptical table refines its |theta_o|
     * nodes, h cells and phi_o nodes alike, by the cube root of the ratio:
     * its error is resolution in all three at once, and any one refined
     * alone buys little (docs/fiber.md). */
    double refine = whole > PLM_FIBER_TABLE_BUDGET ? cbrt((double)whole / (double)PLM_FIBER_TABLE_BUDGET) : 1.0;
    int bins = (int)ceil((round_fiber ? 4.0 : 2.0) * PLM_TWO_PI / p->beta_n);
    bins = (bins + 31) / 32 * 32;
    t->phi_bins = o && o->phi_bins > 0 ? o->phi_bins : bins < 64 ? 64 : bins > 2048 ? 2048 : bins;
    /* A circular table also has a node next to grazing views, past theta_max
     * (without it, the 89 deg node served every view beyond and was 3% off
     * at 89.3 deg); elliptical ones measured no better with it (docs/fiber.md). */
    t->limit_node = round_fiber;
    t->theta_nodes = (o && o->theta_nodes > 1 ? o->theta_nodes : round_fiber ? 60 : (int)lround(12 * refine)) +
                     t->limit_node;
    t->lobe_slots = round_fiber ? p->lobes : 0;
    size_t row_bytes = sizeof(float) * bound_floats(t);
    int rows = (int)(budget / (row_bytes * (size_t)t->theta_nodes));
    int h_set = o && o->h_cells > 0;
    t->h_cells = h_set         ? o->h_cells
                 : round_fiber ? (rows - 1 < 256 ? (rows - 1) / 8 * 8 : 256)
                               : refined_cells(56, refine);
    t->h_cells = t->h_cells < 8 ? 8 : t->h_cells;
    /* Toward grazing views a cell's mass spread evenly over it is off most
     * (the lobes sweep the azimuths faster as h runs through it): at the
     * default budget the last three nodes get 120 cells, and 56 at the
     * others keep the memory, so the phi_o nodes, of 72 everywhere
     * (docs/fiber.md has the errors); a larger budget refines both.
     * Tables with lobe records integrate partial cells as moving lobes. */
    if (!round_fiber) {
        int g = o && o->grazing_nodes != 0 ? o->grazing_nodes : 3;
        t->grazing_nodes = g < 0 ? 0 : g > t->theta_nodes ? t->theta_nodes : g;
        t->grazing_cells = o && o->grazing_cells > 0 ? o->grazing_cells
                           : h_set                   ? 2 * t->h_cells
                                                     : refined_cells(120, refine);
        t->grazing_cells = t->grazing_nodes == 0 ? 0 : t->grazing_cells;
    }
    t->theta_max = plm_radians(89.0);
    t->u_first = 1.0 / p->eta;
    t->u_last = plm_fiber_theta_u(p->eta, t->theta_max);
    t->u_limit = plm_fiber_theta_u(p->eta, PLM_FIBER_THETA_LIMIT);
    t->phi_nodes = 1;
    int nodes = (int)(budget / (sizeof(float) * level_start(t, t->theta_nodes)));
    nodes = o && o->phi_nodes > 0 ? o->phi_nodes : nodes;
    t->phi_nodes = round_fiber ? 1 : nodes < 3 ? 3 : nodes;
    plm_fiber_phi_nodes(t->symmetry, t->phi_nodes, &t->phi_lo, &t->phi_step);
    t->floats = level_start(t, t->theta_nodes) + t->medulla.floats;
}

/* ---- building ------------------------------------------------------------ */

/* A traced lobe's azimuth relative to the view, in [-pi, pi]. */
static double lobe_delta(const plm_fiber_lobe *l, double phi_o)
{
    return remainder(atan2(l->dir.y, l->dir.x) - phi_o, PLM_TWO_PI);
}

/* A node's lobe records: per cell bound h_j the lobes that never met the
 * medulla, traced at h_j, each in the slot of its wall hits (so a total
 * internal reflection, which stores no lobe, does not shift the lobes
 * after it to another slot). A lobe missing at a bound (absorbed, or the
 * path met the medulla or ended first) has A = 0 and the Delta of the
 * nearest bound where it exists, so that its position can still be
 * interpolated. Every cell's flag starts at 1 (check_linear clears it). */
static void build_lobe_records(const plm_fiber_table *t, int node, vec3 wo, double phi_o, plm_rng *rng,
                               plm_fiber_lobe *lobes)
{
    int it = node / t->phi_nodes, bounds = cells_at(t, it) + 1, L = t->lobe_slots;
    const double *h_node = bounds_at(t, it);
    for (int j = 0; j < bounds; ++j) {
        float *r = bound_records(t, node, j);
        r[4 * L] = 1.0f;
        for (int k = 0; k < L; ++k)
            r[4 * k] = NAN, r[4 * k + 1] = r[4 * k + 2] = r[4 * k + 3] = 0.0f;
        int n = plm_fiber_trace(&t->params, wo, h_node[j], rng, lobes);
        for (int i = 0; i < n && !lobes[i].medulla; ++i) {
            int k = lobes[i].wall_hits;
            if (k >= L || !(rgb_mean(lobes[i].throughput) > 0.0))
                continue;
            r[4 * k] = (float)lobe_delta(&lobes[i], phi_o);
            r[4 * k + 1] = (float)lobes[i].throughput.r;
            r[4 * k + 2] = (float)lobes[i].throughput.g;
            r[4 * k + 3] = (float)lobes[i].throughput.b;
        }
    }
    for (int k = 0; k < L; ++k) { /* missing positions: the previous bound's, before the first the next's */
        float last = NAN;
        for (int pass = 0; pass < 2; ++pass)
            for (int i = 0; i < bounds; ++i) {
                float *r = bound_records(t, node, pass ? bounds - 1 - i : i) + 4 * k;
                if (isnan(r[0]))
                    r[0] = last;
                else
                    last = r[0];
            }
        for (int j = 0; j < bounds; ++j) /* never present */
            if (isnan(bound_records(t, node, j)[4 * k]))
                bound_records(t, node, j)[4 * k] = 0.0f;
    }
}

/* Clears cell j's flag if the lobes traced at h, a fraction f across the
 * cell, stray from the straight line between the cell's bounds by more
 * than beta_n, or their weights by more than 2% of the energy (a lobe
 * that starts or stops meeting the medulla within the cell): then a
 * partial cell is taken from the rows (its mass spread evenly) instead.
 * lobes[0..n-1] are those before the first medulla bounce, delta[i] lobe
 * i's lobe_delta. */
static void check_linear(const plm_fiber_table *t, int node, int j, double f, const plm_fiber_lobe *lobes, int n,
                         const double *delta)
{
    float *r0 = bound_records(t, node, j), *r1 = bound_records(t, node, j + 1);
    int L = t->lobe_slots;
    double total = 0.0, off_weight = 0.0, off_place = 0.0;
    double traced[2 * PLM_FIBER_SET_MAX_LOBES][2] = {{0.0}};
    for (int i = 0; i < n; ++i) {
        double a = rgb_mean(lobes[i].throughput);
        total += a;
        if (lobes[i].wall_hits >= L) {
            off_weight += a;
            continue;
        }
        traced[lobes[i].wall_hits][0] = a;
        traced[lobes[i].wall_hits][1] = delta[i];
    }
    for (int k = 0; k < L; ++k) {
        const float *a = r0 + 4 * k, *b = r1 + 4 * k;
        double wa = (a[1] + a[2] + a[3]) / 3.0, wb = (b[1] + b[2] + b[3]) / 3.0, w = wa + f * (wb - wa);
        off_weight += fabs(traced[k][0] - w);
        double place = a[0] + f * remainder((double)b[0] - a[0], PLM_TWO_PI);
        if (traced[k][0] > 0.0)
            off_place = fmax(off_place, fabs(remainder(traced[k][1] - place, PLM_TWO_PI)));
    }
    if (off_place > t->params.beta_n || off_weight > 0.02 * total)
        r0[4 * L] = 0.0f;
}

/* One node: for each h cell, the bin masses of its lobes by the midpoint rule
 * in gamma = asin(h) (dh = cos(gamma) dgamma), then the summed rows. */
static void build_node(void *ctx, int node, double *scratch, plm_fiber_lobe *lobes)
{
    const plm_fiber_table *t = ctx;
    const plm_fiber_params *p = &t->params;
    int bins = t->phi_bins, it = node / t->phi_nodes, ip = node % t->phi_nodes, cells = cells_at(t, it);
    int sub_samples = plm_fiber_h_sub_samples(p->beta_n, cells); /* per cell, midpoint rule in asin(h) */
    const double *h_node = bounds_at(t, it);
    double theta_o = node_theta(t, it), phi_o = t->phi_lo + ip * t->phi_step;
    vec3 wo = plm_fiber_direction(theta_o, phi_o);
    plm_rng rng; /* drives only medulla bounces, whose lobes are left out */
    plm_rng_seed(&rng, 0x7ab1e, (uint64_t)node);
    double *cell = scratch, *row = scratch + 3 * bins;
    float *out = node_data(t, node);
    if (t->lobe_slots > 0)
        build_lobe_records(t, node, wo, phi_o, &rng, lobes);
    for (size_t c = 0; c < row_floats(t); ++c)
        row[c] = out[c] = 0.0f;
    double dgamma = PLM_PI / cells / sub_samples;
    for (int j = 0; j < cells; ++j) {
        memset(cell, 0, sizeof(double) * 3 * (size_t)bins);
        for (int m = 0; m < sub_samples; ++m) {
            double gamma = -HALF_PI + (j * sub_samples + m + 0.5) * dgamma, h = sin(gamma);
            double dh = cos(gamma) * dgamma;
            int n = plm_fiber_trace(p, wo, h, &rng, lobes), direct = 0;
            double delta[PLM_FIBER_SET_MAX_LOBES]; /* of the lobes before the first medulla bounce */
            for (; direct < n && !lobes[direct].medulla; ++direct) {
                delta[direct] = lobe_delta(&lobes[direct], phi_o);
                plm_fiber_gn_deposit(cell, bins, p->beta_n, rgb_scale(lobes[direct].throughput, dh), delta[direct]);
            }
            if (t->lobe_slots > 0)
                check_linear(t, node, j, (h - h_node[j]) / (h_node[j + 1] - h_node[j]), lobes, direct, delta);
        }
        /* S(j + 1, c) = S(j, c) + the cell's mass below column c, summed in double. */
        float *dst = out + row_floats(t) * (size_t)(j + 1);
        for (int ch = 0; ch < 3; ++ch) {
            double below = 0.0;
            for (int c = 0; c <= bins; ++c) {
                row[3 * c + ch] += below;
                if (c < bins)
                    below += cell[3 * c + ch];
            }
        }
        for (int c = 0; c <= bins; ++c) {
            const double *v = row + 3 * c;
            dst[3 * c] = (float)((v[0] + v[1] + v[2]) / 3.0);
            dst[3 * c + 1] = (float)v[0];
            dst[3 * c + 2] = (float)v[1];
        }
    }
}

/* Fills t->data (allocated by the caller) on all cores, showing progress on
 * stderr once the build has taken a second. */
plm_result plm_fiber_table_build(plm_fiber_table *t, const plm_fiber_table_options *o, plm_error *err)
{
    double t0 = plm_seconds();
    int threads = o ? o->threads : 0, quiet = o && o->quiet;
    if (!plm_fiber_parallel(build_node, t, t->theta_nodes * t->phi_nodes,
                            sizeof(double) * 3 * (size_t)(2 * t->phi_bins + 1), t->params.lobes, threads, quiet,
                            "azimuths", t0))
        return plm_fail(err, PLM_ERR_NO_MEMORY, "fiber table: out of memory");
    plm_result rc = plm_fiber_medulla_build(&t->params, &t->medulla, threads, quiet, t0, err);
    if (rc != PLM_OK)
        return rc;
    t->build_seconds = plm_seconds() - t0;
    return PLM_OK;
}

/* Node `node`'s first entry in bound_energy (its bounds follow, as its rows do). */
static size_t node_bounds(const plm_fiber_table *t, int node)
{
    int it = node / t->phi_nodes;
    return level_start(t, it) / bound_floats(t) + (size_t)(cells_at(t, it) + 1) * (size_t)(node % t->phi_nodes);
}

void plm_fiber_table_bound_energies(plm_fiber_table *t)
{
    for (int node = 0; t->lobe_slots == 0 && node < t->theta_nodes * t->phi_nodes; ++node)
        for (int j = 0; j <= cells_at(t, node / t->phi_nodes); ++j)
            t->bound_energy[node_bounds(t, node) + (size_t)j] =
                node_data(t, node)[row_floats(t) * (size_t)j + 3 * (size_t)t->phi_bins];
    plm_fiber_medulla_bound_energies(&t->medulla);
}

/* Frees what plm_fiber_table_alloc allocated and leaves the pointers NULL. */
static void release_arrays(plm_fiber_table *t)
{
    plm_fiber_table_release_data(t);
    free(t->h_node);
    free(t->h_node_grazing);
    free(t->node_cos);
    free(t->bound_energy);
    plm_fiber_medulla_release(&t->medulla);
    t->h_node = t->h_node_grazing = t->node_cos = NULL;
    t->bound_energy = NULL;
}

plm_result plm_fiber_table_alloc(plm_fiber_table *t, plm_error *err)
{
    if (!t->data) /* else mapped from the cache */
        t->data = malloc(sizeof(float) * t->floats);
    t->h_node = plm_fiber_h_nodes(t->h_cells);
    t->h_node_grazing = t->grazing_nodes > 0 ? plm_fiber_h_nodes(t->grazing_cells) : NULL;
    t->node_cos = malloc(sizeof(double) * (size_t)t->theta_nodes);
    t->bound_energy = t->lobe_slots == 0 ? malloc(sizeof(float) * (level_start(t, t->theta_nodes) / bound_floats(t)))
                                         : NULL;
    for (int k = 0; t->node_cos && k < t->theta_nodes; ++k)
        t->node_cos[k] = cos(node_theta(t, k));
    if (t->data)
        t->medulla.data = t->data + (t->floats - t->medulla.floats);
    if (!t->data || !t->h_node || (t->grazing_nodes > 0 && !t->h_node_grazing) || !t->node_cos ||
        (t->lobe_slots == 0 && !t->bound_energy) ||
        plm_fiber_medulla_alloc(&t->medulla, err) != PLM_OK) {
        release_arrays(t);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "fiber table: out of memory (%zu MB)",
                        sizeof(float) * t->floats >> 20);
    }
    return PLM_OK;
}

void plm_fiber_table_free(plm_fiber_table *t)
{
    if (!t)
        return;
    release_arrays(t);
    free(t);
}

size_t plm_fiber_table_bytes(const plm_fiber_table *t)
{
    size_t grazing_bounds = t->grazing_nodes > 0 ? (size_t)t->grazing_cells + 1 : 0;
    size_t energies = t->lobe_slots == 0 ? level_start(t, t->theta_nodes) / bound_floats(t) : 0; /* bound_energy */
    size_t medulla_energies = t->medulla.factored ? (size_t)t->medulla.res.theta_nodes * t->medulla.res.phi_nodes *
                                                        (size_t)(t->medulla.res.h_cells + 1)
                                                  : 0;
    return sizeof *t + sizeof(float) * (t->floats + energies + medulla_energies) +
           sizeof(double) * ((size_t)t->h_cells + 1 + grazing_bounds + (size_t)t->theta_nodes) +
           sizeof(double) * ((size_t)t->medulla.res.h_cells + 1 + (size_t)t->medulla.res.theta_nodes);
}

/* ---- queries ------------------------------------------------------------- */

/* plm_wrap_pi for |a| < 3 pi, without floor (a library call on plain x86-64). */
static PLM_VECTOR_INLINE double wrap_near(double a)
{
    a = a > PLM_PI ? a - PLM_TWO_PI : a < -PLM_PI ? a + PLM_TWO_PI : a;
    return a > PLM_PI ? a - PLM_TWO_PI : a < -PLM_PI ? a + PLM_TWO_PI : a;
}

/* The interval's mean at column col: channel 0 (mean of RGB) ... */
static PLM_VECTOR_INLINE double column_mean(const plm_fiber_table_query *q, int col)
{
    double m = 0.0;
    for (int k = 0; k < q->terms; ++k)
        m += q->coef[k] * q->term[k][3 * col];
    return m;
}

/* ... and the masses of count (1 to 3) adjacent bins from bin b on, in all
 * three channels, as (mean, R, G): count + 1 columns, read once per term. */
static PLM_VECTOR_INLINE void bin_masses(const plm_fiber_table_query *q, int b, int count, double mass[][3])
{
    double col[4][3] = {{0.0}};
    for (int k = 0; k < q->terms; ++k) {
        const float *v = q->term[k] + 3 * b;
        for (int i = 0; i < 3 * (count + 1); ++i)
            col[i / 3][i % 3] += q->coef[k] * v[i];
    }
    for (int i = 0; i < count; ++i)
        for (int ch = 0; ch < 3; ++ch)
            mass[i][ch] = col[i + 1][ch] - col[i][ch];
}

/* Lobe k (a slot) across a cell seen from the view between the four nodes
 * (weights w), from its records r0, r1 at the cell's bounds at each node:
 * its place at the lower bound into *place and its motion across the cell
 * into *motion (both weighted means over the nodes where the lobe exists
 * at either bound), its weight (R, G, B) at the bounds into a0, a1
 * (weighted sums). So a lobe moves between nodes rather than fading out at
 * one place and in at another (its slot names it at every node), and
 * linearly in h across the cell. Returns 0 if it exists nowhere. */
static int lobe_across(const float *const r0[4], const float *const r1[4], const double w[4], int k, double *place,
                       double *motion, double a0[3], double a1[3])
{
    double ref = 0.0, shift = 0.0, move = 0.0, weight = 0.0;
    a0[0] = a0[1] = a0[2] = a1[0] = a1[1] = a1[2] = 0.0;
    for (int c = 0; c < 4; ++c) {
        if (!(w[c] > 0.0))
            continue;
        const float *lo = r0[c] + 4 * k, *hi = r1[c] + 4 * k;
        for (int ch = 0; ch < 3; ++ch) {
            a0[ch] += w[c] * lo[1 + ch];
            a1[ch] += w[c] * hi[1 + ch];
        }
        if (lo[1] + lo[2] + lo[3] + hi[1] + hi[2] + hi[3] > 0.0f) {
            if (weight == 0.0)
                ref = lo[0];
            shift += w[c] * wrap_near(lo[0] - ref);
            move += w[c] * wrap_near((double)hi[0] - lo[0]);
            weight += w[c];
        }
    }
    if (!(weight > 0.0))
        return 0;
    *place = ref + shift / weight;
    *motion = move / weight;
    return 1;
}

/* The piece of cell j from fraction f0 to f1, its share of the interval
 * `share`, seen between the four nodes: a whole cell from the rows; part of
 * one as moving lobes where the lobes of every node move linearly enough
 * across the cell (the cell's flag); else from the rows too, the cell's
 * mass taken as spread evenly over it. */
static void add_piece(const plm_fiber_table *t, const int nodes[4], const double w[4], int j, double f0, double f1,
                      double share, plm_fiber_h_rows *rows, plm_fiber_table_query *q)
{
    if (!(share > 0.0))
        return;
    int from_rows = (f0 <= 0.0 && f1 >= 1.0) || q->moving_count + t->lobe_slots > PLM_FIBER_TABLE_MOVING;
    for (int c = 0; c < 4 && !from_rows; ++c)
        from_rows = w[c] > 0.0 && bound_records(t, nodes[c], j)[4 * t->lobe_slots] == 0.0f;
    if (from_rows) {
        double coef = share / (t->h_node[j + 1] - t->h_node[j]);
        plm_fiber_rows_add(rows, j + 1, coef);
        plm_fiber_rows_add(rows, j, -coef);
        return;
    }
    const float *r0[4], *r1[4];
    for (int c = 0; c < 4; ++c) {
        r0[c] = bound_records(t, nodes[c], j);
        r1[c] = bound_records(t, nodes[c], j + 1);
    }
    for (int k = 0; k < t->lobe_slots; ++k) {
        double place, motion, a0[3], a1[3];
        if (!lobe_across(r0, r1, w, k, &place, &motion, a0, a1))
            continue;
        plm_fiber_table_moving_lobe *m = &q->moving[q->moving_count++];
        m->delta0 = (float)wrap_near(place + f0 * motion);
        m->slope = (float)((f1 - f0) * motion);
        for (int ch = 0; ch < 3; ++ch) {
            m->a0[ch] = (float)((a0[ch] + f0 * (a1[ch] - a0[ch])) * share);
            m->a1[ch] = (float)((a0[ch] + f1 * (a1[ch] - a0[ch])) * share);
        }
    }
}

/* A moving lobe's energy (mean of RGB), as sampling picks it. */
static double moving_mass(const plm_fiber_table_moving_lobe *m)
{
    return ((double)m->a0[0] + m->a0[1] + m->a0[2] + m->a1[0] + m->a1[1] + m->a1[2]) / 6.0;
}

/* The interval's pieces in a table with lobe records (every node's h
 * cells alike): the whole cells j0 + 1 .. j1 - 1 from the rows, the partial
 * cells at the ends as pieces (add_piece); an interval inside one cell is
 * one piece, a zero-width one the density at its h. */
static void interval_pieces(const plm_fiber_table *t, const plm_fiber_view *v, const int nodes[4],
                            const double w[4], plm_fiber_h_rows *rows, plm_fiber_table_query *q)
{
    double f0, f1, hmin = v->hmin, hmax = v->hmax, width = hmax - hmin;
    int j0 = plm_fiber_h_cell(t->h_node, t->h_cells, hmin, v->asin_hmin, &f0);
    int j1 = plm_fiber_h_cell(t->h_node, t->h_cells, hmax, v->asin_hmax, &f1);
    if (width < PLM_FIBER_POINT_WIDTH) {
        add_piece(t, nodes, w, j0, f0, f0, 1.0, rows, q);
    } else if (j0 == j1) {
        add_piece(t, nodes, w, j0, f0, f1, 1.0, rows, q);
    } else {
        double inv = 1.0 / width;
        add_piece(t, nodes, w, j0, f0, 1.0, (t->h_node[j0 + 1] - hmin) * inv, rows, q);
        add_piece(t, nodes, w, j1, 0.0, f1, (hmax - t->h_node[j1]) * inv, rows, q);
        plm_fiber_rows_add(rows, j1, inv);
        plm_fiber_rows_add(rows, j0 + 1, -inv);
    }
}

/* The interval's rows in each of a table's two sets of h cells (the
 * grazing nodes' and the others'), found once per prepare: the energy
 * scale and the terms read the same ones. */
typedef struct interval_rows_cache {
    plm_fiber_h_rows rows[2];
    int found[2];
} interval_rows_cache;

static const plm_fiber_h_rows *rows_at(const plm_fiber_table *t, const plm_fiber_view *v, int it,
                                       interval_rows_cache *cache)
{
    int g = grazing(t, it);
    if (!cache->found[g]) {
        plm_fiber_interval_rows(bounds_at(t, it), cells_at(t, it), v, &cache->rows[g]);
        cache->found[g] = 1;
    }
    return &cache->rows[g];
}

/* The interval's energy (mean of RGB) at |theta_o| node `level` between
 * its phi_o nodes ip[0], ip[1] (fraction fp): its rows' last columns, read
 * from their copies side by side (bound_energy). Only for tables without
 * lobe records (their rows run over the whole interval). */
static double level_energy(const plm_fiber_table *t, const plm_fiber_view *v, int level, const int ip[2], double fp,
                           interval_rows_cache *cache)
{
    const float *b = t->bound_energy;
    return plm_fiber_rows_energy(b + node_bounds(t, level * t->phi_nodes + ip[0]),
                                 b + node_bounds(t, level * t->phi_nodes + ip[1]), fp, rows_at(t, v, level, cache));
}

/* Without lobe records (elliptical cortex or off-centre medulla), the
 * factor by which the four corners' bilinear blend is scaled: the
 * interval's energy interpolated quadratically in cos(|theta_o|) through
 * three |theta_o| nodes (the two around the view and the one below, the
 * one above for the first pair) over the energy of the linear blend. The
 * lobes' weights change nonlinearly between nodes toward grazing views,
 * the reflection rising and the light through the cortex falling; the
 * scale fixes the blend's energy and leaves its shape (docs/fiber.md). */
static double energy_scale(const plm_fiber_table *t, const plm_fiber_view *v, double ft, interval_rows_cache *cache)
{
    int ip[2], first = plm_fiber_energy_first(t->theta_nodes, ft);
    double e[3], fp;
    if (first < 0)
        return 1.0;
    plm_fiber_phi_weights(t->symmetry, t->phi_nodes, t->phi_lo, t->phi_step, v->phi, ip, &fp);
    for (int k = 0; k < 3; ++k)
        e[k] = level_energy(t, v, first + k, ip, fp, cache);
    return plm_fiber_energy_scale(t->node_cos, t->theta_nodes, ft, v->cos_theta, e);
}

void plm_fiber_table_prepare(const plm_fiber_table *t, const plm_fiber_view *v, plm_fiber_table_query *q)
{
    q->theta_o = v->theta_o;
    q->phi_o = v->phi_o;
    q->bin_width = bin_width(t);
    q->flip = v->flip;
    plm_fiber_gm_detector_about(t->params.beta_m, -q->theta_o, &q->gm);
    double ft = theta_coordinate(t, fabs(q->theta_o), v->sin_theta, v->cos_theta);
    int nodes[4];
    double w[4];
    plm_fiber_corners(t->symmetry, t->theta_nodes, t->phi_nodes, t->phi_lo, t->phi_step, ft, v->phi, nodes, w);
    interval_rows_cache cache = {.found = {0, 0}};
    if (t->lobe_slots == 0 && !t->limit_node) {
        double scale = energy_scale(t, v, ft, &cache);
        for (int c = 0; c < 4; ++c)
            w[c] *= scale;
    }
    plm_fiber_h_rows pieces_rows = {.n = 0};
    q->moving_count = 0;
    if (t->lobe_slots > 0)
        interval_pieces(t, v, nodes, w, &pieces_rows, q);
    /* The terms of each |theta_o| node (corners 0, 1 and 2, 3), in its own h
     * cells: without lobe records the interval's rows within them. */
    q->terms = 0;
    for (int level = 0; level < 2; ++level) {
        int it = nodes[2 * level] / t->phi_nodes, local[4];
        double wl[4];
        for (int c = 0; c < 4; ++c) {
            local[c] = nodes[c] % t->phi_nodes;
            wl[c] = c / 2 == level ? w[c] : 0.0;
        }
        const plm_fiber_h_rows *rows = t->lobe_slots > 0 ? &pieces_rows : rows_at(t, v, it, &cache);
        q->terms += plm_fiber_terms(t->data + level_start(t, it), node_floats(t, it), row_floats(t), local, wl,
                                    rows, q->term + q->terms, q->coef + q->terms, NULL);
    }
    q->rows_total = q->terms > 0 ? plm_positive(column_mean(q, t->phi_bins)) : 0.0;
    q->total = q->rows_total;
    for (int i = 0; i < q->moving_count; ++i)
        q->total += moving_mass(&q->moving[i]);
}

/* theta_i, the relative azimuth in the table's orientation, and cos(theta_i)
 * of wi; 0 at the poles. */
int plm_fiber_table_angles(const plm_fiber_table_query *q, vec3 wi, double *theta, double *delta, double *ct)
{
    *ct = sqrt(wi.x * wi.x + wi.y * wi.y);
    if (!(*ct > 1e-12))
        return 0;
    *theta = fabs(wi.z) < 0.9 ? plm_asin(wi.z) : plm_atan2(wi.z, *ct);
    double d = plm_wrap_pi(plm_atan2(wi.y, wi.x) - q->phi_o);
    *delta = q->flip ? -d : d;
    return 1;
}

/* Phi(u0) - Phi(u1) for the standard normal's CDF Phi, from erfc where
 * both are in one tail (erf would lose the digits). */
static PLM_VECTOR_INLINE double normal_mass(double u0, double u1)
{
    const double r = 0.70710678118654752440;
    if (u0 > 0.0 && u1 > 0.0)
        return 0.5 * (erfc(u1 * r) - erfc(u0 * r));
    if (u0 < 0.0 && u1 < 0.0)
        return 0.5 * (erfc(-u0 * r) - erfc(-u1 * r));
    return 0.5 * (erf(u0 * r) - erf(u1 * r));
}

/* A moving lobe's G_N is cut at this many std-devs and renormalised (its
 * mass moves by 2e-9), so that a lobe further than that from wi costs
 * nothing; the sampler draws the same cut Gaussian. */
#define MOVING_CUT 6.0
#define MOVING_TAIL 9.865876450377012e-10 /* the Gaussian's mass beyond MOVING_CUT std-devs on one side */

/* One moving lobe's share of the density at dx = x - delta0 (one image of
 * x on the circle), into d (RGB). With u = (dx - slope s) / beta_n, the
 * weight's two moments over s in [0, 1] are closed forms:
 *   J0 = int G ds   = (Phi(u0) - Phi(u1)) / slope,
 *   J1 = int s G ds = (dx J0 - beta_n (phi(u1) - phi(u0)) / slope) / slope,
 * with Phi, phi the standard normal's CDF and density, u0, u1 the values at
 * s = 0, 1 clipped to the cut, all over the cut Gaussian's mass. A lobe
 * that barely moves (slope below 1e-4 beta_n) takes G at its midpoint, off
 * by a relative 1e-9. */
static PLM_VECTOR_INLINE void moving_lobe_density(const plm_fiber_table_moving_lobe *m, double dx, double beta,
                                                   double norm, double d[3])
{
    const double inv_sqrt_2pi = 0.39894228040143267794;
    double slope = m->slope, j0, j1;
    if (fabs(slope) > 1e-4 * beta) {
        double u0 = plm_clamp(dx / beta, -MOVING_CUT, MOVING_CUT);
        double u1 = plm_clamp((dx - slope) / beta, -MOVING_CUT, MOVING_CUT);
        j0 = normal_mass(u0, u1) / slope;
        double dphi = inv_sqrt_2pi * (exp(-0.5 * u1 * u1) - exp(-0.5 * u0 * u0));
        j1 = (dx * j0 - beta * dphi / slope) / slope;
    } else {
        double u = (dx - 0.5 * slope) / beta;
        j0 = fabs(u) < MOVING_CUT ? inv_sqrt_2pi / beta * exp(-0.5 * u * u) : 0.0;
        j1 = 0.5 * j0;
    }
    for (int ch = 0; ch < 3; ++ch)
        d[ch] += norm * (m->a0[ch] * (j0 - j1) + m->a1[ch] * j1);
}

/* The moving lobes' density at relative azimuth x in [-pi, pi) (R, G, B,
 * then their mean into d[3]): the sum over lobes of the integral over s in
 * [0, 1] of (a0 + (a1 - a0) s) G_N(x - delta0 - slope s), G_N cut. Only the
 * images of x within the cut of a lobe's path count (one, unless the path
 * and the cut reach around the circle). */
static PLM_VECTOR_INLINE void moving_density(const plm_fiber_table_query *q, double x, double d[4])
{
    double beta = q->table->params.beta_n, cut = MOVING_CUT * beta, norm = 1.0 / (1.0 - 2.0 * MOVING_TAIL);
    d[0] = d[1] = d[2] = 0.0;
    for (int i = 0; i < q->moving_count; ++i) {
        const plm_fiber_table_moving_lobe *m = &q->moving[i];
        double half = 0.5 * fabs(m->slope), reach = half + cut, dx = wrap_near(x - m->delta0 - 0.5 * m->slope);
        if (reach < PLM_PI) {
            if (fabs(dx) < reach)
                moving_lobe_density(m, dx + 0.5 * m->slope, beta, norm, d);
            continue;
        }
        int images = 1 + (int)(reach / PLM_TWO_PI);
        for (int k = -images; k <= images; ++k)
            if (fabs(dx + PLM_TWO_PI * k) < reach)
                moving_lobe_density(m, dx + PLM_TWO_PI * k + 0.5 * m->slope, beta, norm, d);
    }
    d[3] = (d[0] + d[1] + d[2]) / 3.0;
}

/* The table part at (theta_i, delta, cos(theta_i)): eval (G_M N / cos^2(theta_i),
 * N from the whole cells as the quadratic whose means over wi's bin and its
 * two neighbours are their masses, plus the moving lobes') into *f if f is
 * not NULL, and the sampler's density (G_M times the whole cells'
 * piecewise-constant bin density plus the moving lobes', per solid angle)
 * into *pdf. The quadratic keeps each bin's mass and follows a lobe's
 * curvature, which linear interpolation between bin centres flattens at a
 * peak and lifts on a flank (docs/fiber.md); the pdf reads wi's bin, which
 * eval reads anyway. */
PLM_VECTOR_CLONES void plm_fiber_table_lookup(const plm_fiber_table_query *q, double theta, double delta, double ct,
                                              rgb *f, double *pdf)
{
    const plm_fiber_table *t = q->table;
    double gm = plm_fiber_gm(t->params.beta_m, q->gm.scale, theta + q->theta_o);
    if (gm == 0.0)
        return;
    int n = t->phi_bins;
    double w = q->bin_width, x = (delta + PLM_PI) / w;
    int bin = (int)floor(x);
    bin = bin < 0 ? 0 : bin >= n ? n - 1 : bin;
    double m[3][3] = {{0.0}}, mass = 0.0, moving[4] = {0.0};
    if (q->moving_count > 0) /* only circular fibers' partial cells have moving lobes */
        moving_density(q, delta, moving);
    if (!f) {
        if (q->terms > 0)
            mass = column_mean(q, bin + 1) - column_mean(q, bin);
    } else {
        if (q->terms > 0 && bin > 0 && bin < n - 1) {
            bin_masses(q, bin - 1, 3, m);
        } else if (q->terms > 0) { /* the neighbours across the wrap */
            bin_masses(q, (bin + n - 1) % n, 1, &m[0]);
            bin_masses(q, bin, 1, &m[1]);
            bin_masses(q, (bin + 1) % n, 1, &m[2]);
        }
        /* p(u) = a + b u + c u^2 over u in [-1/2, 1/2] (the bin's centre at 0),
         * its means over the bins at u = -1, 0, 1 the masses m[0..2] / w. */
        double s = gm / (ct * ct), u = x - bin - 0.5, v[3];
        for (int ch = 0; ch < 3; ++ch) {
            double c = 0.5 * (m[2][ch] - 2.0 * m[1][ch] + m[0][ch]), b = 0.5 * (m[2][ch] - m[0][ch]);
            v[ch] = (m[1][ch] - c / 12.0 + (b + c * u) * u) * s / w;
        }
        *f = rgb_make(plm_positive(v[1]) + moving[0] * s, plm_positive(v[2]) + moving[1] * s,
                      plm_positive(3.0 * v[0] - v[1] - v[2]) + moving[2] * s);
        mass = m[1][0];
    }
    *pdf = gm * (plm_positive(mass) / w + moving[3]) / (q->total * ct);
}

/* Within a moving lobe (u in [0, 1)): the place s along its piece, whose
 * density is proportional to the weight a0 + (a1 - a0) s (the CDF's
 * quadratic solved in a form that is stable when a0 = a1). */
static double moving_place(double a0, double a1, double u)
{
    double root = sqrt(a0 * a0 + u * (a1 * a1 - a0 * a0));
    return a0 + root > 0.0 ? plm_clamp(u * (a0 + a1) / (a0 + root), 0.0, 1.0) : u;
}

/* The relative azimuth by the mean channel (u0 picks the whole cells' rows
 * or a moving lobe by energy; in the rows a bin by their CDF, then uniform
 * within the bin; in a moving lobe the place along its piece, then u2 the
 * offset from G_N) and theta_i from G_M (u1): the angles into theta, delta
 * (in the table's orientation) and the direction into wi. */
PLM_VECTOR_CLONES int plm_fiber_table_sample(const plm_fiber_table_query *q, double u0, double u1, double u2,
                                             double *theta, double *delta, vec3 *wi)
{
    if (!(q->total > 0.0))
        return 0;
    const plm_fiber_table *t = q->table;
    double target = u0 * q->total;
    if (target < q->rows_total) {
        double a = 0.0, b = q->rows_total;
        int lo = 0, hi = t->phi_bins; /* column lo <= target < column hi */
        for (int probe = 0; hi - lo > 1; ++probe) {
            int mid = plm_fiber_search_probe(probe, lo, hi, a, b, target);
            double m = column_mean(q, mid);
            if (m <= target)
                lo = mid, a = m;
            else
                hi = mid, b = m;
        }
        if (hi - lo != 1 || !(b > a))
            return 0;
        /* Kept off the bin's edges by far more than rounding moves an angle, so
         * that wi's own angles find this bin again (pdf(wi) = the record's pdf). */
        double frac = plm_clamp((target - a) / (b - a), 1e-9, 1.0 - 1e-9);
        *delta = -PLM_PI + (lo + frac) * q->bin_width;
    } else {
        target -= q->rows_total;
        int i = 0;
        double mass = 0.0;
        for (; i < q->moving_count; ++i) {
            mass = moving_mass(&q->moving[i]);
            if (target < mass || i == q->moving_count - 1)
                break;
            target -= mass;
        }
        if (i >= q->moving_count || !(mass > 0.0))
            return 0;
        const plm_fiber_table_moving_lobe *m = &q->moving[i];
        double a0 = ((double)m->a0[0] + m->a0[1] + m->a0[2]) / 3.0, a1 = ((double)m->a1[0] + m->a1[1] + m->a1[2]) / 3.0;
        double s = moving_place(a0, a1, plm_clamp(target / mass, 0.0, 1.0));
        double z = plm_fiber_normal_quantile(MOVING_TAIL + u2 * (1.0 - 2.0 * MOVING_TAIL)); /* the cut Gaussian */
        z = plm_clamp(z, -MOVING_CUT, MOVING_CUT);
        *delta = plm_wrap_pi(m->delta0 + m->slope * s + t->params.beta_n * z);
    }
    *theta = plm_fiber_sample_gm(&q->gm, u1);
    *wi = plm_fiber_direction(*theta, q->phi_o + (q->flip ? -*delta : *delta));
    return 1;
}
