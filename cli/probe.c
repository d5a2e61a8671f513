/* plumage probe <model>: dispatches to one probe per model. */
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/options.h"

static const plm_subcommand probes[] = {
    {"masking", probe_masking, "barb/barbule masking weights and h-intervals (analytic or Monte Carlo), Fig. 9 pictures"},
    {"fiber", probe_fiber, "fiber BCSDF lobes (exit direction, RGB throughput) for view directions and offsets h"},
    {"layout", probe_layout, "a pelt, feather ball or wing layout's instances as CSV (prototype, variation, matrix)"},
    {"visibility", probe_visibility, "the ID pass: which feather and part each camera ray ends on, visible fractions, bare skin"},
    {"bcsdf", probe_bcsdf, "fiber BCSDF lat-long reflectance plots (PNG + CSV), albedo, Fig. 7 contact sheet"},
    {NULL, NULL, NULL}, /* sentinel: probes are added here as the models land */
};

int cmd_probe(int argc, char **argv)
{
    return plm_dispatch("plumage probe <model> [options] < directions", "model", probes, argc, argv);
}
