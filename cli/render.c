/* plumage render: a scene file in, a linear EXR and a tone-mapped PNG out. */
#include <signal.h>
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"
#include "cli/options.h"
#include "render/render.h"

static volatile sig_atomic_t interrupted;

static void on_sigint(int sig)
{
    (void)sig;
    interrupted = 1;
}

/* "dir/name.json" -> "name" + ext, in the working directory. */
static void default_output(const char *scene_path, const char *ext, char *out, size_t size)
{
    const char *base = strrchr(scene_path, '/');
    base = base ? base + 1 : scene_path;
    const char *dot = strrchr(base, '.');
    int len = dot ? (int)(dot - base) : (int)strlen(base);
    snprintf(out, size, "%.*s%s", len, base, ext);
}

int cmd_render(int argc, char **argv)
{
    static const char *const estimators[] = {"mis", "nee", "bsdf", NULL};
    int spp = 0, threads = 0, seed = -1, max_depth = -1, quiet = 0, estimator = 0;
    double exposure = 0.0;
    const char *png = NULL, *exr = NULL;
    plm_option opts[] = {
        {"--spp", PLM_OPT_INT, &spp, 0, 1, 1 << 24, NULL, "N", "samples per pixel (default: the scene's film.spp)", 0},
        {"--threads", PLM_OPT_INT, &threads, 0, 1, 1024, NULL, "N", "render threads (default: all cores)", 0},
        {"--seed", PLM_OPT_INT, &seed, 0, 0, 2147483647, NULL, "N", "random seed (default: the scene's film.seed)", 0},
        {"--max-depth", PLM_OPT_INT, &max_depth, 0, 0, 1024, NULL, "N",
         "most scattering events per path (default: the scene's film.max_depth)", 0},
        {"-o", PLM_OPT_STRING, &png, 0, 0, 0, NULL, "FILE.png",
         "tone-mapped PNG output (default: film.png, else <scene name>.png); with -o, EXR only if --exr", 0},
        {"--exr", PLM_OPT_STRING, &exr, 0, 0, 0, NULL, "FILE.exr",
         "linear EXR output (default: film.exr, else <scene name>.exr)", 0},
        {"--exposure", PLM_OPT_DOUBLE, &exposure, 0, -30, 30, NULL, "STOPS", "PNG exposure (default: film.exposure)", 0},
        {"--estimator", PLM_OPT_CHOICE, &estimator, 0, 0, 0, estimators, "NAME",
         "mis (default), nee (light sampling only) or bsdf (BSDF sampling only): for validation", 0},
        {"--quiet", PLM_OPT_FLAG, &quiet, 0, 0, 0, NULL, NULL, "no progress bar", 0},
    };
    const int n_opts = (int)(sizeof opts / sizeof opts[0]);
    plm_command_help help = {
        "plumage render SCENE.json [options]",
        "Renders a scene file (fields: docs/scene-format.md) with a path tracer: next-event estimation,\n"
        "multiple importance sampling, Russian roulette, feathers' delta transmission as fractional visibility.\n"
        "Writes a linear EXR and a tone-mapped sRGB PNG, atomically. Ctrl-C stops early and writes the image\n"
        "rendered so far; the same scene, seed and spp give the same image at any thread count."};
    const char *positional[1];
    int n_positional = 0;
    int rc = plm_parse_options(&help, argc, argv, 1, opts, n_opts, positional, 1, &n_positional);
    if (rc)
        return rc == 1 ? 0 : 2;
    if (n_positional != 1) {
        fprintf(stderr, "error: plumage render needs exactly one scene file (see --help)\n");
        return 2;
    }
    plm_error err = {{0}};
    plm_scene scene;
    if (plm_scene_load(positional[0], &scene, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 1;
    }
    /* Outputs: -o/--exr replace the scene's; with neither anywhere, name them after the scene. */
    char png_path[PLM_PATH_MAX], exr_path[PLM_PATH_MAX];
    int from_cli = png || exr;
    snprintf(png_path, sizeof png_path, "%s", from_cli ? (png ? png : "") : scene.film.png);
    snprintf(exr_path, sizeof exr_path, "%s", from_cli ? (exr ? exr : "") : scene.film.exr);
    if (!from_cli && !png_path[0] && !exr_path[0]) {
        default_output(positional[0], ".png", png_path, sizeof png_path);
        default_output(positional[0], ".exr", exr_path, sizeof exr_path);
    }
    plm_render_options ro = {0};
    ro.threads = threads;
    ro.spp = spp;
    ro.max_depth = max_depth < 0 ? 0 : (max_depth == 0 ? -1 : max_depth);
    ro.seed = seed < 0 ? 0 : (seed == 0 ? -1 : seed);
    ro.estimator = (plm_estimator)estimator;
    ro.progress = !quiet;
    ro.cancel = &interrupted;
    struct sigaction sa, old;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigint;
    sa.sa_flags = SA_RESETHAND; /* a second Ctrl-C kills at once */
    sigaction(SIGINT, &sa, &old);

    plm_film film;
    int status = 0;
    if (plm_render(&scene, &ro, &film, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        sigaction(SIGINT, &old, NULL);
        plm_scene_free(&scene);
        return 1;
    }
    sigaction(SIGINT, &old, NULL);
    double exp_stops = opts[6].seen ? exposure : scene.film.exposure;
    if (plm_film_write(&film, exr_path, png_path, exp_stops, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        status = 1;
    }
    fprintf(stderr, "%s%dx%d, %lld samples in %.2f s on %d threads (%.0f samples/s/thread)%s%s%s%s\n",
            film.interrupted ? "interrupted: " : "", film.width, film.height, film.sample_count, film.seconds,
            film.threads, film.seconds > 0 ? film.sample_count / film.seconds / film.threads : 0.0,
            png_path[0] ? ", wrote " : "", png_path, exr_path[0] ? " " : "", exr_path);
    if (film.nonfinite)
        fprintf(stderr, "warning: %lld non-finite samples were dropped (counted as black)\n", film.nonfinite);
    else
        fprintf(stderr, "non-finite samples: 0\n");
    plm_film_free(&film);
    plm_scene_free(&scene);
    return status ? status : (film.interrupted ? 130 : 0);
}
