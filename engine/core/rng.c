/* rng.c - xoshiro256** seeded with splitmix64 (Blackman and Vigna 2018). Does not provide
 * cryptographic randomness or any shared/global generator. */
#include "rng.h"

#include <math.h>

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

void texopt_rng_seed(texopt_rng *rng, uint64_t seed)
{
    uint64_t state = seed;
    for (int i = 0; i < 4; i++)
        rng->s[i] = splitmix64(&state);
}

uint64_t texopt_rng_next(texopt_rng *rng)
{
    uint64_t *s = rng->s;
    uint64_t result = rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

double texopt_rng_uniform(texopt_rng *rng)
{
    return (double)(texopt_rng_next(rng) >> 11) * 0x1.0p-53;
}

double texopt_rng_normal(texopt_rng *rng)
{
    /* 1 - u keeps the logarithm's argument in (0, 1]. */
    double u1 = 1.0 - texopt_rng_uniform(rng);
    double u2 = texopt_rng_uniform(rng);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

uint32_t texopt_rng_below(texopt_rng *rng, uint32_t n)
{
    /* Lemire's multiply-shift: the bias is at most n / 2^32. */
    return (uint32_t)(((texopt_rng_next(rng) >> 32) * (uint64_t)n) >> 32);
}
