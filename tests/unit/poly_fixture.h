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

#include "poly.h"

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

/* Adds nterms distinct terms per output to part p. */
static inline void fixture_terms(poly_system *s, int p, int nterms, int maxdeg, fixture_rng *g)
{
    for (int o = 0; o < 5; o++) {
        int added = 0, tries = 0;
        while (added < nterms && tries < 100000) {
            tries++;
            int e[5], deg = 0;
            /* low degrees are likelier, as in fitted systems */
            int target = (int)(maxdeg * pow(fixture_uniform(g), 1.5) + 0.5);
            if (added == nterms - 1)
                target = maxdeg; /* the highest degree occurs at least once */
            for (int i = 0; i < 5; i++)
                e[i] = 0;
            for (int k = 0; k < target; k++)
                e[(int)(5 * fixture_uniform(g)) % 5]++;
            for (int i = 0; i < 5; i++)
                deg += e[i];
            int px = (e[0] + e[2]) & 1, py = (e[1] + e[3]) & 1;
            int want_x = o == 0 || o == 2, want_y = o == 1 || o == 3;
            if (px != want_x || py != want_y || deg > maxdeg)
                continue;
            double c = (2 * fixture_uniform(g) - 1) / (1 + deg);
            if (poly_add_term(s, p, o, e, c) == 0)
                added++;
        }
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

#endif
