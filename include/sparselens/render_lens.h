#ifndef SPARSELENS_RENDER_LENS_H
#define SPARSELENS_RENDER_LENS_H
/* The two lens maps the renderer can use (render.h's render_map_fn): exact tracing
 * through a lens_t, or a polynomial system evaluated to the outer pupil (inputs x y u v
 * [lambda], outputs out_x out_y out_u out_v [out_eta]) and turned into a ray on the
 * front element of the lens it was fitted to. */
#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/poly.h"
#include "sparselens/render.h"

typedef struct render_lens_ctx render_lens_ctx;

/* Both keep pointers to lens (and sys): they must outlive the camera. sensor_w/h in mm. */
render_lens_ctx *render_lens_exact(const lens_t *lens, double sensor_w, double sensor_h,
                                   render_camera *cam, lens_err *err);
/* A system without a lambda input is used at every wavelength (fitted for grey scenes). */
render_lens_ctx *render_lens_poly(const poly_system *sys, const lens_t *lens, double sensor_w,
                                  double sensor_h, render_camera *cam, lens_err *err);
void render_lens_free(render_lens_ctx *c);

/* An aperture of blades (0: the stop's circle; 3 .. RENDER_MAX_BLADES): the regular
 * polygon inscribed in the stop's circle, its vertices at angles rotation + k 2 pi /
 * blades (radians, from +x of the lens frame), tested where each ray meets the stop (exact:
 * traced there; a system: its ap_x ap_y outputs, which it must have). The line pupil
 * of the circle still covers every passing direction. 0, or -1 with err. */
#define RENDER_MAX_BLADES 16
int render_lens_set_blades(render_lens_ctx *c, int blades, double rotation, lens_err *err);

/* Applies the scene's focus distance (mm in front of the front vertex, INFINITY) by the
 * paraxial last thickness, and its f-stop by the stop's semi-diameter; NAN leaves the
 * lens as it is. */
int render_lens_setup(lens_t *lens, double focus, double fstop, lens_err *err);

#endif
