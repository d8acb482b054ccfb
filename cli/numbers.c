/* numbers.c - see numbers.h. */
#include "numbers.h"

#include <errno.h>
#include <stdlib.h>

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
