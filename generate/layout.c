/* What every layout shares (generate/layout_parts.h): prototypes, their
 * extents, per-feather variation, the instance matrix. The pelt and the
 * feather ball are generate/pelt.c, the wing generate/wing.c. */
#include "generate/layout.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/rng.h"
#include "generate/geometry.h"
#include "generate/layout_parts.h"
#include "generate/outline.h"

void plm_layout_free(plm_layout *layout)
{
    free(layout->prototypes);
    free(layout->instances);
    memset(layout, 0, sizeof *layout);
}

/* ---- Prototypes and their extents ---- */

static double jitter(plm_rng *rng, double amount) { return amount * (2.0 * plm_rng_uniform(rng) - 1.0); }

void plm_species_variant(const plm_species *base, int variant, uint64_t seed, plm_shape *shape, plm_pigment *pigment)
{
    *shape = base->shape;
    *pigment = base->pigment;
    if (variant == 0)
        return;
    plm_rng rng;
    plm_rng_seed(&rng, plm_hash64(seed, (uint64_t)variant, 0x7a41u), PLM_LAYOUT_STREAM_VARIANT);
    plm_shape s = base->shape;
    double width_scale = 1.0 + jitter(&rng, 0.06), length_scale = 1.0 + jitter(&rng, 0.04);
    s.length *= length_scale;
    s.calamus_length *= length_scale;
    for (int side = 0; side < 2; ++side)
        for (int i = 0; i < s.width[side].count; ++i)
            s.width[side].width[i] *= width_scale;
    s.bend_in_plane += jitter(&rng, plm_radians(2.0));
    s.bend_out_of_plane += jitter(&rng, plm_radians(2.0));
    s.twist += jitter(&rng, plm_radians(2.0));
    s.curl += jitter(&rng, plm_radians(1.5));
    double angle = jitter(&rng, plm_radians(2.0));
    for (int side = 0; side < 2; ++side) {
        s.barb_angle_base[side] += angle;
        s.barb_angle_tip[side] += angle;
    }
    /* Its own draws (drawn splits, barb ends, fray) from a seed of its own. */
    s.seed = plm_hash64(seed, (uint64_t)variant, base->shape.seed) & 0x7fffffffu;
    /* Listed splits move along the vane and change depth; they stay in the pennaceous part. */
    for (int i = 0; i < s.split_count; ++i) {
        plm_split *sp = &s.splits[i];
        double lo = s.plumulaceous + 0.02;
        sp->position = lo + (0.98 - lo) * plm_rng_uniform(&rng);
        sp->depth = plm_clamp(sp->depth * (1.0 + jitter(&rng, 0.3)), 0.05, 1.0);
        sp->side = plm_rng_uniform(&rng) < 0.5;
    }
    plm_species v = *base;
    v.shape = s;
    /* A jitter that breaks a constraint (rare: presets near a limit) keeps the species' shape. */
    if (plm_species_validate(&v, NULL, NULL) == PLM_OK)
        *shape = s;
    pigment->seed = plm_hash64(seed, (uint64_t)variant, pigment->seed) & 0x7fffffffu;
}

void plm_layout_extents_free(plm_layout_extent *e, int n)
{
    for (int i = 0; i < n && e; ++i) {
        plm_mesh_free(&e[i].mesh[0]);
        plm_mesh_free(&e[i].mesh[1]);
        free(e[i].hull);
        free(e[i].top);
    }
    free(e);
}

static int compare_point(const void *a, const void *b)
{
    const double *p = a, *q = b;
    return p[0] < q[0] ? -1 : p[0] > q[0] ? 1 : (p[1] > q[1]) - (p[1] < q[1]);
}

static double turn(const double *o, const double *a, const double *b)
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* Convex hull of n points (Andrew's monotone chain) of their first two
 * coordinates into h, which has room for 2n; returns its size. Sorts p. */
static int convex_hull(double (*p)[3], int n, double (*h)[3])
{
    qsort(p, (size_t)n, sizeof *p, compare_point);
    int k = 0;
    for (int i = 0; i < n; ++i) {
        while (k >= 2 && turn(h[k - 2], h[k - 1], p[i]) <= 0.0)
            --k;
        memcpy(h[k++], p[i], sizeof *p);
    }
    for (int i = n - 2, lower = k + 1; i >= 0; --i) {
        while (k >= lower && turn(h[k - 2], h[k - 1], p[i]) <= 0.0)
            --k;
        memcpy(h[k++], p[i], sizeof *p);
    }
    return k > 1 ? k - 1 : k;
}

static plm_result hull_of(plm_layout_extent *e, plm_error *err)
{
    int n = e->mesh[0].vertex_count + e->mesh[1].vertex_count;
    double(*p)[3] = malloc(sizeof *p * (size_t)n);
    e->hull = malloc(sizeof *e->hull * 2 * (size_t)n);
    if (!p || !e->hull) {
        free(p);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a layout's prototype extents");
    }
    int k = 0;
    e->w_min = INFINITY;
    for (int m = 0; m < 2; ++m)
        for (int i = 0; i < e->mesh[m].vertex_count; ++i, ++k) {
            const float *v = e->mesh[m].positions + 3 * i;
            p[k][0] = v[1];
            p[k][1] = v[2];
            p[k][2] = (double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2];
            e->w_min = fmin(e->w_min, p[k][2]);
        }
    e->hull_count = convex_hull(p, n, e->hull);
    free(p);
    return PLM_OK;
}

/* Raises the height map to the triangle a, b, c over the cells whose centres it covers. */
static void raster_triangle(plm_layout_extent *e, const float *a, const float *b, const float *c)
{
    double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    if (fabs(det) < 1e-12)
        return;
    double lo_x = fmin(a[0], fmin(b[0], c[0])), hi_x = fmax(a[0], fmax(b[0], c[0]));
    double lo_y = fmin(a[1], fmin(b[1], c[1])), hi_y = fmax(a[1], fmax(b[1], c[1]));
    int i0 = (int)fmax(0.0, ceil((lo_x - e->x0) / e->dx - 0.5)), i1 = (int)fmin(e->nx - 1, floor((hi_x - e->x0) / e->dx - 0.5));
    int j0 = (int)fmax(0.0, ceil((lo_y - e->y0) / e->dy - 0.5)), j1 = (int)fmin(e->ny - 1, floor((hi_y - e->y0) / e->dy - 0.5));
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
            double x = e->x0 + (i + 0.5) * e->dx, y = e->y0 + (j + 0.5) * e->dy;
            double u = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det;
            double v = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det;
            if (u < -1e-9 || v < -1e-9 || u + v > 1.0 + 1e-9)
                continue;
            float z = (float)(a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2]));
            float *t = &e->top[j * e->nx + i];
            *t = fmaxf(*t, z);
        }
}

/* The vane's height map (cells about a barb spacing's size: a quarter of a
 * cage column across, an eighth of a row along) and bounding sphere. */
static plm_result heights_of(plm_layout_extent *e, plm_error *err)
{
    const plm_mesh *m = &e->mesh[0];
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < m->vertex_count; ++i)
        for (int c = 0; c < 3; ++c) {
            lo[c] = fmin(lo[c], m->positions[3 * i + c]);
            hi[c] = fmax(hi[c], m->positions[3 * i + c]);
        }
    e->nx = 4 * PLM_VANE_COLUMNS;
    e->ny = 4 * PLM_VANE_ROWS;
    e->x0 = lo[0], e->y0 = lo[1];
    e->dx = fmax(hi[0] - lo[0], 1e-9) / e->nx;
    e->dy = fmax(hi[1] - lo[1], 1e-9) / e->ny;
    e->centre = v3(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
    e->radius = 0.5 * v3_length(v3(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));
    e->top = malloc(sizeof(float) * (size_t)(e->nx * e->ny));
    if (!e->top)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a layout's prototype extents");
    for (int i = 0; i < e->nx * e->ny; ++i)
        e->top[i] = -INFINITY;
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *v = m->indices + 3 * t;
        raster_triangle(e, m->positions + 3 * v[0], m->positions + 3 * v[1], m->positions + 3 * v[2]);
    }
    return PLM_OK;
}

double plm_layout_height(const plm_layout_extent *e, double x, double y)
{
    double fi = (x - e->x0) / e->dx, fj = (y - e->y0) / e->dy;
    if (!(fi >= 0.0 && fj >= 0.0 && fi < e->nx && fj < e->ny))
        return -INFINITY;
    return e->top[(int)fj * e->nx + (int)fi];
}

static plm_result extent_of(const plm_layout_prototype *pr, plm_layout_extent *e, plm_error *err)
{
    plm_outline o;
    plm_result rc = plm_outline_init(&o, &pr->shape, NULL, err);
    if (rc == PLM_OK)
        rc = plm_vane_mesh(&o, 1, &e->mesh[0], err);
    if (rc == PLM_OK)
        rc = plm_rachis_mesh(&o, 1, &e->mesh[1], err);
    if (rc == PLM_OK)
        rc = hull_of(e, err);
    if (rc == PLM_OK)
        rc = heights_of(e, err);
    e->length = pr->shape.length;
    e->rachis_radius = 0.5 * pr->shape.rachis_base_width;
    return rc;
}

plm_result plm_layout_make_prototypes(const plm_species *const *species, int species_count, int variants, uint64_t seed,
                                      plm_layout *out, plm_layout_extent **extents, plm_error *err)
{
    int n = species_count * variants;
    out->prototypes = calloc((size_t)n, sizeof *out->prototypes);
    *extents = calloc((size_t)n, sizeof **extents);
    if (!out->prototypes || !*extents)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for %d layout prototypes", n);
    out->prototype_count = n;
    for (int s = 0; s < species_count; ++s)
        for (int v = 0; v < variants; ++v) {
            plm_layout_prototype *pr = &out->prototypes[s * variants + v];
            pr->species = s;
            pr->variant = v;
            plm_species_variant(species[s], v, plm_hash64(seed, (uint64_t)s, 0), &pr->shape, &pr->pigment);
            plm_result rc = extent_of(pr, &(*extents)[s * variants + v], err);
            if (rc != PLM_OK)
                return rc;
        }
    return PLM_OK;
}

/* ---- Per-feather variation ---- */

plm_layout_ranges plm_layout_ranges_of(const plm_layout_variation *v)
{
    plm_layout_ranges r = {0.0, 0.0, 0.0, 0.0};
    if (v->none)
        return r;
    r.scale = v->scale > 0.0 ? v->scale : 0.1;
    r.yaw = v->yaw > 0.0 ? v->yaw : plm_radians(6.0);
    r.lift = v->lift > 0.0 ? v->lift : plm_radians(3.0);
    r.tint = v->tint > 0.0 ? v->tint : 0.1;
    return r;
}

void plm_layout_draw_variation(plm_rng *rng, const plm_layout_ranges *v, plm_layout_instance *in)
{
    in->scale = 1.0 + jitter(rng, v->scale);
    in->yaw = jitter(rng, v->yaw);
    in->lift = v->lift * plm_rng_uniform(rng);
    /* Mostly a shared brightness, a quarter of it per channel (slight hue shifts). */
    double b = 1.0 - 0.75 * v->tint * plm_rng_uniform(rng);
    in->tint.r = b * (1.0 - 0.25 * v->tint * plm_rng_uniform(rng));
    in->tint.g = b * (1.0 - 0.25 * v->tint * plm_rng_uniform(rng));
    in->tint.b = b * (1.0 - 0.25 * v->tint * plm_rng_uniform(rng));
}

void plm_layout_set_matrix(plm_layout_instance *in, vec3 x, vec3 t, vec3 z, vec3 origin, double scale)
{
    vec3 col[3] = {x, t, z};
    double o[3] = {origin.x, origin.y, origin.z};
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            double v[3] = {col[c].x, col[c].y, col[c].z};
            in->m[r][c] = scale * v[r];
        }
        in->m[r][3] = o[r];
    }
}

vec3 plm_layout_apply(const plm_layout_instance *in, const float *p)
{
    return v3(in->m[0][0] * p[0] + in->m[0][1] * p[1] + in->m[0][2] * p[2] + in->m[0][3],
              in->m[1][0] * p[0] + in->m[1][1] * p[1] + in->m[1][2] * p[2] + in->m[1][3],
              in->m[2][0] * p[0] + in->m[2][1] * p[1] + in->m[2][2] * p[2] + in->m[2][3]);
}
