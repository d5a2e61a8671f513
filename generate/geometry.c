#include "generate/geometry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "generate/subdiv.h"

/* Fitting passes: the residual shrinks by at least 2/3 per pass (the
 * smallest eigenvalue of the cubic B-spline limit operator is 1/3). */
#define FIT_ITERATIONS 40

plm_rachis_frame plm_rachis_frame_at(const plm_outline *o, double y)
{
    const plm_shape *sh = &o->shape;
    /* Angular velocity per mm in the initial frame (x lateral, y along, z dorsal):
     * a positive in-plane bend turns the tip toward +x, a positive
     * out-of-plane bend toward the ventral side (-z). */
    vec3 omega = v3_scale(v3(-sh->bend_out_of_plane, sh->twist, -sh->bend_in_plane), 1.0 / sh->length);
    double w = v3_length(omega);
    plm_rachis_frame f;
    vec3 ey = v3(0, 1, 0);
    if (w < 1e-12) {
        f.c = v3(0, y, 0);
        f.x = v3(1, 0, 0);
        f.t = ey;
        f.z = v3(0, 0, 1);
        return f;
    }
    vec3 k = v3_scale(omega, 1.0 / w);
    double a = w * y;
    f.x = v3_rotate(v3(1, 0, 0), k, a);
    f.t = v3_rotate(ey, k, a);
    f.z = v3_rotate(v3(0, 0, 1), k, a);
    /* C(y) = integral of the rotated tangent, in closed form. */
    double ky = v3_dot(k, ey);
    f.c = v3_add(v3_add(v3_scale(ey, sin(a) / w), v3_scale(v3_cross(k, ey), (1.0 - cos(a)) / w)),
                 v3_scale(k, ky * (y - sin(a) / w)));
    return f;
}

vec3 plm_vane_point(const plm_outline *o, double x, double y)
{
    int side = x >= 0.0;
    /* Cupping: a parabola across each vane whose slope at the widest point is tan(curl). */
    double z = -tan(o->shape.curl) * x * x / (2.0 * o->widest[side]);
    plm_rachis_frame f = plm_rachis_frame_at(o, y);
    return v3_add(f.c, v3_add(v3_scale(f.x, x), v3_scale(f.z, z)));
}

static void put3(float *dst, vec3 v)
{
    dst[0] = (float)v.x;
    dst[1] = (float)v.y;
    dst[2] = (float)v.z;
}

static vec3 get3(const double *p) { return v3(p[0], p[1], p[2]); }

/* Triangles from the refined quads, split along the shorter diagonal. */
static plm_result triangulate(const plm_subdiv_limit *l, plm_mesh *m, plm_error *err)
{
    m->triangle_count = 2 * l->quad_count;
    m->indices = malloc(sizeof(uint32_t) * 3 * (size_t)m->triangle_count);
    if (!m->indices)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory triangulating the feather");
    uint32_t *t = m->indices;
    for (int q = 0; q < l->quad_count; ++q) {
        const int *v = l->quads + 4 * q;
        vec3 p[4];
        for (int k = 0; k < 4; ++k)
            p[k] = get3(l->value + (size_t)v[k] * l->width);
        int shorter02 = v3_length(v3_sub(p[0], p[2])) <= v3_length(v3_sub(p[1], p[3]));
        static const int split02[6] = {0, 1, 2, 0, 2, 3}, split13[6] = {0, 1, 3, 1, 2, 3};
        const int *s = shorter02 ? split02 : split13;
        for (int k = 0; k < 6; ++k)
            *t++ = (uint32_t)v[s[k]];
    }
    return PLM_OK;
}

/* Sum of the geometric normals of the faces around each vertex: used to
 * orient each limit normal consistently with the triangle winding. */
static vec3 *face_normal_sums(const plm_mesh *m)
{
    vec3 *sum = calloc((size_t)m->vertex_count, sizeof *sum);
    if (!sum)
        return NULL;
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * t;
        vec3 a = v3(m->positions[3 * i[0]], m->positions[3 * i[0] + 1], m->positions[3 * i[0] + 2]);
        vec3 b = v3(m->positions[3 * i[1]], m->positions[3 * i[1] + 1], m->positions[3 * i[1] + 2]);
        vec3 c = v3(m->positions[3 * i[2]], m->positions[3 * i[2] + 1], m->positions[3 * i[2] + 2]);
        vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
        for (int k = 0; k < 3; ++k)
            sum[i[k]] = v3_add(sum[i[k]], n);
    }
    return sum;
}

static plm_result alloc_mesh(plm_mesh *m, int vertices, int with_uvs, plm_error *err)
{
    memset(m, 0, sizeof *m);
    m->vertex_count = vertices;
    m->positions = malloc(sizeof(float) * 3 * (size_t)vertices);
    m->normals = malloc(sizeof(float) * 3 * (size_t)vertices);
    if (with_uvs) {
        m->uvs = malloc(sizeof(float) * 2 * (size_t)vertices);
        m->tangents = malloc(sizeof(float) * 3 * (size_t)vertices);
    }
    if (!m->positions || !m->normals || (with_uvs && (!m->uvs || !m->tangents))) {
        plm_mesh_free(m);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a %d-vertex mesh", vertices);
    }
    return PLM_OK;
}

/* Fits the cage to the targets, refines it into l, and triangulates l into
 * out (vertex arrays allocated, with uvs and tangents if with_uvs, for the
 * caller to fill from l). The caller frees l in any case (it starts zeroed,
 * so a failed fit leaves nothing to free) and out on failure. */
static plm_result limit_mesh(const plm_subdiv_cage *cage, double *values, int level, int with_uvs,
                             plm_subdiv_limit *l, plm_mesh *out, plm_error *err)
{
    memset(l, 0, sizeof *l);
    plm_result rc = plm_subdiv_fit(cage, values, FIT_ITERATIONS, NULL, err);
    if (rc == PLM_OK)
        rc = plm_subdiv_refine(cage, values, level, l, err);
    if (rc == PLM_OK)
        rc = alloc_mesh(out, l->vertex_count, with_uvs, err);
    return rc == PLM_OK ? triangulate(l, out, err) : rc;
}

/* Vane cage: (COLUMNS + 1) x (ROWS + 1) vertices over s in [-1, 1] across and
 * t in [0, 1] along; each vertex carries position and uv. */
plm_result plm_vane_mesh(const plm_outline *o, int level, plm_mesh *out, plm_error *err)
{
    enum { NX = PLM_VANE_COLUMNS + 1, NY = PLM_VANE_ROWS + 1, W = 5 };
    double values[NX * NY * W];
    int quads[4 * PLM_VANE_COLUMNS * PLM_VANE_ROWS], *q = quads;
    memset(out, 0, sizeof *out);
    for (int j = 0; j < NY; ++j) {
        double t = (double)j / PLM_VANE_ROWS, y = o->vane_base + t * o->vane_length;
        for (int i = 0; i < NX; ++i) {
            double s = -1.0 + 2.0 * i / PLM_VANE_COLUMNS;
            double x = s * plm_outline_mesh_extent(o, s >= 0.0, t);
            double *v = values + (size_t)(j * NX + i) * W;
            vec3 p = plm_vane_point(o, x, y);
            vec2 uv = plm_outline_uv(o, x, y);
            v[0] = p.x, v[1] = p.y, v[2] = p.z, v[3] = uv.x, v[4] = uv.y;
        }
    }
    for (int j = 0; j + 1 < NY; ++j)
        for (int i = 0; i + 1 < NX; ++i) {
            int a = j * NX + i;
            *q++ = a, *q++ = a + 1, *q++ = a + 1 + NX, *q++ = a + NX; /* x then y: dorsal */
        }
    plm_subdiv_cage cage = {NX * NY, PLM_VANE_COLUMNS * PLM_VANE_ROWS, quads, W};
    plm_subdiv_limit l;
    plm_result rc = limit_mesh(&cage, values, level, 1, &l, out, err);
    for (int i = 0; rc == PLM_OK && i < l.vertex_count; ++i) {
        const double *v = l.value + (size_t)i * W, *a = l.d1 + (size_t)i * W, *b = l.d2 + (size_t)i * W;
        /* dP/du and dP/dv from the two limit derivatives of position and uv:
         * [P1 P2] = [Pu Pv] J with J = [[u1 u2], [v1 v2]]. */
        double det = a[3] * b[4] - b[3] * a[4];
        vec3 p1 = get3(a), p2 = get3(b);
        vec3 pu = v3_scale(v3_sub(v3_scale(p1, b[4]), v3_scale(p2, a[4])), 1.0 / det);
        vec3 pv = v3_scale(v3_sub(v3_scale(p2, a[3]), v3_scale(p1, b[3])), 1.0 / det);
        vec3 n = v3_normalize(v3_cross(pu, pv)), tu = v3_normalize(pu);
        if (!(fabs(det) > 0.0) || !isfinite(n.x + n.y + n.z + tu.x + tu.y + tu.z))
            rc = plm_fail(err, PLM_ERR_INTERNAL, "vane limit surface: degenerate derivatives at vertex %d", i);
        put3(out->positions + 3 * i, get3(v));
        put3(out->normals + 3 * i, n);
        put3(out->tangents + 3 * i, tu);
        out->uvs[2 * i] = (float)plm_clamp(v[3], 0.0, 1.0);
        out->uvs[2 * i + 1] = (float)plm_clamp(v[4], 0.0, 1.0);
    }
    plm_subdiv_limit_free(&l);
    if (rc != PLM_OK)
        plm_mesh_free(out);
    return rc;
}

/* Tube cage: RING x (ROWS + 1) ring vertices plus a centre at each end; the
 * ends are closed by four quads each (centre and three consecutive ring
 * vertices), so the cage is all quads and watertight. Rows are graded,
 * ten times denser at the ends than in the middle, and the centres sit half
 * an end row beyond the end rings: the limit surface closes in a short dome,
 * and the gradual spacing keeps the fitted surface from ringing. */
plm_result plm_rachis_mesh(const plm_outline *o, int level, plm_mesh *out, plm_error *err)
{
    enum { N = PLM_RACHIS_RING, NY = PLM_RACHIS_ROWS + 1, W = 3, V = N * NY + 2 };
    double values[V * W];
    int quads[4 * (N * PLM_RACHIS_ROWS + N)], *q = quads;
    memset(out, 0, sizeof *out);
    const double grading = 0.9; /* row spacing ~ 1 - grading cos(2 pi s) */
    for (int j = 0; j < NY; ++j) {
        double s = (j + 0.5) / NY;
        double y = o->rachis_end * (s - grading * sin(PLM_TWO_PI * s) / PLM_TWO_PI);
        plm_rachis_frame f = plm_rachis_frame_at(o, y);
        double r = plm_outline_rachis_radius(o, y);
        for (int k = 0; k < N; ++k) {
            double a = PLM_TWO_PI * k / N;
            vec3 p = v3_add(f.c, v3_add(v3_scale(f.x, r * cos(a)), v3_scale(f.z, r * sin(a))));
            memcpy(values + (size_t)(j * N + k) * W, &p, sizeof p);
        }
    }
    int base = N * NY, tip = base + 1;
    vec3 c0 = plm_rachis_frame_at(o, 0.0).c, c1 = plm_rachis_frame_at(o, o->rachis_end).c;
    memcpy(values + (size_t)base * W, &c0, sizeof c0);
    memcpy(values + (size_t)tip * W, &c1, sizeof c1);
    for (int j = 0; j + 1 < NY; ++j)
        for (int k = 0; k < N; ++k) {
            int a = j * N + k, b = j * N + (k + 1) % N;
            *q++ = a, *q++ = a + N, *q++ = b + N, *q++ = b; /* along T, then around: outward */
        }
    int last = N * (NY - 1);
    for (int m = 0; m < N / 2; ++m) {
        int k0 = 2 * m, k1 = 2 * m + 1, k2 = (2 * m + 2) % N;
        *q++ = base, *q++ = k0, *q++ = k1, *q++ = k2;                      /* faces -T */
        *q++ = tip, *q++ = last + k2, *q++ = last + k1, *q++ = last + k0;  /* faces +T */
    }
    plm_subdiv_cage cage = {V, (int)(q - quads) / 4, quads, W};
    plm_subdiv_limit l;
    plm_result rc = limit_mesh(&cage, values, level, 0, &l, out, err);
    for (int i = 0; rc == PLM_OK && i < l.vertex_count; ++i)
        put3(out->positions + 3 * i, get3(l.value + (size_t)i * W));
    vec3 *ref = rc == PLM_OK ? face_normal_sums(out) : NULL;
    if (rc == PLM_OK && !ref)
        rc = plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for rachis normals");
    for (int i = 0; rc == PLM_OK && i < l.vertex_count; ++i) {
        vec3 n = v3_normalize(v3_cross(get3(l.d1 + (size_t)i * W), get3(l.d2 + (size_t)i * W)));
        if (v3_dot(n, ref[i]) < 0.0)
            n = v3_neg(n);
        if (!isfinite(n.x + n.y + n.z))
            rc = plm_fail(err, PLM_ERR_INTERNAL, "rachis limit surface: degenerate derivatives at vertex %d", i);
        put3(out->normals + 3 * i, n);
    }
    free(ref);
    plm_subdiv_limit_free(&l);
    if (rc != PLM_OK)
        plm_mesh_free(out);
    return rc;
}
