/* The batch kernel of poly_eval.c, included there once per instruction set with
 *   KERNEL_NAME    the function's name
 *   KERNEL_TARGET  its target attribute (empty for the baseline)
 *   VW             doubles per hardware vector of that set (8 AVX-512, 4 AVX2, 2 SSE)
 * and KBLK (rays per block, a multiple of VW) and RUN_EVAL / RUN_JAC defined.
 *
 * Runs plan pl on n rays: ray r is row idx[r] of in (row first + r if idx is NULL) and
 * goes to the same row of out (and pass). A block is NV = KBLK / VW vectors; the loops
 * over q < NV have constant bounds and are unrolled, so the partial sums stay in
 * registers (one vector type of KBLK lanes would be split by the compiler through the
 * stack). vbuf (nvals x KBLK), resbuf (nout x KBLK) and off (2 nprod + 2 nterms) are
 * scratch, 64-byte aligned; value k of lane r is vbuf[k * KBLK + r]. Unused lanes of the
 * last block repeat its first ray so no lane computes on garbage. Only IEEE multiplies,
 * adds and divides, never contracted: every instruction set gives the bits of the scalar
 * path. No include guard: meant to be included several times. */
#define NV (KBLK / VW)

KERNEL_TARGET static void KERNEL_NAME(const poly_system *s, const poly_plan *pl, int what,
                                      size_t n, const size_t *idx, size_t first,
                                      const double *in, double *out, unsigned char *pass,
                                      double *vbuf, double *resbuf, int *off)
{
    typedef double vn __attribute__((vector_size(VW * sizeof(double))));
    typedef long long vmask __attribute__((vector_size(VW * sizeof(long long))));
    vn *v = (vn *)vbuf, *res = (vn *)resbuf;
    const int nin = s->nin, nres = pl->nout, np = pl->nprod, nt = pl->start[nres];
    /* the plan's value numbers as offsets in doubles into v: one load each, no
     * arithmetic on the index (half the integer work of the loops below) */
    int *pr = off, *fa_off = off + 2 * np, *fb_off = fa_off + nt;
    for (int j = 0; j < 2 * np; j++)
        pr[j] = pl->prod[j] * KBLK;
    for (int t = 0; t < nt; t++) {
        fa_off[t] = pl->fa[t] * KBLK;
        fb_off[t] = pl->fb[t] * KBLK;
    }
    const double *vd = (const double *)v;
    vn *d = v + (1 + nin) * NV;
    for (size_t b0 = 0; b0 < n; b0 += KBLK) {
        const int m = n - b0 < KBLK ? (int)(n - b0) : KBLK;
        const double *src[KBLK];
        size_t row[KBLK];
        for (int r = 0; r < KBLK; r++) {
            size_t k = b0 + (size_t)(r < m ? r : 0);
            row[r] = idx ? idx[k] : first + k;
            src[r] = in + row[r] * (size_t)nin;
        }
        for (int q = 0; q < NV; q++)
            for (int r = 0; r < VW; r++)
                v[q][r] = 1;
        for (int i = 0; i < nin; i++) {
            double col[KBLK];
            for (int r = 0; r < KBLK; r++)
                col[r] = src[r][i];
            poly_scale_column(s, i, col, KBLK);
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
        const double *rs = (const double *)res; /* output k of lane r at rs[k * KBLK + r] */
        if (what == RUN_JAC) {
            for (int r = 0; r < m; r++) {
                double *jr = out + row[r] * (size_t)nres;
                for (int k = 0; k < nres; k++)
                    jr[k] = poly_scale_chain(s, k % nin, src[r][k % nin], rs[k * KBLK + r]);
            }
            continue;
        }
        for (int r = 0; r < m; r++) {
            double *o = out + row[r] * (size_t)nres;
            for (int k = 0; k < nres; k++)
                o[k] = rs[k * KBLK + r];
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

#undef NV
