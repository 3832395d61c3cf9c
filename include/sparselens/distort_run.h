#ifndef SPARSELENS_DISTORT_RUN_H
#define SPARSELENS_DISTORT_RUN_H
/* lens-distort as a library call (the command only parses arguments and prints). */
#include <stdio.h>

#include "sparselens/distort.h"
#include "sparselens/spot_run.h"
#include "sparselens/table_out.h"

typedef struct {
    imaging im[2];              /* the lens, and optionally a system beside it */
    const char *model_names[2];
    int nmodels;
    const double *field;
    int nfields;
    double lambda;
    focus_mode focus;
    int illum_rays;             /* N x N rays per bundle; 0: no relative illumination */
    int grid;                   /* grid map points per side; 0: no grid map */
    int mapping;                /* proj_kind of the grid, or -1: the best one */
    double sensor_w, sensor_h;  /* mm; NAN: the lens header's, else from the largest field */
    int cv_width, cv_height;    /* pixels for the OpenCV fits; 0: none */
} distort_request;

typedef struct {
    int nmodels, nfields, finite;
    distort_row *rows;          /* m * nfields + f */
    int not_imaged;             /* rows of fields a model cannot image (their why is set) */
    double scale;               /* focal length, or magnification (finite object) */
    double sensor_shift;
    proj_kind best[2];
    double best_rms[2];
    int best_left_out;          /* fields a model does not image, left out of every model's
                                   best mapping so that they are compared on the same ones */
    proj_kind mapping;          /* of the grid */
    double sensor_w, sensor_h;
    int grid;
    double *pts[2];             /* grid map per model (distort_grid), or NULL */
    int fit_ok[2][2];           /* [model][0 brown, 1 fisheye] */
    cv_camera_fit fit[2][2];
    char fit_msg[2][2][sizeof(lens_err)];
} distort_report;

int distort_run(const distort_request *rq, distort_report *rep, lens_err *err);
void distort_report_free(distort_report *rep);
/* "MODEL: why; its row is nan" for each field not imaged (at most max) into w[]. */
int distort_report_warnings(const distort_request *rq, const distort_report *rep,
                            report_warning *w, int max);
/* The table "distortion", then (text) comment lines, or (JSON) tables "ideal",
 * "best_mapping" and "opencv": focal length, best mappings, OpenCV fits. */
void distort_report_print(table_out *t, const distort_request *rq, const distort_report *rep);
/* The grid displacement field as text. */
void distort_report_write_map(FILE *f, const char *input, const distort_request *rq,
                              const distort_report *rep);
/* The picture factor that draws the largest displacement at about a tenth of the half
 * width, rounded to 1, 2 or 5 x 10^k, at least 1. */
double distort_auto_factor(const distort_report *rep);

#endif
