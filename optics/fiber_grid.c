/* The grid both parts of the tabulated fiber BCSDF are laid on and read
 * through (optics/fiber_grid.h), and the builds' thread pool. */
#include "optics/fiber_grid.h"
#include "common/clock.h"
#include "common/threads.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "common/progress.h"

#define HALF_PI (0.5 * PLM_PI)

double plm_fiber_theta_u(double eta, double theta) { return plm_fiber_inverse_index(eta, sin(theta), cos(theta)); }

double plm_fiber_theta_coordinate(double eta, double u_last, double theta_max, int nodes, double theta,
                                  double sin_theta, double cos_theta)
{
    double u = plm_fiber_inverse_index(eta, sin_theta, cos_theta), u_first = 1.0 / eta;
    double x = 0.5 * (theta / theta_max + (u_first - u) / (u_first - u_last));
    return plm_clamp(x, 0.0, 1.0) * (nodes - 1);
}

double plm_fiber_node_theta(double eta, double u_last, double theta_max, int nodes, int k)
{
    double lo = 0.0, hi = theta_max; /* the coordinate inverted by bisection (it increases) */
    for (int i = 0; i < 60; ++i) {
        double mid = 0.5 * (lo + hi);
        if (plm_fiber_theta_coordinate(eta, u_last, theta_max, nodes, mid, sin(mid), cos(mid)) < k)
            lo = mid;
        else
            hi = mid;
    }
    return k == 0 ? 0.0 : k == nodes - 1 ? theta_max : 0.5 * (lo + hi);
}

void plm_fiber_phi_nodes(int symmetry, int phi_nodes, double *phi_lo, double *phi_step)
{
    static const double span[] = {0.0, HALF_PI, PLM_PI, PLM_PI, PLM_TWO_PI};
    static const double lo[] = {0.0, 0.0, -HALF_PI, 0.0, -PLM_PI};
    *phi_lo = lo[symmetry];
    *phi_step = phi_nodes > 1 ? span[symmetry] / (phi_nodes - (symmetry != PLM_FIBER_TABLE_NONE)) : 0.0;
}

double *plm_fiber_h_nodes(int cells)
{
    double *node = malloc(sizeof(double) * (size_t)(cells + 1));
    if (!node)
        return NULL;
    for (int j = 0; j <= cells; ++j)
        node[j] = sin(-HALF_PI + PLM_PI * j / cells);
    node[0] = -1.0;
    node[cells] = 1.0;
    return node;
}

int plm_fiber_h_sub_samples(double beta_n, int cells)
{
    /* Lobes move about 4 radians per radian of asin(h) at most: sub-samples
     * half a beta_n apart keep the midpoint rule's error far below 1e-4. */
    int n = (int)ceil(8.0 * PLM_PI / cells / beta_n);
    return n < 4 ? 4 : n;
}

void plm_fiber_gn_deposit(double *cell, int bins, double beta, rgb A, double delta)
{
    double w = PLM_TWO_PI / bins, cut = 6.0 * beta, inv = 1.0 / (sqrt(2.0) * beta);
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

typedef struct parallel_run {
    plm_fiber_work work;
    void *ctx;
    int items, lobes;
    size_t scratch_bytes;
    atomic_int next, done, failed;
} parallel_run;

static void *parallel_worker(void *arg)
{
    parallel_run *r = arg;
    double *scratch = malloc(r->scratch_bytes);
    plm_fiber_lobe *lobes = malloc(sizeof(plm_fiber_lobe) * (size_t)r->lobes);
    if (!scratch || !lobes)
        atomic_store(&r->failed, 1);
    for (int n; !atomic_load(&r->failed) && (n = atomic_fetch_add(&r->next, 1)) < r->items;) {
        r->work(r->ctx, n, scratch, lobes);
        atomic_fetch_add(&r->done, 1);
    }
    free(scratch);
    free(lobes);
    return NULL;
}

int plm_fiber_parallel(plm_fiber_work work, void *ctx, int items, size_t scratch_bytes, int lobes, int threads,
                       int quiet, const char *what, double started)
{
    parallel_run r = {work, ctx, items, lobes, scratch_bytes, 0, 0, 0};
    plm_threads pool;
    int launched = plm_threads_start(&pool, threads, parallel_worker, &r);
    if (launched == 0)
        parallel_worker(&r);
    /* Progress once the build has taken a second; each phase ends with its line. */
    plm_progress progress = {.start = 0.0};
    char detail[96];
    snprintf(detail, sizeof detail, "%s, %d threads", what, launched);
    while (launched > 0 && atomic_load(&r.done) < items && !atomic_load(&r.failed)) {
        struct timespec nap = {0, 100000000};
        nanosleep(&nap, NULL);
        if (plm_seconds() - started > 1.0 && !quiet) {
            if (progress.start == 0.0)
                plm_progress_start(&progress, "fiber table");
            plm_progress_update(&progress, (double)atomic_load(&r.done) / items, detail);
        }
    }
    plm_threads_join(&pool);
    if (progress.start != 0.0)
        plm_progress_finish(&progress, (double)atomic_load(&r.done) / items, detail);
    return !atomic_load(&r.failed);
}

void plm_fiber_interval_rows(const double *h_node, int cells, const plm_fiber_view *v, plm_fiber_h_rows *l)
{
    double f0, f1;
    int j0 = plm_fiber_h_cell(h_node, cells, v->hmin, v->asin_hmin, &f0), j1 = plm_fiber_h_cell(h_node, cells, v->hmax, v->asin_hmax, &f1);
    l->n = 0;
    double width = v->hmax - v->hmin;
    if (width < PLM_FIBER_POINT_WIDTH) { /* the density at a point: its cell's */
        double inv = 1.0 / (h_node[j0 + 1] - h_node[j0]);
        plm_fiber_rows_add(l, j0 + 1, inv);
        plm_fiber_rows_add(l, j0, -inv);
        return;
    }
    double inv = 1.0 / width;
    plm_fiber_rows_add(l, j1, (1.0 - f1) * inv);
    plm_fiber_rows_add(l, j1 + 1, f1 * inv);
    plm_fiber_rows_add(l, j0, -(1.0 - f0) * inv);
    plm_fiber_rows_add(l, j0 + 1, -f0 * inv);
}

void plm_fiber_phi_weights(int symmetry, int phi_nodes, double phi_lo, double phi_step, double phi, int ip[2],
                           double *frac)
{
    ip[0] = ip[1] = 0;
    *frac = 0.0;
    if (phi_nodes < 2)
        return;
    double x = (phi - phi_lo) / phi_step;
    if (symmetry == PLM_FIBER_TABLE_NONE) { /* periodic */
        x = x - phi_nodes * floor(x / phi_nodes);
        ip[0] = (int)x % phi_nodes;
        ip[1] = (ip[0] + 1) % phi_nodes;
        *frac = x - floor(x);
    } else {
        x = plm_clamp(x, 0.0, phi_nodes - 1.0);
        ip[0] = (int)x;
        ip[0] = ip[0] >= phi_nodes - 1 ? phi_nodes - 2 : ip[0];
        ip[1] = ip[0] + 1;
        *frac = x - ip[0];
    }
}

int plm_fiber_view_of(int symmetry, vec3 wo, double hmin, double hmax, plm_fiber_view *v)
{
    double ct = sqrt(wo.x * wo.x + wo.y * wo.y);
    if (!(ct > 1e-12) || !(hmin <= hmax))
        return 0;
    double len = sqrt(ct * ct + wo.z * wo.z); /* wo is about unit length: no hypot needed */
    v->theta_o = plm_atan2(wo.z, ct);
    v->phi_o = plm_atan2(wo.y, wo.x);
    v->sin_theta = fabs(wo.z) / len;
    v->cos_theta = ct / len;
    /* x -> -x takes phi to pi - phi, y -> -y takes phi to -phi; either turns
     * relative azimuths and h around (docs/fiber.md). phi_o is in [-pi, pi],
     * so its signs tell cos(phi_o) < 0 and sin(phi_o) < 0. */
    int mirror_x = (symmetry == PLM_FIBER_TABLE_MIRROR_XY || symmetry == PLM_FIBER_TABLE_MIRROR_X) &&
                   fabs(v->phi_o) > HALF_PI;
    int mirror_y = (symmetry == PLM_FIBER_TABLE_MIRROR_XY || symmetry == PLM_FIBER_TABLE_MIRROR_Y) && v->phi_o < 0.0;
    double phi = mirror_x ? PLM_PI - v->phi_o : v->phi_o;
    v->phi = plm_wrap_pi(mirror_y ? -phi : phi);
    v->flip = mirror_x ^ mirror_y;
    if (v->flip) {
        double lo = -hmax;
        hmax = -hmin;
        hmin = lo;
    }
    v->hmin = plm_clamp(hmin, -1.0, 1.0);
    v->hmax = plm_clamp(hmax, -1.0, 1.0);
    v->asin_hmin = plm_asin(v->hmin);
    v->asin_hmax = plm_asin(v->hmax);
    return 1;
}

void plm_fiber_corners(int symmetry, int theta_nodes, int phi_nodes, double phi_lo, double phi_step, double ft,
                       double phi, int nodes[4], double w[4])
{
    int it = (int)ft;
    it = it >= theta_nodes - 1 ? theta_nodes - 2 : it;
    ft -= it;
    int ip[2];
    double fp;
    plm_fiber_phi_weights(symmetry, phi_nodes, phi_lo, phi_step, phi, ip, &fp);
    nodes[0] = it * phi_nodes + ip[0], nodes[1] = it * phi_nodes + ip[1];
    nodes[2] = (it + 1) * phi_nodes + ip[0], nodes[3] = (it + 1) * phi_nodes + ip[1];
    w[0] = (1 - ft) * (1 - fp), w[1] = (1 - ft) * fp, w[2] = ft * (1 - fp), w[3] = ft * fp;
}

int plm_fiber_energy_first(int theta_nodes, double ft)
{
    if (theta_nodes < 3)
        return -1;
    int it = (int)ft;
    it = it >= theta_nodes - 1 ? theta_nodes - 2 : it;
    return it >= 1 ? it - 1 : it;
}

double plm_fiber_energy_scale(const double *node_cos, int theta_nodes, double ft, double cos_theta, const double e[3])
{
    int it = (int)ft, first = plm_fiber_energy_first(theta_nodes, ft);
    it = it >= theta_nodes - 1 ? theta_nodes - 2 : it;
    double f = ft - it, x = fmax(cos_theta, node_cos[theta_nodes - 1]), quad = 0.0;
    for (int k = 0; k < 3; ++k) {
        double l = 1.0; /* Lagrange's weight of node first + k at x */
        for (int m = 0; m < 3; ++m)
            if (m != k)
                l *= (x - node_cos[first + m]) / (node_cos[first + k] - node_cos[first + m]);
        quad += l * e[k];
    }
    /* Not beyond the two nodes' energies: the quadratic overshoots where the
     * energy's slope changes abruptly between nodes (a white fiber's parts
     * both stay within theirs, so that their sum is kept). */
    double lo = e[it - first], hi = e[it + 1 - first], lin = (1.0 - f) * lo + f * hi;
    quad = plm_clamp(quad, fmin(lo, hi), fmax(lo, hi));
    return lin > 0.0 ? plm_positive(quad) / lin : 1.0;
}

int plm_fiber_terms(const float *data, size_t node_floats, size_t row_floats, const int nodes[4], const double w[4],
                    const plm_fiber_h_rows *rows, const float **term, double *coef, int *node_end)
{
    /* Row 0 is all zeros, and so is what a zero weight multiplies: neither makes a term. */
    int n = 0;
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < rows->n; ++r)
            if (w[c] > 0.0 && rows->coef[r] != 0.0 && rows->row[r] > 0) {
                term[n] = data + node_floats * (size_t)nodes[c] + row_floats * (size_t)rows->row[r];
                coef[n++] = w[c] * rows->coef[r];
            }
        if (node_end)
            node_end[c] = n;
    }
    return n;
}
