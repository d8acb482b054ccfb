/* rng.h - a small explicit pseudo-random generator (xoshiro256**, seeded by splitmix64).
 *
 * Blackman and Vigna 2018, "Scrambled linear pseudorandom number generators". The state is
 * a plain struct owned by the caller, so every thread and every triangle can have its own
 * reproducible stream: no rand(), no hidden global state. Not for cryptography. */
#ifndef TEXOPT_RNG_H
#define TEXOPT_RNG_H

#include <stdint.h>

typedef struct texopt_rng {
    uint64_t s[4];
} texopt_rng;

/* Expands a 64-bit seed into a full state with splitmix64 (any seed is fine, 0 included). */
void texopt_rng_seed(texopt_rng *rng, uint64_t seed);

uint64_t texopt_rng_next(texopt_rng *rng);

/* Uniform double in [0, 1) with 53 random bits. */
double texopt_rng_uniform(texopt_rng *rng);

/* Standard normal deviate (Box-Muller, one of the pair; deterministic, no cached state). */
double texopt_rng_normal(texopt_rng *rng);

/* Uniform integer in [0, n) (n > 0), without modulo bias worth speaking of for n < 2^32. */
uint32_t texopt_rng_below(texopt_rng *rng, uint32_t n);

#endif
