/* splitmix64 (Steele, Lea, Flood 2014) as a stream generator keyed by (seed, index). */
#include "sparselens/rng.h"

#define GOLDEN 0x9e3779b97f4a7c15ULL

static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

rng_t rng_stream(uint64_t seed, uint64_t index)
{
    /* Two rounds of mixing so that neighbouring seeds and indices start far apart. */
    rng_t r = {mix64(mix64(seed + GOLDEN) ^ (index * 0xd1b54a32d192ed03ULL + 0x632be59bd9b4e019ULL))};
    return r;
}

uint64_t rng_u64(rng_t *r)
{
    r->s += GOLDEN;
    return mix64(r->s);
}

double rng_uniform(rng_t *r)
{
    return (double)(rng_u64(r) >> 11) * (1.0 / 9007199254740992.0);
}
