/* PCG32 random numbers (O'Neill 2014): small state, independent streams, so
 * every pixel sample or test case can own a reproducible sequence. */
#ifndef PLUMAGE_COMMON_RNG_H
#define PLUMAGE_COMMON_RNG_H

#include <stdint.h>

typedef struct plm_rng {
    uint64_t state;
    uint64_t inc;
} plm_rng;

/* Same (seed, stream) gives the same sequence on every machine. */
void plm_rng_seed(plm_rng *rng, uint64_t seed, uint64_t stream);
uint32_t plm_rng_u32(plm_rng *rng);
/* Uniform in [0, 1), with 53 bits. */
double plm_rng_uniform(plm_rng *rng);

/* A 64-bit mix of several integers, for deriving seeds (pixel, sample, seed). */
uint64_t plm_hash64(uint64_t a, uint64_t b, uint64_t c);

#endif
