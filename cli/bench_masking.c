/* plumage bench masking: single-thread nanoseconds per full masking call
 * (plm_masking_eval, and plm_masking_eval_prepared with the view-independent
 * work done once) over random view directions, for three parameter sets; and
 * what the feather BSDF spends per filter candidate (plm_feather_transmission)
 * and per shading point (plm_feather_prepare, fiber lobes included). */
#include <stdio.h>
#include <stdlib.h>

#include "cli/bench.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "common/rng.h"
#include "render/feather_bsdf.h"
#include "render/masking.h"

#define DIRECTIONS 4096

enum { TIME_EVAL, TIME_PREPARED, TIME_FEATHER_TRANSMISSION, TIME_FEATHER_PREPARE };

typedef struct bench_ctx {
    plm_masking_params params;
    plm_masking_model model;
    plm_feather_params feather;
    frame barb; /* a tilted barb frame in world space */
    plm_rng rng;
    int what; /* TIME_... */
    vec3 dirs[DIRECTIONS];
    double sink; /* keeps the calls from being optimised away */
} bench_ctx;

static void body(void *arg, long calls)
{
    bench_ctx *c = arg;
    double acc = 0.0;
    for (long i = 0; i < calls; ++i) {
        plm_masking m;
        vec3 wo = c->dirs[i & (DIRECTIONS - 1)];
        if (c->what == TIME_PREPARED) {
            plm_masking_eval_prepared(&c->model, wo, &m);
        } else if (c->what == TIME_EVAL) {
            plm_masking_eval(&c->params, wo, &m);
        } else if (c->what == TIME_FEATHER_TRANSMISSION) {
            acc += plm_feather_transmission(&c->feather, &c->barb, wo);
            continue;
        } else {
            plm_feather_bsdf f;
            plm_feather_prepare(&c->feather, &c->barb, wo, rgb_gray(1.0), &c->rng, &f);
            acc += f.weight[0] + f.pick[1];
            continue;
        }
        acc += m.w_barb + m.barb[0].hmin;
    }
    c->sink += acc;
}

int bench_masking(int argc, char **argv)
{
    int runs = 9, calls = 2000000;
    plm_option opts[] = {
        {"--runs", PLM_OPT_INT, &runs, 0, 1, 64, NULL, "N", "timed runs; the median is reported (default 9)", 0},
        {"--calls", PLM_OPT_INT, &calls, 0, 1000, 1e9, NULL, "N", "calls per run (default 2000000)", 0},
    };
    plm_command_help help = {"plumage bench masking [--runs N] [--calls N]",
                             "Nanoseconds per full masking call (both barbule levels and the barb level) over "
                             "random view directions\nuniform on the sphere, single thread, median of the runs."};
    int rc = plm_parse_options(&help, argc, argv, 1, opts, 2, NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    bench_ctx *c = calloc(1, sizeof *c);
    if (!c) {
        fprintf(stderr, "error: out of memory\n");
        return 1;
    }
    plm_rng rng;
    plm_rng_seed(&rng, 2024, 3);
    for (int i = 0; i < DIRECTIONS; ++i) {
        double y = 2.0 * plm_rng_uniform(&rng) - 1.0, phi = PLM_TWO_PI * plm_rng_uniform(&rng);
        double r = sqrt(1.0 - y * y);
        c->dirs[i] = v3(r * cos(phi), y, r * sin(phi));
    }
    /* The default parameters, then the paper's two Fig. 9 sets. */
    const struct { const char *name; double e_b, l, theta_deg; } sets[] = {
        {"defaults (e_b 1, l_bb 1, theta_bb 0)", 1.0, 1.0, 0.0},
        {"Fig. 9 set 1 (e_b 3, l_bb 1, theta_bb 0)", 3.0, 1.0, 0.0},
        {"Fig. 9 set 2 (e_b 1, l_bb 3, theta_bb 45)", 1.0, 3.0, 45.0},
    };
    printf("masking: single thread, %d random directions, median of %d runs of %d calls\n", DIRECTIONS, runs, calls);
    for (size_t k = 0; k < sizeof sets / sizeof sets[0]; ++k) {
        plm_masking_params_default(&c->params);
        c->params.barb_eccentricity = sets[k].e_b;
        c->params.barbule_length = sets[k].l;
        c->params.barbule_inclination = plm_radians(sets[k].theta_deg);
        plm_masking_prepare(&c->params, &c->model);
        c->what = TIME_EVAL;
        double ns = plm_bench_ns_per_call(body, c, calls, runs);
        c->what = TIME_PREPARED;
        double ns_prepared = plm_bench_ns_per_call(body, c, calls, runs);
        printf("  %-44s %8.1f ns per plm_masking_eval, %8.1f ns prepared\n", sets[k].name, ns, ns_prepared);
    }
    /* The feather BSDF with Fig. 9 set 2's masking on a barb frame tilted
     * away from the world axes; a tenth of the calls for the lobe tracing. */
    plm_feather_params_default(&c->feather);
    c->feather.masking.barbule_length = 3.0;
    c->feather.masking.barbule_inclination = plm_radians(45.0);
    plm_feather_params_prepare_masking(&c->feather);
    c->barb.y = v3_normalize(v3(0.3, 0.9, 0.2));
    c->barb.z = v3_normalize(v3_cross(c->barb.y, v3(1.0, 0.0, 0.0)));
    c->barb.x = v3_cross(c->barb.y, c->barb.z);
    plm_rng_seed(&c->rng, 7, 1);
    c->what = TIME_FEATHER_TRANSMISSION;
    double ns_transmission = plm_bench_ns_per_call(body, c, calls, runs);
    c->what = TIME_FEATHER_PREPARE;
    double ns_prepare = plm_bench_ns_per_call(body, c, calls / 10 > 1000 ? calls / 10 : 1000, runs);
    printf("feather BSDF (Fig. 9 set 2 masking): %8.1f ns per plm_feather_transmission (filter candidate), "
           "%8.1f ns per plm_feather_prepare (shading point)\n", ns_transmission, ns_prepare);
    free(c);
    return 0;
}
