/* Evaluation of polynomial systems: one ray, batches, and the Jacobian.
 * Every path runs the plan of poly_impl.h with the same products and the same order of
 * additions, so scalar and batch results are bit-identical. */
#include "poly_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Rays per block in the batch path. The values of a block's rays for one monomial lie
 * side by side, so every product and every term is one operation on BLK lanes, which
 * the compiler splits into as many hardware vectors as the clone has (2 on AVX-512). A
 * block's values must stay in the L1 cache: 16 rays x 8 bytes x ~140 kept values of a
 * 5 x 40 term system is 18 KiB. Larger blocks measured slower, smaller ones pay the
 * per-term index and coefficient loads on fewer rays. */
#define BLK 16
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

/* The plan's values for one ray into v[nvals]. */
static void values_one(const poly_system *s, const poly_plan *pl, const double *in, double *v)
{
    v[0] = 1;
    for (int i = 0; i < s->nin; i++) {
        v[1 + i] = in[i];
        poly_scale_column(s, i, &v[1 + i], 1);
    }
    const int *pr = pl->prod;
    double *d = v + 1 + s->nin;
    for (int j = 0; j < pl->nprod; j++)
        d[j] = v[pr[2 * j]] * v[pr[2 * j + 1]];
}

/* The plan's sums for one ray (the same additions as the batch kernel's). */
static void sums_one(const poly_plan *pl, const double *v, double *out)
{
    for (int o = 0; o < pl->nout; o++) {
        const int t0 = pl->start[o], ns = pl->nsingle[o], nf = pl->start[o + 1] - t0 - ns;
        const double *c = pl->coef + t0;
        const int *fa = pl->fa + t0;
        double a0 = 0, a1 = 0, a2 = 0, a3 = 0;
        int t = 0;
        for (; t + 4 <= ns; t += 4) {
            a0 += c[t] * v[fa[t]];
            a1 += c[t + 1] * v[fa[t + 1]];
            a2 += c[t + 2] * v[fa[t + 2]];
            a3 += c[t + 3] * v[fa[t + 3]];
        }
        if (t < ns)
            a0 += c[t] * v[fa[t]];
        if (t + 1 < ns)
            a1 += c[t + 1] * v[fa[t + 1]];
        if (t + 2 < ns)
            a2 += c[t + 2] * v[fa[t + 2]];
        c += ns;
        fa += ns;
        const int *fb = pl->fb + t0 + ns;
        for (t = 0; t + 4 <= nf; t += 4) {
            a0 += c[t] * (v[fa[t]] * v[fb[t]]);
            a1 += c[t + 1] * (v[fa[t + 1]] * v[fb[t + 1]]);
            a2 += c[t + 2] * (v[fa[t + 2]] * v[fb[t + 2]]);
            a3 += c[t + 3] * (v[fa[t + 3]] * v[fb[t + 3]]);
        }
        if (t < nf)
            a0 += c[t] * (v[fa[t]] * v[fb[t]]);
        if (t + 1 < nf)
            a1 += c[t + 1] * (v[fa[t + 1]] * v[fb[t + 1]]);
        if (t + 2 < nf)
            a2 += c[t + 2] * (v[fa[t + 2]] * v[fb[t + 2]]);
        out[o] = (a0 + a1) + (a2 + a3);
    }
}

/* Runs plan pl on one ray: out[pl->nout]. Returns -1 when out of memory. */
static int run_one(const poly_system *s, const poly_plan *pl, const double *in, double *out)
{
    double buf[512];
    double *v = pl->nvals <= 512 ? buf : malloc((size_t)pl->nvals * sizeof(double));
    if (!v)
        return -1;
    values_one(s, pl, in, v);
    sums_one(pl, v, out);
    if (v != buf)
        free(v);
    return 0;
}

int poly_eval(const poly_system *s, const double *in, double *out)
{
    return poly_eval_part(s, s->nparts ? poly_select_part(s, in) : -1, in, out);
}

int poly_eval_part(const poly_system *s, int part, const double *in, double *out)
{
    if (part < 0 || part >= s->nparts || run_one(s, &s->parts[part].plan, in, out) != 0) {
        fill_nan(out, s->nout);
        return 0;
    }
    return passes(s, out);
}

/* A block of BLK rays in one vector (GCC/clang vector extension), split by the compiler
 * into the vectors of the clone below. Only IEEE multiplies, adds and divides, never
 * contracted: every clone gives the same bits as the scalar path. */
typedef double vblk __attribute__((vector_size(BLK * sizeof(double))));
typedef long long vmask __attribute__((vector_size(BLK * sizeof(long long))));

/* What a batch run computes: the outputs with the passage test, or the derivatives
 * d out_o / d in_i of the derivative plan (chain rule applied). */
enum { RUN_EVAL, RUN_JAC };

/* Runs plan pl on n rays: ray r is row idx[r] of in (row first + r if idx is NULL) and
 * goes to the same row of out (and pass). The whole loop over blocks is one function
 * per instruction set, chosen once per call. v[pl->nvals] and res[pl->nout] are
 * scratch. Unused lanes of the last block repeat its first ray so no lane computes on
 * garbage. */
__attribute__((target_clones("avx512f", "avx2", "default"))) static void
run_blocks(const poly_system *s, const poly_plan *pl, int what, size_t n, const size_t *idx,
           size_t first, const double *in, double *out, unsigned char *pass, vblk *v,
           vblk *res)
{
    const int nin = s->nin, nres = pl->nout, np = pl->nprod;
    const int *pr = pl->prod;
    vblk *d = v + 1 + nin;
    for (size_t b0 = 0; b0 < n; b0 += BLK) {
        const int m = n - b0 < BLK ? (int)(n - b0) : BLK;
        size_t row[BLK];
        for (int r = 0; r < BLK; r++) {
            size_t k = b0 + (size_t)(r < m ? r : 0);
            row[r] = idx ? idx[k] : first + k;
        }
        for (int r = 0; r < BLK; r++)
            v[0][r] = 1;
        for (int i = 0; i < nin; i++) {
            double col[BLK];
            for (int r = 0; r < BLK; r++)
                col[r] = in[row[r] * (size_t)nin + (size_t)i];
            poly_scale_column(s, i, col, BLK);
            memcpy(&v[1 + i], col, sizeof col);
        }
        for (int j = 0; j < np; j++)
            d[j] = v[pr[2 * j]] * v[pr[2 * j + 1]];
        for (int o = 0; o < nres; o++) {
            const int t0 = pl->start[o], ns = pl->nsingle[o], nf = pl->start[o + 1] - t0 - ns;
            const double *c = pl->coef + t0;
            const int *fa = pl->fa + t0;
            vblk a0 = {0}, a1 = {0}, a2 = {0}, a3 = {0};
            int t = 0;
            for (; t + 4 <= ns; t += 4) {
                a0 += c[t] * v[fa[t]];
                a1 += c[t + 1] * v[fa[t + 1]];
                a2 += c[t + 2] * v[fa[t + 2]];
                a3 += c[t + 3] * v[fa[t + 3]];
            }
            if (t < ns)
                a0 += c[t] * v[fa[t]];
            if (t + 1 < ns)
                a1 += c[t + 1] * v[fa[t + 1]];
            if (t + 2 < ns)
                a2 += c[t + 2] * v[fa[t + 2]];
            c += ns;
            fa += ns;
            const int *fb = pl->fb + t0 + ns;
            for (t = 0; t + 4 <= nf; t += 4) {
                a0 += c[t] * (v[fa[t]] * v[fb[t]]);
                a1 += c[t + 1] * (v[fa[t + 1]] * v[fb[t + 1]]);
                a2 += c[t + 2] * (v[fa[t + 2]] * v[fb[t + 2]]);
                a3 += c[t + 3] * (v[fa[t + 3]] * v[fb[t + 3]]);
            }
            if (t < nf)
                a0 += c[t] * (v[fa[t]] * v[fb[t]]);
            if (t + 1 < nf)
                a1 += c[t + 1] * (v[fa[t + 1]] * v[fb[t + 1]]);
            if (t + 2 < nf)
                a2 += c[t + 2] * (v[fa[t + 2]] * v[fb[t + 2]]);
            res[o] = (a0 + a1) + (a2 + a3);
        }
        if (what == RUN_JAC) {
            for (int r = 0; r < m; r++) {
                const double *x = in + row[r] * (size_t)nin;
                double *jr = out + row[r] * (size_t)nres;
                for (int k = 0; k < nres; k++)
                    jr[k] = poly_scale_chain(s, k % nin, x[k % nin], res[k][r]);
            }
            continue;
        }
        /* the passage test of passes(), per lane (all bits set: passes) */
        vmask ok = res[0] == res[0];
        for (int o = 0; o < nres; o++)
            ok &= (res[o] - res[o]) == 0; /* finite: inf - inf and nan give nan */
        for (int c = 0; c < s->ncircles; c++) {
            const vblk a = res[s->circles[c].a], b = res[s->circles[c].b];
            const double rad = s->circles[c].radius;
            ok &= a * a + b * b <= rad * rad;
        }
        for (int r = 0; r < m; r++) {
            double *o = out + row[r] * (size_t)nres;
            for (int k = 0; k < nres; k++)
                o[k] = res[k][r];
            if (pass)
                pass[row[r]] = ok[r] != 0;
        }
    }
}

/* The batch driver of poly_eval_batch and poly_eval_jacobian_batch: rays in runs of one
 * part (each chunk counting-sorted by part when there are several). */
static void batch(const poly_system *s, int what, size_t count, const double *in, double *out,
                  unsigned char *pass)
{
    const int nw = what == RUN_JAC ? s->nout * s->nin : s->nout;
    if (count == 0)
        return;
    int maxv = 0, maxo = nw;
    for (int p = 0; p < s->nparts; p++) {
        const poly_plan *pl = what == RUN_JAC ? &s->parts[p].dplan : &s->parts[p].plan;
        if (pl->nvals > maxv)
            maxv = pl->nvals;
    }
    vblk *v = s->nparts ? aligned_alloc(sizeof(vblk), (size_t)maxv * sizeof(vblk)) : NULL;
    vblk *res = aligned_alloc(sizeof(vblk), (size_t)maxo * sizeof(vblk));
    size_t *idx = s->nparts > 1 ? malloc(CHUNK * sizeof(size_t)) : NULL;
    int *part = s->nparts > 1 ? malloc(CHUNK * sizeof(int)) : NULL;
    int *start = calloc((size_t)s->nparts + 1, sizeof(int));
    int *cur = calloc((size_t)s->nparts + 1, sizeof(int));
    if (!v || !res || !start || !cur || (s->nparts > 1 && (!idx || !part))) {
        /* no parts, or out of memory: the rays do not pass */
        for (size_t r = 0; r < count; r++) {
            fill_nan(out + r * (size_t)nw, nw);
            if (pass)
                pass[r] = 0;
        }
    } else if (s->nparts == 1) {
        const poly_plan *pl = what == RUN_JAC ? &s->parts[0].dplan : &s->parts[0].plan;
        run_blocks(s, pl, what, count, NULL, 0, in, out, pass, v, res);
    } else {
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
            for (int q = 0; q < s->nparts; q++) {
                const poly_plan *pl = what == RUN_JAC ? &s->parts[q].dplan : &s->parts[q].plan;
                if (start[q + 1] > start[q])
                    run_blocks(s, pl, what, (size_t)(start[q + 1] - start[q]), idx + start[q],
                               0, in, out, pass, v, res);
            }
        }
    }
    free(v);
    free(res);
    free(idx);
    free(part);
    free(start);
    free(cur);
}

void poly_eval_batch(const poly_system *s, size_t count, const double *in, double *out,
                     unsigned char *pass)
{
    batch(s, RUN_EVAL, count, in, out, pass);
}

void poly_eval_jacobian_batch(const poly_system *s, size_t count, const double *in,
                              double *jac)
{
    batch(s, RUN_JAC, count, in, jac, NULL);
}

int poly_eval_jacobian(const poly_system *s, const double *in, double *out, double *jac)
{
    const int nin = s->nin, nout = s->nout;
    int pass = poly_eval(s, in, out);
    if (s->nparts == 0 ||
        run_one(s, &s->parts[poly_select_part(s, in)].dplan, in, jac) != 0) {
        fill_nan(jac, nin * nout);
        return 0;
    }
    for (int k = 0; k < nin * nout; k++)
        jac[k] = poly_scale_chain(s, k % nin, in[k % nin], jac[k]);
    return pass;
}
