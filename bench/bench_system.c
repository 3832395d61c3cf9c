/* Times fitted systems against the exact tracer on the same rays, for the reports
 * (tools/sweep.sh):
 *   bench_system --samples FILE --lens LENS [--rounds R] [--samples FILE2] --poly A.poly ...
 * Each --poly is timed on the columns of the --samples given last before it (poly_eval_batch,
 * one thread), the lens (trace_batch to the outer pupil, one thread) on those given
 * before --lens. Every round times the lens and then every system once (each timed call
 * after an untimed one), for R rounds
 * (default 15): interleaved, so that a slow phase of a shared machine slows them all,
 * and a system's time divided by the lens's of the same run stays put. CPU time of
 * this thread. Prints
 *   exact BEST_NS MEDIAN_NS SPREAD_PCT
 *   system PATH BEST_NS MEDIAN_NS SPREAD_PCT BEST_OVER_EXACT
 * (best: the fastest round, a quiet machine's figure; spread: median / best - 1).
 * Without arguments it prints nothing, so that `make bench` can run every bench
 * program alike. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sparselens/lens.h"
#include "sparselens/poly.h"
#include "sparselens/samples.h"
#include "sparselens/trace.h"

#define MAX_SYSTEMS 256
#define MAX_ROUNDS 100

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
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
    if (n > 16 || samples_map(r, names, n, map, &err) != 0) {
        fprintf(stderr, "bench_system: %s\n", n > 16 ? "more than 16 inputs" : err.msg);
        exit(1);
    }
    size_t cap = 1024, k = 0;
    double *rows = malloc(cap * (size_t)n * sizeof *rows);
    double vals[64];
    int st;
    while (rows && (st = samples_next(r, vals, &err)) != 0) {
        if (st < 0)
            continue;
        int finite = 1;
        for (int i = 0; i < n; i++)
            finite &= isfinite(vals[map[i]]) != 0;
        if (!finite)
            continue;
        if (k == cap)
            rows = realloc(rows, (cap *= 2) * (size_t)n * sizeof *rows);
        for (int i = 0; rows && i < n; i++)
            rows[k * (size_t)n + (size_t)i] = vals[map[i]];
        k++;
    }
    samples_close(r);
    if (!rows) {
        fprintf(stderr, "bench_system: out of memory\n");
        exit(1);
    }
    *count = k;
    return rows;
}

typedef struct {
    const char *path;
    poly_system *sys;
    double *in, *out;
    unsigned char *pass;
    size_t n;
    double t[MAX_ROUNDS];
} timed_system;

static void summary(double *t, int rounds, size_t n, double *best, double *med, double *spread)
{
    qsort(t, (size_t)rounds, sizeof *t, cmp);
    *best = t[0] / (double)(n ? n : 1) * 1e9;
    *med = t[rounds / 2] / (double)(n ? n : 1) * 1e9;
    *spread = 100 * (*med / *best - 1);
}

int main(int argc, char **argv)
{
    const char *samples = NULL, *lens_path = NULL, *lens_samples = NULL;
    int rounds = 15, nsys = 0;
    static timed_system sys[MAX_SYSTEMS];
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--samples")) {
            samples = argv[i + 1];
        } else if (!strcmp(argv[i], "--lens")) {
            lens_path = argv[i + 1];
            lens_samples = samples;
        } else if (!strcmp(argv[i], "--rounds") || !strcmp(argv[i], "--reps")) {
            rounds = atoi(argv[i + 1]);
        } else if (!strcmp(argv[i], "--poly") && samples && nsys < MAX_SYSTEMS) {
            lens_err err;
            timed_system *s = &sys[nsys++];
            s->path = argv[i + 1];
            if (poly_read(s->path, &s->sys, &err) != 0) {
                fprintf(stderr, "bench_system: %s\n", err.msg);
                return 1;
            }
            int ni = poly_ninputs(s->sys);
            const char *names[16];
            for (int k = 0; k < ni && k < 16; k++)
                names[k] = poly_input_name(s->sys, k);
            s->in = load(samples, names, ni, &s->n);
            s->out = malloc((s->n ? s->n : 1) * (size_t)poly_noutputs(s->sys) * sizeof *s->out);
            s->pass = malloc(s->n ? s->n : 1);
            if (!s->out || !s->pass)
                return 1;
        } else {
            fprintf(stderr, "bench_system: bad argument %s\n", argv[i]);
            return 1;
        }
    }
    if (!samples)
        return 0;
    if (rounds < 1 || rounds > MAX_ROUNDS)
        rounds = 15;
    lens_t lens;
    lens_err err;
    double *lin = NULL, *lout = NULL, tl[MAX_ROUNDS];
    size_t ln = 0;
    if (lens_path) {
        static const char *const names[] = {"x", "y", "u", "v", "lambda"};
        if (lens_load(lens_path, NULL, &lens, &err) != 0) {
            fprintf(stderr, "bench_system: %s\n", err.msg);
            return 1;
        }
        lin = load(lens_samples, names, 5, &ln);
        lout = malloc((ln ? ln : 1) * 5 * sizeof *lout);
        if (!lout)
            return 1;
    }
    /* Each timed call follows an untimed one of the same work, so that it finds its own
     * rays, code and branch history in place rather than the last system's (as
     * bench_poly does; there the same call measured 60-63 or 53-57 ns a ray by its
     * place in the round without it). */
    for (int r = 0; r < rounds; r++) {
        if (lens_path) {
            trace_batch(&lens, TRACE_TO_OUTER, ln, lin, lout, NULL, 1, &err);
            double t0 = now();
            trace_batch(&lens, TRACE_TO_OUTER, ln, lin, lout, NULL, 1, &err);
            tl[r] = now() - t0;
        }
        for (int k = 0; k < nsys; k++) {
            poly_eval_batch(sys[k].sys, sys[k].n, sys[k].in, sys[k].out, sys[k].pass);
            double t0 = now();
            poly_eval_batch(sys[k].sys, sys[k].n, sys[k].in, sys[k].out, sys[k].pass);
            sys[k].t[r] = now() - t0;
        }
    }
    double eb = NAN, em, es;
    if (lens_path) {
        summary(tl, rounds, ln, &eb, &em, &es);
        printf("exact %.2f %.2f %.1f\n", eb, em, es);
    }
    for (int k = 0; k < nsys; k++) {
        double b, m, sp;
        summary(sys[k].t, rounds, sys[k].n, &b, &m, &sp);
        printf("system %s %.2f %.2f %.1f %.4f\n", sys[k].path, b, m, sp, b / eb);
        poly_free(sys[k].sys);
        free(sys[k].in);
        free(sys[k].out);
        free(sys[k].pass);
    }
    if (lens_path) {
        lens_free(&lens);
        free(lin);
        free(lout);
    }
    return 0;
}
