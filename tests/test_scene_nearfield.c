/* Near-field renders, small (docs/nearfield.md): a frame-filling close-up of
 * the pigeon remex at 0.03 mm per pixel shows barbs at the species' spacing
 * and angle (the image's dominant spatial frequency against the species'
 * stream function), and zooming out through the transition keeps the
 * vane's mean colour. Larger versions: slow_scene_nearfield.c. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include "nearfield_render.h"

static void closeup_shows_the_species_barbs(void **state)
{
    (void)state;
    closeup_check_barbs(closeup_species, 96, 8, 0.05, 3.0);
}

static void zooming_out_keeps_the_mean_colour(void **state)
{
    (void)state;
    const double pixels_mm[] = {0.05, 0.2, 0.3};
    closeup_check_zoom(closeup_species, 32, 256, pixels_mm, 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(closeup_shows_the_species_barbs),
        cmocka_unit_test(zooming_out_keeps_the_mean_colour),
    };
    return cmocka_run_group_tests(tests, closeup_setup, closeup_teardown);
}
