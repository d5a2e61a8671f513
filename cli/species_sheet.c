/* The species contact sheet: each species generated as a scene generates it
 * (scene/feathers.h: the same feather, colours and rachis as in a pelt),
 * rendered from the dorsal side (front) and the ventral side (back) under a
 * bluish sky and a warm low sun from the side, as outdoors, and laid out in a
 * labelled grid. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "cli/species_sheet.h"
#include "common/clock.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "cli/bench.h"
#include "cli/outputs.h"
#include "common/image_io.h"
#include "generate/species.h"
#include "render/render.h"
#include "scene/scene_file.h"

/* Layout, in pixels. */
enum { GAP = 8, VIEW_GAP = 2, LABEL_H = 24, FOOT_H = 16, FONT = 15, FONT_SMALL = 12, COLUMNS_DEFAULT = 6 };

static const float sheet_grey = 0.02f;
static const float ink[3] = {0.92f, 0.92f, 0.92f}, faint[3] = {0.75f, 0.75f, 0.75f};
/* The sky's radiance (the views' backdrop, a mid blue-grey once tone-mapped)
 * and the sun's irradiance: their ratio and tints those of a clear day's
 * shade and sun, a pale blue sky and a sun a little warmer than white. */
static const double sky[3] = {0.17, 0.2, 0.25}, sun[3] = {3.2, 3.05, 2.8};
#define FOV 20.0       /* degrees: a long lens, so the feather is seen almost without perspective */
#define MARGIN 1.08    /* room around the feather in its view */

typedef struct sheet {
    plm_image img;
    int cols, rows, view_w, view_h, cell_w, cell_h;
} sheet;

/* The scene of one species: its feather at the origin, a sky and a side light. */
static cJSON *species_scene(const char *species, const plm_species_sheet_options *opt, int w, int h)
{
    char json[8192];
    int n = snprintf(json, sizeof json,
                     "{\"film\": {\"width\": %d, \"height\": %d, \"spp\": %d, \"filter_radius\": 1},"
                     " \"lights\": [{\"type\": \"environment\", \"radiance\": [%g, %g, %g]},"
                     "              {\"type\": \"distant\", \"direction\": [0, 0, 1], \"irradiance\": [%g, %g, %g]}],"
                     " \"feathers\": {\"f\": {\"species\": \"\", \"level\": %d, \"texture_size\": %d}},"
                     " \"objects\": [{\"feather\": \"f\"}]}",
                     w, h, opt->spp, sky[0], sky[1], sky[2], sun[0], sun[1], sun[2], opt->level, opt->texture_size);
    cJSON *root = n < (int)sizeof json ? cJSON_Parse(json) : NULL;
    cJSON *f = root ? cJSON_GetObjectItem(cJSON_GetObjectItem(root, "feathers"), "f") : NULL;
    if (f)
        cJSON_ReplaceItemInObject(f, "species", cJSON_CreateString(species));
    return root;
}

static void mesh_bounds(const plm_mesh *m, vec3 *lo, vec3 *hi)
{
    for (int i = 0; i < m->vertex_count; ++i) {
        const float *p = m->positions + 3 * i;
        *lo = v3(fmin(lo->x, p[0]), fmin(lo->y, p[1]), fmin(lo->z, p[2]));
        *hi = v3(fmax(hi->x, p[0]), fmax(hi->y, p[1]), fmax(hi->z, p[2]));
    }
}

/* Frames the feather from +z (side 0, dorsal: the front) or -z (side 1, the
 * back, seen as when the feather is turned over), the light raking in from
 * the viewer's upper left at 60 degrees from the view axis. */
static void place_view(plm_scene *s, int side)
{
    vec3 lo = v3(1e30, 1e30, 1e30), hi = v3(-1e30, -1e30, -1e30);
    for (int m = 0; m < s->mesh_count; ++m)
        mesh_bounds(&s->meshes[m].mesh, &lo, &hi);
    vec3 centre = v3_scale(v3_add(lo, hi), 0.5);
    double aspect = (double)s->film.width / s->film.height;
    double half = 0.5 * MARGIN * fmax(hi.y - lo.y, (hi.x - lo.x) / aspect);
    double distance = half / tan(plm_radians(0.5 * FOV)) + 0.5 * (hi.z - lo.z);
    double toward = side ? -1.0 : 1.0;
    s->camera = (plm_camera_desc){.position = v3_add(centre, v3(0.0, 0.0, toward * distance)),
                                  .look_at = centre, .up = v3(0.0, 1.0, 0.0), .fov = FOV, .given = 1};
    for (int l = 0; l < s->light_count; ++l)
        if (s->lights[l].type == PLM_LIGHT_DISTANT)
            s->lights[l].direction = v3_normalize(v3(-toward * 0.75, 0.5, toward * 0.43));
}

/* Copies src (w x h RGB) into dst at (x0, y0). */
static void paste(plm_image *dst, const float *src, int w, int h, int x0, int y0)
{
    for (int y = 0; y < h; ++y)
        memcpy(dst->pixels + 3 * ((size_t)(y0 + y) * (size_t)dst->width + (size_t)x0), src + 3 * (size_t)y * (size_t)w,
               sizeof(float) * 3 * (size_t)w);
}

/* The species' name and length over the cell, "front" and "back" under its views. */
static plm_result label_cell(const sheet *sh, plm_image *cell, const plm_species *sp, plm_error *err)
{
    char text[192];
    snprintf(text, sizeof text, "%s  (%.0f mm)", sp->name, sp->shape.length);
    plm_result rc = plm_image_draw_text(cell, 2, LABEL_H - 7, FONT, text, ink, err);
    for (int side = 0; side < 2 && rc == PLM_OK; ++side)
        rc = plm_image_draw_text(cell, side * (sh->view_w + VIEW_GAP) + 2, LABEL_H + sh->view_h + 12, FONT_SMALL,
                                 side ? "back" : "front", faint, err);
    return rc;
}

/* Renders one species' two views and labels into its cell (drawn apart, so
 * that a long name is cut at the cell's edge); returns 0 after a message. */
static int render_species(sheet *sh, int k, const char *file, const plm_species *sp,
                          const plm_species_sheet_options *opt, long long *nonfinite)
{
    char species[PLM_PATH_MAX];
    if (!realpath(file, species)) /* the scene below has no folder of its own */
        snprintf(species, sizeof species, "%s", file);
    cJSON *root = species_scene(species, opt, sh->view_w, sh->view_h);
    plm_scene scene;
    plm_error err;
    if (!root || plm_scene_load_json(root, file, &scene, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", root ? err.message : "out of memory");
        cJSON_Delete(root);
        return 0;
    }
    cJSON_Delete(root);
    plm_image cell = {sh->cell_w, sh->cell_h, 3, malloc(sizeof(float) * 3 * (size_t)sh->cell_w * (size_t)sh->cell_h)};
    int ok = cell.pixels != NULL;
    if (!ok)
        fprintf(stderr, "error: out of memory\n");
    for (size_t i = 0; ok && i < 3 * (size_t)cell.width * (size_t)cell.height; ++i)
        cell.pixels[i] = sheet_grey;
    plm_render_options ro = {.threads = opt->threads};
    for (int side = 0; side < 2 && ok; ++side) {
        place_view(&scene, side);
        plm_film film;
        if (plm_render(&scene, &ro, &film, &err) != PLM_OK) {
            fprintf(stderr, "error: %s: %s\n", file, err.message);
            ok = 0;
            break;
        }
        *nonfinite += film.nonfinite;
        paste(&cell, film.rgb, film.width, film.height, side * (sh->view_w + VIEW_GAP), LABEL_H);
        plm_film_free(&film);
    }
    plm_scene_free(&scene);
    if (ok && label_cell(sh, &cell, sp, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        ok = 0;
    }
    if (ok)
        paste(&sh->img, cell.pixels, cell.width, cell.height, GAP + (k % sh->cols) * (sh->cell_w + GAP),
              GAP + (k / sh->cols) * (sh->cell_h + GAP));
    free(cell.pixels);
    return ok;
}

static int make_sheet(sheet *sh, int n, const plm_species_sheet_options *opt)
{
    sh->view_h = opt->tile;
    sh->view_w = opt->tile / 2;
    sh->cols = opt->columns ? opt->columns : COLUMNS_DEFAULT;
    sh->cols = sh->cols < n ? sh->cols : n;
    sh->rows = (n + sh->cols - 1) / sh->cols;
    sh->cell_w = 2 * sh->view_w + VIEW_GAP;
    sh->cell_h = LABEL_H + sh->view_h + FOOT_H;
    long long w = (long long)sh->cols * (sh->cell_w + GAP) + GAP, h = (long long)sh->rows * (sh->cell_h + GAP) + GAP;
    plm_error err;
    if (plm_image_check_size("the contact sheet", w, h, 3, &err) != PLM_OK) {
        fprintf(stderr, "error: %s (fewer --columns or a smaller --tile)\n", err.message);
        return 0;
    }
    sh->img = (plm_image){(int)w, (int)h, 3, malloc(sizeof(float) * 3 * (size_t)w * (size_t)h)};
    if (!sh->img.pixels) {
        fprintf(stderr, "error: out of memory for a %lld x %lld contact sheet\n", w, h);
        return 0;
    }
    for (size_t i = 0; i < 3 * (size_t)w * (size_t)h; ++i)
        sh->img.pixels[i] = sheet_grey;
    return 1;
}

int plm_species_sheet(const char *out, const char *const *files, int n, const plm_species_sheet_options *opt)
{
    /* Every species is read first: a typo in the last file stops the sheet at once. */
    plm_species *sp = calloc((size_t)n, sizeof *sp);
    int loaded = 0, ok = sp != NULL;
    plm_error err;
    for (; ok && loaded < n; ++loaded)
        if (plm_species_load(files[loaded], &sp[loaded], &err) != PLM_OK) {
            fprintf(stderr, "error: %s\n", err.message);
            ok = 0;
            break;
        }
    if (!sp)
        fprintf(stderr, "error: out of memory\n");
    plm_outputs outputs = {0};
    sheet sh;
    memset(&sh, 0, sizeof sh);
    ok = ok && plm_outputs_file(&outputs, "--contact-sheet", out) && make_sheet(&sh, n, opt);
    long long nonfinite = 0;
    double start = plm_seconds();
    for (int k = 0; ok && k < n; ++k) {
        ok = render_species(&sh, k, files[k], &sp[k], opt, &nonfinite);
        if (ok && !opt->quiet)
            fprintf(stderr, "contact sheet: %d/%d %s, front and back at %d spp, %.0f s elapsed\n", k + 1, n,
                    sp[k].name, opt->spp, plm_seconds() - start);
    }
    if (ok && plm_image_write_srgb_png(out, sh.img.width, sh.img.height, sh.img.pixels, 0.0, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        ok = 0;
    }
    if (ok && nonfinite)
        fprintf(stderr, "warning: %lld non-finite samples were dropped (counted as black)\n", nonfinite);
    if (ok)
        plm_print_wrote((const char *const[]){out}, 1);
    else
        plm_outputs_undo(&outputs);
    for (int k = 0; k < loaded; ++k)
        plm_species_free(&sp[k]);
    free(sp);
    free(sh.img.pixels);
    return ok ? 0 : 1;
}
