/* The default scene's wing (presets/scenes/default.json) spread and seen
 * through the ID pass (render/visibility.h) from straight above and straight
 * below: the coverts hide every flight feather's base from above, and no
 * skin shows from either side. Tolerances, fixed before measuring:
 * - bases: rays ending on the proximal fifth (v < 0.2) of a primary,
 *   secondary or tertial are at most 0.1% of the rays ending on flight
 *   feathers, and no one flight feather shows its proximal fifth on more
 *   than 3 rays (a feather 0.3 long is about 70 rays long here; a few rays
 *   slip through the ragged barb ends of the coverts over it);
 * - skin: rays ending on the wing's skin are at most 0.5% of the rays ending
 *   on the wing, from above and from below.
 * Rows come from the same scene file's layout, built again: the scene places
 * the layout's instances in order, feather id = instance index + 1. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/params.h"
#include "generate/wing.h"
#include "render/visibility.h"
#include "scene/layout_block.h"
#include "scene/scene_file.h"

#define SCENES PLUMAGE_SOURCE_DIR "/presets/scenes/"

/* The wing layout of default.json, spread. */
static void default_wing(plm_layout *l, plm_species *sp)
{
    static const char *const extra[] = {"type", "rows", "surface_material", "variation", "level", "texture_size",
                                        NULL};
    plm_error err = {{0}};
    cJSON *root = NULL;
    assert_int_equal(plm_json_load(SCENES "default.json", &root, &err), PLM_OK);
    const cJSON *layout = cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(root, "objects"), 0), "layout");
    plm_json_reader r = {"default.json", &err, 0};
    plm_wing_params p = {0};
    assert_int_equal(plm_params_read(&r, layout, "layout", &plm_wing_param_block, extra, &p), PLM_OK);
    const cJSON *variation = cJSON_GetObjectItem(layout, "variation");
    if (variation)
        assert_int_equal(plm_params_read(&r, variation, "variation", &plm_variation_param_block, NULL, &p.variation),
                         PLM_OK);
    p.fold = 0.0;
    const plm_species *rows[PLM_WING_ROWS] = {0};
    for (int row = 0; row < PLM_WING_ROWS; ++row) {
        const cJSON *file = cJSON_GetObjectItem(cJSON_GetObjectItem(layout, "rows"), plm_wing_row_names[row]);
        if (!cJSON_IsString(file))
            continue;
        char path[1024];
        snprintf(path, sizeof path, SCENES "%s", file->valuestring);
        assert_int_equal(plm_species_load(path, &sp[row], &err), PLM_OK);
        rows[row] = &sp[row];
    }
    assert_int_equal(plm_layout_wing(&p, rows, l, &err), PLM_OK);
    cJSON_Delete(root);
}

/* The ID pass of the spread default wing from straight above (side 1) or below (-1). */
static void trace(int side, plm_visibility *v)
{
    char position[64];
    snprintf(position, sizeof position, "camera.position=[0.45,-0.12,%g]", 2.0 * side);
    const char *sets[] = {"objects.0.layout.fold=0", position, "camera.look_at=[0.45,-0.12,0]", "camera.fov=34",
                          "film.width=480", "film.height=300"};
    plm_scene scene;
    plm_world world;
    plm_error err = {{0}};
    plm_result rc = plm_scene_load_with(SCENES "default.json", sets, 6, &scene, &err);
    if (rc == PLM_OK)
        rc = plm_world_build(&scene, &world, &err);
    if (rc != PLM_OK)
        fprintf(stderr, "%s\n", err.message);
    assert_int_equal(rc, PLM_OK);
    assert_int_equal(plm_visibility_trace(&world, &world.camera, v, &err), PLM_OK);
    plm_world_free(&world);
    plm_scene_free(&scene);
}

static long long wing_rays(const plm_visibility *v)
{
    return v->part_hits[PLM_PART_VANE] + v->part_hits[PLM_PART_RACHIS] + v->part_hits[PLM_PART_FLUFF] +
           v->part_hits[PLM_PART_BODY];
}

static void skin_hidden(const plm_visibility *v, const char *side)
{
    double skin = (double)v->part_hits[PLM_PART_BODY] / (double)wing_rays(v);
    printf("from %s: %lld rays on the wing, %lld on its skin (%.4f)\n", side, wing_rays(v),
           v->part_hits[PLM_PART_BODY], skin);
    assert_true(wing_rays(v) > 10000);
    assert_true(skin <= 0.005);
}

static void coverts_hide_the_bases_and_the_skin(void **state)
{
    (void)state;
    plm_species sp[PLM_WING_ROWS] = {0};
    plm_layout l;
    default_wing(&l, sp);
    plm_visibility v;
    trace(1, &v);
    assert_int_equal(v.feather_count, l.instance_count);
    long long flight = 0, bases = 0;
    int worst = 0, worst_feather = 0, *per = calloc((size_t)v.feather_count + 1, sizeof *per);
    for (long long i = 0; i < (long long)v.width * v.height; ++i) {
        int f = v.feather[i];
        if (!f || l.instances[f - 1].row > PLM_WING_TERTIAL)
            continue;
        flight++;
        if (v.v[i] < 0.2f && ++per[f] > worst)
            worst = per[f], worst_feather = f;
    }
    for (int f = 1; f <= v.feather_count; ++f)
        bases += per[f];
    printf("from above: %lld rays on flight feathers, %lld on their proximal fifth (%.5f); at most %d on feather %d "
           "(row %d)\n", flight, bases, (double)bases / (double)flight, worst, worst_feather,
           worst_feather ? l.instances[worst_feather - 1].row : -1);
    assert_true(flight > 5000);
    assert_true((double)bases <= 0.001 * (double)flight);
    assert_true(worst <= 3);
    skin_hidden(&v, "above");
    plm_visibility_free(&v);
    trace(-1, &v);
    skin_hidden(&v, "below");
    plm_visibility_free(&v);
    free(per);
    plm_layout_free(&l);
    for (int row = 0; row < PLM_WING_ROWS; ++row)
        plm_species_free(&sp[row]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(coverts_hide_the_bases_and_the_skin),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
