/* Colorimetry the sky and the film share: the CIE 1931 standard observer,
 * CIE XYZ <-> linear sRGB (D65), and the chromaticity of a blackbody. */
#ifndef PLUMAGE_RENDER_COLOUR_H
#define PLUMAGE_RENDER_COLOUR_H

#include "common/vec.h"

/* The CIE 1931 2-degree colour matching functions at a wavelength in nm, by
 * Wyman, Sloan and Shirley's multi-lobe fit (JCGT 2013). */
void plm_cie_observer(double nm, double *x, double *y, double *z);

rgb plm_xyz_to_srgb(double x, double y, double z);
void plm_srgb_to_xyz(rgb c, double xyz[3]);

/* The chromaticity (x, y) of a blackbody at kelvin: Planck's law weighted by
 * the observer over 360-830 nm. */
void plm_blackbody_chromaticity(double kelvin, double *x, double *y);

#endif
