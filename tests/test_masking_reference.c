/* The analytic masking against explicit 3D barbs and barbules (Embree Monte
 * Carlo), on the paper's Fig. 9 parameter sets with a coarse grid of views;
 * slow_masking.c repeats it finely and measures a wider sweep. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "assert_double.h"
#include "tests/masking_compare.h"

/* The paper's Fig. 9 sets: e_bb = 1, delta_bb = 1, phi_bb = 45 deg and either
 * (e_b 3, l_bb 1, theta_bb 0) or (e_b 1, l_bb 3, theta_bb 45 deg). */
static plm_masking_params figure9_set(int which)
{
    plm_masking_params p;
    plm_masking_params_default(&p);
    p.barb_eccentricity = which == 0 ? 3.0 : 1.0;
    p.barbule_length = which == 0 ? 1.0 : 3.0;
    p.barbule_inclination = plm_radians(which == 0 ? 0.0 : 45.0);
    return p;
}

static plm_masking_reference *make_reference(const plm_masking_params *p)
{
    plm_masking_reference *ref = masking_reference_or_null(p);
    assert_non_null(ref);
    return ref;
}

/* The analytic masking against the rays on a coarse grid of views within
 * 60 degrees of the normal, both sides: mean |difference| of every weight
 * <= 0.01 (slow_masking.c repeats this finely and over a wider sweep). */
static void assert_matches_rays(const plm_masking_params *p, const char *label, uint64_t seed)
{
    plm_masking_reference *ref = make_reference(p);
    masking_agreement a;
    assert_true(masking_compare(p, ref, &a, 5.0, 55.0, 10.0, 30.0, 4096, seed));
    masking_agreement_print(label, &a);
    assert_true(masking_agreement_worst_mean(&a) <= 0.01);
    plm_masking_reference_destroy(ref);
}

static void figure9_flat_barbules_match_explicit_geometry(void **state)
{
    (void)state;
    plm_masking_params p = figure9_set(0);
    assert_matches_rays(&p, "Fig. 9 set 1, polar <= 55", 100);
}

static void figure9_inclined_barbules_match_explicit_geometry(void **state)
{
    (void)state;
    plm_masking_params p = figure9_set(1);
    assert_matches_rays(&p, "Fig. 9 set 2, polar <= 55", 200);
}

/* Two sets of the slow sweep: falling flattened barbules, steep round ones. */
static void falling_and_steep_barbules_match_explicit_geometry(void **state)
{
    (void)state;
    plm_masking_params p = figure9_set(1);
    p.barbule_inclination = plm_radians(-30.0);
    p.barbule_eccentricity = 3.0;
    assert_matches_rays(&p, "theta -30, e_bb 3, polar <= 55", 300);
    p = figure9_set(1);
    p.barbule_inclination = plm_radians(60.0);
    p.barbule_length = 1.0;
    assert_matches_rays(&p, "theta 60, l_bb 1, polar <= 55", 400);
}

/* Normal view, theta_bb = 0: the rays see barb 2w, barbules (1 - 2w) of
 * which delta / (1 + delta) is gap; within 4 binomial sigmas. */
static void reference_normal_view_matches_closed_form(void **state)
{
    (void)state;
    plm_masking_params p;
    plm_masking_params_default(&p);
    p.barbule_length = 2.0;
    p.barbule_separation = 0.5;
    plm_masking_reference *ref = make_reference(&p);
    plm_masking r;
    plm_error err;
    unsigned n = 16384;
    assert_int_equal(plm_masking_reference_eval(ref, v3(0, 1, 0), n, 7, &r, &err), PLM_OK);
    double w = 0.5 / 3.0, t = 0.5 / 1.5;
    double expect[4] = {2 * w, (0.5 - w) * (1 - t), (0.5 - w) * (1 - t), (1 - 2 * w) * t};
    double got[4] = {r.w_barb, r.w_proximal, r.w_distal, r.w_transmission};
    for (int k = 0; k < 4; ++k)
        assert_true(fabs(got[k] - expect[k]) <= 4.0 * sqrt(expect[k] * (1 - expect[k]) / n));
    /* the same seed gives the same counts, another seed other ones (the rays are jittered) */
    plm_masking again, other;
    assert_int_equal(plm_masking_reference_eval(ref, v3(0, 1, 0), n, 7, &again, &err), PLM_OK);
    assert_int_equal(plm_masking_reference_eval(ref, v3(0, 1, 0), n, 8, &other, &err), PLM_OK);
    double same[4] = {again.w_barb, again.w_proximal, again.w_distal, again.w_transmission};
    double others[4] = {other.w_barb, other.w_proximal, other.w_distal, other.w_transmission};
    int differ = 0;
    for (int k = 0; k < 4; ++k) {
        assert_true(same[k] == got[k]);
        differ += others[k] != got[k];
    }
    assert_true(differ > 0);
    plm_masking_reference_destroy(ref);
}

/* Where barbules hide each other, the hits on them cover the h-interval the
 * barbule level predicts, for flat and inclined rows. */
static void assert_h_intervals_match(const plm_masking_params *p)
{
    plm_masking_reference *ref = make_reference(p);
    const double views[][3] = {{0.6, 0.5, 0.6}, {-0.7, 0.45, 0.2}, {0.3, -0.4, -0.8}};
    for (int i = 0; i < 3; ++i) {
        vec3 wo = v3(views[i][0], views[i][1], views[i][2]);
        plm_masking m, r;
        plm_error err;
        plm_masking_eval(p, wo, &m);
        assert_int_equal(plm_masking_reference_eval(ref, wo, 16384, 9, &r, &err), PLM_OK);
        const plm_h_range *a[2] = {&m.proximal, &m.distal}, *b[2] = {&r.proximal, &r.distal};
        for (int k = 0; k < 2; ++k)
            if (a[k]->rate > 0.05) {
                if (fabs(a[k]->hmin - b[k]->hmin) >= 0.05 || fabs(a[k]->hmax - b[k]->hmax) >= 0.05)
                    fprintf(stderr, "view %d set %d: analytic [%g, %g], rays [%g, %g]\n", i, k, a[k]->hmin,
                            a[k]->hmax, b[k]->hmin, b[k]->hmax);
                assert_double_near(a[k]->hmin, b[k]->hmin, 0.05);
                assert_double_near(a[k]->hmax, b[k]->hmax, 0.05);
            }
    }
    plm_masking_reference_destroy(ref);
}

static void reference_barbule_h_intervals_match(void **state)
{
    (void)state;
    plm_masking_params flat = figure9_set(0), inclined = figure9_set(1);
    assert_h_intervals_match(&flat);
    assert_h_intervals_match(&inclined);
}

static void reference_rejects_bad_input(void **state)
{
    (void)state;
    plm_masking_params p;
    plm_masking_params_default(&p);
    plm_masking_reference *ref = NULL;
    plm_error err;
    p.barbule_rotation = 0.0;
    assert_int_equal(plm_masking_reference_create(&p, NULL, &ref, &err), PLM_ERR_INVALID);
    assert_null(ref);
    plm_masking_params_default(&p);
    p.barbule_length = -1.0;
    assert_int_equal(plm_masking_reference_create(&p, NULL, &ref, &err), PLM_ERR_INVALID);
    plm_masking_params_default(&p);
    ref = make_reference(&p);
    plm_masking r;
    assert_int_equal(plm_masking_reference_eval(ref, v3(1, 0, 0), 64, 1, &r, &err), PLM_ERR_INVALID);
    assert_int_equal(plm_masking_reference_eval(ref, v3(NAN, 1, 0), 64, 1, &r, &err), PLM_ERR_INVALID);
    plm_masking_reference_destroy(ref);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(figure9_flat_barbules_match_explicit_geometry),
        cmocka_unit_test(figure9_inclined_barbules_match_explicit_geometry),
        cmocka_unit_test(falling_and_steep_barbules_match_explicit_geometry),
        cmocka_unit_test(reference_normal_view_matches_closed_form),
        cmocka_unit_test(reference_barbule_h_intervals_match),
        cmocka_unit_test(reference_rejects_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
