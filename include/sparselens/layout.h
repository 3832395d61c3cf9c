#ifndef SPARSELENS_LAYOUT_H
#define SPARSELENS_LAYOUT_H
/* The meridional section of a lens (the y-z plane, frame: lens.h): each element's outline
 * from its surfaces' real sags (aspheres included) and flat edges, the stop, the sensor,
 * the axis, and fans of rays in the meridional plane per field, traced surface by surface
 * (a vignetted ray is drawn to the surface that stops it). A fitted system has no inside:
 * its rays are drawn from the sensor back to the rear vertex, over the lens's.
 * The drawing is a list of polylines in mm, written as SVG (exact coordinates) or PNG. */
#include "sparselens/imaging.h"

typedef enum {
    LAYOUT_ELEMENT, /* closed outline of a glass element, filled */
    LAYOUT_STOP,    /* the stop's blades */
    LAYOUT_SENSOR,
    LAYOUT_AXIS,
    LAYOUT_RAY,     /* a lens ray, coloured by its field */
    LAYOUT_SYSTEM   /* a system's image-space ray */
} layout_kind;

typedef struct {
    layout_kind kind;
    int field;      /* rays: the field's index */
    int n;
    double *zy;     /* n points (z, y), mm */
} layout_line;

typedef struct {
    layout_line *line;
    int nlines, cap;
    double zmin, zmax, ymin, ymax; /* extent of everything drawn */
    int nfields;
    const double *field;
    int finite;                    /* fields are object heights */
    const char *title;
    /* what the text output reports */
    int rays, passed;              /* lens rays launched and reaching the sensor */
    double system_diff;            /* largest sensor distance between the system's and the
                                      lens's rays, mm (NAN without a system) */
    double seconds[2];             /* imaging the rays: lens, system */
    double span[IMAGING_MAX_FIELDS][2]; /* per field, the normalised stop points (py) the
                                           rays were spread over, lowest and highest */
} layout_drawing;

/* Builds the drawing of model lens_im's lens, with nrays rays per field through the
 * stop's meridian at lambda, and the same rays through sys_im's system (may be NULL)
 * but for the fields f with sys_skip[f] set (sys_skip may be NULL: none; a field the
 * system cannot image). The rays are spread evenly over the part of the meridian whose
 * rays reach the sensor (the vignetted bundle a designer draws: the run of passing stop
 * points around the chief ray, its ends found to 1e-6 of the stop's radius), or with
 * full_stop over the whole meridian, stopped rays drawn up to the surface that stops
 * them. At most IMAGING_MAX_FIELDS fields. -1 with err set. */
int layout_build(const imaging *lens_im, const imaging *sys_im, const unsigned char *sys_skip,
                 const double *field, int nf, double lambda, int nrays, int full_stop, layout_drawing *d,
                 lens_err *err);
void layout_free(layout_drawing *d);

/* Writes the drawing: SVG in mm (y up on the page), or PNG width pixels wide. */
int layout_write_svg(const layout_drawing *d, const char *path, lens_err *err);
int layout_write_png(const layout_drawing *d, const char *path, int width, lens_err *err);

/* The colour of field f of nf (shared by both writers). */
void layout_field_rgb(int f, double rgb[3]);

#endif
