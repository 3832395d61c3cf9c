/* Evaluation speed of a polynomial system against the exact tracer, single thread, CPU
 * time of this thread, on the rays a renderer would ask for: sensor points uniform over
 * fisheye-ii's sensor aimed at uniform points of its rear element, wavelengths uniform
 * over 0.4..0.7 um (lens-trace's rear sampling); some of them the lens blocks.
 *   bench_poly [RAYS [SYSTEM.poly [NOFRAME.poly [TAG]]]]   (RAYS default 20000)
 * TAG names the figures (TAG_batch_ns_per_ray, ratio_TAG_...; default "poly").
 * SYSTEM.poly: the system measured (inputs x y u v lambda, first outputs out_x out_y
 * out_u out_v out_eta, one part); make bench passes the default fit of fisheye-ii
 * (lens-fit --terms 40 --degree 11 on lens-trace's samples: 5 x 40 terms, the meridional
 * frame except out_u, out_v, 1/lambda^2, and the passage: the hit points on the stop and
 * the limiting rims as more outputs with pass circles, 129 small terms in all). Without
 * it, the 5 x 40 term fixture of tests/unit/poly_fixture.h laid out the same way.
 * NOFRAME.poly: the same fit with --frame none --lambda-transform identity.
 *
 * Every method is timed once per round, the methods in turn, for ROUNDS rounds
 * (interleaved, so a slow phase of a shared machine touches them all alike); each prints
 * its best round (the figure of a quiet machine), its median, and the spread
 * (median / best - 1). Ratios are taken between best rounds of this run. The timed call
 * follows an untimed one of the same method, so that what ran before it (another
 * method's rows dirty in the cache over its own, the vector units' clock after scalar
 * work) does not land on it: without that, the same call (jacobian_batch and
 * jacobian_batch_optics of a 5-output system) measured 60-63 and 53-57 ns a ray in one
 * run, by its place in the round; with it, 54-55 both.
 *   trace, trace_passing  the exact tracer (trace_batch, 1 thread) on all the rays / on
 *                     the rays it passes
 *   batch, batch_passing  poly_eval_batch on the same rays (pass test included)
 *   batch_optics      poly_eval_batch_outputs writing the five optical outputs alone,
 *                     with the pass flags (the passage outputs computed, not stored)
 *   batch_noframe     poly_eval_batch of NOFRAME.poly (the cost of the frame)
 *   batch_8           poly_eval_batch in calls of 8 rays (what each call costs beyond
 *                     its rays: a renderer's short batches)
 *   batch_cold        poly_eval_batch on COLD x RAYS rays (rows of 80 bytes a ray in and
 *                     out, beyond the caches: what memory traffic adds; the other
 *                     methods see RAYS rays, a renderer's batch, whose rows stay cached)
 *   scalar            poly_eval, one ray at a time
 *   naive             each term's powers from scratch (the textbook baseline)
 *   jacobian, jacobian_batch  poly_eval_jacobian one ray at a time, and
 *                     poly_eval_jacobian_batch (5 derivatives of every output)
 *   jacobian_batch_optics  poly_eval_jacobian_batch_outputs of the five optical outputs
 *   batch_chunks, jacobian_chunks  poly_eval_batch and jacobian_batch_optics on the same
 *                     rays in calls of 512 (lens-render's), each into the same buffer, as
 *                     lens-render's full estimator calls them: its rows stay in the cache,
 *                     where one call on all the rays writes RAYS rows of 25 doubles (4 MB
 *                     at 20000 rays: through memory, past the caches)
 *   emitted_c, emitted_c_native  the C of poly_emit_c compiled now with $CC (or cc),
 *                     -O2 and -O3 -march=native, one call per ray
 *   emitted_c_batch, emitted_c_batch_native  its NAME_batch function on all rays
 * Per passing ray: time over all rays / the rays the lens passes, the cost of one ray
 * that reaches the sensor (the same denominator for both: the system's own pass flags
 * are printed beside, as a check of its passage). */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../tests/unit/poly_fixture.h"
#include "sparselens/lens.h"
#include "sparselens/poly.h"
#include "sparselens/sampling.h"
#include "sparselens/trace.h"

#define ROUNDS 21
#define COLD 16
/* Rays a call in batch_chunks and jacobian_chunks: lens-render's (POLY_CHUNK in
 * render_lens.c), whose full estimator takes the Jacobian of each chunk's four outer
 * pupil outputs into the same buffer, chunk after chunk. */
#define CHUNK 512

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

typedef int (*emitted_fn)(const double *in, double *out);
typedef void (*emitted_batch_fn)(size_t n, const double *in, double *out, unsigned char *pass);

/* Compiles the emitted C into a shared object with flags and loads it; NULL if no
 * compiler. *batch gets its NAME_batch function. */
static emitted_fn load_emitted(const poly_system *s, const char *dir, const char *tag,
                               const char *flags, void **handle, emitted_batch_fn *batch)
{
    char src[300], so[300], cmd[1024];
    snprintf(src, sizeof src, "%s/fn.c", dir);
    snprintf(so, sizeof so, "%s/fn_%s.so", dir, tag);
    FILE *f = fopen(src, "w");
    if (!f || poly_emit_c(f, s, "bench_fn") != 0) {
        if (f)
            fclose(f);
        return NULL;
    }
    fclose(f);
    const char *cc = getenv("CC");
    snprintf(cmd, sizeof cmd, "%s -std=c99 %s -fPIC -shared %s -o %s -lm", cc && *cc ? cc : "cc",
             flags, src, so);
    if (system(cmd) != 0)
        return NULL;
    *handle = dlopen(so, RTLD_NOW);
    if (!*handle)
        return NULL;
    *batch = (emitted_batch_fn)(uintptr_t)dlsym(*handle, "bench_fn_batch");
    return (emitted_fn)(uintptr_t)dlsym(*handle, "bench_fn");
}

typedef struct {
    int nout, *nterms;
    int *exps; /* terms x 5 inputs */
    double *coef;
    double off[5], scale[5];
} flat;

/* The baseline: every term's powers multiplied out from the scaled inputs (no frame:
 * the work of a textbook evaluator of the same terms). */
static void naive(const flat *F, size_t n, const double *in, double *out)
{
    for (size_t r = 0; r < n; r++) {
        double s[5];
        for (int i = 0; i < 5; i++)
            s[i] = (in[r * 5 + i] - F->off[i]) / F->scale[i];
        const int *e = F->exps;
        const double *c = F->coef;
        for (int o = 0; o < F->nout; o++) {
            double acc = 0;
            for (int t = 0; t < F->nterms[o]; t++, e += 5, c++) {
                double m = *c;
                for (int i = 0; i < 5; i++)
                    for (int k = 0; k < e[i]; k++)
                        m *= s[i];
                acc += m;
            }
            out[r * (size_t)F->nout + o] = acc;
        }
    }
}

static void flatten(const poly_system *s, flat *F)
{
    int total = 0;
    F->nout = poly_noutputs(s);
    F->nterms = malloc((size_t)F->nout * sizeof(int));
    for (int o = 0; o < F->nout; o++)
        total += poly_nterms(s, 0, o);
    F->exps = malloc((size_t)total * 5 * sizeof(int));
    F->coef = malloc((size_t)total * sizeof(double));
    int k = 0;
    for (int o = 0; o < F->nout; o++) {
        F->nterms[o] = poly_nterms(s, 0, o);
        for (int t = 0; t < F->nterms[o]; t++, k++)
            poly_get_term(s, 0, o, t, F->exps + 5 * k, F->coef + k);
    }
    for (int i = 0; i < 5; i++)
        poly_get_scaling(s, i, &F->off[i], &F->scale[i]);
}

enum {
    M_TRACE, M_TRACE_PASSING, M_BATCH, M_BATCH_PASSING, M_BATCH_OPTICS, M_BATCH_NOFRAME, M_BATCH_8,
    M_BATCH_COLD,
    M_SCALAR, M_NAIVE, M_JAC, M_JAC_BATCH, M_JAC_BATCH_OPTICS, M_BATCH_CHUNKS, M_JAC_CHUNKS,
    M_EMIT, M_EMIT_NATIVE, M_EMIT_BATCH,
    M_EMIT_BATCH_NATIVE, M_COUNT
};
static const char *const names[M_COUNT] = {
    "trace",    "trace_passing",  "batch",     "batch_passing",    "batch_optics", "batch_noframe",
    "batch_8",  "batch_cold", "scalar",       "naive",     "jacobian",         "jacobian_batch",
    "jacobian_batch_optics", "batch_chunks", "jacobian_chunks",
    "emitted_c", "emitted_c_native", "emitted_c_batch", "emitted_c_batch_native"};

typedef struct {
    const lens_t *lens;
    const poly_system *s, *s0;
    const flat *F;
    emitted_fn fn[2];
    emitted_batch_fn fnb[2];
    size_t nout;
    double *out, *jac, *cold_out;
    unsigned char *pass, *cold_pass;
} bench_ctx;

/* One round of method m on n rays; returns its CPU time. */
static double run(const bench_ctx *c, int m, size_t n, const double *in)
{
    lens_err err;
    double t0 = now();
    switch (m) {
    case M_TRACE:
    case M_TRACE_PASSING:
        trace_batch(c->lens, TRACE_TO_OUTER, n, in, c->out, NULL, 1, &err);
        break;
    case M_BATCH:
    case M_BATCH_PASSING:
        poly_eval_batch(c->s, n, in, c->out, c->pass);
        break;
    case M_BATCH_OPTICS: {
        static const int optics[5] = {0, 1, 2, 3, 4};
        poly_eval_batch_outputs(c->s, n, in, 5, optics, c->out, c->pass);
        break;
    }
    case M_BATCH_NOFRAME:
        poly_eval_batch(c->s0, n, in, c->out, c->pass);
        break;
    case M_BATCH_8:
        for (size_t r = 0; r < n; r += 8)
            poly_eval_batch(c->s, n - r < 8 ? n - r : 8, in + r * 5, c->out + r * c->nout,
                            c->pass + r);
        break;
    case M_BATCH_COLD:
        poly_eval_batch(c->s, n, in, c->cold_out, c->cold_pass);
        break;
    case M_SCALAR:
        for (size_t r = 0; r < n; r++)
            c->pass[r] = (unsigned char)poly_eval(c->s, in + r * 5, c->out + r * c->nout);
        break;
    case M_NAIVE:
        naive(c->F, n, in, c->out);
        break;
    case M_JAC:
        for (size_t r = 0; r < n; r++)
            poly_eval_jacobian(c->s, in + r * 5, c->out + r * c->nout, c->jac + r * 5 * c->nout);
        break;
    case M_JAC_BATCH:
        poly_eval_jacobian_batch(c->s, n, in, c->jac);
        break;
    case M_JAC_BATCH_OPTICS: {
        static const int optics[5] = {0, 1, 2, 3, 4};
        poly_eval_jacobian_batch_outputs(c->s, n, in, 5, optics, c->jac);
        break;
    }
    case M_BATCH_CHUNKS: /* lens-render's calls: CHUNK rays each into one buffer */
        for (size_t r = 0; r < n; r += CHUNK)
            poly_eval_batch(c->s, n - r < CHUNK ? n - r : CHUNK, in + r * 5, c->out, c->pass + r);
        break;
    case M_JAC_CHUNKS: {
        static const int optics[5] = {0, 1, 2, 3, 4};
        for (size_t r = 0; r < n; r += CHUNK)
            poly_eval_jacobian_batch_outputs(c->s, n - r < CHUNK ? n - r : CHUNK, in + r * 5, 5,
                                             optics, c->jac);
        break;
    }
    case M_EMIT:
    case M_EMIT_NATIVE:
        for (size_t r = 0; r < n; r++)
            c->pass[r] = (unsigned char)c->fn[m == M_EMIT_NATIVE](in + r * 5, c->out + r * c->nout);
        break;
    default:
        c->fnb[m == M_EMIT_BATCH_NATIVE](n, in, c->out, c->pass);
    }
    return now() - t0;
}

/* Realistic rays (see the top): n rays into in, the lens's pass flags into passed. */
static int make_rays(const lens_t *lens, size_t n, double *in)
{
    sampling_options so = sampling_defaults();
    so.strategy = SAMPLING_REAR;
    so.sensor_w = isfinite(lens->sensor_w) ? lens->sensor_w : 23.6;
    so.sensor_h = isfinite(lens->sensor_h) ? lens->sensor_h : 15.7;
    so.lambda_min = 0.4;
    so.lambda_max = 0.7;
    so.seed = 1;
    lens_err err;
    ray_generator *g = ray_generator_new(lens, &so, &err);
    if (!g || ray_generator_fill(g, 0, n, in, &err) != 0) {
        fprintf(stderr, "bench_poly: %s\n", err.msg);
        return -1;
    }
    ray_generator_free(g);
    return 0;
}

static poly_system *fixture_default_layout(int frame)
{
    poly_system *s = fixture_system(40, 11, 1, 2016);
    if (s && frame &&
        (poly_set_frame(s, POLY_FRAME_MERIDIONAL) != 0 || poly_set_output_plain(s, 2, 1) != 0 ||
         poly_set_output_plain(s, 3, 1) != 0 ||
         poly_set_transform(s, 4, POLY_XFORM_INVERSE_SQUARE) != 0)) {
        poly_free(s);
        return NULL;
    }
    if (s && frame)
        poly_set_scaling(s, 4, 4.25, 2.0); /* 1/lambda^2 over 0.40..0.70 um */
    return s;
}

static poly_system *read_system(const char *path)
{
    lens_err err;
    poly_system *s = NULL;
    if (poly_read(path, &s, &err) != 0) {
        fprintf(stderr, "bench_poly: %s\n", err.msg);
        return NULL;
    }
    for (int i = 0; i < 5; i++)
        if (poly_ninputs(s) != 5 || poly_input_index(s, fixture_inputs[i]) != i ||
            poly_noutputs(s) < 5 || poly_nparts(s) != 1) {
            fprintf(stderr, "bench_poly: %s: needs inputs x y u v lambda, 1 part\n",
                    path);
            poly_free(s);
            return NULL;
        }
    return s;
}

/* Per ray the lens passes (the time over all rays times n / npass, f): both over the
 * rays the lens passes, so that a system that lets blocked rays through
 * (system_pass_fraction above exact_pass_fraction) does not look cheaper for it. */
static void print_passing(const char *tag, double f, const double *best)
{
    const double te = best[M_TRACE] * f, tp = best[M_BATCH] * f, to = best[M_BATCH_OPTICS] * f;
    printf("bench %s_trace_ns_per_passing_ray %.2f ns\n", tag, te);
    printf("bench %s_batch_ns_per_passing_ray %.2f ns\n", tag, tp);
    printf("bench ratio_%s_trace_over_batch_per_passing_ray %.2f x\n", tag, te / tp);
    printf("bench %s_batch_optics_ns_per_passing_ray %.2f ns\n", tag, to);
    printf("bench ratio_%s_trace_over_batch_optics_per_passing_ray %.2f x\n", tag, te / to);
}

/* The ratios between methods: how many times the second's time the first's is (> 1: the
 * second is faster). */
static void print_ratios(const char *tag, const int *have, const double *best)
{
    const int pairs[][2] = {{M_TRACE_PASSING, M_BATCH_PASSING}, {M_SCALAR, M_BATCH},
                            {M_JAC_BATCH, M_BATCH},             {M_JAC, M_JAC_BATCH},
                            {M_JAC_BATCH_OPTICS, M_BATCH},       {M_JAC_CHUNKS, M_BATCH_CHUNKS},
                            {M_NAIVE, M_BATCH},                 {M_BATCH, M_BATCH_NOFRAME},
                            {M_BATCH_COLD, M_BATCH},            {M_BATCH_8, M_BATCH},             {M_BATCH, M_BATCH_OPTICS},
                            {M_EMIT, M_SCALAR},                 {M_EMIT_NATIVE, M_SCALAR},
                            {M_EMIT_BATCH, M_BATCH},            {M_EMIT_BATCH_NATIVE, M_BATCH}};
    for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++) {
        int a = pairs[k][0], b = pairs[k][1];
        if (have[a] && have[b])
            printf("bench ratio_%s_%s_over_%s %.2f x\n", tag, names[a], names[b], best[a] / best[b]);
    }
}

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? strtoul(argv[1], NULL, 10) : 20000;
    const char *tag = argc > 4 ? argv[4] : "poly";
    if (n < 1000)
        n = 20000;
    poly_system *s = argc > 2 ? read_system(argv[2]) : fixture_default_layout(1);
    poly_system *s0 = argc > 3 ? read_system(argv[3]) : argc > 2 ? NULL : fixture_default_layout(0);
    lens_t lens;
    lens_err err;
    lens_init(&lens);
    if (!s || lens_load("lenses/fisheye-ii.lens", NULL, &lens, &err) != 0) {
        fprintf(stderr, "bench_poly: %s\n", s ? err.msg : "no system");
        return 1;
    }
    double *in = malloc(n * 5 * sizeof(double)), *pin = malloc(n * 5 * sizeof(double));
    bench_ctx c = {.lens = &lens, .s = s, .s0 = s0};
    c.nout = (size_t)poly_noutputs(s);
    if (s0 && (size_t)poly_noutputs(s0) > c.nout)
        c.nout = (size_t)poly_noutputs(s0);
    c.out = malloc(n * c.nout * sizeof(double));
    c.jac = malloc(n * 5 * c.nout * sizeof(double));
    c.pass = malloc(n);
    double *cold = malloc(COLD * n * 5 * sizeof(double));
    c.cold_out = malloc(COLD * n * c.nout * sizeof(double));
    c.cold_pass = malloc(COLD * n);
    if (!in || !pin || !c.out || !c.jac || !c.pass || !cold || !c.cold_out || !c.cold_pass ||
        make_rays(&lens, n, in) != 0)
        return 1;
    for (size_t k = 0; k < COLD; k++)
        memcpy(cold + k * n * 5, in, n * 5 * sizeof(double));
    /* who passes: the tracer's flags (out_eta > 0) and the system's */
    trace_batch(&lens, TRACE_TO_OUTER, n, in, c.out, NULL, 1, &err);
    size_t npass_exact = 0, npass_poly = 0;
    for (size_t r = 0; r < n; r++)
        if (c.out[5 * r + 4] > 0)
            memcpy(pin + 5 * npass_exact++, in + 5 * r, 5 * sizeof(double));
    poly_eval_batch(s, n, in, c.out, c.pass);
    for (size_t r = 0; r < n; r++)
        npass_poly += c.pass[r];

    flat F;
    flatten(s, &F);
    c.F = &F;
    char dir[] = "/tmp/bench_poly_XXXXXX";
    void *handle[2] = {NULL, NULL};
    if (mkdtemp(dir)) {
        c.fn[0] = load_emitted(s, dir, "O2", "-O2", &handle[0], &c.fnb[0]);
        c.fn[1] = load_emitted(s, dir, "native", "-O3 -march=native", &handle[1], &c.fnb[1]);
    }
    /* the slow methods see a tenth of the rays: the rounds stay short alike */
    double t[M_COUNT][ROUNDS];
    size_t nm[M_COUNT];
    for (int m = 0; m < M_COUNT; m++)
        nm[m] = m == M_TRACE_PASSING || m == M_BATCH_PASSING ? npass_exact
                : m == M_BATCH_COLD ? COLD * n
                : m == M_SCALAR || m == M_NAIVE || m == M_JAC || m == M_EMIT || m == M_EMIT_NATIVE ||
                          m == M_BATCH_8
                    ? n / 10
                    : n;
    int have[M_COUNT];
    for (int m = 0; m < M_COUNT; m++)
        have[m] = !(m == M_BATCH_NOFRAME && !s0) && !((m == M_EMIT || m == M_EMIT_BATCH) && !c.fn[0]) &&
                  !((m == M_EMIT_NATIVE || m == M_EMIT_BATCH_NATIVE) && !c.fn[1]) && nm[m] > 0;
    for (int round = 0; round < ROUNDS; round++)
        for (int m = 0; m < M_COUNT; m++)
            if (have[m]) {
                const double *mi = m == M_TRACE_PASSING || m == M_BATCH_PASSING ? pin
                                   : m == M_BATCH_COLD                        ? cold
                                                                              : in;
                run(&c, m, nm[m], mi); /* the warm-up (above) */
                t[m][round] = run(&c, m, nm[m], mi);
            }
    double best[M_COUNT] = {0};
    for (int m = 0; m < M_COUNT; m++) {
        if (!have[m]) {
            fprintf(stderr, "bench_poly: %s not measured (no system or no C compiler)\n", names[m]);
            continue;
        }
        qsort(t[m], ROUNDS, sizeof t[m][0], cmp);
        best[m] = t[m][0] / (double)nm[m] * 1e9;
        double med = t[m][ROUNDS / 2] / (double)nm[m] * 1e9;
        printf("bench %s_%s_ns_per_ray %.2f ns\n", tag, names[m], best[m]);
        printf("bench %s_%s_median_ns_per_ray %.2f ns\n", tag, names[m], med);
        printf("bench %s_%s_spread %.0f %%\n", tag, names[m], 100 * (med / best[m] - 1));
    }
    printf("bench %s_rays %zu rays\n", tag, n);
    printf("bench %s_outputs %d count\n", tag, poly_noutputs(s));
    printf("bench %s_exact_pass_fraction %.3f fraction\n", tag, (double)npass_exact / n);
    printf("bench %s_system_pass_fraction %.3f fraction\n", tag, (double)npass_poly / n);
    if (npass_exact)
        print_passing(tag, (double)n / (double)npass_exact, best);
    print_ratios(tag, have, best);
    printf("bench %s_monomials %d count\n", tag, poly_nmonomials(s, 0));
    for (int k = 0; k < 2; k++)
        if (handle[k])
            dlclose(handle[k]);
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "bench_poly: could not remove %s\n", dir);
    lens_free(&lens);
    free(in);
    free(pin);
    free(cold);
    free(c.cold_out);
    free(c.cold_pass);
    free(c.out);
    free(c.jac);
    free(c.pass);
    free(F.exps);
    free(F.nterms);
    free(F.coef);
    poly_free(s);
    poly_free(s0);
    return 0;
}
