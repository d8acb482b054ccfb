/* build_info.c - the version and source revision compiled in (build_info.h). */
#include "build_info.h"

#include <cjson/cJSON.h>

#include "texopt_revision.h"

const char *texopt_version(void)
{
    return TEXOPT_VERSION;
}

const char *texopt_build_revision(void)
{
    return TEXOPT_BUILD_REVISION;
}

void texopt_build_info_add_json(cJSON *parent)
{
    cJSON *o = cJSON_AddObjectToObject(parent, "texopt");
    cJSON_AddStringToObject(o, "version", texopt_version());
    cJSON_AddStringToObject(o, "revision", texopt_build_revision());
}
