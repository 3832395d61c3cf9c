/* Evaluation of polynomial systems: one ray, batches, and the Jacobian (the core in the
 * system's frame; poly_frame.c wraps it into the public functions).
 * Every path runs the plan of poly_impl.h with the same products and the same order of
 * additions, so scalar and batch results are bit-identical (the batch Jacobian: to 1e-12). */
#include "poly/poly_impl.h"

/* x86 has a kernel per instruction set below; elsewhere (arm64, ...) the 2-lane one
 * alone, which GCC maps onto that machine's vectors. SPARSELENS_PORTABLE_KERNELS builds
 * that path on x86 too, so the tests can check it where they run. */
#if (defined(__x86_64__) || defined(__i386__)) && !defined(SPARSELENS_PORTABLE_KERNELS)
#define POLY_X86 1
#include <immintrin.h>
#elif defined(__aarch64__) && !defined(SPARSELENS_PORTABLE_KERNELS)
#include <arm_neon.h>
#endif
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Rays per block in the batch path (at most; each instruction set has its own KBLK
 * below). The values of a block's rays for one monomial lie side by side, so every
 * product and every term is one operation on KBLK lanes, which the compiler splits into
 * hardware vectors. A block's values must stay in the L1 cache: 32 rays x 8 bytes x
 * ~100 kept values of the framed 5 x 40 term fisheye-ii system is 25 KiB. */
#define BLK 32
/* Rays whose parts are sorted out together in the batch path (bounds the index buffer). */
#define CHUNK 2048
/* A Jacobian's rows of more bytes than this (the L2 cache here) go past the caches
 * (KERNEL_STREAM; a caller reading them next finds them in memory, not in the cache):
 * bench_poly's 4 MB of rows (20000 rays, 5 outputs) 69.2-73.1 -> 63.9-68.5 ns a ray. */
#define STREAM_MIN ((size_t)2 << 20)

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

/* The fused items of the plan (poly_impl.h): a quad, a pair, a lone term at planned
 * term k. */
#define QUAD_ONE(k)                                                                        \
    (((c[k] * v[fa[k]] + c[(k) + 1] * v[fa[(k) + 1]]) +                                     \
      (c[(k) + 2] * v[fa[(k) + 2]] + c[(k) + 3] * v[fa[(k) + 3]])) *                        \
     v[fb[k]])
#define PAIR_ONE(k) ((c[k] * v[fa[k]] + c[(k) + 1] * v[fa[(k) + 1]]) * v[fb[k]])
#define LONE_ONE(k) ((c[k] * v[fa[k]]) * v[fb[k]])

/* One run of n items of the given width from planned term k on, into a0..a3 (item i to
 * a(i % 4)); k is left past the run. */
#define RUN_ONE(ITEM, width, n)                                                            \
    do {                                                                                   \
        int i_ = 0;                                                                        \
        for (; i_ + 4 <= (n); i_ += 4, k += 4 * (width)) {                                \
            a0 += ITEM(k);                                                                 \
            a1 += ITEM(k + (width));                                                       \
            a2 += ITEM(k + 2 * (width));                                                   \
            a3 += ITEM(k + 3 * (width));                                                   \
        }                                                                                  \
        if (i_ < (n))                                                                      \
            a0 += ITEM(k), k += (width);                                                   \
        if (i_ + 1 < (n))                                                                  \
            a1 += ITEM(k), k += (width);                                                   \
        if (i_ + 2 < (n))                                                                  \
            a2 += ITEM(k), k += (width);                                                   \
    } while (0)

/* The plan's sums for one ray (the same additions as the batch kernel's). */
static void sums_one(const poly_plan *pl, const double *v, const unsigned char *need, double *out)
{
    const double *c = pl->coef;
    const int *fa = pl->fa, *fb = pl->fb;
    for (int o = 0; o < pl->nout; o++) {
        if (need && !need[o]) {
            out[o] = 0;
            continue;
        }
        const int t0 = pl->start[o], ns = pl->nsingle[o];
        const int nq = pl->nquad[o], np = pl->npair[o];
        const int nl = pl->start[o + 1] - t0 - ns - 4 * nq - 2 * np;
        if (t0 == pl->start[o + 1]) {
            out[o] = 0; /* an empty sum: 0, not -0 */
            continue;
        }
        double a0 = -0.0, a1 = -0.0, a2 = -0.0, a3 = -0.0;
        int k = t0;
#define SINGLE_ONE(k) (c[k] * v[fa[k]])
        RUN_ONE(SINGLE_ONE, 1, ns);
#undef SINGLE_ONE
        RUN_ONE(QUAD_ONE, 4, nq);
        RUN_ONE(PAIR_ONE, 2, np);
        RUN_ONE(LONE_ONE, 1, nl);
        out[o] = (a0 + a1) + (a2 + a3);
    }
}
#undef QUAD_ONE
#undef PAIR_ONE
#undef LONE_ONE
#undef RUN_ONE

/* Runs plan pl on one ray: out[pl->nout], the sums need says (NULL: all; the others 0);
 * then plan vp (if not NULL: a vplan over pl's values) into vout, the sums vneed says.
 * Returns -1 when out of memory. */
static int run_one(const poly_system *s, const poly_plan *pl, const double *in,
                   const unsigned char *need, double *out, const poly_plan *vp,
                   const unsigned char *vneed, double *vout)
{
    double buf[512];
    double *v = pl->nvals <= 512 ? buf : malloc((size_t)pl->nvals * sizeof(double));
    if (!v)
        return -1;
    values_one(s, pl, in, v);
    sums_one(pl, v, need, out);
    if (vp)
        sums_one(vp, v, vneed, vout);
    if (v != buf)
        free(v);
    return 0;
}

int poly_eval_values_core(const poly_system *s, int part, const double *in, double *out)
{
    if (part >= 0 && part < s->nparts && poly_fast_run(s->parts[part].plan.fast, s, in, out) == 0)
        return 0;
    if (part < 0 || part >= s->nparts || run_one(s, &s->parts[part].plan, in, NULL, out, NULL, NULL, NULL) != 0) {
        fill_nan(out, s->nout);
        return -1;
    }
    return 0;
}

int poly_eval_part_core(const poly_system *s, int part, const double *in, double *out)
{
    return poly_eval_values_core(s, part, in, out) == 0 && poly_passes(s, out);
}

/* What a batch run computes: the outputs with the frame, transforms and passage test;
 * the derivatives d out_o / d in_i of the derivative plan (scaling's chain rule applied);
 * the outputs of the core alone (the inputs taken as in the frame, no pass flags); or
 * the derivatives through the frame and transforms (poly_eval_jacobian_batch of a
 * framed system: the frame view's values and derivatives, the plain view's derivatives,
 * then poly_frame_chain on the block). */
enum { RUN_EVAL, RUN_JAC, RUN_CORE, RUN_JACF };

/* What a batch run computes and writes, beyond the plans (at most 3, part_plans):
 * outputs sel[0 .. nsel - 1] go to the columns of out (all, in order, by default);
 * need[w][o]: sum o of plan w is computed (asked for, or needed by the pass test or the
 * chain rule); kind[w]: plan w reads the inputs in the frame (0) or as given (1),
 * transformed both; its sums at res + roff[w] (in sums of a block); deriv[w]: they are
 * derivatives d / d s_i, scaled to d / d in_i. The pass test checks outputs finite[0 ..
 * nfinite - 1] for being finite and then the circles (an output in a circle of finite
 * radius needs no check of its own: a*a + b*b <= r*r fails for inf and nan). */
typedef struct {
    int nsel, nfinite;
    const int *sel, *finite;
    const unsigned char *need[3];
    int kind[3], roff[3], deriv[3];
    int vview; /* RUN_JACF: the plan of the frame view's values (its derivatives: 1 - vview) */
    unsigned char written[POLY_MAX_OUTPUTS]; /* RUN_EVAL: output o goes to out (a pair
                                                turns back only then: poly_eval_part) */
} batch_job;

/* The batch kernel once per instruction set, each with the vector width of its registers
 * and a block that keeps its partial sums in registers (AVX-512: 32 rays in 4 x 8 lanes,
 * 16 accumulators of its 32 registers; AVX2: 8 in 2 x 4; SSE: 4 in 2 x 2); batch() runs
 * the widest, a narrower one on a short last block (kernels()). The loop is bound by loads
 * of values (two 64-byte loads a cycle), so a wider block pays the per-term index and
 * coefficient loads on more rays: 32 rays measured 36 -> 29 ns a ray against 16 on the
 * fisheye-ii system. AVX-512 also moves the rows in and out with gathers and scatters (the
 * scalar copy out of a block just stored as vectors cost 4 ns a ray). -O3 for these alone:
 * it unrolls the loops over lanes; it never contracts into FMA (ISO C mode), so the bits
 * stay (KERNEL_FMA aside). */
#if defined(POLY_X86)
#include "poly/poly_eval_rows.h"

#define KERNEL_NAME run_blocks_avx512
#define KERNEL_TARGET __attribute__((target("avx512f"), optimize("O3")))
#define KERNEL_SQRT(x) ((vn)_mm512_sqrt_pd((__m512d)(x)))
#define VW 8
#define KBLK 32
#define KERNEL_SCATTER(base, at, x) _mm512_i64scatter_pd((base), (__m512i)(at), (__m512d)(x), 8)
#define KERNEL_GATHER(base, at) ((vn)_mm512_i64gather_pd((__m512i)(at), (base), 8))
#define KERNEL_STORE_ROWS5(dst, cols) store_rows5((dst), (const __m512d *)(cols))
#define KERNEL_STORE_ROWS8(out, row, nres, k0, cols, ncol)                                   \
    store_rows8((out), (row), (nres), (k0), (const __m512d *)(cols), (ncol))
#define KERNEL_LOAD_COLS5(src, cols) load_cols5((src), (__m512d *)(cols))
#define KERNEL_LE_BITS(k, a, b)                                                               \
    ((unsigned)_mm512_mask_cmp_pd_mask((__mmask8)(k), (__m512d)(a), (__m512d)(b), _CMP_LE_OQ))
#define KERNEL_WHOLE_ROWS 128
#define KERNEL_STREAM(dst, src, n) stream_rows((dst), (src), (n))
#define KERNEL_STREAM_FENCE() _mm_sfence()
#define KERNEL_STREAM_MIN STREAM_MIN
#define KERNEL_FMA(a, b, c) ((vn)_mm512_fmadd_pd((__m512d)(a), (__m512d)(b), (__m512d)(c)))
#include "poly/poly_eval_kernel.h"
#undef KERNEL_WHOLE_ROWS
#undef KERNEL_STREAM
#undef KERNEL_STREAM_FENCE
#undef KERNEL_STREAM_MIN
#undef KERNEL_NAME
#undef KBLK
#define KERNEL_NAME run_blocks_avx512_8
#define KBLK 8
#include "poly/poly_eval_kernel.h"
#undef KERNEL_FMA /* after the 8-ray instance too: the 32-ray one's bits */
#undef KERNEL_SCATTER
#undef KERNEL_LE_BITS
#undef KERNEL_GATHER
#undef KERNEL_STORE_ROWS5
#undef KERNEL_STORE_ROWS8
#undef KERNEL_LOAD_COLS5
#undef KERNEL_NAME
#undef KERNEL_TARGET
#undef VW
#undef KBLK
#undef KERNEL_SQRT
#define KERNEL_NAME run_blocks_avx2
#define KERNEL_TARGET __attribute__((target("avx2"), optimize("O3")))
#define KERNEL_SQRT(x) ((vn)_mm256_sqrt_pd((__m256d)(x)))
#define VW 4
#define KBLK 8
#include "poly/poly_eval_kernel.h"
#undef KERNEL_NAME
#undef KERNEL_TARGET
#undef VW
#undef KBLK
#undef KERNEL_SQRT
#endif
#define KERNEL_NAME run_blocks_sse
#define KERNEL_TARGET __attribute__((optimize("O3")))
#if defined(POLY_X86)
#define KERNEL_SQRT(x) ((vn)_mm_sqrt_pd((__m128d)(x)))
#elif defined(__aarch64__) && !defined(SPARSELENS_PORTABLE_KERNELS)
#define KERNEL_SQRT(x) ((vn)vsqrtq_f64((float64x2_t)(x)))
#else
/* IEEE square roots are correctly rounded, so lane by lane gives the vector's bits. */
#define KERNEL_SQRT(x) ((vn){__builtin_sqrt((x)[0]), __builtin_sqrt((x)[1])})
#endif
#define VW 2
#define KBLK 4
#include "poly/poly_eval_kernel.h"
#undef KERNEL_NAME
#undef KERNEL_TARGET
#undef VW
#undef KBLK
#undef KERNEL_SQRT

typedef void run_fn(const poly_system *, const poly_plan *const *, int, int, size_t,
                    const size_t *, size_t, const double *, double *, unsigned char *,
                    const batch_job *, double *, double *, double *, int *);

/* A run that cannot be made: the rays get nan and do not pass. */
static void job_fail(int nsel, size_t count, double *out, unsigned char *pass)
{
    for (size_t r = 0; r < count; r++) {
        fill_nan(out + r * (size_t)nsel, nsel);
        if (pass)
            pass[r] = 0;
    }
}

/* The plans the kernel runs for part p: the part's plan, or with outputs outside the frame
 * the frame view's and the plain view's (poly_impl.h; the system itself for a view that
 * could not be built, as poly_eval_part does). RUN_JACF: the frame view's values and
 * derivatives (vview 1: its derivative plan first, then the values over its values,
 * vplan), then the plain view's derivatives. Returns how many. */
static int part_plans(const poly_system *s, int what, int p, int vview, const poly_plan **pls)
{
    if (what == RUN_JACF) { /* the views exist (poly_eval_jacobian_batch checks) */
        const poly_system *vf = s->frame && s->nplain ? s->vframe : s;
        pls[vview] = vview ? &vf->parts[p].vplan : &vf->parts[p].plan;
        pls[1 - vview] = &vf->parts[p].dplan;
        if (!(s->frame && s->nplain))
            return 2;
        pls[2] = &s->vplain->parts[p].dplan;
        return 3;
    }
    if (what == RUN_JAC) {
        pls[0] = &s->parts[p].dplan;
        return 1;
    }
    if (what == RUN_CORE || !(s->frame && s->nplain)) {
        pls[0] = &s->parts[p].plan;
        return 1;
    }
    pls[0] = &(s->vframe ? s->vframe : s)->parts[p].plan;
    pls[1] = &(s->vplain ? s->vplain : s)->parts[p].plan;
    return 2;
}

/* The kernels of this machine, widest first, and how many of them (poly_eval.c
 * builds one per instruction set; the portable 2-lane one alone off x86): k[0] runs
 * blocks of kblk[0] rays, k[t > 0] takes a last partial block of up to kblk[t] rays.
 * With AVX-512 a second instance of its kernel in blocks of 8 rays takes up to 16
 * (on the fisheye-ii system a call of 8 rays cost 78 ns a ray through AVX2's kernel,
 * 55 through it; 16 rays 66-74 and 50 ns; 24 rays are cheaper in one block of 32). */
static int kernels(run_fn **k, int *kblk)
{
    int n = 0;
#if defined(POLY_X86)
    if (__builtin_cpu_supports("avx512f")) {
        k[n] = run_blocks_avx512, kblk[n++] = 32;
        k[n] = run_blocks_avx512_8, kblk[n++] = 16; /* 2 blocks of 8 beat one of 32 */
        return n;
    }
    if (__builtin_cpu_supports("avx2"))
        k[n] = run_blocks_avx2, kblk[n++] = 8;
#endif
    k[n] = run_blocks_sse, kblk[n++] = 4;
    return n;
}

/* n rays (rows idx[0 .. n - 1], or first .. first + n - 1) through the widest kernel,
 * except a last partial block that a narrower kernel takes (kernels()): a block costs
 * its width whatever its rays, so 1 to 8 rays in AVX-512's block of 32 cost 32 (0.8 us
 * on the fisheye-ii system). Every kernel gives the same bits. */
static void run_rays(run_fn *const *k, const int *kblk, int nk, const poly_system *s,
                     const poly_plan *const *pls, int nview, int what, size_t n,
                     const size_t *idx, size_t first, const double *in, double *out,
                     unsigned char *pass, const batch_job *job, double *v, double *res,
                     double *fb, int *off)
{
    size_t tail = n % (size_t)kblk[0];
    int t = 0;
    while (t + 1 < nk && tail > 0 && tail <= (size_t)kblk[t + 1])
        t++;
    if (t == 0)
        tail = 0;
    if (n > tail)
        k[0](s, pls, nview, what, n - tail, idx, first, in, out, pass, job, v, res, fb, off);
    if (tail)
        k[t](s, pls, nview, what, tail, idx ? idx + (n - tail) : NULL, first + (n - tail), in,
             out, pass, job, v, res, fb, off);
}

/* Scratch of a batch call on the stack up to this size (a default fit's evaluation
 * needs about 40 KiB): eight allocations and frees had cost each call about 0.7 us on
 * the fisheye-ii system, the time of 25 rays in bulk. */
#define STACK_SCRATCH (48 * 1024)

/* Bytes of n items of size sz, rounded up to 64 (each buffer of the scratch aligned). */
static size_t span64(size_t n, size_t sz)
{
    return (n * sz + 63) / 64 * 64;
}

/* The batch driver of poly_eval_batch and poly_eval_jacobian_batch: rays in runs of one
 * part (each chunk counting-sorted by part when there are several, the part chosen from
 * the rays' own inputs as poly_eval does). RUN_EVAL applies the frame and transforms in
 * the kernel; RUN_JAC and RUN_CORE run the core alone. */
static void batch(const poly_system *s, int what, size_t count, const double *in, double *out,
                  unsigned char *pass, const batch_job *job)
{
    const size_t nj = (size_t)s->nout * (size_t)s->nin;
    int maxv = 0, maxo = 1;
    size_t maxoff = 1;
    for (int p = 0; p < s->nparts; p++) {
        const poly_plan *pls[3];
        const int nview = part_plans(s, what, p, job->vview, pls);
        size_t no = 0;
        int nsums = 0;
        for (int w = 0; w < nview; w++) {
            nsums += pls[w]->nout;
            no += 2 * (size_t)pls[w]->nprod + 2 * (size_t)pls[w]->start[pls[w]->nout];
            if (pls[w]->nvals > maxv)
                maxv = pls[w]->nvals;
        }
        if (no > maxoff)
            maxoff = no;
        if (nsums > maxo)
            maxo = nsums;
    }
    run_fn *k[3];
    int kblk[3];
    const int nk = kernels(k, kblk);
    /* the raw inputs, r, c, s; with RUN_JACF the kernel's columns for the chain rule */
    size_t nfb = (size_t)s->nin + 3 + (what == RUN_JACF ? 3 * (size_t)s->nin + 9 + nj : 0);
    const int jrows = (what == RUN_JAC || what == RUN_JACF) &&
                      count * (size_t)job->nsel * sizeof(double) > STREAM_MIN;
    if (job->nsel <= 128 && (job->nsel > 32 || jrows))
        nfb += (size_t)job->nsel; /* a block's rows, KERNEL_WHOLE_ROWS (KERNEL_STREAM) */
    const size_t nch = s->nparts > 1 ? (count < CHUNK ? count : CHUNK) : 0;
    const size_t sv = span64((size_t)maxv * BLK, sizeof(double));
    const size_t sr = span64((size_t)maxo * BLK, sizeof(double));
    const size_t sf = span64(nfb * BLK, sizeof(double)), so = span64(maxoff, sizeof(int));
    const size_t si = span64(nch, sizeof(size_t)), sp = span64(nch, sizeof(int));
    const size_t ss = span64((size_t)s->nparts + 1, sizeof(int));
    const size_t total = sv + sr + sf + so + si + sp + 2 * ss;
    _Alignas(64) unsigned char stack[STACK_SCRATCH];
    unsigned char *mem = total <= sizeof stack ? stack : aligned_alloc(64, total);
    if (!s->nparts || !mem) {
        job_fail(job->nsel, count, out, pass); /* no parts, or out of memory */
        return;
    }
    double *v = (double *)mem, *res = (double *)(mem + sv), *fb = (double *)(mem + sv + sr);
    int *off = (int *)(mem + sv + sr + sf);
    size_t *idx = (size_t *)(mem + sv + sr + sf + so);
    int *part = (int *)(mem + sv + sr + sf + so + si);
    int *start = (int *)(mem + sv + sr + sf + so + si + sp), *cur = start + ss / sizeof(int);
    memset(res, 0, sr); /* outputs a block leaves out stay 0 (never garbage, never subnormal) */
    if (s->nparts == 1) {
        const poly_plan *pls[3];
        const int nview = part_plans(s, what, 0, job->vview, pls);
        run_rays(k, kblk, nk, s, pls, nview, what, count, NULL, 0, in, out, pass, job, v, res,
                 fb, off);
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
                const poly_plan *pls[3];
                const int nview = part_plans(s, what, q, job->vview, pls);
                if (start[q + 1] > start[q])
                    run_rays(k, kblk, nk, s, pls, nview, what, (size_t)(start[q + 1] - start[q]),
                             idx + start[q], 0, in, out, pass, job, v, res, fb, off);
            }
        }
    }
    if (mem != stack)
        free(mem);
}

/* The job (batch_job) of a run writing outputs sel[0 .. nsel - 1] (sel NULL: all nw
 * of them, in order), with the pass test or not; then the run. Without memory for the
 * job, the rays get nan and do not pass. */
static void batch_job_run(const poly_system *s, int what, size_t count, const double *in,
                          int nsel, const int *sel, double *out, unsigned char *pass)
{
    const int nout = s->nout, nj = nout * s->nin;
    const int nw = what == RUN_JAC || what == RUN_JACF ? nj : nout;
    if (count == 0)
        return;
    /* on the stack for up to 256 sums (every default fit; its Jacobian's too) */
    int ids_st[2 * 256 + 1];
    unsigned char need_st[4 * 256 + 1];
    const int small = nw <= 256;
    int *ids = small ? ids_st : malloc((2 * (size_t)nw + 1) * sizeof(int));
    unsigned char *need = small ? need_st : malloc(4 * (size_t)nw + 1); /* 3 plans, scratch */
    if (!ids || !need) {
        job_fail(sel ? nsel : nw, count, out, pass);
        if (!small) {
            free(ids);
            free(need);
        }
        return;
    }
    memset(need, 0, 4 * (size_t)nw + 1);
    const int views = s->frame && s->nplain; /* RUN_EVAL, RUN_JACF: the views of poly_impl.h */
    batch_job job = {.nsel = sel ? nsel : nw, .sel = sel ? sel : ids, .finite = ids + nw,
                     .need = {need, need + nw, need + 2 * nw}};
    for (int k = 0; k < nw; k++) {
        ids[k] = k;
        need[k] = !sel || pass; /* the pass test needs every output */
    }
    for (int j = 0; sel && j < nsel; j++)
        need[sel[j]] = 1;
    memset(job.written, !sel, sizeof job.written);
    for (int j = 0; what == RUN_EVAL && sel && j < nsel; j++)
        job.written[sel[j]] = 1;
    if (what == RUN_EVAL && views) { /* each output from its own view */
        job.kind[1] = 1;
        job.roff[1] = nout;
        for (int o = 0; o < nout; o++) {
            need[nw + o] = need[o] && s->plain[o];
            need[o] = need[o] && !s->plain[o];
        }
    }
    if (what == RUN_JACF) { /* values of the turned pairs, derivatives of each view */
        unsigned char *outs = need + 3 * nw; /* the outputs asked for, and their partners */
        for (int o = 0; o < nout; o++)
            outs[o] = need[o * s->nin];
        for (int k = 0; k < s->npairs; k++)
            outs[s->pair[2 * k]] = outs[s->pair[2 * k + 1]] =
                outs[s->pair[2 * k]] || outs[s->pair[2 * k + 1]];
        memset(need, 0, (size_t)nw); /* of nw >= nout + 1 */
        for (int k = 0; k < 2 * s->npairs; k++)
            need[s->pair[k]] = outs[s->pair[k]];
        for (int k = 0; k < nj; k++)
            need[nw + k] = outs[k / s->nin];
        for (int k = 0; k < nj; k++) {
            const int plain = views && s->plain[k / s->nin];
            need[2 * nw + k] = plain && need[nw + k];
            need[nw + k] = !plain && need[nw + k];
        }
        job.deriv[1] = job.deriv[2] = 1;
        job.roff[1] = nout;
        job.kind[2] = 1;
        job.roff[2] = nout + nj;
        if (poly_jacf_vplan(s)) { /* the values after the derivatives, over their values */
            const unsigned char *nv = job.need[0];
            job.need[0] = job.need[1];
            job.need[1] = nv;
            job.deriv[0] = 1;
            job.deriv[1] = 0;
            job.roff[0] = nout;
            job.roff[1] = 0;
            job.vview = 1;
        }
    }
    if (what != RUN_JACF)
        job.deriv[0] = what == RUN_JAC;
    if (pass) { /* poly_circle_covers of every output in one pass over the circles (a
                 * call per output had cost a short batch 0.1 us) */
        unsigned char *cov = need + 3 * nw; /* scratch: RUN_EVAL alone has pass flags */
        memset(cov, 0, (size_t)nout);
        for (int c = 0; c < s->ncircles; c++)
            if (isfinite(s->circles[c].radius * s->circles[c].radius))
                cov[s->circles[c].a] = cov[s->circles[c].b] = 1;
        for (int o = 0; o < nout; o++)
            if (!cov[o])
                ids[nw + job.nfinite++] = o;
    }
    batch(s, what, count, in, out, pass, &job);
    if (!small) {
        free(ids);
        free(need);
    }
}

void poly_eval_batch_core(const poly_system *s, size_t count, const double *in, double *out,
                          unsigned char *pass)
{
    batch_job_run(s, RUN_EVAL, count, in, 0, NULL, out, pass);
}

int poly_eval_batch_outputs(const poly_system *s, size_t count, const double *in, int nsel,
                            const int *outputs, double *out, unsigned char *pass)
{
    if (nsel < 0 || (nsel > 0 && !outputs))
        return -1;
    for (int j = 0; j < nsel; j++)
        if (outputs[j] < 0 || outputs[j] >= s->nout)
            return -1;
    batch_job_run(s, RUN_EVAL, count, in, nsel, outputs, out, pass);
    return 0;
}

void poly_eval_jacobian_batch_frame(const poly_system *s, size_t count, const double *in,
                                    int nsel, const int *sel, double *jac)
{
    batch_job_run(s, RUN_JACF, count, in, nsel, sel, jac, NULL);
}

void poly_eval_jacobian_batch_core(const poly_system *s, size_t count, const double *in,
                                   int nsel, const int *sel, double *jac)
{
    batch_job_run(s, RUN_JAC, count, in, nsel, sel, jac, NULL);
}

int poly_eval_jacobian_core(const poly_system *s, const double *in, const unsigned char *needv,
                            const unsigned char *needd, double *out, double *jac, double *over,
                            const unsigned char *needo)
{
    const int nin = s->nin, nout = s->nout, part = s->nparts ? poly_select_part(s, in) : -1;
    int pass = 0;
    if (needv) {
        if (part < 0 || run_one(s, &s->parts[part].plan, in, needv, out, NULL, NULL, NULL) != 0)
            fill_nan(out, nout);
    } else if (part < 0 || run_one(s, &s->parts[part].plan, in, NULL, out, NULL, NULL, NULL) != 0) {
        fill_nan(out, nout);
    } else { /* the plan's interpreter, not poly_fast: the batch Jacobian's bits */
        pass = poly_passes(s, out);
    }
    const poly_plan *vp = over && part >= 0 ? &s->parts[part].vplan : NULL;
    if (over && !(vp && vp->start))
        fill_nan(over, nout);
    if (part < 0 ||
        run_one(s, &s->parts[part].dplan, in, needd, jac, vp && vp->start ? vp : NULL, needo,
                over) != 0) {
        fill_nan(jac, nin * nout);
        if (over)
            fill_nan(over, nout);
        return 0;
    }
    for (int k = 0; k < nin * nout; k++)
        if (!needd || needd[k])
            jac[k] = poly_scale_chain(s, k % nin, jac[k]);
    return pass;
}
