/* json_depth.h - a bound on how deeply JSON text nests, checked before any parser sees it.
 *
 * Why: tinygltf's JSON parser and cJSON recurse once per nested array or object, so a small
 * document nesting 100,000 deep overflows a thread's stack (a crash, not an error). This scan
 * is a loop over the bytes with a counter: it tracks strings (and their escapes) so brackets
 * inside them do not count, and nothing else. Does not: validate the JSON (the parser that
 * follows does), or allocate. */
#ifndef TEXOPT_JSON_DEPTH_H
#define TEXOPT_JSON_DEPTH_H

#include <stddef.h>

/* The engine's C headers carry no linkage guards; wrap them for the C++ shims. */
#ifdef __cplusplus
extern "C" {
#endif

#include "status.h"

/* Deepest nesting of arrays and objects texopt parses. A glTF document needs about six
 * levels (plus what its extras hold); a params object two. */
#define TEXOPT_JSON_MAX_DEPTH 128

/* The stack texoptd gives every thread that parses (libmicrohttpd's connection threads,
 * the workers), whatever the process's ulimit: a document at the depth bound loads on an
 * eighth of it (tests/unit/test_hostile_input.c). */
#define TEXOPT_PARSE_STACK_BYTES ((size_t)8 << 20)

/* TEXOPT_OK when the JSON text in bytes[0, len) nests at most max_depth deep; else
 * TEXOPT_E_MALFORMED with "JSON nests deeper than <max_depth>" and the byte offset. Text
 * that is not JSON passes when its brackets stay within the bound (the parser refuses it). */
texopt_status texopt_json_check_depth(const void *bytes, size_t len, int max_depth, char *err, size_t err_len);

/* The same for a .glb (its JSON chunk) or .gltf (the whole text) held in memory: a .glb is
 * recognised by its magic; one too short to hold a JSON chunk header passes (the parser
 * refuses it). */
texopt_status texopt_gltf_check_depth(const void *bytes, size_t len, int max_depth, char *err, size_t err_len);

#ifdef __cplusplus
}
#endif

#endif
