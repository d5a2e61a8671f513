/* The medulla's part of the tabulated fiber BCSDF: building its table, and
 * eval / pdf / sample from it (docs/fiber.md has the design, its resolution
 * and its error).
 *
 * Notation. t is a point (ca + a cos t, cb + b sin t) of the medulla's
 * boundary. The emission E_c(t) is what leaves the fiber, per unit of light
 * reaching t, when the path may still store c lobes: bin masses over
 * (|theta_i|, phi_i) of sum_k A_k G_M G_N, the mean over the diffuse
 * directions (and later bounces) of the lobes that follow. L(t | wo, h) is
 * the light that the path entering at h reaches t with.
 *
 * A rotationally symmetric fiber's table holds, per |theta_o| node, for
 * rows j = 0..h_cells, bands a (|theta_i| bins) and columns c = 0..phi_bins,
 *   S(j, a, c) = integral over s < s_j of the mass in band a with
 *                phi_i - phi_o below column c,
 * i.e. the emission of the point each h reaches, weighted by the light that
 * reaches it, with the rows over s = h / h_reach
 * (plm_fiber_medulla_reach), so that where paths stop meeting the medulla
 * is a cell bound at every view.
 *
 * Every other fiber's table is factored: E(t) at `points` medulla points
 * once (the paths of the last lobe class: all p->lobes - 1 lobes after the
 * medulla), and per view node (|theta_o|, phi_o) the light L at those
 * points (linear in t between them), cumulative over h cells, and the h
 * samples it was summed from. A query blends L over the nodes and the
 * interval into one weight per point; eval is sum_t L(t) E(t)(wi). */
#include "optics/fiber_medulla_table.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "common/vector_clones.h"

#define HALF_PI (0.5 * PLM_PI)

/* A rotationally symmetric table's medulla points the emission is
 * tabulated at (linear in t between them), its azimuth bins per table
 * column, and the lobe budgets it keeps apart: 1, 2, ... up to MAX_CLASSES -
 * 1, the last class all p->lobes - 1 lobes (exact for up to 5 lobes; see
 * docs/fiber.md). A factored table keeps the last class alone. */
enum { POINTS = 96, PHI_REFINE = 2, MAX_CLASSES = 4 };

/* ---- layout -------------------------------------------------------------- */

/* A row: each band's columns, then each band's total (its last column
 * again), which sampling reads in two cache lines, then the row's total
 * (what a prepare reads); RGB. (A mean channel with R and G, as the other
 * part stores, would cost blue its precision where it is much weaker than
 * red, as for the default barb, through the differences of cumulative
 * rows.) */
static size_t band_offset(const plm_fiber_medulla_table *m)
{
    return 3 * (size_t)m->res.theta_bins * (size_t)(m->res.phi_bins + 1);
}
static size_t total_offset(const plm_fiber_medulla_table *m)
{
    return band_offset(m) + 3 * (size_t)m->res.theta_bins;
}
static size_t row_floats(const plm_fiber_medulla_table *m) { return total_offset(m) + 3; }
static size_t node_floats(const plm_fiber_medulla_table *m) { return (size_t)(m->res.h_cells + 1) * row_floats(m); }
static int node_count(const plm_fiber_medulla_table *m) { return m->res.theta_nodes * m->res.phi_nodes; }

/* The factored layout (every fiber but a rotationally symmetric one), in
 * floats: per |theta_i| band and phi_i bin, the points' emission, one
 * channel (R, G, B, then their mean) after another, each over the points
 * (so that eval's sums over the points read consecutive floats); the
 * points' emitted energy, R, G, B and the mean of RGB, each over the
 * points; per point its sampling table: the cumulative band masses (bands
 * + 1) and per band the cumulative row over the bins (bins + 1), mean of
 * RGB; per view node, rows 0..h_cells of the light reaching each
 * point, cumulative over the h cells (RGB, each over the points), then the
 * traced h samples, `records` per cell: the point reached and the light
 * (RGB; zero for a path that misses the medulla). */
static size_t emission_block(const plm_fiber_medulla_table *m)
{
    return 4 * (size_t)m->res.points * (size_t)m->res.theta_bins * (size_t)m->res.phi_bins;
}
static size_t sampling_floats(const plm_fiber_medulla_table *m)
{
    return (size_t)m->res.theta_bins + 1 + (size_t)m->res.theta_bins * (size_t)(m->res.phi_bins + 1);
}
static size_t light_row(const plm_fiber_medulla_table *m) { return 3 * (size_t)m->res.points; }
static size_t records_per_node(const plm_fiber_medulla_table *m)
{
    return (size_t)m->res.h_cells * (size_t)m->res.records;
}
static size_t factored_node(const plm_fiber_medulla_table *m)
{
    return (size_t)(m->res.h_cells + 1) * light_row(m) + 4 * records_per_node(m);
}
static size_t factored_nodes_start(const plm_fiber_medulla_table *m)
{
    return emission_block(m) + (size_t)m->res.points * (4 + sampling_floats(m));
}
static const float *point_energy(const plm_fiber_medulla_table *m) { return m->data + emission_block(m); }
static float *point_sampling(const plm_fiber_medulla_table *m, int k)
{
    return m->data + emission_block(m) + 4 * (size_t)m->res.points + sampling_floats(m) * (size_t)k;
}
static float *node_light(const plm_fiber_medulla_table *m, int node)
{
    return m->data + factored_nodes_start(m) + factored_node(m) * (size_t)node;
}

/* The default resolution per symmetry class, the columns of docs/fiber.md's
 * table (phi_o nodes 0: the override's, else what PLM_FIBER_MEDULLA_BUDGET
 * leaves; a rotationally symmetric fiber's one node is fixed). The part is
 * smooth in theta_i and phi_i but not in h (where paths start or stop
 * meeting the medulla) nor in phi_o for an elliptical cortex, so the
 * classes spend the memory differently (docs/fiber.md has the errors). */
enum { DEFAULT_ROTATIONAL, DEFAULT_BOTH_MIRRORS, DEFAULT_WIDE };
static const plm_fiber_medulla_resolution default_resolution[] = {
    /* Rotationally symmetric: one phi_o node. 24 |theta_i| bands of 3.75
     * deg halve the error against 12; the rows over s = h / h_reach need
     * few h cells (32 do as well as 72), which leaves room for 48 phi_i
     * bins (7.5 deg; they help detectors of 6-15 deg most) and 10
     * |theta_o| nodes. */
    [DEFAULT_ROTATIONAL] = {.theta_nodes = 10, .phi_nodes = 1, .h_cells = 32, .theta_bins = 24, .phi_bins = 48,
                            .directions = 4096},
    /* Factored: the emission is stored once, so its bins can be fine (24
     * bands halve random 3's error against 12); the light per view node is
     * small, so the phi_o nodes can be dense; the interval's partial cells
     * read the traced h samples, so 16 cells do (16 samples each, at least,
     * measure as well as 32, which leave fewer phi_o nodes and cost a
     * partial interval's prepare twice the samples). 64 points cost 0.1 points of
     * error against 96 and a third less memory and eval. Where the phi_o
     * nodes cover half the circle or all of it, 7 |theta_o| nodes leave
     * room for more of them. */
    [DEFAULT_BOTH_MIRRORS] = {.theta_nodes = 10, .h_cells = 16, .theta_bins = 24, .phi_bins = 96,
                              .directions = 4096, .points = 64, .records = 16},
    [DEFAULT_WIDE] = {.theta_nodes = 7, .h_cells = 16, .theta_bins = 24, .phi_bins = 96, .directions = 4096,
                      .points = 64, .records = 16},
};

static const plm_fiber_medulla_resolution *defaults_for(int symmetry)
{
    return &default_resolution[symmetry == PLM_FIBER_TABLE_ROTATIONAL  ? DEFAULT_ROTATIONAL
                               : symmetry == PLM_FIBER_TABLE_MIRROR_XY ? DEFAULT_BOTH_MIRRORS
                                                                       : DEFAULT_WIDE];
}

/* x rounded up to a multiple of k. */
static int round_up(int x, int k) { return (x + k - 1) / k * k; }

/* The factored layout's points (a multiple of 8, as eval's sums over them
 * take 8 at a time; even, as the mirrors map points onto points), records
 * and bins (even, as the mirrors map bins onto bins); the floats before the
 * view nodes and those of one node. */
static void factored_resolution(const plm_fiber_params *p, const plm_fiber_medulla_resolution *r,
                                const plm_fiber_medulla_resolution *d, plm_fiber_medulla_table *m, size_t *fixed,
                                size_t *per_node)
{
    int points = r && r->points > 0 ? round_up(r->points, 8) : d->points;
    m->res.points = points < PLM_FIBER_MEDULLA_POINTS ? points : PLM_FIBER_MEDULLA_POINTS;
    /* A narrow detector needs the samples closer (as the other part's, half a beta_n of lobe motion
     * apart): random 1 of slow_fiber_table, beta_n 4.3 deg, 0.5-1.9% with 16 samples, 0-0.2% with 24. */
    int sub = plm_fiber_h_sub_samples(p->beta_n, m->res.h_cells);
    m->res.records = r && r->records > 0 ? r->records : sub > d->records ? sub : d->records;
    m->res.phi_bins = round_up(m->res.phi_bins, 2);
    m->factored = 1;
    *fixed = factored_nodes_start(m);
    *per_node = factored_node(m);
}

void plm_fiber_medulla_layout(const plm_fiber_params *p, int symmetry, const plm_fiber_medulla_resolution *r,
                              plm_fiber_medulla_table *m)
{
    memset(m, 0, sizeof *m);
    if (!plm_fiber_has_medulla(p) || p->lobes < 2)
        return; /* no lobe can follow a medulla bounce */
    const plm_fiber_medulla_resolution *d = defaults_for(symmetry);
    m->res.theta_nodes = r && r->theta_nodes > 1 ? r->theta_nodes : d->theta_nodes;
    m->res.h_cells = r && r->h_cells > 0 ? r->h_cells : d->h_cells;
    m->res.theta_bins = r && r->theta_bins > 1 ? r->theta_bins : d->theta_bins;
    m->res.phi_bins = r && r->phi_bins > 1 ? r->phi_bins : d->phi_bins; /* eval reads a bin and its neighbour */
    m->res.directions = r && r->directions > 0 ? r->directions : d->directions;
    size_t fixed = 0, per_node = node_floats(m);
    if (symmetry != PLM_FIBER_TABLE_ROTATIONAL)
        factored_resolution(p, r, d, m, &fixed, &per_node);
    size_t budget = PLM_FIBER_MEDULLA_BUDGET / sizeof(float), left = budget > fixed ? budget - fixed : 0;
    int fit = (int)(left / (per_node * (size_t)m->res.theta_nodes));
    int phi_nodes = r && r->phi_nodes > 1 ? r->phi_nodes : fit < 3 ? 3 : fit > 120 ? 120 : fit;
    m->res.phi_nodes = d->phi_nodes ? d->phi_nodes : phi_nodes;
    m->symmetry = symmetry;
    m->theta_max = plm_radians(89.0);
    m->eta = p->eta;
    m->radius = symmetry == PLM_FIBER_TABLE_ROTATIONAL ? p->medulla_a : 0.0;
    m->per_theta = HALF_PI / m->res.theta_bins < p->beta_m;
    m->u_last = plm_fiber_theta_u(p->eta, m->theta_max);
    plm_fiber_phi_nodes(symmetry, m->res.phi_nodes, &m->phi_lo, &m->phi_step);
    m->floats = fixed + per_node * (size_t)node_count(m);
}

plm_result plm_fiber_medulla_alloc(plm_fiber_medulla_table *m, plm_error *err)
{
    if (m->res.theta_nodes == 0)
        return PLM_OK;
    m->h_node = plm_fiber_h_nodes(m->res.h_cells);
    m->band_scale = malloc(sizeof(double) * (size_t)m->res.theta_bins);
    m->node_cos = malloc(sizeof(double) * (size_t)m->res.theta_nodes);
    m->bound_energy = m->factored ? malloc(sizeof(float) * (size_t)node_count(m) * (size_t)(m->res.h_cells + 1))
                                  : NULL;
    if (!m->h_node || !m->band_scale || !m->node_cos || (m->factored && !m->bound_energy))
        return plm_fail(err, PLM_ERR_NO_MEMORY, "fiber table: out of memory");
    for (int k = 0; k < m->res.theta_nodes; ++k)
        m->node_cos[k] = cos(plm_fiber_node_theta(m->eta, m->u_last, m->theta_max, m->res.theta_nodes, k));
    double w = HALF_PI / m->res.theta_bins;
    for (int a = 0; a < m->res.theta_bins; ++a)
        m->band_scale[a] = m->per_theta ? 1.0 : w / (sin((a + 1) * w) - sin(a * w));
    return PLM_OK;
}

void plm_fiber_medulla_bound_energies(plm_fiber_medulla_table *m)
{
    if (m->res.theta_nodes == 0 || !m->factored)
        return;
    int P = m->res.points;
    const float *energy = point_energy(m);
    for (int node = 0; node < node_count(m); ++node)
        for (int j = 0; j <= m->res.h_cells; ++j) {
            const float *row = node_light(m, node) + light_row(m) * (size_t)j;
            double sum = 0.0;
            for (int ch = 0; ch < 3; ++ch)
                for (int k = 0; k < P; ++k)
                    sum += (double)row[ch * P + k] * energy[ch * P + k];
            m->bound_energy[(size_t)node * (m->res.h_cells + 1) + j] = (float)(sum / 3.0);
        }
}

void plm_fiber_medulla_release(plm_fiber_medulla_table *m)
{
    free(m->h_node);
    free(m->band_scale);
    free(m->node_cos);
    free(m->bound_energy);
    m->h_node = NULL;
    m->band_scale = NULL;
    m->node_cos = NULL;
    m->bound_energy = NULL;
}

double plm_fiber_medulla_reach(const plm_fiber_medulla_table *m, double sin_theta, double cos_theta)
{
    if (!(m->radius > 0.0))
        return 1.0;
    double r = m->radius * sqrt(m->eta * m->eta - sin_theta * sin_theta);
    return r < cos_theta ? r / cos_theta : 1.0;
}

/* ---- building ------------------------------------------------------------ */

/* The emission: per medulla point and lobe class, bin masses over |theta_i|
 * bands and phi_i bins, RGB (a rotationally symmetric table's PHI_REFINE
 * per column, a factored table's its columns). */
typedef struct emission {
    int points, classes, bands, bins;
    float *mass;
} emission;

static size_t emission_floats(const emission *e) { return 3 * (size_t)e->bands * (size_t)e->bins; }

static const float *emission_at(const emission *e, int point, int cls)
{
    return e->mass + emission_floats(e) * ((size_t)point * (size_t)e->classes + (size_t)cls);
}

/* The class of a path that may still store `budget` lobes. */
static int class_of(int budget, int classes) { return budget < classes ? budget - 1 : classes - 1; }

/* Mass of G_M about Theta (normalised on [-pi/2, pi/2]) in each |theta|
 * band [a w, (a + 1) w], both signs of theta together. */
static void band_masses(double *mass, int bands, double beta, double Theta)
{
    double s = 1.0 / (sqrt(2.0) * beta), w = HALF_PI / bands;
    double z = 0.5 * (erf((HALF_PI - Theta) * s) + erf((HALF_PI + Theta) * s));
    double prev_hi = erf(-Theta * s), prev_lo = prev_hi; /* at +theta and -theta */
    for (int a = 0; a < bands; ++a) {
        double x = (a + 1) * w, hi = erf((x - Theta) * s), lo = erf((-x - Theta) * s);
        mass[a] = 0.5 * ((hi - prev_hi) + (prev_lo - lo)) / z;
        prev_hi = hi;
        prev_lo = lo;
    }
}

/* Lobes are first binned finely in (Theta, Phi) (split linearly between
 * bin centres), then blurred by the detectors into bands and bins at once:
 * an erf per lobe would cost ten times its trace. The fine bins are 1/4 and
 * 1/8 of a degree-scale detector at most, which widens it by under 1%. */
enum { FINE_THETA = 96, FINE_PHI = 384 };

typedef struct build_ctx {
    const plm_fiber_params *p;
    plm_fiber_medulla_table *m;
    emission e;
    double *theta_kernel; /* [fine theta][band]: band_masses at the fine bin's centre */
    double *phi_kernel;   /* [fine phi][emission bin]: G_N's masses about the fine bin's centre */
    int *phi_lo, *phi_count; /* per fine phi, the window of emission bins it reaches */
} build_ctx;

static size_t fine_floats(void) { return 3 * (size_t)FINE_THETA * FINE_PHI; }

/* Adds A at (Theta, Phi) to the fine histogram, split between the four
 * nearest bin centres (Theta clamps at the poles, Phi wraps). */
static void fine_deposit(double *hist, double Theta, double Phi, rgb A)
{
    double xt = (Theta + HALF_PI) / PLM_PI * FINE_THETA - 0.5, xp = (Phi + PLM_PI) / PLM_TWO_PI * FINE_PHI - 0.5;
    double ft = floor(xt), fp = floor(xp), at = xt - ft, ap = xp - fp;
    int t0 = (int)ft, t1 = t0 + 1, p0 = ((int)fp % FINE_PHI + FINE_PHI) % FINE_PHI, p1 = (p0 + 1) % FINE_PHI;
    t0 = t0 < 0 ? 0 : t0 >= FINE_THETA ? FINE_THETA - 1 : t0;
    t1 = t1 >= FINE_THETA ? FINE_THETA - 1 : t1 < 0 ? 0 : t1;
    const int ti[2] = {t0, t1}, pi[2] = {p0, p1};
    const double tw[2] = {1.0 - at, at}, pw[2] = {1.0 - ap, ap};
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            double *d = hist + 3 * ((size_t)ti[i] * FINE_PHI + pi[j]), w = tw[i] * pw[j];
            d[0] += w * A.r;
            d[1] += w * A.g;
            d[2] += w * A.b;
        }
}

/* The detectors' blur of a fine histogram into emission masses (added to out, float). */
static void blur(const build_ctx *b, const double *hist, double *band_row, float *out)
{
    const emission *e = &b->e;
    for (int a = 0; a < e->bands; ++a) {
        memset(band_row, 0, sizeof(double) * 3 * FINE_PHI);
        for (int ft = 0; ft < FINE_THETA; ++ft) {
            double k = b->theta_kernel[(size_t)ft * e->bands + a];
            const double *h = hist + 3 * (size_t)ft * FINE_PHI;
            if (k < 1e-12)
                continue;
            for (int x = 0; x < 3 * FINE_PHI; ++x)
                band_row[x] += k * h[x];
        }
        float *dst = out + 3 * (size_t)a * e->bins;
        for (int fp = 0; fp < FINE_PHI; ++fp) {
            const double *v = band_row + 3 * fp;
            if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0)
                continue;
            const double *k = b->phi_kernel + (size_t)fp * e->bins;
            for (int i = 0; i < b->phi_count[fp]; ++i) {
                int c = (b->phi_lo[fp] + i) % e->bins;
                dst[3 * c] += (float)(k[c] * v[0]);
                dst[3 * c + 1] += (float)(k[c] * v[1]);
                dst[3 * c + 2] += (float)(k[c] * v[2]);
            }
        }
    }
}

/* The detectors' kernels (once per build). */
static int make_kernels(build_ctx *b)
{
    const emission *e = &b->e;
    b->theta_kernel = malloc(sizeof(double) * FINE_THETA * (size_t)e->bands);
    b->phi_kernel = calloc((size_t)FINE_PHI * e->bins * 3, sizeof(double));
    b->phi_lo = malloc(sizeof(int) * 2 * FINE_PHI);
    if (!b->theta_kernel || !b->phi_kernel || !b->phi_lo)
        return 0;
    b->phi_count = b->phi_lo + FINE_PHI;
    for (int ft = 0; ft < FINE_THETA; ++ft)
        band_masses(b->theta_kernel + (size_t)ft * e->bands, e->bands, b->p->beta_m,
                    -HALF_PI + (ft + 0.5) * PLM_PI / FINE_THETA);
    double *tmp = b->phi_kernel + (size_t)FINE_PHI * e->bins; /* scratch: the calloc's spare 2/3 */
    for (int fp = 0; fp < FINE_PHI; ++fp) {
        memset(tmp, 0, sizeof(double) * 3 * (size_t)e->bins);
        plm_fiber_gn_deposit(tmp, e->bins, b->p->beta_n, rgb_make(1.0, 0.0, 0.0),
                             -PLM_PI + (fp + 0.5) * PLM_TWO_PI / FINE_PHI);
        double *k = b->phi_kernel + (size_t)fp * e->bins;
        for (int c = 0; c < e->bins; ++c)
            k[c] = tmp[3 * c];
        /* G_N reaches 6 std-devs (plm_fiber_gn_deposit): the bins within that of the centre's. */
        double w = PLM_TWO_PI / e->bins;
        int half = (int)ceil(6.0 * b->p->beta_n / w) + 1, centre = (int)((fp + 0.5) / FINE_PHI * e->bins);
        b->phi_count[fp] = 2 * half + 1 < e->bins ? 2 * half + 1 : e->bins;
        b->phi_lo[fp] = b->phi_count[fp] == e->bins ? 0 : ((centre - half) % e->bins + e->bins) % e->bins;
    }
    return 1;
}

/* The emission of medulla point `point`: the mean over quasi-random diffuse
 * directions (a rank-1 lattice with a per-point shift) of the lobes that
 * follow, by lobe index, then summed into the classes. */
static void build_emission(build_ctx *b, int point, double *scratch, plm_fiber_lobe *lobes)
{
    const plm_fiber_params *p = b->p;
    emission *e = &b->e;
    int K = b->m->res.directions, max_lobes = p->lobes - 1;
    double *hist = scratch, *band_row = hist + fine_floats() * (size_t)e->classes;
    memset(hist, 0, sizeof(double) * fine_floats() * (size_t)e->classes);
    double t = PLM_TWO_PI * point / e->points;
    uint64_t hash = plm_hash64(0x3ed, (uint64_t)point, 1);
    double s1 = (hash >> 11) * 0x1.0p-53, s2 = (plm_hash64(hash, 2, 3) >> 11) * 0x1.0p-53;
    plm_rng rng; /* later bounces */
    plm_rng_seed(&rng, 0x3ed, (uint64_t)point);
    for (int i = 0; i < K; ++i) {
        double u1 = (i + s1) / K, u2 = fmod(i * 0.6180339887498949 + s2, 1.0);
        int n = plm_fiber_trace_from_medulla(p, t, u1, u2, &rng, lobes, max_lobes);
        for (int k = 0; k < n; ++k)
            fine_deposit(hist + fine_floats() * (size_t)(k < e->classes ? k : e->classes - 1),
                         plm_safe_asin(lobes[k].dir.z), atan2(lobes[k].dir.y, lobes[k].dir.x),
                         rgb_scale(lobes[k].throughput, 1.0 / K));
    }
    /* Class c holds the lobes of indices up to c (the last: all of them). */
    size_t per = emission_floats(e);
    float *out = e->mass + per * (size_t)point * (size_t)e->classes;
    memset(out, 0, sizeof(float) * per * (size_t)e->classes);
    for (int c = 0; c < e->classes; ++c) {
        blur(b, hist + fine_floats() * (size_t)c, band_row, out + per * (size_t)c);
        if (c + 1 < e->classes)
            memcpy(out + per * (size_t)(c + 1), out + per * (size_t)c, sizeof(float) * per);
    }
}

/* Pools the emission over the fiber's symmetries, which map medulla points
 * onto medulla points (their count is even, a multiple of 4 for a
 * rotationally symmetric table) and emission bins onto emission bins (their
 * count even, and for a rotation a multiple of the points'): a rotation by t
 * turns phi by t; x -> -x takes t to pi - t and phi to pi - phi; y -> -y
 * takes t and phi to -t and -phi. Each point's emission becomes the mean of its
 * images, which has the same expectation and less noise. */
static int symmetrize(build_ctx *b, int symmetry)
{
    emission *e = &b->e;
    int P = e->points;
    size_t per = emission_floats(e), all = per * (size_t)e->classes * (size_t)P;
    int bins = e->bins, shift = bins / P, group = symmetry == PLM_FIBER_TABLE_ROTATIONAL ? P
                                                        : symmetry == PLM_FIBER_TABLE_MIRROR_XY ? 4
                                                        : symmetry == PLM_FIBER_TABLE_NONE      ? 1
                                                                                                : 2;
    if (group == 1)
        return 1;
    float *copy = malloc(sizeof(float) * all);
    if (!copy)
        return 0;
    memcpy(copy, e->mass, sizeof(float) * all);
    for (int k = 0; k < P; ++k)
        for (int cls = 0; cls < e->classes; ++cls) {
            float *dst = e->mass + per * ((size_t)k * e->classes + cls);
            memset(dst, 0, sizeof(float) * per);
            for (int g = 0; g < group; ++g) {
                /* The image point and how bins map: bin c of it lands on bin (sign c + offset). */
                int mx = 0, my = 0, rot = 0;
                if (symmetry == PLM_FIBER_TABLE_ROTATIONAL)
                    rot = g;
                else if (symmetry == PLM_FIBER_TABLE_MIRROR_XY)
                    mx = g & 1, my = g >> 1;
                else
                    mx = g && symmetry == PLM_FIBER_TABLE_MIRROR_X, my = g && symmetry == PLM_FIBER_TABLE_MIRROR_Y;
                int src = k - rot; /* rotation: E(k) = E(k - g) turned by g points */
                if (mx)
                    src = P / 2 - src;
                if (my)
                    src = -src;
                src = ((src % P) + P) % P;
                const float *from = copy + per * ((size_t)src * e->classes + cls);
                for (int a = 0; a < e->bands; ++a)
                    for (int c = 0; c < bins; ++c) {
                        int to = c + rot * shift; /* centre -pi + (c + 1/2) w */
                        if (mx)
                            to = bins / 2 - 1 - to;
                        if (my)
                            to = bins - 1 - to;
                        to = ((to % bins) + bins) % bins;
                        for (int ch = 0; ch < 3; ++ch)
                            dst[3 * ((size_t)a * bins + to) + ch] += from[3 * ((size_t)a * bins + c) + ch] / group;
                    }
            }
        }
    free(copy);
    return 1;
}

/* Where the centre of each of the node's columns falls among the emission's
 * bins (origin: the columns' azimuth at the view's phi_o): between bins
 * e0[c] and e1[c], at fraction ef[c]. */
static void map_columns(const build_ctx *b, double origin, int *e0, int *e1, double *ef)
{
    int cols = b->m->res.phi_bins, bins = b->e.bins;
    double w = PLM_TWO_PI / cols, we = PLM_TWO_PI / bins;
    for (int c = 0; c < cols; ++c) {
        double x = (origin + (c + 0.5) * w) / we - 0.5; /* -pi + ... + pi cancel */
        double fl = floor(x);
        e0[c] = (int)(fl - bins * floor(fl / bins));
        e1[c] = (e0[c] + 1) % bins;
        ef[c] = x - fl;
    }
}

/* Where medulla point t falls among P points (linear in t between them):
 * between k0 (returned) and *k1, the next (wrapping), at fraction *f. */
static int point_split(double t, int P, int *k1, double *f)
{
    double x = t / PLM_TWO_PI * P, fl = floor(x);
    int k0 = (int)(fl - P * floor(fl / P));
    *f = x - fl;
    *k1 = (k0 + 1) % P;
    return k0;
}

/* The light reaching each medulla point from h cell j seen from wo, per lobe
 * class (RGB; split linearly between the two nearest tabulated points), by
 * the midpoint rule in asin(s) with `sub` samples, s = h / h_reach (per
 * unit s). */
static void cell_reach(const build_ctx *b, vec3 wo, double h_reach, int j, int sub, double *reach,
                       plm_fiber_lobe *lobes)
{
    const plm_fiber_params *p = b->p;
    memset(reach, 0, sizeof(double) * 3 * POINTS * (size_t)b->e.classes);
    double g0 = asin(b->m->h_node[j]), g1 = asin(b->m->h_node[j + 1]), dg = (g1 - g0) / sub;
    for (int s = 0; s < sub; ++s) {
        double g = g0 + (s + 0.5) * dg;
        plm_fiber_medulla_hit hit;
        if (!plm_fiber_trace_to_medulla(p, wo, h_reach * sin(g), lobes, &hit))
            continue;
        double f;
        int k1, k0 = point_split(hit.t, POINTS, &k1, &f);
        int cls = class_of(p->lobes - hit.lobes, b->e.classes);
        rgb T = rgb_scale(hit.throughput, cos(g) * dg);
        double *r0 = reach + 3 * ((size_t)cls * POINTS + k0), *r1 = reach + 3 * ((size_t)cls * POINTS + k1);
        r0[0] += (1 - f) * T.r, r0[1] += (1 - f) * T.g, r0[2] += (1 - f) * T.b;
        r1[0] += f * T.r, r1[1] += f * T.g, r1[2] += f * T.b;
    }
}

/* A cell's bin masses (RGB, band-major): each point's emission, weighted by
 * the light reaching it, resampled at the node's columns (linear between
 * emission bins, scaled from their width to a column's). */
static void cell_masses(const build_ctx *b, const double *reach, const int *e0, const int *e1, const double *ef,
                        double *cell)
{
    const emission *e = &b->e;
    int bands = b->m->res.theta_bins, cols = b->m->res.phi_bins;
    double scale = (double)e->bins / cols;
    memset(cell, 0, sizeof(double) * 3 * (size_t)bands * cols);
    for (int cls = 0; cls < e->classes; ++cls)
        for (int k = 0; k < POINTS; ++k) {
            const double *T = reach + 3 * ((size_t)cls * POINTS + k);
            if (T[0] == 0.0 && T[1] == 0.0 && T[2] == 0.0)
                continue;
            const float *em = emission_at(e, k, cls);
            for (int a = 0; a < bands; ++a) {
                const float *ea = em + 3 * (size_t)a * e->bins;
                double *ca = cell + 3 * (size_t)a * cols;
                for (int c = 0; c < cols; ++c) {
                    const float *v0 = ea + 3 * e0[c], *v1 = ea + 3 * e1[c];
                    double f1 = ef[c] * scale, f0 = scale - f1;
                    for (int ch = 0; ch < 3; ++ch)
                        ca[3 * c + ch] += T[ch] * (f0 * v0[ch] + f1 * v1[ch]);
                }
            }
        }
}

/* The next cumulative row: S(j + 1, a, c) = S(j, a, c) + the cell's mass of
 * band a below column c, kept in `row` (RGB, double) and stored into dst in
 * the table's layout. */
static void store_row(const plm_fiber_medulla_table *m, const double *cell, double *row, float *dst)
{
    int bands = m->res.theta_bins, cols = m->res.phi_bins;
    for (int a = 0; a < bands; ++a) {
        double below[3] = {0.0, 0.0, 0.0};
        for (int c = 0; c <= cols; ++c) {
            size_t o = 3 * ((size_t)a * (cols + 1) + c);
            for (int ch = 0; ch < 3; ++ch)
                row[o + ch] += below[ch];
            for (int ch = 0; ch < 3; ++ch)
                dst[o + ch] = (float)row[o + ch];
            for (int ch = 0; c < cols && ch < 3; ++ch)
                below[ch] += cell[3 * ((size_t)a * cols + c) + ch];
        }
        memcpy(dst + band_offset(m) + 3 * a, dst + 3 * ((size_t)a * (cols + 1) + cols), 3 * sizeof(float));
    }
    for (int ch = 0; ch < 3; ++ch) {
        double total = 0.0;
        for (int a = 0; a < bands; ++a)
            total += row[3 * ((size_t)a * (cols + 1) + cols) + ch];
        dst[total_offset(m) + ch] = (float)total;
    }
}

/* One view node of a rotationally symmetric table: per h cell, the light
 * reaching each medulla point, then those points' emission resampled at
 * the node's columns, summed into cumulative rows (row 0 is all zeros). */
static void build_node(build_ctx *b, int node, double *scratch, plm_fiber_lobe *lobes)
{
    const plm_fiber_medulla_table *m = b->m;
    int bands = m->res.theta_bins, cols = m->res.phi_bins;
    int it = node / m->res.phi_nodes, ip = node % m->res.phi_nodes;
    double theta_o = plm_fiber_node_theta(m->eta, m->u_last, m->theta_max, m->res.theta_nodes, it);
    double phi_o = m->phi_lo + ip * m->phi_step;
    double *reach = scratch, *cell = reach + 3 * (size_t)POINTS * (size_t)b->e.classes;
    double *row = cell + 3 * (size_t)bands * cols, *ef = row + 3 * (size_t)bands * (cols + 1);
    int *e0 = (int *)(ef + cols), *e1 = e0 + cols;
    map_columns(b, phi_o, e0, e1, ef); /* columns over phi_i - phi_o */
    float *out = m->data + node_floats(m) * (size_t)node;
    memset(row, 0, sizeof(double) * 3 * (size_t)bands * (cols + 1));
    for (size_t x = 0; x < row_floats(m); ++x)
        out[x] = 0.0f;
    int sub = plm_fiber_h_sub_samples(b->p->beta_n, m->res.h_cells);
    double h_reach = plm_fiber_medulla_reach(m, sin(theta_o), cos(theta_o));
    for (int j = 0; j < m->res.h_cells; ++j) {
        cell_reach(b, plm_fiber_direction(theta_o, phi_o), h_reach, j, sub, reach, lobes);
        cell_masses(b, reach, e0, e1, ef, cell);
        store_row(m, cell, row, out + row_floats(m) * (size_t)(j + 1));
    }
}

/* ---- building a factored table ------------------------------------------ */

/* Adds light T (RGB) times c reaching the medulla at point position x (in
 * [0, P], t P / (2 pi), from point_split) to w (w[channel stride +
 * point]), split linearly between the two nearest of the P points. */
static void add_light(float *w, size_t stride, int P, float x, float c, const float *T)
{
    int k0 = (int)x;
    float f = x - (float)k0, a = (1.0f - f) * c, b = f * c;
    k0 = k0 < P ? k0 : 0; /* x rounded up onto P, which is point 0 */
    int k1 = k0 + 1 < P ? k0 + 1 : 0;
    for (int ch = 0; ch < 3; ++ch) {
        w[ch * stride + (size_t)k0] += a * T[ch];
        w[ch * stride + (size_t)k1] += b * T[ch];
    }
}

/* The emission into the table's layout (its one class: all the lobes a path
 * may store after the medulla) and each point's sampling table, whose
 * cumulative sums run over the stored means, so that what sampling reads
 * is what pdf reads up to rounding. */
static int store_emission(const build_ctx *b)
{
    const plm_fiber_medulla_table *m = b->m;
    int P = m->res.points, bands = m->res.theta_bins, bins = m->res.phi_bins;
    for (int x = 0; x < bands * bins; ++x)
        for (int k = 0; k < P; ++k) {
            const float *src = b->e.mass + emission_floats(&b->e) * (size_t)k + 3 * (size_t)x;
            float *dst = m->data + 4 * (size_t)P * (size_t)x;
            for (int ch = 0; ch < 3; ++ch)
                dst[ch * P + k] = src[ch];
            dst[3 * P + k] = (float)(((double)src[0] + src[1] + src[2]) / 3.0);
        }
    float *energy = m->data + emission_block(m);
    for (int k = 0; k < P; ++k) {
        float *band = point_sampling(m, k), *row = band + bands + 1;
        double total[3] = {0.0, 0.0, 0.0}, mean = 0.0;
        band[0] = 0.0f;
        for (int a = 0; a < bands; ++a, row += bins + 1) {
            double acc = 0.0;
            row[0] = 0.0f;
            for (int c = 0; c < bins; ++c) {
                const float *v = m->data + 4 * (size_t)P * ((size_t)a * bins + c);
                for (int ch = 0; ch < 3; ++ch)
                    total[ch] += v[ch * P + k];
                acc += v[3 * P + k];
                row[c + 1] = (float)acc;
            }
            mean += row[bins];
            band[a + 1] = (float)mean;
        }
        for (int ch = 0; ch < 3; ++ch)
            energy[ch * P + k] = (float)total[ch];
        energy[3 * P + k] = band[bands];
    }
    return 1;
}

/* One view node of a factored table: `records` h samples per cell (the
 * midpoint rule in asin(h)), each path traced to the medulla and kept as the
 * position of the point it reaches among the points (add_light) and the
 * light it brings times its width in h; and the cumulative rows of that
 * light per point (row 0 is all zeros). */
static void build_factored_node(build_ctx *b, int node, double *scratch, plm_fiber_lobe *lobes)
{
    const plm_fiber_medulla_table *m = b->m;
    int P = m->res.points, S = m->res.records, cells = m->res.h_cells;
    int it = node / m->res.phi_nodes, ip = node % m->res.phi_nodes;
    vec3 wo = plm_fiber_direction(plm_fiber_node_theta(m->eta, m->u_last, m->theta_max, m->res.theta_nodes, it),
                                  m->phi_lo + ip * m->phi_step);
    float *rows = node_light(m, node), *rec = rows + (size_t)(cells + 1) * light_row(m);
    float *cell = (float *)(scratch + light_row(m)); /* one cell's light, summed into the rows in double */
    double dg = PLM_PI / ((double)cells * S);
    memset(scratch, 0, sizeof(double) * light_row(m));
    memset(rows, 0, sizeof(float) * light_row(m));
    for (int j = 0; j < cells; ++j) {
        memset(cell, 0, sizeof(float) * light_row(m));
        for (int s = 0; s < S; ++s) {
            float *r = rec + 4 * ((size_t)j * S + s);
            double g = -HALF_PI + ((double)j * S + s + 0.5) * dg;
            plm_fiber_medulla_hit hit;
            memset(r, 0, 4 * sizeof(float));
            if (!plm_fiber_trace_to_medulla(b->p, wo, sin(g), lobes, &hit))
                continue;
            rgb T = rgb_scale(hit.throughput, cos(g) * dg);
            double f;
            int k1, k0 = point_split(hit.t, P, &k1, &f);
            r[0] = (float)(k0 + f), r[1] = (float)T.r, r[2] = (float)T.g, r[3] = (float)T.b;
            add_light(cell, (size_t)P, P, r[0], 1.0f, r + 1);
        }
        float *row = rows + (size_t)(j + 1) * light_row(m);
        for (size_t i = 0; i < light_row(m); ++i)
            row[i] = (float)(scratch[i] += cell[i]);
    }
}

static void emission_work(void *ctx, int item, double *scratch, plm_fiber_lobe *lobes)
{
    build_emission(ctx, item, scratch, lobes);
}

static void node_work(void *ctx, int item, double *scratch, plm_fiber_lobe *lobes)
{
    build_ctx *b = ctx;
    if (b->m->factored)
        build_factored_node(b, item, scratch, lobes);
    else
        build_node(b, item, scratch, lobes);
}

/* The emission's layout: a rotationally symmetric table's (classes of lobe
 * budgets, PHI_REFINE bins per column, a multiple of the points), or a
 * factored table's (one class, its own points and bins). */
static emission emission_layout(const plm_fiber_params *p, const plm_fiber_medulla_table *m)
{
    if (m->factored)
        return (emission){m->res.points, 1, m->res.theta_bins, m->res.phi_bins, NULL};
    return (emission){POINTS, p->lobes - 1 < MAX_CLASSES ? p->lobes - 1 : MAX_CLASSES, m->res.theta_bins,
                      (PHI_REFINE * m->res.phi_bins + POINTS - 1) / POINTS * POINTS, NULL};
}

/* Scratch per thread for a view node. */
static size_t node_scratch(const build_ctx *b)
{
    const plm_fiber_medulla_table *m = b->m;
    if (m->factored)
        return (sizeof(double) + sizeof(float)) * light_row(m);
    int cols = m->res.phi_bins, bands = m->res.theta_bins;
    return sizeof(double) * (3 * (size_t)POINTS * b->e.classes + 3 * (size_t)bands * cols +
                             3 * (size_t)bands * (cols + 1) + (size_t)cols) +
           sizeof(int) * 2 * (size_t)cols;
}

plm_result plm_fiber_medulla_build(const plm_fiber_params *p, plm_fiber_medulla_table *m, int threads, int quiet,
                                   double started, plm_error *err)
{
    if (m->res.theta_nodes == 0)
        return PLM_OK;
    build_ctx b = {p, m, emission_layout(p, m), NULL, NULL, NULL, NULL};
    size_t per = emission_floats(&b.e);
    b.e.mass = malloc(sizeof(float) * per * (size_t)b.e.classes * (size_t)b.e.points);
    size_t emission_scratch = sizeof(double) * (fine_floats() * (size_t)b.e.classes + 3 * (size_t)FINE_PHI);
    int ok = b.e.mass && make_kernels(&b) &&
             plm_fiber_parallel(emission_work, &b, b.e.points, emission_scratch, p->lobes, threads, quiet, "medulla emission",
                                started) &&
             symmetrize(&b, m->symmetry) && (!m->factored || store_emission(&b)) &&
             plm_fiber_parallel(node_work, &b, node_count(m), node_scratch(&b), p->lobes, threads, quiet, "medulla views",
                                started);
    free(b.e.mass);
    free(b.theta_kernel);
    free(b.phi_kernel);
    free(b.phi_lo);
    return ok ? PLM_OK : plm_fail(err, PLM_ERR_NO_MEMORY, "fiber table: out of memory (medulla)");
}

/* ---- queries ------------------------------------------------------------- */

/* A rotationally symmetric table's sampling picks a view node by its
 * energy, then a band and a bin in that node's terms alone (a quarter of them for four nodes); pdf and eval read
 * all terms at once, and their density is the sampler's, the sum over the
 * nodes, up to rounding. Sums over terms are taken per channel in the
 * terms' order and what pdf and sampling read of a column is the sum of
 * those three sums, so that a band's mass is exactly the end of its
 * cumulative row. */

/* The sum of the RGB at offset o (a column: the sampler's cumulative row;
 * a band's or the row's total) over terms k0 .. k1 - 1. */
static double sum_at(const plm_fiber_medulla_query *q, int k0, int k1, size_t o)
{
    double r = 0.0, g = 0.0, b = 0.0;
    for (int k = k0; k < k1; ++k) {
        const float *v = q->term[k] + o;
        double c = q->coef[k];
        r += c * v[0];
        g += c * v[1];
        b += c * v[2];
    }
    return r + g + b;
}

/* asin of s in [-1, 1]; the ends, where intervals reaching past h_reach
 * clamp, without a library call. */
static double clamped_asin(double s) { return s == 1.0 ? HALF_PI : s == -1.0 ? -HALF_PI : asin(s); }

/* The rows and coefficients whose combination is the part's mean over the
 * view's interval [h-, h+]. Rows over s = h / h_reach hold the integral
 * over s of the part g(s) = f(h_reach s): the mean of f over [h-, h+] is
 * h_reach (s+ - s-) / (h+ - h-) times the mean of g over [s-, s+] (s
 * clamped to [-1, 1], where g is 0), and at a point f(h) = g(s). */
static void interval_rows(const plm_fiber_medulla_table *m, const plm_fiber_view *v, plm_fiber_h_rows *rows)
{
    double reach = plm_fiber_medulla_reach(m, v->sin_theta, v->cos_theta), width = v->hmax - v->hmin;
    if (reach == 1.0) { /* s = h */
        plm_fiber_interval_rows(m->h_node, m->res.h_cells, v, rows);
        return;
    }
    plm_fiber_view s = *v;
    s.hmin = plm_clamp(v->hmin / reach, -1.0, 1.0);
    s.hmax = plm_clamp(v->hmax / reach, -1.0, 1.0);
    s.asin_hmin = clamped_asin(s.hmin);
    s.asin_hmax = clamped_asin(s.hmax);
    plm_fiber_interval_rows(m->h_node, m->res.h_cells, &s, rows);
    /* A point takes g(s) as it is, or 0 beyond the reach, where s was clamped onto the last cell. */
    double scale =
        width < PLM_FIBER_POINT_WIDTH ? (fabs(v->hmin) < reach ? 1.0 : 0.0) : reach * (s.hmax - s.hmin) / width;
    for (int r = 0; r < rows->n; ++r)
        rows->coef[r] *= scale;
}

/* The sum of eight partial sums, in a fixed order. */
static PLM_VECTOR_INLINE double sum8(const float s[8])
{
    return (double)(((s[0] + s[4]) + (s[1] + s[5])) + ((s[2] + s[6]) + (s[3] + s[7])));
}

/* The sum over k < n of a[k] b[k] (n a multiple of 8), in eight partial
 * sums that the compiler keeps in vector registers. */
static PLM_VECTOR_INLINE double dot(const float *a, const float *b, int n)
{
    float s[8] = {0.0f};
    for (int k = 0; k < n; k += 8)
        for (int i = 0; i < 8; ++i)
            s[i] += a[k + i] * b[k + i];
    return sum8(s);
}

/* Per channel ch < 3, into v[ch], the sum over k < n of w[ch][k] times
 * c[0] b[0][ch n + k] + ... + c[3] b[3][ch n + k] (n a multiple of 8; b[i]
 * RGB, each over the n points), in eight partial sums per channel as dot(),
 * the three channels in one pass. */
static PLM_VECTOR_INLINE void dot_mix(const float (*w)[PLM_FIBER_MEDULLA_POINTS], const float *const b[4],
                                      const float c[4], int n, double v[3])
{
    const float *b0 = b[0], *b1 = b[1], *b2 = b[2], *b3 = b[3];
    float c0 = c[0], c1 = c[1], c2 = c[2], c3 = c[3], s[3][8] = {{0.0f}};
    for (int k = 0; k < n; k += 8)
        for (int ch = 0; ch < 3; ++ch)
            for (int i = 0; i < 8; ++i) {
                size_t o = (size_t)ch * (size_t)n + (size_t)(k + i);
                s[ch][i] += w[ch][k + i] * (c0 * b0[o] + c1 * b1[o] + c2 * b2[o] + c3 * b3[o]);
            }
    for (int ch = 0; ch < 3; ++ch)
        v[ch] = sum8(s[ch]);
}

/* Adds the light of the four nodes' h samples over [x0, x1] (in samples
 * from h = -1; each the share of its width the range covers), times k[c]
 * for node c's records rec[c], to acc: per point four floats, the light
 * (RGB) in the last three as in a record, split between the two points
 * around the record's position (point P + 1 stands for 1 and P for 0, for a
 * position rounded up onto P). A record adds its four floats whole, a
 * vector operation per point with no scattered channels; the position it
 * carries in its first float lands in the first, which is never read, and
 * a path that missed the medulla (no light) adds zeros, so no test. */
static PLM_VECTOR_INLINE void add_samples(float (*acc)[4], const float *const rec[4], const float k[4], double x0,
                                           double x1)
{
    int first = (int)x0, last = (int)ceil(x1) - 1;
    for (int i = first; i <= last; ++i) {
        float share = (float)((i == last ? x1 - i : 1.0) - (i == first ? x0 - i : 0.0));
        for (int c = 0; c < 4; ++c) {
            float v[4], lo[4], hi[4]; /* the record, and points k0 and k0 + 1: loaded before any store */
            memcpy(v, rec[c] + 4 * (size_t)i, sizeof v);
            int k0 = (int)v[0];
            float whole = share * k[c], b = (v[0] - (float)k0) * whole, a = whole - b;
            memcpy(lo, acc[k0], sizeof lo);
            memcpy(hi, acc[k0 + 1], sizeof hi);
            for (int j = 0; j < 4; ++j) {
                lo[j] += a * v[j];
                hi[j] += b * v[j];
            }
            memcpy(acc[k0], lo, sizeof lo);
            memcpy(acc[k0 + 1], hi, sizeof hi);
        }
    }
}

/* w_r, w_g, w_b += acc's last three floats per point (of n; the arrays do
 * not overlap, so the loop vectorizes, four points a pass). */
static PLM_VECTOR_INLINE void add_channels(float *restrict w_r, float *restrict w_g, float *restrict w_b,
                                            const float (*restrict acc)[4], int n)
{
    for (int t = 0; t < n; ++t) {
        w_r[t] += acc[t][1];
        w_g[t] += acc[t][2];
        w_b[t] += acc[t][3];
    }
}

/* w[k] = (add ? w[k] : 0) + sum over i < 4 of c[i] r[i][k], k < n (the
 * arrays do not overlap, so the loop vectorizes). */
static PLM_VECTOR_INLINE void mix_rows(float *restrict w, const float *restrict r0, const float *restrict r1,
                                       const float *restrict r2, const float *restrict r3, const float c[4], int n,
                                       int add)
{
    float c0 = c[0], c1 = c[1], c2 = c[2], c3 = c[3];
    for (int k = 0; k < n; ++k)
        w[k] = (add ? w[k] : 0.0f) + c0 * r0[k] + c1 * r1[k] + c2 * r2[k] + c3 * r3[k];
}

/* The query's weights as the sum of coef[t] row[t] over n cumulative rows
 * (n >= 1), four rows a pass; a pass short of four repeats the first row
 * with weight 0. */
PLM_VECTOR_CLONES static void set_rows(plm_fiber_medulla_query *q, const float *const *row, const float *coef, int n)
{
    int P = q->table->res.points;
    for (int t = 0; t < n; t += 4) {
        const float *r[4];
        float c[4];
        for (int i = 0; i < 4; ++i) {
            r[i] = t + i < n ? row[t + i] : row[0];
            c[i] = t + i < n ? coef[t + i] : 0.0f;
        }
        for (int ch = 0; ch < 3; ++ch)
            mix_rows(q->w[ch], r[0] + ch * P, r[1] + ch * P, r[2] + ch * P, r[3] + ch * P, c, P, t > 0);
    }
}

/* Asks the cache for memory that is about to be read, where the compiler
 * can (GCC and clang); elsewhere nothing. */
#if defined(__GNUC__)
#define PREFETCH(p) __builtin_prefetch(p)
#else
#define PREFETCH(p) ((void)(p))
#endif

/* Adds to q->w the light of the four nodes' h samples (records rec[c])
 * over each range x[e] (an interval end and its cell bound; none if
 * empty), times wn[c] scale sign[e]: summed point by point, then added to
 * the channels. */
PLM_VECTOR_CLONES static void end_samples(plm_fiber_medulla_query *q, int P, const float *const rec[4],
                                          const double wn[4], double scale, const double x[2][2],
                                          const float sign[2])
{
    float acc[PLM_FIBER_MEDULLA_POINTS + 2][4]; /* point-major: add_samples */
    memset(acc, 0, sizeof(float) * 4 * (size_t)(P + 2));
    for (int e = 0; e < 2; ++e) {
        const float k[4] = {(float)(wn[0] * scale) * sign[e], (float)(wn[1] * scale) * sign[e],
                            (float)(wn[2] * scale) * sign[e], (float)(wn[3] * scale) * sign[e]};
        if (x[e][1] > x[e][0])
            add_samples(acc, rec, k, x[e][0], x[e][1]);
    }
    for (int j = 0; j < 2; ++j) /* points P and P + 1 are 0 and 1 */
        for (int ch = 1; ch < 4; ++ch)
            acc[j][ch] += acc[P + j][ch];
    add_channels(q->w[0], q->w[1], q->w[2], (const float(*)[4])acc, P);
}

/* The light reaching each point (q->w), its mean over the view's interval
 * blended over the nodes with weights wn. With F(x) the light of the h
 * samples up to x (in samples from h = -1), the mean is F(x1) - F(x0) over
 * the width: F at the cell bound nearest each end from the cumulative
 * rows, and the h samples between the bound and the end added or
 * subtracted (at most half a cell's), all four nodes' in one pass over the
 * samples. At a point interval, the density of the sample holding h. The
 * samples' records are fetched into the cache before the rows are summed:
 * a random partial interval's are rarely there, and their misses then
 * overlap the rows'. */
static void factored_light(const plm_fiber_medulla_table *m, const plm_fiber_view *v, const int nodes[4],
                           const double wn[4], plm_fiber_medulla_query *q)
{
    int S = m->res.records, n = m->res.h_cells * S, P = m->res.points, terms = 0;
    double dg = PLM_PI / n, width = v->hmax - v->hmin;
    double x0 = plm_clamp((v->asin_hmin + HALF_PI) / dg, 0.0, n), x1 = plm_clamp((v->asin_hmax + HALF_PI) / dg, 0.0, n);
    int point = width < PLM_FIBER_POINT_WIDTH, i = x0 < n - 1 ? (int)x0 : n - 1;
    int lo = (int)floor(x0 / S + 0.5), hi = (int)floor(x1 / S + 0.5); /* the nearest cell bounds */
    double scale = point ? 1.0 / (sin(-HALF_PI + (i + 1) * dg) - sin(-HALF_PI + i * dg)) : 1.0 / width;
    /* The samples between each end and its bound, added (an end beyond its bound) or subtracted. */
    double x[2][2] = {{fmin(x0, lo * S), fmax(x0, lo * S)}, {fmin(x1, hi * S), fmax(x1, hi * S)}};
    float sign[2] = {x0 < lo * S ? 1.0f : -1.0f, x1 > hi * S ? 1.0f : -1.0f};
    if (point)
        x[0][0] = i, x[0][1] = i + 1.0, x[1][0] = x[1][1] = 0.0, sign[0] = 1.0f;
    int samples = x[0][1] > x[0][0] || x[1][1] > x[1][0];
    const float *rec[4];
    for (int c = 0; samples && c < 4; ++c) {
        rec[c] = node_light(m, nodes[c]) + (size_t)(m->res.h_cells + 1) * light_row(m);
        for (int e = 0; e < 2; ++e)
            if (x[e][1] > x[e][0]) { /* a range's first and last records: it spans at most three cache
                                      * lines (past its last by one where it ends on a sample's edge) */
                PREFETCH(rec[c] + 4 * (size_t)x[e][0]);
                PREFETCH(rec[c] + 4 * (size_t)x[e][1]);
            }
    }
    const float *row[8];
    float coef[8];
    for (int c = 0; c < 4; ++c) {
        const float *rows = node_light(m, nodes[c]);
        float k = (float)(wn[c] * scale);
        if (wn[c] == 0.0 || point || hi == lo)
            continue;
        row[terms] = rows + light_row(m) * (size_t)hi, coef[terms++] = k;
        if (lo > 0) /* row 0 is all zeros */
            row[terms] = rows + light_row(m) * (size_t)lo, coef[terms++] = -k;
    }
    if (terms)
        set_rows(q, row, coef, terms);
    else
        for (int ch = 0; ch < 3; ++ch)
            memset(q->w[ch], 0, sizeof(float) * (size_t)P);
    if (samples)
        end_samples(q, P, rec, wn, scale, (const double(*)[2])x, sign);
}

/* The query's wbar from its weights w, and from those and the points'
 * emitted energy (RGB and mean, each over the P points, a multiple of 8)
 * the part's energy and the sampler's norm, the four sums in one pass. */
PLM_VECTOR_CLONES static void point_sums(plm_fiber_medulla_query *q, const float *energy, int P)
{
    for (int k = 0; k < P; ++k) {
        float mean = (q->w[0][k] + q->w[1][k] + q->w[2][k]) * (1.0f / 3.0f);
        q->wbar[k] = mean > 0.0f ? mean : 0.0f;
    }
    float s[4][8] = {{0.0f}}; /* per channel (RGB, wbar) eight partial sums, as dot() */
    for (int k = 0; k < P; k += 8)
        for (int i = 0; i < 8; ++i) {
            for (int ch = 0; ch < 3; ++ch)
                s[ch][i] += q->w[ch][k + i] * energy[ch * P + k + i];
            s[3][i] += q->wbar[k + i] * energy[3 * P + k + i];
        }
    double sum = sum8(s[0]) + sum8(s[1]) + sum8(s[2]);
    q->norm = sum8(s[3]);
    q->sum = q->norm > 0.0 ? plm_positive(sum) : 0.0; /* nothing to sample: nothing to see */
    q->total = q->sum / 3.0;
}

/* A factored table's query: the points' weights, the part's energy (the
 * weights times the points' emitted energy) and the sampler's norm. */
static void factored_prepare(const plm_fiber_medulla_table *m, const plm_fiber_view *v, const int nodes[4],
                             const double wn[4], plm_fiber_medulla_query *q)
{
    factored_light(m, v, nodes, wn, q);
    point_sums(q, point_energy(m), m->res.points);
}

void plm_fiber_medulla_prepare(const plm_fiber_medulla_table *m, const struct plm_fiber_view *v,
                               plm_fiber_medulla_query *q)
{
    q->table = NULL;
    q->total = q->sum = 0.0;
    if (m->res.theta_nodes == 0)
        return;
    q->table = m;
    q->phi_o = v->phi_o;
    q->flip = v->flip;
    q->band_width = HALF_PI / m->res.theta_bins;
    q->bin_width = PLM_TWO_PI / m->res.phi_bins;
    q->origin = m->symmetry == PLM_FIBER_TABLE_ROTATIONAL ? 0.0 : v->phi;
    int n = m->res.theta_nodes, nodes[4];
    double w[4], ft = fabs(v->theta_o) < m->theta_max ? plm_fiber_theta_coordinate(m->eta, m->u_last, m->theta_max, n,
                                                                                   fabs(v->theta_o), v->sin_theta,
                                                                                   v->cos_theta)
                                                      : n - 1.0;
    plm_fiber_corners(m->symmetry, n, m->res.phi_nodes, m->phi_lo, m->phi_step, ft, v->phi, nodes, w);
    if (m->factored) {
        /* The blend scaled as the other part's (optics/fiber_table.c's
         * energy_scale): by the interval's energy at three |theta_o| nodes,
         * interpolated quadratically in cos(|theta_o|), over the linear
         * blend's. Both parts alike, so that a white fiber's energies still
         * add up where they share their nodes. */
        int first = plm_fiber_energy_first(n, ft);
        if (first >= 0) {
            /* Each node's energy from its light rows' (bound_energy), the
             * partial cells' taken as spread evenly (the other part's rows
             * do the same; the scale is a ratio). */
            int ip[2], bounds = m->res.h_cells + 1;
            double fp, e[3];
            plm_fiber_phi_weights(m->symmetry, m->res.phi_nodes, m->phi_lo, m->phi_step, v->phi, ip, &fp);
            plm_fiber_h_rows rows;
            plm_fiber_interval_rows(m->h_node, m->res.h_cells, v, &rows);
            for (int k = 0; k < 3; ++k) {
                const float *b = m->bound_energy + (size_t)((first + k) * m->res.phi_nodes) * bounds;
                e[k] = plm_fiber_rows_energy(b + (size_t)ip[0] * bounds, b + (size_t)ip[1] * bounds, fp, &rows);
            }
            double scale = plm_fiber_energy_scale(m->node_cos, n, ft, v->cos_theta, e);
            for (int c = 0; c < 4; ++c)
                w[c] *= scale;
        }
        factored_prepare(m, v, nodes, w, q);
        return;
    }
    plm_fiber_h_rows rows;
    interval_rows(m, v, &rows);
    q->terms = plm_fiber_terms(m->data, node_floats(m), row_floats(m), nodes, w, &rows, q->term, q->coef, q->node_end);
    for (int c = 0; c < 4; ++c) {
        q->node_sum[c] = plm_positive(sum_at(q, c ? q->node_end[c - 1] : 0, q->node_end[c], total_offset(m)));
        q->sum += q->node_sum[c];
    }
    q->total = q->sum / 3.0;
}

/* Column col of band a: its offset in a row. */
static size_t column_offset(const plm_fiber_medulla_query *q, int a, int col)
{
    return 3 * ((size_t)a * (q->table->res.phi_bins + 1) + col);
}

/* The sums of columns col, col + 1 and col + 2 of bands a and a + 1, RGB:
 * s[band][3 column + channel], the terms read once (a fixed count, so the
 * sums stay in registers). */
static void three_columns(const plm_fiber_medulla_query *q, int a, int col, double s[2][9])
{
    size_t o0 = column_offset(q, a, col), o1 = column_offset(q, a + 1, col);
    double x[18] = {0.0};
    for (int k = 0; k < q->terms; ++k) {
        const float *v0 = q->term[k] + o0, *v1 = q->term[k] + o1;
        double c = q->coef[k];
        for (int i = 0; i < 9; ++i) {
            x[i] += c * v0[i];
            x[9 + i] += c * v1[i];
        }
    }
    memcpy(s, x, sizeof x);
}

/* The sums of columns c0, c0 + 1 (bin c0) and c1, c1 + 1 (bin c1, the next,
 * which wraps to 0 after the last) of bands a and a + 1, RGB:
 * col[band][column][channel]. */
static void bin_columns(const plm_fiber_medulla_query *q, int a, int c0, int c1, double col[2][4][3])
{
    double s[2][9], w[2][9];
    if (c1 == c0 + 1) {
        three_columns(q, a, c0, s);
        for (int b = 0; b < 2; ++b) {
            memcpy(col[b][0], s[b], 6 * sizeof(double));
            memcpy(col[b][2], s[b] + 3, 6 * sizeof(double));
        }
    } else { /* c0 the last bin, c1 = 0 */
        three_columns(q, a, c0 - 1, s);
        three_columns(q, a, 0, w);
        for (int b = 0; b < 2; ++b) {
            memcpy(col[b][0], s[b] + 3, 6 * sizeof(double));
            memcpy(col[b][2], w[b], 6 * sizeof(double));
        }
    }
}

/* A factored table's emission in band a, bin c: R, G, B and their mean, each over the points. */
static const float *emission_bin(const plm_fiber_medulla_table *m, int a, int c)
{
    return m->data + 4 * (size_t)m->res.points * ((size_t)a * m->res.phi_bins + c);
}

/* A factored table's eval at wi into *f (if not NULL): the points'
 * emission in the four bins around wi (bands a0, a0 + 1 by bins c0, c1)
 * weighted by c (the bilinear weights over the density's denominator) and
 * by the light reaching the points; returns the sampler's mass in the bin
 * (in_a, in_c), the points' mean emission weighted by wbar, if pdf is not
 * NULL (else 0). */
static PLM_VECTOR_INLINE double factored_lookup(const plm_fiber_medulla_query *q, int a0, int c0, int c1, int in_a,
                                                int in_c, const float c[4], rgb *f, const double *pdf)
{
    const plm_fiber_medulla_table *m = q->table;
    int P = m->res.points;
    if (f) {
        const float *const e[4] = {emission_bin(m, a0, c0), emission_bin(m, a0, c1), emission_bin(m, a0 + 1, c0),
                                   emission_bin(m, a0 + 1, c1)};
        double v[3];
        dot_mix(q->w, e, c, P, v);
        *f = rgb_make(plm_positive(v[0]), plm_positive(v[1]), plm_positive(v[2]));
    }
    return pdf ? dot(q->wbar, emission_bin(m, in_a, in_c) + 3 * P, P) : 0.0;
}

/* Cloned whole, the factored kernels inlined (as is the sampler below):
 * with the kernels alone cloned, the arithmetic that finds the bins ran as
 * the default target's code and each call went through the clones'
 * resolver (docs/fiber.md: eval about 20 ns slower). */
PLM_VECTOR_CLONES void plm_fiber_medulla_lookup(const plm_fiber_medulla_query *q, const double angles[3], rgb *f,
                                                double *pdf)
{
    if (f)
        *f = rgb_gray(0.0);
    if (pdf)
        *pdf = 0.0;
    if (!q->table || !(q->sum > 0.0))
        return;
    const plm_fiber_medulla_table *m = q->table;
    int bands = m->res.theta_bins, cols = m->res.phi_bins;
    double wa = q->band_width, wc = q->bin_width, theta = fabs(angles[0]), ct = angles[2];
    double phi = plm_wrap_pi(q->origin + angles[1]);
    /* Bin centres around wi: below band 0's centre the density is flat (the
     * mirror image of band 0 is itself); beyond the last band's it is
     * extrapolated linearly; columns wrap. What is interpolated is the one
     * of two quantities that is smooth up to the fiber's axis, where eval's
     * 1 / cos^2(theta_i) magnifies any error. Where bands are wider than
     * the detector's beta_m, the lobes' mass per unit theta falls like
     * cos(theta) toward the axis: each bin's density per solid angle (its
     * mass over the integral of cos(theta) across it) stays finite. Where
     * they are narrower, the detector spreads light right up to the axis:
     * the mass per unit theta stays finite, and the density per solid angle
     * grows like 1 / cos(theta), which interpolation overshoots. The bin
     * holding wi, the pdf's, is one of the four. */
    double ya = theta / wa, xa = ya - 0.5, xc = (phi + PLM_PI) / wc - 0.5, flc = floor(xc);
    /* phi in [-pi, pi] puts flc in [-1, cols - 1]: wrapped without a division */
    int a0 = xa < 0.0 ? 0 : (int)xa, c0 = flc < 0.0 ? cols - 1 : (int)flc, c1 = c0 == cols - 1 ? 0 : c0 + 1;
    a0 = a0 > bands - 2 ? bands - 2 : a0;
    int in_a = (int)ya, in_c = xc - flc >= 0.5; /* theta >= 0: truncation is floor */
    in_a = in_a > bands - 1 ? bands - 1 : in_a;
    double fa = xa < 0.0 ? 0.0 : xa - a0, fc = xc - flc, area = 2.0 * wa * wc; /* a band holds both signs */
    /* Over area: a density per solid angle, or (per_theta) per unit theta and phi, which
     * one more 1 / cos(theta_i) turns into one per solid angle; the last is eval's. */
    double mass, norm = q->sum, den = area * (m->per_theta ? ct * ct : ct);
    if (m->factored) {
        /* The bilinear weights of the four bins, as below: the points' emission interpolated first. */
        double lo = (1.0 - fa) * m->band_scale[a0] / den, hi = fa * m->band_scale[a0 + 1] / den;
        const float c[4] = {(float)(lo * (1.0 - fc)), (float)(lo * fc), (float)(hi * (1.0 - fc)), (float)(hi * fc)};
        mass = factored_lookup(q, a0, c0, c1, in_a, in_c ? c1 : c0, c, f, pdf);
        norm = q->norm;
    } else if (f) {
        double col[2][4][3], v[3];
        bin_columns(q, a0, c0, c1, col);
        for (int ch = 0; ch < 3; ++ch) {
            double lo0 = col[0][1][ch] - col[0][0][ch], lo1 = col[0][3][ch] - col[0][2][ch];
            double hi0 = col[1][1][ch] - col[1][0][ch], hi1 = col[1][3][ch] - col[1][2][ch];
            double lo = (lo0 + (lo1 - lo0) * fc) * m->band_scale[a0];
            double hi = (hi0 + (hi1 - hi0) * fc) * m->band_scale[a0 + 1];
            v[ch] = plm_positive((lo * (1.0 - fa) + hi * fa) / den);
        }
        *f = rgb_make(v[0], v[1], v[2]);
        const double(*x)[3] = col[in_a - a0] + 2 * in_c;
        mass = (x[1][0] + x[1][1] + x[1][2]) - (x[0][0] + x[0][1] + x[0][2]);
    } else {
        int bin = in_c ? c1 : c0;
        mass = sum_at(q, 0, q->terms, column_offset(q, in_a, bin + 1)) -
               sum_at(q, 0, q->terms, column_offset(q, in_a, bin));
    }
    /* The sampler never picks a bin of no mass (or less, by rounding). */
    if (pdf)
        *pdf = plm_positive(mass) / (norm * area * ct);
}

/* The row that sampling searches: a factored point's cumulative row, or
 * (row NULL) the rotationally symmetric layout's sums over one node's terms
 * (band a). */
typedef struct sampled_row {
    const plm_fiber_medulla_query *q;
    int k0, k1, a;
    const float *row;
} sampled_row;

/* The last of x[0..n-1] (not decreasing, x[0] <= t) at most t, or 0 if none
 * is (t NaN): the count of those at most t, all compared at once, so that
 * their loads overlap (probes of a search each wait for the one before).
 * Compared as floats with the largest float at most t, which is exact. */
static PLM_VECTOR_INLINE int last_at_most(const float *x, int n, double t)
{
    float g = (float)t;
    if ((double)g > t) { /* rounded up: the float below (t >= x[0] >= 0, so g > 0) */
        uint32_t bits;
        memcpy(&bits, &g, sizeof bits);
        --bits;
        memcpy(&g, &bits, sizeof g);
    }
    int count = 0;
    for (int i = 0; i < n; ++i)
        count += x[i] <= g;
    return count > 0 ? count - 1 : 0;
}

/* wi in band a (the sign of theta_i and the place in the band by u1) and
 * in the bin where the cumulative row reaches u2 times its end `mass`
 * (a factored row's columns all compared at once; the sums' first probes
 * by plm_fiber_search_probe, then bisection), uniform within the bin. */
static PLM_VECTOR_INLINE int direction_in_band(const sampled_row *r, double mass, double u1, double u2,
                                               double angles[3], vec3 *wi)
{
    const plm_fiber_medulla_query *q = r->q;
    double goal = u2 * mass, x0 = 0.0, x1 = mass;
    int lo = 0, hi = q->table->res.phi_bins; /* column lo <= goal < column hi */
    if (r->row) {
        lo = last_at_most(r->row, hi, goal), hi = lo + 1;
        x0 = r->row[lo], x1 = r->row[hi];
    }
    for (int probe = 0; hi - lo > 1; ++probe) {
        int mid = plm_fiber_search_probe(probe, lo, hi, x0, x1, goal);
        double x = sum_at(q, r->k0, r->k1, column_offset(q, r->a, mid));
        if (x <= goal)
            lo = mid, x0 = x;
        else
            hi = mid, x1 = x;
    }
    if (!(x1 > x0))
        return 0;
    /* Kept off the bins' edges by far more than rounding moves an angle, so
     * that the lookup at these angles finds this bin (pdf = the sampler's). */
    double v = u1 < 0.5 ? 2.0 * u1 : 2.0 * u1 - 1.0, edge = 1e-9;
    double theta = (u1 < 0.5 ? -1.0 : 1.0) * (r->a + plm_clamp(v, edge, 1.0 - edge)) * q->band_width;
    double frac = plm_clamp((goal - x0) / (x1 - x0), edge, 1.0 - edge);
    double delta = plm_wrap_pi(-PLM_PI + (lo + frac) * q->bin_width - q->origin);
    *wi = plm_fiber_direction(theta, q->phi_o + (q->flip ? -delta : delta));
    angles[0] = theta;
    angles[1] = delta;
    angles[2] = sqrt(wi->x * wi->x + wi->y * wi->y);
    return 1;
}

/* The point where *target (less the masses wbar(t) energy(t) of the points
 * before it) falls, *target left as what remains of it there; the last
 * point with mass takes what rounding leaves. Whole blocks of eight points
 * are skipped by their sum first (a fixed count the compiler unrolls; the
 * points are a multiple of 8), so that a pick reads about a quarter of the
 * masses one by one. */
static PLM_VECTOR_INLINE int pick_point(const plm_fiber_medulla_query *q, const float *energy, int P, double *target)
{
    double t = *target;
    int k = 0;
    for (; k + 8 < P; k += 8) {
        double block = 0.0;
        for (int i = 0; i < 8; ++i)
            block += q->wbar[k + i] * (double)energy[k + i];
        if (t < block)
            break;
        t -= block;
    }
    for (; k < P; ++k) {
        double x = q->wbar[k] * (double)energy[k];
        if (x > 0.0 && t < x)
            break;
        t -= x > 0.0 ? x : 0.0;
    }
    while (k == P || (k > 0 && !(q->wbar[k] * (double)energy[k] > 0.0)))
        --k; /* past the end by rounding: back to the last point with mass */
    *target = t;
    return k;
}

/* A factored table: a point by its weight times its emitted energy (mean of
 * RGB), then with what is left of u0 a band of its emission by the
 * cumulative band masses; the last band takes what rounding leaves. */
static PLM_VECTOR_INLINE int factored_sample(const plm_fiber_medulla_query *q, double u0, double u1, double u2,
                                             double angles[3], vec3 *wi)
{
    const plm_fiber_medulla_table *m = q->table;
    int P = m->res.points, bands = m->res.theta_bins;
    double target = u0 * q->norm;
    int k = pick_point(q, point_energy(m) + 3 * P, P, &target);
    const float *band = point_sampling(m, k);
    int a = last_at_most(band, bands, plm_clamp(target / q->wbar[k], 0.0, band[bands]));
    sampled_row r = {q, 0, 0, a, band + bands + 1 + (size_t)a * (m->res.phi_bins + 1)};
    double mass = r.row[m->res.phi_bins];
    return mass > 0.0 && direction_in_band(&r, mass, u1, u2, angles, wi);
}

PLM_VECTOR_CLONES int plm_fiber_medulla_sample(const plm_fiber_medulla_query *q, double u0, double u1, double u2,
                                               double angles[3], vec3 *wi)
{
    if (!q->table || !(q->sum > 0.0))
        return 0;
    const plm_fiber_medulla_table *m = q->table;
    if (m->factored)
        return factored_sample(q, u0, u1, u2, angles, wi);
    int bands = m->res.theta_bins, c = 0, a = 0;
    /* A node by its energy, then with what is left of u0 a band by the
     * bands' masses in that node, each summed as its last column is, from
     * the rows' band totals, until u0 falls in one (the last node with
     * energy and the last band take what rounding leaves). */
    double mass = 0.0, target = u0 * q->sum;
    int last = 0;
    for (int i = 0; i < 4; ++i)
        last = q->node_sum[i] > 0.0 ? i : last;
    while (c < last && (target >= q->node_sum[c] || !(q->node_sum[c] > 0.0)))
        target -= q->node_sum[c++];
    int k0 = c ? q->node_end[c - 1] : 0, k1 = q->node_end[c];
    for (; a < bands; ++a) {
        mass = sum_at(q, k0, k1, band_offset(m) + 3 * (size_t)a);
        if (target < mass || a == bands - 1)
            break;
        target -= plm_positive(mass);
    }
    if (!(mass > 0.0))
        return 0;
    sampled_row r = {q, k0, k1, a, NULL};
    return direction_in_band(&r, mass, u1, u2, angles, wi);
}
