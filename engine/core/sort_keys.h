/* sort_keys.h - the 64-bit sort keys the engine's qsort and bsearch calls share: the
 * ascending comparator of uint64_t and the key of an undirected edge.
 *
 * An edge key puts the smaller vertex index in the high word, so sorted edge keys group the
 * uses of each edge whichever way its triangles run it. The comparator reads the first
 * uint64_t of each element, so it also sorts records that begin with a key (for example
 * (key, index) pairs). Not here: comparators of other types or with tie-breaks (they stay
 * with their one user); qsort is not stable, so equal keys come in no promised order. */
#ifndef TEXOPT_SORT_KEYS_H
#define TEXOPT_SORT_KEYS_H

#include <stdint.h>

/* qsort/bsearch comparator: -1, 0 or 1 as the uint64_t at a is below, equal to or above
 * the one at b. */
int texopt_compare_u64(const void *a, const void *b);

/* The key of the edge between vertices a and b, equal for (a, b) and (b, a). */
static inline uint64_t texopt_edge_key(uint32_t a, uint32_t b)
{
    return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}

#endif
