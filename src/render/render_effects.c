/* "Simulate only the effects a scene calls for": the choices, the measurements behind
 * the automatic ones, and the cache of fitted systems (render_effects.h). Every choice
 * depends on the lens and the scene only, never on spp: a preview and the final render
 * use the same system.
 *
 *  - dispersion: lambda is an input only when some glass of the lens disperses (its
 *    index differs over the render's wavelengths) and the scene is not grey; off, every
 *    wavelength of a camera sample shares one ray (render_image.c). Dropped error: the
 *    lateral colour at the field edge, the shift between the chief rays of the band
 *    ends, in pixels;
 *  - transmittance: on when the mean Fresnel transmittance changes by more than 1% from
 *    the centre to the edge of the sensor in use; off, the image is weighted by the mean
 *    transmittance on the axis, so its exposure matches the exact lens. Dropped error:
 *    that change, the brightness error at the edge;
 *  - vignetting: the pass circles of the front element and the other clipping rims
 *    beside the stop's, and camera directions drawn from the line pupil of the whole
 *    lens; on when the front group clips more than 2% of the light through the stop at
 *    the edge (the cat's eye). Off, the system keeps the stop's and the rear's circles
 *    and directions come from the line pupil of the stop alone (render_sampler_stop),
 *    so the switch changes the picture. Dropped error: that share, the brightness
 *    error at the edge;
 *  - domain: the sensor area rendered (half its diagonal), not the lens's whole field;
 *  - tolerance: a tenth of a pixel. Directions at the outer pupil carry the image
 *    position: an angle error da moves the picture by about efl * da on the sensor, so
 *    the direction tolerance is 0.1 * pitch / efl. Positions on the front element move
 *    the picture far less (by the magnification of the scene), and share it.
 * A scene's "transmittance|vignetting|dispersion on|off" overrides the choice. */
#include "sparselens/render_effects.h"

#include <limits.h>
#include <errno.h>
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sparselens/glass.h"
#include "sparselens/outfile.h"
#include "sparselens/paraxial.h"
#include "sparselens/trace.h"

#define PROBE_N 24 /* directions per axis in the vignetting probe */
#define VIGNETTING_BAR 0.02
#define TRANSMITTANCE_BAR 0.01

/* Lateral colour at sensor radius r, mm on the sensor: the chief ray from (r, 0) (aimed
 * through the stop's centre at the d line) leaves the lens at the two band ends in
 * directions da apart, and the pictures of a far object at the two wavelengths then lie
 * about efl * da apart. */
static double lateral_colour(const lens_t *lens, double r)
{
    double n0[lens->nsurf], n1[lens->nsurf], nd[lens->nsurf];
    lens_err e2;
    if (lens_indices(lens, RENDER_LAMBDA_MIN, n0, &e2) || lens_indices(lens, RENDER_LAMBDA_MAX, n1, &e2) ||
        lens_indices(lens, GLASS_D_LINE, nd, &e2))
        return 0;
    /* the chief ray at the d line: the direction from (r, 0) whose stop hit is nearest
     * the axis, by a short search over u */
    const lens_surface *rear = &lens->surf[lens->nsurf - 1];
    double best_u = -r / rear->thickness, best = INFINITY;
    for (int it = 0; it < 3; it++) {
        double span = (it == 0 ? 1.0 : it == 1 ? 0.05 : 0.0025), centre = best_u;
        for (int k = -20; k <= 20; k++) {
            double u = centre + span * k / 20, in[4] = {r, 0, u, 0}, out[4];
            trace_result t = trace_sample(lens, nd, TRACE_TO_STOP, in, out);
            if (t.status == TRACE_PASSED && fabs(out[0]) < best) best = fabs(out[0]), best_u = u;
        }
    }
    double in[4] = {r, 0, best_u, 0}, a[4], b[4];
    trace_result ta = trace_sample(lens, n0, TRACE_TO_OUTER, in, a);
    trace_result tb = trace_sample(lens, n1, TRACE_TO_OUTER, in, b);
    if (ta.status != TRACE_PASSED || tb.status != TRACE_PASSED) return 0;
    lens_ray ra, rb;
    if (ray_from_outer(lens, a, &ra) || ray_from_outer(lens, b, &rb)) return 0;
    double dot = ra.d[0] * rb.d[0] + ra.d[1] * rb.d[1] + ra.d[2] * rb.d[2];
    paraxial_data p;
    if (paraxial_compute(lens, GLASS_D_LINE, &p, &e2)) return 0;
    return acos(fmin(1, dot)) * fabs(p.efl);
}

/* Share of rays from sensor point (r, 0), aimed over the rear element, that pass the
 * stop and are then clipped in front of it; and the mean transmittance of the rays
 * that pass the whole lens. */
static void probe_field(const lens_t *lens, const double *n, double r, double *loss,
                        double *eta_mean)
{
    const lens_surface *rear = &lens->surf[lens->nsurf - 1];
    double h = rear->thickness, R = rear->semi_diameter;
    long through_stop = 0, clipped = 0, passed = 0;
    double eta = 0;
    for (int i = 0; i < PROBE_N; i++)
        for (int j = 0; j < PROBE_N; j++) {
            double px = R * (2.0 * (i + 0.5) / PROBE_N - 1), py = R * (2.0 * (j + 0.5) / PROBE_N - 1);
            if (px * px + py * py > R * R) continue;
            double in[4] = {r, 0, (px - r) / h, py / h}, out[4];
            trace_result s = trace_sample(lens, n, TRACE_TO_STOP, in, out);
            if (s.status != TRACE_PASSED) continue;
            through_stop++;
            trace_result f = trace_sample(lens, n, TRACE_TO_OUTER, in, out);
            if (f.status != TRACE_PASSED) {
                clipped++;
                continue;
            }
            passed++;
            eta += f.transmittance;
        }
    *loss = through_stop ? (double)clipped / through_stop : 0;
    *eta_mean = passed ? eta / passed : 0;
}

int render_lens_disperses(const lens_t *lens)
{
    for (size_t i = 0; i < lens->nsurf; i++) {
        double a = glass_index_unchecked(&lens->surf[i].medium, RENDER_LAMBDA_MIN),
               b = glass_index_unchecked(&lens->surf[i].medium, RENDER_LAMBDA_MAX);
        if (fabs(a - b) > 1e-9) return 1;
    }
    return 0;
}

int render_effects_eta_centre(const lens_t *lens, double *eta, lens_err *err)
{
    double n[lens->nsurf], loss;
    if (lens_indices(lens, GLASS_D_LINE, n, err)) return -1;
    probe_field(lens, n, 0, &loss, eta);
    return 0;
}

int render_effects_decide(const scene_t *s, const lens_t *lens, double sw, double sh,
                          render_effects *e, lens_err *err)
{
    memset(e, 0, sizeof *e);
    paraxial_data p;
    if (paraxial_compute(lens, GLASS_D_LINE, &p, err)) return -1;
    e->efl = fabs(p.efl);
    e->focus = isnan(s->focus) ? p.focus_distance : s->focus;
    e->disperses = render_lens_disperses(lens);
    e->dispersion = s->dispersion == EFFECT_AUTO ? s->mode != SCENE_GREY && e->disperses
                                                 : s->dispersion == EFFECT_ON;
    e->domain_radius = 0.5 * hypot(sw, sh);
    e->pixel_pitch = fmin(sw / s->width, sh / s->height);
    e->tolerance = 0.1 * e->pixel_pitch / e->efl;
    double n[lens->nsurf];
    if (lens_indices(lens, GLASS_D_LINE, n, err)) return -1;
    double loss_edge, eta_edge, loss_centre, eta_centre;
    probe_field(lens, n, 0, &loss_centre, &eta_centre);
    /* the edge of the field that still sends light: a fisheye's image circle may end
     * inside the sensor's corners */
    double r_edge = e->domain_radius;
    for (int k = 0; k < 20; k++, r_edge *= 0.95) {
        probe_field(lens, n, r_edge, &loss_edge, &eta_edge);
        if (eta_edge > 0) break;
    }
    e->vignetting_loss = loss_edge;
    e->eta_centre = eta_centre;
    e->eta_variation = eta_centre > 0 ? fabs(eta_edge - eta_centre) / eta_centre : 0;
    e->vignetting = s->vignetting == EFFECT_AUTO ? loss_edge > VIGNETTING_BAR
                                                 : s->vignetting == EFFECT_ON;
    e->transmittance = s->transmittance == EFFECT_AUTO ? e->eta_variation > TRANSMITTANCE_BAR
                                                       : s->transmittance == EFFECT_ON;
    e->lateral_colour_px = e->disperses ? lateral_colour(lens, r_edge) / e->pixel_pitch : 0;
    return 0;
}

void render_effects_print(FILE *f, const render_effects *e)
{
    if (!f) return;
    char on[128] = "", off[128] = "";
    const char *names[3] = {"dispersion", "transmittance", "vignetting"};
    int flags[3] = {e->dispersion, e->transmittance, e->vignetting};
    for (int k = 0; k < 3; k++) {
        char *dst = flags[k] ? on : off;
        if (*dst) strcat(dst, " ");
        strcat(dst, names[k]);
    }
    fprintf(f, "effects on: %s\n", *on ? on : "(none)");
    fprintf(f, "effects off: %s\n", *off ? off : "(none)");
    fprintf(f, "effect dispersion: %s; glasses %s; dropped, lateral colour at the edge "
               "%.2f px\n", e->dispersion ? "on" : "off", e->disperses ? "disperse" : "do not disperse",
            e->lateral_colour_px);
    fprintf(f, "effect transmittance: %s (when > %.0f%%); dropped, the edge is %.2f%% off in "
               "brightness\n", e->transmittance ? "on" : "off", 100 * TRANSMITTANCE_BAR,
            100 * e->eta_variation);
    fprintf(f, "effect vignetting: %s (when > %.0f%%); dropped, the edge is %.2f%% too bright "
               "(front-group clipping %.1f%%)\n", e->vignetting ? "on" : "off", 100 * VIGNETTING_BAR,
            e->vignetting_loss < 1 ? 100 * e->vignetting_loss / (1 - e->vignetting_loss) : INFINITY,
            100 * e->vignetting_loss);
    fprintf(f, "fit domain: sensor radius %.3g mm; tolerance %.3g (a tenth of a %.3g mm pixel "
               "over efl %.4g mm)\n",
            e->domain_radius, e->tolerance, e->pixel_pitch, e->efl);
}

/* FNV-1a, 64 bit: a cache key, not a security measure. */
static uint64_t fnv(uint64_t h, const void *data, size_t len)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < len; i++) h = (h ^ p[i]) * 0x100000001b3ull;
    return h;
}

/* The lens as written, and its indices at three wavelengths: a glass name resolved in
 * another catalog (--glass-catalog) must not find a system fitted to the first one. */
static uint64_t lens_hash(const lens_t *lens)
{
    uint64_t h = 0xcbf29ce484222325ull;
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    if (m) {
        lens_write(m, lens);
        fclose(m);
        h = fnv(h, buf, len);
    }
    free(buf);
    const double lam[3] = {0.45, GLASS_D_LINE, 0.65};
    for (size_t i = 0; i < lens->nsurf; i++)
        for (int k = 0; k < 3; k++) {
            double n = glass_index_unchecked(&lens->surf[i].medium, lam[k]);
            h = fnv(h, &n, sizeof n);
        }
    return h;
}

/* The version in the key changes whenever render_fit's systems do (v3: the faithful
 * passage; v4: the outer frame that turns with the ray and training
 * rays in the sensor's corners), so that a cache never serves a system of older code. */
void render_effects_key(const lens_t *lens, const render_effects *e, char key[17])
{
    uint64_t h = lens_hash(lens);
    char eff[160];
    int n = snprintf(eff, sizeof eff, "v4 disp %d eta %d vig %d r %.6g tol %.6g D %.6g",
                     e->dispersion, e->transmittance, e->vignetting, e->domain_radius,
                     e->tolerance, e->focus);
    h = fnv(h, eff, (size_t)n);
    snprintf(key, 17, "%016llx", (unsigned long long)h);
}

void render_default_cache_dir(char *buf, size_t len)
{
    const char *x = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    int n = -1;
    if (x && *x) n = snprintf(buf, len, "%s/sparselens", x);
    else if (home && *home) n = snprintf(buf, len, "%s/.cache/sparselens", home);
    /* none, or one too long to hold whole: no cache (never a cut name elsewhere) */
    if ((n < 0 || (size_t)n >= len) && len) buf[0] = 0;
}

/* mkdir -p for the cache; failures only mean no caching. */
static int make_dirs(const char *dir)
{
    char tmp[PATH_MAX];
    if (strlen(dir) >= sizeof tmp) return -1;
    snprintf(tmp, sizeof tmp, "%s", dir);
    for (char *p = tmp + 1; *p; p++)
        if (*p == '/') {
            *p = 0;
            if (mkdir(tmp, 0777) && errno != EEXIST) return -1;
            *p = '/';
        }
    return mkdir(tmp, 0777) && errno != EEXIST ? -1 : 0;
}

/* Fits or loads one system; *fit_s gets the fitting time (0 when cached). */
static poly_system *obtain(const lens_t *lens, const render_effects *e, const char *dir,
                           int threads, FILE *log, double *fit_s, lens_err *err)
{
    char key[17], path[PATH_MAX + 64] = "";
    render_effects_key(lens, e, key);
    *fit_s = 0;
    if (dir && *dir) {
        if (snprintf(path, sizeof path, "%s/%s.poly", dir, key) >= (int)sizeof path)
            path[0] = 0; /* a cache path too long to hold: no caching */
        FILE *f = fopen(path, "r");
        if (f) {
            fclose(f);
            poly_system *sys = NULL;
            lens_err e2;
            if (poly_read(path, &sys, &e2) == 0) {
                if (log) fprintf(log, "system: cached %s\n", path);
                return sys;
            }
            if (log) fprintf(log, "cache: ignoring unreadable %s (%s)\n", path, e2.msg);
        }
    }
    poly_system *sys = render_fit(lens, e, threads, fit_s, err);
    if (!sys) return NULL;
    if (log) fprintf(log, "system: fitted in %.2f s\n", *fit_s);
    if (*path && make_dirs(dir) == 0) {
        lens_err e2;
        outfile *of = outfile_open(path, &e2);
        if (of && poly_write(outfile_stream(of), sys) == 0 && outfile_commit(of, &e2) == 0) {
            if (log) fprintf(log, "cache: wrote %s\n", path);
        } else {
            if (of) outfile_abort(of);
            if (log) fprintf(log, "cache: cannot write %s\n", path);
        }
    }
    return sys;
}

int render_effects_sampler(const lens_t *lens, double lambda_min, double lambda_max,
                           double rmax, int stop_only, const char *dir, int threads, FILE *log,
                           render_sampler *smp, lens_err *err)
{
    uint64_t h = lens_hash(lens);
    char tag[160], path[PATH_MAX + 64] = "";
    int n = snprintf(tag, sizeof tag, "%s v1 %.17g %.17g %.17g", stop_only ? "stop" : "pupil",
                     lambda_min, lambda_max, rmax);
    h = fnv(h, tag, (size_t)n);
    memset(smp, 0, sizeof *smp);
    smp->kind = RENDER_SAMPLE_PUPIL;
    if (dir && *dir) {
        if (snprintf(path, sizeof path, "%s/%016llx.pupil", dir, (unsigned long long)h) >=
            (int)sizeof path)
            path[0] = 0; /* a cache path too long to hold: no caching */
        FILE *f = fopen(path, "rb");
        if (f) {
            lens_err e2;
            smp->ps = pupil_sampler_read(f, &e2);
            fclose(f);
            if (smp->ps) {
                if (log) fprintf(log, "line pupil: cached %s\n", path);
                return 0;
            }
            if (log) fprintf(log, "cache: ignoring unreadable %s (%s)\n", path, e2.msg);
        }
    }
    double t0 = omp_get_wtime();
    if (stop_only ? render_sampler_stop(smp, lens, lambda_min, lambda_max, rmax, err)
                  : render_sampler_lens(smp, lens, lambda_min, lambda_max, rmax, threads, err))
        return -1;
    if (log)
        fprintf(log, "line pupil%s: built in %.2f s\n", stop_only ? " of the stop" : "",
                omp_get_wtime() - t0);
    if (*path && make_dirs(dir) == 0) {
        lens_err e2;
        outfile *of = outfile_open(path, &e2);
        if (of && pupil_sampler_write(outfile_stream(of), smp->ps) == 0 &&
            outfile_commit(of, &e2) == 0) {
            if (log) fprintf(log, "cache: wrote %s\n", path);
        } else {
            if (of) outfile_abort(of);
            if (log) fprintf(log, "cache: cannot write %s\n", path);
        }
    }
    return 0;
}

/* Nanoseconds per ray of sys's batch evaluation as the renderer calls it (the pass test
 * and the outputs it reads: render_lens.c), and of the same system without the outputs
 * in drop (the cost of an effect's outputs), timed interleaved, best of several rounds
 * so that other load on the machine hits both alike. */
#define TIMING_RAYS 2048
static poly_system *without(const poly_system *s, const int *drop)
{
    int nin = poly_ninputs(s), nout = poly_noutputs(s);
    const char *in[16], *out[32];
    if (nin > 16 || nout > 32) return NULL;
    for (int i = 0; i < nin; i++) in[i] = poly_input_name(s, i);
    for (int o = 0; o < nout; o++) out[o] = poly_output_name(s, o);
    poly_system *r = poly_new(poly_lens_name(s), nin, in, nout, out);
    if (!r) return NULL;
    poly_set_frame(r, poly_get_frame(s));
    for (int i = 0; i < nin; i++) {
        double a, b;
        poly_get_scaling(s, i, &a, &b);
        poly_set_scaling(r, i, a, b);
        poly_set_transform(r, i, poly_get_transform(s, i));
    }
    for (int o = 0; o < nout; o++) poly_set_output_plain(r, o, poly_get_output_plain(s, o));
    for (int p = 0; p < poly_nparts(s); p++) {
        double r0, r1;
        poly_part_range(s, p, &r0, &r1);
        int q = poly_add_part(r, r0, r1);
        for (int o = 0; o < nout; o++)
            for (int t = 0; !drop[o] && t < poly_nterms(s, p, o); t++) {
                int ex[16];
                double c;
                poly_get_term(s, p, o, t, ex, &c);
                poly_add_term(r, q, o, ex, c);
            }
    }
    return r;
}

static double time_batch(const poly_system *s, int nsel, const int *sel, const double *in,
                         double *out, unsigned char *pass)
{
    double t0 = omp_get_wtime();
    poly_eval_batch_outputs(s, TIMING_RAYS, in, nsel, sel, out, pass);
    return (omp_get_wtime() - t0) / TIMING_RAYS * 1e9;
}

static void output_cost(const poly_system *sys, const render_effects *e, const int *drop,
                        double *t_all, double *t_without)
{
    int nin = poly_ninputs(sys), nout = poly_noutputs(sys);
    *t_all = *t_without = NAN;
    poly_system *w = without(sys, drop);
    double *in = malloc((size_t)TIMING_RAYS * nin * sizeof *in),
           *out = malloc((size_t)TIMING_RAYS * nout * sizeof *out);
    unsigned char *pass = malloc(TIMING_RAYS);
    if (w && in && out && pass) {
        int ix = poly_input_index(sys, "x"), iy = poly_input_index(sys, "y"),
            iu = poly_input_index(sys, "u"), iv = poly_input_index(sys, "v"),
            il = poly_input_index(sys, "lambda");
        for (int k = 0; k < TIMING_RAYS; k++) {
            double a = 2 * M_PI * k / TIMING_RAYS, *row = in + (size_t)k * nin;
            for (int i = 0; i < nin; i++) row[i] = 0;
            row[ix] = 0.5 * e->domain_radius * cos(a);
            row[iy] = 0.5 * e->domain_radius * sin(a);
            row[iu] = -0.01 * cos(a);
            row[iv] = 0.01 * sin(3 * a);
            if (il >= 0) row[il] = 0.45 + 0.2 * (k % 7) / 6.0;
        }
        /* the outputs the renderer reads; w's are those not dropped, listed first */
        static const char *const read[5] = {"out_x", "out_y", "out_u", "out_v", "out_eta"};
        int sel[5], nsel = 0, nsel_w = 0;
        for (int dropped = 0; dropped < 2; dropped++)
            for (int k = 0; k < 5; k++) {
                int o = poly_output_index(sys, read[k]);
                if (o >= 0 && drop[o] == dropped) sel[nsel++] = o;
            }
        for (int j = 0; j < nsel; j++) nsel_w += !drop[sel[j]];
        *t_all = *t_without = INFINITY;
        for (int rep = 0; rep < 9; rep++) {
            *t_all = fmin(*t_all, time_batch(sys, nsel, sel, in, out, pass));
            *t_without = fmin(*t_without, time_batch(w, nsel_w, sel, in, out, pass));
        }
    }
    poly_free(w);
    free(in);
    free(out);
    free(pass);
}

/* The time each effect costs per camera ray, measured on the system itself: for an
 * effect that is on, the evaluation time of its outputs (the system timed with and
 * without them); for one that is off, nothing is fitted, and what it would cost is
 * estimated from this system's mean time per output. */
static void print_costs(FILE *log, const poly_system *sys, const render_effects *e)
{
    int nout = poly_noutputs(sys), drop[32] = {0}, nclip = 0, eta = -1;
    if (nout > 32) return;
    for (int o = 0; o < nout; o++) {
        const char *n = poly_output_name(sys, o);
        if (n[0] == 's' && n[1] >= '0' && n[1] <= '9') nclip++, drop[o] = 1;
        if (!strcmp(n, "out_eta")) eta = o;
    }
    double t_all, t_clip, t_eta = NAN, t_all2;
    output_cost(sys, e, drop, &t_all, &t_clip);
    memset(drop, 0, sizeof drop);
    if (eta >= 0) {
        drop[eta] = 1;
        output_cost(sys, e, drop, &t_all2, &t_eta);
    }
    double per_output = t_all / nout;
    fprintf(log, "system: %d outputs, %.1f ns per ray in batches\n", nout, t_all);
    if (!nclip)
        fprintf(log, "cost vignetting: %s, no rim outputs (a pass circle on out_x out_y: "
                     "no measurable time)\n", e->vignetting ? "on" : "off");
    else
        fprintf(log, "cost vignetting: %s, %d rim outputs, %.1f ns per ray%s\n",
                e->vignetting ? "on" : "off", nclip, t_all - t_clip,
                e->vignetting ? "" : " (fitted all the same: render_fit.c)");
    if (e->transmittance)
        fprintf(log, "cost transmittance: %.1f ns per ray (out_eta)\n", t_all2 - t_eta);
    else
        fprintf(log, "cost transmittance: off, saves about %.1f ns per ray (one output, "
                     "estimated from this system's mean)\n", per_output);
    if (e->dispersion)
        fprintf(log, "cost dispersion: lambda an input, and one camera ray per wavelength\n");
    else
        fprintf(log, "cost dispersion: off, one camera ray per sample for all wavelengths%s\n",
                e->disperses ? "" : " (the lens does not disperse: no error)");
}

poly_system *render_effects_system(const lens_t *lens, const render_effects *e,
                                   const char *cache_dir, int threads, FILE *log,
                                   lens_err *err)
{
    double fit_s;
    poly_system *sys = obtain(lens, e, cache_dir, threads, log, &fit_s, err);
    if (sys && log) print_costs(log, sys, e);
    return sys;
}
