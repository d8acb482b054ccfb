/* sort_keys.c - the shared uint64_t comparator (sort_keys.h). */
#include "sort_keys.h"

int texopt_compare_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}
