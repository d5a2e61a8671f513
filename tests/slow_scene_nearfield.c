/* Near-field renders, larger than the default suite's
 * (test_scene_nearfield.c; docs/nearfield.md): the close-up at 256x256
 * pixels of 0.03 mm with tighter tolerances, and five zoom levels through
 * the transition. */
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
    closeup_check_barbs(closeup_species, 256, 16, 0.02, 1.0);
}

static void zooming_out_keeps_the_mean_colour(void **state)
{
    (void)state;
    const double pixels_mm[] = {0.03, 0.08, 0.15, 0.22, 0.3};
    closeup_check_zoom(closeup_species, 48, 128, pixels_mm, 5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(closeup_shows_the_species_barbs),
        cmocka_unit_test(zooming_out_keeps_the_mean_colour),
    };
    return cmocka_run_group_tests(tests, closeup_setup, closeup_teardown);
}
