/* Preetham, Shirley and Smits 1999, "A Practical Analytic Model for
 * Daylight": the sky of its section 3 and appendix A.2, the sun of its
 * appendix A.1 (formulas and data as the paper gives them). */
#include "render/sky.h"

#include "render/colour.h"

#include <math.h>
#include <stdio.h>

/* Luminous efficacy of radiation at 555 nm, lm/W. */
#define PLM_LUMINOUS_EFFICACY 683.0

/* The extraterrestrial sun's spectral radiance, 380 to 750 nm in 10 nm steps,
 * in units of 100 W m^-2 sr^-1 nm^-1 (the paper's appendix, after Iqbal
 * 1983). Over the sun's 6.8e-5 sr and the CIE observer it gives 128 klx,
 * the solar illuminance above the atmosphere (checked by test_sky). */
static const double sun_spectrum[] = {
    165.5, 162.3, 211.2, 258.8, 258.2, 242.3, 267.6, 296.6, 305.4, 300.6, 306.6, 288.3, 287.1,
    278.2, 271.0, 272.3, 263.6, 255.0, 250.6, 253.1, 253.5, 251.3, 246.3, 241.7, 236.8, 232.1,
    228.2, 223.4, 219.7, 215.3, 211.0, 207.3, 202.4, 198.7, 194.3, 190.7, 186.3, 182.6};
#define SUN_SAMPLES ((int)(sizeof sun_spectrum / sizeof sun_spectrum[0]))
#define SUN_SPECTRUM_UNIT 100.0

/* Ozone's absorption coefficient k_o (1/cm) at the same wavelengths: the
 * Chappuis band (the paper's table, after Iqbal 1983); about 0 below 450 nm. */
static const double ozone_absorption[] = {
    0.0,   0.0,   0.0,   0.0,   0.0,   0.0,   0.0,   0.003, 0.006, 0.009, 0.014, 0.021, 0.030,
    0.040, 0.048, 0.063, 0.075, 0.085, 0.103, 0.120, 0.120, 0.115, 0.125, 0.120, 0.105, 0.090,
    0.079, 0.067, 0.057, 0.048, 0.036, 0.028, 0.023, 0.018, 0.014, 0.011, 0.010, 0.009};
_Static_assert(sizeof ozone_absorption == sizeof sun_spectrum, "one ozone coefficient per wavelength");
#define OZONE_CM 0.35 /* the ozone layer's thickness the paper takes */

/* Chromaticity outside sRGB's gamut (a low sun's deep colours) gives a
 * negative channel; light is never negative. */
static rgb positive(rgb c) { return rgb_make(plm_positive(c.r), plm_positive(c.g), plm_positive(c.b)); }

rgb plm_sun_radiance(double turbidity, double sun_zenith)
{
    /* Relative optical mass of the air along the sun's ray (Kasten's formula, as in the paper). */
    double zenith_deg = plm_degrees(sun_zenith);
    double mass = 1.0 / (cos(sun_zenith) + 0.15 * pow(93.885 - zenith_deg, -1.253));
    double beta = 0.04608 * turbidity - 0.04586, alpha = 1.3; /* Angstrom's aerosol turbidity */
    double x = 0.0, y = 0.0, z = 0.0;
    for (int i = 0; i < SUN_SAMPLES; ++i) {
        double nm = 380.0 + 10.0 * i, um = nm / 1000.0;
        double rayleigh = exp(-0.008735 * pow(um, -4.08) * mass);
        double aerosol = exp(-beta * pow(um, -alpha) * mass);
        double ozone = exp(-ozone_absorption[i] * OZONE_CM * mass);
        double l = sun_spectrum[i] * SUN_SPECTRUM_UNIT * rayleigh * aerosol * ozone * 10.0; /* 10 nm bins */
        double cx, cy, cz;
        plm_cie_observer(nm, &cx, &cy, &cz);
        x += cx * l, y += cy * l, z += cz * l;
    }
    return positive(plm_xyz_to_srgb(PLM_LUMINOUS_EFFICACY * x, PLM_LUMINOUS_EFFICACY * y,
                                    PLM_LUMINOUS_EFFICACY * z));
}

double plm_sky_zenith_luminance(double turbidity, double sun_zenith)
{
    double chi = (4.0 / 9.0 - turbidity / 120.0) * (PLM_PI - 2.0 * sun_zenith);
    return 1000.0 * ((4.0453 * turbidity - 4.9710) * tan(chi) - 0.2155 * turbidity + 2.4192); /* kcd -> cd */
}

/* The zenith's chromaticity: [T^2 T 1] M [theta_s^3 theta_s^2 theta_s 1]^T. */
static double zenith_chromaticity(const double m[3][4], double turbidity, double sun_zenith)
{
    double t[3] = {turbidity * turbidity, turbidity, 1.0};
    double s[4] = {sun_zenith * sun_zenith * sun_zenith, sun_zenith * sun_zenith, sun_zenith, 1.0};
    double sum = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j)
            sum += t[i] * m[i][j] * s[j];
    return sum;
}

/* Perez et al.'s sky function, F(theta, gamma) = (1 + A e^(B / cos theta)) (1 + C e^(D gamma) + E cos^2 gamma). */
static double perez(const double c[5], double cos_theta, double gamma, double cos_gamma)
{
    return (1.0 + c[0] * exp(c[1] / fmax(cos_theta, 1e-6))) *
           (1.0 + c[2] * exp(c[3] * gamma) + c[4] * cos_gamma * cos_gamma);
}

/* The sky above the horizon (cd/m^2, linear sRGB): Y, x and y each the
 * zenith's value times F(theta, gamma) / F(0, theta_s). */
static rgb sky_above(const plm_sky_model *m, vec3 d)
{
    double cos_gamma = plm_clamp(v3_dot(d, m->sun), -1.0, 1.0), gamma = acos(cos_gamma);
    double v[3];
    for (int k = 0; k < 3; ++k)
        v[k] = m->zenith[k] * perez(m->perez[k], d.y, gamma, cos_gamma) * m->inv_f0[k];
    double Y = v[0], x = v[1], y = v[2];
    if (!(Y > 0.0 && y > 0.0))
        return rgb_gray(0.0);
    return positive(plm_xyz_to_srgb(x / y * Y, Y, (1.0 - x - y) / y * Y));
}

rgb plm_sky_radiance(const plm_sky_model *m, vec3 d) { return d.y > 0.0 ? sky_above(m, d) : m->ground; }

/* The sky's irradiance on the ground (without the sun's disk): the integral
 * of radiance times cos(theta) over the upper hemisphere, by the midpoint
 * rule in cos^2(theta) (whose measure is cos(theta) d(cos theta) / 2) and phi. */
static rgb sky_irradiance(const plm_sky_model *m)
{
    enum { RINGS = 64, SECTORS = 128 };
    rgb sum = rgb_gray(0.0);
    for (int i = 0; i < RINGS; ++i) {
        double cos_theta = sqrt((i + 0.5) / RINGS), sin_theta = sqrt(1.0 - cos_theta * cos_theta);
        for (int j = 0; j < SECTORS; ++j) {
            double phi = PLM_TWO_PI * (j + 0.5) / SECTORS;
            sum = rgb_add(sum, sky_above(m, v3(sin_theta * sin(phi), cos_theta, -sin_theta * cos(phi))));
        }
    }
    return rgb_scale(sum, PLM_PI / (RINGS * SECTORS)); /* (1/2) d(cos^2) dphi over [0,1] x [0, 2 pi) */
}

void plm_sky_model_init(const plm_sky_params *p, plm_sky_model *m)
{
    double t = p->turbidity, theta_s = PLM_PI / 2.0 - p->sun_elevation;
    const double coefficients[3][5][2] = {
        /* Y */ {{0.1787, -1.4630}, {-0.3554, 0.4275}, {-0.0227, 5.3251}, {0.1206, -2.5771}, {-0.0670, 0.3703}},
        /* x */ {{-0.0193, -0.2592}, {-0.0665, 0.0008}, {-0.0004, 0.2125}, {-0.0641, -0.8989}, {-0.0033, 0.0452}},
        /* y */ {{-0.0167, -0.2608}, {-0.0950, 0.0092}, {-0.0079, 0.2102}, {-0.0441, -1.6537}, {-0.0109, 0.0529}},
    };
    for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 5; ++c)
            m->perez[k][c] = coefficients[k][c][0] * t + coefficients[k][c][1];
    static const double zenith_x[3][4] = {{0.00166, -0.00375, 0.00209, 0.0},
                                          {-0.02903, 0.06377, -0.03202, 0.00394},
                                          {0.11693, -0.21196, 0.06052, 0.25886}};
    static const double zenith_y[3][4] = {{0.00275, -0.00610, 0.00317, 0.0},
                                          {-0.04214, 0.08970, -0.04153, 0.00516},
                                          {0.15346, -0.26756, 0.06670, 0.26688}};
    m->zenith[0] = plm_sky_zenith_luminance(t, theta_s);
    m->zenith[1] = zenith_chromaticity(zenith_x, t, theta_s);
    m->zenith[2] = zenith_chromaticity(zenith_y, t, theta_s);
    for (int k = 0; k < 3; ++k)
        m->inv_f0[k] = 1.0 / perez(m->perez[k], 1.0, theta_s, cos(theta_s));
    double ce = cos(p->sun_elevation);
    m->sun = v3(ce * sin(p->sun_azimuth), sin(p->sun_elevation), -ce * cos(p->sun_azimuth));
    /* The sun keeps its irradiance whatever its drawn size. */
    double true_solid_angle = PLM_TWO_PI * (1.0 - cos(0.5 * PLM_SUN_DIAMETER));
    m->sun_irradiance = p->sun ? rgb_scale(plm_sun_radiance(t, theta_s), true_solid_angle) : rgb_gray(0.0);
    m->cos_sun_radius = cos(0.5 * p->sun_size);
    m->sun_radiance = rgb_scale(m->sun_irradiance, 1.0 / (PLM_TWO_PI * (1.0 - m->cos_sun_radius)));
    /* Below the horizon: Lambertian ground, albedo / pi times the irradiance of sky and sun. */
    m->ground = rgb_gray(0.0);
    rgb e = rgb_add(sky_irradiance(m), rgb_scale(m->sun_irradiance, fmax(m->sun.y, 0.0)));
    m->ground = rgb_scale(rgb_mul(p->ground_albedo, e), 1.0 / PLM_PI);
}

void plm_sun_position(double latitude, double longitude, double julian_day, double *elevation, double *azimuth)
{
    double n = julian_day - 2451545.0; /* days from J2000.0 */
    double mean_longitude = plm_radians(280.460 + 0.9856474 * n), anomaly = plm_radians(357.528 + 0.9856003 * n);
    double ecliptic = mean_longitude + plm_radians(1.915 * sin(anomaly) + 0.020 * sin(2.0 * anomaly));
    double obliquity = plm_radians(23.439 - 0.0000004 * n);
    double right_ascension = atan2(cos(obliquity) * sin(ecliptic), cos(ecliptic));
    double declination = asin(sin(obliquity) * sin(ecliptic));
    double sidereal = plm_radians(fmod(280.46061837 + 360.98564736629 * n, 360.0)); /* Greenwich, mean */
    double hour_angle = sidereal + longitude - right_ascension;
    *elevation = asin(plm_clamp(sin(latitude) * sin(declination) + cos(latitude) * cos(declination) * cos(hour_angle),
                                -1.0, 1.0));
    *azimuth = atan2(-cos(declination) * sin(hour_angle),
                     sin(declination) * cos(latitude) - cos(declination) * cos(hour_angle) * sin(latitude));
}

/* Julian date at 0h UT of a Gregorian calendar date (Meeus, Astronomical Algorithms, ch. 7). */
static double julian_day_of_date(int year, int month, int day)
{
    if (month <= 2)
        year -= 1, month += 12;
    int century = year / 100, gregorian = 2 - century + century / 4;
    return floor(365.25 * (year + 4716)) + floor(30.6001 * (month + 1)) + day + gregorian - 1524.5;
}

int plm_julian_day_parse(const char *text, double *julian_day)
{
    int year, month, day, hour, minute, used = 0;
    double second = 0.0;
    if (sscanf(text, "%4d-%2d-%2dT%2d:%2d%n", &year, &month, &day, &hour, &minute, &used) != 5 || used != 16)
        return 0;
    const char *rest = text + used;
    if (*rest == ':') {
        int more = 0;
        if (sscanf(rest, ":%lf%n", &second, &more) != 1 || !(second >= 0.0 && second < 60.0))
            return 0;
        rest += more;
    }
    double offset = 0.0;
    if (*rest == 'Z') {
        ++rest;
    } else {
        int oh, om, more = 0;
        if ((*rest != '+' && *rest != '-') || sscanf(rest + 1, "%2d:%2d%n", &oh, &om, &more) != 2 || more != 5 ||
            oh > 14 || om > 59)
            return 0;
        offset = (*rest == '-' ? -1.0 : 1.0) * (oh + om / 60.0);
        rest += 1 + more;
    }
    static const int days_in_month[12] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    int leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
    if (*rest || month < 1 || month > 12 || day < 1 || day > days_in_month[month - 1] ||
        (month == 2 && day == 29 && !leap) || hour > 23 || minute > 59)
        return 0;
    *julian_day = julian_day_of_date(year, month, day) + (hour + minute / 60.0 + second / 3600.0 - offset) / 24.0;
    return 1;
}
