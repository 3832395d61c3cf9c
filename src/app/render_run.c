/* lens-render's job from scene file to image files (render_run.h). */
#include "sparselens/render_run.h"
#include "sparselens/file_fields.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/camera.h"
#include "sparselens/emit_files.h"
#include "sparselens/escape.h"
#include "sparselens/exr_io.h"
#include "sparselens/outfile.h"
#include "sparselens/paraxial.h"
#include "sparselens/glass.h"
#include "sparselens/image.h"
#include "sparselens/lens.h"
#include "sparselens/lens_cli_options.h"
#include "sparselens/poly.h"
#include "sparselens/render_effects.h"
#include "sparselens/render_lens.h"
#include "sparselens/scene.h"
#include "sparselens/trace.h"

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

int render_write_png(const char *path, int w, int h, const float *rgb, lens_err *err)
{
    size_t n = (size_t)w * h;
    float *lum = malloc(n * sizeof *lum);
    double bg[3] = {0, 0, 0};
    img_canvas *c = img_new(w, h, bg);
    if (!lum || !c) {
        free(lum);
        img_free(c);
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    for (size_t i = 0; i < n; i++)
        lum[i] = 0.2126f * rgb[3 * i] + 0.7152f * rgb[3 * i + 1] + 0.0722f * rgb[3 * i + 2];
    qsort(lum, n, sizeof *lum, cmp_float);
    double white = lum[(size_t)(0.99 * (n - 1))];
    if (!(white > 0)) white = lum[n - 1] > 0 ? lum[n - 1] : 1;
    free(lum);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double col[3];
            for (int k = 0; k < 3; k++) {
                double v = rgb[3 * ((size_t)y * w + x) + k] / white;
                v = v <= 0 ? 0 : v >= 1 ? 1 : v;
                col[k] = v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055;
            }
            if (col[0] > 0 || col[1] > 0 || col[2] > 0) img_rect(c, x, y, x + 1, y + 1, col, 0);
        }
    int rc = img_write_png(c, path, err);
    img_free(c);
    return rc;
}

static int write_exr(const char *path, int w, int h, const float *rgb, lens_err *err)
{
    size_t n = (size_t)w * h;
    /* inf or nan never reaches the file unannounced (the scene's bounds keep them out;
     * this says so if something else lets one through) */
    for (size_t i = 0; i < 3 * n; i++)
        if (!isfinite(rgb[i])) {
            lens_errf(err, path, 0, "pixel (%zu, %zu) is not finite (%g): radiance beyond "
                      "what a 32-bit float image holds", i / 3 % (size_t)w, i / 3 / (size_t)w,
                      rgb[i]);
            return -1;
        }
    float *pl = malloc(3 * n * sizeof *pl);
    if (!pl) {
        lens_errf(err, path, 0, "out of memory");
        return -1;
    }
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) pl[k * n + i] = rgb[3 * i + k];
    const char *names[3] = {"R", "G", "B"};
    const float *planes[3] = {pl, pl + n, pl + 2 * n};
    int rc = exr_write_float(path, w, h, 3, names, planes, err);
    free(pl);
    return rc;
}

int render_read_rgb(const char *path, int w, int h, float **rgb, lens_err *err)
{
    exr_image im;
    *rgb = NULL;
    if (exr_read_float(path, &im, err)) return -1;
    const char *names[3] = {"R", "G", "B"};
    const float *pl[3];
    int rc = -1;
    if (im.width != w || im.height != h) {
        lens_errf(err, path, 0, "the image is %dx%d, the render %dx%d", im.width, im.height, w, h);
        goto done;
    }
    for (int k = 0; k < 3; k++)
        if (!(pl[k] = exr_image_channel(&im, names[k]))) {
            lens_errf(err, path, 0, "the image has no channel %s", names[k]);
            goto done;
        }
    size_t n = (size_t)w * h;
    if (!(*rgb = malloc(3 * n * sizeof **rgb))) {
        lens_errf(err, path, 0, "out of memory");
        goto done;
    }
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) (*rgb)[3 * i + k] = pl[k][i];
    rc = 0;
done:
    exr_image_free(&im);
    return rc;
}

int render_compare(const char *ref, int w, int h, const float *rgb, double *rms, double *rel,
                   lens_err *err)
{
    float *r;
    if (render_read_rgb(ref, w, h, &r, err)) return -1;
    double se = 0, mean = 0;
    size_t n = (size_t)w * h;
    for (size_t i = 0; i < 3 * n; i++) {
        double d = rgb[i] - r[i];
        se += d * d;
        mean += r[i];
    }
    free(r);
    *rms = sqrt(se / (3.0 * n));
    mean /= 3.0 * n;
    *rel = mean > 0 ? *rms / mean : NAN;
    return 0;
}

/* Everything render_run holds between its steps, freed by setup_free. */
typedef struct {
    scene_t sc;
    lens_t lens;
    poly_system *sys;      /* the camera's system; NULL when tracing exactly */
    render_lens_ctx *lc;
    render_sampler smp;
    render_camera cam;
    char lens_path[PATH_MAX + 64]; /* the lens file, named in the log */
    double sw, sh;         /* sensor, mm */
    int use_eta, achromatic, stop_only; /* stop_only: vignetting off, the stop's line pupil */
    double eta_const;
} render_setup;

static int cache_dir(const render_options *o, char *dir, size_t len, lens_err *err)
{
    if (!o->cache_dir) {
        render_default_cache_dir(dir, len);
        return 0;
    }
    if (strlen(o->cache_dir) >= len) {
        lens_errf(err, NULL, 0, "--cache-dir: a path of %zu characters, more than the %zu a "
                  "path may have", strlen(o->cache_dir), len - 1);
        return -1;
    }
    snprintf(dir, len, "%s", o->cache_dir);
    return 0;
}

/* Step 1: the scene, its lens (or the lens a given system was fitted to), focus and
 * f-stop, the sensor, and glasses that cover the scene's wavelengths. */
static int load_camera(const render_options *o, render_setup *s, lens_err *err)
{
    scene_t *sc = &s->sc;
    if (scene_load(o->scene, sc, err)) return -1;
    if (o->spp > 0) sc->spp = o->spp;
    if (o->seed) sc->seed = o->seed;
    if (o->focus > 0) sc->focus = o->focus;
    if (o->fstop > 0) sc->fstop = o->fstop;
    if (o->blades) sc->blades = o->blades == RENDER_BLADES_ROUND ? 0 : o->blades;
    memcpy(s->lens_path, sc->camera, strlen(sc->camera) + 1); /* both hold PATH_MAX */
    if (sc->camera_is_poly) {
        if (poly_read(sc->camera, &s->sys, err)) return -1;
        const char *frame = poly_get_meta(s->sys, "trace_frame");
        if (frame && strcmp(frame, "outer") != 0) {
            lens_errf(err, sc->camera, 0, "the system was fitted to samples traced to the %s "
                      "(meta trace_frame %s): a camera needs one to the outer pupil "
                      "(lens-trace --to outer, the default)", frame, frame);
            return -1;
        }
        if (poly_find_lens_file(s->sys, sc->camera, lens_find_file, s->lens_path,
                                sizeof s->lens_path, err)) {
            lens_err e = *err; /* a scene has no --lens: the .poly must lead to it */
            lens_errf(err, NULL, 0, "%s; put the lens beside the .poly or correct its "
                      "lens-path line", e.msg);
            return -1;
        }
    }
    if (lens_load(s->lens_path, o->load, &s->lens, err)) return -1;
    if (o->log) lens_cli_warn_notes("lens-render", &s->lens); /* what an importer skipped */
    lens_sensor_from_fields(&s->lens, NULL); /* a design file's fields give the sensor */
    if (s->sys) {
        /* a fitted system has its focus and aperture baked in */
        /* named where it was given: the option, or the scene's line */
        const char *opt = o->focus > 0 ? "--focus" : o->fstop > 0 ? "--fstop" : NULL;
        if (opt) {
            lens_errf(err, NULL, 0, "%s cannot change a fitted .poly camera (%s); give the "
                      "lens file instead", opt, sc->camera);
            return -1;
        }
        if (!isnan(sc->focus) || !isnan(sc->fstop)) {
            int f = !isnan(sc->focus);
            lens_errf(err, sc->path, f ? sc->focus_line : sc->fstop_line,
                      "%s cannot change a fitted .poly camera; give the lens file instead",
                      f ? "focus" : "fstop");
            return -1;
        }
    } else if (render_lens_setup(&s->lens, sc->focus, sc->fstop, err)) {
        return -1;
    } else if (o->log) {
        /* where the scene's (or --focus's) focus put the sensor, and its f-stop */
        paraxial_data p;
        if (paraxial_compute(&s->lens, GLASS_D_LINE, &p, err)) return -1;
        fprintf(o->log, "camera: focus %.6g%s, the sensor %.6f mm behind the last surface, "
                "f/%.4g (paraxial)\n", p.focus_distance, isinf(p.focus_distance) ? "" : " mm",
                p.sensor_distance, p.fnumber);
    }
    s->sw = isnan(sc->sensor_w) ? s->lens.sensor_w : sc->sensor_w;
    s->sh = isnan(sc->sensor_h) ? s->lens.sensor_h : sc->sensor_h;
    if (!(s->sw > 0 && s->sh > 0)) {
        lens_errf(err, sc->path, 0, "no sensor size: add 'sensor W H' (the lens file has none)");
        return -1;
    }
    if (sc->mode != SCENE_GREY) {
        /* every glass must cover the wavelengths the scene will use */
        double tmp[s->lens.nsurf];
        if (lens_indices(&s->lens, RENDER_LAMBDA_MIN, tmp, err) ||
            lens_indices(&s->lens, RENDER_LAMBDA_MAX, tmp, err))
            return -1;
    }
    return 0;
}

/* Step 2: the lens map: exact tracing, the given system, or a system fitted for the
 * effects the lens and the scene call for; then the scene's blades. */
static int choose_lens_map(const render_options *o, render_setup *s, lens_err *err)
{
    const scene_t *sc = &s->sc;
    s->use_eta = sc->transmittance != EFFECT_OFF;
    s->achromatic = sc->mode == SCENE_GREY || !render_lens_disperses(&s->lens);
    s->eta_const = 1;
    s->stop_only = 0;
    if (o->exact) {
        s->lc = render_lens_exact(&s->lens, s->sw, s->sh, &s->cam, err);
        if (o->log) fprintf(o->log, "lens: exact tracing through %s (%zu surfaces)\n",
                            s->lens_path, s->lens.nsurf);
        /* the transmittance not traced ray by ray: the lens's mean on the axis weighs
         * the rays, as in the fitted path (a weight of 1 had made a white plane through
         * dgauss.50mm 74% too bright) */
        if (!s->use_eta && render_effects_eta_centre(&s->lens, &s->eta_const, err)) return -1;
    } else if (!s->sys) {
        render_effects e;
        char dir[PATH_MAX];
        if (render_effects_decide(sc, &s->lens, s->sw, s->sh, &e, err)) return -1;
        render_effects_print(o->log, &e);
        if (cache_dir(o, dir, sizeof dir, err)) return -1;
        s->sys = render_effects_system(&s->lens, &e, dir, o->threads, o->log, err);
        if (!s->sys) return -1;
        s->use_eta = e.transmittance;
        s->eta_const = e.eta_centre;
        s->achromatic = !e.dispersion;
        s->stop_only = !e.vignetting;
        s->lc = render_lens_poly(s->sys, &s->lens, s->sw, s->sh, &s->cam, err);
    } else {
        if (o->log) fprintf(o->log, "lens: polynomial system %s\n", sc->camera);
        const char *passage = poly_get_meta(s->sys, "passage");
        if (o->log && passage && strncmp(passage, "full", 4) != 0)
            fprintf(o->log, "note: the system's passage is %s: rays the lens blocks there pass "
                    "it\n", passage);
        if (s->use_eta && poly_output_index(s->sys, "out_eta") < 0) {
            s->use_eta = 0;
            if (o->log)
                fprintf(o->log, "note: the system has no out_eta: the lens's mean transmittance "
                        "on the axis stands for it\n");
        }
        if (!s->use_eta && render_effects_eta_centre(&s->lens, &s->eta_const, err)) return -1;
        if (poly_input_index(s->sys, "lambda") < 0) {
            if (sc->mode != SCENE_GREY && !s->achromatic && o->log)
                fprintf(o->log, "note: the system has no lambda input: no dispersion\n");
            s->achromatic = 1;
        }
        s->lc = render_lens_poly(s->sys, &s->lens, s->sw, s->sh, &s->cam, err);
    }
    if (!s->lc) return -1;
    if (sc->blades &&
        render_lens_set_blades(s->lc, sc->blades, sc->blade_rotation * M_PI / 180, err))
        return -1;
    return 0;
}

/* Step 3: the camera-ray sampler, the line pupil over the scene's wavelengths (cached)
 * or the rear element. */
static int build_sampler(const render_options *o, render_setup *s, lens_err *err)
{
    if (o->rear_sampling) {
        render_sampler_rear(&s->smp, &s->cam);
        return 0;
    }
    int grey = s->sc.mode == SCENE_GREY;
    double l0 = grey ? GLASS_D_LINE : RENDER_LAMBDA_MIN, l1 = grey ? GLASS_D_LINE : RENDER_LAMBDA_MAX;
    char dir[PATH_MAX];
    if (cache_dir(o, dir, sizeof dir, err)) return -1;
    return render_effects_sampler(&s->lens, l0, l1, 0.5 * hypot(s->sw, s->sh), s->stop_only, dir,
                                  o->threads, o->log, &s->smp, err);
}

/* Step 4: the image, by render_image. */
static int render_pixels(const render_options *o, render_setup *s, float *img, render_stats *st,
                         lens_err *err)
{
    const scene_t *sc = &s->sc;
    if (o->log)
        fprintf(o->log, "rendering %dx%d, %ld spp, %s mode, %s sampling, %s\n", sc->width,
                sc->height, sc->spp, scene_mode_name(sc->mode),
                o->rear_sampling ? "rear-element" : "line-pupil",
                o->estimator == RENDER_ESTIMATOR_FULL ? "full estimator (Eq. 3, 8, 12)"
                                                      : "estimator of Eq. 13");
    render_job job = {.scene = sc, .cam = &s->cam, .sampler = &s->smp, .estimator = o->estimator,
                      .use_eta = s->use_eta, .achromatic = s->achromatic,
                      .filter = sc->filter_tent ? RENDER_FILTER_TENT : RENDER_FILTER_BOX,
                      .filter_radius = sc->filter_radius, .eta_const = s->eta_const,
                      .spp = sc->spp, .threads = o->threads, .progress = o->progress,
                      .progress_ctx = o->progress_ctx};
    if (render_image(&job, img, NULL, st, err)) return -1;
    if (o->estimator == RENDER_ESTIMATOR_FULL && o->log && st)
        fprintf(o->log, "full estimator: %.0f rays reached the scene, %.0f of them (%.3g%%) "
                "weighted by Eq. 13 (a factor not finite: |A| = 0, a blocked difference step)\n",
                st->full_rays, st->full_fallback,
                st->full_rays > 0 ? 100 * st->full_fallback / st->full_rays : 0);
    return 0;
}

/* Step 5: the image files, and the figures against a reference or a second render. */
static int write_outputs(const render_options *o, const scene_t *sc, const float *img,
                         const render_stats *st, lens_err *err)
{
    if (write_exr(o->exr, sc->width, sc->height, img, err)) return -1;
    if (o->png && render_write_png(o->png, sc->width, sc->height, img, err)) return -1;
    if (o->reference) {
        double rms, rel;
        if (render_compare(o->reference, sc->width, sc->height, img, &rms, &rel, err)) return -1;
        FILE *fig = o->figures ? o->figures : o->log;
        if (fig) fprintf(fig, "error vs %s: rms %.4g (%.2f%% of its mean)\n", o->reference,
                         rms, 100 * rel);
    }
    if (o->noise_against) {
        float *other = NULL;
        if (render_read_rgb(o->noise_against, sc->width, sc->height, &other, err)) return -1;
        double nz = render_noise(sc->width, sc->height, img, other);
        free(other);
        FILE *fig = o->figures ? o->figures : o->log;
        if (fig)
            fprintf(fig, "noise: median per-pixel relative variance %.4g against %s "
                    "(times this render's processor time: %.4g s)\n", nz, o->noise_against,
                    st ? nz * st->cpu_seconds : NAN);
    }
    return 0;
}

typedef struct {
    const render_options *o;
    const render_setup *s;
    const char *name;
} camera_job;

static int camera_body(FILE *f, void *ctx, lens_err *err)
{
    const camera_job *j = ctx;
    return lens_camera_emit(f, &j->s->lens, j->s->sys, j->s->sw, j->s->sh, j->s->sc.blades,
                            j->s->sc.blade_rotation * M_PI / 180, j->name, err);
}

static int camera_header(FILE *f, void *ctx, lens_err *err)
{
    const camera_job *j = ctx;
    return lens_camera_emit_header(f, &j->s->lens, j->name, err);
}

static const char *camera_name(const render_options *o)
{
    return o->camera_name ? o->camera_name : "lens_camera";
}

/* --emit-camera: the scene's camera as one C file (camera.h) and its header, instead of
 * the render. */
static int emit_camera(const render_options *o, const render_setup *s, lens_err *err)
{
    if (!s->sys) {
        lens_errf(err, o->scene, 0, "--emit-camera needs a polynomial system (not --exact)");
        return -1;
    }
    camera_job j = {o, s, camera_name(o)};
    if (emit_c_files(o->emit_camera, camera_body, camera_header, &j, err)) return -1;
    if (o->log)
        fprintf(o->log, "camera module: wrote %s (%s_ray, %s_rays)\n", o->emit_camera, j.name,
                j.name);
    return 0;
}

static void setup_free(render_setup *s)
{
    render_sampler_free(&s->smp);
    render_lens_free(s->lc);
    poly_free(s->sys);
    lens_free(&s->lens);
    scene_free(&s->sc);
}

/* What the outputs need, checked before the render rather than after it: the pictures
 * to compare with (readable, of the scene's size) and the PNG's path. */
static int check_outputs(const render_options *o, const scene_t *sc, lens_err *err)
{
    const char *refs[2] = {o->reference, o->noise_against};
    for (int k = 0; k < 2; k++) {
        float *r = NULL;
        if (refs[k] && render_read_rgb(refs[k], sc->width, sc->height, &r, err)) return -1;
        free(r);
    }
    return o->png && !o->emit_camera ? outfile_check(o->png, err) : 0;
}

int render_run(const render_options *o, render_stats *st, lens_err *err)
{
    render_setup s = {0};
    float *img = NULL;
    int rc = -1;
    lens_init(&s.lens);
    const char *why;
    if (o->emit_camera && !text_c_prefix_ok(camera_name(o), &why)) { /* before any fit */
        lens_errf(err, NULL, 0, "--name: %s", why);
        return -1;
    }
    if (load_camera(o, &s, err) || check_outputs(o, &s.sc, err) || choose_lens_map(o, &s, err))
        goto done;
    if (o->emit_camera) {
        rc = emit_camera(o, &s, err);
        goto done;
    }
    if (build_sampler(o, &s, err)) goto done;
    img = malloc((size_t)s.sc.width * s.sc.height * 3 * sizeof *img);
    if (!img) {
        lens_errf(err, s.sc.path, 0, "out of memory for a %dx%d image", s.sc.width, s.sc.height);
        goto done;
    }
    if (render_pixels(o, &s, img, st, err) || write_outputs(o, &s.sc, img, st, err)) goto done;
    rc = 0;
done:
    free(img);
    setup_free(&s);
    return rc;
}
