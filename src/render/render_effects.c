/* "Simulate only the effects a scene calls for": the choices, the measurements behind
 * the automatic ones, and the cache of fitted systems (render_effects.h).
 *
 *  - dispersion: a grey scene renders one wavelength, so lambda is no input (a system
 *    of four inputs has far fewer candidate terms than one of five);
 *  - transmittance: on/off as the scene says; auto: on when the mean Fresnel
 *    transmittance changes from the centre to the edge of the sensor in use by more than
 *    the noise of the render (of an 8x8-pixel mean, 1/sqrt(64 spp)) and at least 1%; when off, the image is still weighted by the mean transmittance on the axis,
 *    so that its exposure matches the exact lens;
 *  - vignetting: the pass circles of the front element and the other clipping rims
 *    beside the stop's; auto: on when the share of the rays through the stop at the
 *    edge of the sensor in use that the front group clips (the cat's eye) is above the
 *    same noise and at least 2%;
 *  - domain: the sensor area rendered (half its diagonal), not the lens's whole field;
 *  - tolerance: a tenth of a pixel. Directions at the outer pupil carry the image
 *    position: an angle error da moves the picture by about efl * da on the sensor, so
 *    the direction tolerance is 0.1 * pitch / efl. Positions on the front element move
 *    the picture far less (by the magnification of the scene), and share it. */
#include "sparselens/render_effects.h"

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

int render_effects_decide(const scene_t *s, const lens_t *lens, double sw, double sh,
                          render_effects *e, lens_err *err)
{
    memset(e, 0, sizeof *e);
    paraxial_data p;
    if (paraxial_compute(lens, GLASS_D_LINE, &p, err)) return -1;
    e->efl = fabs(p.efl);
    e->focus = isnan(s->focus) ? p.focus_distance : s->focus;
    e->disperses = render_lens_disperses(lens);
    e->dispersion = s->mode != SCENE_GREY && e->disperses;
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
    /* "more than the noise": a pixel's relative noise is about 1/sqrt(spp), and a smooth
     * change is seen over a region, so the bar is the noise of an 8x8-pixel mean, and
     * never below 2% (vignetting) and 1% (transmittance) */
    e->noise = 1 / sqrt(64.0 * (s->spp > 0 ? s->spp : 1));
    e->vignetting = s->vignetting == EFFECT_AUTO ? loss_edge > fmax(0.02, e->noise)
                                                 : s->vignetting == EFFECT_ON;
    e->transmittance =
        s->transmittance == EFFECT_AUTO ? e->eta_variation > fmax(0.01, e->noise)
                                        : s->transmittance == EFFECT_ON;
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
    fprintf(f, "why: front-group clipping at the edge %.1f%% (vignetting when > %.1f%%), "
               "transmittance centre to edge %.2f%% (when > %.1f%%)\n",
            100 * e->vignetting_loss, 100 * fmax(0.02, e->noise), 100 * e->eta_variation,
            100 * fmax(0.01, e->noise));
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

void render_effects_key(const lens_t *lens, const render_effects *e, char key[17])
{
    uint64_t h = lens_hash(lens);
    char eff[160];
    int n = snprintf(eff, sizeof eff, "v2 disp %d eta %d vig %d r %.6g tol %.6g D %.6g",
                     e->dispersion, e->transmittance, e->vignetting, e->domain_radius,
                     e->tolerance, e->focus);
    h = fnv(h, eff, (size_t)n);
    snprintf(key, 17, "%016llx", (unsigned long long)h);
}

void render_default_cache_dir(char *buf, size_t len)
{
    const char *x = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    if (x && *x) snprintf(buf, len, "%s/sparselens", x);
    else if (home && *home) snprintf(buf, len, "%s/.cache/sparselens", home);
    else if (len) buf[0] = 0;
}

/* mkdir -p for the cache; failures only mean no caching. */
static int make_dirs(const char *dir)
{
    char tmp[1024];
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
    char key[17], path[1200] = "";
    render_effects_key(lens, e, key);
    *fit_s = 0;
    if (dir && *dir) {
        snprintf(path, sizeof path, "%s/%s.poly", dir, key);
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
                           double rmax, const char *dir, int threads, FILE *log,
                           render_sampler *smp, lens_err *err)
{
    uint64_t h = lens_hash(lens);
    char tag[160], path[1200] = "";
    int n = snprintf(tag, sizeof tag, "pupil v1 %.17g %.17g %.17g", lambda_min, lambda_max, rmax);
    h = fnv(h, tag, (size_t)n);
    memset(smp, 0, sizeof *smp);
    smp->kind = RENDER_SAMPLE_PUPIL;
    if (dir && *dir) {
        snprintf(path, sizeof path, "%s/%016llx.pupil", dir, (unsigned long long)h);
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
    if (render_sampler_lens(smp, lens, lambda_min, lambda_max, rmax, threads, err)) return -1;
    if (log) fprintf(log, "line pupil: built in %.2f s\n", omp_get_wtime() - t0);
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

/* Seconds per poly_eval of sys and of full over the same sensor rays: the fastest of
 * several interleaved rounds, so that other load on the machine hits both alike. */
#define TIMING_RAYS 4096
static void fill_rays(const poly_system *sys, const render_effects *e, double *in)
{
    int nin = poly_ninputs(sys);
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
}

static double time_once(const poly_system *sys, const double *in, double *sink)
{
    int nin = poly_ninputs(sys);
    double out[32], t0 = omp_get_wtime();
    for (int k = 0; k < TIMING_RAYS; k++) {
        poly_eval(sys, in + (size_t)k * nin, out);
        *sink += out[0];
    }
    return (omp_get_wtime() - t0) / TIMING_RAYS;
}

static void eval_times(const poly_system *sys, const poly_system *full, const render_effects *e,
                       double *t, double *tf)
{
    double *a = malloc(TIMING_RAYS * 8 * sizeof *a), *b = malloc(TIMING_RAYS * 8 * sizeof *b);
    double sink = 0;
    *t = *tf = INFINITY;
    if (a && b && poly_noutputs(sys) <= 32 && poly_noutputs(full) <= 32 &&
        poly_ninputs(sys) <= 8 && poly_ninputs(full) <= 8) {
        fill_rays(sys, e, a);
        fill_rays(full, e, b);
        for (int rep = 0; rep < 15; rep++) {
            *t = fmin(*t, time_once(sys, a, &sink));
            *tf = fmin(*tf, time_once(full, b, &sink));
        }
    }
    free(a);
    free(b);
    if (sink == 12345.678) *t = 0; /* sink keeps the loops */
}

static int total_terms(const poly_system *s)
{
    int n = 0;
    for (int p = 0; p < poly_nparts(s); p++)
        for (int o = 0; o < poly_noutputs(s); o++) n += poly_nterms(s, p, o);
    return n;
}

poly_system *render_effects_system(const lens_t *lens, const render_effects *e,
                                   const char *cache_dir, int threads, FILE *log,
                                   lens_err *err)
{
    double fit_s, full_fit_s;
    poly_system *sys = obtain(lens, e, cache_dir, threads, log, &fit_s, err);
    if (!sys) return NULL;
    render_effects full = *e;
    full.dispersion = full.transmittance = full.vignetting = 1;
    if (full.dispersion == e->dispersion && full.transmittance == e->transmittance &&
        full.vignetting == e->vignetting) {
        if (log) fprintf(log, "saved: nothing (the scene calls for every effect)\n");
        return sys;
    }
    /* the full system is fitted once for the comparison, and cached like any other */
    lens_err e2;
    poly_system *fs = obtain(lens, &full, cache_dir, threads, NULL, &full_fit_s, &e2);
    if (!fs) {
        if (log) fprintf(log, "saved: unknown (the full system failed to fit: %s)\n", e2.msg);
        return sys;
    }
    double t, tf;
    eval_times(sys, fs, e, &t, &tf);
    if (log) {
        fprintf(log, "system: %d terms, %d monomials per ray; the full system: %d terms, %d\n",
                total_terms(sys), poly_nmonomials(sys, 0), total_terms(fs),
                poly_nmonomials(fs, 0));
        fprintf(log, "saved: %.0f ns of %.0f ns per camera ray (%.0f%%) against the full system",
                1e9 * (tf - t), 1e9 * tf, tf > 0 ? 100 * (tf - t) / tf : 0);
        if (fit_s > 0 && full_fit_s > 0)
            fprintf(log, "; fit %.2f s instead of %.2f s", fit_s, full_fit_s);
        fprintf(log, "\n");
    }
    poly_free(fs);
    return sys;
}
