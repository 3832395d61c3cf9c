/* Lexicographic numbering of monomials (see fit_internal.h) and the candidate basis. */
#include <stdlib.h>

#include "fit/fit_internal.h"

/* Monomials in m variables of total degree <= t: C(t + m, m). */
static size_t count_upto(int m, int t)
{
    if (t < 0)
        return 0;
    size_t c = 1;
    for (int i = 1; i <= m; i++)
        c = c * (size_t)(t + i) / (size_t)i; /* exact: a running binomial */
    return c;
}

int fit_lex_init(fit_lex *lx, int nvar, int M)
{
    lx->nvar = nvar;
    lx->M = M;
    lx->count = count_upto(nvar, M);
    size_t M1 = (size_t)M + 1;
    lx->off = calloc((size_t)nvar * M1 * M1, sizeof *lx->off);
    if (!lx->off)
        return -1;
    for (int v = 0; v < nvar; v++)
        for (int used = 0; used <= M; used++) {
            size_t acc = 0;
            for (int e = 0; e + used <= M; e++) {
                lx->off[((size_t)v * M1 + used) * M1 + e] = acc;
                acc += count_upto(nvar - v - 1, M - used - e);
            }
        }
    return 0;
}

void fit_lex_free(fit_lex *lx)
{
    free(lx->off);
    lx->off = NULL;
}

static void tuples_rec(const fit_lex *lx, int v, int rem, int *a, int **out)
{
    for (int e = 0; e <= rem; e++) {
        a[v] = e;
        if (v == lx->nvar - 1) {
            for (int i = 0; i < lx->nvar; i++)
                (*out)[i] = a[i];
            *out += lx->nvar;
        } else {
            tuples_rec(lx, v + 1, rem - e, a, out);
        }
    }
    a[v] = 0;
}

void fit_lex_tuples(const fit_lex *lx, int *exps)
{
    int a[FIT_MAX_VARS] = {0};
    int *p = exps;
    tuples_rec(lx, 0, lx->M, a, &p);
}

int fit_basis_init(fit_basis *b, int nvar, int D)
{
    b->nvar = nvar;
    b->D = D;
    b->exps = NULL;
    b->deg = NULL;
    b->gdiag = NULL;
    b->mom.off = NULL;
    if (nvar < 1 || nvar > FIT_MAX_VARS || D < 0 || D > FIT_MAX_DEG ||
        fit_lex_init(&b->cand, nvar, D) != 0)
        return -1;
    if (fit_lex_init(&b->mom, nvar, 2 * D) != 0)
        goto fail;
    size_t nc = b->cand.count;
    b->exps = malloc(nc * (size_t)nvar * sizeof *b->exps);
    b->deg = malloc(nc * sizeof *b->deg);
    b->gdiag = malloc(nc * sizeof *b->gdiag);
    if (!b->exps || !b->deg || !b->gdiag)
        goto fail;
    fit_lex_tuples(&b->cand, b->exps);
    for (size_t j = 0; j < nc; j++) {
        int a2[FIT_MAX_VARS], d = 0;
        for (int v = 0; v < nvar; v++) {
            d += b->exps[j * nvar + v];
            a2[v] = 2 * b->exps[j * nvar + v];
        }
        b->deg[j] = d;
        b->gdiag[j] = fit_lex_rank(&b->mom, a2);
    }
    return 0;
fail:
    fit_basis_free(b);
    return -1;
}

void fit_basis_free(fit_basis *b)
{
    fit_lex_free(&b->cand);
    fit_lex_free(&b->mom);
    free(b->exps);
    free(b->deg);
    free(b->gdiag);
    b->exps = NULL;
    b->deg = NULL;
    b->gdiag = NULL;
}
