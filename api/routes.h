/* routes.h - the service's URL space: which paths exist and which methods each allows.
 *
 * Does: match a request path to a route (a template such as "/v1/jobs/{id}/result") and
 * extract the job id; say whether a method is allowed and build the Allow header. Does not:
 * handle requests (api/http.c does). The table in routes.c is the single list of routes;
 * tests check that openapi.yaml documents every one of them. */
#ifndef TEXOPT_API_ROUTES_H
#define TEXOPT_API_ROUTES_H

#include "queue.h"

typedef enum api_route {
    ROUTE_NOT_FOUND = 0,
    ROUTE_JOBS,
    ROUTE_JOB,
    ROUTE_JOB_EVENTS,
    ROUTE_JOB_RESULT,
    ROUTE_JOB_STATS,
    ROUTE_JOB_REPORT,
    ROUTE_HEALTHZ,
    ROUTE_READYZ,
    ROUTE_METRICS,
    ROUTE_OPENAPI,
    ROUTE_PARAMS,
    ROUTE_PAGE,
    ROUTE_ASSET,
    ROUTE_COUNT
} api_route;

typedef struct api_match {
    api_route route;
    char id[JOB_ID_LEN + 1]; /* for the /v1/jobs/{id}... routes */
} api_match;

/* Matches path (without the query string). A job id must be 32 lowercase hex digits; an
 * asset name (/ui/{file}) letters, digits, '.', '_' and '-', not starting with '.', so it
 * cannot leave the page's directory; any other path is ROUTE_NOT_FOUND. */
api_match api_route_match(const char *path);

/* The route's template ("/v1/jobs/{id}"; "unmatched" for ROUTE_NOT_FOUND), static. */
const char *api_route_template(api_route route);

/* Methods the route allows, as an Allow header value ("GET, HEAD, DELETE"), static. */
const char *api_route_allow(api_route route);

/* Whether method is allowed on route (HEAD wherever GET is; OPTIONS everywhere). */
int api_route_allows(api_route route, const char *method);

/* Whether the route is a health probe. */
int api_route_is_health(api_route route);

/* Whether the route answers without authentication: the health probes, and the page and its
 * files (a browser cannot send a token when it opens a page; the page holds no data). */
int api_route_is_public(api_route route);

#endif
