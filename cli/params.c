/* plumage params: the parameter tables of the scene format's and the species
 * format's blocks (field, type, default, range, unit, meaning), as text or as
 * the markdown tables of docs/scene-format.md and docs/species.md. The tables
 * are the ones the readers validate with (common/params.h). */
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/options.h"
#include "generate/layout.h"
#include "generate/wing.h"
#include "generate/species.h"
#include "optics/feather_bsdf.h"
#include "optics/pigment.h"
#include "render/scene.h"
#include "scene/layout_block.h"

typedef struct block_entry {
    const char *group; /* "scene" or "species" */
    const plm_param_block *block;
    int n_defaults;
    const char *labels[2];
    const void *defaults[2];
} block_entry;

int cmd_params(int argc, char **argv)
{
    int markdown = 0;
    plm_option opts[] = {
        {"--markdown", PLM_OPT_FLAG, &markdown, 0, 0, 0, NULL, NULL, "markdown tables (as in docs/scene-format.md)", 0},
    };
    plm_command_help help = {
        "plumage params [BLOCK...] [--markdown]",
        "Lists the fields of the scene format's and the species format's parameter blocks: type, default,\n"
        "allowed range, unit and meaning. BLOCK is a block's name (camera, film, the lights environment, sky,\n"
        "distant, sphere and quad, feather, fiber, pigments, masking, pelt, ball, wing, variation; shape,\n"
        "shape.rachis, ..., pigment) or a group, scene or species (default: all).\n"
        "These tables are the ones scene and species files are checked against."};
    const char *names[16];
    int n_names = 0;
    int rc = plm_parse_options(&help, argc, argv, 1, opts, 1, names, 16, &n_names);
    if (rc)
        return rc == 1 ? 0 : 2;
    plm_scene scene;
    plm_scene_init(&scene);
    const plm_light environment = plm_light_default(PLM_LIGHT_CONSTANT_ENV), sky = plm_light_default(PLM_LIGHT_SKY),
                    distant = plm_light_default(PLM_LIGHT_DISTANT), sphere = plm_light_default(PLM_LIGHT_SPHERE),
                    quad = plm_light_default(PLM_LIGHT_QUAD);
    plm_feather_params feather;
    plm_feather_params_default(&feather);
    plm_material material;
    plm_feather_material_default(&material);
    static const plm_pelt_params pelt;
    static const plm_ball_params ball;
    static const plm_wing_params wing;
    static const plm_layout_variation variation;
    static const plm_pigments pigments;
    plm_species species;
    plm_species_default(&species);
    const plm_split split = {0.5, 0.3, 0};
    const plm_shape *shape = &species.shape;
    const block_entry blocks[] = {
        {"scene", &plm_camera_param_block, 1, {""}, {&scene.camera}},
        {"scene", &plm_film_param_block, 1, {""}, {&scene.film}},
        {"scene", &plm_environment_light_param_block, 1, {""}, {&environment}},
        {"scene", &plm_sky_light_param_block, 1, {""}, {&sky}},
        {"scene", &plm_distant_light_param_block, 1, {""}, {&distant}},
        {"scene", &plm_sphere_light_param_block, 1, {""}, {&sphere}},
        {"scene", &plm_quad_light_param_block, 1, {""}, {&quad}},
        {"scene", &plm_feather_material_param_block, 1, {""}, {&material}},
        {"scene", &plm_fiber_param_block, 2, {"barb", "barbule"}, {&feather.barb, &feather.barbule}},
        {"scene", &plm_pigments_param_block, 1, {""}, {&pigments}},
        {"scene", &plm_masking_param_block, 1, {""}, {&feather.masking}},
        {"scene", &plm_pelt_param_block, 1, {""}, {&pelt}},
        {"scene", &plm_ball_param_block, 1, {""}, {&ball}},
        {"scene", &plm_wing_param_block, 1, {""}, {&wing}},
        {"scene", &plm_variation_param_block, 1, {""}, {&variation}},
        {"species", &plm_shape_param_block, 1, {""}, {shape}},
        {"species", &plm_rachis_param_block, 1, {""}, {shape}},
        {"species", &plm_vane_param_block, 1, {""}, {shape}},
        {"species", &plm_vane_tip_param_block, 1, {""}, {shape}},
        {"species", &plm_barbs_param_block, 1, {""}, {shape}},
        {"species", &plm_fluff_param_block, 1, {""}, {shape}},
        {"species", &plm_emargination_param_block[0], 1, {""}, {&shape->emargination[0]}},
        {"species", &plm_splits_param_block, 1, {""}, {shape}},
        {"species", &plm_split_param_block, 1, {""}, {&split}},
        {"species", &plm_pigment_param_block, 1, {""}, {&species.pigment}},
    };
    const int n_blocks = (int)(sizeof blocks / sizeof blocks[0]);
    for (int i = 0; i < n_names; ++i) {
        int known = 0;
        for (int b = 0; b < n_blocks; ++b)
            known |= strcmp(names[i], blocks[b].block->name) == 0 || strcmp(names[i], blocks[b].group) == 0;
        if (!known) {
            fprintf(stderr, "error: unknown block '%s' (a group, scene or species, or one of:", names[i]);
            for (int b = 0; b < n_blocks; ++b)
                fprintf(stderr, "%s %s", b ? "," : "", blocks[b].block->name);
            fprintf(stderr, ")\n");
            return 2;
        }
    }
    int first = 1;
    for (int b = 0; b < n_blocks; ++b) {
        int wanted = n_names == 0;
        for (int i = 0; i < n_names; ++i)
            wanted |= strcmp(names[i], blocks[b].block->name) == 0 || strcmp(names[i], blocks[b].group) == 0;
        if (!wanted)
            continue;
        if (!first)
            fputc('\n', stdout);
        first = 0;
        plm_params_print(stdout, blocks[b].block, blocks[b].n_defaults, blocks[b].labels, blocks[b].defaults,
                         markdown);
    }
    return 0;
}
