/* lens-render's job from scene file to image files (render_run.h). */
#include "sparselens/render_run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/camera.h"
#include "sparselens/exr_io.h"
#include "sparselens/outfile.h"
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

/* --emit-camera: the scene's camera as one C file (camera.h), instead of the render. */
static int emit_camera(const render_options *o, const lens_t *lens, const poly_system *sys,
                       double sw, double sh, lens_err *err)
{
    if (!sys) {
        lens_errf(err, o->scene, 0, "--emit-camera needs a polynomial system (not --exact)");
        return -1;
    }
    outfile *of = outfile_open(o->emit_camera, err);
    if (!of) return -1;
    if (lens_camera_emit(outfile_stream(of), lens, sys, sw, sh, "lens_camera", err)) {
        outfile_abort(of);
        return -1;
    }
    if (outfile_commit(of, err)) return -1;
    if (o->log) fprintf(o->log, "camera module: wrote %s (lens_camera_ray)\n", o->emit_camera);
    return 0;
}

int render_run(const render_options *o, render_stats *st, lens_err *err)
{
    scene_t sc;
    lens_t lens;
    poly_system *sys = NULL;
    render_lens_ctx *lc = NULL;
    render_sampler smp = {0};
    float *img = NULL;
    int rc = -1;
    lens_init(&lens);
    if (scene_load(o->scene, &sc, err)) return -1;
    if (o->spp > 0) sc.spp = o->spp;
    if (o->seed) sc.seed = o->seed;

    /* the lens: the scene's lens file, or the lens a given system was fitted to */
    const char *lens_path = sc.camera;
    char lens_buf[1024];
    if (sc.camera_is_poly) {
        if (poly_read(sc.camera, &sys, err)) goto done;
        if (poly_find_lens_file(sys, sc.camera, lens_buf, sizeof lens_buf, err)) goto done;
        lens_path = lens_buf;
    }
    if (lens_load(lens_path, o->load, &lens, err)) goto done;
    if (o->log) lens_cli_warn_notes("lens-render", &lens); /* what an importer skipped */
    if (sys) {
        /* a fitted system has its focus and aperture baked in */
        if (!isnan(sc.focus) || !isnan(sc.fstop)) {
            lens_errf(err, sc.path, 0, "focus and fstop cannot change a fitted .poly camera; "
                      "give the lens file instead");
            goto done;
        }
    } else if (render_lens_setup(&lens, sc.focus, sc.fstop, err)) {
        goto done;
    }
    double sw = isnan(sc.sensor_w) ? lens.sensor_w : sc.sensor_w;
    double sh = isnan(sc.sensor_h) ? lens.sensor_h : sc.sensor_h;
    if (!(sw > 0 && sh > 0)) {
        lens_errf(err, sc.path, 0, "no sensor size: add 'sensor W H' (the lens file has none)");
        goto done;
    }
    if (sc.mode != SCENE_GREY) {
        /* every glass must cover the wavelengths the scene will use */
        double tmp[lens.nsurf];
        if (lens_indices(&lens, RENDER_LAMBDA_MIN, tmp, err) ||
            lens_indices(&lens, RENDER_LAMBDA_MAX, tmp, err))
            goto done;
    }

    int use_eta = 1, achromatic = sc.mode == SCENE_GREY || !render_lens_disperses(&lens);
    double eta_const = 1;
    int stop_only = 0; /* vignetting off: directions from the stop's line pupil */
    render_camera cam;
    if (o->exact) {
        lc = render_lens_exact(&lens, sw, sh, &cam, err);
        if (o->log) fprintf(o->log, "lens: exact tracing through %s (%zu surfaces)\n", lens_path,
                            lens.nsurf);
        use_eta = sc.transmittance != EFFECT_OFF;
    } else {
        if (!sys) {
            render_effects e;
            if (render_effects_decide(&sc, &lens, sw, sh, &e, err)) goto done;
            render_effects_print(o->log, &e);
            char dir[1024];
            if (o->cache_dir) snprintf(dir, sizeof dir, "%s", o->cache_dir);
            else render_default_cache_dir(dir, sizeof dir);
            sys = render_effects_system(&lens, &e, dir, o->threads, o->log, err);
            if (!sys) goto done;
            use_eta = e.transmittance;
            eta_const = e.eta_centre;
            achromatic = !e.dispersion;
            stop_only = !e.vignetting;
        } else {
            if (o->log) fprintf(o->log, "lens: polynomial system %s\n", sc.camera);
            if (poly_input_index(sys, "lambda") < 0) {
                if (sc.mode != SCENE_GREY && !achromatic && o->log)
                    fprintf(o->log, "note: the system has no lambda input: no dispersion\n");
                achromatic = 1;
            }
            use_eta = sc.transmittance != EFFECT_OFF;
        }
        lc = render_lens_poly(sys, &lens, sw, sh, &cam, err);
    }
    if (!lc) goto done;
    if (sc.blades && render_lens_set_blades(lc, sc.blades, sc.blade_rotation * M_PI / 180, err))
        goto done;
    if (o->emit_camera) {
        if (sc.blades) {
            lens_errf(err, sc.path, 0, "--emit-camera: the module has a round stop (no blades)");
            goto done;
        }
        rc = emit_camera(o, &lens, sys, sw, sh, err);
        goto done;
    }

    double rmax = 0.5 * hypot(sw, sh);
    if (o->rear_sampling) {
        render_sampler_rear(&smp, &cam);
    } else {
        double l0 = sc.mode == SCENE_GREY ? GLASS_D_LINE : RENDER_LAMBDA_MIN,
               l1 = sc.mode == SCENE_GREY ? GLASS_D_LINE : RENDER_LAMBDA_MAX;
        char dir[1024];
        if (o->cache_dir) snprintf(dir, sizeof dir, "%s", o->cache_dir);
        else render_default_cache_dir(dir, sizeof dir);
        if (render_effects_sampler(&lens, l0, l1, rmax, stop_only, dir, o->threads, o->log, &smp,
                                   err))
            goto done;
    }
    img = malloc((size_t)sc.width * sc.height * 3 * sizeof *img);
    if (!img) {
        lens_errf(err, sc.path, 0, "out of memory for a %dx%d image", sc.width, sc.height);
        goto done;
    }
    if (o->log)
        fprintf(o->log, "rendering %dx%d, %ld spp, %s mode, %s sampling, %s\n", sc.width, sc.height,
                sc.spp, scene_mode_name(sc.mode), o->rear_sampling ? "rear-element" : "line-pupil",
                o->estimator == RENDER_ESTIMATOR_FULL ? "full estimator (Eq. 3, 8, 12)"
                                                      : "estimator of Eq. 13");
    render_job job = {.scene = &sc, .cam = &cam, .sampler = &smp, .estimator = o->estimator,
                      .use_eta = use_eta, .achromatic = achromatic,
                      .filter = sc.filter_tent ? RENDER_FILTER_TENT : RENDER_FILTER_BOX,
                      .filter_radius = sc.filter_radius,
                      .eta_const = eta_const, .spp = sc.spp, .threads = o->threads, .progress = o->progress,
                      .progress_ctx = o->progress_ctx};
    if (render_image(&job, img, NULL, st, err)) goto done;
    if (o->estimator == RENDER_ESTIMATOR_FULL && o->log && st)
        fprintf(o->log, "full estimator: %.0f rays reached the scene, %.0f of them (%.3g%%) "
                "weighted by Eq. 13 (a factor not finite: |A| = 0, a blocked difference step)\n",
                st->full_rays, st->full_fallback,
                st->full_rays > 0 ? 100 * st->full_fallback / st->full_rays : 0);
    if (write_exr(o->exr, sc.width, sc.height, img, err)) goto done;
    if (o->png && render_write_png(o->png, sc.width, sc.height, img, err)) goto done;
    if (o->reference) {
        double rms, rel;
        if (render_compare(o->reference, sc.width, sc.height, img, &rms, &rel, err)) goto done;
        if (o->log) fprintf(o->log, "error vs %s: rms %.4g (%.2f%% of its mean)\n", o->reference, rms,
                            100 * rel);
    }
    if (o->noise_against) {
        float *other = NULL;
        if (render_read_rgb(o->noise_against, sc.width, sc.height, &other, err)) goto done;
        double nz = render_noise(sc.width, sc.height, img, other);
        free(other);
        if (o->log)
            fprintf(o->log, "noise: median per-pixel relative variance %.4g against %s "
                    "(times this render's processor time: %.4g s)\n", nz, o->noise_against,
                    st ? nz * st->cpu_seconds : NAN);
    }
    rc = 0;
done:
    free(img);
    render_sampler_free(&smp);
    render_lens_free(lc);
    poly_free(sys);
    lens_free(&lens);
    scene_free(&sc);
    return rc;
}
