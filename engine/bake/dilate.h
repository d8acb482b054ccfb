/* dilate.h - gutter padding: fills the texels no triangle covers from their nearest covered
 * texels.
 *
 * Does: breadth-first dilation over the 8-neighbourhood. Ring k (texels at chessboard
 * distance k from the covered set) takes the mean of its neighbours in rings < k, so colours
 * spread outward from chart borders without mixing in the empty background, and bilinear or
 * mip-mapped lookups that straddle a chart edge read the chart's own colour. With
 * max_distance <= 0 the whole image is filled (what a full mip chain needs).
 * Does not: bake anything (rebake.h does) or know about charts.
 *
 * Part of the re-bake that follows the mesh-wise layout of Sun et al. 2022, "Efficient
 * Texture Parameterization Driven by Perceptual-Loss-on-Screen"; the paper does not say how
 * it pads gutters. */
#ifndef TEXOPT_DILATE_H
#define TEXOPT_DILATE_H

#include <stdint.h>

#include "image.h"
#include "status.h"

/* covered: width * height bytes, non-zero where img holds a baked value. Texels within
 * max_distance (all when <= 0) get dilated values and are marked covered on return; an
 * image with no covered texel is left as it is. */
texopt_status texopt_dilate(texopt_image *img, uint8_t *covered, int max_distance, char *err, size_t err_len);

#endif
