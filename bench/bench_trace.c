/* Exact-trace throughput, sensor -> outer pupil, in ns per ray (median of 5 runs), on
 * fisheye-ii and pbrt's 50 mm double Gauss, single thread and all threads.
 * Rays: uniform on the sensor, aimed at uniform points of the rear element's disc,
 * wavelengths uniform over 0.4..0.7 um (so the index tables are part of the cost).
 * Single thread is timed in CPU time (robust on a shared machine), all threads in wall
 * time. Prints "bench NAME VALUE UNIT" lines. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "../tests/unit/fixture_lenses.h"
#include "sparselens/rng.h"
#include "sparselens/sampling.h"
#include "sparselens/trace.h"

/* The machine may be shared: wall time counts other processes' turns, CPU time does
 * not. Single thread: CPU time of the process; all threads: wall time. */
static double now(int cpu)
{
    struct timespec ts;
    clock_gettime(cpu ? CLOCK_PROCESS_CPUTIME_ID : CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void bench_lens(const lens_t *L, const char *name, double sw, double sh, size_t N)
{
    double *in = malloc(N * 5 * sizeof *in), *out = malloc(N * 5 * sizeof *out);
    if (!in || !out)
        exit(1);
    sampling_options so = sampling_defaults();
    so.strategy = SAMPLING_REAR;
    so.sensor_w = sw;
    so.sensor_h = sh;
    so.lambda_min = 0.4;
    so.lambda_max = 0.7;
    so.seed = 1;
    lens_err err;
    ray_generator *g = ray_generator_new(L, &so, &err);
    if (!g || ray_generator_fill(g, 0, N, in, &err)) {
        fprintf(stderr, "bench_trace: %s\n", err.msg);
        exit(1);
    }
    ray_generator_free(g);
    int maxth = omp_get_max_threads();
    for (int pass = 0; pass < 2; pass++) {
        int th = pass ? maxth : 1;
        double t[5];
        for (int k = 0; k < 5; k++) {
            double t0 = now(!pass);
            trace_batch(L, TRACE_TO_OUTER, N, in, out, NULL, th, &err);
            t[k] = now(!pass) - t0;
        }
        qsort(t, 5, sizeof t[0], cmp);
        size_t passed = 0;
        for (size_t i = 0; i < N; i++)
            passed += out[5 * i + 4] > 0;
        printf("bench trace_%s_%s_ns_per_ray %.1f ns\n", name, pass ? "allthreads" : "1thread",
               t[2] / N * 1e9);
        if (pass) {
            printf("bench trace_%s_threads %d threads\n", name, th);
        } else {
            printf("bench trace_%s_1thread_ns_per_passing_ray %.1f ns\n", name,
                   t[2] / passed * 1e9);
            printf("bench sampling_%s_rear_pass_fraction %.3f fraction\n", name,
                   (double)passed / N);
        }
    }
    /* The pupil-aware strategy: build time and the fraction of its rays that pass. */
    so.strategy = SAMPLING_PUPIL;
    so.threads = 1;
    double t0 = now(1);
    g = ray_generator_new(L, &so, &err);
    double tb = now(1) - t0;
    if (!g || ray_generator_fill(g, 0, N, in, &err)) {
        fprintf(stderr, "bench_trace: %s\n", err.msg);
        exit(1);
    }
    ray_generator_free(g);
    trace_batch(L, TRACE_TO_OUTER, N, in, out, NULL, 0, &err);
    size_t passed = 0;
    for (size_t i = 0; i < N; i++)
        passed += out[5 * i + 4] > 0;
    printf("bench sampling_%s_pupil_build_s %.3f s\n", name, tb);
    printf("bench sampling_%s_pupil_pass_fraction %.3f fraction\n", name, (double)passed / N);
    free(in);
    free(out);
}

int main(void)
{
    lens_t L;
    size_t N = 200000;
    if (fixture_fisheye_ii(&L))
        return 1;
    bench_lens(&L, "fisheye-ii", 23.6, 15.7, N);
    lens_free(&L);
    if (fixture_dgauss50(&L))
        return 1;
    bench_lens(&L, "dgauss.50mm", 36, 24, N);
    lens_free(&L);
    return 0;
}
