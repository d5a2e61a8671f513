/* The scene reader's lowest layer, shared by the scene file, its feathers,
 * layouts and birds: file paths resolved against the file that names them,
 * and the optics a feather material or a species gives (fiber, masking and
 * pigment blocks, the fluff's fiber). It knows nothing of the blocks above it. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene/readers.h"

#include "optics/feather_bsdf.h"
#include "optics/pigment.h"

/* dir(base)/rel unless rel is absolute or base has no directory. */
void plm_scene_resolve_path(const char *base, const char *rel, char *out)
{
    const char *slash = strrchr(base, '/');
    if (rel[0] == '/' || !slash)
        snprintf(out, PLM_PATH_MAX, "%s", rel);
    else
        snprintf(out, PLM_PATH_MAX, "%.*s/%s", (int)(slash - base), base, rel);
}

plm_result plm_scene_read_path_item(const plm_json_reader *r, const cJSON *item, const char *path, const char *key,
                                    char *out)
{
    if (!cJSON_IsString(item))
        return plm_json_fail(r, path, key, "expected a file path (a string)");
    if (!item->valuestring[0])
        return plm_json_fail(r, path, key, "expected a non-empty file path");
    plm_scene_resolve_path(r->file, item->valuestring, out);
    if (!r->record_paths)
        return PLM_OK;
    /* The resolved scene lives elsewhere: it names every file absolutely.
     * The tree being recorded is the loader's own copy (load_file). */
    char absolute[PLM_PATH_MAX], cwd[PLM_PATH_MAX];
    if (out[0] == '/')
        snprintf(absolute, sizeof absolute, "%s", out);
    else if (!getcwd(cwd, sizeof cwd) ||
             snprintf(absolute, sizeof absolute, "%s/%s", cwd, out) >= (int)sizeof absolute)
        return plm_json_fail(r, path, key, "the absolute path of \"%s\" is too long", out);
    if (!cJSON_SetValuestring((cJSON *)item, absolute))
        return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
    return PLM_OK;
}

plm_result plm_scene_read_path(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                               int required, char *out)
{
    const char *s = NULL;
    plm_result rc = plm_json_string(r, obj, path, key, NULL, &s);
    if (rc != PLM_OK)
        return rc;
    if (!s) {
        out[0] = '\0';
        return required ? plm_json_fail(r, path, key, "required (a file path)") : PLM_OK;
    }
    return plm_scene_read_path_item(r, cJSON_GetObjectItemCaseSensitive(obj, key), path, key, out);
}

/* "pigments": concentrations that give the cortex's sigma_a (optics/pigment.h). */
static plm_result read_pigments(const plm_json_reader *r, const cJSON *fiber, const cJSON *obj,
                                const char *fiber_path, plm_fiber_params *p)
{
    if (cJSON_GetObjectItemCaseSensitive(fiber, "sigma_a"))
        return plm_json_fail(r, fiber_path, "pigments", "give either sigma_a or pigments, not both");
    char path[320];
    snprintf(path, sizeof path, "%s.pigments", fiber_path);
    plm_pigments c = {0};
    plm_result rc = plm_params_read(r, obj, path, &plm_pigments_param_block, NULL, &c);
    if (rc == PLM_OK)
        p->sigma_a = plm_pigments_sigma_a(&c);
    return rc;
}

/* A fiber block (docs/fiber.md); absent fields keep p's values. */
static plm_result read_fiber(const plm_json_reader *r, const cJSON *parent, const char *parent_path,
                             const char *key, plm_fiber_params *p)
{
    const cJSON *obj = cJSON_GetObjectItemCaseSensitive(parent, key);
    if (!obj)
        return PLM_OK;
    static const char *const extra[] = {"pigments", NULL};
    char path[300];
    snprintf(path, sizeof path, "%s.%s", parent_path, key);
    plm_result rc = plm_params_read(r, obj, path, &plm_fiber_param_block, extra, p);
    const cJSON *pigments = cJSON_GetObjectItemCaseSensitive(obj, "pigments");
    if (rc == PLM_OK && pigments)
        rc = read_pigments(r, obj, pigments, path, p);
    if (rc == PLM_OK && p->lobes > PLM_FIBER_SET_MAX_LOBES)
        return plm_json_fail(r, path, "lobes", "%d is out of range [1, %d] in a feather material", p->lobes,
                             PLM_FIBER_SET_MAX_LOBES);
    /* What the field ranges cannot say: a medulla must lie inside the cortex. */
    if (rc == PLM_OK && (rc = plm_fiber_params_validate(p, r->err)) != PLM_OK)
        plm_error_prefix(r->err, "%s: %s: ", r->file, path);
    return rc;
}

static plm_result read_masking(const plm_json_reader *r, const cJSON *parent, const char *parent_path,
                               plm_masking_params *m)
{
    const cJSON *obj = cJSON_GetObjectItemCaseSensitive(parent, "masking");
    if (!obj)
        return PLM_OK;
    char path[300];
    snprintf(path, sizeof path, "%s.masking", parent_path);
    return plm_params_read(r, obj, path, &plm_masking_param_block, NULL, m);
}

/* A cross-section is one ellipse: a fiber block's eccentricity (its extent
 * along e3 over e2) and the masking block's barb_eccentricity (a barb's extent
 * along n over b) are the same number, since the barb's fiber frame has
 * e2 = b and e3 = n; so are the barbule's eccentricity and
 * barbule_eccentricity (r2 over r1, its e3 over e2). A file gives either and
 * the other takes its value; one that gives both must give the same. */
static plm_result tie_eccentricity(const plm_json_reader *r, const cJSON *obj, const char *path, const char *fiber_key,
                                   const char *masking_key, plm_fiber_params *fiber, double *masking)
{
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(obj, fiber_key), "eccentricity");
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(obj, "masking"), masking_key);
    char masking_path[320];
    snprintf(masking_path, sizeof masking_path, "%s.masking", path);
    if (f && m && fiber->eccentricity != *masking)
        return plm_json_fail(r, masking_path, masking_key,
                             "%g, while %s.eccentricity is %g: both are the %s cross-section's aspect ratio, so give one "
                             "(the other takes its value) or the same", *masking, fiber_key, fiber->eccentricity,
                             fiber_key);
    char fiber_path[320];
    snprintf(fiber_path, sizeof fiber_path, "%s.%s", path, fiber_key);
    if (f && !m && !(fiber->eccentricity <= 20.0)) /* the masking table's range, (0, 20] */
        return plm_json_fail(r, fiber_path, "eccentricity", "%g is over 20, the most masking.%s (the same number) takes",
                             fiber->eccentricity, masking_key);
    if (m && !f && !(*masking >= 0.01)) /* the fiber table's range, [0.01, 100] */
        return plm_json_fail(r, masking_path, masking_key, "%g is under 0.01, the least %s.eccentricity (the same number) "
                             "takes", *masking, fiber_key);
    if (f)
        *masking = fiber->eccentricity;
    if (m && !f) {
        fiber->eccentricity = *masking;
        if (plm_fiber_params_validate(fiber, r->err) != PLM_OK) { /* a medulla must stay inside the new cortex */
            plm_error_prefix(r->err, "%s: %s (eccentricity from masking.%s): ", r->file, fiber_path, masking_key);
            return PLM_ERR_INVALID;
        }
    }
    return PLM_OK;
}

plm_result plm_feather_optics_read(const plm_json_reader *r, const cJSON *obj, const char *path,
                                   const char *const *extra, plm_material *m)
{
    plm_feather_material_default(m);
    plm_result rc = plm_params_read(r, obj, path, &plm_feather_material_param_block, extra, m);
    if (rc != PLM_OK)
        return rc;
    m->type = PLM_MATERIAL_FEATHER;
    m->feather = malloc(sizeof *m->feather);
    if (!m->feather)
        return plm_fail(r->err, PLM_ERR_NO_MEMORY, "out of memory");
    plm_feather_params_default(m->feather);
    rc = read_fiber(r, obj, path, "barb", &m->feather->barb);
    if (rc == PLM_OK)
        rc = read_fiber(r, obj, path, "barbule", &m->feather->barbule);
    if (rc == PLM_OK)
        rc = read_masking(r, obj, path, &m->feather->masking);
    if (rc == PLM_OK)
        rc = tie_eccentricity(r, obj, path, "barb", "barb_eccentricity", &m->feather->barb,
                              &m->feather->masking.barb_eccentricity);
    if (rc == PLM_OK)
        rc = tie_eccentricity(r, obj, path, "barbule", "barbule_eccentricity", &m->feather->barbule,
                              &m->feather->masking.barbule_eccentricity);
    if (rc != PLM_OK) { /* a failed read leaves nothing allocated (a species' optics leaked: fuzz_species) */
        free(m->feather);
        m->feather = NULL;
    }
    return rc;
}

plm_result plm_fluff_optics_read(const plm_json_reader *r, const cJSON *obj, const char *path,
                                 const struct plm_feather_params *feather, plm_fiber_material *out)
{
    memset(out, 0, sizeof *out);
    out->fiber = feather->barb;
    /* Across e3 the cortex shrinks from the barb's eccentricity to 1, and so does the medulla, which stays inside. */
    double e = out->fiber.eccentricity;
    out->fiber.eccentricity = 1.0;
    out->fiber.medulla_b /= e;
    out->fiber.medulla_cb /= e;
    out->stochastic = feather->bcsdf == PLM_BCSDF_STOCHASTIC;
    return read_fiber(r, obj, path, "fluff", &out->fiber);
}
