/* Affine transforms for instances: a 3x4 matrix and its inverse, so points,
 * directions and normals can go both ways without a run-time inversion. */
#ifndef PLUMAGE_RENDER_TRANSFORM_H
#define PLUMAGE_RENDER_TRANSFORM_H

#include "common/vec.h"

typedef struct plm_xform {
    double m[3][4];   /* object -> world: rows of [linear | translation] */
    double inv[3][4]; /* world -> object */
} plm_xform;

plm_xform plm_xform_identity(void);
plm_xform plm_xform_translate(vec3 t);
plm_xform plm_xform_scale(vec3 s);
/* Rotation by angle (radians) about a unit axis, right-handed. */
plm_xform plm_xform_rotate(vec3 axis, double angle);
/* a after b: points go through b first. */
plm_xform plm_xform_compose(const plm_xform *a, const plm_xform *b);
/* From a row-major 3x4 object-to-world matrix; returns 0 if it is singular. */
int plm_xform_from_matrix(const double m[3][4], plm_xform *out);

static inline vec3 plm_xform_point(const double m[3][4], vec3 p)
{
    return v3(m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
              m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
              m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]);
}
static inline vec3 plm_xform_vector(const double m[3][4], vec3 v)
{
    return v3(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
              m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z);
}
/* Normals transform with the inverse transpose. */
static inline vec3 plm_xform_normal(const plm_xform *x, vec3 n)
{
    const double(*i)[4] = x->inv;
    return v3(i[0][0] * n.x + i[1][0] * n.y + i[2][0] * n.z, i[0][1] * n.x + i[1][1] * n.y + i[2][1] * n.z,
              i[0][2] * n.x + i[1][2] * n.y + i[2][2] * n.z);
}

#endif
