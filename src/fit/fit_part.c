/* The fits of the radial parts of one fit_system_core call (fit.c): every output of a
 * part gets its own sparse polynomial from fit_select (fit_select.c), solved at the end
 * by Householder QR on all rows of the part. When an output misses the tolerance within
 * the term budget, the ray space is cut into equal-count rings of sensor radius, fitted
 * part by part with a small overlap; the fewest rings that meet the tolerances win. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/fit_part.h"

#define PATIENCE 8
#define EXCHANGE_PASSES 2
#define OVERLAP 0.05 /* of a part's rows, on each side */

double fit_tol_of(const fit_options *opt, int o)
{
    return opt->output_tolerance ? opt->output_tolerance[o] : opt->tolerance;
}

void sys_fit_free(sys_fit *f, int nout)
{
    if (!f->p)
        return;
    for (int p = 0; p < f->nparts; p++) {
        if (!f->p[p].o)
            continue;
        for (int o = 0; o < nout; o++) {
            free(f->p[p].o[o].cand);
            free(f->p[p].o[o].coef);
        }
        free(f->p[p].o);
    }
    free(f->p);
    free(f->rms);
    free(f->jump);
    memset(f, 0, sizeof *f);
}

static double eval_row(const fit_ctx *c, const double *s, const out_fit *of)
{
    double sum = 0;
    for (int t = 0; t < of->k; t++) {
        const int *a = c->b.exps + (size_t)of->cand[t] * c->nin;
        double m = of->coef[t];
        for (int v = 0; v < c->nin; v++)
            for (int e = 0; e < a[v]; e++)
                m *= s[v];
        sum += m;
    }
    return sum;
}

/* Fits every output on sorted positions [flo, fhi) (all rows when rows == NULL);
 * held-out error counted over positions [clo, chi). */
static int fit_part(const fit_ctx *c, const size_t *rows, size_t flo, size_t fhi, size_t clo,
                    size_t chi, part_fit *pf, lens_err *err)
{
    int D = c->opt->max_degree, nout = c->nout;
    size_t m = fhi - flo, ntr = 0, nho = 0;
    size_t *itr = malloc((m ? m : 1) * sizeof *itr), *iho = malloc((m ? m : 1) * sizeof *iho);
    size_t *iall = malloc((m ? m : 1) * sizeof *iall);
    unsigned char *core = malloc(m ? m : 1);
    double *ytr = malloc((m ? m : 1) * (size_t)nout * sizeof(double));
    double *yho = malloc((m ? m : 1) * (size_t)nout * sizeof(double));
    double *yall = malloc((m ? m : 1) * (size_t)nout * sizeof(double));
    double *mom = malloc(c->b.mom.count * sizeof(double));
    fit_powers tr = {0}, ho = {0}, all = {0};
    int rc = -1;
    pf->o = calloc((size_t)nout, sizeof *pf->o);
    if (!itr || !iho || !iall || !core || !ytr || !yho || !yall || !mom || !pf->o) {
        lens_errf(err, NULL, 0, "out of memory");
        goto out;
    }
    unsigned char *hcore = core;
    for (size_t q = flo; q < fhi; q++) {
        size_t r = rows ? rows[q] : q;
        iall[q - flo] = r;
        if (c->hold[r]) {
            hcore[nho] = q >= clo && q < chi;
            iho[nho++] = r;
        } else {
            itr[ntr++] = r;
        }
    }
    if (ntr < (size_t)c->opt->max_terms) {
        lens_errf(err, NULL, 0,
                  "%zu training samples in a part (of %zu usable, %zu held out) are fewer "
                  "than the %d terms asked for: trace more rays or lower --terms",
                  ntr, m, nho, c->opt->max_terms);
        goto out;
    }
    for (int o = 0; o < nout; o++)
        for (size_t i = 0; i < m; i++) {
            size_t r = iall[i];
            yall[(size_t)o * m + i] = c->y[r * nout + o];
        }
    for (int o = 0; o < nout; o++) {
        for (size_t i = 0; i < ntr; i++)
            ytr[(size_t)o * m + i] = c->y[itr[i] * nout + o];
        for (size_t i = 0; i < nho; i++)
            yho[(size_t)o * m + i] = c->y[iho[i] * nout + o];
    }
    if (fit_powers_init(&tr, ntr, c->nin, 2 * D, c->s, itr) != 0 ||
        fit_powers_init(&ho, nho, c->nin, D, c->s, iho) != 0 ||
        fit_powers_init(&all, m, c->nin, D, c->s, iall) != 0) {
        lens_errf(err, NULL, 0, "out of memory");
        goto out;
    }
    fit_moments(&c->b.mom, &tr, NULL, mom, c->threads);
    int failed = 0;
    /* Outputs are independent and each is computed by one thread start to end, so the
     * result does not depend on the number of threads. */
#pragma omp parallel for schedule(dynamic, 1) num_threads(c->threads) reduction(+ : failed)
    for (int o = 0; o < nout; o++) {
        out_fit *of = pf->o + o;
        double *by = malloc(c->b.cand.count * sizeof *by);
        fit_selection sel = {0};
        fit_select_opt so = {c->opt->max_terms, fit_tol_of(c->opt, o), PATIENCE, EXCHANGE_PASSES};
        if (!by) {
            failed++;
            continue;
        }
        fit_moments(&c->b.cand, &tr, ytr + (size_t)o * m, by, 1);
        if (fit_select(&c->b, mom, by, &tr, ytr + (size_t)o * m, &ho, yho + (size_t)o * m, &so,
                       &sel) != 0) {
            free(by);
            failed++;
            continue;
        }
        free(by);
        of->k = sel.nterms;
        of->steps = sel.steps;
        of->swaps = sel.swaps;
        of->cand = sel.cand;
        of->coef = malloc((size_t)(sel.nterms ? sel.nterms : 1) * sizeof(double));
        if (!of->coef) {
            fit_selection_free(&sel);
            of->cand = NULL;
            failed++;
            continue;
        }
        for (size_t i = 0; i < nho; i++)
            if (hcore[i]) {
                double d = yho[(size_t)o * m + i] -
                           fit_eval_sample(&c->b, &ho, i, sel.nterms, sel.cand, sel.coef);
                of->hold_sse += d * d;
                of->hold_n++;
            }
        /* Rank deficiency cannot arise from selected terms, but keep the training
         * coefficients if the final solve disagrees. */
        if (sel.nterms == 0 ||
            fit_lsq(&c->b, &all, yall + (size_t)o * m, sel.nterms, sel.cand, of->coef) != 0)
            memcpy(of->coef, sel.coef, (size_t)sel.nterms * sizeof(double));
        free(sel.coef);
    }
    if (failed) {
        lens_errf(err, NULL, 0, "fitting failed (out of memory)");
        goto out;
    }
    pf->flo = flo;
    pf->fhi = fhi;
    rc = 0;
out:
    fit_powers_free(&tr);
    fit_powers_free(&ho);
    fit_powers_free(&all);
    free(itr); free(iho); free(iall); free(core); free(ytr); free(yho); free(yall); free(mom);
    return rc;
}

static int fit_partition(const fit_ctx *c, int P, sys_fit *f, lens_err *err)
{
    int nout = c->nout;
    memset(f, 0, sizeof *f);
    f->nparts = P;
    f->p = calloc((size_t)P, sizeof *f->p);
    f->rms = calloc((size_t)nout, sizeof *f->rms);
    f->jump = calloc((size_t)nout, sizeof *f->jump);
    if (!f->p || !f->rms || !f->jump) {
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    size_t n = c->n;
    for (int p = 0; p < P; p++) {
        size_t lo = n * (size_t)p / (size_t)P, hi = n * (size_t)(p + 1) / (size_t)P;
        size_t ov = P > 1 ? (size_t)ceil(OVERLAP * (double)(hi - lo)) : 0;
        size_t flo = lo > ov ? lo - ov : 0, fhi = hi + ov < n ? hi + ov : n;
        part_fit *pf = f->p + p;
        pf->rmin = p == 0 ? 0 : 0.5 * (c->rad[c->order[lo - 1]] + c->rad[c->order[lo]]);
        pf->rmax = p == P - 1 ? INFINITY
                              : 0.5 * (c->rad[c->order[hi - 1]] + c->rad[c->order[hi]]);
        if (c->opt->verbose)
            fprintf(stderr, "lens-fit: part %d/%d: radius [%g, %g), %zu rows\n", p + 1, P,
                    pf->rmin, pf->rmax, fhi - flo);
        if (fit_part(c, P > 1 ? c->order : NULL, flo, fhi, lo, hi, pf, err) != 0)
            return -1;
    }
    for (int o = 0; o < nout; o++) {
        double sse = 0;
        size_t cnt = 0;
        for (int p = 0; p < P; p++) {
            sse += f->p[p].o[o].hold_sse;
            cnt += f->p[p].o[o].hold_n;
        }
        f->rms[o] = cnt ? sqrt(sse / (double)cnt) : NAN;
    }
    /* Jumps: both neighbours evaluated on the rows they were both fitted to. */
    for (int p = 0; p + 1 < P; p++)
        for (size_t q = f->p[p + 1].flo; q < f->p[p].fhi; q++) {
            const double *s = c->s + c->order[q] * (size_t)c->nin;
            for (int o = 0; o < nout; o++) {
                double d = fabs(eval_row(c, s, f->p[p].o + o) - eval_row(c, s, f->p[p + 1].o + o));
                if (d > f->jump[o])
                    f->jump[o] = d;
            }
        }
    return 0;
}


/* The worst ratio of held-out error to tolerance over the outputs that have one. */
static double worst_ratio(const fit_ctx *c, const sys_fit *f)
{
    double w = 0;
    for (int o = 0; o < c->nout; o++)
        if (fit_tol_of(c->opt, o) > 0)
            w = fmax(w, f->rms[o] / fit_tol_of(c->opt, o));
    return w;
}

int fit_choose_parts(const fit_ctx *c, sys_fit *best, lens_err *err)
{
    const fit_options *opt = c->opt;
    sys_fit cur = {0};
    if (fit_partition(c, opt->force_parts > 0 ? opt->force_parts : 1, best, err) != 0)
        return -1;
    int any_tol = 0;
    for (int o = 0; o < c->nout; o++)
        any_tol |= fit_tol_of(opt, o) > 0;
    if (!any_tol || opt->max_parts <= 1 || opt->force_parts > 0 || c->ix < 0 ||
        (c->iy < 0 && opt->frame != POLY_FRAME_MERIDIONAL))
        return 0;
    double worst = worst_ratio(c, best);
    for (int P = 2; P <= opt->max_parts && worst > 1; P++) {
        lens_err perr;
        if (fit_partition(c, P, &cur, &perr) != 0) {
            sys_fit_free(&cur, c->nout);
            break; /* parts too small for the term budget */
        }
        double w = worst_ratio(c, &cur);
        if (w < worst) {
            sys_fit_free(best, c->nout);
            *best = cur;
            memset(&cur, 0, sizeof cur);
            worst = w;
        } else {
            sys_fit_free(&cur, c->nout);
        }
    }
    return 0;
}
