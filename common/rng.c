#include "common/rng.h"

void plm_rng_seed(plm_rng *rng, uint64_t seed, uint64_t stream)
{
    rng->state = 0u;
    rng->inc = (stream << 1u) | 1u;
    plm_rng_u32(rng);
    rng->state += seed;
    plm_rng_u32(rng);
}

uint32_t plm_rng_u32(plm_rng *rng)
{
    uint64_t old = rng->state;
    rng->state = old * 6364136223846793005ULL + rng->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
}

double plm_rng_uniform(plm_rng *rng)
{
    uint64_t hi = plm_rng_u32(rng), lo = plm_rng_u32(rng);
    uint64_t bits = ((hi << 32) | lo) >> 11; /* 53 random bits */
    return (double)bits * (1.0 / 9007199254740992.0);
}

uint64_t plm_hash64(uint64_t a, uint64_t b, uint64_t c)
{
    return plm_hash64_step(plm_hash64_step(plm_hash64_step(0, a), b), c);
}
