/* plumage generate: a feather (meshes, textures, scene) from a species
 * preset, or a contact sheet of several; plumage texture: the textures alone.
 * Both share one option table. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/outputs.h"
#include "cli/species_sheet.h"
#include "common/image_io.h"
#include "common/json.h"
#include "scene/feathers.h"
#include "texture/feather.h"
#include "texture/preview.h"

static const char *const formats[] = {"both", "exr", "png", NULL};

/* The contact sheet generates as a scene does: of the feather's options it takes these. */
#define SHEET_ONLY_OPTIONS "--spp --tile --columns --threads --quiet "
#define SHEET_OPTIONS SHEET_ONLY_OPTIONS "--contact-sheet --texture-size --level "
enum { FIRST_MESH_OPTION = 9 }; /* --level: where the options `texture` takes end */

/* name is one of the space-separated words of list. */
static int in_list(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = strstr(list, name); p; p = strstr(p + 1, name))
        if ((p == list || p[-1] == ' ') && p[n] == ' ')
            return 1;
    return 0;
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

/* The files plm_feather_write or plm_feather_write_textures wrote, by name. */
static void list_files(const plm_feather *f, const plm_feather_options *fo, const plm_feather_files *files, char *out,
                       size_t size)
{
    static const char *const names[] = {"vane.ply", "rachis.ply", "vane.obj", "rachis.obj", "texture.exr",
                                        "texture.png", "pigment.exr", "pigment.png", "feather.json"};
    int meshes = !fo->no_meshes, wanted[] = {meshes, meshes, meshes && files->obj, meshes && files->obj,
                                             !files->no_exr, !files->no_png, !files->no_exr && f->pigment.pixels,
                                             !files->no_png && f->pigment.pixels, meshes};
    out[0] = '\0';
    for (size_t i = 0, n = 0; i < sizeof names / sizeof names[0]; ++i)
        if (wanted[i])
            n += (size_t)snprintf(out + n, n < size ? size - n : 0, "%s%s", n ? " " : "", names[i]);
}

/* One feather (or its textures alone, `fo->no_meshes`) into the folder out.
 * The species and its optics are read, and the outputs checked, first. */
static int one_feather(const char *species, const char *out, const char *barb_png, const plm_feather_options *fo,
                       const plm_feather_files *files)
{
    plm_species sp;
    plm_error err;
    if (plm_species_load(species, &sp, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 1;
    }
    cJSON *optics = NULL;
    rgb rachis = rgb_gray(0.0);
    plm_outputs outputs = {0};
    plm_result r = fo->no_meshes ? PLM_OK : plm_species_optics_load(species, &optics, &rachis, &err);
    if (r == PLM_OK && !(plm_outputs_folder(&outputs, "-o", out) && (!barb_png || plm_outputs_file(&outputs, "--barb-preview", barb_png)))) {
        plm_species_free(&sp);
        cJSON_Delete(optics);
        return 1;
    }
    plm_feather f;
    char summary[512] = "";
    if (r == PLM_OK && (r = plm_feather_generate(&sp, fo, &f, &err)) == PLM_OK) {
        int n = snprintf(summary, sizeof summary, "%s: ", species);
        if (!fo->no_meshes)
            n += snprintf(summary + n, sizeof summary - (size_t)n, "vane %d triangles, rachis %d triangles, ",
                          f.vane.triangle_count, f.rachis.triangle_count);
        n += snprintf(summary + n, sizeof summary - (size_t)n, "textures %dx%d: ", fo->texture_width, fo->texture_height);
        r = fo->no_meshes ? plm_feather_write_textures(&f, out, files, &err)
                          : plm_feather_write(&f, optics, rachis, out, files, &err);
        list_files(&f, fo, files, summary + n, sizeof summary - (size_t)n);
        if (r == PLM_OK && barb_png)
            r = barb_preview(&f, barb_png, &err);
        plm_feather_free(&f);
    }
    plm_species_free(&sp);
    cJSON_Delete(optics);
    if (r != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        plm_outputs_undo(&outputs);
        return 1;
    }
    char folder[PLM_OUTPUTS_PATH];
    snprintf(folder, sizeof folder, "%s%s", out, out[0] && out[strlen(out) - 1] == '/' ? "" : "/");
    fprintf(stderr, "%s\n", summary);
    plm_print_wrote((const char *const[]){folder, barb_png}, 2);
    return 0;
}

static int run(int argc, char **argv, int textures_only)
{
    const char *species = NULL, *output = NULL, *sheet = NULL, *barb_png = NULL;
    int level = PLM_FEATHER_DEFAULT_LEVEL, size = 1024, tw = 0, th = 0, obj = 0, no_pigment = 0, format = 0;
    plm_species_sheet_options so = {.spp = 16, .tile = 384};
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
        {"--spp", PLM_OPT_INT, &so.spp, 0, 1, 1 << 20, NULL, "N", "contact sheet: samples per pixel (default 16)", 0},
        {"--tile", PLM_OPT_INT, &so.tile, 0, 32, 4096, NULL, "N",
         "contact sheet: height of a view in pixels; its width is half (default 384)", 0},
        {"--columns", PLM_OPT_INT, &so.columns, 0, 1, 64, NULL, "N", "contact sheet: species per row (default 6)", 0},
        {"--threads", PLM_OPT_INT, &so.threads, 0, 1, 1024, NULL, "N", "contact sheet: render threads (default: all cores)",
         0},
        {"--quiet", PLM_OPT_FLAG, &so.quiet, 0, 0, 0, NULL, NULL, "contact sheet: no progress lines", 0},
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
    /* The mesh and sheet options (from --level on) mean nothing to `texture`. */
    int rc = plm_parse_options(help, argc, argv, 1, opts, textures_only ? FIRST_MESH_OPTION : n_opts, positional,
                               textures_only ? 0 : 64, &n_pos);
    if (rc)
        return rc == 1 ? 0 : 2;
    for (int i = 0; i < n_opts; ++i)
        if (opts[i].seen && (sheet ? !in_list(SHEET_OPTIONS, opts[i].name) : in_list(SHEET_ONLY_OPTIONS, opts[i].name))) {
            fprintf(stderr, "error: %s %s --contact-sheet\n", opts[i].name, sheet ? "does not apply to" : "applies only to");
            return 2;
        }
    plm_feather_options fo = {.level = level, .texture_width = tw ? tw : size, .texture_height = th ? th : size,
                              .no_pigment = no_pigment, .no_meshes = textures_only};
    if (sheet) {
        if (n_pos == 0 || species || output) {
            fprintf(stderr, "error: --contact-sheet takes species files as arguments (and no --species or -o)\n");
            return 2;
        }
        so.level = level;
        so.texture_size = size;
        return plm_species_sheet(sheet, positional, n_pos, &so);
    }
    if (!species || !output || n_pos) {
        fprintf(stderr, "error: plumage %s needs --species FILE and -o DIR (see --help)\n", argv[0]);
        return 2;
    }
    return one_feather(species, output, barb_png, &fo, &(plm_feather_files){obj, format == 2, format == 1});
}

int cmd_generate(int argc, char **argv) { return run(argc, argv, 0); }

int cmd_texture(int argc, char **argv) { return run(argc, argv, 1); }
