/* Times one fitted system and the exact tracer on the same rays, for the reports:
 *   bench_system --samples FILE [--poly SYSTEM.poly] [--lens LENS] [--reps R]
 * prints "bench poly_batch_ns_per_ray V ns" and/or "bench exact_1thread_ns_per_ray V ns"
 * (medians of R repetitions, single thread). Without arguments it prints nothing, so
 * that `make bench` can run every bench program alike. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/lens.h"
#include "sparselens/poly.h"
#include "sparselens/samples.h"
#include "sparselens/trace.h"

static double now(void)
{
    return omp_get_wtime();
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Reads columns `names` of every finite row. */
static double *load(const char *path, const char *const *names, int n, size_t *count)
{
    lens_err err;
    samples_reader *r = samples_open(path, &err);
    if (!r) {
        fprintf(stderr, "bench_system: %s\n", err.msg);
        exit(1);
    }
    int map[16];
    if (samples_map(r, names, n, map, &err) != 0) {
        fprintf(stderr, "bench_system: %s\n", err.msg);
        exit(1);
    }
    size_t cap = 1024, k = 0;
    double *rows = malloc(cap * (size_t)n * sizeof *rows);
    double vals[64];
    int st;
    while ((st = samples_next(r, vals, &err)) != 0) {
        if (st < 0)
            continue;
        int finite = 1;
        for (int i = 0; i < n; i++)
            finite &= isfinite(vals[map[i]]) != 0;
        if (!finite)
            continue;
        if (k == cap)
            rows = realloc(rows, (cap *= 2) * (size_t)n * sizeof *rows);
        for (int i = 0; i < n; i++)
            rows[k * (size_t)n + (size_t)i] = vals[map[i]];
        k++;
    }
    samples_close(r);
    *count = k;
    return rows;
}

int main(int argc, char **argv)
{
    const char *samples = NULL, *poly_path = NULL, *lens_path = NULL;
    int reps = 5;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--samples"))
            samples = argv[i + 1];
        else if (!strcmp(argv[i], "--poly"))
            poly_path = argv[i + 1];
        else if (!strcmp(argv[i], "--lens"))
            lens_path = argv[i + 1];
        else if (!strcmp(argv[i], "--reps"))
            reps = atoi(argv[i + 1]);
    }
    if (!samples)
        return 0;
    if (reps < 1 || reps > 100)
        reps = 5;
    double t[100];
    lens_err err;
    if (poly_path) {
        poly_system *sys;
        if (poly_read(poly_path, &sys, &err) != 0) {
            fprintf(stderr, "bench_system: %s\n", err.msg);
            return 1;
        }
        int ni = poly_ninputs(sys), no = poly_noutputs(sys);
        const char *names[16];
        for (int i = 0; i < ni; i++)
            names[i] = poly_input_name(sys, i);
        size_t n;
        double *in = load(samples, names, ni, &n);
        double *out = malloc((n ? n : 1) * (size_t)no * sizeof *out);
        unsigned char *pass = malloc(n ? n : 1);
        for (int r = 0; r < reps; r++) {
            double t0 = now();
            poly_eval_batch(sys, n, in, out, pass);
            t[r] = (now() - t0) / (double)(n ? n : 1) * 1e9;
        }
        printf("bench poly_batch_ns_per_ray %.2f ns\n", median(t, reps));
        free(in);
        free(out);
        free(pass);
        poly_free(sys);
    }
    if (lens_path) {
        lens_t lens;
        if (lens_load(lens_path, NULL, &lens, &err) != 0) {
            fprintf(stderr, "bench_system: %s\n", err.msg);
            return 1;
        }
        static const char *const names[] = {"x", "y", "u", "v", "lambda"};
        size_t n;
        double *in = load(samples, names, 5, &n);
        double *out = malloc((n ? n : 1) * 5 * sizeof *out);
        for (int r = 0; r < reps; r++) {
            double t0 = now();
            trace_batch(&lens, TRACE_TO_OUTER, n, in, out, NULL, 1, &err);
            t[r] = (now() - t0) / (double)(n ? n : 1) * 1e9;
        }
        printf("bench exact_1thread_ns_per_ray %.2f ns\n", median(t, reps));
        free(in);
        free(out);
        lens_free(&lens);
    }
    return 0;
}
