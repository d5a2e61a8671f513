/* plumage probe <model>: dispatches to one probe per model. */
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"

typedef struct probe {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} probe;

static const probe probes[] = {
    {"masking", probe_masking, "barb/barbule masking weights and h-intervals (analytic or Monte Carlo), Fig. 9 pictures"},
    {"fiber", probe_fiber, "fiber BCSDF lobes (exit direction, RGB throughput) for view directions and offsets h"},
    {"bcsdf", probe_bcsdf, "fiber BCSDF lat-long reflectance plots (PNG + CSV), albedo, Fig. 7 contact sheet"},
    {NULL, NULL, NULL}, /* sentinel: probes are added here as the models land */
};

static void usage(FILE *out)
{
    fprintf(out, "usage: plumage probe <model> [options] < directions\n\nmodels:\n");
    for (const probe *p = probes; p->name; ++p)
        fprintf(out, "  %-10s %s\n", p->name, p->summary);
    fprintf(out, "\n'plumage probe <model> --help' describes each probe.\n");
}

int cmd_probe(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        usage(stdout);
        return 0;
    }
    for (const probe *p = probes; p->name; ++p)
        if (strcmp(argv[1], p->name) == 0)
            return p->run(argc - 1, argv + 1);
    fprintf(stderr, "error: unknown probe '%s'\n\n", argv[1]);
    usage(stderr);
    return 2;
}
