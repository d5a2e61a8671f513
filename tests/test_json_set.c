/* Dotted-path assignments to JSON documents (--set and batch overrides). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <stdlib.h>
#include <string.h>

#include "common/json_set.h"

static const char *scene_text =
    "{\"camera\": {\"fov\": 40, \"position\": [0, 1, 3]},"
    " \"lights\": [{\"type\": \"environment\"}, {\"type\": \"distant\", \"irradiance\": [1, 1, 1]}],"
    " \"feathers\": {\"f\": {\"species\": \"a.json\"}}}";

/* Applies one assignment to a fresh document; returns the printed result (caller frees) or NULL on error. */
static char *apply(const char *assignment, plm_error *err)
{
    cJSON *root = cJSON_Parse(scene_text);
    assert_non_null(root);
    char *out = NULL;
    if (plm_json_set_assignment(root, assignment, err) == PLM_OK)
        out = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    return out;
}

static void values_are_json_else_strings(void **state)
{
    (void)state;
    plm_error err = {{0}};
    cJSON *root = cJSON_Parse(scene_text);
    assert_int_equal(plm_json_set_assignment(root, "camera.fov=25.5", &err), PLM_OK);
    assert_int_equal(plm_json_set_assignment(root, "lights.1.irradiance=[2, 3, 4]", &err), PLM_OK);
    assert_int_equal(plm_json_set_assignment(root, "feathers.f.species=other dir/b.json", &err), PLM_OK);
    assert_int_equal(plm_json_set_assignment(root, "camera.aperture=0.1", &err), PLM_OK); /* a new last field */
    assert_int_equal(plm_json_set_assignment(root, "camera.position.2=7", &err), PLM_OK);
    const cJSON *camera = cJSON_GetObjectItem(root, "camera");
    assert_double_near(cJSON_GetObjectItem(camera, "fov")->valuedouble, 25.5, 0.0);
    assert_double_near(cJSON_GetObjectItem(camera, "aperture")->valuedouble, 0.1, 0.0);
    assert_double_near(cJSON_GetArrayItem(cJSON_GetObjectItem(camera, "position"), 2)->valuedouble, 7.0, 0.0);
    const cJSON *irr = cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(root, "lights"), 1), "irradiance");
    assert_int_equal(cJSON_GetArraySize(irr), 3);
    assert_double_near(cJSON_GetArrayItem(irr, 2)->valuedouble, 4.0, 0.0);
    const cJSON *species = cJSON_GetObjectItem(cJSON_GetObjectItem(cJSON_GetObjectItem(root, "feathers"), "f"),
                                               "species");
    assert_string_equal(species->valuestring, "other dir/b.json");
    cJSON_Delete(root);
}

/* Each error names the whole path and what is wrong with which segment. */
static void errors_name_the_path(void **state)
{
    (void)state;
    static const struct {
        const char *assignment, *message;
    } cases[] = {
        {"camera.fovx.y=1", "camera.fovx.y: no field \"fovx\" in camera (it has: fov, position)"},
        {"cam.fov=1", "cam.fov: no field \"cam\" in the top level (it has: camera, lights, feathers)"},
        {"camera.fov.x=1", "camera.fov.x: camera.fov is a number, not an object or array"},
        {"lights.2.type=\"quad\"", "lights.2.type: lights is an array of 2, \"2\" is not an index in [0, 1]"},
        {"lights.first=1", "lights.first: lights is an array of 2, \"first\" is not an index in [0, 1]"},
        {"camera..fov=1", "'camera..fov': expected a dotted path such as camera.fov"},
        {"=1", "'': expected a dotted path such as camera.fov"},
        {"camera.fov", "'camera.fov': expected path.to.field=value"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        plm_error err = {{0}};
        char *out = apply(cases[i].assignment, &err);
        assert_null(out);
        assert_string_equal(err.message, cases[i].message);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(values_are_json_else_strings),
        cmocka_unit_test(errors_name_the_path),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
