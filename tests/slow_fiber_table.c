/* The tabulated fiber BCSDF's accuracy at its default resolution (32 MiB).
 * Per query, against the exact mean over h (tests/fiber_table_stats.h), for
 * the four Fig. 7 fibers, the default barb and random parameter sets:
 * relative L2 per channel over random (wo, wi, h-interval), wi at the lobes
 * and uniform on the sphere; with a medulla, also its part against the
 * converged stochastic mean of the medulla's lobes. Circular fibers must be
 * within 1% per channel; elliptical ones are judged where users see them,
 * in renders: the tabulated and the stochastic estimator's images of a
 * feather whose barbs are elliptical must agree within 0.5% in every
 * quadrant. Their per-query figures are printed, not asserted
 * (docs/fiber.md gives them and film.fiber_table_mib, which buys more). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "tests/fiber_table_stats.h"
#include "tests/fiber_table_render.h"

/* The medulla part's error (medulla_error: 8 views x 64 wi, 10^5
 * reference sets each), printed with the whole BCSDF's at the same
 * queries; returns the largest channel's of the medulla part (the part
 * without the medulla has its own figures on more queries; the whole
 * BCSDF's figure is printed only, as both parts' are asserted). */
static double medulla_part_error(const plm_fiber_table *t, const char *name, plm_rng *rng)
{
    double e[3], noise[3], whole[3];
    medulla_error(t, rng, 8, 64, 100000, e, noise, whole);
    fprintf(stderr, "%-28s medulla part, eval cos: relative L2 %.4f %.4f %.4f (reference noise %.4f %.4f %.4f; "
                    "%d x %d nodes, %d h cells, %d x %d bins, %.1f MiB of the table)\n",
            name, e[0], e[1], e[2], noise[0], noise[1], noise[2], t->medulla.res.theta_nodes,
            t->medulla.res.phi_nodes, t->medulla.res.h_cells, t->medulla.res.theta_bins, t->medulla.res.phi_bins,
            sizeof(float) * t->medulla.floats / 1048576.0);
    fprintf(stderr, "%-28s both parts,   eval cos: relative L2 %.4f %.4f %.4f (the same queries)\n", name, whole[0],
            whole[1], whole[2]);
    return fmax(e[0], fmax(e[1], e[2]));
}

/* Queries per fiber and kind of wi: the error is carried by few queries
 * (grazing views, wi near a pole, narrow h-intervals), so a few hundred
 * rank two tables by chance (docs/fiber.md). */
enum { QUERIES = 2000 };
/* Paths per quadrant of the render comparison, tabulated and stochastic:
 * the stochastic estimator's paths are about 4 times as noisy. */
static const long RENDER_PATHS[2] = {1500000, 6000000};

/* Prints the errors of p's default table (and of its medulla part); returns the largest. */
static double default_table_error(const plm_fiber_params *p, const char *name, plm_rng *rng, int *symmetric)
{
    plm_fiber_table_options o = {0};
    o.quiet = 1;
    plm_fiber_table *t = NULL;
    plm_error err;
    if (plm_fiber_table_get(p, &o, &t, &err) != PLM_OK)
        fail_msg("%s", err.message);
    *symmetric = t->symmetry == PLM_FIBER_TABLE_ROTATIONAL;
    double worst = 0.0;
    for (int uniform = 0; uniform < 2; ++uniform) {
        double e[3];
        table_error(t, rng, QUERIES, uniform, 2000, e);
        fprintf(stderr,
                "%-28s %-10s wi %-8s relative L2 %.4f %.4f %.4f over %d queries (%d x %d nodes, %d h cells, the last "
                "%d nodes %d, %d bins, %.1f MiB)\n",
                name, *symmetric ? "circular" : "elliptical", uniform ? "uniform" : "at lobes", e[0], e[1], e[2],
                QUERIES, t->theta_nodes, t->phi_nodes, t->h_cells, t->grazing_nodes, t->grazing_cells, t->phi_bins,
                plm_fiber_table_bytes(t) / 1048576.0);
        for (int c = 0; c < 3; ++c)
            worst = fmax(worst, e[c]);
    }
    if (t->medulla.res.theta_nodes > 0)
        worst = fmax(worst, medulla_part_error(t, name, rng));
    plm_fiber_table_free(t);
    return worst;
}

/* The Fig. 7 fibers; the circular one's figures are asserted. */
static void figure7_fibers(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 2024, 7);
    double worst = 0.0;
    for (int v = 0; v < PLM_FIBER_FIGURE7_VARIANTS; ++v) {
        plm_fiber_params p;
        plm_fiber_params_figure7(&p, v);
        int symmetric;
        double e = default_table_error(&p, plm_fiber_figure7_names[v], &rng, &symmetric);
        if (symmetric)
            worst = fmax(worst, e);
    }
    assert_true(worst <= 0.01);
}

/* The default feather's barb (optics/feather_bsdf.c): a circular cortex
 * with a concentric white medulla of radius 0.6. */
static void default_barb(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 2024, 8);
    plm_fiber_params p;
    plm_fiber_params_default(&p);
    p.sigma_a = rgb_make(0.133, 1.967, 2.1);
    p.medulla_a = p.medulla_b = 0.6;
    int symmetric;
    assert_true(default_table_error(&p, "default barb", &rng, &symmetric) <= 0.01);
    assert_true(symmetric);
}

/* Random fibers; every other one circular (with a centred circular medulla
 * or none), whose figures are asserted. */
static void random_fibers(void **state)
{
    (void)state;
    plm_rng rng;
    plm_rng_seed(&rng, 77, 1);
    double worst = 0.0;
    for (int i = 0; i < 8;) {
        plm_fiber_params p;
        char name[64];
        if (!random_table_fiber(&rng, i % 2 == 0, i, &p, name, sizeof name))
            continue;
        int symmetric;
        double e = default_table_error(&p, name, &rng, &symmetric);
        if (symmetric)
            worst = fmax(worst, e);
        ++i;
    }
    assert_true(worst <= 0.01);
}

/* The feather sheet with elliptical barbs (eccentricity 1.6, as most
 * species presets have them) rendered with each estimator: in every
 * quadrant the tabulated mean must lie within 0.5% of the stochastic one,
 * measured to a standard error of at most 0.15% of the quadrant's mean (so
 * a bias of 0.5% is over three standard errors; measured: differences of
 * 0.06-0.21%, standard errors 0.04-0.11%). */
static void elliptical_renders_agree(void **state)
{
    (void)state;
    estimate e[2][SHEET_QUADS];
    sheet_estimator_quadrants(1.6, RENDER_PATHS, 7001, 2, e);
    for (int q = 0; q < SHEET_QUADS; ++q) {
        double diff = (e[0][q].mean - e[1][q].mean) / e[1][q].mean;
        double se = sqrt(plm_sqr(e[0][q].se) + plm_sqr(e[1][q].se)) / e[1][q].mean;
        fprintf(stderr, "quadrant %d: tabulated - stochastic %+.3f%% +- %.3f%%\n", q, 100.0 * diff, 100.0 * se);
        assert_true(se <= 0.0015);
        assert_true(fabs(diff) <= 0.005);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(default_barb),
        cmocka_unit_test(figure7_fibers),
        cmocka_unit_test(random_fibers),
        cmocka_unit_test(elliptical_renders_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
