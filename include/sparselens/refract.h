#ifndef SPARSELENS_REFRACT_H
#define SPARSELENS_REFRACT_H
/* Refraction at an interface: vector Snell's law and unpolarised Fresnel transmittance. */

/* Refracts the unit direction d at a surface with unit normal nrm (either orientation)
 * from index n1 into n2. Returns 0 and writes the refracted unit direction to out
 * (may alias d) and the unpolarised Fresnel transmittance to *T; returns -1 for total
 * internal reflection (out and *T untouched). */
int refract(const double d[3], const double nrm[3], double n1, double n2, double out[3],
            double *T);

/* Unpolarised Fresnel reflectance R and transmittance T (the mean of s and p) for the
 * cosines cos_i, cos_t (both >= 0) of the incident and refracted angles. T is computed
 * from the amplitude transmission coefficients, R from the reflection coefficients,
 * so R + T = 1 is a check, not an identity of the code. */
void fresnel_unpolarised(double n1, double n2, double cos_i, double cos_t, double *R, double *T);

#endif
