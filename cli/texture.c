/* plumage texture: re-authors a species' textures alone (no meshes). */
#include <stdio.h>

#include "cli/commands.h"
#include "cli/options.h"
#include "texture/feather.h"

int cmd_texture(int argc, char **argv)
{
    static const char *const formats[] = {"both", "exr", "png", NULL};
    const char *species = NULL, *output = NULL;
    int size = 1024, tw = 0, th = 0, no_pigment = 0, format = 0;
    plm_option opts[] = {
        {"--species", PLM_OPT_STRING, &species, 0, 0, 0, NULL, "FILE", "species preset (presets/species/*.json)", 0},
        {"-o", PLM_OPT_STRING, &output, 0, 0, 0, NULL, "DIR", "output directory (created if missing)", 0},
        {"--output", PLM_OPT_STRING, &output, 0, 0, 0, NULL, "DIR", "same as -o", 0},
        {"--texture-size", PLM_OPT_INT, &size, 0, 8, 16384, NULL, "N", "texture width and height (default 1024)", 0},
        {"--texture-width", PLM_OPT_INT, &tw, 0, 8, 16384, NULL, "N", "texture width (overrides --texture-size)", 0},
        {"--texture-height", PLM_OPT_INT, &th, 0, 8, 16384, NULL, "N", "texture height (overrides --texture-size)", 0},
        {"--format", PLM_OPT_CHOICE, &format, 0, 0, 0, formats, "F", "texture files: both (default), exr or png", 0},
        {"--no-pigment", PLM_OPT_FLAG, &no_pigment, 0, 0, 0, NULL, NULL, "skip the pigment image", 0},
    };
    const plm_command_help help = {
        "plumage texture --species FILE -o DIR [options]",
        "Writes feather.exr/.png (barb direction and regions) and pigment.exr/.png for a species, as 'plumage "
        "generate' does, without the meshes or the scene."};
    int rc = plm_parse_options(&help, argc, argv, 1, opts, (int)(sizeof opts / sizeof opts[0]), NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    if (!species || !output) {
        fprintf(stderr, "error: plumage texture needs --species FILE and -o DIR (see --help)\n");
        return 2;
    }
    plm_species sp;
    plm_feather f = {0};
    plm_error err;
    plm_result r = plm_species_load(species, &sp, &err);
    if (r == PLM_OK) {
        plm_feather_options fo = {.texture_width = tw ? tw : size, .texture_height = th ? th : size,
                                  .no_meshes = 1, .no_pigment = no_pigment};
        plm_feather_files files = {0, format == 2, format == 1};
        r = plm_feather_generate(&sp, &fo, &f, &err);
        if (r == PLM_OK)
            r = plm_feather_write_textures(&f, output, &files, &err);
        plm_feather_free(&f);
        plm_species_free(&sp);
    }
    if (r != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 1;
    }
    printf("%s: textures %dx%d -> %s\n", species, tw ? tw : size, th ? th : size, output);
    return 0;
}
