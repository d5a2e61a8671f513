/* A fiber's parameters: defaults, the paper's Fig. 7 fibers, the parameter
 * table that files and validation share, and the check that the medulla
 * lies inside the cortex. */
#include "optics/fiber_params.h"

#include <stddef.h>

void plm_fiber_params_default(plm_fiber_params *p)
{
    p->eccentricity = 1.0;
    p->eta = 1.55;
    p->sigma_a = rgb_gray(0.0);
    p->beta_m = 0.13;
    p->beta_n = 0.12;
    p->medulla_a = p->medulla_b = 0.0;
    p->medulla_ca = p->medulla_cb = 0.0;
    p->medulla_reflectance = rgb_gray(1.0);
    p->lobes = 5;
}

const char *const plm_fiber_figure7_names[PLM_FIBER_FIGURE7_VARIANTS] = {"circular", "elliptical",
                                                                          "concentric_medulla", "offcentre_medulla"};

void plm_fiber_params_figure7(plm_fiber_params *p, int variant)
{
    plm_fiber_params_default(p);
    p->eta = 1.53;
    p->sigma_a = rgb_make(0.133, 1.967, 2.1);
    p->beta_m = 0.13;
    p->beta_n = 0.12;
    p->eccentricity = variant == 0 ? 1.0 : 1.6;
    if (variant >= 2) {
        p->medulla_a = p->medulla_b = 0.6;
        p->medulla_ca = variant == 3 ? -0.1 : 0.0;
        p->medulla_cb = variant == 3 ? 0.1 : 0.0;
    }
}

/* ---- validation ---------------------------------------------------------- */

/* The cortex's implicit function x^2 + (y/e)^2 at the medulla's boundary
 * point of parameter t: below 1 inside the cortex. */
static double cortex_level_at_medulla(const plm_fiber_params *p, double t)
{
    return plm_sqr(p->medulla_ca + p->medulla_a * cos(t)) +
           plm_sqr((p->medulla_cb + p->medulla_b * sin(t)) / p->eccentricity);
}

/* Its maximum over the medulla's boundary: a dense scan brackets it and a
 * golden-section search pins it down. */
static double medulla_max_cortex_level(const plm_fiber_params *p)
{
    const int n = 720;
    double best_t = 0.0, best = -1.0;
    for (int i = 0; i < n; ++i) {
        double t = PLM_TWO_PI * i / n, v = cortex_level_at_medulla(p, t);
        if (v > best) {
            best = v;
            best_t = t;
        }
    }
    const double g = 0.5 * (sqrt(5.0) - 1.0);
    double lo = best_t - PLM_TWO_PI / n, hi = best_t + PLM_TWO_PI / n;
    for (int i = 0; i < 80; ++i) {
        double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
        if (cortex_level_at_medulla(p, a) > cortex_level_at_medulla(p, b))
            hi = b;
        else
            lo = a;
    }
    return fmax(best, cortex_level_at_medulla(p, 0.5 * (lo + hi)));
}

#define FIELD(name, type, member, lo, hi, unit, meaning) \
    {name, type, offsetof(plm_fiber_params, member), lo, hi, unit, meaning, 0}
static const plm_param fiber_params[] = {
    FIELD("eccentricity", PLM_PARAM_NUMBER, eccentricity, 0.01, 100.0, "",
          "cortex semi-axis along e3 over the one along e2 (1 = circular)"),
    FIELD("eta", PLM_PARAM_NUMBER, eta, 1.0, 4.0, "", "refractive index of cortex and medulla (keratin 1.55)"),
    FIELD("sigma_a", PLM_PARAM_RGB, sigma_a, 0.0, 1e4, "1/radius",
          "pigment absorption per unit path length, in units of the e2 semi-axis"),
    FIELD("beta_m", PLM_PARAM_ANGLE, beta_m, 0.5, 90.0, "degrees", "longitudinal roughness (detector std-dev)"),
    FIELD("beta_n", PLM_PARAM_ANGLE, beta_n, 0.5, 90.0, "degrees", "azimuthal roughness (detector std-dev)"),
    FIELD("medulla_axes", PLM_PARAM_PAIR, medulla_a, 0.0, 100.0, "radius",
          "medulla semi-axes along e2, e3; [0, 0] = no medulla"),
    FIELD("medulla_centre", PLM_PARAM_PAIR, medulla_ca, -100.0, 100.0, "radius",
          "medulla centre; the medulla must lie strictly inside the cortex"),
    FIELD("medulla_reflectance", PLM_PARAM_RGB, medulla_reflectance, 0.0, 1.0, "",
          "Lambertian albedo of the medulla (structural white or blue)"),
    FIELD("lobes", PLM_PARAM_INT, lobes, 1, PLM_FIBER_MAX_LOBES, "",
          "scattering lobes traced per path (a feather material takes at most 32)"),
};
#undef FIELD
const plm_param_block plm_fiber_param_block = {"fiber", "one fiber (barb or barbule): see docs/fiber.md",
                                               fiber_params, PLM_PARAM_COUNT(fiber_params)};

plm_result plm_fiber_params_validate(const plm_fiber_params *p, plm_error *err)
{
    plm_result r = plm_params_check(&plm_fiber_param_block, p, err);
    if (r != PLM_OK)
        return r;
    if ((p->medulla_a > 0.0) != (p->medulla_b > 0.0))
        return plm_fail(err, PLM_ERR_INVALID,
                        "fiber: medulla semi-axes (%g, %g) must both be 0 (no medulla) or both positive",
                        p->medulla_a, p->medulla_b);
    if (plm_fiber_has_medulla(p) && !(medulla_max_cortex_level(p) < 1.0))
        return plm_fail(err, PLM_ERR_INVALID,
                        "fiber: the medulla (semi-axes %g, %g, centre %g, %g) must lie strictly inside the cortex "
                        "(semi-axes 1, %g): it pokes out",
                        p->medulla_a, p->medulla_b, p->medulla_ca, p->medulla_cb, p->eccentricity);
    return PLM_OK;
}
