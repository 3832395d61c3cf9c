#ifndef SPARSELENS_RNG_H
#define SPARSELENS_RNG_H
/* A small counter-based random number generator: the numbers of stream (seed, index)
 * depend on nothing else, so ray i gets the same random numbers whichever thread traces
 * it and however many rays come before it. Each stream is a splitmix64 sequence started
 * at a hash of (seed, index). Not for cryptography. */
#include <stdint.h>

typedef struct {
    uint64_t s;
} rng_t;

rng_t rng_stream(uint64_t seed, uint64_t index);
uint64_t rng_u64(rng_t *r);
double rng_uniform(rng_t *r); /* [0, 1), 53 random bits */

#endif
