/* plumage export: a scene's feathers, bodies and materials as a glTF 2.0
 * file for other tools (export/gltf.h, docs/assets.md). */
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/outputs.h"
#include "common/fileio.h"
#include "export/gltf.h"
#include "scene/scene_file.h"

int cmd_export(int argc, char **argv)
{
    const char *output = NULL;
    int no_fluff = 0, quiet = 0;
    plm_gltf_options go = {0};
    plm_opt_list sets = {{0}, 0};
    plm_option opts[] = {
        {"-o", PLM_OPT_STRING, &output, 0, 0, 0, NULL, "OUT.glb", "the file to write: .glb or .gltf", 0},
        {"--output", PLM_OPT_STRING, &output, 0, 0, 0, NULL, "OUT.glb", "same as -o", 0},
        {"--set", PLM_OPT_LIST, &sets, 0, 0, 0, NULL, "PATH=VALUE", "change a scene field first (as render --set)", 0},
        {"--no-fluff", PLM_OPT_FLAG, &no_fluff, 0, 0, 0, NULL, NULL, "leave the fluffy bases (lines) out", 0},
        {"--bake-views", PLM_OPT_INT, &go.bake.views, 0, 2, 256, NULL, "N",
         "the bake's views: N x N over the hemisphere (default 24)", 0},
        {"--bake-samples", PLM_OPT_INT, &go.bake.samples, 0, 1, 1 << 16, NULL, "N",
         "the bake's BSDF samples per view (default 64)", 0},
        {"--threads", PLM_OPT_INT, &go.table_threads, 0, 1, 1024, NULL, "N",
         "fiber table builds, if the tables are not cached (default: all cores)", 0},
        {"--quiet", PLM_OPT_FLAG, &quiet, 0, 0, 0, NULL, NULL, "no summary line", 0},
    };
    plm_command_help help = {
        "plumage export SCENE.json -o OUT.glb|OUT.gltf [options]",
        "Writes the scene's geometry and materials as glTF 2.0 (through Assimp), for Blender, game engines\n"
        "and web viewers: each distinct feather's vane, rachis and fluff once, each placed feather a node\n"
        "referring to them with its transform, the body and surface meshes, texture coordinates and normals,\n"
        "under a root node that turns the scene's up axis (its camera's) into glTF's +y. Each feather\n"
        "material's base colour is a texture baked from plumage's own BSDF under uniform white light (the\n"
        "colour of plumage's render at a distance), times the pigment and the mean tint of its feathers,\n"
        "with the vane's transparency as alpha; its orientation texture goes along in an unlit material\n"
        "NAME.orientation. The fluff's fibers go out as line segments (glTF lines have no width) coloured\n"
        "by the fiber's far field, or not at all with --no-fluff. .glb embeds everything; .gltf writes\n"
        "OUT.bin and OUT.MATERIAL.albedo.png / .orientation.png beside it. Lights and the camera are not\n"
        "exported. docs/assets.md describes the file."};
    const char *positional[1];
    int n_positional = 0;
    int rc = plm_parse_options(&help, argc, argv, 1, opts, (int)(sizeof opts / sizeof opts[0]), positional, 1,
                               &n_positional);
    if (rc)
        return rc == 1 ? 0 : 2;
    if (n_positional != 1 || !output) {
        fprintf(stderr, "error: plumage export needs one scene file and -o OUT.glb or OUT.gltf (see --help)\n");
        return 2;
    }
    char ext[16];
    plm_path_extension(output, ext, sizeof ext);
    if (strcmp(ext, "glb") != 0 && strcmp(ext, "gltf") != 0) {
        fprintf(stderr, "error: -o %s: unsupported format '.%s' (use .glb or .gltf)\n", output, ext);
        return 2;
    }
    go.no_fluff = no_fluff;
    plm_outputs outputs = {0};
    if (!plm_outputs_file(&outputs, "-o", output))
        return 1;
    plm_scene scene;
    plm_error err = {{0}};
    plm_gltf_report r;
    if (plm_scene_load_with(positional[0], sets.items, sets.count, &scene, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        plm_outputs_undo(&outputs);
        return 1;
    }
    plm_result result = plm_gltf_export(&scene, output, &go, &r, &err);
    plm_scene_free(&scene);
    if (result != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        plm_outputs_undo(&outputs);
        return 1;
    }
    if (!quiet)
        fprintf(stderr,
                "%s: %d nodes (%d feathers), %d meshes (%d of lines: %ld segments), %d materials, %d textures; %d "
                "instances exported, %d left out%s; bake %.2f s, write %.2f s\n",
                output, r.nodes, r.feathers, r.meshes, r.line_meshes, r.segments, r.materials, r.textures,
                r.instances, r.left_out, no_fluff ? " (the fluff: --no-fluff)" : "", r.bake_seconds,
                r.write_seconds);
    plm_print_wrote((const char *const[]){output}, 1);
    return 0;
}
