/* params_json.h - the `params` of a job as JSON, both ways.
 *
 * Does: turn a JSON object into a resolved, validated texopt_params (engine/core/params.h),
 * refusing unknown keys and wrong types by name; turn texopt_params back into JSON (the
 * job resource and params.json on disk). Does not: apply server policy (thread caps).
 *
 * Keys (all optional; absent = the engine's default):
 *   method            "perceptual" | "input" | "ssp" | "tewari" | "arap"
 *   budget            "relative_cost" | "texture_size" | "target_loss"; when absent it is
 *                     inferred from which of the three value keys is given (at most one)
 *   relative_cost     number in (0, 4]
 *   texture_width, texture_height   integers, both, with budget texture_size
 *   target_loss       number in (0, 1)
 *   epsilon, lambda_min   numbers in (0, 1)
 *   iterations        integer 1 .. 10000
 *   threads           integer 0 .. 1024 (0 = the server's threads per job)
 *   seed              integer 0 .. 2^53
 *   evaluate          boolean
 *   eval_resolution   integer 0 .. 8192 */
#ifndef TEXOPT_API_PARAMS_JSON_H
#define TEXOPT_API_PARAMS_JSON_H

#include <cjson/cJSON.h>

#include "texopt.h"

/* Fills *out from obj (NULL or an empty object = defaults), resolved and validated.
 * Returns TEXOPT_E_INVALID_ARGUMENT with a message naming the key on any problem. */
texopt_status api_params_from_json(const cJSON *obj, texopt_params *out, char *err, size_t err_len);

/* Parses text (JSON) then as api_params_from_json. */
texopt_status api_params_from_text(const char *text, size_t len, texopt_params *out, char *err, size_t err_len);

/* Adds key = text to obj as the JSON value it spells (number, true/false, else string),
 * for parameters given as URL query arguments. Returns 0, or -1 on allocation failure. */
int api_params_add_text(cJSON *obj, const char *key, const char *text);

/* A new JSON object with every field of params (caller frees with cJSON_Delete). */
cJSON *api_params_to_json(const texopt_params *params);

#endif
