/* Evaluation throughput of a polynomial system of 5 outputs x 40 terms, degree <= 11, in
 * 5 inputs (the size of the supplement's fisheye-ii system), single thread.
 * Prints "bench NAME VALUE UNIT" lines: the median of 5 runs for
 *   naive   each term's powers computed from scratch (the baseline)
 *   scalar  poly_eval, one ray at a time
 *   batch   poly_eval_batch
 * Usage: bench_poly [RAYS]   (default 1000000) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../tests/unit/poly_fixture.h"
#include "poly.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct {
    int nterms[5];
    int *exps; /* 5 x 40 x 5 */
    double *coef;
    double off[5], scale[5];
} flat;

static void naive(const flat *F, size_t n, const double *in, double *out)
{
    for (size_t r = 0; r < n; r++) {
        double s[5];
        for (int i = 0; i < 5; i++)
            s[i] = (in[r * 5 + i] - F->off[i]) / F->scale[i];
        const int *e = F->exps;
        const double *c = F->coef;
        for (int o = 0; o < 5; o++) {
            double acc = 0;
            for (int t = 0; t < F->nterms[o]; t++, e += 5, c++) {
                double m = *c;
                for (int i = 0; i < 5; i++)
                    for (int k = 0; k < e[i]; k++)
                        m *= s[i];
                acc += m;
            }
            out[r * 5 + o] = acc;
        }
    }
}

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? strtoul(argv[1], NULL, 10) : 1000000;
    if (n == 0)
        n = 1000000;
    poly_system *s = fixture_system(40, 11, 1, 2016);
    double *in = malloc(n * 5 * sizeof(double)), *out = malloc(n * 5 * sizeof(double));
    unsigned char *pass = malloc(n);
    fixture_rng g = {77};
    for (size_t r = 0; r < n; r++)
        fixture_ray(&g, in + r * 5);

    flat F;
    F.exps = malloc(5 * 40 * 5 * sizeof(int));
    F.coef = malloc(5 * 40 * sizeof(double));
    int k = 0;
    for (int o = 0; o < 5; o++) {
        F.nterms[o] = poly_nterms(s, 0, o);
        for (int t = 0; t < F.nterms[o]; t++, k++)
            poly_get_term(s, 0, o, t, F.exps + 5 * k, F.coef + k);
    }
    for (int i = 0; i < 5; i++)
        poly_get_scaling(s, i, &F.off[i], &F.scale[i]);

    const char *names[3] = {"naive", "scalar", "batch"};
    double checksum = 0;
    for (int m = 0; m < 3; m++) {
        double t[5];
        for (int run = 0; run < 5; run++) {
            double t0 = now();
            if (m == 0)
                naive(&F, n, in, out);
            else if (m == 1)
                for (size_t r = 0; r < n; r++)
                    pass[r] = (unsigned char)poly_eval(s, in + r * 5, out + r * 5);
            else
                poly_eval_batch(s, n, in, out, pass);
            t[run] = now() - t0;
            checksum += out[n / 2 * 5];
        }
        qsort(t, 5, sizeof t[0], cmp);
        double ns = t[2] / (double)n * 1e9;
        printf("bench poly_eval_%s_ns_per_ray %.2f ns\n", names[m], ns);
        printf("bench poly_eval_%s_mrays_per_s %.2f Mrays/s\n", names[m], 1e3 / ns);
    }
    printf("bench poly_eval_monomials %d count\n", poly_nmonomials(s, 0));
    fprintf(stderr, "checksum %g\n", checksum);
    free(in);
    free(out);
    free(pass);
    free(F.exps);
    free(F.coef);
    poly_free(s);
    return 0;
}
