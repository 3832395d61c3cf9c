/* A program that uses libsparselens through its installed headers and pkg-config alone
 * (tests/cli/library.sh builds it against the installed tree, shared and static):
 *
 *   example LENS SAMPLES OTHER_LENS N
 *
 * loads LENS and prints its first-order data; traces one ray and a batch; fits a small
 * system to traced rays in memory and another to the sample file SAMPLES (lens-trace's),
 * and evaluates both against the exact trace; makes the lens camera and renders a
 * uniform emitter of radiance 1 (the mean weight of N camera rays over the sensor, and
 * its standard error); and shows that a camera refuses the system fitted to LENS with
 * OTHER_LENS. Prints "key value" lines. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <sparselens.h>

static double uniform(unsigned long long *s) /* splitmix64 */
{
    unsigned long long z = (*s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return (double)((z ^ (z >> 31)) >> 11) / 9007199254740992.0;
}

static int die(const lens_err *err)
{
    fprintf(stderr, "example: %s\n", err->msg);
    return 1;
}

/* RMS difference of out_x from the exact trace over the passing rows (x y u v lambda in
 * in, out_x .. out_eta in out). */
static double rms_out_x(const poly_system *sys, size_t n, const double *in, const double *out)
{
    double se = 0, o[8];
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(out[5 * i])) continue;
        poly_eval(sys, in + 5 * i, o);
        se += (o[0] - out[5 * i]) * (o[0] - out[5 * i]);
        m++;
    }
    return sqrt(se / (double)m);
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: example LENS SAMPLES OTHER_LENS N\n");
        return 2;
    }
    lens_t lens, other;
    lens_err err;
    paraxial_data p;
    if (lens_load(argv[1], NULL, &lens, &err) || lens_load(argv[3], NULL, &other, &err) ||
        paraxial_compute(&lens, GLASS_D_LINE, &p, &err))
        return die(&err);
    printf("efl %.6f\nfnumber %.6f\n", p.efl, p.fnumber);

    /* one ray: from the sensor's centre along the axis, out through the front vertex */
    double *n = malloc(lens.nsurf * sizeof *n), ray_in[4] = {0, 0, 0, 0}, ray_out[4];
    if (lens_indices(&lens, GLASS_D_LINE, n, &err)) return die(&err);
    trace_result r = trace_sample(&lens, n, TRACE_TO_OUTER, ray_in, ray_out);
    printf("axis_ray %s %.3g %.3g\n", trace_status_name(r.status), ray_out[0], ray_out[1]);

    /* a batch: rays from over the sensor towards the rear element */
    const size_t count = 6000;
    double *in = malloc(count * 5 * sizeof *in), *out = malloc(count * 5 * sizeof *out);
    unsigned long long st = 1;
    for (size_t i = 0; i < count; i++) {
        double *q = in + 5 * i;
        q[0] = (uniform(&st) - 0.5) * 30, q[1] = (uniform(&st) - 0.5) * 20;
        q[2] = (uniform(&st) - 0.5) * 0.6, q[3] = (uniform(&st) - 0.5) * 0.6;
        q[4] = GLASS_D_LINE;
    }
    if (trace_batch(&lens, TRACE_TO_OUTER, count, in, out, NULL, 0, &err)) return die(&err);
    size_t passed = 0;
    for (size_t i = 0; i < count; i++) passed += isfinite(out[5 * i]);
    printf("batch_passed %zu of %zu\n", passed, count);

    /* a small fit in memory: out_x .. out_v of the first half, checked on the second */
    const char *inputs[] = {"x", "y", "u", "v", "lambda"};
    const char *outputs[] = {"out_x", "out_y", "out_u", "out_v", "out_eta"};
    fit_options fo;
    fit_options_default(&fo);
    fo.max_terms = 20;
    fo.max_degree = 5;
    double *in4 = malloc(count * 4 * sizeof *in4); /* x y u v: one wavelength */
    for (size_t i = 0; i < count; i++)
        for (int k = 0; k < 4; k++) in4[4 * i + k] = in[5 * i + k];
    poly_system *sys = fit_system(lens.name, 4, inputs, 5, outputs, count / 2, in4, out, &fo, &err);
    if (!sys) return die(&err);
    double se = 0, o[8];
    size_t m = 0;
    for (size_t i = count / 2; i < count; i++)
        if (isfinite(out[5 * i])) {
            poly_eval(sys, in4 + 4 * i, o);
            se += (o[0] - out[5 * i]) * (o[0] - out[5 * i]), m++;
        }
    printf("fit_memory_rms_out_x %.4g\n", sqrt(se / (double)m));

    /* a fit to the sample file, written and read back as a .poly, evaluated in a batch */
    poly_system *fsys = fit_system_file(argv[2], 5, inputs, 4, outputs, &fo, &err), *back;
    FILE *f = fsys ? fopen("example.poly", "w") : NULL;
    if (!fsys) return die(&err);
    if (!f || poly_write(f, fsys) || fclose(f)) return 1;
    if (poly_read("example.poly", &back, &err)) return die(&err);
    printf("fit_file_lens %s\nfit_file_rms_out_x %.4g\n", poly_lens_name(back),
           rms_out_x(back, count, in, out));
    double *pout = malloc(count * 4 * sizeof *pout);
    poly_eval_batch(back, count, in, pout, NULL);
    double worst = 0;
    for (size_t i = 0; i < count; i++) {
        double o[4];
        poly_eval(back, in + 5 * i, o);
        worst = fmax(worst, fabs(o[0] - pout[4 * i]));
    }
    printf("batch_vs_one %.3g\n", worst);

    /* the camera: a uniform emitter of radiance 1 in front of the lens, so that a pixel's
     * value is the mean weight of its rays; here one pixel, the whole sensor */
    lens_camera *cam = lens_camera_new(&lens, NULL, 36, 24, GLASS_D_LINE, GLASS_D_LINE, &err);
    if (!cam) return die(&err);
    long N = atol(argv[4]);
    double sum = 0, sum2 = 0, org[3], dir[3];
    for (long k = 0; k < N; k++) {
        double w = lens_camera_ray(cam, uniform(&st), uniform(&st), GLASS_D_LINE, uniform(&st),
                                   uniform(&st), org, dir);
        if (!(w > 0 && dir[2] > 0)) w = 0; /* the emitter is in front */
        sum += w, sum2 += w * w;
    }
    double mean = sum / N;
    printf("exposure %.6g\nexposure_se %.6g\n", mean, sqrt((sum2 / N - mean * mean) / N));

    /* a system and a lens that do not belong together */
    lens_camera *wrong = lens_camera_new(&other, sys, 36, 24, GLASS_D_LINE, GLASS_D_LINE, &err);
    printf("mismatch %s\n", wrong ? "accepted" : err.msg);

    lens_camera_free(wrong);
    lens_camera_free(cam);
    poly_free(sys);
    poly_free(fsys);
    poly_free(back);
    free(n), free(in), free(in4), free(out), free(pout);
    lens_free(&lens);
    lens_free(&other);
    return 0;
}
