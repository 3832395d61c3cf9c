/* The batch kernel of poly_eval.c, included there once per instruction set with
 *   KERNEL_NAME    the function's name
 *   KERNEL_TARGET  its target attribute (empty for the baseline)
 *   VW             doubles per hardware vector of that set (8 AVX-512, 4 AVX2, 2 SSE)
 *   KERNEL_SQRT    the square root of a vector of VW doubles (that set's instruction)
 * and KBLK (rays per block, a multiple of VW) and RUN_EVAL / RUN_JAC / RUN_CORE / RUN_JACF;
 * optionally KERNEL_WHOLE_ROWS: rows of more than 32 and at most that many columns (a
 * Jacobian's) put together block by block in fbuf and copied out whole; with it
 * KERNEL_STREAM(dst, src, n), KERNEL_STREAM_FENCE() and KERNEL_STREAM_MIN: a Jacobian's
 * rows of more bytes than that copied out past the caches (batch() sizes fbuf for them).
 *
 * Runs the plans pls[0 .. nview - 1] (one part's views, see part_plans()) on n rays: ray r
 * is row idx[r] of in (row first + r if idx is NULL) and goes to the same row of out (and
 * pass), its columns and the sums it computes and tests as job says (batch_job in
 * poly_eval.c). With RUN_EVAL and RUN_JACF the system's frame and transforms are applied
 * in the block too (the arithmetic of poly_frame.c on whole columns), so a framed system
 * costs one pass over its rays, its views' terms and a few operations per ray more;
 * RUN_JACF then runs poly_frame_chain on the block's columns. A block is NV = KBLK / VW
 * vectors; the loops over q < NV have constant bounds and are unrolled, so the partial
 * sums stay in registers (one vector type of KBLK lanes would be split by the compiler
 * through the stack). vbuf (nvals x KBLK), resbuf (every plan's sums x KBLK), fbuf ((nin
 * + 3) x KBLK, with RUN_JACF (4 nin + 12 + nout nin) x KBLK, and then with rows of 33
 * to 128 columns KBLK x the columns more) and offbuf (2 nprod + 2
 * nterms per plan) are scratch, 64-byte
 * aligned; value k of lane r is vbuf[k * KBLK + r]. Unused lanes of the last block repeat
 * its first ray so no lane computes on garbage. Only IEEE multiplies, adds, divides and
 * square roots, never contracted: every instruction set gives the bits of the scalar
 * path; except, with KERNEL_FMA defined (AVX-512), the sums of a Jacobian run (RUN_JAC,
 * RUN_JACF), which fuse each term's multiply and add (the Jacobian is allowed 1e-12
 * relative; poly_eval_sums.h says what it bought). No include guard: meant to be
 * included several times.
 * Long function: a block's whole pass (inputs, frame, plans, chain rule, stores, pass
 * test) is one body so that the block's vectors stay in registers between the steps;
 * its parts are the plans' sums (poly_eval_sums.h) and poly_frame_chain. */
#define NV (KBLK / VW)

KERNEL_TARGET static void KERNEL_NAME(const poly_system *s, const poly_plan *const *pls, int nview,
                                      int what, size_t n, const size_t *idx, size_t first,
                                      const double *in, double *out, unsigned char *pass,
                                      const batch_job *job, double *vbuf, double *resbuf,
                                      double *fbuf, int *offbuf)
{
    typedef double vn __attribute__((vector_size(VW * sizeof(double))));
    typedef long long vmask __attribute__((vector_size(VW * sizeof(long long))));
#ifdef KERNEL_SCATTER
    typedef long long vidx __attribute__((vector_size(VW * sizeof(long long))));
#endif
    vn *v = (vn *)vbuf;
    const int nin = s->nin, nres = pls[0]->nout;
    const int nst = job->nsel, *sel = job->sel; /* res[sel[j]] goes to column j of out */
    const int jf = what == RUN_JACF; /* the chain rule through the frame, per block */
    /* the frame (poly_frame.c) done here, on whole columns of the block, in the order of
     * poly_frame_in / poly_frame_out: view 0 sees the rotated and transformed inputs,
     * view 1 (if any) the transformed ones, and gives the outputs outside the frame */
    const int fr = (what == RUN_EVAL || jf) && s->frame == POLY_FRAME_MERIDIONAL;
    const int xf = (what == RUN_EVAL || jf) && s->nxform > 0;
    const int ix = s->ix, iy = s->iy, iu = s->iu, iv = s->iv;
    /* RUN_JACF: the chain rule may write over the derivatives (poly_frame_chain_in_place) */
    const int in_place = jf && poly_frame_chain_in_place(s, nview > 2);
    double *raw = fbuf, *rad = fbuf + (size_t)nin * KBLK, *cb = rad + KBLK, *sb = cb + KBLK;
    /* RUN_JACF: the inputs rotated (not transformed), the chain rule's scratch, its result */
    double *wcol = sb + KBLK, *gcol = wcol + (size_t)nin * KBLK;
    double *jcol = gcol + (2 * (size_t)nin + 9) * KBLK;
    if (jf && !fr)
        for (int r = 0; r < KBLK; r++) {
            cb[r] = 1;
            sb[r] = 0;
        }
    /* the plans' value numbers as offsets in doubles into v: one load each, no
     * arithmetic on the index (half the integer work of the loops below) */
    int *offs[3];
    for (int w = 0; w < nview; w++) {
        const poly_plan *pl = pls[w];
        const int np = pl->nprod, nt = pl->start[pl->nout];
        int *pr = offs[w] = offbuf, *fa_off = pr + 2 * np, *fb_off = fa_off + nt;
        offbuf = fb_off + nt;
        for (int j = 0; j < 2 * np; j++)
            pr[j] = pl->prod[j] * KBLK;
        for (int t = 0; t < nt; t++) {
            fa_off[t] = pl->fa[t] * KBLK;
            fb_off[t] = pl->fb[t] * KBLK;
        }
    }
    const double *vd = (const double *)v;
    vn *d = v + (1 + nin) * NV;
#ifdef KERNEL_WHOLE_ROWS
    /* A row's 8-column stores each straddle a cache line and touch every line of the
     * block's rows several times; in place first, then copied out line after line:
     * bench_poly, the 19-output fisheye-ii fit's Jacobian (95 columns), 20000 rays: 267-302
     * -> 201-214 ns a ray; no change at 25 columns (5 outputs). In fbuf after the
     * columns in use (batch() sizes it; on the stack here it had cost the 5-output
     * Jacobian 1-2 % by moving the kernel's frame) */
    double *sbuf = jf ? jcol + (size_t)s->nout * (size_t)nin * KBLK : wcol;
#ifdef KERNEL_STREAM
    /* a Jacobian's rows larger than the cache: past it (KERNEL_STREAM, poly_eval_rows.h) */
    const int stream = (jf || what == RUN_JAC) && !idx && nst <= KERNEL_WHOLE_ROWS &&
                       (size_t)n * (size_t)nst * sizeof(double) > KERNEL_STREAM_MIN;
#else
    const int stream = 0;
#endif
    const int whole = ((nst > 32 && nst <= KERNEL_WHOLE_ROWS) || stream) && !idx;
#endif
    for (size_t b0 = 0; b0 < n; b0 += KBLK) {
        const int m = n - b0 < KBLK ? (int)(n - b0) : KBLK;
        size_t row[KBLK];
        for (int r = 0; r < KBLK; r++) {
            size_t k = b0 + (size_t)(r < m ? r : 0);
            row[r] = idx ? idx[k] : first + k;
        }
        for (int q = 0; q < NV; q++)
            for (int r = 0; r < VW; r++)
                v[q][r] = 1;
#ifdef KERNEL_SCATTER
#ifdef KERNEL_LOAD_COLS5
        if (nin == 5 && !idx && m == KBLK)
            for (int q = 0; q < NV; q++) {
                vn cols[5];
                KERNEL_LOAD_COLS5(in + (first + b0 + (size_t)q * VW) * 5, cols);
                for (int i = 0; i < 5; i++)
                    ((vn *)raw)[i * NV + q] = cols[i];
            }
        else
#endif
            for (int q = 0; q < NV; q++) {
                vidx at;
                for (int r = 0; r < VW; r++)
                    at[r] = (long long)row[q * VW + r] * nin;
                for (int i = 0; i < nin; i++)
                    ((vn *)raw)[i * NV + q] = KERNEL_GATHER(in + i, at);
            }
#else
        for (int i = 0; i < nin; i++)
            for (int r = 0; r < KBLK; r++)
                raw[i * KBLK + r] = in[row[r] * (size_t)nin + i];
#endif
        if (fr) {
            const double *X = raw + ix * KBLK, *Y = raw + iy * KBLK;
            for (int q = 0; q < NV; q++) {
                /* r > 0 ? x * (1 / r) : 1 and r > 0 ? y * (1 / r) : 0 by mask (0 * inf lanes dropped) */
                const vn x = ((const vn *)X)[q], y = ((const vn *)Y)[q];
                const vn rr = KERNEL_SQRT(x * x + y * y);
                const vmask pos = rr > 0;
                ((vn *)rad)[q] = rr;
                const vn ir = 1 / rr; /* inf on the axis, dropped by the mask */
                ((vn *)cb)[q] = (vn)(((vmask)(x * ir) & pos) | ((vmask)((vn){0} + 1) & ~pos));
                ((vn *)sb)[q] = (vn)((vmask)(y * ir) & pos);
            }
        }
        for (int w = 0; w < nview; w++) {
            const poly_plan *pl = pls[w];
            const int np = pl->nprod, nsum = pl->nout, kind = job->kind[w];
            const int *pr = offs[w], *fa_off = pr + 2 * np;
            vn *res = (vn *)resbuf + (size_t)job->roff[w] * NV;
            const unsigned char *need = job->need[w];
            for (int i = 0; i < nin && !(w > 0 && kind == job->kind[w - 1]); i++) {
                _Alignas(64) double col[KBLK]; /* aligned: a split vector access here cost up to 2x, by stack position */
                const double *X = raw + i * KBLK;
                const int turns = fr && (i == ix || i == iy || i == iu || i == iv);
                if (w > 0 && !turns)
                    continue; /* the same value as in view 0, still in place */
                if (turns && kind == 0) {
                    const double *U = raw + iu * KBLK, *V = raw + iv * KBLK;
                    for (int r = 0; r < KBLK; r++)
                        col[r] = i == ix   ? rad[r]
                                 : i == iy ? 0
                                 : i == iu ? cb[r] * U[r] + sb[r] * V[r]
                                           : cb[r] * V[r] - sb[r] * U[r];
                } else {
                    memcpy(col, X, sizeof col);
                }
                if (jf && kind == 0)
                    memcpy(wcol + i * KBLK, col, sizeof col);
                if (xf && s->xform[i] == POLY_XFORM_INVERSE_SQUARE)
                    for (int r = 0; r < KBLK; r++)
                        col[r] = 1 / (col[r] * col[r]);
                poly_scale_column(s, i, col, KBLK);
                memcpy(&v[(1 + i) * NV], col, sizeof col);
            }
            for (int j = 0; j < np; j++) {
                const vn *x = (const vn *)(vd + pr[2 * j]), *y = (const vn *)(vd + pr[2 * j + 1]);
                for (int q = 0; q < NV; q++)
                    d[j * NV + q] = x[q] * y[q];
            }
            const int *fb_off = fa_off + pl->start[nsum];
#ifdef KERNEL_FMA
            if (what == RUN_JACF || what == RUN_JAC) { /* fused: poly_eval_sums.h */
#define KERNEL_FUSED 1
#include "poly/poly_eval_sums.h"
#undef KERNEL_FUSED
            } else
#endif
            {
#define KERNEL_FUSED 0
#include "poly/poly_eval_sums.h"
#undef KERNEL_FUSED
            }
            if (job->deriv[w]) /* d / d s_i to d / d in_i (poly_scale_chain), on whole vectors */
                for (int k = 0; k < nsum; k++) {
                    const double inv = 1 / s->scale[k % nin];
                    for (int q = 0; q < NV; q++)
                        res[k * NV + q] *= inv;
                }
        }
        vn *res = (vn *)resbuf;
        if (jf) { /* poly_frame.c's chain rule on the block's columns, into jcol */
            /* over the derivatives where it may: the block's data is more than the L1
             * cache holds, and 6 KiB less of it (5 outputs) took bench_poly's batch
             * Jacobian (20000 rays, the 5-output fisheye-ii fit) from 63.4-64.3 to
             * 60.9-62.3 ns a ray, in turn with the build before; the same bits */
            double *J = resbuf + (size_t)job->roff[1 - job->vview] * KBLK;
            double *jc = in_place ? J : jcol;
            const poly_chain_cols k = {KBLK, raw, wcol, cb, sb,
                                       resbuf + (size_t)job->roff[job->vview] * KBLK, J,
                                       nview > 2 ? resbuf + (size_t)job->roff[2] * KBLK : NULL,
                                       gcol, jc, NULL};
            poly_frame_chain(s, nview > 2, &k);
            res = (vn *)jc;
        } else if (nview > 1) /* the outputs outside the frame from view 1 */
            for (int o = 0; o < nres; o++)
                if (s->plain && s->plain[o])
                    for (int q = 0; q < NV; q++)
                        res[o * NV + q] = res[(nres + o) * NV + q];
        if (pass && what == RUN_EVAL) {
            /* the passage test of poly_passes, per lane (bit set: passes), on the frame's
             * values as in poly_eval_part; circle by circle, each one's outputs and
             * radius fetched once a block (per vector they had cost the faithful
             * passage's eight circles more than the compares) */
            unsigned bits[NV];
            for (int q = 0; q < NV; q++)
                bits[q] = (1u << VW) - 1;
#ifdef KERNEL_LE_BITS
            /* compares into mask registers, each under the last one's mask, where
             * vector masks took a move and an and each */
            const vn zero = {0};
            for (int k = 0; k < job->nfinite; k++) {
                const vn *x = res + job->finite[k] * NV;
                for (int q = 0; q < NV; q++) /* inf - inf, nan: nan, not <= 0 */
                    bits[q] = KERNEL_LE_BITS(bits[q], x[q] - x[q], zero);
            }
            for (int c = 0; c < s->ncircles; c++) {
                const vn *A = res + s->circles[c].a * NV, *B = res + s->circles[c].b * NV;
                const vn r2 = (s->circles[c].radius * s->circles[c].radius) - zero;
                for (int q = 0; q < NV; q++)
                    bits[q] = KERNEL_LE_BITS(bits[q], A[q] * A[q] + B[q] * B[q], r2);
            }
#else
            vmask ok[NV];
            for (int q = 0; q < NV; q++)
                ok[q] = ~(vmask){0};
            for (int k = 0; k < job->nfinite; k++) {
                const vn *x = res + job->finite[k] * NV;
                for (int q = 0; q < NV; q++)
                    ok[q] &= (x[q] - x[q]) == 0; /* inf - inf, nan: nan */
            }
            for (int c = 0; c < s->ncircles; c++) {
                const vn *A = res + s->circles[c].a * NV, *B = res + s->circles[c].b * NV;
                const double r2 = s->circles[c].radius * s->circles[c].radius;
                for (int q = 0; q < NV; q++)
                    ok[q] &= A[q] * A[q] + B[q] * B[q] <= r2;
            }
            for (int q = 0; q < NV; q++) {
                bits[q] = 0;
                for (int r = 0; r < VW; r++)
                    bits[q] |= (unsigned)(ok[q][r] != 0) << r;
            }
#endif
            /* a whole block of consecutive rows: eight flags a store (x86, little-endian:
             * byte r is lane r's). With the test above, in the same process as the code
             * before (interleaved, best of 300 calls of 20000 rays, the default
             * fisheye-ii fit): 26.8 -> 25.6-26.0 ns a ray writing its optical outputs,
             * 33.6 -> 32.8 writing all 19; its five optical outputs alone (one circle)
             * 18.7-18.9 -> 18.2-18.3 */
            if (VW == 8 && !idx && m == KBLK)
                for (int q = 0; q < NV; q++) {
                    /* byte r of the product is bits & 1 << r; + 0x7f carries a set bit
                     * into that byte's top bit */
                    const unsigned long long ones = 0x0101010101010101ULL;
                    const unsigned long long t = (bits[q] * ones) & 0x8040201008040201ULL;
                    const unsigned long long flags = ((t + 0x7f7f7f7f7f7f7f7fULL) >> 7) & ones;
                    memcpy(pass + first + b0 + (size_t)q * VW, &flags, 8);
                }
            else
                for (int r = 0; r < m; r++)
                    pass[row[r]] = bits[r / VW] >> (r % VW) & 1;
        }
        if (fr && !jf) {
            const vn *C = (const vn *)cb, *S = (const vn *)sb;
            for (int k = 0; k < s->npairs; k++) {
                const int pa = s->pair[2 * k], pb = s->pair[2 * k + 1];
                if (!job->need[0][pa] || !(job->written[pa] || job->written[pb]))
                    continue; /* pairs turn: view 0's, where they are written */
                vn *A = res + pa * NV, *B = res + pb * NV;
                for (int q = 0; q < NV; q++) {
                    const vn a = A[q], b = B[q];
                    A[q] = C[q] * a - S[q] * b;
                    B[q] = S[q] * a + C[q] * b;
                }
            }
        }
#ifdef KERNEL_SCATTER
#ifdef KERNEL_STORE_ROWS5
        if (nst == 5 && !idx && m == KBLK)
            for (int q = 0; q < NV; q++) {
                const vn cols[5] = {res[sel[0] * NV + q], res[sel[1] * NV + q],
                                    res[sel[2] * NV + q], res[sel[3] * NV + q],
                                    res[sel[4] * NV + q]};
                KERNEL_STORE_ROWS5(out + (first + b0 + (size_t)q * VW) * 5, cols);
            }
        else
#endif
#ifdef KERNEL_STORE_ROWS8
        {
            double *dst = out; /* rows row[r] of dst */
            const size_t *at = row;
#ifdef KERNEL_WHOLE_ROWS
            size_t here[KBLK]; /* the block's rows first in sbuf, in order */
            const int st = whole && m == KBLK;
            if (st) {
                for (int r = 0; r < KBLK; r++)
                    here[r] = (size_t)r;
                dst = sbuf;
                at = here;
            }
#endif
            for (int q = 0; q < NV; q++)
                for (int k0 = 0; k0 < nst; k0 += 8) {
                    vn cols[8];
                    const int nc = nst - k0 < 8 ? nst - k0 : 8;
                    for (int j = 0; j < nc; j++)
                        cols[j] = res[sel[k0 + j] * NV + q];
                    KERNEL_STORE_ROWS8(dst, at + q * VW, (size_t)nst, (size_t)k0, cols, nc);
                }
#ifdef KERNEL_WHOLE_ROWS
#ifdef KERNEL_STREAM
            if (st && stream)
                KERNEL_STREAM(out + (first + b0) * (size_t)nst, sbuf, (size_t)nst * KBLK);
            else
#endif
            if (st)
                memcpy(out + (first + b0) * (size_t)nst, sbuf, sizeof(double) * (size_t)nst * KBLK);
#endif
        }
#else
            for (int q = 0; q < NV; q++) {
                vidx at;
                for (int r = 0; r < VW; r++)
                    at[r] = (long long)row[q * VW + r] * nst;
                for (int k = 0; k < nst; k++)
                    KERNEL_SCATTER(out + k, at, res[sel[k] * NV + q]);
            }
#endif
#else
        const double *rs = (const double *)res; /* output k of lane r at rs[k * KBLK + r] */
        for (int r = 0; r < m; r++) {
            double *o = out + row[r] * (size_t)nst;
            for (int k = 0; k < nst; k++)
                o[k] = rs[sel[k] * KBLK + r];
        }
#endif
    }
#ifdef KERNEL_STREAM
    if (stream)
        KERNEL_STREAM_FENCE(); /* the streamed rows before anything after */
#endif
}

#undef NV
