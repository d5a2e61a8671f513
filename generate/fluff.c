#include "generate/fluff.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/rng.h"
#include "generate/geometry.h"

/* The shapes below are judgements from photographs of contour feathers'
 * bases and afterfeathers, not measurements. */
#define TIP_RADIUS 0.25          /* a barb's radius at its end, of its root's */
#define ELEVATION_SD 0.45        /* radians: how far a down barb leaves the vane plane (SD) */
#define BARBULE_ANGLE 0.6        /* radians between a barbule and its barb */
#define BARBULE_LENGTH 0.25      /* of its barb's length at the barb's root, half that at its end */
#define BARBULE_RADIUS 0.4       /* of its barb's radius where it leaves */
#define HYPORACHIS_ANGLE 0.26    /* radians between the afterfeather's shaft and the rachis, ventral */
#define HYPORACHIS_RADIUS 0.35   /* its root radius, of the rachis's there */
#define AFTER_BARB_ANGLE 0.75    /* radians between an afterfeather barb and its shaft */
#define AFTER_BARB_LENGTH 0.45   /* an afterfeather barb's longest, of the afterfeather's length */

#define FLUFF_STREAM 0xf1ffu /* the fluff's own stream of the feather's seed */

typedef struct builder {
    plm_curves *c;
    int point_capacity, first_capacity, tag_capacity;
    plm_rng rng;
    const plm_outline *o;
} builder;

static int grow(void **p, int *capacity, int need, size_t size)
{
    if (need <= *capacity)
        return 1;
    int cap = *capacity ? *capacity : 1024;
    while (cap < need)
        cap *= 2;
    void *q = realloc(*p, (size_t)cap * size);
    if (!q)
        return 0;
    *p = q;
    *capacity = cap;
    return 1;
}

/* Appends a curve of n points (with radii); 0 when out of memory. */
static int add_curve(builder *b, const vec3 *p, const double *r, int n, plm_fluff_kind kind)
{
    plm_curves *c = b->c;
    if (!grow((void **)&c->points, &b->point_capacity, c->point_count + n, 4 * sizeof(float)) ||
        !grow((void **)&c->first, &b->first_capacity, c->curve_count + 2, sizeof(int)) ||
        !grow((void **)&c->tag, &b->tag_capacity, c->curve_count + 2, 1))
        return 0;
    for (int i = 0; i < n; ++i) {
        float *q = c->points + 4 * (size_t)(c->point_count + i);
        q[0] = (float)p[i].x, q[1] = (float)p[i].y, q[2] = (float)p[i].z, q[3] = (float)r[i];
    }
    c->first[c->curve_count] = c->point_count;
    c->tag[c->curve_count] = (unsigned char)kind;
    c->point_count += n;
    c->curve_count++;
    c->first[c->curve_count] = c->point_count;
    return 1;
}

static double uniform(builder *b, double lo, double hi) { return lo + (hi - lo) * plm_rng_uniform(&b->rng); }

static double gaussian(builder *b)
{
    double u = 1.0 - plm_rng_uniform(&b->rng), v = plm_rng_uniform(&b->rng);
    return sqrt(-2.0 * log(u)) * cos(PLM_TWO_PI * v);
}

/* d turned by a Gaussian angle of deviation sd about a random axis across it. */
static vec3 wander(builder *b, vec3 d, double sd)
{
    frame f = frame_from_z(d);
    double a = uniform(b, 0.0, PLM_TWO_PI);
    vec3 axis = v3_add(v3_scale(f.x, cos(a)), v3_scale(f.y, sin(a)));
    return v3_normalize(v3_rotate(d, axis, sd * gaussian(b)));
}

/* The point and radius a fraction s along a polyline of n points. */
static vec3 along(const vec3 *p, const double *r, int n, double s, double *radius)
{
    double x = s * (n - 1);
    int i = (int)fmin(floor(x), n - 2);
    double f = x - i;
    *radius = r[i] + f * (r[i + 1] - r[i]);
    return v3_add(p[i], v3_scale(v3_sub(p[i + 1], p[i]), f));
}

/* A curling fiber of n points from root along d0: a random walk of the
 * direction whose turns add up to `curl` (RMS) over its length, the radius
 * thinning linearly from r0 to TIP_RADIUS r0. */
static void walk(builder *b, vec3 root, vec3 d0, double length, double r0, double curl, int n, vec3 *p, double *r)
{
    double step = length / (n - 1), sd = curl / sqrt((double)(n - 1));
    vec3 d = d0;
    p[0] = root;
    r[0] = r0;
    for (int i = 1; i < n; ++i) {
        d = wander(b, d, sd);
        p[i] = v3_madd(p[i - 1], d, step);
        r[i] = r0 * (1.0 - (1.0 - TIP_RADIUS) * i / (n - 1));
    }
}

/* A barb of n points and its barbules, leaving the barb on alternate sides
 * at angle BARBULE_ANGLE, shorter toward its end. */
static int barb_with_barbules(builder *b, vec3 root, vec3 d0, double length, double r0, plm_fluff_kind kind)
{
    const plm_shape *sh = &b->o->shape;
    vec3 p[PLM_FLUFF_BARB_POINTS], q[PLM_FLUFF_BARBULE_POINTS];
    double r[PLM_FLUFF_BARB_POINTS], qr[PLM_FLUFF_BARBULE_POINTS];
    walk(b, root, d0, length, r0, sh->fluff_curl, PLM_FLUFF_BARB_POINTS, p, r);
    if (!add_curve(b, p, r, PLM_FLUFF_BARB_POINTS, kind))
        return 0;
    int count = (int)floor(sh->fluff_barbules * length + plm_rng_uniform(&b->rng));
    for (int k = 0; k < count; ++k) {
        double s = (k + uniform(b, 0.2, 0.8)) / count, radius;
        vec3 at = along(p, r, PLM_FLUFF_BARB_POINTS, s, &radius);
        int i = (int)fmin(floor(s * (PLM_FLUFF_BARB_POINTS - 1)), PLM_FLUFF_BARB_POINTS - 2);
        vec3 t = v3_normalize(v3_sub(p[i + 1], p[i]));
        frame f = frame_from_z(t);
        double a = (k % 2 ? PLM_PI : 0.0) + uniform(b, -0.8, 0.8); /* alternate sides, each its own way */
        vec3 side = v3_add(v3_scale(f.x, cos(a)), v3_scale(f.y, sin(a)));
        vec3 d = v3_normalize(v3_add(v3_scale(t, cos(BARBULE_ANGLE)), v3_scale(side, sin(BARBULE_ANGLE))));
        double l = BARBULE_LENGTH * length * (1.0 - 0.5 * s) * uniform(b, 0.7, 1.3);
        walk(b, at, d, l, BARBULE_RADIUS * radius, sh->fluff_curl, PLM_FLUFF_BARBULE_POINTS, q, qr);
        if (!add_curve(b, q, qr, PLM_FLUFF_BARBULE_POINTS, PLM_FLUFF_BARBULE))
            return 0;
    }
    return 1;
}

/* d lifted out of the plane across `normal` by a random elevation. */
static vec3 lift(builder *b, vec3 d, vec3 normal)
{
    return v3_normalize(v3_rotate(d, v3_normalize(v3_cross(d, normal)), ELEVATION_SD * gaussian(b)));
}

/* The down barbs of the vane's base, each side: roots on the rachis's edge
 * every 1/density cm (jittered), out to the end of the downy base. */
static int vane_down(builder *b)
{
    const plm_outline *o = b->o;
    const plm_shape *sh = &o->shape;
    double spacing = 10.0 / sh->fluff_density, down = sh->plumulaceous * o->vane_length;
    double end = fmin(o->vane_base + down, o->rachis_end);
    for (int side = 0; side < 2; ++side)
        for (double y0 = o->vane_base; y0 < end; y0 += spacing) {
            double y = fmin(y0 + spacing * uniform(b, 0.15, 0.85), end);
            double t = (y - o->vane_base) / o->vane_length, s = (y - o->vane_base) / down;
            plm_rachis_frame f = plm_rachis_frame_at(o, y);
            vec3 out = side ? f.x : v3_neg(f.x);
            vec3 root = v3_madd(f.c, out, plm_outline_rachis_radius(o, y));
            double theta = plm_outline_barb_angle(o, side, y);
            vec3 d = lift(b, v3_add(v3_scale(out, sin(theta)), v3_scale(f.t, cos(theta))), f.z);
            /* Shorter toward the base, as the downy barbs of real feathers are. */
            double length = sh->fluff_length * plm_outline_width(o, side, t) * (0.6 + 0.4 * s) * uniform(b, 0.8, 1.2);
            if (!barb_with_barbules(b, root, d, length, 0.5 * sh->fluff_thickness, PLM_FLUFF_DOWN))
                return 0;
        }
    return 1;
}

/* The afterfeather: its shaft from the rachis's underside at the top of the
 * calamus, turned ventrally, gently curling, and down barbs on both sides,
 * longest in its middle like a small plume. */
static int afterfeather(builder *b)
{
    const plm_outline *o = b->o;
    const plm_shape *sh = &o->shape;
    enum { N = PLM_FLUFF_BARB_POINTS };
    double y = o->vane_base, length = sh->afterfeather_size * sh->length, r = plm_outline_rachis_radius(o, y);
    plm_rachis_frame f = plm_rachis_frame_at(o, y);
    vec3 root = v3_madd(f.c, f.z, -r);
    vec3 d = v3_rotate(f.t, f.x, HYPORACHIS_ANGLE); /* about +x: the tip side turns toward -z */
    vec3 p[N];
    double pr[N];
    walk(b, root, d, length, HYPORACHIS_RADIUS * r, 0.25 * sh->fluff_curl, N, p, pr);
    if (!add_curve(b, p, pr, N, PLM_FLUFF_HYPORACHIS))
        return 0;
    double spacing = 10.0 / sh->fluff_density;
    for (int side = 0; side < 2; ++side)
        for (double a = 0.08 * length; a < length; a += spacing) {
            double s = fmin((a + spacing * uniform(b, 0.0, 0.7)) / length, 1.0), radius;
            vec3 at = along(p, pr, N, s, &radius);
            int i = (int)fmin(floor(s * (N - 1)), N - 2);
            vec3 t = v3_normalize(v3_sub(p[i + 1], p[i]));
            vec3 across = v3_normalize(v3_sub(f.x, v3_scale(t, v3_dot(f.x, t))));
            vec3 out = side ? across : v3_neg(across);
            vec3 bd = lift(b, v3_add(v3_scale(out, sin(AFTER_BARB_ANGLE)), v3_scale(t, cos(AFTER_BARB_ANGLE))),
                           v3_cross(across, t));
            double l = AFTER_BARB_LENGTH * length * fmax(0.3, sin(PLM_PI * (0.15 + 0.8 * s))) * uniform(b, 0.8, 1.2);
            if (!barb_with_barbules(b, v3_madd(at, out, radius), bd, l, 0.5 * sh->fluff_thickness,
                                    PLM_FLUFF_AFTERFEATHER))
                return 0;
        }
    return 1;
}

plm_result plm_fluff_curves(const plm_outline *o, plm_curves *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    const plm_shape *sh = &o->shape;
    if (!(sh->fluff_density > 0.0))
        return PLM_OK;
    builder b = {out, 0, 0, 0, {0, 0}, o};
    plm_rng_seed(&b.rng, sh->seed, FLUFF_STREAM);
    int ok = (sh->plumulaceous > 0.0 ? vane_down(&b) : 1) && (sh->afterfeather ? afterfeather(&b) : 1);
    if (!ok) {
        plm_curves_free(out);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for the fluff's curves");
    }
    return PLM_OK;
}
