/* SIMD packet tracing from the sensor towards the object (see trace_packet.h).
 *
 * The kernel (trace_packet_kernel.h) is written once over GCC generic vectors and
 * instantiated at the native widths: 2 lanes (SSE2, any x86-64), 4 (AVX2) and 8
 * (AVX-512F), chosen at run time. Vectors wider than the hardware were measured to be
 * slower (the compiler spills them), so each instance uses exactly one register per
 * value. Square roots use the intrinsics: sqrt() must set errno and cannot be
 * vectorised. */
#include "sparselens/trace_packet.h"

#include <math.h>
#include <string.h>

#include "sparselens/intersect.h"

/* x86 has the three widths below; elsewhere (arm64, ...) the 2-lane kernel alone, which
 * GCC maps onto that machine's vectors (NEON on arm64). SPARSELENS_PORTABLE_KERNELS
 * builds that path on x86 too, so the tests can check it where they run. */
#if (defined(__x86_64__) || defined(__i386__)) && !defined(SPARSELENS_PORTABLE_KERNELS)
#define PACKET_X86 1
#include <immintrin.h>
#elif defined(__aarch64__) && !defined(SPARSELENS_PORTABLE_KERNELS)
#include <arm_neon.h>
#endif

/* The vector helpers are always inlined, so no vector crosses a call boundary. */
#pragma GCC diagnostic ignored "-Wpsabi"
#define VINLINE static inline __attribute__((always_inline))


#define K(name) name##_w2
#define KW 2
#define KATTR
#if defined(PACKET_X86)
#define KSQRT(x) _mm_sqrt_pd((__m128d)(x))
#elif defined(__aarch64__) && !defined(SPARSELENS_PORTABLE_KERNELS)
#define KSQRT(x) vsqrtq_f64((float64x2_t)(x))
#else
/* IEEE square roots are correctly rounded, so lane by lane gives the vector's bits. */
#define KSQRT(x) ((vd){__builtin_sqrt((x)[0]), __builtin_sqrt((x)[1])})
#endif
#define KNAME trace_w2
#include "trace/trace_packet_kernel.h"
#undef K
#undef KW
#undef KATTR
#undef KSQRT
#undef KNAME

#if defined(PACKET_X86)

#define K(name) name##_w4
#define KW 4
#define KATTR __attribute__((target("avx2")))
#define KSQRT(x) _mm256_sqrt_pd((__m256d)(x))
#define KNAME trace_w4
#include "trace/trace_packet_kernel.h"
#undef K
#undef KW
#undef KATTR
#undef KSQRT
#undef KNAME

#define K(name) name##_w8
#define KW 8
#define KATTR __attribute__((target("avx512f")))
#define KSQRT(x) _mm512_sqrt_pd((__m512d)(x))
#define KNAME trace_w8
#include "trace/trace_packet_kernel.h"
#endif

/* The widest kernel this CPU runs. Lanes are independent and every kernel does the same
 * IEEE operations in the same order (no contraction into FMA: ISO C mode), so the
 * choice never changes a result. */
int trace_packet_width(void)
{
#if defined(PACKET_X86)
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") ? 8 : __builtin_cpu_supports("avx2") ? 4 : 2;
#else
    return 2;
#endif
}

void trace_packet_to_object(const lens_t *lens, const double *const *n, int count,
                            lens_ray *r, int last, trace_result *res, double *outer)
{
    /* A lone ray takes the narrowest kernel: padding lanes cost as much as real ones. */
    int w = trace_packet_width();
    while (w > 2 && count <= w / 2)
        w /= 2;
    trace_packet_to_object_w(lens, n, count, r, last, res, outer, w);
}

void trace_packet_to_object_w(const lens_t *lens, const double *const *n, int count,
                              lens_ray *r, int last, trace_result *res, double *outer, int w)
{
    if (w != 2 && w != 4 && w != 8)
        w = 2;
#if !defined(PACKET_X86)
    w = 2; /* the only kernel built here */
#endif
    for (int i = 0; i < count; i += w) {
        int m = count - i < w ? count - i : w;
#if defined(PACKET_X86)
        if (w == 8)
            trace_w8(lens, n + i, m, r + i, last, res + i, outer ? outer + 4 * i : NULL);
        else if (w == 4)
            trace_w4(lens, n + i, m, r + i, last, res + i, outer ? outer + 4 * i : NULL);
        else
#endif
            trace_w2(lens, n + i, m, r + i, last, res + i, outer ? outer + 4 * i : NULL);
    }
}
