#ifndef SPARSELENS_POLY_SOLVE_H
#define SPARSELENS_POLY_SOLVE_H
/* Object to sensor through a polynomial system. A system maps a sensor ray
 * (x, y, u, v, lambda) to the outer pupil (out_x, out_y, out_u, out_v); imaging an
 * object-space ray means inverting that map: Newton's method on poly_eval_jacobian
 * for the sensor ray whose outer-pupil image is the given one. */
#include "sparselens/diag.h"
#include "sparselens/poly.h"

/* Checks that sys has inputs x y u v lambda and outputs out_x out_y out_u out_v (any
 * order, by name); -1 with err set otherwise. */
int poly_solve_check(const poly_system *sys, lens_err *err);

/* Solves for sensor[4] = (x, y, u, v) with sys(sensor, lambda) = outer. guess (may be
 * NULL: the axis) seeds Newton. Returns 0 when the residual falls below 1e-9 (1 + |outer x, y|)
 * (mm and tangent units), or when Newton stalls within 10x the held-out error the system
 * records for out_x..out_v (a meridional system is that discontinuous at the axis), -1
 * otherwise; *pass (may be NULL) gets the system's passage test at
 * the solution, *eta (may be NULL) its out_eta output or 1 when it has none. */
int poly_solve_sensor(const poly_system *sys, double lambda, const double outer[4],
                      const double *guess, double sensor[4], int *pass, double *eta);

/* poly_solve_sensor for n rays at once, each as that function solves it (the same steps
 * and acceptance, values to 1e-12: the rays still iterating are evaluated together by the
 * batch kernel at each step), in at most max_iter Newton steps (<= 0 or more than
 * poly_solve_sensor's 60: 60). Ray i: wavelength lambda[i], target outer[4 i .. 4 i + 3],
 * seed guess + i * guess_stride (guess NULL: the axis; stride 0: one seed for all);
 * status[i] 0 (solved) or -1, sensor[4 i ..] the last iterate either way, pass[i] and
 * eta[i] (each may be NULL) the passage test and out_eta (1 without it) at a solution, 0
 * and 1 otherwise. Returns 0, or -1 when the system lacks the inputs or outputs or memory
 * runs out (nothing written to status then). */
int poly_solve_sensor_batch(const poly_system *sys, size_t n, const double *lambda,
                            const double *outer, const double *guess, size_t guess_stride,
                            int max_iter, double *sensor, int *status, unsigned char *pass,
                            double *eta);

#endif
