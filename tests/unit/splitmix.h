#ifndef SPARSELENS_TEST_SPLITMIX_H
#define SPARSELENS_TEST_SPLITMIX_H
/* A uniform in [0, 1) from a splitmix64 state: tests' reproducible random numbers,
 * independent of the library's own samplers. */
#include <stdint.h>

static inline double splitmix_uniform(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

#endif
