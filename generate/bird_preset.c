/* Bird presets: JSON read field by field (unknown fields are errors), every
 * range in the tables below, which docs/birds.md prints. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "common/json.h"
#include "generate/bird.h"

#define MM_MAX 5000.0 /* an ostrich is 2.7 m long */

const char *const plm_bill_family_names[PLM_BILL_FAMILIES + 1] = {"hooked", "conical", "dagger", NULL};
const char *const plm_pteryla_names[PLM_PTERYLAE + 1] = {"capital", "spinal",  "ventral", "humeral",
                                                         "femoral", "caudal", NULL};

#define DEG(x) ((x) * (PLM_PI / 180.0))
/* The pterylae in the body's parameterisation; together they clothe it all. */
const plm_bird_region plm_pteryla_regions[PLM_PTERYLAE] = {
    {{0.0, 0.27}, {0.0, DEG(180.0)}},           /* capital */
    {{0.27, 0.9}, {0.0, DEG(62.0)}},            /* spinal */
    {{0.27, 0.9}, {DEG(98.0), DEG(180.0)}},     /* ventral */
    {{0.27, 0.56}, {DEG(62.0), DEG(98.0)}},     /* humeral */
    {{0.56, 0.9}, {DEG(62.0), DEG(98.0)}},      /* femoral */
    {{0.9, 1.0}, {0.0, DEG(180.0)}},            /* caudal */
};

static const plm_param measurement_params[] = {
    {"total_length", PLM_PARAM_NUMBER, offsetof(plm_bird_measurements, total_length), 0.0, MM_MAX, "mm",
     "bill tip to tail tip, the bird laid flat", PLM_PARAM_OPEN_MIN},
    {"wing_chord", PLM_PARAM_NUMBER, offsetof(plm_bird_measurements, wing_chord), 0.0, MM_MAX, "mm",
     "the folded wing from the wrist to the longest primary's tip", PLM_PARAM_OPEN_MIN},
    {"tail_length", PLM_PARAM_NUMBER, offsetof(plm_bird_measurements, tail_length), 0.0, MM_MAX, "mm",
     "base of the central tail feathers to their tip", PLM_PARAM_OPEN_MIN},
    {"bill_length", PLM_PARAM_NUMBER, offsetof(plm_bird_measurements, bill_length), 0.0, MM_MAX, "mm",
     "exposed culmen, chord", PLM_PARAM_OPEN_MIN},
    {"bill_depth", PLM_PARAM_NUMBER, offsetof(plm_bird_measurements, bill_depth), 0.0, MM_MAX, "mm",
     "at the base, both mandibles", PLM_PARAM_OPEN_MIN},
    {"head_width", PLM_PARAM_NUMBER, offsetof(plm_bird_measurements, head_width), 0.0, MM_MAX, "mm",
     "across the skull behind the eyes", PLM_PARAM_OPEN_MIN},
    {"tarsus", PLM_PARAM_NUMBER, offsetof(plm_bird_measurements, tarsus), 0.0, MM_MAX, "mm",
     "tarsometatarsus length", PLM_PARAM_OPEN_MIN},
};
const plm_param_block plm_bird_measurement_block = {"measurements", "a bird's measurements (all required)",
                                                    measurement_params, PLM_PARAM_COUNT(measurement_params)};

static const plm_param proportion_params[] = {
    {"neck", PLM_PARAM_NUMBER, offsetof(plm_bird_proportions, neck), 0.2, 2.0, "", "neck width over head width", 0},
    {"breast", PLM_PARAM_NUMBER, offsetof(plm_bird_proportions, breast), 0.5, 5.0, "",
     "breast width over head width", 0},
    {"rump", PLM_PARAM_NUMBER, offsetof(plm_bird_proportions, rump), 0.1, 1.0, "", "rump width over breast width",
     0},
    {"depth", PLM_PARAM_NUMBER, offsetof(plm_bird_proportions, depth), 0.5, 3.0, "",
     "body depth (back to breast) over breast width", 0},
    {"neck_length", PLM_PARAM_NUMBER, offsetof(plm_bird_proportions, neck_length), 0.02, 0.5, "",
     "the neck's share of the body from the bill's base to the tail's", 0},
    {"posture", PLM_PARAM_ANGLE, offsetof(plm_bird_proportions, posture), 0.0, 90.0, "degrees",
     "the body's axis below the horizontal (perched upright: about 55)", 0},
};
const plm_param_block plm_bird_proportion_block = {"proportions", "the skin body's shape",
                                                   proportion_params, PLM_PARAM_COUNT(proportion_params)};

static const plm_param tract_params[] = {
    {"density", PLM_PARAM_NUMBER, offsetof(plm_bird_tract, density), 0.0, 1000.0, "per cm^2",
     "feathers per square centimetre of skin", PLM_PARAM_OPEN_MIN},
    {"size", PLM_PARAM_PAIR, offsetof(plm_bird_tract, size), 0.0, MM_MAX, "mm",
     "feather length at the tract's head end and at its tail end", PLM_PARAM_OPEN_MIN},
    {"flow", PLM_PARAM_ANGLE, offsetof(plm_bird_tract, flow), -90.0, 90.0, "degrees",
     "the flow's turn from head-to-tail toward the ventral side", 0},
    {"elevation", PLM_PARAM_ANGLE, offsetof(plm_bird_tract, elevation), 0.0, 60.0, "degrees",
     "angle between a feather's base and the skin", 0},
};
const plm_param_block plm_bird_tract_block = {"tract", "a feather tract or colour patch", tract_params,
                                              PLM_PARAM_COUNT(tract_params)};

static void bird_default(plm_bird *b)
{
    memset(b, 0, sizeof *b);
    b->p = (plm_bird_proportions){0.8, 2.0, 0.5, 1.15, 0.14, DEG(55.0)};
    b->bill = (plm_bird_surface){{0.05, 0.05, 0.05}, 0.25};
    b->lower_bill = b->bill;
    b->iris = (plm_bird_surface){{0.5, 0.2, 0.05}, 0.05};
    b->skin = (plm_bird_surface){{0.35, 0.33, 0.32}, 0.6};
    b->feet = (plm_bird_surface){{0.3, 0.3, 0.3}, 0.5};
}

/* A [lo, hi] range in file units scaled into the struct, with lo < hi inside [min, max]. */
static plm_result read_range(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                             double min, double max, double scale, double out[2])
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!a)
        return PLM_OK;
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != 2 || !cJSON_IsNumber(a->child) ||
        !cJSON_IsNumber(a->child->next))
        return plm_json_fail(r, path, key, "expected [from, to]");
    double lo = a->child->valuedouble, hi = a->child->next->valuedouble;
    if (!(lo >= min && hi <= max && lo < hi))
        return plm_json_fail(r, path, key, "[%g, %g] must satisfy %g <= from < to <= %g", lo, hi, min, max);
    out[0] = lo * scale;
    out[1] = hi * scale;
    return PLM_OK;
}

/* {"colour": [r, g, b], "roughness": a} */
static plm_result read_surface(const plm_json_reader *r, const cJSON *parent, const char *path, const char *key,
                               const char *colour_key, plm_bird_surface *s)
{
    const cJSON *obj = cJSON_GetObjectItemCaseSensitive(parent, key);
    char p[160];
    snprintf(p, sizeof p, path[0] ? "%s.%s" : "%s%s", path, key);
    if (!obj)
        return PLM_OK;
    const char *keys[] = {colour_key, "roughness", NULL};
    plm_result rc = plm_json_check_object(r, obj, p, keys);
    if (rc == PLM_OK)
        rc = plm_json_rgb(r, obj, p, colour_key, s->colour, 0.0, 1.0, &s->colour);
    if (rc == PLM_OK)
        rc = plm_json_number(r, obj, p, "roughness", s->roughness, 0.01, 1.0, &s->roughness);
    return rc;
}

static plm_result read_bill(const plm_json_reader *r, const cJSON *root, plm_bird *b)
{
    static const char *const keys[] = {"family", "upper", "lower", NULL};
    const cJSON *bill = cJSON_GetObjectItemCaseSensitive(root, "bill");
    if (!bill)
        return plm_json_fail(r, "bill", NULL, "required: {\"family\": \"hooked\", \"conical\" or \"dagger\", "
                             "\"upper\": {\"colour\", \"roughness\"}, \"lower\": {...}}");
    int family = 0;
    plm_result rc = plm_json_check_object(r, bill, "bill", keys);
    if (rc == PLM_OK)
        rc = plm_json_enum(r, bill, "bill", "family", plm_bill_family_names, 0, &family);
    b->bill_family = (plm_bill_family)family;
    if (rc == PLM_OK)
        rc = read_surface(r, bill, "bill", "upper", "colour", &b->bill);
    b->lower_bill = b->bill;
    if (rc == PLM_OK)
        rc = read_surface(r, bill, "bill", "lower", "colour", &b->lower_bill);
    return rc;
}

static plm_result read_eyes(const plm_json_reader *r, const cJSON *root, plm_bird *b)
{
    static const char *const keys[] = {"diameter", "iris", "roughness", NULL};
    const cJSON *eyes = cJSON_GetObjectItemCaseSensitive(root, "eyes");
    b->eye_diameter = 0.2 * b->m.head_width;
    if (!eyes)
        return PLM_OK;
    plm_result rc = plm_json_check_object(r, eyes, "eyes", keys);
    if (rc == PLM_OK)
        rc = plm_json_number(r, eyes, "eyes", "diameter", b->eye_diameter, 0.1, 0.6 * b->m.head_width,
                             &b->eye_diameter);
    if (rc == PLM_OK)
        rc = plm_json_rgb(r, eyes, "eyes", "iris", b->iris.colour, 0.0, 1.0, &b->iris.colour);
    if (rc == PLM_OK)
        rc = plm_json_number(r, eyes, "eyes", "roughness", b->iris.roughness, 0.01, 1.0, &b->iris.roughness);
    return rc;
}

/* dir(file)/rel unless rel is absolute. */
static void resolve(const char *file, const char *rel, char *out)
{
    const char *slash = strrchr(file, '/');
    if (rel[0] == '/' || !slash)
        snprintf(out, PLM_BIRD_PATH_MAX, "%s", rel);
    else
        snprintf(out, PLM_BIRD_PATH_MAX, "%.*s/%s", (int)(slash - file), file, rel);
}

static plm_result read_tract(const plm_json_reader *r, const cJSON *obj, const char *path, plm_bird_tract *t)
{
    static const char *const extra[] = {"name", "pteryla", "species", "s", "around", NULL};
    memset(t, 0, sizeof *t);
    t->elevation = DEG(10.0);
    if (!cJSON_IsObject(obj))
        return plm_json_fail(r, path, NULL, "expected a tract object {\"name\", \"species\", \"density\", ...}");
    plm_result rc = plm_params_read(r, obj, path, &plm_bird_tract_block, extra, t);
    const char *name = NULL, *species = NULL;
    if (rc == PLM_OK)
        rc = plm_json_string(r, obj, path, "name", NULL, &name);
    if (rc == PLM_OK && (!name || !name[0] || strlen(name) >= PLM_BIRD_NAME_MAX))
        return plm_json_fail(r, path, "name", "required: a name of 1 to %d characters", PLM_BIRD_NAME_MAX - 1);
    if (rc != PLM_OK)
        return rc;
    snprintf(t->name, sizeof t->name, "%s", name);
    /* A tract named after a pteryla is that pteryla unless it says otherwise. */
    int pteryla = -1;
    for (int k = 0; k < PLM_PTERYLAE; ++k)
        if (!strcmp(name, plm_pteryla_names[k]))
            pteryla = k;
    if (!cJSON_GetObjectItemCaseSensitive(obj, "pteryla") && pteryla < 0)
        return plm_json_fail(r, path, "pteryla", "required for a tract not named after one: one of capital, "
                             "spinal, ventral, humeral, femoral, caudal");
    rc = plm_json_enum(r, obj, path, "pteryla", plm_pteryla_names, pteryla, &pteryla);
    if (rc != PLM_OK)
        return rc;
    t->pteryla = (plm_pteryla)pteryla;
    t->region = plm_pteryla_regions[pteryla];
    if ((rc = plm_json_string(r, obj, path, "species", NULL, &species)) != PLM_OK)
        return rc;
    if (!species || !species[0])
        return plm_json_fail(r, path, "species", "required: the species preset file of the tract's feathers");
    resolve(r->file, species, t->species);
    if (!(t->density > 0.0))
        return plm_json_fail(r, path, "density", "required: feathers per square centimetre, in (0, 1000]");
    if (!(t->size[0] > 0.0 && t->size[1] > 0.0))
        return plm_json_fail(r, path, "size", "required: [head end, tail end] feather lengths in mm");
    rc = read_range(r, obj, path, "s", 0.0, 1.0, 1.0, t->region.s);
    if (rc == PLM_OK)
        rc = read_range(r, obj, path, "around", 0.0, 180.0, PLM_PI / 180.0, t->region.around);
    return rc;
}

/* "wings": {"rows": {"primary": file, ...}, "span", "chord", "fold", "primaries", "secondaries", "tertials"} */
static plm_result read_wings(const plm_json_reader *r, const cJSON *root, plm_bird *b)
{
    static const char *const keys[] = {"rows", "span", "chord", "fold", "primaries", "secondaries", "tertials",
                                       NULL};
    const cJSON *w = cJSON_GetObjectItemCaseSensitive(root, "wings");
    plm_bird_wings *o = &b->wings;
    if (!w)
        return PLM_OK;
    o->present = 1;
    plm_result rc = plm_json_check_object(r, w, "wings", keys);
    if (rc == PLM_OK)
        rc = plm_json_number(r, w, "wings", "span", 1.6 * b->m.wing_chord, 1.0, MM_MAX, &o->span);
    if (rc == PLM_OK)
        rc = plm_json_number(r, w, "wings", "chord", 0.5 * b->m.wing_chord, 1.0, MM_MAX, &o->chord);
    if (rc == PLM_OK)
        rc = plm_json_number(r, w, "wings", "fold", 1.0, 0.0, 1.0, &o->fold);
    if (rc == PLM_OK)
        rc = plm_json_int(r, w, "wings", "primaries", 0, 0, 12, &o->primaries);
    if (rc == PLM_OK)
        rc = plm_json_int(r, w, "wings", "secondaries", 0, 0, 24, &o->secondaries);
    if (rc == PLM_OK)
        rc = plm_json_int(r, w, "wings", "tertials", 0, 0, 6, &o->tertials);
    const cJSON *rows = cJSON_GetObjectItemCaseSensitive(w, "rows");
    const char *names[PLM_WING_ROWS + 1] = {NULL};
    for (int k = 0; k < PLM_WING_ROWS; ++k)
        names[k] = plm_wing_row_names[k];
    if (rc == PLM_OK && !rows)
        return plm_json_fail(r, "wings", "rows", "required: {\"primary\": file, \"secondary\": file, ...}");
    if (rc == PLM_OK)
        rc = plm_json_check_object(r, rows, "wings.rows", names);
    for (int k = 0; rc == PLM_OK && k < PLM_WING_ROWS; ++k) {
        const char *file = NULL;
        rc = plm_json_string(r, rows, "wings.rows", names[k], NULL, &file);
        int required = k == PLM_WING_PRIMARY || k == PLM_WING_SECONDARY;
        if (rc == PLM_OK && required && !file)
            rc = plm_json_fail(r, "wings.rows", names[k], "required: a species preset file");
        if (rc == PLM_OK && file)
            resolve(r->file, file, o->rows[k]);
    }
    return rc;
}

/* "tail": {"rectrix": file, "covert": file, "count", "spread", "covert_length", "rounding"} */
static plm_result read_tail(const plm_json_reader *r, const cJSON *root, plm_bird *b)
{
    static const char *const keys[] = {"rectrix", "covert", "count", "spread", "covert_length", "rounding", NULL};
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(root, "tail");
    plm_bird_tail *o = &b->tail;
    if (!t)
        return PLM_OK;
    o->present = 1;
    const char *rectrix = NULL, *covert = NULL;
    plm_result rc = plm_json_check_object(r, t, "tail", keys);
    if (rc == PLM_OK)
        rc = plm_json_string(r, t, "tail", "rectrix", NULL, &rectrix);
    if (rc == PLM_OK && !rectrix)
        rc = plm_json_fail(r, "tail", "rectrix", "required: the species preset file of the tail feathers");
    if (rc == PLM_OK)
        rc = plm_json_string(r, t, "tail", "covert", rectrix, &covert);
    if (rc == PLM_OK)
        rc = plm_json_int(r, t, "tail", "count", 12, 2, 32, &o->count);
    if (rc == PLM_OK)
        rc = plm_json_number(r, t, "tail", "spread", 15.0, 0.0, 90.0, &o->spread);
    o->spread = plm_radians(o->spread);
    if (rc == PLM_OK)
        rc = plm_json_number(r, t, "tail", "covert_length", 0.5, 0.1, 1.0, &o->covert_length);
    if (rc == PLM_OK)
        rc = plm_json_number(r, t, "tail", "rounding", 0.2, 0.0, 0.8, &o->rounding);
    if (rc == PLM_OK) {
        resolve(r->file, rectrix, o->rectrix);
        resolve(r->file, covert, o->covert);
    }
    return rc;
}

static plm_result read_tracts(const plm_json_reader *r, const cJSON *root, plm_bird *b)
{
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(root, "tracts");
    int n = cJSON_GetArraySize(list);
    if (!cJSON_IsArray(list) || n < 1 || n > PLM_BIRD_TRACTS_MAX)
        return plm_json_fail(r, "tracts", NULL, "required: an array of 1 to %d tracts", PLM_BIRD_TRACTS_MAX);
    char path[64];
    int i = 0;
    for (const cJSON *e = list->child; e; e = e->next, ++i) {
        snprintf(path, sizeof path, "tracts[%d]", i);
        plm_result rc = read_tract(r, e, path, &b->tracts[i]);
        if (rc != PLM_OK)
            return rc;
        b->tract_count = i + 1;
    }
    return PLM_OK;
}

static plm_result read_bird(const plm_json_reader *r, const cJSON *root, plm_bird *b)
{
    static const char *const keys[] = {"name", "description", "source", "measurements", "proportions", "bill",
                                       "eyes", "skin", "feet", "tracts", "wings", "tail", "seed", NULL};
    plm_result rc = plm_json_check_object(r, root, "", keys);
    const char *name = NULL;
    if (rc == PLM_OK)
        rc = plm_json_string(r, root, "", "name", "bird", &name);
    if (rc != PLM_OK)
        return rc;
    snprintf(b->name, sizeof b->name, "%s", name);
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(root, "measurements");
    if (!cJSON_IsObject(m))
        return plm_json_fail(r, "", "measurements", "required: {\"total_length\", \"wing_chord\", ...} in mm");
    if ((rc = plm_params_read(r, m, "measurements", &plm_bird_measurement_block, NULL, &b->m)) != PLM_OK)
        return rc;
    for (int i = 0; i < plm_bird_measurement_block.count; ++i) {
        const plm_param *p = &plm_bird_measurement_block.params[i];
        if (!(*(const double *)((const char *)&b->m + p->offset) > 0.0))
            return plm_json_fail(r, "measurements", p->name, "required: %s, mm", p->meaning);
    }
    const cJSON *p = cJSON_GetObjectItemCaseSensitive(root, "proportions");
    if (p && (rc = plm_params_read(r, p, "proportions", &plm_bird_proportion_block, NULL, &b->p)) != PLM_OK)
        return rc;
    if (b->m.tail_length + b->m.bill_length >= 0.8 * b->m.total_length)
        return plm_json_fail(r, "measurements", "total_length", "%g mm leaves too little body after the bill "
                             "(%g) and the tail (%g)", b->m.total_length, b->m.bill_length, b->m.tail_length);
    uint64_t seed = 1;
    double s = 1.0;
    rc = plm_json_number(r, root, "", "seed", 1.0, 0.0, 2147483647.0, &s);
    seed = (uint64_t)s;
    b->seed = seed;
    if (rc == PLM_OK)
        rc = read_bill(r, root, b);
    if (rc == PLM_OK)
        rc = read_eyes(r, root, b);
    if (rc == PLM_OK)
        rc = read_surface(r, root, "", "skin", "colour", &b->skin);
    if (rc == PLM_OK)
        rc = read_surface(r, root, "", "feet", "colour", &b->feet);
    if (rc == PLM_OK)
        rc = read_tracts(r, root, b);
    if (rc == PLM_OK)
        rc = read_wings(r, root, b);
    if (rc == PLM_OK)
        rc = read_tail(r, root, b);
    return rc;
}

plm_result plm_bird_load(const char *path, plm_bird *out, plm_error *err)
{
    bird_default(out);
    cJSON *root = NULL;
    plm_result rc = plm_json_load(path, &root, err);
    if (rc != PLM_OK)
        return rc;
    plm_json_reader r = {path, err, 0};
    rc = cJSON_IsObject(root) ? read_bird(&r, root, out)
                              : plm_json_fail(&r, "", NULL, "expected an object (a bird preset)");
    cJSON_Delete(root);
    return rc;
}
