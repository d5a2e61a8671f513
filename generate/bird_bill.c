/* The bill: each mandible a shape swept along a centre line that bends as
 * the family's bill does (hooked: the upper mandible curls down over the
 * lower one; conical and dagger: straight cones, stout or slender by the
 * measurements). Also the generic sweep. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "generate/bird_parts.h"

#define BILL_RINGS 28
#define BILL_AROUND 16

/* One mandible by family: its centre line's start (in bill depths above the
 * base's centre), length (bill lengths), heading at the base and its turn
 * toward the tip (radians, positive up), and its section (bill depths). */
typedef struct mandible {
    double start, length, heading, turn, turn_power;
    double w, up, down, taper;
} mandible;

static const mandible mandibles[PLM_BILL_FAMILIES][2] = {
    /* hooked: the upper curls through 165 degrees to a point below and behind its reach */
    {{0.12, 1.45, 0.3, -3.2, 1.7, 0.34, 0.32, 0.16, 0.8}, {-0.24, 0.62, 0.45, -0.3, 1.0, 0.32, 0.12, 0.22, 0.8}},
    /* conical */
    {{0.1, 1.0, -0.08, -0.1, 1.0, 0.34, 0.32, 0.06, 1.0}, {-0.1, 0.95, -0.12, 0.05, 1.0, 0.33, 0.06, 0.3, 1.0}},
    /* dagger */
    {{0.08, 1.0, -0.03, -0.03, 1.0, 0.3, 0.28, 0.05, 1.3}, {-0.08, 0.97, -0.03, 0.03, 1.0, 0.28, 0.05, 0.28, 1.3}},
};

static plm_result sweep_mandible(const mandible *md, double length, double depth, vec3 base, vec3 fwd, vec3 dorsal,
                                 vec3 side, double scale, plm_mesh *out, plm_error *err)
{
    plm_sweep_ring rings[BILL_RINGS];
    vec3 c = v3_madd(base, dorsal, md->start * depth);
    double ds = md->length * length / (BILL_RINGS - 1);
    for (int i = 0; i < BILL_RINGS; ++i) {
        double t = (double)i / (BILL_RINGS - 1), a = md->heading + md->turn * pow(t, md->turn_power);
        vec3 dir = v3_add(v3_scale(fwd, cos(a)), v3_scale(dorsal, sin(a)));
        vec3 up = v3_sub(v3_scale(dorsal, cos(a)), v3_scale(fwd, sin(a)));
        double k = pow(1.0 - t, md->taper);
        rings[i] = (plm_sweep_ring){v3_scale(c, scale), side, up, md->w * depth * k * scale,
                                    md->up * depth * k * scale, md->down * depth * k * scale};
        c = v3_madd(c, dir, ds);
    }
    return plm_sweep(rings, BILL_RINGS, BILL_AROUND, out, err);
}

plm_result plm_bird_bill(const plm_bird *bird, vec3 base, vec3 back, vec3 dorsal, double scale, plm_bird_body *out,
                         plm_error *err)
{
    vec3 fwd = v3_neg(back), side = v3_normalize(v3_cross(dorsal, fwd));
    const mandible *md = mandibles[bird->bill_family];
    double l = bird->m.bill_length, d = bird->m.bill_depth;
    /* The bill's base sits a little inside the head's front ring, so no seam shows. */
    vec3 b = v3_madd(base, fwd, -0.15 * l);
    plm_result rc = sweep_mandible(&md[0], l, d, b, fwd, dorsal, side, scale, &out->upper_bill, err);
    if (rc == PLM_OK)
        rc = sweep_mandible(&md[1], l, d, b, fwd, dorsal, side, scale, &out->lower_bill, err);
    return rc;
}

/* ---- The sweep ---- */


static void put(float *a, int i, vec3 v)
{
    a[3 * i] = (float)v.x, a[3 * i + 1] = (float)v.y, a[3 * i + 2] = (float)v.z;
}

/* Area-weighted vertex normals, and the winding turned outward (positive volume). */
static void orient(plm_mesh *m)
{
    double volume = 0.0;
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *v = m->indices + 3 * t;
        volume += v3_dot(plm_mesh_vertex(m->positions, (int)v[0]),
                         v3_cross(plm_mesh_vertex(m->positions, (int)v[1]), plm_mesh_vertex(m->positions, (int)v[2])));
    }
    for (int t = 0; volume < 0.0 && t < m->triangle_count; ++t) {
        uint32_t *v = m->indices + 3 * t, x = v[1];
        v[1] = v[2], v[2] = x;
    }
    memset(m->normals, 0, sizeof(float) * 3 * (size_t)m->vertex_count);
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *v = m->indices + 3 * t;
        vec3 a = plm_mesh_vertex(m->positions, (int)v[0]), b = plm_mesh_vertex(m->positions, (int)v[1]),
             c = plm_mesh_vertex(m->positions, (int)v[2]);
        vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
        for (int k = 0; k < 3; ++k)
            put(m->normals, (int)v[k], v3_add(plm_mesh_vertex(m->normals, (int)v[k]), n));
    }
    for (int i = 0; i < m->vertex_count; ++i) {
        vec3 n = plm_mesh_vertex(m->normals, i);
        put(m->normals, i, v3_length(n) > 0.0 ? v3_normalize(n) : v3(0, 0, 1));
    }
}

plm_result plm_sweep(const plm_sweep_ring *rings, int ring_count, int around, plm_mesh *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    if (ring_count < 2 || around < 3)
        return plm_fail(err, PLM_ERR_INVALID, "a sweep needs 2 rings of 3 points, not %d of %d", ring_count, around);
    /* Every ring has `around` vertices (a point's coincide), plus a centre for each open end. */
    int nv = ring_count * around + 2, nt = 2 * (ring_count - 1) * around + 2 * around;
    out->vertex_count = nv;
    out->triangle_count = nt;
    out->positions = malloc(sizeof(float) * 3 * (size_t)nv);
    out->normals = malloc(sizeof(float) * 3 * (size_t)nv);
    out->indices = malloc(sizeof(uint32_t) * 3 * (size_t)nt);
    if (!out->positions || !out->normals || !out->indices) {
        plm_mesh_free(out);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a sweep of %d vertices", nv);
    }
    for (int i = 0; i < ring_count; ++i) {
        const plm_sweep_ring *r = &rings[i];
        for (int k = 0; k < around; ++k) {
            double a = PLM_TWO_PI * k / around, c = cos(a), s = sin(a);
            vec3 p = v3_add(v3_madd(r->centre, r->side, r->w * s), v3_scale(r->up, c * (c >= 0.0 ? r->up_height
                                                                                               : r->down_height)));
            put(out->positions, i * around + k, p);
        }
    }
    put(out->positions, nv - 2, rings[0].centre);
    put(out->positions, nv - 1, rings[ring_count - 1].centre);
    uint32_t *t = out->indices;
    for (int i = 0; i + 1 < ring_count; ++i)
        for (int k = 0; k < around; ++k) {
            uint32_t a = (uint32_t)(i * around + k), b = (uint32_t)(i * around + (k + 1) % around);
            uint32_t q[6] = {a, b, b + (uint32_t)around, a, b + (uint32_t)around, a + (uint32_t)around};
            memcpy(t, q, sizeof q);
            t += 6;
        }
    /* End caps (zero-area where a ring is a point). */
    for (int k = 0; k < around; ++k) {
        uint32_t a = (uint32_t)k, b = (uint32_t)((k + 1) % around), o = (uint32_t)((ring_count - 1) * around);
        uint32_t q[6] = {(uint32_t)nv - 2, b, a, (uint32_t)nv - 1, o + a, o + b};
        memcpy(t, q, sizeof q);
        t += 6;
    }
    orient(out);
    return PLM_OK;
}
