/* The skin body: rings of a cage along a bent spine, from the measurements
 * and proportions, smoothed by OpenSubdiv into a limit surface that carries
 * the body's parameterisation (s, around) as primvars; each triangle then
 * goes to its tract. The bill and eyes are in bird_bill.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "generate/bird.h"
#include "generate/bird_parts.h"
#include "generate/subdiv.h"

#define RINGS 10
#define AROUND 8
#define WIDTH 6 /* position, s, cos(around), sin(around) */
#define FIT_ITERATIONS 40
#define MM 0.001

/* The spine's stations in the skin's own terms (docs/birds.md). */
typedef struct section {
    double f;             /* fraction of the spine from the bill's base */
    double w, up, down;   /* half-width, dorsal and ventral half-heights, mm */
    double angle;         /* radians the spine runs below the horizontal going back from here */
} section;

typedef struct station {
    section shape;
    vec3 c, d, dorsal;    /* centre, direction toward the tail, unit toward the back */
} station;

/* Head, neck, breast, belly, rump and the tail's base from the measurements. */
static void stations_of(const plm_bird *b, station st[RINGS], double *spine)
{
    const plm_bird_measurements *m = &b->m;
    const plm_bird_proportions *p = &b->p;
    double h = 0.5 * m->head_width, br = p->breast * h, dep = p->depth, r = p->rump * br;
    double f4 = 0.23 + p->neck_length, rest = 1.0 - f4, post = p->posture;
    *spine = m->total_length - m->tail_length - 0.75 * m->bill_length;
    station s[RINGS];
    const section shape[RINGS] = {
        {0.0, 0.55 * h, 0.4 * m->bill_depth, 0.4 * m->bill_depth, 0.0},  /* bill's base */
        {0.07, 0.85 * h, 0.95 * h, 0.75 * h, 0.0},                      /* forehead */
        {0.15, h, 1.05 * h, 0.8 * h, 0.0},                              /* eyes */
        {0.23, 0.9 * h, 0.85 * h, 0.8 * h, post + 0.2},                /* nape */
        {f4, p->neck * h, p->neck * h, 1.1 * p->neck * h, post + 0.25}, /* neck */
        {f4 + 0.18 * rest, 0.8 * br, 0.8 * br * dep, 1.0 * br * dep, post}, /* shoulders */
        {f4 + 0.42 * rest, br, 0.9 * br * dep, 1.1 * br * dep, post},      /* breast */
        {f4 + 0.66 * rest, 0.88 * br, 0.85 * br * dep, 0.95 * br * dep, post}, /* belly */
        {f4 + 0.86 * rest, r, 0.9 * r * dep, r * dep, post + 0.1},         /* rump, vent */
        {1.0, 0.55 * r, 0.3 * r, 0.3 * r, post + 0.1},                     /* tail's base */
    };
    vec3 c = v3(0, 0, 0);
    for (int i = 0; i < RINGS; ++i) {
        s[i].shape = shape[i];
        s[i].c = c;
        double a = i == 0 ? shape[0].angle : 0.5 * (shape[i - 1].angle + shape[i].angle);
        s[i].d = v3(-cos(a), 0.0, -sin(a));
        s[i].dorsal = v3(-sin(a), 0.0, cos(a));
        if (i + 1 < RINGS)
            c = v3_madd(c, v3(-cos(shape[i].angle), 0.0, -sin(shape[i].angle)),
                        (shape[i + 1].f - shape[i].f) * *spine);
    }
    memcpy(st, s, sizeof s);
}

static double station_s(const station *st) { return 0.03 + 0.94 * st->shape.f; }

/* A ring point at `around` (0 dorsal, pi/2 the bird's left, pi ventral, 3pi/2 right). */
static vec3 ring_point(const station *st, double around)
{
    double c = cos(around), s = sin(around);
    double h = c >= 0.0 ? st->shape.up : st->shape.down;
    return v3_add(st->c, v3_add(v3_scale(st->dorsal, c * h), v3(0, st->shape.w * s, 0)));
}

/* Cage: a front pole, RINGS rings of AROUND, a rear pole; each pole closed by four quads. */
static void build_cage(const station st[RINGS], double *values, int *quads)
{
    const int n = RINGS * AROUND, front = 0, rear = n + 1;
    double *v = values;
    const station *last = &st[RINGS - 1];
    vec3 tip = v3_madd(st[0].c, st[0].d, -0.3 * st[0].shape.w), end = v3_madd(last->c, last->d, 0.5 * last->shape.w);
    double pole[2][WIDTH] = {{tip.x, tip.y, tip.z, 0.0, 0.0, 0.0}, {end.x, end.y, end.z, 1.0, 0.0, 0.0}};
    memcpy(v, pole[0], sizeof pole[0]);
    for (int i = 0; i < RINGS; ++i)
        for (int k = 0; k < AROUND; ++k) {
            double a = PLM_TWO_PI * k / AROUND;
            vec3 p = ring_point(&st[i], a);
            double row[WIDTH] = {p.x, p.y, p.z, station_s(&st[i]), cos(a), sin(a)};
            memcpy(v + WIDTH * (1 + i * AROUND + k), row, sizeof row);
        }
    memcpy(v + WIDTH * rear, pole[1], sizeof pole[1]);
    int *q = quads;
    for (int i = 0; i + 1 < RINGS; ++i)
        for (int k = 0; k < AROUND; ++k) {
            int a = 1 + i * AROUND + k, b = 1 + i * AROUND + (k + 1) % AROUND;
            int q4[4] = {a, b, b + AROUND, a + AROUND};
            memcpy(q, q4, sizeof q4);
            q += 4;
        }
    for (int j = 0; j < AROUND / 2; ++j) {
        int r0 = 1 + 2 * j, r1 = 1 + 2 * j + 1, r2 = 1 + (2 * j + 2) % AROUND;
        int qf[4] = {front, r2, r1, r0};
        memcpy(q, qf, sizeof qf);
        q += 4;
        int o = (RINGS - 1) * AROUND;
        int qr[4] = {rear, r0 + o, r1 + o, r2 + o};
        memcpy(q, qr, sizeof qr);
        q += 4;
    }
}

/* The gradient on the surface of a scalar whose derivatives along d1 and d2 are g1 and g2. */
static vec3 surface_gradient(vec3 d1, vec3 d2, double g1, double g2)
{
    double a = v3_dot(d1, d1), b = v3_dot(d1, d2), c = v3_dot(d2, d2), det = a * c - b * b;
    if (!(fabs(det) > 1e-300))
        return v3(0, 0, 0);
    double x = (c * g1 - b * g2) / det, y = (a * g2 - b * g1) / det;
    return v3_add(v3_scale(d1, x), v3_scale(d2, y));
}

static void put3(float *a, int i, vec3 v)
{
    a[3 * i] = (float)v.x;
    a[3 * i + 1] = (float)v.y;
    a[3 * i + 2] = (float)v.z;
}

/* The limit surface as the skin mesh with its parameterisation and flow. */
static plm_result skin_from_limit(const plm_subdiv_limit *l, plm_bird_body *out, plm_error *err)
{
    plm_mesh *m = &out->skin;
    int nv = l->vertex_count, nt = 2 * l->quad_count;
    m->vertex_count = nv;
    m->triangle_count = nt;
    m->positions = malloc(sizeof(float) * 3 * (size_t)nv);
    m->normals = malloc(sizeof(float) * 3 * (size_t)nv);
    m->tangents = malloc(sizeof(float) * 3 * (size_t)nv);
    m->indices = malloc(sizeof(uint32_t) * 3 * (size_t)nt);
    out->ventral = malloc(sizeof(float) * 3 * (size_t)nv);
    out->s = malloc(sizeof(double) * (size_t)nv);
    out->around = malloc(sizeof(double) * (size_t)nv);
    if (!m->positions || !m->normals || !m->tangents || !m->indices || !out->ventral || !out->s || !out->around)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a body of %d vertices", nv);
    for (int i = 0; i < nv; ++i) {
        const double *v = l->value + WIDTH * i, *a = l->d1 + WIDTH * i, *b = l->d2 + WIDTH * i;
        vec3 d1 = v3(a[0], a[1], a[2]), d2 = v3(b[0], b[1], b[2]);
        vec3 n = v3_cross(d1, d2);
        n = v3_length(n) > 0.0 ? v3_normalize(n) : v3(0, 0, 1);
        double rr = v[4] * v[4] + v[5] * v[5], sgn = v[5] >= 0.0 ? 1.0 : -1.0;
        /* around = atan2(|sin|, cos): its derivative along each direction. */
        double ga = rr > 1e-12 ? sgn * (v[4] * a[5] - v[5] * a[4]) / rr : 0.0;
        double gb = rr > 1e-12 ? sgn * (v[4] * b[5] - v[5] * b[4]) / rr : 0.0;
        vec3 flow = surface_gradient(d1, d2, a[3], b[3]);
        flow = v3_length(flow) > 0.0 ? v3_normalize(flow) : frame_from_z(n).x;
        vec3 down = surface_gradient(d1, d2, ga, gb);
        down = v3_sub(down, v3_scale(flow, v3_dot(down, flow)));
        down = v3_length(down) > 1e-12 ? v3_normalize(down) : v3_cross(n, flow);
        put3(m->positions, i, v3_scale(v3(v[0], v[1], v[2]), MM));
        put3(m->normals, i, n);
        put3(m->tangents, i, flow);
        put3(out->ventral, i, down);
        out->s[i] = plm_clamp(v[3], 0.0, 1.0);
        out->around[i] = rr > 1e-12 ? atan2(fabs(v[5]), v[4]) : 0.0;
    }
    for (int q = 0; q < l->quad_count; ++q) {
        const int *k = l->quads + 4 * q;
        uint32_t tri[6] = {(uint32_t)k[0], (uint32_t)k[1], (uint32_t)k[2], (uint32_t)k[0], (uint32_t)k[2],
                           (uint32_t)k[3]};
        memcpy(m->indices + 6 * q, tri, sizeof tri);
    }
    return PLM_OK;
}

/* The skin vertex nearest to (s, around) on the given side (+1 left, -1 right). */
static int nearest_vertex(const plm_bird_body *b, double s, double around, double side)
{
    int best = 0;
    double bd = INFINITY;
    for (int i = 0; i < b->skin.vertex_count; ++i) {
        if (b->skin.positions[3 * i + 1] * side < 0.0)
            continue;
        double d = plm_sqr(b->s[i] - s) + plm_sqr(0.3 * (b->around[i] - around));
        if (d < bd)
            bd = d, best = i;
    }
    return best;
}

static vec3 skin_point(const plm_bird_body *b, int i) { return plm_mesh_vertex(b->skin.positions, i); }

/* Eyes on the sides of the head, shoulders over the humeral tract, the tail's base. */
static void landmarks(const plm_bird *bird, const station st[RINGS], plm_bird_body *out)
{
    out->eye_radius = 0.5 * bird->eye_diameter * MM;
    double s_eye = station_s(&st[1]) + 0.45 * (station_s(&st[2]) - station_s(&st[1]));
    for (int side = 0; side < 2; ++side) {
        double sign = side ? -1.0 : 1.0;
        int e = nearest_vertex(out, s_eye, plm_radians(68.0), sign);
        vec3 n = plm_mesh_vertex(out->skin.normals, e);
        out->eye[side] = v3_madd(skin_point(out, e), n, -0.45 * out->eye_radius);
        out->eye_normal[side] = n;
        int sh = nearest_vertex(out, station_s(&st[5]), plm_radians(70.0), sign);
        out->shoulder[side] = skin_point(out, sh);
        out->shoulder_normal[side] = plm_mesh_vertex(out->skin.normals, sh);
    }
    const station *t = &st[RINGS - 1];
    out->tail_base = v3_scale(t->c, MM);
    out->tail_direction = t->d;
    out->tail_dorsal = t->dorsal;
    out->axis = v3_normalize(v3_sub(st[RINGS - 1].c, st[4].c));
}

/* The feet grip below the breast and belly: the origin goes there. */
static void move_origin(plm_bird_body *out, const plm_bird *bird, const station st[RINGS])
{
    vec3 belly = v3_scale(v3_add(st[6].c, st[7].c), 0.5 * MM);
    double lowest = INFINITY;
    for (int i = 0; i < out->skin.vertex_count; ++i)
        lowest = fmin(lowest, out->skin.positions[3 * i + 2]);
    vec3 o = v3(belly.x, 0.0, lowest - 0.35 * bird->m.tarsus * MM);
    plm_mesh *meshes[3] = {&out->skin, &out->upper_bill, &out->lower_bill};
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < meshes[k]->vertex_count; ++i)
            put3(meshes[k]->positions, i, v3_sub(plm_mesh_vertex(meshes[k]->positions, i), o));
    for (int side = 0; side < 2; ++side) {
        out->eye[side] = v3_sub(out->eye[side], o);
        out->shoulder[side] = v3_sub(out->shoulder[side], o);
    }
    out->tail_base = v3_sub(out->tail_base, o);
}

static int region_holds(const plm_bird_region *r, double s, double around)
{
    return s >= r->s[0] && s <= r->s[1] && around >= r->around[0] - 1e-9 && around <= r->around[1] + 1e-9;
}

/* Each triangle to the last tract whose region holds its centre; bare around the eyes. */
static plm_result assign_tracts(const plm_bird *bird, plm_bird_body *out, plm_error *err)
{
    const plm_mesh *m = &out->skin;
    out->tract = malloc(sizeof(int) * (size_t)m->triangle_count);
    if (!out->tract)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for the body's tracts");
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *v = m->indices + 3 * t;
        double s = (out->s[v[0]] + out->s[v[1]] + out->s[v[2]]) / 3.0;
        double a = (out->around[v[0]] + out->around[v[1]] + out->around[v[2]]) / 3.0;
        vec3 c = v3_scale(v3_add(v3_add(skin_point(out, (int)v[0]), skin_point(out, (int)v[1])),
                                 skin_point(out, (int)v[2])), 1.0 / 3.0);
        out->tract[t] = -1;
        if (v3_length(v3_sub(c, out->eye[0])) < PLM_BIRD_EYE_RING * out->eye_radius ||
            v3_length(v3_sub(c, out->eye[1])) < PLM_BIRD_EYE_RING * out->eye_radius)
            continue;
        for (int k = 0; k < bird->tract_count; ++k)
            if (region_holds(&bird->tracts[k].region, s, a))
                out->tract[t] = k;
        if (out->tract[t] < 0)
            return plm_fail(err, PLM_ERR_INVALID, "%s: no tract covers the skin at s = %.2f, around = %.0f "
                            "degrees: the tracts must clothe the whole body", bird->name, s, plm_degrees(a));
    }
    return PLM_OK;
}

plm_result plm_bird_build(const plm_bird *bird, int level, plm_bird_body *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    station st[RINGS];
    double spine;
    stations_of(bird, st, &spine);
    const int nv = RINGS * AROUND + 2, nq = (RINGS - 1) * AROUND + AROUND;
    double values[WIDTH * (RINGS * AROUND + 2)];
    int quads[4 * ((RINGS - 1) * AROUND + AROUND)];
    build_cage(st, values, quads);
    plm_subdiv_cage cage = {nv, nq, quads, WIDTH};
    plm_subdiv_limit l = {0};
    plm_result rc = plm_subdiv_fit(&cage, values, FIT_ITERATIONS, NULL, err);
    if (rc == PLM_OK)
        rc = plm_subdiv_refine(&cage, values, level, &l, err);
    if (rc == PLM_OK)
        rc = skin_from_limit(&l, out, err);
    plm_subdiv_limit_free(&l);
    if (rc == PLM_OK) {
        landmarks(bird, st, out);
        rc = plm_bird_bill(bird, st[0].c, st[0].d, st[0].dorsal, MM, out, err);
    }
    if (rc == PLM_OK) {
        move_origin(out, bird, st);
        rc = assign_tracts(bird, out, err);
    }
    if (rc != PLM_OK)
        plm_bird_body_free(out);
    return rc;
}

void plm_bird_body_free(plm_bird_body *b)
{
    plm_mesh_free(&b->skin);
    plm_mesh_free(&b->upper_bill);
    plm_mesh_free(&b->lower_bill);
    free(b->s);
    free(b->around);
    free(b->ventral);
    free(b->tract);
    memset(b, 0, sizeof *b);
}
