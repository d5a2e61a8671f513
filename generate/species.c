#include "generate/species.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "common/json.h"
#include "common/rng.h"
#include "common/vec.h"
#include "generate/outline.h"

void plm_species_default(plm_species *s)
{
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "%s", "default");
    plm_shape *sh = &s->shape;
    sh->length = 60.0;
    sh->calamus_length = 8.0;
    sh->rachis_base_width = 1.2;
    sh->rachis_tip_width = 0.2;
    sh->rachis_taper = 1.0;
    sh->bend_out_of_plane = plm_radians(5.0);
    static const double t[4] = {0.0, 0.4, 0.8, 1.0}, w[4] = {9.0, 11.0, 9.0, 6.0};
    for (int side = 0; side < 2; ++side) {
        sh->width[side].count = 4;
        memcpy(sh->width[side].t, t, sizeof t);
        memcpy(sh->width[side].width, w, sizeof w);
    }
    sh->curl = plm_radians(5.0);
    sh->tip_shape = PLM_TIP_ROUNDED;
    sh->tip_length = 0.25;
    sh->barb_angle_base[0] = sh->barb_angle_base[1] = plm_radians(50.0);
    sh->barb_angle_tip[0] = sh->barb_angle_tip[1] = plm_radians(35.0);
    sh->barb_curvature = plm_radians(10.0);
    sh->barb_density = 25.0;
    sh->plumulaceous = 0.25;
    sh->split_gap = 0.8;
    s->pigment.band_width = 0.5;
    s->pigment.tip_length = 0.15;
    s->pigment.barb_jitter = 0.3;
}

/* Reads an angle in degrees into radians. */
static plm_result angle_field(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                              double def_rad, double lo_deg, double hi_deg, double *out)
{
    double deg;
    plm_result rc = plm_json_number(r, obj, path, key, plm_degrees(def_rad), lo_deg, hi_deg, &deg);
    *out = plm_radians(deg);
    return rc;
}

#define TRY(expr)                                                                                            \
    do {                                                                                                     \
        plm_result rc_ = (expr);                                                                             \
        if (rc_ != PLM_OK)                                                                                   \
            return rc_;                                                                                      \
    } while (0)

static plm_result parse_rachis(const plm_json_reader *r, const cJSON *obj, plm_shape *sh)
{
    static const char *const keys[] = {"base_width", "tip_width", "taper", "bend_in_plane", "bend_out_of_plane",
                                       "twist", NULL};
    const char *p = "shape.rachis";
    TRY(plm_json_check_object(r, obj, p, keys));
    TRY(plm_json_number(r, obj, p, "base_width", sh->rachis_base_width, 0.01, 50.0, &sh->rachis_base_width));
    TRY(plm_json_number(r, obj, p, "tip_width", sh->rachis_tip_width, 0.01, 50.0, &sh->rachis_tip_width));
    TRY(plm_json_number(r, obj, p, "taper", sh->rachis_taper, 0.1, 10.0, &sh->rachis_taper));
    TRY(angle_field(r, obj, p, "bend_in_plane", sh->bend_in_plane, -90.0, 90.0, &sh->bend_in_plane));
    TRY(angle_field(r, obj, p, "bend_out_of_plane", sh->bend_out_of_plane, -90.0, 90.0, &sh->bend_out_of_plane));
    return angle_field(r, obj, p, "twist", sh->twist, -180.0, 180.0, &sh->twist);
}

/* "width": [[t, mm], ...] with t strictly increasing from 0 to 1. */
static plm_result parse_width(const plm_json_reader *r, const cJSON *obj, const char *path, plm_width_profile *w)
{
    static const char *const keys[] = {"width", NULL};
    TRY(plm_json_check_object(r, obj, path, keys));
    const cJSON *arr = cJSON_GetObjectItemCaseSensitive(obj, "width");
    if (!arr)
        return PLM_OK;
    int n = cJSON_GetArraySize(arr);
    if (!cJSON_IsArray(arr) || n < 2 || n > PLM_WIDTH_POINTS_MAX)
        return plm_json_fail(r, path, "width", "expected 2 to %d pairs [t, width_mm]", PLM_WIDTH_POINTS_MAX);
    for (int i = 0; i < n; ++i) {
        const cJSON *pair = cJSON_GetArrayItem(arr, i);
        char key[32];
        snprintf(key, sizeof key, "width[%d]", i);
        if (!cJSON_IsArray(pair) || cJSON_GetArraySize(pair) != 2 || !cJSON_IsNumber(pair->child) ||
            !cJSON_IsNumber(pair->child->next))
            return plm_json_fail(r, path, key, "expected a pair [t, width_mm]");
        double t = pair->child->valuedouble, v = pair->child->next->valuedouble;
        if (!(t >= 0.0 && t <= 1.0))
            return plm_json_fail(r, path, key, "position %g is outside the vane [0, 1]", t);
        if (i > 0 && !(t > w->t[i - 1]))
            return plm_json_fail(r, path, key, "positions must increase (%g follows %g)", t, w->t[i - 1]);
        if (!(v >= 0.0 && v <= 500.0))
            return plm_json_fail(r, path, key, "width %g mm is out of range [0, 500]", v);
        w->t[i] = t;
        w->width[i] = v;
    }
    if (w->t[0] != 0.0 || w->t[n - 1] != 1.0)
        return plm_json_fail(r, path, "width", "positions must start at 0 and end at 1");
    w->count = n;
    return PLM_OK;
}

static plm_result parse_vane(const plm_json_reader *r, const cJSON *obj, plm_shape *sh)
{
    static const char *const keys[] = {"left", "right", "curl", "tip", NULL};
    static const char *const tip_keys[] = {"shape", "length", NULL};
    static const char *const shapes[] = {"rounded", "pointed", "notched", NULL};
    const char *p = "shape.vane";
    TRY(plm_json_check_object(r, obj, p, keys));
    const cJSON *left = cJSON_GetObjectItemCaseSensitive(obj, "left");
    const cJSON *right = cJSON_GetObjectItemCaseSensitive(obj, "right");
    if (left)
        TRY(parse_width(r, left, "shape.vane.left", &sh->width[0]));
    if (right)
        TRY(parse_width(r, right, "shape.vane.right", &sh->width[1]));
    TRY(angle_field(r, obj, p, "curl", sh->curl, -60.0, 60.0, &sh->curl));
    const cJSON *tip = cJSON_GetObjectItemCaseSensitive(obj, "tip");
    if (!tip)
        return PLM_OK;
    int shape = (int)sh->tip_shape;
    TRY(plm_json_check_object(r, tip, "shape.vane.tip", tip_keys));
    TRY(plm_json_enum(r, tip, "shape.vane.tip", "shape", shapes, shape, &shape));
    sh->tip_shape = (plm_tip_shape)shape;
    return plm_json_number(r, tip, "shape.vane.tip", "length", sh->tip_length, 0.01, 0.9, &sh->tip_length);
}

/* Barb angles for both sides, then optional "left"/"right" objects that
 * override them for one side (flight feathers differ between vanes). */
static plm_result parse_barbs(const plm_json_reader *r, const cJSON *obj, plm_shape *sh)
{
    static const char *const keys[] = {"angle_base", "angle_tip", "curvature", "density", "left", "right", NULL};
    static const char *const side_keys[] = {"angle_base", "angle_tip", NULL};
    static const char *const side_paths[2] = {"shape.barbs.left", "shape.barbs.right"};
    const char *p = "shape.barbs";
    TRY(plm_json_check_object(r, obj, p, keys));
    double base = sh->barb_angle_base[0], tip = sh->barb_angle_tip[0];
    TRY(angle_field(r, obj, p, "angle_base", base, 5.0, 90.0, &base));
    TRY(angle_field(r, obj, p, "angle_tip", tip, 5.0, 90.0, &tip));
    for (int side = 0; side < 2; ++side) {
        sh->barb_angle_base[side] = base;
        sh->barb_angle_tip[side] = tip;
        const cJSON *so = cJSON_GetObjectItemCaseSensitive(obj, side ? "right" : "left");
        if (!so)
            continue;
        TRY(plm_json_check_object(r, so, side_paths[side], side_keys));
        TRY(angle_field(r, so, side_paths[side], "angle_base", base, 5.0, 90.0, &sh->barb_angle_base[side]));
        TRY(angle_field(r, so, side_paths[side], "angle_tip", tip, 5.0, 90.0, &sh->barb_angle_tip[side]));
    }
    TRY(angle_field(r, obj, p, "curvature", sh->barb_curvature, -45.0, 80.0, &sh->barb_curvature));
    return plm_json_number(r, obj, p, "density", sh->barb_density, 1.0, 200.0, &sh->barb_density);
}

/* Splits either listed one by one or drawn from a seed:
 *   "splits": {"list": [{"position": 0.5, "depth": 0.4, "side": "left"}], "gap": 0.8}
 *   "splits": {"count": 3, "seed": 7, "positions": [0.3, 0.9], "depths": [0.2, 0.6], "gap": 0.8} */
static plm_result parse_splits(const plm_json_reader *r, const cJSON *obj, plm_shape *sh)
{
    static const char *const keys[] = {"list", "count", "seed", "positions", "depths", "gap", NULL};
    static const char *const item_keys[] = {"position", "depth", "side", NULL};
    static const char *const sides[] = {"left", "right", NULL};
    const char *p = "shape.splits";
    TRY(plm_json_check_object(r, obj, p, keys));
    TRY(plm_json_number(r, obj, p, "gap", sh->split_gap, 0.0, 20.0, &sh->split_gap));
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(obj, "list");
    if (list) {
        int n = cJSON_GetArraySize(list);
        if (!cJSON_IsArray(list) || n > PLM_SPLITS_MAX)
            return plm_json_fail(r, p, "list", "expected an array of at most %d splits", PLM_SPLITS_MAX);
        if (cJSON_GetObjectItemCaseSensitive(obj, "count"))
            return plm_json_fail(r, p, "count", "give either \"list\" or \"count\", not both");
        for (int i = 0; i < n; ++i) {
            char path[64];
            snprintf(path, sizeof path, "shape.splits.list[%d]", i);
            const cJSON *it = cJSON_GetArrayItem(list, i);
            plm_split *s = &sh->splits[i];
            TRY(plm_json_check_object(r, it, path, item_keys));
            /* Wide ranges here; plm_species_validate says what fits the vane. */
            TRY(plm_json_number(r, it, path, "position", 0.5, -1e9, 1e9, &s->position));
            TRY(plm_json_number(r, it, path, "depth", 0.3, -1e9, 1e9, &s->depth));
            TRY(plm_json_enum(r, it, path, "side", sides, i % 2, &s->side));
        }
        sh->split_count = n;
        return PLM_OK;
    }
    int count = 0, seed = 1;
    double pos[2] = {0.3, 0.9}, depth[2] = {0.2, 0.6};
    TRY(plm_json_int(r, obj, p, "count", 0, 0, PLM_SPLITS_MAX, &count));
    TRY(plm_json_int(r, obj, p, "seed", 1, 0, 2147483647, &seed));
    const char *range_keys[2] = {"positions", "depths"};
    double *ranges[2] = {pos, depth};
    for (int k = 0; k < 2; ++k) {
        const cJSON *a = cJSON_GetObjectItemCaseSensitive(obj, range_keys[k]);
        if (!a)
            continue;
        if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != 2 || !cJSON_IsNumber(a->child) ||
            !cJSON_IsNumber(a->child->next) || !(a->child->valuedouble <= a->child->next->valuedouble))
            return plm_json_fail(r, p, range_keys[k], "expected [min, max] with min <= max");
        ranges[k][0] = a->child->valuedouble;
        ranges[k][1] = a->child->next->valuedouble;
    }
    plm_rng rng;
    plm_rng_seed(&rng, (uint64_t)seed, 0x5711u);
    for (int i = 0; i < count; ++i) {
        plm_split *s = &sh->splits[i];
        s->position = pos[0] + (pos[1] - pos[0]) * plm_rng_uniform(&rng);
        s->depth = depth[0] + (depth[1] - depth[0]) * plm_rng_uniform(&rng);
        s->side = plm_rng_uniform(&rng) < 0.5 ? 0 : 1;
    }
    sh->split_count = count;
    return PLM_OK;
}

static plm_result parse_pigment(const plm_json_reader *r, const cJSON *obj, plm_pigment *pg)
{
    static const char *const keys[] = {"bands", "band_width", "tip_length", "barb_jitter", "seed", NULL};
    const char *p = "pigment";
    int seed = (int)pg->seed;
    TRY(plm_json_check_object(r, obj, p, keys));
    TRY(plm_json_int(r, obj, p, "bands", pg->band_count, 0, 200, &pg->band_count));
    TRY(plm_json_number(r, obj, p, "band_width", pg->band_width, 0.0, 1.0, &pg->band_width));
    TRY(plm_json_number(r, obj, p, "tip_length", pg->tip_length, 0.0, 1.0, &pg->tip_length));
    TRY(plm_json_number(r, obj, p, "barb_jitter", pg->barb_jitter, 0.0, 1.0, &pg->barb_jitter));
    TRY(plm_json_int(r, obj, p, "seed", seed, 0, 2147483647, &seed));
    pg->seed = (unsigned long long)seed;
    return PLM_OK;
}

static plm_result parse_shape(const plm_json_reader *r, const cJSON *obj, plm_shape *sh)
{
    static const char *const keys[] = {"length", "calamus_length", "rachis", "vane", "barbs",
                                       "plumulaceous", "splits", NULL};
    const char *p = "shape";
    TRY(plm_json_check_object(r, obj, p, keys));
    TRY(plm_json_number(r, obj, p, "length", sh->length, 1.0, 2000.0, &sh->length));
    TRY(plm_json_number(r, obj, p, "calamus_length", sh->calamus_length, 0.0, 1000.0, &sh->calamus_length));
    TRY(plm_json_number(r, obj, p, "plumulaceous", sh->plumulaceous, 0.0, 0.95, &sh->plumulaceous));
    const cJSON *sub;
    if ((sub = cJSON_GetObjectItemCaseSensitive(obj, "rachis")))
        TRY(parse_rachis(r, sub, sh));
    if ((sub = cJSON_GetObjectItemCaseSensitive(obj, "vane")))
        TRY(parse_vane(r, sub, sh));
    if ((sub = cJSON_GetObjectItemCaseSensitive(obj, "barbs")))
        TRY(parse_barbs(r, sub, sh));
    if ((sub = cJSON_GetObjectItemCaseSensitive(obj, "splits")))
        TRY(parse_splits(r, sub, sh));
    return PLM_OK;
}

static plm_result parse_species(const plm_json_reader *r, const cJSON *root, plm_species *out)
{
    static const char *const keys[] = {"name", "description", "source", "shape", "pigment", "optics", NULL};
    TRY(plm_json_check_object(r, root, "", keys));
    const char *name = NULL;
    TRY(plm_json_string(r, root, "", "name", "unnamed", &name));
    snprintf(out->name, sizeof out->name, "%s", name);
    const cJSON *sub;
    if ((sub = cJSON_GetObjectItemCaseSensitive(root, "shape")))
        TRY(parse_shape(r, sub, &out->shape));
    if ((sub = cJSON_GetObjectItemCaseSensitive(root, "pigment")))
        TRY(parse_pigment(r, sub, &out->pigment));
    /* The optics block is the renderer's: scene/ reads it from the same file. */
    if ((sub = cJSON_GetObjectItemCaseSensitive(root, "optics")) && !cJSON_IsObject(sub))
        return plm_json_fail(r, "", "optics", "expected an object");
    return PLM_OK;
}

plm_result plm_species_parse(const cJSON *root, const char *file, plm_species *out, plm_error *err)
{
    plm_json_reader r = {file, err};
    plm_species_default(out);
    plm_result rc = parse_species(&r, root, out);
    if (rc == PLM_OK)
        rc = plm_species_validate(out, file, err);
    if (rc != PLM_OK)
        plm_species_free(out);
    return rc;
}

plm_result plm_species_load(const char *path, plm_species *out, plm_error *err)
{
    cJSON *root = NULL;
    plm_species_default(out);
    plm_result rc = plm_json_load(path, &root, err);
    if (rc != PLM_OK)
        return rc;
    rc = plm_species_parse(root, path, out, err);
    cJSON_Delete(root);
    return rc;
}

static double max_width(const plm_width_profile *w)
{
    double m = 0.0;
    for (int i = 0; i < w->count; ++i)
        m = fmax(m, w->width[i]);
    return m;
}

plm_result plm_species_validate(const plm_species *s, const char *file, plm_error *err)
{
    plm_json_reader r = {file ? file : "(species)", err};
    const plm_shape *sh = &s->shape;
    if (!(sh->calamus_length < 0.9 * sh->length))
        return plm_json_fail(&r, "shape", "calamus_length", "%g mm leaves no room for the vanes: it must be "
                             "below 90%% of shape.length (%g mm)", sh->calamus_length, 0.9 * sh->length);
    if (sh->rachis_tip_width > sh->rachis_base_width)
        return plm_json_fail(&r, "shape.rachis", "tip_width", "%g mm is wider than the base (base_width %g mm); "
                             "the allowed range is (0, base_width]", sh->rachis_tip_width, sh->rachis_base_width);
    for (int side = 0; side < 2; ++side) {
        const char *path = side ? "shape.vane.right" : "shape.vane.left";
        double w = max_width(&sh->width[side]);
        /* The vane must reach beyond the rachis, or there is nothing to render. */
        if (!(w > sh->rachis_base_width))
            return plm_json_fail(&r, path, "width", "the widest point (%g mm) must exceed the rachis base width "
                                 "(%g mm)", w, sh->rachis_base_width);
        if (w > 2.0 * sh->length)
            return plm_json_fail(&r, path, "width", "the widest point (%g mm) exceeds twice the feather length "
                                 "(%g mm)", w, 2.0 * sh->length);
    }
    double lo = fmin(fmin(sh->barb_angle_base[0], sh->barb_angle_tip[0]),
                     fmin(sh->barb_angle_base[1], sh->barb_angle_tip[1]));
    if (!(sh->barb_curvature < lo - plm_radians(2.0)))
        return plm_json_fail(&r, "shape.barbs", "curvature", "%g degrees would turn barbs back toward the rachis: "
                             "it must stay below the smallest barb angle minus 2 (%g degrees)",
                             plm_degrees(sh->barb_curvature), plm_degrees(lo) - 2.0);
    for (int i = 0; i < sh->split_count; ++i) {
        char path[64];
        const plm_split *sp = &sh->splits[i];
        snprintf(path, sizeof path, "shape.splits[%d]", i);
        if (!(sp->position > sh->plumulaceous && sp->position < 1.0))
            return plm_json_fail(&r, path, "position", "%g is beyond the pennaceous vane: allowed (%g, 1), "
                                 "from the end of shape.plumulaceous to the tip", sp->position, sh->plumulaceous);
        if (!(sp->depth > 0.0 && sp->depth <= 1.0))
            return plm_json_fail(&r, path, "depth", "%g is beyond the vane: allowed (0, 1], a fraction of the "
                                 "vane width", sp->depth);
    }
    /* What only the barb field can tell: barbs that would fold over. */
    plm_outline o;
    return plm_outline_init(&o, sh, r.file, err);
}

void plm_species_free(plm_species *s)
{
    memset(s, 0, sizeof *s);
}
