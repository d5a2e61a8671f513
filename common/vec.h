/* Small vector and colour maths, all inline and by value (pbrt-style).
 * Doubles throughout: the fiber tracer and the masking geometry need the
 * precision, and the cost is negligible next to ray traversal. */
#ifndef PLUMAGE_COMMON_VEC_H
#define PLUMAGE_COMMON_VEC_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#define PLM_PI 3.14159265358979323846
#define PLM_TWO_PI 6.28318530717958647692
#define PLM_INV_PI 0.31830988618379067154

typedef struct vec2 { double x, y; } vec2;
typedef struct vec3 { double x, y, z; } vec3;
/* Linear RGB radiance, reflectance or throughput. */
typedef struct rgb { double r, g, b; } rgb;

static inline double plm_radians(double deg) { return deg * (PLM_PI / 180.0); }
static inline double plm_degrees(double rad) { return rad * (180.0 / PLM_PI); }
static inline double plm_clamp(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }
static inline double plm_sqr(double x) { return x * x; }
/* max(x, 0), inline where fmax is a library call; NaN gives 0. */
static inline double plm_positive(double x) { return x > 0.0 ? x : 0.0; }
/* sqrt and asin that tolerate arguments a rounding error outside their domain. */
static inline double plm_safe_sqrt(double x) { return x > 0.0 ? sqrt(x) : 0.0; }
static inline double plm_safe_asin(double x) { return asin(plm_clamp(x, -1.0, 1.0)); }
/* An angle wrapped into [-pi, pi), from any number of turns away. */
static inline double plm_wrap_pi(double a) { return a - PLM_TWO_PI * floor((a + PLM_PI) / PLM_TWO_PI); }

/* sin(x) into *s and cos(x) into *c, at a fraction of the C library's
 * sincos cost for the angles a direction is made from (a fiber BCSDF
 * sample spent about a tenth of its time in two sincos calls;
 * docs/fiber.md). x less the nearest multiple q of pi/2, taken in three
 * parts (33, 33 and 53 bits of pi/2, so that q times each of the first two
 * is exact), lies in [-pi/4, pi/4], where Taylor polynomials of degree 17
 * (sin) and 16 (cos) are off by less than 1e-19; q mod 4 picks the
 * quadrant without a branch. Within 2 ulp of the C library
 * (tests/test_common.c); beyond |x| = 2^19 the library's own. */
static inline void plm_sincos(double x, double *s, double *c)
{
    if (!(fabs(x) < 0x1p19)) {
        *s = sin(x);
        *c = cos(x);
        return;
    }
    const double magic = 0x1.8p52; /* adding it rounds to an integer, which lands in the low bits */
    double t = x * 0x1.45f306dc9c883p-1 + magic, q = t - magic;
    uint64_t bits;
    memcpy(&bits, &t, sizeof bits);
    double r = ((x - q * 0x1.921fb544p0) - q * 0x1.0b4611a6p-34) - q * 0x1.3198a2e037073p-69, z = r * r;
    double sp = r + r * z * (-1.0 / 6.0 + z * (1.0 / 120.0 + z * (-1.0 / 5040.0 + z * (1.0 / 362880.0 +
                z * (-1.0 / 39916800.0 + z * (1.0 / 6227020800.0 + z * (-1.0 / 1307674368000.0 +
                z * (1.0 / 355687428096000.0))))))));
    double cp = 1.0 - 0.5 * z + z * z * (1.0 / 24.0 + z * (-1.0 / 720.0 + z * (1.0 / 40320.0 +
                z * (-1.0 / 3628800.0 + z * (1.0 / 479001600.0 + z * (-1.0 / 87178291200.0 +
                z * (1.0 / 20922789888000.0)))))));
    /* quadrant k: sin(x) = sin(r + k pi/2), cos(x) = sin(r + (k + 1) pi/2), and sin(r + k pi/2) is
     * sp, cp, -sp, -cp for k = 0..3 */
    const double sign[2] = {1.0, -1.0};
    double v[2] = {sp, cp};
    unsigned k = (unsigned)bits;
    *s = sign[(k >> 1) & 1u] * v[k & 1u];
    *c = sign[((k + 1u) >> 1) & 1u] * v[(k + 1u) & 1u];
}

/* atan2(y, x) at a fraction of the C library's cost (the fiber BCSDF's view
 * angles; docs/fiber.md). With n and d the smaller and larger of |x| and
 * |y|, atan(n / d) = atan(c) + atan(u), u = (n - c d) / (d + c n) (one
 * division), for c = 0 up to n / d = 0.16, then 1/4, 1/2 and 1 (0.3697 and
 * 0.7222 lie midway between the arctangents). As c is a power of two and
 * n / d within a factor of two of it, c d and n - c d are exact, so u carries
 * only the division's and d + c n's roundings, relative to u; |u| <= 0.1633
 * everywhere. That error counts against the result in proportion to
 * |u| / |result|: c = 1/4 from n / d = 1/8 up made it 2 ulp just under 1/8,
 * hence 0.16. On |u| <= 0.1633 atan(u) = u + u^3 P(u^2) with P of degree 6,
 * fitted to (atan(u) - u) / u^3 at Chebyshev nodes in u^2 in 50-digit
 * arithmetic and rounded, is off by under 0.02 ulp. The octant's offset
 * (0, pi/2 or pi) plus or minus atan(c) is stored as a double and the rest
 * below it, added to the small terms first, so the sum rounds once; then y's
 * sign. Within 1 ulp of the C library (tests/test_common.c); zeros,
 * infinities, NaNs and the larger of |x|, |y| outside [2^-1000, 2^1000] are
 * the library's. */
static inline double plm_atan2(double y, double x)
{
    static const double c_of[4] = {0.0, 0.25, 0.5, 1.0};
    /* octant o = 2 (x < 0) + (|y| > |x|): {0, pi/2, pi, pi/2} + {1, -1, -1, 1} atan(c) as hi + lo */
    static const double hi[16] = {
        0.0, 0x1.f5b75f92c80ddp-3, 0x1.dac670561bb4fp-2, 0x1.921fb54442d18p-1,
        0x1.921fb54442d18p+0, 0x1.5368c951e9cfdp+0, 0x1.1b6e192ebbe44p+0, 0x1.921fb54442d18p-1,
        0x1.921fb54442d18p+1, 0x1.72c43f4b1650ap+1, 0x1.56c6e7397f5aep+1, 0x1.2d97c7f3321d2p+1,
        0x1.921fb54442d18p+0, 0x1.d0d6a1369bd34p+0, 0x1.0468a8ace4df6p+1, 0x1.2d97c7f3321d2p+1};
    static const double lo[16] = {
        0.0, 0x1.8ab6e3cf7afbdp-57, 0x1.a2b7f222f65e2p-56, 0x1.1a62633145c07p-55,
        0x1.1a62633145c07p-54, -0x1.96f47948a99f1p-54, 0x1.b1b466a88828ep-54, 0x1.1a62633145c07p-55,
        0x1.1a62633145c07p-53, 0x1.c1b6f4f44e10bp-53, 0x1.660b64ece6f4bp-53, 0x1.a79394c9e8a0ap-54,
        0x1.1a62633145c07p-54, -0x1.a23602a65700cp-57, 0x1.0620bf7406affp-55, 0x1.a79394c9e8a0ap-54};
    static const double sign[4] = {1.0, -1.0, -1.0, 1.0};
    double ax = fabs(x), ay = fabs(y);
    unsigned swap = ay > ax, o = 2u * (x < 0.0) + swap;
    double n = swap ? ax : ay, d = swap ? ay : ax;
    if (!(d > 0x1p-1000 && d < 0x1p1000))
        return atan2(y, x);
    unsigned k = (unsigned)(n > 0.16 * d) + (unsigned)(n > 0.3697 * d) + (unsigned)(n > 0.7222 * d);
    double c = c_of[k], u = (n - c * d) / (d + c * n), z = u * u;
    double p = u + u * (z * (-0x1.5555555555554p-2 + z * (0x1.9999999997891p-3 + z * (-0x1.2492491fbb81ap-3 +
               z * (0x1.c71c6942d7333p-4 + z * (-0x1.745983e5f0e4bp-4 + z * (0x1.3a4db58b592cep-4 +
               z * -0x1.f74c7b253c853p-5)))))));
    unsigned i = 4u * o + k;
    return copysign(hi[i] + (sign[o] * p + lo[i]), y);
}

/* asin(s) - s for s = sqrt(w), w in [0, 1/4]: s w Q(w), Q of degree 12
 * fitted to (asin(s) - s) / s^3 at Chebyshev nodes in w in 50-digit
 * arithmetic and rounded, off by under 0.05 ulp there (asin's singularity
 * at w = 1 is what needs the degree). The kernel of plm_asin and
 * plm_acos. */
static inline double plm_asin_tail(double s, double w)
{
    return s * w * (0x1.5555555555556p-3 + w * (0x1.3333333332ecap-4 + w * (0x1.6db6db6e31f13p-5 +
           w * (0x1.f1c71c1db0623p-6 + w * (0x1.6e8bb1c8209a2p-6 + w * (0x1.1c4d35cf95421p-6 +
           w * (0x1.c9cf07674736ap-7 + w * (0x1.782651caa6547p-7 + w * (0x1.52420b04b37bep-7 +
           w * (0x1.65a9c4dfcf8b2p-8 + w * (0x1.1d189408314eep-6 + w * (-0x1.e6aaa8a0a04ccp-7 +
           w * 0x1.d72b2bc8155f8p-6))))))))))));
}

/* asin(x) for x in [-1, 1] (NaN outside), at a fraction of the C library's
 * cost. Up to |x| = 1/2, asin(x) = x + plm_asin_tail(x, x^2); beyond,
 * asin(|x|) = pi/2 - 2 asin(s) with s = sqrt(w), w = (1 - |x|) / 2 (exact),
 * and asin(s) = s + plm_asin_tail(s, w) again: either way w <= 1/4.
 * pi/2 - 2 s is taken before pi/2's low part and the small terms are added.
 * Within 2 ulp of the C library (tests/test_common.c); asin(+-1) = +-pi/2
 * and asin(+-0) = +-0 exactly, +-1 (half the fiber view's h ends: whole
 * intervals) without the polynomial. */
static inline double plm_asin(double x)
{
    double n = fabs(x);
    if (n == 1.0)
        return copysign(0x1.921fb54442d18p+0, x);
    int big = n > 0.5;
    double w = big ? 0.5 - 0.5 * n : n * n, s = big ? sqrt(w) : n, t = plm_asin_tail(s, w);
    double a = big ? (0x1.921fb54442d18p+0 - 2.0 * s) + (0x1.1a62633145c07p-54 - 2.0 * t) : s + t;
    return copysign(a, x);
}

/* acos(x) for x in [-1, 1] (NaN outside), at a fraction of the C library's
 * cost (the environment map's lookup of every escaping ray; docs/benchmarks.md),
 * from plm_asin_tail. Up to |x| = 1/2, acos(x) = pi/2 - (x + tail), with
 * pi/2's low part taken from the tail first (result >= pi/3); beyond, with
 * s = sqrt(w), w = (1 - |x|) / 2 (exact), acos(x) = 2 asin(s) for x > 0,
 * which keeps its relative accuracy as the result goes to 0, and
 * pi - 2 asin(s) for x < 0. Within 2 ulp of the C library
 * (tests/test_common.c); acos(1) = 0 and acos(-1) = pi exactly. */
static inline double plm_acos(double x)
{
    double n = fabs(x);
    int big = n > 0.5;
    double w = big ? 0.5 - 0.5 * n : n * n, s = big ? sqrt(w) : n, t = plm_asin_tail(s, w);
    if (!big)
        return 0x1.921fb54442d18p+0 - (x + (copysign(t, x) - 0x1.1a62633145c07p-54));
    return x > 0.0 ? 2.0 * (s + t) : (0x1.921fb54442d18p+1 - 2.0 * s) + (0x1.1a62633145c07p-53 - 2.0 * t);
}

static inline double plm_safe_acos(double x) { return plm_acos(plm_clamp(x, -1.0, 1.0)); }

static inline vec2 v2(double x, double y) { vec2 v = {x, y}; return v; }
static inline vec2 v2_add(vec2 a, vec2 b) { return v2(a.x + b.x, a.y + b.y); }
static inline vec2 v2_sub(vec2 a, vec2 b) { return v2(a.x - b.x, a.y - b.y); }
static inline vec2 v2_scale(vec2 a, double s) { return v2(a.x * s, a.y * s); }
static inline double v2_dot(vec2 a, vec2 b) { return a.x * b.x + a.y * b.y; }
/* z component of the 3D cross product: positive when b is counter-clockwise of a. */
static inline double v2_cross(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }
static inline double v2_length(vec2 a) { return sqrt(v2_dot(a, a)); }
static inline vec2 v2_normalize(vec2 a) { return v2_scale(a, 1.0 / v2_length(a)); }

static inline vec3 v3(double x, double y, double z) { vec3 v = {x, y, z}; return v; }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_scale(vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline vec3 v3_neg(vec3 a) { return v3(-a.x, -a.y, -a.z); }
static inline vec3 v3_mul(vec3 a, vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline double v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double v3_length(vec3 a) { return sqrt(v3_dot(a, a)); }
static inline vec3 v3_normalize(vec3 a) { return v3_scale(a, 1.0 / v3_length(a)); }
/* a + s * b */
static inline vec3 v3_madd(vec3 a, vec3 b, double s) { return v3(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z); }
/* v turned by angle (radians, right-handed) about the unit axis k (Rodrigues). */
static inline vec3 v3_rotate(vec3 v, vec3 k, double angle)
{
    double c = cos(angle), s = sin(angle);
    return v3_add(v3_add(v3_scale(v, c), v3_scale(v3_cross(k, v), s)), v3_scale(k, v3_dot(k, v) * (1.0 - c)));
}

/* An orthonormal frame; to_local gives (w·x, w·y, w·z). */
typedef struct frame { vec3 x, y, z; } frame;
static inline vec3 frame_to_local(const frame *f, vec3 w) { return v3(v3_dot(w, f->x), v3_dot(w, f->y), v3_dot(w, f->z)); }
static inline vec3 frame_to_world(const frame *f, vec3 l)
{
    return v3_add(v3_add(v3_scale(f->x, l.x), v3_scale(f->y, l.y)), v3_scale(f->z, l.z));
}
/* Any orthonormal frame with z = n (Duff et al. 2017, branchless ONB). */
static inline frame frame_from_z(vec3 n)
{
    double s = copysign(1.0, n.z);
    double a = -1.0 / (s + n.z), b = n.x * n.y * a;
    frame f;
    f.x = v3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    f.y = v3(b, s + n.y * n.y * a, -n.y);
    f.z = n;
    return f;
}

static inline rgb rgb_make(double r, double g, double b) { rgb c = {r, g, b}; return c; }
static inline rgb rgb_gray(double v) { return rgb_make(v, v, v); }
static inline rgb rgb_add(rgb a, rgb b) { return rgb_make(a.r + b.r, a.g + b.g, a.b + b.b); }
static inline rgb rgb_sub(rgb a, rgb b) { return rgb_make(a.r - b.r, a.g - b.g, a.b - b.b); }
static inline rgb rgb_mul(rgb a, rgb b) { return rgb_make(a.r * b.r, a.g * b.g, a.b * b.b); }
static inline rgb rgb_scale(rgb a, double s) { return rgb_make(a.r * s, a.g * s, a.b * s); }
static inline rgb rgb_exp_neg(rgb a) { return rgb_make(exp(-a.r), exp(-a.g), exp(-a.b)); }
static inline double rgb_max(rgb a) { return fmax(a.r, fmax(a.g, a.b)); }
static inline double rgb_mean(rgb a) { return (a.r + a.g + a.b) / 3.0; }
static inline double rgb_luminance(rgb a) { return 0.2126 * a.r + 0.7152 * a.g + 0.0722 * a.b; }
static inline int rgb_is_finite(rgb a) { return isfinite(a.r) && isfinite(a.g) && isfinite(a.b); }
static inline int rgb_is_black(rgb a) { return a.r == 0.0 && a.g == 0.0 && a.b == 0.0; }

#endif
