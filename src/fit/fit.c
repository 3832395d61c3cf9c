/* fit_system_core: lens-fit's job on arrays of samples, in the variables given (see
 * fit_internal.h; fit_frame.c adds the frame and transforms around it).
 *
 * Rows whose outputs are not all finite, or whose out_eta is 0, are rays the lens
 * blocks: they are left out of every fit. The rest are scaled to [-1, 1] per input,
 * split into training and held-out rows by a seeded shuffle, ordered by sensor radius
 * and fitted in radial parts (fit_part.c); the result is written as a system with a
 * pass circle per passage pair. */
#include <math.h>
#include <omp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/fit.h"
#include "fit/fit_distinct.h"
#include "fit/fit_part.h"

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
    opt->drop_circles = 0;
}

int fit_is_passage_output(const char *name)
{
    size_t len = strlen(name);
    if (len < 3 || name[len - 2] != '_' || (name[len - 1] != 'x' && name[len - 1] != 'y'))
        return 0;
    return fit_is_clip_prefix(name, len - 2) && strncmp(name, "out_", 4) != 0;
}

static unsigned long long splitmix(unsigned long long *st)
{
    unsigned long long z = (*st += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
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

/* The options and inputs fit_system_core can work with; 0 if they are. */
static int check_fit_args(int ninputs, const char *const *inputs, int noutputs,
                          const char *const *outputs, size_t count, const double *in,
                          const fit_options *opt, lens_err *err)
{
    if (ninputs < 1 || ninputs > FIT_MAX_VARS || noutputs < 1) {
        lens_errf(err, NULL, 0, "need 1 to %d inputs and at least one output", FIT_MAX_VARS);
        return -1;
    }
    if (opt->max_terms < 1 || opt->max_degree < 0 || opt->max_degree > FIT_MAX_DEG || opt->max_degree > POLY_MAX_DEGREE ||
        opt->max_parts < 1 || !(opt->holdout >= 0 && opt->holdout < 1) ||
        !(opt->tolerance >= 0)) {
        lens_errf(err, NULL, 0,
                  "bad fit options (terms >= 1, 0 <= degree <= %d, parts >= 1, "
                  "0 <= holdout < 1, tolerance >= 0)",
                  FIT_MAX_DEG < POLY_MAX_DEGREE ? FIT_MAX_DEG : POLY_MAX_DEGREE);
        return -1;
    }
    for (int o = 0; opt->output_tolerance && o < noutputs; o++)
        if (!(opt->output_tolerance[o] >= 0)) {
            lens_errf(err, NULL, 0, "tolerance of %s must not be negative", outputs[o]);
            return -1;
        }
    if (count == 0) {
        lens_errf(err, NULL, 0, "no samples to fit");
        return -1;
    }
    for (size_t r = 0; r < count; r++)
        for (int i = 0; i < ninputs; i++)
            if (!isfinite(in[r * ninputs + i])) {
                lens_errf(err, NULL, 0, "sample %zu: input %s is not finite", r + 1, inputs[i]);
                return -1;
            }
    return 0;
}

/* Copies the usable rows (the rays that pass: every output finite, out_eta > 0) into
 * c->s and c->y; sets c->n. */
static int gather_usable(fit_ctx *c, const char *const *outputs, const double *in,
                         const double *out, lens_err *err)
{
    int ninputs = c->nin, noutputs = c->nout;
    int ieta = find_name(noutputs, outputs, "out_eta");
    size_t n = 0;
    for (size_t r = 0; r < c->count; r++) {
        const double *yo = out + r * noutputs;
        int ok = 1;
        for (int o = 0; o < noutputs; o++)
            ok &= isfinite(yo[o]) != 0;
        if (ok && ieta >= 0 && !(yo[ieta] > 0))
            ok = 0;
        if (!ok)
            continue;
        memcpy(c->s + n * ninputs, in + r * ninputs, (size_t)ninputs * sizeof(double));
        memcpy(c->y + n * noutputs, yo, (size_t)noutputs * sizeof(double));
        n++;
    }
    c->n = n;
    if (n == 0) {
        lens_errf(err, NULL, 0, "none of the %zu samples is usable: every ray is blocked",
                  c->count);
        return -1;
    }
    return 0;
}

/* The range of every input over the usable rows, its scaling to [-1, 1], and c->s
 * scaled by it. */
static int scale_inputs(fit_ctx *c, const char *const *inputs, lens_err *err)
{
    const fit_options *opt = c->opt;
    int ninputs = c->nin;
    size_t n = c->n;
    double *lo = c->lo, *hi = c->hi, *off = c->off, *scl = c->scl;
    for (int i = 0; i < ninputs; i++) {
        lo[i] = INFINITY;
        hi[i] = -INFINITY;
        for (size_t r = 0; r < n; r++) {
            double v = c->s[r * ninputs + i];
            lo[i] = v < lo[i] ? v : lo[i];
            hi[i] = v > hi[i] ? v : hi[i];
        }
        double mag = fabs(lo[i]) > fabs(hi[i]) ? fabs(lo[i]) : fabs(hi[i]);
        if (!(hi[i] - lo[i] > 1e-12 * mag) || hi[i] == lo[i]) {
            lens_errf(err, NULL, 0,
                      "input %s is constant (%.17g) over the %zu usable samples: leave it out "
                      "of the inputs", inputs[i], lo[i], n);
            return -1;
        }
    }
    /* An input whose range straddles 0 evenly (sensor and direction coordinates) is
     * scaled without an offset, so that the symmetry of the lens (out_x odd in x and u,
     * ...) stays a sparsity pattern: an offset of 1e-3 would turn every odd term into a
     * sum of odd and even ones. Others are centred. */
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
            double *v = c->s + r * ninputs + i;
            *v = (*v - off[i]) * (1 / scl[i]); /* as evaluation scales (poly_impl.h) */
        }
    return 0;
}

/* Held-out rays: a seeded shuffle of the distinct rays, so the split is reproducible,
 * and every copy of a ray is on the side of the ray (a held-out copy of a training row
 * would make the held-out error that of a memory). Without copies the split is the
 * shuffle of the rows themselves. */
static int hold_out(fit_ctx *c, lens_err *err)
{
    const fit_options *opt = c->opt;
    size_t n = c->n;
    size_t *group = malloc(n * sizeof *group), *perm = malloc(n * sizeof *perm);
    size_t nd = group && perm ? fit_distinct_rays(c->s, n, c->nin, group) : 0;
    if (!nd) {
        free(group), free(perm);
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    c->ndistinct = nd;
    size_t dho = (size_t)floor(opt->holdout * (double)nd);
    if (nd - dho < (size_t)opt->max_terms) {
        free(group), free(perm);
        if (nd < n)
            lens_errf(err, NULL, 0,
                      "%zu usable samples are %zu distinct rays (%zu for training after "
                      "holding out %zu), fewer than the %d terms asked for: trace more rays "
                      "or lower --terms", n, nd, nd - dho, dho, opt->max_terms);
        else
            lens_errf(err, NULL, 0,
                      "%zu usable samples (%zu for training after holding out %zu) are fewer "
                      "than the %d terms asked for: trace more rays or lower --terms",
                      n, n - dho, dho, opt->max_terms);
        return -1;
    }
    unsigned long long st = opt->seed;
    for (size_t i = 0; i < nd; i++)
        perm[i] = i;
    for (size_t i = nd - 1; i > 0; i--) {
        size_t j = (size_t)(splitmix(&st) % (i + 1));
        size_t t = perm[i]; perm[i] = perm[j]; perm[j] = t;
    }
    unsigned char *held = calloc(nd, 1);
    if (!held) {
        free(group), free(perm);
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    for (size_t i = 0; i < dho; i++)
        held[perm[i]] = 1;
    c->nho = 0;
    for (size_t r = 0; r < n; r++) {
        c->hold[r] = held[group[r]];
        c->nho += c->hold[r];
    }
    free(held), free(group), free(perm);
    return 0;
}

/* c->rad (the sensor radius of every usable row) and c->order (the rows by it), which
 * radial parts are cut along. */
static int order_by_radius(fit_ctx *c, lens_err *err)
{
    int ninputs = c->nin, ix = c->ix, iy = c->iy;
    size_t n = c->n;
    const double *off = c->off, *scl = c->scl;
    c->order = malloc(n * sizeof *c->order);
    c->rad = malloc(n * sizeof *c->rad);
    size_t *tmp = malloc(n * sizeof *tmp);
    if (!c->order || !c->rad || !tmp) {
        free(tmp);
        lens_errf(err, NULL, 0, "out of memory");
        return -1;
    }
    for (size_t r = 0; r < n; r++) {
        c->order[r] = r;
        c->rad[r] = 0;
        if (ix >= 0 && iy >= 0) {
            double x = c->s[r * ninputs + ix] * scl[ix] + off[ix];
            double y = c->s[r * ninputs + iy] * scl[iy] + off[iy];
            c->rad[r] = hypot(x, y);
        } else if (ix >= 0 && c->opt->frame == POLY_FRAME_MERIDIONAL) {
            c->rad[r] = fabs(c->s[r * ninputs + ix] * scl[ix] + off[ix]); /* x is r here */
        }
    }
    sort_by(c->order, tmp, n, c->rad);
    free(tmp);
    return 0;
}

/* The moment table has C(2D + n, n) entries: refuse what would not fit in memory
 * (5 inputs at degree 24 need 2.9e6, 16 inputs at degree 11 2.2e10). */
static int check_moment_count(int ninputs, int degree, lens_err *err)
{
    double moments = 1;
    for (int i = 1; i <= ninputs; i++)
        moments = moments * (2.0 * degree + i) / i;
    if (moments > 2e7) {
        lens_errf(err, NULL, 0,
                  "%d inputs at degree %d need %.3g moments (the limit is 2e7): lower "
                  "--degree or use fewer inputs", ninputs, degree, moments);
        return -1;
    }
    return 0;
}

/* The system of the chosen parts. In the frame (no y), it gets a y that no term uses,
 * so that radial parts (which need x and y) can be written; fit_system drops it again. */
static poly_system *build_system(const fit_ctx *c, const char *lens_name,
                                 const char *const *inputs, const char *const *outputs,
                                 const sys_fit *best, lens_err *err)
{
    int ninputs = c->nin, noutputs = c->nout;
    int extra = c->opt->frame == POLY_FRAME_MERIDIONAL && c->iy < 0 && c->ix >= 0;
    const char *names[FIT_MAX_VARS + 1];
    int ex[FIT_MAX_VARS + 1] = {0};
    for (int i = 0; i < ninputs; i++)
        names[i] = inputs[i];
    names[ninputs] = "y";
    poly_system *sys = poly_new(lens_name, ninputs + extra, names, noutputs, outputs);
    if (!sys) {
        lens_errf(err, NULL, 0, "out of memory");
        return NULL;
    }
    for (int i = 0; i < ninputs; i++) {
        poly_set_scaling(sys, i, c->off[i], c->scl[i]);
        poly_set_domain(sys, i, c->lo[i], c->hi[i]);
    }
    for (int p = 0; p < best->nparts; p++) {
        int pi = poly_add_part(sys, best->p[p].rmin, best->p[p].rmax);
        for (int o = 0; o < noutputs; o++) {
            const out_fit *of = best->p[p].o + o;
            for (int t = 0; t < of->k; t++) {
                memcpy(ex, c->b.exps + (size_t)of->cand[t] * ninputs, (size_t)ninputs * sizeof *ex);
                poly_add_term(sys, pi, o, ex, of->coef[t]);
            }
        }
    }
    return sys;
}

/* Passage: inside the furthest passing hit on the front element (out_*), the stop
 * (ap_*) and each clipping surface N (sN_*, lens-trace --clip-columns). */
static void add_pass_circles(const fit_ctx *c, const char *const *outputs, poly_system *sys)
{
    int noutputs = c->nout;
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
        for (size_t r = 0; r < c->n; r++)
            rmax = fmax(rmax, hypot(c->y[r * noutputs + a], c->y[r * noutputs + bb]));
        poly_add_pass_circle(sys, a, bb, rmax * (1 + 1e-9));
    }
}

/* What was fitted how, as meta lines (lens-poly(5)). */
static void write_fit_meta(const fit_ctx *c, const char *const *outputs, const sys_fit *best,
                           poly_system *sys)
{
    const fit_options *opt = c->opt;
    set_metaf(sys, "fit_flags", "--terms %d --degree %d --parts %d --holdout %.17g --seed %lu",
              opt->max_terms, opt->max_degree, opt->max_parts, opt->holdout, opt->seed);
    if (c->ndistinct < c->n) /* copies of rays: the count that measures the fit */
        set_metaf(sys, "fit_samples", "%zu usable, %zu distinct rays (%zu held out) of %zu",
                  c->n, c->ndistinct, c->nho, c->count);
    else
        set_metaf(sys, "fit_samples", "%zu usable (%zu held out) of %zu", c->n, c->nho, c->count);
    set_metaf(sys, "fit_parts", "%d", best->nparts);
    for (int o = 0; o < c->nout; o++) {
        char key[256];
        int kmax = 0, dmax = 0;
        for (int p = 0; p < best->nparts; p++) {
            const out_fit *of = best->p[p].o + o;
            kmax = of->k > kmax ? of->k : kmax;
            for (int t = 0; t < of->k; t++)
                dmax = c->b.deg[of->cand[t]] > dmax ? c->b.deg[of->cand[t]] : dmax;
        }
        snprintf(key, sizeof key, "fit_%s", outputs[o]);
        char rms[64] = "none"; /* no held-out rows: nothing measured */
        if (isfinite(best->rms[o]))
            snprintf(rms, sizeof rms, "%.6g", best->rms[o]);
        set_metaf(sys, key, "terms %d degree %d holdout_rms %s tolerance %.6g", kmax, dmax, rms,
                  fit_tol_of(opt, o));
        if (best->nparts > 1) {
            snprintf(key, sizeof key, "part_jump_%s", outputs[o]);
            set_metaf(sys, key, "%.6g", best->jump[o]);
        }
    }
}

poly_system *fit_system_core(const char *lens_name, int ninputs, const char *const *inputs,
                             int noutputs, const char *const *outputs, size_t count,
                             const double *in, const double *out, const fit_options *opt,
                             lens_err *err)
{
    if (check_fit_args(ninputs, inputs, noutputs, outputs, count, in, opt, err) != 0)
        return NULL;
    fit_ctx c = {0};
    c.opt = opt;
    c.nin = ninputs;
    c.nout = noutputs;
    c.count = count;
    c.threads = opt->threads > 0 ? opt->threads : omp_get_max_threads();
    c.ix = find_name(ninputs, inputs, "x");
    c.iy = find_name(ninputs, inputs, "y");
    poly_system *sys = NULL;
    sys_fit best = {0};
    c.s = malloc(count * (size_t)ninputs * sizeof *c.s);
    c.y = malloc(count * (size_t)noutputs * sizeof *c.y);
    c.hold = calloc(count, 1);
    c.lo = malloc((size_t)ninputs * sizeof *c.lo);
    c.hi = malloc((size_t)ninputs * sizeof *c.hi);
    c.off = malloc((size_t)ninputs * sizeof *c.off);
    c.scl = malloc((size_t)ninputs * sizeof *c.scl);
    if (!c.s || !c.y || !c.hold || !c.lo || !c.hi || !c.off || !c.scl) {
        lens_errf(err, NULL, 0, "out of memory");
        goto done;
    }
    if (gather_usable(&c, outputs, in, out, err) != 0 || scale_inputs(&c, inputs, err) != 0 ||
        hold_out(&c, err) != 0 || order_by_radius(&c, err) != 0 ||
        check_moment_count(ninputs, opt->max_degree, err) != 0)
        goto done;
    if (fit_basis_init(&c.b, ninputs, opt->max_degree) != 0) {
        lens_errf(err, NULL, 0, "out of memory for the candidates of degree %d", opt->max_degree);
        goto done;
    }
    if (fit_choose_parts(&c, &best, err) != 0)
        goto done;
    sys = build_system(&c, lens_name, inputs, outputs, &best, err);
    if (!sys)
        goto done;
    add_pass_circles(&c, outputs, sys);
    write_fit_meta(&c, outputs, &best, sys);
done:
    sys_fit_free(&best, noutputs);
    fit_basis_free(&c.b);
    free(c.s); free(c.y); free(c.hold); free(c.rad); free(c.order);
    free(c.lo); free(c.hi); free(c.off); free(c.scl);
    return sys;
}
