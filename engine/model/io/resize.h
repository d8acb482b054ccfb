/* resize.h - resampling a whole texture to a new size with OpenImageIO's filters.
 *
 * Does: ImageBufAlgo::resize (a separable windowed filter; OpenImageIO's default for
 * downscaling is a Blackman-Harris of adaptive width, for upscaling a cubic) from one
 * in-memory texopt_image into a new one. Used by the evaluation to build "the input texture
 * at a lower cost" (Sun et al. 2022, section 5.1: the input parameterization with its
 * texture resized to the same cost, with a good filter). Does not: know about layouts or
 * wrap modes (edges are clamped), convert colour spaces. */
#ifndef TEXOPT_RESIZE_H
#define TEXOPT_RESIZE_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#include "image.h"
#include "status.h"

/* Resizes src into a new width x height image *dst (same channel count; the caller owns it
 * and frees it with texopt_image_destroy). On failure *dst is empty. */
texopt_status texopt_image_resize(const texopt_image *src, int width, int height, texopt_image *dst, char *err,
                                  size_t err_len);

#ifdef __cplusplus
}
#endif

#endif
