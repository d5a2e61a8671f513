/* The fiber tracer: exact geometric optics in an infinite elliptical
 * cylinder (paper Sec. 5.2, Eq. 3).
 *
 * The cylinder is invariant along its axis, so a path is a 2D position in the
 * cross-section plus a 3D direction. Ray parameters are 3D lengths (the
 * direction is a unit 3D vector), which is what Beer-Lambert needs. Interface
 * normals lie in the cross-section, so 3D vector Snell with them is exactly
 * the Bravais formulation (projected index for the azimuth, Snell for the
 * longitudinal angle), and 3D Fresnel at the true angle of incidence is the
 * exact unpolarised reflectance. */
#include "optics/fiber_trace.h"

/* ---- optics -------------------------------------------------------------- */

/* Unpolarised Fresnel reflectance for cos_i > 0 and eta = n_t / n_i (inv_eta2
 * = 1 / eta^2); also returns cos_t (meaningless under total internal
 * reflection, which gives 1). The two amplitude ratios share one division. */
static double fresnel(double cos_i, double eta, double inv_eta2, double *cos_t)
{
    double sin2_t = (1.0 - cos_i * cos_i) * inv_eta2;
    if (sin2_t >= 1.0) {
        *cos_t = 0.0;
        return 1.0;
    }
    double ct = sqrt(1.0 - sin2_t);
    double s_num = cos_i - eta * ct, s_den = cos_i + eta * ct; /* r_s = s_num / s_den */
    double p_num = eta * cos_i - ct, p_den = eta * cos_i + ct; /* r_p = p_num / p_den */
    *cos_t = ct;
    double sp = s_den * p_den;
    return 0.5 * (plm_sqr(s_num * p_den) + plm_sqr(p_num * s_den)) / (sp * sp);
}

double plm_fiber_fresnel(double cos_i, double eta)
{
    double cos_t;
    return fresnel(cos_i, eta, 1.0 / (eta * eta), &cos_t);
}

/* Refraction of d through an interface with normal n on the incident side
 * (n.d = -cos_i), n_i/n_t = ratio. */
static vec3 refract(vec3 d, vec3 n, double cos_i, double cos_t, double ratio)
{
    return v3_madd(v3_scale(d, ratio), n, ratio * cos_i - cos_t);
}

static vec3 reflect(vec3 d, vec3 n) { return v3_madd(d, n, -2.0 * v3_dot(d, n)); }

/* ---- geometry ------------------------------------------------------------ */

/* An ellipse with centre (cx, cy) and semi-axes a, b along x, y; "unit-circle
 * coordinates" of a point are ((x - cx) / a, (y - cy) / b). The inverses save
 * divisions in the inner loop. */
typedef struct ellipse { double cx, cy, a, b, inv_a, inv_b; } ellipse;

static ellipse ellipse_make(double cx, double cy, double a, double b)
{
    ellipse el = {cx, cy, a, b, a > 0.0 ? 1.0 / a : 0.0, b > 0.0 ? 1.0 / b : 0.0};
    return el;
}

/* Outward unit normal (in the cross-section) at a point of the ellipse given
 * in its unit-circle coordinates (X, Y). */
static vec3 ellipse_normal(const ellipse *el, double X, double Y)
{
    double nx = X * el->inv_a, ny = Y * el->inv_b, inv = 1.0 / sqrt(nx * nx + ny * ny);
    return v3(nx * inv, ny * inv, 0.0);
}

/* Distance along d from pos (inside or on the ellipse; on_boundary says
 * which, so rounding cannot make the start point count as outside) to where
 * the ray leaves it; 0 if it does not get anywhere (tangent). */
static double ellipse_exit(const ellipse *el, vec2 pos, vec3 d, int on_boundary)
{
    double X = (pos.x - el->cx) * el->inv_a, Y = (pos.y - el->cy) * el->inv_b;
    double DX = d.x * el->inv_a, DY = d.y * el->inv_b;
    double A = DX * DX + DY * DY, B = X * DX + Y * DY;
    if (!(A > 0.0))
        return 0.0; /* travelling along the axis: never reaches the boundary */
    if (on_boundary)
        return B < 0.0 ? -2.0 * B / A : 0.0;
    double C = X * X + Y * Y - 1.0;
    C = C < 0.0 ? C : 0.0; /* inside, up to rounding */
    double root = sqrt(B * B - A * C);
    return B <= 0.0 ? (root - B) / A : -C / (B + root); /* the two stable forms of the far root */
}

/* Distance along d from pos (outside the ellipse) to where the ray enters it,
 * or INFINITY when it misses. */
static double ellipse_enter(const ellipse *el, vec2 pos, vec3 d)
{
    double X = (pos.x - el->cx) * el->inv_a, Y = (pos.y - el->cy) * el->inv_b;
    double DX = d.x * el->inv_a, DY = d.y * el->inv_b;
    double A = DX * DX + DY * DY, B = X * DX + Y * DY, C = X * X + Y * Y - 1.0;
    if (B >= 0.0 || C <= 0.0)
        return INFINITY;
    double disc = B * B - A * C;
    return disc > 0.0 ? C / (sqrt(disc) - B) : INFINITY;
}

/* Puts an intersection point that rounding moved a few ulps off the ellipse
 * back onto it (one Newton step of 1/sqrt(r^2) about 1, which is exact to
 * rounding that close); returns the unit-circle coordinates through X, Y. */
static vec2 ellipse_snap(const ellipse *el, vec2 pos, double *X, double *Y)
{
    double x = (pos.x - el->cx) * el->inv_a, y = (pos.y - el->cy) * el->inv_b;
    double scale = 0.5 * (3.0 - (x * x + y * y));
    *X = x * scale;
    *Y = y * scale;
    return v2(el->cx + el->a * *X, el->cy + el->b * *Y);
}

/* ---- the tracer ---------------------------------------------------------- */

/* A path inside the cortex. Its throughput is weight * tint * exp(-sigma_a length):
 * Fresnel factors, medulla albedos and Beer-Lambert kept apart so the
 * exponentials are only taken when a lobe is stored. */
typedef struct fiber_path {
    vec2 pos;
    vec3 dir;
    double weight;
    rgb tint;
    double length;
} fiber_path;

static rgb path_throughput(const plm_fiber_params *p, const fiber_path *path, double factor)
{
    return rgb_scale(rgb_mul(path->tint, rgb_exp_neg(rgb_scale(p->sigma_a, path->length))), path->weight * factor);
}

/* Where light from wo enters at offset h: fills the surface reflection as
 * lobe 0 and starts the refracted path. */
static void enter(const plm_fiber_params *p, const ellipse *cortex, vec3 wo, double h, plm_fiber_lobe *lobe0,
                  fiber_path *path)
{
    double inv_proj = 1.0 / sqrt(wo.x * wo.x + wo.y * wo.y);
    vec2 v = v2(wo.x * inv_proj, wo.y * inv_proj); /* view direction projected in the cross-section */
    vec2 side = v2(v.y, -v.x);              /* h increases along this (docs/fiber.md) */
    double e = cortex->b, inv_e = cortex->inv_b;
    double half_width = sqrt(side.x * side.x + e * e * side.y * side.y); /* support function of the cortex */
    vec3 d = v3_neg(wo);
    /* In unit-circle coordinates the ray's discriminant is exactly A (1 - h^2). */
    double X = h * half_width * side.x, Y = h * half_width * side.y * inv_e, DX = d.x, DY = d.y * inv_e;
    double A = DX * DX + DY * DY, B = X * DX + Y * DY, root = sqrt(A * (1.0 - h * h));
    /* The near root. Its absolute error, all the snap below needs, is about
     * eps (|B| + root) / A; the "stable" form C / (root - B) would divide
     * rounding noise by rounding noise at the silhouettes. */
    double t = -(B + root) / A;
    double PX, PY;
    path->pos = ellipse_snap(cortex, v2(h * half_width * side.x + t * d.x, h * half_width * side.y + t * d.y),
                             &PX, &PY);
    vec3 n = ellipse_normal(cortex, PX, PY);
    double cos_i = plm_clamp(-v3_dot(d, n), 0.0, 1.0), cos_t;
    double inv_eta = 1.0 / p->eta, f = fresnel(cos_i, p->eta, inv_eta * inv_eta, &cos_t);
    lobe0->dir = reflect(d, n);
    lobe0->throughput = rgb_gray(f);
    lobe0->medulla = 0;
    lobe0->wall_hits = 0;
    path->dir = refract(d, n, cos_i, cos_t, inv_eta);
    path->weight = 1.0 - f;
    path->tint = rgb_gray(1.0);
    path->length = 0.0;
}

/* Lambertian bounce off the medulla at path->pos: the 3D direction whose
 * components along (n x z, z) are the unit-disk point (dx, dy) and along the
 * normal n (in the cross-section) is sqrt(1 - dx^2 - dy^2). A uniform disk
 * point makes it cosine-distributed about n; (n x z, z, n) is an
 * orthonormal frame with no normalisation to do. */
static void medulla_bounce_to(const plm_fiber_params *p, const ellipse *medulla, double dx, double dy,
                              fiber_path *path)
{
    double X, Y;
    path->pos = ellipse_snap(medulla, path->pos, &X, &Y);
    vec3 n = ellipse_normal(medulla, X, Y);
    double dz = sqrt(fmax(0.0, 1.0 - dx * dx - dy * dy));
    path->dir = v3(dx * n.y + dz * n.x, -dx * n.x + dz * n.y, dy);
    path->tint = rgb_mul(path->tint, p->medulla_reflectance);
}

/* The random bounce: the disk point by rejection (Malley's method without
 * trigonometry). */
static void medulla_bounce(const plm_fiber_params *p, const ellipse *medulla, plm_rng *rng, fiber_path *path)
{
    double dx, dy;
    do {
        dx = 2.0 * plm_rng_uniform(rng) - 1.0;
        dy = 2.0 * plm_rng_uniform(rng) - 1.0;
    } while (dx * dx + dy * dy >= 1.0);
    medulla_bounce_to(p, medulla, dx, dy, path);
}

/* The fiber's two ellipses. */
typedef struct fiber_shape {
    ellipse cortex, medulla;
    int has_medulla;
} fiber_shape;

static fiber_shape shape_of(const plm_fiber_params *p)
{
    fiber_shape s = {ellipse_make(0.0, 0.0, 1.0, p->eccentricity),
                     ellipse_make(p->medulla_ca, p->medulla_cb, p->medulla_a, p->medulla_b),
                     plm_fiber_has_medulla(p)};
    return s;
}

/* Follows path (inside the cortex; on_cortex says whether it starts on the
 * cortex wall, bounced whether it has met the medulla) until lobes[0..count)
 * holds max_lobes lobes, the light is gone or the interaction bound is hit;
 * returns count. With stop_at_medulla it returns instead when the path first
 * reaches the medulla, leaving path there (*stopped = 1). */
static int propagate(const plm_fiber_params *p, const fiber_shape *s, fiber_path *path, int on_cortex, int bounced,
                     plm_rng *rng, plm_fiber_lobe *lobes, int count, int max_lobes, int *stopped)
{
    const ellipse *cortex = &s->cortex;
    const double inv_eta = 1.0 / p->eta, eta2 = p->eta * p->eta; /* leaving: n_t / n_i = 1 / eta */
    const int max_interactions = 16 * max_lobes + 64;
    for (int interaction = 0; count < max_lobes && path->weight > 0.0 && interaction < max_interactions;
         ++interaction) {
        double t = ellipse_exit(cortex, path->pos, path->dir, on_cortex);
        if (!(t > 0.0))
            break; /* tangent or axial: the path gets nowhere (probability zero) */
        if (s->has_medulla && on_cortex) {
            double tm = ellipse_enter(&s->medulla, path->pos, path->dir);
            if (tm < t) {
                path->length += tm;
                path->pos = v2(path->pos.x + tm * path->dir.x, path->pos.y + tm * path->dir.y);
                if (stopped) {
                    *stopped = 1;
                    return count;
                }
                medulla_bounce(p, &s->medulla, rng, path);
                on_cortex = 0;
                bounced = 1;
                if (rgb_is_black(path->tint))
                    break;
                continue;
            }
        }
        path->length += t;
        double X, Y;
        /* Not snapped back onto the cortex: the exit root from the boundary
         * is exact to rounding, so the drift over even 16 000 interactions
         * stays near 1e-12, and the snap would lengthen the serial chain. */
        path->pos = v2(path->pos.x + t * path->dir.x, path->pos.y + t * path->dir.y);
        X = (path->pos.x - cortex->cx) * cortex->inv_a;
        Y = (path->pos.y - cortex->cy) * cortex->inv_b;
        on_cortex = 1;
        /* The reflected direction, which the next segment waits for, is taken
         * with the unnormalised normal g (one division); the unit normal the
         * Fresnel term and the lobe need is computed beside it. */
        double gx = X * cortex->inv_a, gy = Y * cortex->inv_b, gg = gx * gx + gy * gy;
        double dg = path->dir.x * gx + path->dir.y * gy, k = 2.0 * dg / gg;
        vec3 reflected = v3(path->dir.x - k * gx, path->dir.y - k * gy, path->dir.z);
        double inv_len = 1.0 / sqrt(gg), cos_t;
        double cos_i = plm_clamp(dg * inv_len, 0.0, 1.0), f = fresnel(cos_i, inv_eta, eta2, &cos_t);
        if (f < 1.0) { /* part leaves the cortex: a lobe */
            vec3 n = v3(gx * inv_len, gy * inv_len, 0.0);
            lobes[count].dir = refract(path->dir, v3_neg(n), cos_i, cos_t, p->eta);
            lobes[count].throughput = path_throughput(p, path, 1.0 - f);
            lobes[count].medulla = bounced;
            lobes[count].wall_hits = interaction + 1;
            ++count;
        }
        path->weight *= f;
        path->dir = reflected;
    }
    return count;
}

int plm_fiber_trace_n(const plm_fiber_params *p, vec3 wo, double h, plm_rng *rng, plm_fiber_lobe *lobes,
                      int max_lobes, rgb *inside)
{
    if (inside)
        *inside = rgb_gray(0.0);
    /* Light along the axis never meets the cross-section (below 1e-100 the
     * entry's quadratic would underflow; that cone has no measure anyway). */
    if (max_lobes < 1 || !(wo.x * wo.x + wo.y * wo.y > 1e-200) || !(h >= -1.0 && h <= 1.0))
        return 0;
    fiber_shape s = shape_of(p);
    fiber_path path;
    enter(p, &s.cortex, wo, h, &lobes[0], &path);
    int count = propagate(p, &s, &path, 1, 0, rng, lobes, 1, max_lobes, NULL);
    if (inside)
        *inside = path_throughput(p, &path, 1.0);
    return count;
}

int plm_fiber_trace_to_medulla(const plm_fiber_params *p, vec3 wo, double h, plm_fiber_lobe *lobes,
                               plm_fiber_medulla_hit *hit)
{
    if (!plm_fiber_has_medulla(p) || !(wo.x * wo.x + wo.y * wo.y > 1e-200) || !(h >= -1.0 && h <= 1.0))
        return 0;
    fiber_shape s = shape_of(p);
    fiber_path path;
    enter(p, &s.cortex, wo, h, &lobes[0], &path);
    int stopped = 0;
    hit->lobes = propagate(p, &s, &path, 1, 0, NULL, lobes, 1, p->lobes, &stopped);
    if (!stopped)
        return 0;
    double X, Y;
    ellipse_snap(&s.medulla, path.pos, &X, &Y);
    hit->t = atan2(Y, X);
    hit->throughput = path_throughput(p, &path, 1.0);
    return 1;
}

int plm_fiber_trace_from_medulla(const plm_fiber_params *p, double t, double u1, double u2, plm_rng *rng,
                                 plm_fiber_lobe *lobes, int max_lobes)
{
    if (!plm_fiber_has_medulla(p) || max_lobes < 1)
        return 0;
    fiber_shape s = shape_of(p);
    fiber_path path = {v2(s.medulla.cx + s.medulla.a * cos(t), s.medulla.cy + s.medulla.b * sin(t)),
                       v3(0.0, 0.0, 0.0), 1.0, rgb_gray(1.0), 0.0};
    double r = sqrt(u1), a = PLM_TWO_PI * u2; /* uniform on the unit disk */
    medulla_bounce_to(p, &s.medulla, r * cos(a), r * sin(a), &path);
    if (rgb_is_black(path.tint))
        return 0;
    return propagate(p, &s, &path, 0, 1, rng, lobes, 0, max_lobes, NULL);
}

int plm_fiber_trace(const plm_fiber_params *p, vec3 wo, double h, plm_rng *rng, plm_fiber_lobe *lobes)
{
    return plm_fiber_trace_n(p, wo, h, rng, lobes, p->lobes, NULL);
}
