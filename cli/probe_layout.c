/* plumage probe layout: runs a layout (generate/layout.h) and prints its
 * instances as CSV, one row per placed feather (docs/layouts.md). */
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/options.h"
#include "generate/layout.h"
#include "generate/wing.h"
#include "scene/layout_block.h"

static const char *const kinds[] = {"pelt", "ball", "wing", NULL};
enum { KIND_PELT, KIND_BALL, KIND_WING };

typedef struct layout_args {
    int kind, count, variants, seed;
    double density, overlap, length, elevation_deg, width, height, radius, axis[3];
    double head_size, edge_size, edge_width;
    double span, chord, sweep_deg, fold;
    const char *surface;
    plm_opt_list species, rows;
} layout_args;

static void print_csv(const plm_layout *l)
{
    printf("instance,prototype,species,variant,row,order,scale,yaw_deg,lift_deg,tint_r,tint_g,tint_b,"
           "m00,m01,m02,m03,m10,m11,m12,m13,m20,m21,m22,m23\n");
    for (int i = 0; i < l->instance_count; ++i) {
        const plm_layout_instance *in = &l->instances[i];
        const plm_layout_prototype *pr = &l->prototypes[in->prototype];
        printf("%d,%d,%d,%d,%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", i, in->prototype, pr->species, pr->variant,
               in->row, in->order, in->scale, plm_degrees(in->yaw) + 0.0, plm_degrees(in->lift), in->tint.r,
               in->tint.g, in->tint.b);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c)
                printf(",%.9g", in->m[r][c] + 0.0);
        printf("\n");
    }
}

/* "--row primary=FILE": the row's index and the file. */
static int parse_row(const char *item, int *row, const char **file)
{
    const char *eq = strchr(item, '=');
    for (int r = 0; eq && r < PLM_WING_ROWS; ++r)
        if (strlen(plm_wing_row_names[r]) == (size_t)(eq - item) && !strncmp(item, plm_wing_row_names[r], eq - item)) {
            *row = r;
            *file = eq + 1;
            return 1;
        }
    fprintf(stderr, "error: probe layout: --row %s: expected ROW=FILE with ROW one of primary, secondary, tertial, "
                    "greater_covert, median_covert, lesser_covert, alula, primary_covert, marginal_covert, under_covert, "
                    "speculum\n", item);
    return 0;
}

static plm_result run_layout(const layout_args *a, plm_species *sp, int n, plm_mesh *mesh, plm_layout *out,
                             plm_error *err)
{
    if (a->kind == KIND_WING) {
        const plm_species *rows[PLM_WING_ROWS] = {0};
        for (int i = 0; i < n; ++i) {
            int row = 0;
            const char *file = NULL;
            parse_row(a->rows.items[i], &row, &file);
            rows[row] = &sp[i];
        }
        plm_wing_params w = {.span = a->span, .chord = a->chord, .sweep = plm_radians(a->sweep_deg),
                             .fold = a->fold, .variants = a->variants, .seed = (uint64_t)a->seed};
        return plm_layout_wing(&w, rows, out, err);
    }
    plm_layout_species list[16];
    for (int i = 0; i < n; ++i)
        list[i] = (plm_layout_species){&sp[i], 1.0};
    if (a->kind == KIND_BALL) {
        plm_ball_params b = {.count = a->count, .radius = a->radius, .feather_length = a->length,
                             .variants = a->variants, .seed = (uint64_t)a->seed};
        return plm_layout_ball(&b, list, n, out, err);
    }
    plm_pelt_params p = {.count = a->count, .density = a->density, .overlap = a->overlap,
                         .feather_length = a->length, .elevation = plm_radians(a->elevation_deg),
                         .variants = a->variants, .axis = v3(a->axis[0], a->axis[1], a->axis[2]),
                         .seed = (uint64_t)a->seed, .head_size = a->head_size, .edge_size = a->edge_size,
                         .edge_width = a->edge_width};
    p.surface.width = a->width;
    p.surface.height = a->height;
    p.surface.radius = a->radius;
    if (!strcmp(a->surface, "plane")) {
        p.surface.kind = PLM_SURFACE_PLANE;
    } else if (!strcmp(a->surface, "sphere")) {
        p.surface.kind = PLM_SURFACE_SPHERE;
    } else {
        plm_result rc = plm_mesh_read(a->surface, mesh, err);
        if (rc != PLM_OK)
            return rc;
        p.surface.kind = PLM_SURFACE_MESH;
        p.surface.mesh = mesh;
    }
    return plm_layout_pelt(&p, list, n, out, err);
}

int probe_layout(int argc, char **argv)
{
    layout_args a = {.surface = "plane"};
    plm_option opts[] = {
        {"--kind", PLM_OPT_CHOICE, &a.kind, 1, 0, 0, kinds, "K", "pelt (default), ball or wing", 0},
        {"--species", PLM_OPT_LIST, &a.species, 1, 0, 0, NULL, "FILE",
         "pelt and ball: a species preset (repeat to mix species equally)", 0},
        {"--row", PLM_OPT_LIST, &a.rows, 1, 0, 0, NULL, "ROW=FILE",
         "wing: a row's species (primary and secondary required; the others default to the secondary's)", 0},
        {"--surface", PLM_OPT_STRING, &a.surface, 1, 0, 0, NULL, "S", "pelt: plane (default), sphere or a PLY/OBJ mesh", 0},
        {"--count", PLM_OPT_INT, &a.count, 1, 0, 10000000, NULL, "N", "feathers; default density x area (pelt), 496 (ball)", 0},
        {"--density", PLM_OPT_DOUBLE, &a.density, 1, 0, 1e12, NULL, "D", "pelt: feathers per square unit", 0},
        {"--overlap", PLM_OPT_DOUBLE, &a.overlap, 1, 0, 0.94, NULL, "F", "pelt: fraction of a feather covered by those behind; default 2/3", 0},
        {"--feather-length", PLM_OPT_DOUBLE, &a.length, 1, 0, 1e9, NULL, "L", "layout units; default from the spacing (pelt), 2 radius (ball)", 0},
        {"--elevation", PLM_OPT_DOUBLE, &a.elevation_deg, 1, 0, 89, NULL, "DEG", "pelt: angle to the surface; default 8", 0},
        {"--axis", PLM_OPT_DOUBLES, a.axis, 3, -1e9, 1e9, NULL, "X,Y,Z", "pelt: flow axis; default 0,-1,0", 0},
        {"--head-size", PLM_OPT_DOUBLE, &a.head_size, 1, 0, 1, NULL, "S",
         "pelt: size at the head end of the flow; default 0.6", 0},
        {"--edge-size", PLM_OPT_DOUBLE, &a.edge_size, 1, 0, 1, NULL, "S",
         "pelt: size at the surface's edges; default 0.6", 0},
        {"--edge-width", PLM_OPT_DOUBLE, &a.edge_width, 1, 0, 1e9, NULL, "W",
         "pelt: how far from an edge feathers shrink; default a feather's length", 0},
        {"--width", PLM_OPT_DOUBLE, &a.width, 1, 0, 1e9, NULL, "W", "plane width; default 1", 0},
        {"--height", PLM_OPT_DOUBLE, &a.height, 1, 0, 1e9, NULL, "H", "plane height; default 1", 0},
        {"--radius", PLM_OPT_DOUBLE, &a.radius, 1, 0, 1e9, NULL, "R", "sphere or ball radius; default 1", 0},
        {"--span", PLM_OPT_DOUBLE, &a.span, 1, 0, 1e9, NULL, "S", "wing: span; default 1", 0},
        {"--chord", PLM_OPT_DOUBLE, &a.chord, 1, 0, 1e9, NULL, "C", "wing: secondaries' length; default 0.3 span", 0},
        {"--sweep", PLM_OPT_DOUBLE, &a.sweep_deg, 1, 0, 45, NULL, "DEG", "wing: sweep of the hand; default 0", 0},
        {"--fold", PLM_OPT_DOUBLE, &a.fold, 1, 0, 1, NULL, "F", "wing: 0 spread .. 1 folded; default 0", 0},
        {"--variants", PLM_OPT_INT, &a.variants, 1, 0, 64, NULL, "N", "distinct prototypes per species; default 4 (wing 3)", 0},
        {"--seed", PLM_OPT_INT, &a.seed, 1, 0, 2147483647, NULL, "N", "random seed; default 0", 0},
    };
    /* The ranges are the scene file's layout tables, so a value is refused the same way in both. */
    static const struct { const char *option; const plm_param_block *block; const char *field; } from_table[] = {
        {"--count", &plm_pelt_param_block, "count"},
        {"--density", &plm_pelt_param_block, "density"},
        {"--overlap", &plm_pelt_param_block, "overlap"},
        {"--feather-length", &plm_pelt_param_block, "feather_length"},
        {"--elevation", &plm_pelt_param_block, "elevation"},
        {"--head-size", &plm_pelt_param_block, "head_size"},
        {"--edge-size", &plm_pelt_param_block, "edge_size"},
        {"--edge-width", &plm_pelt_param_block, "edge_width"},
        {"--variants", &plm_pelt_param_block, "variants"},
        {"--seed", &plm_pelt_param_block, "seed"},
        {"--span", &plm_wing_param_block, "span"},
        {"--chord", &plm_wing_param_block, "chord"},
        {"--sweep", &plm_wing_param_block, "sweep"},
        {"--fold", &plm_wing_param_block, "fold"}};
    int n_opts = (int)(sizeof opts / sizeof opts[0]);
    for (size_t i = 0; i < sizeof from_table / sizeof from_table[0]; ++i)
        for (int k = 0; k < n_opts; ++k)
            if (!strcmp(opts[k].name, from_table[i].option))
                plm_option_range_from(&opts[k], from_table[i].block, from_table[i].field);
    const plm_command_help help = {
        "plumage probe layout [options]",
        "Runs a layout (pelt over a plane, a sphere or a mesh; feather ball; wing) and prints one CSV row per "
        "placed feather: its prototype (species index and variant), wing row and dorsal order, variation (scale, "
        "yaw, lift, tint) and the 3x4 matrix from the feather frame (mm) to layout space. docs/layouts.md "
        "explains the parameters.\n"
        "Columns: instance (0-based), prototype (the distinct feather it shows: species x variant), species (index "
        "in the --species or --row order), variant, row (wing: primary 0, secondary 1, tertial 2, greater_covert 3, "
        "median_covert 4, lesser_covert 5, alula 6, primary_covert 7, marginal_covert 8, under_covert 9; pelt and "
        "ball: -1), order (which lies over which: a feather "
        "covers every feather of smaller order it touches), scale, yaw_deg, lift_deg, tint_r/g/b, and m00..m23, the "
        "matrix's rows (m<row><column>; column 3 is where the calamus base lies). The feather frame: rachis along +y from the "
        "calamus at the origin, dorsal side +z. A wing is a right wing: shoulder at the origin, span along +x, "
        "leading edge toward +y, its top (dorsal) side toward +z; a camera at negative z sees it from below, where the "
        "under-wing coverts (row 9) lie with their dorsal side down.\n"
        "  plumage probe layout --species presets/species/covert_parrot.json --count 200 | head -3"};
    int rc = plm_parse_options(&help, argc, argv, 1, opts, n_opts, NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    const plm_opt_list *files = a.kind == KIND_WING ? &a.rows : &a.species;
    if (files->count < 1 || files->count > 16) {
        fprintf(stderr, "error: probe layout: give 1 to 16 %s\n", a.kind == KIND_WING ? "--row ROW=FILE" : "--species FILE");
        return 2;
    }
    plm_species sp[16];
    int loaded = 0, status = 0;
    plm_error err = {{0}};
    for (; loaded < files->count && !status; ++loaded) {
        int row = 0;
        const char *file = files->items[loaded];
        if (a.kind == KIND_WING && !parse_row(files->items[loaded], &row, &file))
            status = 2;
        else if (plm_species_load(file, &sp[loaded], &err) != PLM_OK) {
            fprintf(stderr, "error: %s\n", err.message);
            status = 2;
        }
    }
    if (status)
        --loaded;
    plm_mesh mesh = {0};
    plm_layout l = {0};
    if (!status && run_layout(&a, sp, loaded, &mesh, &l, &err) != PLM_OK) {
        fprintf(stderr, "error: probe layout: %s\n", err.message);
        status = 2;
    }
    if (!status)
        print_csv(&l);
    plm_layout_free(&l);
    plm_mesh_free(&mesh);
    for (int i = 0; i < loaded; ++i)
        plm_species_free(&sp[i]);
    return status;
}
