/* plumage probe bcsdf: lat-long reflectance plots of the fiber BCSDF (the
 * paper's Fig. 7 style), their values as CSV, and the directional albedo.
 *
 * The pixel value is the mean over --sets lobe sets of eval(wi) cos^2(theta_i)
 * = sum_k A_k G_M G_N at the pixel centre: reflectance per unit dtheta dphi,
 * so the plot's integral over its (theta, phi) rectangle is the albedo
 * (eval cos dw = eval cos^2 dtheta dphi).
 * The printed albedo is the mean over the same sets of sum_k A_k, which is
 * each set's exact integral. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/fiber_cli.h"
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

static int write_csv(const char *path, const latlong *ll)
{
    plm_atomic_file f;
    plm_error err;
    if (plm_atomic_open(&f, path, &err) != PLM_OK) {
        fprintf(stderr, "error: plumage probe bcsdf: %s\n", err.message);
        return 0;
    }
    fprintf(f.fp, "theta_deg,phi_deg,value_r,value_g,value_b\n");
    for (int y = 0; y < ll->height; ++y)
        for (int x = 0; x < ll->width; ++x) {
            const float *v = ll->values + 3 * (y * ll->width + x);
            fprintf(f.fp, "%.6g,%.6g,%.9g,%.9g,%.9g\n", 90.0 - 180.0 * (y + 0.5) / ll->height,
                    -180.0 + 360.0 * (x + 0.5) / ll->width, v[0], v[1], v[2]);
        }
    if (plm_atomic_commit(&f, &err) != PLM_OK) {
        fprintf(stderr, "error: plumage probe bcsdf: %s\n", err.message);
        return 0;
    }
    return 1;
}

/* Tiles the plots into a grid (cols wide) with white gaps, scaled so the
 * brightest value of all is 1, and writes an sRGB PNG. */
static int write_sheet(const char *path, const latlong *plots, int n, int cols)
{
    const int gap = 4;
    int w = plots[0].width, h = plots[0].height, rows = (n + cols - 1) / cols;
    int sw = cols * w + (cols - 1) * gap, sh = rows * h + (rows - 1) * gap;
    float *img = malloc((size_t)sw * (size_t)sh * 3 * sizeof(float));
    if (!img) {
        fprintf(stderr, "error: plumage probe bcsdf: out of memory for the picture\n");
        return 0;
    }
    double peak = 0.0;
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < w * h * 3; ++i)
            peak = fmax(peak, plots[k].values[i]);
    for (size_t i = 0; i < (size_t)sw * (size_t)sh * 3; ++i)
        img[i] = 1.0f;
    for (int k = 0; k < n; ++k) {
        int ox = (k % cols) * (w + gap), oy = (k / cols) * (h + gap);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c)
                    img[3 * ((size_t)(oy + y) * sw + ox + x) + c] =
                        peak > 0.0 ? (float)(plots[k].values[3 * (y * w + x) + c] / peak) : 0.0f;
    }
    plm_error err;
    plm_result r = plm_image_write_srgb_png(path, sw, sh, img, 0.0, &err);
    free(img);
    if (r != PLM_OK) {
        fprintf(stderr, "error: plumage probe bcsdf: %s\n", err.message);
        return 0;
    }
    return 1;
}

static char *join(char *buf, size_t size, const char *dir, const char *name, const char *ext)
{
    snprintf(buf, size, "%s/%s.%s", dir, name, ext);
    return buf;
}

int probe_bcsdf(int argc, char **argv)
{
    static const plm_command_help help = {
        "plumage probe bcsdf [fiber options] [--theta DEG] [--phi DEG] --out DIR\n"
        "       plumage probe bcsdf --figure7 --out DIR",
        "Lat-long reflectance plot of the fiber BCSDF for light traced from the direction (--theta,\n"
        "--phi) (the view side; the plot is over the other direction: phi from -180 at the left to 180,\n"
        "theta from 90 at the top to -90). Pixel value: the mean over --sets lobe sets of\n"
        "eval(wi) cos^2(theta_i), reflectance per unit dtheta dphi, so the plot integrates to the albedo.\n"
        "Writes DIR/bcsdf.png (RGB, sRGB, scaled so the brightest value is white) and DIR/bcsdf.csv\n"
        "(theta_deg,phi_deg,value_r,value_g,value_b), and prints the directional albedo per channel.\n"
        "--figure7 instead renders the paper's Fig. 7 fibers at theta 45, phi 0 (circular; elliptical\n"
        "e = 1.6; concentric medulla r = 0.6; medulla at (-0.1, 0.1)) into the contact sheet\n"
        "DIR/figure7.png (2 x 2 in that order, one brightness scale) and DIR/figure7_<name>.csv."};
    plm_fiber_cli fc;
    enum { N_EXTRA = 7 };
    plm_option opts[PLM_FIBER_CLI_OPTIONS + N_EXTRA];
    plm_fiber_cli_options(&fc, opts, PLM_FIBER_SET_MAX_LOBES);
    double theta = 45.0, phi = 0.0;
    int sets = 4000, width = 360, seed = 1, figure7 = 0;
    const char *out_dir = NULL;
    const plm_option extra[N_EXTRA] = {
        {"--theta", PLM_OPT_DOUBLE, &theta, 1, -89.9, 89.9, NULL, "DEG", "theta of the traced direction; default 45", 0},
        {"--phi", PLM_OPT_DOUBLE, &phi, 1, -360, 360, NULL, "DEG", "phi of the traced direction; default 0", 0},
        {"--sets", PLM_OPT_INT, &sets, 1, 1, 1000000, NULL, "N", "lobe sets averaged per plot; default 4000", 0},
        {"--width", PLM_OPT_INT, &width, 1, 8, 4096, NULL, "W", "plot width in pixels (height W/2); default 360", 0},
        {"--seed", PLM_OPT_INT, &seed, 1, 0, 2147483647, NULL, "N", "random seed; default 1", 0},
        {"--figure7", PLM_OPT_FLAG, &figure7, 0, 0, 0, NULL, NULL, "render the four Fig. 7 fibers (fiber options unused)", 0},
        {"--out", PLM_OPT_STRING, &out_dir, 0, 0, 0, NULL, "DIR", "output directory (created); required", 0},
    };
    memcpy(opts + PLM_FIBER_CLI_OPTIONS, extra, sizeof extra);
    int rc = plm_parse_options(&help, argc, argv, 1, opts, PLM_FIBER_CLI_OPTIONS + N_EXTRA, NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    if (!out_dir) {
        fprintf(stderr, "error: plumage probe bcsdf: --out DIR is required\n");
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
    plm_error err;
    if (plm_make_dirs(out_dir, &err) != PLM_OK) {
        fprintf(stderr, "error: plumage probe bcsdf: --out: %s\n", err.message);
        return 2;
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
    char path[4200], name[64];
    for (int k = 0; k < n && ok; ++k) {
        snprintf(name, sizeof name, figure7 ? "figure7_%s" : "bcsdf", plm_fiber_figure7_names[k]);
        ok = write_csv(join(path, sizeof path, out_dir, name, "csv"), &plots[k]);
    }
    if (ok)
        ok = write_sheet(join(path, sizeof path, out_dir, figure7 ? "figure7" : "bcsdf", "png"), plots, n,
                         figure7 ? 2 : 1);
    if (ok) {
        printf("fiber,albedo_r,albedo_g,albedo_b\n");
        for (int k = 0; k < n; ++k)
            printf("%s,%.6f,%.6f,%.6f\n", figure7 ? plm_fiber_figure7_names[k] : "bcsdf", plots[k].albedo.r, plots[k].albedo.g,
                   plots[k].albedo.b);
    }
    for (int k = 0; k < n; ++k)
        free(plots[k].values);
    return ok ? 0 : 1;
}
