#include "common/curves.h"

#include <stdlib.h>
#include <string.h>

int plm_curves_segment_count(const plm_curves *c)
{
    return c->point_count - c->curve_count;
}

size_t plm_curves_bytes(const plm_curves *c)
{
    if (c->curve_count == 0)
        return 0;
    return sizeof(float) * 4 * (size_t)c->point_count + sizeof(int) * ((size_t)c->curve_count + 1) +
           (c->tag ? (size_t)c->curve_count : 0);
}

void plm_curves_free(plm_curves *c)
{
    free(c->points);
    free(c->first);
    free(c->tag);
    memset(c, 0, sizeof *c);
}
