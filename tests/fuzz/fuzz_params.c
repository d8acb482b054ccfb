/* fuzz_params.c - libFuzzer harness: a job's params as the service receives them, the JSON
 * text of a `params` part (api_params_from_text) or the arguments of a query string
 * (api_params_add_text per argument, then api_params_from_json). The first byte chooses:
 * even = JSON, odd = query string ("k=v&k=v", split here as libmicrohttpd splits it; the
 * URL decoding is libmicrohttpd's and not fuzzed here). Properties checked beyond memory
 * safety: a refusal has a message, and accepted params survive the round trip through
 * api_params_to_json unchanged (what params.json on disk and the job resource show). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "params_json.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char *printed(const texopt_params *p)
{
    cJSON *json = api_params_to_json(p);
    char *text = json ? cJSON_PrintUnformatted(json) : NULL;
    cJSON_Delete(json);
    return text;
}

/* A second parse of the accepted params' JSON gives the same params. */
static void check_round_trip(const texopt_params *p)
{
    char *first = printed(p);
    if (!first)
        return; /* out of memory */
    texopt_params again;
    char err[256] = "";
    if (api_params_from_text(first, strlen(first), &again, err, sizeof err) != TEXOPT_OK)
        __builtin_trap();
    char *second = printed(&again);
    if (second && strcmp(first, second) != 0)
        __builtin_trap();
    free(first);
    free(second);
}

/* "k=v&k2=v2" into obj; a missing '=' gives an empty value, as libmicrohttpd's does. */
static int add_query(cJSON *obj, const char *query)
{
    char *copy = strdup(query);
    if (!copy)
        return -1;
    int rc = 0;
    for (char *arg = copy, *next; arg && rc == 0; arg = next) {
        next = strchr(arg, '&');
        if (next)
            *next++ = '\0';
        char *eq = strchr(arg, '=');
        if (eq)
            *eq++ = '\0';
        rc = api_params_add_text(obj, arg, eq ? eq : "");
    }
    free(copy);
    return rc;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    texopt_params params;
    char err[256] = "";
    texopt_status status;
    if (data[0] & 1) {
        char *query = malloc(size);
        cJSON *obj = cJSON_CreateObject();
        int ok = query && obj;
        if (ok) {
            memcpy(query, data + 1, size - 1);
            query[size - 1] = '\0';
            ok = add_query(obj, query) == 0;
        }
        status = ok ? api_params_from_json(obj, &params, err, sizeof err) : TEXOPT_E_NOMEM;
        cJSON_Delete(obj);
        free(query);
        if (!ok)
            return 0;
    } else {
        /* Exactly the part's bytes, no terminating NUL: a read past len is caught. */
        char *text = malloc(size - 1 ? size - 1 : 1);
        if (!text)
            return 0;
        memcpy(text, data + 1, size - 1);
        status = api_params_from_text(text, size - 1, &params, err, sizeof err);
        free(text);
    }
    if (status != TEXOPT_OK && !err[0])
        __builtin_trap();
    if (status == TEXOPT_OK)
        check_round_trip(&params);
    return 0;
}
