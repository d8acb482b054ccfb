/* problem.c - problem+json bodies and the engine-status mapping (see problem.h). */
#include "problem.h"

#include <cjson/cJSON.h>
#include <stdio.h>

const char *api_status_title(int status)
{
    switch (status) {
    case 200: return "OK";
    case 202: return "Accepted";
    case 204: return "No Content";
    case 400: return "Bad Request";
    case 401: return "Unauthorized";
    case 404: return "Not Found";
    case 405: return "Method Not Allowed";
    case 409: return "Conflict";
    case 411: return "Length Required";
    case 413: return "Content Too Large";
    case 414: return "URI Too Long";
    case 415: return "Unsupported Media Type";
    case 422: return "Unprocessable Content";
    case 429: return "Too Many Requests";
    case 431: return "Request Header Fields Too Large";
    case 500: return "Internal Server Error";
    case 503: return "Service Unavailable";
    default: return "Error";
    }
}

char *api_problem_json(int status, const char *slug, const char *detail, const char *instance)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    char type[128];
    snprintf(type, sizeof type, "urn:texopt:problem:%s", slug);
    cJSON_AddStringToObject(o, "type", type);
    cJSON_AddStringToObject(o, "title", api_status_title(status));
    cJSON_AddNumberToObject(o, "status", status);
    cJSON_AddStringToObject(o, "detail", detail ? detail : "");
    if (instance)
        cJSON_AddStringToObject(o, "instance", instance);
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}

int api_status_from_engine(texopt_status status)
{
    switch (status) {
    case TEXOPT_E_MALFORMED:
    case TEXOPT_E_IO:
    case TEXOPT_E_INVALID_ARGUMENT: return 400;
    case TEXOPT_E_LIMIT: return 413;
    case TEXOPT_E_UNSUPPORTED: return 422;
    case TEXOPT_E_CANCELED: return 409;
    default: return 500;
    }
}

const char *api_slug_from_engine(texopt_status status)
{
    switch (status) {
    case TEXOPT_E_MALFORMED: return "malformed-model";
    case TEXOPT_E_IO: return "missing-file";
    case TEXOPT_E_INVALID_ARGUMENT: return "invalid-params";
    case TEXOPT_E_LIMIT: return "model-too-large";
    case TEXOPT_E_UNSUPPORTED: return "unsupported-model";
    case TEXOPT_E_CANCELED: return "canceled";
    case TEXOPT_E_NOMEM: return "out-of-memory";
    case TEXOPT_E_NUMERIC: return "numeric-failure";
    case TEXOPT_E_RENDER: return "render-failure";
    default: return "internal-error";
    }
}
