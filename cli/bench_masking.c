/* plumage bench masking: single-thread nanoseconds per call of what the
 * renderer calls for the masking (render/material.c): plm_masking_eval_window
 * over random view directions for three parameter sets, with the far field's
 * whole period and with a near-field window; and, for the default feather,
 * the near-field window of a shading point (plm_nearfield_at), the masking of
 * a filter candidate (plm_feather_masking) and the BSDF's prepare per shading
 * point with the masking kept from the filter (plm_feather_prepare_masked,
 * the tabulated fiber BCSDF, as rendered by default). */
#include <stdio.h>
#include <stdlib.h>

#include "cli/bench.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "common/rng.h"
#include "optics/feather_bsdf.h"
#include "optics/masking.h"
#include "optics/nearfield.h"

#define DIRECTIONS 4096
/* The synthetic vane of the near-field timing: a unit square with barbs at
 * 60 degrees to u, BARBS periods across it, and a pixel cone about a tenth
 * of a period wide. */
#define TEXELS 256
#define BARBS 32.0
#define CONE_WIDTH 0.003

enum { TIME_FAR, TIME_NEAR, TIME_NEARFIELD_AT, TIME_FEATHER_MASKING, TIME_FEATHER_PREPARE };

typedef struct bench_ctx {
    plm_masking_model model;
    plm_feather_params feather;
    plm_feather_model prepared; /* of feather */
    plm_fiber_table_set tables; /* prepared's */
    plm_feather_texture texture;
    frame barb; /* a tilted barb frame in world space */
    plm_rng rng;
    int what; /* TIME_... */
    vec3 dirs[DIRECTIONS];
    plm_barb_window windows[DIRECTIONS]; /* near-field windows, a tenth of a period at random positions */
    vec2 uvs[DIRECTIONS];
    vec3 rays[DIRECTIONS]; /* camera rays toward the vane z = 0, not grazing it */
    plm_masking kept[DIRECTIONS]; /* the feather's masking per direction, as a filter keeps it */
    double sink; /* keeps the calls from being optimised away */
} bench_ctx;

static const plm_barb_window far_field = {0.0, 1.0}; /* what plm_nearfield_at gives a distant pixel */

static void body(void *arg, long calls)
{
    bench_ctx *c = arg;
    double acc = 0.0;
    for (long i = 0; i < calls; ++i) {
        long k = i & (DIRECTIONS - 1);
        vec3 wo = c->dirs[k];
        plm_masking m;
        if (c->what == TIME_FAR || c->what == TIME_NEAR) {
            plm_masking_eval_window(&c->model, wo, c->what == TIME_FAR ? &far_field : &c->windows[k], &m);
            acc += m.w_barb + m.barb[0].hmin;
        } else if (c->what == TIME_NEARFIELD_AT) {
            plm_texel_site site;
            plm_feather_texture_site(&c->texture, c->uvs[k], &site);
            plm_barb_window w = plm_nearfield_at(&c->texture, &site, v3(1.0, 0.0, 0.0), v3(0.0, 1.0, 0.0),
                                                 v3(0.0, 0.0, 1.0), c->rays[k], CONE_WIDTH);
            acc += w.x1 - w.x0;
        } else if (c->what == TIME_FEATHER_MASKING) {
            plm_feather_masking(&c->prepared, &c->barb, &far_field, wo, &m);
            acc += m.w_transmission;
        } else {
            plm_feather_bsdf f;
            plm_feather_prepare_masked(&c->prepared, &c->barb, wo, &c->kept[k], rgb_gray(1.0), &c->rng, &f);
            acc += f.weight[0] + f.pick[1];
        }
    }
    c->sink += acc;
}

/* All vane; the barb coordinate k (-sin a u + cos a v) is constant along
 * the barb direction (cos a, sin a). */
static plm_result vane_texture(plm_feather_texture *t, plm_error *err)
{
    const double a = plm_radians(60.0);
    float *px = malloc(sizeof(float) * PLM_FTEX_CHANNELS * TEXELS * TEXELS);
    float *barb = malloc(sizeof(float) * TEXELS * TEXELS);
    if (!px || !barb) {
        free(px);
        free(barb);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for the bench's feather texture");
    }
    for (int y = 0; y < TEXELS; ++y)
        for (int x = 0; x < TEXELS; ++x) {
            long i = (long)y * TEXELS + x;
            double u = (x + 0.5) / TEXELS, v = 1.0 - (y + 0.5) / TEXELS;
            px[PLM_FTEX_CHANNELS * i + PLM_FTEX_COS] = plm_ftex_encode_component(cos(a));
            px[PLM_FTEX_CHANNELS * i + PLM_FTEX_SIN] = plm_ftex_encode_component(sin(a));
            px[PLM_FTEX_CHANNELS * i + PLM_FTEX_REGION] = plm_ftex_encode_region(PLM_REGION_VANE);
            barb[i] = plm_ftex_encode_barb(BARBS * (-sin(a) * u + cos(a) * v));
        }
    plm_result rc = plm_feather_texture_from_pixels(TEXELS, TEXELS, px, t, err);
    if (rc == PLM_OK)
        t->barb = barb;
    else
        free(barb);
    return rc;
}

/* The default feather with Fig. 9 set 2's masking, its fiber tables (from
 * the disk cache after the first run), a barb frame tilted away from the
 * world axes, and the masking a filter would keep for each direction. */
static plm_result prepare_feather(bench_ctx *c, plm_error *err)
{
    plm_feather_params_default(&c->feather);
    c->feather.masking.barbule_length = 3.0;
    c->feather.masking.barbule_inclination = plm_radians(45.0);
    plm_feather_model_init(&c->prepared, &c->feather);
    plm_fiber_table_set_init(&c->tables, NULL);
    plm_result rc = plm_feather_model_build_tables(&c->prepared, &c->tables, err);
    if (rc != PLM_OK)
        return rc;
    c->barb.y = v3_normalize(v3(0.3, 0.9, 0.2));
    c->barb.z = v3_normalize(v3_cross(c->barb.y, v3(1.0, 0.0, 0.0)));
    c->barb.x = v3_cross(c->barb.y, c->barb.z);
    for (int i = 0; i < DIRECTIONS; ++i)
        plm_feather_masking(&c->prepared, &c->barb, &far_field, c->dirs[i], &c->kept[i]);
    return vane_texture(&c->texture, err);
}

int bench_masking(int argc, char **argv)
{
    int runs = 9, calls = 2000000;
    plm_option opts[] = {
        {"--runs", PLM_OPT_INT, &runs, 0, 1, 64, NULL, "N", "timed runs; the median is reported (default 9)", 0},
        {"--calls", PLM_OPT_INT, &calls, 0, 1000, 1e9, NULL, "N", "calls per run (default 2000000)", 0},
    };
    plm_command_help help = {"plumage bench masking [--runs N] [--calls N]",
                             "Nanoseconds per masking call as the renderer makes them (far field and near field), "
                             "over random view\ndirections uniform on the sphere, and the feather BSDF's near-field "
                             "window, masking and prepare;\nsingle thread, median of the runs."};
    int rc = plm_parse_options(&help, argc, argv, 1, opts, 2, NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    bench_ctx *c = calloc(1, sizeof *c);
    if (!c) {
        fprintf(stderr, "error: out of memory\n");
        return 1;
    }
    plm_rng_seed(&c->rng, 2024, 3);
    for (int i = 0; i < DIRECTIONS; ++i) {
        double y = 2.0 * plm_rng_uniform(&c->rng) - 1.0, phi = PLM_TWO_PI * plm_rng_uniform(&c->rng);
        double r = sqrt(1.0 - y * y), x = plm_rng_uniform(&c->rng) - 0.5;
        c->dirs[i] = v3(r * cos(phi), y, r * sin(phi));
        c->windows[i] = (plm_barb_window){x - 0.05, x + 0.05};
        c->uvs[i] = v2(plm_rng_uniform(&c->rng), plm_rng_uniform(&c->rng));
        c->rays[i] = v3_normalize(v3(c->dirs[i].x, c->dirs[i].y, -fabs(c->dirs[i].z) - 0.1));
    }
    plm_error err;
    if (prepare_feather(c, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        plm_fiber_table_set_free(&c->tables);
        free(c);
        return 1;
    }
    /* The default parameters, then the paper's two Fig. 9 sets. */
    const struct { const char *name; double e_b, l, theta_deg; } sets[] = {
        {"defaults (e_b 1, l_bb 1, theta_bb 0)", 1.0, 1.0, 0.0},
        {"Fig. 9 set 1 (e_b 3, l_bb 1, theta_bb 0)", 3.0, 1.0, 0.0},
        {"Fig. 9 set 2 (e_b 1, l_bb 3, theta_bb 45)", 1.0, 3.0, 45.0},
    };
    printf("masking: single thread, %d random directions, median of %d runs of %d calls\n", DIRECTIONS, runs, calls);
    for (size_t k = 0; k < sizeof sets / sizeof sets[0]; ++k) {
        plm_masking_params p;
        plm_masking_params_default(&p);
        p.barb_eccentricity = sets[k].e_b;
        p.barbule_length = sets[k].l;
        p.barbule_inclination = plm_radians(sets[k].theta_deg);
        plm_masking_prepare(&p, &c->model);
        c->what = TIME_FAR;
        double ns_far = plm_bench_ns_per_call(body, c, calls, runs);
        c->what = TIME_NEAR;
        double ns_near = plm_bench_ns_per_call(body, c, calls, runs);
        printf("  %-44s %8.1f ns per plm_masking_eval_window, far field; %8.1f ns near field (0.1 period)\n",
               sets[k].name, ns_far, ns_near);
    }
    c->what = TIME_NEARFIELD_AT;
    double ns_window = plm_bench_ns_per_call(body, c, calls, runs);
    c->what = TIME_FEATHER_MASKING;
    double ns_masking = plm_bench_ns_per_call(body, c, calls, runs);
    c->what = TIME_FEATHER_PREPARE; /* a tenth of the calls: it does far more */
    double ns_prepare = plm_bench_ns_per_call(body, c, calls / 10 > 1000 ? calls / 10 : 1000, runs);
    printf("feather BSDF (default feather, Fig. 9 set 2 masking, tabulated fiber BCSDF):\n"
           "  %8.1f ns per plm_nearfield_at (shading point)\n"
           "  %8.1f ns per plm_feather_masking (filter candidate, far field)\n"
           "  %8.1f ns per plm_feather_prepare_masked (shading point, masking kept from the filter)\n",
           ns_window, ns_masking, ns_prepare);
    plm_fiber_table_set_free(&c->tables);
    plm_feather_texture_free(&c->texture);
    free(c);
    return 0;
}
