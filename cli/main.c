/* plumage: the command-line front end. Each subcommand is a thin layer over
 * one stage's library (generate/, texture/, optics/, render/). */
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"

typedef struct command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} command;

static const command commands[] = {
    {"generate", cmd_generate, "build a feather (meshes, textures, scene) from a species preset"},
    {"texture", cmd_texture, "re-author a species' feather and pigment textures alone"},
    {"probe", cmd_probe, "answer questions about the optical models without rendering (CSV and plots)"},
    {"params", cmd_params, "list the scene format's parameter blocks: fields, defaults, ranges, units"},
    {"render", cmd_render, "render a scene file to a linear EXR and a tone-mapped PNG (path tracer)"},
    {"fireflies", cmd_fireflies, "count a rendered EXR's fireflies and compare its mean with a reference's"},
    {"export", cmd_export, "write a scene's feathers, bodies and baked materials as glTF 2.0 (.glb, .gltf)"},
    {"batch", cmd_batch, "run a manifest of render jobs or a parameter sweep, locally or as a Slurm job array"},
    {"bench", cmd_bench, "print performance figures (ns per call, samples per second, memory)"},
};

static void usage(FILE *out)
{
    fprintf(out, "usage: plumage <command> [options]\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        fprintf(out, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\n'plumage <command> --help' describes each command; docs/README.md in the source\n"
                 "tree documents them all.\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "help") == 0) {
        usage(stdout);
        return 0;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        if (strcmp(argv[1], commands[i].name) == 0)
            return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "error: unknown command '%s'\n\n", argv[1]);
    usage(stderr);
    return 2;
}
