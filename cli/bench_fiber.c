/* plumage bench fiber: single-thread nanoseconds per fiber BCSDF query for
 * the paper's four Fig. 7 fibers and the default feather's barb, with each estimator (docs/fiber.md). A
 * shading query prepares the BCSDF for wo (the stochastic one traces a lobe
 * set) and then evaluates or samples it, so the headline figures are
 * prepare + eval and prepare + sample; the parts are timed too. Over the
 * whole h-interval [-1, 1], or over partial ones (two uniform ends, as
 * masking leaves a renderer; the tables' partial cells cost more). Also each
 * table's build time on all cores (not from the cache) and its size. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli/bench.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "optics/feather_bsdf.h"
#include "optics/fiber_bcsdf.h"

/* Powers of two, cycled with a mask. Queries are many so branches cannot be
 * learnt; prepared sets few, because a renderer evaluates the set it has just
 * traced, still in cache. */
enum { N_QUERIES = 4096, N_SETS = 64 };

/* Random (uniform on the sphere) directions and sample numbers, drawn before
 * timing so the timed loops measure the BCSDF alone. */
typedef struct fiber_bench {
    plm_fiber_params params;
    const plm_fiber_table *table; /* NULL: the stochastic estimator */
    vec3 wo[N_QUERIES], wi[N_QUERIES];
    double hmin[N_QUERIES], hmax[N_QUERIES]; /* each query's h-interval */
    double u[N_QUERIES][3];
    plm_fiber_bcsdf sets[N_SETS]; /* prepared, for timing eval and sample alone */
    plm_rng rng;
    volatile double sink; /* keeps the results alive */
} fiber_bench;

static void prepare(fiber_bench *b, int q, plm_fiber_bcsdf *set)
{
    plm_fiber_bcsdf_prepare(&b->params, b->table, b->wo[q], b->hmin[q], b->hmax[q], &b->rng, set);
}

static void bench_prepare_eval(void *ctx, long calls)
{
    fiber_bench *b = ctx;
    double acc = 0.0;
    for (long i = 0; i < calls; ++i) {
        plm_fiber_bcsdf set;
        prepare(b, (int)(i & (N_QUERIES - 1)), &set);
        acc += plm_fiber_bcsdf_eval(&set, b->wi[i & (N_QUERIES - 1)]).g;
    }
    b->sink = acc;
}

static void bench_prepare_sample(void *ctx, long calls)
{
    fiber_bench *b = ctx;
    double acc = 0.0;
    for (long i = 0; i < calls; ++i) {
        int q = (int)(i & (N_QUERIES - 1));
        plm_fiber_bcsdf set;
        plm_fiber_sample_rec rec;
        prepare(b, q, &set);
        if (plm_fiber_bcsdf_sample(&set, b->u[q][0], b->u[q][1], b->u[q][2], &rec))
            acc += rec.pdf;
    }
    b->sink = acc;
}

static void bench_prepare(void *ctx, long calls)
{
    fiber_bench *b = ctx;
    double acc = 0.0;
    for (long i = 0; i < calls; ++i) {
        plm_fiber_bcsdf set;
        prepare(b, (int)(i & (N_QUERIES - 1)), &set);
        acc += set.total;
    }
    b->sink = acc;
}

static void bench_eval(void *ctx, long calls)
{
    fiber_bench *b = ctx;
    double acc = 0.0;
    for (long i = 0; i < calls; ++i)
        acc += plm_fiber_bcsdf_eval(&b->sets[i & (N_SETS - 1)], b->wi[i & (N_QUERIES - 1)]).g;
    b->sink = acc;
}

static void bench_sample(void *ctx, long calls)
{
    fiber_bench *b = ctx;
    double acc = 0.0;
    for (long i = 0; i < calls; ++i) {
        int q = (int)(i & (N_QUERIES - 1));
        plm_fiber_sample_rec rec;
        if (plm_fiber_bcsdf_sample(&b->sets[i & (N_SETS - 1)], b->u[q][0], b->u[q][1], b->u[q][2], &rec))
            acc += rec.pdf;
    }
    b->sink = acc;
}

static vec3 random_direction(plm_rng *rng)
{
    double z = 2.0 * plm_rng_uniform(rng) - 1.0;
    return plm_fiber_direction(asin(z), PLM_TWO_PI * plm_rng_uniform(rng));
}

/* The queries of one run: directions, sample numbers and h-intervals
 * (partial: two uniform ends), the same for each estimator. */
static void draw_queries(fiber_bench *b, int v, int partial)
{
    plm_rng_seed(&b->rng, 2024, (uint64_t)v);
    for (int q = 0; q < N_QUERIES; ++q) {
        b->wo[q] = random_direction(&b->rng);
        b->wi[q] = random_direction(&b->rng);
        for (int k = 0; k < 3; ++k)
            b->u[q][k] = plm_rng_uniform(&b->rng);
        double h0 = partial ? 2.0 * plm_rng_uniform(&b->rng) - 1.0 : -1.0;
        double h1 = partial ? 2.0 * plm_rng_uniform(&b->rng) - 1.0 : 1.0;
        b->hmin[q] = fmin(h0, h1);
        b->hmax[q] = fmax(h0, h1);
    }
    for (int q = 0; q < N_SETS; ++q)
        prepare(b, q, &b->sets[q]);
}

int bench_fiber(int argc, char **argv)
{
    static const char *const intervals[] = {"whole", "partial", "both", NULL};
    static const char *const fibers[] = {"circular", "elliptical", "concentric_medulla", "offcentre_medulla",
                                         "default_barb", "all", NULL};
    static const char *const estimators[] = {"stochastic", "tabulated", "both", NULL};
    int runs = 7, calls = 200000, lobes = 5, cached = 0, interval = 2, only = PLM_FIBER_FIGURE7_VARIANTS + 1,
        estimator = 2, table_mib = PLM_FIBER_TABLE_MIB_DEFAULT;
    plm_option opts[] = {
        {"--runs", PLM_OPT_INT, &runs, 0, 1, 64, NULL, "N", "timed runs; the median is reported (default 7)", 0},
        {"--calls", PLM_OPT_INT, &calls, 0, 1000, 100000000, NULL, "N", "calls per timed run (default 200000)", 0},
        {"--lobes", PLM_OPT_INT, &lobes, 0, 1, PLM_FIBER_SET_MAX_LOBES, NULL, "N", "lobes per set (default 5)", 0},
        {"--interval", PLM_OPT_CHOICE, &interval, 0, 0, 0, intervals, "whole|partial|both",
         "h-intervals: [-1, 1], two uniform ends in [-1, 1] (as masking leaves a renderer), or each in turn "
         "(default both)",
         0},
        {"--fiber", PLM_OPT_CHOICE, &only, 0, 0, 0, fibers, "NAME",
         "one fiber's rows only (circular, elliptical, concentric_medulla, offcentre_medulla, default_barb; "
         "default all)",
         0},
        {"--bcsdf", PLM_OPT_CHOICE, &estimator, 0, 0, 0, estimators, "stochastic|tabulated|both",
         "the estimators timed (default both)", 0},
        {"--cached", PLM_OPT_FLAG, &cached, 0, 0, 0, NULL, NULL,
         "take the tables from the disk cache (no build time; for instruction counts under callgrind)", 0},
        {"--table-mib", PLM_OPT_INT, &table_mib, 0, PLM_FIBER_TABLE_MIB_MIN, PLM_FIBER_TABLE_MIB_MAX, NULL, "N",
         "each table's memory, as a scene's film.fiber_table_mib (default 32)", 0},
    };
    const plm_command_help help = {
        "plumage bench fiber [options]",
        "Single-thread nanoseconds per fiber BCSDF call for the four Fig. 7 fibers, the default feather's\n"
        "barb (a concentric medulla in a circular cortex) and both estimators\n"
        "(stochastic, tabulated; docs/fiber.md), over random view and light directions (uniform on the\n"
        "sphere) and h-intervals (--interval: the whole [-1, 1], or partial ones, whose ends inside the\n"
        "tables' h cells cost more): prepare + eval and prepare + sample (what a shading query costs), and\n"
        "prepare, eval and sample alone (on sets prepared over such intervals). Median of --runs runs. Then\n"
        "each table's build time on all cores (built afresh, not from the cache) and its size."};
    int rc = plm_parse_options(&help, argc, argv, 1, opts, (int)(sizeof opts / sizeof opts[0]), NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    static fiber_bench b;
    printf("fiber,bcsdf,interval,lobes,prepare_eval_ns,prepare_sample_ns,prepare_ns,eval_ns,sample_ns,build_s,"
           "table_mib\n");
    for (int v = 0; v <= PLM_FIBER_FIGURE7_VARIANTS; ++v) { /* the last: the default barb */
        if (only <= PLM_FIBER_FIGURE7_VARIANTS && v != only)
            continue;
        const char *name = "default_barb";
        if (v < PLM_FIBER_FIGURE7_VARIANTS) {
            plm_fiber_params_figure7(&b.params, v);
            name = plm_fiber_figure7_names[v];
        } else {
            plm_feather_params feather;
            plm_feather_params_default(&feather);
            b.params = feather.barb;
        }
        b.params.lobes = lobes;
        plm_fiber_table *table = NULL;
        plm_fiber_table_options build = {0};
        build.no_cache = !cached; /* timed afresh */
        build.budget_mib = table_mib;
        build.quiet = 1;
        plm_error err;
        if (plm_fiber_table_get(&b.params, &build, &table, &err) != PLM_OK) {
            fprintf(stderr, "error: %s\n", err.message);
            return 1;
        }
        for (int tabulated = estimator == 1; tabulated <= (estimator != 0); ++tabulated)
            for (int partial = interval == 1; partial <= (interval != 0); ++partial) {
                b.table = tabulated ? table : NULL;
                draw_queries(&b, v, partial);
                double t_pe = plm_bench_ns_per_call(bench_prepare_eval, &b, calls, runs);
                double t_ps = plm_bench_ns_per_call(bench_prepare_sample, &b, calls, runs);
                double t_p = plm_bench_ns_per_call(bench_prepare, &b, calls, runs);
                double t_e = plm_bench_ns_per_call(bench_eval, &b, calls, runs);
                double t_s = plm_bench_ns_per_call(bench_sample, &b, calls, runs);
                printf("%s,%s,%s,%d,%.1f,%.1f,%.1f,%.1f,%.1f", name, tabulated ? "tabulated" : "stochastic",
                       intervals[partial], lobes, t_pe, t_ps, t_p, t_e, t_s);
                if (tabulated && !table->from_cache)
                    printf(",%.2f,%.1f\n", table->build_seconds, plm_fiber_table_bytes(table) / 1048576.0);
                else if (tabulated)
                    printf(",cached,%.1f\n", plm_fiber_table_bytes(table) / 1048576.0);
                else
                    printf(",,\n");
                fflush(stdout);
            }
        plm_fiber_table_free(table);
    }
    return 0;
}
