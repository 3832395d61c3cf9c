/* Evaluation of polynomial systems: one ray, batches, and the Jacobian (the core in the
 * system's frame; poly_frame.c wraps it into the public functions).
 * All paths compute the same products in the same order (poly_impl.h), so scalar and
 * batch results are bit-identical. */
#include "poly_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Rays per block in the batch path: the slot values of a block live side by side so
 * every product and every term is a short loop the compiler turns into vector code. */
#define BLK 8
/* Rays whose parts are sorted out together in the batch path (bounds the index buffer). */
#define CHUNK 2048

static int passes(const poly_system *s, const double *out)
{
    for (int o = 0; o < s->nout; o++)
        if (!isfinite(out[o]))
            return 0;
    for (int c = 0; c < s->ncircles; c++) {
        double a = out[s->circles[c].a], b = out[s->circles[c].b], r = s->circles[c].radius;
        if (!(a * a + b * b <= r * r))
            return 0;
    }
    return 1;
}

static void fill_nan(double *out, int n)
{
    for (int o = 0; o < n; o++)
        out[o] = NAN;
}

/* Slot values of one ray into v[nslots] (the stored ones: the batch plan's). */
static void slots_one(const poly_system *s, const poly_part *p, const double *in, double *v)
{
    v[0] = 1;
    for (int i = 0; i < s->nin; i++)
        v[1 + i] = (in[i] - s->offset[i]) / s->scale[i];
    const int *sa = p->slot_a, *sb = p->slot_b, *ord = p->stored;
    for (int j = 0; j < p->nstored; j++) {
        int k = ord[j];
        v[k] = v[sa[k]] * v[sb[k]];
    }
}

/* The same sums as the batch path, term t into partial sum t % 4. */
static void dots_one(const poly_system *s, const poly_part *p, const double *v, double *out)
{
    for (int o = 0; o < s->nout; o++) {
        const poly_out_terms *ot = &p->out[o];
        const double *c = ot->coef;
        const int *fa = ot->fa, *fb = ot->fb;
        double a0 = 0, a1 = 0, a2 = 0, a3 = 0;
        int t = 0, nt = ot->nterms;
        for (; t + 4 <= nt; t += 4) {
            a0 += c[t] * (v[fa[t]] * v[fb[t]]);
            a1 += c[t + 1] * (v[fa[t + 1]] * v[fb[t + 1]]);
            a2 += c[t + 2] * (v[fa[t + 2]] * v[fb[t + 2]]);
            a3 += c[t + 3] * (v[fa[t + 3]] * v[fb[t + 3]]);
        }
        if (t < nt)
            a0 += c[t] * (v[fa[t]] * v[fb[t]]);
        if (t + 1 < nt)
            a1 += c[t + 1] * (v[fa[t + 1]] * v[fb[t + 1]]);
        if (t + 2 < nt)
            a2 += c[t + 2] * (v[fa[t + 2]] * v[fb[t + 2]]);
        out[o] = (a0 + a1) + (a2 + a3);
    }
}

int poly_eval_part_core(const poly_system *s, int part, const double *in, double *out)
{
    if (part < 0 || part >= s->nparts) {
        fill_nan(out, s->nout);
        return 0;
    }
    const poly_part *p = &s->parts[part];
    double buf[512];
    double *v = p->nslots <= 512 ? buf : malloc((size_t)p->nslots * sizeof(double));
    if (!v) {
        fill_nan(out, s->nout);
        return 0;
    }
    slots_one(s, p, in, v);
    dots_one(s, p, v, out);
    if (v != buf)
        free(v);
    return passes(s, out);
}

/* A block of BLK rays in one vector (GCC/clang vector extension): on SSE it is split
 * into 2-wide operations, on AVX2 and AVX-512 machines the clones below use wider
 * ones. Only IEEE multiplies, adds and divides: every clone gives the same bits. */
typedef double vblk __attribute__((vector_size(BLK * sizeof(double))));
typedef long long vmask __attribute__((vector_size(BLK * sizeof(long long))));

/* The arithmetic of one block: v[1 + i] holds the raw inputs of BLK rays on entry;
 * res[nout] gets the outputs and *ok the passage test of passes() per lane (all bits
 * set: passes). Pure vector arithmetic without calls, so the wide clones return with
 * the upper register state cleared and never slow down the SSE code around them. */
__attribute__((target_clones("avx512f", "avx2", "default"))) static void
eval_block(const poly_system *s, const poly_part *p, vblk *v, vblk *res, vmask *ok)
{
    const int nin = s->nin, nout = s->nout;
    for (int r = 0; r < BLK; r++)
        v[0][r] = 1;
    for (int i = 0; i < nin; i++)
        v[1 + i] = (v[1 + i] - s->offset[i]) / s->scale[i];
    const int *sa = p->slot_a, *sb = p->slot_b, *ord = p->stored;
    for (int j = 0; j < p->nstored; j++) {
        int k = ord[j];
        v[k] = v[sa[k]] * v[sb[k]];
    }
    for (int o = 0; o < nout; o++) {
        const poly_out_terms *ot = &p->out[o];
        const double *c = ot->coef;
        const int *fa = ot->fa, *fb = ot->fb;
        vblk a0 = {0}, a1 = {0}, a2 = {0}, a3 = {0};
        int t = 0, nt = ot->nterms;
        for (; t + 4 <= nt; t += 4) {
            a0 += c[t] * (v[fa[t]] * v[fb[t]]);
            a1 += c[t + 1] * (v[fa[t + 1]] * v[fb[t + 1]]);
            a2 += c[t + 2] * (v[fa[t + 2]] * v[fb[t + 2]]);
            a3 += c[t + 3] * (v[fa[t + 3]] * v[fb[t + 3]]);
        }
        if (t < nt)
            a0 += c[t] * (v[fa[t]] * v[fb[t]]);
        if (t + 1 < nt)
            a1 += c[t + 1] * (v[fa[t + 1]] * v[fb[t + 1]]);
        if (t + 2 < nt)
            a2 += c[t + 2] * (v[fa[t + 2]] * v[fb[t + 2]]);
        res[o] = (a0 + a1) + (a2 + a3);
    }
    vmask m = res[0] == res[0]; /* all lanes set */
    for (int o = 0; o < nout; o++)
        m &= (res[o] - res[o]) == 0; /* finite: inf - inf and nan give nan */
    for (int c = 0; c < s->ncircles; c++) {
        const vblk a = res[s->circles[c].a], b = res[s->circles[c].b];
        const double r = s->circles[c].radius;
        m &= a * a + b * b <= r * r;
    }
    *ok = m;
}

/* n <= BLK rays, rows idx[r] of in. Unused lanes repeat the first ray so no lane
 * computes on garbage. */
static void run_block(const poly_system *s, const poly_part *p, int n, const size_t *idx,
                      const double *in, double *out, unsigned char *pass, vblk *v, vblk *res)
{
    const size_t nin = (size_t)s->nin, nout = (size_t)s->nout;
    for (size_t i = 0; i < nin; i++)
        for (int r = 0; r < BLK; r++)
            v[1 + i][r] = in[idx[r < n ? r : 0] * nin + i];
    vmask ok;
    eval_block(s, p, v, res, &ok);
    for (int r = 0; r < n; r++) {
        double *o = out + idx[r] * nout;
        for (size_t k = 0; k < nout; k++)
            o[k] = res[k][r];
        if (pass)
            pass[idx[r]] = ok[r] != 0;
    }
}

void poly_eval_batch_core(const poly_system *s, size_t count, const double *in, double *out,
                          unsigned char *pass)
{
    if (count == 0)
        return;
    int maxslots = 0;
    for (int p = 0; p < s->nparts; p++)
        if (s->parts[p].nslots > maxslots)
            maxslots = s->parts[p].nslots;
    vblk *v = s->nparts ? aligned_alloc(sizeof(vblk), (size_t)maxslots * sizeof(vblk)) : NULL;
    vblk *res = aligned_alloc(sizeof(vblk), (size_t)s->nout * sizeof(vblk));
    size_t *idx = s->nparts > 1 ? malloc(CHUNK * sizeof(size_t)) : NULL;
    if (!v || !res || (s->nparts > 1 && !idx)) {
        /* no parts, or out of memory: the rays do not pass */
        for (size_t r = 0; r < count; r++) {
            fill_nan(out + r * (size_t)s->nout, s->nout);
            if (pass)
                pass[r] = 0;
        }
        free(v);
        free(res);
        free(idx);
        return;
    }
    if (s->nparts == 1) {
        size_t id[BLK];
        for (size_t r0 = 0; r0 < count; r0 += BLK) {
            int n = count - r0 < BLK ? (int)(count - r0) : BLK;
            for (int r = 0; r < BLK; r++)
                id[r] = r0 + (size_t)(r < n ? r : 0);
            run_block(s, &s->parts[0], n, id, in, out, pass, v, res);
        }
    } else {
        /* Sort each chunk's rays by part (a counting sort), then run blocks per part. */
        int *part = malloc(CHUNK * sizeof(int));
        int *start = calloc((size_t)s->nparts + 1, sizeof(int));
        int *cur = malloc((size_t)s->nparts * sizeof(int));
        if (part && start && cur) {
            for (size_t c0 = 0; c0 < count; c0 += CHUNK) {
                size_t n = count - c0 < CHUNK ? count - c0 : CHUNK;
                memset(start, 0, ((size_t)s->nparts + 1) * sizeof(int));
                for (size_t r = 0; r < n; r++) {
                    part[r] = poly_select_part(s, in + (c0 + r) * (size_t)s->nin);
                    start[part[r] + 1]++;
                }
                for (int q = 0; q < s->nparts; q++)
                    start[q + 1] += start[q];
                memcpy(cur, start, (size_t)s->nparts * sizeof(int));
                for (size_t r = 0; r < n; r++)
                    idx[cur[part[r]]++] = c0 + r;
                for (int q = 0; q < s->nparts; q++)
                    for (int b = start[q]; b < start[q + 1]; b += BLK) {
                        int m = start[q + 1] - b < BLK ? start[q + 1] - b : BLK;
                        run_block(s, &s->parts[q], m, idx + b, in, out, pass, v, res);
                    }
            }
        }
        free(part);
        free(start);
        free(cur);
    }
    free(v);
    free(res);
    free(idx);
}

int poly_eval_jacobian_core(const poly_system *s, const double *in, double *out, double *jac)
{
    const int nin = s->nin, nout = s->nout;
    int pass = poly_eval_part_core(s, s->nparts ? poly_select_part(s, in) : -1, in, out);
    if (s->nparts == 0) {
        for (int k = 0; k < nin * nout; k++)
            jac[k] = NAN;
        return 0;
    }
    const poly_part *p = &s->parts[poly_select_part(s, in)];
    enum { NP = POLY_MAX_DEGREE + 1 };
    double buf[16 * NP];
    double *pw = nin <= 16 ? buf : malloc((size_t)nin * NP * sizeof(double));
    if (!pw) {
        for (int k = 0; k < nin * nout; k++)
            jac[k] = NAN;
        return 0;
    }
    for (int i = 0; i < nin; i++) {
        double si = (in[i] - s->offset[i]) / s->scale[i];
        pw[i * NP] = 1;
        for (int k = 1; k < NP; k++)
            pw[i * NP + k] = pw[i * NP + k - 1] * si;
    }
    for (int o = 0; o < nout; o++) {
        const poly_out_terms *ot = &p->out[o];
        for (int i = 0; i < nin; i++) {
            double acc = 0;
            for (int t = 0; t < ot->nterms; t++) {
                const int *e = ot->exps + (size_t)t * (size_t)nin;
                if (e[i] == 0)
                    continue;
                double d = ot->coef[t] * e[i] * pw[i * NP + e[i] - 1];
                for (int j = 0; j < nin; j++)
                    if (j != i)
                        d *= pw[j * NP + e[j]];
                acc += d;
            }
            /* chain rule through the scaling s_i = (in_i - offset_i) / scale_i */
            jac[o * nin + i] = acc / s->scale[i];
        }
    }
    if (pw != buf)
        free(pw);
    return pass;
}
