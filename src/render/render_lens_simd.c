/* front_ray in AVX-512 lanes (render_lens_simd.h). Why: a camera ray of the polynomial
 * path pays two square roots and two quotients at the front surface, each waiting on the
 * last; eight rays a step hide that latency. */
#include "render/render_lens_simd.h"

#if RENDER_LENS_SIMD
#include <immintrin.h>
#include <math.h>

int render_lens_simd_ok(void)
{
    static int ok = -1;
    if (ok < 0) ok = __builtin_cpu_supports("avx512f") != 0;
    return ok;
}

__attribute__((target("avx512f"))) void render_simd_front(double c, double kc, double z0, int m,
                                                           int stride, const double *X, double *O,
                                                           double *D, unsigned char *status)
{
    const __m512d one = _mm512_set1_pd(1), zero = _mm512_setzero_pd(), cc = _mm512_set1_pd(c);
    const __m512d kcv = _mm512_set1_pd(kc), inf = _mm512_set1_pd(INFINITY);
    for (int i = 0; i < m; i += 8) {
        __m512d x = _mm512_loadu_pd(X + i), y = _mm512_loadu_pd(X + stride + i);
        __m512d u = _mm512_loadu_pd(X + 2 * stride + i), v = _mm512_loadu_pd(X + 3 * stride + i);
        __m512d h2 = _mm512_add_pd(_mm512_mul_pd(x, x), _mm512_mul_pd(y, y));
        __m512d disc = _mm512_sub_pd(one, _mm512_mul_pd(kcv, h2));
        __m512d w2 = _mm512_sub_pd(_mm512_sub_pd(one, _mm512_mul_pd(u, u)), _mm512_mul_pd(v, v));
        __mmask8 here = _mm512_cmp_pd_mask(disc, zero, _CMP_GT_OQ) &
                        _mm512_cmp_pd_mask(_mm512_abs_pd(x), inf, _CMP_LT_OQ) &
                        _mm512_cmp_pd_mask(_mm512_abs_pd(y), inf, _CMP_LT_OQ);
        __mmask8 fine = here & _mm512_cmp_pd_mask(w2, zero, _CMP_GE_OQ);
        __m512d sq = _mm512_sqrt_pd(disc), w = _mm512_sqrt_pd(w2);
        __m512d n[3] = {_mm512_mul_pd(cc, x), _mm512_mul_pd(cc, y), _mm512_sub_pd(zero, sq)};
        __m512d z = _mm512_mul_pd(_mm512_mul_pd(cc, h2), _mm512_div_pd(one, _mm512_add_pd(one, sq)));
        /* lens_outer_frame: n.z = -sq < 0 here */
        __m512d k = _mm512_div_pd(one, _mm512_sub_pd(one, n[2])), nk = _mm512_sub_pd(zero, k);
        __m512d ex[3] = {_mm512_sub_pd(one, _mm512_mul_pd(_mm512_mul_pd(k, n[0]), n[0])),
                         _mm512_mul_pd(_mm512_mul_pd(nk, n[0]), n[1]), n[0]};
        __m512d ey[3] = {ex[1], _mm512_sub_pd(one, _mm512_mul_pd(_mm512_mul_pd(k, n[1]), n[1])), n[1]};
        _mm512_storeu_pd(O + i, x);
        _mm512_storeu_pd(O + stride + i, y);
        _mm512_storeu_pd(O + 2 * stride + i, _mm512_add_pd(_mm512_set1_pd(z0), z));
        for (int j = 0; j < 3; j++)
            _mm512_storeu_pd(D + j * stride + i,
                             _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(u, ex[j]), _mm512_mul_pd(v, ey[j])),
                                           _mm512_mul_pd(w, n[j])));
        for (int l = 0; l < 8; l++) status[i + l] = !(here >> l & 1) ? 2 : !(fine >> l & 1);
    }
}
#endif
