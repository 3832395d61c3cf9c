/* Radix-2 decimation-in-time FFT (fft.h). */
#include "sparselens/fft.h"

#include <math.h>

size_t fft_size(size_t n)
{
    size_t m = 1;
    while (m < n)
        m <<= 1;
    return m;
}

void fft_1d(double *z, size_t n, size_t stride, int sign)
{
#define RE(k) z[2 * (k) * stride]
#define IM(k) z[2 * (k) * stride + 1]
    /* bit-reversal permutation */
    for (size_t i = 1, j = 0; i < n; i++) {
        size_t bit = n >> 1;
        for (; j & bit; bit >>= 1)
            j ^= bit;
        j |= bit;
        if (i < j) {
            double tr = RE(i), ti = IM(i);
            RE(i) = RE(j), IM(i) = IM(j);
            RE(j) = tr, IM(j) = ti;
        }
    }
    for (size_t len = 2; len <= n; len <<= 1) {
        double ang = sign * 2 * M_PI / (double)len;
        for (size_t k = 0; k < len / 2; k++) {
            /* twiddles from sin/cos directly: no drift from repeated products */
            double wr = cos(ang * (double)k), wi = sin(ang * (double)k);
            for (size_t i = k; i < n; i += len) {
                size_t j = i + len / 2;
                double xr = RE(j) * wr - IM(j) * wi, xi = RE(j) * wi + IM(j) * wr;
                RE(j) = RE(i) - xr, IM(j) = IM(i) - xi;
                RE(i) += xr, IM(i) += xi;
            }
        }
    }
#undef RE
#undef IM
}

void fft_2d(double *z, size_t n, int sign)
{
    for (size_t r = 0; r < n; r++)
        fft_1d(z + 2 * r * n, n, 1, sign);
    for (size_t c = 0; c < n; c++)
        fft_1d(z + 2 * c, n, n, sign);
}
