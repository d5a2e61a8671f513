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

/* splitmix64 finaliser, applied after folding in each word. */
static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

uint64_t plm_hash64(uint64_t a, uint64_t b, uint64_t c)
{
    uint64_t h = mix64(a + 0x9e3779b97f4a7c15ULL);
    h = mix64(h ^ (b + 0x9e3779b97f4a7c15ULL));
    return mix64(h ^ (c + 0x9e3779b97f4a7c15ULL));
}
