#include "generate/species.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "common/json.h"
#include "common/params.h"
#include "common/rng.h"
#include "common/vec.h"
#include "generate/outline.h"

/* The parameter tables of the species file's blocks (common/params.h): one
 * range per field, read by the parser, by `plumage params` and, through it,
 * by docs/species.md. Relations between fields that a single range cannot
 * express are checked in plm_species_validate. */
#define SHAPE_FIELD(name, member, lo, hi, unit, meaning) {name, PLM_PARAM_NUMBER, offsetof(plm_shape, member), lo, hi, unit, meaning, 0}
#define SHAPE_ANGLE(name, member, lo, hi, meaning) {name, PLM_PARAM_ANGLE, offsetof(plm_shape, member), lo, hi, "degrees", meaning, 0}

static const plm_param shape_params[] = {
    SHAPE_FIELD("length", length, 1.0, 2000.0, "mm", "calamus base to tip along the rachis"),
    SHAPE_FIELD("calamus_length", calamus_length, 0.0, 1000.0, "mm",
                "bare base before the vanes; below 90% of length"),
    SHAPE_FIELD("plumulaceous", plumulaceous, 0.0, 0.95, "fraction of the vaned length",
                "downy (fluffy) base: barbs leaving the rachis here are loose strands"),
    {"seed", PLM_PARAM_SEED, offsetof(plm_shape, seed), 0.0, 2147483647.0, "",
     "this feather's own draws: its splits, barb ends and tip fray", 0},
};
const plm_param_block plm_shape_param_block = {"shape", "the feather's size (also rachis, vane, barbs, splits)",
                                               shape_params, PLM_PARAM_COUNT(shape_params)};

static const plm_param rachis_params[] = {
    SHAPE_FIELD("base_width", rachis_base_width, 0.01, 50.0, "mm", "rachis diameter at the base"),
    SHAPE_FIELD("tip_width", rachis_tip_width, 0.01, 50.0, "mm", "diameter at the rachis end; at most base_width"),
    SHAPE_FIELD("taper", rachis_taper, 0.1, 10.0, "", "exponent: width = base + (tip - base) s^taper along the rachis"),
    SHAPE_ANGLE("bend_in_plane", bend_in_plane, -90.0, 90.0, "total turn in the vane plane; > 0 toward the right vane"),
    SHAPE_ANGLE("bend_out_of_plane", bend_out_of_plane, -90.0, 90.0, "total turn out of the plane; > 0 ventral"),
    SHAPE_ANGLE("twist", twist, -180.0, 180.0, "turn of the vane plane about the rachis, base to tip"),
};
const plm_param_block plm_rachis_param_block = {"shape.rachis", "the shaft", rachis_params,
                                                PLM_PARAM_COUNT(rachis_params)};

static const plm_param vane_params[] = {
    SHAPE_ANGLE("curl", curl, -60.0, 60.0, "slope of the vane at its widest point (cupping); > 0 edges ventral"),
};
const plm_param_block plm_vane_param_block = {"shape.vane", "the vanes (also left.width, right.width, tip)",
                                              vane_params, PLM_PARAM_COUNT(vane_params)};

/* shape.vane.tip's "shape" is one of these names (read beside the table). */
static const char *const tip_shapes[] = {"rounded", "pointed", "notched", "truncate", "square", NULL};
static const plm_param tip_params[] = {
    SHAPE_FIELD("length", tip_length, 0.01, 0.9, "fraction of the vaned length", "where the closing starts"),
};
const plm_param_block plm_vane_tip_param_block = {"shape.vane.tip",
                                                  "the vane's tip (also shape: rounded, pointed, notched, truncate, "
                                                  "square)",
                                                  tip_params, PLM_PARAM_COUNT(tip_params)};

/* The first two rows also serve shape.barbs.left and .right, read into
 * side 1 by offsetting the target one double (barb_angle_*[1]). */
static const plm_param barbs_params[] = {
    SHAPE_ANGLE("angle_base", barb_angle_base[0], 5.0, 90.0,
                "barb angle to the rachis (toward the tip) at the vane's base; linear to angle_tip"),
    SHAPE_ANGLE("angle_tip", barb_angle_tip[0], 5.0, 90.0, "barb angle at the vane's tip"),
    SHAPE_ANGLE("curvature", barb_curvature, -45.0, 80.0,
                "turn of a barb toward the tip between rachis and vane edge; below the smallest angle minus 2"),
    SHAPE_FIELD("density", barb_density, 1.0, 200.0, "per cm", "barbs per cm along the rachis, per side"),
    SHAPE_FIELD("end_jitter", barb_end_jitter, 0.0, 20.0, "barb spacings",
                "a barb ends up to this much short of the outline: the ragged edge"),
    SHAPE_FIELD("fray", barb_fray, 0.0, 50.0, "barb spacings", "below the tip, barbs part over this distance"),
};
const plm_param_block plm_barbs_param_block = {"shape.barbs", "barb angles, curvature and density (also left, right)",
                                               barbs_params, PLM_PARAM_COUNT(barbs_params)};
const plm_param_block plm_barb_side_param_block = {"shape.barbs.left", "one vane's own barb angles (also .right)",
                                                   barbs_params, 2};

static const plm_param fluff_params[] = {
    SHAPE_FIELD("density", fluff_density, 0.0, 200.0, "per cm",
                "down barbs per cm along the rachis in the downy base and on the afterfeather, per side; 0 none"),
    SHAPE_FIELD("length", fluff_length, 0.1, 4.0, "vane widths",
                "a down barb's length over the vane's width where it leaves the rachis"),
    SHAPE_ANGLE("curl", fluff_curl, 0.0, 720.0, "RMS turn of a down barb's direction from root to end (random walk)"),
    SHAPE_FIELD("thickness", fluff_thickness, 0.002, 0.5, "mm", "a down barb's diameter at its root; thins to a "
                "quarter at its end"),
    SHAPE_FIELD("barbules", fluff_barbules, 0.0, 40.0, "per mm", "barbules along a down barb; 0 bare barbs"),
    {"afterfeather", PLM_PARAM_BOOL, offsetof(plm_shape, afterfeather), 0.0, 1.0, "",
     "a downy afterfeather on the rachis's underside where the vanes begin", 0},
    SHAPE_FIELD("afterfeather_size", afterfeather_size, 0.02, 0.9, "fraction of length", "the afterfeather's length"),
};
const plm_param_block plm_fluff_param_block = {"shape.fluff", "the fluffy base and the afterfeather as fibers",
                                               fluff_params, PLM_PARAM_COUNT(fluff_params)};

static const plm_param splits_params[] = {
    {"frequency", PLM_PARAM_NUMBER, offsetof(plm_shape, split_frequency), 0.0, 16.0, "per vane",
     "mean splits per vane, drawn for each feather from shape.seed; 0 with a list", 0},
    {"positions", PLM_PARAM_PAIR, offsetof(plm_shape, split_positions), 0.0, 1.0, "fraction of the vaned length",
     "[min, max] of the drawn positions", 0},
    {"depths", PLM_PARAM_PAIR, offsetof(plm_shape, split_depths), 0.0, 1.0, "fraction of the vane width",
     "[min, max] of the drawn depths", PLM_PARAM_OPEN_MIN},
    {"gap", PLM_PARAM_NUMBER, offsetof(plm_shape, split_gap), 0.0, 20.0, "mm", "split width at the vane edge", 0},
};
const plm_param_block plm_splits_param_block = {"shape.splits", "gaps between barbs (also list)", splits_params,
                                                PLM_PARAM_COUNT(splits_params)};

static const plm_param emargination_params[] = {
    {"position", PLM_PARAM_NUMBER, offsetof(plm_emargination, position), 0.0, 1.0, "fraction of the vaned length",
     "centre of the narrowing", 0},
    {"depth", PLM_PARAM_NUMBER, offsetof(plm_emargination, depth), 0.0, 0.9, "fraction of the width",
     "how much narrower the vane is beyond it; 0 none", 0},
    {"length", PLM_PARAM_NUMBER, offsetof(plm_emargination, length), 0.01, 0.5, "fraction of the vaned length",
     "over which it narrows", 0},
};
const plm_param_block plm_emargination_param_block[2] = {
    {"shape.vane.left.emargination", "a step in one vane's width (also right): emarginated primaries",
     emargination_params, PLM_PARAM_COUNT(emargination_params)},
    {"shape.vane.right.emargination", "the right vane's", emargination_params, PLM_PARAM_COUNT(emargination_params)}};

static const char *const sides[] = {"left", "right", NULL};
static const plm_param split_params[] = {
    {"position", PLM_PARAM_NUMBER, offsetof(plm_split, position), 0.0, 1.0, "fraction of the vaned length",
     "where the split's barb leaves the rachis; beyond shape.plumulaceous", PLM_PARAM_OPEN_MAX},
    {"depth", PLM_PARAM_NUMBER, offsetof(plm_split, depth), 0.0, 1.0, "fraction of the vane width",
     "how far the gap reaches in from the edge", PLM_PARAM_OPEN_MIN},
};
const plm_param_block plm_split_param_block = {"shape.splits.list[]",
                                               "one split of the list (also side: left or right, alternating by default)",
                                               split_params, PLM_PARAM_COUNT(split_params)};

static const plm_param pigment_params[] = {
    {"bands", PLM_PARAM_INT, offsetof(plm_pigment, band_count), 0.0, 200.0, "",
     "dark bars across the vane, following the barbs", 0},
    {"band_width", PLM_PARAM_NUMBER, offsetof(plm_pigment, band_width), 0.0, 1.0, "fraction of a period",
     "dark part of each bar period", 0},
    {"tip_length", PLM_PARAM_NUMBER, offsetof(plm_pigment, tip_length), 0.0, 1.0, "fraction of the vane",
     "length of the tip colour ramp", 0},
    {"base_length", PLM_PARAM_NUMBER, offsetof(plm_pigment, base_length), 0.0, 1.0, "fraction of the vane",
     "past the downy base, its colour (the optics' base_tint) fades over this much of the vane", 0},
    {"barb_jitter", PLM_PARAM_NUMBER, offsetof(plm_pigment, barb_jitter), 0.0, 1.0, "",
     "amplitude of the per-barb variation", 0},
    {"barb_clump", PLM_PARAM_NUMBER, offsetof(plm_pigment, barb_clump), 1.0, 100.0, "barbs",
     "half of the variation is shared by about this many neighbouring barbs, half is each barb's own", 0},
    {"seed", PLM_PARAM_SEED, offsetof(plm_pigment, seed), 0.0, 2147483647.0, "", "per-barb values", 0},
};
const plm_param_block plm_pigment_param_block = {"pigment", "pigment variation: bands, tip, downy base, per-barb", pigment_params,
                                                 PLM_PARAM_COUNT(pigment_params)};

#define TRY(expr)                                                                                            \
    do {                                                                                                     \
        plm_result rc_ = (expr);                                                                             \
        if (rc_ != PLM_OK)                                                                                   \
            return rc_;                                                                                      \
    } while (0)

/* A species read from a file or from inside another (a scene's inline
 * species): `prefix` is where its root lies, "" for a species file. */
typedef struct species_reader {
    plm_json_reader json;
    const char *prefix;
} species_reader;

/* prefix.path into buf */
static const char *at(const species_reader *r, const char *path, char *buf, size_t size)
{
    snprintf(buf, size, "%s%s%s", r->prefix, r->prefix[0] && path[0] ? "." : "", path);
    return buf;
}

static plm_result read_block(const species_reader *r, const cJSON *obj, const char *path, const plm_param_block *b,
                             const char *const *extra, void *target)
{
    char full[PLM_SPECIES_PATH_MAX];
    return plm_params_read(&r->json, obj, at(r, path, full, sizeof full), b, extra, target);
}

static plm_result fail(const species_reader *r, const char *path, const char *key, const char *msg)
{
    char full[PLM_SPECIES_PATH_MAX];
    return plm_json_fail(&r->json, at(r, path, full, sizeof full), key, "%s", msg);
}

/* "width": [[t, mm], ...] with t strictly increasing from 0 to 1, and an
 * optional "emargination" block. */
static plm_result parse_width(const species_reader *sr, const cJSON *obj, int side, plm_width_profile *w,
                              plm_emargination *e)
{
    static const char *const keys[] = {"width", "emargination", NULL};
    char path[PLM_SPECIES_PATH_MAX];
    const plm_json_reader *r = &sr->json;
    const plm_param_block *em_block = &plm_emargination_param_block[side];
    at(sr, side ? "shape.vane.right" : "shape.vane.left", path, sizeof path);
    TRY(plm_json_check_object(r, obj, path, keys));
    const cJSON *em = cJSON_GetObjectItemCaseSensitive(obj, "emargination");
    if (em)
        TRY(read_block(sr, em, em_block->name, em_block, NULL, e));
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
        if (!(v >= 0.0 && v <= PLM_WIDTH_MAX_MM))
            return plm_json_fail(r, path, key, "width %g mm is out of range [0, %g]", v, PLM_WIDTH_MAX_MM);
        w->t[i] = t;
        w->width[i] = v;
    }
    if (w->t[0] != 0.0 || w->t[n - 1] != 1.0)
        return plm_json_fail(r, path, "width", "positions must start at 0 and end at 1");
    w->count = n;
    return PLM_OK;
}

static plm_result parse_vane(const species_reader *r, const cJSON *obj, plm_shape *sh)
{
    static const char *const extra[] = {"left", "right", "tip", NULL};
    TRY(read_block(r, obj, "shape.vane", &plm_vane_param_block, extra, sh));
    const cJSON *side[2] = {cJSON_GetObjectItemCaseSensitive(obj, "left"),
                            cJSON_GetObjectItemCaseSensitive(obj, "right")};
    for (int k = 0; k < 2; ++k)
        if (side[k])
            TRY(parse_width(r, side[k], k, &sh->width[k], &sh->emargination[k]));
    static const char *const tip_extra[] = {"shape", NULL};
    const cJSON *tip = cJSON_GetObjectItemCaseSensitive(obj, "tip");
    if (!tip)
        return PLM_OK;
    TRY(read_block(r, tip, "shape.vane.tip", &plm_vane_tip_param_block, tip_extra, sh));
    char path[PLM_SPECIES_PATH_MAX];
    int shape = (int)sh->tip_shape;
    TRY(plm_json_enum(&r->json, tip, at(r, "shape.vane.tip", path, sizeof path), "shape", tip_shapes, shape, &shape));
    sh->tip_shape = (plm_tip_shape)shape;
    return PLM_OK;
}

/* Barb angles for both sides, then optional "left"/"right" objects that
 * override them for one side (flight feathers differ between vanes). */
static plm_result parse_barbs(const species_reader *r, const cJSON *obj, plm_shape *sh)
{
    static const char *const extra[] = {"left", "right", NULL};
    static const char *const side_paths[2] = {"shape.barbs.left", "shape.barbs.right"};
    TRY(read_block(r, obj, "shape.barbs", &plm_barbs_param_block, extra, sh));
    sh->barb_angle_base[1] = sh->barb_angle_base[0];
    sh->barb_angle_tip[1] = sh->barb_angle_tip[0];
    double shared[2] = {sh->barb_angle_base[0], sh->barb_angle_tip[0]};
    for (int side = 0; side < 2; ++side) {
        const cJSON *so = cJSON_GetObjectItemCaseSensitive(obj, side ? "right" : "left");
        if (so)
            TRY(read_block(r, so, side_paths[side], &plm_barb_side_param_block, NULL,
                           (char *)sh + (size_t)side * sizeof(double)));
    }
    /* Side 0's angles are also the shared ones: a left override must not change the right. */
    if (!cJSON_GetObjectItemCaseSensitive(obj, "right")) {
        sh->barb_angle_base[1] = shared[0];
        sh->barb_angle_tip[1] = shared[1];
    }
    return PLM_OK;
}

/* Splits either listed one by one or drawn per feather (plm_outline_init):
 *   "splits": {"list": [{"position": 0.5, "depth": 0.4, "side": "left"}], "gap": 0.8}
 *   "splits": {"frequency": 2, "positions": [0.3, 0.9], "depths": [0.2, 0.6], "gap": 0.8} */
static plm_result parse_splits(const species_reader *r, const cJSON *obj, plm_shape *sh)
{
    static const char *const extra[] = {"list", "count", "seed", NULL};
    /* The draw moved from the species to each feather: say where. */
    if (cJSON_GetObjectItemCaseSensitive(obj, "count"))
        return fail(r, "shape.splits", "count", "splits are drawn per feather now: give \"frequency\" (mean "
                    "splits per vane, 0-16) or a \"list\"");
    if (cJSON_GetObjectItemCaseSensitive(obj, "seed"))
        return fail(r, "shape.splits", "seed", "the feather's draws share one seed: give shape.seed");
    TRY(read_block(r, obj, "shape.splits", &plm_splits_param_block, extra, sh));
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(obj, "list");
    if (!list)
        return PLM_OK;
    int n = cJSON_GetArraySize(list);
    if (!cJSON_IsArray(list) || n > PLM_SPLITS_MAX) {
        char msg[64];
        snprintf(msg, sizeof msg, "expected an array of at most %d splits", PLM_SPLITS_MAX);
        return fail(r, "shape.splits", "list", msg);
    }
    if (cJSON_GetObjectItemCaseSensitive(obj, "frequency"))
        return fail(r, "shape.splits", "frequency", "give either \"list\" or \"frequency\", not both");
    for (int i = 0; i < n; ++i) {
        char path[64];
        snprintf(path, sizeof path, "shape.splits.list[%d]", i);
        static const char *const extra_side[] = {"side", NULL};
        const cJSON *item = cJSON_GetArrayItem(list, i);
        plm_split *s = &sh->splits[i];
        char full[PLM_SPECIES_PATH_MAX];
        *s = (plm_split){0.5, 0.3, i % 2};
        TRY(read_block(r, item, path, &plm_split_param_block, extra_side, s));
        TRY(plm_json_enum(&r->json, item, at(r, path, full, sizeof full), "side", sides, i % 2, &s->side));
    }
    sh->split_count = n;
    sh->split_frequency = 0.0; /* a list replaces the type's draw */
    return PLM_OK;
}

static plm_result parse_shape(const species_reader *r, const cJSON *obj, plm_shape *sh)
{
    static const char *const extra[] = {"rachis", "vane", "barbs", "splits", "fluff", NULL};
    TRY(read_block(r, obj, "shape", &plm_shape_param_block, extra, sh));
    const cJSON *sub;
    if ((sub = cJSON_GetObjectItemCaseSensitive(obj, "fluff")))
        TRY(read_block(r, sub, "shape.fluff", &plm_fluff_param_block, NULL, sh));
    if ((sub = cJSON_GetObjectItemCaseSensitive(obj, "rachis")))
        TRY(read_block(r, sub, "shape.rachis", &plm_rachis_param_block, NULL, sh));
    if ((sub = cJSON_GetObjectItemCaseSensitive(obj, "vane")))
        TRY(parse_vane(r, sub, sh));
    if ((sub = cJSON_GetObjectItemCaseSensitive(obj, "barbs")))
        TRY(parse_barbs(r, sub, sh));
    if ((sub = cJSON_GetObjectItemCaseSensitive(obj, "splits")))
        TRY(parse_splits(r, sub, sh));
    return PLM_OK;
}

/* The type's sizes are at its own length: a species of another length that
 * does not give them gets them scaled (widths, calamus, rachis). */
static void scale_sizes_not_given(const cJSON *shape, double type_length, plm_shape *sh)
{
    double k = sh->length / type_length;
    const cJSON *rachis = cJSON_GetObjectItemCaseSensitive(shape, "rachis");
    const cJSON *vane = cJSON_GetObjectItemCaseSensitive(shape, "vane");
    if (!cJSON_GetObjectItemCaseSensitive(shape, "calamus_length"))
        sh->calamus_length *= k;
    if (!cJSON_GetObjectItemCaseSensitive(rachis, "base_width"))
        sh->rachis_base_width *= k;
    if (!cJSON_GetObjectItemCaseSensitive(rachis, "tip_width"))
        sh->rachis_tip_width *= k;
    for (int side = 0; side < 2; ++side)
        if (!cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(vane, side ? "right" : "left"),
                                              "width"))
            for (int i = 0; i < sh->width[side].count; ++i)
                sh->width[side].width[i] *= k;
}

static plm_result parse_species(const species_reader *r, const cJSON *root, plm_species *out)
{
    static const char *const keys[] = {"name", "type", "description", "source", "shape", "pigment", "optics", NULL};
    char path[PLM_SPECIES_PATH_MAX];
    at(r, "", path, sizeof path);
    TRY(plm_json_check_object(&r->json, root, path, keys));
    int type = PLM_TYPE_CONTOUR;
    TRY(plm_json_enum(&r->json, root, path, "type", plm_feather_type_names, type, &type));
    plm_species_default_of_type(out, (plm_feather_type)type);
    double type_length = out->shape.length;
    const char *name = NULL;
    TRY(plm_json_string(&r->json, root, path, "name", "unnamed", &name));
    snprintf(out->name, sizeof out->name, "%s", name);
    const cJSON *sub;
    if ((sub = cJSON_GetObjectItemCaseSensitive(root, "shape"))) {
        TRY(parse_shape(r, sub, &out->shape));
        scale_sizes_not_given(sub, type_length, &out->shape);
    }
    if ((sub = cJSON_GetObjectItemCaseSensitive(root, "pigment")))
        TRY(read_block(r, sub, "pigment", &plm_pigment_param_block, NULL, &out->pigment));
    /* The optics block is the renderer's: scene/ reads it from the same object. */
    if ((sub = cJSON_GetObjectItemCaseSensitive(root, "optics")) && !cJSON_IsObject(sub))
        return fail(r, "", "optics", "expected an object");
    return PLM_OK;
}

plm_result plm_species_parse_at(const cJSON *root, const char *file, const char *path, plm_species *out,
                                plm_error *err)
{
    species_reader r = {{file, err, 0}, path ? path : ""};
    plm_species_default(out);
    plm_result rc = parse_species(&r, root, out);
    if (rc == PLM_OK)
        rc = plm_species_validate_at(out, file, r.prefix, err);
    if (rc != PLM_OK)
        plm_species_free(out);
    return rc;
}

plm_result plm_species_parse(const cJSON *root, const char *file, plm_species *out, plm_error *err)
{
    return plm_species_parse_at(root, file, "", out, err);
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

/* Every field against its table's range (a species built in code, such as a
 * layout's variant, has not been through the reader). */
static plm_result check_ranges(const species_reader *r, const plm_species *s)
{
    const plm_shape *sh = &s->shape;
    const struct {
        const plm_param_block *block;
        const void *target;
    } blocks[] = {{&plm_shape_param_block, sh},
                  {&plm_rachis_param_block, sh},
                  {&plm_vane_param_block, sh},
                  {&plm_vane_tip_param_block, sh},
                  {&plm_barbs_param_block, sh},
                  {&plm_barb_side_param_block, (const char *)sh + sizeof(double)},
                  {&plm_fluff_param_block, sh},
                  {&plm_splits_param_block, sh},
                  {&plm_emargination_param_block[0], &sh->emargination[0]},
                  {&plm_emargination_param_block[1], &sh->emargination[1]},
                  {&plm_pigment_param_block, &s->pigment}};
    char path[PLM_SPECIES_PATH_MAX];
    for (size_t i = 0; i < sizeof blocks / sizeof blocks[0]; ++i)
        if (plm_params_check(blocks[i].block, blocks[i].target, r->json.err) != PLM_OK) {
            plm_error_prefix(r->json.err, "%s: %s%s", r->json.file, at(r, "", path, sizeof path),
                             r->prefix[0] ? ": " : "");
            return PLM_ERR_INVALID;
        }
    return PLM_OK;
}

plm_result plm_species_validate_at(const plm_species *s, const char *file, const char *prefix, plm_error *err)
{
    species_reader sr = {{file ? file : "(species)", err, 0}, prefix ? prefix : ""};
    const plm_json_reader *r = &sr.json;
    char path[PLM_SPECIES_PATH_MAX];
    const plm_shape *sh = &s->shape;
    TRY(check_ranges(&sr, s));
    if (!(sh->calamus_length < 0.9 * sh->length))
        return plm_json_fail(r, at(&sr, "shape", path, sizeof path), "calamus_length", "%g mm leaves no room for "
                             "the vanes: it must be below 90%% of shape.length (%g mm)", sh->calamus_length,
                             0.9 * sh->length);
    if (sh->rachis_tip_width > sh->rachis_base_width)
        return plm_json_fail(r, at(&sr, "shape.rachis", path, sizeof path), "tip_width", "%g mm is wider than the "
                             "base (base_width %g mm); the allowed range is [0.01, base_width]", sh->rachis_tip_width,
                             sh->rachis_base_width);
    for (int side = 0; side < 2; ++side) {
        at(&sr, side ? "shape.vane.right" : "shape.vane.left", path, sizeof path);
        double w = max_width(&sh->width[side]);
        /* The vane must reach beyond the rachis, or there is nothing to render. */
        if (!(w > sh->rachis_base_width))
            return plm_json_fail(r, path, "width", "the widest point (%g mm) must exceed the rachis base width "
                                 "(%g mm)", w, sh->rachis_base_width);
        if (w > 2.0 * sh->length)
            return plm_json_fail(r, path, "width", "the widest point (%g mm) exceeds twice the feather length "
                                 "(%g mm)", w, 2.0 * sh->length);
    }
    double lo = fmin(fmin(sh->barb_angle_base[0], sh->barb_angle_tip[0]),
                     fmin(sh->barb_angle_base[1], sh->barb_angle_tip[1]));
    if (!(sh->barb_curvature < lo - plm_radians(2.0)))
        return plm_json_fail(r, at(&sr, "shape.barbs", path, sizeof path), "curvature", "%g degrees would turn "
                             "barbs back toward the rachis: it must stay below the smallest barb angle minus 2 (%g "
                             "degrees)", plm_degrees(sh->barb_curvature), plm_degrees(lo) - 2.0);
    if (sh->split_frequency > 0.0) {
        at(&sr, "shape.splits", path, sizeof path);
        if (!(sh->split_positions[0] <= sh->split_positions[1]))
            return plm_json_fail(r, path, "positions", "expected [min, max] with min <= max");
        if (!(sh->split_depths[0] <= sh->split_depths[1]))
            return plm_json_fail(r, path, "depths", "expected [min, max] with min <= max");
        if (!(sh->split_positions[1] > sh->plumulaceous))
            return plm_json_fail(r, path, "positions", "the drawn splits lie in the downy base: the max (%g) must "
                                 "exceed shape.plumulaceous (%g)", sh->split_positions[1], sh->plumulaceous);
        if (sh->split_count > 0)
            return plm_json_fail(r, path, "frequency", "give either a list or a frequency, not both");
    }
    for (int i = 0; i < sh->split_count; ++i) {
        char item[64];
        const plm_split *sp = &sh->splits[i];
        snprintf(item, sizeof item, "shape.splits.list[%d]", i);
        at(&sr, item, path, sizeof path);
        if (plm_params_check(&plm_split_param_block, sp, err) != PLM_OK) {
            plm_error_prefix(err, "%s: %s: ", r->file, path);
            return PLM_ERR_INVALID;
        }
        if (!(sp->position > sh->plumulaceous))
            return plm_json_fail(r, path, "position", "%g is beyond the pennaceous vane: allowed (%g, 1), "
                                 "from the end of shape.plumulaceous to the tip", sp->position, sh->plumulaceous);
    }
    /* What only the barb field can tell: barbs that would fold over. */
    plm_outline o;
    return plm_outline_init(&o, sh, r->file, err);
}

plm_result plm_species_validate(const plm_species *s, const char *file, plm_error *err)
{
    return plm_species_validate_at(s, file, "", err);
}

void plm_species_free(plm_species *s)
{
    memset(s, 0, sizeof *s);
}
