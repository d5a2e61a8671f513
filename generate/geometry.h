/* The feather in 3D: the rachis centre line bent and twisted, the vanes as
 * one open smooth surface across both sides, the rachis as a closed tapering
 * tube, both refined with OpenSubdiv to their limit surfaces. */
#ifndef PLUMAGE_GENERATE_GEOMETRY_H
#define PLUMAGE_GENERATE_GEOMETRY_H

#include "common/mesh.h"
#include "generate/outline.h"

/* The rachis frame at arc length y: centre C, lateral X (toward the right
 * vane), tangent T (toward the tip), normal Z = X x T (dorsal). The frame
 * turns at a constant rate (bend in and out of the vane plane, twist), so
 * the centre line is a helix of exact arc length y. */
typedef struct plm_rachis_frame {
    vec3 c, x, t, z;
} plm_rachis_frame;

plm_rachis_frame plm_rachis_frame_at(const plm_outline *o, double y);

/* Flat point (x, y) of the vane, with the curl, in 3D. */
vec3 plm_vane_point(const plm_outline *o, double x, double y);

/* Vane surface: positions, dorsal normals, uvs (texture space of outline.h)
 * and tangents (unit dP/du); triangles counter-clockwise seen from the dorsal
 * side. `level` is the subdivision level (1..6). */
plm_result plm_vane_mesh(const plm_outline *o, int level, plm_mesh *out, plm_error *err);

/* Closed rachis tube from the calamus base to the rachis end: positions and
 * outward normals (no uvs: the whole tube is rachis). */
plm_result plm_rachis_mesh(const plm_outline *o, int level, plm_mesh *out, plm_error *err);

/* Cage sizes (quads): the vane has PLM_VANE_COLUMNS across and PLM_VANE_ROWS
 * along (outline.h), the tube RACHIS_RING around and RACHIS_ROWS along. */
#define PLM_RACHIS_RING 8
#define PLM_RACHIS_ROWS 24

#endif
