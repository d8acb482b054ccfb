/* model_check.h - the upload's model is checked once before its job is queued.
 *
 * Why: a client should hear "400 malformed" or "422 no TEXCOORD_0" at once, not find a failed
 * job minutes later. Does: texopt_model_load (engine/model/io/gltf_io.h) with the service's size
 * limits and images read only as far as their headers (size and channels; the pixel cap is
 * checked from them), then freed. Does not: decode images: a 250 KB PNG may declare 16000 x
 * 16000 pixels, a gigabyte to decode on the connection's thread. The worker decodes them
 * (a corrupt texture fails the job then) under the memory budget (server/memory_budget.h),
 * and keeps nothing from here (texopt_optimize_file loads the model again). */
#ifndef TEXOPT_API_MODEL_CHECK_H
#define TEXOPT_API_MODEL_CHECK_H

#include <stddef.h>
#include <stdint.h>

#include "texopt.h"

/* Loads path with the limits, images as headers. Returns the engine status; detail gets its
 * message; *pixels the sum of width x height over the model's images. */
texopt_status api_model_check(const char *path, uint64_t max_file_bytes, uint64_t max_pixels, uint64_t *pixels,
                              char *detail, size_t detail_len);

#endif
