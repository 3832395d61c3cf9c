/* Fitting the system a scene needs (render_effects.h): training rays drawn the way the
 * renderer will draw camera rays (sensor points over the domain, line-pupil
 * directions), traced exactly, and fitted by fit_system with the scene's inputs and
 * outputs.
 *
 * Passage: the system passes a ray when three circles hold: the ray's height at the
 * rear element's vertex plane (outputs rear_x rear_y, linear in the inputs), its hit on
 * the stop (ap_x ap_y), and, with vignetting, its hit on the front element (out_x
 * out_y). Rays clipped by other rims are not modelled; the vignetting probe of
 * render_effects.c measures how much that matters. */
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/fit.h"
#include "sparselens/glass.h"
#include "sparselens/render.h"
#include "sparselens/render_effects.h"
#include "sparselens/render_lens.h"
#include "sparselens/trace.h"

#define TRAIN_RAYS 6000 /* the supplement fits with 4000; a fifth is held out here */

static double uniform(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

/* Tolerances of out_x out_y out_u out_v ap_x ap_y rear_x rear_y, then nclip pairs of
 * heights on other clipping surfaces, then out_eta:
 *  - directions: a tenth of a pixel over the efl (e->tolerance; see render_effects.c);
 *  - positions on the front element: a shift d there moves the picture of an object at
 *    distance D by about d efl / D, so a tenth of a pixel allows 0.1 pitch D / efl
 *    (D = the focus distance, at most 100 efl); but the outer frame turns with the
 *    position on the front sphere, by d / R, so d is also held to R times the direction
 *    tolerance, and to 1% of the element's radius for a sharp pass circle;
 *  - heights that only decide passage (stop, rear, clipping surfaces): 0.5% of their
 *    radii;
 *  - the transmittance: 0.002, below what a preview's noise shows. */
static int output_tolerances(const lens_t *lens, const render_effects *e, const int *clip,
                             int nclip, double *tol)
{
    const lens_surface *front = &lens->surf[0];
    double D = isfinite(e->focus) ? fmin(e->focus, 100 * e->efl) : 100 * e->efl;
    double pos = fmin(0.1 * e->pixel_pitch * D / e->efl, 0.01 * front->semi_diameter);
    if (isfinite(front->radius)) pos = fmin(pos, e->tolerance * fabs(front->radius));
    int k = 0;
    tol[k++] = pos, tol[k++] = pos;
    tol[k++] = e->tolerance, tol[k++] = e->tolerance;
    tol[k] = tol[k + 1] = 0.005 * lens->surf[lens->stop].semi_diameter, k += 2;
    tol[k] = tol[k + 1] = 0.005 * lens->surf[lens->nsurf - 1].semi_diameter, k += 2;
    for (int c = 0; c < nclip; c++)
        tol[k] = tol[k + 1] = 0.005 * lens->surf[clip[c]].semi_diameter, k += 2;
    tol[k++] = 0.002;
    return k;
}

/* Surfaces other than the front, the stop and the rear that clip at least 1% of the
 * training rays (at most MAX_CLIP, the worst first): their rims get pass circles. */
#define MAX_CLIP 3
static int clipping_surfaces(const lens_t *lens, const trace_result *res, size_t n, int *clip)
{
    size_t ns = lens->nsurf;
    size_t *count = calloc(ns, sizeof *count);
    if (!count) return 0;
    for (size_t i = 0; i < n; i++)
        if (res[i].status == TRACE_CLIPPED && res[i].surface > 0 &&
            res[i].surface != lens->stop && (size_t)res[i].surface + 1 < ns)
            count[res[i].surface]++;
    int nclip = 0;
    while (nclip < MAX_CLIP) {
        size_t best = 0;
        for (size_t k = 1; k < ns; k++)
            if (count[k] > count[best]) best = k;
        if (count[best] < n / 100 || count[best] == 0) break;
        clip[nclip++] = (int)best;
        count[best] = 0;
    }
    free(count);
    return nclip;
}

/* The system of the scaled fit with every coefficient of output o times tol[o]. */
static poly_system *rebuild(const poly_system *s, const double *tol)
{
    int nin = poly_ninputs(s), nout = poly_noutputs(s);
    const char *in[8], *out[16];
    for (int i = 0; i < nin; i++) in[i] = poly_input_name(s, i);
    for (int o = 0; o < nout; o++) out[o] = poly_output_name(s, o);
    poly_system *r = poly_new(poly_lens_name(s), nin, in, nout, out);
    if (!r) return NULL;
    for (int i = 0; i < nin; i++) {
        double a, b;
        poly_get_scaling(s, i, &a, &b);
        poly_set_scaling(r, i, a, b);
        poly_get_domain(s, i, &a, &b);
        poly_set_domain(r, i, a, b);
    }
    for (int p = 0; p < poly_nparts(s); p++) {
        double r0, r1;
        poly_part_range(s, p, &r0, &r1);
        int q = poly_add_part(r, r0, r1);
        for (int o = 0; o < nout; o++)
            for (int t = 0; t < poly_nterms(s, p, o); t++) {
                int ex[8];
                double c;
                poly_get_term(s, p, o, t, ex, &c);
                poly_add_term(r, q, o, ex, c * tol[o]);
            }
    }
    for (int m = 0; m < poly_nmeta(s); m++) {
        const char *k = poly_meta_key(s, m);
        if (strcmp(k, "fit_flags")) poly_set_meta(r, k, poly_get_meta(s, k));
    }
    return r;
}

poly_system *render_fit(const lens_t *lens, const render_effects *e, int threads,
                        double *seconds, lens_err *err)
{
    double t0 = omp_get_wtime();
    poly_system *sys = NULL;
    render_sampler smp = {0};
    size_t N = TRAIN_RAYS;
    double *in5 = malloc(N * 5 * sizeof *in5), *outer = malloc(N * 5 * sizeof *outer),
           *stop = malloc(N * 5 * sizeof *stop), *X = malloc(N * 5 * sizeof *X),
           *Y = malloc(N * 16 * sizeof *Y);
    trace_result *res = malloc(N * sizeof *res);
    if (!in5 || !outer || !stop || !X || !Y || !res) {
        lens_errf(err, lens->path, 0, "out of memory");
        goto done;
    }
    if (render_sampler_lens(&smp, lens, e->dispersion ? RENDER_LAMBDA_MIN : GLASS_D_LINE,
                            e->dispersion ? RENDER_LAMBDA_MAX : GLASS_D_LINE, e->domain_radius,
                            threads, err))
        goto done;
    uint64_t st = 0x5EED;
    size_t k = 0;
    for (size_t guard = 0; k < N && guard < 50 * N; guard++) {
        double r = e->domain_radius * sqrt(uniform(&st)), a = 2 * M_PI * uniform(&st);
        double x = r * cos(a), y = r * sin(a), u, v;
        if (!(render_sampler_sample(&smp, x, y, uniform(&st), uniform(&st), &u, &v) > 0))
            continue;
        double lam = e->dispersion ? RENDER_LAMBDA_MIN +
                                         uniform(&st) * (RENDER_LAMBDA_MAX - RENDER_LAMBDA_MIN)
                                   : GLASS_D_LINE;
        double *row = in5 + 5 * k++;
        row[0] = x, row[1] = y, row[2] = u, row[3] = v, row[4] = lam;
    }
    N = k;
    if (trace_batch(lens, TRACE_TO_OUTER, N, in5, outer, res, threads, err) ||
        trace_batch(lens, TRACE_TO_STOP, N, in5, stop, NULL, threads, err))
        goto done;
    const lens_surface *rear = &lens->surf[lens->nsurf - 1];
    const char *inputs[5] = {"x", "y", "u", "v", "lambda"};
    int clip[MAX_CLIP], nclip = clipping_surfaces(lens, res, N, clip);
    char clip_names[MAX_CLIP][2][24];
    const char *outputs[16] = {"out_x", "out_y", "out_u", "out_v", "ap_x", "ap_y",
                               "rear_x", "rear_y"};
    int nout = 8;
    for (int c = 0; c < nclip; c++)
        for (int a = 0; a < 2; a++) {
            snprintf(clip_names[c][a], sizeof clip_names[c][a], "s%d_%c", clip[c] + 1, "xy"[a]);
            outputs[nout++] = clip_names[c][a];
        }
    if (e->transmittance) outputs[nout++] = "out_eta";
    int nin = e->dispersion ? 5 : 4;
    size_t used = 0;
    double *nbuf = malloc(lens->nsurf * sizeof *nbuf);
    if (!nbuf) {
        lens_errf(err, lens->path, 0, "out of memory");
        goto done;
    }
    for (size_t i = 0; i < N; i++) {
        const double *o = outer + 5 * i, *s = stop + 5 * i, *p = in5 + 5 * i;
        if (!(o[4] > 0) || !(s[4] > 0)) continue; /* blocked: nothing to fit */
        memcpy(X + (size_t)nin * used, p, nin * sizeof *X);
        double *q = Y + (size_t)nout * used;
        q[0] = o[0], q[1] = o[1], q[2] = o[2], q[3] = o[3], q[4] = s[0], q[5] = s[1];
        q[6] = p[0] + rear->thickness * p[2];
        q[7] = p[1] + rear->thickness * p[3];
        if (nclip) {
            for (size_t k = 0; k < lens->nsurf; k++)
                nbuf[k] = glass_index_unchecked(&lens->surf[k].medium, p[4]);
            for (int c = 0; c < nclip; c++) { /* the ray's hit on that surface */
                lens_ray r;
                ray_from_sensor(lens, p, &r);
                trace_to_object(lens, nbuf, &r, clip[c]);
                q[8 + 2 * c] = r.o[0], q[9 + 2 * c] = r.o[1];
            }
        }
        if (e->transmittance) q[nout - 1] = o[4];
        used++;
    }
    free(nbuf);
    /* per-output tolerances (the fitter has one): outputs are divided by theirs and
     * fitted to tolerance 1, and the coefficients scaled back in rebuild() */
    double tol[16];
    output_tolerances(lens, e, clip, nclip, tol);
    for (size_t i = 0; i < used; i++)
        for (int o = 0; o < nout; o++) Y[i * nout + o] /= tol[o];
    fit_options opt;
    fit_options_default(&opt);
    opt.tolerance = 1;
    opt.threads = threads;
    poly_system *scaled = fit_system(lens->name, nin, inputs, nout, outputs, used, X, Y, &opt, err);
    if (!scaled) goto done;
    sys = rebuild(scaled, tol);
    poly_free(scaled);
    if (!sys) {
        lens_errf(err, lens->path, 0, "out of memory");
        goto done;
    }
    poly_set_lens_path(sys, lens->path);
    poly_add_pass_circle(sys, 4, 5, lens->surf[lens->stop].semi_diameter);
    poly_add_pass_circle(sys, 6, 7, rear->semi_diameter);
    if (e->vignetting) {
        poly_add_pass_circle(sys, 0, 1, lens->surf[0].semi_diameter);
        for (int c = 0; c < nclip; c++)
            poly_add_pass_circle(sys, 8 + 2 * c, 9 + 2 * c, lens->surf[clip[c]].semi_diameter);
    }
    char buf[160];
    snprintf(buf, sizeof buf, "lens-render: dispersion %d transmittance %d vignetting %d "
             "domain %.6g mm tolerance %.6g, %zu rays",
             e->dispersion, e->transmittance, e->vignetting, e->domain_radius, e->tolerance, used);
    poly_set_meta(sys, "fitted-by", buf);
    int len = 0;
    for (int o = 0; o < nout && len < (int)sizeof buf - 12; o++)
        len += snprintf(buf + len, sizeof buf - len, "%s%.3g", o ? " " : "", tol[o]);
    poly_set_meta(sys, "tolerances", buf); /* the fit_* holdout_rms are in these units */
    snprintf(buf, sizeof buf, "%.17g", rear->thickness);
    poly_set_meta(sys, "sensor-distance", buf);
done:
    *seconds = omp_get_wtime() - t0;
    render_sampler_free(&smp);
    free(in5);
    free(outer);
    free(stop);
    free(X);
    free(Y);
    free(res);
    return sys;
}
