/* An experiment, not a test of the product: the part without the medulla
 * of a Fig. 7 fiber's table against the exact mean over h (as
 * slow_fiber_table measures it) at several memory budgets, each with the
 * layout the budget gives (plm_fiber_table_options.budget_mib, a scene's
 * film.fiber_table_mib). Two draws of `queries` queries per kind of wi (at
 * the lobes, uniform), the same at every budget; one line per budget and
 * draw with the layout, the build time and the relative L2 per channel.
 * docs/fiber.md ("Memory and accuracy") has its figures.
 *
 * Usage: proto_table_memory VARIANT MIB... (VARIANT 0-3: circular,
 * elliptical, concentric medulla, off-centre medulla; e.g. 1 32 256 2048).
 * Tables are built afresh, not cached; 2 GiB takes about 20 s to build
 * and the memory; the references about 10 s per budget and draw at the
 * default 2000 queries (PROTO_QUERIES overrides). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "tests/fiber_table_stats.h"

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: proto_table_memory VARIANT MIB...\n");
        return 2;
    }
    char *end;
    long variant = strtol(argv[1], &end, 10);
    int queries = getenv("PROTO_QUERIES") ? atoi(getenv("PROTO_QUERIES")) : 2000;
    if (*end || end == argv[1] || variant < 0 || variant >= PLM_FIBER_FIGURE7_VARIANTS || queries < 1) {
        fprintf(stderr, "proto_table_memory: VARIANT is 0 to %d, PROTO_QUERIES at least 1\n",
                PLM_FIBER_FIGURE7_VARIANTS - 1);
        return 2;
    }
    plm_fiber_params p;
    plm_fiber_params_figure7(&p, (int)variant);
    for (int a = 2; a < argc; ++a) {
        plm_fiber_table_options o = {0};
        o.quiet = 1;
        o.no_cache = 1;
        o.budget_mib = atoi(argv[a]);
        plm_fiber_table *t = NULL;
        plm_error err;
        if (o.budget_mib < PLM_FIBER_TABLE_MIB_MIN || o.budget_mib > PLM_FIBER_TABLE_MIB_MAX) {
            fprintf(stderr, "proto_table_memory: MIB '%s' must be in [%d, %d]\n", argv[a], PLM_FIBER_TABLE_MIB_MIN,
                    PLM_FIBER_TABLE_MIB_MAX);
            return 2;
        }
        if (plm_fiber_table_get(&p, &o, &t, &err) != PLM_OK) {
            fprintf(stderr, "proto_table_memory: %s\n", err.message);
            return 1;
        }
        for (int draw = 0; draw < 2; ++draw) {
            plm_rng rng;
            plm_rng_seed(&rng, 31337, 40 + (uint64_t)draw);
            double e[2][3];
            for (int uniform = 0; uniform < 2; ++uniform)
                table_error(t, &rng, queries, uniform, 2000, e[uniform]);
            printf("%s %d MiB (%d x %d nodes, %d/%d cells, %.1f MiB, built in %.1f s) draw %d: at lobes %.4f %.4f "
                   "%.4f, uniform %.4f %.4f %.4f\n",
                   plm_fiber_figure7_names[variant], o.budget_mib, t->theta_nodes, t->phi_nodes, t->h_cells,
                   t->grazing_cells, plm_fiber_table_bytes(t) / 1048576.0, t->build_seconds, draw, e[0][0], e[0][1],
                   e[0][2], e[1][0], e[1][1], e[1][2]);
            fflush(stdout);
        }
        plm_fiber_table_free(t);
    }
    return 0;
}
