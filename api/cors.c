/* cors.c - matching a request's Origin against --cors-origin (see cors.h). */
#include "cors.h"

#include <string.h>

const char *api_cors_allow(const char *allowed, const char *origin)
{
    if (!allowed[0])
        return NULL;
    if (strcmp(allowed, "*") == 0)
        return "*";
    if (!origin || !origin[0])
        return NULL;
    size_t n = strlen(origin);
    for (const char *p = allowed; *p;) {
        while (*p == ' ' || *p == ',')
            p++;
        size_t len = strcspn(p, ", ");
        if (len == n && strncmp(p, origin, n) == 0)
            return origin;
        p += len;
    }
    return NULL;
}
