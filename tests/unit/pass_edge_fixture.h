/* Rays on the edge of a pass circle, where the pass test of a framed system must take
 * the frame's values, before the pair turns back (poly_eval_part), in every path: out_x
 * is the sensor radius r = EDGE_R0 and out_y is 0 in the frame, and the circle's radius
 * is the double just below EDGE_R0, whose square is 2 units in the last place below
 * EDGE_R0^2. The frame's values fail; the turned ones, (c r, s r), land that far inside
 * for about 4 % of the angles, by their rounding: edge_rays keeps those. Used by
 * test_poly_pass (liblens's paths) and test_poly_emit (the emitted C). */
#ifndef PASS_EDGE_FIXTURE_H
#define PASS_EDGE_FIXTURE_H

#include <math.h>

#include "poly_fixture.h"
#include "sparselens/poly.h"

#define EDGE_R0 7.25

/* out_x = x, with terms that vanish on the edge rays (u = v = 0, lambda at its offset)
 * so that the one-ray path builds its vector form (poly_fast.c); out_y likewise 0;
 * out_u, out_v, out_eta without terms. plan: one term of degree 16 more, which poly_fast
 * declines (powers up to 15), so that poly_eval runs the plan and poly_frame.c. NULL if
 * a step fails. */
static inline poly_system *edge_system(int plan)
{
    poly_system *s = poly_new("edge", 5, fixture_inputs, 5, fixture_outputs);
    const int ex[5] = {1, 0, 0, 0, 0}, eu2[5] = {0, 0, 2, 0, 0}, exl[5] = {1, 0, 0, 0, 1};
    const int ev[5] = {0, 0, 0, 1, 0}, eul[5] = {0, 0, 1, 0, 2}, ev3[5] = {1, 0, 0, 3, 0};
    const int ev16[5] = {0, 0, 0, 16, 0};
    if (!s || poly_add_part(s, 0, INFINITY) != 0 || poly_add_term(s, 0, 0, ex, 1) != 0 ||
        poly_add_term(s, 0, 0, eu2, 0.3) != 0 || poly_add_term(s, 0, 0, exl, -0.2) != 0 ||
        poly_add_term(s, 0, 1, ev, 0.7) != 0 || poly_add_term(s, 0, 1, eul, 0.1) != 0 ||
        poly_add_term(s, 0, 1, ev3, 0.05) != 0 ||
        (plan && poly_add_term(s, 0, 1, ev16, 0.01) != 0) ||
        poly_set_frame(s, POLY_FRAME_MERIDIONAL) != 0 ||
        poly_add_pass_circle(s, 0, 1, nextafter(EDGE_R0, 0)) != 0) {
        poly_free(s);
        return NULL;
    }
    poly_set_scaling(s, 4, 0.55, 1); /* lambda 0.55: its monomials are 0 */
    return s;
}

/* n edge rays (inputs x y u v lambda) that a test on the turned values would pass, into
 * in; how many it found (n unless the sweep of angles ran out). */
static inline int edge_rays(double *in, int n)
{
    const double rr = nextafter(EDGE_R0, 0) * nextafter(EDGE_R0, 0);
    int found = 0;
    for (int k = 0; found < n && k < 1000000; k++) {
        const double t = 6.283185307179586 * k / 1e6;
        double *ray = in + 5 * found;
        ray[0] = EDGE_R0 * cos(t);
        ray[1] = EDGE_R0 * sin(t);
        ray[2] = ray[3] = 0;
        ray[4] = 0.55;
        const double r = sqrt(ray[0] * ray[0] + ray[1] * ray[1]), ir = 1 / r;
        const double c = ray[0] * ir, sn = ray[1] * ir, a = c * r, b = sn * r;
        found += r == EDGE_R0 && a * a + b * b <= rr;
    }
    return found;
}

#endif
