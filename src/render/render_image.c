/* The render loop (render.h, render_image): camera samples drawn per pixel from
 * low-discrepancy points (render_samples.h), sent through the lens in blocks (one
 * cam->map_batch call per block: a polynomial system evaluates them in vector blocks),
 * then the scene, with several wavelengths per sample.
 *
 * Wavelengths and channels:
 *  - grey: one wavelength (the d line); the scene's colours averaged, every channel alike;
 *  - rgb: the three band wavelengths of render_channel_lambda, each scoring its channel;
 *  - spectral: RENDER_HERO wavelengths, a hero lambda_0 uniform over the range and
 *    lambda_j = lambda_0 + j / RENDER_HERO of the range (wrapped): each is uniform, so
 *    each scores the channels by render_rgb_bar / p(lambda) and the sample is their mean
 *    (the scene's r g b turned into spectra by render_rgb_spectrum).
 * With job->achromatic the wavelengths share one camera ray and one scene path (the
 * geometry does not depend on lambda); else each wavelength has its own ray through the
 * lens and its own path. Either way every sample scores every channel: no colour comes
 * from a different set of samples than another. */
#include "sparselens/render.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "render/render_samples.h"
#include "render/scene_camera_block.h"
#include "render/scene_light_block.h"
#include "sparselens/glass.h"
#include "sparselens/render_spectrum.h"
#include "sparselens/trace.h"

/* camera samples per lens batch: a block runs across a row's pixels, so that a system's
 * batch kernel meets hundreds of rays a call whatever the spp (its set-up per call costs
 * about as much as 30 rays) */
#define BLOCK 512
#define MAX_WAVE (RENDER_HERO > 3 ? RENDER_HERO : 3)
#define DRAWS 9

/* sample dimensions (render_samples.h): pairs and singles are numbered apart */
enum { DIM_PIXEL, DIM_PUPIL, DIM_LIGHT, DIM_BSDF };       /* 2D */
enum { DIM_LAMBDA, DIM_SELECT };                          /* 1D */

double render_channel_lambda(int c)
{
    static const double lam[3] = {0.61, 0.55, 0.465}; /* red, green, blue band centres */
    return lam[c];
}

typedef struct {
    int nwave;                 /* wavelengths per sample */
    double lambda[MAX_WAVE];   /* um */
    double score[MAX_WAVE][3]; /* a unit of radiance at wavelength j adds this per channel */
} wave_set;

static void waves_of(const scene_t *sc, double xi, wave_set *w)
{
    memset(w, 0, sizeof *w);
    if (sc->mode == SCENE_GREY) {
        w->nwave = 1;
        w->lambda[0] = GLASS_D_LINE;
        w->score[0][0] = w->score[0][1] = w->score[0][2] = 1;
    } else if (sc->mode == SCENE_RGB) {
        w->nwave = 3;
        for (int c = 0; c < 3; c++) w->lambda[c] = render_channel_lambda(c), w->score[c][c] = 1;
    } else {
        double range = RENDER_LAMBDA_MAX - RENDER_LAMBDA_MIN;
        w->nwave = RENDER_HERO;
        for (int j = 0; j < RENDER_HERO; j++) {
            double f = xi + (double)j / RENDER_HERO;
            w->lambda[j] = RENDER_LAMBDA_MIN + (f - floor(f)) * range;
            render_rgb_bar(w->lambda[j], w->score[j]);
            for (int c = 0; c < 3; c++) w->score[j][c] *= range / RENDER_HERO;
        }
    }
}

/* The value of colour rgb (a scene albedo or emission) at wavelength j of w. */
static double colour_at(const scene_t *sc, const wave_set *w, int j, const double rgb[3])
{
    if (sc->mode == SCENE_GREY) return (rgb[0] + rgb[1] + rgb[2]) / 3;
    if (sc->mode == SCENE_RGB) return rgb[j];
    return render_rgb_spectrum(rgb, w->lambda[j]);
}

/* What a camera ray's hit needs from the scene before its radiance: an emitter's is
 * known at once; a lit surface's albedo, and its direct light, which the block's lit hits
 * get together (scene_direct_mis_many). Returns 1 for a surface that needs direct light. */
static int hit_albedo(const scene_t *sc, const scene_hit *h, double alb[3])
{
    if (scene_is_emitter(&sc->obj[h->obj])) return 0;
    scene_albedo(sc, h->obj, h->p, alb);
    return !(alb[0] <= 0 && alb[1] <= 0 && alb[2] <= 0);
}

/* Radiance leaving the scene along the camera ray (o, d) (scene frame), at the
 * wavelengths j0 .. j1-1 of w, into L[j]: an emitter's, or a lit surface's albedo alb
 * times its direct light terms t (NULL: an unlit surface, 0). */
static void scene_radiance(const scene_t *sc, const wave_set *w, int j0, int j1,
                           const scene_hit *h, const double d[3], const double alb[3],
                           const scene_light_terms *t, double *L)
{
    const scene_object *ob = &sc->obj[h->obj];
    for (int j = j0; j < j1; j++) L[j] = 0;
    if (scene_is_emitter(ob)) {
        double back[3] = {-d[0], -d[1], -d[2]}, le[3];
        if (scene_emitted(sc, h->obj, h->p, back, le))
            for (int j = j0; j < j1; j++) L[j] = colour_at(sc, w, j, le);
        return;
    }
    if (!t) return;
    if (sc->mode == SCENE_RGB && j0 == 0 && j1 == 3) {
        /* colour_at is rgb[j], and the three sums stay in registers (through L, each term
         * waited on the last one's store) */
        double l0 = 0, l1 = 0, l2 = 0;
        for (int i = 0; i < t->n; i++) {
            const double *e = sc->obj[t->emitter[i]].emit, wi = t->w[i];
            l0 += wi * e[0], l1 += wi * e[1], l2 += wi * e[2];
        }
        L[0] = l0 * alb[0], L[1] = l1 * alb[1], L[2] = l2 * alb[2];
        return;
    }
    for (int i = 0; i < t->n; i++)
        for (int j = j0; j < j1; j++)
            L[j] += t->w[i] * colour_at(sc, w, j, sc->obj[t->emitter[i]].emit);
    for (int j = j0; j < j1; j++) L[j] *= colour_at(sc, w, j, alb);
}

/* A tent of radius r (pixels) by inversion of its distribution. */
static double tent(double u, double r)
{
    return u < 0.5 ? r * (sqrt(2 * u) - 1) : r * (1 - sqrt(2 * (1 - u)));
}

typedef struct {
    double in[BLOCK * MAX_WAVE * 5], org[BLOCK * MAX_WAVE * 3], dir[BLOCK * MAX_WAVE * 3];
    double eta[BLOCK * MAX_WAVE], pdf[BLOCK];
    double o4[BLOCK * MAX_WAVE * 4], jac[BLOCK * MAX_WAVE * 16]; /* full estimator */
    unsigned char pass[BLOCK * MAX_WAVE];
    wave_set waves[BLOCK]; /* spectral: each sample's; else waves[0] serves all */
    /* each sample's low-discrepancy numbers: pixel 2, pupil 2, direct light 5 */
    double draw[BLOCK * DRAWS];
    int px[BLOCK];  /* each sample's pixel (column of the row) */
    long k[BLOCK];  /* and its index among the pixel's spp */
    /* per row: its weight, scene-frame direction, hit (hit[r].obj < 0: none), albedo, and
     * its place among the lit hits (-1: none), whose hits, uniforms and terms follow */
    double wt[BLOCK * MAX_WAVE], ds[BLOCK * MAX_WAVE * 3], alb[BLOCK * MAX_WAVE * 3];
    /* the rays from near the lens: origins, directions, rows, hits */
    double os[BLOCK * MAX_WAVE * 3], near_d[BLOCK * MAX_WAVE * 3];
    int near_of[BLOCK * MAX_WAVE];
    scene_hit near_hit[BLOCK * MAX_WAVE];
    unsigned char near_ok[BLOCK * MAX_WAVE];
    scene_hit hit[BLOCK * MAX_WAVE], lit_hit[BLOCK * MAX_WAVE];
    int lit_of[BLOCK * MAX_WAVE];
    double lit_u[BLOCK * MAX_WAVE * 5];
    scene_light_terms lit_t[BLOCK * MAX_WAVE];
} block_buf;

/* Per pixel: the sums of the samples' contributions and of their squares, the counts. */
typedef struct {
    double sum[3], sum2[3];
    double passed, full, fallback;
} pixel_acc;

/* The lens part of one block: rows are (sample, wavelength ray). */
static void lens_block(const render_job *job, size_t rows, block_buf *b)
{
    const render_camera *cam = job->cam;
    if (cam->map_batch) {
        cam->map_batch(cam->ctx, rows, b->in, b->org, b->dir, b->eta, b->pass);
        return;
    }
    for (size_t r = 0; r < rows; r++)
        b->pass[r] = (unsigned char)cam->map(cam->ctx, b->in + 5 * r, b->org + 3 * r,
                                             b->dir + 3 * r, b->eta + r);
}

/* The full estimator's lens part for the block's rows: the outer-pupil coordinates and
 * their Jacobian (in one batch where the camera can), and in place of each row's ray the
 * ray they give; pass gets P_a. */
static void full_block(const render_job *job, size_t rows, block_buf *b)
{
    const render_camera *cam = job->cam;
    if (cam->outer_batch)
        cam->outer_batch(cam->ctx, rows, b->in, b->o4, b->jac, b->eta, b->pass);
    else
        for (size_t r = 0; r < rows; r++)
            b->pass[r] = (unsigned char)cam->outer(cam->ctx, b->in + 5 * r, b->o4 + 4 * r,
                                                   b->jac + 16 * r, b->eta + r);
    for (size_t r = 0; r < rows; r++) {
        lens_ray lr;
        if (!b->pass[r] || ray_from_outer(cam->lens, b->o4 + 4 * r, &lr)) {
            b->pass[r] = 0;
            continue;
        }
        memcpy(b->org + 3 * r, lr.o, sizeof lr.o);
        memcpy(b->dir + 3 * r, lr.d, sizeof lr.d);
    }
}

/* Camera rays leave the lens within this distance of the scene's origin (the front
 * vertex): the front element's rim, widened by a tenth; 0 when unknown (analytic lens). */
static double origin_radius(const render_camera *cam)
{
    if (!cam->lens) return 0;
    const lens_surface *f = &cam->lens->surf[0];
    double sag = lens_sag(f, f->semi_diameter * f->semi_diameter);
    if (!isfinite(sag)) sag = fabs(f->radius);
    return 1.1 * (fabs(cam->lens->vertex_z[0]) + hypot(f->semi_diameter, sag));
}

typedef struct {
    const scene_cull *cull;
    double rho;
} camera_cull;

/* One row's pixels in the making: their sample keys and sums, by column. */
typedef struct {
    int py;
    ld_pixel *key;
    pixel_acc *acc;
} row_state;

/* The block's low-discrepancy numbers, a pixel's run of samples at a time (ld_2d_run:
 * four samples a step); the direct light's only where a hit can need them. */
static void block_draws(const scene_t *sc, const row_state *row, long spp, int m, block_buf *b)
{
    int lit = 0;
    for (size_t o = 0; o < sc->nobj; o++) lit |= !sc->obj[o].emitter;
    for (int i = 0, e; i < m; i = e) {
        for (e = i + 1; e < m && b->px[e] == b->px[i] && b->k[e] == b->k[e - 1] + 1; e++) continue;
        const ld_pixel *key = &row->key[b->px[i]];
        double *d = b->draw + (size_t)DRAWS * i;
        ld_2d_run(key, DIM_PIXEL, spp, b->k[i], e - i, d, DRAWS);
        ld_2d_run(key, DIM_PUPIL, spp, b->k[i], e - i, d + 2, DRAWS);
        if (!lit) continue;
        ld_1d_run(key, DIM_SELECT, spp, b->k[i], e - i, d + 4, DRAWS);
        ld_2d_run(key, DIM_LIGHT, spp, b->k[i], e - i, d + 5, DRAWS);
        ld_2d_run(key, DIM_BSDF, spp, b->k[i], e - i, d + 7, DRAWS);
    }
}

/* The camera rays of the block's rows that passed the lens, in the scene's frame (ds),
 * their weights and hits (hit[r].obj < 0: none); rays from near the lens (all of them,
 * but for an analytic lens) meet the scene together (scene_intersect_camera_many). */
static void block_rays(const render_job *job, const camera_cull *cc, int m, int nray,
                       block_buf *b)
{
    const scene_t *sc = job->scene;
    int n = 0;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < nray; j++) {
            size_t r = (size_t)i * nray + j;
            scene_hit *h = &b->hit[r];
            h->obj = -1;
            if (!(b->pdf[i] > 0) || !b->pass[r]) continue; /* P_a = 0 */
            const double *in = b->in + 5 * r;
            double tr = job->use_eta ? b->eta[r] : job->eta_const > 0 ? job->eta_const : 1;
            double *os = b->os + 3 * n, *ds = b->ds + 3 * r;
            b->wt[r] = render_ray_weight(in[2], in[3], b->pdf[i], tr);
            render_lens_to_scene(b->org + 3 * r, os);
            render_lens_to_scene(b->dir + 3 * r, ds);
            if (os[0] * os[0] + os[1] * os[1] + os[2] * os[2] <= cc->rho * cc->rho) {
                /* made again, not copied: a copy's wide load of ds, just stored, stalls */
                render_lens_to_scene(b->dir + 3 * r, b->near_d + 3 * n);
                b->near_of[n++] = (int)r;
            } else if (!scene_intersect(sc, os, ds, 1e-6, INFINITY, h)) {
                h->obj = -1;
            }
        }
    scene_intersect_camera_many(sc, cc->cull, n, b->os, b->near_d, 1e-6, b->near_hit, b->near_ok);
    for (int k = 0; k < n; k++)
        if (b->near_ok[k]) b->hit[b->near_of[k]] = b->near_hit[k];
}

/* The block's hits: the full estimator's weight, the albedo; the lit hits gathered with
 * their samples' uniforms for direct light. Returns how many are lit. */
static int block_hits(const render_job *job, const row_state *row, int m, int nray,
                      block_buf *b)
{
    const scene_t *sc = job->scene;
    int full = job->estimator == RENDER_ESTIMATOR_FULL, nlit = 0;
    for (int i = 0; i < m; i++) {
        pixel_acc *acc = &row->acc[b->px[i]];
        for (int j = 0; j < nray; j++) {
            size_t r = (size_t)i * nray + j;
            scene_hit *h = &b->hit[r];
            b->lit_of[r] = -1;
            if (h->obj < 0) continue; /* L = 0 */
            if (full) {
                render_full_terms t;
                double tr = job->use_eta ? b->eta[r] : job->eta_const > 0 ? job->eta_const : 1;
                acc->full++;
                if (render_full_weight(job->cam->lens, b->in + 5 * r, b->o4 + 4 * r, b->jac + 16 * r,
                                       b->pdf[i], tr, h->p, h->n, &t) == 0)
                    b->wt[r] = t.weight;
                else
                    acc->fallback++;
            }
            if (!hit_albedo(sc, h, b->alb + 3 * r)) continue;
            b->lit_of[r] = nlit;
            b->lit_hit[nlit] = *h;
            memcpy(b->lit_u + 5 * nlit++, b->draw + DRAWS * i + 4, 5 * sizeof *b->lit_u);
        }
    }
    return nlit;
}

/* The block's samples' contributions (their rays' radiance times weight) into the sums of
 * their pixels, in sample order. */
static void block_sums(const render_job *job, const row_state *row, int m, int nray,
                       const block_buf *b)
{
    const scene_t *sc = job->scene;
    int spectral = sc->mode == SCENE_SPECTRAL;
    for (int i = 0; i < m; i++) {
        pixel_acc *acc = &row->acc[b->px[i]];
        const wave_set *w = &b->waves[spectral ? i : 0];
        double a0 = 0, a1 = 0, a2 = 0; /* the channels' sums in registers, not an array in memory */
        int any = 0;
        for (int j = 0; j < nray && b->pdf[i] > 0; j++) {
            size_t r = (size_t)i * nray + j;
            if (!b->pass[r]) continue; /* P_a = 0 */
            any = 1;
            const scene_hit *h = &b->hit[r];
            if (h->obj < 0) continue;
            double L[MAX_WAVE], wt = b->wt[r];
            int j0 = job->achromatic ? 0 : j, j1 = job->achromatic ? w->nwave : j + 1, lit = b->lit_of[r];
            scene_radiance(sc, w, j0, j1, h, b->ds + 3 * r, b->alb + 3 * r,
                           lit >= 0 ? &b->lit_t[lit] : NULL, L);
            for (int jj = j0; jj < j1; jj++) {
                double v = wt * L[jj];
                a0 += v * w->score[jj][0], a1 += v * w->score[jj][1], a2 += v * w->score[jj][2];
            }
        }
        acc->passed += any;
        double a[3] = {a0, a1, a2};
        for (int c = 0; c < 3; c++) acc->sum[c] += a[c], acc->sum2[c] += a[c] * a[c];
    }
}

/* Samples b->px[i], b->k[i] (i < m) of the row: lens, scene, sums. */
static void render_block(const render_job *job, const camera_cull *cc, const row_state *row,
                         int m, block_buf *b)
{
    const int py = row->py;
    const scene_t *sc = job->scene;
    const render_camera *cam = job->cam;
    long spp = job->spp;
    int full = job->estimator == RENDER_ESTIMATOR_FULL;
    double rad = job->filter_radius > 0 ? job->filter_radius : 1;
    /* the camera rays of the block */
    int nray = 0; /* rays per sample */
    int spectral = sc->mode == SCENE_SPECTRAL;
    if (!spectral) waves_of(sc, 0, &b->waves[0]); /* the same for every sample */
    block_draws(sc, row, spp, m, b);
    for (int i = 0; i < m; i++) {
        long k = b->k[i];
        int px = b->px[i];
        const ld_pixel *key = &row->key[px];
        double q[2] = {b->draw[DRAWS * i], b->draw[DRAWS * i + 1]};
        const double *p2 = b->draw + DRAWS * i + 2;
        if (job->filter == RENDER_FILTER_TENT) q[0] = 0.5 + tent(q[0], rad), q[1] = 0.5 + tent(q[1], rad);
        double x = ((px + q[0]) / sc->width - 0.5) * cam->sensor_w;
        double y = ((py + q[1]) / sc->height - 0.5) * cam->sensor_h;
        wave_set *w = &b->waves[spectral ? i : 0];
        if (spectral) waves_of(sc, ld_1d_px(key, DIM_LAMBDA, spp, k), w);
        double uu, vv;
        b->pdf[i] = render_sampler_sample_2d(job->sampler, x, y, p2[0], p2[1], &uu, &vv);
        nray = job->achromatic ? 1 : w->nwave;
        for (int j = 0; j < nray; j++) {
            double *ray_in = b->in + 5 * ((size_t)i * nray + j);
            ray_in[0] = x, ray_in[1] = y, ray_in[2] = uu, ray_in[3] = vv;
            ray_in[4] = job->achromatic ? GLASS_D_LINE : w->lambda[j];
        }
    }
    if (full) full_block(job, (size_t)m * nray, b);
    else lens_block(job, (size_t)m * nray, b);
    block_rays(job, cc, m, nray, b);
    int nlit = block_hits(job, row, m, nray, b);
    scene_direct_mis_many(sc, nlit, b->lit_hit, b->lit_u, b->lit_t);
    block_sums(job, row, m, nray, b);
}

/* Row py: its pixels' keys, their samples in blocks, their means (and variances) into
 * rgb (var); the counts added to tot. */
static void render_row(const render_job *job, const camera_cull *cc, block_buf *b, row_state *row,
                       int py, float *rgb, float *var, pixel_acc *tot)
{
    const scene_t *sc = job->scene;
    int W = sc->width;
    /* the pixels rendered: [xa, xb) of the row, or none (a crop) */
    int crop = job->x1 > 0, xa = crop ? job->x0 : 0, xb = crop ? job->x1 : W;
    if (xa < 0) xa = 0;
    if (xb > W) xb = W;
    if (crop && (py < job->y0 || py >= job->y1)) xb = xa;
    row->py = py;
    for (int px = xa; px < xb; px++) {
        ld_pixel_init(&row->key[px], ld_pixel_key(sc->seed, (size_t)py * W + px));
        memset(&row->acc[px], 0, sizeof row->acc[px]);
    }
    int m = 0;
    for (int px = xa; px < xb; px++)
        for (long k = 0; k < job->spp; k++) {
            b->px[m] = px, b->k[m] = k;
            if (++m == BLOCK) render_block(job, cc, row, m, b), m = 0;
        }
    if (m) render_block(job, cc, row, m, b);
    for (int px = 0; px < W; px++) {
        size_t pix = (size_t)py * W + px;
        pixel_acc acc;
        if (px >= xa && px < xb) acc = row->acc[px];
        else memset(&acc, 0, sizeof acc);
        tot->passed += acc.passed;
        tot->full += acc.full;
        tot->fallback += acc.fallback;
        double n = (double)job->spp;
        for (int c = 0; c < 3; c++) {
            double mean = acc.sum[c] / n;
            rgb[3 * pix + c] = (float)mean;
            if (var) {
                double v = n > 1 ? (acc.sum2[c] - n * mean * mean) / (n - 1) : 0;
                var[3 * pix + c] = (float)(fmax(v, 0) / n);
            }
        }
    }
}

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int render_image(const render_job *job, float *rgb, float *var, render_stats *st,
                 lens_err *err)
{
    const scene_t *sc = job->scene;
    int W = sc->width, H = sc->height;
    if (job->spp < 1 || W < 1 || H < 1) {
        lens_errf(err, sc->path, 0, "nothing to render (spp %ld, %dx%d)", job->spp, W, H);
        return -1;
    }
    if (job->estimator == RENDER_ESTIMATOR_FULL && (!job->cam->outer || !job->cam->lens)) {
        lens_errf(err, sc->path, 0, "the full estimator needs a lens with an outer-pupil Jacobian");
        return -1;
    }
    double t0 = omp_get_wtime(), c0 = cpu_now();
    long rows_done = 0;
    double passed_total = 0, full_total = 0, fallback_total = 0; /* reduced from tot */
    int threads = job->threads > 0 ? job->threads : omp_get_max_threads();
    int fail = 0;
    camera_cull cc = {NULL, origin_radius(job->cam)};
    scene_cull *cull = cc.rho > 0 ? scene_cull_new(sc, cc.rho) : NULL;
    cc.cull = cull;
#pragma omp parallel num_threads(threads) reduction(+ : passed_total, full_total, fallback_total)
    {
        block_buf *b = malloc(sizeof *b);
        row_state row = {0, malloc((size_t)W * sizeof *row.key), malloc((size_t)W * sizeof *row.acc)};
        pixel_acc tot;
        memset(&tot, 0, sizeof tot);
        if (!b || !row.key || !row.acc) {
#pragma omp atomic write
            fail = 1;
        }
#pragma omp for schedule(dynamic, 1)
        for (int py = 0; py < H; py++) {
            if (!b || !row.key || !row.acc) continue;
            render_row(job, &cc, b, &row, py, rgb, var, &tot);
            long done;
#pragma omp atomic capture
            done = ++rows_done;
            if (job->progress && omp_get_thread_num() == 0)
                job->progress(job->progress_ctx, (double)done / H);
        }
        free(b);
        free(row.key);
        free(row.acc);
        passed_total += tot.passed;
        full_total += tot.full;
        fallback_total += tot.fallback;
    }
    scene_cull_free(cull);
    if (fail) {
        lens_errf(err, sc->path, 0, "out of memory");
        return -1;
    }
    if (st) {
        double npix = job->x1 > 0 ? (double)(fmin(job->x1, W) - fmax(job->x0, 0)) *
                                        (fmin(job->y1, H) - fmax(job->y0, 0))
                                  : (double)W * H;
        st->camera_rays = npix * job->spp;
        st->passed_rays = passed_total;
        st->full_rays = full_total;
        st->full_fallback = fallback_total;
        st->seconds = omp_get_wtime() - t0;
        st->cpu_seconds = cpu_now() - c0;
    }
    return 0;
}
