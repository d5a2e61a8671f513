#include "common/params.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "common/vec.h"

#define MAX_KEYS 48

static const char *const type_names[] = {"number", "angle", "integer", "true/false",
                                         "integer", "[x, y, z]", "[r, g, b]", "[a, b]"};

static void *member(void *target, const plm_param *p) { return (char *)target + p->offset; }
static const void *cmember(const void *target, const plm_param *p) { return (const char *)target + p->offset; }

/* The field as up to three numbers in file units (degrees for angles). */
static int values_of(const plm_param *p, const void *target, double v[3])
{
    const void *m = cmember(target, p);
    switch (p->type) {
    case PLM_PARAM_NUMBER: v[0] = *(const double *)m; return 1;
    case PLM_PARAM_ANGLE: v[0] = plm_degrees(*(const double *)m); return 1;
    case PLM_PARAM_INT:
    case PLM_PARAM_BOOL: v[0] = *(const int *)m; return 1;
    case PLM_PARAM_SEED: v[0] = (double)*(const uint64_t *)m; return 1;
    case PLM_PARAM_VEC3: {
        const vec3 *x = m;
        v[0] = x->x, v[1] = x->y, v[2] = x->z;
        return 3;
    }
    case PLM_PARAM_RGB: {
        const rgb *x = m;
        v[0] = x->r, v[1] = x->g, v[2] = x->b;
        return 3;
    }
    case PLM_PARAM_PAIR: v[0] = ((const double *)m)[0], v[1] = ((const double *)m)[1]; return 2;
    }
    return 0;
}

static int in_range(const plm_param *p, double v) /* false for NaN */
{
    return (p->open & PLM_PARAM_OPEN_MIN ? v > p->min : v >= p->min) &&
           (p->open & PLM_PARAM_OPEN_MAX ? v < p->max : v <= p->max);
}

/* "[lo, hi]", "(lo, hi)", ... */
static const char *range_text(const plm_param *p, char *buf, size_t size)
{
    snprintf(buf, size, "%c%.10g, %.10g%c", p->open & PLM_PARAM_OPEN_MIN ? '(' : '[', p->min, p->max,
             p->open & PLM_PARAM_OPEN_MAX ? ')' : ']');
    return buf;
}

/* Whether some component of the field lies outside its range (*value: the first such). */
static int out_of_range(const plm_param *p, const void *target, double *value)
{
    double v[3];
    int n = p->type == PLM_PARAM_BOOL ? 0 : values_of(p, target, v);
    for (int k = 0; k < n; ++k)
        if (!in_range(p, v[k])) {
            *value = v[k];
            return 1;
        }
    return 0;
}

plm_result plm_params_check(const plm_param_block *b, const void *target, plm_error *err)
{
    for (int i = 0; i < b->count; ++i) {
        const plm_param *p = &b->params[i];
        double v;
        char range[80];
        if (out_of_range(p, target, &v))
            return plm_fail(err, PLM_ERR_INVALID, "%s parameter %s = %g%s%s is out of range %s%s", b->name, p->name,
                            v, p->unit[0] ? " " : "", p->unit, range_text(p, range, sizeof range),
                            isfinite(v) ? "" : " (not a finite number)");
    }
    return PLM_OK;
}

static plm_result read_param(const plm_json_reader *r, const cJSON *obj, const char *path, const plm_param *p,
                             void *target)
{
    void *m = member(target, p);
    switch (p->type) {
    case PLM_PARAM_NUMBER:
        return plm_json_number(r, obj, path, p->name, *(double *)m, p->min, p->max, m);
    case PLM_PARAM_ANGLE: {
        double deg;
        plm_result rc = plm_json_number(r, obj, path, p->name, plm_degrees(*(double *)m), p->min, p->max, &deg);
        *(double *)m = plm_radians(deg);
        return rc;
    }
    case PLM_PARAM_INT:
        return plm_json_int(r, obj, path, p->name, *(int *)m, (int)p->min, (int)p->max, m);
    case PLM_PARAM_BOOL:
        return plm_json_bool(r, obj, path, p->name, *(int *)m, m);
    case PLM_PARAM_SEED: {
        int seed = (int)*(uint64_t *)m;
        plm_result rc = plm_json_int(r, obj, path, p->name, seed, (int)p->min, (int)p->max, &seed);
        *(uint64_t *)m = (uint64_t)seed;
        return rc;
    }
    case PLM_PARAM_VEC3:
        return plm_json_vec3(r, obj, path, p->name, *(vec3 *)m, p->min, p->max, m);
    case PLM_PARAM_RGB:
        return plm_json_rgb(r, obj, path, p->name, *(rgb *)m, p->min, p->max, m);
    case PLM_PARAM_PAIR: {
        const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, p->name);
        if (!item)
            return PLM_OK;
        double *d = m;
        if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 2 || !cJSON_IsNumber(item->child) ||
            !cJSON_IsNumber(item->child->next) ||
            !(item->child->valuedouble >= p->min && item->child->valuedouble <= p->max) ||
            !(item->child->next->valuedouble >= p->min && item->child->next->valuedouble <= p->max))
            return plm_json_fail(r, path, p->name, "expected 2 numbers, each in [%g, %g]", p->min, p->max);
        d[0] = item->child->valuedouble;
        d[1] = item->child->next->valuedouble;
        return PLM_OK;
    }
    }
    return PLM_OK;
}

plm_result plm_params_read(const plm_json_reader *r, const cJSON *obj, const char *path, const plm_param_block *b,
                           const char *const *extra, void *target)
{
    const char *keys[MAX_KEYS + 1];
    int n = 0;
    for (int i = 0; i < b->count && n < MAX_KEYS; ++i)
        keys[n++] = b->params[i].name;
    for (const char *const *e = extra; e && *e && n < MAX_KEYS; ++e)
        keys[n++] = *e;
    keys[n] = NULL;
    plm_result rc = plm_json_check_object(r, obj, path, keys);
    for (int i = 0; rc == PLM_OK && i < b->count; ++i) {
        const plm_param *p = &b->params[i];
        double v;
        char range[80];
        rc = read_param(r, obj, path, p, target);
        /* The readers take closed ranges: an excluded bound is caught here. */
        if (rc == PLM_OK && p->open && out_of_range(p, target, &v))
            rc = plm_json_fail(r, path, p->name, "%g is out of range %s", v, range_text(p, range, sizeof range));
    }
    return rc;
}

static void print_value(FILE *fp, const plm_param *p, const void *target)
{
    double v[3];
    int n = values_of(p, target, v);
    if (p->type == PLM_PARAM_BOOL) {
        fputs(v[0] != 0.0 ? "true" : "false", fp);
        return;
    }
    if (n > 1)
        fputc('[', fp);
    for (int k = 0; k < n; ++k)
        fprintf(fp, k ? ", %.4g" : "%.4g", v[k]);
    if (n > 1)
        fputc(']', fp);
}

void plm_params_print(FILE *fp, const plm_param_block *b, int n_defaults, const char *const *labels,
                      const void *const *defaults, int markdown)
{
    if (markdown) {
        fprintf(fp, "| `%s` field | type |", b->name);
        for (int d = 0; d < n_defaults; ++d)
            fprintf(fp, " default%s%s |", labels[d][0] ? " " : "", labels[d]);
        fprintf(fp, " min | max | unit | meaning |\n| --- | --- |");
        for (int d = 0; d < n_defaults; ++d)
            fprintf(fp, " --- |");
        fprintf(fp, " --- | --- | --- | --- |\n");
    } else {
        fprintf(fp, "%s: %s\n", b->name, b->meaning);
    }
    for (int i = 0; i < b->count; ++i) {
        const plm_param *p = &b->params[i];
        if (markdown)
            fprintf(fp, "| `%s` | %s |", p->name, type_names[p->type]);
        else
            fprintf(fp, "  %-22s %-10s", p->name, type_names[p->type]);
        for (int d = 0; d < n_defaults; ++d) {
            if (!markdown)
                fprintf(fp, " default%s%s%s", labels[d][0] ? " (" : "", labels[d], labels[d][0] ? ")" : "");
            fputc(' ', fp);
            print_value(fp, p, defaults[d]);
            fputs(markdown ? " |" : "", fp);
        }
        int ranged = p->type != PLM_PARAM_BOOL;
        const char *lo = p->open & PLM_PARAM_OPEN_MIN ? "> " : "", *hi = p->open & PLM_PARAM_OPEN_MAX ? "< " : "";
        char range[80];
        if (markdown && ranged)
            fprintf(fp, " %s%.10g | %s%.10g | %s | %s |\n", lo, p->min, hi, p->max, p->unit, p->meaning);
        else if (markdown)
            fprintf(fp, " | | %s | %s |\n", p->unit, p->meaning);
        else {
            if (ranged)
                fprintf(fp, " in %s%s%s", range_text(p, range, sizeof range), p->unit[0] ? " " : "", p->unit);
            fprintf(fp, "\n      %s\n", p->meaning);
        }
    }
}
