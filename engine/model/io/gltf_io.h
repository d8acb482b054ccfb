/* gltf_io.h - loading a glTF 2.0 model into a texopt_model and saving it back as .glb.
 *
 * Does: parse .glb / .gltf (external files next to it, data URIs) with tinygltf, validate
 * every accessor, buffer view and URI before reading it, flatten the triangle primitives
 * (lists, strips, fans) into engine/model/model.h, apply each material's KHR_texture_transform to its TEXCOORD_0,
 * decode the images with OpenImageIO (io/image_io.h), group texture domains; and write the
 * same document back with replaced TEXCOORD_0 (its applied transforms dropped) and images.
 * Does not: fetch anything from the network, decode Draco / meshopt compressed geometry or
 * sparse accessors, lay out one TEXCOORD_0 for several transforms (a material whose
 * TEXCOORD_0 bindings differ is refused, as is a zero scale or a transform that turns or
 * mirrors a normal map), re-bake textures of material extensions other than those
 * texture_keys.h knows (one on TEXCOORD_0 is refused), keep an anisotropy direction that
 * the derived tangent frame would turn (KHR_materials_anisotropy without a TEXCOORD_0 map on
 * a primitive without TANGENT is refused), or evaluate animations (a skinned mesh keeps its
 * bind pose).
 * The format is the Khronos glTF 2.0 specification; the method that consumes the data is
 * Sun et al. 2022, "Efficient Texture Parameterization Driven by Perceptual-Loss-on-Screen".
 *
 * Errors: TEXOPT_E_MALFORMED for broken files (truncated, out-of-bounds accessors, index past
 * the vertex count, NaN/Inf data, URIs leaving the model's directory or naming the network),
 * TEXOPT_E_LIMIT for sizes past the load options, TEXOPT_E_UNSUPPORTED for valid input texopt
 * cannot use (no textured material, a textured primitive without TEXCOORD_0 or not made of
 * triangles, compressed geometry, sparse accessors, transforms, extension textures or an
 * anisotropy direction it cannot follow), TEXOPT_E_IO for files that cannot be read or written.
 * The message names the offending element ("accessor 3: index 812 past vertex count 800").
 * Images are decoded (load) and PNG-encoded (save) on up to one thread per image, never more
 * than the online cores (io/image_jobs.hpp). */
#ifndef TEXOPT_GLTF_IO_H
#define TEXOPT_GLTF_IO_H

#include <stddef.h>
#include <stdint.h>

/* The engine's C headers carry no linkage guards; wrap them for the C++ shims. */
#ifdef __cplusplus
extern "C" {
#endif

#include "image.h"
#include "model.h"
#include "status.h"

/* Limits and choices for loading. A zero-initialised struct gives the defaults. */
typedef struct texopt_load_options {
    uint64_t max_file_bytes;   /* per file read (the model and each external file); 0 = 1 GiB */
    uint64_t max_total_pixels; /* sum of width*height over all images, checked from the image
                                  headers before any decoding; 0 = 2^28 */
    int skip_images;           /* nonzero: read only image headers: images get width, height and
                                  channels but NULL pixels (for `texopt info` and quick checks) */
} texopt_load_options;

/* Loads the .glb or .gltf at path into a new model (*out; NULL on failure). opt may be NULL
 * for the defaults. On success the caller owns *out and frees it with texopt_model_destroy.
 *
 * The model is filled completely: world-space positions (an instanced mesh takes the first
 * node that uses it, in node order; a mesh used by no node keeps its own coordinates; a
 * skinned mesh its bind pose), TEXCOORD_0 as floats (normalized u8/u16 converted), triangles
 * (indexed u8/u16/u32 or non-indexed), primitives, materials (5 slots with texcoord set and
 * sampler wrap modes), decoded images with their names, and texture domains. Primitives
 * that are not triangles and not textured (points, lines) are skipped; an untextured
 * triangle primitive without TEXCOORD_0 is kept with UVs (0, 0). Under a mirroring node
 * transform (negative determinant) each triangle's last two vertices are swapped, so that
 * model triangles wind counter-clockwise in world space as glTF means them to. */
texopt_status texopt_model_load(texopt_model **out, const char *path, const texopt_load_options *opt, char *err,
                                size_t err_len);

/* The encoded size in bytes of model image `image` as its file holds it (PNG, JPEG, ...), 0
 * when the model was not loaded from a file or the index is out of range. */
uint64_t texopt_model_image_bytes(const texopt_model *model, int image);

/* As texopt_model_load, from a .glb or .gltf held in memory (the caller keeps bytes).
 * base_dir is the directory external URIs resolve against; NULL refuses every external
 * URI (only buffer views and data URIs are then allowed). */
texopt_status texopt_model_load_memory(texopt_model **out, const void *bytes, size_t len, const char *base_dir,
                                       const texopt_load_options *opt, char *err, size_t err_len);

/* What to change when saving. A zero-initialised edit saves the model unchanged. */
typedef struct texopt_model_edit {
    /* New TEXCOORD_0 for every model vertex (2 floats per vertex, model->vertex_count
     * vertices, the layout of model->uvs, texture transforms applied), or NULL to keep the
     * file's. Written to the primitives that had TEXCOORD_0 as new float accessors with exact
     * min/max; the KHR_texture_transform of bindings on TEXCOORD_0 is dropped. */
    const float *uvs;
    /* images[i] replaces model image i (any size; a JPEG's replacement encoded as a JPEG of
     * quality 98, any other as PNG), or NULL keeps the original encoded bytes untouched. The
     * array has model->image_count entries; the whole array may be NULL to keep every image.
     * Bindings through another set than TEXCOORD_0 that read a replaced image are pointed at
     * an untouched copy of it. */
    const texopt_image *const *images;
    /* Non-zero: every replacement is encoded as PNG, a JPEG's too, so the file holds the
     * replacement's texels exactly (to its bit depth). */
    int lossless;
} texopt_model_edit;

/* Writes model (as loaded by texopt_model_load*) with edit applied as a binary glTF at path:
 * the same scenes, nodes, meshes, materials, animations, skins, extensions and extras; every
 * buffer merged into the one BIN chunk; every image stored in a buffer view (no data URIs,
 * no external files). The file is written to a temporary name next to path, fsynced and
 * renamed, so path is either the old file or the complete new one. edit may be NULL. */
texopt_status texopt_model_save_glb(const texopt_model *model, const texopt_model_edit *edit, const char *path,
                                    char *err, size_t err_len);

#ifdef __cplusplus
}
#endif

#endif
