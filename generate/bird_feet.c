/* The perch and the feet gripping it: a branch along the bird's side axis
 * under the origin, and on each side a short tarsus and four toes, two
 * forward and two back (zygodactyl, as parrots', the only kind built),
 * curling over the branch. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "generate/bird_parts.h"

#define MM 0.001
#define TOE_RINGS 12
#define AROUND 12

/* Appends b's vertices and triangles to a. */
static plm_result append(plm_mesh *a, const plm_mesh *b, plm_error *err)
{
    int nv = a->vertex_count + b->vertex_count, nt = a->triangle_count + b->triangle_count;
    float *p = realloc(a->positions, sizeof(float) * 3 * (size_t)nv);
    if (p)
        a->positions = p;
    float *n = realloc(a->normals, sizeof(float) * 3 * (size_t)nv);
    if (n)
        a->normals = n;
    uint32_t *t = realloc(a->indices, sizeof(uint32_t) * 3 * (size_t)nt);
    if (t)
        a->indices = t;
    if (!p || !n || !t)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for the feet");
    memcpy(a->positions + 3 * a->vertex_count, b->positions, sizeof(float) * 3 * (size_t)b->vertex_count);
    memcpy(a->normals + 3 * a->vertex_count, b->normals, sizeof(float) * 3 * (size_t)b->vertex_count);
    for (int i = 0; i < 3 * b->triangle_count; ++i)
        a->indices[3 * a->triangle_count + i] = b->indices[i] + (uint32_t)a->vertex_count;
    a->vertex_count = nv;
    a->triangle_count = nt;
    return PLM_OK;
}

/* A toe from the top of the branch (centre c, radius r, axis y) curling
 * `wrap` radians toward `dir` (+1 forward, -1 back), splayed `splay` along y. */
static plm_result toe(vec3 c, double r, double thick, double wrap, double dir, double splay, plm_mesh *out,
                      plm_error *err)
{
    plm_sweep_ring rings[TOE_RINGS];
    double R = r + thick;
    for (int i = 0; i < TOE_RINGS; ++i) {
        double t = (double)i / (TOE_RINGS - 1), a = 0.5 * PLM_PI - dir * wrap * t;
        vec3 radial = v3(cos(a), 0.0, sin(a));
        vec3 along = v3_normalize(v3(-sin(a) * dir, splay, cos(a) * dir));
        vec3 side = v3_normalize(v3_cross(radial, along));
        double k = t < 0.85 ? 1.0 : 0.35 + 0.65 * (1.0 - t) / 0.15; /* the claw's taper */
        rings[i] = (plm_sweep_ring){v3_add(v3_madd(c, radial, R), v3(0, splay * R * wrap * t, 0)), side, radial,
                                    thick * k, thick * k, thick * k};
    }
    return plm_sweep(rings, TOE_RINGS, AROUND, out, err);
}

plm_result plm_bird_perch(const plm_bird *bird, double radius_mm, double length_mm, plm_mesh *branch, plm_mesh *feet,
                          plm_error *err)
{
    memset(branch, 0, sizeof *branch);
    memset(feet, 0, sizeof *feet);
    double r = radius_mm * MM, half = 0.5 * length_mm * MM, tar = bird->m.tarsus * MM;
    vec3 c = v3(0, 0, -r);
    /* The branch: a tube along y, a little bent and thinner toward one end. */
    plm_sweep_ring rings[16];
    for (int i = 0; i < 16; ++i) {
        double t = i / 15.0, y = -half + 2.0 * half * t, k = 1.1 - 0.2 * t;
        vec3 centre = v3(0.02 * half * sin(3.0 * t), y, -r - 0.03 * half * t * t);
        rings[i] = (plm_sweep_ring){centre, v3(1, 0, 0), v3(0, 0, 1), r * k, r * k, r * k};
    }
    plm_result rc = plm_sweep(rings, 16, 24, branch, err);
    double thick = 0.12 * tar, foot_y = 0.45 * bird->m.head_width * MM;
    for (int side = 0; rc == PLM_OK && side < 2; ++side) {
        double sy = side ? -1.0 : 1.0;
        vec3 fc = v3(c.x, sy * foot_y, c.z);
        /* Two toes forward, two back, each pair splayed apart. */
        for (int k = 0; rc == PLM_OK && k < 4; ++k) {
            plm_mesh m;
            double dir = k < 2 ? 1.0 : -1.0, splay = (k % 2 ? 0.18 : -0.18);
            rc = toe(fc, r, thick, plm_radians(k < 2 ? 115.0 : 100.0), dir, splay, &m, err);
            if (rc == PLM_OK)
                rc = append(feet, &m, err);
            plm_mesh_free(&m);
        }
        /* The tarsus: from the foot up into the belly feathers. */
        plm_sweep_ring leg[2] = {{v3(0, sy * foot_y, thick), v3(1, 0, 0), v3(0, 1, 0), 1.3 * thick, 1.3 * thick,
                                  1.3 * thick},
                                 {v3(-0.1 * tar, sy * foot_y * 0.9, 0.8 * tar), v3(1, 0, 0), v3(0, 1, 0), 1.6 * thick,
                                  1.6 * thick, 1.6 * thick}};
        plm_mesh m;
        if (rc == PLM_OK && (rc = plm_sweep(leg, 2, AROUND, &m, err)) == PLM_OK) {
            rc = append(feet, &m, err);
            plm_mesh_free(&m);
        }
    }
    if (rc != PLM_OK) {
        plm_mesh_free(branch);
        plm_mesh_free(feet);
    }
    return rc;
}
