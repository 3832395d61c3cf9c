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

/* A block is NV vectors of VW rays (GCC/clang vector extension). VW = 8 is one AVX-512
 * register (two AVX2 ones); the loops over q < NV below have constant bounds and are
 * unrolled, so the partial sums stay in registers. (A single vector type of BLK lanes
 * would be split by the compiler through the stack.) Only IEEE multiplies, adds and
 * divides, never contracted: every clone gives the same bits as the scalar path. */
#define VW 8
#define NV (BLK / VW)
typedef double vn __attribute__((vector_size(VW * sizeof(double))));
typedef long long vmask __attribute__((vector_size(VW * sizeof(long long))));

/* What a batch run computes: the outputs with the passage test, or the derivatives
 * d out_o / d in_i of the derivative plan (chain rule applied). */
enum { RUN_EVAL, RUN_JAC };

/* Runs plan pl on n rays: ray r is row idx[r] of in (row first + r if idx is NULL) and
 * goes to the same row of out (and pass). The whole loop over blocks is one function
 * per instruction set, chosen once per call. v[pl->nvals * NV] and res[pl->nout * NV]
 * are scratch (value k of lanes q * VW.. at v[k * NV + q]). Unused lanes of the last
 * block repeat its first ray so no lane computes on garbage. */
__attribute__((target_clones("avx512f", "avx2", "default"))) static void
run_blocks(const poly_system *s, const poly_plan *pl, int what, size_t n, const size_t *idx,
           size_t first, const double *in, double *out, unsigned char *pass, vn *v, vn *res,
           int *off)
{
    const int nin = s->nin, nres = pl->nout, np = pl->nprod, nt = pl->start[nres];
    /* the plan's value numbers as offsets in doubles into v: one load each, no
     * arithmetic on the index (half the integer work of the loops below) */
    int *pr = off, *fa_off = off + 2 * np, *fb_off = fa_off + nt;
    for (int j = 0; j < 2 * np; j++)
        pr[j] = pl->prod[j] * BLK;
    for (int t = 0; t < nt; t++) {
        fa_off[t] = pl->fa[t] * BLK;
        fb_off[t] = pl->fb[t] * BLK;
    }
    const double *vd = (const double *)v;
    vn *d = v + (1 + nin) * NV;
    for (size_t b0 = 0; b0 < n; b0 += BLK) {
        const int m = n - b0 < BLK ? (int)(n - b0) : BLK;
        const double *src[BLK];
        size_t row[BLK];
        for (int r = 0; r < BLK; r++) {
            size_t k = b0 + (size_t)(r < m ? r : 0);
            row[r] = idx ? idx[k] : first + k;
            src[r] = in + row[r] * (size_t)nin;
        }
        for (int q = 0; q < NV; q++)
            for (int r = 0; r < VW; r++)
                v[q][r] = 1;
        for (int i = 0; i < nin; i++) {
            double col[BLK];
            for (int r = 0; r < BLK; r++)
                col[r] = src[r][i];
            poly_scale_column(s, i, col, BLK);
            memcpy(&v[(1 + i) * NV], col, sizeof col);
        }
        for (int j = 0; j < np; j++) {
            const vn *x = (const vn *)(vd + pr[2 * j]), *y = (const vn *)(vd + pr[2 * j + 1]);
            for (int q = 0; q < NV; q++)
                d[j * NV + q] = x[q] * y[q];
        }
        for (int o = 0; o < nres; o++) {
            const int t0 = pl->start[o], ns = pl->nsingle[o], nf = pl->start[o + 1] - t0 - ns;
            const double *c = pl->coef + t0;
            const int *fa = fa_off + t0;
            vn a0[NV], a1[NV], a2[NV], a3[NV];
            for (int q = 0; q < NV; q++)
                a0[q] = a1[q] = a2[q] = a3[q] = (vn){0};
#define SINGLE(acc, k)                                                                    \
    do {                                                                                   \
        const vn *x = (const vn *)(vd + fa[k]);                                            \
        const double ck = c[k];                                                            \
        for (int q = 0; q < NV; q++)                                                       \
            acc[q] += ck * x[q];                                                           \
    } while (0)
#define FUSED(acc, k)                                                                     \
    do {                                                                                   \
        const vn *x = (const vn *)(vd + fa[k]), *y = (const vn *)(vd + fb[k]);             \
        const double ck = c[k];                                                            \
        for (int q = 0; q < NV; q++)                                                       \
            acc[q] += ck * (x[q] * y[q]);                                                  \
    } while (0)
            int t = 0;
            for (; t + 4 <= ns; t += 4) {
                SINGLE(a0, t);
                SINGLE(a1, t + 1);
                SINGLE(a2, t + 2);
                SINGLE(a3, t + 3);
            }
            if (t < ns)
                SINGLE(a0, t);
            if (t + 1 < ns)
                SINGLE(a1, t + 1);
            if (t + 2 < ns)
                SINGLE(a2, t + 2);
            c += ns;
            fa += ns;
            const int *fb = fb_off + t0 + ns;
            for (t = 0; t + 4 <= nf; t += 4) {
                FUSED(a0, t);
                FUSED(a1, t + 1);
                FUSED(a2, t + 2);
                FUSED(a3, t + 3);
            }
            if (t < nf)
                FUSED(a0, t);
            if (t + 1 < nf)
                FUSED(a1, t + 1);
            if (t + 2 < nf)
                FUSED(a2, t + 2);
#undef SINGLE
#undef FUSED
            for (int q = 0; q < NV; q++)
                res[o * NV + q] = (a0[q] + a1[q]) + (a2[q] + a3[q]);
        }
        const double *rs = (const double *)res; /* output k of lane r at rs[k * BLK + r] */
        if (what == RUN_JAC) {
            for (int r = 0; r < m; r++) {
                double *jr = out + row[r] * (size_t)nres;
                for (int k = 0; k < nres; k++)
                    jr[k] = poly_scale_chain(s, k % nin, src[r][k % nin], rs[k * BLK + r]);
            }
            continue;
        }
        for (int r = 0; r < m; r++) {
            double *o = out + row[r] * (size_t)nres;
            for (int k = 0; k < nres; k++)
                o[k] = rs[k * BLK + r];
        }
        if (!pass)
            continue;
        for (int q = 0; q < NV; q++) {
            /* the passage test of passes(), per lane (all bits set: passes) */
            vmask ok = res[q] == res[q];
            for (int o = 0; o < nres; o++)
                ok &= (res[o * NV + q] - res[o * NV + q]) == 0; /* inf - inf, nan: nan */
            for (int c = 0; c < s->ncircles; c++) {
                const vn a = res[s->circles[c].a * NV + q], b = res[s->circles[c].b * NV + q];
                const double rad = s->circles[c].radius;
                ok &= a * a + b * b <= rad * rad;
            }
            for (int r = q * VW; r < m && r < (q + 1) * VW; r++)
                pass[row[r]] = ok[r % VW] != 0;
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
    size_t maxoff = 1;
    for (int p = 0; p < s->nparts; p++) {
        const poly_plan *pl = what == RUN_JAC ? &s->parts[p].dplan : &s->parts[p].plan;
        size_t no = 2 * (size_t)pl->nprod + 2 * (size_t)pl->start[pl->nout];
        if (pl->nvals > maxv)
            maxv = pl->nvals;
        if (no > maxoff)
            maxoff = no;
    }
    int *off = malloc(maxoff * sizeof(int));
    vn *v = s->nparts ? aligned_alloc(sizeof(vn), (size_t)maxv * NV * sizeof(vn)) : NULL;
    vn *res = aligned_alloc(sizeof(vn), (size_t)maxo * NV * sizeof(vn));
    size_t *idx = s->nparts > 1 ? malloc(CHUNK * sizeof(size_t)) : NULL;
    int *part = s->nparts > 1 ? malloc(CHUNK * sizeof(int)) : NULL;
    int *start = calloc((size_t)s->nparts + 1, sizeof(int));
    int *cur = calloc((size_t)s->nparts + 1, sizeof(int));
    if (!v || !res || !off || !start || !cur || (s->nparts > 1 && (!idx || !part))) {
        /* no parts, or out of memory: the rays do not pass */
        for (size_t r = 0; r < count; r++) {
            fill_nan(out + r * (size_t)nw, nw);
            if (pass)
                pass[r] = 0;
        }
    } else if (s->nparts == 1) {
        const poly_plan *pl = what == RUN_JAC ? &s->parts[0].dplan : &s->parts[0].plan;
        run_blocks(s, pl, what, count, NULL, 0, in, out, pass, v, res, off);
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
                               0, in, out, pass, v, res, off);
            }
        }
    }
    free(v);
    free(res);
    free(off);
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
