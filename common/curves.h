/* Curves as plain arrays: fibers (the fluffy base of a feather) as the
 * generator makes them and the renderer traces them, each a polyline of
 * points with a radius, rendered as round linear curves (cones between
 * points, round at the joints). Floats, because Embree takes floats. */
#ifndef PLUMAGE_COMMON_CURVES_H
#define PLUMAGE_COMMON_CURVES_H

#include <stddef.h>
#include <stdint.h>

typedef struct plm_curves {
    int curve_count;
    int point_count;
    float *points;       /* 4 per point: x, y, z and the radius there */
    int *first;          /* curve_count + 1 entries: curve c's points are first[c] .. first[c + 1] - 1 */
    unsigned char *tag;  /* per curve, what it is to whoever made it (generate/fluff.h), or NULL */
} plm_curves;

/* Segments (between consecutive points of one curve): what is traced. */
int plm_curves_segment_count(const plm_curves *c);
/* Bytes the arrays hold. */
size_t plm_curves_bytes(const plm_curves *c);
/* Frees the arrays and zeroes the struct. */
void plm_curves_free(plm_curves *c);

#endif
