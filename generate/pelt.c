/* Pelts and feather balls (generate/layout.h) as instance lists: blue-noise
 * roots over a surface, each feather laid along the flow. The reasoning
 * behind shingling and clearance is in docs/layouts.md. */
#include "generate/layout.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/rng.h"
#include "generate/layout_parts.h"

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

/* The size of the feathers over the surface, relative to the largest (1):
 * smaller toward the head (against the flow) and toward the surface's edges. */
typedef struct size_field {
    vec3 axis;          /* unit, the flow's axis: the head lies toward -axis */
    double lo, span;    /* the surface's extent along it: dot(p, axis) in [lo, lo + span] */
    double head, edge;  /* the size at the head end, at an edge */
    double edge_width;  /* layout units over which feathers shrink toward an edge */
    double *boundary;   /* mesh: the end points of its boundary edges, 6 per edge */
    int boundary_count;
    double least;       /* no size anywhere is smaller */
} size_field;

typedef struct surface {
    const plm_surface *s;
    double width, height, radius;
    double area;
    double *cdf; /* mesh: cumulative triangle areas */
    double least_density, most_density; /* mesh: of its density attribute, if it has one */
    size_field size;
} surface;

typedef struct surface_point {
    vec3 p, n, flow; /* flow: unit, in the tangent plane */
    double density;  /* the mesh's density attribute there over its least (1 without one) */
    double size;     /* the size field there */
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
    sf->least_density = INFINITY, sf->most_density = 0.0;
    for (int i = 0; m->density && i < m->vertex_count; ++i) {
        if (!(m->density[i] > 0.0f))
            return plm_fail(err, PLM_ERR_INVALID, "layout surface: the mesh's density at vertex %d is %g; "
                            "densities must be positive", i, (double)m->density[i]);
        sf->least_density = fmin(sf->least_density, m->density[i]);
        sf->most_density = fmax(sf->most_density, m->density[i]);
    }
    if (m->density && sf->most_density > 100.0 * sf->least_density)
        return plm_fail(err, PLM_ERR_INVALID, "layout surface: the mesh's densities range over %g to %g; at most "
                        "a factor of 100 (feather sizes over a factor of 10)", sf->least_density, sf->most_density);
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
    sp.density = 1.0;
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
        if (m->density)
            sp.density = (b0 * m->density[v[0]] + b1 * m->density[v[1]] + b2 * m->density[v[2]]) /
                         sf->least_density;
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

/* ---- The size field ---- */

static void surface_free(surface *sf)
{
    free(sf->cdf);
    free(sf->size.boundary);
}

static int compare_edge(const void *a, const void *b)
{
    const uint32_t *p = a, *q = b;
    return p[0] != q[0] ? (p[0] > q[0]) - (p[0] < q[0]) : (p[1] > q[1]) - (p[1] < q[1]);
}

/* The mesh's boundary: the edges of only one triangle. */
static plm_result mesh_boundary(const plm_mesh *m, size_field *f, plm_error *err)
{
    size_t n = 3 * (size_t)m->triangle_count;
    uint32_t(*e)[2] = malloc(sizeof *e * n);
    if (!e)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for the surface's %zu edges", n);
    for (size_t i = 0; i < n; ++i) {
        uint32_t a = m->indices[i], b = m->indices[i % 3 == 2 ? i - 2 : i + 1];
        e[i][0] = a < b ? a : b;
        e[i][1] = a < b ? b : a;
    }
    qsort(e, n, sizeof *e, compare_edge);
    f->boundary = malloc(sizeof(double) * 6 * n);
    for (size_t i = 0; f->boundary && i < n;) {
        size_t j = i + 1;
        while (j < n && !compare_edge(e[i], e[j]))
            ++j;
        for (int k = 0; j == i + 1 && k < 2; ++k)
            for (int c = 0; c < 3; ++c)
                f->boundary[6 * f->boundary_count + 3 * k + c] = m->positions[3 * e[i][k] + c];
        f->boundary_count += j == i + 1;
        i = j;
    }
    free(e);
    return f->boundary ? PLM_OK : plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for the surface's boundary");
}

/* Distance from p to the nearest edge of the surface (infinite on a sphere
 * and a closed mesh). */
static double edge_distance(const surface *sf, vec3 p)
{
    if (sf->s->kind == PLM_SURFACE_PLANE)
        return fmin(0.5 * sf->width - fabs(p.x), 0.5 * sf->height - fabs(p.y));
    double d = INFINITY;
    for (int i = 0; i < sf->size.boundary_count; ++i) {
        const double *e = sf->size.boundary + 6 * i;
        vec3 a = v3(e[0], e[1], e[2]), ab = v3_sub(v3(e[3], e[4], e[5]), a);
        double t = plm_clamp(v3_dot(v3_sub(p, a), ab) / fmax(v3_dot(ab, ab), 1e-300), 0.0, 1.0);
        d = fmin(d, v3_length(v3_sub(p, v3_madd(a, ab, t))));
    }
    return d;
}

static double size_at(const surface *sf, const surface_point *sp)
{
    const size_field *f = &sf->size;
    vec3 p = sp->p;
    double u = f->span > 0.0 ? plm_clamp((v3_dot(p, f->axis) - f->lo) / f->span, 0.0, 1.0) : 1.0;
    double t = f->edge < 1.0 ? fmin(edge_distance(sf, p) / f->edge_width, 1.0) : 1.0;
    /* Linear along the flow; toward an edge, easing out of it. */
    /* A denser part of a mesh takes smaller feathers, spaced as closely as its density asks. */
    return (f->head + (1.0 - f->head) * u) * (f->edge + (1.0 - f->edge) * t * (2.0 - t)) / sqrt(sp->density);
}

/* The field's axis and extent, and the mesh's boundary. */
static plm_result size_init(surface *sf, vec3 axis, double head, double edge, double edge_width, plm_error *err)
{
    size_field *f = &sf->size;
    f->axis = v3_normalize(axis);
    f->head = head;
    f->edge = edge;
    f->edge_width = edge_width;
    f->least = head * edge * (sf->most_density > 0.0 ? sqrt(sf->least_density / sf->most_density) : 1.0);
    const vec3 a = f->axis;
    double hi;
    switch (sf->s->kind) {
    case PLM_SURFACE_PLANE:
        hi = 0.5 * (sf->width * fabs(a.x) + sf->height * fabs(a.y));
        f->lo = -hi;
        break;
    case PLM_SURFACE_SPHERE:
        hi = sf->radius;
        f->lo = -hi;
        break;
    default: {
        const plm_mesh *m = sf->s->mesh;
        f->lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i < m->vertex_count; ++i) {
            double d = v3_dot(mesh_vertex(m->positions, (uint32_t)i), a);
            f->lo = fmin(f->lo, d), hi = fmax(hi, d);
        }
        if (edge < 1.0) {
            plm_result rc = mesh_boundary(m, f, err);
            if (rc != PLM_OK)
                return rc;
        }
    }
    }
    f->span = hi - f->lo;
    return PLM_OK;
}

/* The area feathers of size 1 would take to cover the surface as these do:
 * the integral of size^-2 over it, from a fixed set of stratified samples. */
static double effective_area(const surface *sf, vec3 axis)
{
    enum { SIDE = 64 };
    plm_rng rng;
    plm_rng_seed(&rng, 0x5a1eu, PLM_LAYOUT_STREAM_PLACE);
    double sum = 0.0;
    for (int j = 0; j < SIDE; ++j)
        for (int i = 0; i < SIDE; ++i) {
            double u0 = (i + plm_rng_uniform(&rng)) / SIDE, u1 = (j + plm_rng_uniform(&rng)) / SIDE;
            surface_point sp = surface_sample(sf, axis, u0, u1, plm_rng_uniform(&rng));
            double s = size_at(sf, &sp);
            sum += 1.0 / (s * s);
        }
    return sf->area * sum / (SIDE * SIDE);
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
static int clear_of_sphere(const surface *sf, const plm_layout_extent *e, const plm_layout_instance *in, double scale,
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
            if (surface_height(sf, NULL, plm_layout_apply(in, e->mesh[k].positions + 3 * i)) < margin)
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

/* Whether an accepted point lies closer to sp than r times the mean of their sizes. */
static int too_close(const dart_grid *g, const surface_point *sp, double r)
{
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz)
                for (int i = g->head[cell_key(g, sp->p, dx, dy, dz)]; i >= 0; i = g->next[i])
                    if (v3_length(v3_sub(g->points[i].p, sp->p)) < 0.5 * r * (g->points[i].size + sp->size))
                        return 1;
    return 0;
}

/* `count` points over the surface, no two closer than a radius times their
 * sizes (the size field): the radius starts at 0.75 of the mean spacing of
 * size-1 feathers over the effective area and shrinks only when darts keep
 * missing. Darts land with a density proportional to size^-2, the density
 * the points end with, so every part of the surface fills alike. */
static plm_result blue_noise(const surface *sf, vec3 axis, int count, double effective_area, uint64_t seed,
                             surface_point *out, plm_error *err)
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
    double r = 0.75 * sqrt(effective_area / count), least = sf->size.least;
    g.cell = r; /* sizes are at most 1 */
    plm_rng rng;
    plm_rng_seed(&rng, seed, PLM_LAYOUT_STREAM_PLACE);
    int placed = 0, misses = 0;
    while (placed < count) {
        double u0 = plm_rng_uniform(&rng), u1 = plm_rng_uniform(&rng), u2 = plm_rng_uniform(&rng);
        surface_point sp = surface_sample(sf, axis, u0, u1, u2);
        sp.size = size_at(sf, &sp);
        if (plm_rng_uniform(&rng) * sp.size * sp.size > least * least)
            continue; /* kept with probability (least / size)^2 */
        if (too_close(&g, &sp, r)) {
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

/* Sets a feather's matrix for base angle alpha and base height h. */
static void pose(const surface_point *root, const plm_layout_extent *e, double scale, double alpha, double h,
                 double flatten, plm_layout_instance *in)
{
    vec3 n = root->n, t = rotate_about(root->flow, n, in->yaw);
    vec3 tt = v3_add(v3_scale(t, cos(alpha)), v3_scale(n, sin(alpha)));
    vec3 z = v3_sub(v3_scale(n, cos(alpha)), v3_scale(t, sin(alpha)));
    plm_layout_set_matrix(in, v3_cross(tt, z), tt, v3_scale(z, flatten),
                          v3_madd(root->p, n, e->rachis_radius * scale + h), scale);
}

/* Places one feather at a root: along the flow turned by its yaw, raised by
 * `elevation` plus its lift, then further (in half-degree steps, up to
 * max_elevation) until every point of the prototype is above the surface. */
static void place_on_surface(const surface *sf, const surface_point *root, const plm_layout_extent *e, double scale,
                             double elevation, double max_elevation, plm_layout_instance *in)
{
    double alpha = fmin(elevation + in->lift, max_elevation);
    const double margin = 0.002 * e->length * scale, step = plm_radians(0.5);
    for (;;) {
        pose(root, e, scale, alpha, 0.0, 1.0, in);
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

/* ---- Settling: each feather rests on the ones beneath it ---- */

/* A placed feather's frame, read back from its matrix. */
typedef struct placed_frame {
    vec3 o, x, t, z; /* unit */
    double s;        /* layout units per mm */
    double k;        /* the dorsal axis's further scale: how much flatter than generated */
    vec3 c;          /* settled feathers: the centre of the vane's bounding sphere */
    double r;        /* and its radius */
} placed_frame;

static placed_frame frame_of(const plm_layout_instance *in)
{
    placed_frame f;
    f.o = v3(in->m[0][3], in->m[1][3], in->m[2][3]);
    vec3 c[3];
    for (int k = 0; k < 3; ++k)
        c[k] = v3(in->m[0][k], in->m[1][k], in->m[2][k]);
    f.s = v3_length(c[1]);
    f.k = v3_length(c[2]) / f.s;
    f.x = v3_scale(c[0], 1.0 / f.s), f.t = v3_scale(c[1], 1.0 / f.s), f.z = v3_scale(c[2], 1.0 / (f.s * f.k));
    return f;
}

typedef struct settle_state {
    const surface *sf;
    const surface_point *roots;
    const plm_layout_extent *ext;
    plm_layout *out;
    placed_frame *frames;  /* of the feathers settled so far */
    int *settled;   /* 1 once a feather is settled */
    dart_grid grid; /* the roots, in cells of the largest reach */
    double reach_max;
    int *near;      /* scratch: candidate neighbours */
    int *listed;    /* scratch: 1 + the feather whose neighbours last listed it (hashed cells may share a chain) */
} settle_state;

/* How far a feather's vane reaches from its root, in layout units (a fifth
 * more: the base may lift while it settles). */
static double reach_of(const plm_layout_extent *e, const plm_layout_instance *in)
{
    return frame_of(in).s * (v3_length(e->centre) + e->radius) * 1.2;
}

/* Where a placed feather's vane's bounding sphere is centred. */
static vec3 sphere_centre(const placed_frame *f, const plm_layout_extent *e)
{
    vec3 c = v3_add(v3_add(v3_scale(f->x, e->centre.x), v3_scale(f->t, e->centre.y)),
                    v3_scale(f->z, e->centre.z * f->k));
    return v3_madd(f->o, c, f->s);
}

/* The settled feathers whose vanes might touch feather i's: their bounding
 * spheres reach within feather i's reach of its root. */
static int neighbours(settle_state *st, int i)
{
    const surface_point *p = &st->roots[i];
    double reach = reach_of(&st->ext[st->out->instances[i].prototype], &st->out->instances[i]);
    int n = 0;
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz)
                for (int j = st->grid.head[cell_key(&st->grid, p->p, dx, dy, dz)]; j >= 0; j = st->grid.next[j]) {
                    if (!st->settled[j] || st->listed[j] == i + 1)
                        continue;
                    const placed_frame *f = &st->frames[j];
                    if (v3_length(v3_sub(f->c, p->p)) < reach + f->r)
                        st->near[n++] = j, st->listed[j] = i + 1;
                }
    return n;
}

/* How far a point q must rise (along the neighbours' normals) to lie
 * `margin` above every settled neighbour's vane under it; 0 if it does. */
static double depth_below(const settle_state *st, const int *near, int n, vec3 q, double margin)
{
    double need = 0.0;
    for (int k = 0; k < n; ++k) {
        const placed_frame *f = &st->frames[near[k]];
        const plm_layout_extent *e = &st->ext[st->out->instances[near[k]].prototype];
        vec3 d = v3_sub(q, f->o);
        vec3 qc = v3_sub(q, f->c);
        if (v3_dot(qc, qc) > f->r * f->r)
            continue;
        double x = v3_dot(d, f->x) / f->s, y = v3_dot(d, f->t) / f->s, z = v3_dot(d, f->z) / (f->s * f->k);
        double h = plm_layout_height(e, x, y);
        if (h > -INFINITY)
            need = fmax(need, (h - z) * f->s * f->k + margin);
    }
    return need;
}

/* How a feather may rise to clear what lies beneath it: turn up about its
 * root, lift its base, or flatten (its dorsal axis scaled down, which lifts
 * the curled edges and the bent tip toward the rachis' plane: a feather
 * pressed onto the ones below). */
typedef struct settle_step {
    double turn, lift, flatten;
} settle_step;

/* The step that clears a point p of the feather (its frame f) that must rise
 * by `need`: flattening as far as it helps, the rest by turning for a point
 * far along the feather, by lifting for one near its root. */
static void step_for(const float *p, const placed_frame *f, double alpha, double need, double least_flatten,
                     double near_root, settle_step *s)
{
    double under = -p[2] * f->s; /* how far below the rachis' plane (layout units, unflattened) */
    if (under > 0.0) {
        double dk = fmin(need / under, f->k - least_flatten);
        s->flatten = fmax(s->flatten, dk);
        need -= dk * under;
    }
    if (need <= 0.0)
        return;
    if (p[1] > near_root)
        s->turn = fmax(s->turn, need / (f->s * p[1] * cos(alpha)));
    else
        s->lift = fmax(s->lift, need);
}

/* Raises feather i until its vane lies `margin` above the skin and every
 * settled neighbour's vane, in rounds of first-order steps (each round's
 * largest needs set the next step, a tenth more). */
static void settle_one(settle_state *st, int i, double max_elevation)
{
    plm_layout_instance *in = &st->out->instances[i];
    const surface_point *root = &st->roots[i];
    const plm_layout_extent *e = &st->ext[in->prototype];
    int n = neighbours(st, i);
    double scale = frame_of(in).s, alpha = in->lift, h = 0.0, flatten = 1.0;
    const double margin = 0.003 * e->length * scale, near_root = 0.5 * e->length, least_flatten = 0.1;
    pose(root, e, scale, alpha, h, flatten, in);
    for (int round = 0; round < 24; ++round) {
        placed_frame f = frame_of(in);
        settle_step step = {0.0, 0.0, 0.0};
        for (int m = 0; m < 2; ++m) /* the vane clears its neighbours' vanes, both clear the skin */
            for (int v = 0; v < e->mesh[m].vertex_count; ++v) {
                const float *p = e->mesh[m].positions + 3 * v;
                vec3 q = plm_layout_apply(in, p);
                double need = margin - surface_height(st->sf, root, q);
                if (m == 0)
                    need = fmax(need, depth_below(st, st->near, n, q, margin));
                if (need > 0.0)
                    step_for(p, &f, alpha, need, least_flatten, near_root, &step);
            }
        if (step.turn == 0.0 && step.lift == 0.0 && step.flatten == 0.0)
            break;
        /* An offset first: a turn for the same need would lift the tip far more. */
        if (step.lift > 0.0)
            h += 1.1 * step.lift;
        else
            alpha = fmin(alpha + 1.1 * step.turn, max_elevation);
        flatten = fmax(flatten - 1.1 * step.flatten, least_flatten);
        pose(root, e, scale, alpha, h, flatten, in);
    }
    in->lift = alpha;
    st->frames[i] = frame_of(in);
    st->frames[i].c = sphere_centre(&st->frames[i], e);
    st->frames[i].r = e->radius * st->frames[i].s;
    st->settled[i] = 1;
}

/* Settles the feathers from the bottom of the shingling (order 0) up. */
static plm_result settle(const surface *sf, const surface_point *roots, const plm_layout_extent *ext,
                         double max_elevation, plm_layout *out, plm_error *err)
{
    int count = out->instance_count;
    settle_state st = {0};
    st.sf = sf, st.roots = roots, st.ext = ext, st.out = out;
    int *by_order = malloc(sizeof(int) * (size_t)count);
    uint64_t size = 1;
    while (size < 2 * (uint64_t)count)
        size <<= 1;
    st.frames = malloc(sizeof *st.frames * (size_t)count);
    st.settled = calloc((size_t)count, sizeof(int));
    st.near = malloc(sizeof(int) * (size_t)count);
    st.listed = calloc((size_t)count, sizeof(int));
    st.grid.head = malloc(sizeof(int) * size);
    st.grid.next = malloc(sizeof(int) * (size_t)count);
    plm_result rc = PLM_OK;
    if (!by_order || !st.frames || !st.settled || !st.near || !st.listed || !st.grid.head || !st.grid.next)
        rc = plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory settling %d feathers", count);
    for (int i = 0; rc == PLM_OK && i < count; ++i)
        st.reach_max = fmax(st.reach_max, reach_of(&ext[out->instances[i].prototype], &out->instances[i]));
    if (rc == PLM_OK) {
        memset(st.grid.head, 0xff, sizeof(int) * size);
        st.grid.mask = size - 1;
        st.grid.cell = 2.0 * st.reach_max; /* neighbours' roots lie within two reaches */
        for (int i = 0; i < count; ++i) {
            uint64_t key = cell_key(&st.grid, roots[i].p, 0, 0, 0);
            st.grid.next[i] = st.grid.head[key];
            st.grid.head[key] = i;
            by_order[out->instances[i].order] = i;
        }
        for (int k = 0; k < count; ++k)
            settle_one(&st, by_order[k], max_elevation);
    }
    free(by_order);
    free(st.frames);
    free(st.settled);
    free(st.near);
    free(st.listed);
    free(st.grid.head);
    free(st.grid.next);
    return rc;
}

typedef struct pelt_setup {
    int count;
    double length;         /* layout units of a scale-1 feather */
    double effective_area; /* effective_area(): the area size-1 feathers would cover */
    double elevation, max_elevation;
    plm_layout_ranges var;
    int variants;
    int settle; /* lay each feather on those beneath it (pelts; a ball's stand free) */
} pelt_setup;

typedef struct flow_rank {
    double along; /* the root's distance along the flow axis */
    int instance;
} flow_rank;

static int compare_along(const void *a, const void *b)
{
    const flow_rank *p = a, *q = b;
    return p->along > q->along ? -1 : p->along < q->along ? 1 : p->instance - q->instance;
}

/* The order in which the feathers shingle: a feather's tip reaches over the
 * bases of those rooted further along the flow, so it lies over them; its
 * `order` counts them (the most downstream feather is 0). */
static plm_result shingle_order(plm_layout *out, const surface_point *roots, vec3 axis, plm_error *err)
{
    int n = out->instance_count;
    flow_rank *r = malloc(sizeof *r * (size_t)n);
    if (!r)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for %d feathers", n);
    for (int i = 0; i < n; ++i)
        r[i] = (flow_rank){v3_dot(roots[i].p, axis), i};
    qsort(r, (size_t)n, sizeof *r, compare_along);
    for (int k = 0; k < n; ++k)
        out->instances[r[k].instance].order = k;
    free(r);
    return PLM_OK;
}

static plm_result pelt(const surface *sf, vec3 axis, const pelt_setup *ps, uint64_t seed,
                       const plm_layout_species *species, int species_count, plm_layout *out, plm_error *err)
{
    const plm_species *list[15];
    double cdf[15];
    if (species_count < 1 || species_count > (int)(sizeof list / sizeof list[0]))
        return plm_fail(err, PLM_ERR_INVALID, "a layout takes 1 to %d species, not %d",
                        (int)(sizeof list / sizeof list[0]), species_count);
    for (int s = 0; s < species_count; ++s) {
        if (!species[s].species)
            return plm_fail(err, PLM_ERR_INVALID, "layout species %d is missing", s);
        list[s] = species[s].species;
        cdf[s] = (s ? cdf[s - 1] : 0.0) + (species[s].weight > 0.0 ? species[s].weight : 1.0);
    }
    plm_layout_extent *ext = NULL;
    surface_point *roots = malloc(sizeof *roots * (size_t)ps->count);
    out->instances = calloc((size_t)ps->count, sizeof *out->instances);
    plm_result rc = roots && out->instances ? PLM_OK
                                            : plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for %d feathers",
                                                       ps->count);
    if (rc == PLM_OK)
        rc = plm_layout_make_prototypes(list, species_count, ps->variants, seed, out, &ext, err);
    if (rc == PLM_OK)
        rc = blue_noise(sf, axis, ps->count, ps->effective_area, seed, roots, err);
    for (int i = 0; rc == PLM_OK && i < ps->count; ++i) {
        plm_layout_instance *in = &out->instances[i];
        plm_rng rng;
        plm_rng_seed(&rng, plm_hash64(seed, (uint64_t)i, 0), PLM_LAYOUT_STREAM_FEATHER);
        int s = pick_weighted(cdf, species_count, plm_rng_uniform(&rng));
        int v = (int)(plm_rng_uniform(&rng) * ps->variants);
        in->prototype = s * ps->variants + v;
        in->row = -1; /* rows are a wing's */
        plm_layout_draw_variation(&rng, &ps->var, in);
        in->scale *= roots[i].size;
        const plm_layout_extent *e = &ext[in->prototype];
        double scale = in->scale * ps->length / e->length;
        if (ps->settle) /* settle() raises it */
            pose(&roots[i], e, scale, (in->lift = ps->elevation + in->lift), 0.0, 1.0, in);
        else
            place_on_surface(sf, &roots[i], e, scale, ps->elevation, ps->max_elevation, in);
    }
    if (rc == PLM_OK) {
        out->instance_count = ps->count;
        rc = shingle_order(out, roots, axis, err);
    }
    if (rc == PLM_OK && ps->settle)
        rc = settle(sf, roots, ext, ps->max_elevation, out, err);
    plm_layout_extents_free(ext, out->prototype_count);
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
    double head = p->head_size > 0.0 ? p->head_size : 0.6, edge = p->edge_size > 0.0 ? p->edge_size : 0.6;
    if (rc == PLM_OK && !(count >= 1.0 && count <= 1e7))
        rc = plm_fail(err, PLM_ERR_INVALID, "pelt: %.0f feathers is out of range [1, 10^7] (count, or density x "
                      "area %g)", count, sf.area);
    if (rc == PLM_OK && !(overlap < 0.95))
        rc = plm_fail(err, PLM_ERR_INVALID, "pelt: overlap %g is out of range (0, 0.95)", overlap);
    if (rc == PLM_OK && !(p->elevation >= 0.0 && p->elevation < 0.5 * PLM_PI))
        rc = plm_fail(err, PLM_ERR_INVALID, "pelt: elevation %g degrees is out of range [0, 90)",
                      plm_degrees(p->elevation));
    if (rc == PLM_OK && !(head <= 1.0 && edge <= 1.0))
        rc = plm_fail(err, PLM_ERR_INVALID, "pelt: head_size %g and edge_size %g must be in (0, 1]", head, edge);
    if (rc == PLM_OK && !(p->edge_width >= 0.0))
        rc = plm_fail(err, PLM_ERR_INVALID, "pelt: edge_width %g must not be negative", p->edge_width);
    vec3 axis = v3_length(p->axis) > 0.0 ? p->axis : v3(0, -1, 0);
    /* Shingling: a feather should come out from under the ones behind it
     * at `overlap` of its length. Blue-noise neighbours ahead along the
     * flow sit partly to the side, and a length of 1.25 mean spacings
     * per (1 - overlap) does it (measured by test_layout, docs/layouts.md). */
    double uniform_length = 1.25 * sqrt(sf.area / count) / (1.0 - overlap);
    if (rc == PLM_OK)
        rc = size_init(&sf, axis, head, edge, p->edge_width > 0.0 ? p->edge_width : uniform_length, err);
    if (rc == PLM_OK) {
        pelt_setup ps;
        ps.count = (int)count;
        ps.effective_area = effective_area(&sf, axis);
        /* The largest feathers: the spacing of size-1 feathers over the effective area. */
        double ahead = 1.25 * sqrt(ps.effective_area / ps.count);
        ps.length = p->feather_length > 0.0 ? p->feather_length : ahead / (1.0 - overlap);
        ps.elevation = p->elevation > 0.0 ? p->elevation : plm_radians(8.0);
        ps.max_elevation = plm_radians(80.0);
        ps.var = plm_layout_ranges_of(&p->variation);
        /* A pelt's neighbours differ in length by a coefficient of variation of about 9%. */
        if (!p->variation.none && !(p->variation.scale > 0.0))
            ps.var.scale = PLM_PELT_SCALE_VARIATION;
        ps.variants = p->variants > 0 ? p->variants : 4;
        /* Rigid feathers settle on a plane; on a curved surface a straight
         * feather's tip stands off it (docs/layouts.md), so they keep the
         * placement that clears the surface alone. */
        ps.settle = p->surface.kind == PLM_SURFACE_PLANE;
        rc = pelt(&sf, axis, &ps, p->seed, species, species_count, out, err);
    }
    surface_free(&sf);
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
    rc = size_init(&sf, v3(0, -1, 0), 1.0, 1.0, 1.0, err); /* all one size */
    if (rc != PLM_OK)
        return rc;
    ps.count = p->count > 0 ? p->count : 496;
    ps.effective_area = sf.area;
    ps.length = p->feather_length > 0.0 ? p->feather_length : 2.0 * sf.radius;
    ps.elevation = 0.5 * PLM_PI - spread;
    ps.max_elevation = 0.5 * PLM_PI;
    ps.var = plm_layout_ranges_of(&p->variation);
    ps.var.lift = spread; /* upright .. leaning by spread */
    ps.var.yaw = PLM_PI;  /* leaning any way */
    ps.variants = p->variants > 0 ? p->variants : 4;
    ps.settle = 0;
    rc = pelt(&sf, v3(0, -1, 0), &ps, p->seed, species, species_count, out, err);
    if (rc != PLM_OK)
        plm_layout_free(out);
    return rc;
}
