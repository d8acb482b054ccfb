/* random_targets.h - a deliberately conflicting field of stage-1 targets for stage-2 tests:
 * per triangle lambda1, lambda2 in [0.2, 1], alpha and beta in [0, pi/2), rotation and
 * stretch weights in [0.1, 1], from texopt_rng with `seed` (test_meshwise_models_slow.c,
 * test_scaffold_models_slow.c). Caller frees; NULL when memory runs out. */
#ifndef TEXOPT_TEST_RANDOM_TARGETS_H
#define TEXOPT_TEST_RANDOM_TARGETS_H

#include <stddef.h>
#include <stdint.h>

#include "target.h"

texopt_triangle_target *random_targets(size_t n, uint64_t seed);

#endif
