/* Low-discrepancy pixel samples (render_samples.h). */
#include "render/render_samples.h"

#include <math.h>

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
static inline uint64_t permute(uint64_t i, uint64_t n, const ld_perm *p)
{
    if (n <= 1) return 0;
    int bits = 64 - __builtin_clzll(n - 1);
    uint64_t mask = bits == 64 ? ~0ull : (1ull << bits) - 1;
    int s = bits / 2 + 1;
    do {
        i = ((i ^ p->k1) * p->m2) & mask;
        i ^= i >> s;
        i = ((i + p->k3) * p->m1) & mask;
        i ^= i >> s;
    } while (i >= n);
    return i;
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
 * change a bit only as a function of the bits below it (Laine and Karras 2011). */
static uint32_t owen_reversed(uint32_t r, uint64_t key)
{
    uint32_t k1 = (uint32_t)key, k2 = (uint32_t)(key >> 32);
    r += k1;
    r ^= r * (k2 << 1);
    r *= k1 | 1u;
    r ^= r * ((k1 ^ k2) & ~1u);
    r += k2;
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

void ld_2d_px(const ld_pixel *p, int dim, uint64_t n, uint64_t k, double out[2])
{
    uint32_t j = (uint32_t)permute(k, n, &p->perm2[dim]);
    /* van der Corput is j reversed: its scramble starts from j itself; 32 digits are
     * finer than any use here needs */
    uint32_t a = owen_reversed(j, p->scr_a[dim]);
    uint32_t b = owen_reversed(sobol_dim2_reversed(j), p->scr_b[dim]);
    out[0] = a * 0x1.0p-32;
    out[1] = b * 0x1.0p-32;
}

double ld_1d_px(const ld_pixel *p, int dim, uint64_t n, uint64_t k)
{
    uint64_t j = permute(k, n, &p->perm1[dim]);
    return ((double)j + shift_of(mix64(p->jit1[dim] + j))) / (double)n;
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
