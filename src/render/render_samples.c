/* Low-discrepancy pixel samples (render_samples.h). */
#include "render/render_samples.h"

#include <math.h>
#include <stddef.h>

static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

uint64_t ld_pixel_key(uint64_t seed, uint64_t pixel)
{
    return mix64(seed * 0x632BE59BD9B4E019ull + mix64(pixel + 0x9E3779B97F4A7C15ull));
}

static ld_perm perm_of(uint64_t key)
{
    ld_perm p = {key, (key >> 17 | key << 47) | 1, key * 0x9E3779B97F4A7C15ull, key | 1};
    return p;
}

/* A bijection of [0, 2^bits) (xor, odd multiply and xorshift steps are each invertible
 * modulo 2^bits), walked until it lands in [0, n): a permutation of [0, n). */
typedef struct {
    uint64_t n, mask;
    int s;
} perm_size;

static inline perm_size size_of(uint64_t n)
{
    int bits = n <= 1 ? 0 : 64 - __builtin_clzll(n - 1);
    perm_size z = {n, bits == 64 ? ~0ull : (1ull << bits) - 1, bits / 2 + 1};
    return z;
}

static inline uint64_t permute_sized(uint64_t i, perm_size z, const ld_perm *p)
{
    uint64_t n = z.n, mask = z.mask;
    int s = z.s;
    if (n <= 1) return 0;
    do {
        i = ((i ^ p->k1) * p->m2) & mask;
        i ^= i >> s;
        i = ((i + p->k3) * p->m1) & mask;
        i ^= i >> s;
    } while (i >= n);
    return i;
}

static inline uint64_t permute(uint64_t i, uint64_t n, const ld_perm *p)
{
    return permute_sized(i, size_of(n), p);
}

static double shift_of(uint64_t key)
{
    return (double)(key >> 11) * 0x1.0p-53;
}

/* The first two dimensions of the Sobol sequence, a (0, 2)-sequence in base 2: van der
 * Corput (the index's bits reversed) and the Pascal-matrix dimension. */
static uint32_t reverse32(uint32_t x)
{
    x = __builtin_bswap32(x);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x >> 4) & 0x0f0f0f0fu);
    x = ((x & 0x33333333u) << 2) | ((x >> 2) & 0x33333333u);
    return ((x & 0x55555555u) << 1) | ((x >> 1) & 0x55555555u);
}

static uint32_t sobol_dim2(uint32_t j)
{
    uint32_t x = 0, v = 1u << 31;
    for (; j; j >>= 1, v ^= v >> 1)
        if (j & 1) x ^= v;
    return x;
}

/* reverse32(sobol_dim2(j)) for j < 2^16, byte by byte: the dimension is linear over
 * GF(2) in j's bits, so a byte's table entries xor together. The loop's trip count is
 * j's length, which a pixel's permuted indices change from sample to sample (a
 * mispredicted branch or two a draw); the tables are filled once, before main. */
static uint32_t sobol_rev_lo[256], sobol_rev_hi[256];

__attribute__((constructor)) static void sobol_tables(void)
{
    for (uint32_t b = 0; b < 256; b++) {
        sobol_rev_lo[b] = reverse32(sobol_dim2(b));
        sobol_rev_hi[b] = reverse32(sobol_dim2(b << 8));
    }
}

static inline uint32_t sobol_dim2_reversed(uint32_t j)
{
    if (j < 65536) return sobol_rev_lo[j & 255] ^ sobol_rev_hi[j >> 8];
    return reverse32(sobol_dim2(j));
}

/* An Owen scramble (owen_reversed takes x with its bits already reversed) of the binary
 * fraction x (MSB = 1/2): each digit is flipped by a
 * hash of the digits above it. With the bits reversed, "above" becomes "below", and
 * adding a constant, multiplying by an odd number or xoring with x times an even number
 * change a bit only as a function of the bits below it (Laine and Karras 2011). The
 * steps are written once for a 32-bit word and for four lanes of them (owen4). */
#define OWEN_STEPS(r, key)                                                                   \
    do {                                                                                     \
        uint32_t k1_ = (uint32_t)(key), k2_ = (uint32_t)((key) >> 32);                       \
        r += k1_;                                                                            \
        r ^= r * (k2_ << 1);                                                                 \
        r *= k1_ | 1u;                                                                       \
        r ^= r * ((k1_ ^ k2_) & ~1u);                                                        \
        r += k2_;                                                                            \
    } while (0)

static uint32_t owen_reversed(uint32_t r, uint64_t key)
{
    OWEN_STEPS(r, key);
    return reverse32(r);
}

static uint64_t key2(uint64_t key, int dim)
{
    return mix64(key ^ (0xD1B54A32D192ED03ull * (uint64_t)(dim + 1)));
}

static uint64_t key1(uint64_t key, int dim)
{
    return mix64(key ^ (0xA24BAED4963EE407ull * (uint64_t)(dim + 1)));
}

void ld_pixel_init(ld_pixel *p, uint64_t key)
{
    for (int d = 0; d < LD_DIMS; d++) {
        uint64_t k2 = key2(key, d), k1 = key1(key, d);
        p->perm2[d] = perm_of(k2), p->scr_a[d] = mix64(k2 + 1), p->scr_b[d] = mix64(k2 + 2);
        p->perm1[d] = perm_of(k1), p->jit1[d] = k1 + 3;
    }
}

static inline void draw_2d(const ld_pixel *p, int dim, perm_size z, uint64_t k, double out[2])
{
    uint32_t j = (uint32_t)permute_sized(k, z, &p->perm2[dim]);
    /* van der Corput is j reversed: its scramble starts from j itself; 32 digits are
     * finer than any use here needs */
    uint32_t a = owen_reversed(j, p->scr_a[dim]);
    uint32_t b = owen_reversed(sobol_dim2_reversed(j), p->scr_b[dim]);
    out[0] = a * 0x1.0p-32;
    out[1] = b * 0x1.0p-32;
}

void ld_2d_px(const ld_pixel *p, int dim, uint64_t n, uint64_t k, double out[2])
{
    draw_2d(p, dim, size_of(n), k, out);
}

void ld_2d_px2(const ld_pixel *p, int dim_a, int dim_b, uint64_t n, uint64_t k, double a[2],
               double b[2])
{
    perm_size z = size_of(n);
    draw_2d(p, dim_a, z, k, a);
    draw_2d(p, dim_b, z, k, b);
}

double ld_1d_px(const ld_pixel *p, int dim, uint64_t n, uint64_t k)
{
    uint64_t j = permute(k, n, &p->perm1[dim]);
    return ((double)j + shift_of(mix64(p->jit1[dim] + j))) / (double)n;
}

/* Runs of a pixel's samples, four at a time (lens-render draws a block's samples pixel
 * by pixel): the integers of draw_2d and ld_1d_px lane by lane. With n < 2^32 every step
 * of permute keeps to the low 32 bits (a product's low half depends on the operands' low
 * halves only), so 32-bit lanes give its values; the Sobol tables are read lane by lane. */
typedef uint32_t v4u __attribute__((vector_size(16)));

/* reverse32, owen_reversed and permute_sized on a vector V of 32-bit lanes (ATTR: the
 * instruction set it is compiled for), written once for four lanes and for sixteen */
#define LANE_FUNCS(V, NAME, ATTR)                                                            \
    /* the bytes swapped by shifts and masks: GCC's __builtin_shuffle is unknown to clang   \
     * (the fuzz build), and compilers turn this into one byte shuffle anyway */            \
    ATTR static inline V reverse_##NAME(V x)                                                 \
    {                                                                                        \
        x = (x >> 24) | ((x >> 8) & 0xff00u) | ((x << 8) & 0xff0000u) | (x << 24);           \
        x = ((x & 0x0f0f0f0fu) << 4) | ((x >> 4) & 0x0f0f0f0fu);                             \
        x = ((x & 0x33333333u) << 2) | ((x >> 2) & 0x33333333u);                             \
        return ((x & 0x55555555u) << 1) | ((x >> 1) & 0x55555555u);                         \
    }                                                                                        \
    ATTR static inline V owen_##NAME(V r, uint64_t key)                                      \
    {                                                                                        \
        OWEN_STEPS(r, key);                                                                  \
        return reverse_##NAME(r);                                                            \
    }                                                                                        \
    /* a lane that has landed in [0, n) keeps its value */                                   \
    ATTR static inline V permute_##NAME(V i, perm_size z, const ld_perm *p)                  \
    {                                                                                        \
        uint32_t k1 = (uint32_t)p->k1, m2 = (uint32_t)p->m2, k3 = (uint32_t)p->k3;           \
        uint32_t m1 = (uint32_t)p->m1, mask = (uint32_t)z.mask, n = (uint32_t)z.n;           \
        V todo = (V)(i == i);                                                                \
        for (;;) {                                                                           \
            V x = ((i ^ k1) * m2) & mask;                                                    \
            x ^= x >> z.s;                                                                   \
            x = ((x + k3) * m1) & mask;                                                      \
            x ^= x >> z.s;                                                                   \
            i = (x & todo) | (i & ~todo);                                                    \
            todo &= (V)(i >= n);                                                             \
            uint32_t any = 0;                                                                \
            for (int l = 0; l < (int)(sizeof(V) / 4); l++) any |= todo[l];                  \
            if (!any) return i;                                                              \
        }                                                                                    \
    }

LANE_FUNCS(v4u, 4, )
#define owen4 owen_4
#define permute4 permute_4

/* The samples of a run that go four at a time (the lanes hold n: below 2^32), and the
 * permuted indices of samples k0 + c .. k0 + c + 3. */
static int in_fours(uint64_t n, int count)
{
    return n > 1 && n < 0xffffffffu ? count / 4 * 4 : 0;
}

static inline v4u permuted4(uint64_t k0, int c, perm_size z, const ld_perm *p)
{
    uint32_t k = (uint32_t)(k0 + c);
    return permute4((v4u){k, k + 1, k + 2, k + 3}, z, p);
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(SPARSELENS_PORTABLE_KERNELS)
#include <immintrin.h>
/* Sixteen samples a step where the processor has AVX-512 (a run of a pixel's 32 samples
 * is two steps, against eight of four lanes); the Sobol tables read by gathers, so only
 * for indices below 2^16 (n <= 65536). */
typedef uint32_t v16u __attribute__((vector_size(64)));
#define AVX512 __attribute__((target("avx512f")))
LANE_FUNCS(v16u, 16, AVX512)

AVX512 static v16u sobol16(v16u j)
{
    __m512i lo = _mm512_i32gather_epi32((__m512i)(j & 255u), (const void *)sobol_rev_lo, 4);
    __m512i hi = _mm512_i32gather_epi32((__m512i)(j >> 8), (const void *)sobol_rev_hi, 4);
    return (v16u)lo ^ (v16u)hi;
}

/* samples k0 + c, c < count rounded down to 16, of ld_2d_run; returns how many */
AVX512 static int run16(const ld_pixel *p, int dim, perm_size z, uint64_t k0, int count,
                        double *out, int stride)
{
    const v16u iota = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
    int c = 0;
    for (; c + 16 <= count; c += 16) {
        v16u j = permute_16((uint32_t)(k0 + c) + iota, z, &p->perm2[dim]);
        v16u a = owen_16(j, p->scr_a[dim]), b = owen_16(sobol16(j), p->scr_b[dim]);
        double da[16], db[16];
        for (int h = 0; h < 2; h++) { /* u32 -> double exactly, then the exact scaling */
            __m256i ah = h ? _mm512_extracti64x4_epi64((__m512i)a, 1) : _mm512_castsi512_si256((__m512i)a);
            __m256i bh = h ? _mm512_extracti64x4_epi64((__m512i)b, 1) : _mm512_castsi512_si256((__m512i)b);
            _mm512_storeu_pd(da + 8 * h, _mm512_mul_pd(_mm512_cvtepu32_pd(ah), _mm512_set1_pd(0x1.0p-32)));
            _mm512_storeu_pd(db + 8 * h, _mm512_mul_pd(_mm512_cvtepu32_pd(bh), _mm512_set1_pd(0x1.0p-32)));
        }
        for (int l = 0; l < 16; l++) {
            double *o = out + (size_t)(c + l) * stride;
            o[0] = da[l], o[1] = db[l];
        }
    }
    return c;
}

static int sixteen_ok(void)
{
    static int ok = -1;
    if (ok < 0) ok = __builtin_cpu_supports("avx512f") != 0;
    return ok;
}
#else
static int run16(const ld_pixel *p, int dim, perm_size z, uint64_t k0, int count, double *out,
                 int stride)
{
    (void)p, (void)dim, (void)z, (void)k0, (void)count, (void)out, (void)stride;
    return 0;
}
static int sixteen_ok(void)
{
    return 0;
}
#endif

void ld_2d_run(const ld_pixel *p, int dim, uint64_t n, uint64_t k0, int count, double *out,
               int stride)
{
    perm_size z = size_of(n);
    int c = 0, fours = in_fours(n, count);
    if (fours && n <= 65536 && sixteen_ok()) c = run16(p, dim, z, k0, fours, out, stride);
    for (; c < fours; c += 4) {
        v4u j = permuted4(k0, c, z, &p->perm2[dim]);
        v4u s = {sobol_dim2_reversed(j[0]), sobol_dim2_reversed(j[1]), sobol_dim2_reversed(j[2]),
                 sobol_dim2_reversed(j[3])};
        v4u a = owen4(j, p->scr_a[dim]), b = owen4(s, p->scr_b[dim]);
        for (int l = 0; l < 4; l++) {
            double *o = out + (size_t)(c + l) * stride;
            o[0] = a[l] * 0x1.0p-32;
            o[1] = b[l] * 0x1.0p-32;
        }
    }
    for (; c < count; c++) draw_2d(p, dim, z, k0 + c, out + (size_t)c * stride);
}

void ld_1d_run(const ld_pixel *p, int dim, uint64_t n, uint64_t k0, int count, double *out,
               int stride)
{
    int c = 0, fours = in_fours(n, count);
    for (; c < fours; c += 4) {
        v4u j = permuted4(k0, c, size_of(n), &p->perm1[dim]);
        for (int l = 0; l < 4; l++)
            out[(size_t)(c + l) * stride] =
                ((double)j[l] + shift_of(mix64(p->jit1[dim] + j[l]))) / (double)n;
    }
    for (; c < count; c++) out[(size_t)c * stride] = ld_1d_px(p, dim, n, k0 + c);
}

void ld_2d(uint64_t key, int dim, uint64_t n, uint64_t k, double out[2])
{
    ld_pixel p;
    ld_pixel_init(&p, key);
    ld_2d_px(&p, dim, n, k, out);
}

double ld_1d(uint64_t key, int dim, uint64_t n, uint64_t k)
{
    ld_pixel p;
    ld_pixel_init(&p, key);
    return ld_1d_px(&p, dim, n, k);
}
