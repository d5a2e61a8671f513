/* The tail and the wings' place on the body: the tail a fan of rectrices
 * whose central pair lies on top, with coverts over the bases above and
 * below; the wings a frame at each shoulder for the wing layout. */
#include <math.h>
#include <stdlib.h>

#include "common/rng.h"
#include "generate/bird_parts.h"
#include "generate/layout_parts.h"

#define MM 0.001
#define TAIL_VARIANTS 3

static vec3 turn(vec3 v, vec3 toward, double angle)
{
    return v3_add(v3_scale(v, cos(angle)), v3_scale(toward, sin(angle)));
}

/* One feather of a fan: rank -1..1 across it, `drop` layout units below the
 * central feathers, pitched `pitch` radians toward the ventral side. */
static void fan_feather(const plm_bird_body *b, double rank, double spread, double length_mm, double species_mm,
                        vec3 origin, double pitch, plm_layout_instance *in)
{
    vec3 side = v3(0, 1, 0), d = b->tail_direction, up = b->tail_dorsal;
    vec3 t = turn(d, side, rank * spread);
    t = v3_normalize(turn(t, v3_neg(up), pitch));
    vec3 z = v3_normalize(v3_sub(up, v3_scale(t, v3_dot(up, t))));
    double scale = in->scale * length_mm / species_mm * MM;
    plm_layout_set_matrix(in, v3_cross(t, z), t, z, origin, scale);
}

plm_result plm_bird_tail_layout(const plm_bird *bird, const plm_bird_body *body, const plm_species *rectrix,
                                const plm_species *covert, plm_layout *out, plm_error *err)
{
    const plm_bird_tail *tl = &bird->tail;
    const plm_species *list[2] = {rectrix, covert};
    plm_layout_extent *ext = NULL;
    uint64_t seed = plm_hash64(bird->seed, 0x7a11u, 0);
    int n = tl->count, total = 3 * n;
    plm_result rc = plm_layout_make_prototypes(list, 2, TAIL_VARIANTS, seed, out, &ext, err);
    plm_layout_extents_free(ext, out->prototype_count);
    out->instances = rc == PLM_OK ? calloc((size_t)total, sizeof *out->instances) : NULL;
    if (rc == PLM_OK && !out->instances)
        rc = plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a tail of %d feathers", total);
    if (rc != PLM_OK) {
        plm_layout_free(out);
        return rc;
    }
    plm_layout_variation none = {0};
    plm_layout_ranges var = plm_layout_ranges_of(&none);
    var.yaw = plm_radians(1.5); /* a fan's feathers keep their places */
    double tail = bird->m.tail_length, thickness = 0.012 * tail * MM;
    vec3 base = body->tail_base, up = body->tail_dorsal, d = body->tail_direction;
    for (int i = 0; i < total; ++i) {
        plm_layout_instance *in = &out->instances[i];
        int layer = i / n, k = i % n; /* rectrices, upper coverts, under coverts */
        double rank = n > 1 ? 2.0 * k / (n - 1) - 1.0 : 0.0;
        plm_rng rng;
        plm_rng_seed(&rng, plm_hash64(seed, (uint64_t)i, 1), PLM_LAYOUT_STREAM_FEATHER);
        int species = layer == 0 ? 0 : 1;
        in->prototype = species * TAIL_VARIANTS + (int)(plm_rng_uniform(&rng) * TAIL_VARIANTS);
        in->row = -1;
        plm_layout_draw_variation(&rng, &var, in);
        /* Outer feathers lie under inner ones: lower, and pitched a little down. */
        double outer = fabs(rank), length, spread = tl->spread, pitch = plm_radians(3.0) * outer;
        vec3 o = v3_madd(base, up, -thickness * outer * n / 2.0);
        if (layer == 0) {
            length = tail * (1.0 - tl->rounding * outer * outer);
        } else {
            length = tl->covert_length * tail * (1.0 - 0.3 * outer);
            spread *= 0.8;
            o = v3_madd(v3_madd(base, d, -0.35 * length * MM), up, (layer == 1 ? 1.0 : -1.0) * 2.0 * thickness * n);
            pitch = layer == 1 ? plm_radians(-4.0) : plm_radians(6.0);
        }
        fan_feather(body, rank, spread, length, list[species]->shape.length, o, pitch, in);
        in->order = layer == 1 ? total + k : layer == 0 ? n - (int)(outer * n) : -k;
    }
    out->instance_count = total;
    return PLM_OK;
}

void plm_bird_wing_frame(const plm_bird_body *b, int side, double lift, double m[3][4])
{
    /* The folded wing lies flat along the flank: its plane faces sideways and
     * a little up, at the body's widest, as far out as the feathers there. */
    double widest = 0.0;
    for (int i = 0; i < b->skin.vertex_count; ++i)
        widest = fmax(widest, -b->skin.positions[3 * i + 1]);
    vec3 z = v3_normalize(v3(0.0, -1.0, 0.25)), f = v3_neg(b->axis);
    vec3 y = v3_normalize(v3_sub(f, v3_scale(z, v3_dot(f, z)))), x = v3_cross(y, z);
    vec3 o = v3(b->shoulder[1].x, -widest - lift, b->shoulder[1].z);
    const vec3 col[4] = {x, y, z, o};
    for (int c = 0; c < 4; ++c) {
        m[0][c] = col[c].x;
        m[1][c] = side == 0 ? -col[c].y : col[c].y; /* the left wing: the right one mirrored */
        m[2][c] = col[c].z;
    }
}
