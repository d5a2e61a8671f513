/* The tabulated fiber BCSDF: building the table, and eval / pdf / sample from
 * it (docs/fiber.md has the design, its resolution and its error).
 *
 * Notation: Delta = phi_i - phi_o is the azimuth relative to the view, cut
 * into phi_bins bins over [-pi, pi). For a node (theta_o, phi_o) the table
 * holds S(j, c), RGB, for rows j = 0..h_cells and columns c = 0..phi_bins:
 *   S(j, c) = integral over h in [h_0, h_j] and Delta below bin c's start of
 *             sum_k A_k(h) G_N(Delta - Delta_k(h)) over the lobes that never
 *             met the medulla,
 * a summed-area table in (h, Delta). A row at any h is the linear
 * interpolation of its cell's rows (the density is taken constant across a
 * cell), so the mean over [h-, h+] of the bin masses is a combination of at
 * most four rows, and the bin masses are differences of adjacent columns. */
#include "render/fiber_table.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define HALF_PI (0.5 * PLM_PI)

/* ---- layout -------------------------------------------------------------- */

static size_t row_floats(const plm_fiber_table *t) { return 3 * (size_t)(t->phi_bins + 1); }
static size_t node_floats(const plm_fiber_table *t) { return (size_t)(t->h_cells + 1) * row_floats(t); }
static double bin_width(const plm_fiber_table *t) { return PLM_TWO_PI / t->phi_bins; }

static double node_theta(const plm_fiber_table *t, int k)
{
    return t->theta_nodes > 1 ? t->theta_max * k / (t->theta_nodes - 1) : 0.0;
}

static int periodic(const plm_fiber_table *t) { return t->symmetry == PLM_FIBER_TABLE_NONE; }

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
    /* Four bins per beta_n keep eval's linear interpolation within 0.5% of a lobe's peak. */
    int bins = (int)ceil(4.0 * PLM_TWO_PI / p->beta_n);
    bins = (bins + 31) / 32 * 32;
    t->phi_bins = o && o->phi_bins > 0 ? o->phi_bins : bins < 64 ? 64 : bins > 2048 ? 2048 : bins;
    /* A rotationally symmetric fiber needs one phi_o node, so it can afford
     * fine h cells and theta_o nodes; otherwise phi_o nodes take what the
     * memory budget leaves (docs/fiber.md has the errors). */
    int round_fiber = t->symmetry == PLM_FIBER_TABLE_ROTATIONAL;
    t->theta_nodes = o && o->theta_nodes > 1 ? o->theta_nodes : round_fiber ? 32 : 12;
    size_t row_bytes = sizeof(float) * row_floats(t);
    int rows = (int)(PLM_FIBER_TABLE_BUDGET / (row_bytes * (size_t)t->theta_nodes));
    t->h_cells = o && o->h_cells > 0 ? o->h_cells : round_fiber ? (rows - 1 < 256 ? (rows - 1) / 8 * 8 : 256) : 48;
    t->h_cells = t->h_cells < 8 ? 8 : t->h_cells;
    t->theta_max = plm_radians(89.0);
    static const double span[] = {0.0, HALF_PI, PLM_PI, PLM_PI, PLM_TWO_PI};
    static const double lo[] = {0.0, 0.0, -HALF_PI, 0.0, -PLM_PI};
    double s = span[t->symmetry];
    size_t node_bytes = sizeof(float) * node_floats(t);
    int nodes = (int)(PLM_FIBER_TABLE_BUDGET / (node_bytes * (size_t)t->theta_nodes));
    nodes = o && o->phi_nodes > 0 ? o->phi_nodes : nodes;
    t->phi_nodes = round_fiber ? 1 : nodes < 3 ? 3 : nodes;
    t->phi_lo = lo[t->symmetry];
    t->phi_step = t->phi_nodes > 1 ? s / (t->phi_nodes - !periodic(t)) : 0.0;
    t->floats = node_floats(t) * (size_t)t->theta_nodes * (size_t)t->phi_nodes;
}

static int make_h_nodes(plm_fiber_table *t)
{
    t->h_node = malloc(sizeof(double) * (size_t)(t->h_cells + 1));
    if (!t->h_node)
        return 0;
    for (int j = 0; j <= t->h_cells; ++j)
        t->h_node[j] = sin(-HALF_PI + PLM_PI * j / t->h_cells);
    t->h_node[0] = -1.0;
    t->h_node[t->h_cells] = 1.0;
    return 1;
}

/* ---- building ------------------------------------------------------------ */

/* Adds A times the mass of each bin under the wrapped Gaussian of std-dev beta
 * centred at Delta (bins of width w over [-pi, pi)); mass beyond 6 std-devs
 * (2e-9) is left out. */
static void deposit(double *cell, int bins, double w, double beta, rgb A, double delta)
{
    double cut = 6.0 * beta, inv = 1.0 / (sqrt(2.0) * beta);
    int wraps = 1 + (int)(cut / PLM_TWO_PI);
    for (int m = -wraps; m <= wraps; ++m) {
        double s = delta + PLM_TWO_PI * m, lo = fmax(s - cut, -PLM_PI), hi = fmin(s + cut, PLM_PI);
        if (!(lo < hi))
            continue;
        int b0 = (int)floor((lo + PLM_PI) / w), b1 = (int)ceil((hi + PLM_PI) / w);
        b0 = b0 < 0 ? 0 : b0;
        b1 = b1 > bins ? bins : b1;
        double prev = erf((-PLM_PI + b0 * w - s) * inv);
        for (int b = b0; b < b1; ++b) {
            double next = erf((-PLM_PI + (b + 1) * w - s) * inv), mass = 0.5 * (next - prev);
            prev = next;
            cell[3 * b] += A.r * mass;
            cell[3 * b + 1] += A.g * mass;
            cell[3 * b + 2] += A.b * mass;
        }
    }
}

typedef struct build_job {
    plm_fiber_table *table;
    int sub_samples; /* h samples per cell (midpoint rule in asin(h)) */
    atomic_int next, done, failed;
} build_job;

/* One node: for each h cell, the bin masses of its lobes by the midpoint rule
 * in gamma = asin(h) (dh = cos(gamma) dgamma), then the summed rows. */
static void build_node(build_job *job, int node, double *scratch, plm_fiber_lobe *lobes)
{
    const plm_fiber_table *t = job->table;
    const plm_fiber_params *p = &t->params;
    int bins = t->phi_bins, it = node / t->phi_nodes, ip = node % t->phi_nodes;
    double theta_o = node_theta(t, it), phi_o = t->phi_lo + ip * t->phi_step, w = bin_width(t);
    vec3 wo = plm_fiber_direction(theta_o, phi_o);
    plm_rng rng; /* drives only medulla bounces, whose lobes are left out */
    plm_rng_seed(&rng, 0x7ab1e, (uint64_t)node);
    double *cell = scratch, *row = scratch + 3 * bins;
    float *out = t->data + node_floats(t) * (size_t)node;
    for (size_t c = 0; c < row_floats(t); ++c)
        row[c] = out[c] = 0.0f;
    double dgamma = PLM_PI / t->h_cells / job->sub_samples;
    for (int j = 0; j < t->h_cells; ++j) {
        memset(cell, 0, sizeof(double) * 3 * (size_t)bins);
        for (int m = 0; m < job->sub_samples; ++m) {
            double gamma = -HALF_PI + (j * job->sub_samples + m + 0.5) * dgamma, h = sin(gamma);
            double dh = cos(gamma) * dgamma;
            int n = plm_fiber_trace(p, wo, h, &rng, lobes);
            for (int k = 0; k < n && !lobes[k].medulla; ++k) {
                double delta = remainder(atan2(lobes[k].dir.y, lobes[k].dir.x) - phi_o, PLM_TWO_PI);
                deposit(cell, bins, w, p->beta_n, rgb_scale(lobes[k].throughput, dh), delta);
            }
        }
        /* S(j + 1, c) = S(j, c) + the cell's mass below column c, summed in double. */
        float *dst = out + row_floats(t) * (size_t)(j + 1);
        for (int ch = 0; ch < 3; ++ch) {
            double below = 0.0;
            for (int c = 0; c <= bins; ++c) {
                row[3 * c + ch] += below;
                dst[3 * c + ch] = (float)row[3 * c + ch];
                if (c < bins)
                    below += cell[3 * c + ch];
            }
        }
    }
}

static void *build_worker(void *arg)
{
    build_job *job = arg;
    const plm_fiber_table *t = job->table;
    double *scratch = malloc(sizeof(double) * 3 * (size_t)(2 * t->phi_bins + 1));
    plm_fiber_lobe *lobes = malloc(sizeof(plm_fiber_lobe) * (size_t)t->params.lobes);
    int nodes = t->theta_nodes * t->phi_nodes;
    if (!scratch || !lobes)
        atomic_store(&job->failed, 1);
    for (int n; !atomic_load(&job->failed) && (n = atomic_fetch_add(&job->next, 1)) < nodes;) {
        build_node(job, n, scratch, lobes);
        atomic_fetch_add(&job->done, 1);
    }
    free(scratch);
    free(lobes);
    return NULL;
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Fills t->data (allocated by the caller) on all cores, showing progress on
 * stderr once the build has taken a second. */
plm_result plm_fiber_table_build(plm_fiber_table *t, const plm_fiber_table_options *o, plm_error *err)
{
    double t0 = now_seconds();
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    int threads = o && o->threads > 0 ? o->threads : cores > 0 ? (int)cores : 1;
    /* Lobes move about 4 radians per radian of asin(h) at most: sub-samples
     * half a beta_n apart keep the midpoint rule's error far below 1e-4. */
    double dgamma = PLM_PI / t->h_cells;
    build_job job = {t, (int)ceil(8.0 * dgamma / t->params.beta_n), 0, 0, 0};
    job.sub_samples = job.sub_samples < 4 ? 4 : job.sub_samples;
    pthread_t *tid = calloc((size_t)threads, sizeof *tid);
    if (!tid)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "fiber table: out of memory");
    int started = 0;
    for (int i = 0; i < threads; ++i)
        if (pthread_create(&tid[started], NULL, build_worker, &job) == 0)
            ++started;
    if (started == 0)
        build_worker(&job);
    int nodes = t->theta_nodes * t->phi_nodes, shown = 0;
    while (started > 0 && atomic_load(&job.done) < nodes && !atomic_load(&job.failed)) {
        struct timespec nap = {0, 100000000};
        nanosleep(&nap, NULL);
        double elapsed = now_seconds() - t0;
        if (elapsed > 1.0 && !(o && o->quiet)) {
            fprintf(stderr, "\rbuilding fiber table: %3d%% (%d threads)",
                    100 * atomic_load(&job.done) / nodes, started);
            shown = 1;
        }
    }
    for (int i = 0; i < started; ++i)
        pthread_join(tid[i], NULL);
    free(tid);
    if (shown)
        fprintf(stderr, "\rbuilding fiber table: done in %.1f s           \n", now_seconds() - t0);
    if (atomic_load(&job.failed))
        return plm_fail(err, PLM_ERR_NO_MEMORY, "fiber table: out of memory");
    t->build_seconds = now_seconds() - t0;
    return PLM_OK;
}

plm_result plm_fiber_table_alloc(plm_fiber_table *t, plm_error *err)
{
    t->data = malloc(sizeof(float) * t->floats);
    if (!t->data || !make_h_nodes(t)) {
        free(t->data);
        t->data = NULL;
        return plm_fail(err, PLM_ERR_NO_MEMORY, "fiber table: out of memory (%zu MB)",
                        sizeof(float) * t->floats >> 20);
    }
    return PLM_OK;
}

void plm_fiber_table_free(plm_fiber_table *t)
{
    if (!t)
        return;
    free(t->data);
    free(t->h_node);
    free(t);
}

size_t plm_fiber_table_bytes(const plm_fiber_table *t)
{
    return sizeof *t + sizeof(float) * t->floats + sizeof(double) * (size_t)(t->h_cells + 1);
}

/* ---- queries ------------------------------------------------------------- */

static double wrap_pi(double a) { return a - PLM_TWO_PI * floor((a + PLM_PI) / PLM_TWO_PI); }

/* The cell of h and h's fraction across it. */
static int h_cell(const plm_fiber_table *t, double h, double *frac)
{
    int j = (int)floor((plm_safe_asin(h) + HALF_PI) / PLM_PI * t->h_cells);
    j = j < 0 ? 0 : j >= t->h_cells ? t->h_cells - 1 : j;
    double lo = t->h_node[j], hi = t->h_node[j + 1];
    *frac = plm_clamp((h - lo) / (hi - lo), 0.0, 1.0);
    return j;
}

static void add_row(plm_fiber_table_query *q, int j, double coef)
{
    size_t off = row_floats(q->table) * (size_t)j;
    for (int r = 0; r < q->rows; ++r)
        if (q->row[r] == off) {
            q->row_coef[r] += coef;
            return;
        }
    q->row[q->rows] = off;
    q->row_coef[q->rows++] = coef;
}

/* The rows whose combination is the mean over [hmin, hmax] (within [-1, 1]). */
static void set_rows(plm_fiber_table_query *q, double hmin, double hmax)
{
    const plm_fiber_table *t = q->table;
    double f0, f1;
    int j0 = h_cell(t, hmin, &f0), j1 = h_cell(t, hmax, &f1);
    q->rows = 0;
    double width = hmax - hmin;
    if (width < 1e-9) { /* the density at a point: its cell's */
        double inv = 1.0 / (t->h_node[j0 + 1] - t->h_node[j0]);
        add_row(q, j0 + 1, inv);
        add_row(q, j0, -inv);
        return;
    }
    double inv = 1.0 / width;
    add_row(q, j1, (1.0 - f1) * inv);
    add_row(q, j1 + 1, f1 * inv);
    add_row(q, j0, -(1.0 - f0) * inv);
    add_row(q, j0 + 1, -f0 * inv);
}

/* The combined rows of corner c at column col, RGB. */
static rgb column(const plm_fiber_table_query *q, int c, int col)
{
    const float *base = q->corner[c] + 3 * (size_t)col;
    double r = 0.0, g = 0.0, b = 0.0;
    for (int i = 0; i < q->rows; ++i) {
        const float *v = base + q->row[i];
        r += q->row_coef[i] * v[0];
        g += q->row_coef[i] * v[1];
        b += q->row_coef[i] * v[2];
    }
    return rgb_make(r, g, b);
}

static void table_prepare(const plm_fiber_table *t, vec3 wo, double hmin, double hmax, plm_fiber_table_query *q)
{
    q->table = t;
    q->total = 0.0;
    double ct = sqrt(wo.x * wo.x + wo.y * wo.y);
    if (!(ct > 1e-12) || !(hmin <= hmax))
        return;
    q->theta_o = atan2(wo.z, ct);
    q->phi_o = atan2(wo.y, wo.x);
    q->gm_scale = plm_fiber_gm_scale(t->params.beta_m, -q->theta_o);
    /* Into the tabulated range of phi_o by the mirrors (docs/fiber.md):
     * x -> -x takes phi to pi - phi, y -> -y takes phi to -phi; either turns
     * relative azimuths and h around. */
    double phi = q->phi_o;
    int mirror_x = 0, mirror_y = 0;
    if ((t->symmetry == PLM_FIBER_TABLE_MIRROR_XY || t->symmetry == PLM_FIBER_TABLE_MIRROR_X) && cos(phi) < 0.0)
        mirror_x = 1;
    if ((t->symmetry == PLM_FIBER_TABLE_MIRROR_XY || t->symmetry == PLM_FIBER_TABLE_MIRROR_Y) && sin(phi) < 0.0)
        mirror_y = 1;
    if (mirror_x)
        phi = PLM_PI - phi;
    if (mirror_y)
        phi = -phi;
    phi = wrap_pi(phi);
    q->flip = mirror_x ^ mirror_y;
    if (q->flip) {
        double lo = -hmax;
        hmax = -hmin;
        hmin = lo;
    }
    hmin = plm_clamp(hmin, -1.0, 1.0);
    hmax = plm_clamp(hmax, -1.0, 1.0);
    /* Bilinear weights over (|theta_o|, phi_o). */
    double ft = fmin(fabs(q->theta_o), t->theta_max) / t->theta_max * (t->theta_nodes - 1);
    int it = (int)ft;
    it = it >= t->theta_nodes - 1 ? t->theta_nodes - 2 : it;
    ft -= it;
    int ip0 = 0, ip1 = 0;
    double fp = 0.0;
    if (t->phi_nodes > 1) {
        double x = (phi - t->phi_lo) / t->phi_step;
        if (periodic(t)) {
            x = x - t->phi_nodes * floor(x / t->phi_nodes);
            ip0 = (int)x % t->phi_nodes;
            ip1 = (ip0 + 1) % t->phi_nodes;
            fp = x - floor(x);
        } else {
            x = plm_clamp(x, 0.0, t->phi_nodes - 1.0);
            ip0 = (int)x;
            ip0 = ip0 >= t->phi_nodes - 1 ? t->phi_nodes - 2 : ip0;
            ip1 = ip0 + 1;
            fp = x - ip0;
        }
    }
    int nodes[4] = {it * t->phi_nodes + ip0, it * t->phi_nodes + ip1, (it + 1) * t->phi_nodes + ip0,
                    (it + 1) * t->phi_nodes + ip1};
    double w[4] = {(1 - ft) * (1 - fp), (1 - ft) * fp, ft * (1 - fp), ft * fp};
    set_rows(q, hmin, hmax);
    for (int c = 0; c < 4; ++c) {
        q->corner[c] = t->data + node_floats(t) * (size_t)nodes[c];
        q->weight[c] = w[c];
        q->corner_total[c] = fmax(0.0, rgb_mean(column(q, c, t->phi_bins)));
        q->total += w[c] * q->corner_total[c];
    }
}

/* theta_i, the relative azimuth in the table's orientation, and cos(theta_i)
 * of wi; 0 at the poles. */
static int table_angles(const plm_fiber_table_query *q, vec3 wi, double *theta, double *delta, double *ct)
{
    *ct = sqrt(wi.x * wi.x + wi.y * wi.y);
    if (!(*ct > 1e-12))
        return 0;
    *theta = fabs(wi.z) < 0.9 ? asin(wi.z) : atan2(wi.z, *ct);
    double d = wrap_pi(atan2(wi.y, wi.x) - q->phi_o);
    *delta = q->flip ? -d : d;
    return 1;
}

/* The table part at wi: eval (G_M N / cos^2(theta_i), N interpolated
 * linearly between the two nearest bin centres) into *f if f is not NULL,
 * and the sampler's density (G_M times the piecewise-constant bin density,
 * per solid angle) into *pdf. The bin holding wi is one of the two eval
 * interpolates, so the pdf comes almost free with eval. */
static void table_lookup(const plm_fiber_table_query *q, vec3 wi, rgb *f, double *pdf)
{
    if (f)
        *f = rgb_gray(0.0);
    *pdf = 0.0;
    double theta, delta, ct;
    if (!(q->total > 0.0) || !table_angles(q, wi, &theta, &delta, &ct))
        return;
    const plm_fiber_table *t = q->table;
    double gm = plm_fiber_gm(t->params.beta_m, q->gm_scale, theta + q->theta_o);
    if (gm == 0.0)
        return;
    int n = t->phi_bins;
    double w = bin_width(t), x = (delta + PLM_PI) / w - 0.5, fl = floor(x), frac = x - fl;
    int b0 = ((int)fl + n) % n, b1 = b0 + 1 < n ? b0 + 1 : 0, upper = frac >= 0.5; /* wi lies in b1 if upper */
    rgb sum = rgb_gray(0.0);
    double mass = 0.0;
    for (int c = 0; c < 4; ++c) {
        if (!(q->weight[c] > 0.0))
            continue;
        rgb c0 = column(q, c, b0), c1 = column(q, c, b0 + 1);
        rgb m0 = rgb_sub(c1, c0), m1 = f || upper ? rgb_sub(b1 ? column(q, c, b1 + 1) : column(q, c, 1),
                                                              b1 ? c1 : column(q, c, 0))
                                                  : m0;
        if (f)
            sum = rgb_add(sum, rgb_scale(rgb_add(rgb_scale(m0, 1.0 - frac), rgb_scale(m1, frac)), q->weight[c]));
        mass += q->weight[c] * fmax(0.0, rgb_mean(upper ? m1 : m0));
    }
    if (f) {
        double s = gm / (w * ct * ct);
        *f = rgb_make(fmax(0.0, sum.r * s), fmax(0.0, sum.g * s), fmax(0.0, sum.b * s));
    }
    *pdf = gm * mass / (q->total * w * ct);
}

/* A node by weight_c corner_total_c (u0), a bin of it by its CDF (u2, then
 * uniform within the bin), theta_i from G_M (u1). */
static int table_sample(const plm_fiber_table_query *q, double u0, double u1, double u2, vec3 *wi)
{
    if (!(q->total > 0.0))
        return 0;
    const plm_fiber_table *t = q->table;
    double u = u0 * q->total;
    int c = 0;
    while (c < 3 && (u >= q->weight[c] * q->corner_total[c] || q->weight[c] * q->corner_total[c] <= 0.0)) {
        u -= q->weight[c] * q->corner_total[c];
        ++c;
    }
    if (!(q->weight[c] * q->corner_total[c] > 0.0))
        return 0;
    double target = u2 * q->corner_total[c];
    int lo = 0, hi = t->phi_bins; /* column lo <= target < column hi */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (rgb_mean(column(q, c, mid)) <= target)
            lo = mid;
        else
            hi = mid;
    }
    double a = rgb_mean(column(q, c, lo)), b = rgb_mean(column(q, c, lo + 1));
    if (!(b > a))
        return 0;
    double frac = plm_clamp((target - a) / (b - a), 0.0, 1.0);
    double delta = -PLM_PI + (lo + frac) * bin_width(t);
    double phi = q->phi_o + (q->flip ? -delta : delta);
    *wi = plm_fiber_direction(plm_fiber_sample_gm(-q->theta_o, t->params.beta_m, u1), phi);
    return 1;
}

/* ---- the prepared BCSDF -------------------------------------------------- */

void plm_fiber_bcsdf_prepare(const plm_fiber_params *p, const plm_fiber_table *table, vec3 wo, double hmin,
                             double hmax, plm_rng *rng, plm_fiber_bcsdf *out)
{
    out->params = p;
    out->tab.table = NULL;
    out->tab.total = 0.0;
    if (!table) {
        plm_fiber_prepare(p, wo, hmin, hmax, rng, &out->set);
        out->pick_table = 0.0;
        out->total = out->set.total;
        return;
    }
    table_prepare(table, wo, hmin, hmax, &out->tab);
    out->set.count = 0;
    out->set.total = 0.0;
    if (plm_fiber_has_medulla(p))
        plm_fiber_prepare_medulla(p, wo, hmin, hmax, rng, &out->set);
    out->total = out->tab.total + out->set.total;
    out->pick_table = out->total > 0.0 ? out->tab.total / out->total : 0.0;
}

/* eval into *f (if not NULL) and the mixture's pdf. */
static void bcsdf_lookup(const plm_fiber_bcsdf *b, vec3 wi, rgb *f, double *pdf)
{
    double tab_pdf = 0.0;
    if (b->tab.table)
        table_lookup(&b->tab, wi, f, &tab_pdf);
    else if (f)
        *f = rgb_gray(0.0);
    *pdf = b->pick_table * tab_pdf;
    if (b->set.count > 0) {
        if (f)
            *f = rgb_add(*f, plm_fiber_eval(b->params, &b->set, wi));
        if (b->pick_table < 1.0)
            *pdf += (1.0 - b->pick_table) * plm_fiber_pdf(b->params, &b->set, wi);
    }
}

rgb plm_fiber_bcsdf_eval(const plm_fiber_bcsdf *b, vec3 wi)
{
    rgb f;
    double unused;
    bcsdf_lookup(b, wi, &f, &unused);
    return f;
}

double plm_fiber_bcsdf_pdf(const plm_fiber_bcsdf *b, vec3 wi)
{
    double pdf;
    bcsdf_lookup(b, wi, NULL, &pdf);
    return pdf;
}

rgb plm_fiber_bcsdf_eval_pdf(const plm_fiber_bcsdf *b, vec3 wi, double *pdf)
{
    rgb f;
    bcsdf_lookup(b, wi, &f, pdf);
    return f;
}

int plm_fiber_bcsdf_sample(const plm_fiber_bcsdf *b, double u0, double u1, double u2, plm_fiber_sample_rec *rec)
{
    if (!(b->total > 0.0))
        return 0;
    if (!b->tab.table)
        return plm_fiber_sample(b->params, &b->set, u0, u1, u2, rec);
    vec3 wi;
    if (u0 < b->pick_table) {
        if (!table_sample(&b->tab, u0 / b->pick_table, u1, u2, &wi))
            return 0;
        rec->lobe = -1;
    } else {
        plm_fiber_sample_rec part;
        double remapped = plm_clamp((u0 - b->pick_table) / (1.0 - b->pick_table), 0.0, 0x1.fffffffffffffp-1);
        if (!plm_fiber_sample(b->params, &b->set, remapped, u1, u2, &part))
            return 0;
        wi = part.wi;
        rec->lobe = part.lobe;
    }
    rgb f;
    double pdf, ct = sqrt(wi.x * wi.x + wi.y * wi.y);
    bcsdf_lookup(b, wi, &f, &pdf);
    if (!(pdf > 0.0))
        return 0;
    rec->wi = wi;
    rec->pdf = pdf;
    rec->weight = rgb_scale(f, ct / pdf);
    return 1;
}
