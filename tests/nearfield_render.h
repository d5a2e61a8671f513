/* Close-up renders of the pigeon remex for the near-field tests
 * (test_scene_nearfield.c, slow_scene_nearfield.c; docs/nearfield.md): a
 * flat copy of the species (no bends, twist or curl, so the vane lies in
 * z = 0 in its flat coordinates, and no per-barb or tip pigment, so the vane
 * has one colour) under a uniform sky (a sun's glints would add noise and
 * nothing to measure), a camera looking straight down at a vane point, the
 * barbs' expected spatial frequency from the species' own model (the
 * outline's stream function), and the dominant frequency of an image from
 * its 2D discrete Fourier transform. Include after <cmocka.h>; compile
 * with PLUMAGE_SOURCE_DIR. */
#ifndef PLUMAGE_TESTS_NEARFIELD_RENDER_H
#define PLUMAGE_TESTS_NEARFIELD_RENDER_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/fileio.h"
#include "common/json.h"
#include "generate/outline.h"
#include "generate/species.h"
#include "render/render.h"
#include "scene/scene_file.h"

#define CLOSEUP_X 9.0    /* mm: halfway out on the broad (right) vane */
#define CLOSEUP_Y 100.0  /* mm: a little past mid-length */
#define CLOSEUP_HEIGHT 80.0

/* Writes the flat species into dir (which must exist); its path in out. */
static inline void closeup_write_species(const char *dir, char *out, size_t n)
{
    char src[1024], *text = NULL;
    plm_error err = {{0}};
    snprintf(src, sizeof src, "%s/presets/species/remex_pigeon.json", PLUMAGE_SOURCE_DIR);
    assert_int_equal(plm_read_text_file(src, &text, &err), PLM_OK);
    cJSON *root = cJSON_Parse(text);
    free(text);
    assert_non_null(root);
    cJSON *shape = cJSON_GetObjectItem(root, "shape"), *rachis = cJSON_GetObjectItem(shape, "rachis");
    const char *flat[] = {"bend_in_plane", "bend_out_of_plane", "twist"};
    for (int i = 0; i < 3; ++i)
        cJSON_ReplaceItemInObject(rachis, flat[i], cJSON_CreateNumber(0));
    cJSON_ReplaceItemInObject(cJSON_GetObjectItem(shape, "vane"), "curl", cJSON_CreateNumber(0));
    cJSON *pigment = cJSON_GetObjectItem(root, "pigment");
    cJSON_ReplaceItemInObject(pigment, "barb_jitter", cJSON_CreateNumber(0));
    cJSON_ReplaceItemInObject(pigment, "tip_length", cJSON_CreateNumber(0));
    char *json = cJSON_Print(root);
    cJSON_Delete(root);
    snprintf(out, n, "%s/remex_flat.json", dir);
    assert_int_equal(plm_write_file(out, json, strlen(json), &err), PLM_OK);
    free(json);
}

/* The scene: the flat remex, a camera CLOSEUP_HEIGHT above (x, y) with the
 * field of view that makes a pixel `pixel_mm` wide, the sky. */
static inline void closeup_load(const char *species, int width, int height, int spp, double pixel_mm,
                                int far_field, plm_scene *scene)
{
    double fov = 2.0 * atan(0.5 * pixel_mm * height / CLOSEUP_HEIGHT) * 180.0 / PLM_PI;
    char json[4096];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [%g, %g, %g], \"look_at\": [%g, %g, 0], \"up\": [0, 1, 0], \"fov\": %.9g},"
             " \"film\": {\"width\": %d, \"height\": %d, \"spp\": %d, \"max_depth\": 8, \"far_field\": %s},"
             " \"lights\": [{\"type\": \"environment\", \"radiance\": [0.35, 0.4, 0.48]}],"
             " \"feathers\": {\"remex\": {\"species\": \"%s\", \"texture_size\": 2048}},"
             " \"objects\": [{\"feather\": \"remex\"}]}",
             CLOSEUP_X, CLOSEUP_Y, CLOSEUP_HEIGHT, CLOSEUP_X, CLOSEUP_Y, fov, width, height, spp,
             far_field ? "true" : "false", species);
    plm_error err = {{0}};
    plm_result rc = plm_scene_load_buffer(json, strlen(json), "closeup.json", scene, &err);
    if (rc != PLM_OK)
        fprintf(stderr, "%s\n", err.message);
    assert_int_equal(rc, PLM_OK);
}

/* Renders the scene `count` times with seeds 1 to count (seed 1 is the
 * scene's own) and spp / count samples each: independent replicates, whose
 * spread gives a mean's Monte Carlo error. The pixel size from the centre
 * ray's hit distance (the vane may not lie exactly at z = 0). */
static inline void closeup_render(const plm_scene *scene, int count, plm_film *films, double *pixel_mm)
{
    plm_world w;
    plm_error err = {{0}};
    assert_int_equal(plm_world_build(scene, &w, &err), PLM_OK);
    vec3 o, d;
    plm_camera_ray(&w.camera, 0.5 * w.camera.width, 0.5 * w.camera.height, 0.5, 0.5, &o, &d);
    double t;
    plm_hit hit;
    assert_true(plm_world_intersect(&w, o, d, INFINITY, &t, &hit));
    *pixel_mm = t * 2.0 * v3_length(w.camera.up) / w.camera.height;
    assert_int_equal(scene->film.spp % count, 0);
    for (int r = 0; r < count; ++r) {
        plm_render_options opt = {0};
        opt.threads = 2;
        opt.seed = r + 1;
        opt.spp = scene->film.spp / count;
        assert_int_equal(plm_render_world(&w, &opt, &films[r], &err), PLM_OK);
        assert_int_equal(films[r].nonfinite, 0);
    }
    plm_world_free(&w);
}

/* The barbs' spatial frequency at the close-up point in cycles per mm (flat
 * x, y): barbs are the level curves of psi, one every 1 / density along the
 * rachis, so it is density * grad psi. */
static inline vec2 closeup_expected_frequency(const char *species)
{
    plm_species sp;
    plm_outline o;
    plm_error err = {{0}};
    assert_int_equal(plm_species_load(species, &sp, &err), PLM_OK);
    assert_int_equal(plm_outline_init(&o, &sp.shape, species, &err), PLM_OK);
    const double h = 1e-3;
    double gx = (plm_outline_sample(&o, CLOSEUP_X + h, CLOSEUP_Y).barb_origin -
                 plm_outline_sample(&o, CLOSEUP_X - h, CLOSEUP_Y).barb_origin) / (2.0 * h);
    double gy = (plm_outline_sample(&o, CLOSEUP_X, CLOSEUP_Y + h).barb_origin -
                 plm_outline_sample(&o, CLOSEUP_X, CLOSEUP_Y - h).barb_origin) / (2.0 * h);
    double per_mm = sp.shape.barb_density / 10.0;
    plm_species_free(&sp);
    return v2(per_mm * gx, per_mm * gy);
}

/* The strongest frequency of the image's luminance (mean removed, Hann
 * window) in cycles per image, (kx right, ky down), refined by the power-
 * weighted centroid of the 3x3 bins around the peak; *power: the peak's
 * share of the total power. A separable DFT: rows, then columns. */
static inline void dominant_frequency(const float *rgb, int w, int h, double *kx, double *ky, double *power)
{
    double *l = malloc(sizeof(double) * w * h), *re = malloc(sizeof(double) * w * h);
    double *im = malloc(sizeof(double) * w * h), *p = malloc(sizeof(double) * w * h);
    assert_true(l && re && im && p);
    double mean = 0.0;
    for (int i = 0; i < w * h; ++i)
        mean += (l[i] = (rgb[3 * i] + rgb[3 * i + 1] + rgb[3 * i + 2]) / 3.0) / (w * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            l[y * w + x] = (l[y * w + x] - mean) * (0.5 - 0.5 * cos(PLM_TWO_PI * (x + 0.5) / w)) *
                           (0.5 - 0.5 * cos(PLM_TWO_PI * (y + 0.5) / h));
    /* Rows: bin a of a row holds frequency a - w/2. */
    for (int y = 0; y < h; ++y)
        for (int a = 0; a < w; ++a) {
            double sr = 0.0, si = 0.0, f = PLM_TWO_PI * (a - w / 2) / w;
            for (int x = 0; x < w; ++x) {
                sr += l[y * w + x] * cos(f * x);
                si -= l[y * w + x] * sin(f * x);
            }
            re[y * w + a] = sr;
            im[y * w + a] = si;
        }
    double total = 0.0;
    for (int b = 0; b < h; ++b)
        for (int a = 0; a < w; ++a) {
            double sr = 0.0, si = 0.0, f = PLM_TWO_PI * (b - h / 2) / h;
            for (int y = 0; y < h; ++y) {
                double c = cos(f * y), s = -sin(f * y);
                sr += re[y * w + a] * c - im[y * w + a] * s;
                si += re[y * w + a] * s + im[y * w + a] * c;
            }
            total += p[b * w + a] = sr * sr + si * si;
        }
    int best = -1;
    for (int b = 0; b < h; ++b)
        for (int a = 0; a < w; ++a) {
            int fa = a - w / 2, fb = b - h / 2;
            if (fa * fa + fb * fb >= 9 && (best < 0 || p[b * w + a] > p[best]))
                best = b * w + a;
        }
    int a0 = best % w, b0 = best / w;
    double sum = 0.0, sx = 0.0, sy = 0.0;
    for (int db = -1; db <= 1; ++db)
        for (int da = -1; da <= 1; ++da) {
            int a = a0 + da, b = b0 + db;
            if (a < 0 || b < 0 || a >= w || b >= h)
                continue;
            sum += p[b * w + a];
            sx += p[b * w + a] * (a - w / 2);
            sy += p[b * w + a] * (b - h / 2);
        }
    *kx = sx / sum;
    *ky = sy / sum;
    *power = sum / total;
    free(l), free(re), free(im), free(p);
}

/* The mean colour of a film. */
static inline void film_mean_rgb(const plm_film *f, double mean[3])
{
    long n = (long)f->width * f->height;
    for (int c = 0; c < 3; ++c) {
        double s = 0.0;
        for (long i = 0; i < n; ++i)
            s += f->rgb[3 * i + c];
        mean[c] = s / n;
    }
}

/* Renders the close-up at `size` pixels of 0.03 mm with and without the near
 * field and checks the near field's dominant frequency and orientation
 * against the species' barbs (within rel_tol and angle_tol degrees), and
 * that the far field has no such peak. */
static inline void closeup_check_barbs(const char *species, int size, int spp, double rel_tol, double angle_tol)
{
    vec2 g = closeup_expected_frequency(species);
    double peak[2], pixel = 0.0, kx = 0.0, ky = 0.0;
    for (int far = 0; far < 2; ++far) {
        plm_scene scene;
        closeup_load(species, size, size, spp, 0.03, far, &scene);
        plm_film film;
        closeup_render(&scene, 1, &film, &pixel);
        double fx, fy;
        dominant_frequency(film.rgb, size, size, &fx, &fy, &peak[far]);
        if (!far)
            kx = fx, ky = fy;
        plm_film_free(&film);
        plm_scene_free(&scene);
    }
    /* Image x is flat +x, image y runs down flat y: cycles per image from cycles per mm. */
    double ex = g.x * pixel * size, ey = -g.y * pixel * size;
    double measured = hypot(kx, ky), expected = hypot(ex, ey);
    double angle = fabs(atan2(kx * ey - ky * ex, kx * ex + ky * ey)) * 180.0 / PLM_PI;
    angle = fmin(angle, 180.0 - angle); /* k and -k are one frequency */
    printf("close-up %dx%d at %.4f mm/px: barbs at %.2f cycles per image (species %.2f), %.2f deg from the species' "
           "direction; peak power share %.3f near field, %.3f far field\n",
           size, size, pixel, measured, expected, angle, peak[0], peak[1]);
    assert_double_near(measured / expected, 1.0, rel_tol);
    assert_double_near(angle, 0.0, angle_tol);
    assert_true(peak[0] > 10.0 * peak[1]);
}

/* The zoom test's Monte Carlo error comes from replicates: each render is
 * ZOOM_REPLICATES renders of spp / ZOOM_REPLICATES samples with seeds 1, 2,
 * ..., and a difference of two mean colours is tested against the standard
 * error of its mean over the replicates. The pixels' spread cannot give it:
 * the near field's stripes would count as noise. Pairing the replicates by
 * seed keeps the correlation of two renders with the same random numbers
 * (near and far field at one zoom share all but the masking), so the error
 * is that of the difference itself, not the larger one of two independent
 * means. ZOOM_T is Student's t for ZOOM_REPLICATES - 1 = 31 degrees of
 * freedom at a two-sided 1e-4: a tolerance that adapts to the render's
 * noise and is never wider than the noise requires. */
#define ZOOM_REPLICATES 32
#define ZOOM_T 4.46

/* a - b per channel, relative to b's mean: its mean over the replicates
 * paired by seed and that mean's standard error. */
static inline void zoom_difference(const double (*a)[3], const double (*b)[3], double d[3], double se[3])
{
    for (int c = 0; c < 3; ++c) {
        double s = 0.0, s2 = 0.0, mb = 0.0;
        for (int r = 0; r < ZOOM_REPLICATES; ++r) {
            double x = a[r][c] - b[r][c];
            s += x;
            s2 += x * x;
            mb += b[r][c] / ZOOM_REPLICATES;
        }
        double mean = s / ZOOM_REPLICATES;
        double var = fmax(s2 / ZOOM_REPLICATES - mean * mean, 0.0) * ZOOM_REPLICATES / (ZOOM_REPLICATES - 1);
        d[c] = mean / mb;
        se[c] = sqrt(var / ZOOM_REPLICATES) / mb;
    }
}

/* Zooms out from 0.03 mm per pixel through the transition (a pixel as wide
 * as a barb period) to the far field: at each zoom the near field's mean
 * colour equals the far field's, and the first zoom's far field, within
 * ZOOM_T standard errors (printed with the differences). The test must be
 * able to see a 2% bias: ZOOM_T standard errors stay under 2%. */
static inline void closeup_check_zoom(const char *species, int size, int spp, const double *pixels_mm, int zooms)
{
    double mean[2][ZOOM_REPLICATES][3], ref[ZOOM_REPLICATES][3];
    for (int z = 0; z < zooms; ++z) {
        double pixel = 0.0;
        for (int far = 0; far < 2; ++far) {
            plm_scene scene;
            closeup_load(species, size, size, spp, pixels_mm[z], far, &scene);
            plm_film films[ZOOM_REPLICATES];
            closeup_render(&scene, ZOOM_REPLICATES, films, &pixel);
            for (int r = 0; r < ZOOM_REPLICATES; ++r) {
                film_mean_rgb(&films[r], mean[far][r]);
                plm_film_free(&films[r]);
            }
            plm_scene_free(&scene);
        }
        if (z == 0)
            memcpy(ref, mean[1], sizeof ref);
        double d[2][3], se[2][3];
        zoom_difference(mean[0], mean[1], d[0], se[0]);
        zoom_difference(mean[0], ref, d[1], se[1]);
        int comparisons = z ? 2 : 1; /* at the first zoom, the far field is the first */
        for (int k = 0; k < comparisons; ++k)
            printf("zoom %.3f mm/px, near field / %s - 1 (RGB): %+.3f%% %+.3f%% %+.3f%%, "
                   "standard errors %.3f%% %.3f%% %.3f%%\n",
                   pixel, k ? "first far field" : "far field", 100.0 * d[k][0], 100.0 * d[k][1], 100.0 * d[k][2],
                   100.0 * se[k][0], 100.0 * se[k][1], 100.0 * se[k][2]);
        for (int k = 0; k < comparisons; ++k)
            for (int c = 0; c < 3; ++c) {
                assert_true(ZOOM_T * se[k][c] < 0.02);
                assert_double_near(d[k][c], 0.0, ZOOM_T * se[k][c]);
            }
    }
}

/* The group's setup and teardown: the flat species in a directory of its own. */
static char closeup_dir[256], closeup_species[512];

static inline int closeup_setup(void **state)
{
    (void)state;
    snprintf(closeup_dir, sizeof closeup_dir, "/tmp/plumage_nearfield_XXXXXX");
    if (!mkdtemp(closeup_dir))
        return -1;
    closeup_write_species(closeup_dir, closeup_species, sizeof closeup_species);
    return 0;
}

static inline int closeup_teardown(void **state)
{
    (void)state;
    remove(closeup_species);
    rmdir(closeup_dir);
    return 0;
}

#endif
