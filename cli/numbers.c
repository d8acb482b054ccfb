/* numbers.c - see numbers.h. */
#include "numbers.h"

#include <errno.h>
#include <stdlib.h>

#define SEED_MAX 9007199254740992ULL /* 2^53 */

int cli_parse_int(const char *s, int lo, int hi, int *out)
{
    char *end = NULL;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (!s[0] || *end || errno != 0 || v < lo || v > hi)
        return -1;
    *out = (int)v;
    return 0;
}

int cli_parse_double(const char *s, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (!s[0] || *end || errno != 0 || !(v >= lo && v <= hi))
        return -1;
    *out = v;
    return 0;
}

int cli_parse_seed(const char *s, uint64_t *out)
{
    char *end = NULL;
    errno = 0;
    if (!s[0] || s[0] == '-' || s[0] == '+' || s[0] == ' ')
        return -1;
    unsigned long long v = strtoull(s, &end, 10);
    if (*end || errno != 0 || v > SEED_MAX)
        return -1;
    *out = (uint64_t)v;
    return 0;
}
