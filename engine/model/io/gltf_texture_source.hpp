/* gltf_texture_source.hpp - which image a glTF texture reads, and its alternate sources.
 *
 * A texture names its image in `source` and, through EXT_texture_webp, KHR_texture_basisu or
 * MSFT_texture_dds, an alternate that viewers knowing the extension read instead. texopt
 * decodes and re-bakes one of them (`source` when present); once that one is replaced, the
 * texture must read the replacement everywhere, or those viewers would draw the old texels
 * through the new UVs.
 * Does not: decode anything or decide what is replaced (gltf_load.cpp, gltf_save.cpp).
 * Internal to engine/io; the extensions are Khronos's and Microsoft's glTF texture extensions. */
#ifndef TEXOPT_GLTF_TEXTURE_SOURCE_HPP
#define TEXOPT_GLTF_TEXTURE_SOURCE_HPP

#include <functional>
#include <vector>

#include <tiny_gltf.h>

/* The image texopt reads for texture t: its `source`, else its first alternate's; -1 if none. */
int gltf_texture_source(const tinygltf::Texture &t);

/* Calls f with a pointer to each image index texture t names, its source's and its
 * alternates'; what f writes there becomes t's reference. */
void gltf_for_each_texture_image(tinygltf::Texture &t, const std::function<void(int *)> &f);

/* Makes t read `image` as its `source` and drops its alternate sources. */
void gltf_texture_read_only(tinygltf::Texture &t, int image);

/* Removes the alternate-source extensions no texture of g uses any more from its
 * extensionsUsed and extensionsRequired. */
void gltf_drop_unused_source_extensions(tinygltf::Model &g);

/* Removes from g the images a texture of `before` read (as source or alternate) that no
 * texture of g reads any more (the alternates of replaced textures), renumbering the
 * textures' references; returns per image of g before the call its new index, -1 when
 * removed. Nothing is removed (the identity is returned) when g uses an extension texopt does
 * not know, which might name images by index. */
std::vector<int> gltf_drop_images_made_unused(tinygltf::Model &g, const tinygltf::Model &before);

#endif
