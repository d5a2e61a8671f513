/* Layouts (generate/layout.h): pelts, feather balls and wings as instance
 * lists. The reasoning behind shingling and the wing's rows is in
 * docs/layouts.md. */
#include "generate/layout.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/rng.h"
#include "generate/geometry.h"
#include "generate/outline.h"

/* Random streams: one per purpose, so that changing one draw does not shift another. */
enum { STREAM_PLACE = 1, STREAM_FEATHER = 2, STREAM_VARIANT = 3 };

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
    plm_rng_seed(&rng, plm_hash64(seed, (uint64_t)variant, 0x7a41u), STREAM_VARIANT);
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
    /* Splits move along the vane and change depth; they stay in the pennaceous part. */
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

/* What placement needs to know of a prototype: its meshes (feather frame,
 * mm) and its size. The meshes are the level-1 limit surfaces: their
 * vertices lie on the same surfaces as any finer level's. */
typedef struct extent {
    plm_mesh mesh[2];  /* vane, rachis */
    double (*hull)[3]; /* convex hull of the vertices' (y, z): all a tilt about x can bring lowest;
                          third, the squared distance from the origin of a vertex there */
    int hull_count;
    double w_min;      /* the smallest squared distance of any vertex from the origin */
    double length, rachis_radius;
} extent;

static void extents_free(extent *e, int n)
{
    for (int i = 0; i < n && e; ++i) {
        plm_mesh_free(&e[i].mesh[0]);
        plm_mesh_free(&e[i].mesh[1]);
        free(e[i].hull);
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

static plm_result hull_of(extent *e, plm_error *err)
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

static plm_result extent_of(const plm_layout_prototype *pr, extent *e, plm_error *err)
{
    plm_outline o;
    plm_result rc = plm_outline_init(&o, &pr->shape, NULL, err);
    if (rc == PLM_OK)
        rc = plm_vane_mesh(&o, 1, &e->mesh[0], err);
    if (rc == PLM_OK)
        rc = plm_rachis_mesh(&o, 1, &e->mesh[1], err);
    if (rc == PLM_OK)
        rc = hull_of(e, err);
    e->length = pr->shape.length;
    e->rachis_radius = 0.5 * pr->shape.rachis_base_width;
    return rc;
}

/* The prototypes: `variants` per species, and their extents. */
static plm_result make_prototypes(const plm_species *const *species, int species_count, int variants, uint64_t seed,
                                  plm_layout *out, extent **extents, plm_error *err)
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

typedef struct variation {
    double scale, yaw, lift, tint;
} variation;

static variation variation_of(const plm_layout_variation *v)
{
    variation r = {0.0, 0.0, 0.0, 0.0};
    if (v->none)
        return r;
    r.scale = v->scale > 0.0 ? v->scale : 0.1;
    r.yaw = v->yaw > 0.0 ? v->yaw : plm_radians(6.0);
    r.lift = v->lift > 0.0 ? v->lift : plm_radians(3.0);
    r.tint = v->tint > 0.0 ? v->tint : 0.1;
    return r;
}

/* Draws a feather's variation (scale, yaw, lift, tint) from its own stream. */
static void draw_variation(plm_rng *rng, const variation *v, plm_layout_instance *in)
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

/* The instance matrix for a feather frame (X, T, Z) at `origin`, `scale` layout units per mm. */
static void set_matrix(plm_layout_instance *in, vec3 x, vec3 t, vec3 z, vec3 origin, double scale)
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

static vec3 apply(const plm_layout_instance *in, const float *p)
{
    return v3(in->m[0][0] * p[0] + in->m[0][1] * p[1] + in->m[0][2] * p[2] + in->m[0][3],
              in->m[1][0] * p[0] + in->m[1][1] * p[1] + in->m[1][2] * p[2] + in->m[1][3],
              in->m[2][0] * p[0] + in->m[2][1] * p[1] + in->m[2][2] * p[2] + in->m[2][3]);
}

static vec3 rotate_about(vec3 v, vec3 k, double angle)
{
    double c = cos(angle), s = sin(angle);
    return v3_add(v3_add(v3_scale(v, c), v3_scale(v3_cross(k, v), s)), v3_scale(k, v3_dot(k, v) * (1.0 - c)));
}

/* Picks an index by weight with u in [0, 1). */
static int pick_weighted(const double *cdf, int n, double u)
{
    int i = 0;
    while (i + 1 < n && u * cdf[n - 1] >= cdf[i])
        ++i;
    return i;
}

/* ---- Surfaces ---- */

typedef struct surface {
    const plm_surface *s;
    double width, height, radius;
    double area;
    double *cdf; /* mesh: cumulative triangle areas */
} surface;

typedef struct surface_point {
    vec3 p, n, flow; /* flow: unit, in the tangent plane */
} surface_point;

static vec3 mesh_vertex(const float *a, uint32_t i) { return v3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); }

static plm_result surface_init(surface *sf, const plm_surface *s, plm_error *err)
{
    memset(sf, 0, sizeof *sf);
    sf->s = s;
    sf->width = s->width > 0.0 ? s->width : 1.0;
    sf->height = s->height > 0.0 ? s->height : 1.0;
    sf->radius = s->radius > 0.0 ? s->radius : 1.0;
    switch (s->kind) {
    case PLM_SURFACE_PLANE:
        sf->area = sf->width * sf->height;
        return PLM_OK;
    case PLM_SURFACE_SPHERE:
        sf->area = 4.0 * PLM_PI * sf->radius * sf->radius;
        return PLM_OK;
    case PLM_SURFACE_MESH: break;
    default: return plm_fail(err, PLM_ERR_INVALID, "layout surface: unknown kind %d", (int)s->kind);
    }
    const plm_mesh *m = s->mesh;
    if (!m || m->triangle_count <= 0)
        return plm_fail(err, PLM_ERR_INVALID, "layout surface: the mesh has no triangles");
    sf->cdf = malloc(sizeof(double) * (size_t)m->triangle_count);
    if (!sf->cdf)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for the surface's %d triangles", m->triangle_count);
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *v = m->indices + 3 * t;
        vec3 a = mesh_vertex(m->positions, v[0]), b = mesh_vertex(m->positions, v[1]),
             c = mesh_vertex(m->positions, v[2]);
        sf->area += 0.5 * v3_length(v3_cross(v3_sub(b, a), v3_sub(c, a)));
        sf->cdf[t] = sf->area;
    }
    if (!(sf->area > 0.0))
        return plm_fail(err, PLM_ERR_INVALID, "layout surface: the mesh has zero area");
    return PLM_OK;
}

/* The axis projected onto the tangent plane; any tangent where it is parallel to n. */
static vec3 tangent_flow(vec3 axis, vec3 n)
{
    vec3 f = v3_sub(axis, v3_scale(n, v3_dot(axis, n)));
    if (v3_length(f) < 1e-6 * (v3_length(axis) + 1e-300))
        return frame_from_z(n).x;
    return v3_normalize(f);
}

static surface_point surface_sample(const surface *sf, vec3 axis, double u0, double u1, double u2)
{
    surface_point sp;
    switch (sf->s->kind) {
    case PLM_SURFACE_PLANE:
        sp.p = v3((u0 - 0.5) * sf->width, (u1 - 0.5) * sf->height, 0.0);
        sp.n = v3(0, 0, 1);
        break;
    case PLM_SURFACE_SPHERE: {
        double z = 1.0 - 2.0 * u0, r = plm_safe_sqrt(1.0 - z * z), phi = PLM_TWO_PI * u1;
        sp.n = v3(r * cos(phi), r * sin(phi), z);
        sp.p = v3_scale(sp.n, sf->radius);
        break;
    }
    default: {
        const plm_mesh *m = sf->s->mesh;
        double target = u0 * sf->area;
        int lo = 0, hi = m->triangle_count - 1;
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (sf->cdf[mid] <= target)
                lo = mid + 1;
            else
                hi = mid;
        }
        const uint32_t *v = m->indices + 3 * lo;
        double su = sqrt(u1), b0 = 1.0 - su, b1 = su * (1.0 - u2), b2 = su * u2;
        vec3 a = mesh_vertex(m->positions, v[0]), b = mesh_vertex(m->positions, v[1]),
             c = mesh_vertex(m->positions, v[2]);
        sp.p = v3_add(v3_add(v3_scale(a, b0), v3_scale(b, b1)), v3_scale(c, b2));
        vec3 face = v3_normalize(v3_cross(v3_sub(b, a), v3_sub(c, a)));
        sp.n = face;
        if (m->normals) {
            vec3 n = v3_add(v3_add(v3_scale(mesh_vertex(m->normals, v[0]), b0),
                                   v3_scale(mesh_vertex(m->normals, v[1]), b1)),
                            v3_scale(mesh_vertex(m->normals, v[2]), b2));
            if (v3_length(n) > 1e-9 && v3_dot(n, face) > 0.0)
                sp.n = v3_normalize(n);
        }
        if (m->tangents)
            axis = v3_add(v3_add(v3_scale(mesh_vertex(m->tangents, v[0]), b0),
                                 v3_scale(mesh_vertex(m->tangents, v[1]), b1)),
                          v3_scale(mesh_vertex(m->tangents, v[2]), b2));
        break;
    }
    }
    sp.flow = tangent_flow(axis, sp.n);
    return sp;
}

/* Height of q above the surface near the root: exact for plane and sphere,
 * above the root's tangent plane for a mesh. */
static double surface_height(const surface *sf, const surface_point *root, vec3 q)
{
    if (sf->s->kind == PLM_SURFACE_SPHERE)
        return v3_length(q) - sf->radius;
    return v3_dot(v3_sub(q, root->p), root->n);
}

/* Whether every vertex of the placed feather stands at least `margin` above
 * the sphere. A vertex (x, y, z) lies at |q|^2 = a^2 + 2 a s h + s^2 w from
 * the centre, with a = |origin| = R + r s, h = y sin(alpha) + z cos(alpha)
 * and w = x^2 + y^2 + z^2. The hull's lowest h with the smallest w bounds
 * the lowest vertex from below, the hull's own vertices from above: only
 * when margin lies between the two are all vertices checked. The answer is
 * the full check's (docs/layouts.md). */
static int clear_of_sphere(const surface *sf, const extent *e, const plm_layout_instance *in, double scale,
                           double alpha, double margin)
{
    double a = sf->radius + e->rachis_radius * scale, sa = sin(alpha), ca = cos(alpha), h_min = INFINITY;
    double upper = INFINITY, need = (sf->radius + margin) * (sf->radius + margin);
    for (int i = 0; i < e->hull_count; ++i) {
        double h = e->hull[i][0] * sa + e->hull[i][1] * ca;
        h_min = fmin(h_min, h);
        upper = fmin(upper, a * a + 2.0 * a * scale * h + scale * scale * e->hull[i][2]);
    }
    if (a * a + 2.0 * a * scale * h_min + scale * scale * e->w_min >= need)
        return 1;
    if (upper < need)
        return 0;
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < e->mesh[k].vertex_count; ++i)
            if (surface_height(sf, NULL, apply(in, e->mesh[k].positions + 3 * i)) < margin)
                return 0;
    return 1;
}

/* ---- Blue noise: dart throwing with a hashed grid ---- */

typedef struct dart_grid {
    double cell;
    int *head, *next;
    uint64_t mask;
    const surface_point *points;
} dart_grid;

static uint64_t cell_key(const dart_grid *g, vec3 p, int dx, int dy, int dz)
{
    int64_t i = (int64_t)floor(p.x / g->cell) + dx, j = (int64_t)floor(p.y / g->cell) + dy,
            k = (int64_t)floor(p.z / g->cell) + dz;
    return plm_hash64((uint64_t)i, (uint64_t)j, (uint64_t)k) & g->mask;
}

static int too_close(const dart_grid *g, vec3 p, double r)
{
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz)
                for (int i = g->head[cell_key(g, p, dx, dy, dz)]; i >= 0; i = g->next[i])
                    if (v3_length(v3_sub(g->points[i].p, p)) < r)
                        return 1;
    return 0;
}

/* `count` points over the surface, no two closer than a radius that starts at
 * 0.75 of the mean spacing and shrinks only when darts keep missing. */
static plm_result blue_noise(const surface *sf, vec3 axis, int count, uint64_t seed, surface_point *out,
                             plm_error *err)
{
    uint64_t size = 1;
    while (size < 2 * (uint64_t)count)
        size <<= 1;
    dart_grid g = {0};
    g.head = malloc(sizeof(int) * size);
    g.next = malloc(sizeof(int) * (size_t)count);
    if (!g.head || !g.next) {
        free(g.head);
        free(g.next);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory placing %d feathers", count);
    }
    memset(g.head, 0xff, sizeof(int) * size);
    g.mask = size - 1;
    g.points = out;
    double r = 0.75 * sqrt(sf->area / count);
    g.cell = r;
    plm_rng rng;
    plm_rng_seed(&rng, seed, STREAM_PLACE);
    int placed = 0, misses = 0;
    while (placed < count) {
        double u0 = plm_rng_uniform(&rng), u1 = plm_rng_uniform(&rng), u2 = plm_rng_uniform(&rng);
        surface_point sp = surface_sample(sf, axis, u0, u1, u2);
        if (too_close(&g, sp.p, r)) {
            if (++misses > 64) {
                r *= 0.97;
                misses = 0;
            }
            continue;
        }
        misses = 0;
        out[placed] = sp;
        uint64_t key = cell_key(&g, sp.p, 0, 0, 0);
        g.next[placed] = g.head[key];
        g.head[key] = placed;
        ++placed;
    }
    free(g.head);
    free(g.next);
    return PLM_OK;
}

/* ---- Pelt ---- */

/* Places one feather at a root: along the flow turned by its yaw, raised by
 * `elevation` plus its lift, then further (in half-degree steps, up to
 * max_elevation) until every point of the prototype is above the surface. */
static void place_on_surface(const surface *sf, const surface_point *root, const extent *e, double scale,
                             double elevation, double max_elevation, plm_layout_instance *in)
{
    vec3 n = root->n;
    vec3 t = rotate_about(root->flow, n, in->yaw);
    vec3 origin = v3_madd(root->p, n, e->rachis_radius * scale);
    double alpha = fmin(elevation + in->lift, max_elevation);
    const double margin = 0.002 * e->length * scale, step = plm_radians(0.5);
    for (;;) {
        vec3 tt = v3_add(v3_scale(t, cos(alpha)), v3_scale(n, sin(alpha)));
        vec3 z = v3_sub(v3_scale(n, cos(alpha)), v3_scale(t, sin(alpha)));
        set_matrix(in, v3_cross(tt, z), tt, z, origin, scale);
        int clear;
        if (sf->s->kind == PLM_SURFACE_SPHERE) {
            clear = clear_of_sphere(sf, e, in, scale, alpha, margin);
        } else {
            /* Above a tangent plane a feather point (x, y, z) stands at
             * scale (r + y sin(alpha) + z cos(alpha)): x plays no part, and
             * the lowest point is a vertex of the (y, z) hull. */
            double lowest = INFINITY;
            for (int i = 0; i < e->hull_count; ++i)
                lowest = fmin(lowest, scale * (e->rachis_radius + e->hull[i][0] * sin(alpha) +
                                               e->hull[i][1] * cos(alpha)));
            clear = lowest >= margin;
        }
        if (clear || alpha >= max_elevation)
            break;
        alpha = fmin(alpha + step, max_elevation);
    }
    in->lift = alpha;
}

typedef struct pelt_setup {
    int count;
    double length;        /* layout units of a scale-1 feather */
    double elevation, max_elevation;
    variation var;
    int variants;
} pelt_setup;

static plm_result pelt(const surface *sf, vec3 axis, const pelt_setup *ps, uint64_t seed,
                       const plm_layout_species *species, int species_count, plm_layout *out, plm_error *err)
{
    const plm_species *list[PLM_WING_ROWS + 8];
    double cdf[PLM_WING_ROWS + 8];
    if (species_count < 1 || species_count > (int)(sizeof list / sizeof list[0]))
        return plm_fail(err, PLM_ERR_INVALID, "a layout takes 1 to %d species, not %d",
                        (int)(sizeof list / sizeof list[0]), species_count);
    for (int s = 0; s < species_count; ++s) {
        if (!species[s].species)
            return plm_fail(err, PLM_ERR_INVALID, "layout species %d is missing", s);
        list[s] = species[s].species;
        cdf[s] = (s ? cdf[s - 1] : 0.0) + (species[s].weight > 0.0 ? species[s].weight : 1.0);
    }
    extent *ext = NULL;
    surface_point *roots = malloc(sizeof *roots * (size_t)ps->count);
    out->instances = calloc((size_t)ps->count, sizeof *out->instances);
    plm_result rc = roots && out->instances ? PLM_OK
                                            : plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for %d feathers",
                                                       ps->count);
    if (rc == PLM_OK)
        rc = make_prototypes(list, species_count, ps->variants, seed, out, &ext, err);
    if (rc == PLM_OK)
        rc = blue_noise(sf, axis, ps->count, seed, roots, err);
    for (int i = 0; rc == PLM_OK && i < ps->count; ++i) {
        plm_layout_instance *in = &out->instances[i];
        plm_rng rng;
        plm_rng_seed(&rng, plm_hash64(seed, (uint64_t)i, 0), STREAM_FEATHER);
        int s = pick_weighted(cdf, species_count, plm_rng_uniform(&rng));
        int v = (int)(plm_rng_uniform(&rng) * ps->variants);
        in->prototype = s * ps->variants + v;
        in->row = s;
        draw_variation(&rng, &ps->var, in);
        const extent *e = &ext[in->prototype];
        place_on_surface(sf, &roots[i], e, in->scale * ps->length / e->length, ps->elevation, ps->max_elevation,
                         in);
    }
    if (rc == PLM_OK)
        out->instance_count = ps->count;
    extents_free(ext, out->prototype_count);
    free(roots);
    return rc;
}

plm_result plm_layout_pelt(const plm_pelt_params *p, const plm_layout_species *species, int species_count,
                           plm_layout *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    surface sf;
    plm_result rc = surface_init(&sf, &p->surface, err);
    double count = p->count > 0 ? p->count : (p->density > 0.0 ? p->density * sf.area : 100.0);
    double overlap = p->overlap > 0.0 ? p->overlap : 2.0 / 3.0;
    if (rc == PLM_OK && !(count >= 1.0 && count <= 1e7))
        rc = plm_fail(err, PLM_ERR_INVALID, "pelt: %.0f feathers is out of range [1, 10^7] (count, or density x "
                      "area %g)", count, sf.area);
    if (rc == PLM_OK && !(overlap < 0.95))
        rc = plm_fail(err, PLM_ERR_INVALID, "pelt: overlap %g is out of range (0, 0.95)", overlap);
    if (rc == PLM_OK && !(p->elevation >= 0.0 && p->elevation < 0.5 * PLM_PI))
        rc = plm_fail(err, PLM_ERR_INVALID, "pelt: elevation %g degrees is out of range [0, 90)",
                      plm_degrees(p->elevation));
    if (rc == PLM_OK) {
        pelt_setup ps;
        ps.count = (int)count;
        /* Shingling: a feather should come out from under the ones behind it
         * at `overlap` of its length. Blue-noise neighbours ahead along the
         * flow sit partly to the side, and a length of 1.25 mean spacings
         * per (1 - overlap) does it (measured by test_layout, docs/layouts.md). */
        double ahead = 1.25 * sqrt(sf.area / ps.count);
        ps.length = p->feather_length > 0.0 ? p->feather_length : ahead / (1.0 - overlap);
        ps.elevation = p->elevation > 0.0 ? p->elevation : plm_radians(8.0);
        ps.max_elevation = plm_radians(80.0);
        ps.var = variation_of(&p->variation);
        ps.variants = p->variants > 0 ? p->variants : 4;
        vec3 axis = v3_length(p->axis) > 0.0 ? p->axis : v3(0, -1, 0);
        rc = pelt(&sf, axis, &ps, p->seed, species, species_count, out, err);
    }
    free(sf.cdf);
    if (rc != PLM_OK)
        plm_layout_free(out);
    return rc;
}

/* A ball is a pelt on a sphere whose feathers stand nearly upright, leaning
 * by up to `spread` in any direction. */
plm_result plm_layout_ball(const plm_ball_params *p, const plm_layout_species *species, int species_count,
                           plm_layout *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    plm_surface s = {.kind = PLM_SURFACE_SPHERE, .radius = p->radius > 0.0 ? p->radius : 1.0};
    surface sf;
    plm_result rc = surface_init(&sf, &s, err);
    double spread = p->spread > 0.0 ? p->spread : plm_radians(10.0);
    if (rc == PLM_OK && !(spread < 0.5 * PLM_PI))
        rc = plm_fail(err, PLM_ERR_INVALID, "ball: spread %g degrees is out of range (0, 90)", plm_degrees(spread));
    if (rc == PLM_OK && !(p->count >= 0 && p->count <= 10000000))
        rc = plm_fail(err, PLM_ERR_INVALID, "ball: count %d is out of range [1, 10^7]", p->count);
    if (rc != PLM_OK)
        return rc;
    pelt_setup ps;
    ps.count = p->count > 0 ? p->count : 496;
    ps.length = p->feather_length > 0.0 ? p->feather_length : 2.0 * sf.radius;
    ps.elevation = 0.5 * PLM_PI - spread;
    ps.max_elevation = 0.5 * PLM_PI;
    ps.var = variation_of(&p->variation);
    ps.var.lift = spread; /* upright .. leaning by spread */
    ps.var.yaw = PLM_PI;  /* leaning any way */
    ps.variants = p->variants > 0 ? p->variants : 4;
    rc = pelt(&sf, v3(0, -1, 0), &ps, p->seed, species, species_count, out, err);
    if (rc != PLM_OK)
        plm_layout_free(out);
    return rc;
}

/* ---- Wing ---- */

const char *const plm_wing_row_names[PLM_WING_ROWS] = {"primary",        "secondary",     "tertial", "greater_covert",
                                                       "median_covert", "lesser_covert", "alula"};

/* The skeleton of the wing at a fold: shoulder, elbow, wrist and hand tip in
 * the wing plane, and the bones' directions. Spread, the bones line up along
 * +x (the hand swept back); folded, the humerus points back, the forearm
 * forward and the hand back again, as a perched bird's wing. */
typedef struct wing_skeleton {
    vec3 joint[4];    /* shoulder, elbow, wrist, hand tip */
    double angle[3];  /* humerus, forearm, hand: radians from +x toward +y (forward) */
    double spread[3]; /* the same bones' angles with the wing spread */
} wing_skeleton;

static vec3 planar(double angle) { return v3(cos(angle), sin(angle), 0.0); }
static double lerp(double a, double b, double t) { return a + (b - a) * t; }

static wing_skeleton skeleton_of(const plm_wing_params *p, double span, double primary)
{
    /* Bone proportions of a typical wing: humerus, forearm, hand about 3 : 4 : 3. */
    static const double share[3] = {0.29, 0.39, 0.32};
    static const double folded[3] = {-60.0, 100.0, -95.0};
    double bones = fmax(span - 0.85 * primary, 0.3 * span);
    wing_skeleton w;
    w.spread[0] = 0.0;
    w.spread[1] = 0.0;
    w.spread[2] = -p->sweep;
    w.joint[0] = v3(0, 0, 0);
    for (int b = 0; b < 3; ++b) {
        w.angle[b] = lerp(w.spread[b], plm_radians(folded[b]), p->fold);
        w.joint[b + 1] = v3_madd(w.joint[b], planar(w.angle[b]), share[b] * bones);
    }
    return w;
}

/* A point a fraction t along bone b, moved `forward` toward the leading edge. */
static vec3 on_bone(const wing_skeleton *w, int b, double t, double forward)
{
    vec3 p = v3_add(v3_scale(w->joint[b], 1.0 - t), v3_scale(w->joint[b + 1], t));
    return v3_madd(p, planar(w->angle[b] + 0.5 * PLM_PI), forward);
}

/* One feather of a row as the wing builds it. */
typedef struct wing_feather {
    int row;
    vec3 root;
    double direction; /* radians in the wing plane */
    double length;    /* layout units */
} wing_feather;

/* Piecewise-linear ramp through (u, value) points. */
static double ramp(const double (*pts)[2], int n, double u)
{
    int k = 0;
    while (k + 2 < n && u > pts[k + 1][0])
        ++k;
    double t = plm_clamp((u - pts[k][0]) / (pts[k + 1][0] - pts[k][0]), 0.0, 1.0);
    return lerp(pts[k][1], pts[k + 1][1], t);
}

/* Direction of a feather: its angle on the spread wing, turned toward the
 * body axis (straight back) as the wing folds. */
static double fold_direction(const plm_wing_params *p, double spread, double folded)
{
    return lerp(spread, plm_radians(folded), p->fold);
}

typedef struct wing_rows {
    wing_feather *f;
    int count, capacity;
    int flight; /* how many flight feathers: they come first, and the rest settle onto them */
} wing_rows;

static void add_feather(wing_rows *w, int row, vec3 root, double direction, double length)
{
    wing_feather *f = &w->f[w->count++];
    f->row = row;
    f->root = root;
    f->direction = direction;
    f->length = length;
}

/* Every feather of the wing in dorsal order, bottom first: primaries from the
 * outermost in (each proximal feather lies over the next distal one), then
 * the secondaries from the wrist in and the tertials; then the greater
 * coverts, the alula (the coverts at the bend of the wing cover its base),
 * and the other covert rows back to front (median, two rows of lesser
 * coverts). Lengths in layout units. */
static void build_wing(const plm_wing_params *p, const wing_skeleton *sk, double chord, double primary, int np,
                       int ns, int nt, wing_rows *w)
{
    /* Primaries lengthen from about the secondaries' length at the wrist to
     * the longest three quarters of the way out; the outermost is shorter. */
    const double primary_ramp[4][2] = {{0.0, 1.05 * chord}, {0.75, primary}, {0.9, 0.98 * primary},
                                       {1.0, 0.86 * primary}};
    for (int i = np - 1; i >= 0; --i) {
        double u = np > 1 ? (double)i / (np - 1) : 1.0;
        add_feather(w, PLM_WING_PRIMARY, on_bone(sk, 2, 0.12 + 0.88 * u, 0.0),
                    fold_direction(p, sk->spread[2] - plm_radians(lerp(78.0, 12.0, u)), -88.0),
                    ramp(primary_ramp, 4, u));
    }
    for (int j = 0; j < ns; ++j) {
        double u = ns > 1 ? (double)j / (ns - 1) : 0.0;
        add_feather(w, PLM_WING_SECONDARY, on_bone(sk, 1, 1.0 - 0.95 * u, 0.0),
                    fold_direction(p, sk->spread[1] - plm_radians(lerp(82.0, 100.0, u)), -91.0),
                    chord * (1.0 - 0.08 * u));
    }
    for (int k = 0; k < nt; ++k) {
        double u = nt > 1 ? (double)k / (nt - 1) : 0.0;
        add_feather(w, PLM_WING_TERTIAL, on_bone(sk, 0, 0.97 - 0.25 * u, 0.0),
                    fold_direction(p, sk->spread[0] - plm_radians(lerp(102.0, 112.0, u)), -95.0),
                    chord * (0.8 - 0.2 * u));
    }
    /* Greater coverts over the bases of every flight feather (the primary
     * coverts among them), in the same order. */
    w->flight = w->count;
    for (int i = 0; i < w->flight - nt; ++i) {
        const wing_feather *r = &w->f[i];
        int bone = r->row == PLM_WING_PRIMARY ? 2 : 1;
        vec3 root = v3_madd(r->root, planar(sk->angle[bone] + 0.5 * PLM_PI), 0.04 * chord);
        add_feather(w, PLM_WING_GREATER_COVERT, root, r->direction,
                    (r->row == PLM_WING_PRIMARY ? 0.3 : 0.42) * r->length);
    }
    /* The alula at the bend of the wing, on the primary coverts' bases along
     * the hand's leading edge: the longest, on top, along it, the shorter
     * ones below fanning a little back over the coverts. */
    for (int a = 2; a >= 0; --a)
        add_feather(w, PLM_WING_ALULA, on_bone(sk, 2, 0.04 + 0.02 * a, 0.015 * chord),
                    fold_direction(p, sk->spread[2] - plm_radians(4.0 * a), -80.0), (0.3 - 0.04 * a) * chord);
    /* Median coverts over the secondaries' coverts, lesser coverts toward the leading edge. */
    for (int j = 0; j < ns; ++j) {
        double u = ns > 1 ? (double)j / (ns - 1) : 0.0;
        add_feather(w, PLM_WING_MEDIAN_COVERT, on_bone(sk, 1, 1.0 - 0.95 * u, 0.14 * chord),
                    fold_direction(p, sk->spread[1] - plm_radians(lerp(80.0, 100.0, u)), -91.0), 0.22 * chord);
    }
    for (int sub = 0; sub < 2; ++sub) {
        int n = 2 * (ns + nt);
        for (int j = 0; j < n; ++j) {
            /* Along forearm and humerus from the wrist in, the front row
             * offset by half a spacing to lie over the back row's gaps. */
            double u = (j + 0.5 * sub) / (n - 1), along = u * 1.6;
            int bone = along < 1.0 ? 1 : 0;
            double t = bone == 1 ? 1.0 - along : 2.0 - along;
            add_feather(w, PLM_WING_LESSER_COVERT, on_bone(sk, bone, plm_clamp(t, 0.05, 1.0), (0.19 + 0.06 * sub) * chord),
                        fold_direction(p, sk->spread[bone] - plm_radians(lerp(75.0, 110.0, u)), -92.0),
                        (0.13 - 0.02 * sub) * chord);
        }
    }
}

/* A height field over the wing plane: the highest z of what lies beneath. */
typedef struct height_grid {
    double x0, y0, cell;
    int nx, ny;
    double *z;
} height_grid;

/* Visits the grid cells whose centres lie in the triangle, with the
 * triangle's height there. mode 0 raises the grid to it; mode 1 returns how
 * far the triangle must rise to clear the grid. */
static double raster(height_grid *g, vec3 a, vec3 b, vec3 c, int mode)
{
    double need = -INFINITY;
    double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (fabs(det) < 1e-300)
        return need;
    int i0 = (int)floor((fmin(a.x, fmin(b.x, c.x)) - g->x0) / g->cell), i1 = (int)ceil((fmax(a.x, fmax(b.x, c.x)) - g->x0) / g->cell);
    int j0 = (int)floor((fmin(a.y, fmin(b.y, c.y)) - g->y0) / g->cell), j1 = (int)ceil((fmax(a.y, fmax(b.y, c.y)) - g->y0) / g->cell);
    for (int j = j0 < 0 ? 0 : j0; j <= j1 && j < g->ny; ++j)
        for (int i = i0 < 0 ? 0 : i0; i <= i1 && i < g->nx; ++i) {
            double x = g->x0 + (i + 0.5) * g->cell, y = g->y0 + (j + 0.5) * g->cell;
            double l1 = ((x - a.x) * (c.y - a.y) - (c.x - a.x) * (y - a.y)) / det;
            double l2 = ((b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y)) / det;
            if (l1 < 0.0 || l2 < 0.0 || l1 + l2 > 1.0)
                continue;
            double z = a.z + l1 * (b.z - a.z) + l2 * (c.z - a.z);
            double *cellz = &g->z[(size_t)j * g->nx + i];
            if (mode == 0)
                *cellz = fmax(*cellz, z);
            else
                need = fmax(need, *cellz - z);
        }
    return need;
}

static double raster_instance(height_grid *g, const plm_layout_instance *in, const extent *e, int mode)
{
    double need = -INFINITY;
    for (int k = 0; k < 2; ++k) {
        const plm_mesh *m = &e->mesh[k];
        for (int t = 0; t < m->triangle_count; ++t) {
            const uint32_t *v = m->indices + 3 * t;
            vec3 a = apply(in, m->positions + 3 * v[0]), b = apply(in, m->positions + 3 * v[1]),
                 c = apply(in, m->positions + 3 * v[2]);
            need = fmax(need, raster(g, a, b, c, mode));
        }
    }
    return need;
}

/* The instance pitched by `angle` about its feather frame's x axis at the
 * root: the tip rises for positive angles. */
static void pitch(plm_layout_instance *in, double angle)
{
    double c = cos(angle), s = sin(angle);
    for (int r = 0; r < 3; ++r) {
        double t = in->m[r][1], z = in->m[r][2];
        in->m[r][1] = c * t + s * z;
        in->m[r][2] = c * z - s * t;
    }
}

/* Settles a feather onto what lies beneath it. Pitched about its root in
 * whole degrees, each time raised just `clearance` clear of the height field
 * (never below where it started), it keeps the pitch that brings the middle
 * of its rachis lowest, as a weight settles: onto two contacts, near its base
 * and further along, instead of balancing on its highest contact with the
 * rest in the air. Pitches at which it touches nothing are not resting; a
 * feather touching nothing stays flat. The range keeps coverts lying along
 * the wing: steeper, a row's bases would stand up off it like a comb. */
#define WING_PITCH_DOWN 8
#define WING_PITCH_UP 10

static void settle(height_grid *g, plm_layout_instance *in, const extent *e, double clearance)
{
    const float middle[3] = {0.0f, (float)(0.5 * e->length), 0.0f};
    plm_layout_instance flat = *in;
    double lowest = INFINITY;
    for (int degrees = -WING_PITCH_DOWN; degrees <= WING_PITCH_UP; ++degrees) {
        plm_layout_instance t = flat;
        pitch(&t, plm_radians(degrees));
        double need = raster_instance(g, &t, e, 1);
        if (need == -INFINITY && degrees != 0)
            continue;
        t.m[2][3] += fmax(need, 0.0) + clearance;
        double z = apply(&t, middle).z;
        if (z < lowest) {
            lowest = z;
            t.lift = plm_radians(degrees);
            *in = t;
        }
    }
}

/* Roll of every wing feather about its rachis, raising its distal (leading)
 * vane: where neighbours overlap, the proximal one's raised vane lies over
 * the distal one's lowered vane, as on a real wing. */
#define WING_ROLL_DEGREES 10.0

plm_result plm_layout_wing(const plm_wing_params *p, const plm_species *const *rows, plm_layout *out,
                           plm_error *err)
{
    memset(out, 0, sizeof *out);
    if (!rows || !rows[PLM_WING_PRIMARY] || !rows[PLM_WING_SECONDARY])
        return plm_fail(err, PLM_ERR_INVALID, "wing: the primary and secondary rows need a species");
    int np = p->primaries ? p->primaries : 10, ns = p->secondaries ? p->secondaries : 12,
        nt = p->tertials ? p->tertials : 3, variants = p->variants > 0 ? p->variants : 3;
    double span = p->span > 0.0 ? p->span : 1.0, chord = p->chord > 0.0 ? p->chord : 0.3 * span;
    if (np < 2 || np > 12)
        return plm_fail(err, PLM_ERR_INVALID, "wing: primaries %d is out of range [2, 12]", np);
    if (ns < 2 || ns > 24)
        return plm_fail(err, PLM_ERR_INVALID, "wing: secondaries %d is out of range [2, 24]", ns);
    if (nt < 1 || nt > 6)
        return plm_fail(err, PLM_ERR_INVALID, "wing: tertials %d is out of range [1, 6]", nt);
    if (!(p->fold >= 0.0 && p->fold <= 1.0))
        return plm_fail(err, PLM_ERR_INVALID, "wing: fold %g is out of range [0, 1]", p->fold);
    if (!(p->sweep >= 0.0 && p->sweep <= plm_radians(45.0)))
        return plm_fail(err, PLM_ERR_INVALID, "wing: sweep %g degrees is out of range [0, 45]", plm_degrees(p->sweep));
    if (!(chord <= span))
        return plm_fail(err, PLM_ERR_INVALID, "wing: chord %g is out of range (0, span %g]", chord, span);
    const plm_species *list[PLM_WING_ROWS];
    for (int r = 0; r < PLM_WING_ROWS; ++r)
        list[r] = rows[r] ? rows[r] : rows[PLM_WING_SECONDARY];

    double primary = 1.4 * chord;
    wing_skeleton sk = skeleton_of(p, span, primary);
    wing_rows w = {0};
    w.capacity = np + 2 * ns + nt + (np + ns) + 4 * (ns + nt) + 3;
    w.f = malloc(sizeof *w.f * (size_t)w.capacity);
    out->instances = calloc((size_t)w.capacity, sizeof *out->instances);
    extent *ext = NULL;
    height_grid g = {0};
    plm_result rc = w.f && out->instances ? PLM_OK : plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a wing");
    if (rc == PLM_OK)
        rc = make_prototypes(list, PLM_WING_ROWS, variants, p->seed, out, &ext, err);
    if (rc == PLM_OK) {
        build_wing(p, &sk, chord, primary, np, ns, nt, &w);
        /* The height field covers every root with a flight feather's length around it. */
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int i = 0; i < w.count; ++i) {
            lo[0] = fmin(lo[0], w.f[i].root.x - primary);
            lo[1] = fmin(lo[1], w.f[i].root.y - primary);
            hi[0] = fmax(hi[0], w.f[i].root.x + primary);
            hi[1] = fmax(hi[1], w.f[i].root.y + primary);
        }
        g.cell = chord / 80.0;
        g.x0 = lo[0];
        g.y0 = lo[1];
        g.nx = (int)ceil((hi[0] - lo[0]) / g.cell);
        g.ny = (int)ceil((hi[1] - lo[1]) / g.cell);
        g.z = malloc(sizeof(double) * (size_t)g.nx * (size_t)g.ny);
        if (!g.z)
            rc = plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a wing's height field");
        for (size_t i = 0; g.z && i < (size_t)g.nx * (size_t)g.ny; ++i)
            g.z[i] = -INFINITY;
    }
    variation var = variation_of(&p->variation);
    /* The rows' sizes and directions are the wing's shape: variation stays small. */
    var.scale *= 0.3;
    var.yaw *= 0.3;
    double roll = plm_radians(WING_ROLL_DEGREES);
    for (int i = 0; rc == PLM_OK && i < w.count; ++i) {
        const wing_feather *f = &w.f[i];
        plm_layout_instance *in = &out->instances[i];
        plm_rng rng;
        plm_rng_seed(&rng, plm_hash64(p->seed, (uint64_t)i, 1), STREAM_FEATHER);
        int v = (int)(plm_rng_uniform(&rng) * variants);
        in->prototype = f->row * variants + v;
        in->row = f->row;
        in->order = i;
        draw_variation(&rng, &var, in);
        in->lift = 0.0;
        const extent *e = &ext[in->prototype];
        vec3 t = planar(f->direction + in->yaw), up = v3(0, 0, 1), x0 = v3_cross(t, up);
        vec3 x = v3_sub(v3_scale(x0, cos(roll)), v3_scale(up, sin(roll)));
        vec3 z = v3_add(v3_scale(x0, sin(roll)), v3_scale(up, cos(roll)));
        /* Folding stacks the flight feathers, each a little above the ones
         * before, so that they overlap in order; the coverts and the alula
         * start from the wing plane and settle onto what lies beneath. */
        double stack = i < w.flight ? p->fold * i * 0.002 * chord : 0.0;
        vec3 root = v3_madd(f->root, up, stack);
        set_matrix(in, x, t, z, root, in->scale * f->length / e->length);
        if (i >= w.flight)
            settle(&g, in, e, 0.004 * chord);
        raster_instance(&g, in, e, 0);
    }
    if (rc == PLM_OK)
        out->instance_count = w.count;
    extents_free(ext, out->prototype_count);
    free(g.z);
    free(w.f);
    if (rc != PLM_OK)
        plm_layout_free(out);
    return rc;
}
