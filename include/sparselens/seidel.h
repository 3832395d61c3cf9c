#ifndef SPARSELENS_SEIDEL_H
#define SPARSELENS_SEIDEL_H
/* The third-order view of a lens: the paraxial marginal and chief rays surface by
 * surface, and the Seidel sums S_I..S_V each surface contributes, object at infinity.
 *
 * Conventions (Welford, "Aberrations of Optical Systems", ch. 7): u is the ray's slope
 * dy/dz (positive rising towards the sensor); n' u' = n u - y (n' - n) c at a surface of
 * curvature c; A = n (u + y c) and Abar the refraction invariants of the marginal and
 * chief rays; H = n (u ybar - ubar y) the Lagrange invariant; D = u'/n' - u/n. Then
 *   S_I = -A^2 y D,  S_II = -A Abar y D,  S_III = -Abar^2 y D,
 *   S_IV = -H^2 c (1/n' - 1/n),  S_V = (Abar / A) (S_III + S_IV),
 * and a conic or even asphere adds, through its quartic departure from the sphere
 * d = k c^3 / 8 + a4, dS_I = 8 (n' - n) d y^4, dS_II = dS_I (ybar / y),
 * dS_III = dS_I (ybar / y)^2, dS_V = dS_I (ybar / y)^3. A positive S_I is
 * undercorrected spherical aberration. The wavefront coefficients follow as
 * W040 = S_I / 8, W131 = S_II / 2, W222 = S_III / 2, W220 = (S_III + S_IV) / 4,
 * W311 = S_V / 2, in mm.
 *
 * The marginal ray enters parallel at the entrance pupil's rim; the chief ray through
 * the entrance pupil's centre at the slope tan(field). Where the marginal ray meets a
 * surface normally (A = 0) S_V is not defined by the formula above: it is 0 there, and
 * counted in s5_undefined when the surface has S_III + S_IV to give it. */
#include "sparselens/lens.h"

typedef struct {
    double y, u;       /* marginal ray: height at the surface, slope after it */
    double ybar, ubar; /* chief ray */
    double n;          /* index after the surface */
    double S[5];       /* S_I .. S_V */
} seidel_surface;

typedef struct {
    double lambda;   /* um */
    double field;    /* degrees: the chief ray's angle in object space */
    double H;        /* Lagrange invariant, mm */
    double y0, ubar0; /* the marginal ray's height and the chief ray's slope entering */
    size_t nsurf;
    seidel_surface *surf; /* nsurf entries */
    double sum[5];
    int s5_undefined; /* surfaces whose S_V was set to 0 because A vanished there */
} seidel_data;

/* The table and sums of lens at lambda (um) for a chief ray at field degrees. -1 with
 * err set (no entrance pupil, an afocal lens, out of memory). */
int seidel_compute(const lens_t *lens, double lambda, double field, seidel_data *s, lens_err *err);
void seidel_free(seidel_data *s);

#endif
