/* The tabulated fiber BCSDF: the paper's Eq. 1 integral over the entry
 * offset h computed ahead of time, so a shading query is deterministic and
 * its narrow lobes do not sparkle (see docs/fiber.md).
 *
 * Every path that leaves the cortex without meeting the medulla leaves at
 * theta = -theta_o, so its part of S is G_M(theta_i + theta_o) / cos^2(theta_i)
 * times an azimuthal function N(phi_i - phi_o) of (theta_o, phi_o, h). The
 * table holds, per (|theta_o|, phi_o) node, the cumulative integral of N over
 * h cells and azimuth bins; an h-interval's mean is then a difference of
 * interpolated rows. The lobes that bounced off the medulla have a table of
 * their own (optics/fiber_medulla_table.h), so a query is deterministic.
 *
 * Tables are built on all cores on first use and cached on disk, keyed by a
 * hash of the parameters, the resolution and the format version. */
#ifndef PLUMAGE_OPTICS_FIBER_TABLE_H
#define PLUMAGE_OPTICS_FIBER_TABLE_H

#include <stddef.h>

#include "optics/fiber.h"
#include "optics/fiber_grid.h"
#include "optics/fiber_medulla_table.h"

#define PLM_FIBER_TABLE_VERSION 16
/* |theta_o| of a table's limit node (plm_fiber_table.limit_node). */
#define PLM_FIBER_THETA_LIMIT (89.9 * PLM_PI / 180.0)
/* Default resolution aims at this many bytes per table. */
#define PLM_FIBER_TABLE_BUDGET ((size_t)32 << 20)
/* The default and the range of plm_fiber_table_options.budget_mib and of a
 * scene's film.fiber_table_mib. */
#define PLM_FIBER_TABLE_MIB_DEFAULT ((int)(PLM_FIBER_TABLE_BUDGET >> 20))
#define PLM_FIBER_TABLE_MIB_MIN 8
#define PLM_FIBER_TABLE_MIB_MAX 4096

typedef struct plm_fiber_table_options {
    int threads;           /* build threads; 0 = all cores */
    /* The memory the default resolution aims at, both parts, in MiB: 0 (or
     * less) the default, else kept within PLM_FIBER_TABLE_MIB_MIN..MAX. A
     * larger budget buys an elliptical table accuracy (docs/fiber.md,
     * "Memory and accuracy"). The medulla's part keeps its own 10 MiB
     * layout, so a fiber with one takes about 14 MiB at least. */
    int budget_mib;
    const char *cache_dir; /* NULL: $PLUMAGE_CACHE_DIR, else $XDG_CACHE_HOME/plumage, else $HOME/.cache/plumage */
    int no_cache;          /* 1: neither read nor write the disk cache */
    int quiet;             /* 1: no progress on stderr */
    /* Resolution, 0 = the defaults of docs/fiber.md (azimuth bins from beta_n);
     * theta_nodes over [0, 89 deg], to which a circular table adds its limit node. */
    int theta_nodes, phi_nodes, h_cells, phi_bins;
    int grazing_nodes, grazing_cells; /* h cells at the last grazing_nodes |theta_o| nodes; -1 nodes: none */
    plm_fiber_medulla_resolution medulla; /* the medulla part's resolution, 0 = defaults */
} plm_fiber_table_options;


typedef struct plm_fiber_table {
    plm_fiber_params params;
    int theta_nodes, phi_nodes, h_cells, phi_bins, symmetry;
    int lobe_slots;    /* lobe records per node and h cell bound, by the lobes' wall hits: p->lobes for a
                        * rotationally symmetric fiber, else none (docs/fiber.md) */
    double theta_max;  /* |theta_o| of the last node placed by u; views beyond it are interpolated toward the
                        * limit node if there is one (and it serves past PLM_FIBER_THETA_LIMIT), else the
                        * last node serves */
    double u_first, u_last; /* nodes are uniform in u(|theta_o|) from u_first to u_last (docs/fiber.md) */
    int limit_node;    /* 1: the last of theta_nodes sits past theta_max at PLM_FIBER_THETA_LIMIT, next to
                        * grazing, and views between are interpolated linearly in u (circular tables) */
    double u_limit;    /* u there */
    double phi_lo, phi_step; /* phi_o of node k is phi_lo + k phi_step */
    /* h cells per |theta_o| node: h_cells, but grazing_cells at the last
     * grazing_nodes nodes, where the lobes move fastest with h (docs/fiber.md);
     * only tables without lobe records have grazing nodes. */
    int grazing_nodes, grazing_cells;
    double *h_node;    /* h_cells + 1 cell bounds, uniform in asin(h) */
    double *h_node_grazing; /* grazing_cells + 1 (NULL without grazing nodes) */
    double *node_cos;  /* cos(|theta_o|) of each |theta_o| node (tables without lobe records scale their
                        * blend by the interval's energy interpolated in it; docs/fiber.md) */
    float *bound_energy; /* tables without lobe records: per node and h cell bound, its row's energy (the
                          * mean channel's last column), together (plm_fiber_table_bound_energies) */
    float *data;       /* per node, rows 0..its h cells, columns 0..phi_bins, (mean of RGB, R, G), then per
                        * cell bound the lobe records (Delta_k, A_k RGB) and a flag (docs/fiber.md); then
                        * the medulla part's */
    size_t floats;     /* both parts */
    plm_fiber_medulla_table medulla; /* theta_nodes 0 without a medulla */
    int from_cache;    /* 1 if read from the disk cache */
    void *mapping;     /* from the cache: its file mapped read-only, data inside it; else NULL, data malloc'd */
    size_t mapping_bytes;
    double build_seconds;
} plm_fiber_table;

/* Loads the table for p from the cache or builds it (and caches it). */
plm_result plm_fiber_table_get(const plm_fiber_params *p, const plm_fiber_table_options *o, plm_fiber_table **out,
                               plm_error *err);
void plm_fiber_table_free(plm_fiber_table *t);
size_t plm_fiber_table_bytes(const plm_fiber_table *t);
/* The steps plm_fiber_table_get takes, for tests and the cache: the
 * resolution and symmetry for (p, o) into a zeroed table (t->floats set),
 * the arrays, and the build on all cores (progress on stderr after 1 s). */
void plm_fiber_table_layout(const plm_fiber_params *p, const plm_fiber_table_options *o, plm_fiber_table *t);
plm_result plm_fiber_table_alloc(plm_fiber_table *t, plm_error *err);
/* Unmaps or frees t->data, as it was got. */
void plm_fiber_table_release_data(plm_fiber_table *t);
plm_result plm_fiber_table_build(plm_fiber_table *t, const plm_fiber_table_options *o, plm_error *err);
/* Both parts' copies of their rows' energies (bound_energy), once the data is built or read. */
void plm_fiber_table_bound_energies(plm_fiber_table *t);

/* The numbers a table depends on besides its options (its cache key's
 * parameters): fibers whose words are equal have the same table. */
enum { PLM_FIBER_TABLE_PARAM_WORDS = 16 };
void plm_fiber_table_param_words(const plm_fiber_params *p, double w[PLM_FIBER_TABLE_PARAM_WORDS]);

/* The cache file the table for (p, o) lives in; returns 0 if there is no cache directory. */
int plm_fiber_table_cache_path(const plm_fiber_params *p, const plm_fiber_table_options *o, char *path,
                               size_t size);

/* The table part of a prepared query, the mean over [h-, h+] at the view's
 * (theta_o, phi_o) in two pieces. The h cells the interval covers whole:
 * at any column c, sum_k coef[k] term[k][3 c] (per channel), each term a
 * row of one of the four nodes around wo, its coefficient the node's
 * bilinear weight times the row's h weight. The partial cells at the ends:
 * moving lobes (docs/fiber.md), each a Gaussian G_N whose centre moves
 * linearly from delta0 to delta0 + slope while its weight goes from a0 to a1
 * (RGB, the piece's share of the interval included; floats, so that three
 * prepared fibers fit a feather BSDF's state). */
#define PLM_FIBER_TABLE_TERMS 16
#define PLM_FIBER_TABLE_MOVING (2 * PLM_FIBER_SET_MAX_LOBES)
typedef struct plm_fiber_table_moving_lobe {
    float delta0, slope, a0[3], a1[3];
} plm_fiber_table_moving_lobe;

typedef struct plm_fiber_table_query {
    const plm_fiber_table *table;
    const float *term[PLM_FIBER_TABLE_TERMS];
    double coef[PLM_FIBER_TABLE_TERMS];
    int terms, moving_count;
    plm_fiber_table_moving_lobe moving[PLM_FIBER_TABLE_MOVING];
    double rows_total;       /* the whole cells' energy (mean of RGB) */
    double total;            /* the part's energy (mean of RGB), for sampling */
    int flip;                /* mirrored node: azimuths relative to phi_o change sign */
    double theta_o, phi_o, bin_width;
    plm_fiber_gm_detector gm; /* G_M about -theta_o, for eval and sampling */
} plm_fiber_table_query;

/* The part's query, as the medulla's part has its own
 * (optics/fiber_medulla_table.h): prepared for a view (plm_fiber_view_of);
 * wi's theta_i, relative azimuth in the table's orientation and
 * cos(theta_i) (0 at the poles); eval (if f) and the part's pdf (if pdf)
 * at those angles; a sampled direction with its angles (0 if the part has
 * no energy). docs/fiber.md, "Queries". */
void plm_fiber_table_prepare(const plm_fiber_table *t, const plm_fiber_view *v, plm_fiber_table_query *q);
int plm_fiber_table_angles(const plm_fiber_table_query *q, vec3 wi, double *theta, double *delta, double *ct);
void plm_fiber_table_lookup(const plm_fiber_table_query *q, double theta, double delta, double ct, rgb *f,
                            double *pdf);
int plm_fiber_table_sample(const plm_fiber_table_query *q, double u0, double u1, double u2, double *theta,
                           double *delta, vec3 *wi);

#endif
