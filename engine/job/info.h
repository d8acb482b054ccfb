/* info.h - the `texopt info` document: what a model's texture domains look like before any
 * optimisation (counts, textures, covered texels, packing, overlaps, flips, wraps).
 *
 * Shared by the command line (cli/cmd_info.c) and the service, so both describe a model the
 * same way. The covered-texel cost is that of Sun et al. 2022, "Efficient Texture
 * Parameterization Driven by Perceptual-Loss-on-Screen" (eq. 20), counted once per texel
 * (coverage.h). Works on a model loaded with or without decoded pixels (image sizes and
 * channel counts are enough).
 *
 * Document (every count an integer, areas in texels or world units squared):
 *   { "vertices", "triangles", "primitives", "materials", "untextured_primitives",
 *     "images": [ { "index", "name", "width", "height", "channels" } ],
 *     "file_cost": { "texture_pixels", "texture_bytes" },  (file_cost.h: sum of width x height
 *                                                      over the images, their encoded bytes)
 *     "domains": [ {
 *        "index", "primitives": [..], "triangles", "model_vertices", "uv_vertices", "points",
 *        "charts", "mirrored_charts", "folded_charts",
 *        "frame": { "width", "height" }, "wrap": { "s", "t" },       ("repeat"|"clamp"|"mirror")
 *        "textures": [ { "slot", "image", "name", "width", "height", "channels",
 *                        "wrap_s", "wrap_t", "reads", "magnify" } ], (slot: "baseColor", "normal",
 *                                                         ..., or an extension texture's key;
 *                                                         reads: the channels any material
 *                                                         reads of it, "RGB", "GB", "RGBA" for
 *                                                         a MASK or BLEND base colour; magnify:
 *                                                         "nearest" only, when its sampler's
 *                                                         magFilter is NEAREST: pixel art, kept
 *                                                         as it is by the layout methods)
 *        "covered_texels", "overlap_texels", "packing_efficiency", "texel_area", "area_3d",
 *        "degenerate", "degenerate_3d", "degenerate_uv", "flipped", "overlapping", "wrapped",
 *        "distortion" (texopt_distortion_json of distortion.h; null when no triangle counts),
 *        "atlas_quality" (texopt_atlas_quality_json of atlas_quality.h; null without extent),
 *        "layout_check": { "passed", "failed", "triangles", "overlapping_triangles",
 *                          "overlapping_within_chart_triangles",
 *                          "overlap_within_chart_texels", "foldover_triangles",
 *                          "oversized_triangles" }
 *     } ] }
 * "layout_check" is layout_check.h's check of the file's own layout (texopt_layout_check_own):
 * triangles on texels of another sharing group (mirrored twins laid on one region are one
 * group, as the pipeline keeps them), fold-overs ("flipped"); the first 16 offenders listed.
 * Counted, not failed: the triangles on a texel centre (in the frame) that their own chart
 * covers already under the same orientation, and those centres (a chart over itself; the
 * two sides of a fold may share); "oversized_triangles" is 0 (no targets to compare with).
 * "degenerate" counts triangles with either degenerate flag; the others are mesh.h flags.
 * When coverage refuses the layout with TEXOPT_E_LIMIT (frame past its cap, a triangle over
 * thousands of repeats), covered_texels, overlap_texels and packing_efficiency are null and
 * "coverage_error" says why; every other field is still there.
 * "mirrored_charts" counts charts whose orientation (mesh.h chart_sign) is opposite to the
 * area-weighted majority of the domain; "folded_charts" those holding a mirrored part welded
 * to the rest at its mirror line (reversed triangles that are not FLIPPED, see mesh.h). */
#ifndef TEXOPT_INFO_H
#define TEXOPT_INFO_H

#include <cjson/cJSON.h>
#include <stddef.h>

#include "model.h"
#include "status.h"

/* Builds the document. On success *out is a new cJSON object the caller frees with
 * cJSON_Delete; on failure *out is NULL and err names the domain that failed. */
texopt_status texopt_info_json(const texopt_model *model, cJSON **out, char *err, size_t err_len);

/* The document as text (pretty: indented; else one line), malloc'd, caller frees with free(). */
texopt_status texopt_info_string(const texopt_model *model, int pretty, char **out, char *err, size_t err_len);

/* The glTF name of a wrap mode ("repeat", "clamp", "mirror"). */
const char *texopt_wrap_name(texopt_wrap wrap);

#endif
