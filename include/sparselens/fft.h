#ifndef SPARSELENS_FFT_H
#define SPARSELENS_FFT_H
/* A small radix-2 complex FFT (no library: the MTF needs a few 2-D transforms of a few
 * hundred points a side). Data are interleaved re, im pairs. */
#include <stddef.h>

/* In-place transform of n (a power of two) complex values at stride `stride` pairs;
 * sign -1 forward (exp(-2 pi i k j / n)), +1 inverse (unnormalised). */
void fft_1d(double *z, size_t n, size_t stride, int sign);

/* In-place 2-D transform of an n x n row-major array (n a power of two). */
void fft_2d(double *z, size_t n, int sign);

/* The smallest power of two >= n. */
size_t fft_size(size_t n);

#endif
