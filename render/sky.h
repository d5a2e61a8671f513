/* A clear sky and its sun, from the analytic daylight model of
 *
 *   A. J. Preetham, P. Shirley, B. Smits, "A Practical Analytic Model for
 *   Daylight", SIGGRAPH 1999,
 *
 * implemented from the paper: the sky's luminance and chromaticity are
 * Perez et al.'s five-parameter function of the view's zenith angle and its
 * angle to the sun, scaled to the zenith values the paper fits to turbidity
 * and the sun's zenith angle; the sun is the extraterrestrial sun's spectral
 * radiance (the paper's appendix) through the paper's Rayleigh, aerosol
 * (Angstrom) and ozone transmittances, a uniform disk of the given angular
 * size. Below the horizon lies a diffuse ground lit by sky and sun.
 *
 * Directions are in the sky's own frame: y the zenith, -z north, +x east.
 * Radiance is linear sRGB in cd/m^2 (luminance) before the light's scale. */
#ifndef PLUMAGE_RENDER_SKY_H
#define PLUMAGE_RENDER_SKY_H

#include "common/vec.h"
#include "render/scene.h"

/* The sun's true angular diameter (0.533 degrees), in radians. */
#define PLM_SUN_DIAMETER 0.0093

typedef struct plm_sky_model {
    double perez[3][5];   /* A..E of Y, x and y */
    double zenith[3];     /* Y at the zenith (cd/m^2), x, y */
    double inv_f0[3];     /* 1 / F(0, theta_s): the zenith's Perez value */
    vec3 sun;             /* unit, toward the sun */
    double cos_sun_radius; /* the disk: directions d with d . sun >= this */
    rgb sun_radiance;     /* uniform over the disk (0 without the disk) */
    rgb sun_irradiance;   /* on a surface facing the sun: the disk's radiance times its solid angle */
    rgb ground;           /* radiance below the horizon */
} plm_sky_model;

void plm_sky_model_init(const plm_sky_params *p, plm_sky_model *m);

/* The sky's radiance along d (unit, sky frame) without the sun's disk; the
 * ground's below the horizon. */
rgb plm_sky_radiance(const plm_sky_model *m, vec3 d);

/* The sky's zenith luminance (cd/m^2) and the sun's luminance and colour,
 * for tests: the paper's zenith formula, and the sun's transmitted
 * spectrum at a sun zenith angle and turbidity (luminance in cd/m^2). */
double plm_sky_zenith_luminance(double turbidity, double sun_zenith);
rgb plm_sun_radiance(double turbidity, double sun_zenith);

/* The sun's place seen from a latitude and longitude (radians, north and
 * east positive) at a Julian date in universal time, from the Astronomical
 * Almanac's low-precision solar coordinates (within 0.01 degrees from 1950
 * to 2050): its elevation above the horizon (negative below it; no
 * refraction) and its azimuth from north toward east. */
void plm_sun_position(double latitude, double longitude, double julian_day, double *elevation, double *azimuth);

/* The Julian date of an ISO 8601 local date and time with its offset from
 * universal time ("2026-06-21T09:30+02:00", seconds optional, "Z" for UT).
 * Returns 0 if the text is not one. */
int plm_julian_day_parse(const char *text, double *julian_day);

#endif
