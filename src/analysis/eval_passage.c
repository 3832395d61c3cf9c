/* Passage as a share of the light (eval_passage.h). */
#include "analysis/eval_passage.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Rings with less lens light than this many rays' worth are too noisy for the worst
 * ring (their rows are still written). */
#define MIN_RING_RAYS 200

int eval_passage_init(eval_passage *p, const poly_system *s)
{
    memset(p, 0, sizeof *p);
    p->ix = poly_input_index(s, "x");
    p->iy = poly_input_index(s, "y");
    p->iu = poly_input_index(s, "u");
    p->iv = poly_input_index(s, "v");
    p->ieta = poly_output_index(s, "out_eta");
    return 0;
}

static int grow(eval_passage *p, size_t ring)
{
    if (ring < p->cap)
        return 0;
    size_t cap = ring + 16;
    double *l = realloc(p->light, cap * sizeof *l);
    if (l)
        p->light = l;
    double *a = realloc(p->fpass, cap * sizeof *a);
    if (a)
        p->fpass = a;
    double *b = realloc(p->fblock, cap * sizeof *b);
    if (b)
        p->fblock = b;
    size_t *r = realloc(p->rays, cap * sizeof *r);
    if (r)
        p->rays = r;
    if (!l || !a || !b || !r)
        return -1;
    for (size_t k = p->cap; k < cap; k++)
        p->light[k] = p->fpass[k] = p->fblock[k] = 0, p->rays[k] = 0;
    p->cap = cap;
    return 0;
}

int eval_passage_add(eval_passage *p, const double *in, const double *pred, int sys_pass,
                     const double *ref, int lens_pass)
{
    double r = p->ix >= 0 && p->iy >= 0 ? hypot(in[p->ix], in[p->iy]) : 0;
    double u = p->iu >= 0 ? in[p->iu] : 0, v = p->iv >= 0 ? in[p->iv] : 0;
    double q = 1 + u * u + v * v, w = 1 / (q * q);
    if (p->ieta >= 0) {
        double t = lens_pass ? ref[p->ieta] : pred[p->ieta];
        w *= isfinite(t) && t > 0 ? fmin(t, 1) : 0;
    }
    size_t ring = isfinite(r) && r < 1e6 ? (size_t)r : 0;
    if (grow(p, ring) != 0)
        return -1;
    if (ring >= p->nring)
        p->nring = ring + 1;
    p->rays[ring]++;
    p->lens_blocked += !lens_pass;
    if (lens_pass)
        p->light[ring] += w;
    if (sys_pass && !lens_pass)
        p->fpass[ring] += w;
    if (!sys_pass && lens_pass)
        p->fblock[ring] += w;
    return 0;
}

int eval_passage_measured(const eval_passage *p) { return p->lens_blocked > 0; }

void eval_passage_write(FILE *f, const eval_passage *p)
{
    if (!eval_passage_measured(p)) {
        fputs("passage not measured\n# (the test set holds no ray the lens blocks: trace "
              "it without --passing-only, best with --sampling full)\n", f);
        return;
    }
    double light = 0, fp = 0, fb = 0, worst = 0;
    size_t wk = 0;
    for (size_t k = 0; k < p->nring; k++) {
        light += p->light[k], fp += p->fpass[k], fb += p->fblock[k];
        double d = p->light[k] > 0 ? (p->fpass[k] + p->fblock[k]) / p->light[k] : 0;
        if (p->rays[k] >= MIN_RING_RAYS && d > worst)
            worst = d, wk = k;
    }
    double L = light > 0 ? light : 1;
    fprintf(f, "light_false_pass %.6g\nlight_false_block %.6g\nlight_disagree %.6g\n"
               "worst_ring_mm %zu\nworst_ring_disagree %.6g\n",
            fp / L, fb / L, (fp + fb) / L, wk, worst);
    fputs("\n# passage by 1 mm ring of sensor radius: shares of the light the lens passes\n"
          "# there (rays weighted by cos^4 theta times the transmittance)\n"
          "# columns: rmin rmax rays false_pass false_block disagree\n", f);
    for (size_t k = 0; k < p->nring; k++) {
        double l = p->light[k] > 0 ? p->light[k] : 1;
        fprintf(f, "%zu %zu %zu %.6g %.6g %.6g\n", k, k + 1, p->rays[k], p->fpass[k] / l,
                p->fblock[k] / l, (p->fpass[k] + p->fblock[k]) / l);
    }
}

void eval_passage_free(eval_passage *p)
{
    free(p->light);
    free(p->fpass);
    free(p->fblock);
    free(p->rays);
    memset(p, 0, sizeof *p);
}
