/* plumage probe masking: the analytic barb/barbule masking (docs/masking.md), its
 * two levels on their own, the explicit-geometry Monte Carlo reference, and
 * Fig. 9-style pictures comparing the two. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/figure.h"
#include "cli/options.h"
#include "cli/outputs.h"
#include "common/image_io.h"
#include "common/progress.h"
#include "optics/masking.h"
#include "render/masking_reference.h"

static const char *const level_names[] = {"full", "barbule", "barb", NULL};
enum { LEVEL_FULL, LEVEL_BARBULE, LEVEL_BARB };
static const char *const reference_names[] = {"none", "monte-carlo", NULL};

enum {
    OPT_BARB_E, OPT_BARBULE_E, OPT_LENGTH, OPT_SEPARATION, OPT_ROTATION, OPT_INCLINATION,
    OPT_T_PROXIMAL, OPT_T_DISTAL, OPT_LEVEL, OPT_REFERENCE, OPT_SAMPLES, OPT_SEED,
    OPT_FIGURE, OPT_FIGURE9, OPT_OUTPUT, OPT_WIDTH, OPT_COUNT
};

typedef struct probe_args {
    double barb_e, barbule_e, length, separation, rotation_deg, inclination_deg;
    double t_proximal, t_distal;
    int level, reference, samples, seed, width, figure, figure9;
    const char *output;
} probe_args;

/* Which options each mode accepts (docs/masking.md lists them per level). */
static int option_allowed(int opt, const probe_args *a)
{
    int picture = a->figure || a->figure9;
    switch (opt) {
    case OPT_BARB_E: return a->level != LEVEL_BARBULE && !a->figure9;
    case OPT_BARBULE_E: case OPT_SEPARATION: return a->level != LEVEL_BARB && !a->figure9;
    case OPT_LENGTH: case OPT_INCLINATION: return a->level != LEVEL_BARBULE && !a->figure9;
    case OPT_ROTATION: return a->level == LEVEL_FULL && !a->figure9;
    case OPT_T_PROXIMAL: case OPT_T_DISTAL: return a->level == LEVEL_BARB;
    case OPT_REFERENCE: return a->level == LEVEL_FULL && !picture;
    case OPT_SAMPLES: case OPT_SEED: return a->reference || picture;
    case OPT_WIDTH: case OPT_OUTPUT: return picture;
    case OPT_FIGURE: case OPT_FIGURE9: return a->level == LEVEL_FULL && !(a->figure && a->figure9);
    default: return 1;
    }
}

static void print_range_list(FILE *out, const plm_h_range *r, int n)
{
    for (int i = 0; i < n; ++i)
        fprintf(out, "%s%.9g:%.9g:%.9g", i ? "|" : "", r[i].hmin, r[i].hmax, r[i].rate);
}

static void print_full(FILE *out, const double in[3], const plm_masking *m)
{
    fprintf(out, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,", in[0], in[1], in[2], m->w_barb,
            m->w_proximal, m->w_distal, m->w_transmission, m->proximal.hmin, m->proximal.hmax, m->distal.hmin,
            m->distal.hmax);
    print_range_list(out, m->barb, m->barb_range_count);
    fprintf(out, "\n");
}

/* A view direction given on stdin must have a direction. */
static int nonzero(const double *v, int n, const char *cmd, long line)
{
    for (int i = 0; i < n; ++i)
        if (v[i] != 0.0)
            return 1;
    fprintf(stderr, "error: %s: stdin line %ld: the direction is the zero vector\n", cmd, line);
    return 0;
}

/* Answers every line of stdin into out; returns 0, or 1 after a message. */
static int answer_lines(FILE *out, const probe_args *a, const plm_masking_params *p, plm_masking_reference *ref)
{
    const char *cmd = "plumage probe masking";
    int n = a->level == LEVEL_FULL ? 3 : 2;
    if (a->level == LEVEL_FULL)
        fprintf(out, "x,y,z,w_barb,w_proximal,w_distal,w_transmission,proximal_hmin,proximal_hmax,distal_hmin,"
                     "distal_hmax,barb_ranges\n");
    else if (a->level == LEVEL_BARBULE)
        fprintf(out, "dx,dy,transmittance,hmin,hmax\n");
    else
        fprintf(out, "dx,dy,w_barb,w_proximal,w_distal,w_transmission,barb_ranges\n");
    long line = 0;
    double v[3];
    int got;
    while ((got = plm_read_numbers(stdin, cmd, &line, v, n)) == 1) {
        if (!nonzero(v, n, cmd, line))
            return 1;
        if (a->level == LEVEL_BARBULE) {
            plm_barbule_masking m;
            plm_masking_barbule(p->barbule_eccentricity, p->barbule_separation, v2(v[0], v[1]), &m);
            fprintf(out, "%.9g,%.9g,%.9g,%.9g,%.9g\n", v[0], v[1], m.transmittance, m.hmin, m.hmax);
        } else if (a->level == LEVEL_BARB) {
            plm_barb_masking m;
            plm_masking_barb(p->barb_eccentricity, p->barbule_length, p->barbule_inclination, a->t_proximal,
                             a->t_distal, v2(v[0], v[1]), &m);
            fprintf(out, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,", v[0], v[1], m.w_barb, m.w_proximal, m.w_distal,
                    m.w_transmission);
            print_range_list(out, m.barb, m.barb_range_count);
            fprintf(out, "\n");
        } else {
            plm_masking m;
            if (ref) {
                plm_error err;
                if (plm_masking_reference_eval(ref, v3(v[0], v[1], v[2]), (unsigned)a->samples, (uint64_t)a->seed, &m,
                                               &err) != PLM_OK) {
                    fprintf(stderr, "error: %s: stdin line %ld: %s\n", cmd, line, err.message);
                    return 1;
                }
            } else {
                plm_masking_eval(p, v3(v[0], v[1], v[2]), &m);
            }
            print_full(out, v, &m);
        }
    }
    return got < 0 ? 1 : 0;
}

/* The CSV is held in memory and written only once every line has been
 * answered, so bad input leaves no partial output. */
static int run_stdin(const probe_args *a, const plm_masking_params *p, plm_masking_reference *ref)
{
    char *text = NULL;
    size_t size = 0;
    FILE *out = open_memstream(&text, &size);
    if (!out) {
        fprintf(stderr, "error: plumage probe masking: out of memory\n");
        return 1;
    }
    int status = answer_lines(out, a, p, ref);
    fclose(out);
    if (status == 0 && fwrite(text, 1, size, stdout) != size)
        status = 1;
    free(text);
    return status;
}

/* ---------------------------------------------------------------- pictures */

/* Fig. 9 of the paper, labelled: the weights of barb, proximal and distal
 * barbules as blue, green and red (black where light passes) over the view's
 * azimuth (horizontal, 0 to 360 degrees from b toward t) and its angle from n
 * (vertical, 0 at the top to 180 at the bottom: the lower half shows views
 * from below the vane). Each parameter set is one row: the analytic masking
 * left, rays against explicit 3D geometry right. Sizes are pixels. */
enum {
    FONT = PLM_FIGURE_FONT,
    LEFT = 46, GAP = 30, RIGHT = 16, MIN_WIDTH = 600, /* panels' margins; the labels need MIN_WIDTH */
    TITLE_H = 52, SET_H = 24, TICKS_H = 22, FOOT_H = 92
};

static const float *const ink = plm_figure_ink;

/* Ticks every 90 degrees of azimuth below the panel at (x0, y0), and every
 * 45 degrees of polar angle to its left (the left panel's only). */
static plm_result panel_axes(plm_image *img, int x0, int y0, int w, int h, int polar_labels, plm_error *err)
{
    static const char *const azimuth[] = {"0", "90", "180", "270", "360"};
    static const char *const polar[] = {"0", "45", "90", "135", "180"};
    return plm_figure_axes(img, x0, y0, w, h, azimuth, 5, polar, polar_labels ? 5 : 0, err);
}

/* Title, column headings, each set's parameters, the axes and the legend. */
static plm_result figure_labels(plm_image *img, const plm_masking_params *sets, int n_sets, int width, int height,
                                int samples, plm_error *err)
{
    char line[256];
    int right_x = LEFT + width + GAP;
    plm_result rc = plm_image_draw_text(img, LEFT, 20, FONT + 2, "Masking weights over the view direction", ink, err);
    if (rc == PLM_OK)
        rc = plm_image_draw_text(img, LEFT, TITLE_H - 10, FONT, "analytic", ink, err);
    if (rc == PLM_OK)
        rc = plm_image_draw_text(img, right_x, TITLE_H - 10, FONT, "rays, explicit 3D geometry", ink, err);
    for (int k = 0; k < n_sets && rc == PLM_OK; ++k) {
        const plm_masking_params *p = &sets[k];
        int y0 = TITLE_H + k * (SET_H + height + TICKS_H);
        int n = n_sets > 1 ? snprintf(line, sizeof line, "set %d:  ", k + 1) : 0;
        snprintf(line + n, sizeof line - (size_t)n, "e_b %g,  e_bb %g,  l_bb %g,  delta_bb %g,  phi_bb %g deg,  theta_bb %g deg",
                 p->barb_eccentricity, p->barbule_eccentricity, p->barbule_length, p->barbule_separation,
                 plm_degrees(p->barbule_rotation), plm_degrees(p->barbule_inclination));
        rc = plm_image_draw_text(img, LEFT, y0 + SET_H - 7, FONT, line, ink, err);
        for (int side = 0; side < 2 && rc == PLM_OK; ++side)
            rc = panel_axes(img, side ? right_x : LEFT, y0 + SET_H, width, height, side == 0, err);
    }
    int foot = TITLE_H + n_sets * (SET_H + height + TICKS_H);
    snprintf(line, sizeof line, "horizontal: view azimuth in degrees from b (0) toward t (90);  %d rays per view", samples);
    if (rc == PLM_OK)
        rc = plm_image_draw_text(img, LEFT, foot + 16, FONT, line, ink, err);
    if (rc == PLM_OK)
        rc = plm_image_draw_text(img, LEFT, foot + 34, FONT,
                                 "vertical: view angle in degrees from n (0, above the vane) to -n (180, below)", ink, err);
    /* The legend: the weights are added as colours; black is what passes. */
    static const float colors[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 0}};
    static const char *const names[4] = {"distal barbules", "proximal barbules", "barb", "transmission"};
    if (rc == PLM_OK)
        rc = plm_figure_legend(img, LEFT, foot + 52, colors, names, 4, err);
    return rc;
}

/* Fills one set's two panels at (x0, y0) and (x1, y0): analytic and rays. */
static int figure_panels(plm_image *img, const plm_masking_params *p, int x0, int x1, int y0, int width, int height,
                         int samples, uint64_t seed, int set, int n_sets, plm_progress *progress)
{
    plm_error err;
    plm_masking_reference *ref = NULL;
    if (plm_masking_reference_create(p, NULL, &ref, &err) != PLM_OK) {
        fprintf(stderr, "error: plumage probe masking: %s\n", err.message);
        return 1;
    }
    int status = 0;
    for (int row = 0; row < height && status == 0; ++row) {
        double polar = PLM_PI * (row + 0.5) / height;
        for (int col = 0; col < width; ++col) {
            double azimuth = PLM_TWO_PI * (col + 0.5) / width;
            vec3 wo = v3(sin(polar) * cos(azimuth), cos(polar), sin(polar) * sin(azimuth));
            plm_masking m[2];
            plm_masking_eval(p, wo, &m[0]);
            if (plm_masking_reference_eval(ref, wo, (unsigned)samples, seed + (uint64_t)(row * width + col), &m[1],
                                           &err) != PLM_OK) {
                fprintf(stderr, "error: plumage probe masking: %s\n", err.message);
                status = 1;
                break;
            }
            for (int side = 0; side < 2; ++side) {
                float c[3] = {(float)m[side].w_distal, (float)m[side].w_proximal, (float)m[side].w_barb};
                plm_figure_fill(img, (side ? x1 : x0) + col, y0 + row, 1, 1, c);
            }
        }
        char detail[64];
        snprintf(detail, sizeof detail, "parameter set %d of %d", set + 1, n_sets);
        plm_progress_update(progress, (set * height + row + 1.0) / (n_sets * height), detail);
    }
    plm_masking_reference_destroy(ref);
    return status;
}

static int write_figure(const char *path, const plm_masking_params *sets, int n_sets, int width, int samples,
                        uint64_t seed)
{
    int height = width / 2;
    int img_w = LEFT + 2 * width + GAP + RIGHT;
    img_w = img_w < MIN_WIDTH ? MIN_WIDTH : img_w;
    int img_h = TITLE_H + n_sets * (SET_H + height + TICKS_H) + FOOT_H;
    plm_image img = plm_figure_page(img_w, img_h);
    if (!img.pixels)
        return 1;
    int status = 0;
    plm_progress progress;
    plm_progress_start(&progress, "figure");
    for (int k = 0; k < n_sets && status == 0; ++k)
        status = figure_panels(&img, &sets[k], LEFT, LEFT + width + GAP, TITLE_H + k * (SET_H + height + TICKS_H) + SET_H,
                               width, height, samples, seed, k, n_sets, &progress);
    if (status == 0)
        plm_progress_finish(&progress, 1.0, NULL);
    plm_error err;
    if (status == 0 && (figure_labels(&img, sets, n_sets, width, height, samples, &err) != PLM_OK ||
                        plm_image_write_srgb_png(path, img_w, img_h, img.pixels, 0.0, &err) != PLM_OK)) {
        fprintf(stderr, "error: plumage probe masking: %s\n", err.message);
        status = 1;
    }
    free(img.pixels);
    return status;
}

/* The two parameter sets of the paper's Fig. 9. */
static int write_figure9(const char *path, int width, int samples, uint64_t seed)
{
    plm_masking_params sets[2];
    for (int k = 0; k < 2; ++k) {
        plm_masking_params_default(&sets[k]);
        sets[k].barbule_eccentricity = 1.0;
        sets[k].barbule_separation = 1.0;
    }
    sets[0].barb_eccentricity = 3.0;
    sets[0].barbule_length = 1.0;
    sets[0].barbule_inclination = 0.0;
    sets[1].barb_eccentricity = 1.0;
    sets[1].barbule_length = 3.0;
    sets[1].barbule_inclination = plm_radians(45.0);
    return write_figure(path, sets, 2, width, samples, seed);
}

int probe_masking(int argc, char **argv)
{
    probe_args a = {1.0, 1.0, 1.0, 1.0, 45.0, 0.0, 0.0, 0.0, LEVEL_FULL, 0, 4096, 1, 240, 0, 0, NULL};
    plm_option opts[OPT_COUNT] = {
        [OPT_T_PROXIMAL] = {"--proximal-transmittance", PLM_OPT_DOUBLE, &a.t_proximal, 0, 0, 1, NULL, "T",
                            "--level barb: proximal barbule-level transmittance (default 0)", 0},
        [OPT_T_DISTAL] = {"--distal-transmittance", PLM_OPT_DOUBLE, &a.t_distal, 0, 0, 1, NULL, "T",
                          "--level barb: distal barbule-level transmittance (default 0)", 0},
        [OPT_LEVEL] = {"--level", PLM_OPT_CHOICE, &a.level, 0, 0, 0, level_names, "LEVEL",
                       "full (default), barbule (stdin: dx dy) or barb (stdin: dx dy)", 0},
        [OPT_REFERENCE] = {"--reference", PLM_OPT_CHOICE, &a.reference, 0, 0, 0, reference_names, "KIND",
                           "monte-carlo: rays against explicit 3D barbs and barbules instead", 0},
        [OPT_SAMPLES] = {"--samples", PLM_OPT_INT, &a.samples, 0, 16, 1 << 26, NULL, "N",
                         "rays per direction for the Monte Carlo reference (default 4096; 256 for pictures)", 0},
        [OPT_SEED] = {"--seed", PLM_OPT_INT, &a.seed, 0, 0, 2147483647, NULL, "N",
                      "random seed of the Monte Carlo reference (default 1)", 0},
        [OPT_FIGURE] = {"--figure", PLM_OPT_FLAG, &a.figure, 0, 0, 0, NULL, NULL,
                        "a Fig. 9-style picture of these parameters into -o (no stdin)", 0},
        [OPT_FIGURE9] = {"--figure9", PLM_OPT_FLAG, &a.figure9, 0, 0, 0, NULL, NULL,
                         "the paper's Fig. 9, both of its parameter sets, into -o (no stdin)", 0},
        [OPT_OUTPUT] = {"-o", PLM_OPT_STRING, &a.output, 0, 0, 0, NULL, "FILE.png",
                        "with --figure or --figure9: the picture (its folder is created if missing)", 0},
        [OPT_WIDTH] = {"--width", PLM_OPT_INT, &a.width, 0, 8, 4096, NULL, "PIXELS",
                       "width of each picture panel; height is half (default 240)", 0},
    };
    /* The geometry's options are the masking table's fields (optics/masking.h): names, ranges, meanings and
     * units as in scene files. */
    const struct { int option; const char *field; double *target; const char *metavar; } from_table[] = {
        {OPT_BARB_E, "barb_eccentricity", &a.barb_e, "E"},
        {OPT_BARBULE_E, "barbule_eccentricity", &a.barbule_e, "E"},
        {OPT_LENGTH, "barbule_length", &a.length, "L"},
        {OPT_SEPARATION, "barbule_separation", &a.separation, "S"},
        {OPT_ROTATION, "barbule_rotation", &a.rotation_deg, "DEG"},
        {OPT_INCLINATION, "barbule_inclination", &a.inclination_deg, "DEG"}};
    enum { FROM_TABLE = sizeof from_table / sizeof from_table[0] };
    plm_option_text text[FROM_TABLE];
    for (size_t i = 0; i < FROM_TABLE; ++i)
        plm_option_param(&opts[from_table[i].option], &text[i], &plm_masking_param_block, from_table[i].field,
                         from_table[i].target, from_table[i].metavar);
    plm_command_help help = {
        "plumage probe masking [options] < directions",
        "Barb and barbule masking (paper Sec. 6.1) for view directions read from stdin, one per line.\n"
        "full (default): stdin 'x y z' in the barb frame (b, n, t), need not be normalised; stdout\n"
        "  x,y,z,w_barb,w_proximal,w_distal,w_transmission,proximal_hmin,proximal_hmax,distal_hmin,distal_hmax,\n"
        "  barb_ranges (hmin:hmax:rate|...). With --reference monte-carlo the weights are counted from rays\n"
        "  cast at explicit 3D geometry, the h-intervals are the extremes of the hits seen, and barb_ranges is\n"
        "  one range holding w_barb.\n"
        "--level barbule: stdin 'dx dy' in a barbule row's cross-section; stdout dx,dy,transmittance,hmin,hmax.\n"
        "--level barb: stdin 'dx dy' in the barb cross-section; stdout dx,dy,w_barb,w_proximal,w_distal,\n"
        "  w_transmission,barb_ranges.\n"
        "--figure / --figure9 -o FILE.png write a labelled PNG instead (barb, proximal, distal weights as blue,\n"
        "  green, red over view azimuth and polar angle; analytic left, Monte Carlo right)."};
    int rc = plm_parse_options(&help, argc, argv, 1, opts, OPT_COUNT, NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    for (size_t i = 0; i < FROM_TABLE; ++i)
        if (!plm_option_check_open(&opts[from_table[i].option], &plm_masking_param_block, from_table[i].field))
            return 2;
    for (int i = 0; i < OPT_COUNT; ++i)
        if (opts[i].seen && !option_allowed(i, &a)) {
            fprintf(stderr, "error: plumage probe masking: %s does not apply here (--level %s%s%s)\n", opts[i].name,
                    level_names[a.level], a.reference ? ", --reference" : "",
                    a.figure || a.figure9 ? ", picture" : "");
            return 2;
        }

    plm_masking_params p = {a.barb_e, a.barbule_e, a.length, a.separation, plm_radians(a.rotation_deg),
                            plm_radians(a.inclination_deg)};
    plm_error err;
    if (plm_masking_params_validate(&p, &err) != PLM_OK) {
        fprintf(stderr, "error: plumage probe masking: %s\n", err.message);
        return 2;
    }
    if ((a.figure || a.figure9) && !a.output) {
        fprintf(stderr, "error: plumage probe masking: %s needs -o FILE.png\n", a.figure ? "--figure" : "--figure9");
        return 2;
    }
    if ((a.figure || a.figure9) && !opts[OPT_SAMPLES].seen)
        a.samples = 256; /* a picture has many directions; its noise is seen, not measured */
    if (a.figure || a.figure9) {
        plm_outputs outputs = {0};
        if (!plm_outputs_file(&outputs, "-o", a.output))
            return 1;
        int status = a.figure9 ? write_figure9(a.output, a.width, a.samples, (uint64_t)a.seed)
                               : write_figure(a.output, &p, 1, a.width, a.samples, (uint64_t)a.seed);
        if (status)
            plm_outputs_undo(&outputs);
        else
            plm_print_wrote((const char *const[]){a.output}, 1);
        return status;
    }
    plm_masking_reference *ref = NULL;
    if (a.reference && plm_masking_reference_create(&p, NULL, &ref, &err) != PLM_OK) {
        fprintf(stderr, "error: plumage probe masking: %s\n", err.message);
        return 2;
    }
    int status = run_stdin(&a, &p, ref);
    plm_masking_reference_destroy(ref);
    return status;
}
