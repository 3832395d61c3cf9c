/* The AVX-512 batch kernel's moves of rows into and out of its columns (poly_eval.c
 * includes this once, on x86, before the kernel's instances). */
#ifndef SPARSELENS_POLY_EVAL_ROWS_H
#define SPARSELENS_POLY_EVAL_ROWS_H
#include <immintrin.h>
#include <stdint.h>
#include <string.h>

/* 8 rows of 5 outputs (x y u v eta) out of their 5 columns of 8 lanes, as 5 contiguous
 * 64-byte stores: a scatter per column cost the AVX-512 kernel 3 ns a ray on fisheye-ii
 * (22.5 -> 20.2 ns with these permutes). Output vector j holds flat positions p = 8 j + e, row p / 5,
 * column p % 5: columns 0 and 1 come by one two-source permute, 2 and 3 by another,
 * 4 by a one-source permute, then two blends. */
static const long long rows5_idx[3][5][8] = {
    {{0, 8, 0, 0, 0, 1, 9, 1}, {1, 1, 2, 10, 2, 2, 2, 3}, {11, 3, 3, 3, 4, 12, 4, 4},
     {4, 5, 13, 5, 5, 5, 6, 14}, {6, 6, 6, 7, 15, 7, 7, 7}},
    {{0, 0, 0, 8, 0, 1, 1, 1}, {9, 1, 2, 2, 2, 10, 2, 3}, {3, 3, 11, 3, 4, 4, 4, 12},
     {4, 5, 5, 5, 13, 5, 6, 6}, {6, 14, 6, 7, 7, 7, 15, 7}},
    {{0, 0, 0, 0, 0, 1, 1, 1}, {1, 1, 2, 2, 2, 2, 2, 3}, {3, 3, 3, 3, 4, 4, 4, 4},
     {4, 5, 5, 5, 5, 5, 6, 6}, {6, 6, 6, 7, 7, 7, 7, 7}}};
static const unsigned char rows5_m01[5] = {0x63, 0x8c, 0x31, 0xc6, 0x18};
static const unsigned char rows5_m23[5] = {0x8c, 0x31, 0xc6, 0x18, 0x63};

__attribute__((target("avx512f"))) static inline void store_rows5(double *dst, const __m512d *c)
{
    for (int j = 0; j < 5; j++) {
        __m512d t01 = _mm512_permutex2var_pd(c[0], _mm512_loadu_si512(rows5_idx[0][j]), c[1]);
        __m512d t23 = _mm512_permutex2var_pd(c[2], _mm512_loadu_si512(rows5_idx[1][j]), c[3]);
        __m512d t4 = _mm512_permutexvar_pd(_mm512_loadu_si512(rows5_idx[2][j]), c[4]);
        __m512d o = _mm512_mask_blend_pd(rows5_m23[j], t4, t23);
        _mm512_storeu_pd(dst + 8 * j, _mm512_mask_blend_pd(rows5_m01[j], o, t01));
    }
}

/* Any number of outputs: columns k0 .. k0 + ncol - 1 (ncol <= 8) of 8 lanes, transposed
 * in registers (an 8 x 8 transpose, 24 shuffles), each lane's values stored with one
 * masked store at its row: out + row[r] * nres + k0. A scatter per column cost the
 * fisheye-ii system with its 19 outputs (the passage's hit points) 24 ns a ray. */
__attribute__((target("avx512f"))) static inline void store_rows8(double *out, const size_t *row,
                                                                  size_t nres, size_t k0,
                                                                  const __m512d *col, int ncol)
{
    __m512d c[8], a[8], b[8];
    for (int j = 0; j < 8; j++)
        c[j] = j < ncol ? col[j] : _mm512_setzero_pd();
    for (int j = 0; j < 4; j++) {
        a[2 * j] = _mm512_unpacklo_pd(c[2 * j], c[2 * j + 1]);
        a[2 * j + 1] = _mm512_unpackhi_pd(c[2 * j], c[2 * j + 1]);
    }
    /* a[0]: lanes 0 2 4 6 of columns 0, 1 in 128-bit pieces; a[1]: lanes 1 3 5 7 */
    for (int h = 0; h < 2; h++) {
        b[4 * h] = _mm512_shuffle_f64x2(a[h], a[2 + h], 0x88);
        b[4 * h + 1] = _mm512_shuffle_f64x2(a[h], a[2 + h], 0xdd);
        b[4 * h + 2] = _mm512_shuffle_f64x2(a[4 + h], a[6 + h], 0x88);
        b[4 * h + 3] = _mm512_shuffle_f64x2(a[4 + h], a[6 + h], 0xdd);
    }
    const __mmask8 mk = (__mmask8)((1u << ncol) - 1);
    for (int h = 0; h < 2; h++) { /* h = 0: even lanes, 1: odd lanes */
        const __m512d r0 = _mm512_shuffle_f64x2(b[4 * h], b[4 * h + 2], 0x88);
        const __m512d r4 = _mm512_shuffle_f64x2(b[4 * h], b[4 * h + 2], 0xdd);
        const __m512d r2 = _mm512_shuffle_f64x2(b[4 * h + 1], b[4 * h + 3], 0x88);
        const __m512d r6 = _mm512_shuffle_f64x2(b[4 * h + 1], b[4 * h + 3], 0xdd);
        _mm512_mask_storeu_pd(out + row[h] * nres + k0, mk, r0);
        _mm512_mask_storeu_pd(out + row[2 + h] * nres + k0, mk, r2);
        _mm512_mask_storeu_pd(out + row[4 + h] * nres + k0, mk, r4);
        _mm512_mask_storeu_pd(out + row[6 + h] * nres + k0, mk, r6);
    }
}

/* n doubles from src (64-byte aligned) to dst, the whole cache lines of dst with
 * non-temporal stores (to memory, past the caches, without reading the lines first), its
 * partial first and last lines with ordinary ones. */
__attribute__((target("avx512f"))) static inline void stream_rows(double *dst, const double *src,
                                                                   size_t n)
{
    size_t j = ((64 - ((uintptr_t)dst & 63)) & 63) / sizeof(double);
    if ((uintptr_t)dst % sizeof(double) || j > n)
        j = n; /* no whole line */
    memcpy(dst, src, j * sizeof(double));
    for (; j + 8 <= n; j += 8)
        _mm512_stream_pd(dst + j, _mm512_loadu_pd(src + j));
    memcpy(dst + j, src + j, (n - j) * sizeof(double));
}

/* The reverse for the inputs (x y u v lambda): 8 rows of 5 in 5 loads, to 5 columns.
 * Column i lane r is flat position p = 5 r + i, in load p / 8 at p % 8. */
static const long long cols5_idx[3][5][8] = {
    {{0, 5, 10, 15, 4, 1, 6, 3}, {1, 6, 11, 0, 5, 2, 7, 4}, {2, 7, 12, 1, 6, 3, 0, 5},
     {3, 8, 13, 2, 7, 4, 1, 6}, {4, 9, 14, 3, 0, 5, 2, 7}},
    {{0, 5, 2, 7, 4, 9, 14, 3}, {1, 6, 3, 0, 5, 10, 15, 4}, {2, 7, 4, 1, 6, 11, 0, 5},
     {3, 0, 5, 2, 7, 12, 1, 6}, {4, 1, 6, 3, 8, 13, 2, 7}},
    {{0, 5, 2, 7, 4, 1, 6, 3}, {1, 6, 3, 0, 5, 2, 7, 4}, {2, 7, 4, 1, 6, 3, 0, 5},
     {3, 0, 5, 2, 7, 4, 1, 6}, {4, 1, 6, 3, 0, 5, 2, 7}}};
static const unsigned char cols5_m01[5] = {0x0f, 0x07, 0x07, 0x07, 0x07};
static const unsigned char cols5_m23[5] = {0x70, 0x78, 0x38, 0x38, 0x38};

__attribute__((target("avx512f"))) static inline void load_cols5(const double *src, __m512d *c)
{
    const __m512d l0 = _mm512_loadu_pd(src), l1 = _mm512_loadu_pd(src + 8);
    const __m512d l2 = _mm512_loadu_pd(src + 16), l3 = _mm512_loadu_pd(src + 24);
    const __m512d l4 = _mm512_loadu_pd(src + 32);
    for (int i = 0; i < 5; i++) {
        __m512d t01 = _mm512_permutex2var_pd(l0, _mm512_loadu_si512(cols5_idx[0][i]), l1);
        __m512d t23 = _mm512_permutex2var_pd(l2, _mm512_loadu_si512(cols5_idx[1][i]), l3);
        __m512d t4 = _mm512_permutexvar_pd(_mm512_loadu_si512(cols5_idx[2][i]), l4);
        __m512d o = _mm512_mask_blend_pd(cols5_m23[i], t4, t23);
        c[i] = _mm512_mask_blend_pd(cols5_m01[i], o, t01);
    }
}

#endif
