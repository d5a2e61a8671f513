/* The wing layout (generate/wing.h): rows of flight feathers and coverts on
 * a three-bone skeleton, settled onto one another in dorsal order. The
 * reasoning behind the rows, the roll and the settling is in
 * docs/layouts.md. */
#include "generate/wing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/rng.h"
#include "generate/layout_parts.h"

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

static double raster_instance(height_grid *g, const plm_layout_instance *in, const plm_layout_extent *e, int mode)
{
    double need = -INFINITY;
    for (int k = 0; k < 2; ++k) {
        const plm_mesh *m = &e->mesh[k];
        for (int t = 0; t < m->triangle_count; ++t) {
            const uint32_t *v = m->indices + 3 * t;
            vec3 a = plm_layout_apply(in, m->positions + 3 * v[0]), b = plm_layout_apply(in, m->positions + 3 * v[1]),
                 c = plm_layout_apply(in, m->positions + 3 * v[2]);
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

static void settle(height_grid *g, plm_layout_instance *in, const plm_layout_extent *e, double clearance)
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
        double z = plm_layout_apply(&t, middle).z;
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
    plm_layout_extent *ext = NULL;
    height_grid g = {0};
    plm_result rc = w.f && out->instances ? PLM_OK : plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a wing");
    if (rc == PLM_OK)
        rc = plm_layout_make_prototypes(list, PLM_WING_ROWS, variants, p->seed, out, &ext, err);
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
    plm_layout_ranges var = plm_layout_ranges_of(&p->variation);
    /* The rows' sizes and directions are the wing's shape: variation stays small. */
    var.scale *= 0.3;
    var.yaw *= 0.3;
    double roll = plm_radians(WING_ROLL_DEGREES);
    for (int i = 0; rc == PLM_OK && i < w.count; ++i) {
        const wing_feather *f = &w.f[i];
        plm_layout_instance *in = &out->instances[i];
        plm_rng rng;
        plm_rng_seed(&rng, plm_hash64(p->seed, (uint64_t)i, 1), PLM_LAYOUT_STREAM_FEATHER);
        int v = (int)(plm_rng_uniform(&rng) * variants);
        in->prototype = f->row * variants + v;
        in->row = f->row;
        in->order = i;
        plm_layout_draw_variation(&rng, &var, in);
        in->lift = 0.0;
        const plm_layout_extent *e = &ext[in->prototype];
        vec3 t = planar(f->direction + in->yaw), up = v3(0, 0, 1), x0 = v3_cross(t, up);
        vec3 x = v3_sub(v3_scale(x0, cos(roll)), v3_scale(up, sin(roll)));
        vec3 z = v3_add(v3_scale(x0, sin(roll)), v3_scale(up, cos(roll)));
        /* Folding stacks the flight feathers, each a little above the ones
         * before, so that they overlap in order; the coverts and the alula
         * start from the wing plane and settle onto what lies beneath. */
        double stack = i < w.flight ? p->fold * i * 0.002 * chord : 0.0;
        vec3 root = v3_madd(f->root, up, stack);
        plm_layout_set_matrix(in, x, t, z, root, in->scale * f->length / e->length);
        if (i >= w.flight)
            settle(&g, in, e, 0.004 * chord);
        raster_instance(&g, in, e, 0);
    }
    if (rc == PLM_OK)
        out->instance_count = w.count;
    plm_layout_extents_free(ext, out->prototype_count);
    free(g.z);
    free(w.f);
    if (rc != PLM_OK)
        plm_layout_free(out);
    return rc;
}
