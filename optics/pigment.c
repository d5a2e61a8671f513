#include "optics/pigment.h"

#include <stddef.h>

#define FIELD(name, member, meaning) \
    {name, PLM_PARAM_NUMBER, offsetof(plm_pigments, member), 0.0, 100.0, "", meaning, 0}
static const plm_param pigment_params[] = {
    FIELD("eumelanin", eumelanin, "black-brown melanin; about 0 (clear) to 8 (black)"),
    FIELD("pheomelanin", pheomelanin, "red-brown melanin"),
    FIELD("yellow", yellow, "yellow carotenoids and psittacofulvins: absorb blue (estimate)"),
    FIELD("red", red, "red keto-carotenoids and psittacofulvins: absorb blue and green (estimate)"),
    FIELD("keratin", keratin, "the faint grey absorption of clear keratin (estimate)"),
};
#undef FIELD
const plm_param_block plm_pigments_param_block = {
    "pigments", "a fiber's pigment concentrations, instead of its sigma_a (docs/species.md)", pigment_params,
    PLM_PARAM_COUNT(pigment_params)};

rgb plm_pigments_sigma_a(const plm_pigments *c)
{
    /* Per unit concentration and fiber radius. Melanins: Chiang, Bitterli,
     * Tappan & Burley 2016; the others: estimates from where their absorption
     * bands lie (docs/species.md). */
    static const struct {
        size_t offset;
        double r, g, b;
    } coefficient[] = {
        {offsetof(plm_pigments, eumelanin), 0.419, 0.697, 1.37},
        {offsetof(plm_pigments, pheomelanin), 0.187, 0.4, 1.05},
        {offsetof(plm_pigments, yellow), 0.0, 0.12, 1.0},
        {offsetof(plm_pigments, red), 0.02, 1.0, 0.75},
        {offsetof(plm_pigments, keratin), 0.02, 0.02, 0.02},
    };
    rgb s = rgb_gray(0.0);
    for (size_t i = 0; i < sizeof coefficient / sizeof coefficient[0]; ++i) {
        double k = *(const double *)((const char *)c + coefficient[i].offset);
        s = rgb_add(s, rgb_scale(rgb_make(coefficient[i].r, coefficient[i].g, coefficient[i].b), k));
    }
    return s;
}
