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

/* A bijection of [0, 2^bits) (xor, odd multiply and xorshift steps are each invertible
 * modulo 2^bits), walked until it lands in [0, n): a permutation of [0, n). */
static uint64_t permute(uint64_t i, uint64_t n, uint64_t key)
{
    if (n <= 1) return 0;
    int bits = 64 - __builtin_clzll(n - 1);
    uint64_t mask = bits == 64 ? ~0ull : (1ull << bits) - 1;
    int s = bits / 2 + 1;
    uint64_t k1 = key, k2 = key >> 17 | key << 47, k3 = key * 0x9E3779B97F4A7C15ull;
    do {
        i = ((i ^ k1) * (k2 | 1)) & mask;
        i ^= i >> s;
        i = ((i + k3) * (k1 | 1)) & mask;
        i ^= i >> s;
    } while (i >= n);
    return i;
}

static double shift_of(uint64_t key)
{
    return (double)(key >> 11) * 0x1.0p-53;
}

void ld_2d(uint64_t key, int dim, uint64_t n, uint64_t k, double out[2])
{
    /* R2: alpha = (1/g, 1/g^2), g the plastic number, the root of g^3 = g + 1 */
    static const double a1 = 0.75487766624669276005, a2 = 0.56984029099805326591;
    uint64_t kd = mix64(key ^ (0xD1B54A32D192ED03ull * (uint64_t)(dim + 1)));
    double j = (double)permute(k, n, kd);
    double x = j * a1 + shift_of(mix64(kd + 1)), y = j * a2 + shift_of(mix64(kd + 2));
    out[0] = x - floor(x);
    out[1] = y - floor(y);
}

double ld_1d(uint64_t key, int dim, uint64_t n, uint64_t k)
{
    static const double phi = 0.61803398874989484820; /* golden ratio - 1 */
    uint64_t kd = mix64(key ^ (0xA24BAED4963EE407ull * (uint64_t)(dim + 1)));
    double x = (double)permute(k, n, kd) * phi + shift_of(mix64(kd + 1));
    return x - floor(x);
}
