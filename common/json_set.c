#include "common/json_set.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *type_name(const cJSON *j)
{
    if (cJSON_IsObject(j))
        return "an object";
    if (cJSON_IsArray(j))
        return "an array";
    if (cJSON_IsString(j))
        return "a string";
    if (cJSON_IsNumber(j))
        return "a number";
    if (cJSON_IsBool(j))
        return "a boolean";
    return "null";
}

/* An array index: decimal digits only ("01" and "-1" are not indices). */
static int parse_index(const char *s, size_t len, int *out)
{
    if (len == 0 || len > 9 || (len > 1 && s[0] == '0'))
        return 0;
    int v = 0;
    for (size_t i = 0; i < len; ++i) {
        if (s[i] < '0' || s[i] > '9')
            return 0;
        v = 10 * v + (s[i] - '0');
    }
    *out = v;
    return 1;
}

/* "no field "fovx" in camera (it has: position, fov)". */
static plm_result missing_field(plm_error *err, const char *path, const cJSON *obj, int parent_len,
                                const char *key, size_t key_len)
{
    char list[512] = "";
    for (const cJSON *c = obj->child; c; c = c->next)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", c == obj->child ? "" : ", ", c->string);
    char parent[1024];
    snprintf(parent, sizeof parent, "%.*s", parent_len, path);
    return plm_fail(err, PLM_ERR_INVALID, "%s: no field \"%.*s\" in %s (%s%s)", path, (int)key_len, key,
                    parent_len ? parent : "the top level", obj->child ? "it has: " : "it is empty", list);
}

plm_result plm_json_set(cJSON *root, const char *path, const cJSON *value, plm_error *err)
{
    if (!path[0] || path[0] == '.' || path[strlen(path) - 1] == '.' || strstr(path, ".."))
        return plm_fail(err, PLM_ERR_INVALID, "'%s': expected a dotted path such as camera.fov", path);
    cJSON *node = root;
    const char *seg = path;
    for (;;) {
        const char *dot = strchr(seg, '.');
        size_t len = dot ? (size_t)(dot - seg) : strlen(seg);
        int parent_len = seg == path ? 0 : (int)(seg - path - 1);
        char key[256];
        if (len >= sizeof key)
            return plm_fail(err, PLM_ERR_INVALID, "%s: a path segment is too long", path);
        memcpy(key, seg, len);
        key[len] = '\0';
        cJSON *child;
        int index = 0;
        if (cJSON_IsObject(node)) {
            child = cJSON_GetObjectItemCaseSensitive(node, key);
        } else if (cJSON_IsArray(node)) {
            int size = cJSON_GetArraySize(node);
            if (!parse_index(key, len, &index) || index >= size)
                return plm_fail(err, PLM_ERR_INVALID, "%s: %.*s is an array of %d, \"%s\" is not an index in [0, %d]",
                                path, parent_len, path, size, key, size - 1);
            child = cJSON_GetArrayItem(node, index);
        } else {
            return plm_fail(err, PLM_ERR_INVALID, "%s: %.*s is %s, not an object or array", path, parent_len, path,
                            type_name(node));
        }
        if (!dot) {
            cJSON *copy = cJSON_Duplicate(value, 1);
            if (!copy)
                return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory", path);
            cJSON_bool ok = cJSON_IsArray(node) ? cJSON_ReplaceItemInArray(node, index, copy)
                            : child            ? cJSON_ReplaceItemInObjectCaseSensitive(node, key, copy)
                                               : cJSON_AddItemToObject(node, key, copy);
            if (!ok) {
                cJSON_Delete(copy);
                return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory", path);
            }
            return PLM_OK;
        }
        if (!child)
            return missing_field(err, path, node, parent_len, key, len);
        node = child;
        seg = dot + 1;
    }
}

plm_result plm_json_set_assignment(cJSON *root, const char *assignment, plm_error *err)
{
    const char *eq = strchr(assignment, '=');
    if (!eq)
        return plm_fail(err, PLM_ERR_INVALID, "'%s': expected path.to.field=value", assignment);
    char path[1024];
    if ((size_t)(eq - assignment) >= sizeof path)
        return plm_fail(err, PLM_ERR_INVALID, "'%.40s...': the path is too long", assignment);
    memcpy(path, assignment, (size_t)(eq - assignment));
    path[eq - assignment] = '\0';
    cJSON *value = cJSON_ParseWithOpts(eq + 1, NULL, 1);
    if (!value)
        value = cJSON_CreateString(eq + 1);
    if (!value)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory", path);
    plm_result rc = plm_json_set(root, path, value, err);
    cJSON_Delete(value);
    return rc;
}
