/* Power tables and moment sums of monomials over a sample set.
 *
 * The Gram matrix of the monomial candidates is a table of moments,
 * <s^a, s^b> = sum_i s_i^(a+b), so all of it costs one pass over the samples for the
 * ~80k moments of degree <= 2D instead of a dense candidates x samples matrix. The
 * sums are formed as nested loops over the exponents of blocks of samples: each level
 * multiplies the prefix product by one power row, and the last variable's loop is a
 * dot product, so every moment costs two flops per sample. */
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "fit/fit_internal.h"

/* The kernels below are the fit's hot loop; the project builds with -O2, whose cheap
 * vectoriser cost model leaves the 2 x 2 dot products scalar. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("O3")
#endif

#define BLOCK FIT_BLOCK

int fit_powers_init(fit_powers *p, size_t n, int nvar, int maxe, const double *s,
                    const size_t *idx)
{
    size_t st = (n + BLOCK - 1) / BLOCK * BLOCK;
    p->n = n;
    p->stride = st;
    p->nvar = nvar;
    p->maxe = maxe;
    p->pw = calloc((size_t)nvar * (size_t)(maxe + 1) * (st ? st : 1), sizeof *p->pw);
    if (!p->pw)
        return -1;
    for (int v = 0; v < nvar; v++) {
        double *r0 = p->pw + (size_t)v * (maxe + 1) * st;
        for (size_t i = 0; i < n; i++)
            r0[i] = 1.0;
        for (int e = 1; e <= maxe; e++) {
            double *r = r0 + (size_t)e * st, *prev = r - st;
            for (size_t i = 0; i < n; i++) {
                size_t row = idx ? idx[i] : i;
                r[i] = prev[i] * s[row * (size_t)nvar + v];
            }
        }
    }
    return 0;
}

void fit_powers_free(fit_powers *p)
{
    free(p->pw);
    p->pw = NULL;
}

void fit_column(const fit_powers *p, const int *a, double *col)
{
    const double *r0 = fit_pow_row(p, 0, a[0]);
    memcpy(col, r0, p->n * sizeof *col);
    for (int v = 1; v < p->nvar; v++) {
        if (a[v] == 0)
            continue;
        const double *r = fit_pow_row(p, v, a[v]);
        for (size_t i = 0; i < p->n; i++)
            col[i] *= r[i];
    }
}

static inline __attribute__((always_inline)) double dot(const double *a, const double *b, int n)
{
    double s = 0;
#pragma omp simd reduction(+ : s)
    for (int i = 0; i < n; i++)
        s += a[i] * b[i];
    return s;
}

typedef struct {
    const fit_powers *p;
    size_t i0;
    int nb;
    double *out;
    double (*pre)[BLOCK]; /* prefix products, one row per level */
} nest_ctx;

/* Dot products of two rows with two others (four sums sharing their loads): the
 * inner kernel of the moment sums, written so that the compiler can keep the four
 * sums in vector registers. */
static inline __attribute__((always_inline)) void dot2x2(const double *a0, const double *a1, const double *b0,
                          const double *b1, int n, double out[4])
{
    double s00 = 0, s01 = 0, s10 = 0, s11 = 0;
#pragma omp simd reduction(+ : s00, s01, s10, s11)
    for (int i = 0; i < n; i++) {
        s00 += a0[i] * b0[i];
        s01 += a0[i] * b1[i];
        s10 += a1[i] * b0[i];
        s11 += a1[i] * b1[i];
    }
    out[0] = s00, out[1] = s01, out[2] = s10, out[3] = s11;
}

/* Level v >= 1 with prefix c->pre[v - 1], remaining degree rem, first index *idx. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
static void nest(nest_ctx *c, int v, int rem, size_t *idx)
{
    const fit_powers *p = c->p;
    const double *pre = c->pre[v - 1];
    enum { nb = BLOCK };
    if (v == p->nvar - 1) {
        for (int e = 0; e <= rem; e++)
            c->out[(*idx)++] += dot(pre, fit_pow_row(p, v, e) + c->i0, nb);
        return;
    }
    double *cur = c->pre[v];
    if (v == p->nvar - 2) {
        /* The last two variables: moments (e, f), e + f <= rem, a triangle of dot
         * products of W_e = pre * s_v^e with s_last^f, done in 2 x 2 tiles. */
        double (*W)[BLOCK] = c->pre + v; /* rows v .. v + rem + 1 are scratch */
        for (int e = 0; e <= rem; e++) {
            const double *r = fit_pow_row(p, v, e) + c->i0;
            for (int i = 0; i < nb; i++)
                W[e][i] = pre[i] * r[i];
        }
        const double *last = fit_pow_row(p, v + 1, 0) + c->i0;
        size_t stride = p->stride, base = *idx;
        /* start index of row e: sum over e' < e of (rem - e' + 1) */
        for (int e = 0; e <= rem; e += 2) {
            size_t s0 = base + (size_t)e * (rem + 1) - (size_t)e * (e - 1) / 2;
            int has1 = e + 1 <= rem;
            size_t s1 = s0 + (size_t)(rem - e + 1);
            int fmax = rem - e; /* row e has f = 0..fmax, row e+1 has 0..fmax-1 */
            int f = 0;
            double o[4];
            for (; has1 && f + 1 <= fmax - 1; f += 2) {
                dot2x2(W[e], W[e + 1], last + f * stride, last + (f + 1) * stride, nb, o);
                c->out[s0 + f] += o[0];
                c->out[s0 + f + 1] += o[1];
                c->out[s1 + f] += o[2];
                c->out[s1 + f + 1] += o[3];
            }
            for (; f <= fmax; f++) {
                c->out[s0 + f] += dot(W[e], last + f * stride, nb);
                if (has1 && f <= fmax - 1)
                    c->out[s1 + f] += dot(W[e + 1], last + f * stride, nb);
            }
        }
        *idx = base + (size_t)(rem + 1) * (rem + 2) / 2;
        return;
    }
    for (int e = 0; e <= rem; e++) {
        const double *r = fit_pow_row(p, v, e) + c->i0;
        for (int i = 0; i < nb; i++)
            cur[i] = pre[i] * r[i];
        nest(c, v + 1, rem - e, idx);
    }
}

void fit_moments(const fit_lex *lx, const fit_powers *p, const double *w, double *out,
                 int threads)
{
    memset(out, 0, lx->count * sizeof *out);
    int M = lx->M, nvar = lx->nvar;
    int nt = threads > 0 ? threads : omp_get_max_threads();
    /* One task per exponent of the first variable: each task owns a contiguous range
     * of out and sums over all samples in the same block order, so the result does
     * not depend on the number of threads. */
#pragma omp parallel for schedule(dynamic, 1) num_threads(nt)
    for (int e0 = 0; e0 <= M; e0++) {
        /* prefix rows, then up to 2 * FIT_MAX_DEG + 1 rows of W in the last two levels */
        double pre[FIT_MAX_VARS + 2 * FIT_MAX_DEG + 2][BLOCK];
        nest_ctx c = {p, 0, 0, out, pre};
        size_t start = lx->off[e0]; /* v = 0, used = 0 */
        const double *r0 = fit_pow_row(p, 0, e0);
        for (size_t i0 = 0; i0 < p->n; i0 += BLOCK) {
            int nb = BLOCK; /* the padding is zero */
            c.i0 = i0;
            c.nb = nb;
            if (nvar == 1) {
                for (int i = 0; i < nb; i++)
                    pre[0][i] = w && i0 + i < p->n ? w[i0 + i] : 1.0;
                out[e0] += dot(pre[0], r0 + i0, nb);
                continue;
            }
            for (int i = 0; i < nb; i++)
                pre[0][i] = w && i0 + i < p->n ? w[i0 + i] * r0[i0 + i] : r0[i0 + i];
            size_t idx = start;
            nest(&c, 1, M - e0, &idx);
        }
    }
}
