/* bench_fit: fits a sample file with fit_system and checks the system on a test file.
 *   bench_fit TRAIN TEST [--terms N] [--degree D] [--tolerance T] [--parts P]
 *             [--threads N] [--bins B] [--label NAME]
 * Prints "bench NAME VALUE UNIT" lines: fit time (wall), held-out error on TEST per
 * output (rms over the test rays that pass the lens), and the outer-pupil position
 * error as a length, sqrt(dx^2 + dy^2), RMS over those rays; with --bins the position
 * error by sensor radius. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "diag.h"
#include "fit.h"
#include "poly.h"
#include "samples.h"

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

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_fit TRAIN TEST [--terms N] [--degree D] [--tolerance T] "
                        "[--parts P] [--threads N] [--bins B] [--label NAME]\n");
        return 1;
    }
    fit_options opt;
    fit_options_default(&opt);
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
        else { fprintf(stderr, "bench_fit: unknown option %s\n", k); return 1; }
    }
    double *tin, *tout, *ein, *eout;
    size_t nt = load(argv[1], &tin, &tout), ne = load(argv[2], &ein, &eout);
    lens_err err;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    clock_t c0 = clock();
    poly_system *sys = fit_system("bench", 5, cols, 5, cols + 5, nt, tin, tout, &opt, &err);
    clock_t c1 = clock();
    clock_gettime(CLOCK_MONOTONIC, &t1);
    if (!sys) {
        fprintf(stderr, "bench_fit: %s\n", err.msg);
        return 1;
    }
    double secs = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    printf("bench %s_fit_wall %.3f s\n", label, secs);
    printf("bench %s_fit_cpu %.3f s\n", label, (double)(c1 - c0) / CLOCKS_PER_SEC);
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
    for (int o = 0; o < 5; o++)
        printf("bench %s_rms_%s %.6g %s\n", label, cols[5 + o], sqrt(sse[o] / (double)cnt),
               o < 2 ? "mm" : "1");
    printf("bench %s_position_rms %.6g mm\n", label, sqrt(pos / (double)cnt));
    printf("bench %s_test_rays %zu rays\n", label, cnt);
    printf("bench %s_nonfinite %zu values\n", label, nonfinite);
    for (int b = 0; b < bins; b++)
        printf("bin %s %.3f..%.3f: position rms %.4g mm over %zu rays\n", binby,
               kmin + (rmax - kmin) * b / bins, kmin + (rmax - kmin) * (b + 1) / bins,
               bc[b] ? sqrt(bs[b] / (double)bc[b]) : NAN, bc[b]);
    for (int o = 0; o < 5; o++) {
        char key[64];
        snprintf(key, sizeof key, "fit_%s", cols[5 + o]);
        const char *m = poly_get_meta(sys, key);
        printf("# %s: %s\n", cols[5 + o], m ? m : "");
    }
    poly_free(sys);
    free(tin); free(tout); free(ein); free(eout); free(pred); free(bs); free(bc); free(key);
    return 0;
}
