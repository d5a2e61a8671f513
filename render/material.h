/* The material interface of the path tracer.
 *
 * At a surface hit the renderer asks the material two things:
 *  - plm_material_transmission(hit, w): the probability that a ray arriving
 *    from direction w (unit, pointing back toward where the ray came from)
 *    passes straight through. This is the delta transmission of the feather
 *    (paper Eq. 4, w_t) handled as fractional visibility (docs/rendering.md): camera
 *    and bounce rays continue straight with this probability, shadow rays
 *    are attenuated by it.
 *  - plm_material_bsdf(hit, wo, rng): the BSDF of the other branch, the
 *    light that does not pass: f_s without its delta term, divided by
 *    (1 - w_t(wo)), so it conserves energy on its own.
 * The BSDF (optics/bsdf.h) is prepared once for the view direction wo (a
 * feather traces its fiber lobe sets here, with rng). */
#ifndef PLUMAGE_RENDER_MATERIAL_H
#define PLUMAGE_RENDER_MATERIAL_H

#include "common/rng.h"
#include "common/vec.h"
#include "optics/bsdf.h"
#include "optics/feather_bsdf.h"
#include "optics/masking.h"
#include "render/scene.h"

/* What rendering derives from a material's description (render/scene.h),
 * kept apart from it so that the scene stays a description: a feather's
 * prepared masking and fiber tables, a fiber's table. The render world
 * prepares one for each material that owns its optics (plm_world_build). */
typedef struct plm_prepared_material {
    plm_feather_model feather;    /* feather only */
    const plm_fiber_table *fiber_table; /* fiber only, from a table set; NULL: the stochastic estimator */
} plm_prepared_material;

/* m's prepared feather masking, without tables. */
void plm_material_prepare(const plm_material *m, plm_prepared_material *out);
/* Adds the fiber tables m's estimator needs (none for the stochastic one)
 * from set, which must outlive p. */
plm_result plm_material_prepare_tables(const plm_material *m, plm_fiber_table_set *set, plm_prepared_material *p,
                                       plm_error *err);

/* What a material needs to know about the surface at a hit, in world space. */
typedef struct plm_hit {
    vec3 p;          /* position */
    vec3 ng;         /* geometric normal, unit, on the mesh's front (counter-clockwise) side */
    vec3 n;          /* shading normal, unit, same side as ng: the feather's dorsal side */
    vec3 dpdu, dpdv; /* surface derivatives; for vanes dP/dv points to the feather's tip */
    vec2 uv;
    rgb tint;        /* per-instance colour variation */
    const plm_material *material;
    const plm_prepared_material *prepared; /* the material's (plm_world_build) */
    /* The pixel cone that found the hit: its width at p (world units; 0 for
     * none: after a scattering event, in shadow queries, with
     * film.far_field) and the ray direction. */
    double cone_width;
    vec3 ray_dir;
    /* On a fiber (curves): its radius there (0 elsewhere) and the closest
     * point of its axis, from which rays leave it (plm_world_offset); dpdu
     * is then the unit axis. */
    double fiber_radius;
    vec3 fiber_axis_point;
    /* Set by plm_material_surface: whether the hit lies on a feather's vane,
     * and there the barb frame (x = b, y = n, z = t; docs/masking.md). */
    int on_vane;
    frame barb;
    /* On a vane, the part of the barb period the pixel covers (a whole
     * period: the far field; docs/nearfield.md). */
    plm_barb_window window;
    /* Set by plm_material_transmission_keep: the feather's masking for the
     * view direction masking_w, which the BSDF reuses when wo is the same. */
    int has_masking;
    vec3 masking_w;
    plm_masking masking;
} plm_hit;

/* Completes a hit whose geometric fields are set: the material's surface
 * data (the texture lookups), done once per hit. In two steps for the
 * Embree filters, which decide a candidate's passing from the first and
 * finish only the hit they keep: _at sets what the transmission needs
 * (site: where uv falls in the material's texture, NULL: looked up), _finish
 * the rest (the pigment's tint). */
void plm_material_surface(plm_hit *hit);
void plm_material_surface_at(plm_hit *hit, const plm_texel_site *site);
void plm_material_surface_finish(plm_hit *hit);
double plm_material_transmission(const plm_hit *hit, vec3 w);
/* The same, keeping what it computed in the hit for plm_material_bsdf with wo = w
 * (a ray's closest hit was seen by the filters that decided its passing). */
double plm_material_transmission_keep(plm_hit *hit, vec3 w);
void plm_material_bsdf(const plm_hit *hit, vec3 wo, plm_rng *rng, plm_bsdf *out);

/* The pigment image's colour factor at uv on a feather's vane (see
 * plm_material; 1 without an image): never above 1, so pigment only absorbs. */
rgb plm_material_pigment(const plm_material *m, vec2 uv);

/* Lambertian reflection on the side of wo (two-sided), albedo in [0, 1]. */
void plm_diffuse_bsdf(const plm_hit *hit, vec3 wo, rgb albedo, plm_bsdf *out);

#endif
