/* An experiment, not a test of the product: how close to the exact mean
 * over h could a table of the part without the medulla come for an
 * elliptical fiber if it displaced each lobe between its four view nodes,
 * instead of blending the nodes' values (docs/fiber.md, "Where the error
 * comes from" and "Tried and not kept")?
 *
 * For each query of slow_fiber_table (the same draws: the fibers, their
 * tables' queries and the medulla parts' references replayed in its order),
 * the four (|theta_o|, phi_o) nodes around wo and their bilinear weights are
 * found as the table finds them, for the default layout. At every one of
 * the reference's h strata, the lobes that never meet the medulla are traced
 * at each node's view, and combined per slot (the lobe's wall hits) into one
 * lobe: its relative azimuth the weighted mean of the nodes' (unwrapped
 * about the first's), its RGB weight the weighted sum over the nodes where
 * the slot exists, with a missing slot counted as 0 ("zero"), or the
 * weights renormalised over the nodes that have it ("renorm"), or a slot
 * missing at one of the nodes left in place at each node and blended by
 * value ("hybrid"). Each estimate is G_M(theta_i + theta_o) /
 * cos^2(theta_i) times the mean over the strata (`strata` of them; the
 * reference keeps 2000) of the lobes' G_N at wi. The estimators:
 *   table     the real table (table_part_eval)
 *   values    the nodes' values blended bilinearly, every h traced: the
 *             table without its h cells and azimuth bins (the control)
 *   lobes     every slot displaced across all four nodes (the oracle)
 *   phi       displaced between the two phi_o nodes of each |theta_o| node,
 *             the two results blended in theta_o
 *   theta     displaced between the two |theta_o| nodes, blended in phi_o
 *   true weights, true places: the oracle (lobes zero) with, per slot, the
 *             weight or the place of the lobe traced at the query's own
 *             view, to tell which of the two it gets wrong
 * Printed per fiber and kind of wi: the relative L2 error per channel
 * (table_error's metric) and, for the worst channel, the share of the
 * squared error from views beyond 78 deg, from queries where slots that
 * exist at some of the nodes but not at others carry over 1% of the
 * oracle's energy, and from the single worst query.
 *
 * Usage: proto_elliptical_oracle [queries [strata [refine_theta
 * [refine_phi [draw [study]]]]]] (defaults 2000, 2000, 1, 1, 0, 0; study
 * 1 runs the |theta_o| blending study below instead of the oracle's
 * estimators, about 2 minutes a draw at 500 strata): the first
 * `queries` of each kind are evaluated (all are drawn, so the later fibers
 * keep slow_fiber_table's queries); the estimators other than the table
 * use view nodes refine_theta times as dense as the table's in |theta_o|
 * and refine_phi times in phi_o (the table's among them); a draw other
 * than 0 evaluates other queries of the same kinds (the same fibers). Set
 * PLUMAGE_CACHE_DIR as ctest does (the build's fiber-cache) to reuse its
 * tables. About 20 minutes of CPU time at the defaults; not run by ctest. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "tests/fiber_table_stats.h"
#include "common/clock.h"

/* slow_fiber_table's queries per fiber and kind of wi, and its reference's h strata. */
enum { QUERIES = 2000, REFERENCE_STRATA = 2000 };

/* How a slot's weight is combined over the nodes: missing counted as 0,
 * renormalised over the nodes that have it, or (hybrid) a slot missing at
 * one of the nodes not displaced at all: each node's lobe blended by value
 * at its own place. */
enum { ZERO, RENORM, HYBRID, MODES };
/* Which nodes a slot is displaced across: all four, the two phi_o nodes
 * (the two |theta_o| nodes' results blended by value) or the two |theta_o|
 * nodes (blended in phi_o). */
enum { ALL, PHI, THETA, GROUPINGS };
/* The estimators: the table, the nodes' values blended, per grouping and
 * mode the displaced lobes, then two diagnostics of the oracle (all four
 * nodes, zero): its lobes with the true weights, or the true places. */
enum { TABLE, VALUES, DISPLACED, TRUE_WEIGHTS = DISPLACED + GROUPINGS * MODES, TRUE_PLACES, ESTIMATORS };
static const char *const grouping_names[GROUPINGS] = {"lobes", "phi", "theta"};
static const char *const mode_names[MODES] = {"zero", "renorm", "hybrid"};

/* Lobes at one h: slot (wall hits), relative azimuth, RGB weight; one
 * view's (a slot at most once) or combined from four (hybrid: a slot up to
 * four times). */
enum { LIST = 4 * PLM_FIBER_SET_MAX_LOBES };
typedef struct lobe_list {
    int n;
    int slot[LIST];
    double delta[LIST];
    rgb a[LIST];
} lobe_list;

/* The |theta_o| blending study (the sixth argument 1): every estimator
 * blends the exact values of the nodes (as "values" does), each with its
 * own weights across |theta_o| nodes (the phi_o fraction as the table's):
 *   lin-ft       linear in the node coordinate's fraction (= "values")
 *   lin-X        the fraction linear in X = theta, cos(theta), cos^2, u^2
 *   mix          the mean of lin-cos's and lin-cos2's fractions
 *   quad-X       Lagrange through three |theta_o| nodes in X = the node
 *                coordinate, cos(theta), u: the interval's two and the one
 *                below (the one above at the first interval); "up": the
 *                one above where there is one
 *   cubic-cos    Lagrange through four nodes in cos(theta) (three at the
 *                first and last intervals, as quad-cos)
 *   quad-cos-73, quad-cos-last  quad-cos only from the node at 73 deg up
 *                (the last four nodes), or in the last interval only;
 *                lin-ft elsewhere
 *   R lin-ft / int lin-cos2, R lin-cos / int lin-cos2  (diagnostics a
 *                table of summed lobes cannot do): the surface reflection
 *                (wall hits 0) and the internal lobes blended apart
 *   quad-cos-73 >=0  quad-cos-73 with each channel clamped at 0
 *   efrac-cos    the two nodes of lin-ft with the fraction at which their
 *                interval energies (mean of RGB, phi_o blended) blend to
 *                quad-cos's of the three nodes' (lin-ft's where the two
 *                are within 1e-3 of each other), clamped to [0, 1]
 *   escale-cos   lin-ft times quad-cos's energy over lin-ft's (clamped at
 *                0; per channel in escale-rgb)
 *   escale-cos-lim  escale-cos with quad-cos's energy kept between the two
 *                nodes' (the table's energy scale)
 *   "-73": from the node at 73 deg up only (lin-ft elsewhere) */
enum {
    LIN_FT, LIN_THETA, LIN_COS, LIN_COS2, LIN_U2, MIX, QUAD_FT, QUAD_COS, QUAD_U, QUAD_COS_UP, CUBIC_COS,
    QUAD_COS_73, QUAD_COS_LAST, SPLIT_FT_COS2, SPLIT_COS_COS2, QUAD_COS_73_CLAMPED, EFRAC_COS, EFRAC_COS_73,
    ESCALE_COS, ESCALE_COS_73, ESCALE_RGB_73, ESCALE_COS_LIMITED, STUDY_ESTIMATORS
};
static const char *const study_names[STUDY_ESTIMATORS] = {
    "lin-ft", "lin-theta", "lin-cos", "lin-cos2", "lin-u2", "mix", "quad-ft", "quad-cos", "quad-u", "quad-cos-up",
    "cubic-cos", "quad-cos-73", "quad-cos-last", "R ft, int cos2", "R cos, int cos2", "quad-cos-73 >=0", "efrac-cos",
    "efrac-cos-73", "escale-cos", "escale-cos-73", "escale-rgb-73", "escale-cos-lim"};
enum { MOST_ESTIMATORS = 2 + STUDY_ESTIMATORS > ESTIMATORS ? 2 + STUDY_ESTIMATORS : ESTIMATORS };

typedef struct query_result {
    rgb ref, est[MOST_ESTIMATORS]; /* the study's: est[0] the table, est[1 + e] the study's estimator e */
    double missing; /* the oracle's share of energy (mean of RGB) in slots missing at one of the nodes */
} query_result;

typedef struct harness {
    const plm_fiber_table *t, *layout; /* the real table; the layout whose nodes the estimators use */
    const stats_query *query;
    query_result *result;
    int strata; /* the estimators' h strata (the reference's are REFERENCE_STRATA) */
    int study;  /* 1: the |theta_o| blending study instead of the oracle's estimators */
} harness;

static int find_slot(const lobe_list *l, int slot)
{
    for (int k = 0; k < l->n; ++k)
        if (l->slot[k] == slot)
            return k;
    return -1;
}

/* The sum of the lobes' G_N at relative azimuth x. */
static rgb lobes_gn(const lobe_list *l, double beta_n, double x)
{
    rgb sum = rgb_gray(0.0);
    for (int k = 0; k < l->n; ++k)
        sum = rgb_add(sum, rgb_scale(l->a[k], reference_gn(beta_n, remainder(x - l->delta[k], PLM_TWO_PI), 1)));
    return sum;
}

static void add_lobe(lobe_list *l, int slot, double delta, rgb a)
{
    l->slot[l->n] = slot;
    l->delta[l->n] = delta;
    l->a[l->n++] = a;
}

/* The lobes of the view (theta, phi_node) at h that never meet the medulla,
 * with azimuths relative to phi_node. */
static void trace_node(const plm_fiber_params *p, vec3 wo, double phi_node, double h, plm_rng *rng,
                       plm_fiber_lobe *lobes, lobe_list *out)
{
    int n = plm_fiber_trace(p, wo, h, rng, lobes);
    out->n = 0;
    for (int k = 0; k < n && !lobes[k].medulla; ++k)
        if (rgb_mean(lobes[k].throughput) > 0.0)
            add_lobe(out, lobes[k].wall_hits,
                     remainder(atan2(lobes[k].dir.y, lobes[k].dir.x) - phi_node, PLM_TWO_PI), lobes[k].throughput);
}

/* Appends to out the lobes of `count` nodes (weights wt, summing to 1)
 * combined per slot as `mode` says, times `scale`: at the weighted mean of
 * its places, with the weighted sum of its weights. If energy is not NULL,
 * adds the combined lobes' energies (mean of RGB) to energy[0] and those of
 * slots missing at one of the nodes to energy[1]. */
static void displaced(const lobe_list *const node[], const double wt[], int count, int mode, double scale,
                      lobe_list *out, double *energy)
{
    for (int i = 0; i < count; ++i)
        for (int k = 0; k < node[i]->n; ++k) {
            int s = node[i]->slot[k], first = 1;
            for (int j = 0; j < i && first; ++j)
                first = find_slot(node[j], s) < 0;
            if (!first)
                continue; /* combined at an earlier node */
            double ref = node[i]->delta[k], shift = 0.0, weight = 0.0;
            rgb a = rgb_gray(0.0);
            int missing = 0;
            for (int j = 0; j < count; ++j) {
                int m = find_slot(node[j], s);
                if (m < 0) {
                    missing = 1;
                    continue;
                }
                shift += wt[j] * remainder(node[j]->delta[m] - ref, PLM_TWO_PI);
                weight += wt[j];
                a = rgb_add(a, rgb_scale(node[j]->a[m], wt[j]));
            }
            a = rgb_scale(a, mode == RENORM ? 1.0 / weight : 1.0);
            if (energy) {
                energy[0] += rgb_mean(a);
                energy[1] += missing ? rgb_mean(a) : 0.0;
            }
            if (mode != HYBRID || !missing) {
                add_lobe(out, s, ref + shift / weight, rgb_scale(a, scale));
                continue;
            }
            for (int j = 0; j < count; ++j) {
                int m = find_slot(node[j], s);
                if (m >= 0)
                    add_lobe(out, s, node[j]->delta[m], rgb_scale(node[j]->a[m], wt[j] * scale));
            }
        }
}

/* The lobes of the nodes of `groups` (per_group corners each) with weight,
 * each group's lobes displaced across its nodes, the groups' results
 * blended by their weights. Groups of one corner each blend the nodes'
 * values. */
static void displaced_groups(const lobe_list lobes[4], const double w[4], const int (*group)[4], int groups,
                             int per_group, int mode, lobe_list *out, double *energy)
{
    out->n = 0;
    for (int g = 0; g < groups; ++g) {
        const lobe_list *node[4];
        double wt[4], total = 0.0;
        int count = 0;
        for (int i = 0; i < per_group; ++i) {
            int c = group[g][i];
            if (!(w[c] > 0.0))
                continue;
            node[count] = &lobes[c];
            wt[count++] = w[c];
            total += w[c];
        }
        for (int i = 0; i < count; ++i)
            wt[i] /= total;
        if (count > 0)
            displaced(node, wt, count, mode, total, out, energy);
    }
}

/* G_N at x of the combined lobes `blend` with, per slot, either the place
 * (exact_place) or the weight taken from `truth`, the lobes of the query's
 * own view: which of the two the oracle gets wrong. A slot only one of
 * them has keeps its own place and its weight in the other (0 where
 * missing). */
static rgb half_exact_gn(const lobe_list *blend, const lobe_list *truth, int exact_place, double beta_n, double x)
{
    lobe_list mixed;
    mixed.n = 0;
    for (int k = 0; k < blend->n; ++k) {
        int m = find_slot(truth, blend->slot[k]);
        double place = exact_place && m >= 0 ? truth->delta[m] : blend->delta[k];
        rgb a = exact_place ? blend->a[k] : m >= 0 ? truth->a[m] : rgb_gray(0.0);
        add_lobe(&mixed, blend->slot[k], place, a);
    }
    for (int m = 0; m < truth->n && !exact_place; ++m)
        if (find_slot(blend, truth->slot[m]) < 0)
            add_lobe(&mixed, truth->slot[m], truth->delta[m], truth->a[m]);
    return lobes_gn(&mixed, beta_n, x);
}

/* The corners (plm_fiber_corners' order: 0, 1 at the lower |theta_o| node,
 * phi_o nodes ip[0], ip[1]; 2, 3 above) grouped per estimator. */
static const int all_corners[1][4] = {{0, 1, 2, 3}};
static const int phi_pairs[2][4] = {{0, 1}, {2, 3}};
static const int theta_pairs[2][4] = {{0, 2}, {1, 3}};
static const int single_corners[4][4] = {{0}, {1}, {2}, {3}};
static const struct {
    const int (*corner)[4];
    int groups, per_group;
} groupings[GROUPINGS] = {{all_corners, 1, 4}, {phi_pairs, 2, 2}, {theta_pairs, 2, 2}};

/* The query's view as the table folds it, wi's theta_i (ct its cosine)
 * and its azimuth x relative to phi_o (in the folded view); 0 where every estimate is 0:
 * wo or wi along the axis, or G_M below e^-72 (the reference's too, to the
 * metric). */
static int query_angles(const plm_fiber_table *t, stats_query q, plm_fiber_view *v, double *theta_i, double *ct,
                        double *x)
{
    *ct = sqrt(q.wi.x * q.wi.x + q.wi.y * q.wi.y);
    if (!plm_fiber_view_of(t->symmetry, q.wo, q.hmin, q.hmax, v) || !(*ct > 1e-12))
        return 0;
    *theta_i = atan2(q.wi.z, *ct);
    double d = remainder(atan2(q.wi.y, q.wi.x) - v->phi_o, PLM_TWO_PI);
    *x = v->flip ? -d : d;
    return fabs(*theta_i + v->theta_o) <= 12.0 * t->params.beta_m;
}

/* Every estimator but the table at one query, with the nodes of t's
 * layout: the mean over `strata` midpoint strata of the folded h-interval. */
static void node_estimates(const plm_fiber_table *t, stats_query q, int strata, plm_fiber_lobe *lobes,
                           query_result *r)
{
    const plm_fiber_params *p = &t->params;
    for (int e = VALUES; e < ESTIMATORS; ++e)
        r->est[e] = rgb_gray(0.0);
    plm_fiber_view v;
    double theta_i, ct, x;
    if (!query_angles(t, q, &v, &theta_i, &ct, &x))
        return;
    /* The nodes as table_prepare finds them (elliptical tables have no limit node). */
    double ft = plm_fiber_theta_coordinate(p->eta, t->u_last, t->theta_max, t->theta_nodes, fabs(v.theta_o),
                                           v.sin_theta, v.cos_theta);
    int nodes[4];
    double w[4], phi_node[4];
    vec3 wo_node[4];
    plm_fiber_corners(t->symmetry, t->theta_nodes, t->phi_nodes, t->phi_lo, t->phi_step, ft, v.phi, nodes, w);
    for (int c = 0; c < 4; ++c) {
        double theta = plm_fiber_node_theta(p->eta, t->u_last, t->theta_max, t->theta_nodes, nodes[c] / t->phi_nodes);
        phi_node[c] = t->phi_lo + (nodes[c] % t->phi_nodes) * t->phi_step;
        wo_node[c] = plm_fiber_direction(theta, phi_node[c]);
    }
    plm_rng rng; /* drives only medulla bounces, whose lobes are left out */
    plm_rng_seed(&rng, 5, 5);
    vec3 wo_folded = plm_fiber_direction(fabs(v.theta_o), v.phi); /* the query's view as the nodes' are */
    rgb sum[ESTIMATORS] = {{0}};
    double energy[2] = {0.0, 0.0};
    lobe_list node[4], truth, combined;
    for (int s = 0; s < strata; ++s) {
        double h = v.hmin + (v.hmax - v.hmin) * (s + 0.5) / strata;
        for (int c = 0; c < 4; ++c) {
            node[c].n = 0;
            if (w[c] > 0.0)
                trace_node(p, wo_node[c], phi_node[c], h, &rng, lobes, &node[c]);
        }
        trace_node(p, wo_folded, v.phi, h, &rng, lobes, &truth);
        displaced_groups(node, w, single_corners, 4, 1, ZERO, &combined, NULL);
        sum[VALUES] = rgb_add(sum[VALUES], lobes_gn(&combined, p->beta_n, x));
        for (int g = 0; g < GROUPINGS; ++g)
            for (int mode = 0; mode < MODES; ++mode) {
                displaced_groups(node, w, groupings[g].corner, groupings[g].groups, groupings[g].per_group, mode,
                                 &combined, g == ALL && mode == ZERO ? energy : NULL);
                rgb d = lobes_gn(&combined, p->beta_n, x);
                sum[DISPLACED + MODES * g + mode] = rgb_add(sum[DISPLACED + MODES * g + mode], d);
                if (g != ALL || mode != ZERO)
                    continue;
                for (int exact_place = 0; exact_place < 2; ++exact_place)
                    sum[TRUE_WEIGHTS + exact_place] = rgb_add(sum[TRUE_WEIGHTS + exact_place],
                                                              half_exact_gn(&combined, &truth, exact_place, p->beta_n,
                                                                            x));
            }
    }
    double gm = reference_gm(p->beta_m, -v.theta_o, theta_i) / (ct * ct * strata);
    for (int e = VALUES; e < ESTIMATORS; ++e)
        r->est[e] = rgb_scale(sum[e], gm);
    r->missing = energy[0] > 0.0 ? energy[1] / energy[0] : 0.0;
}

/* Lagrange weights at x through the n points xs. */
static void lagrange(const double *xs, int n, double x, double *w)
{
    for (int i = 0; i < n; ++i) {
        w[i] = 1.0;
        for (int j = 0; j < n; ++j)
            if (j != i)
                w[i] *= (x - xs[j]) / (xs[i] - xs[j]);
    }
}

/* The study's weights over the |theta_o| levels it - 1 .. it + 2 (wt[0 .. 3];
 * levels outside the table get none) for estimator e and the class of lobe
 * (0: the surface reflection, 1: internal lobes; only the split
 * diagnostics tell them apart). x[k] are the levels' coordinates in the
 * schemes' variables: ft, theta, cos, cos^2, u^2, u (x[var][k]), q the
 * query's. */
enum { VAR_FT, VAR_THETA, VAR_COS, VAR_COS2, VAR_U2, VAR_U, VARS };
static void study_weights(int e, int cls, int it, int n, double x[VARS][4], const double q[VARS], double wt[4])
{
    wt[0] = wt[1] = wt[2] = wt[3] = 0.0;
    int has_below = it >= 1, has_above = it + 2 <= n - 1;
    if (e == SPLIT_FT_COS2)
        e = cls == 0 ? LIN_FT : LIN_COS2;
    else if (e == SPLIT_COS_COS2)
        e = cls == 0 ? LIN_COS : LIN_COS2;
    else if (e == QUAD_COS_73 || e == QUAD_COS_73_CLAMPED)
        e = it >= n - 4 ? QUAD_COS : LIN_FT;
    else if (e >= EFRAC_COS)
        e = LIN_FT; /* corrected afterwards from the energies */
    else if (e == QUAD_COS_LAST)
        e = it == n - 2 ? QUAD_COS : LIN_FT;
    if (e <= MIX) {
        static const int var[MIX] = {VAR_FT, VAR_THETA, VAR_COS, VAR_COS2, VAR_U2};
        double f;
        if (e == MIX) {
            double a = (q[VAR_COS] - x[VAR_COS][1]) / (x[VAR_COS][2] - x[VAR_COS][1]);
            double b = (q[VAR_COS2] - x[VAR_COS2][1]) / (x[VAR_COS2][2] - x[VAR_COS2][1]);
            f = 0.5 * (a + b);
        } else {
            int v = var[e];
            f = (q[v] - x[v][1]) / (x[v][2] - x[v][1]);
        }
        f = plm_clamp(f, 0.0, 1.0);
        wt[1] = 1.0 - f;
        wt[2] = f;
        return;
    }
    int v = e == QUAD_FT ? VAR_FT : e == QUAD_U ? VAR_U : VAR_COS;
    int first; /* the first of three levels (0 .. 3) */
    if (e == CUBIC_COS && has_below && has_above) {
        lagrange(x[v], 4, q[v], wt);
        return;
    }
    if (e == QUAD_COS_UP)
        first = has_above ? 1 : 0;
    else
        first = has_below ? 0 : 1;
    lagrange(x[v] + first, 3, q[v], wt + first);
}

/* The study at one query: the nodes' exact values (the mean over `strata`
 * midpoint strata of the lobes' G_N at wi, the surface reflection and the
 * internal lobes apart) at the two phi_o nodes of the |theta_o| levels
 * it - 1 .. it + 2, blended by each estimator's weights. */
static void study_estimates(const plm_fiber_table *t, stats_query q, int strata, plm_fiber_lobe *lobes, rgb *est)
{
    const plm_fiber_params *p = &t->params;
    for (int e = 0; e < STUDY_ESTIMATORS; ++e)
        est[e] = rgb_gray(0.0);
    plm_fiber_view v;
    double theta_i, ct, x;
    if (!query_angles(t, q, &v, &theta_i, &ct, &x))
        return;
    int n = t->theta_nodes;
    double ft = plm_fiber_theta_coordinate(p->eta, t->u_last, t->theta_max, n, fabs(v.theta_o), v.sin_theta,
                                           v.cos_theta);
    int nodes[4];
    double w[4];
    plm_fiber_corners(t->symmetry, n, t->phi_nodes, t->phi_lo, t->phi_step, ft, v.phi, nodes, w);
    int it = nodes[0] / t->phi_nodes, ip[2] = {nodes[0] % t->phi_nodes, nodes[1] % t->phi_nodes};
    double fp = w[0] + w[1] > 0.0 ? w[1] / (w[0] + w[1]) : w[3] / (w[2] + w[3]);
    double xs[VARS][4], qx[VARS];
    double tq = fabs(v.theta_o);
    qx[VAR_FT] = ft;
    qx[VAR_THETA] = tq;
    qx[VAR_COS] = v.cos_theta;
    qx[VAR_COS2] = v.cos_theta * v.cos_theta;
    qx[VAR_U] = plm_fiber_theta_u(p->eta, tq);
    qx[VAR_U2] = qx[VAR_U] * qx[VAR_U];
    vec3 wo_node[4][2];
    double phi_node[2] = {t->phi_lo + ip[0] * t->phi_step, t->phi_lo + ip[1] * t->phi_step};
    for (int k = 0; k < 4; ++k) {
        int level = it - 1 + k;
        if (level < 0 || level > n - 1)
            continue;
        double th = plm_fiber_node_theta(p->eta, t->u_last, t->theta_max, n, level);
        xs[VAR_FT][k] = level;
        xs[VAR_THETA][k] = th;
        xs[VAR_COS][k] = cos(th);
        xs[VAR_COS2][k] = cos(th) * cos(th);
        xs[VAR_U][k] = plm_fiber_theta_u(p->eta, th);
        xs[VAR_U2][k] = xs[VAR_U][k] * xs[VAR_U][k];
        for (int j = 0; j < 2; ++j)
            wo_node[k][j] = plm_fiber_direction(th, phi_node[j]);
    }
    plm_rng rng;
    plm_rng_seed(&rng, 5, 5);
    rgb value[4][2][2] = {{{{0}}}}; /* level, phi_o node, class (reflection, internal) */
    rgb energy[4][2] = {{{0}}};     /* level, phi_o node: the interval's energy */
    lobe_list l;
    for (int s = 0; s < strata; ++s) {
        double h = v.hmin + (v.hmax - v.hmin) * (s + 0.5) / strata;
        for (int k = 0; k < 4; ++k) {
            int level = it - 1 + k;
            if (level < 0 || level > n - 1)
                continue;
            for (int j = 0; j < 2; ++j) {
                trace_node(p, wo_node[k][j], phi_node[j], h, &rng, lobes, &l);
                for (int m = 0; m < l.n; ++m) {
                    rgb g = rgb_scale(l.a[m], reference_gn(p->beta_n, remainder(x - l.delta[m], PLM_TWO_PI), 1));
                    int cls = l.slot[m] > 0;
                    value[k][j][cls] = rgb_add(value[k][j][cls], g);
                    energy[k][j] = rgb_add(energy[k][j], l.a[m]);
                }
            }
        }
    }
    double gm = reference_gm(p->beta_m, -v.theta_o, theta_i) / (ct * ct * strata);
    /* The levels' energies (phi_o blended), lin-ft's and quad-cos's blends of them. */
    rgb el[4], elin = rgb_gray(0.0), equad = rgb_gray(0.0);
    double wlin[4], wquad[4];
    study_weights(LIN_FT, 0, it, n, xs, qx, wlin);
    study_weights(QUAD_COS, 0, it, n, xs, qx, wquad);
    for (int k = 0; k < 4; ++k) {
        el[k] = rgb_add(rgb_scale(energy[k][0], 1.0 - fp), rgb_scale(energy[k][1], fp));
        elin = rgb_add(elin, rgb_scale(el[k], wlin[k]));
        equad = rgb_add(equad, rgb_scale(el[k], wquad[k]));
    }
    for (int e = 0; e < STUDY_ESTIMATORS; ++e) {
        double wt[2][4];
        for (int cls = 0; cls < 2; ++cls)
            study_weights(e, cls, it, n, xs, qx, wt[cls]);
        int from73 = e == EFRAC_COS_73 || e == ESCALE_COS_73 || e == ESCALE_RGB_73;
        rgb scale = rgb_gray(1.0);
        if (e >= EFRAC_COS && (!from73 || it >= n - 4)) {
            double e1 = rgb_mean(el[1]), e2 = rgb_mean(el[2]), eq = fmax(rgb_mean(equad), 0.0);
            if (e == ESCALE_COS_LIMITED)
                eq = plm_clamp(eq, fmin(e1, e2), fmax(e1, e2));
            if (e == EFRAC_COS || e == EFRAC_COS_73) {
                if (fabs(e2 - e1) > 1e-3 * fmax(e1, e2)) {
                    double f = plm_clamp((eq - e1) / (e2 - e1), 0.0, 1.0);
                    for (int cls = 0; cls < 2; ++cls)
                        wt[cls][1] = 1.0 - f, wt[cls][2] = f;
                }
            } else if (e == ESCALE_RGB_73) {
                scale.r = elin.r > 0.0 ? fmax(equad.r, 0.0) / elin.r : 1.0;
                scale.g = elin.g > 0.0 ? fmax(equad.g, 0.0) / elin.g : 1.0;
                scale.b = elin.b > 0.0 ? fmax(equad.b, 0.0) / elin.b : 1.0;
            } else {
                scale = rgb_gray(rgb_mean(elin) > 0.0 ? eq / rgb_mean(elin) : 1.0);
            }
        }
        for (int cls = 0; cls < 2; ++cls)
            for (int k = 0; k < 4; ++k)
                if (wt[cls][k] != 0.0)
                    for (int j = 0; j < 2; ++j)
                        est[e] = rgb_add(est[e], rgb_scale(value[k][j][cls], gm * wt[cls][k] * (j ? fp : 1.0 - fp)));
        est[e] = rgb_mul(est[e], scale);
        if (e == QUAD_COS_73_CLAMPED)
            est[e] = (rgb){fmax(est[e].r, 0.0), fmax(est[e].g, 0.0), fmax(est[e].b, 0.0)};
    }
}

static void query_work(void *ctx, int item, double *scratch, plm_fiber_lobe *lobes)
{
    (void)scratch;
    const harness *hs = ctx;
    stats_query q = hs->query[item];
    query_result *r = &hs->result[item];
    r->ref = reference_eval(&hs->t->params, q.wo, q.hmin, q.hmax, q.wi, REFERENCE_STRATA);
    r->est[TABLE] = table_part_eval(hs->t, q.wo, q.hmin, q.hmax, q.wi);
    if (hs->study)
        study_estimates(hs->layout, q, hs->strata, lobes, r->est + 1);
    else
        node_estimates(hs->layout, q, hs->strata, lobes, r);
}

static double channel(rgb c, int ch) { return ch == 0 ? c.r : ch == 1 ? c.g : c.b; }

/* Prints each estimator's relative L2 per channel over the n queries and,
 * for its worst channel, the shares of the squared error. */
static void report(const char *name, int uniform, const stats_query *query, const query_result *r, int n, int study)
{
    int grazing_queries = 0, missing_queries = 0;
    for (int i = 0; i < n; ++i) {
        grazing_queries += fabs(query[i].wo.z) > sin(plm_radians(78.0));
        missing_queries += r[i].missing > 0.01;
    }
    fprintf(stderr, "%-28s wi %-8s %d queries, %d beyond 78 deg, %d with over 1%% of the energy in slots missing at a "
                    "node\n", name, uniform ? "uniform" : "at lobes", n, grazing_queries, missing_queries);
    for (int e = 0; e < (study ? 1 + STUDY_ESTIMATORS : ESTIMATORS); ++e) {
        char estimator[32];
        if (study)
            snprintf(estimator, sizeof estimator, "%s", e == 0 ? "table" : study_names[e - 1]);
        else if (e < DISPLACED || e >= TRUE_WEIGHTS)
            snprintf(estimator, sizeof estimator, "%s",
                     e == TABLE ? "table" : e == VALUES ? "values" : e == TRUE_WEIGHTS ? "true weights" : "true places");
        else
            snprintf(estimator, sizeof estimator, "%s %s", grouping_names[(e - DISPLACED) / MODES],
                     mode_names[(e - DISPLACED) % MODES]);
        double num[3] = {0, 0, 0}, den[3] = {0, 0, 0}, grazing[3] = {0, 0, 0}, missing[3] = {0, 0, 0};
        double worst[3] = {0, 0, 0};
        int worst_q[3] = {0, 0, 0}, negative = 0;
        for (int i = 0; i < n; ++i)
            negative += r[i].est[e].r < 0.0 || r[i].est[e].g < 0.0 || r[i].est[e].b < 0.0;
        for (int i = 0; i < n; ++i)
            for (int ch = 0; ch < 3; ++ch) {
                double d2 = plm_sqr(channel(r[i].est[e], ch) - channel(r[i].ref, ch));
                num[ch] += d2;
                den[ch] += plm_sqr(channel(r[i].ref, ch));
                if (fabs(query[i].wo.z) > sin(plm_radians(78.0)))
                    grazing[ch] += d2;
                if (r[i].missing > 0.01)
                    missing[ch] += d2;
                if (d2 > worst[ch]) {
                    worst[ch] = d2;
                    worst_q[ch] = i;
                }
            }
        int c = 0;
        double err[3];
        for (int ch = 0; ch < 3; ++ch) {
            err[ch] = den[ch] > 0.0 ? sqrt(num[ch] / den[ch]) : 0.0;
            c = err[ch] > err[c] ? ch : c;
        }
        double all = num[c] > 0.0 ? num[c] : 1.0;
        const stats_query *wq = &query[worst_q[c]];
        fprintf(stderr,
                "%-28s wi %-8s %-15s relative L2 %.4f %.4f %.4f; channel %d's squared error: beyond 78 deg %3.0f%%, "
                "slots missing %3.0f%%, worst query %3.0f%% (theta_o %.1f deg, h [%.3f, %.3f], ref %.4g, est %.4g)"
                "%s%d\n",
                name, uniform ? "uniform" : "at lobes", estimator, err[0], err[1], err[2], c,
                100.0 * grazing[c] / all, 100.0 * missing[c] / all, 100.0 * worst[c] / all,
                plm_degrees(asin(wq->wo.z)), wq->hmin, wq->hmax, channel(r[worst_q[c]].ref, c),
                channel(r[worst_q[c]].est[e], c), negative ? "; negative " : "", negative);
    }
}

/* One fiber as slow_fiber_table takes it: both kinds of queries (evaluated
 * here if the fiber is elliptical, else only drawn), then its medulla
 * part's reference, run for its draws alone. */
typedef struct run_options {
    int queries;   /* evaluated per kind of wi */
    int strata;    /* the estimators' h strata */
    int refine[2]; /* the estimators' nodes per the table's, in |theta_o| and phi_o */
    int draw;      /* 0: slow_fiber_table's queries; else other queries, from stream (draw, fiber) */
    int study;     /* 1: the |theta_o| blending study */
} run_options;

/* The generator's state after each fiber's medulla reference (which only
 * consumes draws here), kept in the file PROTO_ORACLE_RNG names, if set:
 * a run that finds the file skips the replays (minutes of CPU time). */
enum { FIBERS = PLM_FIBER_FIGURE7_VARIANTS + 8 };
static plm_rng after_medulla[FIBERS];
static int after_medulla_loaded;

static void fiber(const plm_fiber_params *p, const char *name, int index, plm_rng *rng, const run_options *ro)
{
    const int *refine = ro->refine;
    int elliptical = p->eccentricity != 1.0;
    plm_fiber_table_options o = {0};
    o.quiet = 1;
    plm_fiber_table *t = NULL;
    plm_error err;
    if ((elliptical || plm_fiber_has_medulla(p)) && plm_fiber_table_get(p, &o, &t, &err) != PLM_OK)
        fail_msg("%s", err.message);
    assert_true(!elliptical || (t->symmetry != PLM_FIBER_TABLE_ROTATIONAL && t->limit_node == 0));
    /* The estimators' nodes: the table's, or refine[0] times as dense in
     * |theta_o| and refine[1] times in phi_o (the table's among them). */
    plm_fiber_table layout;
    if (elliptical) {
        plm_fiber_table_options dense = {0};
        dense.theta_nodes = refine[0] * (t->theta_nodes - 1) + 1;
        dense.phi_nodes = t->symmetry == PLM_FIBER_TABLE_NONE ? refine[1] * t->phi_nodes
                                                               : refine[1] * (t->phi_nodes - 1) + 1;
        plm_fiber_table_layout(p, &dense, &layout);
    }
    stats_query *query = malloc(sizeof *query * QUERIES);
    query_result *result = calloc(QUERIES, sizeof *result);
    for (int uniform = 0; uniform < 2; ++uniform) {
        for (int i = 0; i < QUERIES; ++i)
            query[i] = error_query(p, rng, uniform);
        if (!elliptical)
            continue;
        plm_rng other;
        plm_rng_seed(&other, (uint64_t)ro->draw, (uint64_t)(2 * index + uniform));
        for (int i = 0; i < QUERIES && ro->draw > 0; ++i)
            query[i] = error_query(p, &other, uniform);
        harness hs = {t, &layout, query, result, ro->strata, ro->study};
        double started = plm_seconds();
        assert_true(plm_fiber_parallel(query_work, &hs, ro->queries, sizeof(double), p->lobes, o.threads, o.quiet, name, started));
        report(name, uniform, query, result, ro->queries, ro->study);
        fprintf(stderr, "%-28s table %d x %d nodes, estimators %d x %d, %d strata, %.0f s\n", name, t->theta_nodes,
                t->phi_nodes, layout.theta_nodes, layout.phi_nodes, ro->strata, plm_seconds() - started);
    }
    if (t && t->medulla.res.theta_nodes > 0 && after_medulla_loaded) {
        *rng = after_medulla[index];
    } else if (t && t->medulla.res.theta_nodes > 0) {
        double e[3], noise[3];
        double started = plm_seconds();
        medulla_error(t, rng, 8, 64, 100000, e, noise, NULL);
        fprintf(stderr, "%-28s medulla reference replayed, %.0f s\n", name, plm_seconds() - started);
    }
    after_medulla[index] = *rng;
    free(query);
    free(result);
    plm_fiber_table_free(t);
}

int main(int argc, char **argv)
{
    run_options ro = {argc > 1 ? atoi(argv[1]) : QUERIES, argc > 2 ? atoi(argv[2]) : 2000,
                      {argc > 3 ? atoi(argv[3]) : 1, argc > 4 ? atoi(argv[4]) : 1}, argc > 5 ? atoi(argv[5]) : 0,
                      argc > 6 ? atoi(argv[6]) : 0};
    if (ro.queries < 1 || ro.queries > QUERIES || ro.strata < 1 || ro.refine[0] < 1 || ro.refine[0] > 8 ||
        ro.refine[1] < 1 || ro.refine[1] > 8 || ro.draw < 0 || ro.study < 0 || ro.study > 1) {
        fprintf(stderr,
                "usage: %s [queries (1-%d) [strata (at least 1) [theta_o and phi_o node refinement (1-8) [draw (0: "
                "slow_fiber_table's queries) [study (1: the theta_o blending study)]]]]]\n",
                argv[0], QUERIES);
        return 2;
    }
    const char *states = getenv("PROTO_ORACLE_RNG");
    FILE *f = states ? fopen(states, "rb") : NULL;
    if (f) {
        after_medulla_loaded = fread(after_medulla, sizeof after_medulla, 1, f) == 1;
        fclose(f);
    }
    plm_rng rng; /* slow_fiber_table's figure7_fibers */
    plm_rng_seed(&rng, 2024, 7);
    for (int v = 0; v < PLM_FIBER_FIGURE7_VARIANTS; ++v) {
        plm_fiber_params p;
        plm_fiber_params_figure7(&p, v);
        fiber(&p, plm_fiber_figure7_names[v], v, &rng, &ro);
    }
    plm_rng_seed(&rng, 77, 1); /* its random_fibers */
    for (int i = 0; i < 8;) {
        plm_fiber_params p;
        char name[64];
        if (!random_table_fiber(&rng, i % 2 == 0, i, &p, name, sizeof name))
            continue;
        fiber(&p, name, PLM_FIBER_FIGURE7_VARIANTS + i, &rng, &ro);
        ++i;
    }
    if (states && !after_medulla_loaded && (f = fopen(states, "wb")) != NULL) {
        fwrite(after_medulla, sizeof after_medulla, 1, f);
        fclose(f);
    }
    return 0;
}
