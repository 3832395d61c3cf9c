#ifndef SPARSELENS_IMAGING_H
#define SPARSELENS_IMAGING_H
/* The imaging set-up shared by lens-spot and lens-distort: what images (the exact lens,
 * or a polynomial system standing in for its tracing), where the object is, which
 * fields and wavelengths, and where the sensor plane is.
 *
 * Conventions (frame: lens.h, z towards the sensor):
 *  - Field f on the +y side. Object at infinity: f is an angle in degrees and the rays
 *    travel along (0, sin f, cos f); past 90 degrees they come from behind the front
 *    vertex plane (fisheyes). Finite object: f is the height (mm) of the object point
 *    (0, -f, -distance), so that in both cases the image lands on the +y side of the
 *    sensor (a lens maps a ray travelling upwards to a point above the axis).
 *  - Pupil points are positions on the stop surface in mm; rays are aimed through them
 *    (aim_from_object), so the chief ray passes the centre of the stop.
 *  - The sensor plane is the lens file's, moved by sensor_shift mm along +z (focus). A
 *    ray on the sensor is (x, y, u, v) as in trace.h: position, and the tangents of the
 *    reversed direction, so moving the plane by dz moves the point by -dz (u, v). */
#include "sparselens/aim.h"
#include "sparselens/diag.h"
#include "sparselens/lens.h"
#include "sparselens/poly.h"
#include "sparselens/trace.h"

#define IMAGING_MAX_WAVELENGTHS 16
#define IMAGING_MAX_FIELDS 64

typedef struct {
    const lens_t *lens;         /* geometry, ray aiming, and the exact trace */
    const poly_system *sys;     /* non-NULL: the system maps the rays instead of the trace */
    double object_distance;     /* INFINITY, or mm in front of the first vertex */
    double sensor_shift;        /* mm along +z from the lens file's sensor plane */
} imaging;

/* "F,d,C", "0.55,0.6", names and values mixed. Names: the Fraunhofer lines
 * i h g F' F e d D C' C r A' (e.g. d = 0.5875618 um). Values are in um, 0.2..2.5.
 * Returns the count (>= 1), or -1 with err set. */
int wavelengths_parse(const char *spec, double *lambda, int max, lens_err *err);

/* Comma-separated finite numbers (at least one); -1 with err set. */
int numbers_parse(const char *spec, const char *what, double *v, int max, lens_err *err);

/* Refractive indices of the lens at lambda (n[nsurf]); -1 with err set. */
int imaging_indices(const imaging *im, double lambda, double *n, lens_err *err);

/* The object-space ray of field f through stop point (sx, sy): 0 on success, -1 when
 * no such ray reaches the stop (aiming fails). */
int imaging_object_ray(const imaging *im, const double *n, double field, double sx, double sy,
                       lens_ray *r);
/* The same for many stop points of one field: the ray through the stop centre is found
 * once (imaging_aim_prepare, -1 when there is none), then aim_object_to(st, sx, sy, r)
 * gives each ray as imaging_object_ray would, bit for bit, several times faster. */
int imaging_aim_prepare(const imaging *im, const double *n, double field, aim_object_start *st);

/* Images an object-space ray: 1 when it reaches the sensor (s = x, y, u, v on the
 * shifted sensor plane, eta its transmittance), 0 when it is vignetted. With a system,
 * the ray's outer-pupil coordinates are found on the front surface and the sensor ray
 * is solved for (poly_solve.h); guess (may be NULL) seeds that solve. */
int imaging_trace(const imaging *im, const double *n, double lambda, const lens_ray *r,
                  const double *guess, double s[4], double *eta);

/* The seed imaging_trace solves r through the system from: r's exact sensor ray (on
 * the file's plane) where the lens passes it, else guess (NULL: the axis). */
void imaging_seed(const imaging *im, const double *n, const lens_ray *r, const double *guess,
                  double seed[4]);

/* Many object-space rays of one wavelength through the system (im->sys) at once: each
 * used ray's outer-pupil coordinates, then its sensor ray solved for from the seed
 * seeds + i * seed_stride (stride 0: one seed for all; seeds NULL: the axis) by
 * poly_solve_sensor_batch in at most max_iter steps, the rays in parallel blocks. ok[i] is 1 where use[i] (NULL:
 * every ray), the solve succeeds and the system passes the ray; then s[4 i ..] is its
 * sensor ray on the file's plane (not shifted: the caller shifts, as imaging_trace
 * does) and eta[i] (eta may be NULL) its transmittance. blocked[i] (blocked may be
 * NULL) is 1 where the solve succeeds and the system blocks the ray: vignetted, not
 * lost to Newton. Returns 0, or -1 when memory runs out. */
int imaging_system_batch(const imaging *im, double lambda, size_t n, const lens_ray *rays,
                         const int *use, const double *seeds, size_t seed_stride,
                         int max_iter, double *s, double *eta, int *ok, int *blocked);

/* The chief ray of field f: 0 and its sensor ray, or -1 with err set naming the field
 * ("field 95 deg: no chief ray through the stop reaches the sensor"). */
int imaging_chief(const imaging *im, const double *n, double lambda, double field, double s[4],
                  lens_err *err);

/* Largest field (degrees, or object height for a finite object) whose chief ray still
 * reaches the sensor, searched up to limit; -1 with err set if even the axis fails. */
int imaging_max_field(const imaging *im, double lambda, double limit, double *field,
                      lens_err *err);

/* The sensor shift that focuses the lens paraxially at lambda (paraxial_focus_thickness
 * minus the file's last thickness). */
int imaging_paraxial_shift(const lens_t *lens, double object_distance, double lambda,
                           double *shift, lens_err *err);

/* What a command was given: a lens (any format lens_load reads) or a .poly system
 * (name ending in .poly; its lens from lens_path, else the path recorded in it), and
 * optionally a system to show beside the lens (compare). */
typedef struct {
    lens_t lens;
    poly_system *sys;     /* the input was a system */
    poly_system *compare; /* --compare */
} imaging_models;

int imaging_models_load(const char *path, const char *compare, const char *lens_path,
                        const lens_load_options *lopt,
                        imaging_models *m, lens_err *err);
void imaging_models_free(imaging_models *m);
/* Fills im[] and names[] ("lens", "poly") for the models given; returns their count. */
int imaging_models_setup(const imaging_models *m, double object_distance, imaging im[2],
                         const char *names[2]);

/* Default fields when none are given (field holds IMAGING_MAX_FIELDS): the design
 * file's own (lens_file_fields), else 0, 0.7 and 1 times the largest field (object at
 * infinity: the half field of view of the sensor diagonal from the lens header, clipped
 * to the largest field whose chief ray passes at every one of the nl wavelengths).
 * Ascending, the largest last. Returns the count, or -1 with err set. */
int imaging_default_fields(const imaging *im, const double *lambda, int nl, double *field,
                           lens_err *err);

#endif
