/* Embree scenes (one per mesh prototype, instanced by a top-level scene),
 * surface hits in world space, and the camera. */
#include "render/world.h"

#include "optics/feather_bsdf.h"

#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static vec3 mesh_vec3(const float *a, uint32_t i) { return v3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); }
static vec2 mesh_vec2(const float *a, uint32_t i) { return v2(a[2 * i], a[2 * i + 1]); }

static vec2 triangle_uv(const plm_mesh *m, unsigned prim, double b1, double b2)
{
    const uint32_t *idx = m->indices + 3 * (size_t)prim;
    if (!m->uvs)
        return v2(b1, b2);
    vec2 a = mesh_vec2(m->uvs, idx[0]), b = mesh_vec2(m->uvs, idx[1]), c = mesh_vec2(m->uvs, idx[2]);
    return v2((1.0 - b1 - b2) * a.x + b1 * b.x + b2 * c.x, (1.0 - b1 - b2) * a.y + b1 * b.y + b2 * c.y);
}

/* Every Embree query passes this context; the filters get it back (it
 * starts with the context Embree expects). A transparent shadow query
 * collects the surfaces it passes instead of stopping at them; a passing
 * query lets each surface go by with its transmission probability. */
#define MAX_CROSSINGS 64
typedef struct query_context {
    struct RTCIntersectContext rtc;
    const plm_world *world;
    int transparent;
    int passing;
    plm_passing numbers;              /* passing: decisions are hash(seed, instance, triangle) + shift, mod 1 */
    double spread;                    /* pixel cone width per unit distance, 0: none (docs/nearfield.md) */
    vec3 back;                        /* unit, opposite to the ray's world-space direction */
    int crossings;                    /* may exceed MAX_CROSSINGS: then the rest went into overflow */
    double t[MAX_CROSSINGS], transmission[MAX_CROSSINGS];
    double overflow;                  /* product of the transmissions beyond MAX_CROSSINGS */
    /* passing: the last candidate kept (NULL: none yet), filled as the
     * filter saw it. Embree reports only candidates nearer than the one it
     * holds, so this is the closest hit unless a surface without filter was
     * found nearer. A candidate is filled into whichever of the caller's hit
     * and the spare does not hold the kept one, so that keeping it copies
     * nothing, and the one candidate of most rays lands in the caller's hit. */
    plm_hit *hit; /* the caller's (NULL: a shadow query) */
    plm_hit *kept;
    unsigned kept_inst, kept_prim;
    float kept_t;
    plm_hit spare;
} query_context;

static void fill_hit(const plm_world *w, unsigned inst, unsigned prim, double b1, double b2,
                     const plm_texel_site *site, double cone_width, vec3 d, plm_hit *hit);

/* The pixel cone's width at distance t (t is the world one, in instances too); 0: no cone. */
static double cone_width(const query_context *ctx, double t) { return ctx->spread * t; }

/* The uniform that decides whether a ray passes a surface: one per surface,
 * from its identity rather than from the order Embree reports candidates in,
 * so that every surface nearer than the hit kept was reported and passed, and
 * the kept hit is distributed as when tracing one crossing at a time. The
 * query's seed and shift are drawn here on first need (plm_passing). */
static double passing_uniform(plm_passing *numbers, unsigned inst, unsigned prim)
{
    if (numbers->draw) {
        numbers->draw(numbers->arg, &numbers->seed, &numbers->shift);
        numbers->draw = NULL;
    }
    double u = (double)(plm_hash64(numbers->seed, inst, prim) >> 11) * 0x1.0p-53 + numbers->shift;
    return u >= 1.0 ? u - 1.0 : u;
}

/* Intersection and occlusion filter. Background texels of the mask are not
 * there at all, so Embree goes on to the next candidate. In a transparent
 * shadow query a surface that lets light through is recorded with its
 * transmission and passed too. Hits arrive as structure-of-arrays packets of
 * N; the offsets follow embree3/rtcore_ray.h. */
static void surface_filter(const struct RTCFilterFunctionNArguments *args)
{
    const plm_prototype *proto = args->geometryUserPtr;
    query_context *ctx = (query_context *)args->context;
    const float *hit = (const float *)args->hit, *ray = (const float *)args->ray;
    const unsigned *hit_ids = (const unsigned *)args->hit;
    unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i) {
        if (args->valid[i] == 0)
            continue;
        unsigned prim = proto->triangle[hit_ids[5 * n + i]], inst = hit_ids[7 * n + i];
        /* The mask is the material's texture: the hit's lookups start from this site. */
        plm_texel_site site;
        if (proto->mask) {
            plm_feather_texture_site(proto->mask, triangle_uv(proto->mesh, prim, hit[3 * n + i], hit[4 * n + i]),
                                     &site);
            if (plm_feather_texture_region_at(proto->mask, &site) == PLM_REGION_BACKGROUND) {
                args->valid[i] = 0;
                continue;
            }
        }
        if (!ctx->transparent && !ctx->passing)
            continue;
        plm_hit *h = ctx->hit && ctx->kept != ctx->hit ? ctx->hit : &ctx->spare;
        /* In instances the ray arrives in object space; its parameter t is the world one.
         * fill_hit sets what the passing needs; intersect finishes the hit kept (its
         * pigment) once the query ends, so surfaces passed never pay for that. */
        fill_hit(ctx->world, inst, prim, hit[3 * n + i], hit[4 * n + i], proto->mask ? &site : NULL,
                 cone_width(ctx, ray[8 * n + i]), v3_neg(ctx->back), h);
        double tr = plm_material_transmission_keep(h, ctx->back);
        if (ctx->passing) {
            if (tr > 0.0 && passing_uniform(&ctx->numbers, inst, prim) < tr) {
                args->valid[i] = 0;
            } else if (ctx->hit) { /* the hit and its masking, for the shading that follows */
                ctx->kept = h;
                ctx->kept_inst = inst;
                ctx->kept_prim = prim;
                ctx->kept_t = ray[8 * n + i];
            }
            continue;
        }
        if (!(tr > 0.0))
            continue; /* opaque: the shadow ray is blocked */
        if (ctx->crossings < MAX_CROSSINGS) {
            ctx->t[ctx->crossings] = ray[8 * n + i]; /* a filter sees the candidate's distance in tfar */
            ctx->transmission[ctx->crossings] = tr;
        } else {
            ctx->overflow *= tr;
        }
        ctx->crossings++;
        args->valid[i] = 0;
    }
}

/* Whether every texel a triangle's uvs can reach (its uv box, one texel
 * more for the nearest-texel lookup) is background: then no hit on it can
 * ever pass the filter, and it is left out of the BVH. */
static int all_background(const plm_mesh *m, const plm_feather_texture *t, int tri)
{
    const uint32_t *idx = m->indices + 3 * (size_t)tri;
    double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (int k = 0; k < 3; ++k) {
        vec2 uv = mesh_vec2(m->uvs, idx[k]);
        u0 = fmin(u0, uv.x), u1 = fmax(u1, uv.x), v0 = fmin(v0, uv.y), v1 = fmax(v1, uv.y);
    }
    int x0 = (int)floor(plm_clamp(u0, 0, 1) * t->width) - 1, x1 = (int)floor(plm_clamp(u1, 0, 1) * t->width) + 1;
    int y0 = (int)floor((1.0 - plm_clamp(v1, 0, 1)) * t->height) - 1;
    int y1 = (int)floor((1.0 - plm_clamp(v0, 0, 1)) * t->height) + 1;
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= t->width ? t->width - 1 : x1, y1 = y1 >= t->height ? t->height - 1 : y1;
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x)
            if (t->region[(size_t)y * t->width + x] != PLM_REGION_BACKGROUND)
                return 0;
    return 1;
}

static void grow_box(vec3 *lo, vec3 *hi, vec3 q, double r)
{
    *lo = v3(fmin(lo->x, q.x - r), fmin(lo->y, q.y - r), fmin(lo->z, q.z - r));
    *hi = v3(fmax(hi->x, q.x + r), fmax(hi->y, q.y + r), fmax(hi->z, q.z + r));
}

/* Curves as round linear curves: a cone between consecutive points, Embree
 * reading the points where they are (the scene outlives the world). */
static plm_result build_curves(plm_embree *embree, plm_prototype *p, plm_error *err)
{
    const plm_curves *c = p->curves;
    int segments = plm_curves_segment_count(c);
    p->triangle = malloc(sizeof *p->triangle * (size_t)(segments + 1));
    if (!p->triangle)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for %d curve segments", segments);
    int k = 0;
    for (int i = 0; i < c->curve_count; ++i)
        for (int j = c->first[i]; j + 1 < c->first[i + 1]; ++j)
            p->triangle[k++] = (unsigned)j;
    p->lo = v3(INFINITY, INFINITY, INFINITY);
    p->hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (int v = 0; v < c->point_count; ++v) {
        const float *q = c->points + 4 * (size_t)v;
        grow_box(&p->lo, &p->hi, v3(q[0], q[1], q[2]), q[3]);
    }
    RTCGeometry g = rtcNewGeometry(embree->device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, c->points, 0, 4 * sizeof(float),
                               (size_t)c->point_count);
    unsigned *idx = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(unsigned),
                                            (size_t)segments);
    char what[64];
    snprintf(what, sizeof what, "curves of %d segments", segments);
    if (!idx) {
        rtcReleaseGeometry(g);
        plm_result rc = plm_embree_check(embree, what, err);
        return rc != PLM_OK ? rc : plm_fail(err, PLM_ERR_NO_MEMORY, "Embree, %s: no buffer", what);
    }
    memcpy(idx, p->triangle, sizeof(unsigned) * (size_t)segments);
    rtcCommitGeometry(g);
    p->rtc = rtcNewScene(embree->device);
    rtcAttachGeometry(p->rtc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(p->rtc);
    return plm_embree_check(embree, what, err);
}

static plm_result build_prototype(plm_embree *embree, plm_prototype *p, plm_error *err)
{
    if (p->curves)
        return build_curves(embree, p, err);
    const plm_mesh *m = p->mesh;
    p->triangle = malloc(sizeof *p->triangle * (size_t)(m->triangle_count + 1));
    if (!p->triangle)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a mesh of %d triangles", m->triangle_count);
    int kept = 0;
    for (int i = 0; i < m->triangle_count; ++i)
        if (!(p->mask && m->uvs && all_background(m, p->mask, i)))
            p->triangle[kept++] = (unsigned)i;
    p->lo = v3(INFINITY, INFINITY, INFINITY);
    p->hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (int v = 0; v < m->vertex_count; ++v)
        grow_box(&p->lo, &p->hi, mesh_vec3(m->positions, (uint32_t)v), 0.0);
    RTCDevice device = embree->device;
    p->rtc = rtcNewScene(device);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                       (size_t)m->vertex_count);
    unsigned *t = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                          (size_t)(kept > 0 ? kept : 1));
    char what[64];
    snprintf(what, sizeof what, "a mesh of %d triangles", m->triangle_count);
    if (!v || !t) { /* Embree has reported why */
        rtcReleaseGeometry(g);
        plm_result rc = plm_embree_check(embree, what, err);
        return rc != PLM_OK ? rc : plm_fail(err, PLM_ERR_NO_MEMORY, "Embree, %s: no buffer", what);
    }
    memcpy(v, m->positions, sizeof(float) * 3 * (size_t)m->vertex_count);
    for (int i = 0; i < kept; ++i)
        memcpy(t + 3 * (size_t)i, m->indices + 3 * (size_t)p->triangle[i], 3 * sizeof(unsigned));
    if (kept == 0) /* nothing visible: one degenerate triangle, which Embree never hits */
        t[0] = t[1] = t[2] = 0, p->triangle[0] = 0;
    if (p->mask || p->transmissive) {
        rtcSetGeometryUserData(g, p);
        rtcSetGeometryIntersectFilterFunction(g, surface_filter);
        rtcSetGeometryOccludedFilterFunction(g, surface_filter);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(p->rtc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(p->rtc);
    return plm_embree_check(embree, what, err);
}

static const plm_feather_texture *material_mask(const plm_material *m)
{
    return m->texture.pixels ? &m->texture : NULL;
}

static int material_transmits(const plm_material *m)
{
    return m->type == PLM_MATERIAL_FEATHER || m->transmission > 0.0;
}

/* One prototype per distinct (mesh, mask, transmissive) among the instances. */
static plm_result build_prototypes(plm_world *w, plm_error *err)
{
    const plm_scene *s = w->scene;
    w->prototypes = calloc((size_t)s->instance_count + 1, sizeof *w->prototypes);
    w->instance_prototype = calloc((size_t)s->instance_count + 1, sizeof *w->instance_prototype);
    if (!w->prototypes || !w->instance_prototype)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for %d instances", s->instance_count);
    for (int i = 0; i < s->instance_count; ++i) {
        const plm_scene_mesh *sm = &s->meshes[s->instances[i].mesh];
        const plm_mesh *mesh = &sm->mesh;
        const plm_material *m = &s->materials[s->instances[i].material];
        const plm_feather_texture *mask = material_mask(m);
        int transmissive = material_transmits(m), k = 0;
        while (k < w->prototype_count && !(w->prototypes[k].mesh == mesh && w->prototypes[k].mask == mask &&
                                           w->prototypes[k].transmissive == transmissive))
            ++k;
        if (k == w->prototype_count) {
            w->prototypes[k].mesh = mesh;
            w->prototypes[k].curves = sm->curves.curve_count > 0 ? &sm->curves : NULL;
            w->prototypes[k].mask = mask;
            w->prototypes[k].transmissive = transmissive;
            w->prototype_count++; /* counted first, so plm_world_free releases a half-built one */
            plm_result rc = build_prototype(&w->embree, &w->prototypes[k], err);
            if (rc != PLM_OK)
                return rc;
        }
        w->instance_prototype[i] = k;
    }
    return PLM_OK;
}

static void grow_bounds(plm_world *w, vec3 p)
{
    w->bounds_min = v3(fmin(w->bounds_min.x, p.x), fmin(w->bounds_min.y, p.y), fmin(w->bounds_min.z, p.z));
    w->bounds_max = v3(fmax(w->bounds_max.x, p.x), fmax(w->bounds_max.y, p.y), fmax(w->bounds_max.z, p.z));
}

static plm_result build_instances(plm_world *w, plm_error *err)
{
    const plm_scene *s = w->scene;
    w->top = rtcNewScene(w->embree.device);
    w->bounds_min = v3(INFINITY, INFINITY, INFINITY);
    w->bounds_max = v3(-INFINITY, -INFINITY, -INFINITY);
    for (int i = 0; i < s->instance_count; ++i) {
        const plm_instance *in = &s->instances[i];
        float m[12];
        for (int k = 0; k < 12; ++k)
            m[k] = (float)in->xform.m[k / 4][k % 4];
        RTCGeometry g = rtcNewGeometry(w->embree.device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(g, w->prototypes[w->instance_prototype[i]].rtc);
        rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, m);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(w->top, g, (unsigned)i);
        rtcReleaseGeometry(g);
        /* World bounds from the corners of the mesh's box. */
        vec3 lo = w->prototypes[w->instance_prototype[i]].lo, hi = w->prototypes[w->instance_prototype[i]].hi;
        for (int c = 0; c < 8; ++c)
            grow_bounds(w, plm_xform_point(in->xform.m, v3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y,
                                                           c & 4 ? hi.z : lo.z)));
    }
    rtcCommitScene(w->top);
    if (s->instance_count == 0)
        w->bounds_min = w->bounds_max = v3(0.0, 0.0, 0.0);
    char what[64];
    snprintf(what, sizeof what, "the scene of %d instances", s->instance_count);
    return plm_embree_check(&w->embree, what, err);
}

vec3 plm_world_frame_position(const plm_world *w, vec3 from, double fov)
{
    vec3 c = v3_scale(v3_add(w->bounds_min, w->bounds_max), 0.5);
    double r = fmax(0.5 * v3_length(v3_sub(w->bounds_max, w->bounds_min)), 1e-3);
    return v3_madd(c, v3_normalize(from), 1.05 * r / sin(plm_radians(0.5 * fov)));
}

plm_camera_desc plm_world_camera_desc(const plm_world *w)
{
    plm_camera_desc d = w->scene->camera;
    if (!d.given) { /* frame the scene's bounding sphere from +z */
        d.look_at = v3_scale(v3_add(w->bounds_min, w->bounds_max), 0.5);
        d.position = plm_world_frame_position(w, v3(0.0, 0.0, 1.0), d.fov);
    }
    return d;
}

void plm_world_set_camera(plm_world *w, const plm_camera_desc *d)
{
    const plm_film_desc *f = &w->scene->film;
    plm_camera_from_desc(d, f->width, f->height, f->far_field, &w->camera);
}

static void build_camera(plm_world *w)
{
    plm_camera_desc d = plm_world_camera_desc(w);
    plm_world_set_camera(w, &d);
}

void plm_camera_from_desc(const plm_camera_desc *desc, int width, int height, int far_field, plm_camera *cam)
{
    const plm_camera_desc d = *desc;
    cam->width = width;
    cam->height = height;
    cam->position = d.position;
    cam->forward = v3_normalize(v3_sub(d.look_at, d.position));
    vec3 right = v3_normalize(v3_cross(cam->forward, d.up));
    vec3 up = v3_cross(right, cam->forward);
    double tan_half = tan(plm_radians(0.5 * d.fov)), aspect = (double)cam->width / cam->height;
    cam->right = v3_scale(right, tan_half * aspect);
    cam->up = v3_scale(up, tan_half);
    cam->lens_radius = d.aperture;
    /* A pixel's angular width (at the image centre); none with film.far_field. */
    cam->pixel_spread = far_field ? 0.0 : 2.0 * tan_half / cam->height;
    cam->focus_distance = d.focus_distance > 0.0 ? d.focus_distance : v3_length(v3_sub(d.look_at, d.position));
}

void plm_camera_ray(const plm_camera *c, double x, double y, double u1, double u2, vec3 *o, vec3 *d)
{
    double sx = 2.0 * x / c->width - 1.0, sy = 1.0 - 2.0 * y / c->height;
    vec3 dir = v3_add(c->forward, v3_add(v3_scale(c->right, sx), v3_scale(c->up, sy)));
    *o = c->position;
    if (c->lens_radius > 0.0) {
        /* Thin lens: rays through the lens point converge on the focus plane. */
        vec3 focus = v3_madd(c->position, dir, c->focus_distance);
        double r = c->lens_radius * sqrt(u1), phi = PLM_TWO_PI * u2;
        *o = v3_add(*o, v3_add(v3_scale(v3_normalize(c->right), r * cos(phi)),
                               v3_scale(v3_normalize(c->up), r * sin(phi))));
        dir = v3_sub(focus, *o);
    }
    *d = v3_normalize(dir);
}

static plm_result choose_lights(plm_world *w, plm_error *err);

/* The earlier material whose feather or fiber parameters material i shares
 * (feathers of one species share their optics), else i itself. */
static int optics_owner(const plm_scene *s, int i)
{
    const plm_material *m = &s->materials[i];
    for (int j = 0; j < i; ++j) {
        const plm_material *o = &s->materials[j];
        if ((m->shares_feather && o->feather == m->feather && !o->shares_feather) ||
            (m->shares_fiber && o->fiber == m->fiber && !o->shares_fiber))
            return j;
    }
    return i;
}

/* What rendering derives from each material, once per set of optics: the
 * feathers' prepared masking (docs/masking.md) and fiber tables (built once,
 * cached on disk, one per distinct fiber; docs/fiber.md), and the tables of
 * the fibers that instances use. The scene is not touched. */
static plm_result prepare_materials(plm_world *w, plm_error *err)
{
    const plm_scene *s = w->scene;
    size_t n = (size_t)s->material_count + 1;
    w->prepared = calloc(n, sizeof *w->prepared);
    w->prepared_of = calloc(n, sizeof *w->prepared_of);
    char *used = calloc(n, 1);
    plm_result rc = w->prepared && w->prepared_of && used ? PLM_OK : plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory");
    for (int i = 0; i < s->instance_count && rc == PLM_OK; ++i)
        used[s->instances[i].material] = 1;
    plm_fiber_table_set_init(&w->tables, &(plm_fiber_table_options){.budget_mib = s->film.fiber_table_mib});
    for (int i = 0; i < s->material_count && rc == PLM_OK; ++i) {
        const plm_material *m = &s->materials[i];
        int owner = optics_owner(s, i);
        plm_prepared_material *p = &w->prepared[owner];
        if (owner == i)
            plm_material_prepare(m, p);
        w->prepared_of[i] = p;
        if (m->feather || (m->fiber && used[i]))
            rc = plm_material_prepare_tables(&s->materials[owner], &w->tables, p, err);
    }
    free(used);
    return rc;
}

plm_result plm_world_build(const plm_scene *scene, plm_world *w, plm_error *err)
{
    memset(w, 0, sizeof *w);
    w->scene = scene;
    plm_result rc = plm_embree_open(&w->embree, 0, err);
    if (rc == PLM_OK)
        rc = build_prototypes(w, err);
    if (rc == PLM_OK)
        rc = build_instances(w, err);
    if (rc != PLM_OK) {
        plm_world_free(w);
        return rc;
    }
    build_camera(w);
    double extent = fmax(fmax(fabs(w->bounds_min.x), fabs(w->bounds_max.x)),
                         fmax(fmax(fabs(w->bounds_min.y), fabs(w->bounds_max.y)),
                              fmax(fabs(w->bounds_min.z), fabs(w->bounds_max.z))));
    w->epsilon = 1e-5 * fmax(1.0, extent); /* well above float rounding at that magnitude */
    for (int i = 0; i < scene->material_count; ++i)
        w->transmissive |= material_transmits(&scene->materials[i]);
    if ((rc = prepare_materials(w, err)) != PLM_OK) {
        plm_world_free(w);
        return rc;
    }
    w->lights = calloc((size_t)scene->light_count + 1, sizeof *w->lights);
    if (!w->lights) {
        plm_world_free(w);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory");
    }
    for (int i = 0; i < scene->light_count; ++i) {
        rc = plm_render_light_init(&scene->lights[i], &w->lights[i], err);
        w->light_count = i + 1;
        if (rc != PLM_OK) {
            plm_world_free(w);
            return rc;
        }
        w->infinite_lights += plm_light_is_infinite(&w->lights[i]);
    }
    return choose_lights(w, err);
}

int plm_world_pick_light(const plm_world *w, double u)
{
    int i = 0;
    while (i + 1 < w->light_count && (u >= w->light_cdf[i + 1] || plm_world_light_pick(w, i) <= 0.0))
        ++i;
    return i;
}

/* Next-event estimation's choice among the lights, by the light each
 * brings to the scene's centre (uniform if none brings any). */
static plm_result choose_lights(plm_world *w, plm_error *err)
{
    int n = w->light_count;
    w->light_cdf = malloc(sizeof(double) * (size_t)(n + 1));
    if (!w->light_cdf) {
        plm_world_free(w);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory");
    }
    vec3 centre = v3_scale(v3_add(w->bounds_min, w->bounds_max), 0.5);
    double total = 0.0;
    w->light_cdf[0] = 0.0;
    for (int i = 0; i < n; ++i) {
        double p = plm_light_power(&w->lights[i], centre);
        total += isfinite(p) && p > 0.0 ? p : 0.0;
        w->light_cdf[i + 1] = total;
    }
    for (int i = 1; i <= n; ++i)
        w->light_cdf[i] = total > 0.0 ? w->light_cdf[i] / total : (double)i / n;
    if (n > 0)
        w->light_cdf[n] = 1.0;
    /* The first environment with a ground holds the shadow catcher. */
    for (int i = 0; i < n && !w->ground.enabled; ++i) {
        const plm_light *l = w->lights[i].desc;
        if (plm_light_is_infinite(&w->lights[i]) && l->ground)
            w->ground = (plm_ground){1, l->up, l->ground_height, rgb_gray(0.0)};
    }
    for (int i = 0; i < n && w->ground.enabled; ++i)
        w->ground.irradiance = rgb_add(w->ground.irradiance, plm_light_irradiance(&w->lights[i], w->ground.normal));
    return PLM_OK;
}

void plm_world_free(plm_world *w)
{
    for (int i = 0; i < w->light_count; ++i)
        plm_render_light_free(&w->lights[i]);
    free(w->lights);
    free(w->light_cdf);
    if (w->top)
        rtcReleaseScene(w->top);
    for (int i = 0; i < w->prototype_count; ++i) {
        if (w->prototypes[i].rtc)
            rtcReleaseScene(w->prototypes[i].rtc);
        free(w->prototypes[i].triangle);
    }
    free(w->prototypes);
    free(w->instance_prototype);
    plm_fiber_table_set_free(&w->tables);
    free(w->prepared);
    free(w->prepared_of);
    plm_embree_close(&w->embree);
    memset(w, 0, sizeof *w);
}

static void make_ray(struct RTCRay *r, vec3 o, vec3 d, double tmax)
{
    r->org_x = (float)o.x, r->org_y = (float)o.y, r->org_z = (float)o.z;
    r->dir_x = (float)d.x, r->dir_y = (float)d.y, r->dir_z = (float)d.z;
    r->tnear = 0.0f;
    r->tfar = tmax < FLT_MAX ? (float)tmax : INFINITY;
    r->time = 0.0f;
    r->mask = 0xffffffffu;
    r->id = 0;
    r->flags = 0;
}

/* World-space surface state at barycentrics (b1, b2) of a triangle of an instance,
 * with the material's surface data that decides passing (plm_material_surface_at;
 * site: where uv falls in the material's texture, NULL: looked up). */
static void fill_hit(const plm_world *w, unsigned inst, unsigned prim, double b1, double b2,
                     const plm_texel_site *site, double cone_width, vec3 d, plm_hit *hit)
{
    const plm_instance *in = &w->scene->instances[inst];
    const plm_mesh *m = &w->scene->meshes[in->mesh].mesh;
    const uint32_t *idx = m->indices + 3 * (size_t)prim;
    double b0 = 1.0 - b1 - b2;
    vec3 p0 = mesh_vec3(m->positions, idx[0]), p1 = mesh_vec3(m->positions, idx[1]);
    vec3 p2 = mesh_vec3(m->positions, idx[2]);
    vec3 p = v3_add(v3_add(v3_scale(p0, b0), v3_scale(p1, b1)), v3_scale(p2, b2));
    hit->p = plm_xform_point(in->xform.m, p);
    hit->ng = v3_normalize(plm_xform_normal(&in->xform, v3_cross(v3_sub(p1, p0), v3_sub(p2, p0))));
    hit->n = hit->ng;
    if (m->normals) {
        vec3 n = v3_add(v3_add(v3_scale(mesh_vec3(m->normals, idx[0]), b0), v3_scale(mesh_vec3(m->normals, idx[1]), b1)),
                        v3_scale(mesh_vec3(m->normals, idx[2]), b2));
        n = plm_xform_normal(&in->xform, n);
        if (v3_length(n) > 0.0)
            hit->n = v3_normalize(n);
        if (v3_dot(hit->n, hit->ng) < 0.0) /* the authored normal names the front (dorsal) side */
            hit->ng = v3_neg(hit->ng);
    }
    hit->uv = triangle_uv(m, prim, b1, b2);
    hit->fiber_radius = 0.0;
    /* dP/du and dP/dv of the triangle's linear parameterisation (pbrt's). */
    vec3 dpdu, dpdv;
    double det = 0.0;
    vec3 dp02 = v3_sub(p0, p2), dp12 = v3_sub(p1, p2);
    double du02 = 0, dv02 = 0, du12 = 0, dv12 = 0;
    if (m->uvs) {
        vec2 t0 = mesh_vec2(m->uvs, idx[0]), t1 = mesh_vec2(m->uvs, idx[1]), t2 = mesh_vec2(m->uvs, idx[2]);
        du02 = t0.x - t2.x, dv02 = t0.y - t2.y, du12 = t1.x - t2.x, dv12 = t1.y - t2.y;
        det = du02 * dv12 - dv02 * du12;
    }
    if (fabs(det) > 1e-20) {
        dpdu = v3_scale(v3_sub(v3_scale(dp02, dv12), v3_scale(dp12, dv02)), 1.0 / det);
        dpdv = v3_scale(v3_sub(v3_scale(dp12, du02), v3_scale(dp02, du12)), 1.0 / det);
        hit->dpdu = plm_xform_vector(in->xform.m, dpdu);
        hit->dpdv = plm_xform_vector(in->xform.m, dpdv);
    } else { /* no usable uvs: any tangent frame */
        frame f = frame_from_z(hit->n);
        hit->dpdu = f.x;
        hit->dpdv = f.y;
    }
    hit->tint = in->tint;
    hit->material = &w->scene->materials[in->material];
    hit->prepared = w->prepared_of[in->material];
    hit->cone_width = cone_width;
    hit->ray_dir = d;
    plm_material_surface_at(hit, site);
}

/* World-space surface state on a curve segment (its first point `first`)
 * at parameter u along it, hit at o + t d with Embree's object-space normal ng. */
static void fill_curve_hit(const plm_world *w, unsigned inst, unsigned first, double u, vec3 ng, vec3 o, vec3 d,
                           double t, double cone_width, plm_hit *hit)
{
    const plm_instance *in = &w->scene->instances[inst];
    const float *a = w->scene->meshes[in->mesh].curves.points + 4 * (size_t)first, *b = a + 4;
    vec3 p0 = v3(a[0], a[1], a[2]), along = v3_sub(v3(b[0], b[1], b[2]), p0);
    vec3 axis = v3_normalize(plm_xform_vector(in->xform.m, along));
    /* The radius scales as a direction across the axis does. */
    double scale = v3_length(plm_xform_vector(in->xform.m, frame_from_z(v3_normalize(along)).x));
    hit->p = v3_madd(o, d, t);
    hit->fiber_axis_point = plm_xform_point(in->xform.m, v3_madd(p0, along, u));
    hit->fiber_radius = scale * (a[3] + u * (b[3] - a[3]));
    vec3 n = plm_xform_normal(&in->xform, ng);
    if (!(v3_length(n) > 0.0) || !isfinite(n.x + n.y + n.z))
        n = v3_sub(hit->p, hit->fiber_axis_point);
    hit->ng = hit->n = v3_normalize(n);
    hit->dpdu = axis;
    hit->dpdv = v3_cross(hit->n, axis);
    hit->uv = v2(u, 0.0);
    hit->tint = in->tint;
    hit->material = &w->scene->materials[in->material];
    hit->prepared = w->prepared_of[in->material];
    hit->cone_width = cone_width;
    hit->ray_dir = d;
    plm_material_surface_at(hit, NULL);
}

static void init_context(query_context *ctx, const plm_world *w, int transparent)
{
    rtcInitIntersectContext(&ctx->rtc);
    ctx->world = w;
    ctx->transparent = transparent;
    ctx->passing = 0;
    ctx->spread = 0.0;
    ctx->crossings = 0;
    ctx->overflow = 1.0;
    ctx->hit = ctx->kept = NULL;
}

static int intersect(const plm_world *w, query_context *ctx, vec3 o, vec3 d, double tmax, double *t, plm_hit *hit)
{
    struct RTCRayHit rh;
    make_ray(&rh.ray, o, d, tmax);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(w->top, &ctx->rtc, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return 0;
    *t = rh.ray.tfar;
    unsigned inst = rh.hit.instID[0];
    const plm_prototype *proto = &w->prototypes[w->instance_prototype[inst]];
    unsigned prim = proto->triangle[rh.hit.primID];
    if (proto->curves)
        fill_curve_hit(w, inst, prim, rh.hit.u, v3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z), o, d, rh.ray.tfar,
                       cone_width(ctx, rh.ray.tfar), hit);
    else if (!(ctx->kept && ctx->kept_inst == inst && ctx->kept_prim == prim && ctx->kept_t == rh.ray.tfar))
        fill_hit(w, inst, prim, rh.hit.u, rh.hit.v, NULL, cone_width(ctx, rh.ray.tfar), d, hit);
    else if (ctx->kept != hit)
        *hit = *ctx->kept;
    plm_material_surface_finish(hit);
    return 1;
}

int plm_world_first_hit(const plm_world *w, vec3 o, vec3 d, double tnear, double tmax, int *instance, double *t)
{
    struct RTCRayHit rh;
    make_ray(&rh.ray, o, d, tmax);
    rh.ray.tnear = (float)tnear;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    query_context ctx;
    init_context(&ctx, w, 0);
    rtcIntersect1(w->top, &ctx.rtc, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return 0;
    *instance = (int)rh.hit.instID[0];
    *t = rh.ray.tfar;
    return 1;
}

int plm_world_intersect(const plm_world *w, vec3 o, vec3 d, double tmax, double *t, plm_hit *hit)
{
    query_context ctx;
    init_context(&ctx, w, 0);
    return intersect(w, &ctx, o, d, tmax, t, hit);
}

int plm_world_intersect_passing(const plm_world *w, vec3 o, vec3 d, double tmax, const plm_passing *passing,
                                double spread, double *t, plm_hit *hit)
{
    query_context ctx;
    init_context(&ctx, w, 0);
    ctx.spread = spread;
    ctx.passing = w->transmissive;
    ctx.numbers = *passing;
    ctx.back = v3_neg(d);
    ctx.hit = hit;
    return intersect(w, &ctx, o, d, tmax, t, hit);
}

double plm_world_transmittance(const plm_world *w, vec3 o, vec3 d, double tmax)
{
    struct RTCRay r;
    make_ray(&r, o, d, tmax);
    query_context ctx;
    init_context(&ctx, w, w->transmissive);
    ctx.back = v3_neg(d);
    rtcOccluded1(w->top, &ctx.rtc, &r);
    if (r.tfar == -INFINITY)
        return 0.0;
    /* Insertion sort by distance: a handful of crossings. */
    int n = ctx.crossings < MAX_CROSSINGS ? ctx.crossings : MAX_CROSSINGS;
    for (int i = 1; i < n; ++i)
        for (int j = i; j > 0 && ctx.t[j - 1] > ctx.t[j]; --j) {
            double tt = ctx.t[j], tr = ctx.transmission[j];
            ctx.t[j] = ctx.t[j - 1], ctx.transmission[j] = ctx.transmission[j - 1];
            ctx.t[j - 1] = tt, ctx.transmission[j - 1] = tr;
        }
    double product = 1.0;
    for (int i = 0; i < n; ++i)
        product *= ctx.transmission[i];
    return product * ctx.overflow;
}

/* Rays leave a fiber from its axis, beyond its surface along d (an
 * infinite cylinder's, r / sin of d's angle to the axis, at most ten radii
 * for directions along it): the fiber BCSDF has already taken the light
 * through the fiber, so a ray must not meet its inside. */
#define FIBER_EXIT_MAX 10.0

vec3 plm_world_offset(const plm_world *w, const plm_hit *hit, vec3 d)
{
    if (hit->fiber_radius > 0.0) {
        double across = v3_length(v3_cross(d, hit->dpdu));
        double exit = hit->fiber_radius * fmin(1.02 / fmax(across, 1e-9), FIBER_EXIT_MAX);
        return v3_madd(hit->fiber_axis_point, d, exit + w->epsilon);
    }
    return v3_madd(hit->p, hit->ng, v3_dot(d, hit->ng) >= 0.0 ? w->epsilon : -w->epsilon);
}
