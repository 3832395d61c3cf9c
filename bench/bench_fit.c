/* bench_fit: fit time and accuracy of lens-fit's fitter.
 *   bench_fit            the suite of reports/fit.md on lenses/fisheye-ii.lens: training
 *                        rays as `lens-trace -n N --seed 1`, test rays as `--seed 2`
 *                        (100000 passing), fits from 4000 and 15000 samples, and the
 *                        sweeps over the term budget and the degree
 *   bench_fit TRAIN TEST [--terms N] [--degree D] [--tolerance T] [--parts P]
 *             [--threads N] [--bins B] [--binby r|lambda|pupil] [--label NAME]
 *             [--frame meridional|none] [--lambda-transform inverse-square|identity]
 * Fits use lens-fit's defaults (the meridional frame except out_u, out_v, and
 * 1/lambda^2); the suite also gives the figures without them ("_noframe").
 * Prints "bench NAME VALUE UNIT" lines: fit time (wall and CPU), error on the test rays
 * that pass the lens per output, and the outer-pupil position error as a length,
 * sqrt(dx^2 + dy^2), RMS over those rays; with --bins the position error by bins. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sparselens/diag.h"
#include "sparselens/fit.h"
#include "sparselens/lens.h"
#include "sparselens/poly.h"
#include "sparselens/samples.h"
#include "sparselens/sampling.h"
#include "sparselens/trace.h"

static const char *cols[10] = {"x", "y", "u", "v", "lambda", "out_x", "out_y", "out_u", "out_v", "out_eta"};

static size_t load(const char *path, double **in, double **out)
{
    lens_err err;
    samples_reader *r = samples_open(path, &err);
    if (!r) {
        fprintf(stderr, "bench_fit: %s\n", err.msg);
        exit(1);
    }
    int map[10];
    if (samples_map(r, cols, 10, map, &err) != 0) {
        fprintf(stderr, "bench_fit: %s\n", err.msg);
        exit(1);
    }
    size_t cap = 1024, n = 0;
    *in = malloc(cap * 5 * sizeof **in);
    *out = malloc(cap * 5 * sizeof **out);
    double *vals = malloc((size_t)samples_ncols(r) * sizeof *vals);
    int st;
    while ((st = samples_next(r, vals, &err)) != 0) {
        if (st < 0) {
            fprintf(stderr, "bench_fit: %s\n", err.msg);
            exit(1);
        }
        if (n == cap) {
            cap *= 2;
            *in = realloc(*in, cap * 5 * sizeof **in);
            *out = realloc(*out, cap * 5 * sizeof **out);
        }
        for (int i = 0; i < 5; i++) {
            (*in)[n * 5 + i] = vals[map[i]];
            (*out)[n * 5 + i] = vals[map[5 + i]];
        }
        n++;
    }
    samples_close(r);
    free(vals);
    return n;
}

/* The first n passing rays of a seed, as lens-trace makes them (index order). */
static size_t generate(const lens_t *lens, unsigned long seed, size_t n, double **in,
                       double **out)
{
    sampling_options so = sampling_defaults();
    so.seed = seed;
    lens_err err;
    ray_generator *g = ray_generator_new(lens, &so, &err);
    if (!g) {
        fprintf(stderr, "bench_fit: %s\n", err.msg);
        exit(1);
    }
    const size_t chunk = 1 << 16;
    double *bi = malloc(chunk * 5 * sizeof *bi), *bo = malloc(chunk * 5 * sizeof *bo);
    *in = malloc(n * 5 * sizeof **in);
    *out = malloc(n * 5 * sizeof **out);
    size_t got = 0, next = 0;
    while (got < n) {
        if (ray_generator_fill(g, next, chunk, bi, &err) != 0 ||
            trace_batch(lens, TRACE_TO_OUTER, chunk, bi, bo, NULL, 0, &err) != 0) {
            fprintf(stderr, "bench_fit: %s\n", err.msg);
            exit(1);
        }
        next += chunk;
        for (size_t i = 0; i < chunk && got < n; i++)
            if (bo[5 * i + 4] > 0) {
                memcpy(*in + 5 * got, bi + 5 * i, 5 * sizeof **in);
                memcpy(*out + 5 * got, bo + 5 * i, 5 * sizeof **out);
                got++;
            }
    }
    free(bi);
    free(bo);
    ray_generator_free(g);
    return got;
}

static void run(const char *label, size_t nt, const double *tin, const double *tout, size_t ne,
                const double *ein, const double *eout, const fit_options *opt, int bins,
                const char *binby, int brief);

/* lens-fit's defaults for the columns of cols[] */
static const unsigned char PLAIN[5] = {0, 0, 1, 1, 0};
static void lens_fit_defaults(fit_options *opt)
{
    fit_options_default(opt);
    opt->frame = POLY_FRAME_MERIDIONAL;
    opt->frame_plain = PLAIN;
    opt->lambda_transform = POLY_XFORM_INVERSE_SQUARE;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        /* The suite. */
        lens_t lens;
        lens_err err;
        if (lens_load("lenses/fisheye-ii.lens", NULL, &lens, &err) != 0) {
            fprintf(stderr, "bench_fit: %s\n", err.msg);
            return 1;
        }
        double *tin, *tout, *ein, *eout;
        size_t nt = generate(&lens, 1, 15000, &tin, &tout);
        size_t ne = generate(&lens, 2, 100000, &ein, &eout);
        fit_options opt;
        fit_options_default(&opt);
        run("fit_fisheye-ii_4000_noframe", 4000, tin, tout, ne, ein, eout, &opt, 0, "r", 1);
        run("fit_fisheye-ii_15000_noframe", nt, tin, tout, ne, ein, eout, &opt, 0, "r", 1);
        lens_fit_defaults(&opt);
        run("fit_fisheye-ii_4000", 4000, tin, tout, ne, ein, eout, &opt, 0, "r", 0);
        run("fit_fisheye-ii_15000", nt, tin, tout, ne, ein, eout, &opt, 0, "r", 0);
        int terms[] = {10, 20, 30, 40, 60, 80};
        for (size_t i = 0; i < sizeof terms / sizeof *terms; i++) {
            char l[64];
            snprintf(l, sizeof l, "fit_fisheye-ii_4000_terms%d_deg11", terms[i]);
            opt.max_terms = terms[i];
            run(l, 4000, tin, tout, ne, ein, eout, &opt, 0, "r", 1);
        }
        opt.max_terms = 40;
        for (int d = 3; d <= 13; d++) {
            char l[64];
            snprintf(l, sizeof l, "fit_fisheye-ii_4000_terms40_deg%d", d);
            opt.max_degree = d;
            run(l, 4000, tin, tout, ne, ein, eout, &opt, 0, "r", 1);
        }
        free(tin); free(tout); free(ein); free(eout);
        lens_free(&lens);
        return 0;
    }
    fit_options opt;
    lens_fit_defaults(&opt);
    int bins = 0;
    const char *label = "fit", *binby = "r";
    for (int i = 3; i + 1 < argc; i += 2) {
        const char *k = argv[i], *v = argv[i + 1];
        if (!strcmp(k, "--terms")) opt.max_terms = atoi(v);
        else if (!strcmp(k, "--degree")) opt.max_degree = atoi(v);
        else if (!strcmp(k, "--tolerance")) opt.tolerance = atof(v);
        else if (!strcmp(k, "--parts")) opt.max_parts = atoi(v);
        else if (!strcmp(k, "--threads")) opt.threads = atoi(v);
        else if (!strcmp(k, "--bins")) bins = atoi(v);
        else if (!strcmp(k, "--label")) label = v;
        else if (!strcmp(k, "--binby")) binby = v;
        else if (!strcmp(k, "--frame") && poly_frame_parse(v) >= 0) opt.frame = poly_frame_parse(v);
        else if (!strcmp(k, "--lambda-transform") && poly_xform_parse(v) >= 0)
            opt.lambda_transform = poly_xform_parse(v);
        else { fprintf(stderr, "bench_fit: unknown option %s\n", k); return 1; }
    }
    double *tin, *tout, *ein, *eout;
    size_t nt = load(argv[1], &tin, &tout), ne = load(argv[2], &ein, &eout);
    run(label, nt, tin, tout, ne, ein, eout, &opt, bins, binby, 0);
    free(tin); free(tout); free(ein); free(eout);
    return 0;
}

static void run(const char *label, size_t nt, const double *tin, const double *tout, size_t ne,
                const double *ein, const double *eout, const fit_options *optp, int bins,
                const char *binby, int brief)
{
    fit_options opt = *optp;
    lens_err err;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    clock_t c0 = clock();
    poly_system *sys = fit_system("bench", 5, cols, 5, cols + 5, nt, tin, tout, &opt, &err);
    clock_t c1 = clock();
    clock_gettime(CLOCK_MONOTONIC, &t1);
    if (!sys) {
        fprintf(stderr, "bench_fit: %s\n", err.msg);
        exit(1);
    }
    double secs = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    printf("bench %s_time %.3f s\n", label, secs);
    printf("bench %s_cpu %.3f s\n", label, (double)(c1 - c0) / CLOCKS_PER_SEC);
    double *pred = malloc(ne * 5 * sizeof *pred);
    poly_eval_batch(sys, ne, ein, pred, NULL);
    double sse[5] = {0}, pos = 0, rmax = 0;
    size_t cnt = 0, nonfinite = 0;
    /* Bin key: sensor radius, wavelength, or the radius where the ray crosses the rear
     * element's vertex plane (41.1 mm before the sensor on fisheye-ii). */
    double *key = malloc(ne * sizeof *key), kmin = INFINITY;
    for (size_t i = 0; i < ne; i++) {
        const double *q = ein + i * 5;
        key[i] = !strcmp(binby, "lambda") ? q[4]
                 : !strcmp(binby, "pupil") ? hypot(q[0] + 41.1 * q[2], q[1] + 41.1 * q[3])
                                           : hypot(q[0], q[1]);
        rmax = fmax(rmax, key[i]);
        kmin = fmin(kmin, key[i]);
    }
    if (strcmp(binby, "lambda"))
        kmin = 0;
    double *bs = calloc((size_t)(bins + 1), sizeof *bs);
    size_t *bc = calloc((size_t)(bins + 1), sizeof *bc);
    for (size_t i = 0; i < ne; i++) {
        if (!(eout[i * 5 + 4] > 0) || !isfinite(eout[i * 5]))
            continue; /* the lens blocks it */
        for (int o = 0; o < 5; o++) {
            double d = pred[i * 5 + o] - eout[i * 5 + o];
            if (!isfinite(d))
                nonfinite++;
            sse[o] += d * d;
        }
        double e2 = pow(pred[i * 5] - eout[i * 5], 2) + pow(pred[i * 5 + 1] - eout[i * 5 + 1], 2);
        pos += e2;
        if (bins > 0) {
            int b = (int)((key[i] - kmin) / (rmax - kmin) * bins);
            b = b >= bins ? bins - 1 : b;
            bs[b] += e2;
            bc[b]++;
        }
        cnt++;
    }
    for (int o = 0; o < 5 && !brief; o++)
        printf("bench %s_rms_%s %.6g %s\n", label, cols[5 + o], sqrt(sse[o] / (double)cnt),
               o < 2 ? "mm" : "1");
    printf("bench %s_position_rms %.6g mm\n", label, sqrt(pos / (double)cnt));
    if (!brief) {
        printf("bench %s_test_rays %zu rays\n", label, cnt);
        printf("bench %s_nonfinite %zu values\n", label, nonfinite);
    }
    for (int b = 0; b < bins; b++)
        printf("bin %s %.3f..%.3f: position rms %.4g mm over %zu rays\n", binby,
               kmin + (rmax - kmin) * b / bins, kmin + (rmax - kmin) * (b + 1) / bins,
               bc[b] ? sqrt(bs[b] / (double)bc[b]) : NAN, bc[b]);
    for (int o = 0; o < 5; o++) {
        char key[64];
        snprintf(key, sizeof key, "fit_%s", cols[5 + o]);
        const char *m = poly_get_meta(sys, key);
        printf("# %s %s: %s\n", label, cols[5 + o], m ? m : "");
    }
    poly_free(sys);
    free(pred); free(bs); free(bc); free(key);
}
