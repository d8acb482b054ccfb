/* random_targets.c - see random_targets.h. */
#include "random_targets.h"

#include <stdlib.h>

#include "rng.h"

#define PI 3.14159265358979323846

texopt_triangle_target *random_targets(size_t n, uint64_t seed)
{
    texopt_triangle_target *t = calloc(n ? n : 1, sizeof *t);
    texopt_rng rng;
    texopt_rng_seed(&rng, seed);
    for (size_t i = 0; i < n && t; i++) {
        t[i].lambda1 = 0.2 + 0.8 * texopt_rng_uniform(&rng);
        t[i].lambda2 = 0.2 + 0.8 * texopt_rng_uniform(&rng);
        t[i].alpha = 0.5 * PI * texopt_rng_uniform(&rng);
        t[i].beta = 0.5 * PI * texopt_rng_uniform(&rng);
        t[i].w_rotation = 0.1 + 0.9 * texopt_rng_uniform(&rng);
        t[i].w_stretch = 0.1 + 0.9 * texopt_rng_uniform(&rng);
    }
    return t;
}
