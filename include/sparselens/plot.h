#ifndef SPARSELENS_PLOT_H
#define SPARSELENS_PLOT_H
/* Line plots on an image.h canvas, for the designer analyses' pictures (ray fans,
 * field curves, MTF): a panel maps data coordinates to pixels, draws its frame, round
 * ticks and labels, and polylines that break at NAN. y grows upwards in data units. */
#include "sparselens/image.h"

typedef struct {
    img_canvas *c;
    double x0, y0, w, h;          /* pixel rectangle of the plotting area */
    double xmin, xmax, ymin, ymax;
} plot_panel;

/* A colour per wavelength: hue from violet (0.40 um) to red (0.70 um), darkened to read
 * on white; grey outside the visible range. */
void plot_lambda_rgb(double lambda, double rgb[3]);

/* A round step (1, 2 or 5 times a power of ten) near x. */
double plot_nice(double x);

/* The finite range of n values widened by 5 % (and to a small span around a constant);
 * symmetric makes it symmetric about 0. Empty data gives -1 .. 1. */
void plot_range(const double *v, int n, int symmetric, double *lo, double *hi);

/* Draws the frame, grid, ticks, tick labels, the zero lines when inside, the title above
 * and the axis labels. */
void plot_axes(const plot_panel *p, const char *title, const char *xlabel, const char *ylabel);

/* Text with its baseline's left end at (x, y), at most width pixels wide: the height
 * shrinks (down to 60 %, then the text is cut with an ellipsis) rather than running off
 * the picture. */
void plot_title(img_canvas *c, double x, double y, double width, const char *text, double height,
                const double rgb[3]);

/* Pixel coordinates of a data point. */
double plot_px(const plot_panel *p, double x);
double plot_py(const plot_panel *p, double y);

/* A polyline through (x[i], y[i]), broken at NAN values, clipped to the panel. */
void plot_line(const plot_panel *p, const double *x, const double *y, int n, const double rgb[3],
               double thickness);
/* Small dots at the points (a second model drawn over the first's lines). */
void plot_dots(const plot_panel *p, const double *x, const double *y, int n, const double rgb[3],
               double radius);

/* One legend entry at pixel (x, y): a short line in the colour and the text; returns the
 * x after it. */
double plot_legend(img_canvas *c, double x, double y, const double rgb[3], int dots, const char *text);
/* A legend entry per wavelength (um), in its colour (plot_lambda_rgb), from pixel (x, y);
 * returns the x after the last. */
double plot_legend_lambdas(img_canvas *c, double x, double y, const double *lambda, int nl);

#endif
