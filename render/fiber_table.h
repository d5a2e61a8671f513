/* The tabulated fiber BCSDF: the paper's Eq. 1 integral over the entry
 * offset h computed ahead of time, so a shading query is deterministic and
 * its narrow lobes do not sparkle (see docs/fiber.md).
 *
 * Every path that leaves the cortex without meeting the medulla leaves at
 * theta = -theta_o, so its part of S is G_M(theta_i + theta_o) / cos^2(theta_i)
 * times an azimuthal function N(phi_i - phi_o) of (theta_o, phi_o, h). The
 * table holds, per (|theta_o|, phi_o) node, the cumulative integral of N over
 * h cells and azimuth bins; an h-interval's mean is then a difference of
 * interpolated rows. The lobes that bounced off the medulla are left to one
 * traced sample (plm_fiber_prepare_medulla), as in the stochastic estimator.
 *
 * Tables are built on all cores on first use and cached on disk, keyed by a
 * hash of the parameters, the resolution and the format version. */
#ifndef PLUMAGE_RENDER_FIBER_TABLE_H
#define PLUMAGE_RENDER_FIBER_TABLE_H

#include <stddef.h>

#include "render/fiber.h"

#define PLM_FIBER_TABLE_VERSION 4
/* Default resolution aims at this many bytes per table. */
#define PLM_FIBER_TABLE_BUDGET ((size_t)32 << 20)

typedef struct plm_fiber_table_options {
    int threads;           /* build threads; 0 = all cores */
    const char *cache_dir; /* NULL: $PLUMAGE_CACHE_DIR, else $XDG_CACHE_HOME/plumage, else $HOME/.cache/plumage */
    int no_cache;          /* 1: neither read nor write the disk cache */
    int quiet;             /* 1: no progress on stderr */
    /* Resolution, 0 = the defaults of docs/fiber.md (azimuth bins from beta_n). */
    int theta_nodes, phi_nodes, h_cells, phi_bins;
} plm_fiber_table_options;

/* Which mirror symmetries of the cross-section the table exploits. */
enum {
    PLM_FIBER_TABLE_ROTATIONAL = 0, /* circular cortex, no or a centred circular medulla: one phi_o node */
    PLM_FIBER_TABLE_MIRROR_XY = 1,  /* phi_o in [0, pi/2] */
    PLM_FIBER_TABLE_MIRROR_X = 2,   /* medulla off the e3 axis only along e3 (x -> -x): phi_o in [-pi/2, pi/2] */
    PLM_FIBER_TABLE_MIRROR_Y = 3,   /* y -> -y: phi_o in [0, pi] */
    PLM_FIBER_TABLE_NONE = 4        /* phi_o all around */
};

typedef struct plm_fiber_table {
    plm_fiber_params params;
    int theta_nodes, phi_nodes, h_cells, phi_bins, symmetry;
    double theta_max;  /* |theta_o| of the last node; beyond it the last node serves */
    double u_first, u_last; /* nodes are uniform in u(|theta_o|) from u_first to u_last (docs/fiber.md) */
    double phi_lo, phi_step; /* phi_o of node k is phi_lo + k phi_step */
    double *h_node;    /* h_cells + 1 cell bounds, uniform in asin(h) */
    float *data;       /* per node, rows 0..h_cells, columns 0..phi_bins, (mean of RGB, R, G) (docs/fiber.md) */
    size_t floats;
    int from_cache;    /* 1 if read from the disk cache */
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
plm_result plm_fiber_table_build(plm_fiber_table *t, const plm_fiber_table_options *o, plm_error *err);

/* The cache file the table for (p, o) lives in; returns 0 if there is no cache directory. */
int plm_fiber_table_cache_path(const plm_fiber_params *p, const plm_fiber_table_options *o, char *path,
                               size_t size);

/* The table part of a prepared query: the mean over [h-, h+] at the view's
 * (theta_o, phi_o) at any column c is sum_k coef[k] term[k][3 c] (per
 * channel): each term is a row of one of the four nodes around wo, its
 * coefficient the node's bilinear weight times the row's h weight. */
#define PLM_FIBER_TABLE_TERMS 16
typedef struct plm_fiber_table_query {
    const plm_fiber_table *table;
    const float *term[PLM_FIBER_TABLE_TERMS];
    double coef[PLM_FIBER_TABLE_TERMS];
    int terms;
    double total;            /* the part's energy (mean of RGB), for sampling */
    int flip;                /* mirrored node: azimuths relative to phi_o change sign */
    double theta_o, phi_o, gm_scale;
} plm_fiber_table_query;

/* The fiber BCSDF prepared for one view direction wo and h-interval, by
 * either estimator: with a table, its part plus a traced sample of the
 * medulla's lobes; without (NULL), the stochastic lobe set of fiber.h.
 * Sampling mixes the two parts by energy; pdf is the mixture's density. */
typedef struct plm_fiber_bcsdf {
    const plm_fiber_params *params;
    plm_fiber_table_query tab; /* tab.table NULL: stochastic */
    plm_fiber_lobe_set set;    /* stochastic: every lobe; tabulated: the medulla's lobes */
    double pick_table;         /* probability that sampling uses the table part */
    double total;              /* > 0 iff something can be sampled */
} plm_fiber_bcsdf;

void plm_fiber_bcsdf_prepare(const plm_fiber_params *p, const plm_fiber_table *table, vec3 wo, double hmin,
                             double hmax, plm_rng *rng, plm_fiber_bcsdf *out);
/* As plm_fiber_eval: eval(wi) cos(theta_i) integrates to the energy over the sphere. */
rgb plm_fiber_bcsdf_eval(const plm_fiber_bcsdf *b, vec3 wi);
double plm_fiber_bcsdf_pdf(const plm_fiber_bcsdf *b, vec3 wi);
/* Both at once: one table lookup serves the two. */
rgb plm_fiber_bcsdf_eval_pdf(const plm_fiber_bcsdf *b, vec3 wi, double *pdf);
int plm_fiber_bcsdf_sample(const plm_fiber_bcsdf *b, double u0, double u1, double u2, plm_fiber_sample_rec *rec);

#endif
