#ifndef SPARSELENS_IMAGE_H
#define SPARSELENS_IMAGE_H
/* Pictures through cairo (src/base/canvas_cairo.c) and camera-model checks through
 * OpenCV (src/base/image_cv.cpp), behind a plain C interface.
 *
 * Canvas: W x H pixels, origin at the top-left pixel corner, x to the right, y down.
 * Coordinates are doubles in pixels; drawing is antialiased; text is set in DejaVu Sans
 * (UTF-8: "µm", "°" print). Colours are {r, g, b} in [0, 1]. A picture is written as
 * PNG, or as SVG or PDF (vector) when the file name ends in .svg or .pdf. */
#include <stddef.h>

#include "sparselens/diag.h"

typedef struct img_canvas img_canvas;

img_canvas *img_new(int width, int height, const double bg[3]); /* NULL on allocation failure */
void img_free(img_canvas *c);
int img_width(const img_canvas *c);
int img_height(const img_canvas *c);

void img_line(img_canvas *c, double x0, double y0, double x1, double y1, const double rgb[3],
              double thickness);
/* A dashed line: dashes and gaps of `dash` pixels. */
void img_dashed_line(img_canvas *c, double x0, double y0, double x1, double y1,
                     const double rgb[3], double thickness, double dash);
/* Outline (thickness > 0) or filled disc (thickness <= 0). */
void img_circle(img_canvas *c, double cx, double cy, double r, const double rgb[3],
                double thickness);
void img_rect(img_canvas *c, double x0, double y0, double x1, double y1, const double rgb[3],
              double thickness);
/* A small filled dot blended over the canvas with opacity alpha (spot diagrams draw
 * thousands of them; alpha shows where they pile up). */
void img_dot(img_canvas *c, double x, double y, double radius, const double rgb[3],
             double alpha);
/* A filled polygon of n points (2 doubles each), blended with opacity alpha. */
void img_polygon(img_canvas *c, const double *xy, int n, const double rgb[3], double alpha);
/* Text with its baseline's left end at (x, y); height is the cap height in pixels. */
void img_text(img_canvas *c, double x, double y, const char *text, double height,
              const double rgb[3]);
/* Width in pixels of text drawn at that height. */
double img_text_width(const char *text, double height);

/* Writes the picture (PNG; SVG or PDF by the file name's ending) through a temporary
 * file and outfile_commit_path, so no partial file is left. 0 on success. */
int img_write_png(const img_canvas *c, const char *path, lens_err *err);

/* Reads a picture back (tests, checks): its size and the number of pixels that differ
 * from the top-left pixel (0 for a blank picture). 0 on success. */
int img_png_info(const char *path, int *width, int *height, long *nonblank, lens_err *err);

/* Camera-model fits to correspondences between object points and image points.
 * nviews views; view v has counts[v] points; obj holds 3 doubles per point (the
 * object frame of that view), pix 2 doubles per point (pixels, origin top-left),
 * all views concatenated. The intrinsics start from the guess (fx = fy = f_px, the
 * principal point at the image centre) and the principal point stays there; the
 * aspect ratio is 1. */
typedef struct {
    double fx, fy, cx, cy; /* pixels */
    double k[5];           /* Brown-Conrady: k1 k2 p1 p2 k3; fisheye: k1 k2 k3 k4 (k[4] = 0) */
    double rms;            /* reprojection residual, pixels (root mean square over points) */
    double max_err;        /* largest reprojection residual, pixels */
} cv_camera_fit;

/* Brown-Conrady model through cv::calibrateCamera (object points of each view on a plane). */
int cv_fit_brown(int width, int height, double f_px, int nviews, const size_t *counts,
                 const double *obj, const double *pix, cv_camera_fit *fit, lens_err *err);
/* Kannala-Brandt model through cv::fisheye::calibrate (every object point in front of the
 * camera: z > 0 in the camera frame after the view's pose). fix_focal keeps fx = fy =
 * f_px (OpenCV 4.6's fisheye::CALIB_FIX_FOCAL_LENGTH: it fails to converge even on exact
 * synthetic data, so lens-distort leaves the focal length free). */
int cv_fit_fisheye(int width, int height, double f_px, int fix_focal, int nviews,
                   const size_t *counts, const double *obj, const double *pix, cv_camera_fit *fit,
                   lens_err *err);

#endif
