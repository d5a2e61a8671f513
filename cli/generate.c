/* plumage generate: a feather (meshes, textures, scene) from a species
 * preset, or a contact sheet of several; plumage texture: the textures alone.
 * Both share one option table. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/options.h"
#include "common/image_io.h"
#include "common/json.h"
#include "texture/feather.h"
#include "texture/preview.h"

static const char *const formats[] = {"both", "exr", "png", NULL};

/* Species files named on the command line, as plm_species loads them. */
static int load_species(const char *path, plm_species *sp)
{
    plm_error err;
    if (plm_species_load(path, sp, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 0;
    }
    return 1;
}

/* The species file's optics block for feather.json (the generator does not keep it). */
static cJSON *load_optics(const char *path)
{
    cJSON *root = NULL;
    plm_error err;
    if (plm_json_load(path, &root, &err) != PLM_OK)
        return NULL;
    cJSON *optics = cJSON_DetachItemFromObjectCaseSensitive(root, "optics");
    cJSON_Delete(root);
    return optics;
}

/* Three panels per feather: an oblique view, a side view (bend and curl)
 * and the texture with traced barbs; feathers side by side. */
static int contact_sheet(const char *out, const char **files, int n, const plm_feather_options *opt, int tile)
{
    const int panel_w[3] = {tile / 2, tile / 4, tile / 2};
    int column = panel_w[0] + panel_w[1] + panel_w[2], width = column * n;
    float *sheet = calloc((size_t)width * tile * 3, sizeof(float));
    float *panel = malloc(sizeof(float) * (size_t)tile * tile * 3);
    int ok = sheet && panel;
    for (int s = 0; ok && s < n; ++s) {
        plm_species sp;
        plm_feather f;
        plm_error err;
        if (!load_species(files[s], &sp))
            ok = 0;
        else if (plm_feather_generate(&sp, opt, &f, &err) != PLM_OK) {
            fprintf(stderr, "error: %s: %s\n", files[s], err.message);
            plm_species_free(&sp);
            ok = 0;
        }
        if (!ok)
            break;
        int x0 = s * column;
        for (int p = 0; p < 3; ++p) {
            int w = panel_w[p];
            if (p == 0)
                plm_preview_shape(&f, 25.0, 15.0, w, tile, panel);
            else if (p == 1)
                plm_preview_shape(&f, 88.0, 5.0, w, tile, panel);
            else
                plm_preview_texture(&f, f.outline.vane_length / 40.0, w, tile, panel);
            for (int j = 0; j < tile; ++j)
                memcpy(sheet + 3 * ((size_t)j * width + x0), panel + 3 * (size_t)j * w, sizeof(float) * 3 * w);
            x0 += w;
        }
        plm_feather_free(&f);
        plm_species_free(&sp);
    }
    plm_error err;
    if (ok && plm_image_write_srgb_png(out, width, tile, sheet, 0.0, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        ok = 0;
    }
    if (!sheet || !panel)
        fprintf(stderr, "error: out of memory for the contact sheet\n");
    free(sheet);
    free(panel);
    return ok ? 0 : 1;
}

/* A close-up of the barb coordinate: twelve barb spacings square, centred
 * halfway out on the wider vane at mid-length. */
static plm_result barb_preview(const plm_feather *f, const char *out, plm_error *err)
{
    const plm_outline *o = &f->outline;
    const int size = 512;
    int side = o->widest[1] >= o->widest[0];
    double y = o->vane_base + 0.5 * o->vane_length;
    double x = (side ? 0.5 : -0.5) * (plm_outline_rachis_radius(o, y) + plm_outline_width(o, side, 0.5));
    float *rgb = malloc(sizeof(float) * 3 * size * size);
    if (!rgb)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory", out);
    plm_preview_barb_coordinate(f, v2(x, y), 12.0 * 10.0 / o->shape.barb_density, size, size, rgb);
    plm_result rc = plm_image_write_srgb_png(out, size, size, rgb, 0.0, err);
    free(rgb);
    return rc;
}

static int run(int argc, char **argv, int textures_only)
{
    const char *species = NULL, *output = NULL, *sheet = NULL, *barb_png = NULL;
    int level = PLM_FEATHER_DEFAULT_LEVEL, size = 1024, tw = 0, th = 0, obj = 0, no_pigment = 0, format = 0;
    int tile = 512;
    plm_option opts[] = {
        {"--species", PLM_OPT_STRING, &species, 0, 0, 0, NULL, "FILE", "species preset (presets/species/*.json)", 0},
        {"-o", PLM_OPT_STRING, &output, 0, 0, 0, NULL, "DIR", "output directory (created if missing)", 0},
        {"--output", PLM_OPT_STRING, &output, 0, 0, 0, NULL, "DIR", "same as -o", 0},
        {"--texture-size", PLM_OPT_INT, &size, 0, 8, 16384, NULL, "N", "texture width and height (default 1024)", 0},
        {"--texture-width", PLM_OPT_INT, &tw, 0, 8, 16384, NULL, "N", "texture width (overrides --texture-size)", 0},
        {"--texture-height", PLM_OPT_INT, &th, 0, 8, 16384, NULL, "N", "texture height (overrides --texture-size)", 0},
        {"--format", PLM_OPT_CHOICE, &format, 0, 0, 0, formats, "F", "texture files: both (default), exr or png", 0},
        {"--no-pigment", PLM_OPT_FLAG, &no_pigment, 0, 0, 0, NULL, NULL, "skip the pigment image", 0},
        {"--barb-preview", PLM_OPT_STRING, &barb_png, 0, 0, 0, NULL, "PNG",
         "also write a close-up of the barb coordinate (docs/generating.md)", 0},
        {"--level", PLM_OPT_INT, &level, 0, 1, 6, NULL, "N", "subdivision level of the meshes (default 3)", 0},
        {"--obj", PLM_OPT_FLAG, &obj, 0, 0, 0, NULL, NULL, "also write the meshes as OBJ", 0},
        {"--contact-sheet", PLM_OPT_STRING, &sheet, 0, 0, 0, NULL, "PNG",
         "instead: a contact sheet of the species files given as arguments", 0},
        {"--tile", PLM_OPT_INT, &tile, 0, 64, 4096, NULL, "N", "contact sheet panel height in pixels (default 512)", 0},
    };
    const plm_command_help generate_help = {
        "plumage generate --species FILE -o DIR [options]\n       plumage generate --contact-sheet OUT.png "
        "SPECIES.json...",
        "Builds a feather from a species preset: the vane and rachis meshes (PLY, OpenSubdiv limit surfaces),\n"
        "the feather texture (barb direction and regions) and the pigment texture (EXR and 16-bit PNG), and\n"
        "feather.json, a scene for 'plumage render'. docs/species.md documents every species field,\n"
        "docs/generating.md the files written."};
    const plm_command_help texture_help = {
        "plumage texture --species FILE -o DIR [--texture-size N] [--format F] [--no-pigment] [--barb-preview PNG]",
        "Writes texture.exr/.png (barb direction and regions) and pigment.exr/.png for a species, as\n"
        "'plumage generate' does, without the meshes or the scene."};
    const plm_command_help *help = textures_only ? &texture_help : &generate_help;
    const char *positional[64];
    int n_pos = 0, n_opts = (int)(sizeof opts / sizeof opts[0]);
    /* The mesh and sheet options (the last four) mean nothing to `texture`. */
    int rc = plm_parse_options(help, argc, argv, 1, opts, textures_only ? n_opts - 4 : n_opts, positional,
                               textures_only ? 0 : 64, &n_pos);
    if (rc)
        return rc == 1 ? 0 : 2;
    plm_feather_options fo = {.level = level, .texture_width = tw ? tw : size, .texture_height = th ? th : size,
                              .no_pigment = no_pigment, .no_meshes = textures_only};
    if (sheet) {
        if (n_pos == 0 || species || output) {
            fprintf(stderr, "error: --contact-sheet takes species files as arguments (and no --species or -o)\n");
            return 2;
        }
        return contact_sheet(sheet, positional, n_pos, &fo, tile);
    }
    if (!species || !output || n_pos) {
        fprintf(stderr, "error: plumage %s needs --species FILE and -o DIR (see --help)\n", argv[0]);
        return 2;
    }
    plm_species sp;
    if (!load_species(species, &sp))
        return 1;
    cJSON *optics = load_optics(species);
    plm_feather f;
    plm_error err;
    plm_feather_files files = {obj, format == 2, format == 1};
    int triangles[2] = {0, 0};
    plm_result r = plm_feather_generate(&sp, &fo, &f, &err);
    if (r == PLM_OK) {
        triangles[0] = f.vane.triangle_count;
        triangles[1] = f.rachis.triangle_count;
        r = textures_only ? plm_feather_write_textures(&f, output, &files, &err)
                          : plm_feather_write(&f, optics, output, &files, &err);
        if (r == PLM_OK && barb_png)
            r = barb_preview(&f, barb_png, &err);
        plm_feather_free(&f);
    }
    plm_species_free(&sp);
    cJSON_Delete(optics);
    if (r != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 1;
    }
    if (textures_only)
        printf("%s: textures %dx%d -> %s\n", species, fo.texture_width, fo.texture_height, output);
    else
        printf("%s: vane %d triangles, rachis %d triangles, textures %dx%d -> %s/feather.json\n", species,
               triangles[0], triangles[1], fo.texture_width, fo.texture_height, output);
    return 0;
}

int cmd_generate(int argc, char **argv) { return run(argc, argv, 0); }

int cmd_texture(int argc, char **argv) { return run(argc, argv, 1); }
