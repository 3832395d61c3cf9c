/* The one-ray evaluation of a plan's sums with vectors (poly_eval, poly_eval_part).
 * One ray has no lanes of rays to fill, and a chain of products (each monomial its
 * parent times a variable, as the plan builds them) is as long as the highest degree:
 * one ray waited on it from one end to the other. Here the work is laid out for 8-lane
 * vectors so that no step waits on more than a few others:
 *
 *   powers   per variable that some term has (an "active" one), its powers s^0 .. s^15
 *            in two vectors, from s, s^2, s^4 and s^8 by masked multiplies (no chain
 *            through the degrees);
 *   terms    each output's terms in chunks of 8 (the last one padded with zero
 *            coefficients): per active variable, the lanes' powers picked out of its two
 *            vectors by one permute with the chunk's exponents, the factors multiplied
 *            together, and one fused multiply-add of the chunk's coefficients into the
 *            output's accumulator; then the accumulator's 8 lanes added.
 * Every chunk is independent of the others, so the work of one ray is a short, wide
 * tree that the next ray's can overlap. Its cost is the chunks' permutes and multiplies
 * (the shuffle port and the two vector ports): the two least used variables are
 * optional, each output's terms sorted by which of them they have, so that a chunk
 * whose 8 terms lack one skips its permute and multiply (the default 5-output fisheye
 * fit: 162 operations for its 25 chunks instead of 200, 2-3 ns a ray). poly_fast_eval
 * runs the whole of poly_eval_part for a system without outputs outside its frame (the
 * frame, transforms and scaling of the active inputs, the rotation back and the pass
 * test inline: 5-7 ns a ray less than through poly_frame_in and the core).
 *
 * One ray's work is longer than the processor's window of instructions in flight, so
 * the chain from the inputs to the first power tables is not hidden by the previous
 * ray's chunks: the rotation takes u' = (x u + y v) / r, its products made while the
 * root and the divide run, and the scaling is one multiply-add (5-6 ns a ray of the
 * 5-output fit; the scaled values agree with the plan's to rounding). The power tables
 * square s as vectors and skip s^8 .. s^15 of a variable whose exponents stay below 8.
 *
 * A term that is inf or nan makes its output non-finite as in the plan (padded lanes
 * take the power 0 of every variable, 1, times 0); a ray with an output that is not
 * finite is evaluated again by the plan's interpreter all the same, so that such a ray
 * gives the plan's values exactly.
 *
 * The results are the plan's sums with other roundings (powers by another product
 * order, another order of additions, fused multiply-adds): they agree with the batch
 * kernel's to rounding (1e-12 of the output's size, tested in test_poly and
 * test_poly_fast), not bit for bit. Only on x86 with AVX-512, for at most FAST_MAXACT
 * active variables and exponents up to 15; elsewhere poly_fast declines and the plan's interpreter runs (poly_eval.c). */
#include "poly/poly_impl.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#if (defined(__x86_64__) || defined(__i386__)) && !defined(SPARSELENS_PORTABLE_KERNELS)
#define FAST_X86 1
#include <immintrin.h>
#endif

/* Active variables at most (two table vectors each stay in registers). */
#define FAST_MAXACT 6
/* The highest exponent the two table vectors hold. */
#define FAST_MAXEXP 15
/* The active variables a chunk may go without (the last ones: the least used). */
#define FAST_MAXOPT 2
#define FAST_KINDS (1 << FAST_MAXOPT)

struct poly_fast {
    int nin, nout, nact;
    int act[FAST_MAXACT]; /* the inputs some term has an exponent of, the most used first */
    int maxe[FAST_MAXACT]; /* their highest exponents */
    int nopt;             /* the last nopt of them are optional: a chunk's "kind" (bit j:
                             it has optional variable j) says which it multiplies by */
    ptrdiff_t *kend;      /* nout x FAST_KINDS: where output o's chunks of each kind end
                             (8 x a chunk's number, in coef; they follow in turn), so the
                             loops over them run on from where the last one stopped */
    int64_t *idx;         /* per chunk, nact x 8: the lanes' exponents of each active input */
    double *coef;         /* per chunk, 8: the lanes' coefficients (0 in padded lanes) */
};

void poly_fast_free(poly_fast *f)
{
    if (!f)
        return;
    free(f->kend);
    free(f->idx);
    free(f->coef);
    free(f);
}

/* The active inputs of the sums, the most used first; -1 when there are too many or an
 * exponent is too high. */
static int fast_active(poly_fast *f, const poly_out_terms *sums)
{
    int used[POLY_MAX_INPUTS] = {0}, maxe[POLY_MAX_INPUTS] = {0};
    for (int o = 0; o < f->nout; o++)
        for (int t = 0; t < sums[o].nterms; t++)
            for (int i = 0; i < f->nin; i++) {
                const int e = sums[o].exps[(size_t)t * f->nin + i];
                if (e < 0 || e > FAST_MAXEXP)
                    return -1;
                used[i] += e > 0;
                maxe[i] = e > maxe[i] ? e : maxe[i];
            }
    f->nact = 0;
    for (int i = 0; i < f->nin; i++)
        if (used[i]) {
            if (f->nact == FAST_MAXACT)
                return -1;
            int k = f->nact++;
            for (; k > 0 && used[f->act[k - 1]] < used[i]; k--)
                f->act[k] = f->act[k - 1];
            f->act[k] = i;
        }
    for (int k = 0; k < f->nact; k++)
        f->maxe[k] = maxe[f->act[k]];
    f->nopt = f->nact > FAST_MAXOPT ? FAST_MAXOPT : f->nact - 1;
    return 0;
}

/* Term t's kind: which optional variables it has. */
static int fast_kind(const poly_fast *f, const int *e)
{
    int kind = 0;
    for (int j = 0; j < f->nopt; j++)
        kind |= (e[f->act[f->nact - f->nopt + j]] > 0) << j;
    return kind;
}

/* Output o's chunks from chunk c on: its terms sorted by kind (so that few chunks mix
 * kinds), 8 a chunk, each chunk of the kind of all its terms together, the chunks
 * ordered by kind. Returns the next chunk; ord (nterms) and ck (chunks) are scratch. */
static int fast_output(poly_fast *f, const poly_out_terms *ot, int o, int c, int *ord, int *ck)
{
    const int na = f->nact, nin = f->nin, nt = ot->nterms, nch = (nt + 7) / 8;
    int n = 0;
    for (int kind = 0; kind < FAST_KINDS; kind++)
        for (int t = 0; t < nt; t++)
            if (fast_kind(f, ot->exps + (size_t)t * nin) == kind)
                ord[n++] = t;
    for (int q = 0; q < nch; q++) {
        ck[q] = 0;
        for (int l = 8 * q; l < nt && l < 8 * q + 8; l++)
            ck[q] |= fast_kind(f, ot->exps + (size_t)ord[l] * nin);
    }
    for (int kind = 0; kind < FAST_KINDS; kind++) {
        for (int q = 0; q < nch; q++) {
            if (ck[q] != kind)
                continue;
            for (int l = 0; l < 8; l++) {
                const int real = 8 * q + l < nt, t = real ? ord[8 * q + l] : 0;
                f->coef[8 * c + l] = real ? ot->coef[t] : 0;
                for (int k = 0; k < na; k++)
                    f->idx[((size_t)c * na + k) * 8 + l] =
                        real ? ot->exps[(size_t)t * nin + f->act[k]] : 0;
            }
            c++;
        }
        f->kend[o * FAST_KINDS + kind] = 8 * (ptrdiff_t)c;
    }
    return c;
}

poly_fast *poly_fast_build(int nin, int nout, const poly_out_terms *sums)
{
    if (nin < 1 || nin > POLY_MAX_INPUTS)
        return NULL;
    int nch = 0, maxt = 0;
    for (int o = 0; o < nout; o++) {
        if (sums[o].nterms && !sums[o].exps)
            return NULL; /* derivative sums: the interpreter's */
        nch += (sums[o].nterms + 7) / 8;
        maxt = sums[o].nterms > maxt ? sums[o].nterms : maxt;
    }
    poly_fast *f = calloc(1, sizeof *f);
    if (!f)
        return NULL;
    f->nin = nin;
    f->nout = nout;
    f->kend = malloc(((size_t)nout * FAST_KINDS + 1) * sizeof(ptrdiff_t));
    int *ord = malloc(((size_t)maxt + (size_t)maxt / 8 + 2) * sizeof(int));
    if (!f->kend || !ord || fast_active(f, sums) != 0 || f->nact == 0) {
        free(ord);
        poly_fast_free(f);
        return NULL;
    }
    const int na = f->nact;
    f->idx = aligned_alloc(64, ((size_t)nch * na + 1) * 8 * sizeof(int64_t));
    f->coef = aligned_alloc(64, ((size_t)nch + 1) * 8 * sizeof(double));
    if (!f->idx || !f->coef) {
        free(ord);
        poly_fast_free(f);
        return NULL;
    }
    for (int o = 0, c = 0; o < nout; o++)
        c = fast_output(f, &sums[o], o, c, ord, ord + maxt + 1);
    free(ord);
    return f;
}

#if defined(FAST_X86)
#define FAST_TARGET __attribute__((target("avx512f,fma")))

/* s^0 .. s^7 in lo and s^8 .. s^15 in hi (hi = lo when no exponent passes 7): lane k
 * of lo is (1|s) * (1|s^2) * (1|s^4) by the bits of k, as masked multiplies of the
 * broadcast powers. Those powers are multiplied as vectors (the broadcast of s a load):
 * the compiler would otherwise square s alone and broadcast each power, a shuffle
 * apiece on the port the chunks' permutes need. */
FAST_TARGET static inline void fast_powers(const double *s, int high, __m512d *lo, __m512d *hi)
{
    __m512d b = _mm512_set1_pd(*s);
    __asm__("" : "+v"(b)); /* opaque: b * b stays a vector multiply */
    const __m512d b2 = _mm512_mul_pd(b, b), b4 = _mm512_mul_pd(b2, b2);
    __m512d p = _mm512_mask_blend_pd(0xaa, _mm512_set1_pd(1), b);
    p = _mm512_mask_mul_pd(p, 0xcc, p, b2);
    *lo = _mm512_mask_mul_pd(p, 0xf0, p, b4);
    *hi = high ? _mm512_mul_pd(*lo, _mm512_mul_pd(b4, b4)) : *lo;
}

/* How fast_sums adds the outputs' lanes, and the frame's rotation back when it does it:
 * bit o of group set when outputs o and o + 1 are added together (their two lanes; the
 * others alone); bit o of pairs when they are a turned pair (then turned by c, s in
 * those lanes), and then every output's value before the turn also goes to pre, for
 * the pass test (made on the frame's values in every path, poly_eval_part). */
typedef struct {
    double c, s;
    uint64_t group, pairs;
    double *pre;
} fast_turn;

/* The factors' product of one chunk of kind KIND (NA active variables, NO optional). */
__attribute__((target("avx512f,fma"), always_inline)) static inline __m512d
fast_chunk(const int NA, const int NO, const int KIND, const __m512d *lo, const __m512d *hi,
           const int64_t *ix)
{
    __m512d p[FAST_MAXACT];
    int m = 0; /* the factors this kind multiplies */
#pragma GCC unroll 6
    for (int k = 0; k < NA; k++)
        if (k < NA - NO || (KIND >> (k - (NA - NO)) & 1))
            p[m++] = _mm512_permutex2var_pd(lo[k], _mm512_load_si512(ix + 8 * k), hi[k]);
    /* a tree of products: two levels for four variables */
#pragma GCC unroll 6
    for (int w = 1; w < m; w *= 2)
#pragma GCC unroll 6
        for (int k = 0; k + w < m; k += 2 * w)
            p[k] = _mm512_mul_pd(p[k], p[k + w]);
    return p[0];
}

/* The chunks of kind KIND from *ix, *cf on to end into acc. Bookkeeping counts: a
 * ray's window of instructions in flight is its bound as much as the vector ports (a
 * count per loop cost about 14 instructions to set up and close each of 20 loops a ray
 * of the 5-output fit, the compiler recomputing the pointers from it; the empty asm
 * keeps the loop's own pointers, and the loops run on from where the last stopped). */
__attribute__((target("avx512f,fma"), always_inline)) static inline __m512d
fast_chunks(const int NA, const int NO, const int KIND, const __m512d *lo, const __m512d *hi,
            const double *end, const int64_t **ix, const double **cf, __m512d acc)
{
    for (; *cf < end; *ix += 8 * NA, *cf += 8) {
        acc = _mm512_fmadd_pd(_mm512_load_pd(*cf), fast_chunk(NA, NO, KIND, lo, hi, *ix), acc);
        __asm__("" : "+r"(*cf), "+r"(*ix)); /* the loop's pointers run on as they are */
    }
    return acc;
}

/* The sums with NA active variables (a constant after inlining: the tables stay in
 * registers). */
__attribute__((target("avx512f,fma"), always_inline)) static inline int
fast_sums(const int NA, const poly_fast *f, const double *sc, const fast_turn *tn, double *out)
{
    const int NO = NA > FAST_MAXOPT ? FAST_MAXOPT : NA - 1;
    __m512d lo[FAST_MAXACT], hi[FAST_MAXACT];
#pragma GCC unroll 6
    for (int k = 0; k < NA; k++)
        fast_powers(sc + k, f->maxe[k] > 7, &lo[k], &hi[k]);
    const int64_t *ix = f->idx;
    const double *cf = f->coef;
    const ptrdiff_t *ke = f->kend;
    __m512d prev = _mm512_setzero_pd();
    __m128d fin = _mm_setzero_pd(); /* v - v summed: 0 when every output is finite */
    const __m128d tc = _mm_set1_pd(tn->c), ts = _mm_set1_pd(tn->s);
    const double *c0 = f->coef;
    for (int o = 0; o < f->nout; o++, ke += FAST_KINDS) {
        __m512d a = fast_chunks(NA, NO, 0, lo, hi, c0 + ke[0], &ix, &cf, _mm512_setzero_pd());
        if (NO >= 1)
            a = fast_chunks(NA, NO, 1, lo, hi, c0 + ke[1], &ix, &cf, a);
        if (NO >= 2) {
            a = fast_chunks(NA, NO, 2, lo, hi, c0 + ke[2], &ix, &cf, a);
            a = fast_chunks(NA, NO, 3, lo, hi, c0 + ke[3], &ix, &cf, a);
        }
        if (tn->group >> o & 1) {
            prev = a; /* added across lanes with the next output's */
            continue;
        }
        if (!(o > 0 && (tn->group >> (o - 1) & 1))) {
            const double v = _mm512_reduce_add_pd(a);
            fin = _mm_add_pd(fin, _mm_set_sd(v - v));
            out[o] = v;
            if (tn->pairs)
                tn->pre[o] = v;
            continue;
        }
        /* two outputs' lanes at once: lanes (2j, 2j + 1) hold their pairs' partial sums */
        const __m512d t = _mm512_add_pd(_mm512_unpacklo_pd(prev, a), _mm512_unpackhi_pd(prev, a));
        const __m256d h = _mm256_add_pd(_mm512_castpd512_pd256(t), _mm512_extractf64x4_pd(t, 1));
        __m128d q = _mm_add_pd(_mm256_castpd256_pd128(h), _mm256_extractf128_pd(h, 1));
        fin = _mm_add_pd(fin, _mm_sub_pd(q, q));
        if (tn->pairs)
            _mm_storeu_pd(tn->pre + o - 1, q);
        if (tn->pairs >> (o - 1) & 1) /* (a, b) to (c a - s b, s a + c b) */
            q = _mm_fmaddsub_pd(q, tc, _mm_mul_pd(_mm_permute_pd(q, 1), ts));
        _mm_storeu_pd(out + o - 1, q);
    }
    return _mm_movemask_pd(_mm_cmpneq_pd(fin, _mm_setzero_pd())) == 0;
}

/* The sums of the scaled active inputs sc. */
FAST_TARGET static int fast_dispatch(const poly_fast *f, const double *sc, const fast_turn *tn,
                                     double *out)
{
    switch (f->nact) {
    case 1: return fast_sums(1, f, sc, tn, out);
    case 2: return fast_sums(2, f, sc, tn, out);
    case 3: return fast_sums(3, f, sc, tn, out);
    case 4: return fast_sums(4, f, sc, tn, out);
    case 5: return fast_sums(5, f, sc, tn, out);
    default: return fast_sums(6, f, sc, tn, out);
    }
}

/* fast_turn's group for nout outputs and turned pairs at the bits of pairs: each turned
 * pair, and the other outputs two by two from an even one whose next is in no pair
 * (without pairs: 0 and 1, 2 and 3, ...). A default fit's passage hit points come after
 * its out_eta, in pairs from an odd output: turned in the lane sums too, poly_eval on
 * that 19-output fisheye-ii fit 100-102 -> 95 ns a ray (three runs of bench_poly in
 * turn with the build before), where poly_frame_turn_back had turned them after. */
static uint64_t fast_group(int nout, uint64_t pairs)
{
    const uint64_t in_pair = pairs | pairs << 1;
    const uint64_t next = nout <= 1    ? 0 /* outputs o with o + 1 < nout */
                          : nout >= 64 ? ~(uint64_t)0 >> 1
                                       : ((uint64_t)1 << (nout - 1)) - 1;
    return pairs | (0x5555555555555555ULL & ~in_pair & ~(in_pair >> 1) & next);
}

/* The core's sums from its raw inputs (scaled here). */
FAST_TARGET static int fast_run(const poly_fast *f, const poly_system *s, const double *in,
                                double *out)
{
    double sc[FAST_MAXACT];
    for (int k = 0; k < f->nact; k++) {
        sc[k] = in[f->act[k]];
        poly_scale_column(s, f->act[k], &sc[k], 1);
    }
    const fast_turn none = {1, 0, fast_group(f->nout, 0), 0, NULL};
    return fast_dispatch(f, sc, &none, out);
}

/* poly_eval_part of a system without outputs outside its frame, in one pass: the
 * frame and transforms of the active inputs (poly_frame_in), their scaling, the core's
 * sums, the turned pairs rotated back (poly_frame_out) and the pass test; -1 where the
 * plan must run instead. */
FAST_TARGET static int fast_eval(const poly_fast *f, const poly_system *s, const double *in,
                                 double *out)
{
    double t[FAST_MAXACT], r = 0, ir = 0, c = 1, sn = 0, pu = 0, pv = 0;
    const int mer = s->frame == POLY_FRAME_MERIDIONAL, rot = mer && s->iu >= 0 && s->iv >= 0;
    if (mer) {
        const double x = in[s->ix], y = in[s->iy];
        poly_frame_angle(x, y, &r, &c, &sn);
        ir = 1 / r;
        if (rot) { /* r u' and r v': computed while the root and the divide run */
            const double u = in[s->iu], v = in[s->iv];
            pu = x * u + y * v;
            pv = x * v - y * u;
        }
    }
    /* (v - offset) / scale as v / scale - offset / scale: one multiply-add after v (both
     * factors kept by poly_set_scaling) */
    for (int k = 0; k < f->nact; k++) {
        const int i = f->act[k];
        const double inv = s->inv_scale[i], off = s->off_scaled[i];
        double v = in[i];
        if (mer && (i == s->ix || i == s->iy))
            v = i == s->ix ? r : 0;
        else if (rot && (i == s->iu || i == s->iv) && r > 0) { /* on the axis c = 1, s = 0 */
            t[k] = fma((i == s->iu ? pu : pv) * inv, ir, -off);
            continue;
        }
        if (s->xform[i] == POLY_XFORM_INVERSE_SQUARE)
            v = 1 / (v * v);
        t[k] = fma(v, inv, -off);
    }
    double pre[POLY_MAX_OUTPUTS];
    const uint64_t pairs = s->neighbour_pairs; /* lens-fit's pairs: in the lane sums */
    const fast_turn tn = {c, sn, fast_group(f->nout, pairs), pairs, pre};
    if (!fast_dispatch(f, t, &tn, out)) /* an output not finite */
        return -1;
    if (tn.pairs) /* poly_passes (every output is finite) on the frame's values */
        return poly_in_circles(s, pre);
    const int pass = poly_in_circles(s, out);
    poly_frame_turn_back(s, c, sn, out);
    return pass;
}
#endif

int poly_fast_eval(const poly_fast *f, const poly_system *s, const double *in, double *out)
{
#if defined(FAST_X86)
    if (f && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("fma"))
        return fast_eval(f, s, in, out);
#else
    (void)f, (void)s, (void)in, (void)out;
#endif
    return -1;
}

int poly_fast_run(const poly_fast *f, const poly_system *s, const double *in, double *out)
{
#if defined(FAST_X86)
    if (f && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("fma")) {
        if (fast_run(f, s, in, out))
            return 0;
    }
#else
    (void)f, (void)s, (void)in, (void)out;
#endif
    return -1;
}
