/* The one-ray evaluation of a plan's sums with vectors (poly_eval, poly_eval_part):
 * the interpreter of poly_impl.h loads an index, a coefficient and a value per term on
 * one ray (about 900 loads a ray), which the batch kernel pays once per 32 rays, so one
 * ray cost 7 batch rays. Here a ray's work is laid out for 8-lane vectors instead:
 *
 *   values   every monomial the sums use, and the ones they are built from, in a row
 *            m[] of 8-value chunks: chunk 0 holds 1 and the scaled inputs, then degree
 *            by degree (each degree from a fresh chunk, at most 4 chunks a degree)
 *            m = parent * s_var, the parent one degree lower: a chunk of 8 is one
 *            multiply of its parents, permuted out of the previous degree's chunks (kept
 *            in registers: the chain of products never waits on memory), by its
 *            variables, permuted out of chunk 0;
 *   sums     outputs in groups of up to 8, each with its own accumulators; per chunk
 *            that any output of the group uses, one fused multiply-add per output of the
 *            chunk's 8 values with that output's 8 coefficients (0 where it has no term).
 * A monomial that is inf or nan then spoils every output of its group (0 * inf is nan),
 * where the plan keeps the outputs without a term on it finite: a ray with an output
 * that is not finite is evaluated again by the plan's interpreter.
 *
 * The results are the plan's sums in another order of additions and with fused
 * multiply-adds: they agree with the batch kernel's to rounding (1e-12 relative,
 * tested in test_poly), not bit for bit. Only on x86 with AVX-512, for at most 7 inputs;
 * elsewhere poly_fast declines and the plan's interpreter runs (poly_eval.c). */
#include "poly/poly_impl.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#if (defined(__x86_64__) || defined(__i386__)) && !defined(SPARSELENS_PORTABLE_KERNELS)
#define FAST_X86 1
#include <immintrin.h>
#endif

/* The most chunks a ray's values may take (on the stack): 512 values. */
#define FAST_MAXCHUNK 64
/* Chunks a degree may take: the previous degree's stay in registers. */
#define FAST_DEGREE 4
/* Outputs per group: one accumulator each, two sets of them in registers. */
#define FAST_GROUP 8

struct poly_fast {
    int nin, nout, nchunk;
    int64_t *idx;    /* per chunk c >= 1, 8 lanes: parent (bits 0..4: its lane among the
                        previous degree's chunks) and 1 + var (bits 16..18: the lane of
                        s_var in chunk 0) */
    int maxd;        /* the highest degree */
    int *first;      /* maxd + 2: degree d >= 2 in chunks first[d] .. first[d + 1] - 1, at
                        most FAST_DEGREE of them; first[1] = 0 */
    int ngroup;
    int *gfirst;     /* ngroup + 1: group g's records are gfirst[g] .. gfirst[g + 1] - 1 */
    int *rchunk;     /* per record: its chunk */
    double *rcoef;   /* per record: G x 8 coefficients (G the group's size), 64-byte aligned */
    int *rcoef_at;   /* per record: its first coefficient */
};

void poly_fast_free(poly_fast *f)
{
    if (!f)
        return;
    free(f->idx);
    free(f->first);
    free(f->gfirst);
    free(f->rchunk);
    free(f->rcoef);
    free(f->rcoef_at);
    free(f);
}

/* The monomials of the build: exponents, degree, parent and variable, by hash. */
typedef struct {
    int n, cap, nin;
    int *e, *deg, *parent, *var, *pos;
    index_hash h;
} fast_set;

struct fast_key {
    const fast_set *fs;
    const int *e;
};

static int fast_same(const void *ctx, int k)
{
    const struct fast_key *q = ctx;
    return memcmp(q->fs->e + (size_t)k * q->fs->nin, q->e, (size_t)q->fs->nin * sizeof(int)) == 0;
}

static int fast_find(const fast_set *fs, const int *e)
{
    struct fast_key q = {fs, e};
    return index_hash_find(&fs->h, index_hash_bytes(e, (size_t)fs->nin * sizeof(int)), fast_same,
                           &q);
}

/* The monomial e (added if new); -1 when out of memory. */
static int fast_add(fast_set *fs, const int *e)
{
    int k = fast_find(fs, e);
    if (k >= 0)
        return k;
    if (fs->n == fs->cap) {
        int nc = fs->cap ? 2 * fs->cap : 64;
        int *ne = realloc(fs->e, (size_t)nc * fs->nin * sizeof(int));
        if (ne)
            fs->e = ne;
        int *nd = realloc(fs->deg, (size_t)nc * sizeof(int));
        if (nd)
            fs->deg = nd;
        int *np = realloc(fs->parent, (size_t)nc * sizeof(int));
        if (np)
            fs->parent = np;
        int *nv = realloc(fs->var, (size_t)nc * sizeof(int));
        if (nv)
            fs->var = nv;
        int *npos = realloc(fs->pos, (size_t)nc * sizeof(int));
        if (npos)
            fs->pos = npos;
        if (!ne || !nd || !np || !nv || !npos)
            return -1;
        fs->cap = nc;
    }
    k = fs->n;
    if (index_hash_add(&fs->h, index_hash_bytes(e, (size_t)fs->nin * sizeof(int)), k) != 0)
        return -1;
    fs->n++;
    memcpy(fs->e + (size_t)k * fs->nin, e, (size_t)fs->nin * sizeof(int));
    int d = 0;
    for (int i = 0; i < fs->nin; i++)
        d += e[i];
    fs->deg[k] = d;
    fs->parent[k] = fs->var[k] = -1;
    return k;
}

static void fast_set_free(fast_set *fs)
{
    free(fs->e);
    free(fs->deg);
    free(fs->parent);
    free(fs->var);
    free(fs->pos);
    index_hash_free(&fs->h);
}

/* Every monomial of degree 2 or more gets a parent one degree lower: one that is there
 * already if any, else e less its last variable (added, and given a parent in turn). */
static int fast_close(fast_set *fs)
{
    int g[64];
    for (int k = 0; k < fs->n; k++) { /* fs->n grows as parents are added */
        if (fs->deg[k] < 2)
            continue;
        memcpy(g, fs->e + (size_t)k * fs->nin, (size_t)fs->nin * sizeof(int));
        int par = -1, var = -1;
        for (int i = fs->nin - 1; i >= 0 && par < 0; i--)
            if (g[i] > 0) {
                g[i]--;
                par = fast_find(fs, g);
                var = i;
                g[i]++;
            }
        if (par < 0) {
            for (var = fs->nin - 1; g[var] == 0; var--)
                ;
            g[var]--;
            par = fast_add(fs, g);
            if (par < 0)
                return -1;
        }
        fs->parent[k] = par;
        fs->var[k] = var;
    }
    return 0;
}

/* Places the monomials in chunks (fs->pos: value number) and fills idx and first;
 * returns the number of chunks, or -1 (also when a degree has more than FAST_DEGREE
 * chunks of monomials). */
static int fast_layout(poly_fast *f, fast_set *fs)
{
    int maxd = 1;
    for (int k = 0; k < fs->n; k++)
        if (fs->deg[k] > maxd)
            maxd = fs->deg[k];
    int *first = f->first = malloc((size_t)(maxd + 2) * sizeof(int)); /* per degree */
    int *width = calloc((size_t)maxd + 2, sizeof(int));
    f->maxd = maxd;
    if (!first || !width) {
        free(width);
        return -1;
    }
    for (int k = 0; k < fs->n; k++) {
        if (fs->deg[k] < 2) { /* chunk 0: the constant, then the inputs */
            int i = 0;
            while (i < fs->nin && fs->e[(size_t)k * fs->nin + i] == 0)
                i++;
            fs->pos[k] = fs->deg[k] == 0 ? 0 : 1 + i;
        } else {
            fs->pos[k] = width[fs->deg[k]]++; /* within its degree, for now */
        }
    }
    int nch = 1, wide = 0;
    first[1] = 0;
    for (int d = 2; d <= maxd; d++) {
        first[d] = nch;
        nch += (width[d] + 7) / 8;
        wide |= width[d] > 8 * FAST_DEGREE;
    }
    first[maxd + 1] = nch;
    free(width);
    f->idx = aligned_alloc(64, (size_t)nch * 8 * sizeof(int64_t));
    if (wide || nch > FAST_MAXCHUNK || !f->idx)
        return -1;
    for (int c = 0; c < 8 * nch; c++)
        f->idx[c] = 0; /* unused lanes: the constant times 1 */
    for (int k = 0; k < fs->n; k++)
        if (fs->deg[k] >= 2)
            fs->pos[k] += 8 * first[fs->deg[k]];
    for (int k = 0; k < fs->n; k++)
        if (fs->deg[k] >= 2)
            f->idx[fs->pos[k]] = (fs->pos[fs->parent[k]] - 8 * first[fs->deg[k] - 1]) |
                                 (int64_t)(1 + fs->var[k]) << 16;
    return nch;
}

/* The records of the sums: per group of outputs, the chunks it uses, with their
 * coefficients. */
static int fast_records(poly_fast *f, const fast_set *fs, const poly_out_terms *sums)
{
    const int nch = f->nchunk, nout = f->nout;
    f->ngroup = (nout + FAST_GROUP - 1) / FAST_GROUP;
    const size_t maxrec = (size_t)f->ngroup * nch;
    f->gfirst = malloc(((size_t)f->ngroup + 1) * sizeof(int));
    f->rchunk = malloc((maxrec + 1) * sizeof(int));
    f->rcoef_at = malloc((maxrec + 1) * sizeof(int));
    double *dense = calloc((size_t)nout * nch * 8 + 1, sizeof(double));
    unsigned char *has = calloc((size_t)nout * nch * 8 + 1, 1);
    if (!f->gfirst || !f->rchunk || !f->rcoef_at || !dense || !has) {
        free(dense);
        free(has);
        return -1;
    }
    for (int o = 0; o < nout; o++)
        for (int t = 0; t < sums[o].nterms; t++) {
            const int k = fast_find(fs, sums[o].exps + (size_t)t * fs->nin);
            const size_t at = (size_t)o * nch * 8 + fs->pos[k];
            dense[at] += sums[o].coef[t];
            has[at] = 1;
        }
    int nrec = 0, ncoef = 0;
    for (int g = 0; g < f->ngroup; g++) {
        const int o0 = g * FAST_GROUP, G = nout - o0 < FAST_GROUP ? nout - o0 : FAST_GROUP;
        f->gfirst[g] = nrec;
        for (int c = 0; c < nch; c++) {
            uint64_t mask = 0;
            for (int o = 0; o < G; o++)
                for (int l = 0; l < 8; l++)
                    mask |= (uint64_t)has[(size_t)(o0 + o) * nch * 8 + 8 * c + l] << (8 * o + l);
            if (!mask)
                continue;
            f->rchunk[nrec] = c;
            f->rcoef_at[nrec++] = ncoef;
            ncoef += 8 * G;
        }
    }
    f->gfirst[f->ngroup] = nrec;
    f->rcoef = aligned_alloc(64, ((size_t)ncoef + 8) * sizeof(double));
    if (!f->rcoef) {
        free(dense);
        free(has);
        return -1;
    }
    for (int g = 0; g < f->ngroup; g++) {
        const int o0 = g * FAST_GROUP, G = nout - o0 < FAST_GROUP ? nout - o0 : FAST_GROUP;
        for (int r = f->gfirst[g]; r < f->gfirst[g + 1]; r++)
            for (int o = 0; o < G; o++)
                memcpy(f->rcoef + f->rcoef_at[r] + 8 * o,
                       dense + (size_t)(o0 + o) * nch * 8 + 8 * f->rchunk[r], 8 * sizeof(double));
    }
    free(dense);
    free(has);
    return 0;
}

poly_fast *poly_fast_build(int nin, int nout, const poly_out_terms *sums)
{
    if (nin > 7 || nin < 1)
        return NULL; /* chunk 0 holds the constant and the inputs */
    for (int o = 0; o < nout; o++)
        if (sums[o].nterms && !sums[o].exps)
            return NULL; /* derivative sums: the interpreter's */
    poly_fast *f = calloc(1, sizeof *f);
    fast_set fs = {.nin = nin};
    int e[8] = {0}, ok = f != NULL;
    for (int i = -1; ok && i < nin; i++) { /* the constant, the inputs */
        if (i >= 0)
            e[i] = 1;
        ok = fast_add(&fs, e) >= 0;
        if (i >= 0)
            e[i] = 0;
    }
    for (int o = 0; ok && o < nout; o++)
        for (int t = 0; ok && t < sums[o].nterms; t++)
            ok = fast_add(&fs, sums[o].exps + (size_t)t * nin) >= 0;
    if (ok) {
        f->nin = nin;
        f->nout = nout;
        ok = fast_close(&fs) == 0 && (f->nchunk = fast_layout(f, &fs)) > 0 &&
             fast_records(f, &fs, sums) == 0;
    }
    fast_set_free(&fs);
    if (!ok) {
        poly_fast_free(f);
        return NULL;
    }
    return f;
}

#if defined(FAST_X86)
/* The sums of one group of G outputs (a constant after inlining: the accumulators stay
 * in registers), two accumulators each, taking the records in turn. */
__attribute__((target("avx512f,fma"), always_inline)) static inline void
fast_group(const int G, const poly_fast *f, int g, const double *m, double *out)
{
    __m512d a[FAST_GROUP], b[FAST_GROUP];
#pragma GCC unroll 8
    for (int o = 0; o < G; o++)
        a[o] = b[o] = _mm512_setzero_pd();
    int r = f->gfirst[g];
    const int end = f->gfirst[g + 1];
    const double *c = f->rcoef + f->rcoef_at[r];
    for (; r + 2 <= end; r += 2, c += 16 * G) {
        const __m512d m0 = _mm512_load_pd(m + 8 * f->rchunk[r]);
        const __m512d m1 = _mm512_load_pd(m + 8 * f->rchunk[r + 1]);
#pragma GCC unroll 8
        for (int o = 0; o < G; o++) {
            a[o] = _mm512_fmadd_pd(_mm512_load_pd(c + 8 * o), m0, a[o]);
            b[o] = _mm512_fmadd_pd(_mm512_load_pd(c + 8 * (G + o)), m1, b[o]);
        }
    }
    if (r < end) {
        const __m512d m0 = _mm512_load_pd(m + 8 * f->rchunk[r]);
#pragma GCC unroll 8
        for (int o = 0; o < G; o++)
            a[o] = _mm512_fmadd_pd(_mm512_load_pd(c + 8 * o), m0, a[o]);
    }
#pragma GCC unroll 8
    for (int o = 0; o < G; o++)
        out[o] = _mm512_reduce_add_pd(_mm512_add_pd(a[o], b[o]));
}

__attribute__((target("avx512f,fma"))) static void fast_run(const poly_fast *f,
                                                            const poly_system *s,
                                                            const double *in, double *out)
{
    _Alignas(64) double m[8 * FAST_MAXCHUNK];
    for (int l = 0; l < 8; l++)
        m[l] = 1;
    for (int i = 0; i < f->nin; i++) {
        m[1 + i] = in[i];
        poly_scale_column(s, i, &m[1 + i], 1);
    }
    const __m512d s0 = _mm512_load_pd(m);
    /* degree by degree, the previous one's chunks in registers (a degree of fewer
       chunks repeats its last: those lanes are never asked for): the chain of products
       runs through registers, a permute, a blend and a multiply a degree */
    __m512d p0 = s0, p1 = s0, p2 = s0, p3 = s0;
    const __m512i sel = _mm512_set1_epi64(16);
    for (int d = 2; d <= f->maxd; d++) {
        const int c0 = f->first[d], nc = f->first[d + 1] - c0;
        __m512d q[FAST_DEGREE];
#pragma GCC unroll 4
        for (int k = 0; k < FAST_DEGREE; k++) {
            if (k >= nc) {
                q[k] = k ? q[k - 1] : p0;
                continue;
            }
            const __m512i ix = _mm512_load_si512(f->idx + 8 * (c0 + k));
            const __m512d sv = _mm512_permutexvar_pd(_mm512_srli_epi64(ix, 16), s0);
            const __m512d lo = _mm512_permutex2var_pd(p0, ix, p1);
            const __m512d hi = _mm512_permutex2var_pd(p2, ix, p3);
            q[k] = _mm512_mul_pd(_mm512_mask_blend_pd(_mm512_test_epi64_mask(ix, sel), lo, hi), sv);
            _mm512_store_pd(m + 8 * (c0 + k), q[k]);
        }
        p0 = q[0];
        p1 = q[1];
        p2 = q[2];
        p3 = q[3];
    }
    for (int g = 0; g < f->ngroup; g++) {
        const int G = f->nout - g * FAST_GROUP < FAST_GROUP ? f->nout - g * FAST_GROUP : FAST_GROUP;
        double *o = out + g * FAST_GROUP;
        switch (G) {
        case 1: fast_group(1, f, g, m, o); break;
        case 2: fast_group(2, f, g, m, o); break;
        case 3: fast_group(3, f, g, m, o); break;
        case 4: fast_group(4, f, g, m, o); break;
        case 5: fast_group(5, f, g, m, o); break;
        case 6: fast_group(6, f, g, m, o); break;
        case 7: fast_group(7, f, g, m, o); break;
        default: fast_group(8, f, g, m, o); break;
        }
    }
}
#endif

int poly_fast_run(const poly_fast *f, const poly_system *s, const double *in, double *out)
{
#if defined(FAST_X86)
    if (f && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("fma")) {
        fast_run(f, s, in, out);
        /* a monomial that is inf or nan makes every output of its group non-finite
           here (0 * inf is nan), where the plan keeps the outputs without a term on it */
        int finite = 1;
        for (int o = 0; o < f->nout; o++)
            finite &= (out[o] - out[o]) == 0;
        if (finite)
            return 0;
    }
#else
    (void)f, (void)s, (void)in, (void)out;
#endif
    return -1;
}
