/* cors.h - which Access-Control-Allow-Origin a response carries (--cors-origin).
 *
 * Does: match the request's Origin against the configured list. Does not: add headers
 * (api/http.c does). */
#ifndef TEXOPT_API_CORS_H
#define TEXOPT_API_CORS_H

/* allowed is "" (no CORS), "*" (any origin), or origins separated by commas, spaces
 * allowed ("https://a.example, http://localhost:5173"). Returns the value to send: "*",
 * origin itself when it is in the list, or NULL (no header). */
const char *api_cors_allow(const char *allowed, const char *origin);

#endif
