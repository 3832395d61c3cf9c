/* Newton inversion of a polynomial system: object-space ray to sensor ray (see
 * poly_solve.h). */
#include "sparselens/poly_solve.h"

#include <math.h>
#include <stdio.h>
#include <string.h>


/* A system's inputs and outputs, at most: the outer pupil and out_eta, and a passage
 * pair for the stop and each of up to 8 surfaces that limit the beam (lens-trace(1)). */
#define SOLVE_MAX_IN 8
#define SOLVE_MAX_OUT 32

static const char *const in_names[5] = {"x", "y", "u", "v", "lambda"};
static const char *const out_names[4] = {"out_x", "out_y", "out_u", "out_v"};

int poly_solve_check(const poly_system *sys, lens_err *err)
{
    for (int i = 0; i < 5; i++)
        if (poly_input_index(sys, in_names[i]) < 0) {
            lens_errf(err, NULL, 0, "the system has no input '%s' (need x y u v lambda)", in_names[i]);
            return -1;
        }
    if (poly_ninputs(sys) != 5) {
        lens_errf(err, NULL, 0, "the system has %d inputs; need exactly x y u v lambda",
                  poly_ninputs(sys));
        return -1;
    }
    for (int i = 0; i < 4; i++)
        if (poly_output_index(sys, out_names[i]) < 0) {
            lens_errf(err, NULL, 0,
                      "the system has no output '%s' (lens-spot and lens-distort need a system "
                      "to the outer pupil)",
                      out_names[i]);
            return -1;
        }
    return 0;
}

/* Solves the 4x4 system a x = b by Gaussian elimination with partial pivoting. */
static int solve4(double a[4][4], double b[4], double x[4])
{
    for (int c = 0; c < 4; c++) {
        int p = c;
        for (int r = c + 1; r < 4; r++)
            if (fabs(a[r][c]) > fabs(a[p][c]))
                p = r;
        if (!(fabs(a[p][c]) > 1e-300))
            return -1;
        if (p != c) {
            for (int k = 0; k < 4; k++) {
                double t = a[c][k];
                a[c][k] = a[p][k];
                a[p][k] = t;
            }
            double t = b[c];
            b[c] = b[p];
            b[p] = t;
        }
        for (int r = c + 1; r < 4; r++) {
            double m = a[r][c] / a[c][c];
            for (int k = c; k < 4; k++)
                a[r][k] -= m * a[c][k];
            b[r] -= m * b[c];
        }
    }
    for (int c = 3; c >= 0; c--) {
        double s = b[c];
        for (int k = c + 1; k < 4; k++)
            s -= a[c][k] * x[k];
        x[c] = s / a[c][c];
    }
    return 0;
}

typedef struct {
    const poly_system *sys;
    int in[5], out[4], eta;
    double lambda;
    const double *target;
    double buf_in[SOLVE_MAX_IN], buf_out[SOLVE_MAX_OUT], jac[SOLVE_MAX_OUT * SOLVE_MAX_IN];
} solver;

/* Residual F(s) = sys(s) - target, and (unless j is NULL) its Jacobian
 * d F / d (x, y, u, v). With j, of out_x .. out_v alone (poly_eval_jacobian_outputs: the
 * passage outputs' derivatives are most of a whole Jacobian's cost); without, only the
 * values, by poly_eval (with its pass flag): the same bits either way. */
static double residual(solver *sv, const double s[4], double f[4], double j[4][4], int *pass)
{
    int ni = poly_ninputs(sv->sys);
    for (int i = 0; i < 4; i++)
        sv->buf_in[sv->in[i]] = s[i];
    sv->buf_in[sv->in[4]] = sv->lambda;
    double val[4];
    int p = j ? poly_eval_jacobian_outputs(sv->sys, sv->buf_in, 4, sv->out, val, sv->jac)
              : poly_eval(sv->sys, sv->buf_in, sv->buf_out);
    if (pass)
        *pass = p;
    double nrm = 0;
    for (int o = 0; o < 4; o++) {
        f[o] = (j ? val[o] : sv->buf_out[sv->out[o]]) - sv->target[o];
        nrm = fmax(nrm, fabs(f[o]));
        if (j)
            for (int i = 0; i < 4; i++)
                j[o][i] = sv->jac[o * ni + sv->in[i]];
    }
    return isfinite(nrm) ? nrm : INFINITY;
}

/* A meridional system is discontinuous at the axis by about its fit error: its frame
 * turns with the sensor point, and a polynomial in the frame is rotation-equivariant at
 * the axis only as far as the fit is right. Newton can stall there (the on-axis spot of
 * dgauss.50mm loses 3% of its rays) at a residual of that size, and such a solution is
 * as good as the system: accepted within 10x the largest held-out error of out_x..out_v
 * the system records (0 when it records none, or has no frame). */
static double fit_level(const poly_system *sys)
{
    if (poly_get_frame(sys) == POLY_FRAME_NONE)
        return 0;
    double level = 0;
    for (int o = 0; o < 4; o++) {
        char key[32];
        snprintf(key, sizeof key, "fit_%s", out_names[o]);
        const char *m = poly_get_meta(sys, key), *h = m ? strstr(m, "holdout_rms ") : NULL;
        double rms;
        if (h && sscanf(h + 12, "%lf", &rms) == 1 && isfinite(rms))
            level = fmax(level, 10 * rms);
    }
    return level;
}

int poly_solve_sensor(const poly_system *sys, double lambda, const double outer[4],
                      const double *guess, double sensor[4], int *pass, double *eta)
{
    solver sv = {.sys = sys, .lambda = lambda, .target = outer};
    if (poly_ninputs(sys) > SOLVE_MAX_IN || poly_noutputs(sys) > SOLVE_MAX_OUT)
        return -1;
    for (int i = 0; i < 5; i++)
        if ((sv.in[i] = poly_input_index(sys, in_names[i])) < 0)
            return -1;
    for (int i = 0; i < 4; i++)
        if ((sv.out[i] = poly_output_index(sys, out_names[i])) < 0)
            return -1;
    sv.eta = poly_output_index(sys, "out_eta");
    double s[4] = {0, 0, 0, 0};
    if (guess)
        memcpy(s, guess, sizeof s);
    /* On the axis a meridional system's Jacobian has no y column (poly_frame.c holds the
     * frame, whose angle is undefined there, fixed): with every outer output in the frame
     * Newton could not leave the axis sideways (lens-mtf seeds on-axis bundles with the
     * chief ray, (0, 0, 0, 0)). A nanometre off the axis the angle is defined. */
    if (s[0] == 0 && s[1] == 0 && poly_get_frame(sys) != POLY_FRAME_NONE)
        s[0] = 1e-6;
    double f[4], j[4][4];
    double r = residual(&sv, s, f, j, NULL);
    double tol = 1e-9 * (1 + fmax(fmax(fabs(outer[0]), fabs(outer[1])), 1.0));
    for (int it = 0; it < 60 && r > tol; it++) {
        double step[4], b[4] = {-f[0], -f[1], -f[2], -f[3]};
        if (solve4(j, b, step) != 0)
            return -1;
        /* Backtracking keeps Newton from leaving the region where the fit is valid. The
         * full step, usually taken, is tried with its Jacobian; shorter ones with values
         * only, and the Jacobian follows once one is taken. */
        double lam = 1, ns[4], nf[4], nj[4][4], nr = INFINITY;
        int k = 0;
        for (; k < 30; k++, lam *= 0.5) {
            for (int i = 0; i < 4; i++)
                ns[i] = s[i] + lam * step[i];
            nr = residual(&sv, ns, nf, k == 0 ? nj : NULL, NULL);
            if (nr < r)
                break;
        }
        if (!(nr < r))
            break; /* stalled */
        if (k > 0)
            residual(&sv, ns, nf, nj, NULL);
        memcpy(s, ns, sizeof s);
        memcpy(f, nf, sizeof f);
        memcpy(j, nj, sizeof j);
        r = nr;
    }
    if (!(r <= tol) && !(r <= fit_level(sys)))
        return -1;
    int p = 0;
    residual(&sv, s, f, NULL, &p);
    memcpy(sensor, s, sizeof s);
    if (pass)
        *pass = p;
    if (eta)
        *eta = sv.eta >= 0 ? sv.buf_out[sv.eta] : 1.0;
    return 0;
}
