/* model_check.h - the upload's model is loaded once before its job is queued.
 *
 * Why: a client should hear "400 malformed" or "422 no TEXCOORD_0" at once, not find a failed
 * job minutes later. Does: texopt_model_load (engine/io/gltf_io.h) with the service's size
 * limits, images decoded (a corrupt texture is refused here too), then freed. Does not:
 * keep the model (the worker loads it again inside texopt_optimize_file). */
#ifndef TEXOPT_API_MODEL_CHECK_H
#define TEXOPT_API_MODEL_CHECK_H

#include <stddef.h>
#include <stdint.h>

#include "status.h"

/* Loads path with the limits. Returns the engine status; detail gets its message. */
texopt_status api_model_check(const char *path, uint64_t max_file_bytes, uint64_t max_pixels,
                              char *detail, size_t detail_len);

#endif
