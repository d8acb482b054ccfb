/* lanczos.h - resizing a whole texture with a Lanczos-3 filter, as image tools do.
 *
 * Does: the separable Lanczos-3 resize of Pillow's Image.resize(..., Image.LANCZOS) (also
 * sharp's and ImageMagick's default for downsizing), the resize an asset pipeline applies
 * to a texture that is too large: on downsizing the kernel is stretched by the scale (its
 * support is 3 source texels times in/out each side), on upsizing it interpolates (support
 * 3); each output texel's window is cut at the image's edges and its weights renormalised
 * (Pillow's edge rule, not a wrap or a mirror); rows are resized first, then columns, and
 * both passes clamp to [0, 1] as Pillow's 8-bit passes do. Method "input" (input_method.c) is
 * this resize of every image, the baseline texopt's layouts are compared against.
 * Does not: weight colour by alpha (Pillow premultiplies RGBA; a glTF texture's alpha may be
 * unused, OPAQUE, so every channel is resized on its own), know wrap modes or layouts, or
 * round to 8 bits between the passes (tests/vectors/lanczos_vectors.py states the
 * tolerance this leaves against Pillow). */
#ifndef TEXOPT_LANCZOS_H
#define TEXOPT_LANCZOS_H

#include <stddef.h>

#include "image.h"
#include "status.h"

/* Resizes src into dst, already allocated with its new size and src's channel count. Rows
 * are shared among `threads` workers (< 1: one); the result does not depend on their
 * number. */
texopt_status texopt_lanczos_resize(const texopt_image *src, texopt_image *dst, int threads, char *err, size_t err_len);

#endif
