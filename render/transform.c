#include "render/transform.h"

#include <string.h>

/* Inverse of an affine 3x4 matrix by the adjugate of its linear part. */
static int invert_affine(const double m[3][4], double out[3][4])
{
    double a = m[0][0], b = m[0][1], c = m[0][2];
    double d = m[1][0], e = m[1][1], f = m[1][2];
    double g = m[2][0], h = m[2][1], k = m[2][2];
    double det = a * (e * k - f * h) - b * (d * k - f * g) + c * (d * h - e * g);
    if (!(fabs(det) > 1e-300) || !isfinite(det))
        return 0;
    double s = 1.0 / det;
    double l[3][3] = {{(e * k - f * h) * s, (c * h - b * k) * s, (b * f - c * e) * s},
                      {(f * g - d * k) * s, (a * k - c * g) * s, (c * d - a * f) * s},
                      {(d * h - e * g) * s, (b * g - a * h) * s, (a * e - b * d) * s}};
    for (int r = 0; r < 3; ++r) {
        for (int j = 0; j < 3; ++j)
            out[r][j] = l[r][j];
        out[r][3] = -(l[r][0] * m[0][3] + l[r][1] * m[1][3] + l[r][2] * m[2][3]);
    }
    return 1;
}

int plm_xform_from_matrix(const double m[3][4], plm_xform *out)
{
    memcpy(out->m, m, sizeof out->m);
    return invert_affine(m, out->inv);
}

plm_xform plm_xform_identity(void)
{
    static const double id[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    plm_xform x;
    plm_xform_from_matrix(id, &x);
    return x;
}

plm_xform plm_xform_translate(vec3 t)
{
    double m[3][4] = {{1, 0, 0, t.x}, {0, 1, 0, t.y}, {0, 0, 1, t.z}};
    plm_xform x;
    plm_xform_from_matrix(m, &x);
    return x;
}

plm_xform plm_xform_scale(vec3 s)
{
    double m[3][4] = {{s.x, 0, 0, 0}, {0, s.y, 0, 0}, {0, 0, s.z, 0}};
    plm_xform x;
    if (!plm_xform_from_matrix(m, &x))
        return plm_xform_identity(); /* callers reject zero scales before this */
    return x;
}

plm_xform plm_xform_rotate(vec3 axis, double angle)
{
    vec3 a = v3_normalize(axis);
    double c = cos(angle), s = sin(angle), t = 1.0 - c;
    double m[3][4] = {{t * a.x * a.x + c, t * a.x * a.y - s * a.z, t * a.x * a.z + s * a.y, 0},
                      {t * a.x * a.y + s * a.z, t * a.y * a.y + c, t * a.y * a.z - s * a.x, 0},
                      {t * a.x * a.z - s * a.y, t * a.y * a.z + s * a.x, t * a.z * a.z + c, 0}};
    plm_xform x;
    plm_xform_from_matrix(m, &x);
    return x;
}

plm_xform plm_xform_compose(const plm_xform *a, const plm_xform *b)
{
    double m[3][4];
    for (int r = 0; r < 3; ++r)
        for (int j = 0; j < 4; ++j) {
            m[r][j] = a->m[r][0] * b->m[0][j] + a->m[r][1] * b->m[1][j] + a->m[r][2] * b->m[2][j];
            if (j == 3)
                m[r][j] += a->m[r][3];
        }
    plm_xform x;
    if (!plm_xform_from_matrix(m, &x))
        return plm_xform_identity();
    return x;
}
