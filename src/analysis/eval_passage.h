#ifndef SPARSELENS_EVAL_PASSAGE_H
#define SPARSELENS_EVAL_PASSAGE_H
/* The passage part of the fitting-error report (eval_report.c): where the system and
 * the lens disagree on which rays pass, as a share of the light. Each ray weighs
 * cos^4 theta (theta: its angle to the axis at the sensor, from the inputs u, v) times
 * its transmittance (the lens's out_eta where the lens passes it, the system's where
 * only the system does): its share of the irradiance when the rays are uniform in
 * (u, v), as lens-trace --sampling full draws them. Shares are of the light the lens
 * passes, overall and per 1 mm ring of sensor radius. */
#include <stddef.h>
#include <stdio.h>

#include "sparselens/poly.h"
#include "sparselens/table_out.h"

typedef struct {
    double light, fpass, fblock; /* the lens's light, false passes, false blocks */
    size_t rays, passing;        /* rays, and those the lens passes */
} eval_ring;

typedef struct {
    int ix, iy, iu, iv, ieta;    /* inputs x y u v, output out_eta; -1 if absent */
    size_t nring, cap;           /* rings [k, k + 1) mm of sensor radius */
    eval_ring *ring;
    size_t lens_blocked;         /* rays the lens blocks */
} eval_passage;

int eval_passage_init(eval_passage *p, const poly_system *s);
/* One ray, as eval_report_add. 0, or -1 out of memory. */
int eval_passage_add(eval_passage *p, const double *in, const double *pred, int sys_pass,
                     const double *ref, int lens_pass);
/* Into the open key-value table: light_false_pass, light_false_block, light_disagree,
 * the worst ring; then the table "passage_by_ring". When no ray was blocked, only
 * passage_measured 0 (and in text a comment saying how to measure it). */
void eval_passage_write(table_out *t, const eval_passage *p);
int eval_passage_measured(const eval_passage *p);
void eval_passage_free(eval_passage *p);

#endif
