/* Fitting the system a scene needs (render_effects.h): training rays drawn the way the
 * renderer will draw camera rays (sensor points over the domain, line-pupil
 * directions), blocked ones included, traced exactly, and fitted by fit_system with the
 * scene's inputs and outputs.
 *
 * Passage (lens-trace(1), PASSAGE): the system passes a ray when its hits on the stop
 * (ap_x ap_y) and on every surface that limits the beam (sN_x sN_y, found by
 * trace_clip_pilot over the whole ray space, weighted by light; the front element
 * among them) lie within their rims. The hits are those of the ray traced with every rim extended, taken where the ray
 * really meets each surface, and are fitted on the blocked training rays too, so the
 * fit sees both sides of each rim. Without vignetting only the stop and the surfaces
 * behind it (towards the sensor) are modelled: the stop's line pupil the renderer then
 * draws from leaves out the front group's clipping on purpose. */
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
#include "sparselens/sampling.h"
#include "sparselens/trace.h"
#include "sparselens/clip_pilot.h"
#include "sparselens/trace_clip.h"

#define TRAIN_RAYS 12000 /* the supplement fits with 4000; passage and the axis want more (tests/unit/render) */

static double uniform(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

/* Tolerances of out_x out_y out_u out_v ap_x ap_y, then nclip pairs of hits on other
 * surfaces, then out_eta:
 *  - directions: a tenth of a pixel over the efl (e->tolerance; see render_effects.c);
 *  - positions on the front element: a shift d there moves the picture of an object at
 *    distance D by about d efl / D, so a tenth of a pixel allows 0.1 pitch D / efl
 *    (D = the focus distance, at most 100 efl); but the outer frame turns with the
 *    position on the front sphere, by d / R, so d is also held to R times the direction
 *    tolerance, and to 1% of the element's radius for a sharp pass circle;
 *  - hits that only decide passage (stop, clipping surfaces): 0.1% of their radii (the
 *    light within that of a rim is a few tenths of a percent; reports/vignetting.md);
 *  - the transmittance: 0.0005, a tenth of a percent of the light (a white furnace
 *    through the system stays within 0.5% of the lens's: tests/unit/render). */
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
    tol[k] = tol[k + 1] = 0.0005 * lens->surf[lens->stop].semi_diameter, k += 2;
    for (int c = 0; c < nclip; c++)
        tol[k] = tol[k + 1] = 0.0005 * lens->surf[clip[c]].semi_diameter, k += 2;
    tol[k++] = 0.0005;
    return k;
}

/* The surfaces besides the stop that limit the beam over the whole ray space
 * (trace_clip_pilot; at most MAX_CLIP: the system's outputs must fit a camera), the
 * front element among them: its hit out_x out_y is fitted only as precisely as the
 * picture needs (ten times looser than a rim test, and from passing rays alone), so
 * its rim gets a passage pair like any other. Without vignetting only the surfaces
 * behind the stop. */
#define MAX_CLIP 8
#define PILOT_RAYS 65536
#define CLIP_MIN_SHARE 0.0005
static int clipping_surfaces(const lens_t *lens, const render_effects *e, int threads,
                             int *clip, lens_err *err)
{
    sampling_options so = sampling_defaults();
    so.sensor_w = so.sensor_h = 2 * e->domain_radius;
    so.lambda_min = e->dispersion ? RENDER_LAMBDA_MIN : GLASS_D_LINE;
    so.lambda_max = e->dispersion ? RENDER_LAMBDA_MAX : GLASS_D_LINE;
    so.seed = 20161;
    so.threads = threads;
    double *share = malloc(lens->nsurf * sizeof *share), leak;
    int *surf = malloc(lens->nsurf * sizeof *surf);
    int n = -1;
    if (share && surf)
        n = trace_clip_pilot(lens, &so, PILOT_RAYS, CLIP_MIN_SHARE, 0, MAX_CLIP, share, surf,
                             &leak, err);
    else
        lens_errf(err, lens->path, 0, "out of memory");
    int k = 0;
    for (int i = 0; i < n; i++)
        if (e->vignetting ? surf[i] != lens->stop : surf[i] > lens->stop)
            clip[k++] = surf[i];
    free(share);
    free(surf);
    return n < 0 ? -1 : k;
}

/* The system of the scaled fit with every coefficient of output o times tol[o]. */
static poly_system *rebuild(const poly_system *s, const double *tol)
{
    int nin = poly_ninputs(s), nout = poly_noutputs(s);
    const char *in[8], *out[24];
    for (int i = 0; i < nin; i++) in[i] = poly_input_name(s, i);
    for (int o = 0; o < nout; o++) out[o] = poly_output_name(s, o);
    poly_system *r = poly_new(poly_lens_name(s), nin, in, nout, out);
    if (!r) return NULL;
    poly_set_frame(r, poly_get_frame(s));
    for (int o = 0; o < nout; o++) poly_set_output_plain(r, o, poly_get_output_plain(s, o));
    for (int i = 0; i < nin; i++) {
        double a, b;
        poly_set_transform(r, i, poly_get_transform(s, i));
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

/* Training rays drawn the way the renderer draws camera rays: n sensor points over
 * the domain, a third uniform over the disc, a third uniform in radius (the axis, where a
 * small pixel sees the rims of the on-axis beam, gets rays enough for a sure fit) and a
 * third uniform in the outer tenth of the radius (the sensor's corners, where a fisheye
 * passes a sliver of light past its image circle at grazing incidence: with half over
 * the disc and half in radius fisheye-ii's corner pixel took 3.2% too much light, 1.7%
 * of it the front rim and 1.5% the transmittance; tests/unit/render/test_render_poly.c),
 * with line-pupil directions. Rows x y u v lambda in in5; returns how many. */
static size_t draw_training_rays(const render_sampler *smp, const render_effects *e, size_t n,
                                 double *in5)
{
    uint64_t st = 0x5EED;
    size_t k = 0;
    for (size_t guard = 0; k < n && guard < 50 * n; guard++) {
        double q = uniform(&st), a = 2 * M_PI * uniform(&st);
        double r = e->domain_radius * (k % 3 == 0 ? sqrt(q) : k % 3 == 1 ? q : 1 - 0.1 * q);
        double x = r * cos(a), y = r * sin(a), u, v;
        if (!(render_sampler_sample(smp, x, y, uniform(&st), uniform(&st), &u, &v) > 0))
            continue;
        double lam = e->dispersion ? RENDER_LAMBDA_MIN +
                                         uniform(&st) * (RENDER_LAMBDA_MAX - RENDER_LAMBDA_MIN)
                                   : GLASS_D_LINE;
        double *row = in5 + 5 * k++;
        row[0] = x, row[1] = y, row[2] = u, row[3] = v, row[4] = lam;
    }
    return k;
}

/* The outputs' names: the outer pupil, the stop's hit, the hits on the clipping
 * surfaces clip[0..nclip-1], out_eta with transmittance. Returns their number. */
static int output_names(const render_effects *e, const int *clip, int nclip,
                        char (*clip_names)[2][24], const char **outputs)
{
    static const char *const fixed[6] = {"out_x", "out_y", "out_u", "out_v", "ap_x", "ap_y"};
    int nout = 6;
    memcpy(outputs, fixed, sizeof fixed);
    for (int c = 0; c < nclip; c++)
        for (int a = 0; a < 2; a++) {
            snprintf(clip_names[c][a], sizeof clip_names[c][a], "s%d_%c", clip[c] + 1, "xy"[a]);
            outputs[nout++] = clip_names[c][a];
        }
    if (e->transmittance) outputs[nout++] = "out_eta";
    return nout;
}

/* Every ray is a row: the outer pupil (and out_eta) where it passes, nan where not,
 * which fit_system leaves out of those outputs; the hits (nsel pairs) wherever they
 * exist. Each output divided by its tolerance. */
static void training_rows(const render_effects *e, size_t n, int nin, int nout, int nsel,
                          const double *in5, const double *outer, const double *hits,
                          const double *tol, double *X, double *Y)
{
    for (size_t i = 0; i < n; i++) {
        const double *o = outer + 5 * i, *h = hits + 2 * (size_t)nsel * i;
        int pass = o[4] > 0;
        memcpy(X + (size_t)nin * i, in5 + 5 * i, nin * sizeof *X);
        double *q = Y + (size_t)nout * i;
        for (int c = 0; c < 4; c++) q[c] = pass ? o[c] : NAN;
        memcpy(q + 4, h, 2 * (size_t)nsel * sizeof *q);
        if (e->transmittance) q[nout - 1] = pass ? o[4] : NAN;
        for (int c = 0; c < nout; c++) q[c] /= tol[c];
    }
}

/* The rims: the hits are exact where the ray meets each surface, so a rim is the
 * semi-diameter itself, unless the element's two surfaces cross inside it (as
 * fisheye-ii's 15-16 do, by 0.16 mm at the rim): a ray then misses the next surface
 * short of the rim, and the rim is the furthest passing hit, fit_system's circle
 * (in units of the tolerance). clip[0] is the stop. */
static void set_rims(poly_system *sys, const poly_system *scaled, const lens_t *lens,
                     const int *clip, const double *tol)
{
    for (int c = 0; c < poly_npass_circles(scaled); c++) {
        int a, b;
        double r, at;
        poly_get_pass_circle(scaled, c, &a, &b, &r);
        if (a == 0)
            continue; /* out_x out_y: the front's rim is a passage pair when it limits */
        int surf = clip[(a - 4) / 2];
        int cross = surf > 0 && lens_min_gap(lens, (size_t)surf - 1, &at) < 0;
        poly_add_pass_circle(sys, a, b, cross ? r * tol[a] : lens->surf[surf].semi_diameter);
    }
}

/* How the system was fitted, as meta lines. */
static void record_fit(poly_system *sys, const lens_t *lens, const render_effects *e, size_t n,
                       int nout, const double *tol)
{
    char buf[160];
    snprintf(buf, sizeof buf, "lens-render: dispersion %d transmittance %d vignetting %d "
             "domain %.6g mm tolerance %.6g, %zu rays",
             e->dispersion, e->transmittance, e->vignetting, e->domain_radius, e->tolerance, n);
    poly_set_meta(sys, "fitted-by", buf);
    poly_set_meta(sys, "passage", e->vignetting ? "full" : "partial: vignetting off (the stop "
                                                            "and the surfaces behind it)");
    int len = 0;
    for (int o = 0; o < nout && len < (int)sizeof buf - 12; o++)
        len += snprintf(buf + len, sizeof buf - len, "%s%.3g", o ? " " : "", tol[o]);
    poly_set_meta(sys, "tolerances", buf); /* the fit_* holdout_rms are in these units */
    snprintf(buf, sizeof buf, "%.17g", lens->surf[lens->nsurf - 1].thickness);
    poly_set_meta(sys, "sensor-distance", buf);
}

poly_system *render_fit(const lens_t *lens, const render_effects *e, int threads,
                        double *seconds, lens_err *err)
{
    double t0 = omp_get_wtime();
    poly_system *sys = NULL;
    render_sampler smp = {0};
    size_t N = TRAIN_RAYS;
    int clip[MAX_CLIP + 1], nclip = clipping_surfaces(lens, e, threads, clip + 1, err);
    if (nclip < 0) {
        *seconds = omp_get_wtime() - t0;
        return NULL;
    }
    clip[0] = lens->stop; /* the hits wanted: the stop, then the clip surfaces */
    double *in5 = malloc(N * 5 * sizeof *in5), *outer = malloc(N * 5 * sizeof *outer),
           *hits = malloc(N * 2 * (MAX_CLIP + 1) * sizeof *hits), *X = malloc(N * 5 * sizeof *X),
           *Y = malloc(N * 24 * sizeof *Y);
    if (!in5 || !outer || !hits || !X || !Y) {
        lens_errf(err, lens->path, 0, "out of memory");
        goto done;
    }
    if (render_sampler_lens(&smp, lens, e->dispersion ? RENDER_LAMBDA_MIN : GLASS_D_LINE,
                            e->dispersion ? RENDER_LAMBDA_MAX : GLASS_D_LINE, e->domain_radius,
                            threads, err))
        goto done;
    N = draw_training_rays(&smp, e, N, in5);
    int nsel = 1 + nclip;
    if (trace_batch(lens, TRACE_TO_OUTER, N, in5, outer, NULL, threads, err) ||
        trace_surfaces_batch(lens, nsel, clip, N, in5, hits, threads, err))
        goto done;
    const char *inputs[5] = {"x", "y", "u", "v", "lambda"};
    char clip_names[MAX_CLIP][2][24];
    const char *outputs[24];
    int nout = output_names(e, clip + 1, nclip, clip_names, outputs);
    int nin = e->dispersion ? 5 : 4;
    /* per-output tolerances: outputs are divided by theirs and fitted to tolerance 1
     * (passage hits included: no passage tolerance on top), and the coefficients scaled
     * back in rebuild() */
    double tol[24];
    output_tolerances(lens, e, clip + 1, nclip, tol);
    training_rows(e, N, nin, nout, nsel, in5, outer, hits, tol, X, Y);
    fit_options opt;
    fit_options_default(&opt);
    opt.tolerance = 1;
    opt.passage_tolerance = 0;
    opt.threads = threads;
    /* radial parts where one polynomial misses a tolerance (the transmittance at the
     * edge of a fisheye's image circle), and 1/lambda^2, in which dispersion is nearly
     * linear (reports/fit.md); no meridional frame: the full estimator needs the
     * system's Jacobian on the axis, where the frame's is not defined */
    opt.max_parts = 3;
    opt.lambda_transform = e->dispersion ? POLY_XFORM_INVERSE_SQUARE : POLY_XFORM_IDENTITY;
    poly_system *scaled = fit_system(lens->name, nin, inputs, nout, outputs, N, X, Y, &opt, err);
    if (!scaled) goto done;
    sys = rebuild(scaled, tol);
    if (!sys) {
        poly_free(scaled);
        lens_errf(err, lens->path, 0, "out of memory");
        goto done;
    }
    poly_set_lens_path(sys, lens->path);
    set_rims(sys, scaled, lens, clip, tol);
    poly_free(scaled);
    record_fit(sys, lens, e, N, nout, tol);
done:
    *seconds = omp_get_wtime() - t0;
    render_sampler_free(&smp);
    free(in5);
    free(outer);
    free(hits);
    free(X);
    free(Y);
    return sys;
}
