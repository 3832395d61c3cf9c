/* The numeric core of lens-fit: monomial numbering, moment sums, and term selection
 * on planted sparse polynomials (whose terms and coefficients are known exactly). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <stdio.h>

#include "fit/fit_internal.h"

static double urand(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

static double binom(int n, int k)
{
    double c = 1;
    for (int i = 1; i <= k; i++)
        c = c * (n - k + i) / i;
    return c;
}

/* Counts are binomials C(M + n, n) (4368 candidates at degree 11 in 5 inputs, as the
 * issue states), and rank() inverts the enumeration. */
static void test_lex_numbering(void **state)
{
    (void)state;
    int cases[][2] = {{5, 11}, {5, 22}, {3, 7}, {1, 9}, {2, 0}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        fit_lex lx;
        int nv = cases[c][0], M = cases[c][1];
        assert_int_equal(fit_lex_init(&lx, nv, M), 0);
        assert_true((double)lx.count == binom(M + nv, nv));
        int *ex = malloc(lx.count * (size_t)nv * sizeof *ex);
        fit_lex_tuples(&lx, ex);
        for (size_t q = 0; q < lx.count; q++) {
            int deg = 0;
            for (int v = 0; v < nv; v++)
                deg += ex[q * nv + v];
            assert_true(deg <= M);
            assert_int_equal(fit_lex_rank(&lx, ex + q * nv), q);
        }
        free(ex);
        fit_lex_free(&lx);
    }
    fit_lex lx;
    fit_lex_init(&lx, 5, 11);
    assert_int_equal(lx.count, 4368);
    fit_lex_free(&lx);
}

/* Moment sums against the direct sums, for weighted and unweighted moments and for
 * sample counts that do and do not fill the last block. */
static void test_moments_direct(void **state)
{
    (void)state;
    for (int trial = 0; trial < 3; trial++) {
        int nv = 3 + trial % 3, M = 6;
        size_t n = trial == 0 ? 128 : 301 + (size_t)trial;
        uint64_t sd = 7 + (uint64_t)trial;
        double *s = malloc(n * nv * sizeof *s), *w = malloc(n * sizeof *w);
        for (size_t i = 0; i < n * nv; i++)
            s[i] = urand(&sd);
        for (size_t i = 0; i < n; i++)
            w[i] = urand(&sd);
        fit_lex lx;
        fit_lex_init(&lx, nv, M);
        fit_powers p;
        assert_int_equal(fit_powers_init(&p, n, nv, M, s, NULL), 0);
        double *m1 = malloc(lx.count * sizeof *m1), *m2 = malloc(lx.count * sizeof *m2);
        fit_moments(&lx, &p, NULL, m1, 2);
        fit_moments(&lx, &p, w, m2, 1);
        int *ex = malloc(lx.count * (size_t)nv * sizeof *ex);
        fit_lex_tuples(&lx, ex);
        for (size_t q = 0; q < lx.count; q++) {
            double a = 0, b = 0, aa = 0;
            for (size_t i = 0; i < n; i++) {
                double m = 1;
                for (int v = 0; v < nv; v++)
                    m *= pow(s[i * nv + v], ex[q * nv + v]);
                a += m;
                b += w[i] * m;
                aa += fabs(m);
            }
            assert_true(fabs(a - m1[q]) <= 1e-13 * (aa + 1));
            assert_true(fabs(b - m2[q]) <= 1e-13 * (aa + 1));
        }
        free(ex); free(m1); free(m2); free(s); free(w);
        fit_powers_free(&p);
        fit_lex_free(&lx);
    }
}

typedef struct {
    int nterms;
    int exps[8][5];
    double coef[8];
} planted;

/* Fits a planted polynomial from noiseless samples and checks the chosen terms and
 * coefficients. Samples: n uniform points in [-1, 1]^5 (optionally squeezed towards 0
 * in some coordinates to make the monomials nearly dependent). */
static void check_planted(const planted *pl, size_t n, int D, uint64_t seed, double squeeze)
{
    fit_basis b;
    assert_int_equal(fit_basis_init(&b, 5, D), 0);
    size_t nh = n / 5, nt = n - nh;
    double *s = malloc(n * 5 * sizeof *s), *y = malloc(n * sizeof *y);
    for (size_t i = 0; i < n * 5; i++) {
        s[i] = urand(&seed);
        if (i % 5 >= 3)
            s[i] = copysign(pow(fabs(s[i]), squeeze), s[i]);
    }
    for (size_t i = 0; i < n; i++) {
        double v = 0;
        for (int t = 0; t < pl->nterms; t++) {
            double m = pl->coef[t];
            for (int k = 0; k < 5; k++)
                m *= pow(s[i * 5 + k], pl->exps[t][k]);
            v += m;
        }
        y[i] = v;
    }
    size_t *ih = malloc(nh * sizeof *ih);
    for (size_t i = 0; i < nh; i++)
        ih[i] = nt + i;
    fit_powers tr, ho, all;
    fit_powers_init(&tr, nt, 5, 2 * D, s, NULL);
    fit_powers_init(&ho, nh, 5, D, s, ih);
    fit_powers_init(&all, n, 5, D, s, NULL);
    double *mom = malloc(b.mom.count * sizeof *mom), *by = malloc(b.cand.count * sizeof *by);
    fit_moments(&b.mom, &tr, NULL, mom, 2);
    fit_moments(&b.cand, &tr, y, by, 1);
    fit_select_opt o = {40, 0, 8, 2};
    fit_selection r;
    assert_int_equal(fit_select(&b, mom, by, &tr, y, &ho, y + nt, &o, &r), 0);
    assert_int_equal(r.nterms, pl->nterms);
    double *coef = malloc((size_t)r.nterms * sizeof *coef);
    assert_int_equal(fit_lsq(&b, &all, y, r.nterms, r.cand, coef), 0);
    /* Monomials are bounded by 1 on [-1, 1]^5, so |error of c_t| bounds the error of that
     * term's contribution; compare it with the size of the polynomial, sum |c_t|. */
    double size = 0;
    for (int t = 0; t < pl->nterms; t++)
        size += fabs(pl->coef[t]);
    for (int t = 0; t < pl->nterms; t++) {
        size_t j = fit_lex_rank(&b.cand, pl->exps[t]);
        int found = -1;
        for (int u = 0; u < r.nterms; u++)
            if ((size_t)r.cand[u] == j)
                found = u;
        assert_true(found >= 0);
        assert_true(fabs(coef[found] - pl->coef[t]) <= 1e-11 * size);
        assert_true(fabs(coef[found] - pl->coef[t]) <= 1e-6 * fabs(pl->coef[t]));
        assert_true(fabs(r.coef[found] - pl->coef[t]) <= 1e-10 * size);
    }
    free(coef); free(mom); free(by); free(ih); free(s); free(y);
    fit_selection_free(&r);
    fit_powers_free(&tr);
    fit_powers_free(&ho);
    fit_powers_free(&all);
    fit_basis_free(&b);
}

static const planted P1 = {6,
                           {{0, 0, 0, 0, 0}, {1, 0, 0, 0, 0}, {0, 2, 1, 0, 0}, {3, 0, 0, 2, 1},
                            {0, 0, 0, 0, 7}, {2, 2, 2, 2, 2}},
                           {0.5, -1.25, 3, 0.125, -2, 1e-3}};

/* A lens-like odd polynomial: x and u with their cubic and quintic aberration terms. */
static const planted P2 = {7,
                           {{1, 0, 0, 0, 0}, {0, 0, 1, 0, 0}, {3, 0, 0, 0, 0}, {1, 2, 0, 0, 0},
                            {1, 0, 2, 0, 1}, {5, 0, 0, 0, 0}, {0, 0, 1, 4, 0}},
                           {-1.17, 8.37, 0.0013, 0.0011, 3.48, 1.6e-6, 53.99}};

static void test_planted_recovered(void **state)
{
    (void)state;
    check_planted(&P1, 3000, 11, 11, 1.0);
    check_planted(&P2, 3000, 11, 12, 1.0);
}

/* 600 samples and 4368 candidates: sparse selection needs only as many samples as
 * terms, not as candidates. */
static void test_fewer_samples_than_candidates(void **state)
{
    (void)state;
    check_planted(&P1, 600, 11, 13, 1.0);
    check_planted(&P2, 400, 11, 14, 1.0);
}

/* Samples squeezed towards 0 in u and v (|s|^3): the monomials in those inputs are
 * nearly dependent, and the planted terms must still come out exactly. */
static void test_planted_clustered(void **state)
{
    (void)state;
    check_planted(&P2, 3000, 13, 15, 3.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lex_numbering),
        cmocka_unit_test(test_moments_direct),
        cmocka_unit_test(test_planted_recovered),
        cmocka_unit_test(test_fewer_samples_than_candidates),
        cmocka_unit_test(test_planted_clustered),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
