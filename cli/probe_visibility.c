/* plumage probe visibility: the ID pass (render/visibility.h) of a scene
 * through its own camera or from directions all around it, summarised: how
 * much of each feather shows, whether the proximal half of any does, and how
 * many rays end on bare skin. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/outputs.h"
#include "common/fileio.h"
#include "common/image_io.h"
#include "common/rng.h"
#include "render/visibility.h"
#include "scene/scene_file.h"

typedef struct visibility_args {
    int directions, min_rays, width, height;
    double fov;
    const char *csv, *ids, *resolution;
    plm_opt_list sets;
} visibility_args;

static void header(void)
{
    printf("%-6s %9s %9s %7s %7s %7s %7s %7s %8s %8s %7s %7s %8s %9s\n", "view", "rays", "hits", "vane", "rachis",
           "fluff", "body", "other", "feathers", "measured", "median", "p90", "proximal", "prox_rays");
}

/* One view's line; the fractions of hits per part, then the feathers entirely
 * on screen: their median and 90th-percentile visible fraction, how many show
 * some of their proximal half and on how many rays. */
static void print_view(const char *name, const plm_visibility *v, const plm_visibility_summary *s)
{
    int crossed = 0;
    for (int id = 1; id <= v->feather_count; ++id)
        crossed += v->feathers[id].crossed > 0;
    double h = v->hits > 0 ? (double)v->hits : 1.0;
    printf("%-6s %9lld %9lld %7.4f %7.4f %7.4f %7.4f %7.4f %8d %8d %7.3f %7.3f %8d %9lld\n", name, v->rays, v->hits,
           v->part_hits[PLM_PART_VANE] / h, v->part_hits[PLM_PART_RACHIS] / h, v->part_hits[PLM_PART_FLUFF] / h,
           v->part_hits[PLM_PART_BODY] / h, v->part_hits[PLM_PART_OTHER] / h, crossed, s->feathers, s->median,
           s->p90, s->proximal_feathers, s->proximal_rays);
}

static void csv_rows(FILE *f, int view, const plm_visibility *v)
{
    for (int id = 1; id <= v->feather_count; ++id) {
        const plm_feather_view *fv = &v->feathers[id];
        if (fv->crossed == 0)
            continue;
        fprintf(f, "%d,%d,%d,%d,%.6f,%d,%.4f,%d\n", view, id, fv->crossed, fv->seen, (double)fv->seen / fv->crossed,
                fv->seen_proximal, fv->seen > 0 ? fv->v_min : -1.0, fv->on_border);
    }
}

/* The ID image: each feather its own hue, brighter toward its tip; the body
 * red, other surfaces grey, the background black. */
static plm_result write_ids(const char *path, const plm_visibility *v, plm_error *err)
{
    size_t n = (size_t)v->width * v->height;
    unsigned char *px = malloc(3 * n);
    if (!px)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "out of memory for %s", path);
    for (size_t i = 0; i < n; ++i) {
        unsigned char *p = px + 3 * i;
        uint64_t h = plm_hash64((uint64_t)v->feather[i], 0x1d5u, 0);
        double shade = 0.35 + 0.65 * plm_clamp(v->v[i], 0.0, 1.0);
        if (v->instance[i] < 0)
            p[0] = p[1] = p[2] = 0;
        else if (v->part[i] == PLM_PART_BODY)
            p[0] = 255, p[1] = 40, p[2] = 40;
        else if (v->feather[i] == 0)
            p[0] = p[1] = p[2] = 128;
        else
            for (int c = 0; c < 3; ++c)
                p[c] = (unsigned char)(shade * (64 + ((h >> (8 * c)) & 0xbf)));
    }
    plm_result rc = plm_image_write(path, v->width, v->height, 3, PLM_PIXEL_UINT8, px, err);
    free(px);
    return rc;
}

static int run(const visibility_args *a, const char *scene_file)
{
    plm_error err = {{0}};
    plm_scene scene;
    if (plm_scene_load_with(scene_file, a->sets.items, a->sets.count, &scene, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 1;
    }
    int width = a->width ? a->width : scene.film.width, height = a->height ? a->height : scene.film.height;
    plm_world w;
    if (plm_world_build(&scene, &w, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        plm_scene_free(&scene);
        return 1;
    }
    plm_atomic_file csv = {0};
    int status = 0;
    if (a->csv && plm_atomic_open(&csv, a->csv, &err) != PLM_OK)
        status = 1;
    if (csv.fp)
        fprintf(csv.fp, "view,feather,crossed,seen,visible_fraction,seen_proximal,v_min_seen,on_border\n");
    header();
    int views = a->directions > 0 ? a->directions : 1;
    plm_visibility_summary total = {0};
    long long hits = 0, body = 0;
    for (int k = 0; !status && k < views; ++k) {
        plm_camera c;
        if (a->directions > 0)
            c = plm_visibility_camera(&w, plm_visibility_direction(k, a->directions), width, height, a->fov);
        else if (scene.camera.given)
            plm_camera_from_desc(&scene.camera, width, height, 1, &c);
        else /* as the renderer frames a scene without a camera */
            c = plm_visibility_camera(&w, v3(0.0, 0.0, 1.0), width, height, scene.camera.fov);
        plm_visibility v;
        plm_visibility_summary s;
        char name[32];
        snprintf(name, sizeof name, a->directions > 0 ? "%d" : "camera", k);
        if (plm_visibility_trace(&w, &c, &v, &err) != PLM_OK ||
            plm_visibility_summarise(&v, a->min_rays, &s, &err) != PLM_OK) {
            status = 1;
            break;
        }
        print_view(name, &v, &s);
        if (csv.fp)
            csv_rows(csv.fp, k, &v);
        if (k == 0 && a->ids && write_ids(a->ids, &v, &err) != PLM_OK)
            status = 1;
        hits += v.hits;
        body += v.part_hits[PLM_PART_BODY];
        total.proximal_rays += s.proximal_rays;
        total.seen_rays += s.seen_rays;
        plm_visibility_free(&v);
    }
    if (!status && views > 1)
        printf("all %d views: %.4f of the rays that end on a surface end on the body; %lld of %lld rays ending on "
               "whole feathers show a proximal half\n", views, hits ? (double)body / hits : 0.0, total.proximal_rays,
               total.seen_rays);
    if (csv.fp && (status ? (plm_atomic_abort(&csv), PLM_OK) : plm_atomic_commit(&csv, &err)) != PLM_OK)
        status = 1;
    if (status)
        fprintf(stderr, "error: %s\n", err.message);
    plm_world_free(&w);
    plm_scene_free(&scene);
    return status;
}

int probe_visibility(int argc, char **argv)
{
    visibility_args a = {0, 20, 0, 0, 40.0, NULL, NULL, NULL, {{0}, 0}};
    plm_option opts[] = {
        {"--directions", PLM_OPT_INT, &a.directions, 0, 0, 10000, NULL, "N",
         "look from N directions spread over the sphere, each framing the whole scene (default 0: the scene's "
         "camera)", 0},
        {"--fov", PLM_OPT_DOUBLE, &a.fov, 0, 1, 170, NULL, "DEG", "--directions: field of view (default 40)", 0},
        {"--resolution", PLM_OPT_STRING, &a.resolution, 0, 0, 0, NULL, "WxH",
         "rays across and down (default: the scene's film)", 0},
        {"--min-rays", PLM_OPT_INT, &a.min_rays, 0, 1, 1 << 30, NULL, "N",
         "feathers whose projection covers fewer rays are left out of the fractions (default 20)", 0},
        {"--set", PLM_OPT_LIST, &a.sets, 0, 0, 0, NULL, "PATH=VALUE", "change a field of the scene file first", 0},
        {"--csv", PLM_OPT_STRING, &a.csv, 0, 0, 0, NULL, "FILE",
         "one row per feather and view: rays crossing it and ending on it, its visible fraction, rays on its "
         "proximal half, the lowest v seen, whether it touches the image border", 0},
        {"--ids", PLM_OPT_STRING, &a.ids, 0, 0, 0, NULL, "FILE.png",
         "the first view's ID image: a colour per feather, brighter toward the tip; the body red", 0},
    };
    plm_command_help help = {
        "plumage probe visibility SCENE.json [options]",
        "Follows one ray per pixel through every surface and records which feather, which part (vane, rachis, "
        "fluff, body, other) and where along the feather (v: 0 at the calamus base, 1 at the tip) it ends on. "
        "Prints per view the fraction of hits on each part, and over the feathers entirely on screen the median "
        "and 90th percentile of the fraction of each feather's projected area that shows, how many feathers "
        "show part of their proximal half (v < 0.5) and on how many rays. Example:\n"
        "  plumage probe visibility presets/scenes/pelt_82.json --resolution 365x210\n"
        "  plumage probe visibility bird.json --directions 26 --resolution 256x256"};
    const char *positional[1];
    int n = 0;
    int rc = plm_parse_options(&help, argc, argv, 1, opts, (int)(sizeof opts / sizeof opts[0]), positional, 1, &n);
    if (rc)
        return rc == 1 ? 0 : 2;
    if (n != 1) {
        fprintf(stderr, "error: probe visibility needs exactly one scene file (see --help)\n");
        return 2;
    }
    if (a.resolution && !plm_parse_resolution(a.resolution, &a.width, &a.height)) {
        fprintf(stderr, "error: --resolution: '%s' must be WxH, each a whole number in [1, 16384]\n", a.resolution);
        return 2;
    }
    plm_outputs outputs = {0}; /* checked before the scene is read */
    if ((a.csv && !plm_outputs_file(&outputs, "--csv", a.csv)) || (a.ids && !plm_outputs_file(&outputs, "--ids", a.ids))) {
        plm_outputs_undo(&outputs);
        return 1;
    }
    int status = run(&a, positional[0]);
    if (status)
        plm_outputs_undo(&outputs);
    else if (a.csv || a.ids) {
        fflush(stdout);
        plm_print_wrote((const char *const[]){a.csv, a.ids}, 2);
    }
    return status;
}
