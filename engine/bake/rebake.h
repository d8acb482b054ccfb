/* rebake.h - re-bakes one texture from the input UV layout into a new layout.
 *
 * Does: for every output texel whose centre lies in a triangle of the new layout, map the
 * centre through that triangle's affine map back to the input texture and take a
 * prefiltered sample there (texture_filter.h: the footprint of the output texel, so a region
 * that shrinks is averaged, not point-sampled); then, by default, fit the texels by least
 * squares so that their bilinear reconstruction matches the input (texopt_rebake_fit
 * below). Texels that a triangle touches but whose
 * centre lies outside every triangle (the one-texel rim of each chart) take the value at the
 * nearest point of the triangle (clamped barycentrics), and a triangle too small to hold any
 * texel centre still writes the texel under its centroid. Everything else is gutter,
 * filled by dilation (dilate.h) over the whole image so mip-mapped lookups stay clean.
 *
 * Normal maps (tangent-space, glTF convention: X right = +u, Y up = -v, Z out): the new
 * layout rotates each triangle's texels by the rotation part R of its map input -> output
 * (2x2 polar decomposition; 90-degree packing rotations are exact rotations). A renderer
 * that derives tangents from the UVs (MikkTSpace, glTF's rule when TANGENT is absent) then
 * sees a tangent frame rotated by R, so the stored XY must turn with it. In the image frame
 * (x right, y down) a surface direction with map components (a, b) is the texel vector
 * (a, -b); it becomes R (a, -b), hence (a', b') = R^T (a, b) in map components, Z kept.
 * A model that stores TANGENT keeps its tangents, so its normal maps must NOT be rotated:
 * the caller decides through `normal_map`.
 *
 * Does not: choose the layout or the output size (pack.h, budget.h), or encode files.
 * Implements the re-bake step that follows the mesh-wise layout of Sun et al. 2022,
 * "Efficient Texture Parameterization Driven by Perceptual-Loss-on-Screen" (section 4.2). */
#ifndef TEXOPT_REBAKE_H
#define TEXOPT_REBAKE_H

#include <stddef.h>
#include <stdint.h>

#include "image.h"
#include "model.h"
#include "monitor.h"
#include "status.h"

/* How the output texels are chosen from the input.
 * PREFILTER: each texel is the prefiltered lookup at its centre (above). A renderer then
 *   interpolates those values bilinearly a second time, which blurs wherever the layout
 *   keeps or magnifies the input's density.
 * LEAST_SQUARES: the prefiltered bake is the start and the ridge target of a least-squares
 *   fit (texel_fit.h): the texels whose bilinear reconstruction best matches the input at
 *   four sub-texel points per covered texel (each point a prefiltered lookup with half a
 *   texel's footprint, i.e. plain bilinear where the layout magnifies), each texel kept
 *   within the range of the input its square covers (no ringing at sharp edges).
 * MAGNIFIED: the same fit, only for texels of triangles the layout magnifies (an output
 *   texel covers at most one input texel); texels of shrunk triangles keep the prefilter.
 * DEFAULT is the one measured best with the whole-mesh evaluation (rebake.c says which). */
typedef enum texopt_rebake_fit {
    TEXOPT_REBAKE_FIT_DEFAULT = 0,
    TEXOPT_REBAKE_FIT_PREFILTER,
    TEXOPT_REBAKE_FIT_LEAST_SQUARES,
    TEXOPT_REBAKE_FIT_MAGNIFIED
} texopt_rebake_fit;

/* A layout pair over shared triangles. UVs are in [0,1] texture units (u = x / W), so one
 * layout serves every image of a domain whatever its size. */
typedef struct texopt_rebake_layout {
    size_t triangle_count;
    const uint32_t *triangles; /* 3 per triangle, indices into uv_in / uv_out */
    const double *uv_in;       /* 2 per vertex: input UVs (may leave [0,1]: wrap modes apply) */
    const double *uv_out;      /* 2 per vertex: new UVs */
    int threads;               /* workers for the sampling and fitting passes; 0 -> 1 */
} texopt_rebake_layout;

/* Bakes input (read through wrap_s / wrap_t) into output, which the caller has allocated
 * with the output size and input's channel count. normal_map: non-zero rotates the
 * tangent-space XY as described above. covered_texels (may be NULL) receives how many
 * output texels have their centre inside a triangle. The monitor (may be NULL) gets stage
 * "bake" with stage_fraction over the triangles (fraction and eta are left to whoever wraps
 * the monitor) and is checked for cancellation every few thousand triangles. */
texopt_status texopt_rebake_image(const texopt_image *input, texopt_wrap wrap_s, texopt_wrap wrap_t, int normal_map,
                                  const texopt_rebake_layout *layout, texopt_image *output, size_t *covered_texels,
                                  const texopt_monitor *monitor, char *err, size_t err_len);

/* As texopt_rebake_image, with the texel rule chosen (texopt_rebake_image uses DEFAULT). */
texopt_status texopt_rebake_image_fit(const texopt_image *input, texopt_wrap wrap_s, texopt_wrap wrap_t, int normal_map,
                                      const texopt_rebake_layout *layout, texopt_rebake_fit fit, texopt_image *output,
                                      size_t *covered_texels, const texopt_monitor *monitor, char *err, size_t err_len);

#endif
