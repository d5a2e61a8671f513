/* The ID pass (render/visibility.h): each camera ray is followed through
 * every surface it crosses, one closest-hit query after another, each
 * starting just beyond the last hit. */
#include "render/visibility.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void plm_visibility_free(plm_visibility *v)
{
    free(v->instance);
    free(v->feather);
    free(v->part);
    free(v->v);
    free(v->feathers);
    memset(v, 0, sizeof *v);
}

/* Where along its feather a hit at world point p on instance i lies: the
 * object-space y over the mesh's extent along y (0 at the calamus base). */
static float along(const plm_world *w, const double *feather_extent, int i, vec3 p)
{
    const plm_instance *in = &w->scene->instances[i];
    const plm_prototype *pr = &w->prototypes[w->instance_prototype[i]];
    vec3 q = plm_xform_point(in->xform.inv, p);
    double extent = in->feather > 0 ? feather_extent[in->feather] : pr->hi.y;
    return extent > 0.0 ? (float)plm_clamp(q.y / extent, 0.0, 1.0) : 0.0f;
}

/* Each placed feather's extent along its object +y: the largest of its
 * parts' (the fluff reaches only part way up the vane). */
static double *feather_extents(const plm_world *w)
{
    const plm_scene *s = w->scene;
    double *e = calloc((size_t)s->feather_count + 1, sizeof *e);
    for (int i = 0; e && i < s->instance_count; ++i)
        e[s->instances[i].feather] = fmax(e[s->instances[i].feather], w->prototypes[w->instance_prototype[i]].hi.y);
    return e;
}

/* One ray: every surface it crosses, the feathers among them counted once each. */
static void trace_ray(const plm_world *w, const double *feather_extent, const plm_camera *c, int x, int y,
                      plm_visibility *out)
{
    size_t pixel = (size_t)y * out->width + x;
    vec3 o, d;
    plm_camera_ray(c, x + 0.5, y + 0.5, 0.5, 0.5, &o, &d);
    int border = x == 0 || y == 0 || x == out->width - 1 || y == out->height - 1;
    int crossed[PLM_VISIBILITY_MAX_LAYERS], n_crossed = 0, layers = 0, instance;
    double t, tnear = 0.0;
    out->rays++;
    while (layers < PLM_VISIBILITY_MAX_LAYERS && plm_world_first_hit(w, o, d, tnear, INFINITY, &instance, &t)) {
        const plm_instance *in = &w->scene->instances[instance];
        if (layers++ == 0) {
            out->instance[pixel] = instance;
            out->feather[pixel] = in->feather;
            out->part[pixel] = (unsigned char)in->part;
            out->v[pixel] = along(w, feather_extent, instance, v3_madd(o, d, t));
            out->hits++;
            out->part_hits[in->part]++;
            if (in->feather > 0) {
                plm_feather_view *f = &out->feathers[in->feather];
                f->seen++;
                f->seen_proximal += out->v[pixel] < 0.5f;
                f->v_min = fminf(f->v_min, out->v[pixel]);
            }
        }
        int k = 0;
        while (k < n_crossed && crossed[k] != in->feather)
            ++k;
        if (in->feather > 0 && k == n_crossed) {
            crossed[n_crossed++] = in->feather;
            out->feathers[in->feather].crossed++;
            out->feathers[in->feather].on_border |= border;
        }
        /* Beyond the hit by the world's ray offset: surfaces closer than it
         * to each other count as one crossing. */
        tnear = t + w->epsilon;
    }
    out->crossings += layers;
    if (layers > out->deepest)
        out->deepest = layers;
}

plm_result plm_visibility_trace(const plm_world *w, const plm_camera *camera, plm_visibility *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    plm_camera c = *camera;
    c.lens_radius = 0.0; /* one pinhole ray per pixel */
    size_t n = (size_t)c.width * (size_t)c.height;
    out->width = c.width;
    out->height = c.height;
    out->feather_count = w->scene->feather_count;
    out->instance = malloc(n * sizeof *out->instance);
    out->feather = calloc(n, sizeof *out->feather);
    out->part = calloc(n, sizeof *out->part);
    out->v = malloc(n * sizeof *out->v);
    out->feathers = calloc((size_t)out->feather_count + 1, sizeof *out->feathers);
    double *extent = feather_extents(w);
    if (!out->instance || !out->feather || !out->part || !out->v || !out->feathers || !extent) {
        free(extent);
        plm_visibility_free(out);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for a %dx%d ID pass", c.width, c.height);
    }
    for (size_t i = 0; i < n; ++i) {
        out->instance[i] = -1;
        out->v[i] = -1.0f;
    }
    for (int f = 0; f <= out->feather_count; ++f)
        out->feathers[f].v_min = 2.0f;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x)
            trace_ray(w, extent, &c, x, y, out);
    free(extent);
    return PLM_OK;
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The q-quantile of n sorted values (nearest rank). */
static double quantile(const double *sorted, int n, double q)
{
    int k = (int)ceil(q * n) - 1;
    return sorted[k < 0 ? 0 : k];
}

plm_result plm_visibility_summarise(const plm_visibility *v, int min_rays, plm_visibility_summary *s, plm_error *err)
{
    memset(s, 0, sizeof *s);
    double *fraction = malloc(((size_t)v->feather_count + 1) * sizeof *fraction);
    if (!fraction)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory summarising %d feathers", v->feather_count);
    for (int id = 1; id <= v->feather_count; ++id) {
        const plm_feather_view *f = &v->feathers[id];
        if (f->on_border || f->crossed < min_rays || f->crossed == 0)
            continue;
        fraction[s->feathers++] = (double)f->seen / f->crossed;
        s->proximal_feathers += f->seen_proximal > 0;
        s->proximal_rays += f->seen_proximal;
        s->seen_rays += f->seen;
    }
    if (s->feathers > 0) {
        qsort(fraction, (size_t)s->feathers, sizeof *fraction, compare_double);
        s->median = quantile(fraction, s->feathers, 0.5);
        s->p90 = quantile(fraction, s->feathers, 0.9);
        s->max = fraction[s->feathers - 1];
    }
    s->body = v->hits > 0 ? (double)v->part_hits[PLM_PART_BODY] / (double)v->hits : 0.0;
    free(fraction);
    return PLM_OK;
}

vec3 plm_visibility_direction(int i, int n)
{
    const double golden = PLM_PI * (3.0 - sqrt(5.0));
    double z = 1.0 - (2.0 * i + 1.0) / n, r = plm_safe_sqrt(1.0 - z * z), phi = golden * i;
    return v3(r * cos(phi), r * sin(phi), z);
}

plm_camera plm_visibility_camera(const plm_world *w, vec3 from, int width, int height, double fov)
{
    plm_camera_desc d = {0};
    d.fov = fov;
    d.look_at = v3_scale(v3_add(w->bounds_min, w->bounds_max), 0.5);
    d.position = plm_world_frame_position(w, from, fov);
    /* Up: +z unless looking along it. */
    d.up = fabs(v3_normalize(from).z) > 0.99 ? v3(0.0, 1.0, 0.0) : v3(0.0, 0.0, 1.0);
    plm_camera c;
    plm_camera_from_desc(&d, width, height, 1, &c);
    return c;
}

/* ---- Crossing pairs ---- */

/* A set of ordered feather pairs (above, below), open addressing. */
typedef struct pair_set {
    uint64_t *keys; /* 0: empty */
    size_t mask, count;
} pair_set;

static uint64_t pair_key(int above, int below) { return ((uint64_t)(uint32_t)above << 32) | (uint32_t)below; }

static int pair_insert(pair_set *s, uint64_t key)
{
    if (2 * (s->count + 1) > s->mask + 1) {
        size_t size = 2 * (s->mask + 1);
        uint64_t *keys = calloc(size, sizeof *keys);
        if (!keys)
            return 0;
        for (size_t i = 0; i <= s->mask; ++i)
            for (size_t h = s->keys[i] ? s->keys[i] * 0x9e3779b97f4a7c15ull : 0; s->keys[i]; ++h)
                if (!keys[h & (size - 1)]) {
                    keys[h & (size - 1)] = s->keys[i];
                    break;
                }
        free(s->keys);
        s->keys = keys;
        s->mask = size - 1;
    }
    for (size_t h = key * 0x9e3779b97f4a7c15ull;; ++h) {
        uint64_t *k = &s->keys[h & s->mask];
        if (*k == key)
            return 1;
        if (!*k) {
            *k = key;
            s->count++;
            return 1;
        }
    }
}

static int pair_has(const pair_set *s, uint64_t key)
{
    for (size_t h = key * 0x9e3779b97f4a7c15ull;; ++h) {
        uint64_t k = s->keys[h & s->mask];
        if (k == key)
            return 1;
        if (!k)
            return 0;
    }
}

/* One ray: the vanes it crosses before the body, in order, each pair more
 * than the tolerance apart added to the set as (nearer, farther). */
static int crossing_ray(const plm_world *w, vec3 o, vec3 d, double tolerance, pair_set *set)
{
    int feather[PLM_VISIBILITY_MAX_LAYERS], n = 0, instance;
    double at[PLM_VISIBILITY_MAX_LAYERS], t, tnear = 0.0;
    while (n < PLM_VISIBILITY_MAX_LAYERS && plm_world_first_hit(w, o, d, tnear, INFINITY, &instance, &t)) {
        const plm_instance *in = &w->scene->instances[instance];
        if (in->part == PLM_PART_BODY)
            break;
        if (in->part == PLM_PART_VANE && in->feather > 0)
            feather[n] = in->feather, at[n++] = t;
        tnear = t + w->epsilon;
    }
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b)
            if (feather[a] != feather[b] && at[b] - at[a] > tolerance &&
                !pair_insert(set, pair_key(feather[a], feather[b])))
                return 0;
    return 1;
}

plm_result plm_visibility_crossings(const plm_world *w, const plm_crossing_grid *g, plm_crossings *out,
                                    plm_error *err)
{
    memset(out, 0, sizeof *out);
    pair_set set = {calloc(1024, sizeof(uint64_t)), 1023, 0};
    if (!set.keys)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for the crossing pairs");
    vec3 d = v3_normalize(g->dir);
    for (int j = 0; j < g->nv; ++j)
        for (int i = 0; i < g->nu; ++i) {
            vec3 o = v3_add(g->origin, v3_add(v3_scale(g->u, (i + 0.5) / g->nu), v3_scale(g->v, (j + 0.5) / g->nv)));
            out->rays++;
            if (!crossing_ray(w, o, d, g->tolerance, &set)) {
                free(set.keys);
                return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for the crossing pairs");
            }
        }
    out->ordered = (long long)set.count;
    for (size_t k = 0; k <= set.mask; ++k) {
        uint64_t key = set.keys[k];
        int above = (int)(key >> 32), below = (int)(key & 0xffffffffu);
        if (key && above < below && pair_has(&set, pair_key(below, above))) {
            if (!out->pairs++)
                out->example[0] = above, out->example[1] = below;
        }
    }
    free(set.keys);
    return PLM_OK;
}
