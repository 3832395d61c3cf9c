#ifndef SPARSELENS_INFO_RUN_H
#define SPARSELENS_INFO_RUN_H
/* lens-info as library calls: the lens prepared as the options say (sensor size,
 * refocusing), then its first-order data. The command only loads, calls and prints. */
#include <stdio.h>

#include "sparselens/info_cli.h"
#include "sparselens/paraxial.h"

typedef struct {
    paraxial_data p;
    double lambda;               /* um */
    int have_sensor;             /* the lens (or --sensor) gives a sensor size */
    double sensor_w, sensor_h;   /* mm */
    double sensor_radius;        /* half the sensor diagonal, mm */
    double field_of_view_deg;    /* full angle of the chief ray at image_circle_radius */
    double image_circle_radius;  /* the sensor radius, or the image circle's where the
                                    sensor corners reach past it */
    /* What a designer would question, one line each (without "lens-info: warning: "):
     * an afocal lens, no sensor size, a sensor past the image circle, a focal length or
     * f-number more than 5 % from the header's, a focus distance that is negative or not
     * at infinity. */
    int nwarnings;
    char warnings[8][400];
} info_report;

/* Applies --sensor and --focus to the lens: refocusing sets the last thickness so that an
 * object at o->focus is sharp (paraxially, at o->lambda) and replaces the notes about the
 * focus. Returns 1 when the lens is to be printed as a lens (--format lens or --focus),
 * 0 when as keys, -1 with err set. */
int info_prepare(const info_cli *o, lens_t *lens, lens_err *err);

/* First-order data of the lens at o->lambda, and its field of view where it has a sensor
 * size. 0, or -1 with err set. */
int info_run(const info_cli *o, const lens_t *lens, info_report *rep, lens_err *err);

/* lens-info --seidel: the paraxial ray table and the Seidel sums (seidel.h) at o->lambda
 * for the chief ray at o->seidel_field, or half rep's field of view; as tables, or JSON.
 * 0, or -1 with err set. */
int info_seidel_print(FILE *f, const lens_t *lens, const info_cli *o, const info_report *rep, lens_err *err);

/* The report as "key value unit" lines, or as JSON (lens-info(1)). */
void info_report_print(FILE *f, const lens_t *lens, const info_report *rep, const output_cli *out);

#endif
