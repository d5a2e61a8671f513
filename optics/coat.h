/* A glossy coat over a diffuse base: a smooth-to-rough dielectric
 * interface (GGX microfacets, Smith height-correlated masking, exact
 * dielectric Fresnel) reflecting specularly, over a Lambertian base that
 * receives the light the coat transmits and returns it through the coat
 * again: f = f_GGX + (1 - F(cos_o)) (1 - F(cos_i)) albedo / pi. The base
 * term leaves out the light the coat reflects back down (a small gain
 * at most), so the sum never exceeds 1: tests/test_coat.c checks the
 * white furnace. Bills, eyes and feet wear it (docs/birds.md). */
#ifndef PLUMAGE_OPTICS_COAT_H
#define PLUMAGE_OPTICS_COAT_H

#include "optics/bsdf.h"

typedef struct plm_coat {
    rgb albedo;   /* the base's, each channel in [0, 1] */
    double alpha; /* the coat's GGX roughness, [0.01, 1] */
    double eta;   /* its index of refraction over the outside's, > 1 */
} plm_coat;

/* Fills out with the coat's BSDF for view direction wo about the unit
 * normal n (on wo's side of the surface). */
void plm_coat_bsdf(const plm_coat *coat, vec3 n, vec3 wo, plm_bsdf *out);

/* Unpolarised Fresnel reflectance of a dielectric for cos_i in [0, 1] from the outside. */
double plm_fresnel_dielectric(double cos_i, double eta);

#endif
