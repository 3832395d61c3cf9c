#ifndef SPARSELENS_PARAXIAL_H
#define SPARSELENS_PARAXIAL_H
/* First-order (paraxial) optics of a lens_t by y-nu ray traces. Signs and origins as in
 * lens-info(1): z positions are measured along +z (towards the sensor). */
#include "sparselens/lens.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    double lambda;                 /* um */
    int afocal;                    /* no power: efl, bfl, ffl, fnumber are +inf */
    double efl;                    /* effective focal length, mm */
    double bfl;                    /* last surface to rear focal point */
    double ffl;                    /* first surface to front focal point (signed, +z) */
    double fnumber;                /* efl / entrance pupil diameter, object at infinity */
    double entrance_pupil_z;       /* from first surface */
    double entrance_pupil_diameter;
    double exit_pupil_z;           /* from last surface */
    double exit_pupil_diameter;
    int stop_surface;              /* 1-based, as lens-info prints it */
    double total_track;            /* first surface to sensor */
    double sensor_distance;        /* last thickness */
    double focus_distance;         /* object distance (from the first surface, > 0 in front) focused on the sensor; INFINITY */
} paraxial_data;

int paraxial_compute(const lens_t *lens, double lambda_um, paraxial_data *p, lens_err *err);

/* y-nu trace of a paraxial ray (height y, reduced angle nu = n u) from object space
 * (in front of surface 0) to the sensor plane; returns height and nu there. */
void paraxial_trace_forward(const lens_t *lens, const double *n, double y0, double nu0,
                            double *y_out, double *nu_out);

/* The last thickness that focuses an object at distance d (mm in front of the first
 * surface; INFINITY for infinity) on the sensor. */
int paraxial_focus_thickness(const lens_t *lens, double lambda_um, double distance,
                             double *thickness, lens_err *err);

#ifdef __cplusplus
}
#endif

#endif
