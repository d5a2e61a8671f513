#include "render/colour.h"

#include <math.h>

/* One lobe of the fit: a Gaussian with different widths on either side of its peak. */
static double lobe(double nm, double peak, double below, double above)
{
    double t = (nm - peak) / (nm < peak ? below : above);
    return exp(-0.5 * t * t);
}

void plm_cie_observer(double nm, double *x, double *y, double *z)
{
    *x = 1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7) - 0.065 * lobe(nm, 501.1, 20.4, 26.2);
    *y = 0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1);
    *z = 1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8);
}

rgb plm_xyz_to_srgb(double x, double y, double z)
{
    return rgb_make(3.2404542 * x - 1.5371385 * y - 0.4985314 * z, -0.9692660 * x + 1.8760108 * y + 0.0415560 * z,
                    0.0556434 * x - 0.2040259 * y + 1.0572252 * z);
}

void plm_srgb_to_xyz(rgb c, double xyz[3])
{
    xyz[0] = 0.4124564 * c.r + 0.3575761 * c.g + 0.1804375 * c.b;
    xyz[1] = 0.2126729 * c.r + 0.7151522 * c.g + 0.0721750 * c.b;
    xyz[2] = 0.0193339 * c.r + 0.1191920 * c.g + 0.9503041 * c.b;
}

void plm_blackbody_chromaticity(double kelvin, double *x, double *y)
{
    /* Planck's law up to a constant factor: lambda^-5 / (exp(hc / (lambda k T)) - 1). */
    const double c2 = 1.4387769e-2; /* hc / k, m K */
    double sx = 0.0, sy = 0.0, sz = 0.0;
    for (double nm = 360.0; nm <= 830.0; nm += 1.0) {
        double m = nm * 1e-9, b = pow(m * 1e6, -5.0) / expm1(c2 / (m * kelvin)), cx, cy, cz;
        plm_cie_observer(nm, &cx, &cy, &cz);
        sx += b * cx, sy += b * cy, sz += b * cz;
    }
    *x = sx / (sx + sy + sz);
    *y = sy / (sx + sy + sz);
}
