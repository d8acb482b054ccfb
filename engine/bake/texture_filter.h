/* texture_filter.h - prefiltered (mip-mapped, anisotropic) lookups into one texture.
 *
 * Does: build a box-filtered mip pyramid of an image once, then answer "what does this
 * input texture look like averaged over the footprint of one output texel" for any affine
 * footprint: the output texel's unit square mapped into the input by a 2x2 Jacobian. A
 * footprint no larger than one input texel is a plain bilinear lookup of level 0 (so an
 * identity or magnifying map reproduces the input exactly at texel centres); a larger one
 * takes up to 16 trilinear probes along the footprint's major axis at the level of its
 * minor axis (the usual anisotropic-filtering scheme of GPUs, after Heckbert 1989 and
 * Schilling et al. 1996). Wrap modes of glTF samplers are respected at every level.
 * Does not: convert colour spaces (values stay as encoded, see image.h), or know about
 * meshes: re-baking a layout (rebake.h) uses it.
 *
 * Used by the re-bake of Sun et al. 2022, "Efficient Texture Parameterization Driven by
 * Perceptual-Loss-on-Screen" (section 4.2 ends with a new layout whose regions shrink, and
 * a shrunk region must be prefiltered, not point-sampled). We use our own pyramid rather
 * than OpenImageIO's TextureSystem because that one reads through its file cache, while our
 * images live in memory; the pyramid costs 1/3 of the image in memory. */
#ifndef TEXOPT_TEXTURE_FILTER_H
#define TEXOPT_TEXTURE_FILTER_H

#include "image.h"
#include "model.h"
#include "status.h"

typedef struct texopt_texture_filter texopt_texture_filter;

/* Builds the pyramid of img. Level 0 is img itself, borrowed: img must outlive the filter.
 * Free with texopt_texture_filter_destroy. */
texopt_status texopt_texture_filter_create(texopt_texture_filter **out, const texopt_image *img, texopt_wrap wrap_s,
                                           texopt_wrap wrap_t, char *err, size_t err_len);

void texopt_texture_filter_destroy(texopt_texture_filter *filter);

int texopt_texture_filter_levels(const texopt_texture_filter *filter);

/* Filtered value at input texel position (x, y) (level-0 texel units, texel centres at
 * i + 0.5) of the footprint whose axes are the columns of jacobian = {dx/du, dx/dv,
 * dy/du, dy/dv} (row-major: input texels per output texel). Writes `channels` floats. */
void texopt_texture_filter_sample(const texopt_texture_filter *filter, double x, double y, const double jacobian[4],
                                  float *out);

/* The range of the input around (x, y): per channel, the minimum into lo and the maximum into
 * hi of the level-0 texels a bilinear lookup anywhere in the box [x - hx, x + hx] x
 * [y - hy, y + hy] reads (wrapped), so no lookup, filtered or not, inside the box leaves it.
 * The box is cut to 64 texels each way from (x, y). Writes `channels` floats to each. */
void texopt_texture_filter_range(const texopt_texture_filter *filter, double x, double y, double hx, double hy,
                                 float *lo, float *hi);

/* Resamples the whole of src into dst (already allocated with its size and the same channel
 * count), each dst texel the prefiltered footprint of its square: what a re-bake of the
 * unchanged layout would give (method "input" resizes with Lanczos-3 instead, lanczos.h, as
 * image tools do). Rows are shared among `threads` workers (0 -> 1); the result does not
 * depend on their number. */
texopt_status texopt_texture_resize(const texopt_image *src, texopt_wrap wrap_s, texopt_wrap wrap_t, texopt_image *dst,
                                    int threads, char *err, size_t err_len);

#endif
