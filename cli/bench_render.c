/* plumage bench render: samples per second per thread and peak memory of the
 * path tracer on (a) one feather at 256x512, (b) 2,500 instanced feathers
 * over a plane at 512x256 and (c) a close-up of one feather whose vane fills
 * the 256x256 frame, all under an environment map with maximum depth 16; and
 * a trace-only pass (same camera rays and bounce count, no shading) so the
 * shading overhead shows as a ratio. With --bcsdf both each case renders
 * with the tabulated, then the stochastic estimator on the same world before
 * the trace-only pass, so all their ratios come from one run. The feather is
 * generated from a species preset, or (--vane-quad) a curled quad cut out by
 * an analytic feather texture. Case (d) weighs the environment map's
 * sampling: one feather under the map alone against a constant environment
 * of its mean, and MIS against BSDF sampling alone at equal time. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/bench.h"
#include "common/clock.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "cli/outputs.h"
#include "common/memory.h"
#include "optics/feather_bsdf.h"
#include "render/render.h"
#include "render/scene_build.h"
#include "scene/feathers.h"

/* The analytic vane texture of presets/scenes/vane_texture.png: an ogive
 * outline, a tapering rachis stripe, barbs at 35 to 60 degrees from the rachis. */
static float *vane_texture_pixels(int w, int h)
{
    float *px = malloc(sizeof(float) * 3 * (size_t)w * (size_t)h);
    if (!px)
        return NULL;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double u = (x + 0.5) / w, v = 1.0 - (y + 0.5) / h, du = u - 0.5;
            double half = 0.47 * pow(sin(PLM_PI * fmin(1.0, 0.08 + v * 0.95)), 0.7) * (v > 0.06);
            double region = fabs(du) < 0.018 * (1.2 - v) && v < 0.97 ? 0.5 : (fabs(du) < half ? 1.0 : 0.0);
            double a = plm_radians(35.0 + 25.0 * v);
            float *p = px + 3 * ((size_t)y * w + x);
            p[0] = (float)(((du >= 0 ? sin(a) : -sin(a)) + 1.0) / 2.0);
            p[1] = (float)((cos(a) + 1.0) / 2.0);
            p[2] = (float)region;
        }
    return px;
}

/* A sky gradient with a small bright sun, as a 64x32 lat-long map. */
static plm_light sky_light(void)
{
    plm_light l = plm_light_default(PLM_LIGHT_ENV_MAP);
    plm_image *im = &l.image;
    im->width = 64, im->height = 32, im->channels = 3;
    im->pixels = malloc(sizeof(float) * 64 * 32 * 3);
    for (int y = 0; im->pixels && y < 32; ++y)
        for (int x = 0; x < 64; ++x) {
            float *p = im->pixels + 3 * (y * 64 + x);
            int sun = (x == 40 || x == 41) && (y == 9 || y == 10);
            double up = fmax(0.0, cos(PLM_PI * (y + 0.5) / 32));
            p[0] = sun ? 300.0f : (float)(0.25 + 0.3 * up);
            p[1] = sun ? 280.0f : (float)(0.3 + 0.35 * up);
            p[2] = sun ? 250.0f : (float)(0.4 + 0.5 * up);
        }
    return l;
}

/* The feather every scene instances: a generated one (vane and rachis) or
 * the analytic vane quad, scaled to about one unit long. */
static int add_vane_quad(plm_scene *s, plm_tile_feather *p, plm_error *err)
{
    plm_mesh vane;
    if (plm_shape_quad(0.4, 1.0, 1.5, 32, &vane, err) != PLM_OK)
        return 0;
    plm_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "vane");
    m.type = PLM_MATERIAL_FEATHER;
    m.reflectance = rgb_make(0.85, 0.8, 0.7);
    m.feather = malloc(sizeof *m.feather);
    float *px = vane_texture_pixels(256, 512);
    if (!m.feather || !px || plm_feather_texture_from_pixels(256, 512, px, &m.texture, err) != PLM_OK) {
        free(m.feather);
        return 0;
    }
    plm_feather_params_default(m.feather);
    *p = (plm_tile_feather){1, {plm_scene_add_mesh(s, "vane", &vane)}, {plm_scene_add_material(s, &m)}, 1.0};
    return 1;
}

static int add_species(plm_scene *s, const char *species, plm_tile_feather *p, plm_error *err)
{
    plm_feather_cache cache = {0};
    plm_feather_request q = {species, 3, 1024, 0, 0, NULL, NULL, NULL, NULL};
    plm_feather_parts parts;
    plm_result rc = plm_feather_cache_get(&cache, s, "f", &q, &parts, err);
    plm_feather_cache_free(&cache);
    if (rc != PLM_OK)
        return 0;
    /* Scale the feather (in millimetres) to a length of about one unit. */
    *p = (plm_tile_feather){2,
                            {parts.mesh[0], parts.mesh[1]},
                            {parts.material[0], parts.material[1]},
                            parts.length > 0.0 ? 1.0 / parts.length : 1.0};
    return 1;
}

/* A camera 0.2 units above the vane, beside the rachis, with a 20 degree
 * field of view: the vane fills the frame. */
static void close_up(plm_scene *s, const plm_tile_feather *p)
{
    const plm_mesh *m = &s->meshes[p->mesh[0]].mesh;
    vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (int v = 0; v < m->vertex_count; ++v) {
        vec3 q = v3(m->positions[3 * v], m->positions[3 * v + 1], m->positions[3 * v + 2]);
        lo = v3(fmin(lo.x, q.x), fmin(lo.y, q.y), fmin(lo.z, q.z));
        hi = v3(fmax(hi.x, q.x), fmax(hi.y, q.y), fmax(hi.z, q.z));
    }
    vec3 at = v3_scale(v3(0.5 * (lo.x + hi.x) + 0.12 * (hi.x - lo.x), lo.y + 0.55 * (hi.y - lo.y), hi.z), p->scale);
    s->camera.given = 1;
    s->camera.up = v3(0, 1, 0);
    s->camera.look_at = at;
    s->camera.position = v3_add(at, v3(0.0, -0.05, 0.2));
    s->camera.fov = 20;
}

static int build_scene(plm_scene *s, int feathers, int closeup, int width, int height, const char *species,
                       int diffuse, plm_error *err)
{
    plm_scene_init(s);
    s->film.width = width;
    s->film.height = height;
    s->film.max_depth = 16;
    plm_tile_feather proto;
    if (!(species ? add_species(s, species, &proto, err) : add_vane_quad(s, &proto, err)))
        return 0;
    if (diffuse) /* the texture still cuts the vane out */
        s->materials[proto.material[0]].type = PLM_MATERIAL_DIFFUSE;
    plm_light sky = sky_light();
    if (!sky.image.pixels || plm_scene_add_light(s, &sky) < 0)
        return 0;
    if (feathers == 1) { /* the camera frames the feather's bounds from +z, the dorsal side */
        plm_xform scale = plm_xform_scale(v3(proto.scale, proto.scale, proto.scale));
        for (int k = 0; k < proto.count; ++k)
            if (plm_scene_add_object(s, proto.mesh[k], proto.material[k], scale) < 0)
                return 0;
        if (closeup)
            close_up(s, &proto);
        return 1;
    }
    if (plm_scene_add_ground(s, 40.0, rgb_gray(0.3), err) < 0)
        return 0;
    /* A pelt over 8 x 8 units, the grid as fine as the count asks. */
    s->camera.given = 1;
    s->camera.up = v3(0, 1, 0);
    s->camera.position = v3(0, 3.2, 6.0);
    s->camera.look_at = v3(0, 0, 0);
    s->camera.fov = 45;
    return plm_scene_add_feather_tiles(s, &proto, feathers, 8.0 / ceil(sqrt((double)feathers)), 2500);
}

typedef struct bench_options {
    int threads, spp, feathers, diffuse, vane_quad, downscale, shaded_only, table_mib;
    const char *species, *images, *bcsdf, *cases;
    int kinds;                /* how many estimators to run: 1, or 2 for "both" */
    plm_bcsdf_kind kind[2];
} bench_options;

static const char *kind_name(plm_bcsdf_kind k) { return k == PLM_BCSDF_STOCHASTIC ? "stochastic" : "tabulated"; }

static void set_kind(plm_scene *scene, plm_bcsdf_kind kind)
{
    for (int i = 0; i < scene->material_count; ++i)
        if (scene->materials[i].feather)
            scene->materials[i].feather->bcsdf = kind;
}

/* One row: the shaded film's rates against the trace-only film's. */
static void print_row(const char *label, const char *kind, const plm_film *shaded, const plm_film *traced, int spp,
                      double build)
{
    double per_thread = 1.0 / shaded->threads;
    double samples_rate = shaded->sample_count / shaded->seconds * per_thread;
    double shaded_rays = shaded->ray_count / shaded->seconds * per_thread;
    double traced_rays = traced->ray_count / traced->seconds * per_thread;
    printf("%-30s %-10s %4dx%-4d %4d %7d %16.0f %14.0f %14.0f %9.2f %8.3f %9.1f %9.2f\n", label, kind, shaded->width,
           shaded->height, spp, shaded->threads, samples_rate, shaded_rays, traced_rays, traced_rays / shaded_rays, build,
           plm_memory_peak_mib(), shaded->seconds);
    if (shaded->nonfinite)
        printf("  (%lld non-finite samples dropped)\n", shaded->nonfinite);
}

static int run_case(const char *label, const char *tag, int feathers, int width, int height, const bench_options *o)
{
    if (!strchr(o->cases, tag[0]))
        return 0;
    plm_scene scene;
    plm_error err = {{0}};
    width = (width + o->downscale - 1) / o->downscale;
    height = (height + o->downscale - 1) / o->downscale;
    if (!build_scene(&scene, feathers, tag[0] == 'c', width, height, o->vane_quad ? NULL : o->species, o->diffuse,
                     &err)) {
        fprintf(stderr, "error: %s\n", err.message[0] ? err.message : "out of memory");
        plm_scene_free(&scene);
        return 1;
    }
    /* The world is built for the first estimator; a tabulated one first
     * builds the tables, which the stochastic one then leaves unused. */
    set_kind(&scene, o->kind[0]);
    scene.film.fiber_table_mib = o->table_mib;
    plm_world world;
    double t0 = plm_seconds();
    if (plm_world_build(&scene, &world, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        plm_scene_free(&scene);
        return 1;
    }
    double build = plm_seconds() - t0;
    plm_render_options opt = {0};
    opt.threads = o->threads;
    opt.spp = o->spp;
    plm_film shaded[2], traced;
    for (int k = 0; k < o->kinds; ++k) {
        set_kind(&scene, o->kind[k]);
        plm_render_world(&world, &opt, &shaded[k], &err);
        if (o->images) { /* to look at what was measured, and to compare (EXR) */
            char png[4096], exr[4096];
            const char *suffix = o->kinds > 1 ? kind_name(o->kind[k]) : "";
            snprintf(png, sizeof png, "%s_%s%s%s.png", o->images, tag, *suffix ? "_" : "", suffix);
            snprintf(exr, sizeof exr, "%s_%s%s%s.exr", o->images, tag, *suffix ? "_" : "", suffix);
            plm_picture picture = plm_picture_of(&scene.film);
            if (plm_film_write(&shaded[k], exr, png, &picture, &err) != PLM_OK)
                fprintf(stderr, "error: %s\n", err.message);
            else
                plm_print_wrote((const char *const[]){png, exr}, 2);
        }
    }
    opt.trace_only = 1;
    if (o->shaded_only)
        traced = (plm_film){.ray_count = 0, .seconds = 1.0};
    else
        plm_render_world(&world, &opt, &traced, &err);
    for (int k = 0; k < o->kinds; ++k)
        print_row(label, kind_name(o->kind[k]), &shaded[k], &traced, o->spp, build);
    if (o->kinds > 1)
        printf("%-30s tabulated samples/s over stochastic: %.2f\n", "",
               (shaded[0].sample_count / shaded[0].seconds) / (shaded[1].sample_count / shaded[1].seconds));
    for (int k = 0; k < o->kinds; ++k)
        plm_film_free(&shaded[k]);
    plm_film_free(&traced);
    plm_world_free(&world);
    plm_scene_free(&scene);
    return 0;
}

/* The map's radiance averaged over the sphere (texels weighted by their solid angle). */
static rgb env_mean(const plm_image *im)
{
    rgb sum = rgb_gray(0.0);
    double weight = 0.0;
    for (int y = 0; y < im->height; ++y) {
        double w = sin(PLM_PI * (y + 0.5) / im->height);
        for (int x = 0; x < im->width; ++x) {
            const float *p = im->pixels + (size_t)im->channels * ((size_t)y * im->width + x);
            sum = rgb_add(sum, rgb_scale(rgb_make(p[0], p[1], p[2]), w));
            weight += w;
        }
    }
    return rgb_scale(sum, 1.0 / weight);
}

/* Root mean square difference of two films' pixels (all channels). */
static double film_rmse(const plm_film *a, const plm_film *b)
{
    double sum = 0.0;
    size_t n = (size_t)a->width * a->height * 3;
    for (size_t i = 0; i < n; ++i)
        sum += ((double)a->rgb[i] - b->rgb[i]) * ((double)a->rgb[i] - b->rgb[i]);
    return sqrt(sum / n);
}

static double samples_per_thread(const plm_film *f) { return f->sample_count / f->seconds / f->threads; }

/* (d) One feather at 128x256 lit by the environment map alone: its sampling
 * cost against a constant environment of the map's mean radiance, and the
 * error of MIS and of BSDF sampling alone against a reference of 16 times the
 * samples (equal time: BSDF sampling's error scaled by the square root of its
 * time over MIS's). */
static int run_env_case(const bench_options *o)
{
    if (!strchr(o->cases, 'd'))
        return 0;
    plm_scene scene[2];
    plm_world world[2];
    plm_error err = {{0}};
    int w = (128 + o->downscale - 1) / o->downscale, h = (256 + o->downscale - 1) / o->downscale, built = 0;
    const char *species = o->vane_quad ? NULL : o->species;
    for (; built < 2; ++built) {
        if (!build_scene(&scene[built], 1, 0, w, h, species, o->diffuse, &err)) {
            plm_scene_free(&scene[built]);
            break;
        }
        set_kind(&scene[built], o->kind[0]);
        scene[built].film.fiber_table_mib = o->table_mib;
        if (built == 1) { /* the same world under the map's mean, a constant */
            plm_light *map = &scene[1].lights[0];
            rgb mean = env_mean(&map->image);
            free(map->image.pixels);
            *map = plm_constant_sky(mean);
        }
        if (plm_world_build(&scene[built], &world[built], &err) != PLM_OK) {
            plm_scene_free(&scene[built]);
            break;
        }
    }
    int ok = built == 2;
    if (ok) {
        plm_render_options opt = {.threads = o->threads, .spp = o->spp};
        plm_film map, constant, bsdf, reference;
        plm_render_world(&world[0], &opt, &map, &err);
        plm_render_world(&world[1], &opt, &constant, &err);
        opt.estimator = PLM_ESTIMATOR_BSDF;
        plm_render_world(&world[0], &opt, &bsdf, &err);
        opt.estimator = PLM_ESTIMATOR_MIS;
        opt.spp = 16 * o->spp;
        opt.seed = 7919;
        plm_render_world(&world[0], &opt, &reference, &err);
        double mis_error = film_rmse(&map, &reference), bsdf_error = film_rmse(&bsdf, &reference);
        double equal_time = bsdf_error * sqrt(bsdf.seconds / map.seconds);
        printf("\n(d) one feather %dx%d under the environment map alone, %d spp, %d threads:\n", w, h, o->spp,
               map.threads);
        printf("  samples/s/thread: map %.0f, constant of its mean %.0f (map over constant %.2f)\n",
               samples_per_thread(&map), samples_per_thread(&constant),
               samples_per_thread(&map) / samples_per_thread(&constant));
        printf("  RMSE against %d spp: MIS %.5f, BSDF alone %.5f, BSDF alone at MIS's time %.5f (%.2fx MIS's)\n",
               opt.spp, mis_error, bsdf_error, equal_time, equal_time / mis_error);
        plm_film *films[] = {&map, &constant, &bsdf, &reference};
        for (int i = 0; i < 4; ++i)
            plm_film_free(films[i]);
    } else {
        fprintf(stderr, "error: %s\n", err.message[0] ? err.message : "out of memory");
    }
    for (int i = 0; i < built; ++i) {
        plm_world_free(&world[i]);
        plm_scene_free(&scene[i]);
    }
    return ok ? 0 : 1;
}

int bench_render(int argc, char **argv)
{
    bench_options o = {0, 16, 2500, 0, 0, 1, 0, PLM_FIBER_TABLE_MIB_DEFAULT,
                       "presets/species/covert_parrot.json", NULL, "tabulated", "abcd",
                       1, {PLM_BCSDF_TABULATED, PLM_BCSDF_STOCHASTIC}};
    plm_option opts[] = {
        {"--threads", PLM_OPT_INT, &o.threads, 0, 1, 1024, NULL, "N", "render threads (default: all cores)", 0},
        {"--spp", PLM_OPT_INT, &o.spp, 0, 1, 65536, NULL, "N", "samples per pixel of each pass (default 16)", 0},
        {"--feathers", PLM_OPT_INT, &o.feathers, 0, 2, 1000000, NULL, "N", "feathers in the pelt scene (default 2500)", 0},
        {"--species", PLM_OPT_STRING, &o.species, 0, 0, 0, NULL, "FILE",
         "the feather, generated in memory (default presets/species/covert_parrot.json)", 0},
        {"--vane-quad", PLM_OPT_FLAG, &o.vane_quad, 0, 0, 0, NULL, NULL,
         "instead a curled quad cut out by an analytic feather texture", 0},
        {"--diffuse", PLM_OPT_FLAG, &o.diffuse, 0, 0, 0, NULL, NULL, "diffuse vanes instead of the feather BSDF", 0},
        {"--images", PLM_OPT_STRING, &o.images, 0, 0, 0, NULL, "PREFIX",
         "also write the shaded images as PREFIX_a.png, PREFIX_a.exr and so on", 0},
        {"--bcsdf", PLM_OPT_STRING, &o.bcsdf, 0, 0, 0, NULL, "NAME",
         "the fiber estimator: tabulated (default), stochastic (docs/fiber.md) or both (the same world, one after\n"
         "the other, and their samples/s ratio)", 0},
        {"--cases", PLM_OPT_STRING, &o.cases, 0, 0, 0, NULL, "LETTERS", "which cases to run (default abcd)", 0},
        {"--downscale", PLM_OPT_INT, &o.downscale, 0, 1, 64, NULL, "N",
         "divide each case's width and height by N (for expensive references)", 0},
        {"--shaded-only", PLM_OPT_FLAG, &o.shaded_only, 0, 0, 0, NULL, NULL,
         "skip the trace-only pass (no shading ratio)", 0},
        {"--table-mib", PLM_OPT_INT, &o.table_mib, 0, PLM_FIBER_TABLE_MIB_MIN, PLM_FIBER_TABLE_MIB_MAX, NULL, "N",
         "each fiber table's memory, as a scene's film.fiber_table_mib (default 32)", 0},
    };
    plm_command_help help = {
        "plumage bench render [options]",
        "Samples per second per thread of the path tracer (max depth 16, environment map) on (a) one feather\n"
        "at 256x512, (b) a pelt of instanced feathers over a plane at 512x256 and (c) a close-up whose vane\n"
        "fills the 256x256 frame, then the same rays traced without shading; and (d) one feather at 128x256\n"
        "under the environment map alone: samples/s/thread against a constant environment of the map's mean,\n"
        "and the error of MIS and of BSDF sampling alone against 16 times the samples, at equal time too.\n"
        "Rays are surface and shadow queries; 'shading x' is the cost of a shaded ray over a\n"
        "trace-only ray (rays/s of the trace-only pass over rays/s of the shaded one). Peak memory is the\n"
        "process's so far (it includes the libraries and the first scene). The feather is generated from a\n"
        "species preset (run from the repository root, or give --species) and rendered with the feather BSDF.\n"
        "Reference: the paper's Mitsuba 0.6 renderer did about 51,000 samples/s/thread on its 2,500-feather scene."};
    int rc = plm_parse_options(&help, argc, argv, 1, opts, (int)(sizeof opts / sizeof opts[0]), NULL, 0, NULL);
    if (rc)
        return rc == 1 ? 0 : 2;
    if (strcmp(o.bcsdf, "tabulated") != 0 && strcmp(o.bcsdf, "stochastic") != 0 && strcmp(o.bcsdf, "both") != 0) {
        fprintf(stderr, "error: --bcsdf %s: must be tabulated, stochastic or both\n", o.bcsdf);
        return 2;
    }
    if (strcmp(o.bcsdf, "stochastic") == 0)
        o.kind[0] = PLM_BCSDF_STOCHASTIC;
    o.kinds = strcmp(o.bcsdf, "both") == 0 ? 2 : 1;
    if (o.images && !plm_images_prefix_ok(o.images))
        return 1;
    if (strpbrk(o.cases, "abc"))
        printf("%-30s %-10s %9s %4s %7s %16s %14s %14s %9s %8s %9s %9s\n", "scene", "bcsdf", "size", "spp", "threads",
               "samples/s/thread", "rays/s/thread", "trace-only", "shading x", "build s", "peak MiB", "shaded s");
    char one[64], pelt[64];
    snprintf(one, sizeof one, "(a) one feather%s", o.vane_quad ? " (vane quad)" : "");
    snprintf(pelt, sizeof pelt, "(b) %d instanced feathers", o.feathers);
    if (run_case(one, "a", 1, 256, 512, &o) != 0 || run_case(pelt, "b", o.feathers, 512, 256, &o) != 0)
        return 1;
    if (run_case("(c) close-up of one feather", "c", 1, 256, 256, &o) != 0)
        return 1;
    return run_env_case(&o);
}
