/* The one-ray evaluation of a plan's sums with vectors (poly_eval, poly_eval_part).
 * One ray has no lanes of rays to fill, and a chain of products (each monomial its
 * parent times a variable, as the plan builds them) is as long as the highest degree:
 * one ray waited on it from one end to the other. Here the work is laid out for 8-lane
 * vectors so that no step waits on more than a few others:
 *
 *   powers   per variable that some term has (an "active" one), its powers s^0 .. s^15
 *            in two vectors, from s, s^2, s^4 and s^8 by blends and two multiplies (no
 *            chain through the degrees);
 *   terms    each output's terms in chunks of 8 (the last one padded with zero
 *            coefficients): per active variable, the lanes' powers picked out of its two
 *            vectors by one permute with the chunk's exponents, the factors multiplied
 *            together, and one fused multiply-add of the chunk's coefficients into the
 *            output's accumulator; then the accumulator's 8 lanes added.
 * Every chunk is independent of the others, so the work of one ray is a short, wide
 * tree that the next ray's can overlap.
 *
 * A term that is inf or nan makes its output non-finite as in the plan (padded lanes
 * take the power 0 of every variable, 1, times 0); a ray with an output that is not
 * finite is evaluated again by the plan's interpreter all the same, so that such a ray
 * gives the plan's values exactly.
 *
 * The results are the plan's sums with other roundings (powers by another product
 * order, another order of additions, fused multiply-adds): they agree with the batch
 * kernel's to rounding (1e-12 of the output's size, tested in test_poly), not bit for
 * bit. Only on x86 with AVX-512, for at most FAST_MAXACT active variables and exponents
 * up to 15; elsewhere poly_fast declines and the plan's interpreter runs (poly_eval.c). */
#include "poly/poly_impl.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#if (defined(__x86_64__) || defined(__i386__)) && !defined(SPARSELENS_PORTABLE_KERNELS)
#define FAST_X86 1
#include <immintrin.h>
#endif

/* Active variables at most (two table vectors each stay in registers). */
#define FAST_MAXACT 6
/* The highest exponent the two table vectors hold. */
#define FAST_MAXEXP 15

struct poly_fast {
    int nin, nout, nact;
    int act[FAST_MAXACT]; /* the inputs some term has an exponent of */
    int *ofirst;          /* nout + 1: output o's chunks are ofirst[o] .. ofirst[o + 1] - 1 */
    int64_t *idx;         /* per chunk, nact x 8: the lanes' exponents of each active input */
    double *coef;         /* per chunk, 8: the lanes' coefficients (0 in padded lanes) */
};

void poly_fast_free(poly_fast *f)
{
    if (!f)
        return;
    free(f->ofirst);
    free(f->idx);
    free(f->coef);
    free(f);
}

/* The active inputs of the sums; -1 when there are too many or an exponent is too high. */
static int fast_active(poly_fast *f, const poly_out_terms *sums)
{
    int used[POLY_MAX_INPUTS] = {0};
    for (int o = 0; o < f->nout; o++)
        for (int t = 0; t < sums[o].nterms; t++)
            for (int i = 0; i < f->nin; i++) {
                const int e = sums[o].exps[(size_t)t * f->nin + i];
                if (e < 0 || e > FAST_MAXEXP)
                    return -1;
                used[i] |= e > 0;
            }
    f->nact = 0;
    for (int i = 0; i < f->nin; i++)
        if (used[i]) {
            if (f->nact == FAST_MAXACT)
                return -1;
            f->act[f->nact++] = i;
        }
    return 0;
}

poly_fast *poly_fast_build(int nin, int nout, const poly_out_terms *sums)
{
    if (nin < 1 || nin > POLY_MAX_INPUTS)
        return NULL;
    for (int o = 0; o < nout; o++)
        if (sums[o].nterms && !sums[o].exps)
            return NULL; /* derivative sums: the interpreter's */
    poly_fast *f = calloc(1, sizeof *f);
    if (!f)
        return NULL;
    f->nin = nin;
    f->nout = nout;
    f->ofirst = malloc(((size_t)nout + 1) * sizeof(int));
    int nch = 0;
    for (int o = 0; o < nout; o++)
        nch += (sums[o].nterms + 7) / 8;
    if (!f->ofirst || fast_active(f, sums) != 0 || f->nact == 0) {
        poly_fast_free(f);
        return NULL;
    }
    const int na = f->nact;
    f->idx = aligned_alloc(64, ((size_t)nch * na + 1) * 8 * sizeof(int64_t));
    f->coef = aligned_alloc(64, ((size_t)nch + 1) * 8 * sizeof(double));
    if (!f->idx || !f->coef) {
        poly_fast_free(f);
        return NULL;
    }
    int c = 0;
    for (int o = 0; o < nout; o++) {
        f->ofirst[o] = c;
        for (int t0 = 0; t0 < sums[o].nterms; t0 += 8, c++)
            for (int l = 0; l < 8; l++) {
                const int t = t0 + l, real = t < sums[o].nterms;
                const int *e = real ? sums[o].exps + (size_t)t * nin : NULL;
                f->coef[8 * c + l] = real ? sums[o].coef[t] : 0;
                for (int k = 0; k < na; k++)
                    f->idx[((size_t)c * na + k) * 8 + l] = real ? e[f->act[k]] : 0;
            }
    }
    f->ofirst[nout] = c;
    return f;
}

#if defined(FAST_X86)
#define FAST_TARGET __attribute__((target("avx512f,fma")))

/* s^0 .. s^7 in lo and s^8 .. s^15 in hi: lanes k of (1|s) * (1|s^2) * (1|s^4) by
 * blends of the broadcast powers on the bits of k. */
FAST_TARGET static inline void fast_powers(double s, __m512d *lo, __m512d *hi)
{
    const __m512d one = _mm512_set1_pd(1), b = _mm512_set1_pd(s);
    const __m512d b2 = _mm512_mul_pd(b, b), b4 = _mm512_mul_pd(b2, b2);
    const __m512d q = _mm512_mask_blend_pd(0xaa, one, b), w = _mm512_mask_blend_pd(0xcc, one, b2);
    *lo = _mm512_mul_pd(_mm512_mul_pd(q, w), _mm512_mask_blend_pd(0xf0, one, b4));
    *hi = _mm512_mul_pd(*lo, _mm512_mul_pd(b4, b4));
}

/* The sums with NA active variables (a constant after inlining: the tables stay in
 * registers). */
__attribute__((target("avx512f,fma"), always_inline)) static inline void
fast_sums(const int NA, const poly_fast *f, const double *sc, double *out)
{
    __m512d lo[FAST_MAXACT], hi[FAST_MAXACT];
#pragma GCC unroll 6
    for (int k = 0; k < NA; k++)
        fast_powers(sc[k], &lo[k], &hi[k]);
    const int64_t *ix = f->idx;
    const double *cf = f->coef;
    for (int o = 0; o < f->nout; o++) {
        __m512d acc = _mm512_setzero_pd();
        for (int c = f->ofirst[o]; c < f->ofirst[o + 1]; c++, ix += 8 * NA, cf += 8) {
            __m512d p[FAST_MAXACT];
#pragma GCC unroll 6
            for (int k = 0; k < NA; k++)
                p[k] = _mm512_permutex2var_pd(lo[k], _mm512_load_si512(ix + 8 * k), hi[k]);
            /* a tree of products: two levels for four variables */
#pragma GCC unroll 6
            for (int w = 1; w < NA; w *= 2)
#pragma GCC unroll 6
                for (int k = 0; k + w < NA; k += 2 * w)
                    p[k] = _mm512_mul_pd(p[k], p[k + w]);
            acc = _mm512_fmadd_pd(_mm512_load_pd(cf), p[0], acc);
        }
        out[o] = _mm512_reduce_add_pd(acc);
    }
}

FAST_TARGET static void fast_run(const poly_fast *f, const poly_system *s, const double *in,
                                 double *out)
{
    double sc[FAST_MAXACT];
    for (int k = 0; k < f->nact; k++) {
        sc[k] = in[f->act[k]];
        poly_scale_column(s, f->act[k], &sc[k], 1);
    }
    switch (f->nact) {
    case 1: fast_sums(1, f, sc, out); break;
    case 2: fast_sums(2, f, sc, out); break;
    case 3: fast_sums(3, f, sc, out); break;
    case 4: fast_sums(4, f, sc, out); break;
    case 5: fast_sums(5, f, sc, out); break;
    default: fast_sums(6, f, sc, out); break;
    }
}
#endif

int poly_fast_run(const poly_fast *f, const poly_system *s, const double *in, double *out)
{
#if defined(FAST_X86)
    if (f && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("fma")) {
        fast_run(f, s, in, out);
        /* a monomial that is inf or nan makes its whole output non-finite here, where
           the plan may keep it finite */
        int finite = 1;
        for (int o = 0; o < f->nout; o++)
            finite &= (out[o] - out[o]) == 0;
        if (finite)
            return 0;
    }
#else
    (void)f, (void)s, (void)in, (void)out;
#endif
    return -1;
}
