/* The sums of one view's plan over a block, the middle of poly_eval_kernel.h's pass:
 * included there in the body of the kernel, where pl, nsum, need, fa_off, fb_off, vd,
 * res, vn and NV are in scope, with KERNEL_FUSED 0 and, in an instantiation that
 * defines KERNEL_FMA (AVX-512's: a * b + c rounded once), once more with KERNEL_FUSED 1.
 * KERNEL_FUSED 0: every item as separate IEEE multiplies and adds, the bits of the
 * one-ray path (poly_eval.c's sums_one), of the emitted C and of lens-eval.
 * KERNEL_FUSED 1: the same items in the same order with fused multiply-adds, for the
 * sums of a Jacobian run alone, which may differ from the unfused sums by 1e-12
 * relative (the Jacobian's stated tolerance; test_poly and test_poly_fast check the batch Jacobian against
 * the one-ray one so): a single term is one operation instead of two, a quad five
 * instead of nine, a pair three instead of five, a lone term two instead of three.
 * bench_poly on the default fisheye-ii fit with its five optical outputs, best of 6
 * interleaved rounds: batch Jacobian 65.1 -> 60.5 ns a ray at 2000 rays, 66.4 -> 64.2
 * at 20000 (there its rows' stores past the cache weigh more); the sums are now bound
 * by loads (a term's value, index and coefficient), no longer by the vector ports.
 * No include guard: meant to be included several times. */
for (int o = 0; o < nsum; o++) {
    if (!need[o])
        continue; /* not asked for, or the other view's (res stays 0) */
    const int t0 = pl->start[o], ns = pl->nsingle[o];
    const int nq = pl->nquad[o], npr = pl->npair[o];
    const int nl = pl->start[o + 1] - t0 - ns - 4 * nq - 2 * npr;
    const double *c = pl->coef;
    const int *fa = fa_off, *fb = fb_off;
    vn a0[NV], a1[NV], a2[NV], a3[NV];
/* the items of the plan (poly_impl.h) at planned term k, into acc */
#define V(k) ((const vn *)(vd + fa[k]))
#if KERNEL_FUSED
/* a coefficient in every lane (c - 0 is c, even -0: the compiler drops the subtraction) */
#define SPLAT(c) ((c) - (vn){0})
#define SINGLE(acc, k)                                                                 \
    do {                                                                               \
        const vn *x = V(k), ck = SPLAT(c[k]);                                          \
        for (int q = 0; q < NV; q++)                                                   \
            acc[q] = KERNEL_FMA(ck, x[q], acc[q]);                                     \
    } while (0)
#define QUAD(acc, k)                                                                   \
    do {                                                                               \
        const vn *x0 = V(k), *x1 = V((k) + 1), *x2 = V((k) + 2), *x3 = V((k) + 3);     \
        const vn *y = (const vn *)(vd + fb[k]);                                        \
        const vn c0 = SPLAT(c[k]), c1 = SPLAT(c[(k) + 1]);                             \
        const vn c2 = SPLAT(c[(k) + 2]), c3 = SPLAT(c[(k) + 3]);                       \
        for (int q = 0; q < NV; q++) {                                                 \
            const vn t = KERNEL_FMA(c1, x1[q], KERNEL_FMA(c2, x2[q], c3 * x3[q]));     \
            acc[q] = KERNEL_FMA(KERNEL_FMA(c0, x0[q], t), y[q], acc[q]);               \
        }                                                                              \
    } while (0)
#define PAIR(acc, k)                                                                   \
    do {                                                                               \
        const vn *x0 = V(k), *x1 = V((k) + 1), *y = (const vn *)(vd + fb[k]);          \
        const vn c0 = SPLAT(c[k]), c1 = SPLAT(c[(k) + 1]);                             \
        for (int q = 0; q < NV; q++)                                                   \
            acc[q] = KERNEL_FMA(KERNEL_FMA(c0, x0[q], c1 * x1[q]), y[q], acc[q]);      \
    } while (0)
#define LONE(acc, k)                                                                   \
    do {                                                                               \
        const vn *x0 = V(k), *y = (const vn *)(vd + fb[k]);                            \
        const vn c0 = SPLAT(c[k]);                                                     \
        for (int q = 0; q < NV; q++)                                                   \
            acc[q] = KERNEL_FMA(c0 * x0[q], y[q], acc[q]);                             \
    } while (0)
#else
#define SINGLE(acc, k)                                                                 \
    do {                                                                               \
        const vn *x = V(k);                                                            \
        const double ck = c[k];                                                        \
        for (int q = 0; q < NV; q++)                                                   \
            acc[q] += ck * x[q];                                                       \
    } while (0)
#define QUAD(acc, k)                                                                   \
    do {                                                                               \
        const vn *x0 = V(k), *x1 = V((k) + 1), *x2 = V((k) + 2), *x3 = V((k) + 3);     \
        const vn *y = (const vn *)(vd + fb[k]);                                        \
        const double c0 = c[k], c1 = c[(k) + 1], c2 = c[(k) + 2], c3 = c[(k) + 3];     \
        for (int q = 0; q < NV; q++)                                                   \
            acc[q] += ((c0 * x0[q] + c1 * x1[q]) + (c2 * x2[q] + c3 * x3[q])) * y[q];  \
    } while (0)
#define PAIR(acc, k)                                                                   \
    do {                                                                               \
        const vn *x0 = V(k), *x1 = V((k) + 1), *y = (const vn *)(vd + fb[k]);          \
        const double c0 = c[k], c1 = c[(k) + 1];                                       \
        for (int q = 0; q < NV; q++)                                                   \
            acc[q] += (c0 * x0[q] + c1 * x1[q]) * y[q];                                \
    } while (0)
#define LONE(acc, k)                                                                   \
    do {                                                                               \
        const vn *x0 = V(k), *y = (const vn *)(vd + fb[k]);                            \
        const double c0 = c[k];                                                        \
        for (int q = 0; q < NV; q++)                                                   \
            acc[q] += (c0 * x0[q]) * y[q];                                             \
    } while (0)
#endif
/* a run of n items of the given width from planned term k on, item i into a(i % 4) */
#define RUN(ITEM, width, n)                                                            \
    do {                                                                               \
        int i_ = 0;                                                                    \
        for (; i_ + 4 <= (n); i_ += 4, k += 4 * (width)) {                             \
            ITEM(a0, k);                                                               \
            ITEM(a1, k + (width));                                                     \
            ITEM(a2, k + 2 * (width));                                                 \
            ITEM(a3, k + 3 * (width));                                                 \
        }                                                                              \
        if (i_ < (n)) {                                                                \
            ITEM(a0, k);                                                               \
            k += (width);                                                              \
        }                                                                              \
        if (i_ + 1 < (n)) {                                                            \
            ITEM(a1, k);                                                               \
            k += (width);                                                              \
        }                                                                              \
        if (i_ + 2 < (n)) {                                                            \
            ITEM(a2, k);                                                               \
            k += (width);                                                              \
        }                                                                              \
    } while (0)
    int k = t0;
    /* each sum from -0 on (poly_impl.h): with 4 single terms or more their
     * first ones are the sums, no adds (fisheye-ii's default fit: 0.4 ns a ray) */
    if (ns >= POLY_NSUMS) {
#define SET(acc, k)                                                                    \
    do {                                                                               \
        const vn *x = V(k);                                                            \
        const double ck = c[k];                                                        \
        for (int q = 0; q < NV; q++)                                                   \
            acc[q] = ck * x[q];                                                        \
    } while (0)
        SET(a0, k);
        SET(a1, k + 1);
        SET(a2, k + 2);
        SET(a3, k + 3);
#undef SET
        k += POLY_NSUMS;
        RUN(SINGLE, 1, ns - POLY_NSUMS);
    } else {
        for (int q = 0; q < NV; q++)
            a0[q] = a1[q] = a2[q] = a3[q] = -(vn){0}; /* -0: x + -0 is x */
        RUN(SINGLE, 1, ns);
    }
    RUN(QUAD, 4, nq);
    RUN(PAIR, 2, npr);
    RUN(LONE, 1, nl);
#undef V
#undef SPLAT
#undef SINGLE
#undef QUAD
#undef PAIR
#undef LONE
#undef RUN
    for (int q = 0; q < NV; q++) /* an empty sum is 0, not -0 */
        res[o * NV + q] =
            t0 == pl->start[o + 1] ? (vn){0} : (a0[q] + a1[q]) + (a2[q] + a3[q]);
}
