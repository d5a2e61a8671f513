/* Brute-force masking reference: explicit 3D barbs and barbules traced with
 * Embree (see masking_reference.h for the scene). Independent of masking.c
 * by design: nothing here calls the analytic code. */
#include "render/masking_reference.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <stdlib.h>

#include "common/rng.h"
#include "render/embree.h"

enum { KIND_BARB, KIND_PROXIMAL, KIND_DISTAL };

/* A convex solid: an elliptic cylinder (points whose offset from the axis line
 * through `origin` along `axis` has coordinates (p, q) on (e2, e3) with
 * (p / r2)^2 + (q / r3)^2 <= 1) cut to the slab lo <= x . slab <= hi. */
typedef struct solid {
    vec3 origin, axis, e2, e3, slab;
    double r2, r3, lo, hi;
    int kind;
} solid;

struct plm_masking_reference {
    plm_embree embree;
    RTCScene scene;
    solid *solids;
    unsigned count;
    double x0, x1, z1;      /* one period: x in [x0, x1), z in [0, z1) */
    double y0, y1;          /* every solid lies in y in [y0, y1] */
};

void plm_masking_reference_options_default(plm_masking_reference_options *o)
{
    o->barbs = 16;
    o->pitch = 0.005;
    o->length = 2.0;
    o->layout_seed = 1;
}

/* Entry distance of the ray o + t v into the solid, if it is in (tnear, tfar). */
static int solid_entry(const solid *s, vec3 o, vec3 v, double tnear, double tfar, double *t_hit)
{
    vec3 q = v3_sub(o, s->origin);
    double qp = v3_dot(q, s->e2) / s->r2, qq = v3_dot(q, s->e3) / s->r3;
    double vp = v3_dot(v, s->e2) / s->r2, vq = v3_dot(v, s->e3) / s->r3;
    double a = vp * vp + vq * vq, b = qp * vp + qq * vq, c = qp * qp + qq * qq - 1.0;
    double t0 = -INFINITY, t1 = INFINITY;
    if (a > 1e-300) {
        double disc = b * b - a * c;
        if (disc < 0.0)
            return 0;
        double root = sqrt(disc);
        t0 = (-b - root) / a;
        t1 = (-b + root) / a;
    } else if (c > 0.0) {
        return 0; /* parallel to the axis and outside */
    }
    double xo = v3_dot(o, s->slab), xv = v3_dot(v, s->slab);
    if (fabs(xv) > 1e-300) {
        double s0 = (s->lo - xo) / xv, s1 = (s->hi - xo) / xv;
        t0 = fmax(t0, fmin(s0, s1));
        t1 = fmin(t1, fmax(s0, s1));
    } else if (xo < s->lo || xo > s->hi) {
        return 0;
    }
    if (t0 > t1 || t0 < tnear || t0 > tfar)
        return 0;
    *t_hit = t0;
    return 1;
}

static void solid_bounds_cb(const struct RTCBoundsFunctionArguments *args)
{
    const solid *s = (const solid *)args->geometryUserPtr + args->primID;
    /* Axis points where it meets the slab's planes, pushed out by how far the
     * cross-section reaches along the slab normal, then widened by the
     * cross-section's extent along each world axis. */
    double an = v3_dot(s->axis, s->slab), on = v3_dot(s->origin, s->slab);
    double reach = sqrt(plm_sqr(s->r2 * v3_dot(s->e2, s->slab)) + plm_sqr(s->r3 * v3_dot(s->e3, s->slab)));
    double l0 = (s->lo - reach - on) / an, l1 = (s->hi + reach - on) / an;
    vec3 p0 = v3_madd(s->origin, s->axis, l0), p1 = v3_madd(s->origin, s->axis, l1);
    double ext[3] = {sqrt(plm_sqr(s->r2 * s->e2.x) + plm_sqr(s->r3 * s->e3.x)),
                     sqrt(plm_sqr(s->r2 * s->e2.y) + plm_sqr(s->r3 * s->e3.y)),
                     sqrt(plm_sqr(s->r2 * s->e2.z) + plm_sqr(s->r3 * s->e3.z))};
    double pad = 1e-6;
    args->bounds_o->lower_x = (float)(fmin(p0.x, p1.x) - ext[0] - pad);
    args->bounds_o->lower_y = (float)(fmin(p0.y, p1.y) - ext[1] - pad);
    args->bounds_o->lower_z = (float)(fmin(p0.z, p1.z) - ext[2] - pad);
    args->bounds_o->upper_x = (float)(fmax(p0.x, p1.x) + ext[0] + pad);
    args->bounds_o->upper_y = (float)(fmax(p0.y, p1.y) + ext[1] + pad);
    args->bounds_o->upper_z = (float)(fmax(p0.z, p1.z) + ext[2] + pad);
}

static void solid_intersect_cb(const struct RTCIntersectFunctionNArguments *args)
{
    if (!args->valid[0])
        return;
    struct RTCRayHit *rh = (struct RTCRayHit *)args->rayhit; /* single rays only (rtcIntersect1) */
    const solid *s = (const solid *)args->geometryUserPtr + args->primID;
    vec3 o = v3(rh->ray.org_x, rh->ray.org_y, rh->ray.org_z), v = v3(rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z);
    double t;
    if (!solid_entry(s, o, v, rh->ray.tnear, rh->ray.tfar, &t))
        return;
    rh->ray.tfar = (float)t;
    rh->hit.geomID = args->geomID;
    rh->hit.primID = args->primID;
    rh->hit.u = rh->hit.v = 0.0f;
    rh->hit.Ng_x = rh->hit.Ng_y = rh->hit.Ng_z = 0.0f;
    rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

/* A barbule set's axis and cross-section axes, built from the arrangement
 * (side +1 distal, -1 proximal): the row is the plane through the barb axis
 * t = z and the direction p that rises at theta_bb across the barb's side;
 * a barbule runs at phi_bb from t within it; e3 is the row plane's normal on
 * the dorsal side, e2 = e3 x axis lies in the row across the barbules. */
static void barbule_axes(const plm_masking_params *p, double side, vec3 *axis, vec3 *e2, vec3 *e3)
{
    vec3 t = v3(0.0, 0.0, 1.0);
    vec3 across = v3(side * cos(p->barbule_inclination), sin(p->barbule_inclination), 0.0);
    *axis = v3_add(v3_scale(across, sin(p->barbule_rotation)), v3_scale(t, cos(p->barbule_rotation)));
    *e3 = v3_normalize(v3_cross(t, across));
    if (e3->y < 0.0)
        *e3 = v3_neg(*e3);
    *e2 = v3_cross(*e3, *axis);
}

/* Appends the barbules of one set of barb j, and their copies one period
 * along z where they cross the scene's z boundary. */
static unsigned add_barbule_set(solid *out, const plm_masking_params *p, const plm_masking_reference_options *o,
                                double w, int j, double side, double phase)
{
    vec3 axis, e2, e3;
    barbule_axes(p, side, &axis, &e2, &e3);
    double radius = o->pitch / (2.0 * (1.0 + p->barbule_separation));
    double spacing = o->pitch / sqrt(1.0 - plm_sqr(axis.z));
    double root_x = j + side * w, ridge_x = j + side * 0.5;
    /* how far along z a barbule runs from its root to the ridge, plus its radius */
    double run = fabs((ridge_x - root_x) * axis.z / axis.x) + radius * (1.0 + p->barbule_eccentricity);
    unsigned n = 0;
    for (double z = phase * spacing; z < o->length; z += spacing)
        for (int copy = 0; copy < 2; ++copy) {
            double zc = copy ? z - o->length : z;
            if (copy && z + run < o->length)
                continue;
            solid *s = &out[n++];
            s->origin = v3(root_x, 0.0, zc);
            s->axis = axis;
            s->e2 = e2;
            s->e3 = e3;
            s->r2 = radius;
            s->r3 = radius * p->barbule_eccentricity;
            s->slab = v3(1.0, 0.0, 0.0);
            s->lo = fmin(root_x, ridge_x);
            s->hi = fmax(root_x, ridge_x);
            s->kind = side > 0.0 ? KIND_DISTAL : KIND_PROXIMAL;
        }
    return n;
}

static plm_result build_solids(plm_masking_reference *ref, const plm_masking_params *p,
                               const plm_masking_reference_options *o, plm_error *err)
{
    double w = 0.5 / (1.0 + p->barbule_length * cos(p->barbule_inclination));
    vec3 axis, e2, e3;
    barbule_axes(p, 1.0, &axis, &e2, &e3);
    double spacing = o->pitch / sqrt(1.0 - plm_sqr(axis.z));
    size_t per_set = (size_t)(o->length / spacing) + 2;
    size_t capacity = (size_t)o->barbs * (1 + 2 * 2 * per_set);
    ref->solids = malloc(capacity * sizeof(solid));
    if (!ref->solids)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "masking reference: no memory for %zu solids", capacity);
    plm_rng rng;
    plm_rng_seed(&rng, o->layout_seed, 0x6d61736bu);
    unsigned n = 0;
    for (int j = 0; j < o->barbs; ++j) {
        solid *b = &ref->solids[n++];
        b->origin = v3(j, 0.0, 0.0);
        b->axis = v3(0.0, 0.0, 1.0);
        b->e2 = v3(1.0, 0.0, 0.0);
        b->e3 = v3(0.0, 1.0, 0.0);
        b->r2 = w;
        b->r3 = w * p->barb_eccentricity;
        b->slab = v3(0.0, 0.0, 1.0);
        b->lo = -1.0;
        b->hi = o->length + 1.0;
        b->kind = KIND_BARB;
        n += add_barbule_set(ref->solids + n, p, o, w, j, 1.0, plm_rng_uniform(&rng));
        n += add_barbule_set(ref->solids + n, p, o, w, j, -1.0, plm_rng_uniform(&rng));
    }
    ref->count = n;
    ref->x0 = -0.5;
    ref->x1 = o->barbs - 0.5;
    ref->z1 = o->length;
    /* vertical extent: barb tops and bottoms and the ridges (valleys, if
     * the rows fall), with the barbules' thickness and a margin */
    double rise = (0.5 - w) * axis.y / axis.x;
    double thick = o->pitch * (1.0 + p->barbule_eccentricity), hb = w * p->barb_eccentricity;
    ref->y1 = fmax(hb, fmax(rise, 0.0) + thick) + 0.01;
    ref->y0 = -fmax(hb, fmax(-rise, 0.0) + thick) - 0.01;
    return PLM_OK;
}

plm_result plm_masking_reference_create(const plm_masking_params *p, const plm_masking_reference_options *options,
                                        plm_masking_reference **out, plm_error *err)
{
    *out = NULL;
    plm_result r = plm_masking_params_validate(p, err);
    if (r != PLM_OK)
        return r;
    if (p->barbule_rotation < plm_radians(1.0))
        return plm_fail(err, PLM_ERR_INVALID,
                        "masking reference: barbule_rotation must be at least 1 deg (barbules along the barb never "
                        "reach the ridge)");
    plm_masking_reference_options o;
    plm_masking_reference_options_default(&o);
    if (options)
        o = *options;
    if (o.barbs < 2 || o.barbs > 4096 || !(o.pitch >= 1e-4 && o.pitch <= 0.1) || !(o.length >= 0.5 && o.length <= 100))
        return plm_fail(err, PLM_ERR_INVALID,
                        "masking reference: options out of range (barbs [2, 4096], pitch [1e-4, 0.1], length [0.5, 100])");
    plm_masking_reference *ref = calloc(1, sizeof *ref);
    if (!ref)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "masking reference: no memory");
    if ((r = build_solids(ref, p, &o, err)) != PLM_OK) {
        plm_masking_reference_destroy(ref);
        return r;
    }
    if ((r = plm_embree_open(&ref->embree, 0, err)) != PLM_OK) {
        plm_masking_reference_destroy(ref);
        return r;
    }
    ref->scene = rtcNewScene(ref->embree.device);
    RTCGeometry geom = rtcNewGeometry(ref->embree.device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, ref->count);
    rtcSetGeometryUserData(geom, ref->solids);
    rtcSetGeometryBoundsFunction(geom, solid_bounds_cb, NULL);
    rtcSetGeometryIntersectFunction(geom, solid_intersect_cb);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(ref->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(ref->scene);
    if ((r = plm_embree_check(&ref->embree, "masking reference", err)) != PLM_OK) {
        plm_masking_reference_destroy(ref);
        return r;
    }
    *out = ref;
    return PLM_OK;
}

void plm_masking_reference_destroy(plm_masking_reference *ref)
{
    if (!ref)
        return;
    if (ref->scene)
        rtcReleaseScene(ref->scene);
    plm_embree_close(&ref->embree);
    free(ref->solids);
    free(ref);
}

/* h of a hit point on a solid for view direction wo (as in masking.h): the
 * point's offset along (d_y, -d_x) over the solid's projected half-width. */
static double hit_h(const solid *s, vec3 p, vec3 wo)
{
    vec3 q = v3_sub(p, s->origin);
    double dx = v3_dot(wo, s->e2), dy = v3_dot(wo, s->e3);
    double len = sqrt(dx * dx + dy * dy);
    if (!(len > 1e-12))
        return 0.0;
    double offset = (v3_dot(q, s->e2) * dy - v3_dot(q, s->e3) * dx) / len;
    double half = sqrt(plm_sqr(s->r2 * dy) + plm_sqr(s->r3 * dx)) / len;
    return plm_clamp(offset / half, -1.0, 1.0);
}

/* Follows one ray through the periodic scene; returns the kind hit first, or
 * -1 when it leaves through the far side, and the hit's h. */
static int trace(const plm_masking_reference *ref, vec3 o, vec3 v, vec3 wo, double *h)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (int crossings = 0; crossings < 1000000; ++crossings) {
        /* distance to the faces ahead along x, z and y */
        double tx = v.x > 0.0 ? (ref->x1 - o.x) / v.x : v.x < 0.0 ? (ref->x0 - o.x) / v.x : INFINITY;
        double tz = v.z > 0.0 ? (ref->z1 - o.z) / v.z : v.z < 0.0 ? (0.0 - o.z) / v.z : INFINITY;
        double ty = v.y > 0.0 ? (ref->y1 - o.y) / v.y : (ref->y0 - o.y) / v.y;
        double t_exit = fmax(0.0, fmin(tx, fmin(tz, ty)));
        struct RTCRayHit rh;
        rh.ray.org_x = (float)o.x;
        rh.ray.org_y = (float)o.y;
        rh.ray.org_z = (float)o.z;
        rh.ray.dir_x = (float)v.x;
        rh.ray.dir_y = (float)v.y;
        rh.ray.dir_z = (float)v.z;
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = (float)t_exit;
        rh.ray.time = 0.0f;
        rh.ray.mask = 0xffffffffu;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(ref->scene, &ctx, &rh);
        if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
            const solid *s = &ref->solids[rh.hit.primID];
            vec3 org = v3(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z);
            *h = hit_h(s, v3_madd(org, v, rh.ray.tfar), wo);
            return s->kind;
        }
        if (ty <= tx && ty <= tz)
            return -1; /* left through the far side of the vane */
        o = v3_madd(o, v, t_exit);
        /* wrap around every face reached (corners reach two) */
        if (tx <= t_exit)
            o.x += v.x > 0.0 ? ref->x0 - ref->x1 : ref->x1 - ref->x0;
        if (tz <= t_exit)
            o.z += v.z > 0.0 ? -ref->z1 : ref->z1;
    }
    return -2;
}

/* Hits are uniform in h over what is visible, so the interval is read off
 * their histogram, leaving out H_TRIM of the hits at each end: rays that
 * slip past the cut ends of a barbule row (where a neighbour is missing) or
 * the wedge between a barb and its barbules' roots would otherwise stretch
 * it. Each end is accurate to about one bin plus H_TRIM of its width. */
#define H_BINS 400
#define H_TRIM 0.01
static void h_interval(const double *histogram, double count, double *lo, double *hi)
{
    *lo = *hi = 0.0;
    if (count <= 0.0)
        return;
    double below = 0.0;
    int first = 0, last = H_BINS - 1;
    while (first < H_BINS - 1 && below + histogram[first] <= H_TRIM * count)
        below += histogram[first++];
    double above = 0.0;
    while (last > first && above + histogram[last] <= H_TRIM * count)
        above += histogram[last--];
    *lo = -1.0 + 2.0 * first / H_BINS;
    *hi = -1.0 + 2.0 * (last + 1) / H_BINS;
}

plm_result plm_masking_reference_eval(const plm_masking_reference *ref, vec3 wo, unsigned samples, uint64_t seed,
                                      plm_masking *out, plm_error *err)
{
    double len = v3_length(wo);
    if (!(len > 0.0) || !isfinite(len))
        return plm_fail(err, PLM_ERR_INVALID, "masking reference: the view direction must be finite and non-zero");
    wo = v3_scale(wo, 1.0 / len);
    if (fabs(wo.y) < 1e-6)
        return plm_fail(err, PLM_ERR_INVALID,
                        "masking reference: a view within 1e-6 of the vane plane never leaves the scene");
    vec3 v = v3_neg(wo);
    double start_y = wo.y > 0.0 ? ref->y1 : ref->y0;
    /* jittered grid over one period of the start plane, cells about square */
    double span_x = ref->x1 - ref->x0;
    unsigned nx = (unsigned)ceil(sqrt((double)samples * span_x / ref->z1));
    if (nx < 1)
        nx = 1;
    unsigned nz = (samples + nx - 1) / nx;
    plm_rng rng;
    plm_rng_seed(&rng, seed, 0x7265664dULL);
    double count[3] = {0, 0, 0}, through = 0.0;
    static const int bins = H_BINS;
    double histogram[3][H_BINS] = {{0}};
    for (unsigned iz = 0; iz < nz; ++iz)
        for (unsigned ix = 0; ix < nx; ++ix) {
            double x = ref->x0 + span_x * (ix + plm_rng_uniform(&rng)) / nx;
            double z = ref->z1 * (iz + plm_rng_uniform(&rng)) / nz;
            double h = 0.0;
            int kind = trace(ref, v3(x, start_y, z), v, wo, &h);
            if (kind == -2)
                return plm_fail(err, PLM_ERR_INTERNAL, "masking reference: a ray never left the scene");
            if (kind < 0) {
                through += 1.0;
                continue;
            }
            count[kind] += 1.0;
            int bin = (int)((h + 1.0) * 0.5 * bins);
            histogram[kind][bin < 0 ? 0 : bin >= bins ? bins - 1 : bin] += 1.0;
        }
    double n = (double)nx * (double)nz;
    double hlo[3], hhi[3];
    for (int k = 0; k < 3; ++k)
        h_interval(histogram[k], count[k], &hlo[k], &hhi[k]);
    out->w_barb = count[KIND_BARB] / n;
    out->w_proximal = count[KIND_PROXIMAL] / n;
    out->w_distal = count[KIND_DISTAL] / n;
    out->w_transmission = through / n;
    out->proximal = (plm_h_range){hlo[KIND_PROXIMAL], hhi[KIND_PROXIMAL], out->w_proximal};
    out->distal = (plm_h_range){hlo[KIND_DISTAL], hhi[KIND_DISTAL], out->w_distal};
    out->barb_range_count = count[KIND_BARB] > 0.0;
    out->barb[0] = (plm_h_range){hlo[KIND_BARB], hhi[KIND_BARB], out->w_barb};
    return PLM_OK;
}
