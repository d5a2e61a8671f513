/* plumage probe bcsdf: lat-long reflectance plots of the fiber BCSDF (the
 * paper's Fig. 7 style), their values as CSV, and the directional albedo.
 *
 * The pixel value is the mean over --sets lobe sets of eval(wi) cos^2(theta_i)
 * = sum_k A_k G_M G_N at the pixel centre: reflectance per unit dtheta dphi,
 * so the plot's integral over its (theta, phi) rectangle is the albedo
 * (eval cos dw = eval cos^2 dtheta dphi).
 * The printed albedo is the mean over the same sets of sum_k A_k, which is
 * each set's exact integral. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/fiber_cli.h"
#include "cli/figure.h"
#include "cli/outputs.h"
#include "common/fileio.h"
#include "common/image_io.h"

typedef struct latlong {
    int width, height;
    float *values; /* height x width x RGB, top row theta = +90 */
    rgb albedo;
} latlong;

/* Accumulates the plot of one fiber seen from wo. Each lobe's detectors are
 * separable, so a lobe costs one row and one column of detector values and
 * an outer product rather than an eval per pixel. */
static int render_latlong(const plm_fiber_params *p, vec3 wo, int sets, uint64_t seed, latlong *out)
{
    int w = out->width, h = out->height;
    double *sum = calloc((size_t)w * (size_t)h * 3, sizeof(double));
    double *gm = malloc((size_t)(w + h) * sizeof(double)), *gn = gm + h;
    out->values = malloc((size_t)w * (size_t)h * 3 * sizeof(float));
    if (!sum || !gm || !out->values) {
        free(sum);
        free(gm);
        fprintf(stderr, "error: plumage probe bcsdf: out of memory for a %d x %d plot\n", w, h);
        return 0;
    }
    plm_rng rng;
    plm_rng_seed(&rng, seed, 0);
    out->albedo = rgb_gray(0.0);
    for (int s = 0; s < sets; ++s) {
        plm_fiber_lobe_set set;
        plm_fiber_prepare(p, wo, -1.0, 1.0, &rng, &set);
        for (int k = 0; k < set.count; ++k) {
            rgb a = rgb_scale(set.throughput[k], 1.0 / sets);
            out->albedo = rgb_add(out->albedo, a);
            for (int y = 0; y < h; ++y)
                gm[y] = plm_fiber_lobe_gm(p, &set, k, 0.5 * PLM_PI - PLM_PI * (y + 0.5) / h);
            for (int x = 0; x < w; ++x)
                gn[x] = plm_fiber_lobe_gn(p, &set, k, -PLM_PI + PLM_TWO_PI * (x + 0.5) / w);
            for (int y = 0; y < h; ++y) {
                if (gm[y] == 0.0)
                    continue;
                double *row = sum + 3 * (size_t)y * w;
                for (int x = 0; x < w; ++x) {
                    double d = gm[y] * gn[x];
                    row[3 * x] += a.r * d;
                    row[3 * x + 1] += a.g * d;
                    row[3 * x + 2] += a.b * d;
                }
            }
        }
    }
    for (int i = 0; i < w * h * 3; ++i)
        out->values[i] = (float)sum[i];
    free(sum);
    free(gm);
    return 1;
}

/* One CSV for all plots: a row per pixel of each, the plot named first. */
static int write_csv(const char *path, const latlong *plots, const char *const *names, int n)
{
    plm_atomic_file f;
    plm_error err;
    if (plm_atomic_open(&f, path, &err) != PLM_OK) {
        fprintf(stderr, "error: plumage probe bcsdf: %s\n", err.message);
        return 0;
    }
    fprintf(f.fp, "fiber,theta_deg,phi_deg,value_r,value_g,value_b\n");
    for (int k = 0; k < n; ++k) {
        const latlong *ll = &plots[k];
        for (int y = 0; y < ll->height; ++y)
            for (int x = 0; x < ll->width; ++x) {
                const float *v = ll->values + 3 * (y * ll->width + x);
                fprintf(f.fp, "%s,%.6g,%.6g,%.9g,%.9g,%.9g\n", names[k], 90.0 - 180.0 * (y + 0.5) / ll->height,
                        -180.0 + 360.0 * (x + 0.5) / ll->width, v[0], v[1], v[2]);
            }
    }
    if (plm_atomic_commit(&f, &err) != PLM_OK) {
        fprintf(stderr, "error: plumage probe bcsdf: %s\n", err.message);
        return 0;
    }
    return 1;
}

/* The picture's layout in pixels: plots in a grid under a title, each under
 * its heading, with ticks below and (first column) to the left; the axes and
 * the brightness scale explained at the foot. */
enum { LEFT = 46, GAP = 44, RIGHT = 16, MIN_WIDTH = 620, TITLE_H = 34, HEAD_H = 38, TICKS_H = 24, FOOT_H = 44 };

/* "circular", "e 1.6, medulla 0.6 x 0.6 at (-0.1, 0.1)": what sets a fiber apart. */
static void describe(const plm_fiber_params *p, char *out, size_t size)
{
    int n = p->eccentricity == 1.0 ? snprintf(out, size, "circular") : snprintf(out, size, "e %g", p->eccentricity);
    if (p->medulla_a > 0.0 && (size_t)n < size)
        n += snprintf(out + n, size - (size_t)n, ", medulla %g x %g", p->medulla_a, p->medulla_b);
    if (p->medulla_a > 0.0 && (p->medulla_ca != 0.0 || p->medulla_cb != 0.0) && (size_t)n < size)
        snprintf(out + n, size - (size_t)n, " at (%g, %g)", p->medulla_ca, p->medulla_cb);
}

static plm_result draw_labels(plm_image *img, const latlong *plots, const plm_fiber_params *params, int n, int cols,
                              double theta, double phi, double peak, int figure7, plm_error *err)
{
    static const char *const phis[] = {"-180", "-90", "0", "90", "180"}, *const thetas[] = {"90", "45", "0", "-45", "-90"};
    const float *ink = plm_figure_ink;
    const int font = PLM_FIGURE_FONT, w = plots[0].width, h = plots[0].height, rows = (n + cols - 1) / cols;
    char line[256], name[128];
    snprintf(line, sizeof line, "Fiber scattering seen from theta %g, phi %g degrees%s", theta, phi,
             figure7 ? " (the paper's Fig. 7)" : "");
    plm_result rc = plm_image_draw_text(img, LEFT, 22, font + 2, line, ink, err);
    for (int k = 0; k < n && rc == PLM_OK; ++k) {
        int x0 = LEFT + (k % cols) * (w + GAP), y0 = TITLE_H + (k / cols) * (HEAD_H + h + TICKS_H);
        describe(&params[k], name, sizeof name);
        snprintf(line, sizeof line, "albedo %.2f %.2f %.2f", plots[k].albedo.r, plots[k].albedo.g, plots[k].albedo.b);
        rc = plm_image_draw_text(img, x0, y0 + HEAD_H - 23, font, name, ink, err);
        if (rc == PLM_OK)
            rc = plm_image_draw_text(img, x0, y0 + HEAD_H - 7, font, line, ink, err);
        if (rc == PLM_OK)
            rc = plm_figure_axes(img, x0, y0 + HEAD_H, w, h, phis, 5, thetas, k % cols == 0 ? 5 : 0, err);
    }
    int foot = TITLE_H + rows * (HEAD_H + h + TICKS_H);
    if (rc == PLM_OK)
        rc = plm_image_draw_text(img, LEFT, foot + 16, font,
                                 "horizontal: outgoing azimuth phi; vertical: outgoing elevation theta (degrees)", ink, err);
    snprintf(line, sizeof line, "brightness: reflectance per unit theta and phi, one scale for all, white = %.3g", peak);
    if (rc == PLM_OK)
        rc = plm_image_draw_text(img, LEFT, foot + 34, font, line, ink, err);
    return rc;
}

/* The plots in a grid (cols wide), scaled so the brightest value of all is
 * white, labelled, as an sRGB PNG. */
static int write_picture(const char *path, const latlong *plots, const plm_fiber_params *params, int n, int cols,
                         double theta, double phi, int figure7)
{
    int w = plots[0].width, h = plots[0].height, rows = (n + cols - 1) / cols;
    int page_w = LEFT + cols * w + (cols - 1) * GAP + RIGHT, page_h = TITLE_H + rows * (HEAD_H + h + TICKS_H) + FOOT_H;
    plm_image img = plm_figure_page(page_w < MIN_WIDTH ? MIN_WIDTH : page_w, page_h);
    if (!img.pixels)
        return 0;
    double peak = 0.0;
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < w * h * 3; ++i)
            peak = fmax(peak, plots[k].values[i]);
    for (int k = 0; k < n; ++k) {
        int ox = LEFT + (k % cols) * (w + GAP), oy = TITLE_H + (k / cols) * (HEAD_H + h + TICKS_H) + HEAD_H;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c)
                    img.pixels[3 * ((size_t)(oy + y) * (size_t)img.width + (size_t)(ox + x)) + c] =
                        peak > 0.0 ? (float)(plots[k].values[3 * (y * w + x) + c] / peak) : 0.0f;
    }
    plm_error err;
    int ok = draw_labels(&img, plots, params, n, cols, theta, phi, peak, figure7, &err) == PLM_OK &&
             plm_image_write_srgb_png(path, img.width, img.height, img.pixels, 0.0, &err) == PLM_OK;
    if (!ok)
        fprintf(stderr, "error: plumage probe bcsdf: %s\n", err.message);
    free(img.pixels);
    return ok;
}

int probe_bcsdf(int argc, char **argv)
{
    static const plm_command_help help = {
        "plumage probe bcsdf [fiber options] [--theta DEG] [--phi DEG] -o FILE.png [--csv FILE.csv]\n"
        "       plumage probe bcsdf --figure7 -o FILE.png [--csv FILE.csv]",
        "Lat-long reflectance plot of the fiber BCSDF for light traced from the direction (--theta,\n"
        "--phi) (the view side; the plot is over the other direction: phi from -180 at the left to 180,\n"
        "theta from 90 at the top to -90). Pixel value: the mean over --sets lobe sets of\n"
        "eval(wi) cos^2(theta_i), reflectance per unit dtheta dphi, so the plot integrates to the albedo.\n"
        "Writes the labelled plot to -o (sRGB PNG, scaled so the brightest value is white; the albedo per\n"
        "channel in its heading) and prints the albedos as CSV on stdout. --csv also writes every plotted value\n"
        "(fiber,theta_deg,phi_deg,value_r,value_g,value_b; about 5 MB per plot at the default width).\n"
        "--figure7 instead renders the paper's Fig. 7 fibers at theta 45, phi 0 (circular; elliptical\n"
        "e = 1.6; concentric medulla r = 0.6; medulla at (-0.1, 0.1)), 2 x 2 in that order on one brightness\n"
        "scale."};
    plm_fiber_cli fc;
    enum { N_EXTRA = 8 };
    plm_option opts[PLM_FIBER_CLI_OPTIONS + N_EXTRA];
    plm_fiber_cli_options(&fc, opts, PLM_FIBER_SET_MAX_LOBES);
    double theta = 45.0, phi = 0.0;
    int sets = 4000, width = 360, seed = 1, figure7 = 0;
    const char *out = NULL, *csv = NULL;
    const plm_option extra[N_EXTRA] = {
        {"--theta", PLM_OPT_DOUBLE, &theta, 1, -89.9, 89.9, NULL, "DEG", "theta of the traced direction; default 45", 0},
        {"--phi", PLM_OPT_DOUBLE, &phi, 1, -360, 360, NULL, "DEG", "phi of the traced direction; default 0", 0},
        {"--sets", PLM_OPT_INT, &sets, 1, 1, 1000000, NULL, "N", "lobe sets averaged per plot; default 4000", 0},
        {"--width", PLM_OPT_INT, &width, 1, 8, 4096, NULL, "W", "plot width in pixels (height W/2); default 360", 0},
        {"--seed", PLM_OPT_INT, &seed, 1, 0, 2147483647, NULL, "N", "random seed; default 1", 0},
        {"--figure7", PLM_OPT_FLAG, &figure7, 0, 0, 0, NULL, NULL, "render the four Fig. 7 fibers (fiber options unused)", 0},
        {"-o", PLM_OPT_STRING, &out, 0, 0, 0, NULL, "FILE.png", "the picture (its folder is created if missing); required",
         0},
        {"--csv", PLM_OPT_STRING, &csv, 0, 0, 0, NULL, "FILE.csv", "also every plotted value, as CSV", 0},
    };
    memcpy(opts + PLM_FIBER_CLI_OPTIONS, extra, sizeof extra);
    int rc = plm_parse_options(&help, argc, argv, 1, opts, PLM_FIBER_CLI_OPTIONS + N_EXTRA, NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    if (!out) {
        fprintf(stderr, "error: plumage probe bcsdf: -o FILE.png is required\n");
        return 2;
    }
    if (width % 2) {
        fprintf(stderr, "error: plumage probe bcsdf: --width %d must be even (height is width / 2)\n", width);
        return 2;
    }
    for (int i = 0; figure7 && i < PLM_FIBER_CLI_OPTIONS + 2; ++i)
        if (opts[i].seen) {
            fprintf(stderr, "error: plumage probe bcsdf: %s cannot be combined with --figure7\n", opts[i].name);
            return 2;
        }
    int n = figure7 ? 4 : 1;
    plm_fiber_params params[4];
    if (figure7) {
        for (int k = 0; k < 4; ++k)
            plm_fiber_params_figure7(&params[k], k);
    } else if (!plm_fiber_cli_params(&fc, "plumage probe bcsdf", &params[0])) {
        return 2;
    }
    plm_outputs outputs = {0};
    if (!plm_outputs_file(&outputs, "-o", out) || (csv && !plm_outputs_file(&outputs, "--csv", csv))) {
        plm_outputs_undo(&outputs);
        return 1;
    }
    latlong plots[4];
    memset(plots, 0, sizeof plots);
    vec3 wo = plm_fiber_direction(plm_radians(theta), plm_radians(phi));
    int ok = 1;
    for (int k = 0; k < n && ok; ++k) {
        plots[k].width = width;
        plots[k].height = width / 2;
        ok = render_latlong(&params[k], wo, sets, (uint64_t)seed, &plots[k]);
    }
    const char *const *names = figure7 ? plm_fiber_figure7_names : (const char *const[]){"bcsdf"};
    ok = ok && write_picture(out, plots, params, n, figure7 ? 2 : 1, theta, phi, figure7);
    ok = ok && (!csv || write_csv(csv, plots, names, n));
    if (ok) {
        printf("fiber,albedo_r,albedo_g,albedo_b\n");
        for (int k = 0; k < n; ++k)
            printf("%s,%.6f,%.6f,%.6f\n", names[k], plots[k].albedo.r, plots[k].albedo.g, plots[k].albedo.b);
        fflush(stdout);
        plm_print_wrote((const char *const[]){out, csv}, 2);
    } else {
        plm_outputs_undo(&outputs);
    }
    for (int k = 0; k < n; ++k)
        free(plots[k].values);
    return ok ? 0 : 1;
}
