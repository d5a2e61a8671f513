/* Batch manifests parsed from buffers: sweeps expand to their product in
 * order, jobs inherit the top-level fields, bad manifests name the field. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "batch/manifest.h"

#define SCENE PLUMAGE_SOURCE_DIR "/presets/scenes/vane_quad.json"

static plm_result parse(const char *text, plm_manifest *m, plm_error *err)
{
    return plm_manifest_parse(text, strlen(text), "/tmp/m.json", m, err);
}

static void sweep_is_the_product_last_key_fastest(void **state)
{
    (void)state;
    plm_manifest m;
    plm_error err = {{0}};
    const char *text = "{\"scene\": \"" SCENE "\", \"spp\": 4, \"set\": {\"film.exposure\": 1},"
                       " \"sweep\": {\"camera.fov\": [20, 30, 40], \"materials.vane.type\": [\"feather\", \"diffuse\"],"
                       " \"film.seed\": [7]}}";
    assert_int_equal(parse(text, &m, &err), PLM_OK);
    assert_int_equal(m.n_jobs, 6);
    assert_int_equal(m.n_keys, 3);
    assert_int_equal(m.key_counts[0], 3);
    assert_int_equal(m.key_counts[1], 2);
    assert_int_equal(m.key_counts[2], 1);
    static const char *const fov[] = {"20", "20", "30", "30", "40", "40"};
    for (int i = 0; i < 6; ++i) {
        const plm_batch_job *j = &m.jobs[i];
        char name[8], set[64], label[128];
        snprintf(name, sizeof name, "%04d", i);
        assert_string_equal(j->name, name);
        assert_string_equal(j->scene, SCENE);
        assert_int_equal(j->spp, 4);
        assert_int_equal(j->n_sets, 4); /* the manifest's set first, then one per swept key */
        assert_string_equal(j->sets[0], "film.exposure=1");
        snprintf(set, sizeof set, "camera.fov=%s", fov[i]);
        assert_string_equal(j->sets[1], set);
        assert_string_equal(j->sets[2], i % 2 ? "materials.vane.type=\"diffuse\"" : "materials.vane.type=\"feather\"");
        assert_string_equal(j->sets[3], "film.seed=7");
        /* The label names the keys that vary by their whole path, strings without their quotes. */
        snprintf(label, sizeof label, "camera.fov=%s\nmaterials.vane.type=%s", fov[i], i % 2 ? "diffuse" : "feather");
        assert_string_equal(j->label, label);
        for (int k = 0; k < i; ++k)
            assert_true(m.jobs[k].key != j->key);
    }
    plm_manifest_free(&m);
    /* Keys that end alike stay told apart. */
    assert_int_equal(parse("{\"scene\": \"" SCENE "\", \"sweep\": {\"lights.0.radiance\": [1, 2],"
                           " \"lights.1.radiance\": [3, 4], \"camera.fov\": [5, 6]}}", &m, &err), PLM_OK);
    assert_string_equal(m.jobs[7].label, "lights.0.radiance=2\nlights.1.radiance=4\ncamera.fov=6");
    plm_manifest_free(&m);
}

static void jobs_inherit_and_override(void **state)
{
    (void)state;
    plm_manifest m;
    plm_error err = {{0}};
    /* No NUL after the text: the parser must respect the length. */
    char text[512];
    int n = snprintf(text, sizeof text,
                     "{\"scene\": \"" SCENE "\", \"resolution\": [64, 32], \"seed\": 3, \"output\": \"out\","
                     " \"jobs\": [{\"name\": \"plain\"}, {\"spp\": 9, \"resolution\": [8, 4], \"seed\": -1,"
                     " \"set\": {\"camera.fov\": 10}}]}XXXX");
    assert_int_equal(plm_manifest_parse(text, (size_t)n - 4, "/tmp/m.json", &m, &err), PLM_OK);
    assert_int_equal(m.n_jobs, 2);
    assert_int_equal(m.n_keys, 0);
    assert_string_equal(m.output, "out");
    assert_string_equal(m.jobs[0].name, "0000-plain");
    assert_string_equal(m.jobs[0].label, "plain");
    assert_int_equal(m.jobs[0].width, 64);
    assert_int_equal(m.jobs[0].seed, 3);
    assert_int_equal(m.jobs[0].spp, 0);
    assert_int_equal(m.jobs[0].n_sets, 0);
    assert_string_equal(m.jobs[1].name, "0001");
    assert_int_equal(m.jobs[1].spp, 9);
    assert_int_equal(m.jobs[1].width, 8);
    assert_int_equal(m.jobs[1].height, 4);
    assert_int_equal(m.jobs[1].seed, -1);
    assert_string_equal(m.jobs[1].sets[0], "camera.fov=10");
    /* The same job text gives the same key (resuming depends on it). */
    plm_manifest again;
    assert_int_equal(plm_manifest_parse(text, (size_t)n - 4, "/tmp/m.json", &again, &err), PLM_OK);
    assert_true(again.jobs[1].key == m.jobs[1].key);
    assert_true(again.jobs[0].key != m.jobs[1].key);
    plm_manifest_free(&again);
    plm_manifest_free(&m);
    /* Assets: on unless the manifest or the job says otherwise; a job's setting is part of its key. */
    const char *assets = "{\"scene\": \"" SCENE "\", \"assets\": false,"
                         " \"jobs\": [{}, {\"assets\": true}, {\"assets\": false}]}";
    assert_int_equal(parse(assets, &m, &err), PLM_OK);
    assert_int_equal(m.jobs[0].assets, 0);
    assert_int_equal(m.jobs[1].assets, 1);
    assert_int_equal(m.jobs[2].assets, 0);
    assert_true(m.jobs[0].key != m.jobs[1].key);
    plm_manifest_free(&m);
    assert_int_equal(parse("{\"scene\": \"" SCENE "\", \"jobs\": [{}]}", &m, &err), PLM_OK);
    assert_int_equal(m.jobs[0].assets, 1);
    plm_manifest_free(&m);
}

static void bad_manifests_name_the_field(void **state)
{
    (void)state;
    static const struct {
        const char *text, *message;
    } cases[] = {
        {"{\"scene\": \"" SCENE "\", \"jobz\": []}", "/tmp/m.json: jobz: unknown field (allowed: scene, output, spp, "
                                                    "resolution, seed, assets, set, jobs, sweep)"},
        {"{\"scene\": \"" SCENE "\", \"sweep\": {}}", "/tmp/m.json: sweep: expected a non-empty object of "
                                                     "\"path.to.field\": [values...]"},
        {"{\"scene\": \"" SCENE "\", \"sweep\": {\"camera.fov\": 3}}",
         "/tmp/m.json: sweep.camera.fov: expected a non-empty array of values"},
        {"{\"scene\": \"" SCENE "\", \"jobs\": []}", "/tmp/m.json: jobs: expected a non-empty array of jobs"},
        {"{\"jobs\": [{\"scene\": \"no/such.json\"}]}",
         "/tmp/m.json: jobs[0].scene: /tmp/no/such.json: cannot read: No such file or directory"},
        {"{\"jobs\": [{\"name\": \"x\"}]}",
         "/tmp/m.json: jobs[0].scene: required (a scene file, here or at the top level)"},
        {"{\"scene\": \"" SCENE "\", \"jobs\": [{\"name\": \"../up\"}]}",
         "/tmp/m.json: jobs[0].name: \"../up\": 1 to 64 letters, digits, '.', '_' or '-' (a folder name)"},
        {"{\"scene\": \"" SCENE "\", \"jobs\": [{\"set\": {\"a=b\": 1}}]}",
         "/tmp/m.json: jobs[0].set: \"a=b\" is not a dotted path such as camera.fov"},
        {"{\"scene\": \"" SCENE "\", \"spp\": 0, \"jobs\": [{}]}", "/tmp/m.json: spp: 0 is out of range [1, 16777216]"},
        {"{\"scene\": \"" SCENE "\"}", "/tmp/m.json: (top level): give either \"jobs\" (a list) or \"sweep\" "
                                      "(parameter values), not neither"},
        {"{\"scene\": \"" SCENE "\", \"sweep\": {\"a\": [1,2,3,4,5,6,7,8,9,10], \"b\": [1,2,3,4,5,6,7,8,9,10],"
         " \"c\": [1,2,3,4,5,6,7,8,9,10,11], \"d\": [1,2,3,4,5,6,7,8,9,10], \"e\": [1,2,3,4,5,6,7,8,9,10]}}",
         "/tmp/m.json: sweep: more than 100000 jobs in the product"},
        {"[1, 2", "/tmp/m.json:1:5: malformed JSON"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        plm_manifest m;
        plm_error err = {{0}};
        assert_int_not_equal(parse(cases[i].text, &m, &err), PLM_OK);
        assert_string_equal(err.message, cases[i].message);
        assert_null(m.jobs);
        assert_int_equal(m.n_jobs, 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sweep_is_the_product_last_key_fastest),
        cmocka_unit_test(jobs_inherit_and_override),
        cmocka_unit_test(bad_manifests_name_the_field),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
