/* web.h - the page texoptd serves at / and its files at /ui/{file}.
 *
 * Does: map a request path to a file of the page's directory (--web-dir), with its
 * Content-Type, and answer it with validation caching (ETag, Cache-Control: no-cache) and
 * a Content-Security-Policy that keeps the page to its own origin; a symbolic link is not
 * followed (404). Does not: decide
 * which names are safe (routes.c lets only flat names through /ui/), or authenticate (the
 * page is public; it sends the token the user gives it with each API call). */
#ifndef TEXOPT_API_WEB_H
#define TEXOPT_API_WEB_H

#include <stddef.h>

#include "routes.h"

/* The file, relative to the page's directory, that serves path on route ("index.html" for
 * ROUTE_PAGE, "ui/<name>" for ROUTE_ASSET). Returns 0, or -1 for any other route or when
 * out is too small. */
int web_file_name(api_route route, const char *path, char *out, size_t out_len);

/* The Content-Type for a file name, by its extension; application/octet-stream when unknown. */
const char *web_content_type(const char *name);

#endif
