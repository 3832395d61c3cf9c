// The C++ side of tests/cli/library.sh: libsparselens from C++ through the installed
// headers (their extern "C" guards) and pkg-config alone.
//
//   example_cpp LENS SYSTEM.poly N
//
// loads LENS, traces a batch, evaluates SYSTEM (fitted to LENS) against the trace, makes
// the lens camera through SYSTEM and through the exact lens, and renders a uniform
// emitter of radiance 1 with the exact one (the mean weight of N camera rays over the
// sensor, in batches). Prints "key value" lines.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include <sparselens.h>

static int fail(const lens_err &err)
{
    std::fprintf(stderr, "example_cpp: %s\n", err.msg);
    return 1;
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        std::fprintf(stderr, "usage: example_cpp LENS SYSTEM.poly N\n");
        return 2;
    }
    lens_t lens;
    lens_err err;
    poly_system *sys = nullptr;
    if (lens_load(argv[1], nullptr, &lens, &err) || poly_read(argv[2], &sys, &err))
        return fail(err);
    paraxial_data p;
    if (paraxial_compute(&lens, GLASS_D_LINE, &p, &err)) return fail(err);
    std::printf("efl %.6f\n", p.efl);

    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u01(0, 1);
    const std::size_t count = 2000;
    std::vector<double> in(5 * count), out(5 * count), pout(poly_noutputs(sys) * count);
    for (std::size_t i = 0; i < count; i++) {
        in[5 * i] = (u01(rng) - 0.5) * 30, in[5 * i + 1] = (u01(rng) - 0.5) * 20;
        in[5 * i + 2] = (u01(rng) - 0.5) * 0.6, in[5 * i + 3] = (u01(rng) - 0.5) * 0.6;
        in[5 * i + 4] = GLASS_D_LINE;
    }
    if (trace_batch(&lens, TRACE_TO_OUTER, count, in.data(), out.data(), nullptr, 0, &err))
        return fail(err);
    poly_eval_batch(sys, count, in.data(), pout.data(), nullptr);
    double se = 0;
    std::size_t m = 0;
    for (std::size_t i = 0; i < count; i++)
        if (std::isfinite(out[5 * i])) {
            double d = pout[poly_noutputs(sys) * i] - out[5 * i];
            se += d * d, m++;
        }
    std::printf("system_rms_out_x %.4g\n", std::sqrt(se / m));

    lens_camera *through_sys = lens_camera_new(&lens, sys, 36, 24, GLASS_D_LINE, GLASS_D_LINE, &err);
    if (!through_sys) return fail(err);
    lens_camera *cam = lens_camera_new(&lens, nullptr, 36, 24, GLASS_D_LINE, GLASS_D_LINE, &err);
    if (!cam) return fail(err);

    const long N = std::atol(argv[3]), batch = 4096;
    std::vector<double> samples(LENS_CAMERA_SAMPLE * batch), rays(LENS_CAMERA_RAY * batch);
    double sum = 0, sum2 = 0;
    for (long k0 = 0; k0 < N; k0 += batch) {
        long nb = N - k0 < batch ? N - k0 : batch;
        for (long k = 0; k < nb; k++) {
            double *s = &samples[LENS_CAMERA_SAMPLE * k];
            s[0] = u01(rng), s[1] = u01(rng), s[2] = GLASS_D_LINE, s[3] = u01(rng), s[4] = u01(rng);
        }
        lens_camera_rays(cam, nb, samples.data(), rays.data());
        for (long k = 0; k < nb; k++) {
            const double *r = &rays[LENS_CAMERA_RAY * k];
            double w = r[6] > 0 && r[5] > 0 ? r[6] : 0; // the emitter is in front
            sum += w, sum2 += w * w;
        }
    }
    double mean = sum / N;
    std::printf("exposure %.6g\nexposure_se %.6g\n", mean, std::sqrt((sum2 / N - mean * mean) / N));

    lens_camera_free(through_sys);
    lens_camera_free(cam);
    poly_free(sys);
    lens_free(&lens);
    return 0;
}
