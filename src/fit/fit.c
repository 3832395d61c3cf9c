/* fit_system: the whole of lens-fit's job on arrays of samples (see fit.h).
 *
 * Rows whose outputs are not all finite, or whose out_eta is 0, are rays the lens
 * blocks: they are left out of every fit. The rest are scaled to [-1, 1] per input,
 * split into training and held-out rows by a seeded shuffle, and each output gets its
 * own sparse polynomial from fit_select (fit_select.c). The final coefficients are a
 * Householder QR least-squares solve on all usable rows of the chosen terms. When an
 * output misses the tolerance within the term budget, the ray space is cut into
 * equal-count rings of sensor radius, fitted part by part with a small overlap. */
#include <math.h>
#include <omp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/fit.h"
#include "fit/fit_internal.h"

#define PATIENCE 8
#define EXCHANGE_PASSES 2
#define OVERLAP 0.05 /* of a part's rows, on each side */

static int fit_is_clip_prefix(const char *name, size_t len);

void fit_options_default(fit_options *opt)
{
    opt->max_terms = 40;
    opt->max_degree = 11;
    opt->tolerance = 0;
    opt->output_tolerance = NULL;
    opt->max_parts = 1;
    opt->holdout = 0.2;
    opt->seed = 1;
    opt->threads = 0;
    opt->verbose = 0;
    opt->no_offset = 0;
    opt->frame = POLY_FRAME_NONE;
    opt->frame_plain = NULL;
    opt->scaling = NULL;
    opt->force_parts = 0;
    opt->lambda_transform = POLY_XFORM_IDENTITY;
    opt->passage_tolerance = 1e-3;
}

int fit_is_passage_output(const char *name)
{
    size_t len = strlen(name);
    if (len < 3 || name[len - 2] != '_' || (name[len - 1] != 'x' && name[len - 1] != 'y'))
        return 0;
    return fit_is_clip_prefix(name, len - 2) && strncmp(name, "out_", 4) != 0;
}

typedef struct {
    int k;
    int *cand;
    double *coef;      /* final: QR on every row of the part */
    double hold_sse;   /* of the training-only fit, over held-out rows of the part's core */
    size_t hold_n;
    int steps, swaps;
} out_fit;

typedef struct {
    double rmin, rmax;
    size_t flo, fhi;   /* rows fitted: sorted positions [flo, fhi) */
    out_fit *o;
} part_fit;

typedef struct {
    int nparts;
    part_fit *p;
    double *rms;       /* per output, held-out, over all parts */
    double *jump;      /* per output, largest jump between neighbouring parts */
} sys_fit;

static double tol_of(const fit_options *opt, int o)
{
    return opt->output_tolerance ? opt->output_tolerance[o] : opt->tolerance;
}

typedef struct {
    const fit_options *opt;
    fit_basis b;
    int nin, nout;
    size_t n;            /* usable rows */
    double *s;           /* n x nin scaled inputs */
    double *y;           /* n x nout outputs */
    unsigned char *hold; /* per usable row */
    double *rad;         /* sensor radius per usable row (NULL without x and y) */
    size_t *order;       /* usable rows by radius */
    int threads;
} ctx;

static unsigned long long splitmix(unsigned long long *st)
{
    unsigned long long z = (*st += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

static void sys_fit_free(sys_fit *f, int nout)
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

static double eval_row(const ctx *c, const double *s, const out_fit *of)
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
static int fit_part(const ctx *c, const size_t *rows, size_t flo, size_t fhi, size_t clo,
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
        fit_select_opt so = {c->opt->max_terms, tol_of(c->opt, o), PATIENCE, EXCHANGE_PASSES};
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

static int fit_partition(const ctx *c, int P, sys_fit *f, lens_err *err)
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

static int find_name(int n, const char *const *names, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(names[i], name) == 0)
            return i;
    return -1;
}

/* Output prefixes that name a hit whose furthest passing radius bounds passage: out
 * (front element), ap (stop), sN (surface N, lens-trace --clip-columns). */
static int fit_is_clip_prefix(const char *name, size_t len)
{
    if ((len == 3 && !strncmp(name, "out", 3)) || (len == 2 && !strncmp(name, "ap", 2)))
        return 1;
    if (len < 2 || name[0] != 's')
        return 0;
    for (size_t i = 1; i < len; i++)
        if (name[i] < '0' || name[i] > '9')
            return 0;
    return 1;
}


/* qsort_r is not C11; a small merge sort keeps the order deterministic and stable. */
static void sort_by(size_t *idx, size_t *tmp, size_t n, const double *key)
{
    if (n < 2)
        return;
    size_t h = n / 2;
    sort_by(idx, tmp, h, key);
    sort_by(idx + h, tmp, n - h, key);
    size_t i = 0, j = h, k = 0;
    while (i < h && j < n)
        tmp[k++] = key[idx[j]] < key[idx[i]] ? idx[j++] : idx[i++];
    while (i < h)
        tmp[k++] = idx[i++];
    while (j < n)
        tmp[k++] = idx[j++];
    memcpy(idx, tmp, n * sizeof *idx);
}

static void set_metaf(poly_system *sys, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void set_metaf(poly_system *sys, const char *key, const char *fmt, ...)
{
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    poly_set_meta(sys, key, buf);
}

poly_system *fit_system_core(const char *lens_name, int ninputs, const char *const *inputs,
                             int noutputs, const char *const *outputs, size_t count,
                             const double *in, const double *out, const fit_options *opt,
                             lens_err *err)
{
    ctx c = {0};
    c.opt = opt;
    c.nin = ninputs;
    c.nout = noutputs;
    c.threads = opt->threads > 0 ? opt->threads : omp_get_max_threads();
    poly_system *sys = NULL;
    sys_fit best = {0}, cur = {0};
    double *lo = NULL, *hi = NULL, *off = NULL, *scl = NULL;
    if (ninputs < 1 || ninputs > FIT_MAX_VARS || noutputs < 1) {
        lens_errf(err, NULL, 0, "need 1 to %d inputs and at least one output", FIT_MAX_VARS);
        return NULL;
    }
    if (opt->max_terms < 1 || opt->max_degree < 0 || opt->max_degree > FIT_MAX_DEG || opt->max_degree > POLY_MAX_DEGREE ||
        opt->max_parts < 1 || !(opt->holdout >= 0 && opt->holdout < 1) ||
        !(opt->tolerance >= 0)) {
        lens_errf(err, NULL, 0,
                  "bad fit options (terms >= 1, 0 <= degree <= %d, parts >= 1, "
                  "0 <= holdout < 1, tolerance >= 0)",
                  FIT_MAX_DEG < POLY_MAX_DEGREE ? FIT_MAX_DEG : POLY_MAX_DEGREE);
        return NULL;
    }
    for (int o = 0; opt->output_tolerance && o < noutputs; o++)
        if (!(opt->output_tolerance[o] >= 0)) {
            lens_errf(err, NULL, 0, "tolerance of %s must not be negative", outputs[o]);
            return NULL;
        }
    if (count == 0) {
        lens_errf(err, NULL, 0, "no samples to fit");
        return NULL;
    }
    for (size_t r = 0; r < count; r++)
        for (int i = 0; i < ninputs; i++)
            if (!isfinite(in[r * ninputs + i])) {
                lens_errf(err, NULL, 0, "sample %zu: input %s is not finite", r + 1, inputs[i]);
                return NULL;
            }
    int ieta = find_name(noutputs, outputs, "out_eta");
    c.s = malloc(count * (size_t)ninputs * sizeof *c.s);
    c.y = malloc(count * (size_t)noutputs * sizeof *c.y);
    c.hold = calloc(count, 1);
    lo = malloc((size_t)ninputs * sizeof *lo);
    hi = malloc((size_t)ninputs * sizeof *hi);
    off = malloc((size_t)ninputs * sizeof *off);
    scl = malloc((size_t)ninputs * sizeof *scl);
    if (!c.s || !c.y || !c.hold || !lo || !hi || !off || !scl) {
        lens_errf(err, NULL, 0, "out of memory");
        goto fail;
    }
    /* Usable rows: the rays that pass. */
    size_t n = 0;
    for (size_t r = 0; r < count; r++) {
        const double *yo = out + r * noutputs;
        int ok = 1;
        for (int o = 0; o < noutputs; o++)
            ok &= isfinite(yo[o]) != 0;
        if (ok && ieta >= 0 && !(yo[ieta] > 0))
            ok = 0;
        if (!ok)
            continue;
        memcpy(c.s + n * ninputs, in + r * ninputs, (size_t)ninputs * sizeof(double));
        memcpy(c.y + n * noutputs, yo, (size_t)noutputs * sizeof(double));
        n++;
    }
    c.n = n;
    if (n == 0) {
        lens_errf(err, NULL, 0, "none of the %zu samples is usable: every ray is blocked", count);
        goto fail;
    }
    for (int i = 0; i < ninputs; i++) {
        lo[i] = INFINITY;
        hi[i] = -INFINITY;
        for (size_t r = 0; r < n; r++) {
            double v = c.s[r * ninputs + i];
            lo[i] = v < lo[i] ? v : lo[i];
            hi[i] = v > hi[i] ? v : hi[i];
        }
        double mag = fabs(lo[i]) > fabs(hi[i]) ? fabs(lo[i]) : fabs(hi[i]);
        if (!(hi[i] - lo[i] > 1e-12 * mag) || hi[i] == lo[i]) {
            lens_errf(err, NULL, 0,
                      "input %s is constant (%.17g) over the %zu usable samples: leave it out "
                      "of the inputs", inputs[i], lo[i], n);
            goto fail;
        }
    }
    /* Scaling to [-1, 1]. An input whose range straddles 0 evenly (sensor and
     * direction coordinates) is scaled without an offset, so that the symmetry of the
     * lens (out_x odd in x and u, ...) stays a sparsity pattern: an offset of 1e-3 would
     * turn every odd term into a sum of odd and even ones. Others are centred. */
    for (int i = 0; i < ninputs; i++) {
        double a = -lo[i], bnd = hi[i];
        if ((i < 32 && (opt->no_offset >> i & 1u)) ||
            (a > 0 && bnd > 0 && fmin(a, bnd) >= 0.25 * fmax(a, bnd))) {
            off[i] = 0;
            scl[i] = fmax(fabs(lo[i]), fabs(hi[i]));
        } else {
            off[i] = 0.5 * (lo[i] + hi[i]);
            scl[i] = 0.5 * (hi[i] - lo[i]);
        }
    }
    for (int i = 0; opt->scaling && i < ninputs; i++)
        if (isfinite(opt->scaling[2 * i]) && isfinite(opt->scaling[2 * i + 1]) &&
            opt->scaling[2 * i + 1] != 0) {
            off[i] = opt->scaling[2 * i];
            scl[i] = opt->scaling[2 * i + 1];
        }
    for (size_t r = 0; r < n; r++)
        for (int i = 0; i < ninputs; i++) {
            double *v = c.s + r * ninputs + i;
            *v = (*v - off[i]) * (1 / scl[i]); /* as evaluation scales (poly_impl.h) */
        }
    /* Held-out rows: a seeded shuffle, so the split is reproducible. */
    size_t nho = (size_t)floor(opt->holdout * (double)n);
    if (n - nho < (size_t)opt->max_terms) {
        lens_errf(err, NULL, 0,
                  "%zu usable samples (%zu for training after holding out %zu) are fewer than "
                  "the %d terms asked for: trace more rays or lower --terms",
                  n, n - nho, nho, opt->max_terms);
        goto fail;
    }
    {
        size_t *perm = malloc(n * sizeof *perm);
        if (!perm) {
            lens_errf(err, NULL, 0, "out of memory");
            goto fail;
        }
        unsigned long long st = opt->seed;
        for (size_t i = 0; i < n; i++)
            perm[i] = i;
        for (size_t i = n - 1; i > 0; i--) {
            size_t j = (size_t)(splitmix(&st) % (i + 1));
            size_t t = perm[i]; perm[i] = perm[j]; perm[j] = t;
        }
        for (size_t i = 0; i < nho; i++)
            c.hold[perm[i]] = 1;
        free(perm);
    }
    int ix = find_name(ninputs, inputs, "x"), iy = find_name(ninputs, inputs, "y");
    c.order = malloc(n * sizeof *c.order);
    c.rad = malloc(n * sizeof *c.rad);
    if (!c.order || !c.rad) {
        lens_errf(err, NULL, 0, "out of memory");
        goto fail;
    }
    for (size_t r = 0; r < n; r++) {
        c.order[r] = r;
        c.rad[r] = 0;
        if (ix >= 0 && iy >= 0) {
            double x = c.s[r * ninputs + ix] * scl[ix] + off[ix];
            double y = c.s[r * ninputs + iy] * scl[iy] + off[iy];
            c.rad[r] = hypot(x, y);
        } else if (ix >= 0 && opt->frame == POLY_FRAME_MERIDIONAL) {
            c.rad[r] = fabs(c.s[r * ninputs + ix] * scl[ix] + off[ix]); /* x is r here */
        }
    }
    {
        size_t *tmp = malloc(n * sizeof *tmp);
        if (!tmp) {
            lens_errf(err, NULL, 0, "out of memory");
            goto fail;
        }
        sort_by(c.order, tmp, n, c.rad);
        free(tmp);
    }
    /* The moment table has C(2D + n, n) entries: refuse what would not fit in memory
     * (5 inputs at degree 24 need 2.9e6, 16 inputs at degree 11 2.2e10). */
    {
        double moments = 1;
        for (int i = 1; i <= ninputs; i++)
            moments = moments * (2.0 * opt->max_degree + i) / i;
        if (moments > 2e7) {
            lens_errf(err, NULL, 0,
                      "%d inputs at degree %d need %.3g moments (the limit is 2e7): lower "
                      "--degree or use fewer inputs", ninputs, opt->max_degree, moments);
            goto fail;
        }
    }
    if (fit_basis_init(&c.b, ninputs, opt->max_degree) != 0) {
        lens_errf(err, NULL, 0, "out of memory for the candidates of degree %d", opt->max_degree);
        goto fail;
    }
    if (fit_partition(&c, opt->force_parts > 0 ? opt->force_parts : 1, &best, err) != 0)
        goto fail;
    /* Radial parts, fewest that meet the tolerance; else the best tried. */
    int any_tol = 0;
    for (int o = 0; o < noutputs; o++)
        any_tol |= tol_of(opt, o) > 0;
    if (any_tol && opt->max_parts > 1 && opt->force_parts <= 0 && ix >= 0 &&
        (iy >= 0 || opt->frame == POLY_FRAME_MERIDIONAL)) {
        double worst = 0;
        for (int o = 0; o < noutputs; o++)
            if (tol_of(opt, o) > 0)
                worst = fmax(worst, best.rms[o] / tol_of(opt, o));
        for (int P = 2; P <= opt->max_parts && worst > 1; P++) {
            lens_err perr;
            if (fit_partition(&c, P, &cur, &perr) != 0) {
                sys_fit_free(&cur, noutputs);
                break; /* parts too small for the term budget */
            }
            double w = 0;
            for (int o = 0; o < noutputs; o++)
                if (tol_of(opt, o) > 0)
                    w = fmax(w, cur.rms[o] / tol_of(opt, o));
            if (w < worst) {
                sys_fit_free(&best, noutputs);
                best = cur;
                memset(&cur, 0, sizeof cur);
                worst = w;
            } else {
                sys_fit_free(&cur, noutputs);
            }
        }
    }

    {
        /* In the frame (no y), the system gets a y that no term uses, so that radial
         * parts (which need x and y) can be written; fit_system drops it again. */
        int extra = opt->frame == POLY_FRAME_MERIDIONAL && iy < 0 && ix >= 0;
        const char *names[FIT_MAX_VARS + 1];
        int ex[FIT_MAX_VARS + 1] = {0};
        for (int i = 0; i < ninputs; i++)
            names[i] = inputs[i];
        names[ninputs] = "y";
        sys = poly_new(lens_name, ninputs + extra, names, noutputs, outputs);
        if (!sys) {
            lens_errf(err, NULL, 0, "out of memory");
            goto fail;
        }
        for (int i = 0; i < ninputs; i++) {
            poly_set_scaling(sys, i, off[i], scl[i]);
            poly_set_domain(sys, i, lo[i], hi[i]);
        }
        for (int p = 0; p < best.nparts; p++) {
            int pi = poly_add_part(sys, best.p[p].rmin, best.p[p].rmax);
            for (int o = 0; o < noutputs; o++) {
                const out_fit *of = best.p[p].o + o;
                for (int t = 0; t < of->k; t++) {
                    memcpy(ex, c.b.exps + (size_t)of->cand[t] * ninputs, (size_t)ninputs * sizeof *ex);
                    poly_add_term(sys, pi, o, ex, of->coef[t]);
                }
            }
        }
    }
    /* Passage: inside the furthest passing hit on the front element (out_*), the stop
     * (ap_*) and each clipping surface N (sN_*, lens-trace --clip-columns). */
    for (int a = 0; a < noutputs; a++) {
        char yname[64];
        size_t len = strlen(outputs[a]);
        if (len < 3 || len >= sizeof yname || strcmp(outputs[a] + len - 2, "_x") != 0 ||
            !fit_is_clip_prefix(outputs[a], len - 2))
            continue;
        memcpy(yname, outputs[a], len - 1);
        yname[len - 1] = 'y';
        yname[len] = '\0';
        int bb = find_name(noutputs, outputs, yname);
        if (bb < 0)
            continue;
        double rmax = 0;
        for (size_t r = 0; r < n; r++)
            rmax = fmax(rmax, hypot(c.y[r * noutputs + a], c.y[r * noutputs + bb]));
        poly_add_pass_circle(sys, a, bb, rmax * (1 + 1e-9));
    }
    set_metaf(sys, "fit_flags", "--terms %d --degree %d --parts %d --holdout %.17g --seed %lu",
              opt->max_terms, opt->max_degree, opt->max_parts, opt->holdout, opt->seed);
    set_metaf(sys, "fit_samples", "%zu usable (%zu held out) of %zu", n, nho, count);
    set_metaf(sys, "fit_parts", "%d", best.nparts);
    for (int o = 0; o < noutputs; o++) {
        char key[256];
        int kmax = 0, dmax = 0;
        for (int p = 0; p < best.nparts; p++) {
            const out_fit *of = best.p[p].o + o;
            kmax = of->k > kmax ? of->k : kmax;
            for (int t = 0; t < of->k; t++)
                dmax = c.b.deg[of->cand[t]] > dmax ? c.b.deg[of->cand[t]] : dmax;
        }
        snprintf(key, sizeof key, "fit_%s", outputs[o]);
        char rms[64] = "none"; /* no held-out rows: nothing measured */
        if (isfinite(best.rms[o]))
            snprintf(rms, sizeof rms, "%.6g", best.rms[o]);
        set_metaf(sys, key, "terms %d degree %d holdout_rms %s tolerance %.6g", kmax, dmax, rms,
                  tol_of(opt, o));
        if (best.nparts > 1) {
            snprintf(key, sizeof key, "part_jump_%s", outputs[o]);
            set_metaf(sys, key, "%.6g", best.jump[o]);
        }
    }
    goto done;
fail:
    if (sys)
        poly_free(sys);
    sys = NULL;
done:
    sys_fit_free(&best, noutputs);
    sys_fit_free(&cur, noutputs);
    fit_basis_free(&c.b);
    free(c.s); free(c.y); free(c.hold); free(c.rad); free(c.order); free(lo); free(hi); free(off); free(scl);
    return sys;
}
