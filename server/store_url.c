/* store_url.c - the --store setting's kind and its loggable form (see store_url.h). */
#include "store_url.h"

#include <stdio.h>
#include <string.h>

static const char *after_scheme(const char *url)
{
    static const char *const schemes[] = {"postgresql://", "postgres://"};
    for (size_t i = 0; i < sizeof schemes / sizeof schemes[0]; i++)
        if (strncmp(url, schemes[i], strlen(schemes[i])) == 0)
            return url + strlen(schemes[i]);
    return NULL;
}

store_url_kind_t store_url_kind(const char *url)
{
    if (!url || !*url)
        return STORE_URL_DISK;
    return after_scheme(url) ? STORE_URL_POSTGRES : STORE_URL_INVALID;
}

void store_url_redact(const char *url, char *out, size_t out_len)
{
    const char *rest = url ? after_scheme(url) : NULL;
    const char *at = rest ? strchr(rest, '@') : NULL;
    const char *slash = rest ? strchr(rest, '/') : NULL;
    const char *colon = rest ? strchr(rest, ':') : NULL;
    /* user:password@host: the colon must come before the @, which must come before the path. */
    if (!at || (slash && slash < at) || !colon || colon > at) {
        snprintf(out, out_len, "%s", url ? url : "");
        return;
    }
    snprintf(out, out_len, "%.*s***%s", (int)(colon + 1 - url), url, at);
}
