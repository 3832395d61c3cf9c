#ifndef SPARSELENS_POLY_FIXTURE_H
#define SPARSELENS_POLY_FIXTURE_H
/* A realistic test system for the poly tests and bench/bench_poly.c: inputs x y u v
 * lambda, outputs out_x out_y out_u out_v out_eta, each with nterms terms of total
 * degree <= maxdeg and the symmetry of a rotationally symmetric lens (out_x and out_u
 * odd in (x, u), even in (y, v); out_y and out_v the reverse; out_eta even in both), as
 * in the fisheye-ii system of the supplement. Coefficients are random but seeded. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sparselens/poly.h"

typedef struct {
    uint64_t s;
} fixture_rng;

static inline double fixture_uniform(fixture_rng *g)
{
    g->s = g->s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(g->s >> 11) * (1.0 / 9007199254740992.0);
}

static const char *const fixture_inputs[5] = {"x", "y", "u", "v", "lambda"};
static const char *const fixture_outputs[5] = {"out_x", "out_y", "out_u", "out_v", "out_eta"};

/* Ranges of the inputs (mm, direction, um) and the scaling used for them. */
static const double fixture_lo[5] = {-18, -18, -0.6, -0.6, 0.40};
static const double fixture_hi[5] = {18, 18, 0.6, 0.6, 0.70};

static inline void fixture_ray(fixture_rng *g, double *in)
{
    for (int i = 0; i < 5; i++)
        in[i] = fixture_lo[i] + (fixture_hi[i] - fixture_lo[i]) * fixture_uniform(g);
}

/* A random monomial of the symmetry class (px, py): parity of the x+u and y+v exponents. */
static inline void fixture_monomial(fixture_rng *g, int maxdeg, int px, int py, int *e)
{
    for (;;) {
        /* low degrees are likelier, as in fitted systems */
        int target = (int)(maxdeg * pow(fixture_uniform(g), 1.5) + 0.5), deg = 0;
        for (int i = 0; i < 5; i++)
            e[i] = 0;
        for (int k = 0; k < target; k++)
            e[(int)(5 * fixture_uniform(g)) % 5]++;
        for (int i = 0; i < 5; i++)
            deg += e[i];
        if (((e[0] + e[2]) & 1) == px && ((e[1] + e[3]) & 1) == py && deg <= maxdeg)
            return;
    }
}

static inline int fixture_add(poly_system *s, int p, int o, const int *e, fixture_rng *g)
{
    int deg = e[0] + e[1] + e[2] + e[3] + e[4];
    return poly_add_term(s, p, o, e, (2 * fixture_uniform(g) - 1) / (1 + deg)) == 0;
}

/* Adds nterms distinct terms per output to part p, shaped like a fitted lens system:
 * out_u shares about half its monomials with out_x, out_y and out_v mirror out_x and
 * out_u (x <-> y, u <-> v), positions and directions reach degree min(7, maxdeg) and
 * out_eta maxdeg. */
static inline void fixture_terms(poly_system *s, int p, int nterms, int maxdeg, fixture_rng *g)
{
    int lowdeg = maxdeg < 7 ? maxdeg : 7;
    int ex[4096][5], nx = 0, eu[4096][5], nu = 0;
    if (nterms > 4096)
        nterms = 4096;
    for (int tries = 0; nx < nterms && tries < 100000; tries++) {
        fixture_monomial(g, lowdeg, 1, 0, ex[nx]);
        if (fixture_add(s, p, 0, ex[nx], g))
            nx++;
    }
    for (int tries = 0; nu < nterms && tries < 100000; tries++) {
        int *e = eu[nu];
        if (fixture_uniform(g) < 0.5)
            memcpy(e, ex[(int)(nx * fixture_uniform(g)) % nx], sizeof eu[0]);
        else
            fixture_monomial(g, lowdeg, 1, 0, e);
        if (fixture_add(s, p, 2, e, g))
            nu++;
    }
    for (int k = 0; k < nx; k++) {
        int m[5] = {ex[k][1], ex[k][0], ex[k][3], ex[k][2], ex[k][4]};
        fixture_add(s, p, 1, m, g);
    }
    for (int k = 0; k < nu; k++) {
        int m[5] = {eu[k][1], eu[k][0], eu[k][3], eu[k][2], eu[k][4]};
        fixture_add(s, p, 3, m, g);
    }
    int added = 0;
    for (int tries = 0; added < nterms && tries < 100000; tries++) {
        int e[5];
        fixture_monomial(g, maxdeg, 0, 0, e);
        if (added == nterms - 1) { /* the highest degree occurs at least once */
            memset(e, 0, sizeof e);
            e[0] = maxdeg & 1 ? maxdeg - 1 : maxdeg;
            e[4] = maxdeg & 1;
        }
        added += fixture_add(s, p, 4, e, g);
    }
}

static inline poly_system *fixture_system(int nterms, int maxdeg, int nparts, uint64_t seed)
{
    poly_system *s = poly_new("fixture", 5, fixture_inputs, 5, fixture_outputs);
    fixture_rng g = {seed};
    poly_set_scaling(s, 0, 0, 18);
    poly_set_scaling(s, 1, 0, 18);
    poly_set_scaling(s, 2, 0, 0.6);
    poly_set_scaling(s, 3, 0, 0.6);
    poly_set_scaling(s, 4, 0.55, 0.15);
    for (int i = 0; i < 5; i++)
        poly_set_domain(s, i, fixture_lo[i], fixture_hi[i]);
    double rmax = 18 * sqrt(2.0);
    for (int p = 0; p < nparts; p++) {
        double a = rmax * p / nparts, b = p == nparts - 1 ? INFINITY : rmax * (p + 1) / nparts;
        int q = poly_add_part(s, a, b);
        fixture_terms(s, q, nterms, maxdeg, &g);
    }
    return s;
}

/* The value of a system by its definition, term by term with pow(): an independent
 * check of the evaluation plan. */
static inline void fixture_naive(const poly_system *s, const double *in, double *out)
{
    int nin = poly_ninputs(s), p = poly_part_of(s, in);
    double sc[64];
    for (int i = 0; i < nin; i++) {
        double off, scale;
        poly_get_scaling(s, i, &off, &scale);
        sc[i] = (in[i] - off) / scale;
    }
    for (int o = 0; o < poly_noutputs(s); o++) {
        double acc = 0;
        for (int t = 0; t < poly_nterms(s, p, o); t++) {
            int e[64];
            double c;
            poly_get_term(s, p, o, t, e, &c);
            double m = c;
            for (int i = 0; i < nin; i++)
                m *= pow(sc[i], e[i]);
            acc += m;
        }
        out[o] = acc;
    }
}

/* The batch Jacobian against the one-ray one, entry by entry: poly_eval_jacobian_batch
 * sums its derivative and value terms with fused multiply-adds where the machine has
 * them (AVX-512), poly_eval_jacobian with separate multiplies and adds, so the two may
 * differ by rounding: 1e-12 relative is allowed. Entry k of n (one ray's row)
 * agrees when equal (inf, nan alike) or within 1e-12 of the larger of its size and
 * scale[k] (the entry's size over the rays, or of its output's row: a derivative that
 * cancels to nearly 0 keeps its terms' rounding). Returns the first entry that does
 * not, or -1. */
static inline int fixture_jacobian_differs(const double *one, const double *batch,
                                           const double *scale, int n)
{
    for (int k = 0; k < n; k++) {
        if ((isnan(one[k]) && isnan(batch[k])) || one[k] == batch[k])
            continue;
        if (!(fabs(one[k] - batch[k]) <= 1e-12 * fmax(fabs(batch[k]), scale[k])))
            return k;
    }
    return -1;
}

/* scale[k] for fixture_jacobian_differs: the largest finite |jac[r * n + k]| over rays
 * r < nrays. */
static inline void fixture_jacobian_scale(const double *jac, size_t nrays, int n, double *scale)
{
    for (int k = 0; k < n; k++) {
        scale[k] = 0;
        for (size_t r = 0; r < nrays; r++)
            if (isfinite(jac[r * (size_t)n + (size_t)k]))
                scale[k] = fmax(scale[k], fabs(jac[r * (size_t)n + (size_t)k]));
    }
}

#endif
