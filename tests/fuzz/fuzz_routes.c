/* fuzz_routes.c - libFuzzer harness: the request router (api/routes.c) on any path and method.
 * An input is "METHOD PATH" (the first space splits; no space: the whole input is the path
 * and the method is GET). Properties checked beyond memory safety: a matched route's template
 * with the id put in for {id} is the path again (so nothing else matches: no trailing bytes,
 * no upper-case or short ids), an asset path (/ui/{file}) names a flat file of safe
 * characters, an unmatched path has no id and allows nothing, and an
 * allowed method is in the route's Allow list. Does not: run the handlers (api/http.c). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "routes.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* template with {id} replaced by id. */
static void expand(const char *template, const char *id, char *out, size_t out_len)
{
    const char *brace = strstr(template, "{id}");
    if (!brace) {
        snprintf(out, out_len, "%s", template);
        return;
    }
    snprintf(out, out_len, "%.*s%s%s", (int)(brace - template), template, id, brace + 4);
}

/* Whether name is one the page's directory may serve: non-empty, of letters, digits, '.',
 * '_' and '-', not starting with '.' (no way out of the directory, no hidden file). */
static int is_flat_asset_name(const char *name)
{
    if (!name[0] || name[0] == '.')
        return 0;
    for (const char *c = name; *c; c++)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') || *c == '.' ||
              *c == '_' || *c == '-'))
            return 0;
    return 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *input = malloc(size + 1);
    if (!input)
        return 0;
    memcpy(input, data, size);
    input[size] = '\0';
    char *space = strchr(input, ' ');
    const char *method = "GET", *path = input;
    if (space) {
        *space = '\0';
        method = input;
        path = space + 1;
    }
    api_match m = api_route_match(path);
    const char *template = api_route_template(m.route);
    const char *allow = api_route_allow(m.route);
    int allowed = api_route_allows(m.route, method);
    if (!template || !allow || (unsigned)m.route >= ROUTE_COUNT)
        __builtin_trap();
    if (m.route == ROUTE_NOT_FOUND) {
        if (m.id[0] || allowed)
            __builtin_trap();
    } else if (m.route == ROUTE_ASSET) {
        if (m.id[0] || strncmp(path, "/ui/", 4) != 0 || !is_flat_asset_name(path + 4))
            __builtin_trap();
        if (allowed && (!method[0] || !strstr(allow, method)))
            __builtin_trap();
    } else {
        char expected[256];
        expand(template, m.id, expected, sizeof expected);
        if (strcmp(expected, path) != 0)
            __builtin_trap();
        if (allowed && (!method[0] || !strstr(allow, method)))
            __builtin_trap();
    }
    (void)api_route_is_health(m.route);
    free(input);
    return 0;
}
