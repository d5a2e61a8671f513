/* Slow validation of the analytic masking against explicit 3D geometry:
 * - the paper's two Fig. 9 parameter sets on a fine grid of views within 60
 *   degrees of the normal, both sides, 16384 rays per view (asserted);
 * - a wider sweep (e_b 1-3, e_bb 1-3, l_bb 1-4, delta_bb 0.1-3, theta_bb
 *   0-60 deg, views up to 85 deg from the normal), printed as a table. The
 *   sweep measures; it asserts only where the model claims exactness
 *   (theta_bb = 0, views within 60 degrees). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "tests/masking_compare.h"

static plm_masking_params params(double e_b, double e_bb, double l, double delta, double theta_deg)
{
    plm_masking_params p;
    plm_masking_params_default(&p);
    p.barb_eccentricity = e_b;
    p.barbule_eccentricity = e_bb;
    p.barbule_length = l;
    p.barbule_separation = delta;
    p.barbule_inclination = plm_radians(theta_deg);
    return p;
}

static plm_masking_reference *make_reference(const plm_masking_params *p)
{
    plm_masking_reference *ref = masking_reference_or_null(p);
    assert_non_null(ref);
    return ref;
}

static void figure9_sets_fine(void **state)
{
    (void)state;
    const masking_model_fn models[2] = {masking_design_frames, masking_rooted_frames};
    for (int set = 0; set < 2; ++set) {
        plm_masking_params p = set == 0 ? params(3, 1, 1, 1, 0) : params(1, 1, 3, 1, 45);
        plm_masking_reference *ref = make_reference(&p);
        masking_agreement a[2];
        assert_true(masking_compare_models(&p, ref, models, 2, a, 2.5, 60.0, 2.5, 10.0, 16384, 1000 * (set + 1)));
        char label[96];
        snprintf(label, sizeof label, "Fig. 9 set %d, model frames, polar <= 60", set + 1);
        masking_agreement_print(label, &a[0]);
        snprintf(label, sizeof label, "Fig. 9 set %d, geometry's frames, polar <= 60", set + 1);
        masking_agreement_print(label, &a[1]);
        /* The product's model where its frames are the geometry's (set 1),
         * the level computations everywhere. */
        if (set == 0)
            assert_true(masking_agreement_worst_mean(&a[0]) <= 0.01);
        assert_true(masking_agreement_worst_mean(&a[1]) <= 0.01);
        plm_masking_reference_destroy(ref);
    }
}

static void wide_sweep_table(void **state)
{
    (void)state;
    const double e_bs[] = {1, 3}, e_bbs[] = {1, 3}, ls[] = {1, 4}, deltas[] = {0.1, 1, 3}, thetas[] = {0, 30, 60};
    const masking_model_fn models[2] = {masking_design_frames, masking_rooted_frames};
    printf("\nworst mean |analytic - rays| over the four weights; 'design' = plm_masking_eval, 'geometry' = levels "
           "with the\nreference geometry's own frames. Views: polar 5-55 and 65-85 deg, both sides, every 30 deg of "
           "azimuth, 4096 rays.\n");
    printf("%4s %4s %4s %5s %5s | %13s %13s | %13s %13s\n", "e_b", "e_bb", "l_bb", "delta", "theta", "design<=55",
           "design65-85", "geometry<=55", "geometry65-85");
    double worst_flat = 0.0;
    uint64_t seed = 1;
    for (size_t a = 0; a < 2; ++a)
        for (size_t b = 0; b < 2; ++b)
            for (size_t c = 0; c < 2; ++c)
                for (size_t d = 0; d < 3; ++d)
                    for (size_t e = 0; e < 3; ++e) {
                        plm_masking_params p = params(e_bs[a], e_bbs[b], ls[c], deltas[d], thetas[e]);
                        plm_masking_reference *ref = make_reference(&p);
                        masking_agreement near[2], far[2];
                        assert_true(masking_compare_models(&p, ref, models, 2, near, 5, 55, 10, 30, 4096, seed));
                        assert_true(masking_compare_models(&p, ref, models, 2, far, 65, 85, 10, 30, 4096, seed + 500));
                        seed += 1000;
                        printf("%4g %4g %4g %5g %5g | %13.4f %13.4f | %13.4f %13.4f\n", e_bs[a], e_bbs[b], ls[c],
                               deltas[d], thetas[e], masking_agreement_worst_mean(&near[0]),
                               masking_agreement_worst_mean(&far[0]), masking_agreement_worst_mean(&near[1]),
                               masking_agreement_worst_mean(&far[1]));
                        fflush(stdout);
                        if (thetas[e] == 0.0)
                            worst_flat = fmax(worst_flat, masking_agreement_worst_mean(&near[0]));
                        plm_masking_reference_destroy(ref);
                    }
    printf("worst over theta_bb = 0, views within 55 deg: %.4f\n", worst_flat);
    assert_true(worst_flat <= 0.02);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(figure9_sets_fine),
        cmocka_unit_test(wide_sweep_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
