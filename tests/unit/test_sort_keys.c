/* test_sort_keys.c - the shared uint64_t comparator and edge key (engine/core/sort_keys.c).
 *
 * Keys that differ only in the high word, only in the low word, and by more than 2^63 (where
 * a comparator built on subtraction or a signed cast gets the order wrong) sort ascending
 * and are found by bsearch; (key, index) records sort by their key; an edge has one key
 * whichever way it runs, ordered by its smaller vertex. */
#include <stdlib.h>

#include "sort_keys.h"
#include "test.h"

TEST(keys_sort_ascending_across_the_whole_range)
{
    uint64_t key[6] = {UINT64_MAX, 1, (uint64_t)1 << 63, 0, ((uint64_t)1 << 32) | 5, ((uint64_t)1 << 32) | 4};
    const uint64_t want[6] = {0, 1, ((uint64_t)1 << 32) | 4, ((uint64_t)1 << 32) | 5, (uint64_t)1 << 63, UINT64_MAX};
    qsort(key, 6, sizeof *key, texopt_compare_u64);
    for (int i = 0; i < 6; i++)
        CHECK_MSG(key[i] == want[i], "key %d: %llu", i, (unsigned long long)key[i]);
    for (int i = 0; i < 6; i++)
        CHECK(bsearch(&want[i], key, 6, sizeof *key, texopt_compare_u64) == &key[i]);
    uint64_t absent = 2;
    CHECK(bsearch(&absent, key, 6, sizeof *key, texopt_compare_u64) == NULL);
    CHECK(texopt_compare_u64(&key[1], &key[1]) == 0);
}

TEST(records_led_by_a_key_sort_by_it)
{
    uint64_t record[8] = {30, 0, 10, 1, UINT64_MAX, 2, 20, 3};
    qsort(record, 4, 2 * sizeof *record, texopt_compare_u64);
    const uint64_t want[8] = {10, 1, 20, 3, 30, 0, UINT64_MAX, 2};
    for (int i = 0; i < 8; i++)
        CHECK(record[i] == want[i]);
}

TEST(an_edge_has_one_key_either_way)
{
    CHECK(texopt_edge_key(3, 9) == texopt_edge_key(9, 3));
    CHECK(texopt_edge_key(3, 9) == (((uint64_t)3 << 32) | 9));
    CHECK(texopt_edge_key(UINT32_MAX, 0) == (uint64_t)UINT32_MAX);
    CHECK(texopt_edge_key(2, 2) == (((uint64_t)2 << 32) | 2));
    CHECK(texopt_edge_key(1, UINT32_MAX) < texopt_edge_key(2, 3));
}
