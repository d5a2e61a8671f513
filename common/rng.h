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

/* One word folded into a hash: the splitmix64 finaliser after adding the
 * golden-ratio increment. plm_hash64(a, b, c) is
 * plm_hash64_step(plm_hash64_step(plm_hash64_step(0, a), b), c), so callers
 * that hash several last words after the same first ones (the sampler)
 * fold those in once. Inline: the render path's hashing is hot. */
static inline uint64_t plm_hash64_step(uint64_t h, uint64_t word)
{
    uint64_t z = h ^ (word + 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

#endif
