/* Passage as a share of the light (eval_passage.h). */
#include "analysis/eval_passage.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

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
    eval_ring *r = realloc(p->ring, cap * sizeof *r);
    if (!r)
        return -1;
    memset(r + p->cap, 0, (cap - p->cap) * sizeof *r);
    p->ring = r;
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
    eval_ring *g = p->ring + ring;
    g->rays++;
    g->passing += lens_pass != 0;
    p->lens_blocked += !lens_pass;
    if (lens_pass)
        g->light += w;
    if (sys_pass && !lens_pass)
        g->fpass += w;
    if (!sys_pass && lens_pass)
        g->fblock += w;
    return 0;
}

int eval_passage_measured(const eval_passage *p) { return p->lens_blocked > 0; }

static void share(table_out *t, const char *key, double v)
{
    table_out_str(t, key);
    table_out_num(t, v, 0);
    table_out_row_end(t);
}

void eval_passage_write(table_out *t, const eval_passage *p)
{
    if (!eval_passage_measured(p)) {
        table_out_str(t, "passage_measured");
        table_out_int(t, 0);
        table_out_row_end(t);
        size_t rays = 0;
        for (size_t k = 0; k < p->nring; k++)
            rays += p->ring[k].rays;
        if (!t->json && rays == 0)
            fputs("# passage not measured: the test set holds no ray\n", t->f);
        else if (!t->json)
            fputs("# passage not measured: the test set holds no ray the lens blocks (trace "
                  "it without --passing-only, best with --sampling full)\n", t->f);
        return;
    }
    double light = 0, fp = 0, fb = 0, worst = 0;
    size_t wk = 0;
    for (size_t k = 0; k < p->nring; k++) {
        const eval_ring *g = p->ring + k;
        light += g->light, fp += g->fpass, fb += g->fblock;
        double d = g->light > 0 ? (g->fpass + g->fblock) / g->light : 0;
        /* every ring the table shows competes: a summary that left out the sparse outer
         * rings printed 0 beside a ring of 31.7 %; worst_ring_rays says how sparse */
        if (g->passing > 0 && d > worst)
            worst = d, wk = k;
    }
    double L = light > 0 ? light : 1;
    share(t, "light_false_pass", fp / L);
    share(t, "light_false_block", fb / L);
    share(t, "light_disagree", (fp + fb) / L);
    table_out_str(t, "worst_ring_mm");
    table_out_int(t, (long long)wk);
    table_out_row_end(t);
    share(t, "worst_ring_disagree", worst);
    table_out_str(t, "worst_ring_rays");
    table_out_int(t, (long long)(p->nring ? p->ring[wk].passing : 0));
    table_out_row_end(t);
    static const char *const cols[] = {"rmin_mm", "rmax_mm", "rays", "false_pass", "false_block",
                                       "disagree"};
    table_out_table(t, "passage_by_ring",
                    "passage by 1 mm ring of sensor radius: shares of the light the lens passes\n"
                    "there (rays weighted by cos^4 theta times the transmittance)", cols, 6);
    for (size_t k = 0; k < p->nring; k++) {
        const eval_ring *g = p->ring + k;
        double l = g->light > 0 ? g->light : 1;
        table_out_int(t, (long long)k);
        table_out_int(t, (long long)k + 1);
        table_out_int(t, (long long)g->rays);
        table_out_num(t, g->fpass / l, 0);
        table_out_num(t, g->fblock / l, 0);
        table_out_num(t, (g->fpass + g->fblock) / l, 0);
        table_out_row_end(t);
    }
}

void eval_passage_free(eval_passage *p)
{
    free(p->ring);
    memset(p, 0, sizeof *p);
}
