/* The clear-sky model (Preetham, Shirley and Smits 1999) against values
 * worked out from the paper by hand and against daylight measurements: the
 * zenith's luminance, the Perez function's normalisation, the sun's
 * illuminance and reddening, the sky's symmetry about the sun, and the
 * ground below the horizon as the irradiance the sky and sun give it; the
 * sun's place from a time and a place against the almanac's equinox and
 * solstice and the geometry of noon. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <math.h>

#include "common/rng.h"
#include "render/sky.h"

static double sun_solid_angle(void) { return PLM_TWO_PI * (1.0 - cos(0.5 * PLM_SUN_DIAMETER)); }

static plm_sky_model model(double elevation_deg, double azimuth_deg, double turbidity)
{
    plm_light l = plm_light_default(PLM_LIGHT_SKY);
    l.sky.sun_elevation = plm_radians(elevation_deg);
    l.sky.sun_azimuth = plm_radians(azimuth_deg);
    l.sky.turbidity = turbidity;
    plm_sky_model m;
    plm_sky_model_init(&l.sky, &m);
    return m;
}

/* The paper's zenith luminance worked by hand for T = 3 and the sun 30
 * degrees up: chi = (4/9 - 3/120)(pi - 2 pi/3) = 0.439241, tan chi = 0.469886,
 * Yz = (4.0453 * 3 - 4.9710) 0.469886 - 0.2155 * 3 + 2.4192 = 5.1392 kcd/m^2.
 * Looking straight up the Perez ratio is 1: the sky's luminance there is Yz,
 * and its colour is blue. */
static void zenith(void **state)
{
    (void)state;
    assert_double_near(plm_sky_zenith_luminance(3.0, PLM_PI / 3.0), 5139.2, 1.0);
    plm_sky_model m = model(30.0, 40.0, 3.0);
    rgb z = plm_sky_radiance(&m, v3(0, 1, 0));
    assert_double_near(rgb_luminance(z), plm_sky_zenith_luminance(3.0, PLM_PI / 3.0), 1e-3 * 5139.2);
    assert_true(z.b > 1.5 * z.g && z.g > 1.3 * z.r);
}

/* The sun through a clear atmosphere: its illuminance on a surface facing it
 * at the zenith (T = 2) near the measured clear-sky 100-110 klx; less and
 * redder the lower it stands, and less through haze. */
static void sun(void **state)
{
    (void)state;
    double e_zenith = rgb_luminance(plm_sun_radiance(2.0, 0.0)) * sun_solid_angle();
    assert_true(e_zenith > 95000.0 && e_zenith < 112000.0);
    double last_e = INFINITY, last_red = 0.0;
    const double elevations[] = {90.0, 45.0, 20.0, 10.0, 5.0};
    for (int i = 0; i < 5; ++i) {
        rgb s = plm_sun_radiance(2.0, plm_radians(90.0 - elevations[i]));
        double e = rgb_luminance(s) * sun_solid_angle(), red = s.r / s.b;
        assert_true(e < last_e && red > last_red);
        last_e = e, last_red = red;
    }
    assert_true(rgb_luminance(plm_sun_radiance(6.0, 0.0)) < 0.8 * rgb_luminance(plm_sun_radiance(2.0, 0.0)));
    /* The disk's radiance times its solid angle is its irradiance, whatever its drawn size. */
    plm_light l = plm_light_default(PLM_LIGHT_SKY);
    l.sky.sun_size = plm_radians(5.0);
    plm_sky_model m;
    plm_sky_model_init(&l.sky, &m);
    double solid = PLM_TWO_PI * (1.0 - m.cos_sun_radius);
    assert_double_near(m.sun_radiance.g * solid, m.sun_irradiance.g, 1e-9 * m.sun_irradiance.g);
    assert_double_near(m.sun_irradiance.g, plm_sun_radiance(3.0, PLM_PI / 3.0).g * sun_solid_angle(),
                       1e-9 * m.sun_irradiance.g);
}

/* The sky is the same on both sides of the sun's vertical plane, brightest
 * around the sun (the circumsolar glow) and darker 90 degrees from it. */
static void symmetry_and_circumsolar_glow(void **state)
{
    (void)state;
    plm_sky_model m = model(25.0, 70.0, 3.0);
    double az = plm_radians(70.0), el = plm_radians(25.0);
    for (int i = 1; i < 8; ++i) {
        double da = 0.3 * i, e = plm_radians(5.0 + 10.0 * i);
        vec3 a = v3(cos(e) * sin(az + da), sin(e), -cos(e) * cos(az + da));
        vec3 b = v3(cos(e) * sin(az - da), sin(e), -cos(e) * cos(az - da));
        rgb ra = plm_sky_radiance(&m, a), rb = plm_sky_radiance(&m, b);
        assert_double_near(ra.r, rb.r, 1e-9 * ra.r);
        assert_double_near(ra.b, rb.b, 1e-9 * ra.b);
    }
    vec3 near_sun = v3(cos(el + 0.05) * sin(az), sin(el + 0.05), -cos(el + 0.05) * cos(az));
    vec3 across = v3(cos(el) * sin(az + PLM_PI / 2), sin(el), -cos(el) * cos(az + PLM_PI / 2));
    assert_true(rgb_luminance(plm_sky_radiance(&m, near_sun)) > 3.0 * rgb_luminance(plm_sky_radiance(&m, across)));
}

/* Below the horizon lies a Lambertian ground: its radiance is albedo / pi
 * times the irradiance of the sky (integrated here by Monte Carlo over the
 * upper hemisphere, independently of the model's own quadrature) and the sun. */
static void ground_is_lit_by_sky_and_sun(void **state)
{
    (void)state;
    plm_light l = plm_light_default(PLM_LIGHT_SKY);
    l.sky.sun_elevation = plm_radians(40.0);
    l.sky.ground_albedo = rgb_make(0.1, 0.2, 0.3);
    plm_sky_model m;
    plm_sky_model_init(&l.sky, &m);
    plm_rng rng;
    plm_rng_seed(&rng, 5, 5);
    enum { N = 400000 };
    double sum[3] = {0}, sum2[3] = {0};
    for (int i = 0; i < N; ++i) {
        double u1 = plm_rng_uniform(&rng), u2 = plm_rng_uniform(&rng), c = sqrt(u1), s = sqrt(1.0 - u1);
        /* cosine-weighted: irradiance = pi E[L] */
        rgb le = plm_sky_radiance(&m, v3(s * cos(PLM_TWO_PI * u2), c, s * sin(PLM_TWO_PI * u2)));
        double v[3] = {le.r, le.g, le.b};
        for (int k = 0; k < 3; ++k)
            sum[k] += v[k], sum2[k] += v[k] * v[k];
    }
    double albedo[3] = {0.1, 0.2, 0.3}, sun[3] = {m.sun_irradiance.r, m.sun_irradiance.g, m.sun_irradiance.b};
    double ground[3] = {m.ground.r, m.ground.g, m.ground.b};
    for (int k = 0; k < 3; ++k) {
        double mean = sum[k] / N, se = sqrt((sum2[k] / N - mean * mean) / N);
        double e = PLM_PI * mean + sun[k] * sin(plm_radians(40.0));
        double want = albedo[k] / PLM_PI * e, tol = albedo[k] * (4.0 * se + 1e-3 * mean);
        assert_double_near(ground[k], want, tol);
    }
    assert_double_near(plm_sky_radiance(&m, v3(0.0, -1.0, 0.0)).g, m.ground.g, 0.0);
}

static double julian(const char *text)
{
    double jd = 0.0;
    if (!plm_julian_day_parse(text, &jd))
        fail_msg("\"%s\" refused", text);
    return jd;
}

/* J2000.0 is 2000-01-01 12:00 UT, JD 2451545.0, however the offset writes it;
 * malformed or impossible times are refused. */
static void times_parse_to_julian_days(void **state)
{
    (void)state;
    assert_double_near(julian("2000-01-01T12:00Z"), 2451545.0, 1e-9);
    assert_double_near(julian("2000-01-01T14:00+02:00"), 2451545.0, 1e-9);
    assert_double_near(julian("1999-12-31T23:30:00-12:30"), 2451545.0, 1e-9);
    assert_double_near(julian("2024-02-29T00:00Z") - julian("2024-02-28T00:00Z"), 1.0, 1e-9);
    assert_double_near(julian("2026-03-01T00:00Z") - julian("2026-02-28T00:00Z"), 1.0, 1e-9);
    const char *bad[] = {"2026-06-21T09:30",       "2026-06-21 09:30Z", "2026-02-29T10:00Z", "2026-13-01T00:00Z",
                         "2026-06-21T24:00Z",      "2026-06-21T09:60Z", "2026-06-21T09:30+2", "2026-06-21T09:30Zx",
                         "2026-06-21T09:30:61Z", "summer"};
    double jd;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i)
        if (plm_julian_day_parse(bad[i], &jd))
            fail_msg("\"%s\" accepted", bad[i]);
}

static void sun_at(double lat, double lon, const char *time, double *elevation, double *azimuth)
{
    plm_sun_position(plm_radians(lat), plm_radians(lon), julian(time), elevation, azimuth);
    *elevation = plm_degrees(*elevation);
    *azimuth = fmod(plm_degrees(*azimuth) + 360.0, 360.0);
}

/* From the pole the sun's elevation is its declination: 0 at the March
 * equinox (2026-03-20 14:46 UT) and the obliquity, 23.436 degrees, at the
 * June solstice (2026-06-21 08:24 UT), whatever the hour. At Greenwich's
 * noon that day (12:01:36 UT, the equation of time -1.6 min) the sun stands
 * due south at 90 - 51.477 + 23.436 = 61.959 degrees, and the morning and
 * afternoon mirror each other about the meridian, the morning's in the east. */
static void sun_position_from_time_and_place(void **state)
{
    (void)state;
    double e, a, e2, a2;
    sun_at(90.0, 0.0, "2026-03-20T14:46Z", &e, &a);
    assert_double_near(e, 0.0, 0.02);
    sun_at(90.0, 120.0, "2026-06-21T08:24Z", &e, &a);
    assert_double_near(e, 23.436, 0.02);
    sun_at(51.477, 0.0, "2026-06-21T13:01:36+01:00", &e, &a);
    assert_double_near(e, 61.959, 0.05);
    assert_double_near(a, 180.0, 1.0);
    sun_at(51.477, 0.0, "2026-06-21T08:01:36Z", &e, &a);
    sun_at(51.477, 0.0, "2026-06-21T16:01:36Z", &e2, &a2);
    assert_double_near(e, e2, 0.1);
    assert_double_near(a + a2, 360.0, 0.3);
    assert_true(a > 60.0 && a < 120.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(zenith),
        cmocka_unit_test(sun),
        cmocka_unit_test(symmetry_and_circumsolar_glow),
        cmocka_unit_test(ground_is_lit_by_sky_and_sun),
        cmocka_unit_test(times_parse_to_julian_days),
        cmocka_unit_test(sun_position_from_time_and_place),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
