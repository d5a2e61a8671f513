#include "common/json.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/fileio.h"

plm_result plm_json_parse(const char *text, size_t length, const char *name, cJSON **out, plm_error *err)
{
    const char *end = NULL;
    *out = cJSON_ParseWithLengthOpts(text, length, &end, 0);
    /* Only white space (or a terminating NUL) may follow the value. */
    while (*out && end < text + length && (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r'))
        ++end;
    if (*out && (end == text + length || *end == '\0'))
        return PLM_OK;
    cJSON_Delete(*out);
    *out = NULL;
    /* Report where parsing stopped as line:column. */
    int line = 1, col = 1;
    for (const char *p = text; end && p < end && p < text + length; ++p, ++col)
        if (*p == '\n') {
            ++line;
            col = 0;
        }
    return plm_fail(err, PLM_ERR_PARSE, "%s:%d:%d: malformed JSON", name, line, col);
}

plm_result plm_json_load(const char *path, cJSON **out, plm_error *err)
{
    *out = NULL; /* callers may free *out whatever the result */
    char *text;
    plm_result rc = plm_read_text_file(path, &text, err);
    if (rc != PLM_OK)
        return rc;
    rc = plm_json_parse(text, strlen(text), path, out, err);
    free(text);
    return rc;
}

static const char *join(char *buf, size_t n, const char *path, const char *key)
{
    if (!key)
        snprintf(buf, n, "%s", path && path[0] ? path : "(top level)");
    else if (path && path[0])
        snprintf(buf, n, "%s.%s", path, key);
    else
        snprintf(buf, n, "%s", key);
    return buf;
}

plm_result plm_json_fail(const plm_json_reader *r, const char *path, const char *key, const char *fmt, ...)
{
    char where[512], what[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return plm_fail(r->err, PLM_ERR_INVALID, "%s: %s: %s", r->file ? r->file : "(json)",
                    join(where, sizeof where, path, key), what);
}

plm_result plm_json_check_object(const plm_json_reader *r, const cJSON *obj, const char *path,
                                 const char *const *allowed)
{
    if (!cJSON_IsObject(obj))
        return plm_json_fail(r, path, NULL, "expected an object");
    for (const cJSON *item = obj->child; item; item = item->next) {
        int known = 0;
        for (const char *const *a = allowed; *a && !known; ++a)
            known = strcmp(*a, item->string) == 0;
        if (!known) {
            char list[512] = "";
            for (const char *const *a = allowed; *a; ++a)
                snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", a == allowed ? "" : ", ", *a);
            return plm_json_fail(r, path, item->string, "unknown field (allowed: %s)", list);
        }
    }
    return PLM_OK;
}

plm_result plm_json_number(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                           double def, double lo, double hi, double *out)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!item) {
        *out = def;
        return PLM_OK;
    }
    if (!cJSON_IsNumber(item))
        return plm_json_fail(r, path, key, "expected a number in [%.10g, %.10g]", lo, hi);
    double v = item->valuedouble;
    if (!(v >= lo && v <= hi))
        return plm_json_fail(r, path, key, "%.10g is out of range [%.10g, %.10g]", v, lo, hi);
    *out = v;
    return PLM_OK;
}

plm_result plm_json_int(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                        int def, int lo, int hi, int *out)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!item) {
        *out = def;
        return PLM_OK;
    }
    /* The range printed as integers: [1, 16777216], not [1, 1.67772e+07]. */
    if (!cJSON_IsNumber(item))
        return plm_json_fail(r, path, key, "expected a number in [%d, %d]", lo, hi);
    double v = item->valuedouble;
    if (!(v >= lo && v <= hi))
        return plm_json_fail(r, path, key, "%.10g is out of range [%d, %d]", v, lo, hi);
    if (v != (double)(int)v)
        return plm_json_fail(r, path, key, "%.10g is not a whole number in [%d, %d]", v, lo, hi);
    *out = (int)v;
    return PLM_OK;
}

plm_result plm_json_bool(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                         int def, int *out)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!item) {
        *out = def;
        return PLM_OK;
    }
    if (!cJSON_IsBool(item))
        return plm_json_fail(r, path, key, "expected true or false");
    *out = cJSON_IsTrue(item);
    return PLM_OK;
}

plm_result plm_json_string(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                           const char *def, const char **out)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!item) {
        *out = def;
        return PLM_OK;
    }
    if (!cJSON_IsString(item))
        return plm_json_fail(r, path, key, "expected a string");
    *out = item->valuestring;
    return PLM_OK;
}

plm_result plm_json_enum(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                         const char *const *choices, int def, int *out)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!item) {
        *out = def;
        return PLM_OK;
    }
    char list[512] = "";
    for (int i = 0; choices[i]; ++i) {
        if (cJSON_IsString(item) && strcmp(choices[i], item->valuestring) == 0) {
            *out = i;
            return PLM_OK;
        }
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s\"%s\"", i ? ", " : "", choices[i]);
    }
    /* Not a string (a number, an object): what is allowed says more than the type. */
    if (!cJSON_IsString(item))
        return plm_json_fail(r, path, key, "expected one of %s", list);
    return plm_json_fail(r, path, key, "\"%s\" is not one of %s", item->valuestring, list);
}

static plm_result json_triple(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                              const double def[3], double lo, double hi, double out[3])
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!item) {
        memcpy(out, def, 3 * sizeof *out);
        return PLM_OK;
    }
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 3)
        return plm_json_fail(r, path, key, "expected an array of 3 numbers in [%.10g, %.10g]", lo, hi);
    for (int i = 0; i < 3; ++i) {
        const cJSON *e = cJSON_GetArrayItem(item, i);
        if (!cJSON_IsNumber(e) || !(e->valuedouble >= lo && e->valuedouble <= hi))
            return plm_json_fail(r, path, key, "element %d must be a number in [%.10g, %.10g]", i, lo, hi);
        out[i] = e->valuedouble;
    }
    return PLM_OK;
}

plm_result plm_json_vec3(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                         vec3 def, double lo, double hi, vec3 *out)
{
    double d[3] = {def.x, def.y, def.z}, v[3];
    plm_result rc = json_triple(r, obj, path, key, d, lo, hi, v);
    if (rc == PLM_OK)
        *out = v3(v[0], v[1], v[2]);
    return rc;
}

plm_result plm_json_rgb(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                        rgb def, double lo, double hi, rgb *out)
{
    double d[3] = {def.r, def.g, def.b}, v[3];
    plm_result rc = json_triple(r, obj, path, key, d, lo, hi, v);
    if (rc == PLM_OK)
        *out = rgb_make(v[0], v[1], v[2]);
    return rc;
}
