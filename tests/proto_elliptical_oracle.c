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
 * [refine_phi [draw]]]]] (defaults 2000, 2000, 1, 1, 0): the first
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

typedef struct query_result {
    rgb ref, est[ESTIMATORS];
    double missing; /* the oracle's share of energy (mean of RGB) in slots missing at one of the nodes */
} query_result;

typedef struct harness {
    const plm_fiber_table *t, *layout; /* the real table; the layout whose nodes the estimators use */
    const stats_query *query;
    query_result *result;
    int strata; /* the estimators' h strata (the reference's are REFERENCE_STRATA) */
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

/* Every estimator but the table at one query, with the nodes of t's
 * layout: the mean over `strata` midpoint strata of the folded h-interval. */
static void node_estimates(const plm_fiber_table *t, stats_query q, int strata, plm_fiber_lobe *lobes,
                           query_result *r)
{
    const plm_fiber_params *p = &t->params;
    for (int e = VALUES; e < ESTIMATORS; ++e)
        r->est[e] = rgb_gray(0.0);
    plm_fiber_view v;
    double ct = sqrt(q.wi.x * q.wi.x + q.wi.y * q.wi.y);
    if (!plm_fiber_view_of(t->symmetry, q.wo, q.hmin, q.hmax, &v) || !(ct > 1e-12))
        return;
    double theta_i = atan2(q.wi.z, ct), x = remainder(atan2(q.wi.y, q.wi.x) - v.phi_o, PLM_TWO_PI);
    x = v.flip ? -x : x;
    if (fabs(theta_i + v.theta_o) > 12.0 * p->beta_m)
        return; /* G_M below e^-72: every estimate, the reference too, is 0 to the metric */
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

static void query_work(void *ctx, int item, double *scratch, plm_fiber_lobe *lobes)
{
    (void)scratch;
    const harness *hs = ctx;
    stats_query q = hs->query[item];
    query_result *r = &hs->result[item];
    r->ref = reference_eval(&hs->t->params, q.wo, q.hmin, q.hmax, q.wi, REFERENCE_STRATA);
    r->est[TABLE] = table_part_eval(hs->t, q.wo, q.hmin, q.hmax, q.wi);
    node_estimates(hs->layout, q, hs->strata, lobes, r);
}

static double channel(rgb c, int ch) { return ch == 0 ? c.r : ch == 1 ? c.g : c.b; }

/* Prints each estimator's relative L2 per channel over the n queries and,
 * for its worst channel, the shares of the squared error. */
static void report(const char *name, int uniform, const stats_query *query, const query_result *r, int n)
{
    int grazing_queries = 0, missing_queries = 0;
    for (int i = 0; i < n; ++i) {
        grazing_queries += fabs(query[i].wo.z) > sin(plm_radians(78.0));
        missing_queries += r[i].missing > 0.01;
    }
    fprintf(stderr, "%-28s wi %-8s %d queries, %d beyond 78 deg, %d with over 1%% of the energy in slots missing at a "
                    "node\n", name, uniform ? "uniform" : "at lobes", n, grazing_queries, missing_queries);
    for (int e = 0; e < ESTIMATORS; ++e) {
        char estimator[32];
        if (e < DISPLACED || e >= TRUE_WEIGHTS)
            snprintf(estimator, sizeof estimator, "%s",
                     e == TABLE ? "table" : e == VALUES ? "values" : e == TRUE_WEIGHTS ? "true weights" : "true places");
        else
            snprintf(estimator, sizeof estimator, "%s %s", grouping_names[(e - DISPLACED) / MODES],
                     mode_names[(e - DISPLACED) % MODES]);
        double num[3] = {0, 0, 0}, den[3] = {0, 0, 0}, grazing[3] = {0, 0, 0}, missing[3] = {0, 0, 0};
        double worst[3] = {0, 0, 0};
        int worst_q[3] = {0, 0, 0};
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
                "%-28s wi %-8s %-12s relative L2 %.4f %.4f %.4f; channel %d's squared error: beyond 78 deg %3.0f%%, "
                "slots missing %3.0f%%, worst query %3.0f%% (theta_o %.1f deg, h [%.3f, %.3f], ref %.4g, est %.4g)\n",
                name, uniform ? "uniform" : "at lobes", estimator, err[0], err[1], err[2], c,
                100.0 * grazing[c] / all, 100.0 * missing[c] / all, 100.0 * worst[c] / all,
                plm_degrees(asin(wq->wo.z)), wq->hmin, wq->hmax, channel(r[worst_q[c]].ref, c),
                channel(r[worst_q[c]].est[e], c));
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
} run_options;

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
        harness hs = {t, &layout, query, result, ro->strata};
        double started = plm_fiber_seconds();
        assert_true(plm_fiber_parallel(query_work, &hs, ro->queries, sizeof(double), p->lobes, &o, name, started));
        report(name, uniform, query, result, ro->queries);
        fprintf(stderr, "%-28s table %d x %d nodes, estimators %d x %d, %d strata, %.0f s\n", name, t->theta_nodes,
                t->phi_nodes, layout.theta_nodes, layout.phi_nodes, ro->strata, plm_fiber_seconds() - started);
    }
    if (t && t->medulla.res.theta_nodes > 0) {
        double e[3], noise[3];
        double started = plm_fiber_seconds();
        medulla_error(t, rng, 8, 64, 100000, e, noise);
        fprintf(stderr, "%-28s medulla reference replayed, %.0f s\n", name, plm_fiber_seconds() - started);
    }
    free(query);
    free(result);
    plm_fiber_table_free(t);
}

int main(int argc, char **argv)
{
    run_options ro = {argc > 1 ? atoi(argv[1]) : QUERIES, argc > 2 ? atoi(argv[2]) : 2000,
                      {argc > 3 ? atoi(argv[3]) : 1, argc > 4 ? atoi(argv[4]) : 1}, argc > 5 ? atoi(argv[5]) : 0};
    if (ro.queries < 1 || ro.queries > QUERIES || ro.strata < 1 || ro.refine[0] < 1 || ro.refine[0] > 8 ||
        ro.refine[1] < 1 || ro.refine[1] > 8 || ro.draw < 0) {
        fprintf(stderr,
                "usage: %s [queries (1-%d) [strata (at least 1) [theta_o and phi_o node refinement (1-8) [draw (0: "
                "slow_fiber_table's queries)]]]]\n",
                argv[0], QUERIES);
        return 2;
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
    return 0;
}
