#ifndef SPARSELENS_CAMERA_H
#define SPARSELENS_CAMERA_H
/* A lens camera for a renderer (camera.c): camera samples in, rays in scene space out,
 * with the weight of the supplement's Eq. 13, through the exact lens or a polynomial
 * system, many at a time.
 *
 * A sample is (sx, sy, lambda, r1, r2): the point on the sensor as a fraction of its
 * width and height ((0, 0) the top-left corner of the picture, as scene.h), the
 * wavelength in um, and two uniforms in [0, 1) for the direction, drawn from the line
 * pupil (render.h's pupil sampler, built from the exact lens over [lambda_min,
 * lambda_max]) by a map smooth in both (render_sampler_sample_2d), so that stratified
 * uniforms give stratified directions. A ray is (org[3], dir[3], weight, pdf) in the scene frame of scene.h
 * (mm, the front vertex at the origin, looking along +z): org on the front element, dir
 * a unit vector into the scene, weight = P_a T_r cos^4(theta) / p(u, v) (0 when the lens
 * blocks it), pdf = p(u, v) per du dv. A pixel's value is the mean over its samples of
 * weight times the radiance arriving at org from the scene along -dir: the mean
 * irradiance over the pixel, as lens-render computes it.
 *
 * Everything here is read-only after lens_camera_new: any number of threads may call
 * lens_camera_rays at once. */
#include <stddef.h>
#include <stdio.h>

#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/poly.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lens_camera lens_camera;

/* sys NULL: exact tracing through lens; else the system (fitted to lens: inputs x y u v
 * [lambda], outputs out_x out_y out_u out_v [out_eta]). lens and sys must outlive the
 * camera. A system fitted to another lens (poly_lens_mismatch) is refused. Sensor size
 * in mm, centred on the axis. NULL with err on failure. */
lens_camera *lens_camera_new(const lens_t *lens, const poly_system *sys, double sensor_w,
                             double sensor_h, double lambda_min, double lambda_max,
                             lens_err *err);
void lens_camera_free(lens_camera *c);

#define LENS_CAMERA_SAMPLE 5 /* sx sy lambda r1 r2 */
#define LENS_CAMERA_RAY 8    /* org[3] dir[3] weight pdf */

/* n samples (rows of LENS_CAMERA_SAMPLE) to n rays (rows of LENS_CAMERA_RAY); a blocked
 * ray has weight 0 (and org, dir NAN). Returns the number of rays with weight > 0. The
 * polynomial backend evaluates the rays in vector blocks. */
size_t lens_camera_rays(const lens_camera *c, size_t n, const double *samples, double *rays);

/* One sample to one ray, as lens_camera_rays: returns the weight (0 when the lens blocks
 * the ray, and org, dir NAN). */
double lens_camera_ray(const lens_camera *c, double sx, double sy, double lambda, double r1,
                       double r2, double org[3], double dir[3]);

/* An aperture of blades (0: the stop's circle; 3 .. 16): the regular polygon inscribed
 * in the stop's circle, its vertices at angles rotation + k 2 pi / blades (radians, from
 * +x of the lens frame), tested where each ray meets the stop (a system needs its
 * outputs ap_x ap_y). 0, or -1 with err. Not while another thread calls
 * lens_camera_rays. */
int lens_camera_set_blades(lens_camera *c, int blades, double rotation, lens_err *err);

/* The camera as one self-contained C file a renderer compiles in (camera_emit.c): the
 * system sys fitted to lens (its passage included), a line pupil of boxes probed from
 * the system, the aperture's blades (0: the stop's circle, as lens_camera_set_blades),
 * the front element and the weight, behind
 *   double NAME_ray(double sx, double sy, double lambda, double r1, double r2,
 *                   double org[3], double dir[3])
 * with the meanings of lens_camera_rays (it returns the weight), and
 *   size_t NAME_rays(size_t n, const double *samples, double *rays)
 * with the rows and the return value of lens_camera_rays, the system evaluated in
 * blocks by its vectorised batch function. Its line pupil is coarser than the
 * library's (fewer rays pass), the estimate the same. 0, or -1 with err (a NAME
 * that cannot prefix the module's symbols (text_c_prefix_ok, escape.h), a system
 * without the camera's inputs, blades without ap_x ap_y). Every external symbol begins
 * with NAME; the file compiles as C11 or C++, its functions with C linkage. */
int lens_camera_emit(FILE *f, const lens_t *lens, const poly_system *sys, double sensor_w,
                     double sensor_h, int blades, double rotation, const char *name,
                     lens_err *err);
/* The module's header: NAME_ray and NAME_rays declared, extern "C" in C++. */
int lens_camera_emit_header(FILE *f, const lens_t *lens, const char *name, lens_err *err);

#ifdef __cplusplus
}
#endif

#endif
