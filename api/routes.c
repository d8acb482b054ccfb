/* routes.c - the route table and path matching (see routes.h). */
#include "routes.h"

#include <string.h>

typedef struct route_entry {
    const char *template;
    const char *allow;
} route_entry;

static const route_entry table[ROUTE_COUNT] = {
    [ROUTE_NOT_FOUND] = {"unmatched", ""},
    [ROUTE_JOBS] = {"/v1/jobs", "GET, HEAD, POST, OPTIONS"},
    [ROUTE_JOB] = {"/v1/jobs/{id}", "GET, HEAD, DELETE, OPTIONS"},
    [ROUTE_JOB_EVENTS] = {"/v1/jobs/{id}/events", "GET, OPTIONS"},
    [ROUTE_JOB_RESULT] = {"/v1/jobs/{id}/result", "GET, HEAD, OPTIONS"},
    [ROUTE_JOB_STATS] = {"/v1/jobs/{id}/stats", "GET, HEAD, OPTIONS"},
    [ROUTE_JOB_REPORT] = {"/v1/jobs/{id}/report", "GET, HEAD, OPTIONS"},
    [ROUTE_HEALTHZ] = {"/healthz", "GET, HEAD, OPTIONS"},
    [ROUTE_READYZ] = {"/readyz", "GET, HEAD, OPTIONS"},
    [ROUTE_METRICS] = {"/metrics", "GET, HEAD, OPTIONS"},
    [ROUTE_OPENAPI] = {"/openapi.yaml", "GET, HEAD, OPTIONS"},
    [ROUTE_PARAMS] = {"/v1/params", "GET, HEAD, OPTIONS"},
    [ROUTE_PAGE] = {"/", "GET, HEAD, OPTIONS"},
    [ROUTE_ASSET] = {"/ui/{file}", "GET, HEAD, OPTIONS"},
};

#define MAX_ASSET_NAME 100

static int is_job_id(const char *s, size_t len)
{
    if (len != JOB_ID_LEN)
        return 0;
    for (size_t i = 0; i < len; i++)
        if (!((s[i] >= '0' && s[i] <= '9') || (s[i] >= 'a' && s[i] <= 'f')))
            return 0;
    return 1;
}

static int is_asset_name(const char *s)
{
    size_t n = strlen(s);
    if (n == 0 || n > MAX_ASSET_NAME || s[0] == '.')
        return 0;
    for (size_t i = 0; i < n; i++)
        if (!((s[i] >= '0' && s[i] <= '9') || (s[i] >= 'a' && s[i] <= 'z') || (s[i] >= 'A' && s[i] <= 'Z') ||
              s[i] == '.' || s[i] == '_' || s[i] == '-'))
            return 0;
    return 1;
}

static api_route job_subroute(const char *rest)
{
    if (*rest == '\0')
        return ROUTE_JOB;
    if (strcmp(rest, "/events") == 0)
        return ROUTE_JOB_EVENTS;
    if (strcmp(rest, "/result") == 0)
        return ROUTE_JOB_RESULT;
    if (strcmp(rest, "/stats") == 0)
        return ROUTE_JOB_STATS;
    if (strcmp(rest, "/report") == 0)
        return ROUTE_JOB_REPORT;
    return ROUTE_NOT_FOUND;
}

api_match api_route_match(const char *path)
{
    api_match m = {ROUTE_NOT_FOUND, ""};
    static const api_route fixed[] = {ROUTE_JOBS,    ROUTE_HEALTHZ, ROUTE_READYZ, ROUTE_METRICS,
                                      ROUTE_OPENAPI, ROUTE_PARAMS,  ROUTE_PAGE};
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++)
        if (strcmp(path, table[fixed[i]].template) == 0) {
            m.route = fixed[i];
            return m;
        }
    static const char ui[] = "/ui/";
    if (strncmp(path, ui, sizeof ui - 1) == 0) {
        if (is_asset_name(path + sizeof ui - 1))
            m.route = ROUTE_ASSET;
        return m;
    }
    static const char prefix[] = "/v1/jobs/";
    if (strncmp(path, prefix, sizeof prefix - 1) != 0)
        return m;
    const char *id = path + sizeof prefix - 1;
    const char *slash = strchr(id, '/');
    size_t id_len = slash ? (size_t)(slash - id) : strlen(id);
    if (!is_job_id(id, id_len))
        return m;
    m.route = job_subroute(id + id_len);
    if (m.route != ROUTE_NOT_FOUND) {
        memcpy(m.id, id, JOB_ID_LEN);
        m.id[JOB_ID_LEN] = '\0';
    }
    return m;
}

const char *api_route_template(api_route route)
{
    return (unsigned)route < ROUTE_COUNT ? table[route].template : "unmatched";
}

const char *api_route_allow(api_route route)
{
    return (unsigned)route < ROUTE_COUNT ? table[route].allow : "";
}

int api_route_allows(api_route route, const char *method)
{
    const char *allow = api_route_allow(route);
    size_t n = strlen(method);
    if (n == 0) /* "" would match at every position without advancing */
        return 0;
    for (const char *p = allow; (p = strstr(p, method)) != NULL; p += n) {
        int starts = p == allow || p[-1] == ' ';
        int ends = p[n] == ',' || p[n] == '\0';
        if (starts && ends)
            return 1;
    }
    return 0;
}

int api_route_is_health(api_route route)
{
    return route == ROUTE_HEALTHZ || route == ROUTE_READYZ;
}

int api_route_is_public(api_route route)
{
    return api_route_is_health(route) || route == ROUTE_PAGE || route == ROUTE_ASSET;
}
