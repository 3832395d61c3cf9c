#ifndef SPARSELENS_DISTORT_H
#define SPARSELENS_DISTORT_H
/* Distortion: where real chief rays land compared with an ideal projection, the
 * relative illumination, the distorted image of a regular object grid, and OpenCV's
 * camera models fitted to that mapping. Conventions: imaging.h. */
#include <stdio.h>

#include "sparselens/image.h"
#include "sparselens/imaging.h"
#include "sparselens/projection.h"

typedef struct {
    double field;      /* degrees, or object height mm */
    double h_real;     /* chief-ray image height (sensor y), mm */
    double x_real;     /* chief-ray sensor x (0 for a rotationally symmetric lens), mm */
    double h_ideal;    /* f tan(theta) (infinity), or paraxial magnification x height */
    double dist_pct;   /* 100 (h_real - h_ideal) / h_ideal; 0 on the axis */
    double rel_illum;  /* relative illumination, 1 on the axis */
    double map_pct[PROJ_COUNT]; /* distortion against each ideal projection (infinity) */
    /* No chief ray reaches the sensor (a field past what the model can image): the
     * figures are nan and why says what failed; empty for a field imaged. */
    char why[sizeof(lens_err)];
} distort_row;

/* First-order scale of the ideal image: the paraxial focal length (object at infinity)
 * or the paraxial magnification of the chief ray on the sensor plane (finite object,
 * image height per object height, positive for an inverted real image). */
int distort_scale(const imaging *im, double lambda, double *scale, lens_err *err);

/* The distortion curve and, with ris > 0, the relative illumination
 * (distort_illumination_irradiance, through the lens or the system alike). A field whose
 * chief ray reaches no point of the sensor gets a row of nan with `why` set; the others
 * are computed (0 is returned all the same). */
int distort_curve(const imaging *im, double lambda, const double *field, int nf, int ris,
                  distort_row *rows, lens_err *err);

/* Relative illumination as irradiance: for an object of uniform radiance, the integral
 * of P T cos^4(theta) du dv over every sensor direction that can pass, at the chief
 * ray's point of each row (x_real, h_real) over the same on the axis, on a grid of
 * 8 ris x 8 ris directions traced forward from the sensor; through the system or the
 * exact lens. It is the definition itself (radiance is conserved along each ray), so it
 * holds where a beam does not land where its chief ray does: the flux of a field's beam
 * over the image area of the chief-ray heights, the figure used before, was 16% low at
 * 90 degrees on fisheye-ii. Nothing is inverted, which a system needs too (a meridional
 * system is exact on its axis only to its fit error: an inverted figure came out at 2.4
 * near fisheye-ii's axis). 0, or -1 when no light reaches the axis. */
int distort_illumination_irradiance(const imaging *im, double lambda, int nf, int ris,
                                    distort_row *rows);

/* The projection with the least RMS distortion over the rows with a non-zero field
 * (object at infinity); *rms_pct gets that RMS. */
proj_kind distort_best_mapping(const distort_row *rows, int nf, double *rms_pct);

/* distort_best_mapping of each of nm models (rows m * nf + f) over the fields every
 * model images, so that they are compared on the same ones (a field one model cannot
 * image, its why set, is left out of the others' too). Returns how many fields were
 * left out so (0 for one model), or -1 when out of memory. */
int distort_best_mappings(const distort_row *rows, int nm, int nf, proj_kind *best,
                          double *rms_pct);

/* The grid map: nx x ny points spread evenly over a sensor rectangle 2 half_w x 2 half_h
 * centred on the axis, taken as ideal image points of projection k (focal length or
 * magnification `scale`), traced back to their object (direction or point) and imaged
 * through the model. pts gets 4 doubles per point: ideal x, y, real x, y (NAN when the
 * chief ray fails or the projection has no object there). Returns the number of
 * points with a real image. */
int distort_grid(const imaging *im, double lambda, proj_kind k, double scale, double half_w,
                 double half_h, int nx, int ny, double *pts);

/* OpenCV's models fitted to the grid map made with projection k (object at infinity;
 * points within max_deg of the axis): the object points are the directions of the rays
 * on the plane z = 1 in front of the camera, the image points the real sensor points in
 * pixels of a sensor of width x height pixels over 2 half_w x 2 half_h mm. */
int distort_opencv(const imaging *im, double lambda, int fisheye, proj_kind k, const double *pts,
                   int npts, double scale, double half_w, double half_h, int width, int height,
                   double max_deg, cv_camera_fit *fit, lens_err *err);

/* Grid map picture: the ideal grid in grey and each model's distorted grid (ideal +
 * factor x displacement) in its colour. pts[m] as from distort_grid. */
int distort_write_png(const char *path, const char *title, int nmodels, const char *const *names,
                      const double *const *pts, int nx, int ny, double half_w, double half_h,
                      double factor, lens_err *err);

#endif
