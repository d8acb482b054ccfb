/* overshoot.h - how far a re-baked texture rings: its texels' values beyond the range of the
 * source texels around the point they were baked from.
 *
 * For every texel of `out` whose centre lies inside a triangle of the new layout, the centre
 * is mapped back to the source through that triangle (barycentric interpolation of the UVs)
 * and compared, channel by channel, with the minimum and maximum of the source texels whose
 * centres lie within `radius` output texels of that point (in source texels: radius times
 * the triangle's larger singular value of d source / d output, at least one texel). A texel
 * above the local maximum or below the local minimum overshoots by that much. A Lanczos-3
 * resize is the same measure with the input layout as the new one (uv_out = uv_in) and the
 * resized image as out; its negative lobes overshoot too, which is the baseline.
 * Wrap modes are ignored (the window is cut at the source's edges). Does not: decide what
 * counts as too much, or render anything. */
#ifndef TEXOPT_TEST_OVERSHOOT_H
#define TEXOPT_TEST_OVERSHOOT_H

#include <stddef.h>
#include <stdint.h>

#include "image.h"

typedef struct overshoot {
    double above, below; /* largest overshoot above the local max / below the local min, in
                            8-bit code values (value x 255) */
    double share;        /* fraction of measured texel channels over one code value either way */
    size_t texels;       /* texels measured */
} overshoot;

/* Measures out (baked over uv_out) against src (over uv_in), both UV arrays 2 floats per
 * vertex in [0,1] texture units, triangles 3 indices each; channels with a non-zero entry in
 * channel_mask (NULL: all; at least src->channels entries) count. Returns 0, or -1 on bad
 * arguments (channel counts differ, no triangle). */
int overshoot_measure(const texopt_image *src, const texopt_image *out, const float *uv_in, const float *uv_out,
                      const uint32_t *triangles, size_t triangle_count, double radius, const int *channel_mask,
                      overshoot *result);

#endif
