/* The fiber BCSDF front end (optics/fiber_bcsdf.h): the stochastic lobe
 * set, or the table's two parts mixed by energy. */
#include "optics/fiber_bcsdf.h"

void plm_fiber_bcsdf_prepare(const plm_fiber_params *p, const plm_fiber_table *table, vec3 wo, double hmin,
                             double hmax, plm_rng *rng, plm_fiber_bcsdf *out)
{
    out->params = p;
    out->tab.table = NULL;
    out->tab.total = 0.0;
    out->med.table = NULL;
    out->med.total = 0.0;
    if (!table) {
        plm_fiber_prepare(p, wo, hmin, hmax, rng, &out->set);
        out->pick_table = 0.0;
        out->total = out->set.total;
        return;
    }
    out->tab.table = table;
    plm_fiber_view view;
    if (plm_fiber_view_of(table->symmetry, wo, hmin, hmax, &view)) {
        plm_fiber_table_prepare(table, &view, &out->tab);
        plm_fiber_medulla_prepare(&table->medulla, &view, &out->med);
    }
    out->set.count = 0;
    out->set.total = 0.0;
    out->total = out->tab.total + out->med.total;
    out->pick_table = out->total > 0.0 ? out->tab.total / out->total : 0.0;
}

/* eval into *f (if not NULL) and the mixture's pdf at wi into *pdf (if not
 * NULL: eval alone need not pay for the medulla part's pdf); angles, if not
 * NULL, are wi's (theta_i, delta, cos(theta_i)) in the table's orientation,
 * known when a part sampled wi; both parts read them. */
static void bcsdf_lookup(const plm_fiber_bcsdf *b, vec3 wi, const double *angles, rgb *f, double *pdf)
{
    if (!b->tab.table) {
        if (f)
            *f = plm_fiber_eval(b->params, &b->set, wi);
        if (pdf)
            *pdf = plm_fiber_pdf(b->params, &b->set, wi);
        return;
    }
    double tab_pdf = 0.0, own[3];
    if (f)
        *f = rgb_gray(0.0);
    if (pdf)
        *pdf = 0.0;
    if (!angles) {
        if (!(b->total > 0.0) || !plm_fiber_table_angles(&b->tab, wi, &own[0], &own[1], &own[2]))
            return;
        angles = own;
    }
    if (b->tab.total > 0.0)
        plm_fiber_table_lookup(&b->tab, angles[0], angles[1], angles[2], f, &tab_pdf);
    if (pdf)
        *pdf = b->pick_table * tab_pdf;
    if (b->med.total > 0.0) {
        rgb med;
        double med_pdf;
        plm_fiber_medulla_lookup(&b->med, angles, f ? &med : NULL, pdf ? &med_pdf : NULL);
        if (f)
            *f = rgb_add(*f, med);
        if (pdf)
            *pdf += (1.0 - b->pick_table) * med_pdf;
    }
}

rgb plm_fiber_bcsdf_eval(const plm_fiber_bcsdf *b, vec3 wi)
{
    rgb f;
    bcsdf_lookup(b, wi, NULL, &f, NULL);
    return f;
}

double plm_fiber_bcsdf_pdf(const plm_fiber_bcsdf *b, vec3 wi)
{
    double pdf;
    bcsdf_lookup(b, wi, NULL, NULL, &pdf);
    return pdf;
}

rgb plm_fiber_bcsdf_eval_pdf(const plm_fiber_bcsdf *b, vec3 wi, double *pdf)
{
    rgb f;
    bcsdf_lookup(b, wi, NULL, &f, pdf);
    return f;
}

/* A direction from the mixture of the two parts, and its angles (theta_i,
 * delta, cos(theta_i)) in the table's orientation, which the lookup of its
 * eval and pdf then takes. */
static int bcsdf_sample_wi(const plm_fiber_bcsdf *b, double u0, double u1, double u2, vec3 *wi, double angles[3])
{
    if (u0 < b->pick_table) {
        if (!plm_fiber_table_sample(&b->tab, u0 / b->pick_table, u1, u2, &angles[0], &angles[1], wi))
            return 0;
        angles[2] = sqrt(wi->x * wi->x + wi->y * wi->y);
        return 1;
    }
    double remapped = plm_clamp((u0 - b->pick_table) / (1.0 - b->pick_table), 0.0, 0x1.fffffffffffffp-1);
    return plm_fiber_medulla_sample(&b->med, remapped, u1, u2, angles, wi);
}

int plm_fiber_bcsdf_sample_direction(const plm_fiber_bcsdf *b, double u0, double u1, double u2, vec3 *wi)
{
    if (!(b->total > 0.0))
        return 0;
    if (!b->tab.table) {
        plm_fiber_sample_rec rec;
        if (!plm_fiber_sample(b->params, &b->set, u0, u1, u2, &rec))
            return 0;
        *wi = rec.wi;
        return 1;
    }
    double angles[3];
    return bcsdf_sample_wi(b, u0, u1, u2, wi, angles);
}

int plm_fiber_bcsdf_sample(const plm_fiber_bcsdf *b, double u0, double u1, double u2, plm_fiber_sample_rec *rec)
{
    if (!(b->total > 0.0))
        return 0;
    if (!b->tab.table)
        return plm_fiber_sample(b->params, &b->set, u0, u1, u2, rec);
    vec3 wi;
    double angles[3];
    if (!bcsdf_sample_wi(b, u0, u1, u2, &wi, angles))
        return 0;
    rec->lobe = -1;
    rgb f;
    double pdf, ct = angles[2];
    bcsdf_lookup(b, wi, angles, &f, &pdf);
    if (!(pdf > 0.0))
        return 0;
    rec->wi = wi;
    rec->pdf = pdf;
    rec->weight = rgb_scale(f, ct / pdf);
    return 1;
}
