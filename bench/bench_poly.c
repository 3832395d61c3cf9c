/* Evaluation throughput of a polynomial system of 5 outputs x 40 terms, degree <= 11, in
 * 5 inputs (the size of the supplement's fisheye-ii system; the term set of
 * tests/unit/poly_fixture.h, random coefficients: speed does not depend on them),
 * single thread, CPU time of this thread.
 * Prints "bench NAME VALUE UNIT" lines, each the median of 5 runs (11 shorter ones for
 * the batch paths; their best run too, the figure of a quiet machine), for
 *   naive     each term's powers computed from scratch (the baseline)
 *   scalar    poly_eval, one ray at a time
 *   batch     poly_eval_batch, the system as lens-fit's defaults make it: the meridional
 *             frame except out_u, out_v, and 1/lambda^2 (the fixture's terms, so the
 *             same count; with a SYSTEM.poly, that file)
 *   batch_noframe  poly_eval_batch of the same terms without frame or transform (lens-fit
 *             --frame none --lambda-transform identity; with SYSTEM.poly, NOFRAME.poly
 *             if given), for the cost of the frame
 *   emitted   the C of poly_emit_c, compiled now with $CC (or cc) -O2, one call per ray
 *   emitted_c_batch         its NAME_batch function on all rays, -O2 as well
 *   emitted_c_batch_native  the same compiled with -O2 -march=native (this CPU's vectors)
 *   jacobian  poly_eval_jacobian (outputs and all 25 derivatives), one ray at a time
 *   jacobian_batch  poly_eval_jacobian_batch (the 25 derivatives)
 *   trace     the exact tracer (trace_batch, one thread) on passing fisheye-ii rays,
 *             for the speed-up of the polynomial system over tracing
 * Usage: bench_poly [RAYS [SYSTEM.poly [NOFRAME.poly]]]   (default 1000000 rays, the
 * fixture system; a system file must have the inputs x y u v lambda) */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../tests/unit/poly_fixture.h"
#include "sparselens/lens.h"
#include "sparselens/poly.h"
#include "sparselens/trace.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

typedef int (*emitted_fn)(const double *in, double *out);
typedef void (*emitted_batch_fn)(size_t n, const double *in, double *out, unsigned char *pass);

/* Compiles the emitted C into a shared object with the extra flags and loads it; NULL if
 * no compiler. *batch gets its NAME_batch function. */
static emitted_fn load_emitted(const poly_system *s, char *dir, const char *flags, void **handle,
                               emitted_batch_fn *batch)
{
    char src[300], so[300], cmd[1024];
    snprintf(src, sizeof src, "%s/fn.c", dir);
    snprintf(so, sizeof so, "%s/fn%s.so", dir, *flags ? "_native" : "");
    FILE *f = fopen(src, "w");
    if (!f || poly_emit_c(f, s, "bench_fn") != 0) {
        if (f)
            fclose(f);
        return NULL;
    }
    fclose(f);
    const char *cc = getenv("CC");
    snprintf(cmd, sizeof cmd, "%s -std=c99 -O2 %s -fPIC -shared %s -o %s -lm", cc && *cc ? cc : "cc",
             flags, src, so);
    if (system(cmd) != 0)
        return NULL;
    *handle = dlopen(so, RTLD_NOW);
    if (!*handle)
        return NULL;
    *batch = (emitted_batch_fn)(uintptr_t)dlsym(*handle, "bench_fn_batch");
    return (emitted_fn)(uintptr_t)dlsym(*handle, "bench_fn");
}

/* Passing fisheye-ii rays: sensor points over the sensor, aimed at the rear element
 * at 0.55 um, keeping those the tracer passes. Returns how many it made (0 if the lens is not found). */
static size_t tracer_rays(lens_t *lens, double *in, size_t n)
{
    lens_err err;
    lens_init(lens);
    if (lens_load("lenses/fisheye-ii.lens", NULL, lens, &err) != 0)
        return 0;
    double idx[64];
    if (lens->nsurf + 1 > 64 || lens_indices(lens, 0.55, idx, &err) != 0)
        return 0;
    double w = isfinite(lens->sensor_w) ? lens->sensor_w : 24, h = isfinite(lens->sensor_h) ? lens->sensor_h : 16;
    size_t last = lens->nsurf - 1;
    double rear = lens->surf[last].semi_diameter;
    double dist = lens_total_track(lens) - lens->vertex_z[last];
    fixture_rng g = {5};
    size_t m = 0;
    for (size_t tries = 0; m < n && tries < 20 * n; tries++) {
        double x = w * (fixture_uniform(&g) - 0.5), y = h * (fixture_uniform(&g) - 0.5);
        double a = 6.283185307179586 * fixture_uniform(&g), r = rear * sqrt(fixture_uniform(&g));
        double u = (r * cos(a) - x) / dist, v = (r * sin(a) - y) / dist, out[4];
        double xyuv[4] = {x, y, u, v};
        if (trace_sample(lens, idx, TRACE_TO_OUTER, xyuv, out).status != TRACE_PASSED)
            continue;
        double *row = in + 5 * m++;
        row[0] = x, row[1] = y, row[2] = u, row[3] = v, row[4] = 0.55;
    }
    return m;
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
    poly_system *s = NULL, *s0 = NULL;
    for (int a = 2; a < argc && a < 4; a++) {
        lens_err err;
        poly_system **d = a == 2 ? &s : &s0;
        if (poly_read(argv[a], d, &err) != 0) {
            fprintf(stderr, "bench_poly: %s\n", err.msg);
            return 1;
        }
        for (int i = 0; i < 5; i++)
            if (poly_ninputs(*d) != 5 || poly_input_index(*d, fixture_inputs[i]) != i ||
                poly_noutputs(*d) != 5 || poly_nparts(*d) != 1) {
                fprintf(stderr, "bench_poly: %s: needs inputs x y u v lambda, 5 outputs, 1 part\n",
                        argv[a]);
                return 1;
            }
    }
    if (!s) {
        /* the fixture twice: as lens-fit's defaults lay it out, and without the frame */
        s = fixture_system(40, 11, 1, 2016);
        s0 = fixture_system(40, 11, 1, 2016);
        if (!s || !s0 || poly_set_frame(s, POLY_FRAME_MERIDIONAL) != 0 ||
            poly_set_output_plain(s, 2, 1) != 0 || poly_set_output_plain(s, 3, 1) != 0 ||
            poly_set_transform(s, 4, POLY_XFORM_INVERSE_SQUARE) != 0) {
            fprintf(stderr, "bench_poly: cannot build the framed fixture\n");
            return 1;
        }
        poly_set_scaling(s, 4, 4.25, 2.0); /* 1/lambda^2 over 0.40..0.70 um */
    }
    double *in = malloc(n * 5 * sizeof(double)), *out = malloc(n * 5 * sizeof(double));
    unsigned char *pass = malloc(n);
    fixture_rng g = {77};
    for (size_t r = 0; r < n; r++)
        fixture_ray(&g, in + r * 5);

    flat F;
    int total = 0;
    for (int o = 0; o < 5; o++)
        total += poly_nterms(s, 0, o);
    F.exps = malloc((size_t)total * 5 * sizeof(int));
    F.coef = malloc((size_t)total * sizeof(double));
    int k = 0;
    for (int o = 0; o < 5; o++) {
        F.nterms[o] = poly_nterms(s, 0, o);
        for (int t = 0; t < F.nterms[o]; t++, k++)
            poly_get_term(s, 0, o, t, F.exps + 5 * k, F.coef + k);
    }
    for (int i = 0; i < 5; i++)
        poly_get_scaling(s, i, &F.off[i], &F.scale[i]);

    char dir[] = "/tmp/bench_poly_XXXXXX";
    void *handle = NULL, *handle_native = NULL;
    emitted_batch_fn fn_batch = NULL, fn_batch_native = NULL;
    emitted_fn fn = mkdtemp(dir) ? load_emitted(s, dir, "", &handle, &fn_batch) : NULL;
    if (fn && !load_emitted(s, dir, "-march=native", &handle_native, &fn_batch_native))
        fn_batch_native = NULL;
    const char *names[9] = {"naive",           "scalar",         "batch",
                            "emitted_c",       "jacobian",       "jacobian_batch",
                            "emitted_c_batch", "emitted_c_batch_native", "batch_noframe"};
    double checksum = 0, batch_ns = 0;
    double *jac = malloc(n * 25 * sizeof(double));
    for (int m = 0; m < 9; m++) {
        if (m == 8 && !s0)
            continue;
        if ((m == 3 && !fn) || (m == 6 && !fn_batch) || (m == 7 && !fn_batch_native)) {
            fprintf(stderr, "bench_poly: no C compiler: emitted C (%s) not measured\n", names[m]);
            continue;
        }
        /* the batch paths are fast: more, shorter runs (a tenth of the rays each) give a
         * steadier median on a shared machine */
        const int batchlike = m == 2 || m >= 5, runs = batchlike ? 11 : 5;
        const size_t nr = batchlike ? (n / 10 ? n / 10 : n) : m == 4 ? (n / 10 ? n / 10 : n) : n;
        double t[11];
        for (int run = 0; run < runs; run++) {
            const double *rin = in + (batchlike ? (size_t)run % 10 * nr * 5 : 0);
            double t0 = now();
            if (m == 0)
                naive(&F, nr, rin, out);
            else if (m == 1)
                for (size_t r = 0; r < nr; r++)
                    pass[r] = (unsigned char)poly_eval(s, rin + r * 5, out + r * 5);
            else if (m == 2)
                poly_eval_batch(s, nr, rin, out, pass);
            else if (m == 3)
                for (size_t r = 0; r < nr; r++)
                    pass[r] = (unsigned char)fn(rin + r * 5, out + r * 5);
            else if (m == 4)
                for (size_t r = 0; r < nr; r++)
                    pass[r] = (unsigned char)poly_eval_jacobian(s, rin + r * 5, out + r * 5,
                                                                jac + r * 25);
            else if (m == 5)
                poly_eval_jacobian_batch(s, nr, rin, jac);
            else if (m == 8)
                poly_eval_batch(s0, nr, rin, out, pass);
            else
                (m == 6 ? fn_batch : fn_batch_native)(nr, rin, out, pass);
            t[run] = now() - t0;
            checksum += out[nr / 2 * 5] + jac[nr / 2 * 25];
        }
        qsort(t, (size_t)runs, sizeof t[0], cmp);
        double ns = t[runs / 2] / (double)nr * 1e9;
        if (m == 2)
            batch_ns = ns;
        printf("bench poly_eval_%s_ns_per_ray %.2f ns\n", names[m], ns);
        printf("bench poly_eval_%s_mrays_per_s %.2f Mrays/s\n", names[m], 1e3 / ns);
        if (batchlike)
            printf("bench poly_eval_%s_best_ns_per_ray %.2f ns\n", names[m],
                   t[0] / (double)nr * 1e9);
    }
    free(jac);
    if (handle)
        dlclose(handle);
    if (handle_native)
        dlclose(handle_native);
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "bench_poly: could not remove %s\n", dir);

    /* the exact tracer on the same machine, in the same run */
    lens_t lens;
    size_t nt = n / 20 < 20000 ? n / 20 : 20000;
    double *tin = malloc(nt * 5 * sizeof(double)), *tout = malloc(nt * 5 * sizeof(double));
    size_t got = tracer_rays(&lens, tin, nt);
    if (got > 0) {
        double t[5];
        lens_err err;
        for (int run = 0; run < 5; run++) {
            double t0 = now();
            trace_batch(&lens, TRACE_TO_OUTER, got, tin, tout, NULL, 1, &err);
            t[run] = now() - t0;
        }
        qsort(t, 5, sizeof t[0], cmp);
        double ns = t[2] / (double)got * 1e9;
        printf("bench trace_fisheye_ii_ns_per_ray %.2f ns\n", ns);
        printf("bench poly_batch_speedup_over_trace %.1f x\n", ns / batch_ns);
        lens_free(&lens);
    } else {
        fprintf(stderr, "bench_poly: lenses/fisheye-ii.lens not usable: tracer not measured\n");
    }
    free(tin);
    free(tout);
    printf("bench poly_eval_monomials %d count\n", poly_nmonomials(s, 0));
    fprintf(stderr, "checksum %g\n", checksum);
    free(in);
    free(out);
    free(pass);
    free(F.exps);
    free(F.coef);
    poly_free(s);
    poly_free(s0);
    return 0;
}
