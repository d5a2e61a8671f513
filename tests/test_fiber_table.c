/* The tabulated fiber BCSDF (render/fiber_table.h): accuracy against a
 * first-principles mean over h, white furnace, chi-square of sample against
 * pdf, agreement with the stochastic estimator in a render, and the disk
 * cache (hit, miss, truncated and corrupt files, two processes at once).
 * slow_fiber_table.c runs the accuracy test on every Fig. 7 fiber and random
 * parameters at the default resolution. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "render/feather_bsdf.h"
#include "render/render.h"
#include "tests/fiber_stats.h"
#include "tests/fiber_table_stats.h"
#include "test_render_stats.h"

static plm_fiber_table *get_table(const plm_fiber_params *p, const plm_fiber_table_options *o)
{
    plm_fiber_table *t = NULL;
    plm_error err;
    if (plm_fiber_table_get(p, o, &t, &err) != PLM_OK)
        fail_msg("%s", err.message);
    return t;
}

/* The circular Fig. 7 fiber at its default resolution (one phi_o node, so
 * it builds in well under a second): within 1% of the exact h-mean, with wi
 * at the lobes and uniform on the sphere. */
static void circular_fiber_matches_h_mean(void **state)
{
    (void)state;
    plm_fiber_params p;
    plm_fiber_params_figure7(&p, 0);
    plm_fiber_table_options o = {0};
    o.no_cache = 1;
    plm_fiber_table *t = get_table(&p, &o);
    plm_rng rng;
    plm_rng_seed(&rng, 17, 0);
    for (int uniform = 0; uniform < 2; ++uniform) {
        double e[3];
        table_error(t, &rng, 150, uniform, 1000, e);
        fprintf(stderr, "circular fiber, wi %s: relative L2 %.4f %.4f %.4f\n", uniform ? "uniform" : "at lobes", e[0],
                e[1], e[2]);
        for (int c = 0; c < 3; ++c)
            assert_true(e[c] <= 0.01);
    }
    plm_fiber_table_free(t);
}

/* sigma_a = 0, no medulla: the integral of eval cos is the mean lobe energy
 * over the h-interval (from the tracer, 4000 strata), and the pdf integrates
 * to 1; for an elliptical fiber through its mirror symmetries, on a coarse table. */
static void white_furnace(void **state)
{
    (void)state;
    plm_fiber_table_options o = {0};
    o.no_cache = 1;
    o.theta_nodes = 7, o.phi_nodes = 5, o.h_cells = 32, o.phi_bins = 128;
    const double ecc[] = {1.0, 1.6};
    for (int e = 0; e < 2; ++e) {
        plm_fiber_params p;
        plm_fiber_params_figure7(&p, 0);
        p.sigma_a = rgb_gray(0.0);
        p.eccentricity = ecc[e];
        p.beta_n = 0.2;
        plm_fiber_table *t = get_table(&p, &o);
        plm_rng rng;
        plm_rng_seed(&rng, 4, (uint64_t)e);
        plm_fiber_lobe lobes[5];
        for (int q = 0; q < 4; ++q) {
            vec3 wo = random_sphere(&rng);
            double h0 = 2.0 * plm_rng_uniform(&rng) - 1.0, h1 = 2.0 * plm_rng_uniform(&rng) - 1.0;
            double hmin = fmin(h0, h1), hmax = fmax(h0, h1), energy = 0.0;
            const int strata = 4000;
            for (int s = 0; s < strata; ++s) {
                int n = plm_fiber_trace(&p, wo, hmin + (hmax - hmin) * (s + 0.5) / strata, NULL, lobes);
                for (int k = 0; k < n; ++k)
                    energy += lobes[k].throughput.g / strata;
            }
            plm_fiber_bcsdf b;
            plm_fiber_bcsdf_prepare(&p, t, wo, hmin, hmax, &rng, &b);
            double integral = integrate_bcsdf(&b, 1, -0.5 * PLM_PI, 0.5 * PLM_PI, -PLM_PI, PLM_PI, 360, 720);
            double pdf = integrate_bcsdf(&b, 3, -0.5 * PLM_PI, 0.5 * PLM_PI, -PLM_PI, PLM_PI, 360, 720);
            fprintf(stderr, "furnace e %.1f: integral %.5f, lobe energy %.5f, pdf %.5f\n", ecc[e], integral, energy, pdf);
            assert_double_near(integral, energy, 2e-3 * energy);
            assert_double_near(pdf, 1.0, 2e-3);
        }
        plm_fiber_table_free(t);
    }
}

/* Sampling has exactly the density pdf says: the table part alone (no
 * medulla), and mixed with the medulla's traced lobes (off-centre medulla,
 * no symmetry), at small resolution. */
static void sampling_matches_pdf(void **state)
{
    (void)state;
    enum { N_TESTS = 4 };
    const double threshold = 1.0 - pow(1.0 - 0.01, 1.0 / N_TESTS); /* Sidak */
    plm_fiber_table_options o = {0};
    o.no_cache = 1;
    o.theta_nodes = 7, o.phi_nodes = 6, o.h_cells = 16, o.phi_bins = 96;
    plm_rng rng;
    plm_rng_seed(&rng, 8, 0);
    for (int i = 0; i < N_TESTS; ++i) {
        plm_fiber_params p;
        plm_fiber_params_figure7(&p, i % 2 ? 3 : 1);
        plm_fiber_table *t = get_table(&p, &o);
        vec3 wo = plm_fiber_direction(i < 2 ? 0.5 : -1.2, 0.7 + 1.9 * i);
        plm_fiber_bcsdf b;
        plm_fiber_bcsdf_prepare(&p, t, wo, -0.7 + 0.2 * i, 0.9, &rng, &b);
        double pv = bcsdf_chi_square(&b, &rng, 300000);
        fprintf(stderr, "chi-square %d (%s, %d medulla lobes, table share %.3f): p-value %.4f\n", i,
                plm_fiber_figure7_names[p.medulla_a > 0 ? 3 : 1], b.set.count, b.pick_table, pv);
        assert_true(pv > threshold);
        plm_fiber_table_free(t);
    }
}

/* ---- the cache ----------------------------------------------------------- */

static void scratch_dir(char *dir, size_t size, const char *name)
{
    snprintf(dir, size, "%s/fiber_table_%s_%ld", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", name, (long)getpid());
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

static void remove_dir(const char *dir)
{
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

static int files_in(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d));)
        n += e->d_name[0] != '.' || strstr(e->d_name, ".tmp") != NULL;
    if (d)
        closedir(d);
    return n;
}

static plm_fiber_table_options small_cached(const char *dir)
{
    plm_fiber_table_options o = {0};
    o.cache_dir = dir;
    o.quiet = 1;
    o.theta_nodes = 5, o.phi_nodes = 4, o.h_cells = 8, o.phi_bins = 64;
    return o;
}

static void same_data(const plm_fiber_table *a, const plm_fiber_table *b)
{
    assert_true(a->floats == b->floats);
    assert_memory_equal(a->data, b->data, sizeof(float) * a->floats);
}

/* Same parameters hit, changed ones miss, a truncated or corrupted file is
 * rebuilt (and replaced by a valid one). */
static void cache_hits_misses_and_rebuilds(void **state)
{
    (void)state;
    char dir[512], path[4096];
    scratch_dir(dir, sizeof dir, "cache");
    plm_fiber_table_options o = small_cached(dir);
    plm_fiber_params p;
    plm_fiber_params_figure7(&p, 1);
    plm_fiber_table *built = get_table(&p, &o), *hit = get_table(&p, &o);
    assert_false(built->from_cache);
    assert_true(hit->from_cache);
    same_data(built, hit);
    assert_int_equal(files_in(dir), 1);

    plm_fiber_params q = p;
    q.sigma_a.r += 1e-9;
    plm_fiber_table *miss = get_table(&q, &o);
    assert_false(miss->from_cache);
    assert_int_equal(files_in(dir), 2);

    assert_true(plm_fiber_table_cache_path(&p, &o, path, sizeof path));
    for (int damage = 0; damage < 2; ++damage) {
        FILE *fp = fopen(path, "r+b");
        assert_non_null(fp);
        fseek(fp, 0, SEEK_END);
        long size = ftell(fp);
        if (damage == 0) {
            assert_int_equal(ftruncate(fileno(fp), size - 100), 0);
        } else { /* one flipped byte in the data */
            fseek(fp, size / 2, SEEK_SET);
            int c = fgetc(fp);
            fseek(fp, size / 2, SEEK_SET);
            fputc(c ^ 0x40, fp);
        }
        fclose(fp);
        plm_fiber_table *rebuilt = get_table(&p, &o), *again = get_table(&p, &o);
        assert_false(rebuilt->from_cache);
        assert_true(again->from_cache);
        same_data(built, rebuilt);
        plm_fiber_table_free(rebuilt);
        plm_fiber_table_free(again);
    }
    plm_fiber_table_free(built);
    plm_fiber_table_free(hit);
    plm_fiber_table_free(miss);
    remove_dir(dir);
}

/* Two processes build the same table at once: both succeed, one valid file
 * is left (no temporaries), and it holds what a fresh build gives. */
static void two_processes_build_at_once(void **state)
{
    (void)state;
    char dir[512];
    scratch_dir(dir, sizeof dir, "race");
    plm_fiber_table_options o = small_cached(dir);
    plm_fiber_params p;
    plm_fiber_params_figure7(&p, 3);
    pid_t child[2];
    for (int i = 0; i < 2; ++i) {
        child[i] = fork();
        assert_true(child[i] >= 0);
        if (child[i] == 0) {
            plm_fiber_table *t = NULL;
            int ok = plm_fiber_table_get(&p, &o, &t, NULL) == PLM_OK && !t->from_cache;
            _exit(ok ? 0 : 1);
        }
    }
    for (int i = 0; i < 2; ++i) {
        int status = 0;
        assert_int_equal(waitpid(child[i], &status, 0), child[i]);
        assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    }
    assert_int_equal(files_in(dir), 1);
    plm_fiber_table *cached = get_table(&p, &o);
    assert_true(cached->from_cache);
    plm_fiber_table_options fresh = o;
    fresh.no_cache = 1;
    plm_fiber_table *built = get_table(&p, &fresh);
    same_data(cached, built);
    plm_fiber_table_free(cached);
    plm_fiber_table_free(built);
    remove_dir(dir);
}

/* ---- the renderer -------------------------------------------------------- */

/* A curled feather sheet under a sky with a sun, rendered with each
 * estimator: the image means agree within their Monte Carlo errors. */
static void render_estimators_agree(void **state)
{
    (void)state;
    estimate e[2];
    for (int k = 0; k < 2; ++k) {
        plm_scene s;
        plm_scene_init(&s);
        plm_mesh mesh;
        plm_error err;
        assert_int_equal(plm_shape_quad(2.0, 2.0, 1.0, 16, &mesh, &err), PLM_OK);
        plm_material m;
        memset(&m, 0, sizeof m);
        snprintf(m.name, sizeof m.name, "vane");
        m.type = PLM_MATERIAL_FEATHER;
        m.reflectance = rgb_gray(0.7);
        m.feather = malloc(sizeof *m.feather);
        assert_non_null(m.feather);
        plm_feather_params_default(m.feather);
        m.feather->bcsdf = k ? PLM_BCSDF_STOCHASTIC : PLM_BCSDF_TABULATED;
        float *px = malloc(sizeof(float) * 3 * 4); /* the texture takes it */
        assert_non_null(px);
        for (int i = 0; i < 4; ++i) /* all vane, barbs at 60 degrees */
            px[3 * i] = (float)((sin(plm_radians(60.0)) + 1) / 2), px[3 * i + 1] = (float)((cos(plm_radians(60.0)) + 1) / 2),
            px[3 * i + 2] = 1.0f;
        assert_int_equal(plm_feather_texture_from_pixels(2, 2, px, &m.texture, &err), PLM_OK);
        plm_instance in = {plm_scene_add_mesh(&s, "vane", &mesh), plm_scene_add_material(&s, &m),
                           plm_xform_identity(), rgb_gray(1.0)};
        assert_true(plm_scene_add_instance(&s, &in) >= 0);
        plm_light sun;
        memset(&sun, 0, sizeof sun);
        sun.type = PLM_LIGHT_QUAD;
        sun.corner = v3(1.0, 1.0, 2.0);
        sun.edge_u = v3(0, 0.5, 0); /* facing down, -z */
        sun.edge_v = v3(0.5, 0, 0);
        sun.radiance = rgb_gray(20.0);
        plm_scene_add_light(&s, &sun);
        s.camera = (plm_camera_desc){v3(0.3, -0.4, 2.5), v3(0, 0, 0), v3(0, 1, 0), 40, 0, 0, 1};
        s.film.width = s.film.height = 24;
        plm_world w;
        assert_int_equal(plm_world_build(&s, &w, &err), PLM_OK);
        e[k] = film_mean(&w, PLM_ESTIMATOR_MIS, 6, 40000, 11 + k);
        fprintf(stderr, "%s: image mean %.5f +- %.5f\n", k ? "stochastic" : "tabulated", e[k].mean, e[k].se);
        plm_world_free(&w);
        plm_scene_free(&s);
    }
    assert_agree(e[0], e[1], 4.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(circular_fiber_matches_h_mean),
        cmocka_unit_test(white_furnace),
        cmocka_unit_test(sampling_matches_pdf),
        cmocka_unit_test(cache_hits_misses_and_rebuilds),
        cmocka_unit_test(two_processes_build_at_once),
        cmocka_unit_test(render_estimators_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
