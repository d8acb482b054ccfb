/* Tests of build_info.c: the version and revision compiled in, and their JSON member. */
#include <cjson/cJSON.h>
#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "build_info.h"
#include "test.h"

/* "unknown", or what `git describe --always --dirty` prints: hex commit digits (7 or more),
 * possibly after "TAG-N-g", possibly followed by "-dirty". */
static int looks_like_revision(const char *r)
{
    if (!strcmp(r, "unknown"))
        return 1;
    const char *g = strstr(r, "-g");
    const char *hex = g ? g + 2 : r;
    size_t digits = 0;
    while (isxdigit((unsigned char)hex[digits]) && !isupper((unsigned char)hex[digits]))
        digits++;
    return digits >= 7 && (hex[digits] == 0 || !strcmp(hex + digits, "-dirty"));
}

TEST(version_is_the_project_version_and_the_revision_a_commit)
{
    const char *v = texopt_version();
    int major, minor, patch;
    char rest;
    CHECK_MSG(sscanf(v, "%d.%d.%d%c", &major, &minor, &patch, &rest) == 3, "version '%s'", v);
    CHECK_MSG(looks_like_revision(texopt_build_revision()), "revision '%s'", texopt_build_revision());
    CHECK(looks_like_revision("0123456789ab") && looks_like_revision("0123456789ab-dirty") &&
          looks_like_revision("v1.0-3-g0123456789ab") && !looks_like_revision("") && !looks_like_revision("0123") &&
          !looks_like_revision("0123456789ab-old"));
}

TEST(json_member_names_version_and_revision)
{
    cJSON *root = cJSON_CreateObject();
    CHECK(root != NULL);
    texopt_build_info_add_json(root);
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(root, "texopt");
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(t, "version");
    const cJSON *r = cJSON_GetObjectItemCaseSensitive(t, "revision");
    CHECK(cJSON_IsString(v) && !strcmp(v->valuestring, texopt_version()));
    CHECK(cJSON_IsString(r) && !strcmp(r->valuestring, texopt_build_revision()));
    cJSON_Delete(root);
}
