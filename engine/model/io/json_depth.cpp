/* json_depth.cpp - the nesting bound of JSON and glTF text (see json_depth.h). */
#include "json_depth.h"

#include <cstdint>
#include <cstring>

extern "C" texopt_status texopt_json_check_depth(const void *bytes, size_t len, int max_depth, char *err,
                                                 size_t err_len)
{
    const unsigned char *p = static_cast<const unsigned char *>(bytes);
    int depth = 0;
    bool in_string = false, escaped = false;
    for (size_t i = 0; i < len; i++) {
        unsigned char c = p[i];
        if (in_string) {
            if (escaped)
                escaped = false;
            else if (c == '\\')
                escaped = true;
            else if (c == '"')
                in_string = false;
            continue;
        }
        if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max_depth)
                return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "JSON nests deeper than %d (at byte %zu)",
                                   max_depth, i);
        } else if ((c == ']' || c == '}') && depth > 0) {
            depth--;
        }
    }
    return TEXOPT_OK;
}

static uint32_t read_u32le(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

extern "C" texopt_status texopt_gltf_check_depth(const void *bytes, size_t len, int max_depth, char *err,
                                                 size_t err_len)
{
    const unsigned char *p = static_cast<const unsigned char *>(bytes);
    /* A .glb: 12-byte header, then the JSON chunk's length and type, then its text. */
    const size_t header = 12, chunk_header = 8;
    if (len < 4 || memcmp(p, "glTF", 4) != 0)
        return texopt_json_check_depth(bytes, len, max_depth, err, err_len);
    if (len < header + chunk_header)
        return TEXOPT_OK;
    size_t chunk = read_u32le(p + header);
    size_t available = len - header - chunk_header;
    return texopt_json_check_depth(p + header + chunk_header, chunk < available ? chunk : available, max_depth, err,
                                   err_len);
}
