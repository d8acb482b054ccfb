/* gltf_extension_textures.hpp - where a material's extension objects hold the textures of
 * material extensions (clearcoat, sheen, specular...) that texopt lays out and re-bakes beside
 * the core slots (the known ones: texture_keys.h).
 *
 * A known one is a textureInfo directly under its extension's object (KHR_materials_clearcoat's
 * clearcoatNormalTexture); each has a kind (model.h texopt_texture_kind). Anything else shaped
 * like a texture (a key ending in "Texture" holding an integer index), at any depth, is
 * unknown: its texels' meaning, and so how to compare or turn them, is not known here. Each known
 * one also says which channels hold its numbers (clearcoat's R, specular's A).
 * Left unknown on purpose: KHR_materials_pbrSpecularGlossiness, whose diffuse texture takes
 * base colour's place, which the whole-mesh evaluation renders (it would judge every layout
 * by a grey surface).
 * Does not: bind, transform or bake anything (gltf_load.cpp, gltf_save.cpp, the pipeline).
 * Internal to engine/io; the extensions are Khronos's KHR_materials_* specifications. */
#ifndef TEXOPT_GLTF_EXTENSION_TEXTURES_HPP
#define TEXOPT_GLTF_EXTENSION_TEXTURES_HPP

#include <string>

#include <tiny_gltf.h>

extern "C" {
#include "model.h"
#include "texture_keys.h"
}

/* Whether v, under `key`, is a textureInfo: an object with an integer "index" under a key
 * ending in "Texture". Its texCoord (0 when absent or not an integer) goes to *texcoord. */
bool gltf_is_texture_info(const std::string &key, const tinygltf::Value &v, int *texcoord);

/* The kind, the channels read (model.h TEXOPT_CHANNEL_*) and the key's static copy of texture
 * `key` of material extension `extension`; false when texopt does not know that texture. */
bool gltf_known_extension_texture(const std::string &extension, const std::string &key, texopt_texture_kind *kind,
                                  unsigned *channels, const char **name);

/* The first unknown texture on TEXCOORD_0 inside the extension object v (any depth); its key
 * in *name. Known ones at the top level are skipped. */
bool gltf_unknown_extension_texture_on_set0(const std::string &extension, const tinygltf::Value &v, std::string *name);

#endif
