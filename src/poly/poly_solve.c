/* Newton inversion of a polynomial system: object-space ray to sensor ray (see
 * poly_solve.h). */
#include "sparselens/poly_solve.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


/* A system's inputs and outputs, at most: the outer pupil and out_eta, and a passage
 * pair for the stop and each of up to 8 surfaces that limit the beam (lens-trace(1)). */
#define SOLVE_MAX_IN 8
/* Newton steps at most (poly_solve_sensor; poly_solve_sensor_batch's max_iter at most) */
#define SOLVE_MAX_ITER 60
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
    const char *frame = poly_get_meta(sys, "trace_frame");
    if (frame && strcmp(frame, "outer") != 0) {
        lens_errf(err, NULL, 0, "the system was fitted to samples traced to the %s (meta "
                  "trace_frame %s): lens-spot and lens-distort need one to the outer pupil "
                  "(lens-trace --to outer, the default)", frame, frame);
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

/* A target with an infinite out_x or out_y would make the tolerance below infinite and
 * any iterate pass for a solution; a nan one never converges. */
static int finite_target(const double outer[4])
{
    for (int o = 0; o < 4; o++)
        if (!isfinite(outer[o]))
            return 0;
    return 1;
}

/* The columns of x y u v lambda and out_x .. out_v; -1 when one is missing or the system
 * is larger than a solve's buffers. */
static int solve_columns(const poly_system *sys, int in[5], int out[4])
{
    if (poly_ninputs(sys) > SOLVE_MAX_IN || poly_noutputs(sys) > SOLVE_MAX_OUT)
        return -1;
    for (int i = 0; i < 5; i++)
        if ((in[i] = poly_input_index(sys, in_names[i])) < 0)
            return -1;
    for (int i = 0; i < 4; i++)
        if ((out[i] = poly_output_index(sys, out_names[i])) < 0)
            return -1;
    return 0;
}

typedef struct {
    const poly_system *sys;
    int in[5], out[4], eta;
    double lambda;
    const double *target;
    double buf_in[SOLVE_MAX_IN], buf_out[SOLVE_MAX_OUT], jac[SOLVE_MAX_OUT * SOLVE_MAX_IN];
} solver;

/* The larger of a residual norm and |f|, nan when f is: fmax would drop a nan, and a
 * nan target or a step into nan values would pass for converged. */
static double worse(double nrm, double f)
{
    return fabs(f) > nrm || f != f ? fabs(f) : nrm;
}

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
        nrm = worse(nrm, f[o]);
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
    if (solve_columns(sys, sv.in, sv.out) != 0)
        return -1;
    sv.eta = poly_output_index(sys, "out_eta");
    if (!finite_target(outer))
        return -1;
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
    for (int it = 0; it < SOLVE_MAX_ITER && r > tol; it++) {
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

/* The batch solve: every ray's Newton as poly_solve_sensor's, the rays still iterating
 * evaluated together at each step (poly_eval_batch_outputs and
 * poly_eval_jacobian_batch_outputs on the gathered trial points), where one ray at a time
 * cost a whole one-ray Jacobian per step: lens-mtf through fisheye-ii's default fit spent
 * 45% of its time there. */
typedef struct {
    double s[4], f[4], j[4][4], step[4], lam, r, tol, nf[4], nj[4][4], nr;
    int state; /* SOLVE_* */
} batch_ray;

enum { SOLVE_RUNNING, SOLVE_DONE, SOLVE_FAILED };

typedef struct {
    const poly_system *sys;
    int nin, in[5], out[4];
    const double *lambda, *outer;
    size_t *rows; /* the rays of the current evaluation */
    double *in_buf, *val, *jac;
    unsigned char *pass;
} batch_eval;

/* Values (and with want_jac the Jacobian) of out_x .. out_v for the m rays in e->rows at
 * the points pt(ray), into each ray's nf, nr (and nj): poly_solve_sensor's residual. */
static void eval_rays(batch_eval *e, batch_ray *br, size_t m, int want_jac,
                      void (*pt)(const batch_ray *, double[4]))
{
    if (m == 0)
        return;
    for (size_t k = 0; k < m; k++) {
        size_t i = e->rows[k];
        double x[4], *row = e->in_buf + k * (size_t)e->nin;
        pt(&br[i], x);
        for (int a = 0; a < 4; a++)
            row[e->in[a]] = x[a];
        row[e->in[4]] = e->lambda[i];
    }
    poly_eval_batch_outputs(e->sys, m, e->in_buf, 4, e->out, e->val, e->pass);
    if (want_jac)
        poly_eval_jacobian_batch_outputs(e->sys, m, e->in_buf, 4, e->out, e->jac);
    for (size_t k = 0; k < m; k++) {
        batch_ray *b = &br[e->rows[k]];
        const double *t = e->outer + 4 * e->rows[k];
        double nrm = 0;
        for (int o = 0; o < 4; o++) {
            b->nf[o] = e->val[4 * k + o] - t[o];
            nrm = worse(nrm, b->nf[o]);
            if (want_jac)
                for (int a = 0; a < 4; a++)
                    b->nj[o][a] = e->jac[k * 4 * (size_t)e->nin + (size_t)o * e->nin + e->in[a]];
        }
        b->nr = isfinite(nrm) ? nrm : INFINITY;
    }
}

static void at_s(const batch_ray *b, double x[4])
{
    memcpy(x, b->s, sizeof b->s);
}

static void at_trial(const batch_ray *b, double x[4])
{
    for (int a = 0; a < 4; a++)
        x[a] = b->s[a] + b->lam * b->step[a];
}

/* The last evaluation's residual (and Jacobian) become the ray's current ones. */
static void take_values(batch_ray *b, int with_jac)
{
    memcpy(b->f, b->nf, sizeof b->f);
    if (with_jac)
        memcpy(b->j, b->nj, sizeof b->j);
    b->r = b->nr;
}

/* The trial point becomes the iterate, with its values. */
static void take_trial(batch_ray *b, int with_jac)
{
    at_trial(b, b->s);
    take_values(b, with_jac);
}

/* One Newton step of every ray still iterating: the full step with its Jacobian, then
 * halved steps with values only for the rays it did not improve, then the Jacobian where
 * a halved step was taken. Returns the number of rays that took part (0: all done). */
static size_t newton_round(batch_eval *e, batch_ray *br, size_t n, size_t *pending)
{
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        batch_ray *b = &br[i];
        if (b->state != SOLVE_RUNNING)
            continue;
        if (!(b->r > b->tol)) {
            b->state = SOLVE_DONE;
            continue;
        }
        double a[4][4], rhs[4] = {-b->f[0], -b->f[1], -b->f[2], -b->f[3]};
        memcpy(a, b->j, sizeof a);
        if (solve4(a, rhs, b->step) != 0) {
            b->state = SOLVE_FAILED;
            continue;
        }
        b->lam = 1;
        e->rows[m++] = i;
    }
    if (m == 0)
        return 0;
    eval_rays(e, br, m, 1, at_trial);
    size_t np = 0;
    for (size_t k = 0; k < m; k++) {
        batch_ray *b = &br[e->rows[k]];
        if (b->nr < b->r)
            take_trial(b, 1);
        else
            pending[np++] = e->rows[k];
    }
    size_t nj = 0; /* rays that took a shorter step, listed from the end of rows */
    for (int k = 1; k < 30 && np > 0; k++) {
        for (size_t q = 0; q < np; q++) {
            br[pending[q]].lam *= 0.5;
            e->rows[q] = pending[q];
        }
        eval_rays(e, br, np, 0, at_trial);
        size_t left = 0;
        for (size_t q = 0; q < np; q++) {
            batch_ray *b = &br[pending[q]];
            if (b->nr < b->r) {
                take_trial(b, 0);
                e->rows[n - 1 - nj++] = pending[q]; /* the front of rows is in use */
            } else {
                pending[left++] = pending[q];
            }
        }
        np = left;
    }
    for (size_t q = 0; q < np; q++)
        br[pending[q]].state = SOLVE_DONE; /* stalled: judged by the caller */
    if (nj > 0) {
        memmove(e->rows, e->rows + n - nj, nj * sizeof *e->rows);
        eval_rays(e, br, nj, 1, at_s);
        for (size_t k = 0; k < nj; k++)
            take_values(&br[e->rows[k]], 1);
    }
    return m;
}

/* The verdicts: accepted within tolerance, or stalled within the fit's own error; the
 * pass test and out_eta at the solutions. */
static void finish(batch_eval *e, const batch_ray *br, size_t n, double level, double *sensor,
                   int *status, unsigned char *pass, double *eta)
{
    const int ieta = poly_output_index(e->sys, "out_eta");
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        const batch_ray *b = &br[i];
        int good = b->state != SOLVE_FAILED && (b->r <= b->tol || b->r <= level);
        status[i] = good ? 0 : -1;
        if (good)
            e->rows[m++] = i;
        memcpy(sensor + 4 * i, b->s, sizeof b->s);
        if (pass)
            pass[i] = 0;
        if (eta)
            eta[i] = 1.0;
    }
    for (size_t k = 0; k < m; k++) {
        size_t i = e->rows[k];
        double *row = e->in_buf + k * (size_t)e->nin;
        for (int a = 0; a < 4; a++)
            row[e->in[a]] = br[i].s[a];
        row[e->in[4]] = e->lambda[i];
    }
    if (m > 0)
        poly_eval_batch_outputs(e->sys, m, e->in_buf, ieta >= 0, &ieta, e->val, e->pass);
    for (size_t k = 0; k < m; k++) {
        if (pass)
            pass[e->rows[k]] = e->pass[k];
        if (eta && ieta >= 0)
            eta[e->rows[k]] = e->val[k];
    }
}

int poly_solve_sensor_batch(const poly_system *sys, size_t n, const double *lambda,
                            const double *outer, const double *guess, size_t guess_stride,
                            int max_iter, double *sensor, int *status, unsigned char *pass,
                            double *eta)
{
    batch_eval e = {.sys = sys, .nin = poly_ninputs(sys), .lambda = lambda, .outer = outer};
    if (solve_columns(sys, e.in, e.out) != 0)
        return -1;
    if (n == 0)
        return 0;
    batch_ray *br = malloc(n * sizeof *br);
    e.rows = malloc(n * sizeof *e.rows);
    /* zeros in the inputs other than x y u v lambda, as poly_solve_sensor's buf_in */
    e.in_buf = calloc(n * (size_t)e.nin, sizeof *e.in_buf);
    e.val = malloc(n * 4 * sizeof *e.val);
    e.jac = malloc(n * 4 * (size_t)e.nin * sizeof *e.jac);
    e.pass = malloc(n);
    size_t *pending = malloc(n * sizeof *pending);
    int rc = 0;
    if (!br || !e.rows || !e.in_buf || !e.val || !e.jac || !e.pass || !pending) {
        rc = -1;
        goto out;
    }
    const int framed = poly_get_frame(sys) != POLY_FRAME_NONE;
    for (size_t i = 0; i < n; i++) {
        batch_ray *b = &br[i];
        memset(b, 0, sizeof *b);
        if (guess)
            memcpy(b->s, guess + i * guess_stride, sizeof b->s);
        if (b->s[0] == 0 && b->s[1] == 0 && framed)
            b->s[0] = 1e-6; /* off the axis, as poly_solve_sensor */
        const double *t = outer + 4 * i;
        b->tol = 1e-9 * (1 + fmax(fmax(fabs(t[0]), fabs(t[1])), 1.0));
        if (!finite_target(t))
            b->state = SOLVE_FAILED;
        e.rows[i] = i;
    }
    eval_rays(&e, br, n, 1, at_s);
    for (size_t i = 0; i < n; i++)
        take_values(&br[i], 1);
    if (max_iter <= 0 || max_iter > SOLVE_MAX_ITER)
        max_iter = SOLVE_MAX_ITER;
    for (int it = 0; it < max_iter && newton_round(&e, br, n, pending) > 0; it++)
        ;
    finish(&e, br, n, fit_level(sys), sensor, status, pass, eta);
out:
    free(br);
    free(e.rows);
    free(e.in_buf);
    free(e.val);
    free(e.jac);
    free(e.pass);
    free(pending);
    return rc;
}
