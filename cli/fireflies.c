/* plumage fireflies: how many isolated bright pixels a rendered EXR holds
 * (the share of pixels brighter than RATIO times the median of their 3x3
 * neighbourhood, in luminance), its mean luminance and, given a reference
 * rendered with many more samples, whether the means agree within the noise. */
#include <stdio.h>
#include <stdlib.h>

#include "cli/commands.h"
#include "cli/options.h"
#include "common/image_io.h"
#include "render/film_stats.h"

static int read_rgb(const char *path, plm_image *im)
{
    plm_error err = {{0}};
    if (plm_image_read(path, &im->width, &im->height, &im->channels, &im->pixels, &err) != PLM_OK) {
        fprintf(stderr, "error: %s\n", err.message);
        return 0;
    }
    if (im->channels < 3) {
        fprintf(stderr, "error: %s: %d channels; an RGB image is needed\n", path, im->channels);
        free(im->pixels);
        return 0;
    }
    return 1;
}

int cmd_fireflies(int argc, char **argv)
{
    const char *reference = NULL;
    double ratio = 5.0;
    plm_option opts[] = {
        {"--ratio", PLM_OPT_DOUBLE, &ratio, 0, 1.0, 1e6, NULL, "R",
         "a firefly is brighter than R times its 3x3 neighbourhood's median (default 5)", 0},
        {"--reference", PLM_OPT_STRING, &reference, 0, 0, 0, NULL, "REF.exr",
         "the same scene rendered with many more samples: compare the mean luminance", 0},
    };
    plm_command_help help = {
        "plumage fireflies IMAGE.exr [--reference REF.exr] [--ratio R]",
        "Counts the fireflies of a linear image (a render's EXR): pixels whose luminance is more than R times\n"
        "the median luminance of their 3x3 neighbourhood. Prints the image's mean luminance and, with a\n"
        "reference of the same size, the difference of the means with its standard error (from the pixels'\n"
        "differences) and z = difference / standard error: |z| < 3 means the two agree within the noise.\n"
        "Exit status 0, or 2 on an error."};
    const char *positional[1];
    int n_positional = 0;
    int rc = plm_parse_options(&help, argc, argv, 1, opts, 2, positional, 1, &n_positional);
    if (rc)
        return rc == 1 ? 0 : 2;
    if (n_positional != 1) {
        fprintf(stderr, "error: plumage fireflies needs exactly one image (see --help)\n");
        return 2;
    }
    plm_image im, ref = {0};
    if (!read_rgb(positional[0], &im))
        return 2;
    if (reference && !read_rgb(reference, &ref)) {
        free(im.pixels);
        return 2;
    }
    int status = 0;
    size_t pixels = (size_t)im.width * im.height;
    long long n = plm_count_fireflies(im.pixels, im.width, im.height, im.channels, ratio);
    printf("%s: %dx%d, fireflies (> %g x the 3x3 median): %lld of %zu pixels (%.3f%%)\n", positional[0], im.width,
           im.height, ratio, n, pixels, 100.0 * n / pixels);
    if (!reference) {
        printf("mean luminance %.6g\n", plm_mean_luminance(im.pixels, pixels, im.channels));
    } else if (ref.width != im.width || ref.height != im.height) {
        fprintf(stderr, "error: %s is %dx%d, %s is %dx%d: the sizes must agree\n", reference, ref.width, ref.height,
                positional[0], im.width, im.height);
        status = 2;
    } else {
        plm_mean_comparison c = plm_compare_means(im.pixels, ref.pixels, pixels, im.channels);
        printf("mean luminance %.6g, reference %.6g: difference %+.3g +- %.2g (z = %+.2f, %+.3f%%)\n", c.mean,
               c.reference_mean, c.difference, c.standard_error,
               c.standard_error > 0.0 ? c.difference / c.standard_error : 0.0,
               c.reference_mean != 0.0 ? 100.0 * c.difference / c.reference_mean : 0.0);
    }
    free(im.pixels);
    free(ref.pixels);
    return status;
}
